//! Host tests of the edge-beveled polyhedra (the edge-beveling thesis §4.3–4.4), the a-priori level of detail (chapter 5), and
//! the `curvicast tessellate` command.
//!
//! Every check here measures the built polyhedra with code of its own (plane distances from the true surface
//! normal, a directed-edge map, Newell normals, a bisection for the distance to an ellipsoid), not with the
//! kernel's.

#[path = "../support/mod.rs"]
mod support;

use curvicast::V3;
use curvicast::real::Real;
use curvicast::tessellate::bevel::{self, Face};
use curvicast::tessellate::lod::{self, Bound, Shape};
use curvicast_cli::cli::tessellate::{Mesh, build, max_deviation, min_dihedral};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::OnceLock;

const WGS84: [f64; 3] = [6378137.0, 6378137.0, 6356752.314245179];

/// Checks that every directed edge appears once and its reverse once (closed, consistently oriented), that
/// V − E + F = 2, and returns E.
fn closed_edges(faces: &[Vec<u32>], nv: usize) -> usize {
    let mut directed: Vec<(u32, u32)> = Vec::with_capacity(faces.len() * 6);
    for f in faces {
        for k in 0..f.len() {
            let e = (f[k], f[(k + 1) % f.len()]);
            assert!(
                (e.0 as usize) < nv && (e.1 as usize) < nv,
                "index out of range"
            );
            directed.push(e);
        }
    }
    directed.sort_unstable();
    for w in directed.windows(2) {
        assert_ne!(
            w[0], w[1],
            "directed edge {:?} appears twice (orientation)",
            w[0]
        );
    }
    for &(a, b) in &directed {
        assert!(
            directed.binary_search(&(b, a)).is_ok(),
            "edge {a}-{b} has one face"
        );
    }
    let e = directed.len() / 2;
    assert_eq!(nv as i64 - e as i64 + faces.len() as i64, 2, "Euler");
    e
}

/// Builds with the kernel in scalar `T` and checks tangency, outside-ness, closure and counts; returns the worst
/// plane distance in units of `eps · max axis`.
fn check_level<T: Real>(level: u32, axes: [f64; 3]) -> f64 {
    let mut v = vec![V3::<T>::ZERO; bevel::vertex_count(level)];
    let mut f = vec![Face::<T>::EMPTY; bevel::face_count(level)];
    let a = axes.map(T::from_f64);
    let counts = bevel::bevel_ellipsoid(level, a, &mut v, &mut f).unwrap();
    assert_eq!(counts.vertices, 8 * 4usize.pow(level));
    assert_eq!(counts.faces, 4 * 4usize.pow(level) + 2);
    let faces: Vec<Vec<u32>> = f.iter().map(|x| x.vertex_indices().to_vec()).collect();
    assert_eq!(closed_edges(&faces, v.len()), bevel::edge_count(level));
    assert_eq!(counts.edges, bevel::edge_count(level));
    assert_eq!(faces.iter().filter(|x| x.len() == 4).count(), 6);
    assert!(faces.iter().all(|x| x.len() == 4 || x.len() == 6));
    let radius = axes.iter().cloned().fold(0.0, f64::max);
    let eps = T::EPSILON.to_f64();
    let mut worst = 0.0_f64;
    let to64 = |p: V3<T>| [p.x.to_f64(), p.y.to_f64(), p.z.to_f64()];
    for face in &f {
        let c = to64(face.center);
        // The center point is on the surface ...
        let s: f64 = (0..3).map(|i| (c[i] / axes[i]).powi(2)).sum();
        assert!((s - 1.0).abs() <= 8.0 * eps, "center off the surface: {s}");
        // ... the true surface normal there, from the center alone ...
        let g = [
            c[0] / axes[0].powi(2),
            c[1] / axes[1].powi(2),
            c[2] / axes[2].powi(2),
        ];
        let gl = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        let n = [g[0] / gl, g[1] / gl, g[2] / gl];
        // ... and every vertex of the face lies in that tangent plane.
        for &i in face.vertex_indices() {
            let p = to64(v[i as usize]);
            let d = (p[0] - c[0]) * n[0] + (p[1] - c[1]) * n[1] + (p[2] - c[2]) * n[2];
            worst = worst.max(d.abs() / (eps * radius));
        }
    }
    for p in &v {
        let p = to64(*p);
        let s: f64 = (0..3).map(|i| (p[i] / axes[i]).powi(2)).sum();
        assert!(s >= 1.0, "vertex inside the surface: {s}");
    }
    worst
}

