//! The scalar layer: one trait, [`Real`], implemented for `f64`, `f32` and (with the `fast-math` feature)
//! `F32Fast`.
//!
//! Every algorithm in the kernel is generic over [`Real`]. The math backend is chosen by the scalar type, so one
//! program can run the same traversal in several modes side by side (the report does exactly that):
//!
//! | scalar | arithmetic | `sqrt` | `sin`, `cos`, `atan2` |
//! | --- | --- | --- | --- |
//! | `f64` | IEEE binary64 | `libm::sqrt` (correctly rounded; a hardware instruction where one exists) | `libm` |
//! | `f32` | IEEE binary32 | correctly rounded: the FPU's `VSQRT.F32` on hard-float ARM, else `libm::sqrtf` | `sin`, `cos`: in `f32` (below, ≤ 1.04 ulp); `atan2`: `libm` |
//! | `F32Fast` | IEEE binary32 | the FPU's `VSQRT.F32` on hard-float ARM (correctly rounded, as `f32`); elsewhere `micromath`'s inverse-sqrt estimate + 3 multiply-only Newton steps | as `f32` (see below) |
//!
//! Arithmetic (`+ - * /`) is always the hardware's correctly rounded IEEE operation; only the library functions
//! differ. The error that the fast backend adds is measured by the host oracle, not assumed.
//!
//! The `f32` square root on a hard-float ARM core (a Cortex-M4F) is the FPU's `VSQRT.F32`: stable Rust has no
//! `no_std` square root (`f32::sqrt` is in `std`, `core::f32::math::sqrt` is unstable) and libm has no 32-bit
//! ARM path (its `sqrtf` is software there), so the instruction lives behind a safe function in the tiny crate
//! `curvicast-arm-sqrt`, a dependency on those targets only; this crate stays `#![forbid(unsafe_code)]`. Both
//! routes are IEEE's correctly rounded square root, so results do not depend on the target.
//!
//! Why the fast `sqrt` is refined: micromath's bare estimate is 5 % off, which would make every crossing useless.
//! The estimate plus three Newton steps costs about ten multiplications and no division, and is within a few
//! ulps. Where the FPU has a square root that stable `no_std` Rust can reach (hard-float ARM, through
//! `curvicast-arm-sqrt`), `F32Fast` uses it instead: on a Cortex-M4F `VSQRT.F32` takes 14 cycles, fewer than the
//! estimate and its Newton steps, and is exact, so there `F32Fast`'s square root is `f32`'s bit for bit (checked
//! on the emulated Cortex-M4F by `kernel/m4f-bench`'s `sqrt-check`) and its errors are `f32`'s; the report's
//! `f32-fast` figures are measured on the host, with the micromath route.
//!
//! Why the `f32` sine and cosine are computed here: libm's `sinf` and `cosf` compute in `f64` internally, which on a
//! single-precision FPU (a Cortex-M4F) is software and brings about 9 KB of code, soft double precision included,
//! into every `f32` firmware that builds a grid; the `f32` routine below (Cody–Waite reduction, Taylor
//! polynomials) has a measured bound of 1.04 ulp, where libm's is about half an ulp.
//!
//! Why the fast backend keeps the exact `sin`, `cos` and `atan2`: the kernel calls them only while precomputing
//! (grid breakpoints, surfaces, geodetic conversions of a hit), never per crossing, so an approximation there
//! would buy no speed and would move every cone and half-plane built from an angle by micromath's ~1e-3 error
//! (the host oracle measured exactly that before this choice). The per-crossing library function is `sqrt`.
//!
//! ```
//! use curvicast::real::Real;
//! fn hypot3<T: Real>(x: T, y: T, z: T) -> T {
//!     (x * x + y * y + z * z).sqrt()
//! }
//! assert_eq!(hypot3(2.0_f64, 3.0, 6.0), 7.0);
//! assert_eq!(hypot3(2.0_f32, 3.0, 6.0), 7.0);
//! ```

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// A real scalar: `f64`, `f32`, or `F32Fast` (feature `fast-math`).
///
/// The trait carries exactly what the kernel needs. Its functions never panic; they follow IEEE semantics for
/// NaN and infinities, like the primitive types.
pub trait Real:
    Copy
    + Debug
    + Display
    + Default
    + PartialEq
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + Send
    + Sync
    + 'static
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 2.
    const TWO: Self;
    /// 1/2.
    const HALF: Self;
    /// π.
    const PI: Self;
    /// π/2, rounded to nearest.
    const FRAC_PI_2: Self;
    /// Machine epsilon (the gap between 1 and the next representable number).
    const EPSILON: Self;
    /// The largest finite value.
    const MAX: Self;
    /// The smallest positive normal value.
    const MIN_POSITIVE: Self;
    /// +∞.
    const INFINITY: Self;
    /// −∞.
    const NEG_INFINITY: Self;
    /// A quiet NaN.
    const NAN: Self;
    /// Number of significand bits, including the implicit one (53 or 24).
    const MANTISSA_DIGITS: u32;
    /// A short name of the mode for reports: `"f64"`, `"f32"`, `"f32-fast"`.
    const NAME: &'static str;

    /// The nearest value to `x` (rounding to nearest).
    fn from_f64(x: f64) -> Self;
    /// The value as `f64` (exact for every implementor).
    fn to_f64(self) -> f64;
    /// The nearest value to the `f32` `x` (exact for `f64`, `f32` and `F32Fast`). Lets a constant be given to
    /// a single-precision scalar without a conversion from `f64`, which on a single-precision FPU is software.
    #[inline]
    fn from_f32(x: f32) -> Self {
        Self::from_f64(f64::from(x))
    }
    /// The nearest value to `n`.
    fn from_i32(n: i32) -> Self;

    /// Square root (see the module docs for which backend).
    fn sqrt(self) -> Self;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// Four-quadrant arctangent of `self / x`.
    fn atan2(self, x: Self) -> Self;
    /// `self * a + b` with a single rounding where the backend provides it (libm's `fma`), else two.
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// `self * 2^k`, exact unless the result overflows or is subnormal.
    fn scalbn(self, k: i32) -> Self;
    /// The binary exponent: `floor(log2(|self|))` for finite non-zero values; see `libm::ilogb` otherwise.
    fn ilogb(self) -> i32;
    /// For a positive normal number below the top binade, `(ilogb(self), 2^-ilogb(self))` (both powers of two
    /// are then normal numbers, so a multiplication by either is exact unless its result leaves the normal
    /// range — and then it is what `scalbn` gives, one correctly rounded product); `None` for anything else.
    /// Read from the bits for the primitive types (no libm call).
    #[inline]
    fn binade(self) -> Option<(i32, Self)> {
        if !(self >= Self::MIN_POSITIVE && self < Self::MAX) {
            return None;
        }
        let e = self.ilogb();
        let inv = Self::ONE.scalbn(e.saturating_neg());
        (inv >= Self::MIN_POSITIVE && inv.is_finite() && e != Self::MAX.ilogb()).then_some((e, inv))
    }
    /// The nearest integer, halfway cases away from zero (libm's `round`; `f32` and `F32Fast`: `roundf`, in
    /// `f32` arithmetic).
    #[inline]
    fn round(self) -> Self {
        Self::from_f64(libm::round(self.to_f64()))
    }
    /// The real cube root: libm's `cbrt` for `f64` (and, rounding through `f64`, for other implementors);
    /// for `f32` and `F32Fast` a routine in `f32` arithmetic within 1 ulp (`cbrt_f32`), because libm's `cbrtf`
    /// computes in `f64`.
    #[inline]
    fn cbrt(self) -> Self {
        Self::from_f64(libm::cbrt(self.to_f64()))
    }

    /// Absolute value.
    #[inline]
    fn abs(self) -> Self {
        if self < Self::ZERO { -self } else { self }
    }
    /// True for neither NaN nor ±∞.
    #[inline]
    fn is_finite(self) -> bool {
        self.abs() < Self::INFINITY
    }
    /// True for NaN.
    #[inline]
    #[allow(clippy::eq_op)]
    fn is_nan(self) -> bool {
        self != self
    }
    /// The smaller of two values; if one is NaN, the other.
    #[inline]
    fn min(self, other: Self) -> Self {
        if other < self || self.is_nan() {
            other
        } else {
            self
        }
    }
    /// The larger of two values; if one is NaN, the other.
    #[cfg_attr(curvicast_small_code, inline(never))]
    #[cfg_attr(not(curvicast_small_code), inline)]
    fn max(self, other: Self) -> Self {
        if other > self || self.is_nan() {
            other
        } else {
            self
        }
    }
    /// `|self|` with the sign of `sign` (a zero `sign` counts as positive).
    #[inline]
    fn with_sign_of(self, sign: Self) -> Self {
        if sign < Self::ZERO {
            -self.abs()
        } else {
            self.abs()
        }
    }
    /// The square.
    #[inline]
    fn sq(self) -> Self {
        self * self
    }
}

