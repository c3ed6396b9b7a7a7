//! The final refinement of the nearest hit (once per ray, after the traversal).
//!
//! # Why
//!
//! The traversal tests triangles whose vertices are computed in the scalar type: `lat0_deg + i·dlat_deg` rounded, degrees
//! to radians rounded, `sin`/`cos` (an ulp), `N = a/√(1 − e² sin²φ)` and the ECEF products. Each vertex is off
//! by a few ulps of its coordinates (about 1e-9 m at Earth scale in `f64`). The triangle test itself is far more
//! accurate relative to *those* vertices, but a vertex error δ moves the hit along a ray of elevation ε over the
//! triangle by about δ / sin ε: 377 δ at 0.15°, 5700 δ at 0.01°, so a grazing ray 150 km long misses the exact
//! surface's hit point by more than 1 µm.
//!
//! # What
//!
//! For the hit triangle only (the traversal's choice of triangle is kept), its three vertices are recomputed in
//! double-double ([`crate::dd`]): the latitude `lat0_deg + i·dlat_deg` and longitude `lon0_deg + j·dlon_deg` as exact pairs,
//! `sin`/`cos` and the ECEF conversion to a few `ε²` relative. The hit parameter then comes from the triangle's
//! plane (next section).
//!
//! The normal `n = (v1 − v0) × (v2 − v0)` is computed in plain scalars from the rounded edge vectors, and its
//! error does not matter: the plane used still passes *exactly* (to pair precision) through `v0`, and a
//! normal tilted by an angle of a few ε moves it, at the hit point, by a few ε times the distance from `v0` —
//! the size of the triangle (a grid cell), not the size of the Earth, which is what the vertices' own rounding
//! costs.
//!
//! # The step
//!
//! The plane's parameter is reached in one step from a parameter `t_ref` near it (the traversal's): with
//! `q = o + t_ref·d`, `t = t_ref + n·(v0 − q) / (n·d)`. The plane equation is linear in `t`, so the step is exact
//! for any `t_ref`; what matters is the arithmetic. `q` (with `t_ref·d` exact by `two_prod`), `v0 − q` and the
//! residual `n·(v0 − q)` are formed in pairs, so the residual, which is only a few vertex roundings δ long, is
//! known far below an ulp. So is `n·d`, which at elevation ε over the plane cancels to `sin ε` of its terms
//! (in scalars it would be off by `ε / sin ε` relatively). The step `dt` is then one scalar division, correct
//! to a few ε relatively, and it is only as long as the traversal's error along the ray.
//!
//! The hit point `q + dt·d` is formed in pairs and rounded once per coordinate, so [`super::Hit::ecef`] is the
//! correctly rounded point of the refined plane (and may differ from `ray.at(hit.t)` by the rounding of `t·d`).
//!
//! # Ties: the containment walk
//!
//! When the ray passes within rounding distance of an edge or vertex, the traversal's choice between the
//! triangles that share it is decided by the `f64` vertices, and the exact ray may cross the neighbour instead.
//! The plane of the chosen triangle then meets the ray *outside* that triangle, and at grazing incidence the
//! point slides along the plane by the miss distance over `sin ε` (4.8e-8 m for a 0.1° ray through a vertex of
//! flat terrain, where the neighbouring planes differ by the Earth's curvature). So the refined point's in-plane
//! distances inside the three edges are checked (barycentric coordinates times the triangle's heights, with a
//! tolerance of `16 ε ‖p‖∞`), and while it lies beyond an edge the refinement steps to the triangle across that
//! edge (at most `MAX_WALK` steps, staying in the grid). A walk that does not settle in a triangle (a nodata
//! neighbour, the grid's edge, or `MAX_WALK` steps) keeps the traversal's unrefined hit: a plane point outside
//! every triangle tried is not on the surface. The reported [`super::Hit::cell`] stays the traversal's: at such
//! a tie either cell is a correct answer.
//!
//! # The guard
//!
//! The refinement removes errors of a few ulps of the coordinates. The refined hit is accepted only when it is
//! finite, lies in `[t_min, t_max]`, and moves the point, measured along the triangle's normal, by at most
//! `256 ε (‖o‖∞ + ‖p‖∞)` (`p` the unrefined hit point), that is by about a hundred times what the vertex and
//! triangle-test rounding can account for. Otherwise (a degenerate triangle whose plane is undefined, a ray
//! lying in the plane, an overflow, or a refinement that disagrees with the traversal for any other reason) the
//! unrefined hit is kept: the refinement can sharpen a hit, never remove or move one by more than rounding. The
//! normal-direction measure is the right one because along the plane a grazing ray legitimately moves by
//! `1 / sin ε` times more.

