//! `curvicast render` on cylindrical and polar grids: the analytic fields are functions of the distance from the
//! grid's axis, cell averages weighted by the area element `ρ dρ` (docs/formats.md, `curvicast render`). Pixel values are
//! held to closed forms derived here from the contract's pixel geometry: the chord of the constant "ball" (an
//! infinite cylinder, cut by the cylindrical grid's height range), the exact sum over annuli of the piecewise
//! constant r² field, its convergence to the continuous `(2/3)h(R² + 2d²)`, an oblique view of a polar wedge (a
//! polar grid ignores z: lengths grow by 1/|d_xy|), and the Cartesian baseline of a cylindrical grid, whose error
//! falls as its voxels shrink. A polar grid has no bounding cube, so its Cartesian baseline is exit 2.

use super::render::render;
use crate::support::{read_f64, uniform};
use std::f64::consts::{FRAC_PI_2, SQRT_2, TAU};
use std::path::Path;

fn meta(d: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(d.join("out/render.json")).unwrap()).unwrap()
}

const WIDTH: f64 = 2.2;

/// The contract's image-plane offsets `(a, b)` of pixel (i, j): `a` along `right`, `b` along `up'`.
fn offsets(i: usize, j: usize, w: usize, h: usize) -> (f64, f64) {
    let a = ((j as f64 + 0.5) / w as f64 - 0.5) * WIDTH;
    let b = (0.5 - (i as f64 + 0.5) / h as f64) * WIDTH * h as f64 / w as f64;
    (a, b)
}

/// The length of the line at distance `d` from the axis inside the annulus `r0 ≤ ρ < r1` (both halves).
fn annulus_chord(d: f64, r0: f64, r1: f64) -> f64 {
    let half = |r: f64| (r * r - d * d).max(0.0).sqrt();
    2.0 * (half(r1) - half(r0))
}

/// A side view of a cylindrical grid around the z axis through (0, 0, 0): the camera looks along +x from x = −3
/// at height 0.1 with up +z, so `right` is −y and `up'` is +z; pixel (i, j) is the line y = −a, z = 0.1 + b, at
/// distance |a| from the axis.
fn side_camera() -> serde_json::Value {
    serde_json::json!({"kind": "orthographic", "eye": [-3.0, 0.0, 0.1], "look_at": [0.0, 0.0, 0.1],
        "up": [0.0, 0.0, 1.0], "width": WIDTH})
}

const Z: [f64; 4] = [-0.5, -0.1, 0.3, 0.6];

fn cylinder(n_rho: usize) -> serde_json::Value {
    serde_json::json!({"kind": "cylindrical", "rho": uniform(n_rho, 0.0, 1.0), "phi": uniform(7, 0.0, TAU),
        "z": Z})
}

#[test]
fn cylindrical_constant_ball_projection_is_the_chord_inside_the_height_range() {
    let d = tempfile::tempdir().unwrap();
    let (w, h) = (40, 30);
    let scene = serde_json::json!({"grid": cylinder(5), "field": {"analytic": "ball"}, "camera": side_camera(),
        "pixels": [w, h]});
    let (code, err) = render(d.path(), &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.path().join("out/values.f64"));
    let (mut inside, mut outside) = (0, 0);
    for i in 0..h {
        for j in 0..w {
            let (a, b) = offsets(i, j, w, h);
            let z = 0.1 + b;
            let want = if (Z[0]..Z[3]).contains(&z) {
                inside += 1;
                annulus_chord(a, 0.0, 1.0)
            } else {
                outside += 1;
                0.0
            };
            let got = v[i * w + j];
            assert!(
                (got - want).abs() <= 1e-12 * want.max(1e-3),
                "({i}, {j}): {got} against {want}"
            );
        }
    }
    assert!(inside > 500 && outside > 100, "{inside} {outside}");
    let m = meta(d.path());
    assert_eq!(m["grid"], "cylindrical");
    assert_eq!(m["cells"], serde_json::json!([5, 7, 3]));
    assert!(m["crossings"].as_u64().unwrap() > inside as u64);
}

