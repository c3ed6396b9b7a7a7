#!/usr/bin/env bash
# Where a pick's instructions go, by phase: callgrind over `pick_count` (the report's terrain rows, Trinidad and the
# quick report's synthetic 1024 × 1024 DEM: rays from a camera 2 km up and from orbit, leaf blocks of 8 × 8 and
# 16 × 16 cells), 3 passes minus 1 pass so that loading
# the DEM, building the tree and forming the rays cancel, each instruction charged to a phase by the kernel source
# file it comes from (code inlined from the kernel counts for the file it was written in; code inlined from the
# standard library or from the kernel's arithmetic helpers counts for the function it was inlined into).
#
# Usage: host-tests/examples/pick_phases.sh [N]   (N rays per row, 2000 by default; needs valgrind)
# Prints one table, instructions per pick by phase and row, and the total.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
N=${1:-2000}
# The report's two terrains: Trinidad and the quick report's synthetic fractal DEM (DEMS="trinidad" for one).
DEMS=${DEMS:-trinidad synthetic}
cargo build -q --release -p curvicast-host --example pick_count
BIN=target/release/examples/pick_count
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

# phase_of: reads callgrind_annotate's "Ir file:function" lines, prints "phase Ir" per line.
phase_of() {
    awk '
    function phase(path, fn,    f) {
        # the kernel file the instruction was written in, unless it is a helper inlined everywhere
        if (path ~ /kernel\/src\// && path !~ /kernel\/src\/(real|vec3|dd|sort|interval)\.rs$/ && path !~ /kernel\/src\/real\//) f = path
        else {
            # the module the function is written in: for a method, the module of its impl block, not its type path
            f = fn; i = index(f, "<impl "); if (i > 0) f = substr(f, 1, i - 1)
        }
        if (f ~ /terrain\/(picker|walk|grid|error)\.rs|terrain::(picker|walk|grid)::|kernel\/src\/ray\.rs|curvicast::ray::/) return "set-up (ray, zones, the walk'"'"'s state)"
        if (f ~ /terrain\/boxes\.rs|terrain::boxes::/) return "quads: box test"
        if (f ~ /geodesy\/(bounds|relaxed)|geodesy::(bounds|relaxed)|kernel\/src\/surface\/|curvicast::surface::/) return "quads: spheroidal volumes"
        if (f ~ /terrain\/traverse\.rs|terrain::traverse::/) return "quads: visit and order"
        if (f ~ /terrain\/(leaf|stitch|subset|parallel|windows)|terrain::(leaf|stitch|subset|parallel|windows)/) return "leaf cells walked"
        if (f ~ /terrain\/triangle\.rs|terrain::triangle::/) return "triangles tested"
        if (f ~ /terrain\/(refine|hit)\.rs|terrain::(refine|hit)::/) return "refinement"
        if (f ~ /geodesy\/ellipsoid|geodesy::ellipsoid|geodesy\/mod\.rs/) return "geodetic output"
        if (f ~ /terrain\/storage\.rs|terrain::storage::|product\/src\/storage|curvicast_cli::storage|pick_count::/) return "storage (the caller'"'"'s data)"
        return "other"
    }
    $2 ~ /^\(/ {
        ir = $1; gsub(/,/, "", ir)
        rest = $0; sub(/^[ ]*[0-9,]+ \([ 0-9.]+%\)[ ]+/, "", rest); sub(/ \[[^]]*\]$/, "", rest)
        i = index(rest, ".rs:"); if (i == 0) next
        print phase(substr(rest, 1, i + 2), substr(rest, i + 4)) "\t" ir
    }'
}

ROWS=()
for dem in $DEMS; do
for rays in camera orbit; do
    for block in 8 16; do
        row="$dem $rays, ${block} × ${block}"
        ROWS+=("$row")
        for passes in 1 3; do
            valgrind --tool=callgrind --callgrind-out-file="$WORK/cg.$passes" "$BIN" "$rays" "$block" "$N" "$passes" \
                "dem=$dem" >/dev/null 2>&1
            callgrind_annotate --auto=no --threshold=100 "$WORK/cg.$passes" 2>/dev/null | phase_of |
                awk -F'\t' '{ s[$1] += $2 } END { for (p in s) printf "%s\t%d\n", p, s[p] }' >"$WORK/p.$passes"
        done
        awk -F'\t' -v row="$row" -v n="$N" '
            FNR == NR { one[$1] = $2; next }
            { printf "%s\t%s\t%.1f\n", row, $1, ($2 - one[$1]) / (2 * n) }' "$WORK/p.1" "$WORK/p.3" >>"$WORK/all"
    done
done
done

awk -F'\t' -v nrows="${#ROWS[@]}" -v rows="$(IFS='|'; echo "${ROWS[*]}")" '
    BEGIN {
        split(rows, R, "|")
        np = split("set-up (ray, zones, the walk'"'"'s state)|quads: visit and order|quads: box test|quads: spheroidal volumes|leaf cells walked|triangles tested|refinement|geodetic output|storage (the caller'"'"'s data)|other", P, "|")
    }
    { v[$1, $2] = $3 }
    END {
        printf "| phase |"; for (r = 1; r <= nrows; r++) printf " %s |", R[r]; printf "\n|---|"
        for (r = 1; r <= nrows; r++) printf "---:|"; printf "\n"
        for (p = 1; p <= np; p++) {
            printf "| %s |", P[p]
            for (r = 1; r <= nrows; r++) { x = v[R[r], P[p]] + 0; t[r] += x; printf " %.0f |", x }
            printf "\n"
        }
        printf "| **instructions per pick** |"; for (r = 1; r <= nrows; r++) printf " **%.0f** |", t[r]; printf "\n"
    }' "$WORK/all"
