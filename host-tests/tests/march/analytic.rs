//! Analytic validation of marching (Hannasch §6.1–6.2): projections through a ball of radius R = 1
//! computed from the kernel's crossings equal their closed forms to a relative error of 1e-12, in f64, with both
//! engines.
//!
//! * Constant density: the column is the chord `2√(R² − y² − z²)` for a ray along x at offsets (y, z).
//! * The step field χ₀.₅ of §6.1 (2 for r < 1/2, 1 for 1/2 ≤ r < 1): the column is `2√(R² − ρ²) + 2√(1/4 − ρ²)`
//!   (the second term when ρ < 1/2). On a grid with the breakpoint 1/2 the field is constant per cell and the
//!   projection sampler (value × length) applies as is. On grids whose breakpoints do not contain 1/2 (the
//!   paper's `2^k − 1` uniform ranges put 1/2 in the middle of a cell, plus a random non-uniform grid) each
//!   crossing's exact integral is summed: its length plus the length of its part inside r < 1/2.
//! * The field r² (remark after Fig. 6.14): the column is `(2/3)√(R² − ρ²)(R² + 2ρ²)`; each crossing contributes
//!   the exact integral of the polynomial `|p + t d|²` over `[t_enter, t_exit]`.

use curvicast::march::{CellCrossing, SphericalGrid};
use curvicast::ray::Ray;
use rand::{Rng, SeedableRng};
use std::f64::consts::{PI, TAU};

const TOL: f64 = curvicast_host::tolerances::MARCH_ANALYTIC_REL.bound;

use crate::support::uniform;

struct Grid {
    r: Vec<f64>,
    theta: Vec<f64>,
    phi: Vec<f64>,
}

impl Grid {
    fn paper(k: u32) -> Grid {
        // 2^k − 1 uniform radial ranges: 1/2 lies mid-cell
        let n = (1usize << k) - 1;
        Grid {
            r: uniform(n, 0.0, 1.0),
            theta: uniform(16, 0.0, PI),
            phi: uniform(32, 0.0, TAU),
        }
    }
    fn aligned() -> Grid {
        Grid {
            r: vec![0.0, 0.125, 0.3, 0.5, 0.55, 0.8, 0.9, 1.0],
            theta: vec![0.0, 0.3, 1.0, 1.2, 2.0, 2.9, PI],
            phi: vec![0.0, 0.4, 1.9, 3.0, 4.4, 5.0, TAU],
        }
    }
    fn random(seed: u64) -> Grid {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut r: Vec<f64> = (0..20).map(|_| rng.random_range(0.01..0.99)).collect();
        r.retain(|&x| (x - 0.5).abs() > 1e-3);
        r.push(0.0);
        r.push(1.0);
        r.sort_by(|a, b| a.total_cmp(b));
        let mut theta: Vec<f64> = (0..9).map(|_| rng.random_range(0.01..3.13)).collect();
        theta.extend([0.0, PI]);
        theta.sort_by(|a, b| a.total_cmp(b));
        let mut phi: Vec<f64> = (0..9).map(|_| rng.random_range(0.01..6.27)).collect();
        phi.extend([0.0, TAU]);
        phi.sort_by(|a, b| a.total_cmp(b));
        Grid { r, theta, phi }
    }

