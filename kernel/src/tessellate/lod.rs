//! The a-priori level of detail (seed 004, chapter 5): "model only what a scene needs".
//!
//! Chapter 5 observes that the smallest dihedral angle `φ` of a beveled polyhedron "may always be found by
//! following the worst case (smallest `φ`) from one refinement to the next". For the sphere the worst case is the
//! chain of *central* triangles of the dual triangulation (§4.3.3): the octant, then the triangle of its three
//! edge midpoints, and so on. Each is equilateral; with `u_k = 1 − cos s_k` for its side `s_k` (the largest angle
//! between the normals of two adjacent faces at level `k`), the paper's half-angle formula
//! `cos a' = (cos²(a/2) + cos²(b/2) + cos²(c/2) − 1) / (2 cos(b/2) cos(c/2))` with `a = b = c` becomes
//!
//! ```text
//! u_0 = 1,    u_{k+1} = u_k / (2 (2 − u_k)),
//! ```
//!
//! free of cancellation as `u_k → 0`. At level `k`:
//! * the smallest dihedral angle is `π − s_k`, `s_k = atan2(√(u_k (2 − u_k)), 1 − u_k)`;
//! * the largest deviation from the unit sphere is at the **Y**-point of the central triangle, whose three
//!   tangent planes meet at distance `1 / cos ρ = √(3 / (3 − 2 u_k))` from the center, so
//!   `δ_k = √(3 / (3 − 2 u_k)) − 1` (computed as `(2u / (3 − 2u)) / (√(3 / (3 − 2u)) + 1)`).
//!
//! Each of these is strictly monotone in `k`, so [`min_level`] walks `k = 0, 1, …` and stops at the first level
//! that meets the bound: O(k) scalar operations, no polyhedron built. The host tests build every level up to 8 and
//! confirm that the measured smallest dihedral angle and largest deviation are exactly these, and that the level
//! returned meets the bound while the one below fails it.
//!
//! **Ellipsoids** (§4.4, chapter 5 "first scale the unit sphere along each of its three axes"): the polyhedron is
//! the sphere's scaled by `S = diag(A, B, C)`; a face with sphere center point `c` has the normal `S⁻¹c / |S⁻¹c|`.
//! The worst case no longer sits on one chain, so [`min_level`] decides each level `k = 0, 1, …` in turn and
//! returns the first that meets the bound; every level below it has been shown to fail by an explicit vertex or
//! edge that violates the bound. Per level (all lengths relative to the largest semi-axis, `ratio` = largest /
//! smallest semi-axis):
//!
//! 1. **Witnesses** (O(k) each): thirteen triangles of level `k` found by descending the refinement tree with
//!    integer lattice coordinates, their center points computed exactly as the builder computes them: the corner
//!    triangle at each axis tip, the central triangle of the chain above, and the three triangles around each
//!    midpoint of the octant's sides — where the worst vertices and edges of nearly spherical, oblate and prolate
//!    ellipsoids sit (a triaxial ellipsoid's worst vertex may lie elsewhere; the walk finds it). If one of their
//!    edges (normal angle) or vertices (distance, below) violates the bound, the level fails.
//! 2. **Guarantees** (closed form): with `|â − b̂| ≤ |a − b| / √(|a||b|)`, adjacent normals satisfy
//!    `sin(θ'/2) ≤ ratio · sin(s_k / 2)`; a vertex `p` of the unit polyhedron (`|p| ≤ 1 + δ_k`) maps to `S p`,
//!    within `(|p| − 1)·|S p̂| ≤ δ_k` of the surface point `S p̂`. If the guarantee meets the bound, the level meets it.
//! 3. **Exact decision** when neither settles the level: a depth-first walk over the refinement tree of one
//!    octant (the polyhedron is symmetric under the three coordinate reflections), regenerating the center points
//!    exactly as the builder does, with an explicit stack of `3k + 1` triangles and no other memory. At depth `k`
//!    it checks the three edges (normal angles) or the vertex (distance) of each triangle, and stops at the first
//!    violation. Subtrees are skipped when a bound clears all of them: below a triangle with corner `c₀` and
//!    largest chord `ρ`, a level-`k` edge is an arc of at most `s_k` along which the normal turns at most
//!    `ratio / (|S⁻¹c₀| − ratio · ρ)` times as fast; a level-`k` vertex `p` has `|p| − 1 ≤ δ_k` and `p̂` within the
//!    chord `σ_k = √(2δ_k / (1 + δ_k))` of its triangle's corners, so it is at most `δ_k (|S c₀| + ρ + σ_k)` from
//!    the surface, and at most `δ_k / g + δ_k² / (2r)` with `g = |S⁻¹c₀| − ratio (ρ + σ_k)` (below).
//!
//! **Vertex distances**: for `S p = (1 + ε) S p̂`, the height above the supporting plane at `S p̂`,
//! `h = ε / |S⁻¹p̂|`, is a lower bound; by Blaschke's rolling theorem the ball of radius `r = (min axis)²`
//! (the smallest radius of curvature) touching the ellipsoid from inside at `S p̂` lies inside it, so
//! `h + τ² / (2 (h + r))` (`τ ≤ ε |S p̂|` the offset along the plane) is an upper bound. Only when these straddle
//! the bound is the distance solved: the closest point's Lagrange parameter by Newton's method on the convex,
//! decreasing secular function from `t = 0` (monotone, at most 64 steps). The pruning and bracketing comparisons
//! keep a relative slack of `√ε_mach` against rounding in the bounds; the decisions themselves compare the
//! computed angle or distance of a witness or walked edge/vertex with the bound directly, so the level agrees with
//! the built polyhedron's measured worst case except for bounds within rounding of a measured value.
//!
//! Why the walk is right: the distance to a convex body is a convex function, so over each (convex, planar) face
//! it is largest at a vertex, and the polyhedron lies outside the ellipsoid; the smallest dihedral angle is a
//! minimum over edges. So the largest deviation is a maximum over vertices and the largest normal angle a maximum
//! over edges, which the walk visits (or clears by a bound) one by one.
//!
//! Cost: steps 1–2 take O(k) scalar operations per level (thirteen descents of `k` midpoints each), O(k²) for
//! the whole search. The walk at level `k` visits at most `(4^(k+1) − 1) / 3` triangles, each O(1) (plus a few
//! Newton steps for a rare straddling vertex); it runs only for levels whose bound falls between the witnesses and
//! the guarantee; its pruning skips the regions that a bound clears, and it visits the children with the larger
//! bound first, so that a violation is met early. Measured (release build, on a shared machine; the host test
//! `ellipsoid_a_priori_level_time_per_call` prints it): for bounds drawn between two consecutive levels' worst
//! values of five ellipsoids, the median call takes 10–30 µs up to level 8 (most levels are settled by steps 1–2),
//! the mean up to about 0.9 ms and the slowest about 8 ms at level 8 (a walk that must clear most of a worst
//! region); for extreme shapes the bounds prune less (a 1000:1 oblate spheroid took up to 73 ms, at level 9). [`ellipsoid_worst_case`] walks a whole octant without pruning and returns the level's exact largest
//! deviation and smallest dihedral angle.
//!
//! **Screen space**: a deviation `e` on an object of bounding radius `r` whose center is at distance `d > r` from
//! the eye lies no nearer than `D = d − r − e`, so it subtends at most `2·asin(e / (2D))`; that is at most the
//! pixel's angular size `p` iff `e ≤ 2 (d − r) sin(p/2) / (1 + 2 sin(p/2))` ([`screen_space_error`] evaluates the
//! angle itself).
//!
//! ```
//! use curvicast::tessellate::lod::{min_level, worst_case, Bound, Shape};
//! // Earth-sized sphere seen from 20 000 km with 1-arc-minute pixels.
//! let bound = Bound::ScreenSpace { distance: 2.0e7_f64, pixel_angle: (1.0_f64 / 60.0).to_radians() };
//! let k = min_level(Shape::Sphere(6.371e6), bound)?;
//! assert_eq!(k, 6);
//! assert!(worst_case::<f64>(k)?.max_deviation < worst_case::<f64>(k - 1)?.max_deviation);
//!
//! // The WGS84 ellipsoid within 100 km: the smallest level, and the one below misses it.
//! use curvicast::tessellate::lod::ellipsoid_worst_case;
//! let wgs84 = [6378137.0, 6378137.0, 6356752.314245179];
//! let k = min_level(Shape::Ellipsoid(wgs84), Bound::MaxDeviation(1.0e5))?;
//! assert_eq!(k, 3);
//! assert!(ellipsoid_worst_case(wgs84, k)?.max_deviation <= 1.0e5);
//! assert!(ellipsoid_worst_case(wgs84, k - 1)?.max_deviation > 1.0e5);
//! # Ok::<(), curvicast::tessellate::TessellateError>(())
//! ```

