//! Criterion benchmarks of the ray–surface solvers: one benchmark per surface kind × precision mode, each over a
//! fixed random batch of 1024 ray–surface pairs (the report's generator: scales 1e-8..1e8, direction lengths up
//! to 1e±30, origins inside and outside), reported per intersection (throughput in elements).
//!
//! Quick run: `cargo bench -p curvicast-host --bench surfaces -- --warm-up-time 1 --measurement-time 2`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use curvicast::F32Fast;
use curvicast::Ray;
use curvicast::real::Real;
use curvicast::surface::{AxialCone, HalfPlane, PlaneZ, Spheroid, Surface};
use curvicast_host::report::surfaces::{Kind, Precision, SurfaceCase, kernel_ray, random_cases};
use std::hint::black_box;

const BATCH: usize = 1024;

fn run<T: Real, S: Surface<T>>(surfaces: &[S], rays: &[Ray<T>]) -> usize {
    let mut n = 0usize;
    for (s, r) in surfaces.iter().zip(rays) {
        n += black_box(s.crossings(black_box(r))).len();
    }
    n
}

fn bench_mode<T: Real>(c: &mut Criterion, kind: Kind, mode: Precision, cases: &[SurfaceCase]) {
    let cases: Vec<SurfaceCase> = cases.iter().map(|x| x.for_mode(mode)).collect();
    let rays: Vec<Ray<T>> = cases
        .iter()
        .filter_map(|x| kernel_ray::<T>(x).ok())
        .collect();
    assert_eq!(rays.len(), cases.len(), "every benchmark ray must be valid");
    let p = |x: &SurfaceCase| (T::from_f64(x.p[0]), T::from_f64(x.p[1]));
    let mut g = c.benchmark_group(format!("surface/{}", kind.name()));
    g.throughput(Throughput::Elements(rays.len() as u64));
    let id = BenchmarkId::from_parameter(mode.name());
    match kind {
        Kind::Spheroid => {
            let s: Vec<_> = cases
                .iter()
                .filter_map(|x| Spheroid::new(p(x).0, p(x).1).ok())
                .collect();
            assert_eq!(s.len(), rays.len());
            g.bench_function(id, |b| b.iter(|| run(&s, &rays)));
        }
        Kind::Cone => {
            let s: Vec<_> = cases
                .iter()
                .filter_map(|x| AxialCone::from_zenith_rad(p(x).0, p(x).1).ok())
                .collect();
            assert_eq!(s.len(), rays.len());
            g.bench_function(id, |b| b.iter(|| run(&s, &rays)));
        }
        Kind::HalfPlane => {
            let s: Vec<_> = cases
                .iter()
                .filter_map(|x| HalfPlane::from_azimuth_rad(p(x).0).ok())
                .collect();
            assert_eq!(s.len(), rays.len());
            g.bench_function(id, |b| b.iter(|| run(&s, &rays)));
        }
        Kind::PlaneZ => {
            let s: Vec<_> = cases
                .iter()
                .filter_map(|x| PlaneZ::new(p(x).0).ok())
                .collect();
            assert_eq!(s.len(), rays.len());
            g.bench_function(id, |b| b.iter(|| run(&s, &rays)));
        }
    }
    g.finish();
}

fn surfaces(c: &mut Criterion) {
    for kind in Kind::ALL {
        let cases = random_cases(kind, BATCH, 2026);
        for mode in Precision::ALL {
            match mode {
                Precision::F64 => bench_mode::<f64>(c, kind, mode, &cases),
                Precision::F32 => bench_mode::<f32>(c, kind, mode, &cases),
                Precision::F32Fast => bench_mode::<F32Fast>(c, kind, mode, &cases),
            }
        }
    }
}

criterion_group!(benches, surfaces);
criterion_main!(benches);
