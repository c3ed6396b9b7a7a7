//! The single-precision square root of a hard-float ARM core, `VSQRT.F32`, behind a safe function.
//!
//! The curvicast kernel is `#![forbid(unsafe_code)]`, and on a Cortex-M4F it spends a square root per radius or
//! zenith crossing (Hannasch, ch. 4: one square root per sphere or cone crossing). Stable Rust offers no
//! `no_std` square root (`f32::sqrt` lives in `std`; `core::f32::math::sqrt` is unstable), and libm has no
//! 32-bit ARM path, so `libm::sqrtf` is its portable software routine there. This crate holds the one
//! instruction instead, so that the kernel's own code stays free of `unsafe`.
//!
//! `sqrtf` exists only where the target uses the hard-float ABI (`target_abi = "eabihf"`: every such ARM
//! target has a VFP unit with at least single precision, whose `VSQRT.F32` is IEEE 754's correctly rounded
//! square root). Elsewhere the crate is empty and the kernel keeps `libm::sqrtf`, which is correctly rounded
//! too, so both give the same bits for every input (NaN payloads aside).
//!
//! **The unsafe block.** Stable Rust 1.95 does not let inline assembly name a single-precision register on
//! `thumbv7em-none-eabihf` (the `sreg` register class requires the `vfp2` target feature, which that target,
//! having no double precision, does not enable), so the operand travels in a core register: the block saves
//! `s0` in a core register, moves the operand into `s0`, takes the square root there, moves the result out and
//! restores `s0`. Every register it writes is either declared as an output or restored before it ends; it
//! touches no memory and no stack. It changes only the FPU's cumulative exception flags (inexact, invalid),
//! which Rust's floating-point semantics do not observe (every `+ - * /` sets them too), so `preserves_flags` is
//! not claimed and the compiler treats the flags as clobbered. The result is correctly rounded in the FPU's
//! default mode (round to nearest, no flush-to-zero), the mode the rest of the kernel's arithmetic assumes.
//!
//! Tested on the emulated Cortex-M4F by the `sqrt-check` firmware of `kernel/m4f-bench`, which compares it bit
//! for bit with `libm::sqrtf` on the special values and on a sweep of bit patterns covering every binade.

#![no_std]
#![deny(unsafe_code)]

/// The correctly rounded square root of `x` by the FPU's `VSQRT.F32` (hard-float ARM targets only): the same
/// value as `libm::sqrtf(x)` for every `x` (`-0` for `-0`, `+∞` for `+∞`, NaN for NaN and for `x < 0`).
///
/// Costs six moves between core and floating-point registers around the instruction (see the crate docs for
/// why), still far below a software square root.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[inline]
pub fn sqrtf(x: f32) -> f32 {
    let bits: u32;
    // SAFETY: the instructions read and write only `s0` and the two core registers given as operands: `s0` is
    // saved in `save` (declared as an output, so the compiler keeps nothing there) and restored before the block
    // ends, so no register the compiler did not allocate to the block changes. No memory or stack is touched
    // (`nomem`, `nostack`), and the output depends only on the input (`pure`). VSQRT.F32 exists on every
    // hard-float ARM target (VFPv2 and later, single precision included), which is what the `cfg` above selects.
    #[allow(unsafe_code)]
    unsafe {
        core::arch::asm!(
            "vmov {save}, s0",
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {x}, s0",
            "vmov s0, {save}",
            x = inout(reg) x.to_bits() => bits,
            save = out(reg) _,
            options(pure, nomem, nostack),
        );
    }
    f32::from_bits(bits)
}
