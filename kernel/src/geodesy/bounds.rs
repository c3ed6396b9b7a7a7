//! The bounding volume of a spheroidal height-quad (Wartell et al. §3.1–3.4), made conservative for the
//! *triangles* of the quad, and the ray–volume test of §3.5.
//!
//! A quad covers the DEM cells with latitudes in `[ψ_S, ψ_N]`, longitudes in `[λ_W, λ_E]` and vertex heights in
//! `[h_min, h_max]`. Its volume is the intersection of
//!
//! 1. the **meridian wedge** between the half-planes λ_W and λ_E (§3.3) — used only when `λ_E − λ_W < 180°`,
//!    where the wedge is convex. A planar triangle whose vertices lie in a convex set lies in it, so this wall is
//!    exact for triangles;
//! 2. the **upper spheroid** `B^{h_max}` of eq. 3.1.2-1: semi-axes `(a + h, b + h a/b)` for `h ≥ 0` and
//!    `(a + h b/a, b + h)` for `−b²/a < h < 0` (it contains the true parallel surface `TB^h`: Appendix A3).
//!    The region `{height ≤ H}` is a parallel body of a convex body (outer for `H ≥ 0`, inner for `H < 0`),
//!    hence convex, so a triangle with vertices at height `≤ h_max` never rises above `h_max`: exact for
//!    triangles. (For `h > b` the axes of eq. 3.1.2-1 would be prolate; the sphere of the larger axis is used.);
//! 3. the **lower sphere** of radius `b + h_min − s`, with `s` the [`chord_sagitta_bound`]. §3.2 uses the sphere
//!    through the closest *vertex*, which is not a lower bound of the *triangles*: the height function is convex
//!    outside the ellipsoid, so a chord dips below its end points. Proof of the bound: the geodetic height `h` is
//!    the signed distance to the ellipsoid; for `h > −b²/a` its Hessian has eigenvalues `κᵢ/(1 + κᵢ h)` (κᵢ the
//!    principal curvatures, `κ ≤ a/b²`) and 0, so it is bounded by `L(h) = a/b²` for `h ≥ 0` and
//!    `1/(b²/a + h)` for `h < 0`. For `p = Σ wₖ vₖ` in a triangle, the L-smoothness inequality at `p` summed with
//!    the weights gives `h(p) ≥ Σ wₖ h(vₖ) − (L/2) Σ wₖ |vₖ − p|² ≥ h_min − L D²/6`, since the weighted variance
//!    is at most the squared radius of the smallest enclosing disc, `≤ D²/3` (Jung), D the longest edge. With
//!    L taken at the lowest point, `s ≤ D²/(6(c − s))`, `c = b²/a + h_min`, whose smaller root
//!    `s = (D²/3)/(c + sqrt(c² − 2D²/3))` bounds the dip (continuity from the flat triangle). Every point at
//!    height `≥ H > −b` is at distance `≥ b + H` from the center (`|foot + H n| ≥ ⟨foot|n⟩ + H ≥ b + H`);
//! 4. the **latitude walls** (§3.4): with the cone function `f(p) = (z − k) cos ψ − r sin ψ`, `r = sqrt(x² + y²)`
//!    (positive north of the cone of latitude ψ, apex k), the Hessian of f is `−sin ψ · Hess r`, and
//!    `Hess r` has eigenvalues `1/r` and 0. So f is concave for ψ > 0, convex for ψ < 0: on the *convex side*
//!    of a wall (the south wall of a northern quad, the north wall of a southern quad, and ψ = 0) triangles stay
//!    inside exactly; on the other side they bulge across — the **containment problem** of §4, Fig. 10. By the
//!    same smoothness argument the bulge is at most `σ = |sin ψ| D² / (6 r_min)` in units of f, where `r_min`
//!    bounds the distance to the axis over the triangle (`(a + min(h_min, 0)) cos ψ* · cos(Δλ/2)`, ψ* the
//!    largest |latitude| of the quad); see [`latitude_bulge_bound`]. The wall is moved outward by σ: the cone of
//!    the same opening with its apex shifted by `σ / cos ψ`. When `r_min = 0` (a quad that reaches a pole and
//!    also has a non-convex wall) that wall is dropped, which is conservative.
//!
//! The quad's triangles therefore lie in the volume (up to the floating-point tolerance of the point tests,
//! which inflate every wall by `64 ε` relative). [`HeightQuadBounds::ray_interval`] returns the hull `[t_in, t_out]`
//! of the ray's parameters inside the volume in two stages. The convex walls first ([`convex_interval`]): inside
//! the upper spheroid and inside the wedge the ray's parameters form one interval each, read off their crossings
//! (with the wedge's planes inflated like the point tests). Then, within that interval, the breakpoints are the
//! crossings of the lower sphere and the latitude cones (all crossings come from the shared [`crate::surface`]
//! solvers) and each piece between breakpoints is classified by a point test at its midpoint. A volume the ray
//! enters twice (two crossings of a latitude cone or of the lower sphere) yields one hull covering both visits.
//! A terrain traversal uses a cheaper superset of the volume whose walls are all convex ([`relaxed_interval`]).

