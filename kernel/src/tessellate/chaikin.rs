//! Rational Chaikin refinement: polygons that converge to circles, ellipses and sheared ellipses (the edge-beveling thesis
//! chapter 3).
//!
//! A closed control polygon is a cycle of *arcs* (§3.2.2 "second method", §3.3): arc `i` runs from the tangent
//! point `start_i` past the corner `corner_i` to the next arc's tangent point `start_{i+1}`, and carries the
//! interior angle `α_i` of its level-0 corner (its *parent* angle). One refinement of the arc `{T₀, C, T₁}` at level
//! `k` cuts the corner with the tangent line at the arc's midpoint:
//!
//! ```text
//! C'  = (1 − t_k) T₀ + t_k C          M = (C' + C'') / 2  (the new tangent point)
//! C'' = t_k C + (1 − t_k) T₁           t_k / (1 − t_k) = cos((π − α) / 2^(k+1))   (eq. 3.1)
//! ```
//!
//! so `{T₀, C, T₁}` becomes `{T₀, C', M}` and `{M, C'', T₁}`. For a circle (and any arc whose control polygon has
//! two equal sides, §3.3) every tangent point lies on the circle and every edge `C'C''` is tangent there; the
//! parameter is non-stationary (`t_k → 1/2`). Because the rule uses ratios along lines only, an affine image of
//! the square's control polygon refined with `α = π/2` is the same affine image of the refined circle: ellipses by
//! scaling (§3.4) and sheared circles and ellipses (§3.6).
//!
//! Level `k` of a closed curve of `n` arcs has `n·2^k` arcs, written as `2·n·2^k` points alternating tangent point
//! (even index, on the curve) and corner (odd index, a vertex of the polygon whose edges touch the curve); the
//! square's curves have [`square_len`]`(k) = 2^(k+3)` points.
//!
//! ```
//! use curvicast::tessellate::chaikin;
//! let mut out = [[0.0_f64; 2]; chaikin::square_len(3)];
//! chaikin::circle([0.0, 0.0], 2.0, 3, &mut out)?;
//! for (i, p) in out.iter().enumerate() {
//!     let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
//!     if i % 2 == 0 {
//!         assert!((r - 2.0).abs() < 1e-14); // tangent points lie on the circle
//!     } else {
//!         assert!(r > 2.0); // corners outside
//!     }
//! }
//! # Ok::<(), curvicast::tessellate::TessellateError>(())
//! ```

use super::error::{TessellateError, need};
use crate::real::Real;

/// The deepest level accepted: `2^21` points per arc, so every length fits a 32-bit `usize`.
pub const MAX_LEVEL: u32 = 20;

/// One arc of a closed control polygon: from the tangent point `start` past `corner` to the next arc's `start`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc<T> {
    /// The tangent point where the arc begins (on the curve).
    pub start: [T; 2],
    /// The corner of the control polygon between this tangent point and the next.
    pub corner: [T; 2],
    /// The interior angle at the level-0 corner (the parent angle α of §3.3), in `(0, π)`.
    pub alpha: T,
}

/// Points written per arc at `level`: `2^(level+1)`. Saturates at `usize::MAX` above [`MAX_LEVEL`].
pub const fn points_per_arc(level: u32) -> usize {
    if level > MAX_LEVEL {
        return usize::MAX;
    }
    match 2usize.checked_pow(level) {
        Some(p) => match p.checked_mul(2) {
            Some(q) => q,
            None => usize::MAX,
        },
        None => usize::MAX,
    }
}

/// Points of a closed curve of `arcs` arcs at `level`: `arcs · 2^(level+1)`. Saturates at `usize::MAX`.
pub const fn closed_len(arcs: usize, level: u32) -> usize {
    match points_per_arc(level).checked_mul(arcs) {
        Some(n) => n,
        None => usize::MAX,
    }
}

/// Points of a circle, ellipse or sheared ellipse (four arcs from the square) at `level`: `2^(level+3)`.
pub const fn square_len(level: u32) -> usize {
    closed_len(4, level)
}

fn lerp<T: Real>(a: [T; 2], b: [T; 2], t: T) -> [T; 2] {
    let [ax, ay] = a;
    let [bx, by] = b;
    [ax + t * (bx - ax), ay + t * (by - ay)]
}