use super::TessellateError;
use super::bevel::{MAX_LEVEL, normalized, tangent_planes_meet};
use crate::real::Real;
use crate::vec3::V3;

/// The object whose level is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape<T> {
    /// A sphere of this radius.
    Sphere(T),
    /// An ellipsoid with these semi-axes (`x²/A² + y²/B² + z²/C² = 1`); the squared ratio of the smallest to the
    /// largest must be a normal number.
    Ellipsoid([T; 3]),
}

/// A level-of-detail requirement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound<T> {
    /// The smallest dihedral angle between adjacent faces must be at least this (radians, in `[0, π)`).
    MinDihedral(T),
    /// The largest distance between the polyhedron and the true surface must be at most this (same unit as the
    /// shape, positive; `+∞` accepts level 0).
    MaxDeviation(T),
    /// Seen from `distance` (eye to the object's center, larger than its bounding radius), no deviation may
    /// subtend more than `pixel_angle` (radians, in `(0, π]`).
    ScreenSpace {
        /// Distance from the eye to the object's center.
        distance: T,
        /// Angular size of one pixel, radians.
        pixel_angle: T,
    },
}

/// The worst case of the unit sphere's polyhedron at one level (chapter 5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorstCase<T> {
    /// `u = 1 − cos s`, `s` the largest angle between the normals of adjacent faces.
    pub one_minus_cos: T,
    /// The largest angle between the normals of adjacent faces, radians (`π −` the smallest dihedral angle).
    pub max_normal_angle: T,
    /// The smallest dihedral angle between adjacent faces, radians.
    pub min_dihedral: T,
    /// The largest distance between the polyhedron and the unit sphere.
    pub max_deviation: T,
}

fn worst_from_u<T: Real>(u: T) -> WorstCase<T> {
    let s = (u * (T::TWO - u)).sqrt().atan2(T::ONE - u);
    let three = T::from_i32(3);
    let den = three - T::TWO * u;
    let dev = (T::TWO * u / den) / ((three / den).sqrt() + T::ONE);
    WorstCase {
        one_minus_cos: u,
        max_normal_angle: s,
        min_dihedral: T::PI - s,
        max_deviation: dev,
    }
}

fn next_u<T: Real>(u: T) -> T {
    u / (T::TWO * (T::TWO - u))
}

/// The worst case of the unit sphere's polyhedron at `level`, by the recursion of the module docs.
///
/// # Errors
/// [`TessellateError::LevelTooDeep`] above [`MAX_LEVEL`].
pub fn worst_case<T: Real>(level: u32) -> Result<WorstCase<T>, TessellateError> {
    if level > MAX_LEVEL {
        return Err(TessellateError::LevelTooDeep {
            level,
            max: MAX_LEVEL,
        });
    }
    let mut u = T::ONE;
    for _ in 0..level {
        u = next_u(u);
    }
    Ok(worst_from_u(u))
}

/// The angle that a deviation `deviation` on an object of bounding radius `radius` subtends at most, seen from
/// `distance` from its center: `2·asin(e / (2(d − r − e)))`, or `π` when the eye could touch the polyhedron.
pub fn screen_space_error<T: Real>(radius: T, distance: T, deviation: T) -> T {
    let near = distance - radius - deviation;
    let half = deviation / (T::TWO * near);
    if !(near > T::ZERO) || !(half < T::ONE) || half.is_nan() {
        return T::PI;
    }
    // asin(x) = atan2(x, √(1 − x²)).
    T::TWO * half.atan2(((T::ONE - half) * (T::ONE + half)).sqrt())
}

