//! Edge-beveling a cube into its inscribed sphere, and a box into its inscribed ellipsoid (the edge-beveling thesis §4.3–4.4).
//!
//! # The construction (§4.3.4)
//!
//! Level 0 is the cube `(±1, ±1, ±1)`; each face is tangent to the unit sphere at its *center point* (its
//! centroid). One refinement cuts every edge off with a plane parallel to the edge and tangent to the sphere at
//! the midpoint of the geodesic between the center points of the two faces adjacent to the edge; that new center
//! is the new Type **E** face's center point, and the Type **F** faces keep theirs. Every vertex of level `k`
//! (valence three, §4.3.3) is replaced by a **Y**-point (the intersection of the three new Type **E** planes) and
//! three face points (the intersection of one old plane with two new planes).
//!
//! The dual view of §4.3.2–4.3.3 makes this a fixed-memory algorithm: the center points of level `k` are the
//! vertices of the octahedral triangulation of the sphere after `k` triangle subdivisions by geodesic midpoints,
//! and each vertex of the polyhedron is the intersection of the three tangent planes at the corners of one
//! triangle. In a subdivided triangle the central child gives the **Y**-point and the three corner children give
//! the face points. So this module computes the center points level by level (each new one is the normalized sum
//! of its two parents: the geodesic midpoint), then intersects planes once per triangle of the finest level.
//! The center points live on the integer lattice `|i| + |j| + |l| = 2^k` of the octahedron, which indexes the
//! faces without any map or allocation.
//!
//! A note on §4.3.4's formula for the new center: it writes `t_k = 1 / (1 + cos θ_k)` with
//! `θ_k = (π − arccos(n₀·n₁)) / 2`. Putting the new center on the segment from the edge point `P_p` to the chord
//! midpoint `(C₀ + C₁)/2` and on the sphere gives `t_k = 1 / (1 + cos(ψ/2))` with `ψ = arccos(n₀·n₁)`; the two agree
//! only at `ψ = π/2` (the cube). The test `center_point_formula_derived_again` checks the corrected form against
//! the geodesic midpoint used here.
//!
//! # Counts
//!
//! Level `k` has [`face_count`]`(k) = 4·4^k + 2` faces (6 quadrilaterals — the cube's Type **F** faces — and
//! hexagons), [`vertex_count`]`(k) = 8·4^k` vertices, all of valence three, and [`edge_count`]`(k) = 12·4^k`
//! edges; `V − E + F = 2`. (§4.3.3 says the first refinement has twenty-four vertices; it has thirty-two: each of
//! the cube's eight vertices becomes a **Y**-point and three face points.)
//!
//! # Ellipsoids (§4.4)
//!
//! The polyhedron for the ellipsoid `x²/A² + y²/B² + z²/C² = 1` is the sphere's scaled by `(A, B, C)`: a face with
//! sphere center point `c` has center point `(A c_x, B c_y, C c_z)` on the ellipsoid, and its plane is the
//! ellipsoid's tangent plane there (normal `∝ (c_x/A, c_y/B, c_z/C)`).
//!
//! ```
//! use curvicast::tessellate::bevel::{self, Face};
//! use curvicast::V3;
//! let mut v = [V3::ZERO; bevel::vertex_count(1)];
//! let mut f = [Face::EMPTY; bevel::face_count(1)];
//! let counts = bevel::bevel_ellipsoid(1, [3.0_f64, 2.0, 1.0], &mut v, &mut f)?;
//! assert_eq!((counts.vertices, counts.edges, counts.faces), (32, 48, 18));
//! // Every vertex of every face lies in the face's plane, which touches the ellipsoid at the face's center.
//! for face in &f {
//!     for &i in face.vertex_indices() {
//!         let d = v[i as usize].minus(face.center).dot(face.normal);
//!         assert!(d.abs() < 1e-14);
//!     }
//! }
//! # Ok::<(), curvicast::tessellate::TessellateError>(())
//! ```

