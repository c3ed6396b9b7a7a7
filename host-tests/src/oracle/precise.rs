//! The arbitrary-precision setup every oracle shares, written once: astro-float's rounding mode, its constants
//! cache (π and the series the trigonometry needs, one per thread), and numbers in and out of `f64` (exact in,
//! correctly rounded out). Each oracle keeps its own working precision (bits), stated and argued in its docs.

use astro_float::{BigFloat, Consts, RoundingMode, Sign};
use std::cell::RefCell;

/// The rounding mode of every oracle operation: to nearest, ties to even.
pub const RM: RoundingMode = RoundingMode::ToEven;

thread_local! {
    static CONSTS: RefCell<Option<Consts>> = const { RefCell::new(None) };
}

/// `x` at `precision` bits (exact: an `f64` has 53).
pub fn bf(x: f64, precision: usize) -> BigFloat {
    BigFloat::from_f64(x, precision)
}

/// Runs `f` with this thread's constants cache (made on first use).
pub fn with_consts<R>(f: impl FnOnce(&mut Consts) -> R) -> R {
    CONSTS.with(|c| {
        let mut c = c.borrow_mut();
        // Consts::new only fails on allocation failure.
        #[allow(clippy::expect_used)]
        let cc = c.get_or_insert_with(|| Consts::new().expect("astro-float constants cache"));
        f(cc)
    })
}

/// Rounds a high-precision number to the nearest `f64` (ties to even), from its whole mantissa (the bits beyond
/// the top word count as sticky bits), so never twice. Values beyond the `f64` range become infinities; values
/// below the normal range are rounded twice (to 53 bits, then by the multiplication into the subnormal range),
/// which never matters for the magnitudes the oracles return.
pub fn to_f64(x: &BigFloat) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x.is_inf_pos() {
        return f64::INFINITY;
    }
    if x.is_inf_neg() {
        return f64::NEG_INFINITY;
    }
    if x.is_zero() {
        return 0.0;
    }
    let Some((words, _bits, sign, exponent, _inexact)) = x.as_raw_parts() else {
        return f64::NAN;
    };
    // The mantissa is little-endian in words with the most significant bit of the last word set:
    // x = 0.m × 2^exponent.
    let n = words.len();
    let top: u64 = words.get(n.wrapping_sub(1)).copied().unwrap_or(0);
    let sticky_low = words.iter().take(n.saturating_sub(1)).any(|&w| w != 0);
    let kept_bits = 53u32;
    let shift = 64 - kept_bits; // 11
    let mut kept = top >> shift;
    let rem = top & ((1u64 << shift) - 1);
    let half = 1u64 << (shift - 1);
    let round_up = rem > half || (rem == half && (sticky_low || kept & 1 == 1));
    let mut e: i32 = exponent - kept_bits as i32;
    if round_up {
        kept += 1;
        if kept == 1u64 << kept_bits {
            kept >>= 1;
            e += 1;
        }
    }
    let mag = kept as f64 * pow2(e);
    if sign == Sign::Neg { -mag } else { mag }
}

/// 2^e as an f64 product of in-range factors (so that very large or small e saturate gracefully).
fn pow2(mut e: i32) -> f64 {
    let mut r = 1.0f64;
    while e > 1000 {
        r *= 2f64.powi(1000);
        e -= 1000;
    }
    while e < -1000 {
        r *= 2f64.powi(-1000);
        e += 1000;
    }
    r * 2f64.powi(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f64_values_round_trip_and_ties_go_to_even() {
        for x in [
            1.0,
            -2.5,
            6378137.0,
            1e-300,
            3.0e12,
            0.1,
            -123456.789,
            f64::MAX,
            f64::MIN_POSITIVE,
        ] {
            assert_eq!(to_f64(&bf(x, 256)), x);
        }
        // 1 + 2^-53 is a tie between 1 and 1 + 2^-52: to even (1); a bit more rounds up.
        let one = bf(1.0, 256);
        let tie = one.add(&bf(2f64.powi(-53), 256), 256, RM);
        assert_eq!(to_f64(&tie), 1.0);
        let above = tie.add(&bf(2f64.powi(-200), 256), 256, RM);
        assert_eq!(to_f64(&above), 1.0 + f64::EPSILON);
        // A value that a 64-bit intermediate rounding would round twice: 1 + 2^-53 + 2^-70 (to 64 bits it
        // becomes the tie 1 + 2^-53, which rounds to even, 1); rounded once it is above the tie.
        let twice =
            one.add(&bf(2f64.powi(-53), 256), 256, RM)
                .add(&bf(2f64.powi(-70), 256), 256, RM);
        assert_eq!(to_f64(&twice), 1.0 + f64::EPSILON);
    }
}
