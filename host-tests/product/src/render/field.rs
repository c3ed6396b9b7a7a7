//! Fields on curved grids for `curvicast render`: the grid's breakpoints (spherical, cylindrical or polar) and one
//! value per cell, the analytic fields of Hannasch §6.1 as exact cell averages (closed forms in the cell's radii),
//! the closed-form truths of their projections (§6.1 and the remark of §6.3), and the coarser spherical grids of
//! §6.3 that discard every other breakpoint.
//!
//! On a cylindrical or polar grid (§3.3, §3.4) the analytic fields depend on the distance from the grid's axis
//! (ρ, or the polar r; a polar grid is a prism unbounded in z), so a cell's exact average weighs its radii by the
//! area element `ρ dρ`, and the projection along a line perpendicular to the axis is the same closed form of the
//! line's distance from the axis as the spherical one of its distance from the center.

/// A spherical grid (physics convention, as in the command-line contract): breakpoints in r, θ (zenith) and φ
/// (azimuth), around `center`. Cell `[i, j, k]` has the flat index `(i · nθ + j) · nφ + k`.
#[derive(Debug, Clone, PartialEq)]
pub struct SphericalCells {
    /// The center.
    pub center: [f64; 3],
    /// Radius breakpoints.
    pub r: Vec<f64>,
    /// Zenith breakpoints.
    pub theta: Vec<f64>,
    /// Azimuth breakpoints.
    pub phi: Vec<f64>,
}

impl SphericalCells {
    /// Cells along `[r, θ, φ]`.
    pub fn shape(&self) -> [usize; 3] {
        [
            self.r.len().saturating_sub(1),
            self.theta.len().saturating_sub(1),
            self.phi.len().saturating_sub(1),
        ]
    }

    /// The number of cells.
    pub fn cell_count(&self) -> usize {
        self.shape().iter().product()
    }

    /// The flat index of cell `[i, j, k]`, or `None` outside the shape.
    pub fn flat(&self, cell: [u32; 3]) -> Option<usize> {
        let [nr, nt, np] = self.shape();
        let [i, j, k] = cell.map(|c| c as usize);
        (i < nr && j < nt && k < np).then_some((i * nt + j) * np + k)
    }

    /// The outer radius.
    pub fn outer_radius(&self) -> f64 {
        self.r.last().copied().unwrap_or(0.0)
    }

    /// The volume of cell `[i, j, k]` (flat order), up to the common factor 1/3:
    /// `(r₁³ − r₀³)(cos θ₀ − cos θ₁)(φ₁ − φ₀)`.
    fn volume(&self, i: usize, j: usize, k: usize) -> f64 {
        cube_difference(self.r[i], self.r[i + 1])
            * (self.theta[j].cos() - self.theta[j + 1].cos())
            * (self.phi[k + 1] - self.phi[k])
    }

    /// The grid of Hannasch §6.3's ladder one level coarser: every other breakpoint discarded along each axis
    /// (the first and, when their count is odd, the last are kept; an axis of one cell stays), and each coarse
    /// cell's value the volume-weighted mean of the finite values of the fine cells it covers (NaN when it covers
    /// none). For the analytic fields this is again the exact cell average.
    pub fn coarsen(&self, values: &[f64]) -> (SphericalCells, Vec<f64>) {
        let keep = |v: &[f64]| -> Vec<usize> {
            if v.len() <= 2 {
                return (0..v.len()).collect();
            }
            let mut idx: Vec<usize> = (0..v.len()).step_by(2).collect();
            if idx.last() != Some(&(v.len() - 1)) {
                idx.push(v.len() - 1);
            }
            idx
        };
        let (kr, kt, kp) = (keep(&self.r), keep(&self.theta), keep(&self.phi));
        let coarse = SphericalCells {
            center: self.center,
            r: kr.iter().map(|&i| self.r[i]).collect(),
            theta: kt.iter().map(|&i| self.theta[i]).collect(),
            phi: kp.iter().map(|&i| self.phi[i]).collect(),
        };
        let [_, nt, np] = self.shape();
        let mut out = Vec::with_capacity(coarse.cell_count());
        for ir in kr.windows(2) {
            for it in kt.windows(2) {
                for ip in kp.windows(2) {
                    let (mut sum, mut vol) = (0.0, 0.0);
                    for i in ir[0]..ir[1] {
                        for j in it[0]..it[1] {
                            for k in ip[0]..ip[1] {
                                let v = values[(i * nt + j) * np + k];
                                if v.is_finite() {
                                    let w = self.volume(i, j, k);
                                    sum += v * w;
                                    vol += w;
                                }
                            }
                        }
                    }
                    out.push(if vol > 0.0 { sum / vol } else { f64::NAN });
                }
            }
        }
        (coarse, out)
    }
}

