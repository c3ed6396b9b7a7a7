//! `curvicast render --scene SCENE.json --out DIR`
//!
//! Renders one view of a field on a spherical, cylindrical or polar grid (see [`crate::render`] and the
//! command-line contract) and writes `DIR/image.png`, `DIR/values.f32` (each pixel's value before colour mapping,
//! little-endian f32, row-major, row 0 at the top; `DIR/values.f64` holds the same unrounded) and
//! `DIR/render.json` (size, method, seconds, rays, crossings, the grid's kind and cell counts, and the resampling
//! time of the Cartesian baseline). A bad scene or data file is a one-line message naming the file, exit code 2,
//! and nothing written.

use crate::render::image::{ColorMap, Panel, Scale, colorize, figure, finite_range, write_png};
use crate::render::sampler::Mode;
use crate::render::scene::load_scene;
use crate::render::{Method, Rendered, Scene, render};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

/// The arguments of `curvicast render`.
#[derive(Debug, Clone)]
pub struct RenderArgs {
    /// SCENE.json.
    pub scene: PathBuf,
    /// The output folder (created if missing).
    pub out: PathBuf,
}

/// Runs the command.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let scene = load_scene(&args.scene)?;
    let bar = std::io::stderr().is_terminal().then(|| {
        let pb = indicatif::ProgressBar::with_draw_target(
            Some(scene.pixels[1] as u64),
            indicatif::ProgressDrawTarget::stderr(),
        );
        pb.set_message("render (rows)");
        pb
    });
    let tick = || {
        if let Some(pb) = &bar {
            pb.inc(1);
        }
    };
    let out = render(&scene, &tick);
    if let Some(pb) = bar {
        pb.finish_and_clear();
    }
    write_outputs(&args.out, &scene, &out)
}

/// Writes `image.png` (the picture, one pixel per ray), `figure.png` (the same with its colour bar, the range and
/// what the values are), `values.f32` and `render.json` of a render into `dir` (created if missing).
pub fn write_outputs(dir: &Path, scene: &Scene, out: &Rendered) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?;
    let [w, h] = scene.pixels;
    let map = match scene.mode {
        Mode::EmissionAbsorption(_) => ColorMap::Inferno,
        _ => ColorMap::Viridis,
    };
    let range = finite_range(&out.values);
    let image = colorize(&out.values, w, h, range, map);
    write_png(&dir.join("image.png"), &image)?;
    let (title, unit) = match scene.mode {
        Mode::Projection => ("projection", "sum of value × length"),
        Mode::TravelTime => ("travel time", "sum of length / value"),
        Mode::EmissionAbsorption(_) => ("emission-absorption", "intensity"),
    };
    let method = match scene.method {
        Method::Native => "native".to_string(),
        Method::Cartesian(n) => format!("Cartesian {n}^3"),
    };
    let title = format!("{title}, {method}");
    let panels = [Panel {
        image: &image,
        title: &title,
    }];
    write_png(
        &dir.join("figure.png"),
        &figure(&[(&panels, Scale { range, map, unit })]),
    )?;
    let bytes: Vec<u8> = out
        .values
        .iter()
        .flat_map(|&v| (v as f32).to_le_bytes())
        .collect();
    let path = dir.join("values.f32");
    std::fs::write(&path, bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let mut meta = serde_json::json!({
        "width": w,
        "height": h,
        "method": match scene.method { Method::Native => "native", Method::Cartesian(_) => "cartesian" },
        "seconds": out.seconds,
        "rays": out.rays,
        "crossings": out.crossings,
        "mode": scene.mode.name(),
        "failed_rays": out.failed,
        "value_range": range,
        "grid": scene.grid.kind(),
        "cells": scene.grid.dims(),
        "values_f64": "values.f64",
    });
    match scene.method {
        Method::Native => {
            meta["precision"] = serde_json::json!(scene.precision.name());
        }
        Method::Cartesian(n) => {
            meta["voxels_per_side"] = serde_json::json!(n);
            meta["resample_seconds"] = serde_json::json!(out.resample_seconds);
            meta["precision"] = serde_json::json!("f64");
        }
    }
    // the same values unrounded, for checks finer than f32 (an extra file, same layout)
    let bytes: Vec<u8> = out.values.iter().flat_map(|&v| v.to_le_bytes()).collect();
    let path = dir.join("values.f64");
    std::fs::write(&path, bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let path = dir.join("render.json");
    let mut f =
        std::fs::File::create(&path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    writeln!(f, "{meta}").map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(())
}