/// The smallest refinement level whose polyhedron meets `bound` for `shape` (chapter 5), without building any
/// level: every level below the one returned fails the bound. Allocation-free; for spheres O(k) scalar
/// operations, for ellipsoids as described in the module docs.
///
/// # Errors
/// [`TessellateError::InvalidShape`] for a non-positive or non-finite radius/axis,
/// [`TessellateError::AxisRatioTooLarge`] for an axis ratio above [`MAX_AXIS_RATIO`], [`TessellateError::InvalidBound`] for a bound out of range (NaN, a dihedral angle ≥ π
/// or < 0, a deviation ≤ 0, a pixel angle outside `(0, π]`, an eye inside the object's bounding sphere),
/// [`TessellateError::Unreachable`] when no level up to [`MAX_LEVEL`] meets it.
pub fn min_level<T: Real>(shape: Shape<T>, bound: Bound<T>) -> Result<u32, TessellateError> {
    let (r_max, ellipsoid) = match shape {
        Shape::Sphere(r) => {
            if !(r > T::ZERO) || !r.is_finite() {
                return Err(TessellateError::InvalidShape);
            }
            (r, None)
        }
        Shape::Ellipsoid(axes) => {
            let (e, hi) = Ell::new(axes)?;
            // Equal axes: the sphere's exact chain.
            (hi, if e.ratio == T::ONE { None } else { Some(e) })
        }
    };
    let test = match bound {
        Bound::MinDihedral(phi) => {
            if !(phi >= T::ZERO) || !(phi < T::PI) {
                return Err(TessellateError::InvalidBound);
            }
            EllTest::NormalAngle(T::PI - phi)
        }
        Bound::MaxDeviation(e) => {
            if !(e > T::ZERO) {
                return Err(TessellateError::InvalidBound);
            }
            EllTest::Deviation(e / r_max)
        }
        Bound::ScreenSpace {
            distance,
            pixel_angle,
        } => {
            if !(pixel_angle > T::ZERO)
                || !(pixel_angle <= T::PI)
                || !(distance > r_max)
                || !distance.is_finite()
            {
                return Err(TessellateError::InvalidBound);
            }
            let s = (pixel_angle * T::HALF).sin();
            let allowed = T::TWO * (distance - r_max) * s / (T::ONE + T::TWO * s);
            if !(allowed > T::ZERO) {
                return Err(TessellateError::InvalidBound);
            }
            EllTest::Deviation(allowed / r_max)
        }
    };
    match (ellipsoid, test) {
        (None, EllTest::NormalAngle(limit)) => {
            first_level(|w: &WorstCase<T>| w.max_normal_angle <= limit)
        }
        (None, EllTest::Deviation(limit)) => {
            first_level(|w: &WorstCase<T>| w.max_deviation <= limit)
        }
        (Some(e), test) => {
            for level in 0..=MAX_LEVEL {
                if ellipsoid_meets(&e, level, test)? {
                    return Ok(level);
                }
            }
            Err(TessellateError::Unreachable)
        }
    }
}

/// Follows the worst case from level 0 up and returns the first level that passes `ok`.
fn first_level<T: Real>(ok: impl Fn(&WorstCase<T>) -> bool) -> Result<u32, TessellateError> {
    let mut u = T::ONE;
    for level in 0..=MAX_LEVEL {
        if ok(&worst_from_u(u)) {
            return Ok(level);
        }
        u = next_u(u);
    }
    Err(TessellateError::Unreachable)
}

/// The exact worst case of an ellipsoid's polyhedron at one level, from [`ellipsoid_worst_case`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EllipsoidWorstCase<T> {
    /// The largest angle between the normals of adjacent faces, radians.
    pub max_normal_angle: T,
    /// The smallest dihedral angle between adjacent faces, radians (`π −` the largest normal angle).
    pub min_dihedral: T,
    /// The largest distance between the polyhedron and the ellipsoid (in the unit of the semi-axes).
    pub max_deviation: T,
}

/// The largest deviation and smallest dihedral angle of the level-`level` polyhedron of the ellipsoid with
/// semi-axes `axes` (§4.4, chapter 5), by walking every vertex and edge of one octant without building the level
/// (module docs, step 3, without pruning): `(4^(level+1) − 1) / 3` triangles, each with one closest-point solve and
/// three normal angles; fixed memory.
///
/// # Errors
/// [`TessellateError::LevelTooDeep`] above [`MAX_LEVEL`], [`TessellateError::InvalidShape`] and
/// [`TessellateError::AxisRatioTooLarge`] as for [`min_level`].
pub fn ellipsoid_worst_case<T: Real>(
    axes: [T; 3],
    level: u32,
) -> Result<EllipsoidWorstCase<T>, TessellateError> {
    let (e, hi) = Ell::new(axes)?;
    let mut angle = T::ZERO;
    let mut dev = T::ZERO;
    walk_octant(
        level,
        |_| Some(T::ZERO),
        |c| {
            let [c0, c1, c2] = *c;
            for (x, y) in [(c0, c1), (c1, c2), (c2, c0)] {
                angle = angle.max(e.normal_angle(x, y).ok_or(TessellateError::Internal)?);
            }
            let p = tangent_planes_meet(c0, c1, c2).ok_or(TessellateError::Internal)?;
            dev = dev.max(e.distance(p));
            Ok(true)
        },
    )?;
    Ok(EllipsoidWorstCase {
        max_normal_angle: angle,
        min_dihedral: T::PI - angle,
        max_deviation: dev * hi,
    })
}

// ---------------------------------------------------------------------------------------------------------------
// Ellipsoids: witnesses, guarantees and the exhaustive octant walk.
// ---------------------------------------------------------------------------------------------------------------

/// The largest ratio of an ellipsoid's largest to smallest semi-axis that [`min_level`] and
/// [`ellipsoid_worst_case`] accept (`AxisRatioTooLarge` beyond). A fuzz input at 7e134 : 1 made the closest-point
/// solver report a zero deviation; the method is checked (against built polyhedra, and against the unpruned
/// walk) far below this limit.
pub const MAX_AXIS_RATIO: f64 = 1.0e6;

/// The ellipsoid scaled so that its largest semi-axis is 1 (`a`), with `a²` and `1/a` per axis.
#[derive(Debug, Clone, Copy)]
struct Ell<T> {
    a: [T; 3],
    w: [T; 3],
    inv: [T; 3],
    /// Largest over smallest semi-axis (`1 / min a`).
    ratio: T,
    /// The smallest radius of curvature, `(min a)²`: by Blaschke's rolling theorem a ball of this radius touching
    /// the ellipsoid from inside at any point lies inside it.
    roll: T,
}