use super::ellipsoid::{Ellipsoid, GeodesyError, sin_cos_deg};
use crate::interval::clip_half_space;
use crate::ray::Ray;
use crate::real::Real;
use crate::sort::insertion_sort;
use crate::surface::{AxialCone, Side, Spheroid, Surface};
use crate::vec3::V3;

#[cfg(test)]
mod tests;

/// Bound on how far a planar triangle with longest edge ≤ `d` and vertex heights ≥ `h_min` dips below `h_min`
/// (module docs, item 3). Error [`GeodesyError::HeightTooLow`] when `h_min ≤ −b²/a`,
/// [`GeodesyError::TriangleTooLarge`] when `d ≥ √1.5 · (b²/a + h_min)` (the bound's quadratic has no root).
pub fn chord_sagitta_bound<T: Real>(e: &Ellipsoid<T>, d: T, h_min: T) -> Result<T, GeodesyError> {
    if !d.is_finite() || !h_min.is_finite() {
        return Err(GeodesyError::NonFinite);
    }
    let (a, b) = (e.a(), e.b());
    let d2 = d * d;
    let s0 = (a / (b * b)) * d2 / T::from_f64(6.0);
    if h_min - s0 >= T::ZERO {
        return Ok(s0);
    }
    let c = b * (b / a) + h_min;
    let disc = c * c - T::TWO * d2 / T::from_f64(3.0);
    if !(c > T::ZERO) {
        return Err(GeodesyError::HeightTooLow);
    }
    if !(disc > T::ZERO) {
        return Err(GeodesyError::TriangleTooLarge);
    }
    let s = (d2 / T::from_f64(3.0)) / (c + disc.sqrt());
    // Rounding margin (the bound is used as a safety inflation: a slight overestimate is harmless).
    Ok(s * (T::ONE + T::from_f64(16.0) * T::EPSILON))
}

/// The upper bounding spheroid `B^h` of eq. 3.1.2-1: semi-axes `(a + h, b + h a/b)` for `h ≥ 0`,
/// `(a + h b/a, b + h)` for `−b²/a < h < 0`; for `h > b` (where those axes would be prolate) the sphere of the
/// larger one. Error [`GeodesyError::HeightTooLow`] for `h ≤ −b²/a` (Appendix A2).
pub fn upper_spheroid<T: Real>(e: &Ellipsoid<T>, h: T) -> Result<Spheroid<T>, GeodesyError> {
    if !h.is_finite() {
        return Err(GeodesyError::NonFinite);
    }
    if !(h > e.min_height()) {
        return Err(GeodesyError::HeightTooLow);
    }
    let (a, b) = (e.a(), e.b());
    if h >= T::ZERO {
        let (ua, ub) = (a + h, b + h * (a / b));
        if ua >= ub {
            Ok(Spheroid::new(ua, ub)?)
        } else {
            Ok(Spheroid::sphere(ub)?)
        }
    } else {
        Ok(Spheroid::new(a + h * (b / a), b + h)?)
    }
}

