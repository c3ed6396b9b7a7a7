//! `curvicast pick --terrain TERRAIN.json [--rays RAYS.jsonl] [--min-level N] [--block B]` (command-line contract):
//! the nearest intersection of each ray with a DEM's triangle surface, through the kernel's
//! [`curvicast::terrain::Picker`] over the host's [`DemStorage`] (seed 000 §3–§4).
//!
//! Output, one line per ray in input order:
//! `{"ray": 0, "hit": {"t": .., "ecef": [x, y, z], "lat": .., "lon": .., "h": .., "cell": [i, j], "level": L}}`,
//! `{"ray": 1, "hit": null}`, or `{"ray": 2, "error": ".."}` for a ray that cannot be answered. `level` (the
//! quadtree depth of the leaf, zones are 0) is an extra field.

use super::io::{UsageError, error_line, read_rays};
use crate::scenes::spec::RaySpec;
use crate::scenes::terrain::{DemStorage, load_terrain};
use curvicast::Ray;
use curvicast::terrain::Picker;
use rayon::prelude::*;
use std::io::Write;
use std::path::PathBuf;

/// The arguments of `curvicast pick`.
#[derive(Debug, Clone)]
pub struct PickArgs {
    /// The `TERRAIN.json` file.
    pub terrain: PathBuf,
    /// The rays file (JSON Lines); standard input when `None`.
    pub rays: Option<PathBuf>,
    /// The coarsest quadtree level whose blocks may answer (multi-resolution terrain). The trees built here are
    /// single-resolution — every leaf holds the full-resolution cells — so any valid level gives the same answer;
    /// values deeper than the tree are rejected.
    pub min_level: u32,
    /// Cells per leaf-block side (default 16), 1 to 1024.
    pub block: usize,
}

/// The output line for one answered ray.
pub fn hit_line(ray: usize, hit: Option<&curvicast::terrain::Hit<f64>>) -> String {
    match hit {
        None => serde_json::json!({"ray": ray, "hit": null}).to_string(),
        Some(h) => serde_json::json!({"ray": ray, "hit": {
            "t": h.t, "ecef": h.ecef, "lat": h.lat, "lon": h.lon, "h": h.h,
            "cell": h.cell, "level": h.level}})
        .to_string(),
    }
}

/// Answers one ray (the line it prints).
pub fn answer(picker: &Picker<'_, f64, DemStorage<'_>>, k: usize, r: &RaySpec) -> String {
    let ray =
        match Ray::new(r.origin, r.dir).and_then(|x| x.with_interval(r.t_min, r.t_max_or_inf())) {
            Ok(x) => x,
            Err(e) => return error_line(k, &format!("invalid ray: {e}")),
        };
    match picker.pick(&ray) {
        Ok(h) => hit_line(k, h.as_ref()),
        Err(e) => error_line(k, &format!("pick failed: {e}")),
    }
}

/// Runs the subcommand, writing the answer lines to `out`. Every file or argument problem is returned as a
/// [`UsageError`] before anything is written.
pub fn run(args: &PickArgs, out: &mut dyn Write) -> Result<(), UsageError> {
    if !(1..=1024).contains(&args.block) {
        return Err(UsageError(format!(
            "--block: must be between 1 and 1024 cells, got {}",
            args.block
        )));
    }
    let dem = load_terrain(&args.terrain).map_err(|e| UsageError(e.to_string()))?;
    let storage = DemStorage::new(&dem, args.block);
    let picker: Picker<'_, f64, DemStorage<'_>> = Picker::new(&storage)
        .map_err(|e| UsageError(format!("{}: terrain rejected: {e}", args.terrain.display())))?;
    let depth = storage.depth();
    if args.min_level > depth {
        return Err(UsageError(format!(
            "--min-level: {} is deeper than the terrain's quadtree (levels 0 to {depth} with --block {})",
            args.min_level, args.block
        )));
    }
    let rays = read_rays(args.rays.as_deref())?;
    // A progress bar on stderr for long runs, only when stderr is a terminal (never on stdout).
    let bar = (rays.len() >= 10_000 && std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .then(|| indicatif::ProgressBar::new(rays.len() as u64));
    let lines: Vec<String> = rays
        .par_iter()
        .enumerate()
        .map(|(k, r)| {
            if let Some(b) = &bar {
                b.inc(1);
            }
            match r {
                Ok(r) => answer(&picker, k, r),
                Err(e) => error_line(k, e),
            }
        })
        .collect();
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    for l in lines {
        writeln!(out, "{l}").map_err(|e| UsageError(format!("<stdout>: {e}")))?;
    }
    Ok(())
}
