//! Criterion benchmarks of `curvicast::tessellate`: building beveled polyhedra (f64, f32), refining Chaikin
//! curves, and the a-priori level of detail.
//!
//! Run with `cargo bench -p curvicast-host --bench tessellate -- --warm-up-time 1 --measurement-time 2`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use curvicast::V3;
use curvicast::tessellate::bevel::{self, Face};
use curvicast::tessellate::chaikin;
use curvicast::tessellate::lod::{self, Bound, Shape};
use std::hint::black_box;

const WGS84: [f64; 3] = [6378137.0, 6378137.0, 6356752.314245179];

fn bevel_levels(c: &mut Criterion) {
    let mut g = c.benchmark_group("bevel_ellipsoid");
    for level in [2u32, 4, 6] {
        let mut v = vec![V3::<f64>::ZERO; bevel::vertex_count(level)];
        let mut f = vec![Face::<f64>::EMPTY; bevel::face_count(level)];
        g.bench_with_input(BenchmarkId::new("f64 WGS84", level), &level, |b, &k| {
            b.iter(|| bevel::bevel_ellipsoid(k, black_box(WGS84), &mut v, &mut f).unwrap())
        });
        let mut v = vec![V3::<f32>::ZERO; bevel::vertex_count(level)];
        let mut f = vec![Face::<f32>::EMPTY; bevel::face_count(level)];
        g.bench_with_input(
            BenchmarkId::new("f32 unit sphere", level),
            &level,
            |b, &k| b.iter(|| bevel::bevel_sphere(k, black_box(1.0_f32), &mut v, &mut f).unwrap()),
        );
    }
    g.finish();
}

fn chaikin_levels(c: &mut Criterion) {
    let mut g = c.benchmark_group("chaikin_ellipse");
    for level in [4u32, 10] {
        let mut out = vec![[0.0_f64; 2]; chaikin::square_len(level)];
        g.bench_with_input(BenchmarkId::new("f64", level), &level, |b, &k| {
            b.iter(|| chaikin::ellipse([0.0, 0.0], black_box(3.0), 1.0, k, &mut out).unwrap())
        });
    }
    g.finish();
}

fn a_priori(c: &mut Criterion) {
    c.bench_function("lod::min_level screen space (sphere)", |b| {
        b.iter(|| {
            lod::min_level(
                Shape::Sphere(black_box(6.371e6_f64)),
                Bound::ScreenSpace {
                    distance: 2.0e7,
                    pixel_angle: 1e-4,
                },
            )
            .unwrap()
        })
    });
}

criterion_group!(benches, bevel_levels, chaikin_levels, a_priori);
criterion_main!(benches);
