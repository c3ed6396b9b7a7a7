#!/usr/bin/env bash
# Builds the firmwares, the Rust ones here and the C ones of kernel/ffi/c/firmware (opt-level 3 for the
# instruction counts, opt-level "s" for the code sizes), runs each under
# QEMU's mps2-an386 (Cortex-M4F) with instruction counting, checks the f32 march firmware's code (VSQRT.F32
# present, no soft double precision), splits the march firmware's kernel code into what the benchmark's rays
# execute and what they never reach (profile.sh), prints the table and writes it to `embedded.md` next to this
# script.
#
# Needs: the thumbv7em-none-eabihf target, arm-none-eabi-gcc with newlib (the C firmwares), qemu-system-arm, llvm-objdump / llvm-nm (rustup's llvm-tools
# component, or the system's) and binutils' addr2line (for text-by-function.sh). Exits non-zero if a firmware
# fails its own checks or a code check fails.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

TARGET=thumbv7em-none-eabihf
QEMU=(qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic -semihosting-config enable=on,target=native
      -icount shift=0 -kernel)
FIRMWARES=(empty march-workload-f32 march-f32 march-workload-f64 march-f64 pick-f32 bevel-f32 sqrt-check)

tool() {
    local t
    t="$(rustc --print sysroot)/lib/rustlib/$(rustc -vV | awk '/^host:/ { print $2 }')/bin/$1"
    if [[ -x "$t" ]]; then echo "$t"; elif command -v "$1" >/dev/null; then command -v "$1"; else
        echo "missing $1 (rustup component add llvm-tools)" >&2; return 1; fi
}
OBJDUMP=$(tool llvm-objdump)
NM=$(tool llvm-nm)

cargo build --release --bins
cargo build --profile release-s --bins
cargo build --profile release-z --bins
# The C firmwares: the same workloads through the C interface (kernel/ffi), built with arm-none-eabi-gcc.
../ffi/c/firmware/build.sh
CFW=../ffi/staticlib/target/c-firmware
C_FIRMWARES=(c-empty c-march-f32 c-march-next-f32 c-pick-f32)

text() { size -A "target/$TARGET/$1/$2" | awk '$1 == ".text" { print $2 }'; }
ctext() { size -A "$CFW/$1/$2" | awk '$1 == ".text" { print $2 }'; }

declare -A OUT
status=0
for f in "${FIRMWARES[@]}"; do
    log=$(timeout 600 "${QEMU[@]}" "target/$TARGET/release/$f") || status=1
    echo "$log"
    OUT[$f]=$log
    grep -q "^m4f-bench $f: status ok$" <<<"$log" || { echo "!!! $f failed"; status=1; }
done
for f in "${C_FIRMWARES[@]}"; do
    log=$(timeout 600 "${QEMU[@]}" "$CFW/release/$f") || status=1
    echo "$log"
    OUT[$f]=$log
    grep -q "^m4f-bench $f: status ok$" <<<"$log" || { echo "!!! $f failed"; status=1; }
done
# The smallest build of the f32 march must work too (the same checks, its numbers are not tabled).
log=$(timeout 600 "${QEMU[@]}" "target/$TARGET/release-z/march-f32") || status=1
grep -q "^m4f-bench march-f32: status ok$" <<<"$log" || { echo "!!! march-f32 (opt z) failed"; status=1; }

# The f32 firmwares: the hardware square root is there, soft double precision is not. The Cortex-M4F has no
# double-precision unit, so any f64 operation (arithmetic, comparison, conversion; libm's f64 functions included)
# calls one of compiler-builtins' routines below.
march32=target/$TARGET/release-s/march-f32
pick32=target/$TARGET/release-s/pick-f32
SOFT_F64='__(aeabi_d[a-z0-9]+|aeabi_[a-z0-9]*2d|[a-z]+df[0-9])$'
vsqrt=$("$OBJDUMP" -d "$march32" | grep -c 'vsqrt.f32' || true)
softf64=$("$NM" "$march32" | awk '{ print $NF }' | grep -cE "$SOFT_F64" || true)
echo "march-f32: $vsqrt vsqrt.f32 instructions, $softf64 soft double-precision routines"
[[ $vsqrt -gt 0 && $softf64 -eq 0 ]] || { echo "!!! march-f32: expected vsqrt.f32 and no soft f64"; status=1; }
pick_softf64=$("$NM" "$pick32" | awk '{ print $NF }' | grep -cE "$SOFT_F64" || true)
echo "pick-f32: $pick_softf64 soft double-precision routines"
[[ $pick_softf64 -eq 0 ]] || { echo "!!! pick-f32: expected no soft f64"; "$NM" "$pick32" | awk '{ print $NF }' | grep -E "$SOFT_F64"; status=1; }

