#!/usr/bin/env bash
# Builds the C firmwares (main.c: c-empty, c-march-f32, c-march-next-f32, c-pick-f32) with arm-none-eabi-gcc against the
# thumbv7em-none-eabihf libcurvicast.a, twice, as kernel/m4f-bench builds the Rust ones: the static library's
# `release` profile (opt-level 3) with -O2 C for the instruction counts, its `release-s` profile (opt-level
# "s") with -Os C for the code sizes. The ELFs go to kernel/ffi/staticlib/target/c-firmware/<profile>/.
# The link uses --gc-sections and leaves curvicast_panic_path_is_reachable undefined, so it fails if any
# function the firmware calls can reach a panic; c-panic-proof (linked, never run) references every function of
# the header.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
HERE=$(pwd)
LIB=$HERE/../../staticlib
TARGET=thumbv7em-none-eabihf
(cd "$LIB" && cargo build --quiet --release --target $TARGET && cargo build --quiet --profile release-s --target $TARGET)
CFLAGS=(-std=gnu99 -Wall -Wextra -Werror -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16
        -ffunction-sections -fdata-sections -g -I"$HERE/../../include")
LDFLAGS=(-nostartfiles -T"$HERE/link.ld" -Wl,--gc-sections -Wl,--no-warn-execstack --specs=nano.specs)
for profile in release release-s; do
    out=$LIB/target/c-firmware/$profile
    mkdir -p "$out"
    opt=-O2
    [[ $profile == release-s ]] && opt=-Os
    for fw in c-empty c-march-f32 c-march-next-f32 c-pick-f32; do
        def=()
        [[ $fw == c-march-f32 ]] && def=(-DBENCH_MARCH)
        [[ $fw == c-march-next-f32 ]] && def=(-DBENCH_MARCH -DMARCH_NEXT)
        [[ $fw == c-pick-f32 ]] && def=(-DBENCH_PICK)
        arm-none-eabi-gcc "${CFLAGS[@]}" $opt "${def[@]}" main.c harness.c \
            "$LIB/target/$TARGET/$profile/libcurvicast.a" "${LDFLAGS[@]}" -o "$out/$fw"
    done
done
# The panic-path proof on the Cortex-M4F for every function of the header, not only those the firmwares call:
# a program that references each of them (all-functions.sh), linked as the firmwares are, at both profiles.
# It is never run; that it links is the proof.
gen=$(mktemp -d)
trap 'rm -rf "$gen"' EXIT
bash ../all-functions.sh "$HERE/../../include/curvicast.h" >"$gen/all_functions.h"
printf '%s\n' '#include "curvicast.h"' '#include "all_functions.h"' \
    'int main(void) { unsigned i; for (i = 0; i < sizeof curvicast_all_functions / sizeof curvicast_all_functions[0]; i++) if (!curvicast_all_functions[i]) return 1; return 0; }' \
    >"$gen/proof.c"
for profile in release release-s; do
    arm-none-eabi-gcc "${CFLAGS[@]}" -I"$gen" -Os "$gen/proof.c" harness.c \
        "$LIB/target/$TARGET/$profile/libcurvicast.a" "${LDFLAGS[@]}" -o "$LIB/target/c-firmware/$profile/c-panic-proof"
done
echo "built: $(ls "$LIB/target/c-firmware/release" | tr '\n' ' ')"
echo "panic-path proof (Cortex-M4F link): $(grep -c '(curvicast_fn)' "$gen/all_functions.h") functions, none can panic"
