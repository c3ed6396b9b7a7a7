//! The relaxed volume of a height-quad (beyond the paper): a convex superset of [`HeightQuadBounds`] that
//! a terrain traversal tests instead, with each latitude cone replaced by a plane bounding its side (the tangent
//! plane along the middle meridian on the convex side, the chord plane through the generators at the quad's
//! meridians on the other), so that the ray's hull needs no point tests.

use super::bounds::{
    HeightQuadBounds, LatitudeParts, QuadTrig, WallApex, Wedge, clip_upper, clip_wedge,
    ray_point_slack,
};
use super::ellipsoid::{Ellipsoid, GeodesyError};
use crate::interval::clip_half_space;
use crate::ray::Ray;
use crate::real::Real;
use crate::surface::{Side, Spheroid, Surface};
use crate::vec3::V3;

#[cfg(test)]
mod tests;

/// The middle meridian of a wedge narrower than 180° from its walls' sines and cosines: `(cos λm, sin λm)`, and
/// `cos(Δλ/2)` lowered by a few ε so that the rounding of λm and of the span cannot make a chord plane too tight.
fn middle_meridian<T: Real>(trig: &QuadTrig<T>) -> (T, T, T) {
    let ((sw, cw), (se, ce)) = (trig.west, trig.east);
    let (mx, my) = (cw + ce, sw + se);
    let len = (mx * mx + my * my).sqrt(); // 2 cos(Δλ/2)
    (
        mx / len,
        my / len,
        len * T::HALF - T::from_f64(8.0) * T::EPSILON,
    )
}

/// A quad's relaxed volume ([`relaxed_interval`]), formed once for repeated tests (a picker's zones).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RelaxedVolume<T> {
    wedge: Wedge<T>,
    middle: (T, T, T),
    south: Option<WallApex<T>>,
    north: Option<WallApex<T>>,
    upper: Spheroid<T>,
    lower_r: T,
    /// Quads of 180° or more: the full volume.
    full: Option<HeightQuadBounds<T>>,
}

impl<T: Real> RelaxedVolume<T> {
    /// The relaxed volume of the quad (arguments as [`HeightQuadBounds::from_trig`]).
    pub fn new(
        e: &Ellipsoid<T>,
        trig: &QuadTrig<T>,
        h_min: T,
        h_max: T,
        cell_dlat: T,
        cell_dlon: T,
    ) -> Result<Self, GeodesyError> {
        let lat = LatitudeParts::new(e, trig, h_min, h_max, cell_dlat, cell_dlon)?;
        let (upper, lower_r) = lat.height_walls(e, h_min, h_max)?;
        let full = if trig.span_deg < T::from_f64(180.0) {
            None
        } else {
            Some(HeightQuadBounds::from_trig(
                e, trig, h_min, h_max, cell_dlat, cell_dlon,
            )?)
        };
        Ok(RelaxedVolume {
            wedge: trig.wedge()?,
            middle: middle_meridian(trig),
            south: lat.south,
            north: lat.north,
            upper,
            lower_r,
            full,
        })
    }

    /// The hull of the ray's parameters in the volume, or `None` (the ray's interval must be finite).
    pub fn interval(&self, ray: &Ray<T>) -> Option<(T, T)> {
        if let Some(b) = &self.full {
            return b.ray_interval(ray);
        }
        let (mut lo, mut hi) = (ray.t_min(), ray.t_max());
        let ok = lo.is_finite()
            && hi.is_finite()
            && clip_wedge(&mut lo, &mut hi, self.wedge, ray)
            && clip_latitude_planes(&mut lo, &mut hi, ray, self.middle, self.south, self.north)
            && clip_height_walls(&mut lo, &mut hi, ray, &self.upper, self.lower_r);
        ok.then_some((lo, hi))
    }
}

