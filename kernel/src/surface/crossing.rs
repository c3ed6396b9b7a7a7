//! What every surface shares (the one geometry layer of both traversals): the [`Surface`] trait, its
//! [`Crossings`] with their [`Side`]s, [`SurfaceError`], and the numerically stable quadratic the solvers use.

use crate::ray::Ray;
use crate::real::Real;
use crate::vec3::V3;

/// The side of a surface: `Positive` is where its normal points (where the grid coordinate is larger).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// Inside a spheroid, smaller θ, smaller φ, smaller z.
    Negative,
    /// Outside a spheroid, larger θ, larger φ, larger z.
    Positive,
}

impl Side {
    /// The other side.
    #[inline]
    pub fn flip(self) -> Side {
        match self {
            Side::Negative => Side::Positive,
            Side::Positive => Side::Negative,
        }
    }
    /// `Positive` when `positive` is true.
    #[inline]
    pub fn from_bool(positive: bool) -> Side {
        if positive {
            Side::Positive
        } else {
            Side::Negative
        }
    }
}

/// One crossing of a ray with a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing<T> {
    /// The ray parameter, in the caller's units of `d`.
    pub t: T,
    /// The side the ray enters at `t`.
    pub into: Side,
}

/// At most two crossings, sorted by `t`, all within the ray's interval. Dereferences to a slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossings<T> {
    items: [Crossing<T>; 2],
    len: usize,
}

impl<T: Real> Crossings<T> {
    /// No crossing.
    pub const NONE: Self = Crossings {
        items: [Crossing {
            t: T::ZERO,
            into: Side::Negative,
        }; 2],
        len: 0,
    };

    /// Keeps those of the candidate roots (given in the ray's scaled parameter, see [`Ray::t_from_scaled`]) that
    /// fall in the ray's interval, in order. `roots` must already be sorted by `t`.
    pub(crate) fn from_scaled_roots(ray: &Ray<T>, roots: &[(T, Side)]) -> Self {
        let mut out = Self::NONE;
        for &(s, into) in roots {
            let t = ray.t_from_scaled(s);
            if ray.contains_t(t) {
                if let Some(slot) = out.items.get_mut(out.len) {
                    *slot = Crossing { t, into };
                    out.len = out.len.saturating_add(1);
                }
            }
        }
        out
    }

    /// The crossings as a slice.
    #[inline]
    pub fn as_slice(&self) -> &[Crossing<T>] {
        self.items.get(..self.len).unwrap_or(&[])
    }
}

impl<T> core::ops::Deref for Crossings<T>
where
    T: Real,
{
    type Target = [Crossing<T>];
    #[inline]
    fn deref(&self) -> &[Crossing<T>] {
        self.as_slice()
    }
}

impl<'a, T: Real> IntoIterator for &'a Crossings<T> {
    type Item = &'a Crossing<T>;
    type IntoIter = core::slice::Iter<'a, Crossing<T>>;
    fn into_iter(self) -> Self::IntoIter {
        self.as_slice().iter()
    }
}

/// Why a surface could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceError {
    /// A parameter is NaN or infinite.
    NonFinite,
    /// A radius or axis is not positive, or `a < b` for a spheroid.
    BadAxes,
    /// An angle is outside its range (θ ∉ [0, π]), or a (cos, sin) pair is not a direction.
    AngleOutOfRange,
}

impl core::fmt::Display for SurfaceError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            SurfaceError::NonFinite => "surface parameter is not finite",
            SurfaceError::BadAxes => "spheroid axes must satisfy a >= b > 0",
            SurfaceError::AngleOutOfRange => "angle out of range",
        })
    }
}

impl core::error::Error for SurfaceError {}

/// A surface that a ray can cross: one shape of API for every quadric family of the kernel.
pub trait Surface<T: Real> {
    /// The crossings of `ray` with the surface inside `[t_min, t_max]`, sorted by `t`.
    fn crossings(&self, ray: &Ray<T>) -> Crossings<T>;
    /// The side of the surface `point` lies on, or `None` when it lies on the surface (or where the side is not
    /// defined, as at a cone's apex).
    fn side_of(&self, point: V3<T>) -> Option<Side>;
}

