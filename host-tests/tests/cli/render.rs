//! `curvicast render` follows the command-line contract: the native projection of the constant ball is the chord
//! to rounding in f64 (both cameras), a coarse Cartesian grid shows its error, the r² field's native error falls as
//! the grid is refined, per-cell data files and every mode work, and bad scene files exit 2 with one line naming
//! the file and nothing written.

use crate::support::{read_f64, run, temp_dir as dir, uniform};
use std::f64::consts::{PI, TAU};
use std::path::Path;

fn grid(nr: usize, nt: usize, np: usize) -> serde_json::Value {
    serde_json::json!({"kind": "spherical", "r": uniform(nr, 0.0, 1.0), "theta": uniform(nt, 0.0, PI), "phi": uniform(np, 0.0, TAU)})
}

const ORTHO_EYE: [f64; 3] = [-3.0, 0.4, 0.7];

fn ortho() -> serde_json::Value {
    serde_json::json!({"kind": "orthographic", "eye": ORTHO_EYE, "look_at": [0, 0, 0], "up": [0, 0, 1], "width": 2.2})
}

/// Runs `render` on `scene` written into `d` (output in `d/out`); returns (exit code, stderr).
pub(super) fn render(d: &Path, scene: &serde_json::Value) -> (i32, String) {
    let path = d.join("scene.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    render_file(&path, &d.join("out"))
}

fn render_file(scene: &Path, out: &Path) -> (i32, String) {
    let args = [
        "render",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, stdout, stderr) = run(&args, "");
    assert!(stdout.is_empty(), "{stdout}");
    (code, stderr)
}

fn read_f32(p: &Path) -> Vec<f32> {
    std::fs::read(p)
        .unwrap()
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// The orthographic pixel ray's closest distance to the origin, from the contract's pixel geometry (written
/// here independently of the renderer's camera).
fn ortho_rho(i: usize, j: usize, w: usize, h: usize) -> f64 {
    let e = ORTHO_EYE;
    let l = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
    let d = e.map(|x| -x / l);
    let up = [0.0, 0.0, 1.0];
    let c = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let right = c(d, up);
    let rl = (right[0] * right[0] + right[1] * right[1] + right[2] * right[2]).sqrt();
    let right = right.map(|x| x / rl);
    let up2 = c(right, d);
    let a = ((j as f64 + 0.5) / w as f64 - 0.5) * 2.2;
    let b = (0.5 - (i as f64 + 0.5) / h as f64) * 2.2 * h as f64 / w as f64;
    let p = [0, 1, 2].map(|k| a * right[k] + b * up2[k]);
    (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
}

/// RMS of the absolute error against `truth(rho)` over the pixels.
fn rms_error(values: &[f64], w: usize, h: usize, truth: impl Fn(f64) -> f64) -> (f64, f64) {
    let (mut s, mut worst_rel) = (0.0, 0.0f64);
    for i in 0..h {
        for j in 0..w {
            let t = truth(ortho_rho(i, j, w, h));
            let e = values[i * w + j] - t;
            s += e * e;
            if t > 1e-3 {
                worst_rel = worst_rel.max(e.abs() / t);
            }
        }
    }
    ((s / (w * h) as f64).sqrt(), worst_rel)
}

fn chord(rho: f64) -> f64 {
    2.0 * (1.0 - rho * rho).max(0.0).sqrt()
}

#[test]
fn constant_ball_native_projection_is_the_chord_in_f64_orthographic() {
    let tmp = dir("ball-ortho");
    let d = tmp.path();
    let (w, h) = (48, 40);
    let scene = serde_json::json!({"grid": grid(5, 7, 9), "field": {"analytic": "ball"}, "camera": ortho(),
        "pixels": [w, h], "mode": "projection", "method": "native", "precision": "f64"});
    let (code, err) = render(d, &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.join("out/values.f64"));
    let (_, worst_rel) = rms_error(&v, w, h, chord);
    assert!(worst_rel < 1e-12, "worst relative error {worst_rel:e}");
    let v32 = read_f32(&d.join("out/values.f32"));
    assert_eq!(v32.len(), w * h);
    assert!(v32.iter().zip(&v).all(|(a, b)| *a == *b as f32));
    let meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("out/render.json")).unwrap()).unwrap();
    assert_eq!(meta["width"], w);
    assert_eq!(meta["height"], h);
    assert_eq!(meta["method"], "native");
    assert_eq!(meta["rays"], w * h);
    assert!(meta["seconds"].as_f64().unwrap() >= 0.0);
    assert!(meta["crossings"].as_u64().unwrap() > (w * h) as u64);
    let png = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(d.join("out/image.png")).unwrap(),
    ));
    let info = png.read_info().unwrap();
    assert_eq!(
        (info.info().width, info.info().height),
        (w as u32, h as u32)
    );
    let (image, iw, _) = read_rgb(&d.join("out/image.png"));
    // figure.png: the same picture enlarged by a whole factor to at least 256 pixels, with a colour bar beside it.
    let (figure, fw, fh) = read_rgb(&d.join("out/figure.png"));
    assert!(fw >= 512 && fh >= 256 + 16, "figure {fw}×{fh}");
    let k = 256_usize.div_ceil(h);
    let (x0, y0) = (16, 16 + 2 * 16); // the margin, and the title's line above the picture
    for (row, col) in [(0, 0), (h / 2, w / 2), (h - 1, w - 1)] {
        let src = &image[(row * iw + col) * 3..][..3];
        let (fx, fy) = (x0 + col * k + k / 2, y0 + row * k + k / 2);
        assert_eq!(
            &figure[(fy * fw + fx) * 3..][..3],
            src,
            "pixel ({row}, {col})"
        );
    }
}