macro_rules! impl_real_prim {
    ($t:ty, $name:literal, $sqrt:path, $sin:path, $cos:path, $atan2:path, $fma:path, $scalbn:path, $ilogb:path,
     $round:path, $cbrt:path, $bits:ty, $fraction_bits:literal, $bias:literal) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const TWO: Self = 2.0;
            const HALF: Self = 0.5;
            const PI: Self = core::f64::consts::PI as $t;
            const FRAC_PI_2: Self = core::f64::consts::FRAC_PI_2 as $t;
            const EPSILON: Self = <$t>::EPSILON;
            const MAX: Self = <$t>::MAX;
            const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
            const INFINITY: Self = <$t>::INFINITY;
            const NEG_INFINITY: Self = <$t>::NEG_INFINITY;
            const NAN: Self = <$t>::NAN;
            const MANTISSA_DIGITS: u32 = <$t>::MANTISSA_DIGITS;
            const NAME: &'static str = $name;

            #[inline]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn from_i32(n: i32) -> Self {
                n as $t
            }
            #[inline]
            fn from_f32(x: f32) -> Self {
                x as $t
            }
            #[inline]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            #[inline]
            fn sin(self) -> Self {
                $sin(self)
            }
            #[inline]
            fn cos(self) -> Self {
                $cos(self)
            }
            #[inline]
            fn atan2(self, x: Self) -> Self {
                $atan2(self, x)
            }
            #[inline]
            fn mul_add(self, a: Self, b: Self) -> Self {
                $fma(self, a, b)
            }
            #[inline]
            fn scalbn(self, k: i32) -> Self {
                $scalbn(self, k)
            }
            #[inline]
            fn ilogb(self) -> i32 {
                $ilogb(self)
            }
            #[inline]
            fn binade(self) -> Option<(i32, Self)> {
                // the biased exponent of a positive number (a negative one has the sign bit above it)
                let biased = self.to_bits() >> $fraction_bits;
                let top: $bits = 2 * $bias; // the biased exponent of the top binade, whose 2^-e is subnormal
                if biased == 0 || biased >= top {
                    return None;
                }
                let e = i32::try_from(biased).ok()?.wrapping_sub($bias);
                Some((
                    e,
                    <$t>::from_bits(top.wrapping_sub(biased) << $fraction_bits),
                ))
            }
            #[inline]
            fn round(self) -> Self {
                $round(self)
            }
            #[inline]
            fn cbrt(self) -> Self {
                $cbrt(self)
            }
            #[inline]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline]
            fn is_nan(self) -> bool {
                <$t>::is_nan(self)
            }
        }
    };
}