/// Bound (in units of the cone function f, i.e. meters across the wall) on how far a triangle with longest edge
/// ≤ `d`, lying at distance ≥ `r_min` from the z axis, bulges across the latitude wall of latitude ψ on its
/// non-convex side (module docs, item 4). Infinite when `r_min ≤ 0`.
pub fn latitude_bulge_bound<T: Real>(sin_lat: T, d: T, r_min: T) -> T {
    if !(r_min > T::ZERO) {
        return T::INFINITY;
    }
    sin_lat.abs() * d * d / (T::from_f64(6.0) * r_min) * (T::ONE + T::from_f64(16.0) * T::EPSILON)
}

/// One latitude wall: the cone of latitude ψ with its apex shifted outward by the bulge bound.
#[derive(Debug, Clone, Copy, PartialEq)]
struct LatWall<T> {
    cone: AxialCone<T>,
    apex: T,
    sin: T,
    cos: T,
}

impl<T: Real> LatWall<T> {
    /// `f(p) = (z − k) cos ψ − r sin ψ`, and a magnitude for its rounding tolerance.
    #[inline]
    fn f(&self, p: V3<T>) -> (T, T) {
        let r = (p.x * p.x + p.y * p.y).sqrt();
        let dz = p.z - self.apex;
        (
            dz * self.cos - r * self.sin,
            p.z.abs() + self.apex.abs() + r,
        )
    }
}

/// The sines and cosines of a quad's boundary parallels and meridians ([`HeightQuadBounds::from_trig`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadTrig<T> {
    /// `(sin, cos)` of the southern boundary latitude.
    pub south: (T, T),
    /// `(sin, cos)` of the northern boundary latitude.
    pub north: (T, T),
    /// `(sin, cos)` of the western boundary longitude.
    pub west: (T, T),
    /// `(sin, cos)` of the eastern boundary longitude.
    pub east: (T, T),
    /// `λ_E − λ_W` in degrees (the wedge wall is used only below 180°).
    pub span_deg: T,
    /// `cos(Δλ/2)` of one cell (for the distance to the axis over a cell's triangles).
    pub cos_half_cell_dlon: T,
    /// Which side walls bound the volume ([`SideWalls::ALL`] for a quad on its own).
    pub walls: SideWalls,
}

/// Which of a quad's four side walls (two meridian planes, two latitude cones) its volume includes.
///
/// A child's outer sides lie on its parent's sides, and a traversal only tests a child along the part of the
/// ray already inside the parent (§3.5: the children are told apart by the parent's *internal* partition
/// walls). So a child's volume may leave its outer walls out: the volume only grows, which stays conservative,
/// and the ray meets half as many walls per child.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SideWalls {
    /// The meridian plane of the western boundary.
    pub west: bool,
    /// The meridian plane of the eastern boundary.
    pub east: bool,
    /// The latitude cone of the southern boundary.
    pub south: bool,
    /// The latitude cone of the northern boundary.
    pub north: bool,
}

impl SideWalls {
    /// All four walls.
    pub const ALL: Self = SideWalls {
        west: true,
        east: true,
        south: true,
        north: true,
    };
}

/// The meridian planes that bound a quad: `(cos λ, sin λ)` of its western and eastern boundary, each `None` when
/// that wall is left out. The quad lies east of the first (`cos λ_W · y − sin λ_W · x ≥ 0`) and west of the
/// second.
pub type Wedge<T> = [Option<(T, T)>; 2];

impl<T: Real> QuadTrig<T> {
    /// The trigonometry of the quad with latitudes `[lat_s, lat_n]` and longitudes `[lon_w, lon_e]` (degrees),
    /// made of cells `cell_dlon` degrees wide, with all four walls.
    pub fn from_degrees(lat_s: T, lat_n: T, lon_w: T, lon_e: T, cell_dlon: T) -> Self {
        QuadTrig {
            south: sin_cos_deg(lat_s),
            north: sin_cos_deg(lat_n),
            west: sin_cos_deg(lon_w),
            east: sin_cos_deg(lon_e),
            span_deg: lon_e - lon_w,
            cos_half_cell_dlon: sin_cos_deg(cell_dlon.abs() / T::TWO).1,
            walls: SideWalls::ALL,
        }
    }

