//! Grids and rays for testing the marchers (Hannasch, ch. 3 and 5) against the oracle: random
//! non-uniform full and partial grids with rays aimed at them and one generator per named hard case, as
//! [`GridSpec`]s and [`RaySpec`]s (data only: [`crate::march_run`] feeds them to the kernel's engines).
//!
//! Exact ties need exact inputs: the named cases use dyadic breakpoints and rays whose tie points are
//! representable (a corner at `(R, 0, 0)` with `R` dyadic, an axis crossing at `t = 1` of `(−a, −b, z) + t (a, b,
//! dz)`), so the oracle sees a true tie, not two crossings a rounding apart.

use curvicast_cli::formats::spec::{GridSpec, RaySpec};
use rand::Rng;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// A named hard case: one grid and the rays that exercise it.
#[derive(Debug, Clone)]
pub struct Case {
    /// What the geometry is.
    pub name: &'static str,
    /// The grid.
    pub grid: GridSpec,
    /// The rays.
    pub rays: Vec<RaySpec>,
}

// ---------------------------------------------------------------------------------------------------------------
// random grids and rays

fn sorted_uniform(rng: &mut impl Rng, n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let mut v: Vec<f64> = (0..n).map(|_| rng.random_range(lo..hi)).collect();
    v.sort_by(|a, b| a.total_cmp(b));
    v.dedup();
    v
}

/// Breakpoints `lo = b_0 < … < b_n = hi` with `n − 1` random interior values.
fn breakpoints(rng: &mut impl Rng, lo: f64, hi: f64, max_interior: usize) -> Vec<f64> {
    let n = rng.random_range(0..=max_interior);
    let mut v = vec![lo];
    let margin = (hi - lo) * 1e-3;
    v.extend(
        sorted_uniform(rng, n, lo + margin, hi - margin)
            .into_iter()
            .filter(|&x| x > lo && x < hi),
    );
    v.push(hi);
    v.dedup();
    v
}

fn random_azimuth(rng: &mut impl Rng) -> Vec<f64> {
    if rng.random_bool(0.45) {
        // full circle: φ_0 + 2π must round so that the span is exactly 2π in f64
        loop {
            let p0 = match rng.random_range(0..3) {
                0 => 0.0,
                1 => -PI,
                _ => rng.random_range(-PI..TAU),
            };
            let p1 = p0 + TAU;
            if p1 - p0 == TAU {
                return breakpoints(rng, p0, p1, 8);
            }
        }
    }
    // a wedge of any width (incl. wider than π), starting anywhere (incl. across φ = 0)
    let w = rng.random_range(0.1..6.2);
    let p0 = rng.random_range(-PI..TAU);
    breakpoints(rng, p0, p0 + w, 6)
}

fn random_radii(rng: &mut impl Rng, scale: f64) -> Vec<f64> {
    let r0 = if rng.random_bool(0.6) {
        0.0
    } else {
        rng.random_range(0.05..0.5) * scale
    };
    breakpoints(rng, r0, scale, 8)
}

/// A random spherical grid: non-uniform radii (inner radius 0 or > 0), a full zenith range or a band that
/// excludes a pole (sometimes with the plane θ = π/2 as a breakpoint), a full azimuth circle or a wedge.
pub fn random_spherical(rng: &mut impl Rng) -> GridSpec {
    let scale = 10f64.powf(rng.random_range(-1.0..1.0));
    let center = if rng.random_bool(0.5) {
        None
    } else {
        Some([0; 3].map(|_| rng.random_range(-1.0..1.0) * scale))
    };
    let (t0, t1) = match rng.random_range(0..4) {
        0 => (0.0, PI),
        1 => (rng.random_range(0.05..1.4), PI),
        2 => (0.0, rng.random_range(1.7..3.1)),
        _ => (rng.random_range(0.05..1.4), rng.random_range(1.7..3.1)),
    };
    let mut theta = breakpoints(rng, t0, t1, 6);
    if rng.random_bool(0.3) && !theta.contains(&FRAC_PI_2) {
        theta.push(FRAC_PI_2);
        theta.sort_by(|a, b| a.total_cmp(b));
    }
    GridSpec::Spherical {
        center,
        r: random_radii(rng, scale),
        theta,
        phi: random_azimuth(rng),
    }
}

/// A random cylindrical grid.
pub fn random_cylindrical(rng: &mut impl Rng) -> GridSpec {
    let scale = 10f64.powf(rng.random_range(-1.0..1.0));
    let z0 = rng.random_range(-1.0..0.5) * scale;
    let z1 = z0 + rng.random_range(0.2..2.0) * scale;
    GridSpec::Cylindrical {
        center: if rng.random_bool(0.5) {
            None
        } else {
            Some([0; 3].map(|_| rng.random_range(-1.0..1.0) * scale))
        },
        rho: random_radii(rng, scale),
        phi: random_azimuth(rng),
        z: breakpoints(rng, z0, z1, 6),
    }
}

/// A random polar grid.
pub fn random_polar(rng: &mut impl Rng) -> GridSpec {
    let scale = 10f64.powf(rng.random_range(-1.0..1.0));
    GridSpec::Polar {
        center: if rng.random_bool(0.5) {
            None
        } else {
            Some([0; 2].map(|_| rng.random_range(-1.0..1.0) * scale))
        },
        r: random_radii(rng, scale),
        phi: random_azimuth(rng),
    }
}

/// A random grid: 70 % spherical, 15 % cylindrical, 15 % polar.
pub fn random_grid(rng: &mut impl Rng) -> GridSpec {
    match rng.random_range(0..20) {
        0..=13 => random_spherical(rng),
        14..=16 => random_cylindrical(rng),
        _ => random_polar(rng),
    }
}