impl_real_prim!(
    f64,
    "f64",
    libm::sqrt,
    libm::sin,
    libm::cos,
    libm::atan2,
    libm::fma,
    libm::scalbn,
    libm::ilogb,
    libm::round,
    libm::cbrt,
    u64,
    52,
    1023
);
/// The `f32` square root: the FPU's `VSQRT.F32` on hard-float ARM (a Cortex-M4F), through the one-instruction
/// crate `curvicast-arm-sqrt` that holds its `unsafe` block; libm's elsewhere. Both are correctly rounded, so
/// the kernel's results are the same bits on every target.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
use curvicast_arm_sqrt::sqrtf as sqrt_f32;
#[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
use libm::sqrtf as sqrt_f32;

impl_real_prim!(
    f32,
    "f32",
    sqrt_f32,
    sin_f32,
    cos_f32,
    libm::atan2f,
    libm::fmaf,
    libm::scalbnf,
    libm::ilogbf,
    libm::roundf,
    cbrt_f32,
    u32,
    23,
    127
);

/// Kahan's first guess at a cube root from the bits of `x`: the biased exponent and significand, read as one
/// integer, divided by three, plus this bias (`(127 − 127/3 − 0.03306235651) · 2²³`), give `∛x` to about 5 bits.
const CBRT_GUESS_BIAS: u32 = 709_958_130;