/// A cylindrical grid (Hannasch §3.3): breakpoints in ρ (distance from the axis), φ (azimuth) and z (height
/// relative to `center[2]`). Cell `[i, k, m]` has the flat index `(i · nφ + k) · nz + m`.
#[derive(Debug, Clone, PartialEq)]
pub struct CylindricalCells {
    /// A point of the axis (the axis is parallel to z).
    pub center: [f64; 3],
    /// Radius breakpoints.
    pub rho: Vec<f64>,
    /// Azimuth breakpoints.
    pub phi: Vec<f64>,
    /// Height breakpoints.
    pub z: Vec<f64>,
}

/// A 2-D polar grid (Hannasch §3.4): breakpoints in r and φ around `center` in the xy plane; the rays' z
/// components are ignored, so its cells are prisms unbounded in z. Cell `[i, k]` (the kernel's `[i, k, 0]`) has
/// the flat index `i · nφ + k`.
#[derive(Debug, Clone, PartialEq)]
pub struct PolarCells {
    /// The center `(x, y)`.
    pub center: [f64; 2],
    /// Radius breakpoints.
    pub r: Vec<f64>,
    /// Azimuth breakpoints.
    pub phi: Vec<f64>,
}

/// The grid of a render: one of the three kinds of the command-line contract's GRID.json.
#[derive(Debug, Clone, PartialEq)]
pub enum Cells {
    /// Spherical (r, θ, φ).
    Spherical(SphericalCells),
    /// Cylindrical (ρ, φ, z).
    Cylindrical(CylindricalCells),
    /// Polar (r, φ).
    Polar(PolarCells),
}

impl From<SphericalCells> for Cells {
    fn from(g: SphericalCells) -> Cells {
        Cells::Spherical(g)
    }
}

impl Cells {
    /// Cells along each axis in the kernel's index order (a polar grid has one cell along the third).
    pub fn shape(&self) -> [usize; 3] {
        let n = |v: &Vec<f64>| v.len().saturating_sub(1);
        match self {
            Cells::Spherical(g) => g.shape(),
            Cells::Cylindrical(g) => [n(&g.rho), n(&g.phi), n(&g.z)],
            Cells::Polar(g) => [n(&g.r), n(&g.phi), 1],
        }
    }

    /// The shape as the grid file's kind has it (two counts for a polar grid), for `render.json`.
    pub fn dims(&self) -> Vec<usize> {
        let s = self.shape();
        match self {
            Cells::Polar(_) => s[..2].to_vec(),
            _ => s.to_vec(),
        }
    }

    /// `"spherical"`, `"cylindrical"` or `"polar"`.
    pub fn kind(&self) -> &'static str {
        match self {
            Cells::Spherical(_) => "spherical",
            Cells::Cylindrical(_) => "cylindrical",
            Cells::Polar(_) => "polar",
        }
    }

    /// The number of cells.
    pub fn cell_count(&self) -> usize {
        self.shape().iter().product()
    }

    /// The flat index (row-major, last index fastest) of the kernel's cell index, or `None` outside the shape.
    pub fn flat(&self, cell: [u32; 3]) -> Option<usize> {
        let [a, b, c] = self.shape();
        let [i, j, k] = cell.map(|x| x as usize);
        (i < a && j < b && k < c).then_some((i * b + j) * c + k)
    }

    /// The radial breakpoints: r (spherical, polar) or ρ (cylindrical).
    pub fn radial(&self) -> &[f64] {
        match self {
            Cells::Spherical(g) => &g.r,
            Cells::Cylindrical(g) => &g.rho,
            Cells::Polar(g) => &g.r,
        }
    }

    /// The outer radius.
    pub fn outer_radius(&self) -> f64 {
        self.radial().last().copied().unwrap_or(0.0)
    }

    /// The radial thickness of the domain, `r_max − r_min`.
    pub fn thickness(&self) -> f64 {
        self.outer_radius() - self.radial().first().copied().unwrap_or(0.0)
    }
}

/// `b³ − a³` without cancellation: `(b − a)(b² + ab + a²)`.
fn cube_difference(a: f64, b: f64) -> f64 {
    (b - a) * (b * b + a * b + a * a)
}

/// `b² − a²` without cancellation: `(b − a)(b + a)`.
fn square_difference(a: f64, b: f64) -> f64 {
    (b - a) * (b + a)
}

/// `b⁵ − a⁵` without cancellation.
fn fifth_difference(a: f64, b: f64) -> f64 {
    let (a2, b2) = (a * a, b * b);
    (b - a) * (b2 * b2 + b2 * b * a + b2 * a2 + b * a2 * a + a2 * a2)
}

