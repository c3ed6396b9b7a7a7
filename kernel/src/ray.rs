//! The ray `p + t d` for `t_min <= t <= t_max`, and its per-ray invariants.
//!
//! Hannasch writes every conversion in terms of `‖d‖²`, `⟨p|d⟩` and the closest approach
//! (Lemma 8); this type computes them once per ray. Two numerical choices are made here so that every surface
//! solver inherits them:
//!
//! * **Scale-free direction.** `d` is stored multiplied by a power of two so that its largest component lies in
//!   `[1/2, 2)`: a direction there (every unit vector) is kept as given, any other is brought into `[1, 2)`.
//!   The scaling is exact, so a direction of length `1e-30` or `1e30` (which would underflow or overflow
//!   `‖d‖²` in `f32`) behaves exactly like a unit-sized one; solvers work in the scaled parameter and
//!   [`Ray::t_from_scaled`] converts back, again exactly. A solver's expressions are homogeneous in `d`, so
//!   which power of two is chosen changes no bit of its result (short of overflow); keeping unit-sized
//!   directions as given only saves the conversions (`s = t`).
//! * **No cancellation in the closest approach.** `|p × d|²` is kept, so the squared distance of the line from the
//!   origin is `|p × d|² / ‖d‖²`, never `‖p‖²‖d‖² − ⟨p|d⟩²` (the form Lemma 8 and §4.3 warn against).
//!
//! ```
//! use curvicast::ray::Ray;
//! use glam::DVec3;
//! let ray = Ray::new(DVec3::new(0.0, -5.0, 0.0), DVec3::new(0.0, 2.0, 0.0))?.with_interval(0.0, 10.0)?;
//! assert_eq!(ray.at(1.5), [0.0, -2.0, 0.0]);
//! // the hinge of r (closest approach to the origin, Lemma 8) in the caller's units of t:
//! assert_eq!(ray.t_closest(), 2.5);
//! # Ok::<(), curvicast::ray::RayError>(())
//! ```

use crate::real::Real;
use crate::vec3::V3;

/// Why a ray was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RayError {
    /// The origin has a NaN or infinite component.
    NonFiniteOrigin,
    /// The direction has a NaN or infinite component.
    NonFiniteDirection,
    /// The direction is the zero vector.
    ZeroDirection,
    /// `t_min` or `t_max` is NaN, or `t_min > t_max`, or `t_min` is +∞ or `t_max` is −∞.
    InvalidInterval,
}

impl core::fmt::Display for RayError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            RayError::NonFiniteOrigin => "ray origin is not finite",
            RayError::NonFiniteDirection => "ray direction is not finite",
            RayError::ZeroDirection => "ray direction is zero",
            RayError::InvalidInterval => "ray interval is invalid (NaN, or t_min > t_max)",
        })
    }
}

impl core::error::Error for RayError {}

/// A ray (or segment) `p + t d`, `t_min <= t <= t_max`, with its invariants precomputed.
///
/// `t` is in the caller's units of `d` (`d` need not be unit length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray<T> {
    /// The line with its invariants (what the surface solvers read).
    line: Line<T>,
    dir: V3<T>,
    t_min: T,
    t_max: T,
}

/// The line of a ray, `p + s d` in the scaled parameter `s`, with the invariants the surface solvers read and
/// the exact rescaling to the ray's `t`; without the ray's interval or its direction as given (the marcher
/// keeps this much of a ray for the whole march).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Line<T> {
    origin: V3<T>,
    /// `dir * 2^-e`, largest component in `[1/2, 2)`.
    d: V3<T>,
    /// The exact rescaling between `t` and the scaled parameter.
    scale: Scale<T>,
    /// `‖d‖²` of the scaled direction, in `[1/4, 12)`.
    dd: T,
    /// `⟨p|d⟩` with the scaled direction.
    pd: T,
    /// `p × d` with the scaled direction.
    w: V3<T>,
}