#[test]
fn faces_tangent_at_center_vertices_outside_closed_levels_0_to_8_f64() {
    for (name, axes, top) in [
        ("unit sphere", [1.0; 3], 8),
        ("WGS84", WGS84, 8),
        ("ellipsoid 3:2:1", [3.0, 2.0, 1.0], 7),
    ] {
        for level in 0..=top {
            let w = check_level::<f64>(level, axes);
            eprintln!("{name} level {level}: worst plane distance {w:.2} eps*radius");
            assert!(w <= 8.0, "{name} level {level}: {w} eps*radius");
        }
    }
}

#[test]
fn faces_tangent_at_center_levels_0_to_6_f32() {
    for axes in [[1.0; 3], WGS84] {
        for level in 0..=6 {
            let w = check_level::<f32>(level, axes);
            eprintln!("f32 {axes:?} level {level}: worst plane distance {w:.2} eps*radius");
            assert!(w <= 8.0, "f32 level {level}: {w} eps*radius");
        }
    }
}

/// Measured (smallest dihedral angle, largest deviation) of the unit sphere's polyhedron, levels 0..=8.
fn measured_unit() -> &'static [(f64, f64)] {
    static M: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    M.get_or_init(|| {
        (0..=8)
            .map(|k| {
                let m: Mesh = build(Shape::Sphere(1.0), k).unwrap();
                (min_dihedral(&m), max_deviation(&m, Shape::Sphere(1.0)))
            })
            .collect()
    })
}

#[test]
fn worst_case_followed_a_priori_is_the_measured_worst_case() {
    for (k, &(dihedral, deviation)) in measured_unit().iter().enumerate() {
        let w = lod::worst_case::<f64>(k as u32).unwrap();
        eprintln!(
            "level {k}: min dihedral {:.12}° (a priori {:.12}°), max deviation {deviation:.6e} (a priori {:.6e})",
            dihedral.to_degrees(),
            w.min_dihedral.to_degrees(),
            w.max_deviation
        );
        assert!(
            (dihedral - w.min_dihedral).abs() < 1e-11,
            "level {k} dihedral"
        );
        assert!(
            ((deviation - w.max_deviation) / w.max_deviation).abs() < 1e-9,
            "level {k} deviation"
        );
    }
}

/// Draws `n` bounds with `draw`, skipping any within a relative 1e-7 of a measured threshold (where rounding
/// could decide) or needing a level above 8; checks minimality of each; returns how many were checked.
fn check_minimal(
    n: usize,
    seed: u64,
    mut draw: impl FnMut(&mut ChaCha8Rng) -> (Shape<f64>, Bound<f64>),
    meets: impl Fn(Shape<f64>, Bound<f64>, u32) -> Option<bool>,
) -> Vec<u32> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut levels = Vec::new();
    let mut tries = 0;
    while levels.len() < n {
        tries += 1;
        assert!(tries < 100 * n, "too few usable bounds");
        let (shape, bound) = draw(&mut rng);
        let k = lod::min_level(shape, bound).unwrap();
        if k > 8 {
            continue;
        }
        // None: too close to a threshold to decide by measurement.
        let Some(ok) = meets(shape, bound, k) else {
            continue;
        };
        assert!(ok, "{bound:?} on {shape:?}: level {k} does not meet it");
        if k > 0 {
            let Some(below) = meets(shape, bound, k - 1) else {
                continue;
            };
            assert!(
                !below,
                "{bound:?} on {shape:?}: level {} already meets it",
                k - 1
            );
        }
        levels.push(k);
    }
    levels
}

fn close(a: f64, b: f64) -> bool {
    ((a - b) / b).abs() < 1e-7
}

#[test]
fn a_priori_level_is_the_smallest_for_dihedral_bounds() {
    let m = measured_unit();
    let levels = check_minimal(
        60,
        1,
        |rng| {
            let r = 10f64.powf(rng.random_range(-3.0..7.0));
            // The angle between adjacent normals, log-uniform from 0.56° (level 8) to 100°.
            let x = 10f64.powf(rng.random_range(0.56f64.log10()..2.0));
            let phi = (180.0 - x).to_radians();
            (Shape::Sphere(r), Bound::MinDihedral(phi))
        },
        |_, b, k| {
            let Bound::MinDihedral(phi) = b else {
                unreachable!()
            };
            let d = m[k as usize].0;
            if close(d, phi) { None } else { Some(d >= phi) }
        },
    );
    eprintln!("dihedral bounds: levels {levels:?}");
    assert!(levels.iter().filter(|&&k| k >= 5).count() > 5);
}

