//! The scalar layer: one trait, [`Real`], implemented for `f64`, `f32` and (with the `fast-math` feature)
//! `F32Fast`.
//!
//! Every algorithm in the kernel is generic over [`Real`]. The math backend is chosen by the scalar type, so one
//! program can run the same traversal in several modes side by side (the report does exactly that):
//!
//! | scalar | arithmetic | `sqrt` | `sin`, `cos`, `atan2` |
//! | --- | --- | --- | --- |
//! | `f64` | IEEE binary64 | `libm::sqrt` (correctly rounded; a hardware instruction where one exists) | `libm` |
//! | `f32` | IEEE binary32 | `libm::sqrtf` (correctly rounded; software on a Cortex-M4F, see below) | `libm` |
//! | `F32Fast` | IEEE binary32 | `micromath` inverse-sqrt estimate + 3 multiply-only Newton steps | `libm` (see below) |
//!
//! Arithmetic (`+ - * /`) is always the hardware's correctly rounded IEEE operation; only the library functions
//! differ. The error that the fast backend adds is measured by the host oracle, not assumed.
//!
//! Why the fast `sqrt` is refined: micromath's bare estimate is 5 % off, which would make every crossing useless,
//! while stable Rust offers no `no_std` path to the Cortex-M4F's `vsqrt.f32` without `unsafe` (libm's `sqrtf` is
//! software there). The estimate plus three Newton steps costs about ten multiplications and no division, and is
//! within a few ulps.
//!
//! Why the fast backend keeps libm's `sin`, `cos` and `atan2`: the kernel calls them only while precomputing
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
    #[inline]
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
    ($t:ty, $name:literal, $sqrt:path, $sin:path, $cos:path, $atan2:path, $fma:path, $scalbn:path, $ilogb:path) => {
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
    libm::ilogb
);
impl_real_prim!(
    f32,
    "f32",
    libm::sqrtf,
    libm::sinf,
    libm::cosf,
    libm::atan2f,
    libm::fmaf,
    libm::scalbnf,
    libm::ilogbf
);

/// Single precision with the fast math backend: IEEE `f32` arithmetic and a division-free `sqrt` built on
/// micromath's estimate; `sin`, `cos` and `atan2` (precomputation only) stay libm's (available with the
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
    use micromath::F32;

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
            // micromath's inverse-square-root estimate (~5 % off) refined by three division-free Newton steps
            // y ← y (3 − x y²) / 2 (relative error 5e-2 → 4e-3 → 2e-5 → rounding level), then √x = x·y.
            let x = self.0;
            if !(x > 0.0) || x == f32::INFINITY {
                return if x == 0.0 || x == f32::INFINITY {
                    self
                } else {
                    F32Fast(f32::NAN)
                };
            }
            let mut y = F32(x).invsqrt().0;
            for _ in 0..3 {
                y = y * (1.5 - 0.5 * x * y * y);
            }
            F32Fast(x * y)
        }
        #[inline]
        fn sin(self) -> Self {
            F32Fast(libm::sinf(self.0))
        }
        #[inline]
        fn cos(self) -> Self {
            F32Fast(libm::cosf(self.0))
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
    }

    impl From<f32> for F32Fast {
        #[inline]
        fn from(x: f32) -> Self {
            F32Fast(x)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Real;

    fn check_basic<T: Real>() {
        assert_eq!(T::from_f64(9.0).sqrt(), T::from_f64(3.0));
        assert_eq!(T::from_f64(-2.5).abs(), T::from_f64(2.5));
        assert!(!T::INFINITY.is_finite());
        assert!(T::NAN.is_nan());
        assert_eq!(T::ONE.scalbn(10), T::from_f64(1024.0));
        assert_eq!(T::from_f64(1000.0).ilogb(), 9);
        assert_eq!(T::from_f64(3.0).min(T::from_f64(-1.0)), T::from_f64(-1.0));
        assert_eq!(T::from_f64(3.0).max(T::NAN), T::from_f64(3.0));
        assert_eq!(
            T::from_f64(2.0).with_sign_of(T::from_f64(-0.1)),
            T::from_f64(-2.0)
        );
    }

    #[test]
    fn f64_basics() {
        check_basic::<f64>();
        assert_eq!(<f64 as Real>::sqrt(2.0), core::f64::consts::SQRT_2);
    }

    #[test]
    fn f32_basics() {
        check_basic::<f32>();
        assert_eq!(<f32 as Real>::sqrt(2.0), core::f32::consts::SQRT_2);
    }

    #[cfg(feature = "fast-math")]
    #[test]
    fn f32_fast_is_close_not_exact() {
        use super::F32Fast;
        for x in [2.0_f32, 1e-30, 3.5, 1e30, 0.7] {
            let s = F32Fast(x).sqrt().0;
            let e = libm::sqrtf(x);
            assert!((s - e).abs() <= 4.0 * f32::EPSILON * e, "{x}: {s} vs {e}");
        }
        assert_eq!(F32Fast(0.0).sqrt().0, 0.0);
        assert!(F32Fast(-1.0).sqrt().is_nan());
        assert_eq!(F32Fast(1.5) * F32Fast(2.0), F32Fast(3.0));
    }

    #[cfg(feature = "fast-math")]
    #[test]
    fn f32_fast_sin_cos_of_huge_angles_stay_on_the_unit_circle() {
        // Found by the `surfaces` fuzz target: HalfPlane::<F32Fast>::from_azimuth(7.9e28) was rejected as
        // non-finite while micromath's sin/cos (whose argument reduction saturates an i32 cast) were in use.
        use super::F32Fast;
        for x in [4096.5_f32, -5000.0, 1e10, -1.4e10, 7.946_028e28, 3.0e38] {
            let (s, c) = (F32Fast(x).sin().0, F32Fast(x).cos().0);
            // F32Fast's sin and cos are libm's sinf and cosf: bit for bit.
            assert_eq!(s.to_bits(), libm::sinf(x).to_bits(), "sin {x}: {s}");
            assert_eq!(c.to_bits(), libm::cosf(x).to_bits(), "cos {x}: {c}");
        }
        assert!(crate::surface::HalfPlane::from_azimuth(F32Fast(7.946_028e28)).is_ok());
        assert!(F32Fast(f32::INFINITY).sin().is_nan());
    }
}