use super::error::{TessellateError, need};
use crate::real::Real;
use crate::vec3::V3;

/// The deepest level the builders accept: `8·4^12` (about 134 million) vertices, so that vertex indices fit a `u32`
/// and every count fits a 32-bit `usize`.
pub const MAX_LEVEL: u32 = 12;

/// Largest number of vertices of one face (hexagons; the cube's six faces stay quadrilaterals).
pub const MAX_FACE_VERTICES: usize = 6;

/// `4^level`, or `None` above [`MAX_LEVEL`].
const fn pow4(level: u32) -> Option<usize> {
    if level > MAX_LEVEL {
        return None;
    }
    4usize.checked_pow(level)
}

/// Number of faces at `level`: `4·4^level + 2`. Saturates at `usize::MAX` above [`MAX_LEVEL`] (which the builders
/// reject).
pub const fn face_count(level: u32) -> usize {
    match pow4(level) {
        Some(p) => match p.checked_mul(4) {
            Some(q) => match q.checked_add(2) {
                Some(r) => r,
                None => usize::MAX,
            },
            None => usize::MAX,
        },
        None => usize::MAX,
    }
}

/// Number of vertices at `level`: `8·4^level`, all of valence three. Saturates like [`face_count`].
pub const fn vertex_count(level: u32) -> usize {
    match pow4(level) {
        Some(p) => match p.checked_mul(8) {
            Some(q) => q,
            None => usize::MAX,
        },
        None => usize::MAX,
    }
}

/// Number of edges at `level`: `12·4^level`. Saturates like [`face_count`].
pub const fn edge_count(level: u32) -> usize {
    match pow4(level) {
        Some(p) => match p.checked_mul(12) {
            Some(q) => q,
            None => usize::MAX,
        },
        None => usize::MAX,
    }
}

/// One face of a beveled polyhedron: a planar convex polygon tangent to the surface at `center` (`repr(C)`: the
/// C interface writes arrays of them).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct Face<T> {
    /// The center point (§4.3.4): where the face's plane touches the sphere or ellipsoid.
    pub center: V3<T>,
    /// The unit outward normal of the face's plane (the surface normal at `center`).
    pub normal: V3<T>,
    /// Indices into the vertex buffer, counter-clockwise seen from outside; only the first `len` are used.
    pub vertices: [u32; MAX_FACE_VERTICES],
    /// Number of vertices: 4 (the cube's faces) or 6.
    pub len: u8,
}

impl<T: Real> Face<T> {
    /// A face with no vertices, to fill buffers with.
    pub const EMPTY: Self = Face {
        center: V3::ZERO,
        normal: V3::ZERO,
        vertices: [0; MAX_FACE_VERTICES],
        len: 0,
    };

    /// The vertex indices of the face, counter-clockwise seen from outside.
    pub fn vertex_indices(&self) -> &[u32] {
        self.vertices.get(..usize::from(self.len)).unwrap_or(&[])
    }
}

/// The numbers of elements written by [`bevel_sphere`] / [`bevel_ellipsoid`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts {
    /// Vertices written (`vertex_count(level)`).
    pub vertices: usize,
    /// Edges of the polyhedron (`edge_count(level)`); edges are implicit in the faces.
    pub edges: usize,
    /// Faces written (`face_count(level)`).
    pub faces: usize,
}

/// Builds the level-`level` edge-beveled polyhedron of the sphere of radius `radius` centered at the origin (§4.3).
///
/// Writes `vertex_count(level)` vertices and `face_count(level)` faces into the front of the buffers; every
/// face's plane is tangent to the sphere at the face's center point, and every vertex lies outside the sphere.
///
/// # Errors
/// [`TessellateError::LevelTooDeep`] above [`MAX_LEVEL`], [`TessellateError::BufferTooSmall`] for short buffers,
/// [`TessellateError::InvalidShape`] unless `radius` is positive and finite.
pub fn bevel_sphere<T: Real>(
    level: u32,
    radius: T,
    vertices: &mut [V3<T>],
    faces: &mut [Face<T>],
) -> Result<Counts, TessellateError> {
    bevel_ellipsoid(level, [radius, radius, radius], vertices, faces)
}

