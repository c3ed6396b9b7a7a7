//! The rows' parallels and the columns' meridians in double-double (for the refinement of the nearest hit,
//! `refine.rs`; Wartell et al. §2's geodetic → ECEF conversion): a vertex row's latitude and a column's longitude as
//! exact pairs, their sines and cosines, and the latitude-dependent factors of the conversion.

use super::grid::Grid;
use crate::dd::{Dd, sin_cos_deg, two_prod};
use crate::geodesy::Ellipsoid;
use crate::real::Real;

/// The latitude of vertex row `i` as a pair: `lat0_deg + i·dlat_deg` exactly (up to pair rounding), clamped to ±90° like
/// [`Grid::lat_deg`].
fn lat_dd<T: Real>(g: &Grid<T>, i: u32) -> Dd<T> {
    let lat = Dd::from(g.lat0_deg).plus(two_prod(T::from_f64(f64::from(i)), g.dlat_deg));
    let ninety = T::from_f64(90.0);
    if lat.hi > ninety || (lat.hi == ninety && lat.lo > T::ZERO) {
        Dd::from(ninety)
    } else if lat.hi < -ninety || (lat.hi == -ninety && lat.lo < T::ZERO) {
        Dd::from(-ninety)
    } else {
        lat
    }
}

/// The longitude of vertex column `j` as a pair: `lon0_deg + j·dlon_deg`; the last column of a grid that spans 360°
/// (within 1e-9°) is exactly `lon0_deg + 360°`, so that the seam's two sides share their vertices exactly (a global
/// grid whose last column repeats the first).
fn lon_dd<T: Real>(g: &Grid<T>, j: u32) -> Dd<T> {
    let last = g.cols.saturating_sub(1);
    let full = T::from_f64(360.0);
    if j == last {
        let span = two_prod(T::from_f64(f64::from(last)), g.dlon_deg).plus_t(-full);
        if span.value().abs() <= T::from_f64(1e-9) {
            return Dd::from(g.lon0_deg).plus_t(full);
        }
    }
    Dd::from(g.lon0_deg).plus(two_prod(T::from_f64(f64::from(j)), g.dlon_deg))
}

/// The latitude-dependent factors of geodetic → ECEF for one parallel, in pairs (Wartell et al. §2):
/// `X = (N + h) cos φ cos λ`, `Y = (N + h) cos φ sin λ`, `Z = (N b²/a² + h) sin φ` with
/// `N = a²/D`, `N b²/a² = b²/D`, `D = √(a² cos²φ + b² sin²φ)` (the form without `e²`: every term is a sum of
/// positive quantities, so no digit is lost to cancellation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parallel<T> {
    /// `N cos φ`.
    pub n_cos: Dd<T>,
    /// `N (b²/a²) sin φ`.
    pub nb_sin: Dd<T>,
    /// `cos φ`.
    pub cos: Dd<T>,
    /// `sin φ`.
    pub sin: Dd<T>,
}

impl<T: Real> Parallel<T> {
    /// The parallel of geodetic latitude `lat_deg` (degrees, as a pair) on ellipsoid `e` (its axes `a`, `b` are
    /// taken as exact).
    pub fn new(e: &Ellipsoid<T>, lat_deg: Dd<T>) -> Self {
        let (sin, cos) = sin_cos_deg(lat_deg);
        Self::from_sin_cos(e, sin, cos)
    }

    /// The parallel whose latitude has sine `sin` and cosine `cos`.
    pub fn from_sin_cos(e: &Ellipsoid<T>, sin: Dd<T>, cos: Dd<T>) -> Self {
        let a2 = two_prod(e.a(), e.a());
        let b2 = two_prod(e.b(), e.b());
        let d2 = a2.times(cos.times(cos)).plus(b2.times(sin.times(sin)));
        let inv_d = Dd::one().over(d2.sqrt());
        Parallel {
            n_cos: a2.times(inv_d).times(cos),
            nb_sin: b2.times(inv_d).times(sin),
            cos,
            sin,
        }
    }

    /// ECEF of the point of this parallel at longitude `(sin λ, cos λ)` and height `h`.
    pub fn ecef(&self, sin_lon: Dd<T>, cos_lon: Dd<T>, h: T) -> [Dd<T>; 3] {
        let rho = self.n_cos.plus(self.cos.times_t(h));
        [
            rho.times(cos_lon),
            rho.times(sin_lon),
            self.nb_sin.plus(self.sin.times_t(h)),
        ]
    }
}