    /// The meridian walls that bound the quad: those of [`QuadTrig::walls`], when the span is below 180° (where
    /// the wedge is convex); none for wider quads.
    pub fn wedge(&self) -> Result<Wedge<T>, GeodesyError> {
        let ((sw, cw), (se, ce), span) = (self.west, self.east, self.span_deg);
        // One test for all five: sines and cosines are at most 1, so the sum is finite exactly when each is.
        if !(sw + cw + se + ce + span).is_finite() || span < T::ZERO {
            return Err(GeodesyError::NonFinite);
        }
        let convex = span < T::from_f64(180.0);
        Ok([
            (convex && self.walls.west).then_some((cw, sw)),
            (convex && self.walls.east).then_some((ce, se)),
        ])
    }
}

/// The conservative bounding volume of a spheroidal height-quad (module docs) and its ray test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeightQuadBounds<T> {
    /// The meridian walls (those included, when the wedge is convex: span < 180°).
    wedge: Wedge<T>,
    south: Option<LatWall<T>>,
    north: Option<LatWall<T>>,
    upper: Spheroid<T>,
    /// Radius of the lower sphere (≤ 0: no lower wall).
    lower_r: T,
}

impl<T: Real> HeightQuadBounds<T> {
    /// The volume of the quad with latitudes `[lat_s, lat_n]`, longitudes `[lon_w, lon_e]` (degrees; `lon_w ≤
    /// lon_e`, any multiple of 360 offset), vertex heights `[h_min, h_max]`, made of cells `cell_dlat × cell_dlon`
    /// degrees (their sizes bound the triangle edges for the sagitta and bulge bounds).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        e: &Ellipsoid<T>,
        lat_s: T,
        lat_n: T,
        lon_w: T,
        lon_e: T,
        h_min: T,
        h_max: T,
        cell_dlat: T,
        cell_dlon: T,
    ) -> Result<Self, GeodesyError> {
        let all = [lat_s, lat_n, lon_w, lon_e];
        if all.iter().any(|x| !x.is_finite()) {
            return Err(GeodesyError::NonFinite);
        }
        let ninety = T::from_f64(90.0);
        if !(lat_s >= -ninety && lat_n <= ninety && lat_s <= lat_n) {
            return Err(GeodesyError::LatitudeOutOfRange);
        }
        let trig = QuadTrig::from_degrees(lat_s, lat_n, lon_w, lon_e, cell_dlon);
        Self::from_trig(e, &trig, h_min, h_max, cell_dlat, cell_dlon)
    }

    /// [`HeightQuadBounds::new`] from the sines and cosines of the quad's boundary latitudes and longitudes, as
    /// [`sin_cos_deg`] gives them (a picker reads them from the storage's per-row and per-column cache, so that
    /// building a volume needs no trigonometry). A latitude whose cosine is 0 is a pole.
    pub fn from_trig(
        e: &Ellipsoid<T>,
        trig: &QuadTrig<T>,
        h_min: T,
        h_max: T,
        cell_dlat: T,
        cell_dlon: T,
    ) -> Result<Self, GeodesyError> {
        let lat = LatitudeParts::new(e, trig, h_min, h_max, cell_dlat, cell_dlon)?;
        let (upper, lower_r) = lat.height_walls(e, h_min, h_max)?;
        let wall = |w: Option<WallApex<T>>| -> Result<Option<LatWall<T>>, GeodesyError> {
            w.map(|WallApex { sin, cos, apex }| {
                Ok(LatWall {
                    cone: AxialCone::from_cos_sin(apex, sin, cos)?,
                    apex,
                    sin,
                    cos,
                })
            })
            .transpose()
        };
        Ok(HeightQuadBounds {
            wedge: trig.wedge()?,
            south: wall(lat.south)?,
            north: wall(lat.north)?,
            upper,
            lower_r,
        })
    }

    /// The upper bounding spheroid `B^{h_max}`.
    pub fn upper(&self) -> &Spheroid<T> {
        &self.upper
    }

    /// The radius of the lower sphere (sagitta included); `≤ 0` means no lower wall.
    pub fn lower_radius(&self) -> T {
        self.lower_r
    }

    /// True when the point lies in the volume (every wall inflated by `64 ε` relative).
    pub fn contains(&self, p: V3<T>) -> bool {
        let tau = T::from_f64(64.0) * T::EPSILON;
        let tol = tau * (p.x.abs() + p.y.abs());
        let [west, east] = self.wedge;
        if west.is_some_and(|(c, s)| c * p.y - s * p.x < -tol)
            || east.is_some_and(|(c, s)| c * p.y - s * p.x > tol)
        {
            return false;
        }
        inside_spheroid(&self.upper, p, T::ZERO) && self.inside_walls(p, T::ZERO)
    }

    /// The non-convex part of [`HeightQuadBounds::contains`]: the latitude cones and the lower sphere, each
    /// inflated by `64 ε` relative plus `slack` metres (the rounding of a point computed along a ray).
    fn inside_walls(&self, p: V3<T>, slack: T) -> bool {
        let tau = T::from_f64(64.0) * T::EPSILON;
        // f is a signed distance (its gradient has unit length off the apex), so `slack` adds directly.
        if let Some(w) = self.south {
            let (f, m) = w.f(p);
            if f < -(tau * m + slack) {
                return false;
            }
        }
        if let Some(w) = self.north {
            let (f, m) = w.f(p);
            if f > tau * m + slack {
                return false;
            }
        }
        let r = self.lower_r - slack;
        if r > T::ZERO && p.length_squared() < r * r * (T::ONE - tau) {
            return false;
        }
        true
    }

    /// The hull `[t_in, t_out]` of the ray's parameters (within its finite interval) inside the volume, or `None`.
    /// An infinite ray interval is an error of the caller: clip to the global bound first (it returns `None`).
    pub fn ray_interval(&self, ray: &Ray<T>) -> Option<(T, T)> {
        let (lo, hi) = convex_interval(&self.upper, self.wedge, ray)?;
        self.walls_interval(ray, lo, hi)
    }

    /// The second stage of [`HeightQuadBounds::ray_interval`]: the hull within `[lo, hi]`, which must be the
    /// [`convex_interval`] of this volume's upper spheroid and wedge.
    pub fn walls_interval(&self, ray: &Ray<T>, lo: T, hi: T) -> Option<(T, T)> {
        let sub = ray.with_interval(lo, hi).ok()?;
        // The other walls (lower sphere, latitude cones) bound non-convex regions: breakpoints at their
        // crossings, each piece classified by a point test at its midpoint.
        let mut bp = [T::ZERO; 10];
        let mut n = 0usize;
        let mut push = |t: T| {
            if let Some(slot) = bp.get_mut(n) {
                *slot = t;
                n = n.saturating_add(1);
            }
        };
        push(lo);
        push(hi);
        if self.lower_r > T::ZERO {
            if let Ok(sph) = Spheroid::sphere(self.lower_r) {
                for c in &sph.crossings(&sub) {
                    push(c.t);
                }
            }
        }
        for w in [self.south, self.north].into_iter().flatten() {
            for c in &w.cone.crossings(&sub) {
                push(c.t);
            }
        }
        let pts = bp.get_mut(..n).unwrap_or(&mut []);
        insertion_sort(pts, |x, y| x < y);
        // `[lo, hi]` already lies in the upper spheroid and the wedge, so a point needs only the other walls.
        // They are inflated by the rounding of the point `p + t·d` itself, which grows with the origin's
        // distance: a ray from 10⁹ m away misplaces a point near the pole by micrometres.
        let slack = ray_point_slack(ray, lo, hi);
        let inside_at = |t: T| self.inside_walls(V3::from(ray.at(t)), slack);
        if n == 2 && lo == hi {
            return inside_at(lo).then_some((lo, hi));
        }
        // The first piece inside from the front and the last from the back (the hull between them is
        // conservative; pieces in between need no test).
        let inside = |a: T, b: T| inside_at(a + (b - a) * T::HALF);
        let mut first: Option<usize> = None;
        for (k, w) in pts.windows(2).enumerate() {
            if let [a, b] = *w {
                if inside(a, b) {
                    first = Some(k);
                    break;
                }
            }
        }
        let first = first?;
        let mut last = first;
        for (k, w) in pts.windows(2).enumerate().rev() {
            if k <= first {
                break;
            }
            if let [a, b] = *w {
                if inside(a, b) {
                    last = k;
                    break;
                }
            }
        }
        let t_in = pts.get(first).copied()?;
        let t_out = pts.get(last.saturating_add(1)).copied()?;
        Some((t_in, t_out))
    }
}

