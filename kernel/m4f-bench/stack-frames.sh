#!/usr/bin/env bash
# The stack frame of every function of a firmware, from its prologue: the registers it pushes (`push`: 4 bytes
# each, `vpush`: 8 bytes per d register) plus what it reserves with `sub sp` (stable Rust has no
# `-Z emit-stack-sizes`). A frame holds everything inlined into that function, so the painted-stack high-water mark
# of a call is about the sum of the frames along its deepest call chain. Prints `bytes function` lines, largest
# first, for frames of at least MIN bytes (default 1).
#
# Usage: stack-frames.sh ELF [MIN] (needs llvm-objdump, as run.sh finds it).
set -euo pipefail
elf=$1
min=${2:-1}
objdump=${OBJDUMP:-llvm-objdump}

"$objdump" -d --no-show-raw-insn -C "$elf" | awk -v min="$min" '
    function num(s) { sub(/^#/, "", s); return (s ~ /^0x/) ? hex(s) : s + 0 }
    function hex(s,   i, n) { n = 0; s = tolower(substr(s, 3))
        for (i = 1; i <= length(s); i++) n = n * 16 + index("0123456789abcdef", substr(s, i, 1)) - 1
        return n }
    /^[0-9a-f]+ <.*>:$/ { fn = $0; sub(/^[0-9a-f]+ </, "", fn); sub(/>:$/, "", fn); sub(/::h[0-9a-f]+$/, "", fn)
        gsub(/\$LT\$/, "<", fn); gsub(/\$GT\$/, ">", fn); gsub(/\$u20\$/, " ", fn); gsub(/\$C\$/, ",", fn)
        frame[fn] += 0; next }
    $2 ~ /^(push|push\.w|vpush)$/ && fn != "" {
        regs = $0; sub(/.*\{/, "", regs); sub(/\}.*/, "", regs)
        k = split(regs, r, ",")
        for (i = 1; i <= k; i++) { gsub(/ /, "", r[i]); frame[fn] += (r[i] ~ /^d/) ? 8 : 4 }
        next }
    $2 ~ /^sub(\.w|w)?$/ && $3 == "sp," && fn != "" { v = ($4 == "sp,") ? $5 : $4; if (v ~ /^#/) frame[fn] += num(v) }
    END { for (f in frame) if (frame[f] >= min) printf "%7d %s\n", frame[f], f | "sort -rn" }'
