//! Images of fields on spherical, cylindrical and polar grids (`curvicast render`, Hannasch ch. 6): a camera
//! casts one ray per pixel, the ray is marched through the grid natively (the kernel's serial engine, in f64, f32
//! or f32-fast) or through the Cartesian-resampling baseline, and a sampler folds the `(value, length)` of each
//! cell crossed into the pixel's value. Rows are rendered across the cores; memory is the image plus the field
//! (and, for the baseline, its voxels).
//!
//! * [`camera`]: pixel rays, orthographic and perspective;
//! * [`field`]: the grids, the analytic fields as exact cell averages, their closed-form projections, coarsening;
//! * [`sampler`]: projection, travel time, emission–absorption;
//! * [`cartesian`]: the resampled voxels and their Amanatides–Woo march;
//! * [`data`]: the shipped ocean temperature and PREM as spherical fields, and PREM's quadrature truth;
//! * [`image`]: colour maps and PNG;
//! * [`scene`]: the scene file, SCENE.json.

pub mod camera;
pub mod cartesian;
pub mod data;
pub mod dda;
pub mod field;
pub mod image;
pub mod sampler;
pub mod scene;

use crate::precision::Precision;
use camera::Camera;
use cartesian::VoxelValues;
use curvicast::F32Fast;
use curvicast::march::{CylindricalGrid, Grid, GridError, GridKind, PolarGrid, SphericalGrid};
use curvicast::ray::Ray;
use curvicast::real::Real;
use field::Cells;
use rayon::prelude::*;
use sampler::{Accumulator, Mode};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// How the rays are marched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The kernel's serial engine on the native grid.
    Native,
    /// The cells resampled onto `N³` voxels, then Amanatides–Woo.
    Cartesian(usize),
}

/// Everything a render needs, validated.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The grid.
    pub grid: Cells,
    /// One value per cell (flat order; NaN = empty).
    pub values: Vec<f64>,
    /// The camera.
    pub camera: Camera,
    /// `[W, H]`.
    pub pixels: [usize; 2],
    /// The sampler.
    pub mode: Mode,
    /// Native or Cartesian.
    pub method: Method,
    /// The kernel's scalar (native method only; the baseline runs in f64).
    pub precision: Precision,
}

/// A rendered image and what it cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Rendered {
    /// One value per pixel, row-major, row 0 at the top (NaN where the march failed).
    pub values: Vec<f64>,
    /// Seconds spent casting the rays (the resampling not included).
    pub seconds: f64,
    /// Seconds spent resampling onto voxels (Cartesian only).
    pub resample_seconds: Option<f64>,
    /// Rays cast.
    pub rays: usize,
    /// Cells (native) or voxels (Cartesian) crossed, over all rays.
    pub crossings: u64,
    /// Rays whose march returned an error.
    pub failed: u64,
}

/// Renders `scene`; `progress` ticks once per finished row.
pub fn render(scene: &Scene, progress: &(dyn Fn() + Sync)) -> Rendered {
    match scene.method {
        Method::Native => match scene.precision {
            Precision::F64 => render_native::<f64>(scene, progress),
            Precision::F32 => render_native::<f32>(scene, progress),
            Precision::F32Fast => render_native::<F32Fast>(scene, progress),
        },
        Method::Cartesian(n) => {
            let start = Instant::now();
            let Ok(voxels) = VoxelValues::resample(&scene.grid, &scene.values, n) else {
                // refused when the scene was made (a polar grid); never a panic
                return failed_render(scene);
            };
            let resample = start.elapsed().as_secs_f64();
            let mut out = render_cartesian(scene, &voxels, progress);
            out.resample_seconds = Some(resample);
            out
        }
    }
}

/// Casts the rays of `scene` through already resampled voxels (the baseline without its resampling).
pub fn render_cartesian(
    scene: &Scene,
    voxels: &VoxelValues,
    progress: &(dyn Fn() + Sync),
) -> Rendered {
    rows(scene, progress, |i, j| {
        let (o, d) = scene.camera.ray(i, j);
        let mut acc = Accumulator::new(scene.mode);
        let n = voxels.sample(o, d, &mut acc);
        (acc.value(), n, false)
    })
}

