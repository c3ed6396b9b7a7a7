//! SCENE.json of `curvicast render` (see the command-line contract): parsed, checked, and turned into a
//! [`Scene`]. Every problem is a [`UsageError`] naming the file at fault.

use super::camera::{Camera, CameraSpec};
use super::field::{Analytic, Cells, CylindricalCells, PolarCells, SphericalCells};
use super::sampler::{Mode, Transfer};
use super::{Method, Scene};
use crate::cli::io::UsageError;
use crate::formats::spec::GridSpec;
use crate::precision::Precision;
use serde::Deserialize;
use std::path::Path;

/// The largest voxel count per side of the Cartesian baseline (512³ `f32` voxels are 512 MiB).
pub const MAX_VOXELS_PER_SIDE: usize = 512;
/// The largest image, in pixels.
pub const MAX_PIXELS: usize = 1 << 26;
/// The largest grid, in cells.
pub const MAX_CELLS: usize = 1 << 28;

/// SCENE.json as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// A GRID.json object (spherical, cylindrical or polar).
    pub grid: GridSpec,
    /// The field.
    pub field: FieldSpec,
    /// The camera.
    pub camera: CameraSpec,
    /// `[W, H]`.
    pub pixels: [usize; 2],
    /// The sampler (default `"projection"`).
    #[serde(default)]
    pub mode: ModeSpec,
    /// The method (default `"native"`).
    #[serde(default)]
    pub method: MethodSpec,
    /// The kernel's scalar (default `"f64"`).
    #[serde(default)]
    pub precision: Precision,
}

/// `{"analytic": "ball" | "r2" | "step", "radius": R}` or `{"cells": "values.f32"}`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldSpec {
    /// An analytic field.
    pub analytic: Option<Analytic>,
    /// Its radius (defaults in [`Analytic::default_radius`]).
    pub radius: Option<f64>,
    /// Per-cell data: little-endian f32, row-major by cell index, path relative to the scene file.
    pub cells: Option<String>,
}

/// The sampler as written.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ModeSpec {
    /// `"projection"`.
    #[default]
    Projection,
    /// `"travel_time"`.
    TravelTime,
    /// `{"emission_absorption": {"range": [lo, hi], "opacity": k, "cutoff": c}}`, all optional.
    EmissionAbsorption(TransferSpec),
}

/// The transfer function as written (see [`Transfer`]); every field is optional.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransferSpec {
    /// Values mapped to 0 and 1 (default: the smallest and largest finite cell value).
    pub range: Option<[f64; 2]>,
    /// Extinction per unit length at full scale (default: 4 / the domain's radial thickness `r_max − r_min`,
    /// or `ρ_max − ρ_min`).
    pub opacity: Option<f64>,
    /// Early termination at this accumulated opacity (default 0.99).
    pub cutoff: Option<f64>,
}

/// `"native"` or `{"cartesian": N}`.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MethodSpec {
    /// The kernel's serial engine.
    #[default]
    Native,
    /// Resampling to `N³` voxels.
    Cartesian(usize),
}

/// Reads, checks and builds the scene in `path` (per-cell data relative to it).
pub fn load_scene(path: &Path) -> Result<Scene, UsageError> {
    let name = path.display();
    let text = std::fs::read_to_string(path)
        .map_err(|e| UsageError(format!("{name}: cannot read scene file: {e}")))?;
    let spec: SceneSpec = serde_json::from_str(&text)
        .map_err(|e| UsageError(format!("{name}: invalid scene: {e}")))?;
    let base = path.parent().unwrap_or(Path::new("."));
    build_scene(&spec, base).map_err(|e| match e {
        SceneError::Scene(m) => UsageError(format!("{name}: invalid scene: {m}")),
        SceneError::Data(file, m) => UsageError(format!("{}: {m}", file.display())),
    })
}

/// What is wrong, and in which file.
#[derive(Debug)]
pub enum SceneError {
    /// The scene itself.
    Scene(String),
    /// A data file it names.
    Data(std::path::PathBuf, String),
}