#[test]
fn a_priori_level_is_the_smallest_for_deviation_bounds() {
    let m = measured_unit();
    let levels = check_minimal(
        60,
        2,
        |rng| {
            let r = 10f64.powf(rng.random_range(-3.0..7.0));
            let rel = 10f64.powf(rng.random_range(-5.0..0.0));
            (Shape::Sphere(r), Bound::MaxDeviation(rel * r))
        },
        |s, b, k| {
            let (Shape::Sphere(r), Bound::MaxDeviation(e)) = (s, b) else {
                unreachable!()
            };
            let d = m[k as usize].1 * r; // the radius-r polyhedron is r times the unit one
            if close(d, e) { None } else { Some(d <= e) }
        },
    );
    eprintln!("deviation bounds: levels {levels:?}");
    assert!(levels.iter().filter(|&&k| k >= 5).count() > 5);
}

#[test]
fn a_priori_level_is_the_smallest_for_screen_space_bounds() {
    let m = measured_unit();
    let levels = check_minimal(
        60,
        3,
        |rng| {
            let r = 10f64.powf(rng.random_range(-2.0..7.0));
            let d = r * (1.0 + 10f64.powf(rng.random_range(-2.0..3.0)));
            let pixel = 10f64.powf(rng.random_range(-5.0..-2.0));
            (
                Shape::Sphere(r),
                Bound::ScreenSpace {
                    distance: d,
                    pixel_angle: pixel,
                },
            )
        },
        |s, b, k| {
            let (
                Shape::Sphere(r),
                Bound::ScreenSpace {
                    distance,
                    pixel_angle,
                },
            ) = (s, b)
            else {
                unreachable!()
            };
            let err = lod::screen_space_error(r, distance, m[k as usize].1 * r);
            if close(err, pixel_angle) {
                None
            } else {
                Some(err <= pixel_angle)
            }
        },
    );
    eprintln!("screen-space bounds: levels {levels:?}");
    assert!(levels.iter().filter(|&&k| k >= 4).count() > 5);
}

/// The ellipsoids on which the a-priori level is checked: the Earth (WGS84, nearly a sphere), strongly oblate,
/// prolate, triaxial, and triaxial with the axes in another order.
const ELLIPSOIDS: [(&str, [f64; 3]); 5] = [
    ("WGS84", WGS84),
    ("oblate 1:1:0.3", [1.0, 1.0, 0.3]),
    ("prolate 1:1:3", [1.0, 1.0, 3.0]),
    ("triaxial 3:2:1", [3.0, 2.0, 1.0]),
    ("triaxial 1:3:2", [1.0, 3.0, 2.0]),
];

/// Deepest level measured for the ellipsoid checks.
const TOP: u32 = 8;

/// Measured (smallest dihedral angle, largest deviation) of each of [`ELLIPSOIDS`] at levels `0..=TOP`: built by
/// the kernel, measured by the host's own code (Newell normals over every edge, a bisection for every vertex).
fn measured_ellipsoids() -> &'static [Vec<(f64, f64)>] {
    static M: OnceLock<Vec<Vec<(f64, f64)>>> = OnceLock::new();
    M.get_or_init(|| {
        use rayon::prelude::*;
        ELLIPSOIDS
            .par_iter()
            .map(|&(_, axes)| {
                (0..=TOP)
                    .map(|k| {
                        let shape = Shape::Ellipsoid(axes);
                        let m: Mesh = build(shape, k).unwrap();
                        (min_dihedral(&m), max_deviation(&m, shape))
                    })
                    .collect()
            })
            .collect()
    })
}