# Where the march-only f32 firmware's bytes go (opt "s"), by the kernel function they were inlined from.
echo "march-f32 .text (opt \"s\") by kernel function (inlined code included):"
OBJDUMP=$OBJDUMP ./text-by-function.sh "$march32" 64 | tee march-f32-text.txt
# The pick firmware's too, in the log only (functions of 512 B or more).
echo "pick-f32 .text (opt \"s\") by kernel function, 512 B or more:"
OBJDUMP=$OBJDUMP ./text-by-function.sh "$pick32" 512
# What of the march firmware's kernel code (opt "s") the benchmark's rays execute, and what they never reach (the
# paths for hard cases, errors; no other grid kind is compiled in): from QEMU's execution log, by profile.sh.
# (profile.sh's own output on stderr is the firmware's, already shown above)
if ! split=$(BYTES=1 ./profile.sh march-f32 release-s 1000000 2>/dev/null | awk '$2 == "kernel" { print $1 }' | tr '\n' ' '); then
    echo "!!! march-f32: profile.sh BYTES=1 failed"; status=1
fi
read -r kernel_ran kernel_never <<<"${split:-}"
echo "march-f32 (opt \"s\") kernel code: ${kernel_ran:-?} B ran on the benchmark's rays, ${kernel_never:-?} B never"
# And the march's stack: the frames (opt 3, the build whose stack is measured) of 64 B or more.
echo "march-f32 stack frames (opt 3) of 64 B or more:"
OBJDUMP=$OBJDUMP ./stack-frames.sh "target/$TARGET/release/march-f32" | tee march-f32-all-frames.txt \
    | awk '$1 >= 64' | tee march-f32-frames.txt
# the timed run's closure: the innermost of march_bench's three (per grid, per ray, the run)
C='_$u7b$$u7b$closure$u7d$$u7d$'
closure_frame=$(awk -v f="curvicast_m4f_bench::march_bench::$C::$C::$C" '$2 == f { print $1 }' march-f32-all-frames.txt | head -n 1)

field() { grep -oE "$2 [-0-9.]+" <<<"${OUT[$1]}" | head -n "${3:-1}" | tail -n 1 | awk '{ print $2 }'; }
grid() { grep -E "^m4f-bench $1: grid $2 " <<<"${OUT[$1]}" | grep -oE "$3 [-0-9.]+" | awk '{ print $2 }'; }