/// Builds a scene from its parsed form; `base` is the folder per-cell data paths are relative to.
pub fn build_scene(spec: &SceneSpec, base: &Path) -> Result<Scene, SceneError> {
    let bad = |m: String| SceneError::Scene(m);
    let grid = grid_cells(&spec.grid).map_err(|e| bad(format!("grid: {e}")))?;
    if grid.cell_count() > MAX_CELLS {
        return Err(bad(format!("grid: more than {MAX_CELLS} cells")));
    }
    let [w, h] = spec.pixels;
    if w == 0 || h == 0 || w.saturating_mul(h) > MAX_PIXELS {
        return Err(bad(format!(
            "pixels must be two positive counts with W·H ≤ {MAX_PIXELS}, got [{w}, {h}]"
        )));
    }
    let camera = Camera::new(&spec.camera, spec.pixels).map_err(bad)?;
    let values = field_values(&spec.field, &grid, base)?;
    let mode = match spec.mode {
        ModeSpec::Projection => Mode::Projection,
        ModeSpec::TravelTime => Mode::TravelTime,
        ModeSpec::EmissionAbsorption(t) => {
            let [lo, hi] = match t.range {
                Some(r) => r,
                None => super::image::finite_range(&values),
            };
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(bad(format!(
                    "emission_absorption: range must be finite with lo < hi, got [{lo}, {hi}]"
                )));
            }
            let opacity = t.opacity.unwrap_or(4.0 / grid.thickness());
            if !(opacity.is_finite() && opacity >= 0.0) {
                return Err(bad(format!(
                    "emission_absorption: opacity must be finite and ≥ 0, got {opacity}"
                )));
            }
            let cutoff = t.cutoff.unwrap_or(0.99);
            if !(cutoff > 0.0 && cutoff <= 1.0) {
                return Err(bad(format!(
                    "emission_absorption: cutoff must be in (0, 1], got {cutoff}"
                )));
            }
            Mode::EmissionAbsorption(Transfer {
                lo,
                hi,
                opacity,
                cutoff,
            })
        }
    };
    let method = match spec.method {
        MethodSpec::Native => Method::Native,
        MethodSpec::Cartesian(_) if matches!(grid, Cells::Polar(_)) => {
            return Err(bad(
                "cartesian: a polar grid is unbounded in z and has no bounding cube to resample onto".into(),
            ));
        }
        MethodSpec::Cartesian(n) if (1..=MAX_VOXELS_PER_SIDE).contains(&n) => Method::Cartesian(n),
        MethodSpec::Cartesian(n) => {
            return Err(bad(format!(
                "cartesian: N must be between 1 and {MAX_VOXELS_PER_SIDE}, got {n}"
            )));
        }
    };
    let precision = spec.precision;
    Ok(Scene {
        grid,
        values,
        camera,
        pixels: spec.pixels,
        mode,
        method,
        precision,
    })
}

/// The grid of a GRID.json object, checked by the kernel's own validation of the breakpoints and center.
pub fn grid_cells(spec: &GridSpec) -> Result<Cells, curvicast::march::GridError> {
    use curvicast::march::{CylindricalGrid, PolarGrid, SphericalGrid};
    Ok(match spec {
        GridSpec::Spherical {
            center,
            r,
            theta,
            phi,
        } => {
            let center = center.unwrap_or([0.0; 3]);
            let mut ws =
                vec![0.0; SphericalGrid::<f64>::workspace_len(r.len(), theta.len(), phi.len())];
            SphericalGrid::new(r, theta, phi, &mut ws)?.with_center(center)?;
            Cells::Spherical(SphericalCells {
                center,
                r: r.clone(),
                theta: theta.clone(),
                phi: phi.clone(),
            })
        }
        GridSpec::Cylindrical {
            center,
            rho,
            phi,
            z,
        } => {
            let center = center.unwrap_or([0.0; 3]);
            let mut ws = vec![0.0; CylindricalGrid::<f64>::workspace_len(rho.len(), phi.len())];
            CylindricalGrid::new(rho, phi, z, &mut ws)?.with_center(center)?;
            Cells::Cylindrical(CylindricalCells {
                center,
                rho: rho.clone(),
                phi: phi.clone(),
                z: z.clone(),
            })
        }
        GridSpec::Polar { center, r, phi } => {
            let center = center.unwrap_or([0.0; 2]);
            let mut ws = vec![0.0; PolarGrid::<f64>::workspace_len(r.len(), phi.len())];
            PolarGrid::new(r, phi, &mut ws)?.with_center(center)?;
            Cells::Polar(PolarCells {
                center,
                r: r.clone(),
                phi: phi.clone(),
            })
        }
    })
}

fn field_values(f: &FieldSpec, grid: &Cells, base: &Path) -> Result<Vec<f64>, SceneError> {
    let bad = |m: String| SceneError::Scene(m);
    match (f.analytic, &f.cells) {
        (Some(kind), None) => {
            let radius = f
                .radius
                .unwrap_or_else(|| kind.default_radius(grid.outer_radius()));
            if !(radius.is_finite() && radius > 0.0) {
                return Err(bad(format!("field: radius must be positive, got {radius}")));
            }
            Ok(kind.averages(grid, radius))
        }
        (None, Some(file)) => {
            if f.radius.is_some() {
                return Err(bad("field: radius belongs to analytic fields".into()));
            }
            let path = base.join(file);
            let bytes = std::fs::read(&path).map_err(|e| {
                SceneError::Data(path.clone(), format!("cannot read cell values: {e}"))
            })?;
            let want = grid.cell_count();
            if bytes.len() != want * 4 {
                return Err(SceneError::Data(
                    path,
                    format!(
                        "expected {want} little-endian f32 cell values ({} bytes), found {} bytes",
                        want * 4,
                        bytes.len()
                    ),
                ));
            }
            Ok(bytes
                .chunks_exact(4)
                .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
                .collect())
        }
        _ => Err(bad(
            "field: give exactly one of {\"analytic\": ..} and {\"cells\": FILE}".into(),
        )),
    }
}