/// The exact rescaling between a ray's `t` and the parameter `s = t·2^e` of its scaled direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Scale<T> {
    /// The exponent `e`: `t = s · 2^-e`.
    e: i32,
    /// `2^-e` and `2^e` when both are normal numbers (then a multiplication by them is the exact rescaling,
    /// bit for bit what `scalbn` gives, without its call); `0` when either is not (a direction of subnormal or
    /// near-maximal size), where the conversions fall back to `scalbn`.
    to_t: T,
    to_s: T,
}

impl<T: Real> Scale<T> {
    /// No rescaling (`e = 0`: `s = t`).
    const IDENTITY: Self = Scale {
        e: 0,
        to_t: T::ONE,
        to_s: T::ONE,
    };

    /// `s · 2^-e` (exact unless it under- or overflows).
    #[cfg_attr(curvicast_small_code, inline(never))]
    #[cfg_attr(not(curvicast_small_code), inline)]
    pub(crate) fn t_from_scaled(&self, s: T) -> T {
        if self.to_t == T::ZERO {
            s.scalbn(self.e.saturating_neg())
        } else {
            s * self.to_t
        }
    }
    /// True when `t = s·2^-e` can overflow where `s` does not (`e < 0`: a direction that was scaled up).
    #[inline]
    pub(crate) fn enlarges(&self) -> bool {
        self.e < 0
    }
    /// `t · 2^e` (exact unless it under- or overflows).
    #[cfg_attr(curvicast_small_code, inline(never))]
    #[cfg_attr(not(curvicast_small_code), inline)]
    pub(crate) fn t_to_scaled(&self, t: T) -> T {
        if self.to_s == T::ZERO {
            t.scalbn(self.e)
        } else {
            t * self.to_s
        }
    }
}

/// The direction `dir` (largest component `m > 0`, finite) at unit size, exactly, with its rescaling: as given
/// when `m` is in `[1/2, 2)` (every unit vector: `s = t`), else times the power of two that brings `m` into
/// `[1, 2)`.
#[inline]
fn at_unit_size<T: Real>(dir: V3<T>, m: T) -> (V3<T>, Scale<T>) {
    if m >= T::HALF && m < T::TWO {
        return (dir, Scale::IDENTITY);
    }
    // m = 2^ilogb(m) * [1, 2): dividing by 2^ilogb(m) is exact.
    if let Some((e, to_t)) = m.binade() {
        if let Some((_, to_s)) = to_t.binade() {
            // both powers of two normal: the scaling is a multiplication (no libm call)
            return (dir.scaled(to_t), Scale { e, to_t, to_s });
        }
    }
    let e = m.ilogb();
    let (to_t, to_s) = normal_powers_of_two::<T>(e.saturating_neg());
    let d = if to_t == T::ZERO {
        dir.scalbn(e.saturating_neg())
    } else {
        dir.scaled(to_t)
    };
    (d, Scale { e, to_t, to_s })
}

/// `(2^k, 2^-k)` when both are normal numbers of `T`, else `(0, 0)`.
#[inline]
fn normal_powers_of_two<T: Real>(k: i32) -> (T, T) {
    let (p, q) = (T::ONE.scalbn(k), T::ONE.scalbn(k.saturating_neg()));
    if p.is_finite() && q.is_finite() && p >= T::MIN_POSITIVE && q >= T::MIN_POSITIVE {
        (p, q)
    } else {
        (T::ZERO, T::ZERO)
    }
}

impl<T: Real> Ray<T> {
    /// A ray from `origin` along `dir`, for `0 <= t < +∞`.
    ///
    /// Accepts `glam::DVec3` / `glam::Vec3`, arrays, or [`V3`].
    pub fn new(origin: impl Into<V3<T>>, dir: impl Into<V3<T>>) -> Result<Self, RayError> {
        let origin = origin.into();
        let dir = dir.into();
        if !origin.is_finite() {
            return Err(RayError::NonFiniteOrigin);
        }
        if !dir.is_finite() {
            return Err(RayError::NonFiniteDirection);
        }
        let m = dir.max_abs();
        if m == T::ZERO {
            return Err(RayError::ZeroDirection);
        }
        let (d, scale) = at_unit_size(dir, m);
        Ok(Self::with_scaled(origin, dir, d, scale))
    }