/// For each of `n` bounds per ellipsoid (drawn by `draw` from the measured levels, on the ellipsoid scaled by a
/// random factor), checks that `lod::min_level` returns a level that meets the bound when measured while every
/// level below fails it. `meets(scale, axes, bound, (dihedral, deviation)) -> margin`: positive when the measured
/// level meets the bound, with the relative margin; bounds within 1e-9 (relative) of a measured value are
/// skipped (rounding could decide them). Returns the levels, per ellipsoid.
fn check_ellipsoid_minimal(
    kind: &str,
    n: usize,
    seed: u64,
    draw: impl Fn(&mut ChaCha8Rng, [f64; 3], &[(f64, f64)]) -> Bound<f64>,
    meets: impl Fn([f64; 3], Bound<f64>, (f64, f64)) -> (bool, f64),
) -> usize {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut total = 0;
    for ((name, base), m) in ELLIPSOIDS.iter().zip(measured_ellipsoids()) {
        let mut levels = vec![0usize; TOP as usize + 1];
        let mut tight = 0;
        let mut count = 0;
        let mut tries = 0;
        while count < n {
            tries += 1;
            assert!(tries < 100 * n, "too few usable bounds");
            let scale = 10f64.powf(rng.random_range(-3.0..3.0));
            let axes = base.map(|a| a * scale);
            let scaled: Vec<(f64, f64)> = m.iter().map(|&(d, e)| (d, e * scale)).collect();
            // Every fourth bound sits 1e-6 (relative) beside a measured value: the hardest decisions.
            let bound = if count % 4 == 3 {
                tight += 1;
                tight_bound(&mut rng, kind, axes, &scaled)
            } else {
                draw(&mut rng, axes, &scaled)
            };
            let k = lod::min_level(Shape::Ellipsoid(axes), bound).unwrap();
            if k > TOP {
                continue;
            }
            let verdicts: Vec<(bool, f64)> =
                scaled.iter().map(|&x| meets(axes, bound, x)).collect();
            if verdicts.iter().any(|&(_, margin)| margin.abs() < 1e-9) {
                continue;
            }
            assert!(
                verdicts[k as usize].0,
                "{kind} {bound:?} on {name} {axes:?}: level {k} does not meet it (measured {:?})",
                scaled[k as usize]
            );
            for j in 0..k as usize {
                assert!(
                    !verdicts[j].0,
                    "{kind} {bound:?} on {name} {axes:?}: level {j} < {k} already meets it (measured {:?})",
                    scaled[j]
                );
            }
            levels[k as usize] += 1;
            count += 1;
        }
        eprintln!(
            "{kind} on {name}: {count} bounds ({tight} within 1e-6 of a measured value), all minimal; bounds per level {levels:?}"
        );
        assert!(
            levels.iter().filter(|&&c| c > 0).count() >= 6,
            "{kind} on {name}: levels too few"
        );
        total += count;
    }
    total
}

/// A bound 1e-6 (relative) above or below one level's measured value.
fn tight_bound(rng: &mut ChaCha8Rng, kind: &str, axes: [f64; 3], m: &[(f64, f64)]) -> Bound<f64> {
    let k = rng.random_range(0..=TOP as usize);
    let side = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let f = 1.0 + side * 1e-6;
    let (dihedral, deviation) = m[k];
    let r = axes.iter().cloned().fold(0.0, f64::max);
    match kind {
        "dihedral" => {
            Bound::MinDihedral(std::f64::consts::PI - (std::f64::consts::PI - dihedral) * f)
        }
        "deviation" => Bound::MaxDeviation(deviation * f),
        _ => {
            // Far enough that even the cube's corners subtend less than π.
            let distance = (r + 4.0 * m[0].1) * (1.0 + 10f64.powf(rng.random_range(-1.0..2.0)));
            Bound::ScreenSpace {
                distance,
                pixel_angle: lod::screen_space_error(r, distance, deviation) * f,
            }
        }
    }
}

fn log_between(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    10f64.powf(rng.random_range(lo.log10()..hi.log10()))
}

#[test]
fn ellipsoid_a_priori_level_is_the_smallest_for_dihedral_bounds() {
    let total = check_ellipsoid_minimal(
        "dihedral",
        60,
        11,
        |rng, _, m| {
            // The largest normal angle, log-uniform from just below level TOP's to level 0's (90°).
            let x = log_between(rng, 0.9 * (std::f64::consts::PI - m[TOP as usize].0), 1.6);
            Bound::MinDihedral(std::f64::consts::PI - x)
        },
        |_, b, (dihedral, _)| {
            let Bound::MinDihedral(phi) = b else {
                unreachable!()
            };
            (
                dihedral >= phi,
                (dihedral - phi) / (std::f64::consts::PI - phi),
            )
        },
    );
    assert!(total >= 50);
}