/// Builds the level-`level` edge-beveled polyhedron of the ellipsoid `x²/A² + y²/B² + z²/C² = 1` with
/// `axes = [A, B, C]` (§4.4): the sphere's polyhedron scaled by `(A, B, C)`.
///
/// # Errors
/// As [`bevel_sphere`]; [`TessellateError::InvalidShape`] unless every semi-axis is positive and finite and the
/// results stay finite.
pub fn bevel_ellipsoid<T: Real>(
    level: u32,
    axes: [T; 3],
    vertices: &mut [V3<T>],
    faces: &mut [Face<T>],
) -> Result<Counts, TessellateError> {
    if level > MAX_LEVEL {
        return Err(TessellateError::LevelTooDeep {
            level,
            max: MAX_LEVEL,
        });
    }
    for a in axes {
        if !(a > T::ZERO) || !a.is_finite() {
            return Err(TessellateError::InvalidShape);
        }
    }
    let counts = Counts {
        vertices: vertex_count(level),
        edges: edge_count(level),
        faces: face_count(level),
    };
    need("vertex", counts.vertices, vertices.len())?;
    need("face", counts.faces, faces.len())?;
    let faces = faces
        .get_mut(..counts.faces)
        .ok_or(TessellateError::Internal)?;
    let vertices = vertices
        .get_mut(..counts.vertices)
        .ok_or(TessellateError::Internal)?;
    for f in faces.iter_mut() {
        *f = Face::EMPTY;
    }
    let n: i64 = 1i64.checked_shl(level).ok_or(TessellateError::Internal)?; // level <= 12
    center_points(level, n, faces)?;
    unit_vertices(n, vertices, faces)?;
    for f in faces.iter_mut() {
        order_ring(f, vertices)?;
    }
    // §4.4: scale the unit sphere's polyhedron into the ellipsoid's.
    let [a, b, c] = axes;
    let scale = V3::new(a, b, c);
    for v in vertices.iter_mut() {
        *v = mul(*v, scale);
        if !v.is_finite() {
            return Err(TessellateError::InvalidShape);
        }
    }
    for f in faces.iter_mut() {
        let cs = f.center;
        f.center = mul(cs, scale);
        f.normal = normalized(V3::new(cs.x / a, cs.y / b, cs.z / c))
            .ok_or(TessellateError::InvalidShape)?;
        if !f.center.is_finite() {
            return Err(TessellateError::InvalidShape);
        }
    }
    Ok(counts)
}

fn mul<T: Real>(v: V3<T>, s: V3<T>) -> V3<T> {
    V3::new(v.x * s.x, v.y * s.y, v.z * s.z)
}

/// `v / |v|`, scaled first so that neither huge nor tiny components overflow; `None` for zero or non-finite `v`.
pub(crate) fn normalized<T: Real>(v: V3<T>) -> Option<V3<T>> {
    let m = v.max_abs();
    if !(m > T::ZERO) || !m.is_finite() {
        return None;
    }
    let w = v.scaled(T::ONE / m);
    let l = w.length();
    let r = w.scaled(T::ONE / l);
    if r.is_finite() { Some(r) } else { None }
}

/// Index of the lattice point `(i, j, l)`, `|i| + |j| + |l| = n`, among the `4n² + 2` points of the octahedron:
/// the upper half (`l ≥ 0`) is the diamond `|i| + |j| ≤ n` row by row, the lower half the diamond `|i| + |j| ≤ n − 1`.
fn lattice_index(n: i64, i: i64, j: i64, l: i64) -> Option<usize> {
    let idx = if l >= 0 {
        diamond_index(n, i, j)?
    } else {
        let upper = n
            .checked_mul(n)?
            .checked_mul(2)?
            .checked_add(n.checked_mul(2)?)?
            .checked_add(1)?;
        upper.checked_add(diamond_index(n.checked_sub(1)?, i, j)?)?
    };
    usize::try_from(idx).ok()
}