impl<T: Real> Ell<T> {
    /// Validates the semi-axes and normalizes them; returns the ellipsoid and the largest semi-axis.
    fn new(axes: [T; 3]) -> Result<(Self, T), TessellateError> {
        let mut hi = T::ZERO;
        for a in axes {
            if !(a > T::ZERO) || !a.is_finite() {
                return Err(TessellateError::InvalidShape);
            }
            hi = hi.max(a);
        }
        let a = axes.map(|x| x / hi);
        let w = a.map(|x| x * x);
        let inv = a.map(|x| T::ONE / x);
        let lo = a[0].min(a[1]).min(a[2]);
        let ratio = T::ONE / lo;
        // The ratio at most MAX_AXIS_RATIO, the range in which the method's bounds and solver have been
        // checked, and the squared axis ratio a normal number for the closest-point solver (in f32 too).
        if !(ratio <= T::from_f64(MAX_AXIS_RATIO)) || w.iter().any(|&x| !(x >= T::MIN_POSITIVE)) {
            return Err(TessellateError::AxisRatioTooLarge);
        }
        Ok((
            Ell {
                a,
                w,
                inv,
                ratio,
                roll: lo * lo,
            },
            hi,
        ))
    }

    /// `S c` (a point of the unit sphere mapped onto the ellipsoid).
    fn scale(&self, c: V3<T>) -> V3<T> {
        V3::new(c.x * self.a[0], c.y * self.a[1], c.z * self.a[2])
    }

    /// `S⁻¹ c` (the ellipsoid's outward normal direction at `S c`).
    fn unscale(&self, c: V3<T>) -> V3<T> {
        V3::new(c.x * self.inv[0], c.y * self.inv[1], c.z * self.inv[2])
    }

    /// The angle between the ellipsoid's normals at `S c0` and `S c1` (the faces with sphere center points `c0`,
    /// `c1`), as `atan2(|n0 × n1|, n0 · n1)`.
    fn normal_angle(&self, c0: V3<T>, c1: V3<T>) -> Option<T> {
        let n0 = normalized(self.unscale(c0))?;
        let n1 = normalized(self.unscale(c1))?;
        Some(n0.cross(n1).length().atan2(n0.dot(n1)))
    }

    /// Is `S p` (a vertex of the unit sphere's polyhedron mapped by `S`) within `limit` of the ellipsoid?
    ///
    /// With `ε = |p| − 1`, `S p = (1 + ε) S p̂` lies above the supporting plane at `S p̂` by `h = ε / |S⁻¹p̂|`
    /// (a lower bound of the distance), and at most `h + τ² / (2 (h + r))` from the rolling ball of radius `r`
    /// touching there (`τ ≤ ε |S p̂|` the offset along the plane; an upper bound), and at most `ε |S p̂|` from
    /// `S p̂`. The closest point is solved for only when these bounds straddle `limit`.
    fn vertex_meets(&self, p: V3<T>, limit: T) -> bool {
        let slack = T::ONE + T::EPSILON.sqrt();
        let pp = p.dot(p);
        let excess = pp - T::ONE;
        if !(excess > T::ZERO) {
            return T::ZERO <= limit;
        }
        let r = pp.sqrt();
        let eps = excess / (r + T::ONE);
        let h = eps * r / self.unscale(p).length();
        if h > limit * slack {
            return false;
        }
        let tau = eps * self.scale(p).length() / r;
        let upper = tau.min(h + tau * tau / (T::TWO * (h + self.roll)));
        if upper * slack <= limit {
            return true;
        }
        self.distance(p) <= limit
    }

    /// Distance from `S p` (a vertex of the unit sphere's polyhedron mapped by `S`) to the ellipsoid; 0 for a point
    /// on or inside it.
    ///
    /// The closest point is `x_i = w_i y_i / (t + w_i)` with `y = S p` and the Lagrange parameter `t ≥ 0` the root
    /// of `F(t) = Σ (w_i p_i / (t + w_i))² − 1`; `F` is decreasing and convex on `t ≥ 0`, so Newton's method from
    /// `t = 0` (where `F(0) = |p|² − 1`) climbs monotonically to the root without overshooting. At most 64 steps;
    /// it stops as soon as a step makes no progress. The gap is `y_i t / (t + w_i)` per axis: no cancellation.
    fn distance(&self, p: V3<T>) -> T {
        let p = p.to_array();
        let f0 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - T::ONE;
        if !(f0 > T::ZERO) {
            return T::ZERO;
        }
        let mut t = T::ZERO;
        let mut f = f0;
        for _ in 0..64 {
            let mut slope = T::ZERO;
            for (&pi, &wi) in p.iter().zip(self.w.iter()) {
                let d = t + wi;
                let g = wi * pi / d;
                slope += T::TWO * g * g / d;
            }
            if !(slope > T::ZERO) {
                break;
            }
            let next = t + f / slope;
            if !(next > t) || !next.is_finite() {
                break;
            }
            t = next;
            let mut s = T::ZERO;
            for (&pi, &wi) in p.iter().zip(self.w.iter()) {
                let g = wi * pi / (t + wi);
                s += g * g;
            }
            f = s - T::ONE;
            if !(f > T::ZERO) {
                break;
            }
        }
        let mut gap = T::ZERO;
        for ((&pi, &wi), &ai) in p.iter().zip(self.w.iter()).zip(self.a.iter()) {
            let g = ai * pi * t / (t + wi);
            gap += g * g;
        }
        gap.sqrt()
    }
}

/// What a level must satisfy, in the normalized ellipsoid's units.
#[derive(Debug, Clone, Copy)]
enum EllTest<T> {
    /// Every angle between adjacent face normals at most this (radians; `π −` the smallest dihedral angle).
    NormalAngle(T),
    /// Every vertex at most this far from the ellipsoid (relative to the largest semi-axis).
    Deviation(T),
}

/// The sphere's level-`k` numbers that bound the ellipsoid's: `(s_k, δ_k)`.
fn sphere_numbers<T: Real>(level: u32) -> Result<(T, T), TessellateError> {
    let w = worst_case::<T>(level)?;
    Ok((w.max_normal_angle, w.max_deviation))
}

/// The positive octant's corners: the center points of the cube's faces `+x`, `+y`, `+z`.
fn octant<T: Real>() -> [V3<T>; 3] {
    let (o, l) = (T::ZERO, T::ONE);
    [V3::new(l, o, o), V3::new(o, l, o), V3::new(o, o, l)]
}

/// The geodesic midpoint of two unit vectors, exactly as the builder computes new center points.
fn mid<T: Real>(a: V3<T>, b: V3<T>) -> Result<V3<T>, TessellateError> {
    normalized(a.plus(b)).ok_or(TessellateError::Internal)
}

/// The four children of a triangle: the central one first, then the corners' (the order [`walk_octant`] and
/// [`leaf_at`] share).
fn children<P: Copy>(c: [P; 3], m01: P, m12: P, m20: P) -> [[P; 3]; 4] {
    let [c0, c1, c2] = c;
    [
        [m01, m12, m20],
        [c0, m01, m20],
        [m01, c1, m12],
        [m20, m12, c2],
    ]
}