#[test]
fn cylindrical_r2_cells_sum_exactly_over_annuli_and_converge_to_the_closed_form() {
    let (w, h) = (36, 12);
    let mut worst_continuous = Vec::new();
    for n_rho in [4, 16, 64] {
        let d = tempfile::tempdir().unwrap();
        let scene = serde_json::json!({"grid": cylinder(n_rho), "field": {"analytic": "r2"},
            "camera": side_camera(), "pixels": [w, h]});
        let (code, err) = render(d.path(), &scene);
        assert_eq!(code, 0, "{err}");
        let v = read_f64(&d.path().join("out/values.f64"));
        let rho = uniform(n_rho, 0.0, 1.0);
        let mut worst = 0.0f64;
        for i in 0..h {
            for j in 0..w {
                let (a, b) = offsets(i, j, w, h);
                if !(Z[0]..Z[3]).contains(&(0.1 + b)) {
                    continue;
                }
                // each annulus holds the area-weighted mean of ρ² over it, (ρ0² + ρ1²) / 2
                let cells: f64 = rho
                    .windows(2)
                    .map(|r| (r[0] * r[0] + r[1] * r[1]) / 2.0 * annulus_chord(a, r[0], r[1]))
                    .sum();
                let got = v[i * w + j];
                assert!(
                    (got - cells).abs() <= 1e-12 * cells.max(1e-3),
                    "{n_rho} cells, ({i}, {j}): {got} against {cells}"
                );
                let hh = (1.0 - a * a).max(0.0).sqrt();
                let continuous = 2.0 / 3.0 * hh * (1.0 + 2.0 * a * a);
                worst = worst.max((got - continuous).abs());
            }
        }
        worst_continuous.push(worst);
    }
    // the piecewise-constant error shrinks with the radial cell width
    assert!(worst_continuous[0] > 1e-3, "{worst_continuous:?}");
    assert!(
        worst_continuous[1] < worst_continuous[0] / 3.0,
        "{worst_continuous:?}"
    );
    assert!(
        worst_continuous[2] < worst_continuous[1] / 3.0,
        "{worst_continuous:?}"
    );
}

#[test]
fn cylindrical_cartesian_baseline_error_falls_with_finer_voxels() {
    let (w, h) = (32, 32);
    let mut rms = Vec::new();
    for n in [8, 64] {
        let d = tempfile::tempdir().unwrap();
        let scene = serde_json::json!({"grid": cylinder(5), "field": {"analytic": "ball"},
            "camera": side_camera(), "pixels": [w, h], "method": {"cartesian": n}});
        let (code, err) = render(d.path(), &scene);
        assert_eq!(code, 0, "{err}");
        let v = read_f64(&d.path().join("out/values.f64"));
        let mut s = 0.0;
        for i in 0..h {
            for j in 0..w {
                let (a, b) = offsets(i, j, w, h);
                let want = if (Z[0]..Z[3]).contains(&(0.1 + b)) {
                    annulus_chord(a, 0.0, 1.0)
                } else {
                    0.0
                };
                s += (v[i * w + j] - want).powi(2);
            }
        }
        rms.push((s / (w * h) as f64).sqrt());
        let m = meta(d.path());
        assert_eq!(m["method"], "cartesian");
        assert!(m["resample_seconds"].as_f64().unwrap() >= 0.0);
    }
    assert!(rms[0] > 1e-2, "{rms:?}");
    assert!(rms[1] < rms[0] / 2.0, "{rms:?}");
}

