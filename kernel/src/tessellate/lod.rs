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
//! the sphere's scaled by `S = diag(A, B, C)`. The results for an ellipsoid are *sufficient* levels from
//! guarantees that hold for every face, exact when `A = B = C`:
//! * normals: the face normal is `S⁻¹n / |S⁻¹n|`, and `|â − b̂| ≤ |a − b| / √(|a||b|)` gives
//!   `sin(θ'/2) ≤ (max axis / min axis) · sin(θ/2)` between the normals of adjacent faces;
//! * deviation: a vertex `(1 + δ)·u` of the unit polyhedron maps to `S(1 + δ)u`, at most `max axis · δ` from the
//!   surface point `S u`.
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
//! # Ok::<(), curvicast::tessellate::TessellateError>(())
//! ```

use super::TessellateError;
use super::bevel::MAX_LEVEL;
use crate::real::Real;

/// The object whose level is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape<T> {
    /// A sphere of this radius: the level is exactly the smallest that meets the bound.
    Sphere(T),
    /// An ellipsoid with these semi-axes: the level is the smallest whose guarantee (see the module docs) meets
    /// the bound — sufficient, and the smallest when the axes are equal.
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
/// level.
///
/// # Errors
/// [`TessellateError::InvalidShape`] for a non-positive or non-finite radius/axis, [`TessellateError::InvalidBound`]
/// for a bound out of range (NaN, a dihedral angle ≥ π or < 0, a deviation ≤ 0, a pixel angle outside `(0, π]`, an
/// eye inside the object's bounding sphere), [`TessellateError::Unreachable`] when no level up to [`MAX_LEVEL`]
/// meets it.
pub fn min_level<T: Real>(shape: Shape<T>, bound: Bound<T>) -> Result<u32, TessellateError> {
    let (r_max, ratio) = match shape {
        Shape::Sphere(r) => {
            if !(r > T::ZERO) || !r.is_finite() {
                return Err(TessellateError::InvalidShape);
            }
            (r, T::ONE)
        }
        Shape::Ellipsoid(axes) => {
            let mut lo = T::INFINITY;
            let mut hi = T::ZERO;
            for a in axes {
                if !(a > T::ZERO) || !a.is_finite() {
                    return Err(TessellateError::InvalidShape);
                }
                lo = lo.min(a);
                hi = hi.max(a);
            }
            let ratio = hi / lo;
            if !ratio.is_finite() {
                return Err(TessellateError::InvalidShape);
            }
            (hi, ratio)
        }
    };
    // Turn the bound into a test on the unit sphere's worst case.
    enum Test<T> {
        /// ratio · sin(s/2) ≤ limit (= cos(φ/2)); for the sphere (ratio 1) the same as s ≤ π − φ.
        HalfChord(T),
        /// max_deviation ≤ limit (relative to the largest semi-axis).
        Deviation(T),
    }
    let test = match bound {
        Bound::MinDihedral(phi) => {
            if !(phi >= T::ZERO) || !(phi < T::PI) {
                return Err(TessellateError::InvalidBound);
            }
            if ratio == T::ONE {
                // Exact comparison on the angle itself for spheres.
                let limit = T::PI - phi;
                return first_level(|w: &WorstCase<T>| w.max_normal_angle <= limit);
            }
            Test::HalfChord((phi * T::HALF).cos())
        }
        Bound::MaxDeviation(e) => {
            if !(e > T::ZERO) {
                return Err(TessellateError::InvalidBound);
            }
            Test::Deviation(e / r_max)
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
            Test::Deviation(allowed / r_max)
        }
    };
    match test {
        Test::HalfChord(limit) => {
            first_level(|w: &WorstCase<T>| ratio * (w.one_minus_cos * T::HALF).sqrt() <= limit)
        }
        Test::Deviation(limit) => first_level(|w: &WorstCase<T>| w.max_deviation <= limit),
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
        // An ellipsoid never gets a coarser level than its largest sphere, and equal axes are a sphere.
        let b = Bound::MaxDeviation(1e-3);
        assert_eq!(
            min_level(Shape::Ellipsoid([2.0_f64, 2.0, 2.0]), b).unwrap(),
            min_level(Shape::Sphere(2.0_f64), b).unwrap()
        );
        assert!(
            min_level(
                Shape::Ellipsoid([2.0_f64, 1.0, 0.5]),
                Bound::MinDihedral(deg(170.0))
            )
            .unwrap()
                >= min_level(Shape::Sphere(1.0_f64), Bound::MinDihedral(deg(170.0))).unwrap()
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
            Err(TessellateError::InvalidShape)
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