use super::grid::Grid;
use super::storage::TerrainCaches;
use super::triangle::exact_edge_sides;
use crate::dd::{Dd, two_prod};

use crate::ray::Ray;
use crate::real::Real;
use crate::vec3::V3;

/// Which triangle of a cell: [`Tri::First`] is `(V(i,j), V(i,j+1), V(i+1,j+1))`, [`Tri::Second`] is
/// `(V(i,j), V(i+1,j+1), V(i+1,j))` (the order of [`Grid`]'s contract and of the traversal's tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Tri {
    First,
    Second,
}

/// A vertex of a traced triangle that is not a full-resolution cell's (coarse cells, stitched fans): grid
/// vertex `V(i, j)`, or the middle of the segment `V(i, j)–V(i1, j1)` (`Mid([i, j, i1, j1])`, a stitched cell's
/// fan center).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Vtx {
    Grid(u32, u32),
    Mid([u32; 4]),
}

/// Which triangle a candidate is: one of a full-resolution cell's two (refined with the containment walk), or
/// any other by its vertices (coarse cells and stitched fans, refined without a walk).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum TriRef {
    Cell(Tri),
    Vertices([Vtx; 3]),
}

/// `a − b` rounded to scalars.
#[inline]
fn diff<T: Real>(a: &[Dd<T>; 3], b: &[Dd<T>; 3]) -> V3<T> {
    let ([a0, a1, a2], [b0, b1, b2]) = (a, b);
    V3::new(
        a0.minus(*b0).value(),
        a1.minus(*b1).value(),
        a2.minus(*b2).value(),
    )
}

/// Grid vertex `V(i, j)` in pairs from the storage's parallels and meridians; `None` for nodata or outside the
/// grid.
fn vertex_dd<T: Real, S: TerrainCaches<T> + ?Sized>(
    s: &S,
    g: &Grid<T>,
    (i, j): (u32, u32),
) -> Option<[Dd<T>; 3]> {
    if i >= g.rows || j >= g.cols {
        return None;
    }
    let h = s.height(i, j).filter(|h| h.is_finite())?;
    let (so, co) = s.col_sin_cos_dd(j);
    Some(s.row_parallel(i).ecef(so, co, h))
}

/// The intersection of the ray with the plane of one triangle, in pairs.
#[derive(Debug, Clone, Copy)]
struct PlaneHit<T> {
    t: T,
    /// The point `o + t d`, formed in pairs and rounded.
    p: [T; 3],
    /// `|n·d| / |n|`: the sine of the ray's elevation over the plane times `|d|`.
    slope: T,
    /// `|n|` of the scalar normal.
    n_len: T,
    /// Barycentric coordinates of `p` times `|n|²` (for `v0`, `v1`, `v2`).
    bary: [T; 3],
    /// Squared lengths of the edges opposite `v0`, `v1`, `v2`.
    edge2: [T; 3],
}

impl<T: Real> PlaneHit<T> {
    /// The signed in-plane distance of `p` inside the edge opposite `v_k` (negative: outside): its barycentric
    /// coordinate times the triangle's height over that edge.
    fn inside(&self, k: usize) -> T {
        let (c, e2) = (self.bary.get(k), self.edge2.get(k));
        match (c, e2) {
            (Some(&c), Some(&e2)) => c / (self.n_len * e2.sqrt()),
            _ => T::NAN,
        }
    }

