#!/usr/bin/env bash
# Where a firmware's `.text` goes: every instruction's bytes are charged to the outermost function of the kernel
# (`kernel/src/`) in its inlining chain, read from the debug information (so code the optimiser inlined into a
# caller is charged to the kernel function it came from, not to the caller). Instructions with no kernel frame are
# charged to their outermost function, marked `[library]` (libm, compiler-builtins) or `[firmware]` (the
# measuring harness and the firmware's own code). Prints `bytes function` lines, largest first, for functions of at
# least MIN bytes (default 1), then the totals of the three groups.
#
# Usage: text-by-function.sh ELF [MIN] (needs llvm-objdump, as run.sh finds it, and binutils' addr2line).
#
# With WEIGHTS=FILE (lines `hex weight`, the address in lower-case hex without `0x` or leading zeros) each
# address is charged its weight instead of its size: `profile.sh` charges executed instructions this way. With
# COUNTS=FILE (the same form, execution counts) and SELECT=executed or SELECT=never, only the bytes of the
# instructions that ran at least once, or never, are charged (`profile.sh` with BYTES=1).
set -euo pipefail
elf=$1
min=${2:-1}
objdump=${OBJDUMP:-llvm-objdump}

# The instruction (and literal-pool word) addresses of .text, each with its size (or weight), as `hex size`.
end=$(size -A -x "$elf" | awk '$1 == ".text" { print $2, $3 }')
if [[ -n ${WEIGHTS:-} ]]; then sizes=$(cat "$WEIGHTS"); else
sizes=$("$objdump" -d --no-show-raw-insn "$elf" | awk -v end="$end" '
    function hex(s,   i, n) { n = 0; s = tolower(s); sub(/^0x/, "", s)
        for (i = 1; i <= length(s); i++) n = n * 16 + index("0123456789abcdef", substr(s, i, 1)) - 1
        return n }
    /^ +[0-9a-f]+:/ { a = $1; sub(/:$/, "", a); addr[n++] = hex(a) }
    END { split(end, e, " "); addr[n] = hex(e[1]) + hex(e[2])
        for (i = 0; i < n; i++) if (addr[i + 1] > addr[i]) printf "%x %d\n", addr[i], addr[i + 1] - addr[i] }')
fi
if [[ -n ${COUNTS:-} ]]; then
    sizes=$(awk -v select="${SELECT:-executed}" 'NR == FNR { if ($2 > 0) ran[$1] = 1; next }
        (select == "never") != ($1 in ran) { print }' "$COUNTS" - <<<"$sizes")
fi

# The sizes go to awk in a file: as a `-v` argument a large firmware's list passes the kernel's 128 KiB limit on one
# argument ("Argument list too long").
sizes_file=$(mktemp)
trap 'rm -f "$sizes_file"' EXIT
printf '%s\n' "$sizes" >"$sizes_file"
awk '{ print "0x" $1 }' "$sizes_file" | addr2line -a -f -i -C -e "$elf" | awk -v min="$min" -v sizes_file="$sizes_file" '
    BEGIN { while ((getline line < sizes_file) > 0) { split(line, p, " "); size["0x" p[1]] = p[2] } }
    function flush(   i, entry, group) {
        if (cur == "") return
        entry = ""
        for (i = depth - 1; i >= 0; i--) if (loc[i] ~ /\/kernel\/src\//) { entry = fn[i]; break }
        if (entry != "") group = "kernel"
        else {
            entry = fn[depth - 1]
            group = (entry ~ /^(libm::|compiler_builtins::|__aeabi|__|mem(cpy|set|cmp|move)$)/ || loc[depth - 1] ~ /(libm|compiler-builtins)/) ? "library" : "firmware"
            entry = "[" group "] " entry
        }
        sub(/::h[0-9a-f]+$/, "", entry)
        bytes[entry] += size[cur]; total[group] += size[cur]
    }
    /^0x[0-9a-f]+$/ { flush(); a = $0; sub(/^0x0*/, "0x", a); cur = a; depth = 0; next }
    { fn[depth] = $0; if ((getline line) > 0) loc[depth] = line; depth++ }
    END {
        flush()
        for (e in bytes) if (bytes[e] >= min) printf "%7d %s\n", bytes[e], e | "sort -rn"
        close("sort -rn")
        printf "%7d kernel (all of its functions)\n%7d libraries\n%7d firmware and harness\n", total["kernel"], total["library"], total["firmware"]
    }'