/// The real cube root in `f32` arithmetic (libm's `cbrtf` computes in `f64`, software on a single-precision
/// FPU): Kahan's 5-bit guess from the bits, then three Newton steps `y ← y − (y − x/y²)/3` (5 → 10 → 20 → full
/// precision; the last step's roundings leave at most 1 ulp: measured 0.73 ulp against libm's `f64` `cbrt` on
/// 2¹⁸ inputs over every binade by the test `cbrt_f32_within_1_ulp_on_a_sweep`). Subnormal `x` are scaled by 2²⁴
/// first. ±0, ±∞ and NaN give themselves.
fn cbrt_f32(x: f32) -> f32 {
    if x == 0.0 || !x.is_finite() {
        return x + x;
    }
    let a = x.abs();
    let (a, unscale) = if a < f32::MIN_POSITIVE {
        (a * 16_777_216.0, 1.0 / 256.0)
    } else {
        (a, 1.0)
    };
    // No overflow: a.to_bits() < 2³¹, so the sum stays below 2³⁰ + 2³⁰.
    let mut y = f32::from_bits((a.to_bits() / 3).wrapping_add(CBRT_GUESS_BIAS));
    for _ in 0..3 {
        y -= (y - a / (y * y)) * (1.0 / 3.0);
    }
    (y * unscale).copysign(x)
}

/// `π/2 = C1 + C2 + C3 + C4 + O(2⁻⁶⁸)`: `C1`, `C2` and `C3` have 12 significant bits, so `k·C1`, `k·C2` and
/// `k·C3` are exact for `|k| < 2¹²` (Cody and Waite's reduction, carried out in `f32`). Given by their bits, so
/// that the values are exactly these; the decimal values beside them are rounded.
const PIO2_C1: f32 = f32::from_bits(0x3FC9_1000); // 1.570801
const PIO2_C2: f32 = f32::from_bits(0xB695_7000); // -4.453585e-6
const PIO2_C3: f32 = f32::from_bits(0xB06F_5000); // -8.706138e-10
const PIO2_C4: f32 = f32::from_bits(0x298C_234C); // 6.223372e-14
/// Above this `|x|` the quadrant `k = round(2x/π)` could reach 2¹², where the products stop being exact: such
/// `x` are first reduced exactly modulo `f32`'s 2π.
const EXACT_REDUCTION_BELOW: f32 = 6400.0;
/// `1.5 · 2²³`: `(y + M) − M` is `y` rounded to the nearest integer for `|y| < 2²²`.
const ROUND_MAGIC: f32 = 12_582_912.0;

