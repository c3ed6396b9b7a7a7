//! Generators of terrain scenes and rays for the oracle suites, the fuzz target's seeds, the benchmarks and the
//! report: synthetic DEMs (flat, fractal, spiky, negative heights) and ray families (random, from a camera above
//! ground, from orbit, and the adversarial kinds of the terrain issue).

use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::{Dem, WGS84_A, WGS84_B, geodetic_to_ecef_f64};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The kinds of synthetic terrain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TerrainKind {
    /// Constant height.
    Flat,
    /// Sum of random sinusoids over octaves (1/f amplitude): smooth hills to rough ridges.
    Fractal,
    /// Mostly low ground with isolated needles up to 5 km.
    Spiky,
    /// Heights between −6000 m and −100 m (an ocean floor).
    Negative,
}

/// A synthetic DEM on WGS84: `rows × cols` vertices from (lat0, lon0) with steps (dlat, dlon) degrees.
pub fn synthetic(
    kind: TerrainKind,
    geo: (f64, f64, f64, f64),
    shape: (usize, usize),
    seed: u64,
) -> Dem {
    let (rows, cols) = shape;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut h = vec![0.0f32; rows * cols];
    match kind {
        TerrainKind::Flat => {
            let v = rng.random_range(-200.0..3000.0f32).round();
            h.fill(v);
        }
        TerrainKind::Fractal | TerrainKind::Negative => {
            let waves: Vec<(f64, f64, f64, f64)> = (0..12)
                .map(|k| {
                    let f = 2f64.powi(k / 2) * rng.random_range(0.5..1.5);
                    let a = 1.0 / f;
                    (
                        f,
                        rng.random_range(0.0..6.3),
                        rng.random_range(-1.0..1.0),
                        a,
                    )
                })
                .collect();
            for i in 0..rows {
                for j in 0..cols {
                    let (x, y) = (i as f64 / rows as f64, j as f64 / cols as f64);
                    let mut s = 0.0;
                    for &(f, ph, dir, a) in &waves {
                        s += a
                            * (std::f64::consts::TAU * f * (x * dir + y * (1.0 - dir.abs())) * 4.0
                                + ph)
                                .sin();
                    }
                    h[i * cols + j] = if kind == TerrainKind::Fractal {
                        (800.0 + 900.0 * s) as f32
                    } else {
                        (-3000.0 + 1200.0 * s).clamp(-6000.0, -100.0) as f32
                    };
                }
            }
        }
        TerrainKind::Spiky => {
            for v in h.iter_mut() {
                *v = if rng.random_bool(0.05) {
                    rng.random_range(1000.0..5000.0f32).round()
                } else {
                    rng.random_range(0.0..20.0f32).round()
                };
            }
        }
    }
    Dem::wgs84(geo, shape, h).expect("synthetic DEM parameters are valid")
}

/// A random point of the DEM's extent at a height between `h0` and `h1` (ECEF).
pub fn point_over(dem: &Dem, rng: &mut impl Rng, h0: f64, h1: f64) -> [f64; 3] {
    let fi = rng.random_range(0.0..(dem.rows - 1) as f64);
    let fj = rng.random_range(0.0..(dem.cols - 1) as f64);
    let lat = dem.lat0 + fi * dem.dlat;
    let lon = dem.lon0 + fj * dem.dlon;
    let h = if h1 > h0 {
        rng.random_range(h0..h1)
    } else {
        h0
    };
    geodetic_to_ecef_f64(dem.a, dem.b, lat, lon, h)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Random rays: from above the terrain (1 m to 20 km over its maximum) to a random point of its height range,
/// direction jittered, half of them with a finite `t_max`.
pub fn random_rays(dem: &Dem, n: usize, seed: u64) -> Vec<RaySpec> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (lo, hi) = dem.height_range().unwrap_or((0.0, 0.0));
    let (lo, hi) = (f64::from(lo), f64::from(hi));
    (0..n)
        .map(|k| {
            let o = point_over(dem, &mut rng, hi + 1.0, hi + 20_000.0);
            let target = point_over(dem, &mut rng, lo - 10.0, hi + 10.0);
            let mut d = sub(target, o);
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            for c in d.iter_mut() {
                *c += rng.random_range(-0.05..0.05) * len;
            }
            let mut r = RaySpec::new(o, d);
            if k % 2 == 1 {
                r.t_max = Some(rng.random_range(0.3..1.5));
            }
            r
        })
        .collect()
}

/// Rays from a camera `height` meters above the ground (above the vertex under it) looking down at random
/// points of the DEM within `reach` cells.
pub fn camera_rays(dem: &Dem, n: usize, height: f64, seed: u64) -> Vec<RaySpec> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (ci, cj) = (dem.rows / 2, dem.cols / 2);
    let hg = dem.height(ci, cj).map_or(0.0, f64::from);
    let cam = geodetic_to_ecef_f64(dem.a, dem.b, dem.lat(ci), dem.lon(cj), hg + height);
    (0..n)
        .map(|_| {
            let target = point_over(dem, &mut rng, hg - 500.0, hg);
            RaySpec::new(cam, sub(target, cam))
        })
        .collect()
}

/// Rays from orbit (4·10⁷ m from the Earth's centre, above the DEM) aimed at random points of the DEM.
pub fn orbit_rays(dem: &Dem, n: usize, seed: u64) -> Vec<RaySpec> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (ci, cj) = (dem.rows / 2, dem.cols / 2);
    let c = geodetic_to_ecef_f64(dem.a, dem.b, dem.lat(ci), dem.lon(cj), 0.0);
    let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let cam = c.map(|x| x / l * 4.0e7);
    let (lo, hi) = dem.height_range().unwrap_or((0.0, 0.0));
    (0..n)
        .map(|_| {
            let target = point_over(dem, &mut rng, f64::from(lo), f64::from(hi));
            RaySpec::new(cam, sub(target, cam))
        })
        .collect()
}

/// WGS84 semi-axes, re-exported for generators.
pub const WGS84: (f64, f64) = (WGS84_A, WGS84_B);