/// The RGB bytes, width and height of a PNG.
fn read_rgb(path: &std::path::Path) -> (Vec<u8>, usize, usize) {
    let mut reader = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (buf, info.width as usize, info.height as usize)
}

#[test]
fn constant_ball_native_projection_is_the_chord_in_f64_perspective() {
    let tmp = dir("ball-persp");
    let d = tmp.path();
    let (w, h) = (32, 32);
    let eye = [0.5, -2.5, 1.2];
    let scene = serde_json::json!({"grid": grid(3, 5, 6), "field": {"analytic": "ball"},
        "camera": {"kind": "perspective", "eye": eye, "look_at": [0.1, 0, -0.1], "up": [0, 0, 1], "fov_deg": 50},
        "pixels": [w, h]});
    let (code, err) = render(d, &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.join("out/values.f64"));
    // the chord of a ray from the eye depends on the ray's closest distance; check the center pixel's neighbourhood
    // exactly through the ray the contract defines, and every pixel against the bound 2R
    let hit = v.iter().filter(|&&x| x > 1e-3).count();
    assert!(hit > w * h / 4, "{hit}");
    assert!(v.iter().all(|&x| (0.0..=2.0 + 1e-12).contains(&x)));
    // center-ish pixel (16, 16): the image-plane point, then the closest distance of the line from the eye
    let dist = {
        let l: [f64; 3] = [0.1 - eye[0], -eye[1], -0.1 - eye[2]];
        (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt()
    };
    let width = 2.0 * dist * (25.0f64).to_radians().tan();
    let dir0 = [0.1 - eye[0], -eye[1], -0.1 - eye[2]].map(|x| x / dist);
    let cr = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let right = cr(dir0, [0.0, 0.0, 1.0]);
    let rl = (right[0] * right[0] + right[1] * right[1] + right[2] * right[2]).sqrt();
    let right = right.map(|x| x / rl);
    let up2 = cr(right, dir0);
    for (i, j) in [(16, 16), (10, 20), (20, 9)] {
        let a = ((j as f64 + 0.5) / w as f64 - 0.5) * width;
        let b = (0.5 - (i as f64 + 0.5) / h as f64) * width;
        let p = [0, 1, 2].map(|k| [0.1, 0.0, -0.1][k] + a * right[k] + b * up2[k]);
        let ray = [0, 1, 2].map(|k| p[k] - eye[k]);
        let rn = (ray[0] * ray[0] + ray[1] * ray[1] + ray[2] * ray[2]).sqrt();
        let u = ray.map(|x| x / rn);
        let c = cr(eye, u);
        let rho = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        let want = chord(rho);
        let got = v[i * w + j];
        assert!(want > 0.1, "pixel ({i}, {j}) misses the ball");
        assert!(
            ((got - want) / want).abs() < 1e-12,
            "({i}, {j}): {got} vs {want}"
        );
    }
}

#[test]
fn coarse_cartesian_ball_shows_its_error_and_finer_voxels_reduce_it() {
    let mut errs = Vec::new();
    for n in [8, 32] {
        let tmp = dir(&format!("ball-cart-{n}"));
        let d = tmp.path();
        let (w, h) = (40, 40);
        let scene = serde_json::json!({"grid": grid(4, 4, 4), "field": {"analytic": "ball"}, "camera": ortho(),
            "pixels": [w, h], "method": {"cartesian": n}});
        let (code, err) = render(d, &scene);
        assert_eq!(code, 0, "{err}");
        let v = read_f64(&d.join("out/values.f64"));
        errs.push(rms_error(&v, w, h, chord).0);
        let meta: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("out/render.json")).unwrap())
                .unwrap();
        assert_eq!(meta["method"], "cartesian");
        assert!(meta["resample_seconds"].as_f64().is_some());
    }
    assert!(errs[0] > 1e-2, "8³ voxels: RMS error {:e}", errs[0]);
    assert!(errs[1] < errs[0] && errs[1] > 1e-4, "{errs:?}");
}