/// A latitude wall before its cone is built: the latitude's sine and cosine and the (bulge-shifted) apex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct WallApex<T> {
    pub(super) sin: T,
    pub(super) cos: T,
    pub(super) apex: T,
}

/// The parts of a quad's volume that need no trigonometry beyond `trig` (module docs, items 1–4): the
/// bulge-shifted apexes of the latitude walls it includes, and the longest triangle edge `d`, from which
/// [`LatitudeParts::height_walls`] forms the upper spheroid and the lower sphere.
pub(super) struct LatitudeParts<T> {
    pub(super) d: T,
    pub(super) south: Option<WallApex<T>>,
    pub(super) north: Option<WallApex<T>>,
}

impl<T: Real> LatitudeParts<T> {
    /// Checks the quad's parameters and forms its latitude walls.
    pub(super) fn new(
        e: &Ellipsoid<T>,
        trig: &QuadTrig<T>,
        h_min: T,
        h_max: T,
        cell_dlat: T,
        cell_dlon: T,
    ) -> Result<Self, GeodesyError> {
        let QuadTrig {
            south: (s_s, c_s),
            north: (s_n, c_n),
            cos_half_cell_dlon: c_half,
            ..
        } = *trig;
        let all = [
            s_s, c_s, s_n, c_n, c_half, h_min, h_max, cell_dlat, cell_dlon,
        ];
        if all.iter().any(|x| !x.is_finite()) {
            return Err(GeodesyError::NonFinite);
        }
        if !(s_s <= s_n) || c_s < T::ZERO || c_n < T::ZERO {
            return Err(GeodesyError::LatitudeOutOfRange);
        }
        if !(h_min > e.min_height()) || !(h_max >= h_min) {
            return Err(GeodesyError::HeightTooLow);
        }
        let (a, b) = (e.a(), e.b());
        let rad = T::PI / T::from_f64(180.0);
        let dpsi = cell_dlat.abs() * rad;
        let dlam = cell_dlon.abs() * rad;
        // Longest triangle edge: |∂P/∂ψ| = M + h, |∂P/∂λ| = (N + h) cos ψ, both ≤ a²/b + max(h, 0); |∂P/∂h| = 1.
        let d = (a * (a / b) + h_max.max(T::ZERO)) * (dpsi * dpsi + dlam * dlam).sqrt()
            + (h_max - h_min);
        let d = d * (T::ONE + T::from_f64(16.0) * T::EPSILON);

        // Distance to the axis over the quad's triangles.
        let cos_star = c_s.min(c_n);
        let r_min = (a + h_min.min(T::ZERO)) * cos_star * c_half;

        // The wall of latitude ψ with its apex moved by `shift_f / cos ψ`: f grows by `shift_f`, so the region
        // f ≥ 0 grows when `shift_f < 0` (a south wall) and f ≤ 0 grows when `shift_f > 0` (a north wall). An
        // unbounded bulge drops the wall (conservative).
        let wall = |sin: T, cos: T, shift_f: T| {
            shift_f.is_finite().then(|| WallApex {
                sin,
                cos,
                apex: e.latitude_cone_apex(sin) + shift_f / cos,
            })
        };
        let south = if !trig.walls.south || c_s == T::ZERO && s_s < T::ZERO {
            None
        } else {
            let sigma = if s_s < T::ZERO {
                latitude_bulge_bound(s_s, d, r_min)
            } else {
                T::ZERO
            };
            wall(s_s, c_s, -sigma)
        };
        let north = if !trig.walls.north || c_n == T::ZERO && s_n > T::ZERO {
            None
        } else {
            let sigma = if s_n > T::ZERO {
                latitude_bulge_bound(s_n, d, r_min)
            } else {
                T::ZERO
            };
            wall(s_n, c_n, sigma)
        };
        Ok(LatitudeParts { d, south, north })
    }