/// Twice the signed area of the lattice triangle `(a, b, x)`, projected on the first two coordinates.
fn orient(a: [i64; 3], b: [i64; 3], x: [i64; 3]) -> Option<i64> {
    let (ux, uy) = (b[0].checked_sub(a[0])?, b[1].checked_sub(a[1])?);
    let (vx, vy) = (x[0].checked_sub(a[0])?, x[1].checked_sub(a[1])?);
    ux.checked_mul(vy)?.checked_sub(uy.checked_mul(vx)?)
}

/// The corners (center points, computed exactly as the builder computes them) of the level-`level` triangle of the
/// positive octant whose centroid is `target / 3`, in lattice coordinates (`|i| + |j| + |l| = 2^level`, so `target`
/// sums to `3 · 2^level`): O(level) midpoints along the refinement tree.
fn leaf_at<T: Real>(level: u32, target: [i64; 3]) -> Result<[V3<T>; 3], TessellateError> {
    let err = TessellateError::Internal;
    let n = 1i64.checked_shl(level).ok_or(err)?;
    // Lattice corners scaled by 3 so that the target is a lattice point too.
    let n3 = n.checked_mul(3).ok_or(err)?;
    let mut lat = [[n3, 0, 0], [0, n3, 0], [0, 0, n3]];
    let mut c = octant::<T>();
    let half = |a: [i64; 3], b: [i64; 3]| -> Option<[i64; 3]> {
        Some([
            a[0].checked_add(b[0])?.checked_div(2)?,
            a[1].checked_add(b[1])?.checked_div(2)?,
            a[2].checked_add(b[2])?.checked_div(2)?,
        ])
    };
    for _ in 0..level {
        let [l0, l1, l2] = lat;
        let kids = children(
            lat,
            half(l0, l1).ok_or(err)?,
            half(l1, l2).ok_or(err)?,
            half(l2, l0).ok_or(err)?,
        );
        let [c0, c1, c2] = c;
        let pts = children(c, mid(c0, c1)?, mid(c1, c2)?, mid(c2, c0)?);
        let mut found = None;
        for (k, p) in kids.iter().zip(pts.iter()) {
            let [a, b, d] = *k;
            let whole = orient(a, b, d).ok_or(err)?;
            let inside = [(a, b), (b, d), (d, a)].iter().all(|&(u, v)| {
                orient(u, v, target).is_some_and(|o| o == 0 || (o > 0) == (whole > 0))
            });
            if inside {
                found = Some((*k, *p));
                break;
            }
        }
        (lat, c) = found.ok_or(err)?;
    }
    Ok(c)
}

/// Centroids (times 3, lattice coordinates of level `level`) of the witness triangles: the corner triangle at
/// each axis tip, the central triangle, and the three triangles of the octant around each midpoint of its sides
/// (where the worst vertices and edges of oblate, prolate and triaxial ellipsoids sit).
fn witness_targets(level: u32) -> Result<([[i64; 3]; 13], usize), TessellateError> {
    let err = TessellateError::Internal;
    let mut out = [[0i64; 3]; 13];
    if level == 0 {
        *out.first_mut().ok_or(err)? = [1, 1, 1];
        return Ok((out, 1));
    }
    let n = 1i64.checked_shl(level).ok_or(err)?;
    let h3 = n.checked_div(2).and_then(|h| h.checked_mul(3)).ok_or(err)?;
    let tip = n.checked_mul(3).and_then(|x| x.checked_sub(2)).ok_or(err)?;
    let (hp1, hm1, hm2) = (
        h3.checked_add(1).ok_or(err)?,
        h3.checked_sub(1).ok_or(err)?,
        h3.checked_sub(2).ok_or(err)?,
    );
    let mut len = 0usize;
    let mut put = |t: [i64; 3]| -> Result<(), TessellateError> {
        *out.get_mut(len).ok_or(err)? = t;
        len = len.checked_add(1).ok_or(err)?;
        Ok(())
    };
    put([n, n, n])?;
    for (p, q, r) in [(0usize, 1usize, 2usize), (1, 2, 0), (2, 0, 1)] {
        // Axis tip p, and the three triangles around the midpoint of the side from axis p to axis q.
        for (vp, vq, vr) in [(tip, 1, 1), (hp1, hm2, 1), (hm1, hm1, 2), (hm2, hp1, 1)] {
            let mut t = [0i64; 3];
            for (axis, v) in [(p, vp), (q, vq), (r, vr)] {
                *t.get_mut(axis).ok_or(err)? = v;
            }
            put(t)?;
        }
    }
    Ok((out, len))
}

/// `Some(false)` if an explicitly known edge or vertex of level `level` violates the test (a witness that the
/// level fails), `Some(true)` if the axis-ratio guarantee of the module docs shows that it meets it, `None` when
/// neither decides.
fn decide_cheaply<T: Real>(
    e: &Ell<T>,
    level: u32,
    test: EllTest<T>,
) -> Result<Option<bool>, TessellateError> {
    let (s, delta) = sphere_numbers::<T>(level)?;
    let (targets, len) = witness_targets(level)?;
    for &t in targets.get(..len).ok_or(TessellateError::Internal)? {
        let c = leaf_at::<T>(level, t)?;
        if !leaf_meets(e, &c, test)? {
            return Ok(Some(false));
        }
    }
    let guaranteed = match test {
        // sin(angle/2) ≤ ratio · sin(s_k/2) for every pair of adjacent faces.
        EllTest::NormalAngle(limit) => e.ratio * (s * T::HALF).sin() <= (limit * T::HALF).sin(),
        // Every vertex is within δ_k (largest semi-axis = 1) of the ellipsoid.
        EllTest::Deviation(limit) => delta <= limit,
    };
    Ok(if guaranteed { Some(true) } else { None })
}

/// Does the level-`k` triangle with corners `c` pass the test: its three edges (normal angles) or its vertex?
fn leaf_meets<T: Real>(
    e: &Ell<T>,
    c: &[V3<T>; 3],
    test: EllTest<T>,
) -> Result<bool, TessellateError> {
    let [c0, c1, c2] = *c;
    match test {
        EllTest::NormalAngle(limit) => {
            for (x, y) in [(c0, c1), (c1, c2), (c2, c0)] {
                let a = e.normal_angle(x, y).ok_or(TessellateError::Internal)?;
                if !(a <= limit) {
                    return Ok(false);
                }
            }
            Ok(true)
        }
        EllTest::Deviation(limit) => {
            let p = tangent_planes_meet(c0, c1, c2).ok_or(TessellateError::Internal)?;
            Ok(e.vertex_meets(p, limit))
        }
    }
}

