//! Watertight ray–triangle intersection (Woop, Benthin, Wald, *Watertight Ray/Triangle Intersection*, JCGT 2013),
//! derived again here.
//!
//! The ray is made the +z axis of a sheared frame: with `k_z` the axis of the largest `|d|` component (and
//! `k_x, k_y` the next two, swapped when `d[k_z] < 0` to keep the frame right-handed), the shear `S = (d_x/d_z,
//! d_y/d_z, 1/d_z)` maps `d` to `(0, 0, 1)`. In that frame the ray pierces the triangle iff the origin lies inside
//! its 2-D projection, which is decided by the three edge functions `U, V, W` (twice the signed areas of the
//! sub-triangles). Each edge function depends only on the two vertices of its edge and on the ray, computed with
//! the same operations in the same order whichever triangle the edge belongs to, so two triangles that share an
//! edge see the same value with opposite orientation: a ray can never slip between them (no crack), and a ray
//! through a shared vertex or edge hits at least one of them. When an edge function is exactly 0, it is
//! recomputed exactly (for `f32` scalars: each product as an exact pair, the difference in pair arithmetic,
//! [`crate::dd`]; no `f64`, which a single-precision FPU lacks) so that its sign is decided reliably. Both orientations of the
//! triangle are hit (no back-face culling): a ray from below the terrain hits it from underneath.
//!
//! The hit distance is `t = (U z_A + V z_B + W z_C) / (U + V + W)` with `z` the sheared heights, the barycentric
//! coordinates are `(U, V, W) / det`.
//!
//! # Edges on the border of the surface
//!
//! Watertightness covers an edge that two triangles share. An edge that only one triangle has (on the DEM's outer
//! edge, or next to a nodata vertex) has no neighbour to catch a ray that the vertices' rounding puts on the wrong
//! side of it: the scalar vertices are a few ulps of their coordinates off the contract's exact ones, so a ray
//! through the exact vertex `V(0, j)` of a DEM's first row may pass just outside the scalar triangles on either
//! side, and a ray just outside the exact edge may pass just inside them. So wherever an edge function is within
//! what the rounding of the vertices and of the sheared coordinates can explain, `64 ε m (|Δx| + |Δy|)` (`m` is
//! `‖origin‖∞` plus the largest `‖v − origin‖∞` of the three vertices, `Δ` the edge in the sheared frame),
//! [`WatertightRay::intersect_with_border`] asks the caller about that edge ([`Edge`]): a shared edge keeps the
//! scalar decision (its neighbour answers), and for an edge on the border the caller decides the side exactly,
//! from the exact vertices ([`exact_edge_sides`]: the sign of `d · ((v_a − o) × (v_b − o))` in pair arithmetic,
//! a tie counting as on the edge, since triangles are closed). The band only chooses where to ask; it never
//! decides a hit.

use crate::dd::{Dd, two_prod};
use crate::real::Real;
use crate::vec3::V3;

#[inline]
fn comp<T: Copy>(v: V3<T>, k: usize) -> T {
    match k {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

/// An edge of a triangle that a ray passes within rounding of (module docs, "Edges on the border of the surface").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Edge {
    /// Another triangle shares the edge: the scalar decision stands (watertightness gives the ray to one of the
    /// two).
    Shared,
    /// On the border of the surface, and the exact ray passes through the closed triangle at this edge.
    Inside,
    /// On the border of the surface, and the exact ray passes outside this edge.
    Outside,
}

impl Edge {
    /// An edge that is on the border of the surface or not (`border`), with the exact side of the ray where known
    /// (`inside`, from [`exact_edge_sides`]; without it the scalar decision stands).
    pub fn of(border: bool, inside: Option<bool>) -> Self {
        match (border, inside) {
            (true, Some(true)) => Edge::Inside,
            (true, Some(false)) => Edge::Outside,
            _ => Edge::Shared,
        }
    }
}

/// The precomputed shear of a ray (per ray, reused for every triangle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WatertightRay<T> {
    origin: V3<T>,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: T,
    sy: T,
    sz: T,
}

impl<T: Real> WatertightRay<T> {
    /// The shear of the ray `origin + t dir`; `None` for a zero or non-finite direction.
    pub fn new(origin: V3<T>, dir: V3<T>) -> Option<Self> {
        let (ax, ay, az) = (dir.x.abs(), dir.y.abs(), dir.z.abs());
        let kz: usize = if ax >= ay && ax >= az {
            0
        } else if ay >= az {
            1
        } else {
            2
        };
        let mut kx: usize = if kz == 2 { 0 } else { kz.saturating_add(1) };
        let mut ky: usize = if kx == 2 { 0 } else { kx.saturating_add(1) };
        let dz = comp(dir, kz);
        if !(dz.abs() > T::ZERO) || !dir.is_finite() {
            return None;
        }
        if dz < T::ZERO {
            core::mem::swap(&mut kx, &mut ky);
        }
        Some(WatertightRay {
            origin,
            kx,
            ky,
            kz,
            sx: comp(dir, kx) / dz,
            sy: comp(dir, ky) / dz,
            sz: T::ONE / dz,
        })
    }