/// `a + b` as the rounded sum and its exact rounding error (Knuth's two-sum).
#[inline]
fn two_sum_f32(a: f32, b: f32) -> (f32, f32) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `x mod 2π` for `f32`'s 2π, exactly and with the sign of `x` (what `fmodf(x, TAU)` gives), for finite `x`
/// (`sin_cos_f32` calls it for `|x| >= 6400`): binary long division, one subtraction of `2π·2^j` per quotient bit from the largest `j` with
/// `2π·2^j <= |x|` down to 0. Each subtraction is exact (Sterbenz: the remainder `r` stays below `2·2π·2^j`, so
/// `2π·2^j <= r` implies `r/2 < 2π·2^j <= r`), and so is each halving. In `f32` arithmetic: libm's `fmodf` works
/// on the integers of both operands and is 224 B more code in the M4F firmware, so a build for size
/// (`cfg(curvicast_small_code)`) uses this.
fn rem_tau_f32(x: f32) -> f32 {
    let tau = core::f32::consts::TAU;
    let mut r = x.abs();
    // 2π·2^j with the biased exponent of r (j = 0 below 4, where r < 2π·2 already), then halved to at most r:
    // the first `d` is in (r/2, r] or (r, 2r), and `r < 2d` holds at every step below; at most 126 steps
    let j = (r.to_bits() >> 23).saturating_sub(tau.to_bits() >> 23);
    let mut d = f32::from_bits(tau.to_bits().wrapping_add(j << 23));
    for _ in 0..=j {
        if d <= r {
            r -= d;
        }
        d *= 0.5;
    }
    r.copysign(x)
}

/// `(sin x, cos x)` in `f32` arithmetic only, for the `f32` scalar (Hannasch §2 needs `(cos, sin)` of every θ and
/// φ breakpoint; libm's `sinf` and `cosf` compute in `f64`, which on a single-precision FPU is software and
/// brings the soft double-precision routines into every `f32` firmware that builds a grid).
///
/// Reduction: `k = round(2x/π)` and `r = x − k π/2 = r_hi + r_lo` with the four-part `π/2` above (Cody–Waite;
/// the three exact products are subtracted with their rounding errors kept, so `r` carries about 48 bits),
/// `|r| ≤ π/4`; then the Taylor polynomials of `sin r` to `r⁹` and of `cos r` to `r¹⁰` (truncation below 0.05 ulp
/// at `π/4`) with `r_lo` added as the first-order term, and the quadrant `k mod 4`.
///
/// Error bound for `|x| < 6400` (every breakpoint of a grid, every geodetic angle): at most 1.04 ulp, measured
/// against the double-precision `sin` and `cos` over every `f32` in `[0, 6400)` (the ignored test
/// `sin_cos_f32_exhaustive_error`; the function is odd/even in `x`). `|x| >= 6400` is first reduced modulo `f32`'s
/// 2π exactly (`fmodf`; [`rem_tau_f32`] in a build for size), so the result is the sine and cosine of a point within half an
/// ulp of `x` (`f32`'s 2π is 2π(1 − 2.8e-8)), on the unit circle to a few ulps: all that an `f32` angle that large
/// determines. NaN and ±∞ give NaN; ±0 gives (±0, 1).
fn sin_cos_f32(x: f32) -> (f32, f32) {
    if !x.is_finite() {
        return (f32::NAN, f32::NAN);
    }
    if x == 0.0 {
        return (x, 1.0);
    }
    let x = if x.abs() < EXACT_REDUCTION_BELOW {
        x
    } else if cfg!(curvicast_small_code) {
        rem_tau_f32(x)
    } else {
        // the same bits; at opt 3 `rem_tau_f32` in place of libm's (inlined) `fmodf` made every call dearer
        // (0.6 % more instructions per terrain pick on the M4F, which computes sines per pick)
        libm::fmodf(x, core::f32::consts::TAU)
    };
    let k = (x * core::f32::consts::FRAC_2_PI + ROUND_MAGIC) - ROUND_MAGIC;
    // x − k·C1 is exact (Sterbenz); k·C2 and k·C3 are exact and subtracted with their rounding errors kept.
    let (a, ea) = two_sum_f32(x - k * PIO2_C1, -(k * PIO2_C2));
    let (r, eb) = two_sum_f32(a, -(k * PIO2_C3));
    let r_lo = (ea + eb) - k * PIO2_C4;
    let w = r * r;
    let sin_r = r
        + (r_lo
            + r * w
                * (-1.0 / 6.0 + w * (1.0 / 120.0 + w * (-1.0 / 5040.0 + w * (1.0 / 362_880.0)))));
    // cos r = 1 − r²/2 + r⁴ Q(r²): the leading terms carry the result, so r² is formed exactly (Dekker's
    // product: r = r₁ + r₂ with 12-bit halves) and 1 − w/2 with its rounding error kept.
    let split = r * 4097.0;
    let r1 = split - (split - r);
    let r2 = r - r1;
    let w_lo = ((r1 * r1 - w) + 2.0 * r1 * r2) + r2 * r2;
    let (c, ec) = two_sum_f32(1.0, -0.5 * w);
    let cos_r = c
        + (ec - 0.5 * w_lo - r * r_lo
            + w * w
                * (1.0 / 24.0
                    + w * (-1.0 / 720.0 + w * (1.0 / 40_320.0 + w * (-1.0 / 3_628_800.0)))));
    // |k| <= 4074 here, so the conversion is exact and `& 3` is k mod 4 (two's complement).
    match (k as i32) & 3 {
        0 => (sin_r, cos_r),
        1 => (cos_r, -sin_r),
        2 => (-sin_r, -cos_r),
        _ => (-cos_r, sin_r),
    }
}

