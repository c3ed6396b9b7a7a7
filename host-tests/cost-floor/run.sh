#!/usr/bin/env bash
# What the serial march's safeguards cost, and what is left without them: the floor of its instructions per
# crossing on the report's marching scene (see the README, "What a crossing costs").
#
# Copies the committed tree (HEAD) to target/cost-floor/src, applies ablate.patch there (never to the working
# tree), and measures `march_count f64 serial-fold uniform 64` with callgrind (3 passes minus 1, as in the
# README) for the kernel as it is, with each safeguard removed alone, with all of them removed, and with the zenith
# stream's ring of second roots removed. The patch's switches are bits of CURVICAST_ABLATE, read when the kernel
# is compiled:
#   0  the Newton step on each cone root (accuracy of crossings near the apex)
#   1  the check that the ray's crossings of the outer ball have representable t (MarchError::Unrepresentable)
#   2  each stream's clamp to its previous event and its test against t_max
#   3  the azimuth step's arc test (is the boundary ahead of the point's own direction) and its crossing count
#   4  the zenith stream's event bound (MarchError::IterationBound)
#   5  the exact rescaling between the scaled parameter and t (right only for directions already at unit size,
#      as on this scene)
#   6  the ring of second roots (not a safeguard: what it saves)
# The removed safeguards make answers wrong on hard cases (the named tests); on this scene the crossings are
# the same. With --m4f, also builds and runs the Cortex-M4F march-f32 firmware (kernel/m4f-bench, QEMU) as it is
# and with bits 0-5 removed. Needs valgrind (and for --m4f what kernel/m4f-bench/run.sh needs). About 10 minutes.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(git -C "$here" rev-parse --show-toplevel)
work=$root/target/cost-floor/src
rm -rf "$work"
mkdir -p "$work"
git -C "$root" archive HEAD | tar -x -C "$work"
# (git apply outside any repository: the copy lies inside this one's target directory, which it must not see)
if ! (cd "$work" && GIT_CEILING_DIRECTORIES=$(dirname "$work") git apply "$here/ablate.patch"); then
    echo "ablate.patch no longer applies to the kernel at HEAD: make its switches again on the current code" >&2
    exit 1
fi
export CARGO_TARGET_DIR=$root/target/cost-floor/target
bin=$CARGO_TARGET_DIR/release/examples/march_count

per_crossing() {
    (cd "$work" && CURVICAST_ABLATE=$1 cargo build -q --release -p curvicast-host --example march_count)
    local args=(f64 serial-fold uniform 64) n1 n3 cr
    n1=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "${args[@]}" 1 2>&1 | awk '/Collected/ { print $4 }')
    n3=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "${args[@]}" 3 2>&1 | awk '/Collected/ { print $4 }')
    cr=$("$bin" "${args[@]}" 1 | sed -n 's/.*(\([0-9]*\) per pass.*/\1/p')
    awk -v a="$n1" -v b="$n3" -v c="$cr" 'BEGIN { printf "%.1f", (b - a) / (2 * c) }'
}

names=("Newton step on cone roots" "outer-ball representability check" "clamps and t_max tests"
       "azimuth arc test and count" "zenith event bound" "exact rescaling s <-> t")
base=$(per_crossing 0)
echo "instructions per crossing, f64, internal iteration, uniform 64^3 scene (callgrind, 3 passes - 1)"
printf '%-46s %8s %8s\n' "kernel" "count" "saved"
printf '%-46s %8s %8s\n' "as it is" "$base" ""
for k in 0 1 2 3 4 5; do
    v=$(per_crossing $((1 << k)))
    printf '%-46s %8s %8s\n' "without the ${names[$k]}" "$v" "$(awk -v a="$base" -v b="$v" 'BEGIN { printf "%.1f", a - b }')"
done
v=$(per_crossing 63)
printf '%-46s %8s %8s\n' "without all six" "$v" "$(awk -v a="$base" -v b="$v" 'BEGIN { printf "%.1f", a - b }')"
v=$(per_crossing 64)
printf '%-46s %8s %8s\n' "without the ring of second roots" "$v" "$(awk -v a="$base" -v b="$v" 'BEGIN { printf "%.1f", a - b }')"

if [[ ${1:-} == --m4f ]]; then
    unset CARGO_TARGET_DIR
    echo "Cortex-M4F, march-f32 (kernel/m4f-bench/run.sh), instructions per crossing on both grids:"
    for m in 0 63; do
        line=$(cd "$work/kernel/m4f-bench" && CURVICAST_ABLATE=$m ./run.sh 2>&1 | grep '^| march-f32' || true)
        echo "  CURVICAST_ABLATE=$m: ${line:-run.sh failed}"
    done
fi