/// One triangle of the subdivided octant: its corners are center points of faces of the polyhedron.
#[derive(Debug, Clone, Copy)]
struct Tri<T> {
    c: [V3<T>; 3],
    depth: u32,
}

/// Depth-first walk over the refinement tree of the positive octant down to `level`, with an explicit stack
/// (each expansion pops one triangle and pushes at most four, so `3·level + 1` slots suffice).
///
/// `score(corners)` is asked for every triangle before it is pushed: `None` when nothing in it needs to be
/// visited (a bound clears it), else an upper bound of its worst value, and the children with the larger scores
/// are visited first (so that a violation, if any, is met early). `leaf(corners)` returns false to stop the walk.
/// Returns whether the walk ran to the end. Every step pops one of at most `(4^(level+1) − 1) / 3` triangles.
fn walk_octant<T: Real>(
    level: u32,
    mut score: impl FnMut(&[V3<T>; 3]) -> Option<T>,
    mut leaf: impl FnMut(&[V3<T>; 3]) -> Result<bool, TessellateError>,
) -> Result<bool, TessellateError> {
    const SLOTS: usize = 3 * MAX_LEVEL as usize + 2;
    let err = TessellateError::Internal;
    if level > MAX_LEVEL {
        return Err(TessellateError::LevelTooDeep {
            level,
            max: MAX_LEVEL,
        });
    }
    let zero = Tri {
        c: [V3::ZERO; 3],
        depth: 0,
    };
    let mut stack = [zero; SLOTS];
    let root = octant();
    if score(&root).is_none() {
        return Ok(true);
    }
    *stack.first_mut().ok_or(err)? = Tri { c: root, depth: 0 };
    let mut len = 1usize;
    // Number of triangles in the tree: (4^(level+1) − 1) / 3.
    let nodes = 4u64
        .checked_pow(level.checked_add(1).ok_or(err)?)
        .ok_or(err)?
        .checked_div(3)
        .ok_or(err)?;
    for _ in 0..nodes {
        let Some(top) = len.checked_sub(1) else {
            return Ok(true);
        };
        len = top;
        let tri = *stack.get(top).ok_or(err)?;
        if tri.depth >= level {
            if !leaf(&tri.c)? {
                return Ok(false);
            }
            continue;
        }
        let [c0, c1, c2] = tri.c;
        let depth = tri.depth.checked_add(1).ok_or(err)?;
        // The children that no bound clears, sorted by score (insertion sort of at most four).
        let mut kept = [(T::ZERO, zero); 4];
        let mut n = 0usize;
        for c in children(tri.c, mid(c0, c1)?, mid(c1, c2)?, mid(c2, c0)?) {
            let Some(sc) = score(&c) else { continue };
            let mut at = n;
            while let Some(prev) = at.checked_sub(1) {
                let p = *kept.get(prev).ok_or(err)?;
                if p.0 > sc {
                    *kept.get_mut(at).ok_or(err)? = p;
                    at = prev;
                } else {
                    break;
                }
            }
            *kept.get_mut(at).ok_or(err)? = (sc, Tri { c, depth });
            n = n.checked_add(1).ok_or(err)?;
        }
        // Ascending onto the stack: the largest score is popped first.
        for &(_, t) in kept.get(..n).ok_or(err)? {
            *stack.get_mut(len).ok_or(err)? = t;
            len = len.checked_add(1).ok_or(err)?;
        }
    }
    // The loop ran once per triangle of the tree; the stack must be empty now.
    if len == 0 { Ok(true) } else { Err(err) }
}

/// Decides `test` at `level` exactly by visiting every vertex (deviation) or every edge (normal angle) of the
/// positive octant — the polyhedron is symmetric under the three coordinate reflections — skipping the subtrees
/// that the bounds of the module docs clear, and stopping at the first violation.
fn decide_by_walk<T: Real>(
    e: &Ell<T>,
    level: u32,
    test: EllTest<T>,
) -> Result<bool, TessellateError> {
    let (s, delta) = sphere_numbers::<T>(level)?;
    let slack = T::ONE + T::EPSILON.sqrt();
    // A level-k vertex p has |p| − 1 ≤ δ_k and its direction within the chord σ_k of its triangle's corners.
    let sigma = (T::TWO * delta / (T::ONE + delta)).sqrt();
    let bound = |c: &[V3<T>; 3]| {
        let [c0, c1, c2] = *c;
        // Largest chord from c0 to any point of the triangle.
        let reach = c1
            .minus(c0)
            .length()
            .max(c2.minus(c0).length())
            .max(c2.minus(c1).length());
        let (worst, limit) = match test {
            EllTest::NormalAngle(limit) => {
                // Every level-k edge inside is an arc of at most s_k inside the triangle, where the normal map
                // stretches arcs by at most ratio / |S⁻¹c|, and |S⁻¹c| ≥ |S⁻¹c₀| − ratio · reach.
                let floor = e.unscale(c0).length() - e.ratio * reach;
                let w = if floor > T::ZERO {
                    s * e.ratio / floor
                } else {
                    T::INFINITY
                };
                (w, limit)
            }
            EllTest::Deviation(limit) => {
                // (|p| − 1)·|S p̂| with |S p̂| ≤ |S c₀| + reach + σ_k, or the supporting plane's height
                // δ_k / |S⁻¹p̂| plus the rolling ball's δ_k² / (2r), with |S⁻¹p̂| ≥ |S⁻¹c₀| − ratio (reach + σ_k).
                let far = delta * (e.scale(c0).length() + reach + sigma);
                let floor = e.unscale(c0).length() - e.ratio * (reach + sigma);
                let ball = if floor > T::ZERO {
                    delta / floor + delta * delta / (T::TWO * e.roll)
                } else {
                    T::INFINITY
                };
                (far.min(ball), limit)
            }
        };
        if worst * slack <= limit {
            None
        } else {
            Some(worst)
        }
    };
    walk_octant(level, bound, |c| leaf_meets(e, c, test))
}

