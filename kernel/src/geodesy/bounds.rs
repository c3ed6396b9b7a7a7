//! The bounding volume of a spheroidal height-quad (seed 000 §3.1–3.4), made conservative for the
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

use super::{Ellipsoid, GeodesyError, sin_cos_deg};
use crate::interval::clip_half_space;
use crate::ray::Ray;
use crate::real::Real;
use crate::sort::insertion_sort;
use crate::surface::{AxialCone, Side, Spheroid, Surface};
use crate::vec3::V3;

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
struct WallApex<T> {
    sin: T,
    cos: T,
    apex: T,
}

/// The parts of a quad's volume that need no trigonometry beyond `trig` (module docs, items 1–4): the
/// bulge-shifted apexes of the latitude walls it includes, and the longest triangle edge `d`, from which
/// [`LatitudeParts::height_walls`] forms the upper spheroid and the lower sphere.
struct LatitudeParts<T> {
    d: T,
    south: Option<WallApex<T>>,
    north: Option<WallApex<T>>,
}

impl<T: Real> LatitudeParts<T> {
    /// Checks the quad's parameters and forms its latitude walls.
    fn new(
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
    fn height_walls(
        &self,
        e: &Ellipsoid<T>,
        h_min: T,
        h_max: T,
    ) -> Result<(Spheroid<T>, T), GeodesyError> {
        let s = chord_sagitta_bound(e, self.d, h_min)?;
        Ok((upper_spheroid(e, h_max)?, e.b() + h_min - s))
    }
}

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

/// Clips `[lo, hi]` to the meridian planes of `wedge` (each inflated like the point tests); false when empty.
fn clip_wedge<T: Real>(lo: &mut T, hi: &mut T, wedge: Wedge<T>, ray: &Ray<T>) -> bool {
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
fn clip_upper<T: Real>(lo: &mut T, hi: &mut T, upper: &Spheroid<T>, ray: &Ray<T>) -> bool {
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
fn ray_point_slack<T: Real>(ray: &Ray<T>, lo: T, hi: T) -> T {
    let (o, d) = (ray.origin(), ray.dir());
    let tau = T::from_f64(64.0) * T::EPSILON;
    tau * ((o.x.abs() + o.y.abs() + o.z.abs())
        + (d.x.abs() + d.y.abs() + d.z.abs()) * lo.abs().max(hi.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sagitta_of_a_chord_on_the_sphere_is_bounded() {
        // Sphere of radius R: a chord of length D between two points at height 0 dips by
        // R − sqrt(R² − D²/4) ≈ D²/(8R); the bound (for triangles, D²/(6R)) must exceed it.
        let r = 6.4e6_f64;
        let e = Ellipsoid::new(r, r).unwrap();
        for &d in &[10.0, 1000.0, 1.0e5] {
            let true_dip = r - (r * r - d * d / 4.0).sqrt();
            let s = chord_sagitta_bound(&e, d, 0.0).unwrap();
            assert!(s >= true_dip, "{d}: {s} < {true_dip}");
            assert!(s <= 2.0 * true_dip, "{d}: bound too loose");
        }
        // Equilateral triangle inscribed in a circle of radius ρ = D/√3: its centroid dips by
        // R − sqrt(R² − ρ²) ≈ D²/(6R), which the bound matches to first order.
        let d = 1.0e5;
        let dip = r - (r * r - d * d / 3.0).sqrt();
        let s = chord_sagitta_bound(&e, d, 0.0).unwrap();
        assert!(s >= dip && s <= dip * 1.01, "{s} vs {dip}");
    }

    #[test]
    fn sagitta_rejects_depth_near_evolute() {
        let e = Ellipsoid::<f64>::wgs84();
        assert_eq!(
            chord_sagitta_bound(&e, 1.0e6, e.min_height() - 10.0),
            Err(GeodesyError::HeightTooLow)
        );
        // Just above −b²/a, a 1000 km chord is already beyond √1.5 (b²/a + h_min).
        assert_eq!(
            chord_sagitta_bound(&e, 1.0e6, e.min_height() + 10.0),
            Err(GeodesyError::TriangleTooLarge)
        );
        assert_eq!(
            HeightQuadBounds::new(&e, 0.0, 1.0, 0.0, 1.0, -7.0e6, 0.0, 0.1, 0.1),
            Err(GeodesyError::HeightTooLow)
        );
    }

    #[test]
    fn upper_bound_eq_3_1_2_1_contains_the_true_parallel_surface() {
        let e = Ellipsoid::<f64>::wgs84();
        for &h in &[0.0, 8848.0, 1.0e5, -1.0e4, -5.0e6] {
            let q = HeightQuadBounds::new(&e, -90.0, 90.0, -180.0, 180.0, h, h, 1.0, 1.0).unwrap();
            for k in 0..=90 {
                let lat = -90.0 + 2.0 * k as f64;
                let p = e.geodetic_deg_to_ecef(lat, 10.0, h);
                assert!(q.contains(p), "h = {h}, lat = {lat}");
            }
        }
    }

    #[test]
    fn bulging_triangle_at_80_degrees_is_inside_the_inflated_wall() {
        // A coarse (1°) cell along the north border at 80°: the midpoint of the border edge lies north of the
        // cone (the containment problem) but inside the inflated wall.
        let e = Ellipsoid::<f64>::wgs84();
        let q = HeightQuadBounds::new(&e, 79.0, 80.0, 10.0, 11.0, 0.0, 0.0, 1.0, 1.0).unwrap();
        let v0 = e.geodetic_deg_to_ecef(80.0, 10.0, 0.0);
        let v1 = e.geodetic_deg_to_ecef(80.0, 11.0, 0.0);
        let mid = v0.plus(v1).scaled(0.5);
        let g = e.ecef_to_geodetic(mid);
        assert!(
            g.lat.to_degrees() > 80.0,
            "the chord bulges north of the wall"
        );
        assert!(q.contains(mid));
        // The uninflated cone excludes it.
        let (s, c) = sin_cos_deg(80.0);
        let cone = e.latitude_cone(s, c).unwrap();
        assert_eq!(cone.side_of(mid), Some(crate::surface::Side::Negative));
    }

    #[test]
    fn radial_ray_interval_matches_heights() {
        let e = Ellipsoid::<f64>::wgs84();
        let q =
            HeightQuadBounds::new(&e, 10.0, 11.0, 20.0, 21.0, -100.0, 500.0, 0.01, 0.01).unwrap();
        let n = e.normal(10.5_f64.to_radians(), 20.5_f64.to_radians());
        let top = e.geodetic_deg_to_ecef(10.5, 20.5, 10_000.0);
        let ray = Ray::new(top, n.negated())
            .unwrap()
            .with_interval(0.0, 20_000.0)
            .unwrap();
        let (t_in, t_out) = q.ray_interval(&ray).unwrap();
        // Enters B^500 at about 9500 m (B^h is slightly outside TB^h), leaves below −100 m.
        assert!(t_in > 9490.0 && t_in <= 9500.0 + 1e-6, "{t_in}");
        assert!(t_out >= 10_100.0, "{t_out}");
        // A ray passing outside the wedge misses.
        let far = e.geodetic_deg_to_ecef(10.5, 25.0, 10_000.0);
        let miss = Ray::new(far, n.negated())
            .unwrap()
            .with_interval(0.0, 20_000.0)
            .unwrap();
        assert_eq!(q.ray_interval(&miss), None);
    }

    #[test]
    fn volume_entered_twice_yields_one_hull_over_both_visits() {
        // The band 70°..80° (all longitudes, so no wedge) at heights 0..400 km: a segment over the polar cap
        // from (75°, 0°, 300 km) to (75°, 180°, 300 km) starts in the band, crosses the cap north of 80° (outside
        // the band, but above the ground) and enters the band again on the far side.
        let e = Ellipsoid::<f64>::wgs84();
        let q = HeightQuadBounds::new(&e, 70.0, 80.0, -180.0, 180.0, 0.0, 4.0e5, 0.5, 0.5).unwrap();
        let a = e.geodetic_deg_to_ecef(75.0, 0.0, 3.0e5);
        let b = e.geodetic_deg_to_ecef(75.0, 180.0, 3.0e5);
        let ray = Ray::segment(a, b).unwrap();
        let (t_in, t_out) = q.ray_interval(&ray).unwrap();
        // Both visits lie in the hull, and the middle of the chord is outside the band (north of 80°).
        assert!(q.contains(V3::from(ray.at(0.0))) && q.contains(V3::from(ray.at(1.0))));
        assert!(!q.contains(V3::from(ray.at(0.5))));
        assert!(t_in <= 1e-12 && t_out >= 1.0 - 1e-12, "{t_in} {t_out}");
        // The gap between the two visits is the latitude wall's doing: the middle is above ground, north of 80°.
        let mid = e.ecef_to_geodetic(V3::from(ray.at(0.5)));
        assert!(
            mid.lat.to_degrees() > 80.0 && mid.h > 0.0 && mid.h < 4.0e5,
            "{mid:?}"
        );
    }

    #[test]
    #[cfg_attr(miri, ignore)]
    fn hull_covers_every_sampled_point_inside_the_volume() {
        // Quads from the equator to the poles (wide and narrow wedges, negative heights), rays from above, from
        // below and grazing: every sample the point test puts inside lies in the two-stage hull, and the hull is
        // not looser than the samples by more than one step at either end.
        let e = Ellipsoid::<f64>::wgs84();
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for _ in 0..300 {
            let lat_s = -90.0 + 170.0 * rnd();
            let lat_n = (lat_s + 0.01 + 20.0 * rnd()).min(90.0);
            let lon_w = -180.0 + 360.0 * rnd();
            let lon_e = lon_w + 0.01 + 200.0 * rnd();
            let h_lo = -500.0 + 1000.0 * rnd();
            let h_hi = h_lo + 5000.0 * rnd();
            let Ok(q) = HeightQuadBounds::new(&e, lat_s, lat_n, lon_w, lon_e, h_lo, h_hi, 0.1, 0.1)
            else {
                continue;
            };
            let (lat, lon) = (
                lat_s + (lat_n - lat_s) * rnd(),
                lon_w + (lon_e - lon_w) * rnd(),
            );
            let target = e.geodetic_deg_to_ecef(lat, lon, h_lo + (h_hi - h_lo) * rnd());
            let from = e.geodetic_deg_to_ecef(
                lat + 4.0 * (rnd() - 0.5),
                lon + 4.0 * (rnd() - 0.5),
                -2.0e4 + 1.0e5 * rnd(),
            );
            let ray = Ray::segment(from, target.add_scaled(1.0, target.minus(from))).unwrap();
            let hull = q.ray_interval(&ray);
            // The traversal's relaxed child test, with all walls and with a random subset of them.
            let mut trig = QuadTrig::from_degrees(lat_s, lat_n, lon_w, lon_e, 0.1);
            let relaxed_all = relaxed_interval(&e, &trig, h_lo, h_hi, 0.1, 0.1, &ray).unwrap();
            trig.walls = SideWalls {
                west: rnd() < 0.5,
                east: rnd() < 0.5,
                south: rnd() < 0.5,
                north: rnd() < 0.5,
            };
            let relaxed_some = relaxed_interval(&e, &trig, h_lo, h_hi, 0.1, 0.1, &ray).unwrap();
            // The volume formed once (a picker's zones) gives the same interval as the lazy test.
            let formed = RelaxedVolume::new(&e, &trig, h_lo, h_hi, 0.1, 0.1).unwrap();
            assert_eq!(formed.interval(&ray), relaxed_some);
            let n = 400;
            let inside: std::vec::Vec<f64> = (0..=n)
                .map(|k| k as f64 / n as f64)
                .filter(|&t| q.contains(V3::from(ray.at(t))))
                .collect();
            let (Some(&a), Some(&b)) = (inside.first(), inside.last()) else {
                continue;
            };
            assert!(hull.is_some(), "no hull, but t = {a} is inside");
            let (t_in, t_out) = hull.unwrap();
            checked += 1;
            assert!(
                t_in <= a && b <= t_out,
                "hull {t_in}..{t_out} misses {a}..{b}"
            );
            assert!(t_in >= a - 1.0 / n as f64 && t_out <= b + 1.0 / n as f64);
            for (what, r) in [("all walls", relaxed_all), ("some walls", relaxed_some)] {
                assert!(
                    r.is_some_and(|(lo, hi)| lo <= a && b <= hi),
                    "relaxed ({what}) {r:?} misses {a}..{b}"
                );
            }
        }
        assert!(checked > 100, "{checked}");
    }
}
