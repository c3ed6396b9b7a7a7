//! `curvicast march --grid GRID.json [--rays RAYS.jsonl] [--engine serial|separable] [--precision f64|f32|f32-fast]`
//!
//! Marches every ray through a spherical, cylindrical or polar grid (seed 001) and prints one JSON line per ray:
//! `{"ray": i, "crossings": [{"cell": [i, j, k], "t_enter": .., "t_exit": ..}, ..]}` (polar cells have two
//! indices), or `{"ray": i, "error": ".."}` for a ray that cannot be marched. A malformed grid file is a usage
//! error (exit code 2, one line on stderr naming the file, nothing on stdout).

use super::io::{UsageError, error_line, read_rays};
use crate::scenes::spec::{GridSpec, RaySpec};
use curvicast::F32Fast;
use curvicast::ray::Ray;
use curvicast::real::Real;
use curvicast::spherical::{CellCrossing, CylindricalGrid, MarchError, PolarGrid, SphericalGrid};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

/// Which engine marches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Engine {
    /// The serial, constant-memory engine (seed 001 ch. 5).
    Serial,
    /// The separable engine (seed 001 §3), buffers sized from the grid.
    Separable,
}

/// Which scalar the kernel runs in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Precision {
    /// IEEE binary64.
    F64,
    /// IEEE binary32 with correctly rounded sqrt.
    F32,
    /// binary32 with the fast math backend.
    #[value(name = "f32-fast")]
    F32Fast,
}

/// The arguments of `curvicast march`.
#[derive(Debug, Clone)]
pub struct MarchArgs {
    /// The grid file.
    pub grid: PathBuf,
    /// The rays file (standard input when absent).
    pub rays: Option<PathBuf>,
    /// The engine.
    pub engine: Engine,
    /// The scalar type.
    pub precision: Precision,
}

/// Reads and parses a grid file; every problem is a [`UsageError`] naming the file.
pub fn read_grid(path: &Path) -> Result<GridSpec, UsageError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| UsageError(format!("{}: cannot read grid file: {e}", path.display())))?;
    serde_json::from_str(&text)
        .map_err(|e| UsageError(format!("{}: invalid grid: {e}", path.display())))
}

/// Runs the command, writing the answers to `out`.
pub fn run(args: &MarchArgs, out: &mut dyn Write) -> anyhow::Result<()> {
    let spec = read_grid(&args.grid)?;
    let rays = read_rays(args.rays.as_deref())?;
    match args.precision {
        Precision::F64 => run_in::<f64>(&spec, &args.grid, &rays, args.engine, out),
        Precision::F32 => run_in::<f32>(&spec, &args.grid, &rays, args.engine, out),
        Precision::F32Fast => run_in::<F32Fast>(&spec, &args.grid, &rays, args.engine, out),
    }
}

fn conv<T: Real>(v: &[f64]) -> Vec<T> {
    v.iter().map(|&x| T::from_f64(x)).collect()
}

