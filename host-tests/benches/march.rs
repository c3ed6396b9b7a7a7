//! Criterion benchmarks of spherical marching (seed 001): serial and separable engines, in f64, f32 and
//! f32-fast, on (a) 256² parallel rays through full-sphere grids of 64³ and 128³ cells and (b) a 256²
//! perspective view from 3R. Throughput is in rays; the crossings per ray of each scene are printed once, so
//! ns per crossing = ns per ray / crossings per ray.
//!
//! Quick run: `cargo bench -p curvicast-host --bench march -- --warm-up-time 1 --measurement-time 2`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use curvicast::F32Fast;
use curvicast::ray::Ray;
use curvicast::real::Real;
use curvicast::spherical::SphericalGrid;
use std::f64::consts::PI;
use std::hint::black_box;

const SIDE: usize = 256;

/// Mildly non-uniform breakpoints from `lo` to `hi` (n cells).
fn breakpoints(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| {
            let u = i as f64 / n as f64;
            lo + (hi - lo) * (u + 0.05 * (2.0 * PI * u).sin() / (2.0 * PI))
        })
        .collect()
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// (origin, direction) pairs in f64.
fn scene(perspective: bool) -> Vec<([f64; 3], [f64; 3])> {
    let view = norm([1.0, 0.45, 0.3]);
    let u = norm(cross(view, [0.0, 0.0, 1.0]));
    let v = cross(u, view);
    let mut out = Vec::with_capacity(SIDE * SIDE);
    for i in 0..SIDE {
        for j in 0..SIDE {
            let a = (i as f64 + 0.5) / SIDE as f64 * 2.0 - 1.0;
            let b = (j as f64 + 0.5) / SIDE as f64 * 2.0 - 1.0;
            if perspective {
                // eye at 3R looking at the center, the sphere filling the view (tan of half-angle 0.36)
                let eye = [-3.0 * view[0], -3.0 * view[1], -3.0 * view[2]];
                let d = [
                    view[0] + 0.36 * (a * u[0] + b * v[0]),
                    view[1] + 0.36 * (a * u[1] + b * v[1]),
                    view[2] + 0.36 * (a * u[2] + b * v[2]),
                ];
                out.push((eye, d));
            } else {
                let o = [
                    -2.0 * view[0] + 1.05 * (a * u[0] + b * v[0]),
                    -2.0 * view[1] + 1.05 * (a * u[1] + b * v[1]),
                    -2.0 * view[2] + 1.05 * (a * u[2] + b * v[2]),
                ];
                out.push((o, view));
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

fn bench_mode<T: Real>(c: &mut Criterion, cells: usize, perspective: bool) {
    let r: Vec<T> = breakpoints(0.0, 1.0, cells)
        .into_iter()
        .map(T::from_f64)
        .collect();
    let th: Vec<T> = breakpoints(0.0, PI, cells)
        .into_iter()
        .map(T::from_f64)
        .collect();
    let mut ph: Vec<T> = breakpoints(0.0, 2.0 * PI, cells)
        .into_iter()
        .map(T::from_f64)
        .collect();
    *ph.last_mut().unwrap() = T::PI + T::PI;
    let mut ws = vec![T::ZERO; SphericalGrid::<T>::workspace_len(r.len(), th.len(), ph.len())];
    let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let rays = rays::<T>(&scene(perspective));
    let crossings: usize = rays.iter().map(|ray| grid.march(ray).count()).sum();
    let name = format!(
        "march/{}/{}{}",
        if perspective {
            "perspective"
        } else {
            "parallel"
        },
        cells,
        "^3"
    );
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

fn benches(c: &mut Criterion) {
    println!(
        "size_of SerialMarch: f64 {} bytes, f32 {} bytes",
        std::mem::size_of::<curvicast::spherical::SerialMarch<'static, f64>>(),
        std::mem::size_of::<curvicast::spherical::SerialMarch<'static, f32>>()
    );
    for (cells, perspective) in [(64, false), (128, false), (64, true)] {
        bench_mode::<f64>(c, cells, perspective);
        bench_mode::<f32>(c, cells, perspective);
        bench_mode::<F32Fast>(c, cells, perspective);
    }
}

criterion_group!(march, benches);
criterion_main!(march);