#[test]
fn ellipsoid_a_priori_level_is_the_smallest_for_deviation_bounds() {
    let total = check_ellipsoid_minimal(
        "deviation",
        60,
        12,
        |rng, _, m| Bound::MaxDeviation(log_between(rng, 0.9 * m[TOP as usize].1, 1.1 * m[0].1)),
        |_, b, (_, deviation)| {
            let Bound::MaxDeviation(e) = b else {
                unreachable!()
            };
            (deviation <= e, (e - deviation) / e)
        },
    );
    assert!(total >= 50);
}

#[test]
fn ellipsoid_a_priori_level_is_the_smallest_for_screen_space_bounds() {
    let total = check_ellipsoid_minimal(
        "screen-space",
        60,
        13,
        |rng, axes, m| {
            let r = axes.iter().cloned().fold(0.0, f64::max);
            let distance = (r + 4.0 * m[0].1) * (1.0 + log_between(rng, 0.1, 100.0));
            let lo = lod::screen_space_error(r, distance, 0.9 * m[TOP as usize].1);
            let hi = lod::screen_space_error(r, distance, 1.1 * m[0].1);
            Bound::ScreenSpace {
                distance,
                pixel_angle: log_between(rng, lo, hi),
            }
        },
        |axes, b, (_, deviation)| {
            let Bound::ScreenSpace {
                distance,
                pixel_angle,
            } = b
            else {
                unreachable!()
            };
            let r = axes.iter().cloned().fold(0.0, f64::max);
            let err = lod::screen_space_error(r, distance, deviation);
            (err <= pixel_angle, (pixel_angle - err) / pixel_angle)
        },
    );
    assert!(total >= 50);
}

#[test]
fn ellipsoid_worst_case_walk_is_the_measured_worst_case() {
    for ((name, axes), m) in ELLIPSOIDS.iter().zip(measured_ellipsoids()) {
        for (k, &(dihedral, deviation)) in m.iter().enumerate() {
            let w = lod::ellipsoid_worst_case(*axes, k as u32).unwrap();
            let (dd, de) = (
                (w.min_dihedral - dihedral) / (std::f64::consts::PI - dihedral),
                (w.max_deviation - deviation) / deviation,
            );
            assert!(
                dd.abs() < 1e-10 && de.abs() < 1e-10,
                "{name} level {k}: {dd:e} {de:e}"
            );
        }
        eprintln!("{name}: walked worst case = measured, levels 0..={TOP}");
    }
}

#[test]
fn ellipsoid_a_priori_level_time_per_call() {
    // Reported, not asserted: mean wall time of `min_level` per call for bounds whose answer is each level.
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    for ((name, axes), m) in ELLIPSOIDS.iter().zip(measured_ellipsoids()) {
        let mut line = format!(
            "min_level time on {name} (µs per call by level returned: median / mean / max):"
        );
        for k in 0..=TOP as usize {
            let mut times = Vec::new();
            for kind in 0..2 {
                for _ in 0..20 {
                    // A bound between level k's measured value and level k-1's: the answer is k.
                    let t: f64 = rng.random_range(0.0..1.0);
                    let bound = if kind == 0 {
                        let hi = if k == 0 {
                            1.6
                        } else {
                            std::f64::consts::PI - m[k - 1].0
                        };
                        let lo = std::f64::consts::PI - m[k].0;
                        Bound::MinDihedral(std::f64::consts::PI - (lo + t * (hi - lo)))
                    } else {
                        let hi = if k == 0 { 2.0 * m[0].1 } else { m[k - 1].1 };
                        Bound::MaxDeviation(m[k].1 + t * (hi - m[k].1))
                    };
                    let start = std::time::Instant::now();
                    let got = lod::min_level(Shape::Ellipsoid(*axes), std::hint::black_box(bound));
                    let dt = start.elapsed().as_secs_f64() * 1e6;
                    assert_eq!(got, Ok(k as u32), "{name} {bound:?}");
                    times.push(dt);
                }
            }
            times.sort_by(f64::total_cmp);
            let mean = times.iter().sum::<f64>() / times.len() as f64;
            line += &format!(
                " L{k} {:.1}/{mean:.1}/{:.0}",
                times[times.len() / 2],
                times[times.len() - 1]
            );
        }
        eprintln!("{line}");
    }
}

