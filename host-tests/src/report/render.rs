//! Report section: error against runtime, native against Cartesian (Hannasch §6.2–6.3, Fig. 6.13 and 6.14).
//!
//! For each scene, the same camera's rays are cast through a ladder of native grids (each rung discards every
//! other breakpoint of the one above, §6.3, the coarse cells holding the volume-weighted mean of the fine ones)
//! and through a ladder of Cartesian `N³` resamplings of the finest grid (Amanatides–Woo; the resampling timed
//! apart and not charged, as in §6.3). Every image is compared with the truth: closed forms for the analytic
//! fields, quadrature of the model for PREM, the finest native grid for the ocean. The conclusions are computed
//! from these runs.

use super::plot::{Labels, Series, loglog_svg};
use super::{Options, Section};
use curvicast_cli::cli::march::Precision;
use curvicast_cli::render::camera::{Camera, CameraSpec};
use curvicast_cli::render::cartesian::VoxelValues;
use curvicast_cli::render::data::{self, EARTH_RADIUS_M};
use curvicast_cli::render::field::{Analytic, SphericalCells, closest_distance};
use curvicast_cli::render::image::{
    ColorMap, Panel, Rgb, Scale, colorize, figure, finite_range, quantile_range, write_png,
};
use curvicast_cli::render::sampler::{Mode, Transfer};
use curvicast_cli::render::{Method, Rendered, Scene, render, render_cartesian};
use std::f64::consts::{PI, TAU};
use std::fmt::Write as _;
use std::time::Instant;

/// The error of an image against the truth, over the pixels whose ray meets the field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageError {
    /// Root mean square of the absolute error.
    pub rms_abs: f64,
    /// Largest absolute error.
    pub max_abs: f64,
    /// `rms_abs` over the root mean square of the truth.
    pub rms_rel: f64,
    /// `max_abs` over the largest truth.
    pub max_rel: f64,
}

/// Compares `values` with `truth` over the pixels where either is non-zero.
pub fn image_error(values: &[f64], truth: &[f64]) -> ImageError {
    let (mut n, mut se, mut st, mut max_abs, mut max_t) = (0usize, 0.0, 0.0, 0.0f64, 0.0f64);
    for (&v, &t) in values.iter().zip(truth) {
        if v == 0.0 && t == 0.0 {
            continue;
        }
        let e = if v.is_finite() {
            (v - t).abs()
        } else {
            f64::INFINITY
        };
        n += 1;
        se += e * e;
        st += t * t;
        max_abs = max_abs.max(e);
        max_t = max_t.max(t.abs());
    }
    let n = n.max(1) as f64;
    let rms_abs = (se / n).sqrt();
    ImageError {
        rms_abs,
        max_abs,
        rms_rel: rms_abs / (st / n).sqrt(),
        max_rel: max_abs / max_t,
    }
}

/// One configuration's measured run.
#[derive(Debug, Clone)]
struct Run {
    native: bool,
    label: String,
    seconds: f64,
    resample: Option<f64>,
    crossings_per_ray: f64,
    err: ImageError,
    values: Vec<f64>,
}

/// A scene of the study.
struct Study {
    key: &'static str,
    title: String,
    unit: &'static str,
    fine: SphericalCells,
    values: Vec<f64>,
    camera: CameraSpec,
    pixels: [usize; 2],
    mode: Mode,
    truth: Vec<f64>,
    /// Native rungs below the finest.
    coarsenings: usize,
    /// Whether the finest grid is a rung (not when it is the truth).
    finest_is_rung: bool,
    cartesian: Vec<usize>,
    /// Write the native / Cartesian / error comparison image.
    images: bool,
}

fn min_time(reps: usize, f: impl Fn() -> Rendered) -> Rendered {
    // the first render also starts the thread pool and warms the caches: not timed
    let _ = f();
    let mut best = f();
    for _ in 1..reps {
        let r = f();
        if r.seconds < best.seconds {
            best = r;
        }
    }
    best
}

fn scene_of(
    st: &Study,
    grid: SphericalCells,
    values: Vec<f64>,
    method: Method,
) -> anyhow::Result<Scene> {
    Ok(Scene {
        grid: grid.into(),
        values,
        camera: Camera::new(&st.camera, st.pixels).map_err(anyhow::Error::msg)?,
        pixels: st.pixels,
        mode: st.mode,
        method,
        precision: Precision::F64,
    })
}

