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
//! edge, or next to a nodata vertex) has no neighbour to catch a ray that the vertices' rounding puts just
//! outside it: a ray through the exact vertex `V(0, j)` of a DEM's first row passes, in the scalar vertices,
//! up to a few ulps of their coordinates outside the triangles on either side, and the closed triangles of the
//! contract would be missed. [`WatertightRay::intersect_with_border`] therefore takes which edges are on the
//! border and, for those only, counts an edge function of the wrong sign as 0 when it is within what the
//! rounding of the vertices and of the sheared coordinates can explain: `16 ε m (|Δx| + |Δy|)`, where `m` is
//! `‖origin‖∞` plus the largest `‖v − origin‖∞` of the three vertices and `Δ` the edge in the sheared frame
//! (the edge function is the edge's length times the origin's distance from it; `16 ε m` is about 1e-8 m at
//! Earth scale in `f64`). The ray then hits the triangle on its edge. Inner edges keep the exact rule: their
//! neighbour answers.

use crate::dd::two_prod;
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
        self.intersect_with_border(v0, v1, v2, t_lo, t_hi, || [false; 3])
    }

    /// [`WatertightRay::intersect`], with the edges on the border of the surface closed up to the vertices'
    /// rounding (module docs, "Edges on the border of the surface"). `border()` is asked only when the ray
    /// passes that close outside an edge: which of the edges `v1–v2`, `v2–v0`, `v0–v1` have no neighbouring
    /// triangle.
    #[inline]
    pub fn intersect_with_border(
        &self,
        v0: V3<T>,
        v1: V3<T>,
        v2: V3<T>,
        t_lo: T,
        t_hi: T,
        border: impl FnOnce() -> [bool; 3],
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
        let neg = u < T::ZERO || v < T::ZERO || w < T::ZERO;
        let pos = u > T::ZERO || v > T::ZERO || w > T::ZERO;
        if neg && pos {
            let norm = |p: V3<T>| p.x.abs().max(p.y.abs()).max(p.z.abs());
            let scale = norm(self.origin) + norm(a).max(norm(b)).max(norm(c));
            // Through `dyn`, so that one copy serves every caller's closure.
            let mut border = Some(border);
            let mut open = || border.take().map_or([false; 3], |b| b());
            [u, v, w] = close_border_edges(scale, [ax, ay, bx, by, cx, cy], [u, v, w], &mut open)?;
        }
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

/// The edge functions `f = [U, V, W]` of a ray that misses the triangle by their signs, with each one of the
/// wrong sign set to 0 if its edge is on the border and the miss is within rounding (module docs); `None` if
/// any edge function keeps the wrong sign. `scale` is `m` of the module docs, `p` the vertices' sheared
/// coordinates `[ax, ay, bx, by, cx, cy]`, `border` says which edges are on the border (called at most once).
/// Out of line: it runs only for misses.
#[inline(never)]
fn close_border_edges<T: Real>(
    scale: T,
    [ax, ay, bx, by, cx, cy]: [T; 6],
    mut f: [T; 3],
    border: &mut dyn FnMut() -> [bool; 3],
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
    let tol = T::from_f64(16.0) * T::EPSILON * scale;
    // The edges opposite v0, v1, v2: v1–v2, v2–v0, v0–v1.
    let lengths = [
        (bx - cx).abs() + (by - cy).abs(),
        (cx - ax).abs() + (cy - ay).abs(),
        (ax - bx).abs() + (ay - by).abs(),
    ];
    // Only for a triangle that is not a sliver as the ray sees it (seen edge-on, or a polar sliver): there a
    // closed gap of rounding size moves the hit along the sliver by its length over its width, far beyond rounding.
    let longest = lengths[0].max(lengths[1]).max(lengths[2]);
    if !(det.abs() >= T::from_f64(1e-3) * longest * longest) {
        return None;
    }
    let mut need = [false; 3];
    for ((x, len), n) in f.iter().zip(lengths).zip(&mut need) {
        if wrong(*x) {
            if !(x.abs() <= tol * len) {
                return None;
            }
            *n = true;
        }
    }
    let open = border();
    if need.iter().zip(open).any(|(&n, o)| n && !o) {
        return None;
    }
    for x in &mut f {
        if wrong(*x) {
            *x = T::ZERO;
        }
    }
    Some(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_a_unit_triangle_from_both_sides() {
        let (v0, v1, v2) = (
            V3::new(0.0, 0.0, 0.0),
            V3::new(1.0, 0.0, 0.0),
            V3::new(0.0, 1.0, 0.0),
        );
        let down = WatertightRay::new(V3::new(0.25, 0.25, 2.0), V3::new(0.0, 0.0, -1.0)).unwrap();
        let (t, b) = down.intersect(v0, v1, v2, 0.0, 10.0).unwrap();
        assert_eq!(t, 2.0);
        assert!((b[0] - 0.5).abs() < 1e-15 && (b[1] - 0.25).abs() < 1e-15);
        let up = WatertightRay::new(V3::new(0.25, 0.25, -2.0), V3::new(0.0, 0.0, 1.0)).unwrap();
        assert_eq!(up.intersect(v0, v1, v2, 0.0, 10.0).unwrap().0, 2.0);
        let miss = WatertightRay::new(V3::new(0.75, 0.75, 2.0), V3::new(0.0, 0.0, -1.0)).unwrap();
        assert!(miss.intersect(v0, v1, v2, 0.0, 10.0).is_none());
        // Out of the interval.
        assert!(down.intersect(v0, v1, v2, 0.0, 1.5).is_none());
    }

    #[test]
    fn ray_almost_in_the_plane_of_a_triangle_is_a_miss() {
        // The triangle lies in the plane x = 0; the ray starts in that plane (outside the triangle) and leaves
        // it at an angle of 1e-13, so it meets the plane only at its origin. The projection along the ray is
        // a segment and the edge functions are rounding noise: no hit.
        let (v0, v1, v2) = (
            V3::new(0.0, 0.0, 0.0),
            V3::new(0.0, 1.0, 0.0),
            V3::new(0.0, 0.3, 1.0),
        );
        for (o, d) in [
            (V3::new(0.0, -1.0, 0.25), V3::new(1e-13, 1.0, 0.0)),
            (V3::new(0.0, -5.0e6, 0.25), V3::new(-3e-13, 1.0, 1e-9)),
            (V3::new(0.0, 2.0, 0.1), V3::new(1e-14, -1.0, 0.05)),
        ] {
            let w = WatertightRay::new(o, d).unwrap();
            assert_eq!(w.intersect(v0, v1, v2, 0.0, 1e7), None, "{o:?} {d:?}");
        }
        // A polar sliver (two vertices on the z axis, 0.25 m apart, the third 457 km away) and a ray from the
        // z axis 5.4e9 m below, heading out almost in the sliver's meridian plane (a fuzz finding): U and W
        // round to exactly 0 and V to noise, which without the edge-on test reads as a hit at vertex B, at a
        // point of the ray 343 km from the axis.
        let w = WatertightRay::new(
            V3::new(0.0, -0.0, -5_362_342_899.685_755),
            V3::new(
                -240_033.236_469_758_65,
                245_013.668_449_579_42,
                5_355_995_345.833_253,
            ),
        )
        .unwrap();
        let sliver = [
            V3::new(-0.0, 0.0, -6_356_752.564_245_179),
            V3::new(-0.0, 0.0, -6_356_752.314_245_179),
            V3::new(
                -319_786.616_911_798_5,
                326_421.845_920_123_2,
                -6_337_689.425_257_364,
            ),
        ];
        assert_eq!(
            w.intersect(sliver[0], sliver[1], sliver[2], 0.0, 10.0),
            None
        );
    }

    #[test]
    fn ray_through_shared_edge_hits_at_least_one_triangle() {
        // Quad split along its diagonal; rays exactly through the diagonal never slip through.
        let p = [
            V3::new(0.0, 0.0, 0.3),
            V3::new(1.0, 0.0, 0.1),
            V3::new(1.0, 1.0, 0.7),
            V3::new(0.0, 1.0, 0.2),
        ];
        for k in 0..=20 {
            let s = k as f64 / 20.0 * 0.999 + 0.0005;
            // The point (s, s) of the diagonal, approached vertically and obliquely.
            let z = 0.3 + (0.7 - 0.3) * s;
            for dir in [V3::new(0.0, 0.0, -1.0), V3::new(0.013, -0.007, -1.0)] {
                let o = V3::new(s, s, z).add_scaled(-5.0, dir);
                let r = WatertightRay::new(o, dir).unwrap();
                let h1 = r.intersect(p[0], p[1], p[2], 0.0, 10.0);
                let h2 = r.intersect(p[0], p[2], p[3], 0.0, 10.0);
                assert!(h1.is_some() || h2.is_some(), "slipped through at s = {s}");
            }
        }
    }

    #[test]
    fn border_edge_is_closed_up_to_rounding_and_no_further() {
        // A triangle of Earth-scale coordinates and a ray down through a point 1e-9 m outside its edge v0–v1
        // (y = 6.4e6 − 0.5): within the vertices' rounding, so a hit on that edge when it is on the border,
        // a miss when it is not (its neighbour answers) and a miss 1e-6 m outside.
        let y0 = 6.4e6 - 0.5;
        let (v0, v1, v2) = (
            V3::new(0.0, y0, 10.0),
            V3::new(1.0, y0, 10.0),
            V3::new(0.0, y0 + 1.0, 10.0),
        );
        for (gap, border, hits) in [
            (1e-9, [false, false, true], true),
            (1e-9, [false, false, false], false),
            (1e-9, [true, true, false], false),
            (1e-6, [true, true, true], false),
        ] {
            let r =
                WatertightRay::new(V3::new(0.5, y0 - gap, 20.0), V3::new(0.0, 0.0, -1.0)).unwrap();
            let hit = r.intersect_with_border(v0, v1, v2, 0.0, 100.0, || border);
            assert_eq!(hit.is_some(), hits, "{gap} {border:?}");
            if let Some((t, b)) = hit {
                assert!((t - 10.0).abs() < 1e-12 && b[2] == 0.0, "{t} {b:?}");
            }
        }
    }

    #[test]
    fn degenerate_triangle_and_zero_direction() {
        let v = V3::new(1.0, 1.0, 1.0);
        let r = WatertightRay::new(V3::new(1.0, 1.0, 5.0), V3::new(0.0, 0.0, -1.0)).unwrap();
        assert!(r.intersect(v, v, v, 0.0, 10.0).is_none());
        assert!(WatertightRay::new(V3::new(0.0, 0.0, 0.0), V3::new(0.0, 0.0, 0.0)).is_none());
    }
}