/// Center and a radius that bounds a grid.
pub fn bounds(g: &GridSpec) -> ([f64; 3], f64) {
    match g {
        GridSpec::Spherical { center, r, .. } => (center.unwrap_or([0.0; 3]), r[r.len() - 1]),
        GridSpec::Cylindrical { center, rho, z, .. } => {
            let c = center.unwrap_or([0.0; 3]);
            let (z0, z1) = (z[0], z[z.len() - 1]);
            let h = (z1 - z0) / 2.0;
            (
                [c[0], c[1], c[2] + (z0 + z1) / 2.0],
                (rho[rho.len() - 1].powi(2) + h * h).sqrt(),
            )
        }
        GridSpec::Polar { center, r, .. } => {
            let c = center.unwrap_or([0.0; 2]);
            ([c[0], c[1], 0.0], r[r.len() - 1])
        }
    }
}

fn unit(rng: &mut impl Rng) -> [f64; 3] {
    loop {
        let v = [0; 3].map(|_| rng.random_range(-1.0..1.0));
        let n2: f64 = v.iter().map(|a| a * a).sum();
        if n2 > 1e-4 && n2 <= 1.0 {
            let n = n2.sqrt();
            return v.map(|a| a / n);
        }
    }
}

/// A random ray aimed at the grid: origin inside the bounding ball or outside it (up to 4 radii away), aimed at
/// a random point of the ball, direction length `10^U(-2, 2)`; sometimes a finite `[t_min, t_max]` that starts
/// or ends inside.
pub fn random_ray(rng: &mut impl Rng, g: &GridSpec) -> RaySpec {
    let (c, rad) = bounds(g);
    let inside = rng.random_bool(0.4);
    let u = unit(rng);
    let dist = if inside {
        rng.random_range(0.0..1.0) * rad
    } else {
        rng.random_range(1.05..4.0) * rad
    };
    let origin = [0, 1, 2].map(|i| c[i] + u[i] * dist);
    let v = unit(rng);
    let target = [0, 1, 2].map(|i| c[i] + v[i] * rng.random_range(0.0..1.0) * rad);
    let mut dir = [0, 1, 2].map(|i| target[i] - origin[i]);
    let n = dir.iter().map(|a| a * a).sum::<f64>().sqrt();
    if n < 1e-9 * rad {
        dir = unit(rng);
    }
    let len = 10f64.powf(rng.random_range(-2.0..2.0));
    let n = dir.iter().map(|a| a * a).sum::<f64>().sqrt();
    let dir = dir.map(|a| a / n * len);
    let mut ray = RaySpec::new(origin, dir);
    // the ray's natural t scale
    let ts = rad / len;
    match rng.random_range(0..10) {
        0 => {
            ray.t_min = rng.random_range(0.0..3.0) * ts;
            ray.t_max = Some(ray.t_min + rng.random_range(0.0..3.0) * ts);
        }
        1 => ray.t_max = Some(rng.random_range(0.0..4.0) * ts),
        2 => ray.t_min = -rng.random_range(0.0..4.0) * ts,
        _ => {}
    }
    ray
}

// ---------------------------------------------------------------------------------------------------------------
// named hard cases

/// A full spherical grid with dyadic radii and a θ = π/2 plane: r = [0, 1/4, 9/16, 3/4, 1], θ = [0, 0.4, 1.1,
/// π/2, 2.0, 2.7, π], φ = [0, 0.7, 2.0, 3.3, 4.4, 5.5, 2π].
pub fn full_grid() -> GridSpec {
    GridSpec::Spherical {
        center: None,
        r: vec![0.0, 0.25, 0.5625, 0.75, 1.0],
        theta: vec![0.0, 0.4, 1.1, FRAC_PI_2, 2.0, 2.7, PI],
        phi: vec![0.0, 0.7, 2.0, 3.3, 4.4, 5.5, TAU],
    }
}

/// A partial spherical grid: inner radius 1/4, a zenith band [0.3, 2.5] excluding both poles with π/2 a
/// breakpoint, and a wedge [−0.5, 4.0] wider than π across φ = 0.
pub fn partial_grid() -> GridSpec {
    GridSpec::Spherical {
        center: None,
        r: vec![0.25, 0.5, 0.625, 1.0],
        theta: vec![0.3, 1.0, FRAC_PI_2, 2.5],
        phi: vec![-0.5, 0.3, 1.5, 3.6, 4.0],
    }
}

/// A spherical grid centred off the origin (to test the centre shift), otherwise [`full_grid`].
pub fn shifted_grid() -> GridSpec {
    match full_grid() {
        GridSpec::Spherical { r, theta, phi, .. } => GridSpec::Spherical {
            center: Some([0.5, -0.25, 2.0]),
            r,
            theta,
            phi,
        },
        g => g,
    }
}

fn shift(c: [f64; 3], o: [f64; 3]) -> [f64; 3] {
    [c[0] + o[0], c[1] + o[1], c[2] + o[2]]
}

fn deterministic_rng(seed: u64) -> rand_chacha::ChaCha8Rng {
    use rand::SeedableRng;
    rand_chacha::ChaCha8Rng::seed_from_u64(seed)
}

/// Grids and rays of the random suite: `n_rays` rays, 20 per random grid, reproducible from `seed`.
pub fn random_suite_inputs(n_rays: usize, seed: u64) -> Vec<(GridSpec, Vec<RaySpec>)> {
    let mut rng = deterministic_rng(seed);
    let mut out = Vec::new();
    let mut left = n_rays;
    while left > 0 {
        let g = random_grid(&mut rng);
        let k = left.min(20);
        let rays = (0..k).map(|_| random_ray(&mut rng, &g)).collect();
        out.push((g, rays));
        left -= k;
    }
    out
}

mod hard;
pub use hard::*;