    /// Whether `p` lies inside all three edges, or beyond one by at most `tol` (a root and a division only for
    /// the edges `p` is beyond).
    fn within(&self, tol: T) -> bool {
        (0..3).all(|k| self.bary.get(k).is_some_and(|&c| c >= T::ZERO) || self.inside(k) >= -tol)
    }
}

/// The refined intersection with triangle `tri` of cell `[i, j]` (module docs); `None` if a corner is nodata or
/// outside the grid, or the result is not finite.
fn plane_hit<T: Real, S: TerrainCaches<T> + ?Sized>(
    s: &S,
    g: &Grid<T>,
    ray: &Ray<T>,
    t_ref: T,
    [i, j]: [u32; 2],
    tri: Tri,
) -> Option<PlaneHit<T>> {
    let (i1, j1) = (i.checked_add(1)?, j.checked_add(1)?);
    if i1 >= g.rows || j1 >= g.cols {
        return None;
    }
    let (row0, row1) = (s.row_parallel(i), s.row_parallel(i1));
    let ((sw, cw), (se, ce)) = (s.col_sin_cos_dd(j), s.col_sin_cos_dd(j1));
    let height = |i: u32, j: u32| s.height(i, j).filter(|h| h.is_finite());
    let v0 = row0.ecef(sw, cw, height(i, j)?);
    let v11 = row1.ecef(se, ce, height(i1, j1)?);
    let (v1, v2) = match tri {
        Tri::First => (row0.ecef(se, ce, height(i, j1)?), v11),
        Tri::Second => (v11, row1.ecef(sw, cw, height(i1, j)?)),
    };
    plane_through(ray, t_ref, &v0, &v1, &v2)
}

/// A [`Vtx`] in pairs.
fn vtx_dd<T: Real, S: TerrainCaches<T> + ?Sized>(s: &S, g: &Grid<T>, v: Vtx) -> Option<[Dd<T>; 3]> {
    match v {
        Vtx::Grid(i, j) => vertex_dd(s, g, (i, j)),
        Vtx::Mid([i, j, i1, j1]) => {
            let a = vertex_dd(s, g, (i, j))?;
            let b = vertex_dd(s, g, (i1, j1))?;
            let [a0, a1, a2] = a;
            let [b0, b1, b2] = b;
            let half = |x: Dd<T>, y: Dd<T>| x.plus(y).times_t(T::HALF);
            Some([half(a0, b0), half(a1, b1), half(a2, b2)])
        }
    }
}

/// Whether the exact ray passes through the closed triangle `tri` of cell `[i, j]` at each of its edges (opposite
/// its first, second and third vertex), from its vertices in pairs ([`exact_edge_sides`]); `None` if a vertex has
/// no data or the triangle is seen edge-on.
pub(super) fn exact_sides<T: Real, S: TerrainCaches<T> + ?Sized>(
    s: &S,
    g: &Grid<T>,
    ray: &Ray<T>,
    [i, j]: [u32; 2],
    tri: TriRef,
) -> Option<[bool; 3]> {
    let vertices = match tri {
        TriRef::Vertices(v) => v,
        TriRef::Cell(t) => {
            let (i1, j1) = (i.checked_add(1)?, j.checked_add(1)?);
            match t {
                Tri::First => [Vtx::Grid(i, j), Vtx::Grid(i, j1), Vtx::Grid(i1, j1)],
                Tri::Second => [Vtx::Grid(i, j), Vtx::Grid(i1, j1), Vtx::Grid(i1, j)],
            }
        }
    };
    let [a, b, c] = vertices;
    let v = [vtx_dd(s, g, a)?, vtx_dd(s, g, b)?, vtx_dd(s, g, c)?];
    exact_edge_sides(ray.origin(), ray.scaled_dir(), &v)
}

