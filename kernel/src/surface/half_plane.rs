//! Ray ∩ half-plane bounded by the z axis at azimuth φ: `{(ρ cos φ, ρ sin φ, z) : ρ ≥ 0}`.
//!
//! Hannasch §4.6 intersects the azimuth facet `sin φ x = cos φ y` with one division, and Wartell et al. §3.3 bounds a
//! quad by the meridian plane `cos λ x + sin λ y = 0` (its eq. 3.3-1 has the roles of sin and cos swapped for a
//! plane *containing* the meridian; the plane containing azimuth λ has normal `(−sin λ, cos λ, 0)`). With that
//! normal `n`, the full plane is crossed at `t = −⟨n|p⟩ / ⟨n|d⟩`. Which half the crossing lies on needs no second
//! evaluation: the point's coordinate along `(cos φ, sin φ)` at the root is `(p × d)_z / ⟨n|d⟩`, an identity
//! (`(cos φ p_x + sin φ p_y)⟨n|d⟩ − (cos φ d_x + sin φ d_y)⟨n|p⟩ = p_x d_y − p_y d_x`). So the ray meets the half
//! exactly when `(p × d)_z` and `⟨n|d⟩` do not have opposite signs — Lemma 6's turning sense of φ. When
//! `(p × d)_z = 0` the line meets the z axis, which belongs to every closed half-plane: the crossing is reported
//! for every φ (φ jumps by π there; a marcher steps through the wedges it jumps over).
//!
//! **Error bound**: `⟨n|p⟩` and `⟨n|d⟩` have absolute errors below `2ε|p|` and `2ε|d|` (plus the rounding of
//! cos φ, sin φ), so the computed point lies within about `4ε·S` of the plane (backward error), S = max(|p|,
//! |p + t d|); along the ray that is divided by the sine of the crossing angle. The side test is exact in sign
//! except when `(p × d)_z` is within rounding of 0, i.e. when the line passes within `~ε·S` of the z axis.

use super::crossing::{Crossings, Side, Surface, SurfaceError, side_of_sign};
use crate::ray::{Line, Ray};
use crate::real::Real;
use crate::vec3::V3;

/// The half-plane at azimuth φ bounded by the z axis. Its positive side is the side of increasing φ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfPlane<T> {
    cos: T,
    sin: T,
}

impl<T: Real> HalfPlane<T> {
    /// The half-plane at azimuth `phi` in radians (any finite angle; taken modulo 2π).
    pub fn from_azimuth_rad(phi: T) -> Result<Self, SurfaceError> {
        if !phi.is_finite() {
            return Err(SurfaceError::NonFinite);
        }
        Self::from_cos_sin(phi.cos(), phi.sin())
    }

    /// The half-plane through the direction `(cos, sin)` (renormalised if not unit).
    pub fn from_cos_sin(cos: T, sin: T) -> Result<Self, SurfaceError> {
        if !cos.is_finite() || !sin.is_finite() {
            return Err(SurfaceError::NonFinite);
        }
        let n2 = cos * cos + sin * sin;
        if !(n2 > T::ZERO) || !n2.is_finite() {
            return Err(SurfaceError::AngleOutOfRange);
        }
        if n2 == T::ONE {
            return Ok(HalfPlane { cos, sin });
        }
        let n = n2.sqrt();
        Ok(HalfPlane {
            cos: cos / n,
            sin: sin / n,
        })
    }

    /// The half-plane from a `(cos φ, sin φ)` pair taken from a half-plane that was already built and validated
    /// (its [`HalfPlane::cos`] and [`HalfPlane::sin`]): no check, no renormalisation, no square root or division.
    /// The spherical marcher keeps its azimuth breakpoints in this form (Hannasch §2).
    #[inline]
    pub(crate) fn from_validated_unit_parts(cos: T, sin: T) -> Self {
        HalfPlane { cos, sin }
    }

    /// cos φ.
    #[inline]
    pub fn cos(&self) -> T {
        self.cos
    }
    /// sin φ.
    #[inline]
    pub fn sin(&self) -> T {
        self.sin
    }

    /// `⟨n|v⟩` with `n = (−sin φ, cos φ, 0)`: positive toward increasing φ.
    #[inline]
    fn normal_dot(&self, v: V3<T>) -> T {
        self.cos * v.y - self.sin * v.x
    }