/// The `f32` sine ([`sin_cos_f32`]).
#[inline]
fn sin_f32(x: f32) -> f32 {
    sin_cos_f32(x).0
}

/// The `f32` cosine ([`sin_cos_f32`]).
#[inline]
fn cos_f32(x: f32) -> f32 {
    sin_cos_f32(x).1
}

/// Single precision with the fast math backend: IEEE `f32` arithmetic and a division-free `sqrt` built on
/// micromath's estimate (the FPU's `VSQRT.F32` on hard-float ARM, which is both exact and faster there); `sin`,
/// `cos` (the `f32` backend's) and `atan2` (libm's), used in precomputation only, are exact (available with the
/// `fast-math` feature; see the module docs).
///
/// It is a distinct type so that exact and fast modes can run in one program and be compared.
///
/// ```
/// # #[cfg(feature = "fast-math")] {
/// use curvicast::real::{F32Fast, Real};
/// let two = F32Fast(4.0).sqrt();
/// assert!((two.0 - 2.0).abs() < 1e-6);
/// # }
/// ```
#[cfg(feature = "fast-math")]
#[derive(Debug, Clone, Copy, Default, PartialEq, PartialOrd)]
#[repr(transparent)]
pub struct F32Fast(pub f32);

#[cfg(feature = "fast-math")]
mod fast {
    use super::{F32Fast, Real};
    use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

