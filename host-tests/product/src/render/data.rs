//! The real spherical data shipped in `host-tests/data/` (see its README), as fields on spherical grids:
//!
//! * the Levitus (World Ocean Atlas) annual temperature climatology, 20 non-uniform depth cells × 180 × 360 1°
//!   cells, NaN on land and below the sea floor, as a thin shell at the Earth's radius (meters);
//! * PREM (Dziewonski and Anderson 1981), the 1-D Earth model, as whole-Earth shells of P-wave speed (km, km/s),
//!   and the truth its travel times are held to: `∫ ds / v_p` by Gauss–Legendre quadrature of the piecewise-linear
//!   model along the straight ray, written apart from the renderer.

use super::field::SphericalCells;
use crate::formats::real_dem::{data_dir, decode_packed};
use std::f64::consts::{PI, TAU};

/// The Earth's radius used by both scenes, meters.
pub const EARTH_RADIUS_M: f64 = 6_371_000.0;

/// Depth cell edges of the Levitus levels, meters (from the data set's sidecar).
pub const LEVITUS_DEPTH_EDGES_M: [f64; 21] = [
    0.0, 5.0, 15.0, 25.0, 40.0, 62.5, 87.5, 125.0, 175.0, 250.0, 350.0, 500.0, 700.0, 900.0,
    1100.0, 1350.0, 1750.0, 2500.0, 3500.0, 4500.0, 5000.0,
];