    /// The crossing in the ray's scaled parameter (one division), or `None` when the ray is parallel to the
    /// plane, lies in it, or meets the plane on the opposite half.
    #[inline]
    pub(crate) fn scaled_root(&self, ray: &Line<T>) -> Option<(T, Side)> {
        self.scaled_root_fraction(ray)
            .map(|(num, den, side)| (num / den, side))
    }

    /// The crossing in the ray's scaled parameter as the fraction `num / den` with `den > 0`, not yet divided:
    /// the marcher divides it itself, folding the ray's exact rescaling into the denominator (Hannasch §4.6: one
    /// division per azimuth crossing). `num / den` is bit for bit the value [`HalfPlane::scaled_root`] returns
    /// (the sign is moved to the numerator exactly).
    #[inline]
    pub(crate) fn scaled_root_fraction(&self, ray: &Line<T>) -> Option<(T, T, Side)> {
        let nd = self.normal_dot(ray.scaled_dir());
        if nd == T::ZERO || nd.is_nan() {
            return None;
        }
        let wz = ray.p_cross_d().z;
        if (wz > T::ZERO && nd < T::ZERO) || (wz < T::ZERO && nd > T::ZERO) {
            return None; // the opposite half-plane
        }
        let np = self.normal_dot(ray.origin());
        Some(if nd > T::ZERO {
            (-np, nd, Side::Positive)
        } else {
            (np, -nd, Side::Negative)
        })
    }
}

impl<T: Real> HalfPlane<T> {
    /// [`HalfPlane::scaled_root_fraction`] for a line already known to meet this half-plane (not the opposite
    /// one) going toward the side `sign` (`+1` positive, `-1` negative) with `sign·⟨n|d⟩ > 0`, as the azimuth
    /// stream's arc test establishes (Hannasch §4.6, Lemma 6): `(num, den)` with `den > 0`, the same bits.
    #[inline(always)]
    pub(crate) fn scaled_root_fraction_ahead(&self, ray: &Line<T>, sign: T) -> (T, T) {
        let nd = self.normal_dot(ray.scaled_dir());
        let np = self.normal_dot(ray.origin());
        (-(np * sign), nd * sign)
    }
}

impl<T: Real> Surface<T> for HalfPlane<T> {
    fn crossings(&self, ray: &Ray<T>) -> Crossings<T> {
        match self.scaled_root(ray.line()) {
            Some(root) => Crossings::from_scaled_roots(ray, &[root]),
            None => Crossings::NONE,
        }
    }