    /// The ray from its origin, its direction as given and the exactly rescaled one.
    #[inline]
    fn with_scaled(origin: V3<T>, dir: V3<T>, d: V3<T>, scale: Scale<T>) -> Self {
        Ray {
            line: Line {
                origin,
                d,
                scale,
                dd: d.length_squared(),
                pd: origin.dot(d),
                w: origin.cross(d),
            },
            dir,
            t_min: T::ZERO,
            t_max: T::INFINITY,
        }
    }

    /// The same ray restricted to `t_min <= t <= t_max` (either may be infinite).
    pub fn with_interval(mut self, t_min: T, t_max: T) -> Result<Self, RayError> {
        let ok = !t_min.is_nan()
            && !t_max.is_nan()
            && t_min <= t_max
            && t_min < T::INFINITY
            && t_max > T::NEG_INFINITY;
        if !ok {
            return Err(RayError::InvalidInterval);
        }
        self.t_min = t_min;
        self.t_max = t_max;
        Ok(self)
    }

    /// The segment from `a` (t = 0) to `b` (t = 1).
    pub fn segment(a: impl Into<V3<T>>, b: impl Into<V3<T>>) -> Result<Self, RayError> {
        let a = a.into();
        let b = b.into();
        if !b.is_finite() {
            return Err(RayError::NonFiniteDirection);
        }
        Self::new(a, b.minus(a))?.with_interval(T::ZERO, T::ONE)
    }

    /// The same ray with its origin moved by `-center` (the ray in coordinates centred at `center`).
    pub fn relative_to(&self, center: impl Into<V3<T>>) -> Result<Self, RayError> {
        let mut r = *self;
        r.line.recenter(center.into())?;
        Ok(r)
    }

    /// The line with its invariants, as the surface solvers read it.
    #[inline]
    pub(crate) fn line(&self) -> &Line<T> {
        &self.line
    }
    /// The origin `p`.
    #[inline]
    pub fn origin(&self) -> V3<T> {
        self.line.origin
    }
    /// The direction `d`, as given.
    #[inline]
    pub fn dir(&self) -> V3<T> {
        self.dir
    }
    /// The lower end of the interval.
    #[inline]
    pub fn t_min(&self) -> T {
        self.t_min
    }
    /// The upper end of the interval.
    #[inline]
    pub fn t_max(&self) -> T {
        self.t_max
    }
    /// True when `t_min <= t <= t_max`.
    #[inline]
    pub fn contains_t(&self, t: T) -> bool {
        self.t_min <= t && t <= self.t_max
    }
    /// The point `p + t d`.
    #[inline]
    pub fn at(&self, t: T) -> [T; 3] {
        self.line.origin.add_scaled(t, self.dir).to_array()
    }

    /// The direction rescaled exactly so that its largest component is in `[1/2, 2)`: the direction as given
    /// when it is there already, else brought into `[1, 2)`.
    #[inline]
    pub fn scaled_dir(&self) -> V3<T> {
        self.line.d
    }
    /// `‖d‖²` of the scaled direction (in `[1/4, 12)`).
    #[inline]
    pub fn dd(&self) -> T {
        self.line.dd
    }
    /// `⟨p|d⟩` with the scaled direction.
    #[inline]
    pub fn pd(&self) -> T {
        self.line.pd
    }
    /// `p × d` with the scaled direction; `|p × d|² / ‖d‖²` is the squared distance of the line from the origin.
    #[inline]
    pub fn p_cross_d(&self) -> V3<T> {
        self.line.w
    }
    /// Converts a parameter of the scaled direction to the caller's `t` (exact: a multiplication by a power of 2).
    #[inline]
    pub fn t_from_scaled(&self, s: T) -> T {
        self.line.scale.t_from_scaled(s)
    }
    /// The exponent `e` of the exact rescaling: `t = t_scaled · 2^-e` (see [`Ray::t_from_scaled`]).
    #[inline]
    pub(crate) fn scale_exponent(&self) -> i32 {
        self.line.scale_exponent()
    }
    /// Converts the caller's `t` to the parameter of the scaled direction (exact).
    #[inline]
    pub fn t_to_scaled(&self, t: T) -> T {
        self.line.scale.t_to_scaled(t)
    }