empty_s=$(text release-s empty)
empty_z=$(text release-z empty)
empty_3=$(text release empty)
# A march firmware is measured against its workload firmware: the harness plus the benchmark's own breakpoints and
# rays, made by the same driver with no kernel call (lib.rs, `march_workload`).
base() { case $2 in march-f32|march-f64) text "$1" "march-workload-${2#march-}" ;; *) text "$1" empty ;; esac; }
march_s=$(( $(text release-s march-f32) - $(base release-s march-f32) ))
march_z=$(( $(text release-z march-f32) - $(base release-z march-f32) ))
march_s_empty=$(( $(text release-s march-f32) - empty_s ))
per_crossing=$(grid march-f32 both per_crossing)
march_stack=$(field march-f32 march_stack_bytes)
verdict() { if awk -v a="$1" -v b="$2" 'BEGIN { exit !(a <= b) }'; then echo "met"; else echo "not met"; fi; }
{
    echo "### Embedded: the kernel on an emulated Cortex-M4F"
    echo
    echo "| firmware (minus its baseline) | \`.text\` opt \"s\" | \`.text\` opt \"z\" | \`.text\` opt 3 | instructions | stack |"
    echo "|---|---|---|---|---|---|"
    for f in march-f32 march-f64; do
        echo "| $f, 16³ / 32³ / both grids | $(( $(text release-s "$f") - $(base release-s "$f") )) B" \
             "| $(( $(text release-z "$f") - $(base release-z "$f") )) B" \
             "| $(( $(text release "$f") - $(base release "$f") )) B" \
             "| $(grid "$f" '16\^3' per_crossing) / $(grid "$f" '32\^3' per_crossing) / $(grid "$f" both per_crossing) per crossing" \
             "(set-up $(grid "$f" both setup) per ray; $(grid "$f" both rays) rays, $(grid "$f" both crossings) crossings)" \
             "| $(field "$f" march_stack_bytes) B |"
    done
    if grep -q per_pick <<<"${OUT[pick-f32]}"; then
        echo "| pick-f32 | $(( $(text release-s pick-f32) - empty_s )) B | $(( $(text release-z pick-f32) - empty_z )) B" \
             "| $(( $(text release pick-f32) - empty_3 )) B" \
             "| $(field pick-f32 per_pick) per pick ($(field pick-f32 picks) picks, $(field pick-f32 hits) hits) | $(field pick-f32 stack_bytes) B |"
    fi
    cempty_s=$(ctext release-s c-empty)
    cempty_3=$(ctext release c-empty)
    for f in c-march-f32 c-march-next-f32; do
        how="\`curvicast_march_f32_fill\`, batches of 32"
        [[ $f == c-march-next-f32 ]] && how="\`curvicast_march_f32_next\`"
        echo "| $f (C: $how), 16³ / 32³ / both grids | $(( $(ctext release-s "$f") - cempty_s )) B | – | $(( $(ctext release "$f") - cempty_3 )) B" \
             "| $(grid "$f" '16\^3' per_crossing) / $(grid "$f" '32\^3' per_crossing) / $(grid "$f" both per_crossing) per crossing" \
             "(set-up $(grid "$f" both setup) per ray; $(grid "$f" both rays) rays, $(grid "$f" both crossings) crossings)" \
             "| $(field "$f" march_stack_bytes) B |"
    done
    echo "| c-pick-f32 (C) | $(( $(ctext release-s c-pick-f32) - cempty_s )) B | – | $(( $(ctext release c-pick-f32) - cempty_3 )) B" \
         "| $(field c-pick-f32 per_pick) per pick ($(field c-pick-f32 picks) picks, $(field c-pick-f32 hits) hits) | $(field c-pick-f32 stack_bytes) B |"
    echo "| bevel-f32, level $(field bevel-f32 level) ($(field bevel-f32 faces) faces) | $(( $(text release-s bevel-f32) - empty_s )) B" \
         "| $(( $(text release-z bevel-f32) - empty_z )) B" \
         "| $(( $(text release bevel-f32) - empty_3 )) B | $(field bevel-f32 per_bevel) per bevel | $(field bevel-f32 stack_bytes) B |"
    echo
    echo "Emulated Cortex-M4F (QEMU mps2-an386, \`-icount shift=0\`), instructions counted by SysTick:" \
         "calibration $(field empty calibration_instructions) instructions = $(field empty calibration_ticks) ticks" \
         "($(field empty instructions_per_tick) per tick); a delay loop of 2 instructions per iteration measures" \
         "$(field empty loop_per_iteration). Per crossing: least-squares slope over the hitting rays (marginal), with" \
         "its intercept as the set-up per ray. Stack: painted-stack high-water mark of one call, including the" \
         "frame of the closure through which the harness makes it (march-f32: ${closure_frame:-?} B)." \
         "Baselines: the empty firmware (the measuring harness alone) is $empty_s B (opt \"s\") / $empty_z B (opt \"z\") /" \
         "$empty_3 B (opt 3); a march firmware's is its workload firmware (\`march-workload-f32\`, $(text release-s march-workload-f32) B at" \
         "opt \"s\"; \`-f64\`, $(text release-s march-workload-f64) B), the harness plus the benchmark's grid breakpoints and rays made by" \
         "the same driver with no kernel call, so that the difference is the kernel, the libraries it links and the" \
         "lines a user writes to make a grid and a ray and fold a march. Measured against the empty firmware, as" \
         "before that baseline existed, march-f32 is $march_s_empty B at opt \"s\". The opt \"z\" build of march-f32 runs as well (status ok checked)." \
         "The f32 march firmware holds $vsqrt \`vsqrt.f32\` and $softf64 soft double-precision routines, the f32" \
         "pick firmware $pick_softf64." \
         "$(grep -oE 'checked [0-9]+ mismatches [0-9]+' <<<"${OUT[sqrt-check]}" | sed 's/^/VSQRT.F32 against libm: /')."
    echo
    echo "The C firmwares (\`kernel/ffi/c/firmware\`, arm-none-eabi-gcc -O2 / -Os against \`libcurvicast.a\` at" \
         "opt 3 / \"s\") run the Rust firmwares' workloads (the same rays) through the C interface, minus their own" \
         "empty firmware ($cempty_s B at -Os). The C boundary costs" \
         "$(awk -v c="$(grid c-march-f32 both per_crossing)" -v r="$per_crossing" 'BEGIN { printf "%+.1f %%", 100 * (c / r - 1) }')" \
         "per crossing in batches (fill) and" \
         "$(awk -v c="$(grid c-march-next-f32 both per_crossing)" -v r="$per_crossing" 'BEGIN { printf "%+.1f %%", 100 * (c / r - 1) }')" \
         "one crossing per call (next) against march-f32's fold, and" \
         "$(awk -v c="$(field c-pick-f32 per_pick)" -v r="$(field pick-f32 per_pick)" 'BEGIN { printf "%+.1f %%", 100 * (c / r - 1) }')" \
         "per pick against pick-f32 (whose storage has no paging and whose picker holds 4 zones; the C picker" \
         "holds 32 and pages); \`.text\` at opt \"s\" $(( $(ctext release-s c-march-f32) - cempty_s - march_s_empty )) B" \
         "more for the march (both minus their empty firmwares) and $(( $(ctext release-s c-pick-f32) - cempty_s - $(text release-s pick-f32) + empty_s )) B" \
         "more for the pick, of which the libraries the C harness does not share with the kernel (compiler-builtins'" \
         "memcpy and 64-bit division, in the Rust empty firmware already) are part."
    echo
    echo "Targets for f32 marching: at most 150 instructions per crossing ($per_crossing on both grids:" \
         "$(verdict "$per_crossing" 150)); march-only firmware at most 12 KiB of \`.text\` at opt \"s\" or smaller" \
         "($march_s B at opt \"s\", $march_z B at opt \"z\": $(verdict "$(( march_s < march_z ? march_s : march_z ))" 12288));" \
         "one march's stack at most 1 KiB ($march_stack B:" \
         "$(verdict "$march_stack" 1024)). Of the kernel's code in the march-f32 firmware at opt \"s\"," \
         "${kernel_ran:-?} B ran on the benchmark's rays and ${kernel_never:-?} B never did: the paths for what" \
         "these rays do not meet (rays through the centre or along the z axis, repairs near the axis, errors," \
         "rays that end near the z axis; \`BYTES=1 ./profile.sh march-f32 release-s\` by function). docs/performance.md's \"How far the" \
         "targets are\" and docs/embedded.md's \"The M4F firmwares\" give the floor of the instructions per crossing, measured."
    echo
    echo "Where the march-f32 firmware's \`.text\` goes (opt \"s\"; each instruction charged to the outermost kernel" \
         "function it was inlined from, by \`text-by-function.sh\`; functions of 256 B or more):"
    echo
    echo "| bytes | function |"
    echo "|---:|---|"
    awk '$1 >= 256 && $2 !~ /^\[/ && $2 != "kernel" && $2 != "libraries" && $2 != "firmware" { b = $1; $1 = ""; sub(/^ /, ""); printf "| %d | `%s` |\n", b, $0 }' march-f32-text.txt
    kernel=$(awk '$2 == "kernel" { print $1 }' march-f32-text.txt)
    echo "| $kernel | the kernel, all of its functions |"
    echo "| $(( march_s - kernel )) | the rest beyond the baseline: libraries (libm, compiler-builtins) and the firmware's own code (making the grid and the rays, the fold over the crossings) |"
    echo
    echo "The march's stack by frame (opt 3, from each function's prologue by \`stack-frames.sh\`; a frame holds" \
         "what was inlined into it): the firmware's \`march_once\` holds the \`SerialMarch\` itself, and the per-ray" \
         "set-up (\`event::setup\`, kept out of line) adds its frame below it while it runs;" \
         "$(awk '$2 ~ /march_once|curvicast::/ { b = $1; $1 = ""; sub(/^ /, ""); printf "%s`%s` %d B", sep, $0, b; sep = ", " }' march-f32-frames.txt)."
} > embedded.md
rm -f march-f32-text.txt march-f32-frames.txt march-f32-all-frames.txt
echo
cat embedded.md
exit $status
