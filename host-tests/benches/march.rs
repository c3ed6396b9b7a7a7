//! Criterion benchmarks of spherical marching (Hannasch), on the report's marching scene
//! (`curvicast_host::scenes::marching`): a 64³ grid and 256² parallel rays along (1, 0.15, 0.1), 3 units back,
//! covering the ball.
//!
//! * `march/<grid>`: the serial engine through `next` (`serial/<precision>`, a `for` loop) and through its
//!   internal iteration (`serial_fold/<precision>`, `Iterator::fold`), and the separable engine filled in place into one
//!   reused march (`separable_into/<precision>`, `march_separable_into`, what a caller marching many rays does),
//!   in f64, f32 and f32-fast, on the uniform grid, a grid of random (seeded) breakpoints and a partial grid
//!   (shell r ∈ [0.3, 1], θ ∈ [0.4, 2.6], φ ∈ [−1, 4]); on the uniform grid also `separable_by_value/f64`,
//!   `march_separable` returning a new march per ray (its three 512-event buffers, 37 KB, are moved per ray);
//! * `march/perspective`: the uniform grid seen by a 256² perspective camera from 3R, both engines;
//! * `march_batch`: the parallel image through `curvicast_cli::batch::march_batch` on 1 and 2 threads (a
//!   projection image, Σ length per ray), the scaling of the batch entry across cores.
//!
//! Every benchmark marches the rays inside the timed loop and folds each crossing into a sum that is passed to
//! `black_box`. Throughput is in rays; the crossings per ray of each scene are printed once, so ns per crossing =
//! ns per ray / crossings per ray. Instruction counts of the same scene: `examples/march_count.rs`.
//!
//! Quick run: `cargo bench -p curvicast-host --bench march -- --warm-up-time 1 --measurement-time 2`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use curvicast::F32Fast;
use curvicast::march::{SeparableMarch, SerialMarch, Spherical, SphericalGrid};
use curvicast::ray::Ray;
use curvicast::real::Real;
use curvicast_cli::batch::march_batch;
use curvicast_host::scenes::marching::{
    Breakpoints, GridLayout, parallel_rays, perspective_rays, rays_in,
};
use std::hint::black_box;

/// Rays per side.
const SIDE: usize = 256;
/// The separable engine's capacity per coordinate.
const N: usize = 512;

/// Σ (t_exit − t_enter) over every crossing of every ray, serial engine.
fn serial_sum<T: Real>(grid: &SphericalGrid<'_, T>, rays: &[Ray<T>]) -> T {
    let mut acc = T::ZERO;
    for ray in rays {
        for x in grid.march(black_box(ray)) {
            acc += x.t_exit - x.t_enter;
        }
    }
    acc
}

/// The same sum through the serial engine's internal iteration (`Iterator::fold`).
fn serial_fold_sum<T: Real>(grid: &SphericalGrid<'_, T>, rays: &[Ray<T>]) -> T {
    let mut acc = T::ZERO;
    for ray in rays {
        acc = grid
            .march(black_box(ray))
            .fold(acc, |a, x| a + (x.t_exit - x.t_enter));
    }
    acc
}

/// The same sum, separable engine listing into one reused march.
fn separable_into_sum<T: Real>(
    grid: &SphericalGrid<'_, T>,
    rays: &[Ray<T>],
    march: &mut SeparableMarch<T, N>,
) -> T {
    let mut acc = T::ZERO;
    for ray in rays {
        grid.march_separable_into(black_box(ray), march)
            .expect("the scene fits the buffers");
        for x in march.by_ref() {
            acc += x.t_exit - x.t_enter;
        }
    }
    acc
}

/// The same sum, separable engine returning a new march by value per ray.
fn separable_by_value_sum<T: Real>(grid: &SphericalGrid<'_, T>, rays: &[Ray<T>]) -> T {
    let mut acc = T::ZERO;
    for ray in rays {
        let march = grid
            .march_separable::<N>(black_box(ray))
            .expect("the scene fits the buffers");
        for x in march {
            acc += x.t_exit - x.t_enter;
        }
    }
    acc
}

fn bench_mode<T: Real>(c: &mut Criterion, kind: GridLayout, perspective: bool) {
    let mut breakpoints = Breakpoints::<T>::new(kind);
    let grid = breakpoints.grid().expect("valid grid");
    let scene = if perspective {
        perspective_rays(SIDE)
    } else {
        parallel_rays(SIDE)
    };
    let rays = rays_in::<T>(&scene).expect("valid rays");
    let crossings: usize = rays.iter().map(|ray| grid.march(ray).count()).sum();
    let name = if perspective {
        "march/perspective".to_string()
    } else {
        format!("march/{}", kind.name())
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
        b.iter(|| black_box(serial_sum(&grid, &rays)))
    });
    g.bench_function(BenchmarkId::new("serial_fold", T::NAME), |b| {
        b.iter(|| black_box(serial_fold_sum(&grid, &rays)))
    });
    let mut march = SeparableMarch::<T, N>::default();
    g.bench_function(BenchmarkId::new("separable_into", T::NAME), |b| {
        b.iter(|| black_box(separable_into_sum(&grid, &rays, &mut march)))
    });
    if kind == GridLayout::Uniform && !perspective && T::NAME == "f64" {
        g.bench_function(BenchmarkId::new("separable_by_value", T::NAME), |b| {
            b.iter(|| black_box(separable_by_value_sum(&grid, &rays)))
        });
    }
    g.finish();
}

/// The batch entry on 1 and 2 threads: a projection image of the parallel view in f64.
fn bench_batch(c: &mut Criterion) {
    let mut breakpoints = Breakpoints::<f64>::new(GridLayout::Uniform);
    let grid = breakpoints.grid().expect("valid grid");
    let rays = rays_in::<f64>(&parallel_rays(SIDE)).expect("valid rays");
    let mut g = c.benchmark_group("march_batch");
    g.sample_size(10);
    g.throughput(Throughput::Elements(rays.len() as u64));
    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
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
        std::mem::size_of::<SerialMarch<'static, f64, Spherical>>(),
        std::mem::size_of::<SerialMarch<'static, f32, Spherical>>()
    );
    for kind in GridLayout::ALL {
        bench_mode::<f64>(c, kind, false);
        bench_mode::<f32>(c, kind, false);
        bench_mode::<F32Fast>(c, kind, false);
    }
    bench_mode::<f64>(c, GridLayout::Uniform, true);
    bench_mode::<f32>(c, GridLayout::Uniform, true);
    bench_batch(c);
}

criterion_group!(march, benches);
criterion_main!(march);