/// A cheaper, looser hull of the ray's parameters in a quad's volume, for the traversal's test of a child
/// (beyond the paper; the volume of [`HeightQuadBounds::from_trig`] with the same `trig` and heights lies inside
/// it, so it is conservative). Every wall is convex here, so the hull comes from crossings alone, with no point
/// tests: the meridian planes, then each latitude wall replaced by a plane that bounds its side of the
/// (bulge-shifted) cone, then the upper spheroid, and last the lower sphere cut from either end. Each step runs
/// only if the interval is still non-empty, and the parts of the volume it needs are formed only then.
///
/// The planes, with `f = (z − k) cos ψ − r sin ψ` the cone, λm the quad's middle meridian and Δλ its span:
/// `g = (z − k) cos ψ − sin ψ (x cos λm + y sin λm)` (the tangent plane along λm) satisfies `g − f =
/// r sin ψ (1 − cos(λ − λm))`, so `g ≥ f` everywhere when ψ ≥ 0 and `g ≤ f` when ψ < 0: the convex side of the
/// cone lies on one side of it. `h = (z − k) cos ψ cos(Δλ/2) − sin ψ (x cos λm + y sin λm)` (the plane through
/// the cone's generators at λ_W and λ_E: the leaves' row plane) bounds the other side, for points in the wedge,
/// where `cos(λ − λm) ≥ cos(Δλ/2)`. The quad's triangles lie in its wedge (its meridian planes contain the
/// vertex normals), so `h` may be used even when the child's meridian walls are left out. The planes need a
/// convex wedge: for spans of 180° or more this returns the full volume's [`HeightQuadBounds::ray_interval`].
#[allow(clippy::too_many_arguments)]
pub fn relaxed_interval<T: Real>(
    e: &Ellipsoid<T>,
    trig: &QuadTrig<T>,
    h_min: T,
    h_max: T,
    cell_dlat: T,
    cell_dlon: T,
    ray: &Ray<T>,
) -> Result<Option<(T, T)>, GeodesyError> {
    if !(trig.span_deg < T::from_f64(180.0)) {
        // The latitude planes need a convex wedge: the full volume.
        return Ok(
            HeightQuadBounds::from_trig(e, trig, h_min, h_max, cell_dlat, cell_dlon)?
                .ray_interval(ray),
        );
    }
    let wedge = trig.wedge()?;
    let (mut lo, mut hi) = (ray.t_min(), ray.t_max());
    if !lo.is_finite() || !hi.is_finite() || !clip_wedge(&mut lo, &mut hi, wedge, ray) {
        return Ok(None);
    }
    let lat = LatitudeParts::new(e, trig, h_min, h_max, cell_dlat, cell_dlon)?;
    let middle = middle_meridian(trig);
    if !clip_latitude_planes(&mut lo, &mut hi, ray, middle, lat.south, lat.north) {
        return Ok(None);
    }
    let (upper, lower_r) = lat.height_walls(e, h_min, h_max)?;
    Ok(clip_height_walls(&mut lo, &mut hi, ray, &upper, lower_r).then_some((lo, hi)))
}

/// Clips `[lo, hi]` to the planes that replace the latitude walls ([`relaxed_interval`]); false when empty.
/// `middle` is [`middle_meridian`]'s.
fn clip_latitude_planes<T: Real>(
    lo: &mut T,
    hi: &mut T,
    ray: &Ray<T>,
    (cm, sm, ch): (T, T, T),
    south: Option<WallApex<T>>,
    north: Option<WallApex<T>>,
) -> bool {
    let (o, d) = (ray.origin(), ray.dir());
    let tau = T::from_f64(64.0) * T::EPSILON;
    let t_abs = ray.t_min().abs().max(ray.t_max().abs());
    let d1 = d.x.abs() + d.y.abs() + d.z.abs();
    let (radial_o, radial_d) = (cm * o.x + sm * o.y, cm * d.x + sm * d.y);
    let mut plane = |w: WallApex<T>, north_side: bool| {
        let tangent = (w.sin >= T::ZERO) == north_side;
        let kz = if tangent { w.cos } else { w.cos * ch };
        if !tangent && !(ch > T::ZERO) {
            return;
        }
        let qz = o.z - w.apex;
        let s0 = kz * qz - w.sin * radial_o;
        let sd = kz * d.z - w.sin * radial_d;
        let tol = tau * (o.x.abs() + o.y.abs() + qz.abs() + w.apex.abs() + d1 * t_abs);
        if north_side {
            clip_half_space(lo, hi, s0, sd, tol);
        } else {
            clip_half_space(lo, hi, -s0, -sd, tol);
        }
    };
    // The quad lies north of its south wall and south of its north wall.
    if let Some(w) = south {
        plane(w, true);
    }
    if let Some(w) = north {
        plane(w, false);
    }
    *lo <= *hi
}

/// Clips `[lo, hi]` to the upper spheroid, then cuts the lower sphere (shrunk by the rounding of the ray's
/// points) from whichever end it covers: the ball is convex, so the ray is inside it on one interval. False
/// when empty.
fn clip_height_walls<T: Real>(
    lo: &mut T,
    hi: &mut T,
    ray: &Ray<T>,
    upper: &Spheroid<T>,
    lower_r: T,
) -> bool {
    if !clip_upper(lo, hi, upper, ray) {
        return false;
    }
    let r = lower_r - ray_point_slack(ray, *lo, *hi);
    if r > T::ZERO {
        let inside = |t: T| V3::from(ray.at(t)).length_squared() < r * r;
        let (in_lo, in_hi) = (inside(*lo), inside(*hi));
        if in_lo && in_hi {
            return false;
        }
        if in_lo || in_hi {
            let Ok(ball) = Spheroid::sphere(r) else {
                return true;
            };
            for c in &ball.crossings(ray) {
                match c.into {
                    Side::Positive if in_lo => *lo = lo.max(c.t),
                    Side::Negative if in_hi => *hi = hi.min(c.t),
                    _ => {}
                }
            }
        }
    }
    *lo <= *hi
}
