#!/usr/bin/env bash
# Where a firmware's executed instructions go: runs FIRMWARE under QEMU as run.sh does, with QEMU's execution log
# (`-d exec,nochain,in_asm`: each translated block's instructions, and every execution of a block), counts how
# often each instruction ran, and charges the counts to functions the way `text-by-function.sh` charges bytes
# (code inlined from a kernel function counts for that function). Prints `instructions function` lines, largest
# first, for functions of at least MIN instructions, then the totals of the kernel, the libraries and the
# firmware with its harness; with PER, every count is divided by PER first (e.g. the number of crossings the
# firmware marched, to read instructions per crossing; march-f32 marches each ray 9 times, 8 timed runs and one
# for the stack, so PER = 9 × the crossings it prints).
#
# With BYTES=1 it prints instead the bytes of the instructions that ran at least once and of those that never ran,
# by function (functions of at least MIN bytes), e.g. `BYTES=1 ./profile.sh march-f32 release-s 100000` for the
# totals alone.
#
# Usage: profile.sh FIRMWARE [PROFILE] [MIN] [PER]   e.g. `./profile.sh march-f32 release 100 19575`
# (PROFILE is a cargo profile, `release` by default; build it first, e.g. `cargo build --release --bins`).
# Needs qemu-system-arm and what text-by-function.sh needs. The log is large (about 300 MB for march-f32).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
fw=$1
profile=${2:-release}
min=${3:-1}
per=${4:-1}
elf=target/thumbv7em-none-eabihf/$profile/$fw
[[ -f $elf ]] || { echo "no $elf: build it first (cargo build --profile $profile --bins)" >&2; exit 2; }
log=$(mktemp)
trap 'rm -f "$log" "$log.weights"' EXIT
qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -semihosting-config enable=on,target=native \
    -icount shift=0 -d exec,nochain,in_asm -D "$log" -kernel "$elf" >&2

# Each block's instructions are listed when it is translated ("IN:" then `0xADDR: ...` lines), and each execution
# is a "Trace" line whose bracket holds the block's address second. Addresses are normalised to bare hex.
awk '
    function bare(a) { sub(/^0x/, "", a); sub(/^0+/, "", a); return a == "" ? "0" : a }
    /^IN:/ { listing = 1; n = 0; next }
    listing && /^0x[0-9a-f]+:/ { a = $1; sub(/:$/, "", a); ins[n++] = bare(a); next }
    /^Trace/ {
        match($0, /\[[0-9a-f]+\/[0-9a-f]+\//); split(substr($0, RSTART + 1, RLENGTH - 2), f, "/"); pc = bare(f[2])
        if (listing && !(pc in len)) { len[pc] = n; for (i = 0; i < n; i++) at[pc, i] = ins[i] }
        listing = 0; runs[pc]++; next
    }
    END {
        for (pc in runs) for (i = 0; i < len[pc]; i++) count[at[pc, i]] += runs[pc]
        for (a in count) printf "%s %d\n", a, count[a]
    }' "$log" > "$log.weights"
rm -f "$log"
if [[ -n ${BYTES:-} ]]; then
    # the code size of what ran and of what never ran, by function (functions of at least MIN bytes)
    for select in executed never; do
        echo "bytes of instructions that ran $([[ $select == never ]] && echo never || echo "at least once"):"
        COUNTS="$log.weights" SELECT=$select ./text-by-function.sh "$elf" "$min"
    done
    exit 0
fi
WEIGHTS="$log.weights" ./text-by-function.sh "$elf" 1 | awk -v per="$per" -v min="$min" '
    { w = $1 / per; $1 = ""; sub(/^ /, "") }
    w >= min || !/^\[|::/ { printf(per == 1 ? "%9d %s\n" : "%9.1f %s\n", w, $0) }'