/// The intersection of the ray with the plane through `v0, v1, v2` (pairs), with the point's in-plane distances
/// inside the three edges, as a correction of a parameter `t_ref` near it (module docs, "The step").
fn plane_through<T: Real>(
    ray: &Ray<T>,
    t_ref: T,
    v0: &[Dd<T>; 3],
    v1: &[Dd<T>; 3],
    v2: &[Dd<T>; 3],
) -> Option<PlaneHit<T>> {
    // Edges rounded to scalars; the normal in scalars (module docs: its error tilts the plane about v0 only).
    let a = diff(v1, v0);
    let b = diff(v2, v0);
    let n = a.cross(b);
    let [o0, o1, o2] = ray.origin().to_array();
    let [d0, d1, d2] = ray.dir().to_array();
    let [n0, n1, n2] = n.to_array();
    let [v00, v01, v02] = *v0;
    // `q = o + t_ref·d` and `v0 − q` in pairs, the plane's residual `n·(v0 − q)` in pairs, then one step.
    let q = [
        two_prod(t_ref, d0).plus_t(o0),
        two_prod(t_ref, d1).plus_t(o1),
        two_prod(t_ref, d2).plus_t(o2),
    ];
    let [q0, q1, q2] = q;
    let gap = [v00.minus(q0), v01.minus(q1), v02.minus(q2)];
    let [g0, g1, g2] = gap;
    let residual = g0.times_t(n0).plus(g1.times_t(n1)).plus(g2.times_t(n2));
    let den = two_prod(n0, d0)
        .plus(two_prod(n1, d1))
        .plus(two_prod(n2, d2))
        .value();
    let dt = residual.value() / den;
    let t = t_ref + dt;
    let p = [
        q0.plus_t(dt * d0).value(),
        q1.plus_t(dt * d1).value(),
        q2.plus_t(dt * d2).value(),
    ];
    // Barycentric coordinates of p: λ1 = (w × b)·n / |n|², λ2 = (a × w)·n / |n|², λ0 = 1 − λ1 − λ2; kept times
    // |n|² (`PlaneHit::inside` turns them into in-plane distances inside each edge). `w = p − v0 = dt·d − gap`.
    let w = V3::new(
        dt * d0 - g0.value(),
        dt * d1 - g1.value(),
        dt * d2 - g2.value(),
    );
    let nn = n.length_squared();
    let n_len = nn.sqrt();
    let (c1, c2) = (w.cross(b).dot(n), a.cross(w).dot(n));
    let bary = [nn - c1 - c2, c1, c2];
    let edge2 = [
        b.minus(a).length_squared(),
        b.length_squared(),
        a.length_squared(),
    ];
    let finite = t.is_finite()
        && n_len > T::ZERO
        && n_len.is_finite()
        && p.iter().chain(&bary).chain(&edge2).all(|x| x.is_finite());
    finite.then_some(PlaneHit {
        t,
        p,
        slope: den.abs() / n_len,
        n_len,
        bary,
        edge2,
    })
}

/// The triangle across edge `k` (the edge opposite vertex `k`) of triangle `tri` of cell `[i, j]`, if inside
/// the grid's index range.
fn across<T: Real>(g: &Grid<T>, [i, j]: [u32; 2], tri: Tri, k: usize) -> Option<([u32; 2], Tri)> {
    let n = match (tri, k) {
        // First (V(i,j), V(i,j+1), V(i+1,j+1)): column j+1, the diagonal, row i.
        (Tri::First, 0) => ([i, j.checked_add(1)?], Tri::Second),
        (Tri::First, 1) => ([i, j], Tri::Second),
        (Tri::First, _) => ([i.checked_sub(1)?, j], Tri::Second),
        // Second (V(i,j), V(i+1,j+1), V(i+1,j)): row i+1, column j, the diagonal.
        (Tri::Second, 0) => ([i.checked_add(1)?, j], Tri::First),
        (Tri::Second, 1) => ([i, j.checked_sub(1)?], Tri::First),
        (Tri::Second, _) => ([i, j], Tri::First),
    };
    (n.0[0] < g.cell_rows() && n.0[1] < g.cell_cols()).then_some(n)
}

