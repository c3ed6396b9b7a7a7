//! Criterion benchmarks of spherical marching (seed 001), on the report's scene: a 64³ full-sphere grid and
//! 256² parallel rays along (1, 0.15, 0.1), 3 units back, covering the ball.
//!
//! * `march/<grid>`: the serial and separable engines in f64, f32 and f32-fast, on the uniform grid, a grid of
//!   random (seeded) breakpoints and a partial grid (shell r ∈ [0.3, 1], θ ∈ [0.4, 2.6], φ ∈ [−1, 4]);
//! * `march/perspective`: the uniform grid seen by a 256² perspective camera from 3R;
//! * `march_batch`: the same image through `curvicast_host::batch::march_batch` on 1 and 2 threads (a
//!   projection image, Σ length per ray), the scaling of the batch entry across cores.
//!
//! Throughput is in rays; the crossings per ray of each scene are printed once, so ns per crossing = ns per ray
//! / crossings per ray. Instruction counts of the same scene: `examples/march_count.rs`.
//!
//! Quick run: `cargo bench -p curvicast-host --bench march -- --warm-up-time 1 --measurement-time 2`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use curvicast::F32Fast;
use curvicast::ray::Ray;
use curvicast::real::Real;
use curvicast::spherical::SphericalGrid;
use curvicast_host::batch::march_batch;
use rand::{Rng, SeedableRng};
use std::f64::consts::{PI, TAU};
use std::hint::black_box;

const SIDE: usize = 256;
const CELLS: usize = 64;

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
    for x in &w[..n - 1] {
        acc += x;
        out.push(lo + (hi - lo) * acc / total);
    }
    out.push(hi);
    out
}

/// The breakpoints of the named grid (full turn in φ except for the partial grid).
fn grid_breakpoints(kind: &str) -> [Vec<f64>; 3] {
    match kind {
        "uniform" => [
            uniform(CELLS, 0.0, 1.0),
            uniform(CELLS, 0.0, PI),
            uniform(CELLS, 0.0, TAU),
        ],
        "nonuniform" => {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(16);
            [
                random(CELLS, 0.0, 1.0, &mut rng),
                random(CELLS, 0.0, PI, &mut rng),
                random(CELLS, 0.0, TAU, &mut rng),
            ]
        }
        _ => [
            uniform(CELLS, 0.3, 1.0),
            uniform(CELLS, 0.4, 2.6),
            uniform(CELLS, -1.0, 4.0),
        ],
    }
}

fn norm(v: [f64; 3]) -> [f64; 3] {
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

/// (origin, direction) pairs in f64: the report's parallel rays, or a perspective view from 3R.
fn scene(perspective: bool) -> Vec<([f64; 3], [f64; 3])> {
    let d = norm([1.0, 0.15, 0.1]);
    let u = norm([-d[1], d[0], 0.0]);
    let v = cross(d, u);
    let mut out = Vec::with_capacity(SIDE * SIDE);
    for i in 0..SIDE {
        for j in 0..SIDE {
            let a = (i as f64 + 0.5) / SIDE as f64 * 2.0 - 1.0;
            let b = (j as f64 + 0.5) / SIDE as f64 * 2.0 - 1.0;
            if perspective {
                let eye = d.map(|x| -3.0 * x);
                let half = (1.0f64 / 3.0).asin().tan() * 1.05;
                let dir = [0, 1, 2].map(|k| d[k] + half * (a * u[k] + b * v[k]));
                out.push((eye, dir));
            } else {
                let o = [0, 1, 2].map(|k| 1.05 * (a * u[k] + b * v[k]) - 3.0 * d[k]);
                out.push((o, d));
            }
        }
    }
    out
}

fn rays<T: Real>(s: &[([f64; 3], [f64; 3])]) -> Vec<Ray<T>> {
    s.iter()
        .map(|(o, d)| Ray::new(o.map(T::from_f64), d.map(T::from_f64)).unwrap())
        .collect()
}

/// The grid's breakpoints in `T` (the full turn's end is `T`'s own 2π).
fn breakpoints_in<T: Real>(kind: &str) -> [Vec<T>; 3] {
    let [r, th, ph] = grid_breakpoints(kind);
    let conv = |v: Vec<f64>| v.into_iter().map(T::from_f64).collect::<Vec<T>>();
    let (r, th, mut ph) = (conv(r), conv(th), conv(ph));
    if kind != "partial" {
        *ph.last_mut().unwrap() = T::PI + T::PI;
    }
    [r, th, ph]
}

fn bench_mode<T: Real>(c: &mut Criterion, kind: &str, perspective: bool) {
    let [r, th, ph] = breakpoints_in::<T>(kind);
    let mut ws = vec![T::ZERO; SphericalGrid::<T>::workspace_len(r.len(), th.len(), ph.len())];
    let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let rays = rays::<T>(&scene(perspective));
    let crossings: usize = rays.iter().map(|ray| grid.march(ray).count()).sum();
    let name = if perspective {
        "march/perspective".to_string()
    } else {
        format!("march/{kind}")
    };
    println!(
        "{name} {}: {} rays, {} crossings ({:.1} per ray)",
        T::NAME,
        rays.len(),
        crossings,
        crossings as f64 / rays.len() as f64
    );
    let mut g = c.benchmark_group(name);
    g.sample_size(10);
    g.throughput(Throughput::Elements(rays.len() as u64));
    g.bench_function(BenchmarkId::new("serial", T::NAME), |b| {
        b.iter(|| {
            let mut acc = T::ZERO;
            for ray in &rays {
                for x in grid.march(black_box(ray)) {
                    acc += x.t_exit - x.t_enter;
                }
            }
            black_box(acc)
        })
    });
    g.bench_function(BenchmarkId::new("separable", T::NAME), |b| {
        b.iter(|| {
            let mut acc = T::ZERO;
            for ray in &rays {
                for x in grid.march_separable::<512>(black_box(ray)).unwrap() {
                    acc += x.t_exit - x.t_enter;
                }
            }
            black_box(acc)
        })
    });
    g.finish();
}

/// The batch entry on 1 and 2 threads: a projection image of the report's scene in f64.
fn bench_batch(c: &mut Criterion) {
    let [r, th, ph] = breakpoints_in::<f64>("uniform");
    let mut ws = vec![0.0; SphericalGrid::<f64>::workspace_len(r.len(), th.len(), ph.len())];
    let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let rays = rays::<f64>(&scene(false));
    let mut g = c.benchmark_group("march_batch");
    g.sample_size(10);
    g.throughput(Throughput::Elements(rays.len() as u64));
    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        g.bench_function(BenchmarkId::new("projection_f64", threads), |b| {
            b.iter(|| {
                let image = pool.install(|| {
                    march_batch(&grid, black_box(&rays), |_, m| {
                        m.map(|x| x.t_exit - x.t_enter).sum::<f64>()
                    })
                });
                black_box(image)
            })
        });
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
    println!(
        "size_of SerialMarch: f64 {} bytes, f32 {} bytes",
        std::mem::size_of::<curvicast::spherical::SerialMarch<'static, f64>>(),
        std::mem::size_of::<curvicast::spherical::SerialMarch<'static, f32>>()
    );
    for kind in ["uniform", "nonuniform", "partial"] {
        bench_mode::<f64>(c, kind, false);
        bench_mode::<f32>(c, kind, false);
        bench_mode::<F32Fast>(c, kind, false);
    }
    bench_mode::<f64>(c, "uniform", true);
    bench_mode::<f32>(c, "uniform", true);
    bench_batch(c);
}

criterion_group!(march, benches);
criterion_main!(march);