/// A grid of any kind behind one marching interface.
enum AnyGrid<'a, T> {
    S(SphericalGrid<'a, T>),
    C(CylindricalGrid<'a, T>),
    P(PolarGrid<'a, T>),
}

impl<T: Real + Send + Sync> AnyGrid<'_, T> {
    fn serial(&self, ray: &Ray<T>) -> Result<Vec<CellCrossing<T>>, MarchError> {
        let mut m = match self {
            AnyGrid::S(g) => g.march(ray),
            AnyGrid::C(g) => g.march(ray),
            AnyGrid::P(g) => g.march(ray),
        };
        let v: Vec<_> = m.by_ref().collect();
        match m.error() {
            Some(e) => Err(e),
            None => Ok(v),
        }
    }

    /// The largest capacity's buffers (3·N events of 24 bytes in f64: 2.4 MB for N = 32768, and the value is
    /// moved a few times) do not fit the main thread's stack: that march runs on a thread of its own.
    fn separable_on_own_stack<const N: usize>(
        &self,
        ray: &Ray<T>,
    ) -> Result<Vec<CellCrossing<T>>, String> {
        let bytes = std::mem::size_of::<curvicast::spherical::SeparableMarch<T, N>>();
        std::thread::scope(|s| {
            std::thread::Builder::new()
                .stack_size(bytes.saturating_mul(8).saturating_add(1 << 20))
                .spawn_scoped(s, || self.separable::<N>(ray))
                .map_err(|e| format!("cannot start the separable march: {e}"))?
                .join()
                .map_err(|_| "the separable march failed".to_string())?
                .map_err(|e| e.to_string())
        })
    }

    /// Not inlined: the engine's buffers (3·N events, 24 bytes each in f64) live in this function's own frame,
    /// allocated only when this capacity is used (inlined, every capacity's frame would be reserved on every
    /// call of the caller, serial or not, and the largest overflows the main thread's stack).
    #[inline(never)]
    fn separable<const N: usize>(&self, ray: &Ray<T>) -> Result<Vec<CellCrossing<T>>, MarchError> {
        Ok(match self {
            AnyGrid::S(g) => g.march_separable::<N>(ray)?.collect(),
            AnyGrid::C(g) => g.march_separable::<N>(ray)?.collect(),
            AnyGrid::P(g) => g.march_separable::<N>(ray)?.collect(),
        })
    }
}

fn run_in<T: Real + Send + Sync>(
    spec: &GridSpec,
    path: &Path,
    rays: &[Result<RaySpec, String>],
    engine: Engine,
    out: &mut dyn Write,
) -> anyhow::Result<()> {
    let bad = |e: curvicast::spherical::GridError| {
        UsageError(format!("{}: invalid grid: {e}", path.display()))
    };
    let (a, b, c, center, polar) = match spec {
        GridSpec::Spherical {
            center,
            r,
            theta,
            phi,
        } => (r, theta, phi, center.unwrap_or([0.0; 3]), false),
        GridSpec::Cylindrical {
            center,
            rho,
            phi,
            z,
        } => (rho, phi, z, center.unwrap_or([0.0; 3]), false),
        GridSpec::Polar { center, r, phi } => {
            let c = center.unwrap_or([0.0; 2]);
            (r, phi, phi, [c[0], c[1], 0.0], true)
        }
    };
    let (a, b, c): (Vec<T>, Vec<T>, Vec<T>) = (conv(a), conv(b), conv(c));
    let center3 = [
        T::from_f64(center[0]),
        T::from_f64(center[1]),
        T::from_f64(center[2]),
    ];
    let (mut ws, grid);
    match spec {
        GridSpec::Spherical { .. } => {
            ws = vec![T::ZERO; SphericalGrid::<T>::workspace_len(a.len(), b.len(), c.len())];
            grid = AnyGrid::S(
                SphericalGrid::new(&a, &b, &c, &mut ws)
                    .and_then(|g| g.with_center(center3))
                    .map_err(bad)?,
            );
        }
        GridSpec::Cylindrical { .. } => {
            ws = vec![T::ZERO; CylindricalGrid::<T>::workspace_len(a.len(), b.len())];
            grid = AnyGrid::C(
                CylindricalGrid::new(&a, &b, &c, &mut ws)
                    .and_then(|g| g.with_center(center3))
                    .map_err(bad)?,
            );
        }
        GridSpec::Polar { .. } => {
            ws = vec![T::ZERO; PolarGrid::<T>::workspace_len(a.len(), b.len())];
            grid = AnyGrid::P(
                PolarGrid::new(&a, &b, &mut ws)
                    .and_then(|g| g.with_center([center3[0], center3[1]]))
                    .map_err(bad)?,
            );
        }
    }
    // Separable buffers: at most about two crossings per breakpoint per axis (ditone r and θ), plus ties.
    let longest = a.len().max(b.len()).max(c.len());
    let need = 2 * longest + 8;
    let bar = (std::io::stderr().is_terminal() && rays.len() >= 10_000).then(|| {
        let pb = indicatif::ProgressBar::with_draw_target(
            Some(rays.len() as u64),
            indicatif::ProgressDrawTarget::stderr(),
        );
        pb.set_message("march");
        pb
    });
    let mut buf = std::io::BufWriter::new(out);
    for (i, line) in rays.iter().enumerate() {
        if let Some(pb) = &bar {
            pb.inc(1);
        }
        let ray = match line {
            Ok(r) => make_ray::<T>(r),
            Err(e) => Err(e.clone()),
        };
        let result = ray.and_then(|ray| match engine {
            Engine::Serial => grid.serial(&ray).map_err(|e| e.to_string()),
            Engine::Separable if need <= 256 => {
                grid.separable::<256>(&ray).map_err(|e| e.to_string())
            }
            Engine::Separable if need <= 4096 => {
                grid.separable::<4096>(&ray).map_err(|e| e.to_string())
            }
            Engine::Separable => grid.separable_on_own_stack::<32768>(&ray),
        });
        let text = match result {
            Ok(cs) => crossings_line(i, &cs, polar),
            Err(e) => error_line(i, &e),
        };
        writeln!(buf, "{text}")?;
    }
    if let Some(pb) = bar {
        pb.finish_and_clear();
    }
    buf.flush()?;
    Ok(())
}

/// The kernel ray for a rays-file line, or the message of the `{"ray": i, "error": ..}` line.
pub fn make_ray<T: Real>(r: &RaySpec) -> Result<Ray<T>, String> {
    let v = |a: [f64; 3]| [T::from_f64(a[0]), T::from_f64(a[1]), T::from_f64(a[2])];
    let t_max = T::from_f64(r.t_max_or_inf());
    Ray::new(v(r.origin), v(r.dir))
        .and_then(|ray| ray.with_interval(T::from_f64(r.t_min), t_max))
        .map_err(|e| e.to_string())
}

/// The output line of a marched ray.
pub fn crossings_line<T: Real>(i: usize, cs: &[CellCrossing<T>], polar: bool) -> String {
    let items: Vec<serde_json::Value> = cs
        .iter()
        .map(|c| {
            let cell: Vec<u32> = if polar { c.cell[..2].to_vec() } else { c.cell.to_vec() };
            serde_json::json!({"cell": cell, "t_enter": c.t_enter.to_f64(), "t_exit": c.t_exit.to_f64()})
        })
        .collect();
    serde_json::json!({"ray": i, "crossings": items}).to_string()
}