/// The analytic fields of Hannasch §6.1; each depends on the distance r from the grid's center only (on a
/// cylindrical or polar grid: the distance ρ from its axis), and is 0 beyond its radius `R` and outside the grid's
/// domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Analytic {
    /// Constant density 1 for r ≤ R (R defaults to the grid's outer radius): the projection is the chord
    /// `2√(R² − ρ²)` at closest distance ρ (§6.1).
    Ball,
    /// The step function: 1 for r ≤ R, 0 beyond (R defaults to half the grid's outer radius, the step of §6.1's
    /// χ₀.₅); the projection is the chord inside R.
    Step,
    /// r² for r ≤ R (R defaults to the grid's outer radius): the projection is `(2/3)√(R² − ρ²)(R² + 2ρ²)`
    /// (remark in §6.3).
    R2,
}

impl Analytic {
    /// The radius used when the scene gives none.
    pub fn default_radius(self, outer: f64) -> f64 {
        match self {
            Analytic::Ball | Analytic::R2 => outer,
            Analytic::Step => outer / 2.0,
        }
    }

    /// The exact average of the field over each cell of `grid` (flat order): the angular factors cancel, so it
    /// is `∫ f(r) r² dr / ∫ r² dr` over the cell's radii, clipped at `radius`.
    pub fn cell_averages(self, grid: &SphericalCells, radius: f64) -> Vec<f64> {
        let [_, nt, np] = grid.shape();
        let mut out = Vec::with_capacity(grid.cell_count());
        for w in grid.r.windows(2) {
            let (r0, r1) = (w[0], w[1]);
            let m = radius.clamp(r0, r1);
            let avg = match self {
                Analytic::Ball | Analytic::Step => cube_difference(r0, m) / cube_difference(r0, r1),
                Analytic::R2 => 0.6 * fifth_difference(r0, m) / cube_difference(r0, r1),
            };
            out.extend(std::iter::repeat_n(avg, nt * np));
        }
        out
    }

    /// The exact average of the field over each cell of `grid` (flat order). Spherical: as
    /// [`Analytic::cell_averages`]. Cylindrical and polar: the field is a function of the distance ρ from the
    /// axis, and the angular and height factors cancel, so the average is `∫ f(ρ) ρ dρ / ∫ ρ dρ` over the cell's
    /// radii, clipped at `radius`.
    pub fn averages(self, grid: &Cells, radius: f64) -> Vec<f64> {
        if let Cells::Spherical(g) = grid {
            return self.cell_averages(g, radius);
        }
        let [_, b, c] = grid.shape();
        let mut out = Vec::with_capacity(grid.cell_count());
        for w in grid.radial().windows(2) {
            let (r0, r1) = (w[0], w[1]);
            let m = radius.clamp(r0, r1);
            let area = square_difference(r0, r1);
            let avg = match self {
                Analytic::Ball | Analytic::Step => square_difference(r0, m) / area,
                Analytic::R2 => 0.5 * square_difference(r0, m) * (m * m + r0 * r0) / area,
            };
            out.extend(std::iter::repeat_n(avg, b * c));
        }
        out
    }

    /// The exact projection `∫ f ds` along a whole line at closest distance `rho` from the center, for a field of
    /// radius `radius` (the grid must cover the ball of that radius).
    pub fn projection(self, radius: f64, rho: f64) -> f64 {
        let h2 = radius * radius - rho * rho;
        if h2 <= 0.0 {
            return 0.0;
        }
        match self {
            Analytic::Ball | Analytic::Step => 2.0 * h2.sqrt(),
            Analytic::R2 => 2.0 / 3.0 * h2.sqrt() * (radius * radius + 2.0 * rho * rho),
        }
    }
}

