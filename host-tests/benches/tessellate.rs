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

/// `min_level` for ellipsoids, with bounds halfway between two levels' exact worst values (taken from
/// `lod::ellipsoid_worst_case`): the answer is the finer level, and whether a walk is needed depends on the shape.
fn a_priori_ellipsoid(c: &mut Criterion) {
    let mut g = c.benchmark_group("lod::min_level ellipsoid");
    for (name, axes) in [
        ("WGS84", WGS84),
        ("3:2:1", [3.0, 2.0, 1.0]),
        ("1:1:0.3", [1.0, 1.0, 0.3]),
    ] {
        for level in [4u32, 6, 8] {
            let hi = lod::ellipsoid_worst_case(axes, level).unwrap();
            let lo = lod::ellipsoid_worst_case(axes, level - 1).unwrap();
            let dev = Bound::MaxDeviation(0.5 * (hi.max_deviation + lo.max_deviation));
            let dih = Bound::MinDihedral(0.5 * (hi.min_dihedral + lo.min_dihedral));
            for (kind, bound) in [("deviation", dev), ("dihedral", dih)] {
                assert_eq!(lod::min_level(Shape::Ellipsoid(axes), bound), Ok(level));
                g.bench_with_input(
                    BenchmarkId::new(format!("{name} {kind}"), level),
                    &bound,
                    |b, &bound| b.iter(|| lod::min_level(Shape::Ellipsoid(black_box(axes)), bound)),
                );
            }
        }
    }
    g.finish();
}

criterion_group!(
    benches,
    bevel_levels,
    chaikin_levels,
    a_priori,
    a_priori_ellipsoid
);
criterion_main!(benches);