/// Does the level-`level` polyhedron of `e` meet `test`? Cheap witnesses and guarantees first, the walk only
/// when they leave it open.
fn ellipsoid_meets<T: Real>(
    e: &Ell<T>,
    level: u32,
    test: EllTest<T>,
) -> Result<bool, TessellateError> {
    match decide_cheaply(e, level, test)? {
        Some(v) => Ok(v),
        None => decide_by_walk(e, level, test),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn worst_case_matches_the_papers_numbers() {
        // Level 0: the cube (dihedral 90°, corner at √3); level 1: dihedral 120° (the new faces' normals are 60°
        // apart, §4.3.3 cos a' = 1/2).
        let w0 = worst_case::<f64>(0).unwrap();
        assert!((w0.min_dihedral - core::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((w0.max_deviation - (3f64.sqrt() - 1.0)).abs() < 1e-15);
        let w1 = worst_case::<f64>(1).unwrap();
        assert!((w1.min_dihedral.to_degrees() - 120.0).abs() < 1e-12);
        // The Y-point (√2/2)(1,1,1) of §4.3.4 is the farthest vertex: √6/2 − 1.
        assert!((w1.max_deviation - (6f64.sqrt() / 2.0 - 1.0)).abs() < 1e-15);
        for k in 1..=MAX_LEVEL {
            let a = worst_case::<f64>(k - 1).unwrap();
            let b = worst_case::<f64>(k).unwrap();
            assert!(b.min_dihedral > a.min_dihedral && b.max_deviation < a.max_deviation);
            // From level 2 on, the side roughly halves.
            if k >= 2 {
                assert!((b.max_normal_angle / a.max_normal_angle - 0.5).abs() < 0.07);
            }
        }
    }

    #[test]
    fn f32_and_f64_agree() {
        for k in 0..=MAX_LEVEL {
            let a = worst_case::<f64>(k).unwrap();
            let b = worst_case::<f32>(k).unwrap();
            assert!(((b.max_deviation as f64) / a.max_deviation - 1.0).abs() < 1e-5);
            assert!(((b.max_normal_angle as f64) / a.max_normal_angle - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn bounds_pick_the_first_level_that_meets_them() {
        let deg = |d: f64| d.to_radians();
        let lvl = |b| min_level(Shape::Sphere(1.0_f64), b).unwrap();
        assert_eq!(lvl(Bound::MinDihedral(deg(90.0))), 0);
        assert_eq!(lvl(Bound::MinDihedral(deg(90.1))), 1);
        assert_eq!(lvl(Bound::MinDihedral(deg(120.1))), 2);
        assert_eq!(lvl(Bound::MaxDeviation(f64::INFINITY)), 0);
        assert_eq!(lvl(Bound::MaxDeviation(0.2248)), 1);
        assert_eq!(lvl(Bound::MaxDeviation(0.2247)), 2);
        // Radius scales the deviation.
        assert_eq!(
            min_level(Shape::Sphere(10.0_f64), Bound::MaxDeviation(2.248)).unwrap(),
            1
        );
        // Equal axes are a sphere.
        let b = Bound::MaxDeviation(1e-3);
        assert_eq!(
            min_level(Shape::Ellipsoid([2.0_f64, 2.0, 2.0]), b).unwrap(),
            min_level(Shape::Sphere(2.0_f64), b).unwrap()
        );
    }

    /// Distance from `y` to the spheroid with equatorial radius `a` and polar `c`, in closed form for a point in
    /// the meridian plane by a different route: bisection on the angle of the closest point (normal through `y`).
    fn spheroid_distance(a: f64, c: f64, rho: f64, z: f64) -> f64 {
        let foot = |t: f64| (a * t.cos(), c * t.sin());
        // The normal at foot(t) passes through y where g(t) = 0 (t in [0, π/2] for the first quadrant).
        let g = |t: f64| {
            let (x, w) = foot(t);
            let (nx, nw) = (x / (a * a), w / (c * c));
            (rho - x) * nw - (z - w) * nx
        };
        let (mut lo, mut hi) = (0.0_f64, core::f64::consts::FRAC_PI_2);
        for _ in 0..200 {
            let m = 0.5 * (lo + hi);
            if (g(lo) > 0.0) == (g(m) > 0.0) {
                lo = m;
            } else {
                hi = m;
            }
        }
        let (x, w) = foot(0.5 * (lo + hi));
        ((rho - x).powi(2) + (z - w).powi(2)).sqrt()
    }

    #[test]
    fn closest_point_distance_matches_a_meridian_bisection() {
        let (e, hi) = Ell::new([3.0_f64, 3.0, 1.0]).unwrap();
        assert_eq!(hi, 3.0);
        for (px, pz) in [
            (1.0_f64, 0.01),
            (0.3, 0.999),
            (0.8, 0.8),
            (1.0001, 0.0),
            (0.0, 1.2),
        ] {
            let p = V3::new(px, 0.0, pz);
            let want = spheroid_distance(1.0, 1.0 / 3.0, px, pz / 3.0);
            let got = e.distance(p);
            assert!(
                (got - want).abs() <= 1e-12 * want.max(1e-3),
                "{px} {pz}: {got} vs {want}"
            );
            // The bracket of vertex_meets agrees with the solved distance on both sides.
            assert!(e.vertex_meets(p, want * (1.0 + 1e-9)));
            assert!(!e.vertex_meets(p, want * (1.0 - 1e-9)));
        }
        assert_eq!(e.distance(V3::new(0.5, 0.5, 0.0)), 0.0); // inside
    }

    #[test]
    fn witness_triangles_are_lattice_leaves() {
        // Each witness target lies strictly inside exactly one leaf, whose corners are unit center points.
        for level in 0..=4 {
            let (t, len) = witness_targets(level).unwrap();
            for &target in &t[..len] {
                assert_eq!(target.iter().sum::<i64>(), 3 << level, "{target:?}");
                let c = leaf_at::<f64>(level, target).unwrap();
                for v in c {
                    assert!((v.length() - 1.0).abs() < 1e-15);
                }
            }
        }
        // The tip witness at level 3 is the corner triangle at +x: its vertex is (1, tan(θ/2), tan(θ/2)).
        let c = leaf_at::<f64>(3, [22, 1, 1]).unwrap();
        let p = tangent_planes_meet(c[0], c[1], c[2]).unwrap();
        let tau = (core::f64::consts::PI / 32.0).tan();
        assert!(
            (p.x - 1.0).abs() < 1e-14 && (p.y - tau).abs() < 1e-14 && (p.z - tau).abs() < 1e-14
        );
    }

    /// The smallest level by the unpruned walk of [`ellipsoid_worst_case`].
    fn by_full_walk(
        axes: [f64; 3],
        ok: impl Fn(&EllipsoidWorstCase<f64>) -> bool,
        top: u32,
    ) -> u32 {
        (0..=top)
            .find(|&k| ok(&ellipsoid_worst_case(axes, k).unwrap()))
            .unwrap_or(top + 1)
    }

    #[test]
    fn ellipsoid_level_agrees_with_the_unpruned_walk() {
        let top = if cfg!(miri) { 2 } else { 4 };
        for axes in [[3.0_f64, 2.0, 1.0], [1.0, 1.0, 0.3], [1.0, 4.0, 1.0]] {
            let worst: [EllipsoidWorstCase<f64>; 5] = core::array::from_fn(|k| {
                ellipsoid_worst_case(axes, k.min(top as usize) as u32).unwrap()
            });
            for k in 0..top as usize {
                // Bounds halfway between consecutive levels' exact values: the answer is k + 1.
                let dev = 0.5 * (worst[k].max_deviation + worst[k + 1].max_deviation);
                assert_eq!(
                    min_level(Shape::Ellipsoid(axes), Bound::MaxDeviation(dev)),
                    Ok(k as u32 + 1)
                );
                assert_eq!(
                    by_full_walk(axes, |w| w.max_deviation <= dev, top),
                    k as u32 + 1
                );
                let phi = 0.5 * (worst[k].min_dihedral + worst[k + 1].min_dihedral);
                assert_eq!(
                    min_level(Shape::Ellipsoid(axes), Bound::MinDihedral(phi)),
                    Ok(k as u32 + 1)
                );
            }
        }
    }

    #[test]
    #[cfg_attr(miri, ignore)]
    fn ellipsoid_walk_decides_levels_the_witnesses_leave_open() {
        // Bounds just above each level's exact worst value, where only the walk can show that the level meets.
        let axes = [3.0_f64, 2.0, 1.0];
        let (e, hi) = Ell::new(axes).unwrap();
        for k in 2..=6u32 {
            let w = ellipsoid_worst_case(axes, k).unwrap();
            let below = ellipsoid_worst_case(axes, k - 1).unwrap();
            for f in [1e-9, 1e-6, 1e-3] {
                let limit = w.max_deviation * (1.0 + f) / hi;
                assert_eq!(decide_cheaply(&e, k, EllTest::Deviation(limit)), Ok(None));
                let limit = w.max_normal_angle * (1.0 + f);
                assert_eq!(decide_cheaply(&e, k, EllTest::NormalAngle(limit)), Ok(None));
                let b = Bound::MaxDeviation(w.max_deviation * (1.0 + f));
                assert!(below.max_deviation > w.max_deviation * (1.0 + f));
                assert_eq!(min_level(Shape::Ellipsoid(axes), b), Ok(k), "{b:?}");
                let a = w.max_normal_angle * (1.0 + f);
                let b = Bound::MinDihedral(core::f64::consts::PI - a);
                assert_eq!(min_level(Shape::Ellipsoid(axes), b), Ok(k), "{b:?}");
            }
        }
    }

    #[test]
    fn ellipsoid_f32_gives_the_f64_level() {
        let axes = [3.0_f64, 2.0, 1.0];
        let w = [
            ellipsoid_worst_case(axes, 2).unwrap(),
            ellipsoid_worst_case(axes, 3).unwrap(),
        ];
        let dev = 0.5 * (w[0].max_deviation + w[1].max_deviation);
        let axes32 = axes.map(|a| a as f32);
        assert_eq!(
            min_level(Shape::Ellipsoid(axes32), Bound::MaxDeviation(dev as f32)),
            Ok(3)
        );
    }

    #[test]
    fn impossible_requests_are_typed_errors() {
        let s = Shape::Sphere(1.0_f64);
        for b in [
            Bound::MinDihedral(f64::NAN),
            Bound::MinDihedral(core::f64::consts::PI),
            Bound::MinDihedral(-0.1),
            Bound::MaxDeviation(0.0),
            Bound::MaxDeviation(f64::NAN),
            Bound::ScreenSpace {
                distance: 0.5,
                pixel_angle: 1e-3,
            },
            Bound::ScreenSpace {
                distance: 5.0,
                pixel_angle: 0.0,
            },
        ] {
            assert_eq!(min_level(s, b), Err(TessellateError::InvalidBound), "{b:?}");
        }
        assert_eq!(
            min_level(Shape::Sphere(1.0_f64), Bound::MaxDeviation(1e-300)),
            Err(TessellateError::Unreachable)
        );
        assert_eq!(
            min_level(Shape::Sphere(-1.0_f64), Bound::MaxDeviation(1.0)),
            Err(TessellateError::InvalidShape)
        );
        assert_eq!(
            min_level(
                Shape::Ellipsoid([1.0_f64, f64::MAX, f64::MIN_POSITIVE]),
                Bound::MaxDeviation(1.0)
            ),
            Err(TessellateError::AxisRatioTooLarge)
        );
        // Beyond MAX_AXIS_RATIO (a fuzz input at 7e134 : 1 had the solver report a zero deviation).
        assert_eq!(
            min_level(
                Shape::Ellipsoid([
                    1.0000000006402843_f64,
                    7.268387242956069e134,
                    0.1511801481283328
                ]),
                Bound::MaxDeviation(0.01)
            ),
            Err(TessellateError::AxisRatioTooLarge)
        );
        assert!(
            min_level(
                Shape::Ellipsoid([1.0_f64, 0.9e6, 1.0]),
                Bound::MaxDeviation(1.0)
            )
            .is_ok()
        );
        // The squared axis ratio must stay a normal number.
        assert_eq!(
            min_level(
                Shape::Ellipsoid([1.0_f64, 1e200, 1.0]),
                Bound::MaxDeviation(1.0)
            ),
            Err(TessellateError::AxisRatioTooLarge)
        );
        assert!(
            min_level(
                Shape::Ellipsoid([1.0_f64, 0.9e6, 1.0]),
                Bound::MaxDeviation(1e7)
            )
            .is_ok()
        );
    }

    #[test]
    fn screen_space_error_is_the_inverse_of_the_allowed_deviation() {
        let (r, d, p) = (1.0_f64, 10.0, 1e-3);
        let s = (p / 2.0).sin();
        let allowed = 2.0 * (d - r) * s / (1.0 + 2.0 * s);
        assert!((screen_space_error(r, d, allowed) - p).abs() < 1e-15);
        assert_eq!(screen_space_error(r, 1.0, 0.1), core::f64::consts::PI);
    }
}