/// The ocean temperature (°C) on its spherical grid: `r` = Earth radius − depth edges (increasing), θ from the
/// north pole in 1° steps (row 0 of the data is 90°N–89°N), φ east from 0° in 1° steps (the data's columns start
/// at 20°E and are rotated into place). NaN where there is no water.
pub fn ocean() -> anyhow::Result<(SphericalCells, Vec<f64>)> {
    let path = data_dir().join("levitus_temp/temp.dem.cc");
    let bytes = std::fs::read(&path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let packed = decode_packed(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let (nd, nt, np) = (20usize, 180usize, 360usize);
    let (rows, cols) = packed.shape;
    anyhow::ensure!(
        rows == nd * nt && cols == np,
        "{}: expected {}×{np} values, found {rows}×{cols}",
        path.display(),
        nd * nt
    );
    // Each depth level is a 1° grid of cell centres from 89.5°N, 20.5°E on a sphere of the Earth's radius.
    anyhow::ensure!(
        packed.axes == (EARTH_RADIUS_M, EARTH_RADIUS_M)
            && packed.georeference == (89.5, 20.5, -1.0, 1.0),
        "{}: the header's georeference differs from the documented one",
        path.display()
    );
    let t = packed.values;
    let grid = SphericalCells {
        center: [0.0; 3],
        r: LEVITUS_DEPTH_EDGES_M
            .iter()
            .rev()
            .map(|d| EARTH_RADIUS_M - d)
            .collect(),
        theta: (0..=nt)
            .map(|j| if j == nt { PI } else { (j as f64).to_radians() })
            .collect(),
        phi: (0..=np)
            .map(|k| {
                if k == np {
                    TAU
                } else {
                    (k as f64).to_radians()
                }
            })
            .collect(),
    };
    let mut values = Vec::with_capacity(nd * nt * np);
    for i in 0..nd {
        let depth = nd - 1 - i;
        for j in 0..nt {
            for k in 0..np {
                let col = (k + np - 20) % np;
                let v = t[(depth * nt + j) * np + col];
                values.push(f64::from(v));
            }
        }
    }
    Ok((grid, values))
}

/// PREM's P-wave speed as a function of radius: the model's rows by increasing depth, linear between rows, a
/// repeated depth marking a discontinuity.
#[derive(Debug, Clone, PartialEq)]
pub struct Prem {
    /// Radius of each row, km (decreasing).
    pub radius_km: Vec<f64>,
    /// P-wave speed at each row, km/s.
    pub vp: Vec<f64>,
}

/// Reads `host-tests/data/prem/prem.csv`.
pub fn prem() -> anyhow::Result<Prem> {
    let path = data_dir().join("prem/prem.csv");
    let text =
        std::fs::read_to_string(&path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let (mut radius_km, mut vp) = (Vec::new(), Vec::new());
    for (n, line) in text.lines().enumerate().skip(1) {
        let f: Vec<f64> = line
            .split(',')
            .map(str::parse)
            .collect::<Result<_, _>>()
            .map_err(|e| anyhow::anyhow!("{}: line {}: {e}", path.display(), n + 1))?;
        anyhow::ensure!(
            f.len() >= 2,
            "{}: line {}: too few columns",
            path.display(),
            n + 1
        );
        radius_km.push(EARTH_RADIUS_M / 1000.0 - f[0]);
        vp.push(f[1]);
    }
    Ok(Prem { radius_km, vp })
}

impl Prem {
    /// The model's linear pieces `(r_lo, r_hi, v at r_lo, v at r_hi)` by increasing radius (zero-thickness
    /// pieces at discontinuities left out).
    pub fn pieces(&self) -> Vec<(f64, f64, f64, f64)> {
        let mut out = Vec::new();
        for k in (1..self.radius_km.len()).rev() {
            let (r_lo, r_hi) = (self.radius_km[k], self.radius_km[k - 1]);
            if r_hi > r_lo {
                out.push((r_lo, r_hi, self.vp[k], self.vp[k - 1]));
            }
        }
        out
    }

    /// Whole-Earth shells: each linear piece cut into `split` equal shells, each holding its mean speed (exact
    /// for a linear piece); θ and φ in `n_theta` and `n_phi` equal cells.
    pub fn grid(&self, split: usize, n_theta: usize, n_phi: usize) -> (SphericalCells, Vec<f64>) {
        let mut r = vec![0.0];
        let mut shell_v = Vec::new();
        for (r_lo, r_hi, v_lo, v_hi) in self.pieces() {
            for s in 0..split {
                let a = s as f64 / split as f64;
                let b = (s + 1) as f64 / split as f64;
                let rb = if s + 1 == split {
                    r_hi
                } else {
                    r_lo + (r_hi - r_lo) * b
                };
                r.push(rb);
                shell_v.push(v_lo + (v_hi - v_lo) * (a + b) / 2.0);
            }
        }
        let grid = SphericalCells {
            center: [0.0; 3],
            r,
            theta: (0..=n_theta)
                .map(|j| PI * j as f64 / n_theta as f64)
                .collect(),
            phi: (0..=n_phi).map(|k| TAU * k as f64 / n_phi as f64).collect(),
        };
        let values = shell_v
            .iter()
            .flat_map(|&v| std::iter::repeat_n(v, n_theta * n_phi))
            .collect();
        (grid, values)
    }

    /// The travel time `∫ ds / v_p` (s) along a whole straight line at closest distance `rho_km` from the
    /// center: per linear piece, the arc length `s = √(r² − ρ²)` is the variable (smooth, no endpoint
    /// singularity), integrated by 8-point Gauss–Legendre on 16 sub-intervals, both halves of the chord.
    pub fn travel_time(&self, rho_km: f64) -> f64 {
        const X: [f64; 4] = [
            0.183_434_642_495_649_8,
            0.525_532_409_916_329,
            0.796_666_477_413_626_7,
            0.960_289_856_497_536_3,
        ];
        const W: [f64; 4] = [
            0.362_683_783_378_362,
            0.313_706_645_877_887_3,
            0.222_381_034_453_374_5,
            0.101_228_536_290_376_3,
        ];
        let mut total = 0.0;
        for (r_lo, r_hi, v_lo, v_hi) in self.pieces() {
            if r_hi <= rho_km {
                continue;
            }
            let lo = r_lo.max(rho_km);
            let (s0, s1) = (
                (lo * lo - rho_km * rho_km).max(0.0).sqrt(),
                (r_hi * r_hi - rho_km * rho_km).sqrt(),
            );
            let parts = 16;
            let h = (s1 - s0) / parts as f64;
            for p in 0..parts {
                let mid = s0 + h * (p as f64 + 0.5);
                for (x, w) in X.iter().zip(W) {
                    for s in [mid - x * h / 2.0, mid + x * h / 2.0] {
                        let r = (rho_km * rho_km + s * s).sqrt();
                        let v = v_lo + (v_hi - v_lo) * (r - r_lo) / (r_hi - r_lo);
                        total += w * h / 2.0 / v;
                    }
                }
            }
        }
        2.0 * total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prem_vertical_travel_time_matches_the_layer_sum() {
        let m = prem().unwrap();
        // through the center: ∫ dr / v over each linear piece is (Δr / Δv) ln(v_hi / v_lo)
        let exact: f64 = m
            .pieces()
            .iter()
            .map(|&(a, b, va, vb)| {
                if (vb - va).abs() < 1e-12 {
                    (b - a) / va
                } else {
                    (b - a) / (vb - va) * (vb / va).ln()
                }
            })
            .sum::<f64>()
            * 2.0;
        let q = m.travel_time(0.0);
        assert!((q - exact).abs() < 1e-9 * exact, "{q} {exact}");
        // the known PREM PKIKP time through the center is about 20 minutes
        assert!((1150.0..1250.0).contains(&q), "{q}");
    }

    #[test]
    fn ocean_has_water_and_land_and_plausible_temperatures() {
        let (g, v) = ocean().unwrap();
        assert_eq!(g.shape(), [20, 180, 360]);
        let finite: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
        assert_eq!(finite.len(), 718_725);
        assert!(finite.iter().all(|t| (-2.1..29.8).contains(t)));
        // the surface cell at 0.5°N, 150.5°W (central Pacific) is warm water; at 0.5°N, 20.5°E (Congo) land
        let surface = |lat_row: usize, lon: usize| v[(19 * 180 + lat_row) * 360 + lon];
        assert!(surface(89, 209) > 25.0, "{}", surface(89, 209));
        assert!(surface(89, 20).is_nan());
    }
}
