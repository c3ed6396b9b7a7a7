//! The marching scene of the report, the `march` criterion bench and the `march_count` example (Hannasch ch. 5–6:
//! the cost of a crossing): a 64³ spherical grid in three forms — uniform over the unit ball, random (seeded)
//! non-uniform breakpoints, and a partial domain (shell, zenith band and wedge) — seen by `m²` parallel rays along
//! (1, 0.15, 0.1) covering the ball, or by an `m²` perspective camera at distance 3R.
//!
//! Written once so that the three places measure the same rays through the same grids, bit for bit.

use curvicast::march::{GridError, SphericalGrid};
use curvicast::ray::{Ray, RayError};
use curvicast::real::Real;
use curvicast_cli::formats::spec::{GridSpec, RaySpec};
use rand::{Rng, SeedableRng};
use std::f64::consts::{PI, TAU};

/// Cells along each axis.
pub const CELLS: usize = 64;

/// The seed of the non-uniform grid's breakpoints.
const NONUNIFORM_SEED: u64 = 16;

/// The three grids of the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridLayout {
    /// Uniform in r ∈ [0, 1], θ ∈ [0, π], φ ∈ [0, 2π].
    Uniform,
    /// The same ranges with random (seeded) cell widths between 0.25 and 1.75 times the mean.
    NonUniform,
    /// Uniform over a partial domain: the shell r ∈ [0.3, 1], the zenith band θ ∈ [0.4, 2.6], the wedge
    /// φ ∈ [−1, 4].
    Partial,
}

impl GridLayout {
    /// Every grid of the scene.
    pub const ALL: [GridLayout; 3] = [
        GridLayout::Uniform,
        GridLayout::NonUniform,
        GridLayout::Partial,
    ];

    /// The grid's name on command lines and in benchmark ids: `uniform`, `nonuniform`, `partial`.
    pub fn name(self) -> &'static str {
        match self {
            GridLayout::Uniform => "uniform",
            GridLayout::NonUniform => "nonuniform",
            GridLayout::Partial => "partial",
        }
    }

    /// The grid of that [`name`](Self::name).
    pub fn from_name(name: &str) -> Option<GridLayout> {
        GridLayout::ALL.into_iter().find(|k| k.name() == name)
    }

    /// What the grid is, in words (for the report).
    pub fn describe(self) -> &'static str {
        match self {
            GridLayout::Uniform => "uniform",
            GridLayout::NonUniform => "random non-uniform breakpoints",
            GridLayout::Partial => "partial (shell, zenith band, wedge)",
        }
    }

    /// True when the φ breakpoints span a full turn.
    pub fn full_turn(self) -> bool {
        self != GridLayout::Partial
    }

    /// The breakpoints `[r, θ, φ]` in `f64`.
    pub fn breakpoints(self) -> [Vec<f64>; 3] {
        match self {
            GridLayout::Uniform => [
                uniform(CELLS, 0.0, 1.0),
                uniform(CELLS, 0.0, PI),
                uniform(CELLS, 0.0, TAU),
            ],
            GridLayout::NonUniform => {
                let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(NONUNIFORM_SEED);
                [
                    random(CELLS, 0.0, 1.0, &mut rng),
                    random(CELLS, 0.0, PI, &mut rng),
                    random(CELLS, 0.0, TAU, &mut rng),
                ]
            }
            GridLayout::Partial => [
                uniform(CELLS, 0.3, 1.0),
                uniform(CELLS, 0.4, 2.6),
                uniform(CELLS, -1.0, 4.0),
            ],
        }
    }

    /// The grid as a GRID.json object (centred at the origin), for the oracle.
    pub fn spec(self) -> GridSpec {
        let [r, theta, phi] = self.breakpoints();
        GridSpec::Spherical {
            center: None,
            r,
            theta,
            phi,
        }
    }
}

/// The breakpoints of one grid converted to `T`, with the workspace the kernel's grid needs; a full turn ends at
/// `T`'s own 2π.
#[derive(Debug, Clone)]
pub struct Breakpoints<T> {
    /// Radius breakpoints.
    pub r: Vec<T>,
    /// Zenith breakpoints.
    pub theta: Vec<T>,
    /// Azimuth breakpoints.
    pub phi: Vec<T>,
    workspace: Vec<T>,
}

impl<T: Real> Breakpoints<T> {
    /// The breakpoints of `kind` in `T`.
    pub fn new(kind: GridLayout) -> Breakpoints<T> {
        let conv = |v: Vec<f64>| v.into_iter().map(T::from_f64).collect::<Vec<T>>();
        let [r, theta, phi] = kind.breakpoints();
        let (r, theta, mut phi) = (conv(r), conv(theta), conv(phi));
        if kind.full_turn() {
            if let Some(last) = phi.last_mut() {
                *last = T::PI + T::PI;
            }
        }
        let workspace =
            vec![T::ZERO; SphericalGrid::<T>::workspace_len(r.len(), theta.len(), phi.len())];
        Breakpoints {
            r,
            theta,
            phi,
            workspace,
        }
    }

    /// The kernel's grid over these breakpoints.
    pub fn grid(&mut self) -> Result<SphericalGrid<'_, T>, GridError> {
        SphericalGrid::new(&self.r, &self.theta, &self.phi, &mut self.workspace)
    }
}

/// `n` equal cells from `lo` to `hi`.
fn uniform(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect()
}