fn cells_label([a, b, c]: [usize; 3]) -> String {
    format!("{a}×{b}×{c}")
}

fn run_study(st: &Study, reps: usize) -> anyhow::Result<Vec<Run>> {
    let none = || {};
    let mut runs = Vec::new();
    // native ladder, finest first
    let mut rungs = vec![(st.fine.clone(), st.values.clone())];
    for _ in 0..st.coarsenings {
        let (g, v) = {
            let (g, v) = rungs
                .last()
                .ok_or_else(|| anyhow::anyhow!("empty ladder"))?;
            g.coarsen(v)
        };
        rungs.push((g, v));
    }
    if !st.finest_is_rung {
        rungs.remove(0);
    }
    for (g, v) in rungs.into_iter().rev() {
        let label = cells_label(g.shape());
        let scene = scene_of(st, g, v, Method::Native)?;
        let out = min_time(reps, || render(&scene, &none));
        runs.push(Run {
            native: true,
            label,
            seconds: out.seconds,
            resample: None,
            crossings_per_ray: out.crossings as f64 / out.rays as f64,
            err: image_error(&out.values, &st.truth),
            values: out.values,
        });
    }
    for &n in &st.cartesian {
        let scene = scene_of(st, st.fine.clone(), st.values.clone(), Method::Cartesian(n))?;
        let start = Instant::now();
        let voxels =
            VoxelValues::resample(&scene.grid, &scene.values, n).map_err(anyhow::Error::msg)?;
        let resample = start.elapsed().as_secs_f64();
        let out = min_time(reps, || render_cartesian(&scene, &voxels, &none));
        drop(voxels);
        runs.push(Run {
            native: false,
            label: format!("{n}³"),
            seconds: out.seconds,
            resample: Some(resample),
            crossings_per_ray: out.crossings as f64 / out.rays as f64,
            err: image_error(&out.values, &st.truth),
            values: out.values,
        });
    }
    Ok(runs)
}

fn ms(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.2} s")
    } else {
        format!("{:.1} ms", s * 1e3)
    }
}

/// The cheapest run of one method whose RMS relative error is at most `target`.
fn cheapest(runs: &[Run], native: bool, target: f64) -> Option<&Run> {
    runs.iter()
        .filter(|r| r.native == native && r.err.rms_rel <= target)
        .min_by(|a, b| a.seconds.total_cmp(&b.seconds))
}

fn conclusions(runs: &[Run]) -> String {
    let mut s = String::new();
    for target in [1e-2, 1e-3, 1e-4] {
        let n = cheapest(runs, true, target);
        let c = cheapest(runs, false, target);
        let best = |native: bool| {
            runs.iter()
                .filter(|r| r.native == native)
                .min_by(|a, b| a.err.rms_rel.total_cmp(&b.err.rms_rel))
                .map(|r| format!("best {:.1e} at {}", r.err.rms_rel, r.label))
                .unwrap_or_default()
        };
        let _ = match (n, c) {
            (Some(n), Some(c)) => writeln!(
                s,
                "- RMS relative error ≤ {target:.0e}: native {} cells in {}, Cartesian {} voxels in {} (plus {} \
                 resampling): native is {:.1}× {}.",
                n.label,
                ms(n.seconds),
                c.label,
                ms(c.seconds),
                ms(c.resample.unwrap_or(0.0)),
                if n.seconds <= c.seconds {
                    c.seconds / n.seconds
                } else {
                    n.seconds / c.seconds
                },
                if n.seconds <= c.seconds {
                    "faster"
                } else {
                    "slower"
                },
            ),
            (Some(n), None) => writeln!(
                s,
                "- RMS relative error ≤ {target:.0e}: native {} cells in {}; no Cartesian grid of the ladder reaches \
                 it ({}).",
                n.label,
                ms(n.seconds),
                best(false)
            ),
            (None, Some(c)) => writeln!(
                s,
                "- RMS relative error ≤ {target:.0e}: Cartesian {} voxels in {}; no native grid of the ladder \
                 reaches it ({}).",
                c.label,
                ms(c.seconds),
                best(true)
            ),
            (None, None) => writeln!(
                s,
                "- RMS relative error ≤ {target:.0e}: neither ladder reaches it (native {}, Cartesian {}).",
                best(true),
                best(false)
            ),
        };
    }
    s
}

