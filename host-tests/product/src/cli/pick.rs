//! `curvicast pick (--terrain TERRAIN.json | --dem FILE) [--rays RAYS.jsonl] [--min-level N] [--block B]`
//! (command-line contract):
//! the nearest intersection of each ray with a DEM's triangle surface, through the kernel's
//! [`curvicast::terrain::Picker`] over the host's [`DemStorage`] (Wartell et al. §3–§4).
//!
//! Output, one line per ray in input order:
//! `{"ray": 0, "hit": {"t": .., "ecef": [x, y, z], "lat": .., "lon": .., "h": .., "cell": [i, j], "level": L,
//! "stride": S}}`, `{"ray": 1, "hit": null}`, or `{"ray": 2, "error": ".."}` for a ray that cannot be answered.
//! `level` (the quadtree depth of the node whose block answered, zones are 0) and `stride` (the traced cell's
//! size in grid steps) are extra fields.
//!
//! `--dem FILE` reads an SRTM `.hgt` tile, a single-band geographic GeoTIFF or the project's `.dem.cc` format
//! directly, with the georeference from the file ([`crate::formats::dem_files`]); it builds the same model as
//! `--terrain`, so the same heights give the same answers.
//!
//! Multi-resolution experiments (Wartell et al. §5): `--fine-region` and `--coarse-level` shape a tree whose branches
//! end early outside a box, `--non-resident-levels` and `--non-resident-region` mark blocks as not in memory,
//! and `--min-level` limits which coarser blocks may stand in for missing ones. With any of the first four, every
//! node has its own block (the DEM subsampled at 2^k grid steps, k its height above the full-resolution
//! level). A ray whose answer needs a missing block gets it paged in and is asked again (the caller's side of
//! `NeedsBlock`; per ray, so answers do not depend on the order of the rays), or with `--no-paging` an error
//! line naming the node.

use super::io::{RayLine, StreamError, UsageError, error_line, stream_answers};
use crate::formats::dem_files::read_dem;
use crate::formats::spec::RaySpec;
use crate::formats::terrain::load_terrain;
use crate::storage::{DemStorage, MultiRes, pick_paging_in};
use curvicast::Ray;
use curvicast::terrain::{NodeId, Picker};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Where the terrain comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TerrainSource {
    /// `--terrain TERRAIN.json`.
    Terrain(PathBuf),
    /// `--dem FILE`: an SRTM `.hgt`, a GeoTIFF or a `.dem.cc` file (see [`crate::formats::dem_files`]).
    Dem(PathBuf),
}

impl TerrainSource {
    /// The file named on the command line.
    pub fn path(&self) -> &Path {
        match self {
            TerrainSource::Terrain(p) | TerrainSource::Dem(p) => p,
        }
    }
}

/// The arguments of `curvicast pick`.
#[derive(Debug, Clone)]
pub struct PickArgs {
    /// The terrain: `--terrain` or `--dem`.
    pub terrain: TerrainSource,
    /// The rays file (JSON Lines); standard input when `None`.
    pub rays: Option<PathBuf>,
    /// The coarsest quadtree level whose blocks may stand in for missing finer ones (Wartell et al. §5). Without the
    /// multi-resolution options every block is resident and full resolution, so it does not change the
    /// answers; values deeper than the tree are rejected.
    pub min_level: u32,
    /// Cells per leaf-block side (default 16), 1 to 1024.
    pub block: usize,
    /// The multi-resolution options.
    pub multires: MultiResArgs,
}

/// The multi-resolution options of `curvicast pick` (as given on the command line; checked by [`run`]).
#[derive(Debug, Clone, Default)]
pub struct MultiResArgs {
    /// `LAT_S,LAT_N,LON_W,LON_E`: full resolution only inside.
    pub fine_region: Option<String>,
    /// Pyramid level where branches outside the fine region end.
    pub coarse_level: Option<u32>,
    /// Comma-separated quadtree levels whose blocks are not resident.
    pub non_resident_levels: Option<String>,
    /// `LAT_S,LAT_N,LON_W,LON_E`: blocks of nodes inside are not resident.
    pub non_resident_region: Option<String>,
    /// Print needed blocks as errors instead of paging them in.
    pub no_paging: bool,
}

impl MultiResArgs {
    fn any(&self) -> bool {
        self.fine_region.is_some()
            || self.coarse_level.is_some()
            || self.non_resident_levels.is_some()
            || self.non_resident_region.is_some()
    }
}

/// Parses `LAT_S,LAT_N,LON_W,LON_E`.
fn parse_box(flag: &str, v: &str) -> Result<[f64; 4], UsageError> {
    let parts: Vec<f64> = v
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| {
            UsageError(format!(
                "{flag}: {e} in {v:?} (expected LAT_S,LAT_N,LON_W,LON_E)"
            ))
        })?;
    match parts.as_slice() {
        &[a, b, c, d] if parts.iter().all(|x| x.is_finite()) && a <= b && c <= d => {
            Ok([a, b, c, d])
        }
        _ => Err(UsageError(format!(
            "{flag}: expected four finite numbers LAT_S,LAT_N,LON_W,LON_E with LAT_S <= LAT_N and LON_W <= LON_E, \
             got {v:?}"
        ))),
    }
}

