//! The level of detail of an ellipsoid (the edge-beveling thesis §4.4, chapter 5): its exact worst case at a level, the
//! cheap witnesses and guarantees that decide most levels, and the exhaustive octant walk for the rest (the
//! steps of the [`super`] module docs).

use super::sphere::worst_case;
use crate::real::Real;
use crate::tessellate::bevel::{MAX_LEVEL, normalized, tangent_planes_meet};
use crate::tessellate::error::{MAX_AXIS_RATIO, TessellateError};
use crate::vec3::V3;

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
/// (the `lod` module docs, step 3, without pruning): `(4^(level+1) − 1) / 3` triangles, each with one
/// closest-point solve and three normal angles; fixed memory.
///
/// # Errors
/// [`TessellateError::LevelTooDeep`] above [`MAX_LEVEL`], [`TessellateError::InvalidShape`] and
/// [`TessellateError::AxisRatioTooLarge`] as for [`min_level`](crate::tessellate::lod::min_level).
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

/// The ellipsoid scaled so that its largest semi-axis is 1 (`a`), with `a²` and `1/a` per axis.
#[derive(Debug, Clone, Copy)]
pub(super) struct Ell<T> {
    a: [T; 3],
    w: [T; 3],
    inv: [T; 3],
    /// Largest over smallest semi-axis (`1 / min a`).
    pub(super) ratio: T,
    /// The smallest radius of curvature, `(min a)²`: by Blaschke's rolling theorem a ball of this radius touching
    /// the ellipsoid from inside at any point lies inside it.
    roll: T,
}

impl<T: Real> Ell<T> {
    /// Validates the semi-axes and normalizes them; returns the ellipsoid and the largest semi-axis.
    pub(super) fn new(axes: [T; 3]) -> Result<(Self, T), TessellateError> {
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
    pub(super) fn vertex_meets(&self, p: V3<T>, limit: T) -> bool {
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
    pub(super) fn distance(&self, p: V3<T>) -> T {
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
pub(super) enum EllTest<T> {
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
pub(super) fn leaf_at<T: Real>(
    level: u32,
    target: [i64; 3],
) -> Result<[V3<T>; 3], TessellateError> {
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
pub(super) fn witness_targets(level: u32) -> Result<([[i64; 3]; 13], usize), TessellateError> {
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
/// level fails), `Some(true)` if the axis-ratio guarantee of the `lod` module docs shows that it meets it, `None` when
/// neither decides.
pub(super) fn decide_cheaply<T: Real>(
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
/// that the bounds of the `lod` module docs clear, and stopping at the first violation.
pub(super) fn decide_by_walk<T: Real>(
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
pub(super) fn ellipsoid_meets<T: Real>(
    e: &Ell<T>,
    level: u32,
    test: EllTest<T>,
) -> Result<bool, TessellateError> {
    match decide_cheaply(e, level, test)? {
        Some(v) => Ok(v),
        None => decide_by_walk(e, level, test),
    }
}