    /// The upper spheroid and the radius of the lower sphere (sagitta included).
    pub(super) fn height_walls(
        &self,
        e: &Ellipsoid<T>,
        h_min: T,
        h_max: T,
    ) -> Result<(Spheroid<T>, T), GeodesyError> {
        let s = chord_sagitta_bound(e, self.d, h_min)?;
        Ok((upper_spheroid(e, h_max)?, e.b() + h_min - s))
    }
}

/// Clips `[lo, hi]` to the meridian planes of `wedge` (each inflated like the point tests); false when empty.
pub(super) fn clip_wedge<T: Real>(lo: &mut T, hi: &mut T, wedge: Wedge<T>, ray: &Ray<T>) -> bool {
    let (o, d) = (ray.origin(), ray.dir());
    let tau = T::from_f64(64.0) * T::EPSILON;
    let t_abs = ray.t_min().abs().max(ray.t_max().abs());
    let mag = (o.x.abs() + o.y.abs()) + (d.x.abs() + d.y.abs()) * t_abs;
    let [west, east] = wedge;
    // East of λ_W: c·y − s·x ≥ 0; west of λ_E: c·y − s·x ≤ 0 (both inflated as in `contains`).
    if let Some((c, s)) = west {
        clip_half_space(lo, hi, c * o.y - s * o.x, c * d.y - s * d.x, tau * mag);
    }
    if let Some((c, s)) = east {
        clip_half_space(lo, hi, s * o.x - c * o.y, s * d.x - c * d.y, tau * mag);
    }
    *lo <= *hi
}

