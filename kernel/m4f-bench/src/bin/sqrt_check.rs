//! `curvicast_arm_sqrt::sqrtf` (the FPU's `VSQRT.F32`) against libm's software `sqrtf`, bit for bit: the
//! special values (±0, ±∞, NaN, negatives, the smallest and largest subnormals and normals) and 2²⁰ bit patterns
//! spread over every sign and binade (the pattern `i << 12` with pseudo-random low bits). NaN results must both
//! be NaN. The fast-math scalar `F32Fast`, whose square root on this target is the same instruction, is checked
//! against it on the same inputs. Prints the number of inputs checked and of mismatches.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use curvicast::Real;
use curvicast::real::F32Fast;
use curvicast_m4f_bench::{Out, finish};

/// Same bits, or both NaN: the instruction and libm, and the instruction and `F32Fast`'s square root.
fn agree(x: f32) -> bool {
    let same = |a: f32, b: f32| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    let hw = curvicast_arm_sqrt::sqrtf(x);
    same(hw, libm::sqrtf(x)) && same(hw, F32Fast(x).sqrt().0)
}

#[entry]
fn main() -> ! {
    let mut out = Out::new("sqrt-check");
    let special = [
        0.0_f32,
        -0.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -1.0,
        -f32::MIN_POSITIVE,
        f32::from_bits(1),
        f32::from_bits(0x007F_FFFF),
        f32::MIN_POSITIVE,
        f32::MAX,
        1.0,
        2.0,
        4.0,
    ];
    let mut checked = 0u64;
    let mut mismatches = 0u64;
    for x in special {
        checked += 1;
        if !agree(x) {
            mismatches += 1;
        }
    }
    for i in 0..(1u32 << 20) {
        let bits = (i << 12) | (i.wrapping_mul(0x9E37_79B1) >> 20);
        checked += 1;
        if !agree(f32::from_bits(bits)) {
            mismatches += 1;
        }
    }
    // A value must survive in a register the instruction borrows: the sum below keeps partial results live
    // across every call.
    let mut acc = 0.0_f32;
    let mut expect = 0.0_f32;
    for k in 1..=64u16 {
        let x = f32::from(k);
        acc += curvicast_arm_sqrt::sqrtf(x * x) * 0.5 + x;
        expect += x * 0.5 + x;
    }
    checked += 1;
    if acc.to_bits() != expect.to_bits() {
        mismatches += 1;
    }
    out.str("checked ")
        .num(checked)
        .str(" mismatches ")
        .num(mismatches);
    out.flush();
    finish(&mut out, mismatches == 0)
}