fn finite<T: Real>(p: [T; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// Refines the closed control polygon `arcs` to `level` and writes `closed_len(arcs.len(), level)` points into
/// the front of `out`: per arc, `2^level` pairs (tangent point, corner), in order around the curve. Returns the
/// number of points written.
///
/// # Errors
/// [`TessellateError::InvalidControlPolygon`] for no arcs, a non-finite point or an `alpha` outside `(0, π)`;
/// [`TessellateError::LevelTooDeep`]; [`TessellateError::BufferTooSmall`].
pub fn refine_closed<T: Real>(
    arcs: &[Arc<T>],
    level: u32,
    out: &mut [[T; 2]],
) -> Result<usize, TessellateError> {
    if level > MAX_LEVEL {
        return Err(TessellateError::LevelTooDeep {
            level,
            max: MAX_LEVEL,
        });
    }
    let first = arcs.first().ok_or(TessellateError::InvalidControlPolygon)?;
    for a in arcs {
        if !finite(a.start) || !finite(a.corner) || !(a.alpha > T::ZERO) || !(a.alpha < T::PI) {
            return Err(TessellateError::InvalidControlPolygon);
        }
    }
    let per = points_per_arc(level);
    if per == 0 {
        // Never (at least 2 points per arc), but `chunks_exact_mut` panics on 0: the check removes that path.
        return Err(TessellateError::Internal);
    }
    let total = closed_len(arcs.len(), level);
    need("point", total, out.len())?;
    let out = out.get_mut(..total).ok_or(TessellateError::Internal)?;
    let ends = arcs.iter().skip(1).chain(core::iter::once(first));
    for ((arc, next), block) in arcs.iter().zip(ends).zip(out.chunks_exact_mut(per)) {
        refine_arc(arc, next.start, level, block)?;
    }
    Ok(total)
}

/// Refines one arc in place in `block` (length `2^(level+1)`), ending at the tangent point `end`.
fn refine_arc<T: Real>(
    arc: &Arc<T>,
    end: [T; 2],
    level: u32,
    block: &mut [[T; 2]],
) -> Result<(), TessellateError> {
    let err = TessellateError::Internal;
    *block.get_mut(0).ok_or(err)? = arc.start;
    *block.get_mut(1).ok_or(err)? = arc.corner;
    let supplement = T::PI - arc.alpha;
    let mut pairs: usize = 1;
    for k in 0..level {
        // eq. 3.1: t_k / (1 − t_k) = cos((π − α) / 2^(k+1)).
        let shift = i32::try_from(k)
            .map_err(|_| err)?
            .checked_add(1)
            .ok_or(err)?;
        let c = supplement.scalbn(shift.checked_neg().ok_or(err)?).cos();
        let t = c / (T::ONE + c);
        // Back to front, so that nothing is overwritten before it is read: pair i moves to 2i.
        for i in (0..pairs).rev() {
            let at = |m: usize, o: usize| m.checked_mul(i)?.checked_add(o);
            let t0 = *block.get(at(2, 0).ok_or(err)?).ok_or(err)?;
            let cc = *block.get(at(2, 1).ok_or(err)?).ok_or(err)?;
            let t1 = if i.checked_add(1).ok_or(err)? < pairs {
                *block.get(at(4, 4).ok_or(err)?).ok_or(err)? // already moved: the next pair's tangent point
            } else {
                end
            };
            let c1 = lerp(t0, cc, t);
            let c2 = lerp(t1, cc, t);
            let mid = lerp(c1, c2, T::HALF);
            *block.get_mut(at(4, 0).ok_or(err)?).ok_or(err)? = t0;
            *block.get_mut(at(4, 1).ok_or(err)?).ok_or(err)? = c1;
            *block.get_mut(at(4, 2).ok_or(err)?).ok_or(err)? = mid;
            *block.get_mut(at(4, 3).ok_or(err)?).ok_or(err)? = c2;
        }
        pairs = pairs.checked_mul(2).ok_or(err)?;
    }
    Ok(())
}

/// The image of the unit circle under `x ↦ center + M x` (`m` row-major), refined from the image of the square
/// `(±1, ±1)` with `α = π/2` (§3.4, §3.6): an ellipse for any invertible `M`. Writes [`square_len`]`(level)` points
/// starting at the image of `(1, 0)`, counter-clockwise for `det M > 0`.
///
/// # Errors
/// As [`refine_closed`]; [`TessellateError::InvalidShape`] for a non-finite or singular `M` or center.
pub fn affine_circle<T: Real>(
    center: [T; 2],
    m: [[T; 2]; 2],
    level: u32,
    out: &mut [[T; 2]],
) -> Result<usize, TessellateError> {
    let [[a, b], [c, d]] = m;
    let det = a * d - b * c;
    if !det.is_finite() || det == T::ZERO || !finite(center) {
        return Err(TessellateError::InvalidShape);
    }
    let map = |x: T, y: T| [center[0] + a * x + b * y, center[1] + c * x + d * y];
    let (o, l) = (T::ZERO, T::ONE);
    let alpha = T::FRAC_PI_2;
    let arcs = [
        Arc {
            start: map(l, o),
            corner: map(l, l),
            alpha,
        },
        Arc {
            start: map(o, l),
            corner: map(-l, l),
            alpha,
        },
        Arc {
            start: map(-l, o),
            corner: map(-l, -l),
            alpha,
        },
        Arc {
            start: map(o, -l),
            corner: map(l, -l),
            alpha,
        },
    ];
    refine_closed(&arcs, level, out)
}

/// A circle of radius `r` (§3.2): [`affine_circle`] with `M = r·I`.
///
/// # Errors
/// As [`affine_circle`]; [`TessellateError::InvalidShape`] unless `r` is positive and finite.
pub fn circle<T: Real>(
    center: [T; 2],
    r: T,
    level: u32,
    out: &mut [[T; 2]],
) -> Result<usize, TessellateError> {
    ellipse(center, r, r, level, out)
}

/// The axis-aligned ellipse `x²/a² + y²/b² = 1` about `center`, by scaling the square into the rectangle
/// `(±a, ±b)` (§3.4).
///
/// # Errors
/// As [`affine_circle`]; [`TessellateError::InvalidShape`] unless `a` and `b` are positive and finite.
pub fn ellipse<T: Real>(
    center: [T; 2],
    a: T,
    b: T,
    level: u32,
    out: &mut [[T; 2]],
) -> Result<usize, TessellateError> {
    sheared_ellipse(center, a, b, T::ZERO, level, out)
}

/// The sheared ellipse of §3.6: every point `(a x, b y)` of the ellipse becomes `(a x + s·b y, b y)`; its control
/// polygon is the parallelogram with corners `(±a ± s b, ±b)`.
///
/// # Errors
/// As [`affine_circle`]; [`TessellateError::InvalidShape`] unless `a`, `b` are positive and finite and `s` finite.
pub fn sheared_ellipse<T: Real>(
    center: [T; 2],
    a: T,
    b: T,
    s: T,
    level: u32,
    out: &mut [[T; 2]],
) -> Result<usize, TessellateError> {
    if !(a > T::ZERO) || !(b > T::ZERO) || !a.is_finite() || !b.is_finite() || !s.is_finite() {
        return Err(TessellateError::InvalidShape);
    }
    affine_circle(center, [[a, s * b], [T::ZERO, b]], level, out)
}

/// The arcs of a polygon whose sides are all tangent to the circle about `center` (§3.5: "begin with any polygon
/// that has all of its sides tangent to the circle … use a different α for each section"): the tangent point on
/// each side is the foot of the perpendicular from `center`, and each corner's α is its interior angle. Writes
/// `corners.len()` arcs (arc `i` at corner `i`) and returns that count.
///
/// # Errors
/// [`TessellateError::InvalidControlPolygon`] for fewer than three corners or a degenerate corner;
/// [`TessellateError::BufferTooSmall`].
pub fn arcs_of_tangential_polygon<T: Real>(
    center: [T; 2],
    corners: &[[T; 2]],
    arcs: &mut [Arc<T>],
) -> Result<usize, TessellateError> {
    let n = corners.len();
    if n < 3 {
        return Err(TessellateError::InvalidControlPolygon);
    }
    need("arc", n, arcs.len())?;
    let bad = TessellateError::InvalidControlPolygon;
    let sub = |p: [T; 2], q: [T; 2]| [p[0] - q[0], p[1] - q[1]];
    let dot = |p: [T; 2], q: [T; 2]| p[0] * q[0] + p[1] * q[1];
    let prevs = corners.iter().cycle().skip(n.checked_sub(1).ok_or(bad)?);
    let nexts = corners.iter().cycle().skip(1);
    for (((&c, &p), &q), arc) in corners.iter().zip(prevs).zip(nexts).zip(arcs.iter_mut()) {
        let e = sub(c, p);
        let ee = dot(e, e);
        if !(ee > T::ZERO) || !ee.is_finite() {
            return Err(bad);
        }
        let t = dot(sub(center, p), e) / ee;
        let start = lerp(p, c, t);
        let (u, v) = (sub(p, c), sub(q, c));
        let alpha = (u[0] * v[1] - u[1] * v[0]).abs().atan2(dot(u, v));
        if !finite(start) || !(alpha > T::ZERO) || !(alpha < T::PI) {
            return Err(bad);
        }
        *arc = Arc {
            start,
            corner: c,
            alpha,
        };
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec;

    /// Checks a refined curve against the unit circle after mapping it back by `inv` (the inverse affine map).
    fn check_on_unit_circle(
        out: &[[f64; 2]],
        level: u32,
        inv: impl Fn([f64; 2]) -> [f64; 2],
        tol: f64,
    ) {
        assert_eq!(out.len(), square_len(level));
        let theta = core::f64::consts::PI / f64::from(2u32.pow(level + 2)); // half the arc per corner
        for (i, &p) in out.iter().enumerate() {
            let [x, y] = inv(p);
            let r = x.hypot(y);
            if i % 2 == 0 {
                assert!((r - 1.0).abs() < tol, "tangent point {i} at radius {r}");
                // Evenly spaced: the i/2-th of 4·2^level points around the circle.
                let want = 2.0 * theta * (i / 2) as f64;
                let got = y.atan2(x).rem_euclid(2.0 * core::f64::consts::PI);
                // (modulo a turn: an angle a rounding below 0 reads as just below 2π)
                let off = (got - want).abs();
                assert!(
                    off.min(2.0 * core::f64::consts::PI - off) < tol,
                    "tangent point {i} at angle {got}, want {want}"
                );
            } else {
                assert!(
                    (r * theta.cos() - 1.0).abs() < tol,
                    "corner {i} at radius {r}"
                );
            }
        }
        // Each edge (corner, tangent point, corner) is tangent: the tangent point is perpendicular to the edge.
        for k in (0..out.len()).step_by(2) {
            let t = inv(out[k]);
            let c0 = inv(out[(k + out.len() - 1) % out.len()]);
            let c1 = inv(out[k + 1]);
            let e = [c1[0] - c0[0], c1[1] - c0[1]];
            assert!((e[0] * t[0] + e[1] * t[1]).abs() < tol * 4.0);
        }
    }

    #[test]
    fn square_refines_to_the_inscribed_circle() {
        for level in 0..=6 {
            let mut out = vec![[0.0; 2]; square_len(level)];
            assert_eq!(circle([0.0, 0.0], 1.0, level, &mut out).unwrap(), out.len());
            check_on_unit_circle(&out, level, |p| p, 1e-14);
        }
        // Level 1 corner from the paper (§3.2.1): the octagon's corner (1, √2 − 1).
        let mut out = vec![[0.0; 2]; square_len(1)];
        circle([0.0, 0.0], 1.0, 1, &mut out).unwrap();
        assert!((out[1][0] - 1.0).abs() < 1e-15 && (out[1][1] - (2f64.sqrt() - 1.0)).abs() < 1e-15);
    }

    #[test]
    fn non_stationary_parameter_matches_eq_3_1() {
        // One arc with a 60° corner (not the square's 90°), refined by the kernel: the corner cut at level k puts
        // C' at t_k along T₀C, where t_k / (1 − t_k) = cos((π − α) / 2^(k+1)) (eq. 3.1); read t_k back off the
        // output at levels 1 and 2 (level 2 cuts the corner C' of the arc {T₀, C', M}).
        let alpha = core::f64::consts::PI / 3.0;
        let (t0, c) = ([0.0, 0.0], [1.0, 0.0]);
        let t1 = [0.5, 0.75_f64.sqrt()];
        let arcs = [
            Arc {
                start: t0,
                corner: c,
                alpha,
            },
            Arc {
                start: t1,
                corner: [-0.5, 0.5],
                alpha: 1.0,
            },
        ];
        let ratio = |k: u32| ((core::f64::consts::PI - alpha) / f64::from(2u32.pow(k + 1))).cos();
        let dist = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
        let mut out1 = vec![[0.0; 2]; closed_len(2, 1)];
        refine_closed(&arcs, 1, &mut out1).unwrap();
        assert_eq!((out1[0], out1[4]), (t0, t1));
        let t_1 = dist(out1[1], t0) / dist(c, t0);
        assert!((t_1 / (1.0 - t_1) - ratio(0)).abs() < 1e-14, "t_1 = {t_1}");
        // C'' lies at the same t_1 from T₁ toward C.
        assert!((dist(out1[3], t1) / dist(c, t1) - t_1).abs() < 1e-14);
        let mut out2 = vec![[0.0; 2]; closed_len(2, 2)];
        refine_closed(&arcs, 2, &mut out2).unwrap();
        let t_2 = dist(out2[1], t0) / dist(out1[1], t0);
        assert!((t_2 / (1.0 - t_2) - ratio(1)).abs() < 1e-14, "t_2 = {t_2}");
        // The two parameters differ: the refinement is non-stationary.
        assert!(t_2 - t_1 > 0.05);
    }

    /// A general affine image (every entry of `M` non-zero, a negative one among them): its points map back onto
    /// the unit circle by `M⁻¹`.
    #[test]
    fn affine_circle_with_a_full_matrix_maps_back_onto_the_unit_circle() {
        let (m, c) = ([[2.0, 0.5], [-0.7, 1.5]], [1.0, -2.0]);
        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        for level in 0..=4 {
            let mut out = vec![[0.0; 2]; square_len(level)];
            affine_circle(c, m, level, &mut out).unwrap();
            check_on_unit_circle(
                &out,
                level,
                |[x, y]| {
                    let (u, v) = (x - c[0], y - c[1]);
                    [
                        (m[1][1] * u - m[0][1] * v) / det,
                        (m[0][0] * v - m[1][0] * u) / det,
                    ]
                },
                1e-13,
            );
        }
    }

    #[test]
    fn ellipse_and_sheared_ellipse_are_affine_images() {
        let (a, b, s, cx, cy) = (3.0, 0.5, 0.75, 1.0, -2.0);
        for level in 0..=5 {
            let mut out = vec![[0.0; 2]; square_len(level)];
            ellipse([cx, cy], a, b, level, &mut out).unwrap();
            check_on_unit_circle(&out, level, |[x, y]| [(x - cx) / a, (y - cy) / b], 1e-13);
            // counter-clockwise (the map's determinant is positive): at least 0.8 π a b, at most 4 a b (the
            // circumscribed parallelogram)
            let area = |p: &[[f64; 2]]| {
                (0..p.len()).fold(0.0, |acc, k| {
                    let ([x0, y0], [x1, y1]) = (p[k], p[(k + 1) % p.len()]);
                    acc + 0.5 * (x0 * y1 - x1 * y0)
                })
            };
            let full = core::f64::consts::PI * a * b;
            assert!(
                area(&out) > 0.8 * full && area(&out) <= 4.0 * a * b,
                "{level}: {}",
                area(&out)
            );
            sheared_ellipse([cx, cy], a, b, s, level, &mut out).unwrap();
            assert!(
                area(&out) > 0.8 * full && area(&out) <= 4.0 * a * b,
                "{level}: {}",
                area(&out)
            );
            check_on_unit_circle(
                &out,
                level,
                |[x, y]| {
                    let yy = (y - cy) / b;
                    [((x - cx) - s * b * yy) / a, yy]
                },
                1e-13,
            );
        }
    }

    #[test]
    fn f32_circle() {
        let mut out = vec![[0.0_f32; 2]; square_len(4)];
        circle([0.0, 0.0], 1.0_f32, 4, &mut out).unwrap();
        for p in out.iter().step_by(2) {
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 4e-7);
        }
    }

    #[test]
    fn tangential_triangle_and_kite_refine_to_the_circle() {
        // A triangle and a kite circumscribing the unit circle: each corner has its own α (§3.5).
        let tri = [[-3f64.sqrt(), -1.0], [3f64.sqrt(), -1.0], [0.0, 2.0]];
        let k = 2f64.sqrt();
        // The kite's corners: (0,-k) and (0, 3) on the axis, and (±x, y) where the tangents meet.
        let kite_top = 3.0;
        let kite = {
            // Tangent lines from (0, 3) touch the circle at y = 1/3; from (0, -k) at y = -1/k.
            let (y1, y2) = (1.0 / kite_top, -1.0 / k);
            let (x1, x2) = ((1.0 - y1 * y1).sqrt(), (1.0 - y2 * y2).sqrt());
            // Intersection of the tangent lines x·x1 + y·y1 = 1 and x·x2 + y·y2 = 1.
            let det = x1 * y2 - x2 * y1;
            let (px, py) = ((y2 - y1) / det, (x1 - x2) / det);
            [[0.0, -k], [px, py], [0.0, kite_top], [-px, py]]
        };
        for corners in [&tri[..], &kite[..]] {
            let mut arcs = vec![
                Arc {
                    start: [0.0; 2],
                    corner: [0.0; 2],
                    alpha: 1.0
                };
                corners.len()
            ];
            arcs_of_tangential_polygon([0.0, 0.0], corners, &mut arcs).unwrap();
            for level in 0..=6 {
                let mut out = vec![[0.0; 2]; closed_len(arcs.len(), level)];
                refine_closed(&arcs, level, &mut out).unwrap();
                for p in out.iter().step_by(2) {
                    assert!(
                        (p[0].hypot(p[1]) - 1.0).abs() < 1e-14,
                        "level {level}: {p:?}"
                    );
                }
                for p in out.iter().skip(1).step_by(2) {
                    assert!(p[0].hypot(p[1]) > 1.0);
                }
            }
        }
    }

    #[test]
    fn impossible_requests_are_typed_errors() {
        let mut out = vec![[0.0_f64; 2]; 8];
        assert_eq!(
            circle([0.0, 0.0], 1.0, 1, &mut out),
            Err(TessellateError::BufferTooSmall {
                buffer: "point",
                needed: 16,
                got: 8
            })
        );
        assert!(matches!(
            circle([0.0, 0.0], 1.0, MAX_LEVEL + 1, &mut out),
            Err(TessellateError::LevelTooDeep { .. })
        ));
        assert_eq!(
            circle([0.0, 0.0], f64::NAN, 0, &mut out),
            Err(TessellateError::InvalidShape)
        );
        assert_eq!(
            refine_closed::<f64>(&[], 0, &mut out),
            Err(TessellateError::InvalidControlPolygon)
        );
        let arc = Arc {
            start: [1.0, 0.0],
            corner: [1.0, 1.0],
            alpha: core::f64::consts::PI,
        };
        assert_eq!(
            refine_closed(&[arc], 0, &mut out),
            Err(TessellateError::InvalidControlPolygon)
        );
        assert_eq!(square_len(MAX_LEVEL + 1), usize::MAX);
    }

    /// Each bad number alone is refused: the center's either coordinate not finite, a singular map (determinant
    /// exactly 0 with no zero entry), a map with an infinite or NaN entry, a semi-axis 0, negative or infinite, a
    /// NaN shear; and a tangential polygon with a straight corner (collinear neighbours, α = π) or a folded one
    /// (α = 0). The same calls with good numbers succeed.
    #[test]
    fn each_non_finite_or_degenerate_input_alone_is_refused() {
        let mut out = vec![[0.0_f64; 2]; 64];
        let shape = Err(TessellateError::InvalidShape);
        let (nan, inf) = (f64::NAN, f64::INFINITY);
        let identity = [[1.0, 0.0], [0.0, 1.0]];
        assert!(affine_circle([0.0, 0.0], identity, 2, &mut out).is_ok());
        for center in [[nan, 0.0], [0.0, nan], [inf, 0.0], [0.0, -inf]] {
            assert_eq!(
                affine_circle(center, identity, 2, &mut out),
                shape,
                "{center:?}"
            );
        }
        for m in [
            [[1.0, 2.0], [2.0, 4.0]],
            [[inf, 0.0], [0.0, 1.0]],
            [[1.0, nan], [0.0, 1.0]],
        ] {
            assert_eq!(affine_circle([0.0, 0.0], m, 2, &mut out), shape, "{m:?}");
        }
        assert!(sheared_ellipse([0.0, 0.0], 2.0, 1.0, 0.5, 2, &mut out).is_ok());
        for (a, b, s) in [
            (0.0, 1.0, 0.5),
            (2.0, 0.0, 0.5),
            (-2.0, 1.0, 0.5),
            (2.0, -1.0, 0.5),
            (inf, 1.0, 0.5),
            (2.0, inf, 0.5),
            (2.0, 1.0, nan),
            (2.0, 1.0, inf),
        ] {
            assert_eq!(
                sheared_ellipse([0.0, 0.0], a, b, s, 2, &mut out),
                shape,
                "{a} {b} {s}"
            );
        }
        let mut arcs = [Arc {
            start: [0.0; 2],
            corner: [0.0; 2],
            alpha: 0.0,
        }; 4];
        let square = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        assert_eq!(
            arcs_of_tangential_polygon([0.0, 0.0], &square, &mut arcs),
            Ok(4)
        );
        let bad = Err(TessellateError::InvalidControlPolygon);
        // a straight corner: (1, 0) between (1, −1) and (1, 1)
        let straight = [[-1.0, -1.0], [1.0, -1.0], [1.0, 0.0], [1.0, 1.0]];
        assert_eq!(
            arcs_of_tangential_polygon([0.0, 0.0], &straight, &mut arcs),
            bad
        );
        // a folded corner: (1, −1) between (−1, −1) and (0, −1), going back along the same line
        let folded = [[-1.0, -1.0], [1.0, -1.0], [0.0, -1.0]];
        assert_eq!(
            arcs_of_tangential_polygon([0.0, 0.0], &folded, &mut arcs),
            bad
        );
        // One folded corner alone: (2, 0) has both neighbours to its west (every other corner is proper).
        let one_fold = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        assert_eq!(
            arcs_of_tangential_polygon([0.5, 0.25], &one_fold, &mut arcs),
            bad
        );
        // A side whose squared length overflows (corners 1e200 apart).
        let huge = [
            [-1e200, -1e200],
            [1e200, -1e200],
            [1e200, 1e200],
            [-1e200, 1e200],
        ];
        assert_eq!(
            arcs_of_tangential_polygon([0.0, 0.0], &huge, &mut arcs),
            bad
        );
        assert_eq!(
            arcs_of_tangential_polygon(
                [0.0, 0.0],
                &huge.map(|[x, y]| [x * 1e-100, y * 1e-100]),
                &mut arcs
            ),
            Ok(4)
        );
        // An arc with one bad number alone: its start or corner not finite, its α not in (0, π).
        let good = Arc {
            start: [1.0, 0.0],
            corner: [1.0, 1.0],
            alpha: core::f64::consts::FRAC_PI_2,
        };
        assert!(refine_closed(&[good; 4], 1, &mut out).is_ok());
        let pi = core::f64::consts::PI;
        for arc in [
            Arc {
                start: [nan, 0.0],
                ..good
            },
            Arc {
                start: [1.0, inf],
                ..good
            },
            Arc {
                corner: [-inf, 1.0],
                ..good
            },
            Arc {
                corner: [1.0, nan],
                ..good
            },
            Arc { alpha: 0.0, ..good },
            Arc { alpha: pi, ..good },
            Arc { alpha: nan, ..good },
        ] {
            assert_eq!(
                refine_closed(&[good, arc, good], 1, &mut out),
                bad,
                "{arc:?}"
            );
        }
        // MAX_LEVEL itself is accepted (2^21 points an arc): only the buffer is too short for it.
        assert_eq!(points_per_arc(MAX_LEVEL), 1 << (MAX_LEVEL + 1));
        assert!(matches!(
            refine_closed(&[good; 4], MAX_LEVEL, &mut out),
            Err(TessellateError::BufferTooSmall {
                buffer: "point",
                ..
            })
        ));
    }
}