    /// The hinge of `r`: the `t` of the closest approach to the origin, `−⟨p|d⟩/‖d‖²` (Hannasch, Lemma 8).
    #[inline]
    pub fn t_closest(&self) -> T {
        self.line.t_closest()
    }
    /// The squared distance of the line from the origin, `|p × d|²/‖d‖²` (Hannasch, Lemma 8, without cancellation).
    #[inline]
    pub fn closest_distance_squared(&self) -> T {
        self.line.w.length_squared() / self.line.dd
    }
}

impl<T: Real> Line<T> {
    /// The line with its origin moved by `-center`, in place (unchanged on error): only the origin's
    /// invariants are formed again.
    pub(crate) fn recenter(&mut self, center: V3<T>) -> Result<(), RayError> {
        let origin = self.origin.minus(center);
        if !origin.is_finite() {
            return Err(RayError::NonFiniteOrigin);
        }
        self.origin = origin;
        self.pd = origin.dot(self.d);
        self.w = origin.cross(self.d);
        Ok(())
    }

    /// The origin `p`.
    #[inline]
    pub(crate) fn origin(&self) -> V3<T> {
        self.origin
    }
    /// The scaled direction (see [`Ray::scaled_dir`]).
    #[inline]
    pub(crate) fn scaled_dir(&self) -> V3<T> {
        self.d
    }
    /// `‖d‖²` of the scaled direction.
    #[inline]
    pub(crate) fn dd(&self) -> T {
        self.dd
    }
    /// `⟨p|d⟩` with the scaled direction.
    #[inline]
    pub(crate) fn pd(&self) -> T {
        self.pd
    }
    /// `p × d` with the scaled direction.
    #[inline]
    pub(crate) fn p_cross_d(&self) -> V3<T> {
        self.w
    }
    /// See [`Ray::t_from_scaled`].
    #[inline]
    pub(crate) fn t_from_scaled(&self, s: T) -> T {
        self.scale.t_from_scaled(s)
    }
    /// See [`Ray::t_to_scaled`].
    #[inline]
    pub(crate) fn t_to_scaled(&self, t: T) -> T {
        self.scale.t_to_scaled(t)
    }
    /// The exact rescaling between `t` and the scaled parameter.
    #[inline]
    pub(crate) fn scale(&self) -> Scale<T> {
        self.scale
    }
    /// See [`Ray::scale_exponent`].
    #[inline]
    pub(crate) fn scale_exponent(&self) -> i32 {
        self.scale.e
    }
    /// See [`Ray::t_closest`].
    #[inline]
    pub(crate) fn t_closest(&self) -> T {
        self.t_from_scaled(-self.pd / self.dd)
    }
}

#[cfg(test)]
mod tests {
    use super::{Ray, RayError};