/// `n` cells from `lo` to `hi` with random widths between 0.25 and 1.75 times the mean.
fn random(n: usize, lo: f64, hi: f64, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<f64> {
    let w: Vec<f64> = (0..n).map(|_| rng.random_range(0.25..1.75)).collect();
    let total: f64 = w.iter().sum();
    let mut out = vec![lo];
    let mut acc = 0.0;
    for x in w.iter().take(n.saturating_sub(1)) {
        acc += x;
        out.push(lo + (hi - lo) * acc / total);
    }
    out.push(hi);
    out
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|a| a / n)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `m²` parallel rays along (1, 0.15, 0.1) (unit length), their origins on a square of side 2.1 across the ball,
/// 3 units back along the direction.
pub fn parallel_rays(m: usize) -> Vec<RaySpec> {
    let d = normalize([1.0, 0.15, 0.1]);
    // an orthonormal frame (u, v) perpendicular to d
    let u = {
        let w = [-d[1], d[0], 0.0];
        let l = (w[0] * w[0] + w[1] * w[1]).sqrt();
        w.map(|a| a / l)
    };
    let v = cross(d, u);
    let mut out = Vec::with_capacity(m * m);
    for i in 0..m {
        for j in 0..m {
            let a = -1.05 + 2.1 * (i as f64 + 0.5) / m as f64;
            let b = -1.05 + 2.1 * (j as f64 + 0.5) / m as f64;
            let o = [0, 1, 2].map(|k| a * u[k] + b * v[k] - 3.0 * d[k]);
            out.push(RaySpec::new(o, d));
        }
    }
    out
}

/// `m²` rays of a perspective camera at distance 3R, slightly off the axes, looking at the center; the field of
/// view just covers the ball.
pub fn perspective_rays(m: usize) -> Vec<RaySpec> {
    let eye = normalize([0.3, -3.0 * 0.98, 0.45]).map(|a| a * 3.0);
    let fwd = eye.map(|a| -a / 3.0);
    let right = {
        let w = [fwd[1], -fwd[0], 0.0];
        let l = (w[0] * w[0] + w[1] * w[1]).sqrt();
        w.map(|a| a / l)
    };
    let up = cross(right, fwd);
    let half = (1.0f64 / 3.0).asin().tan() * 1.05;
    let mut out = Vec::with_capacity(m * m);
    for i in 0..m {
        for j in 0..m {
            let a = half * (-1.0 + 2.0 * (i as f64 + 0.5) / m as f64);
            let b = half * (-1.0 + 2.0 * (j as f64 + 0.5) / m as f64);
            let d = [0, 1, 2].map(|k| fwd[k] + a * right[k] + b * up[k]);
            out.push(RaySpec::new(eye, d));
        }
    }
    out
}

/// The kernel's rays in `T` (interval `[0, ∞)`).
pub fn rays_in<T: Real>(rays: &[RaySpec]) -> Result<Vec<Ray<T>>, RayError> {
    rays.iter()
        .map(|s| Ray::new(s.origin.map(T::from_f64), s.dir.map(T::from_f64)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_parallel_scene_crosses_the_known_number_of_cells() {
        let mut b = Breakpoints::<f64>::new(GridLayout::Uniform);
        let grid = b.grid().unwrap();
        let rays = rays_in::<f64>(&parallel_rays(64)).unwrap();
        let n: usize = rays.iter().map(|r| grid.march(r).count()).sum();
        // the figure docs/performance.md's instruction counts are divided by
        assert_eq!(n, 222_784);
    }

    #[test]
    fn every_grid_is_valid_and_spans_its_range() {
        for kind in GridLayout::ALL {
            assert_eq!(GridLayout::from_name(kind.name()), Some(kind));
            let [r, th, ph] = kind.breakpoints();
            assert!([&r, &th, &ph].iter().all(|v| v.len() == CELLS + 1));
            assert!(
                r.windows(2)
                    .chain(th.windows(2))
                    .chain(ph.windows(2))
                    .all(|w| w[0] < w[1])
            );
            let mut b32 = Breakpoints::<f32>::new(kind);
            assert!(b32.grid().is_ok(), "{kind:?}");
            assert_eq!(b32.grid().unwrap().azimuth_is_full_turn(), kind.full_turn());
        }
        let [r, _, ph] = GridLayout::NonUniform.breakpoints();
        let widths: Vec<f64> = r.windows(2).map(|w| w[1] - w[0]).collect();
        let (lo, hi) = widths
            .iter()
            .fold((1.0f64, 0.0f64), |(a, b), &w| (a.min(w), b.max(w)));
        assert!(hi > 2.0 * lo, "random widths vary: {lo} {hi}");
        assert_eq!((r[CELLS], ph[CELLS]), (1.0, TAU));
    }

    #[test]
    fn perspective_rays_start_at_3r_and_look_at_the_ball() {
        let rays = perspective_rays(8);
        for s in &rays {
            let e = s.origin;
            assert!(((e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt() - 3.0).abs() < 1e-12);
        }
        let mut b = Breakpoints::<f64>::new(GridLayout::Uniform);
        let grid = b.grid().unwrap();
        let hits = rays_in::<f64>(&rays)
            .unwrap()
            .iter()
            .filter(|r| grid.march(r).next().is_some())
            .count();
        assert!(hits > 32 && hits < 64, "{hits}");
    }
}
