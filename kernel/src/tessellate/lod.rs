//! The a-priori level of detail (the edge-beveling thesis, chapter 5): "model only what a scene needs".
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

use super::bevel::MAX_LEVEL;
pub use super::error::MAX_AXIS_RATIO;
use super::error::TessellateError;
use crate::real::Real;
use ellipsoid::{Ell, EllTest, ellipsoid_meets};
pub use ellipsoid::{EllipsoidWorstCase, ellipsoid_worst_case};
pub use sphere::{WorstCase, worst_case};
use sphere::{next_u, worst_from_u};

mod ellipsoid;
mod sphere;
#[cfg(test)]
mod tests;

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