/// Index of `(i, j)` in the diamond `|i| + |j| ≤ r`, rows `j = −r..=r`, each row from its smallest `i`.
fn diamond_index(r: i64, i: i64, j: i64) -> Option<i64> {
    let aj = j.checked_abs()?;
    let half_width = r.checked_sub(aj)?;
    let ai = i.checked_abs()?;
    if half_width < 0 || ai > half_width {
        return None;
    }
    let before = if j <= 0 {
        let m = j.checked_add(r)?;
        m.checked_mul(m)?
    } else {
        let r1 = r.checked_add(1)?;
        let m = r.checked_sub(j)?.checked_add(1)?;
        r1.checked_mul(r1)?
            .checked_add(r.checked_mul(r)?)?
            .checked_sub(m.checked_mul(m)?)?
    };
    before.checked_add(i.checked_add(half_width)?)
}

/// Writes the center points (unit vectors) of level `level` into `faces[..].center`, level by level: the six
/// cube centers, then each new center as the geodesic midpoint of the two centers it lies between.
fn center_points<T: Real>(
    level: u32,
    n: i64,
    faces: &mut [Face<T>],
) -> Result<(), TessellateError> {
    let err = TessellateError::Internal;
    let neg = |x: i64| x.checked_neg().ok_or(err);
    let mn = neg(n)?;
    for (i, j, l) in [
        (n, 0, 0),
        (mn, 0, 0),
        (0, n, 0),
        (0, mn, 0),
        (0, 0, n),
        (0, 0, mn),
    ] {
        let k = lattice_index(n, i, j, l).ok_or(err)?;
        let f = faces.get_mut(k).ok_or(err)?;
        f.center = V3::new(
            T::from_i32(sign(i)),
            T::from_i32(sign(j)),
            T::from_i32(sign(l)),
        );
    }
    for m in 1..=level {
        let h = n.checked_shr(m).ok_or(err)?;
        let h2 = h.checked_mul(2).ok_or(err)?;
        // Upper half including the equator, then the lower half: every lattice point with step h.
        let mut j = mn;
        while j <= n {
            let w = n.checked_sub(j.checked_abs().ok_or(err)?).ok_or(err)?;
            let mut i = neg(w)?;
            while i <= w {
                let rest = w.checked_sub(i.checked_abs().ok_or(err)?).ok_or(err)?;
                new_center(n, h, h2, i, j, rest, faces)?;
                if rest > 0 {
                    new_center(n, h, h2, i, j, neg(rest)?, faces)?;
                }
                i = i.checked_add(h).ok_or(err)?;
            }
            j = j.checked_add(h).ok_or(err)?;
        }
    }
    Ok(())
}

fn sign(x: i64) -> i32 {
    match x.cmp(&0) {
        core::cmp::Ordering::Less => -1,
        core::cmp::Ordering::Equal => 0,
        core::cmp::Ordering::Greater => 1,
    }
}