/// Parses an OBJ file: vertices and polygon faces (0-based).
fn parse_obj(text: &str) -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => {
                let p: Vec<f64> = w.map(|x| x.parse().unwrap()).collect();
                assert_eq!(p.len(), 3);
                v.push([p[0], p[1], p[2]]);
            }
            Some("f") => f.push(
                w.map(|x| x.split('/').next().unwrap().parse::<u32>().unwrap() - 1)
                    .collect(),
            ),
            Some("#") | None => {}
            Some(other) => panic!("unexpected OBJ record {other}"),
        }
    }
    (v, f)
}

/// `curvicast tessellate ARGS`: (exit code, stdout, stderr).
fn run_cli(args: &[&str]) -> (i32, String, String) {
    support::run(&[&["tessellate"], args].concat(), "")
}

#[test]
fn cli_obj_loads_as_a_closed_outward_mesh() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (args, axes) in [
        (vec!["--sphere", "2.5", "--level", "3"], [2.5; 3]),
        (
            vec!["--ellipsoid", "3", "2", "1", "--max-deviation", "0.01"],
            [3.0, 2.0, 1.0],
        ),
        (vec!["--sphere", "1", "--max-angle-deg", "10"], [1.0; 3]),
        (
            vec!["--ellipsoid", "4", "1", "2", "--max-angle-deg", "10"],
            [4.0, 1.0, 2.0],
        ),
    ] {
        let obj = dir.join("mesh.obj");
        let mut all = args.clone();
        all.extend(["--out", obj.to_str().unwrap()]);
        let (code, stdout, err) = run_cli(&all);
        assert_eq!(code, 0, "{err}");
        assert_eq!(stdout.lines().count(), 1);
        let j: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
        let (v, f) = parse_obj(&std::fs::read_to_string(&obj).unwrap());
        assert_eq!(j["faces"].as_u64().unwrap() as usize, f.len());
        assert_eq!(j["vertices"].as_u64().unwrap() as usize, v.len());
        let k = j["level"].as_u64().unwrap() as u32;
        assert_eq!(f.len(), bevel::face_count(k));
        closed_edges(&f, v.len());
        // Outward: positive volume, and inside the ellipsoid's box scaled by the level-0 corner distance.
        let mut vol = 0.0;
        for face in &f {
            for t in 1..face.len() - 1 {
                let (a, b, c) = (
                    v[face[0] as usize],
                    v[face[t] as usize],
                    v[face[t + 1] as usize],
                );
                vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]))
                    / 6.0;
            }
        }
        let ellipsoid_vol = 4.0 / 3.0 * std::f64::consts::PI * axes[0] * axes[1] * axes[2];
        assert!(vol > ellipsoid_vol && vol < 8.0 * axes[0] * axes[1] * axes[2] + 1e-9);
        let dev = j["max_deviation"].as_f64().unwrap();
        let dih = j["min_dihedral_deg"].as_f64().unwrap();
        assert!(dev > 0.0 && dih > 90.0 && dih < 180.0);
        // The level is the smallest that meets the bound: the one below, built here, fails it.
        let shape = if axes[0] == axes[2] {
            Shape::Sphere(axes[0])
        } else {
            Shape::Ellipsoid(axes)
        };
        let below = (k > 0).then(|| build(shape, k - 1).unwrap());
        if args.contains(&"--max-deviation") {
            assert!(dev <= 0.01);
            assert!(max_deviation(&below.unwrap(), shape) > 0.01);
        } else if args.contains(&"--max-angle-deg") {
            assert!(dih >= 170.0);
            assert!(min_dihedral(&below.unwrap()).to_degrees() < 170.0);
        }
    }
}

#[test]
fn cli_bad_arguments_exit_2_with_one_line() {
    for args in [
        vec!["--sphere", "1", "--level", "2"],
        vec!["--sphere", "0", "--level", "2", "--out", "x.obj"],
        vec![
            "--sphere",
            "1",
            "--ellipsoid",
            "1",
            "1",
            "1",
            "--level",
            "2",
            "--out",
            "x.obj",
        ],
        vec!["--sphere", "1", "--level", "99", "--out", "x.obj"],
        vec!["--sphere", "1", "--max-deviation", "-1", "--out", "x.obj"],
        vec!["--ellipsoid", "1", "2", "--level", "1", "--out", "x.obj"],
        vec![
            "--sphere",
            "1",
            "--level",
            "1",
            "--out",
            "/nonexistent-dir/x.obj",
        ],
    ] {
        let (code, out, err) = run_cli(&args);
        assert_eq!(code, 2, "{args:?}");
        assert!(out.is_empty(), "{args:?}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    }
}