    impl core::fmt::Display for F32Fast {
        fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
            core::fmt::Display::fmt(&self.0, f)
        }
    }

    macro_rules! binop {
        ($tr:ident, $m:ident, $tra:ident, $ma:ident, $op:tt) => {
            impl $tr for F32Fast {
                type Output = F32Fast;
                #[inline]
                fn $m(self, rhs: F32Fast) -> F32Fast {
                    F32Fast(self.0 $op rhs.0)
                }
            }
            impl $tra for F32Fast {
                #[inline]
                fn $ma(&mut self, rhs: F32Fast) {
                    self.0 = self.0 $op rhs.0;
                }
            }
        };
    }
    binop!(Add, add, AddAssign, add_assign, +);
    binop!(Sub, sub, SubAssign, sub_assign, -);
    binop!(Mul, mul, MulAssign, mul_assign, *);
    binop!(Div, div, DivAssign, div_assign, /);

    impl Neg for F32Fast {
        type Output = F32Fast;
        #[inline]
        fn neg(self) -> F32Fast {
            F32Fast(-self.0)
        }
    }

    /// `F32Fast`'s square root on hard-float ARM: the FPU's `VSQRT.F32` (the `f32` backend's), correctly rounded
    /// and, at 14 cycles on a Cortex-M4F, faster than the estimate and Newton steps below.
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    #[inline]
    fn fast_sqrt(x: f32) -> f32 {
        super::sqrt_f32(x)
    }

    /// `F32Fast`'s square root where the hardware has no single-precision square root reachable from stable
    /// `no_std` Rust: micromath's inverse-square-root estimate (~5 % off) refined by three division-free Newton
    /// steps y ← y (3 − x y²) / 2 (relative error 5e-2 → 4e-3 → 2e-5 → rounding level), then √x = x·y.
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    #[inline]
    fn fast_sqrt(x: f32) -> f32 {
        use micromath::F32;
        if !(x > 0.0) || x == f32::INFINITY {
            return if x == 0.0 || x == f32::INFINITY {
                x
            } else {
                f32::NAN
            };
        }
        let mut y = F32(x).invsqrt().0;
        for _ in 0..3 {
            y = y * (1.5 - 0.5 * x * y * y);
        }
        x * y
    }

    impl Real for F32Fast {
        const ZERO: Self = F32Fast(0.0);
        const ONE: Self = F32Fast(1.0);
        const TWO: Self = F32Fast(2.0);
        const HALF: Self = F32Fast(0.5);
        const PI: Self = F32Fast(core::f32::consts::PI);
        const FRAC_PI_2: Self = F32Fast(core::f32::consts::FRAC_PI_2);
        const EPSILON: Self = F32Fast(f32::EPSILON);
        const MAX: Self = F32Fast(f32::MAX);
        const MIN_POSITIVE: Self = F32Fast(f32::MIN_POSITIVE);
        const INFINITY: Self = F32Fast(f32::INFINITY);
        const NEG_INFINITY: Self = F32Fast(f32::NEG_INFINITY);
        const NAN: Self = F32Fast(f32::NAN);
        const MANTISSA_DIGITS: u32 = f32::MANTISSA_DIGITS;
        const NAME: &'static str = "f32-fast";

        #[inline]
        fn from_f64(x: f64) -> Self {
            F32Fast(x as f32)
        }
        #[inline]
        fn to_f64(self) -> f64 {
            f64::from(self.0)
        }
        #[inline]
        fn from_i32(n: i32) -> Self {
            F32Fast(n as f32)
        }
        #[inline]
        fn sqrt(self) -> Self {
            F32Fast(fast_sqrt(self.0))
        }
        #[inline]
        fn sin(self) -> Self {
            F32Fast(super::sin_f32(self.0))
        }
        #[inline]
        fn cos(self) -> Self {
            F32Fast(super::cos_f32(self.0))
        }
        #[inline]
        fn atan2(self, x: Self) -> Self {
            F32Fast(libm::atan2f(self.0, x.0))
        }
        #[inline]
        fn mul_add(self, a: Self, b: Self) -> Self {
            F32Fast(self.0 * a.0 + b.0)
        }
        #[inline]
        fn scalbn(self, k: i32) -> Self {
            F32Fast(libm::scalbnf(self.0, k))
        }
        #[inline]
        fn ilogb(self) -> i32 {
            libm::ilogbf(self.0)
        }
        #[inline]
        fn binade(self) -> Option<(i32, Self)> {
            self.0.binade().map(|(e, inv)| (e, F32Fast(inv)))
        }
        #[inline]
        fn from_f32(x: f32) -> Self {
            F32Fast(x)
        }
        #[inline]
        fn round(self) -> Self {
            F32Fast(libm::roundf(self.0))
        }
        #[inline]
        fn cbrt(self) -> Self {
            F32Fast(super::cbrt_f32(self.0))
        }
    }

    impl From<f32> for F32Fast {
        #[inline]
        fn from(x: f32) -> Self {
            F32Fast(x)
        }
    }
}

#[cfg(test)]
mod tests;