/// If `(i, j, l)` (coordinates multiples of `h`) first appears at this level, computes its center from its two
/// parents (the ends of the coarser edge it bisects: ±h along the two coordinates that are odd multiples of h).
fn new_center<T: Real>(
    n: i64,
    h: i64,
    h2: i64,
    i: i64,
    j: i64,
    l: i64,
    faces: &mut [Face<T>],
) -> Result<(), TessellateError> {
    let err = TessellateError::Internal;
    let c = [i, j, l];
    let odd = |x: i64| x.checked_rem(h2).is_some_and(|r| r != 0);
    let mut which = [0usize; 2];
    let mut count = 0usize;
    for (axis, &x) in c.iter().enumerate() {
        if odd(x) {
            if let Some(slot) = which.get_mut(count) {
                *slot = axis;
            }
            count = count.checked_add(1).ok_or(err)?;
        }
    }
    if count == 0 {
        return Ok(()); // on the coarser lattice: already computed
    }
    if count != 2 {
        return Err(err);
    }
    // Move h of |coordinate| from one odd coordinate to the other, keeping signs (both are nonzero).
    let shift = |p: [i64; 3], from: usize, to: usize| -> Option<[i64; 3]> {
        let mut q = p;
        let f = q.get_mut(from)?;
        *f = f.checked_sub(h.checked_mul(i64::from(sign(*f)))?)?;
        let t = q.get_mut(to)?;
        *t = t.checked_add(h.checked_mul(i64::from(sign(*t)))?)?;
        Some(q)
    };
    let [a0, a1] = which;
    let p = shift(c, a0, a1).ok_or(err)?;
    let q = shift(c, a1, a0).ok_or(err)?;
    let cp = faces
        .get(lattice_index(n, p[0], p[1], p[2]).ok_or(err)?)
        .ok_or(err)?
        .center;
    let cq = faces
        .get(lattice_index(n, q[0], q[1], q[2]).ok_or(err)?)
        .ok_or(err)?
        .center;
    let mid = normalized(cp.plus(cq)).ok_or(err)?;
    let k = lattice_index(n, i, j, l).ok_or(err)?;
    faces.get_mut(k).ok_or(err)?.center = mid;
    Ok(())
}

/// The point where the planes tangent to the unit sphere at the (unit) points `n0, n1, n2` meet (§4.1.1, "The
/// Intersection of Three Planes"), solved for `q = P − n0` so that nothing cancels when the normals are nearly
/// parallel: `n0·q = 1 − |n0|²`, `(n_i − n0)·q = (1 − n_i·n0) − (1 − |n0|²)`, with `1 − a·b` taken as
/// `|a − b|²/2 + (1 − |a|²)/2 + (1 − |b|²)/2`.
pub(crate) fn tangent_planes_meet<T: Real>(n0: V3<T>, n1: V3<T>, n2: V3<T>) -> Option<V3<T>> {
    let d1 = n1.minus(n0);
    let d2 = n2.minus(n0);
    let defect = |v: V3<T>| (T::ONE - v.dot(v)) * T::HALF;
    let r0 = defect(n0) * T::TWO;
    let b1 = d1.dot(d1) * T::HALF + defect(n1) + defect(n0) - r0;
    let b2 = d2.dot(d2) * T::HALF + defect(n2) + defect(n0) - r0;
    let x12 = d1.cross(d2);
    let det = n0.dot(x12);
    if !(det.abs() > T::ZERO) || !det.is_finite() {
        return None;
    }
    let q = x12
        .scaled(r0)
        .add_scaled(b1, d2.cross(n0))
        .add_scaled(b2, n0.cross(d1))
        .scaled(T::ONE / det);
    let p = n0.plus(q);
    if p.is_finite() { Some(p) } else { None }
}

/// Computes every vertex of the unit-sphere polyhedron (one per triangle of the subdivided octahedron) and adds
/// its index to the rings of the three faces that meet there.
fn unit_vertices<T: Real>(
    n: i64,
    vertices: &mut [V3<T>],
    faces: &mut [Face<T>],
) -> Result<(), TessellateError> {
    let err = TessellateError::Internal;
    let mut next: u32 = 0;
    for octant in 0u8..8 {
        let sx: i64 = if octant & 1 == 0 { 1 } else { -1 };
        let sy: i64 = if octant & 2 == 0 { 1 } else { -1 };
        let sz: i64 = if octant & 4 == 0 { 1 } else { -1 };
        let idx = |a: i64, b: i64| -> Option<usize> {
            let c = n.checked_sub(a)?.checked_sub(b)?;
            lattice_index(
                n,
                sx.checked_mul(a)?,
                sy.checked_mul(b)?,
                sz.checked_mul(c)?,
            )
        };
        for b in 0..n {
            let mut a = 0i64;
            while a.checked_add(b).ok_or(err)? < n {
                let a1 = a.checked_add(1).ok_or(err)?;
                let b1 = b.checked_add(1).ok_or(err)?;
                let up = [
                    idx(a, b).ok_or(err)?,
                    idx(a1, b).ok_or(err)?,
                    idx(a, b1).ok_or(err)?,
                ];
                add_vertex(up, &mut next, vertices, faces)?;
                if a1.checked_add(b).ok_or(err)? < n {
                    let down = [
                        idx(a1, b).ok_or(err)?,
                        idx(a1, b1).ok_or(err)?,
                        idx(a, b1).ok_or(err)?,
                    ];
                    add_vertex(down, &mut next, vertices, faces)?;
                }
                a = a1;
            }
        }
    }
    if usize::try_from(next).ok() != Some(vertices.len()) {
        return Err(err);
    }
    Ok(())
}