/// Native, Cartesian, and both absolute-error maps on one scale, side by side.
fn comparison_image(
    st: &Study,
    native: &Run,
    cart: &Run,
    path: &std::path::Path,
) -> anyhow::Result<()> {
    let [w, h] = st.pixels;
    let range = quantile_range(&st.truth, 0.99);
    let en: Vec<f64> = native
        .values
        .iter()
        .zip(&st.truth)
        .map(|(v, t)| (v - t).abs())
        .collect();
    let ec: Vec<f64> = cart
        .values
        .iter()
        .zip(&st.truth)
        .map(|(v, t)| (v - t).abs())
        .collect();
    let emax = quantile_range(&en, 0.99)[1].max(quantile_range(&ec, 0.99)[1]);
    let images: [Rgb; 4] = [
        colorize(&native.values, w, h, range, ColorMap::Viridis),
        colorize(&cart.values, w, h, range, ColorMap::Viridis),
        colorize(&en, w, h, [0.0, emax], ColorMap::Magma),
        colorize(&ec, w, h, [0.0, emax], ColorMap::Magma),
    ];
    let [vn, vc, errn, errc] = &images;
    let values = [
        Panel {
            image: vn,
            title: "native",
        },
        Panel {
            image: vc,
            title: "Cartesian",
        },
    ];
    let errors = [
        Panel {
            image: errn,
            title: "|native - truth|",
        },
        Panel {
            image: errc,
            title: "|Cartesian - truth|",
        },
    ];
    let value_scale = Scale {
        range,
        map: ColorMap::Viridis,
        unit: st.unit,
    };
    let error_scale = Scale {
        range: [0.0, emax],
        map: ColorMap::Magma,
        unit: st.unit,
    };
    write_png(
        path,
        &figure(&[(&values, value_scale), (&errors, error_scale)]),
    )
}

fn study_markdown(st: &Study, runs: &[Run], opts: &Options) -> anyhow::Result<String> {
    let mut md = String::new();
    let _ = writeln!(md, "### {}\n", st.title);
    let svg = format!("error_runtime_{}.svg", st.key);
    let series = |native: bool, name: &str| Series {
        name: name.to_string(),
        points: runs
            .iter()
            .filter(|r| r.native == native)
            .map(|r| (r.seconds, r.err.rms_rel))
            .collect(),
        labels: runs
            .iter()
            .filter(|r| r.native == native)
            .map(|r| r.label.clone())
            .collect(),
    };
    loglog_svg(
        &opts.out_dir.join(&svg),
        Labels {
            title: &format!("{}: RMS relative error against runtime", st.key),
            x: "seconds to cast the image's rays (2 threads)",
            y: "RMS relative error",
        },
        &[
            series(true, "native (serial engine, f64)"),
            series(false, "Cartesian N³ + Amanatides–Woo"),
        ],
    )?;
    let _ = writeln!(md, "![error against runtime, {}]({svg})\n", st.key);
    let _ = writeln!(
        md,
        "| method | grid | seconds | resampling | crossings/ray | RMS abs ({u}) | max abs ({u}) | RMS rel | max rel |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|",
        u = st.unit
    );
    for r in runs {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.0} | {:.2e} | {:.2e} | {:.2e} | {:.2e} |",
            if r.native { "native" } else { "Cartesian" },
            r.label,
            ms(r.seconds),
            r.resample.map_or("—".into(), ms),
            r.crossings_per_ray,
            r.err.rms_abs,
            r.err.max_abs,
            r.err.rms_rel,
            r.err.max_rel
        );
    }
    md.push('\n');
    md.push_str(&conclusions(runs));
    if st.images {
        // the middle native rung, and the Cartesian run closest to it in time
        let natives: Vec<&Run> = runs.iter().filter(|r| r.native).collect();
        let n = natives.get(natives.len() / 2).copied();
        let c = n.and_then(|n| {
            runs.iter().filter(|r| !r.native).min_by(|a, b| {
                (a.seconds / n.seconds)
                    .ln()
                    .abs()
                    .total_cmp(&(b.seconds / n.seconds).ln().abs())
            })
        });
        if let (Some(n), Some(c)) = (n, c) {
            let png = format!("compare_{}.png", st.key);
            comparison_image(st, n, c, &opts.out_dir.join(&png))?;
            let _ = writeln!(
                md,
                "\n![native, Cartesian, |native − truth|, |Cartesian − truth|]({png})\n\n\
                 Left to right: native {} cells ({}), Cartesian {} voxels ({}, the Cartesian run closest in time), \
                 then the absolute error of each against the truth on one colour scale (magma). Colour scales end at \
                 the 99th percentile, so that a few limb pixels do not wash out the rest.",
                n.label,
                ms(n.seconds),
                c.label,
                ms(c.seconds),
            );
        }
    }
    md.push('\n');
    Ok(md)
}