/// A polar wedge (the right half-disc x ≥ cx around a shifted center) seen obliquely: the camera looks along
/// (1, 0, −1)/√2, so `right` is −y, and pixel (i, j) projects onto the xy line y = cy − a, crossed along x; a
/// polar grid ignores z, so each unit of that line costs √2 of the ray.
#[test]
fn polar_wedge_oblique_view_is_half_the_chord_times_the_slant() {
    let d = tempfile::tempdir().unwrap();
    let (w, h) = (30, 10);
    let c = [0.1, -0.2];
    let scene = serde_json::json!({
        "grid": {"kind": "polar", "center": c, "r": uniform(4, 0.0, 1.0), "phi": [-FRAC_PI_2, 0.0, FRAC_PI_2]},
        "field": {"analytic": "ball"},
        "camera": {"kind": "orthographic", "eye": [c[0] - 3.0, c[1], 3.0], "look_at": [c[0], c[1], 0.0],
            "up": [0.0, 0.0, 1.0], "width": WIDTH},
        "pixels": [w, h]});
    let (code, err) = render(d.path(), &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.path().join("out/values.f64"));
    for i in 0..h {
        for j in 0..w {
            let (a, _) = offsets(i, j, w, h);
            let want = SQRT_2 * annulus_chord(a, 0.0, 1.0) / 2.0;
            let got = v[i * w + j];
            assert!(
                (got - want).abs() <= 1e-12 * want.max(1e-3),
                "({i}, {j}): {got} against {want}"
            );
        }
    }
    let m = meta(d.path());
    assert_eq!(m["grid"], "polar");
    assert_eq!(m["cells"], serde_json::json!([4, 2]));
}

#[test]
fn polar_r2_emission_absorption_and_travel_time_follow_the_cells() {
    let (w, h) = (24, 4);
    let grid = serde_json::json!({"kind": "polar", "r": [0.0, 0.5, 1.0], "phi": [0.0, TAU]});
    // travel time through speeds r²-averaged per annulus: Σ length / ((r0² + r1²) / 2)
    let d = tempfile::tempdir().unwrap();
    let scene = serde_json::json!({"grid": grid, "field": {"analytic": "r2"}, "camera": side_camera(),
        "pixels": [w, h], "mode": "travel_time", "precision": "f32"});
    let (code, err) = render(d.path(), &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.path().join("out/values.f64"));
    for i in 0..h {
        for j in 0..w {
            let (a, _) = offsets(i, j, w, h);
            let want = annulus_chord(a, 0.0, 0.5) / 0.125 + annulus_chord(a, 0.5, 1.0) / 0.625;
            let got = v[i * w + j];
            assert!(
                (got - want).abs() <= 1e-5 * want.max(1.0),
                "f32 ({i}, {j}): {got} against {want}"
            );
        }
    }
    // emission–absorption with the default transfer function: finite, in [0, 1], brightest through the middle
    let d = tempfile::tempdir().unwrap();
    let scene = serde_json::json!({"grid": grid, "field": {"analytic": "r2"}, "camera": side_camera(),
        "pixels": [w, h], "mode": {"emission_absorption": {}}});
    let (code, err) = render(d.path(), &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.path().join("out/values.f64"));
    assert!(v.iter().all(|x| (0.0..=1.0).contains(x)), "{v:?}");
    assert!(v[w / 2] > v[1] && v[w / 2] > 0.1, "{v:?}");
}