    /// The intersection of the ray with triangle `(v0, v1, v2)` for `t_lo ≤ t ≤ t_hi`: `(t, [b0, b1, b2])`.
    #[inline]
    pub fn intersect(
        &self,
        v0: V3<T>,
        v1: V3<T>,
        v2: V3<T>,
        t_lo: T,
        t_hi: T,
    ) -> Option<(T, [T; 3])> {
        self.intersect_with_border(v0, v1, v2, t_lo, t_hi, |_| [Edge::Shared; 3])
    }

    /// [`WatertightRay::intersect`], with the edges on the border of the surface decided exactly (module docs,
    /// "Edges on the border of the surface"). `edges(near)` is asked only when the ray passes within rounding
    /// of an edge (`near`, for the edges `v1–v2`, `v2–v0`, `v0–v1`), and says what each of those edges is.
    #[inline]
    pub fn intersect_with_border(
        &self,
        v0: V3<T>,
        v1: V3<T>,
        v2: V3<T>,
        t_lo: T,
        t_hi: T,
        edges: impl FnOnce([bool; 3]) -> [Edge; 3],
    ) -> Option<(T, [T; 3])> {
        let a = v0.minus(self.origin);
        let b = v1.minus(self.origin);
        let c = v2.minus(self.origin);
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let (sx, sy) = (self.sx, self.sy);
        let ax = comp(a, kx) - sx * comp(a, kz);
        let ay = comp(a, ky) - sy * comp(a, kz);
        let bx = comp(b, kx) - sx * comp(b, kz);
        let by = comp(b, ky) - sy * comp(b, kz);
        let cx = comp(c, kx) - sx * comp(c, kz);
        let cy = comp(c, ky) - sy * comp(c, kz);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if (u == T::ZERO || v == T::ZERO || w == T::ZERO) && T::MANTISSA_DIGITS < 53 {
            // Each product exactly as a pair (Dekker), the difference in pair arithmetic (relative error
            // ≤ 3ε², so the sign is exact and 0 only for an exact 0), without leaving the scalar.
            let det2 = |p: T, q: T, r: T, s: T| two_prod(p, q).minus(two_prod(r, s)).value();
            u = det2(cx, by, cy, bx);
            v = det2(ax, cy, ay, cx);
            w = det2(bx, ay, by, ax);
        }
        // The signs decide, except where an edge function is within the band of 0 (module docs): there the
        // caller says what the edge is.
        let norm = |p: V3<T>| p.x.abs().max(p.y.abs()).max(p.z.abs());
        let scale = norm(self.origin) + norm(a).max(norm(b)).max(norm(c));
        // Through `dyn`, so that one copy serves every caller's closure.
        let mut edges = Some(edges);
        let mut ask = |near: [bool; 3]| edges.take().map_or([Edge::Shared; 3], |e| e(near));
        [u, v, w] = settle_near_edges(scale, [ax, ay, bx, by, cx, cy], [u, v, w], &mut ask)?;
        let det = u + v + w;
        if det == T::ZERO || det.is_nan() {
            return None;
        }
        // A triangle seen edge-on to working precision (the ray lies in its plane within rounding): its
        // projection is a segment, U, V and W are rounding noise around 0, and neither the inside decision nor
        // `t` means anything. Treated as a miss, like det = 0 (a ray from the z axis in the meridian plane of a
        // polar sliver otherwise "hits" it kilometres away). Each product carries at most one rounding and each
        // edge function one more, so rounding alone cannot make |det| exceed 4 ε times the sum of the products.
        let products = (cx * by).abs()
            + (cy * bx).abs()
            + (ax * cy).abs()
            + (ay * cx).abs()
            + (bx * ay).abs()
            + (by * ax).abs();
        if det.abs() <= T::from_f64(8.0) * T::EPSILON * products {
            return None;
        }
        let sz = self.sz;
        let az = sz * comp(a, kz);
        let bz = sz * comp(b, kz);
        let cz = sz * comp(c, kz);
        let t = (u * az + v * bz + w * cz) / det;
        if !(t >= t_lo && t <= t_hi) {
            return None;
        }
        Some((t, [u / det, v / det, w / det]))
    }
}

/// The band of the scalar edge functions, in `ε m` per unit of edge length, within which an edge's side is asked
/// of the caller (module docs).
const BAND: f64 = 64.0;