fn uniform(n: usize, hi: f64) -> Vec<f64> {
    (0..=n)
        .map(|i| if i == n { hi } else { hi * i as f64 / n as f64 })
        .collect()
}

fn truth_image(
    camera: &CameraSpec,
    pixels: [usize; 2],
    f: impl Fn([f64; 3], [f64; 3]) -> f64,
) -> anyhow::Result<Vec<f64>> {
    let cam = Camera::new(camera, pixels).map_err(anyhow::Error::msg)?;
    let [w, h] = pixels;
    Ok((0..w * h)
        .map(|p| {
            let (o, d) = cam.ray(p / w, p % w);
            f(o, d)
        })
        .collect())
}

fn analytic_study(kind: Analytic, radius: f64, quick: bool) -> anyhow::Result<Study> {
    let k = if quick { 32 } else { 128 };
    let fine = SphericalCells {
        center: [0.0; 3],
        r: uniform(k, 1.0),
        theta: uniform(k, PI),
        phi: uniform(k, TAU),
    };
    let values = kind.cell_averages(&fine, radius);
    let camera = CameraSpec::Orthographic {
        eye: [-3.0, 0.9, 1.3],
        look_at: [0.0; 3],
        up: [0.0, 0.0, 1.0],
        width: 2.2,
    };
    let pixels = if quick { [96, 96] } else { [200, 200] };
    let truth = truth_image(&camera, pixels, |o, d| {
        kind.projection(radius, closest_distance([0.0; 3], o, d))
    })?;
    let (key, title) = match kind {
        Analytic::Ball => (
            "ball",
            "Constant ball (density 1, R = 1; truth 2√(R² − ρ²))".to_string(),
        ),
        Analytic::Step => (
            "step",
            format!(
                "Step (1 for r ≤ {radius}, 0 beyond, off every breakpoint; truth: the chord inside it)"
            ),
        ),
        Analytic::R2 => (
            "r2",
            "r² (R = 1; truth (2/3)√(R² − ρ²)(R² + 2ρ²))".to_string(),
        ),
    };
    Ok(Study {
        key,
        title,
        unit: "length units",
        fine,
        values,
        camera,
        pixels,
        mode: Mode::Projection,
        truth,
        coarsenings: if quick { 3 } else { 5 },
        finest_is_rung: true,
        cartesian: if quick {
            vec![16, 32, 64, 128]
        } else {
            vec![16, 32, 64, 128, 256]
        },
        images: kind == Analytic::R2,
    })
}

fn ocean_globe_camera() -> CameraSpec {
    // from space above 20°N 30°W (the Atlantic)
    let (lat, lon) = (20f64.to_radians(), (-30f64).to_radians());
    let dir = [lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()];
    CameraSpec::Orthographic {
        eye: dir.map(|x| 3.0 * EARTH_RADIUS_M * x),
        look_at: [0.0; 3],
        up: [0.0, 0.0, 1.0],
        width: 2.1 * EARTH_RADIUS_M,
    }
}

fn ocean_study(quick: bool) -> anyhow::Result<Study> {
    let (fine, values) = data::ocean()?;
    let camera = ocean_globe_camera();
    let pixels = if quick { [96, 96] } else { [256, 256] };
    // the truth: the data itself, marched natively in f64
    let scene = Scene {
        grid: fine.clone().into(),
        values: values.clone(),
        camera: Camera::new(&camera, pixels).map_err(anyhow::Error::msg)?,
        pixels,
        mode: Mode::Projection,
        method: Method::Native,
        precision: Precision::F64,
    };
    let truth = render(&scene, &|| {}).values;
    Ok(Study {
        key: "ocean",
        title: "Ocean temperature (Levitus, 20 depths × 180 × 360, R = 6 371 000 m; projection °C·m seen from \
                space; truth: the full-resolution data marched natively)"
            .into(),
        unit: "°C·m",
        fine,
        values,
        camera,
        pixels,
        mode: Mode::Projection,
        truth,
        coarsenings: 3,
        finest_is_rung: false,
        cartesian: if quick { vec![64, 128] } else { vec![64, 128, 256] },
        images: true,
    })
}