    #[test]
    fn rejects_bad_input() {
        assert_eq!(
            Ray::new([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0]),
            Err(RayError::NonFiniteOrigin)
        );
        assert_eq!(
            Ray::new([0.0, 0.0, 0.0], [1.0, f64::INFINITY, 0.0]),
            Err(RayError::NonFiniteDirection)
        );
        assert_eq!(
            Ray::new([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
            Err(RayError::ZeroDirection)
        );
        let r = Ray::new([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert_eq!(r.with_interval(2.0, 1.0), Err(RayError::InvalidInterval));
        assert_eq!(
            r.with_interval(f64::NAN, 1.0),
            Err(RayError::InvalidInterval)
        );
        assert_eq!(
            r.with_interval(f64::INFINITY, f64::INFINITY),
            Err(RayError::InvalidInterval)
        );
        assert!(r.with_interval(f64::NEG_INFINITY, f64::INFINITY).is_ok());
    }

    #[test]
    fn tiny_and_huge_directions_scale_exactly() {
        for s in [1e-30_f32, 1e30, 3.0e-38, 1.0e38] {
            let r = Ray::new([1.0_f32, 2.0, 3.0], [s, -s, 0.5 * s]).unwrap();
            assert!(r.dd() >= 1.0 && r.dd() < 12.0);
            // the rescaling is exact both ways
            let t = 0.75_f32 / s;
            assert_eq!(r.t_from_scaled(r.t_to_scaled(t)), t);
        }
    }

    #[test]
    fn subnormal_direction_components_give_exactly_scaled_crossings_in_every_solver() {
        use crate::surface::{AxialCone, HalfPlane, PlaneZ, Spheroid, Surface};
        // Everything 2^-53 the unit size, the direction 2^-1030 (subnormal components, exactly representable):
        // every solver's t is the unit case's times 2^977, bit for bit.
        let (o, d) = ([-1.5_f64, 0.25, -0.375], [1.0, 0.125, 0.09375]);
        // (powers of two from their bits: `powi` need not be exact, and under Miri it is not)
        let (ks, kd) = (f64::from_bits(970 << 52), f64::from_bits(1 << 44)); // 2^-53, 2^-1030 (subnormal)
        let unit = Ray::new(o, d).unwrap();
        let tiny = Ray::new(o.map(|x| x * ks), d.map(|x| x * kd)).unwrap();
        assert!(tiny.dir().z < f64::MIN_POSITIVE && tiny.dir().z > 0.0);
        let k = f64::from_bits(2000 << 52); // 2^977
        let check = |name: &str,
                     a: &[crate::surface::Crossing<f64>],
                     b: &[crate::surface::Crossing<f64>]| {
            assert!(!a.is_empty(), "{name}");
            assert_eq!(a.len(), b.len());
            for (x, y) in a.iter().zip(b) {
                assert_eq!((x.t * k, x.into), (y.t, y.into), "{name}");
            }
        };
        let sphere = |r: f64| Spheroid::sphere(r).unwrap();
        check(
            "sphere",
            &sphere(1.0).crossings(&unit),
            &sphere(ks).crossings(&tiny),
        );
        let spheroid = |a: f64, b: f64| Spheroid::new(a, b).unwrap();
        check(
            "spheroid",
            &spheroid(1.0, 0.75).crossings(&unit),
            &spheroid(ks, 0.75 * ks).crossings(&tiny),
        );
        let cone = AxialCone::from_zenith_rad(0.0, 1.5).unwrap();
        check("cone", &cone.crossings(&unit), &cone.crossings(&tiny));
        let offset = |k: f64| AxialCone::from_zenith_rad(-0.25 * k, 1.52).unwrap();
        check(
            "offset cone",
            &offset(1.0).crossings(&unit),
            &offset(ks).crossings(&tiny),
        );
        let half = HalfPlane::from_azimuth_rad(1.0).unwrap();
        check("half-plane", &half.crossings(&unit), &half.crossings(&tiny));
        let plane = |z: f64| PlaneZ::new(z).unwrap();
        check(
            "plane",
            &plane(-0.125).crossings(&unit),
            &plane(-0.125 * ks).crossings(&tiny),
        );
    }

    #[test]
    fn closest_approach_has_no_cancellation() {
        // A ray nearly through the origin from far away: |p|²|d|² − ⟨p|d⟩² cancels completely in f64.
        let r = Ray::new([1e8_f64, 0.0, 0.0], [-1.0, 1e-9, 0.0]).unwrap();
        let m2 = r.closest_distance_squared();
        let exact = 0.01 / (1.0 + 1e-18); // (1e8 · 1e-9)² / (1 + 1e-18)
        assert!(
            (m2 - exact).abs() <= 4.0 * f64::EPSILON * exact,
            "{m2} vs {exact}"
        );
    }

    #[test]
    fn segment_runs_from_a_to_b() {
        let s = Ray::segment([1.0_f64, 1.0, 1.0], [3.0, 1.0, -1.0]).unwrap();
        assert_eq!(s.at(1.0), [3.0, 1.0, -1.0]);
        assert_eq!((s.t_min(), s.t_max()), (0.0, 1.0));
    }
}
