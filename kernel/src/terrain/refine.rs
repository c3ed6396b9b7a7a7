//! The final refinement of the nearest hit (once per ray, after the traversal).
//!
//! # Why
//!
//! The traversal tests triangles whose vertices are computed in the scalar type: `lat0 + i·dlat` rounded, degrees
//! to radians rounded, `sin`/`cos` (an ulp), `N = a/√(1 − e² sin²φ)` and the ECEF products. Each vertex is off
//! by a few ulps of its coordinates (about 1e-9 m at Earth scale in `f64`). The triangle test itself is far more
//! accurate relative to *those* vertices, but a vertex error δ moves the hit along a ray of elevation ε over the
//! triangle by about δ / sin ε: 377 δ at 0.15°, 5700 δ at 0.01°, so a grazing ray 150 km long misses the exact
//! surface's hit point by more than 1 µm.
//!
//! # What
//!
//! For the hit triangle only (the traversal's choice of triangle is kept), its three vertices are recomputed in
//! double-double ([`crate::dd`]): the latitude `lat0 + i·dlat` and longitude `lon0 + j·dlon` as exact pairs,
//! `sin`/`cos` and the ECEF conversion to a few `ε²` relative. The hit parameter then comes from the triangle's
//! plane: `t = n·(v0 − o) / (n·d)`, with `v0 − o` and both dot products in pairs.
//!
//! The normal `n = (v1 − v0) × (v2 − v0)` is computed in plain scalars from the rounded edge vectors, and its
//! error does not matter: the plane used still passes *exactly* (to pair precision) through `v0`, and a
//! normal tilted by an angle of a few ε moves it, at the hit point, by a few ε times the distance from `v0` —
//! the size of the triangle (a grid cell), not the size of the Earth, which is what the vertices' own rounding
//! costs. Likewise a scalar `n·d` would lose `ε / sin ε` relatively at grazing incidence, which is why it is
//! formed in pairs too.
//!
//! The hit point `o + t·d` is formed in pairs from the pair `t` and rounded once per coordinate, so
//! [`super::Hit::ecef`] is the correctly rounded point of the refined plane (and may differ from
//! `ray.at(hit.t)` by the rounding of `t·d`).
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

use super::Grid;
use crate::dd::{Dd, Parallel, sin_cos_deg, two_prod};
use crate::geodesy::Ellipsoid;
use crate::ray::Ray;
use crate::real::Real;

/// The latitude of vertex row `i` as a pair: `lat0 + i·dlat` exactly (up to pair rounding), clamped to ±90° like
/// [`Grid::lat_deg`].
fn lat_dd<T: Real>(g: &Grid<T>, i: u32) -> Dd<T> {
    let lat = Dd::from(g.lat0).plus(two_prod(T::from_f64(f64::from(i)), g.dlat));
    let ninety = T::from_f64(90.0);
    if lat.hi > ninety || (lat.hi == ninety && lat.lo > T::ZERO) {
        Dd::from(ninety)
    } else if lat.hi < -ninety || (lat.hi == -ninety && lat.lo < T::ZERO) {
        Dd::from(-ninety)
    } else {
        lat
    }
}

/// The longitude of vertex column `j` as a pair: `lon0 + j·dlon`; the last column of a grid that spans 360°
/// (within 1e-9°) is exactly `lon0 + 360°`, so that the seam's two sides share their vertices exactly (a global
/// grid whose last column repeats the first).
fn lon_dd<T: Real>(g: &Grid<T>, j: u32) -> Dd<T> {
    let last = g.cols.saturating_sub(1);
    let full = T::from_f64(360.0);
    if j == last {
        let span = two_prod(T::from_f64(f64::from(last)), g.dlon).plus_t(-full);
        if span.value().abs() <= T::from_f64(1e-9) {
            return Dd::from(g.lon0).plus_t(full);
        }
    }
    Dd::from(g.lon0).plus(two_prod(T::from_f64(f64::from(j)), g.dlon))
}

/// Which triangle of a cell: [`Tri::First`] is `(V(i,j), V(i,j+1), V(i+1,j+1))`, [`Tri::Second`] is
/// `(V(i,j), V(i+1,j+1), V(i+1,j))` (the order of [`Grid`]'s contract and of the traversal's tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Tri {
    First,
    Second,
}

/// `a − b` rounded to scalars.
#[inline]
fn diff<T: Real>(a: &[Dd<T>; 3], b: &[Dd<T>; 3]) -> [T; 3] {
    let ([a0, a1, a2], [b0, b1, b2]) = (a, b);
    [
        a0.minus(*b0).value(),
        a1.minus(*b1).value(),
        a2.minus(*b2).value(),
    ]
}

/// The refined hit `(t, point)` of `ray` with triangle `tri` of cell `[i, j]` whose corner heights are
/// `[h(i,j), h(i,j+1), h(i+1,j+1), h(i+1,j)]` (module docs), or `None` when the guard rejects it; `t0` is the
/// traversal's hit parameter.
pub(super) fn refine<T: Real>(
    e: &Ellipsoid<T>,
    g: &Grid<T>,
    ray: &Ray<T>,
    t0: T,
    [i, j]: [u32; 2],
    tri: Tri,
    [h00, h01, h11, h10]: [T; 4],
) -> Option<(T, [T; 3])> {
    let (i1, j1) = (i.checked_add(1)?, j.checked_add(1)?);
    let (row0, row1) = (
        Parallel::new(e, lat_dd(g, i)),
        Parallel::new(e, lat_dd(g, i1)),
    );
    let ((sw, cw), (se, ce)) = (sin_cos_deg(lon_dd(g, j)), sin_cos_deg(lon_dd(g, j1)));
    let v00 = row0.ecef(sw, cw, h00);
    let v11 = row1.ecef(se, ce, h11);
    let (v1, v2) = match tri {
        Tri::First => (row0.ecef(se, ce, h01), v11),
        Tri::Second => (v11, row1.ecef(sw, cw, h10)),
    };
    let v0 = v00;
    // Edges rounded to scalars; the normal in scalars (module docs: its error tilts the plane about v0 only).
    let [a0, a1, a2] = diff(&v1, &v0);
    let [b0, b1, b2] = diff(&v2, &v0);
    let n = [a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0];
    let o = ray.origin().to_array();
    let d = ray.dir().to_array();
    let mut num = Dd::from(T::ZERO);
    let mut den = Dd::from(T::ZERO);
    for (((vk, ok), nk), dk) in v0.iter().zip(o).zip(n).zip(d) {
        num = num.plus(vk.plus_t(-ok).times_t(nk));
        den = den.plus(two_prod(nk, dk));
    }
    let t_dd = num.over(den);
    let t = t_dd.value();
    let [o0, o1, o2] = o;
    let [d0, d1, d2] = d;
    let at = |ok: T, dk: T| t_dd.times_t(dk).plus_t(ok).value();
    let p = [at(o0, d0), at(o1, d1), at(o2, d2)];
    // The guard (module docs).
    let finite = t.is_finite() && p.iter().all(|x| x.is_finite());
    if !(finite && ray.t_min() <= t && t <= ray.t_max()) {
        return None;
    }
    let max_abs = |[x, y, z]: [T; 3]| x.abs().max(y.abs()).max(z.abs());
    let [n0, n1, n2] = n;
    let n_len = (n0 * n0 + n1 * n1 + n2 * n2).sqrt();
    let moved = (t - t0).abs() * den.value().abs();
    let allowed = T::from_f64(256.0) * T::EPSILON * (max_abs(o) + max_abs(ray.at(t0))) * n_len;
    (moved <= allowed).then_some((t, p))
}