#[test]
fn r2_native_error_falls_as_the_grid_is_refined() {
    let truth = |rho: f64| 2.0 / 3.0 * (1.0 - rho * rho).max(0.0).sqrt() * (1.0 + 2.0 * rho * rho);
    let mut errs = Vec::new();
    for n in [4, 8, 16, 32] {
        let tmp = dir(&format!("r2-{n}"));
        let d = tmp.path();
        let (w, h) = (40, 40);
        let scene = serde_json::json!({"grid": grid(n, 4, 4), "field": {"analytic": "r2"}, "camera": ortho(),
            "pixels": [w, h]});
        let (code, err) = render(d, &scene);
        assert_eq!(code, 0, "{err}");
        errs.push(rms_error(&read_f64(&d.join("out/values.f64")), w, h, truth).0);
    }
    for p in errs.windows(2) {
        assert!(p[1] < 0.6 * p[0], "{errs:?}");
    }
}

#[test]
fn cells_file_with_empty_cells_and_travel_time_and_emission_absorption() {
    let tmp = dir("cells");
    let d = tmp.path();
    // 2 shells × 1 × 1: inner shell speed 2, outer shell empty (NaN)
    let vals: Vec<u8> = [2.0f32, f32::NAN]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(d.join("cells.f32"), vals).unwrap();
    let g = serde_json::json!({"kind": "spherical", "r": [0.0, 0.5, 1.0], "theta": [0.0, PI], "phi": [0.0, TAU]});
    let (w, h) = (24, 24);
    let scene = serde_json::json!({"grid": g, "field": {"cells": "cells.f32"}, "camera": ortho(),
        "pixels": [w, h], "mode": "travel_time"});
    let (code, err) = render(d, &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.join("out/values.f64"));
    for i in 0..h {
        for j in 0..w {
            let rho = ortho_rho(i, j, w, h);
            let want = 2.0 * (0.25 - rho * rho).max(0.0).sqrt() / 2.0;
            assert!((v[i * w + j] - want).abs() < 1e-12, "({i}, {j})");
        }
    }
    let scene = serde_json::json!({"grid": g, "field": {"cells": "cells.f32"}, "camera": ortho(),
        "pixels": [w, h], "mode": {"emission_absorption": {"range": [0.0, 2.0], "opacity": 100.0}}});
    let (code, err) = render(d, &scene);
    assert_eq!(code, 0, "{err}");
    let v = read_f64(&d.join("out/values.f64"));
    // opaque core: intensity 1 · (accumulated opacity ≥ the 0.99 cutoff)
    let center = v[(h / 2) * w + w / 2];
    assert!(center > 0.99 && center <= 1.0, "{center}");
    assert!(v.iter().all(|x| (0.0..=1.0).contains(x)));
}