    /// The crossings of both engines (asserting that they agree).
    fn march(&self, origin: [f64; 3], dir: [f64; 3]) -> Vec<CellCrossing<f64>> {
        let mut ws =
            vec![
                0.0;
                SphericalGrid::<f64>::workspace_len(self.r.len(), self.theta.len(), self.phi.len())
            ];
        let grid = SphericalGrid::new(&self.r, &self.theta, &self.phi, &mut ws).unwrap();
        let ray = Ray::new(origin, dir).unwrap();
        let mut it = grid.march(&ray);
        let serial: Vec<_> = it.by_ref().collect();
        assert_eq!(it.error(), None);
        let separable: Vec<_> = grid.march_separable::<1024>(&ray).unwrap().collect();
        assert_eq!(serial, separable, "engines disagree");
        serial
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Length of the part of the segment `p + t d`, `t ∈ [a, b]`, inside the ball `r < rad` (times |d|).
fn inside_length(p: [f64; 3], d: [f64; 3], a: f64, b: f64, rad: f64) -> f64 {
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let pd = p[0] * d[0] + p[1] * d[1] + p[2] * d[2];
    let tc = -pd / dd;
    let q = [p[0] + tc * d[0], p[1] + tc * d[1], p[2] + tc * d[2]];
    let rho2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    if rho2 >= rad * rad {
        return 0.0;
    }
    let h = ((rad * rad - rho2) / dd).sqrt();
    let (lo, hi) = (a.max(tc - h), b.min(tc + h));
    if hi > lo { (hi - lo) * dd.sqrt() } else { 0.0 }
}

/// ∫ |p + t d|² ds over `t ∈ [a, b]` (s the arclength).
fn r2_integral(p: [f64; 3], d: [f64; 3], a: f64, b: f64) -> f64 {
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let pd = p[0] * d[0] + p[1] * d[1] + p[2] * d[2];
    let pp = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    // primitive of pp + 2 pd t + dd t² is pp t + pd t² + dd t³ / 3, evaluated around the closest approach
    let tc = -pd / dd;
    let rho2 = pp - pd * pd / dd;
    let f = |t: f64| {
        let u = t - tc;
        rho2.max(0.0) * u + dd * u * u * u / 3.0
    };
    (f(b) - f(a)) * dd.sqrt()
}

/// Rays along x at offsets (y, z) with y² + z² ≤ 0.98 (away from the limb, where the chord → 0), plus rays in
/// random directions through random offsets.
fn rays() -> Vec<([f64; 3], [f64; 3], f64)> {
    let mut out = Vec::new();
    for i in 0..21 {
        for j in 0..21 {
            let (y, z) = (-0.99 + 0.099 * i as f64, -0.99 + 0.099 * j as f64);
            let rho2: f64 = y * y + z * z;
            if rho2 <= 0.98 {
                // as in §6.1: from x = −R with direction 2R along x
                out.push(([-1.5, y, z], [2.0, 0.0, 0.0], rho2.sqrt()));
            }
        }
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    for _ in 0..200 {
        let u = loop {
            let v = [0; 3].map(|_| rng.random_range(-1.0..1.0));
            let n = norm(v);
            if n > 0.1 && n <= 1.0 {
                break v.map(|a| a / n);
            }
        };
        // an offset perpendicular to u
        let w = [u[1], -u[0], 0.0];
        let wn = norm(w);
        let off = rng.random_range(0.0..0.98f64).sqrt();
        let c = if wn > 1e-6 {
            w.map(|a| a / wn * off)
        } else {
            [off, 0.0, 0.0]
        };
        let origin = [0, 1, 2].map(|i| c[i] - 3.0 * u[i]);
        out.push((origin, u, off));
    }
    out
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn constant_density_ball_column_is_the_chord() {
    let mut worst: f64 = 0.0;
    for g in [Grid::paper(5), Grid::aligned(), Grid::random(1)] {
        for (p, d, rho) in rays() {
            let col: f64 = g
                .march(p, d)
                .iter()
                .map(|c| (c.t_exit - c.t_enter) * norm(d))
                .sum();
            let exact = 2.0 * (1.0 - rho * rho).sqrt();
            let e = rel(col, exact);
            worst = worst.max(e);
            assert!(
                e <= TOL,
                "column {col} vs chord {exact} (ρ = {rho}): rel {e:e}"
            );
        }
    }
    println!("constant density: max relative error {worst:e}");
}

fn chi_exact(rho: f64) -> f64 {
    2.0 * (1.0 - rho * rho).sqrt()
        + if rho < 0.5 {
            2.0 * (0.25 - rho * rho).sqrt()
        } else {
            0.0
        }
}

#[test]
fn step_field_chi_half_on_grid_with_breakpoint_at_the_jump() {
    // the jump at r = 1/2 is a breakpoint: χ is constant per cell, value × length is exact
    let g = Grid::aligned();
    let mut worst: f64 = 0.0;
    for (p, d, rho) in rays() {
        let col: f64 = g
            .march(p, d)
            .iter()
            .map(|c| {
                let v = if g.r[c.cell[0] as usize + 1] <= 0.5 {
                    2.0
                } else {
                    1.0
                };
                v * (c.t_exit - c.t_enter) * norm(d)
            })
            .sum();
        let e = rel(col, chi_exact(rho));
        worst = worst.max(e);
        assert!(
            e <= TOL,
            "χ column {col} vs {} (ρ = {rho}): rel {e:e}",
            chi_exact(rho)
        );
    }
    println!("χ0.5 aligned: max relative error {worst:e}");
}

#[test]
fn step_field_chi_half_on_grids_not_aligned_with_the_jump() {
    // 2^k − 1 uniform ranges (1/2 mid-cell, as in §6.1) and a random grid avoiding 1/2: per crossing, the exact
    // integral of χ over [t_enter, t_exit] (its length plus its length inside r < 1/2)
    let mut worst: f64 = 0.0;
    for g in [Grid::paper(4), Grid::paper(6), Grid::random(2)] {
        assert!(!g.r.contains(&0.5));
        for (p, d, rho) in rays() {
            let col: f64 = g
                .march(p, d)
                .iter()
                .map(|c| {
                    (c.t_exit - c.t_enter) * norm(d) + inside_length(p, d, c.t_enter, c.t_exit, 0.5)
                })
                .sum();
            let e = rel(col, chi_exact(rho));
            worst = worst.max(e);
            assert!(
                e <= TOL,
                "χ column {col} vs {} (ρ = {rho}): rel {e:e}",
                chi_exact(rho)
            );
        }
    }
    println!("χ0.5 unaligned: max relative error {worst:e}");
}

#[test]
fn field_r_squared_integrates_to_the_closed_form() {
    let mut worst: f64 = 0.0;
    for g in [Grid::paper(5), Grid::aligned(), Grid::random(3)] {
        for (p, d, rho) in rays() {
            let col: f64 = g
                .march(p, d)
                .iter()
                .map(|c| r2_integral(p, d, c.t_enter, c.t_exit))
                .sum();
            let a = (1.0 - rho * rho).sqrt();
            let exact = 2.0 / 3.0 * a * (1.0 + 2.0 * rho * rho);
            let e = rel(col, exact);
            worst = worst.max(e);
            assert!(
                e <= TOL,
                "r² column {col} vs {exact} (ρ = {rho}): rel {e:e}"
            );
        }
    }
    println!("r²: max relative error {worst:e}");
}