/// The distance from `center` to the line `origin + t dir` (`dir` unit length).
pub fn closest_distance(center: [f64; 3], origin: [f64; 3], dir: [f64; 3]) -> f64 {
    let p = [0, 1, 2].map(|k| origin[k] - center[k]);
    let c = [
        p[1] * dir[2] - p[2] * dir[1],
        p[2] * dir[0] - p[0] * dir[2],
        p[0] * dir[1] - p[1] * dir[0],
    ];
    (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    fn grid(n: usize) -> SphericalCells {
        let u = |hi: f64| {
            (0..=n)
                .map(|i| hi * i as f64 / n as f64)
                .collect::<Vec<_>>()
        };
        SphericalCells {
            center: [0.0; 3],
            r: u(1.0),
            theta: u(PI),
            phi: u(TAU),
        }
    }

    #[test]
    fn r2_cell_average_matches_midpoint_quadrature() {
        let g = grid(4);
        let avg = Analytic::R2.cell_averages(&g, 1.0);
        // cell i = 2: r in [0.5, 0.75]
        let (a, b) = (0.5_f64, 0.75_f64);
        let m = 100_000;
        let (mut num, mut den) = (0.0, 0.0);
        for s in 0..m {
            let r = a + (b - a) * (s as f64 + 0.5) / m as f64;
            num += r.powi(4);
            den += r * r;
        }
        assert!((avg[2 * 16] - num / den).abs() < 1e-9, "{}", avg[32]);
    }

    #[test]
    fn step_cell_straddling_the_radius_holds_its_volume_fraction() {
        let g = grid(4);
        let avg = Analytic::Step.cell_averages(&g, 0.6);
        let want = (0.6f64.powi(3) - 0.125) / (0.421875 - 0.125);
        assert!((avg[2 * 16] - want).abs() < 1e-15);
        assert_eq!(avg[3 * 16], 0.0);
        assert_eq!(avg[0], 1.0);
    }

    #[test]
    fn cylindrical_and_polar_averages_weigh_by_area_and_match_midpoint_quadrature() {
        let cyl = Cells::Cylindrical(CylindricalCells {
            center: [0.0; 3],
            rho: vec![0.0, 0.5, 0.75, 1.0],
            phi: vec![0.0, 1.0, TAU],
            z: vec![-1.0, 0.0, 2.0, 3.0],
        });
        assert_eq!(cyl.shape(), [3, 2, 3]);
        let r2 = Analytic::R2.averages(&cyl, 0.9);
        let step = Analytic::Step.averages(&cyl, 0.6);
        assert_eq!(r2.len(), 18);
        // cell i = 1: ρ in [0.5, 0.75]; r² average by midpoint quadrature of ∫ ρ³ dρ / ∫ ρ dρ
        let (a, b, m) = (0.5_f64, 0.75_f64, 100_000);
        let (mut num, mut den) = (0.0, 0.0);
        for s in 0..m {
            let r = a + (b - a) * (s as f64 + 0.5) / m as f64;
            num += r.powi(3);
            den += r;
        }
        assert!((r2[6] - num / den).abs() < 1e-9, "{}", r2[6]);
        assert!(r2[6..12].iter().all(|&v| v == r2[6]));
        // clipped at R = 0.9 in the outer cell: ∫ from 0.75 to 0.9 of ρ³ over the cell's ∫ ρ dρ
        let want = (0.9f64.powi(4) - 0.75f64.powi(4)) / 4.0 / ((1.0 - 0.5625) / 2.0);
        assert!((r2[12] - want).abs() < 1e-15);
        // the step straddling ρ = 0.6 holds its area fraction
        assert!((step[6] - (0.36 - 0.25) / (0.5625 - 0.25)).abs() < 1e-15);
        assert_eq!((step[0], step[12]), (1.0, 0.0));
        let polar = Cells::Polar(PolarCells {
            center: [0.0; 2],
            r: vec![0.5, 0.75],
            phi: vec![0.0, 1.0, 2.0],
        });
        assert_eq!(polar.dims(), vec![1, 2]);
        assert_eq!(polar.flat([0, 1, 0]), Some(1));
        assert_eq!(polar.flat([0, 1, 1]), None);
        assert_eq!(Analytic::R2.averages(&polar, 1.0), vec![r2[6]; 2]);
    }

    #[test]
    fn coarsening_exact_averages_gives_the_coarse_exact_averages() {
        let fine = grid(8);
        let v = Analytic::R2.cell_averages(&fine, 1.0);
        let (coarse, cv) = fine.coarsen(&v);
        assert_eq!(coarse.shape(), [4, 4, 4]);
        let exact = Analytic::R2.cell_averages(&coarse, 1.0);
        for (a, b) in cv.iter().zip(&exact) {
            assert!((a - b).abs() < 1e-14, "{a} {b}");
        }
    }

    #[test]
    fn coarsening_skips_empty_cells_and_keeps_both_ends() {
        let g = SphericalCells {
            center: [0.0; 3],
            r: vec![1.0, 2.0, 3.0, 4.0],
            theta: vec![0.0, PI],
            phi: vec![0.0, TAU],
        };
        let (c, v) = g.coarsen(&[f64::NAN, 5.0, f64::NAN]);
        assert_eq!(c.r, vec![1.0, 3.0, 4.0]);
        assert!((v[0] - 5.0).abs() < 1e-14);
        assert!(v[1].is_nan());
    }
}