#[test]
fn bad_scene_files_exit_2_with_one_line_naming_the_file_and_write_nothing() {
    let tmp = dir("bad");
    let d = tmp.path();
    let good = serde_json::json!({"grid": grid(2, 2, 2), "field": {"analytic": "ball"}, "camera": ortho(),
        "pixels": [4, 4]});
    let mut cases: Vec<(&str, String)> = vec![("not-json.json", "{".into())];
    let mut edit = |name: &'static str, f: &dyn Fn(&mut serde_json::Value)| {
        let mut s = good.clone();
        f(&mut s);
        cases.push((name, s.to_string()));
    };
    edit("polar-cartesian.json", &|s| {
        s["grid"] = serde_json::json!({"kind": "polar", "r": [0, 1], "phi": [0, 1]});
        s["method"] = serde_json::json!({"cartesian": 8})
    });
    edit("unsorted.json", &|s| {
        s["grid"]["r"] = serde_json::json!([0.0, 1.0, 0.5])
    });
    edit("zero-pixels.json", &|s| {
        s["pixels"] = serde_json::json!([0, 4])
    });
    edit("cartesian-0.json", &|s| {
        s["method"] = serde_json::json!({"cartesian": 0})
    });
    edit("up-along-view.json", &|s| {
        s["camera"]["up"] = serde_json::json!([-3.0, 0.4, 0.7])
    });
    edit("two-fields.json", &|s| {
        s["field"] = serde_json::json!({"analytic": "ball", "cells": "x.f32"})
    });
    edit("unknown-mode.json", &|s| {
        s["mode"] = serde_json::json!("mip")
    });
    edit("bad-precision.json", &|s| {
        s["precision"] = serde_json::json!("f16")
    });
    edit("missing-cells.json", &|s| {
        s["field"] = serde_json::json!({"cells": "nowhere.f32"})
    });
    edit("short-cells.json", &|s| {
        s["field"] = serde_json::json!({"cells": "short.f32"})
    });
    std::fs::write(d.join("short.f32"), [0u8; 12]).unwrap();
    for (name, text) in &cases {
        let path = d.join(name);
        std::fs::write(&path, text).unwrap();
        let out = d.join(format!("out-{name}"));
        let (code, err) = render_file(&path, &out);
        assert_eq!(code, 2, "{name}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: {err}");
        let named = if name.contains("cells") && !name.contains("two") {
            if name.starts_with("missing") {
                "nowhere.f32"
            } else {
                "short.f32"
            }
        } else {
            name
        };
        assert!(err.contains(named), "{name}: {err}");
        assert!(!out.exists(), "{name}: wrote {}", out.display());
    }
}

#[test]
fn single_precision_native_projection_is_close_to_f64() {
    let (w, h) = (24, 24);
    let mut base = Vec::new();
    for precision in ["f64", "f32", "f32-fast"] {
        let tmp = dir(&format!("prec-{precision}"));
        let d = tmp.path();
        let scene = serde_json::json!({"grid": grid(8, 6, 6), "field": {"analytic": "r2"}, "camera": ortho(),
            "pixels": [w, h], "precision": precision});
        let (code, err) = render(d, &scene);
        assert_eq!(code, 0, "{err}");
        let v = read_f64(&d.join("out/values.f64"));
        let meta: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("out/render.json")).unwrap())
                .unwrap();
        assert_eq!(meta["precision"], precision);
        if base.is_empty() {
            base = v;
        } else {
            let worst = v
                .iter()
                .zip(&base)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-4 && worst > 0.0, "{precision}: {worst:e}");
        }
    }
}