/// The sign of `x` as a side: `Some(Positive)` for `x > 0`, `Some(Negative)` for `x < 0`, `None` for 0 or NaN.
#[inline]
pub(crate) fn side_of_sign<T: Real>(x: T) -> Option<Side> {
    if x > T::ZERO {
        Some(Side::Positive)
    } else if x < T::ZERO {
        Some(Side::Negative)
    } else {
        None
    }
}

/// Both roots of `a s² + 2 b s + c = 0` from the half-discriminant's square root `root_d = sqrt(b² − a c) ≥ 0`,
/// by the stable formula: `q = −(b + sign(b)·root_d)`, roots `q / a` and `c / q`.
///
/// Returns `(s_minus, s_plus)`, where `s_minus` is the root at which `a s + b = −root_d` (the quadratic is
/// decreasing there) and `s_plus` the root at which `a s + b = +root_d` (increasing). When `a = 0` the quadratic is
/// linear and only `s_plus` / `s_minus` (whichever matches the sign of `b`) is finite: the other is returned as
/// NaN, so callers drop it. `root_d = 0` gives a double root (both equal).
///
/// Error: each root is the exact root of a quadratic whose coefficients differ from `a, b, c` by the rounding of
/// two operations (relative 2ε), the sqrt being correctly rounded; no difference of nearly equal terms is formed.
#[inline]
pub(crate) fn stable_quadratic<T: Real>(a: T, b: T, c: T, root_d: T) -> (T, T) {
    stable_quadratic_signed(a, b, c, root_d, sign_of(b))
}

/// The sign that [`stable_quadratic`] gives its root for the coefficient `b`: −1 when `b < 0`, else +1 (a zero
/// or NaN `b` counts as positive, as in `with_sign_of`). A caller that solves many quadratics with one `b`
/// takes it once.
#[inline]
pub(crate) fn sign_of<T: Real>(b: T) -> T {
    if b < T::ZERO { -T::ONE } else { T::ONE }
}

/// [`stable_quadratic`] with `b`'s sign `sign = sign_of(b)` given (the same operations: `sign · root_d` is
/// exact).
#[cfg_attr(curvicast_small_code, inline(never))]
#[cfg_attr(not(curvicast_small_code), inline)]
pub(crate) fn stable_quadratic_signed<T: Real>(a: T, b: T, c: T, root_d: T, sign: T) -> (T, T) {
    let q = -(b + sign * root_d);
    let nan = T::NAN;
    if q == T::ZERO {
        // b = 0 and root_d = 0: then a·c = 0, and the double root is s = 0 (or, if a = 0 as well, every s or none).
        return if a == T::ZERO {
            (nan, nan)
        } else {
            (T::ZERO, T::ZERO)
        };
    }
    // q has the sign of −b; a·s + b at s = q/a is −sign(b)·root_d, and at c/q it is +sign(b)·root_d.
    let far = if a == T::ZERO { nan } else { q / a };
    let near = c / q;
    if sign > T::ZERO {
        (far, near)
    } else {
        (near, far)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_surface_error_has_its_own_message() {
        use std::string::ToString;
        let all = [
            SurfaceError::NonFinite,
            SurfaceError::BadAxes,
            SurfaceError::AngleOutOfRange,
        ];
        let texts: std::vec::Vec<std::string::String> =
            all.iter().map(ToString::to_string).collect();
        assert!(texts.iter().all(|t| t.len() > 10), "{texts:?}");
        assert!(texts[0] != texts[1] && texts[1] != texts[2] && texts[0] != texts[2]);
    }

    #[test]
    fn a_double_root_at_zero_and_a_vanishing_quadratic() {
        // b = 0 and root_d = 0 (so a·c = 0): the double root s = 0 when a ≠ 0, none when a = 0 too.
        assert_eq!(stable_quadratic(2.0, 0.0, 0.0, 0.0), (0.0, 0.0));
        let (x, y) = stable_quadratic(0.0, 0.0, 0.0, 0.0);
        assert!(x.is_nan() && y.is_nan());
        // s² − 4 = 0 (b = 0): the roots in the order (decreasing, increasing).
        assert_eq!(stable_quadratic(1.0, 0.0, -4.0, 2.0), (-2.0, 2.0));
    }
}