/// The most triangles the containment walk visits (the six around a vertex, and one more).
const MAX_WALK: usize = 7;

/// The refined hit `(t, point)` of `ray` for the traversal's triangle `tri` of cell `[i, j]` at parameter `t0`
/// (module docs), or `None` when the guard rejects it. `height` gives the storage's vertex heights;
/// `full_resolution` tells whether a cell is traced at the DEM's own resolution (the walk steps only into such
/// cells: elsewhere a multi-resolution surface has other triangles).
#[allow(clippy::too_many_arguments)]
pub(super) fn refine<T: Real, S: TerrainCaches<T> + ?Sized>(
    s: &S,
    g: &Grid<T>,
    ray: &Ray<T>,
    t0: T,
    cell: [u32; 2],
    tri: Tri,
    full_resolution: &impl Fn([u32; 2]) -> bool,
) -> Option<(T, [T; 3])> {
    let first = plane_hit(s, g, ray, t0, cell, tri)?;
    // Containment walk (module docs): at a tie the traversal may have chosen a triangle that the exact ray only
    // grazes past; step across the edge that the refined point lies beyond, to the triangle that contains it.
    let tol = T::from_f64(16.0) * T::EPSILON * V3::from(first.p).max_abs();
    let mut cur = (first, cell, tri);
    let mut chosen = None;
    for _ in 0..MAX_WALK {
        let (h, c, tr) = cur;
        if h.within(tol) {
            chosen = Some(h);
            break;
        }
        let [d0, d1, d2] = [0, 1, 2].map(|k| h.inside(k));
        let k = if d0 <= d1 && d0 <= d2 {
            0
        } else if d1 <= d2 {
            1
        } else {
            2
        };
        let Some((nc, nt)) = across(g, c, tr, k).filter(|(nc, _)| full_resolution(*nc)) else {
            break;
        };
        let Some(nh) = plane_hit(s, g, ray, t0, nc, nt) else {
            break;
        };
        cur = (nh, nc, nt);
    }
    // The guard (module docs). A walk that did not settle in a triangle keeps the traversal's hit: the plane's
    // point then lies outside every triangle tried (a ray almost in the triangle's plane slides along it
    // arbitrarily far).
    guard(ray, t0, &chosen?)
}

/// The guard (module docs): the refined hit if it is in the ray's range and moved along the normal by at most
/// a few hundred ulps of the coordinates.
fn guard<T: Real>(ray: &Ray<T>, t0: T, chosen: &PlaneHit<T>) -> Option<(T, [T; 3])> {
    let (t, p) = (chosen.t, chosen.p);
    if !(ray.t_min() <= t && t <= ray.t_max()) {
        return None;
    }
    let moved = (t - t0).abs() * chosen.slope;
    let allowed =
        T::from_f64(256.0) * T::EPSILON * (ray.origin().max_abs() + V3::from(ray.at(t0)).max_abs());
    (moved <= allowed).then_some((t, p))
}