#[test]
fn polar_cartesian_and_bad_cylinders_exit_2_with_one_line_and_write_nothing() {
    let cases = [
        (
            "polar-cartesian",
            serde_json::json!({"grid": {"kind": "polar", "r": [0.0, 1.0], "phi": [0.0, TAU]},
                "field": {"analytic": "ball"}, "camera": side_camera(), "pixels": [4, 4],
                "method": {"cartesian": 16}}),
            "polar grid",
        ),
        (
            "cylinder-unsorted-z",
            serde_json::json!({"grid": {"kind": "cylindrical", "rho": [0.0, 1.0], "phi": [0.0, TAU],
                "z": [0.0, 1.0, 0.5]}, "field": {"analytic": "ball"}, "camera": side_camera(), "pixels": [4, 4]}),
            "grid",
        ),
        (
            "polar-short-cells",
            serde_json::json!({"grid": {"kind": "polar", "r": [0.0, 0.5, 1.0], "phi": [0.0, 1.0, TAU]},
                "field": {"cells": "short.f32"}, "camera": side_camera(), "pixels": [4, 4]}),
            "short.f32",
        ),
    ];
    for (name, scene, says) in cases {
        let d = tempfile::tempdir().unwrap();
        // a polar grid of 2 × 2 cells needs 16 bytes
        std::fs::write(d.path().join("short.f32"), [0u8; 12]).unwrap();
        let (code, err) = render(d.path(), &scene);
        assert_eq!(code, 2, "{name}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
        assert!(!d.path().join("out").exists(), "{name}");
    }
}

/// A cylinder whose axis passes through (0.3, −0.2, 1) (its z breakpoints relative to that center's z), seen
/// from the side: native in f64 is the chord to rounding, and the Cartesian baseline's cube follows the axis and
/// the height range (64³ voxels stay close to the chord; a cube left at the origin would miss most of it).
#[test]
fn cylindrical_grid_off_the_origin_native_and_cartesian_follow_its_center() {
    let c = [0.3, -0.2, 1.0];
    let (w, h) = (32, 24);
    let camera = serde_json::json!({"kind": "orthographic", "eye": [c[0] - 3.0, c[1], c[2] + 0.1],
        "look_at": [c[0], c[1], c[2] + 0.1], "up": [0.0, 0.0, 1.0], "width": WIDTH});
    let grid = serde_json::json!({"kind": "cylindrical", "center": c, "rho": uniform(3, 0.0, 1.0),
        "phi": uniform(5, 0.0, TAU), "z": Z});
    let truth = |i: usize, j: usize| {
        let (a, b) = offsets(i, j, w, h);
        if (Z[0]..Z[3]).contains(&(0.1 + b)) {
            annulus_chord(a, 0.0, 1.0)
        } else {
            0.0
        }
    };
    for (method, tolerance) in [
        (serde_json::json!("native"), 1e-12),
        (serde_json::json!({"cartesian": 64}), 0.1),
    ] {
        let d = tempfile::tempdir().unwrap();
        let scene = serde_json::json!({"grid": grid, "field": {"analytic": "ball"}, "camera": camera,
            "pixels": [w, h], "method": method});
        let (code, err) = render(d.path(), &scene);
        assert_eq!(code, 0, "{err}");
        let v = read_f64(&d.path().join("out/values.f64"));
        let mut s = 0.0;
        for i in 0..h {
            for j in 0..w {
                let want = truth(i, j);
                let got = v[i * w + j];
                s += (got - want).powi(2);
                if tolerance < 1e-6 {
                    assert!(
                        (got - want).abs() <= tolerance * want.max(1e-3),
                        "({i}, {j}): {got} against {want}"
                    );
                }
            }
        }
        let rms = (s / (w * h) as f64).sqrt();
        assert!(rms < tolerance, "{method}: rms {rms}");
    }
}

/// A polar grid seen straight down its axis: each ray's trace in the xy plane is a point, so a ray that starts
/// in a cell stays in it for ever. A cell holding the step's 1 gives an infinite projection, a cell holding 0
/// gives 0 (not 0 · ∞), and rays outside the annulus give 0.
#[test]
fn polar_grid_seen_along_its_axis_is_infinite_in_filled_cells_and_zero_elsewhere() {
    let d = tempfile::tempdir().unwrap();
    let (w, h) = (20, 20);
    let scene = serde_json::json!({
        "grid": {"kind": "polar", "r": [0.5, 1.0, 1.5], "phi": [0.0, TAU]},
        "field": {"analytic": "step", "radius": 1.0},
        "camera": {"kind": "orthographic", "eye": [0.0, 0.0, 3.0], "look_at": [0.0, 0.0, 0.0],
            "up": [0.0, 1.0, 0.0], "width": 3.2},
        "pixels": [w, h]});
    let (code, err) = render(d.path(), &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.path().join("out/values.f64"));
    let mut filled = 0;
    for i in 0..h {
        for j in 0..w {
            // the camera's right is +x and its up' is +y
            let a = ((j as f64 + 0.5) / w as f64 - 0.5) * 3.2;
            let b = (0.5 - (i as f64 + 0.5) / h as f64) * 3.2;
            let rho = a.hypot(b);
            let got = v[i * w + j];
            if (0.5..1.0).contains(&rho) {
                filled += 1;
                assert_eq!(got, f64::INFINITY, "({i}, {j}) at ρ = {rho}");
            } else {
                assert_eq!(got, 0.0, "({i}, {j}) at ρ = {rho}");
            }
        }
    }
    assert!(filled > 50, "{filled}");
}