/// Every pixel failed: what a scene that cannot be rendered gives (scenes are validated when they are made, so
/// this is not reached in practice, but it is never a panic).
fn failed_render(scene: &Scene) -> Rendered {
    let n = scene.pixels[0] * scene.pixels[1];
    Rendered {
        values: vec![f64::NAN; n],
        seconds: 0.0,
        resample_seconds: None,
        rays: 0,
        crossings: 0,
        failed: n as u64,
    }
}

fn render_native<T: Real>(scene: &Scene, progress: &(dyn Fn() + Sync)) -> Rendered {
    let conv = |v: &[f64]| v.iter().map(|&x| T::from_f64(x)).collect::<Vec<T>>();
    let built: Result<Rendered, GridError> = match &scene.grid {
        Cells::Spherical(g) => {
            let (r, th, ph) = (conv(&g.r), conv(&g.theta), conv(&g.phi));
            let mut ws =
                vec![T::ZERO; SphericalGrid::<T>::workspace_len(r.len(), th.len(), ph.len())];
            SphericalGrid::new(&r, &th, &ph, &mut ws)
                .and_then(|k| k.with_center(g.center.map(T::from_f64)))
                .map(|k| cast_native(scene, &k, progress))
        }
        Cells::Cylindrical(g) => {
            let (rho, ph, z) = (conv(&g.rho), conv(&g.phi), conv(&g.z));
            let mut ws = vec![T::ZERO; CylindricalGrid::<T>::workspace_len(rho.len(), ph.len())];
            CylindricalGrid::new(&rho, &ph, &z, &mut ws)
                .and_then(|k| k.with_center(g.center.map(T::from_f64)))
                .map(|k| cast_native(scene, &k, progress))
        }
        Cells::Polar(g) => {
            let (r, ph) = (conv(&g.r), conv(&g.phi));
            let mut ws = vec![T::ZERO; PolarGrid::<T>::workspace_len(r.len(), ph.len())];
            PolarGrid::new(&r, &ph, &mut ws)
                .and_then(|k| k.with_center(g.center.map(T::from_f64)))
                .map(|k| cast_native(scene, &k, progress))
        }
    };
    // validated when the scene was made
    built.unwrap_or_else(|_| failed_render(scene))
}

/// Casts the pixel rays of `scene` through the kernel's grid with the serial engine.
fn cast_native<T: Real, K: GridKind>(
    scene: &Scene,
    grid: &Grid<'_, T, K>,
    progress: &(dyn Fn() + Sync),
) -> Rendered {
    rows(scene, progress, |i, j| {
        let (o, d) = scene.camera.ray(i, j);
        let Ok(ray) = Ray::new(o.map(T::from_f64), d.map(T::from_f64)) else {
            return (f64::NAN, 0, true);
        };
        let mut acc = Accumulator::new(scene.mode);
        let mut n = 0u64;
        let mut march = grid.march(&ray);
        for c in march.by_ref() {
            n += 1;
            let v = scene
                .grid
                .flat(c.cell)
                .map_or(f64::NAN, |f| scene.values[f]);
            if !acc.add(v, (c.t_exit - c.t_enter).to_f64()) {
                break;
            }
        }
        if march.error().is_some() {
            (f64::NAN, n, true)
        } else {
            (acc.value(), n, false)
        }
    })
}

/// Runs `pixel(i, j) -> (value, crossings, failed)` over the image, rows across the cores, timed.
fn rows(
    scene: &Scene,
    progress: &(dyn Fn() + Sync),
    pixel: impl Fn(usize, usize) -> (f64, u64, bool) + Sync,
) -> Rendered {
    let [w, h] = scene.pixels;
    let mut values = vec![0.0; w * h];
    let crossings = AtomicU64::new(0);
    let failed = AtomicU64::new(0);
    let start = Instant::now();
    values.par_chunks_mut(w).enumerate().for_each(|(i, row)| {
        let (mut n, mut bad) = (0, 0);
        for (j, v) in row.iter_mut().enumerate() {
            let (value, c, f) = pixel(i, j);
            *v = value;
            n += c;
            bad += u64::from(f);
        }
        crossings.fetch_add(n, Ordering::Relaxed);
        failed.fetch_add(bad, Ordering::Relaxed);
        progress();
    });
    Rendered {
        values,
        seconds: start.elapsed().as_secs_f64(),
        resample_seconds: None,
        rays: w * h,
        crossings: crossings.into_inner(),
        failed: failed.into_inner(),
    }
}