/// The parallel of vertex row `i` in pairs ([`TerrainCaches::row_parallel`](crate::terrain::TerrainCaches::row_parallel)): latitude `lat0_deg + i·dlat_deg` as an
/// exact pair, its sine and cosine and the ECEF factors to a few `ε²`.
pub fn row_parallel<T: Real>(e: &Ellipsoid<T>, g: &Grid<T>, i: u32) -> Parallel<T> {
    Parallel::new(e, lat_dd(g, i))
}

/// `(sin, cos)` of the longitude of vertex column `j` in pairs ([`TerrainCaches::col_sin_cos_dd`](crate::terrain::TerrainCaches::col_sin_cos_dd)).
pub fn col_sin_cos_dd<T: Real>(g: &Grid<T>, j: u32) -> (Dd<T>, Dd<T>) {
    sin_cos_deg(lon_dd(g, j))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ecef_of_the_parallels_matches_closed_forms() {
        let e = Ellipsoid::<f64>::wgs84();
        let (a, b) = (e.a(), e.b());
        let close = |x: Dd<f64>, y: f64, tol: f64| (x.value() - y).abs() <= tol;
        // Equator, lon 90°: (0, a + h, 0) exactly; pole: (0, 0, b + h).
        let (so, co) = sin_cos_deg(Dd::from(90.0));
        let p = Parallel::new(&e, Dd::from(0.0)).ecef(so, co, 10.0);
        assert_eq!(
            [p[0].value(), p[1].value(), p[2].value()],
            [0.0, a + 10.0, 0.0]
        );
        let (so, co) = sin_cos_deg(Dd::from(37.0));
        let p = Parallel::new(&e, Dd::from(-90.0)).ecef(so, co, -5.0);
        assert_eq!([p[0].value(), p[1].value()], [0.0, 0.0]);
        assert!(close(p[2], -(b - 5.0), 1e-9));
        // 45°: agrees with the f64 forward formula to its rounding, and the pair point lies on the ellipsoid
        // (x² + y²)/a² + z²/b² = 1 to ~1e-30.
        let lat = Dd::from(45.0);
        let (so, co) = sin_cos_deg(Dd::from(-71.5));
        let p = Parallel::new(&e, lat).ecef(so, co, 0.0);
        let q = e.geodetic_deg_to_ecef(45.0, -71.5, 0.0);
        assert!(close(p[0], q.x, 4e-9) && close(p[1], q.y, 4e-9) && close(p[2], q.z, 4e-9));
        let a2 = two_prod(a, a);
        let b2 = two_prod(b, b);
        let on = p[0]
            .times(p[0])
            .plus(p[1].times(p[1]))
            .over(a2)
            .plus(p[2].times(p[2]).over(b2));
        assert!(on.minus(Dd::one()).value().abs() < 1e-30, "{on:?}");
    }

    #[test]
    fn grid_angles_as_exact_pairs_and_the_closing_column() {
        // 1/3° spacing: 1080 columns span 360° only up to the rounding of 1/3; the last column is lon0_deg + 360°.
        let g = Grid {
            lat0_deg: 89.5,
            lon0_deg: 20.0 + 1.0 / 6.0,
            dlat_deg: -1.0 / 3.0,
            dlon_deg: 1.0 / 3.0,
            rows: 540,
            cols: 1081,
        };
        let last = lon_dd(&g, 1080);
        assert_eq!(last, Dd::from(g.lon0_deg).plus_t(360.0));
        // Other columns: lon0_deg + j·dlon_deg exactly (the product's rounding error is kept in the low part).
        let l7 = lon_dd(&g, 7);
        let exact = two_prod(7.0, 1.0 / 3.0);
        assert_eq!(l7.minus(Dd::from(g.lon0_deg)).minus(exact).value(), 0.0);
        assert!(l7.lo != 0.0);
        // Rows clamp at the poles like `Grid::lat_deg`.
        let g = Grid {
            lat0_deg: 80.0,
            dlat_deg: 10.000_000_000_000_002,
            ..g
        };
        assert_eq!(lat_dd(&g, 1), Dd::from(90.0));
        assert_eq!(lat_dd(&g, 0), Dd::from(80.0));
    }
}