/// The refined hit for a triangle given by its vertices (coarse cells and stitched fans, §5): the same plane
/// and guard as [`refine`], without the containment walk — a point beyond an edge keeps the traversal's hit.
pub(super) fn refine_vertices<T: Real, S: TerrainCaches<T> + ?Sized>(
    s: &S,
    g: &Grid<T>,
    ray: &Ray<T>,
    t0: T,
    tri: [Vtx; 3],
) -> Option<(T, [T; 3])> {
    let [a, b, c] = tri;
    let h = plane_through(
        ray,
        t0,
        &vtx_dd(s, g, a)?,
        &vtx_dd(s, g, b)?,
        &vtx_dd(s, g, c)?,
    )?;
    let tol = T::from_f64(16.0) * T::EPSILON * V3::from(h.p).max_abs();
    if !h.within(tol) {
        return None;
    }
    guard(ray, t0, &h)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The grid vertices `(row, col)` of triangle `tri` of cell `[i, j]`, in the order `v0, v1, v2`.
    fn corners([i, j]: [u32; 2], tri: Tri) -> [(u32, u32); 3] {
        match tri {
            Tri::First => [(i, j), (i, j + 1), (i + 1, j + 1)],
            Tri::Second => [(i, j), (i + 1, j + 1), (i + 1, j)],
        }
    }

    /// A point in pairs from scalars.
    fn dd3([x, y, z]: [f64; 3]) -> [Dd<f64>; 3] {
        [Dd::from(x), Dd::from(y), Dd::from(z)]
    }

    /// The right triangle `v0 = (1, −2, 3)`, `v1 = v0 + (2, 0, 0)`, `v2 = v0 + (0, 4, 0)` (normal `(0, 0, 8)`),
    /// and the ray from `v0 + (x − 0.25, y − 0.5, 2)` along `(0.25, 0.5, −2)`, which meets its plane at
    /// `v0 + (x, y, 0)` at `t = 1`; every value here is exact in binary.
    fn slanted_hit(x: f64, y: f64, t_ref: f64) -> PlaneHit<f64> {
        let v0 = [1.0, -2.0, 3.0];
        let [a, b, c] = v0;
        let ray = Ray::new([a + x - 0.25, b + y - 0.5, c + 2.0], [0.25, 0.5, -2.0]).unwrap();
        plane_through(
            &ray,
            t_ref,
            &dd3(v0),
            &dd3([a + 2.0, b, c]),
            &dd3([a, b + 4.0, c]),
        )
        .unwrap()
    }

    /// The plane hit of the slanted ray through `v0 + (0.5, 1, 0)`, stepped from `t_ref` before, at and after
    /// it: `t = 1` and the point exactly, the slope `|n·d| / |n| = 16 / 8`, `|n| = 8`, the barycentric
    /// coordinates `(1/2, 1/4, 1/4)` times `|n|² = 64`, and the squared lengths of the edges opposite each
    /// vertex (20, 16, 4).
    #[test]
    fn plane_through_a_right_triangle_from_a_slanted_ray_is_exact_from_any_reference_parameter() {
        for t_ref in [0.75, 1.0, 3.0, -5.0] {
            let h = slanted_hit(0.5, 1.0, t_ref);
            assert_eq!(h.t, 1.0, "{t_ref}");
            assert_eq!(h.p, [1.5, -1.0, 3.0], "{t_ref}");
            assert_eq!((h.slope, h.n_len), (2.0, 8.0), "{t_ref}");
            assert_eq!(h.bary, [32.0, 16.0, 16.0], "{t_ref}");
            assert_eq!(h.edge2, [20.0, 16.0, 4.0], "{t_ref}");
        }
    }

    /// `PlaneHit::inside`: the signed in-plane distance inside each edge (opposite `v0`: the hypotenuse
    /// `2x + y = 4`; opposite `v1`: `x = 0`; opposite `v2`: `y = 0`), for a point inside and points beyond each
    /// edge; `within(tol)` accepts a point beyond an edge by at most `tol`, and no further.
    #[test]
    fn in_plane_distances_inside_each_edge_and_the_tolerance_beyond_one() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-15;
        let h = slanted_hit(0.5, 1.0, 1.0);
        assert!(close(h.inside(0), 2.0 / 5.0_f64.sqrt()));
        assert_eq!((h.inside(1), h.inside(2)), (0.5, 1.0));
        assert!(h.within(0.0));
        assert!(h.inside(3).is_nan());
        // Beyond each edge by 0.5, 0.25 and 2/√5 (the hypotenuse, from (2, 2)).
        for (x, y, k, beyond) in [
            (-0.5, 1.0, 1, 0.5),
            (0.5, -0.25, 2, 0.25),
            (2.0, 2.0, 0, 2.0 / 5.0_f64.sqrt()),
        ] {
            let h = slanted_hit(x, y, 1.0);
            assert!(close(h.inside(k), -beyond), "{x} {y}: {}", h.inside(k));
            assert!(h.bary.get(k).is_some_and(|&c| c < 0.0));
            assert!(!h.within(0.0) && !h.within(0.99 * beyond), "{x} {y}");
            assert!(h.within(1.01 * beyond) && h.within(2.0 * beyond), "{x} {y}");
        }
        // Exactly the tolerance beyond (an exact distance): within.
        assert!(slanted_hit(-0.5, 1.0, 1.0).within(0.5));
    }

    /// The guard: a refined hit is kept when it lies in `[t_min, t_max]` (either end included) and moved along
    /// the normal, `|t − t0|·slope`, by at most `256 ε (‖o‖∞ + ‖o + t0 d‖∞)`: here `256 ε (8 + 4)` with the
    /// slope 2, so 384 steps of `ulp(4) = 4 ε` from `t0 = 4` are kept and 385 are not, either way.
    #[test]
    fn the_guard_keeps_a_refined_hit_moved_by_at_most_its_bound_along_the_normal_and_inside_the_range()
     {
        let ray = Ray::new([0.0, 0.0, 8.0], [0.0, 0.0, -1.0]).unwrap();
        let step = 4.0 * f64::EPSILON;
        let hit = |t: f64| PlaneHit {
            t,
            p: [0.0, 0.0, 8.0 - t],
            slope: 2.0,
            n_len: 1.0,
            bary: [1.0; 3],
            edge2: [1.0; 3],
        };
        let kept = |ray: &Ray<f64>, t: f64| guard(ray, 4.0, &hit(t)).map(|(t, _)| t);
        for m in [-384.0, -1.0, 0.0, 1.0, 384.0] {
            assert_eq!(kept(&ray, 4.0 + m * step), Some(4.0 + m * step), "{m}");
        }
        for m in [-385.0, 385.0, 1e6] {
            assert_eq!(kept(&ray, 4.0 + m * step), None, "{m}");
        }
        // The range, each end included: t0 on t_max, then on t_min.
        let to_t0 = ray.with_interval(0.0, 4.0).unwrap();
        assert_eq!(kept(&to_t0, 4.0), Some(4.0));
        assert_eq!(kept(&to_t0, 4.0 + step), None);
        let from_t0 = ray.with_interval(4.0, 6.0).unwrap();
        assert_eq!(kept(&from_t0, 4.0), Some(4.0));
        assert_eq!(kept(&from_t0, 4.0 - step), None);
    }

    #[test]
    fn the_triangle_across_each_edge_shares_exactly_that_edge() {
        let g = Grid {
            lat0_deg: 10.0,
            lon0_deg: 20.0,
            dlat_deg: -0.5,
            dlon_deg: 0.5,
            rows: 4,
            cols: 5,
        };
        let mut crossings = 0;
        for i in 0..3 {
            for j in 0..4 {
                for tri in [Tri::First, Tri::Second] {
                    let v = corners([i, j], tri);
                    for k in 0..3 {
                        let edge: std::vec::Vec<_> =
                            (0..3).filter(|&m| m != k).map(|m| v[m]).collect();
                        let Some((c, t)) = across(&g, [i, j], tri, k) else {
                            // Only the grid's outer edges have no triangle across.
                            let outer = edge.iter().all(|&(r, _)| r == 0)
                                || edge.iter().all(|&(r, _)| r == 3)
                                || edge.iter().all(|&(_, s)| s == 0)
                                || edge.iter().all(|&(_, s)| s == 4);
                            assert!(outer, "{i},{j} {tri:?} edge {k}");
                            continue;
                        };
                        let w = corners(c, t);
                        assert!((c, t) != ([i, j], tri));
                        assert!(edge.iter().all(|e| w.contains(e)), "{i},{j} {tri:?} {k}");
                        crossings += 1;
                    }
                }
            }
        }
        // 3 × 4 cells: 12 diagonals twice, 2·4 interior row edges and 3·3 interior column edges twice each.
        assert_eq!(crossings, 2 * (12 + 2 * 4 + 3 * 3));
    }
}