fn add_vertex<T: Real>(
    corners: [usize; 3],
    next: &mut u32,
    vertices: &mut [V3<T>],
    faces: &mut [Face<T>],
) -> Result<(), TessellateError> {
    let err = TessellateError::Internal;
    let [f0, f1, f2] = corners;
    let c = |k: usize| faces.get(k).map(|f| f.center).ok_or(err);
    let p = tangent_planes_meet(c(f0)?, c(f1)?, c(f2)?).ok_or(err)?;
    let vi = *next;
    *vertices
        .get_mut(usize::try_from(vi).map_err(|_| err)?)
        .ok_or(err)? = p;
    for k in corners {
        let f = faces.get_mut(k).ok_or(err)?;
        let slot = f.vertices.get_mut(usize::from(f.len)).ok_or(err)?;
        *slot = vi;
        f.len = f.len.checked_add(1).ok_or(err)?;
    }
    *next = vi.checked_add(1).ok_or(err)?;
    Ok(())
}

/// Sorts a face's vertices counter-clockwise around its (unit-sphere) center seen from outside, and sets its
/// normal; a face of the regular lattice has 4 (cube corners of the octahedron) or 6 vertices.
fn order_ring<T: Real>(f: &mut Face<T>, vertices: &[V3<T>]) -> Result<(), TessellateError> {
    let err = TessellateError::Internal;
    if f.len != 4 && f.len != 6 {
        return Err(err);
    }
    let nrm = f.center;
    // A tangent basis (u, w) with u × w = nrm.
    let (ax, ay, az) = (nrm.x.abs(), nrm.y.abs(), nrm.z.abs());
    let e = if ax <= ay && ax <= az {
        V3::new(T::ONE, T::ZERO, T::ZERO)
    } else if ay <= az {
        V3::new(T::ZERO, T::ONE, T::ZERO)
    } else {
        V3::new(T::ZERO, T::ZERO, T::ONE)
    };
    let u = normalized(nrm.cross(e)).ok_or(err)?;
    let w = nrm.cross(u);
    let mut keyed = [(T::ZERO, 0u32); MAX_FACE_VERTICES];
    let len = usize::from(f.len);
    for (slot, &vi) in keyed.iter_mut().zip(f.vertices.iter()).take(len) {
        let v = vertices
            .get(usize::try_from(vi).map_err(|_| err)?)
            .ok_or(err)?
            .minus(nrm);
        *slot = (v.dot(w).atan2(v.dot(u)), vi);
    }
    let ring = keyed.get_mut(..len).ok_or(err)?;
    // Insertion sort of at most six angles.
    for s in 1..ring.len() {
        let mut t = s;
        while t > 0 {
            let prev = t.checked_sub(1).ok_or(err)?;
            let (a, b) = (ring.get(prev).ok_or(err)?.0, ring.get(t).ok_or(err)?.0);
            if a > b {
                ring.swap(prev, t);
                t = prev;
            } else {
                break;
            }
        }
    }
    for (dst, src) in f.vertices.iter_mut().zip(ring.iter()) {
        *dst = src.1;
    }
    f.normal = nrm;
    Ok(())
}

#[cfg(test)]
mod tests;