/// Clips `[lo, hi]` (within the ray's interval) to the inside of the upper spheroid; false when empty.
pub(super) fn clip_upper<T: Real>(
    lo: &mut T,
    hi: &mut T,
    upper: &Spheroid<T>,
    ray: &Ray<T>,
) -> bool {
    let cr = upper.crossings(ray);
    if cr.is_empty() {
        // No crossing within the ray's interval: all of it lies on one side.
        let mid = V3::from(ray.at(*lo + (*hi - *lo) * T::HALF));
        return inside_spheroid(upper, mid, ray_point_slack(ray, ray.t_min(), ray.t_max()));
    }
    for c in &cr {
        match c.into {
            Side::Negative => *lo = lo.max(c.t),
            Side::Positive => *hi = hi.min(c.t),
        }
    }
    *lo <= *hi
}

/// The first stage of [`HeightQuadBounds::ray_interval`] (§3.5's "B^h interval"): inside the meridian wedge
/// (its planes, each inflated like the point tests) and inside the upper spheroid the ray's parameters form one
/// interval each, found from their crossings alone. The planes come first (a division each), so that most
/// volumes a ray misses are rejected before the spheroid is crossed, and all of them before the rest of the
/// volume (sagitta, bulge-shifted cones) is even built.
pub fn convex_interval<T: Real>(
    upper: &Spheroid<T>,
    wedge: Wedge<T>,
    ray: &Ray<T>,
) -> Option<(T, T)> {
    let (mut lo, mut hi) = (ray.t_min(), ray.t_max());
    if !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    (clip_wedge(&mut lo, &mut hi, wedge, ray) && clip_upper(&mut lo, &mut hi, upper, ray))
        .then_some((lo, hi))
}

/// The upper-spheroid test of [`HeightQuadBounds::contains`] (inflated by `64 ε`, plus `slack` metres).
#[inline]
fn inside_spheroid<T: Real>(upper: &Spheroid<T>, p: V3<T>, slack: T) -> bool {
    let tau = T::from_f64(64.0) * T::EPSILON;
    let (ua, ub) = (upper.a(), upper.b());
    let q = (p.x / ua).sq() + (p.y / ua).sq() + (p.z / ub).sq();
    // q − 1 ≈ 2·(distance outside)/b near the surface.
    q <= T::ONE + tau + T::TWO * slack / ub
}

/// A bound (metres, with a margin) on the rounding of a point `p + t·d` computed for `t` in `[lo, hi]`.
#[inline]
pub(super) fn ray_point_slack<T: Real>(ray: &Ray<T>, lo: T, hi: T) -> T {
    let (o, d) = (ray.origin(), ray.dir());
    let tau = T::from_f64(64.0) * T::EPSILON;
    tau * ((o.x.abs() + o.y.abs() + o.z.abs())
        + (d.x.abs() + d.y.abs() + d.z.abs()) * lo.abs().max(hi.abs()))
}