/// The output line for one answered ray.
pub fn hit_line(ray: usize, hit: Option<&curvicast::terrain::Hit<f64>>) -> String {
    match hit {
        None => serde_json::json!({"ray": ray, "hit": null}).to_string(),
        Some(h) => serde_json::json!({"ray": ray, "hit": {
            "t": h.t, "ecef": h.ecef, "lat": h.lat_deg, "lon": h.lon_deg, "h": h.h,
            "cell": h.cell, "level": h.level, "stride": h.stride}})
        .to_string(),
    }
}

/// Answers one ray (the line it prints): with `paging`, a needed block is paged in (for this ray only) and the
/// ray asked again.
pub fn answer(
    picker: &Picker<'_, f64, DemStorage<'_>>,
    storage: &DemStorage<'_>,
    paging: bool,
    k: usize,
    r: &RaySpec,
) -> String {
    let ray =
        match Ray::new(r.origin, r.dir).and_then(|x| x.with_interval(r.t_min, r.t_max_or_inf())) {
            Ok(x) => x,
            Err(e) => return error_line(k, &format!("invalid ray: {e}")),
        };
    let result = if paging {
        pick_paging_in(picker, storage, &ray).map(|(h, _)| h)
    } else {
        picker.pick(&ray)
    };
    match result {
        Ok(h) => hit_line(k, h.as_ref()),
        Err(e) => error_line(k, &format!("pick failed: {e}")),
    }
}

/// The most rays picked at once (in parallel); an answer line is about 250 bytes.
const WINDOW: usize = 4096;

/// Runs the subcommand, writing the answer lines to `out` as the rays arrive (see [`super::io`] for the streaming
/// rules). Every file or argument problem is returned as a [`UsageError`] before anything is written.
pub fn run(args: &PickArgs, out: &mut dyn Write) -> Result<(), StreamError> {
    if !(1..=1024).contains(&args.block) {
        return Err(UsageError(format!(
            "--block: must be between 1 and 1024 cells, got {}",
            args.block
        ))
        .into());
    }
    let m = &args.multires;
    let fine_region = m
        .fine_region
        .as_deref()
        .map(|v| parse_box("--fine-region", v))
        .transpose()?;
    let non_resident_region = m
        .non_resident_region
        .as_deref()
        .map(|v| parse_box("--non-resident-region", v))
        .transpose()?;
    let non_resident_levels: Vec<u32> = match &m.non_resident_levels {
        None => Vec::new(),
        Some(v) => v
            .split(',')
            .map(|x| x.trim().parse::<u32>())
            .collect::<Result<_, _>>()
            .map_err(|e| {
                UsageError(format!(
                    "--non-resident-levels: {e} in {v:?} (expected levels like 2,3)"
                ))
            })?,
    };
    if m.coarse_level.is_some_and(|c| c > 30) {
        return Err(UsageError("--coarse-level: must be between 0 and 30".into()).into());
    }
    let dem = match &args.terrain {
        TerrainSource::Terrain(p) => load_terrain(p),
        TerrainSource::Dem(p) => read_dem(p),
    }
    .map_err(|e| UsageError(e.to_string()))?;
    let storage = if m.any() {
        DemStorage::multi_resolution(
            &dem,
            args.block,
            MultiRes {
                fine_region,
                coarse_level: if fine_region.is_some() {
                    m.coarse_level.unwrap_or(2) as usize
                } else {
                    0
                },
            },
        )
    } else {
        DemStorage::new(&dem, args.block)
    };
    let depth = storage.depth();
    if args.min_level > depth {
        return Err(UsageError(format!(
            "--min-level: {} is deeper than the terrain's quadtree (levels 0 to {depth} with --block {})",
            args.min_level, args.block
        )).into());
    }
    if let Some(&l) = non_resident_levels.iter().find(|&&l| l > depth) {
        return Err(UsageError(format!(
            "--non-resident-levels: {l} is deeper than the terrain's quadtree (levels 0 to {depth})"
        ))
        .into());
    }
    if m.any() {
        let lat = |i: u32| dem.lat0 + f64::from(i) * dem.dlat;
        let lon = |j: u32| dem.lon0 + f64::from(j) * dem.dlon;
        for n in storage.tree() {
            let inside = non_resident_region.is_some_and(|[s, nn, w, e]| {
                let (a, b) = (lat(n.rows[0]), lat(n.rows[1]));
                a.min(b) >= s && a.max(b) <= nn && lon(n.cols[0]) >= w && lon(n.cols[1]) <= e
            });
            if inside || non_resident_levels.contains(&u32::from(n.level)) {
                storage.set_resident(NodeId(n.id), false);
            }
        }
    }
    let picker: Picker<'_, f64, DemStorage<'_>> = Picker::new(&storage).map_err(|e| {
        UsageError(format!(
            "{}: terrain rejected: {e}",
            args.terrain.path().display()
        ))
    })?;
    let picker = picker.with_min_level(u8::try_from(args.min_level).unwrap_or(u8::MAX));
    let paging = !m.no_paging;
    let answer = |k: usize, line: RayLine, w: &mut dyn Write| -> std::io::Result<()> {
        let text = match line {
            Ok(r) => answer(&picker, &storage, paging, k, &r),
            Err(e) => error_line(k, &e),
        };
        writeln!(w, "{text}")
    };
    stream_answers(args.rays.as_deref(), out, WINDOW, "pick", &answer)?;
    Ok(())
}