fn prem_study(quick: bool) -> anyhow::Result<Study> {
    let model = data::prem()?;
    let (fine, values) = if quick {
        model.grid(4, 45, 90)
    } else {
        model.grid(8, 90, 180)
    };
    let r = fine.outer_radius();
    let camera = CameraSpec::Orthographic {
        eye: [3.0 * r, 0.2 * r, 0.1 * r],
        look_at: [0.0; 3],
        up: [0.0, 0.0, 1.0],
        width: 2.1 * r,
    };
    let pixels = if quick { [64, 64] } else { [160, 160] };
    let truth = truth_image(&camera, pixels, |o, d| {
        model.travel_time(closest_distance([0.0; 3], o, d))
    })?;
    Ok(Study {
        key: "prem",
        title: format!(
            "PREM travel times ∫ ds / v_p through the whole Earth (km, s; {} shells, each linear piece of the \
             model cut in {}; truth: Gauss–Legendre quadrature of the piecewise-linear model)",
            fine.shape()[0],
            if quick { 4 } else { 8 }
        ),
        unit: "s",
        fine,
        values,
        camera,
        pixels,
        mode: Mode::TravelTime,
        truth,
        coarsenings: if quick { 3 } else { 4 },
        finest_is_rung: true,
        cartesian: if quick {
            vec![32, 64, 128]
        } else {
            vec![32, 64, 128, 256]
        },
        images: false,
    })
}

/// Runs the section.
pub fn section(opts: &Options) -> anyhow::Result<Section> {
    let started = Instant::now();
    let quick = opts.quick;
    let reps = if quick { 2 } else { 3 };
    let mut md = String::new();
    md.push_str(
        "Hannasch §6.2–6.3 (Fig. 6.13, 6.14): native spherical marching costs more per cell than a Cartesian \
         voxel walk but reaches a given error with a much coarser grid. Each scene is cast with one camera \
         through a ladder of native grids (each rung discards every other breakpoint of the one above, its cells \
         holding the volume-weighted mean of the finer cells) and a ladder of Cartesian N³ resamplings of the \
         finest grid (a voxel holds the value of the native cell containing its center, 0 outside; the \
         resampling is timed apart and not charged, as in §6.3). Both run in f64 across the cores, same rays, \
         after one untimed warm-up, best of ",
    );
    let _ = write!(
        md,
        "{reps} run{}. Errors are over the pixels whose ray meets the field: RMS relative = RMS of the absolute \
         error over the RMS of the truth, max relative = largest absolute error over the largest truth (a \
         per-pixel relative error would be dominated by the limb, §6.2). The camera is oblique, not aligned \
         with the voxel axes. Times are wall-clock on the machine that runs the report: where other work shares \
         it, a rung can come out slower than a finer one, and the ratios below move with it; the errors do not.\n\n",
        if reps > 1 { "s" } else { "" }
    );
    let studies = [
        analytic_study(Analytic::Ball, 1.0, quick)?,
        analytic_study(Analytic::Step, 0.55, quick)?,
        analytic_study(Analytic::R2, 1.0, quick)?,
        ocean_study(quick)?,
        prem_study(quick)?,
    ];
    for st in &studies {
        let runs = run_study(st, reps)?;
        md.push_str(&study_markdown(st, &runs, opts)?);
    }
    md.push_str("### The real scenes on their own\n\n");
    md.push_str(&real_renders(opts)?);
    let _ = writeln!(
        md,
        "This section took {:.1} s ({} mode).",
        started.elapsed().as_secs_f64(),
        if quick { "quick" } else { "full" }
    );
    Ok(Section {
        title: "Error against runtime: native against Cartesian (render)".into(),
        markdown: md,
    })
}

mod real;
use real::*;

#[cfg(test)]
mod tests;