    /// The side relative to the full plane for points in front of the z axis (`⟨(cos φ, sin φ)|p⟩ ≥ 0`); for points
    /// behind the axis the half-plane does not separate space and `None` is returned, as on the plane itself.
    fn side_of(&self, point: V3<T>) -> Option<Side> {
        let along = self.cos * point.x + self.sin * point.y;
        if along < T::ZERO {
            return None;
        }
        side_of_sign(self.normal_dot(point))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::FRAC_PI_2;

    #[test]
    fn crosses_the_x_half_axis_counter_clockwise() {
        let h = HalfPlane::from_cos_sin(1.0, 0.0).unwrap();
        let r = Ray::new([2.0, -1.0, 0.3], [0.0, 0.5, 0.0]).unwrap();
        let c = h.crossings(&r);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].t, c[0].into), (2.0, Side::Positive));
        let back = Ray::new([2.0, 1.0, 0.3], [0.0, -1.0, 0.0]).unwrap();
        assert_eq!(h.crossings(&back)[0].into, Side::Negative);
    }

    #[test]
    fn opposite_half_is_not_crossed() {
        let h = HalfPlane::from_cos_sin(1.0, 0.0).unwrap();
        let r = Ray::new([-2.0, -1.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
        assert!(h.crossings(&r).is_empty());
    }

    #[test]
    fn ray_in_the_plane_reports_nothing() {
        let h = HalfPlane::from_azimuth_rad(FRAC_PI_2).unwrap();
        let r = Ray::new([0.0, 1.0, 0.0], [0.0, 1.0, 1.0]).unwrap();
        assert!(h.crossings(&r).is_empty());
    }

    #[test]
    fn ray_through_z_axis_meets_every_half_plane_at_the_axis() {
        let r = Ray::new([-1.0, -1.0, 5.0], [1.0, 1.0, 0.0]).unwrap();
        for phi in [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0] {
            let c = HalfPlane::from_azimuth_rad(phi).unwrap().crossings(&r);
            assert_eq!(c.len(), 1, "phi {phi}");
            assert!((c[0].t - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn ray_along_z_axis_is_parallel() {
        let h = HalfPlane::from_azimuth_rad(0.3).unwrap();
        let r = Ray::new([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]).unwrap();
        assert!(h.crossings(&r).is_empty());
    }

    #[test]
    fn side_of_points() {
        let h = HalfPlane::from_azimuth_rad(0.0).unwrap();
        assert_eq!(h.side_of(V3::new(1.0, 0.1, 0.0)), Some(Side::Positive));
        assert_eq!(h.side_of(V3::new(1.0, -0.1, 0.0)), Some(Side::Negative));
        assert_eq!(h.side_of(V3::new(-1.0, -0.1, 0.0)), None);
        assert_eq!(h.side_of(V3::new(2.0, 0.0, 7.0)), None);
    }

    #[test]
    fn a_non_unit_direction_is_renormalised_and_a_unit_one_kept_as_given() {
        let h = HalfPlane::from_cos_sin(3.0, 4.0).unwrap();
        assert_eq!((h.cos(), h.sin()), (0.6, 0.8));
        let u = HalfPlane::from_cos_sin(0.6, 0.8).unwrap();
        assert_eq!((u.cos(), u.sin()), (0.6, 0.8));
    }

    #[test]
    fn a_zero_overflowing_or_non_finite_direction_is_refused() {
        assert_eq!(
            HalfPlane::from_cos_sin(0.0, 0.0),
            Err(SurfaceError::AngleOutOfRange)
        );
        assert_eq!(
            HalfPlane::from_cos_sin(1e200, 1e200),
            Err(SurfaceError::AngleOutOfRange)
        );
        assert_eq!(
            HalfPlane::from_cos_sin(f64::NAN, 1.0),
            Err(SurfaceError::NonFinite)
        );
        assert_eq!(
            HalfPlane::from_cos_sin(1.0, f64::INFINITY),
            Err(SurfaceError::NonFinite)
        );
    }

    #[test]
    fn a_ray_parallel_to_the_plane_has_no_root_fraction() {
        // The half-plane φ = 0 (normal +y); a ray along x at y = 1 never reaches it.
        let h = HalfPlane::from_cos_sin(1.0, 0.0).unwrap();
        let r = Ray::new([-2.0, 1.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert_eq!(h.scaled_root_fraction(r.line()), None);
    }

    #[test]
    fn a_ray_crossing_the_opposite_half_from_either_side_is_not_a_crossing() {
        // φ = 0: the plane y = 0 is crossed at x = −1, behind the axis, going −y and going +y.
        let h = HalfPlane::from_cos_sin(1.0, 0.0).unwrap();
        for (origin, dir) in [
            ([-1.0, 1.0, 0.0], [0.0, -1.0, 0.0]),
            ([-1.0, -1.0, 0.0], [0.0, 1.0, 0.0]),
        ] {
            let r = Ray::new(origin, dir).unwrap();
            assert_eq!(h.scaled_root_fraction(r.line()), None, "{origin:?}");
            assert!(h.crossings(&r).is_empty());
        }
    }

    #[test]
    fn side_of_points_in_front_of_behind_and_square_to_the_axis() {
        // φ = π/4 with cos = sin exactly.
        let h = HalfPlane::from_cos_sin(1.0, 1.0).unwrap();
        assert_eq!(h.cos(), h.sin());
        let side = |x: f64, y: f64| h.side_of(V3::new(x, y, 0.3));
        assert_eq!(side(1.0, 0.5), Some(Side::Negative)); // in front, below φ = π/4
        assert_eq!(side(0.5, 1.0), Some(Side::Positive)); // in front, above
        assert_eq!(side(-1.0, 1.0), Some(Side::Positive)); // square to the axis (along = 0 exactly): in front
        assert_eq!(side(-1.0, 2.0), Some(Side::Positive)); // in front (along > 0) though x < 0
        assert_eq!(side(-2.0, 1.0), None); // behind the axis
        assert_eq!(side(1.0, -2.0), None); // behind
        assert_eq!(side(0.5, -0.6), None); // just behind
        assert_eq!(side(1.0, 1.0), None); // on the half-plane
    }
}