/// The edge functions `f = [U, V, W]` with each edge that the ray passes within rounding of settled by `edges`
/// (module docs): a border edge the exact ray passes outside makes a miss, one it passes inside sets a
/// wrong-signed edge function to 0 (the ray hits the closed triangle on that edge), a shared edge keeps its
/// sign; away from every edge, the signs decide. `None` for a miss. `scale` is `m` of the module docs, `p` the
/// vertices' sheared coordinates `[ax, ay, bx, by, cx, cy]`, `edges` is called at most once (only when an edge
/// is near). Out of line: one copy for every caller.
#[inline(never)]
fn settle_near_edges<T: Real>(
    scale: T,
    [ax, ay, bx, by, cx, cy]: [T; 6],
    mut f: [T; 3],
    edges: &mut dyn FnMut([bool; 3]) -> [Edge; 3],
) -> Option<[T; 3]> {
    let det = f.iter().fold(T::ZERO, |s, &x| s + x);
    // The orientation is the sign of the sum: only rounding-sized terms can have the other sign.
    if !(det.abs() > T::ZERO) {
        return None;
    }
    let wrong = |x: T| {
        if det > T::ZERO {
            x < T::ZERO
        } else {
            x > T::ZERO
        }
    };
    let tol = T::from_f64(BAND) * T::EPSILON * scale;
    // The edges opposite v0, v1, v2: v1–v2, v2–v0, v0–v1.
    let lengths = [
        (bx - cx).abs() + (by - cy).abs(),
        (cx - ax).abs() + (cy - ay).abs(),
        (ax - bx).abs() + (ay - by).abs(),
    ];
    let mut near = [false; 3];
    for ((x, len), n) in f.iter().zip(lengths).zip(&mut near) {
        *n = x.abs() <= tol * len;
        if wrong(*x) && !*n {
            return None;
        }
    }
    if !near.iter().any(|&n| n) {
        return Some(f);
    }
    let sides = edges(near);
    let mut closes = false;
    for ((x, side), n) in f.iter_mut().zip(sides).zip(near) {
        match (n, side) {
            (true, Edge::Outside) => return None,
            (true, Edge::Inside) if wrong(*x) => {
                *x = T::ZERO;
                closes = true;
            }
            (_, _) if wrong(*x) => return None,
            _ => {}
        }
    }
    // Closing a gap only for a triangle that is not a sliver as the ray sees it (seen edge-on, or a polar sliver):
    // there a closed gap of rounding size moves the hit along the sliver by its length over its width, far beyond
    // rounding.
    let longest = lengths[0].max(lengths[1]).max(lengths[2]);
    if closes && !(det.abs() >= T::from_f64(1e-3) * longest * longest) {
        return None;
    }
    Some(f)
}

/// Whether the exact ray `origin + t dir` passes through the closed triangle `v` (vertices in pairs) at each of
/// its edges `v1–v2`, `v2–v0`, `v0–v1` (module docs, "Edges on the border of the surface"): the sign of `dir ·
/// ((v_a − origin) × (v_b − origin))` in pair arithmetic against the triangle's orientation (their sum), a value
/// within the pair arithmetic's error of 0 counting as on the edge. `None` when the triangle is seen edge-on
/// within that error (no orientation).
pub fn exact_edge_sides<T: Real>(
    origin: V3<T>,
    dir: V3<T>,
    v: &[[Dd<T>; 3]; 3],
) -> Option<[bool; 3]> {
    let rel = |p: &[Dd<T>; 3]| {
        let [x, y, z] = *p;
        [
            x.plus_t(-origin.x),
            y.plus_t(-origin.y),
            z.plus_t(-origin.z),
        ]
    };
    let [r0, r1, r2] = [rel(&v[0]), rel(&v[1]), rel(&v[2])];
    let side = |[a0, a1, a2]: [Dd<T>; 3], [b0, b1, b2]: [Dd<T>; 3]| {
        let cx = a1.times(b2).minus(a2.times(b1));
        let cy = a2.times(b0).minus(a0.times(b2));
        let cz = a0.times(b1).minus(a1.times(b0));
        cx.times_t(dir.x)
            .plus(cy.times_t(dir.y))
            .plus(cz.times_t(dir.z))
            .value()
    };
    let s = [side(r1, r2), side(r2, r0), side(r0, r1)];
    // Error bound: the vertices are within a few ε² of their coordinates, each product and sum of the pair
    // arithmetic within a few ε² of its magnitude; 256 ε² (‖a‖ + M)(‖b‖ + M)‖dir‖₁ covers both with room (M the
    // largest vertex coordinate).
    let big = |p: &[Dd<T>; 3]| p.iter().fold(T::ZERO, |m, x| m.max(x.value().abs()));
    let m = big(&v[0]).max(big(&v[1])).max(big(&v[2]));
    let dir1 = dir.x.abs() + dir.y.abs() + dir.z.abs();
    let eps2 = T::from_f64(256.0) * T::EPSILON * T::EPSILON * dir1;
    let bound = |a: &[Dd<T>; 3], b: &[Dd<T>; 3]| eps2 * (big(a) + m) * (big(b) + m);
    let e = [bound(&r1, &r2), bound(&r2, &r0), bound(&r0, &r1)];
    let total = s[0] + s[1] + s[2];
    if !(total.abs() > e[0] + e[1] + e[2]) {
        return None;
    }
    let sign = if total > T::ZERO { T::ONE } else { -T::ONE };
    Some([0, 1, 2].map(|k| match (s.get(k), e.get(k)) {
        (Some(&x), Some(&b)) => x * sign >= -b,
        _ => false,
    }))
}

#[cfg(test)]
mod tests;
