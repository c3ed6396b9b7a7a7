//! `curvicast march --grid GRID.json [--rays RAYS.jsonl] [--engine serial|separable] [--precision f64|f32|f32-fast]`
//!
//! Marches every ray through a spherical, cylindrical or polar grid (Hannasch) and prints one JSON line per ray:
//! `{"ray": i, "crossings": [{"cell": [i, j, k], "t_enter": .., "t_exit": ..}, ..]}` (polar cells have two
//! indices), or `{"ray": i, "error": ".."}` for a ray that cannot be marched. A malformed grid file is a usage
//! error (exit code 2, one line on stderr naming the file, nothing on stdout).
//!
//! Rays stream through (see [`super::io`]): they are answered in parallel windows sized so that a window's
//! answers fit in about 32 MB by the grid's bound on one ray's crossings. On a grid so fine that one answer may
//! exceed 1 MB (a million radii: over a million crossings for one ray), rays are answered one at a time and each
//! one's crossings go to the output every 64 KiB as the serial engine produces them, so memory does not grow with
//! the answer. If such a march fails after part of its crossings was written, its line keeps them and ends with
//! an `"error"` field; otherwise a failed ray's line is the contract's `{"ray": i, "error": ".."}`.

use super::io::{RayLine, UsageError, error_line, stream_answers};
use crate::formats::spec::{GridSpec, RaySpec};
pub use crate::precision::{Engine, Precision};
use curvicast::F32Fast;
use curvicast::march::{
    AnyGrid, CellCrossing, CylindricalGrid, MarchError, PolarGrid, SeparableMarch, SphericalGrid,
};
use curvicast::ray::Ray;
use curvicast::real::Real;
use std::io::Write;
use std::path::{Path, PathBuf};

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

/// Runs the command, writing the answers to `out` as the rays arrive (see [`super::io`] for the streaming rules).
pub fn run(args: &MarchArgs, out: &mut dyn Write) -> anyhow::Result<()> {
    let spec = read_grid(&args.grid)?;
    let rays = args.rays.as_deref();
    match args.precision {
        Precision::F64 => run_in::<f64>(&spec, &args.grid, rays, args.engine, out),
        Precision::F32 => run_in::<f32>(&spec, &args.grid, rays, args.engine, out),
        Precision::F32Fast => run_in::<F32Fast>(&spec, &args.grid, rays, args.engine, out),
    }
}

fn conv<T: Real>(v: &[f64]) -> Vec<T> {
    v.iter().map(|&x| T::from_f64(x)).collect()
}

/// The separable engine on a grid of any kind (the kernel's [`AnyGrid`] marches with the serial one).
trait Separable<T> {
    /// The largest capacity's buffers (3·N events of 24 bytes in f64: 2.4 MB for N = 32768, and the value is
    /// moved a few times) do not fit the main thread's stack: that march runs on a thread of its own.
    fn separable_on_own_stack<const N: usize>(
        &self,
        ray: &Ray<T>,
    ) -> Result<Vec<CellCrossing<T>>, String>
    where
        Self: Sync,
        T: Send + Sync,
    {
        let bytes = std::mem::size_of::<SeparableMarch<T, N>>();
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
    fn separable<const N: usize>(&self, ray: &Ray<T>) -> Result<Vec<CellCrossing<T>>, MarchError>;
}

impl<T: Real> Separable<T> for AnyGrid<'_, T> {
    #[inline(never)]
    fn separable<const N: usize>(&self, ray: &Ray<T>) -> Result<Vec<CellCrossing<T>>, MarchError> {
        Ok(match self {
            AnyGrid::Spherical(g) => g.march_separable::<N>(ray)?.collect(),
            AnyGrid::Cylindrical(g) => g.march_separable::<N>(ray)?.collect(),
            AnyGrid::Polar(g) => g.march_separable::<N>(ray)?.collect(),
        })
    }
}

fn run_in<T: Real + Send + Sync>(
    spec: &GridSpec,
    path: &Path,
    rays: Option<&Path>,
    engine: Engine,
    out: &mut dyn Write,
) -> anyhow::Result<()> {
    let bad = |e: curvicast::march::GridError| {
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
            grid = AnyGrid::Spherical(
                SphericalGrid::new(&a, &b, &c, &mut ws)
                    .and_then(|g| g.with_center(center3))
                    .map_err(bad)?,
            );
        }
        GridSpec::Cylindrical { .. } => {
            ws = vec![T::ZERO; CylindricalGrid::<T>::workspace_len(a.len(), b.len())];
            grid = AnyGrid::Cylindrical(
                CylindricalGrid::new(&a, &b, &c, &mut ws)
                    .and_then(|g| g.with_center(center3))
                    .map_err(bad)?,
            );
        }
        GridSpec::Polar { .. } => {
            ws = vec![T::ZERO; PolarGrid::<T>::workspace_len(a.len(), b.len())];
            grid = AnyGrid::Polar(
                PolarGrid::new(&a, &b, &mut ws)
                    .and_then(|g| g.with_center([center3[0], center3[1]]))
                    .map_err(bad)?,
            );
        }
    }
    // Separable buffers: at most about two crossings per breakpoint per axis (ditone r and θ), plus ties.
    let longest = a.len().max(b.len()).max(c.len());
    let need = 2 * longest + 8;
    // A ray crosses each sphere or cone at most twice and each half-plane or plane once, plus the zero-length
    // crossings at ties: a bound on one answer's length, which sizes the window of rays answered at once.
    let bound = (2 * (a.len() + b.len() + c.len()) + 8).saturating_mul(CROSSING_BYTES);
    let (window, spill) = if bound > STREAM_ONE_RAY_BYTES {
        (1, SPILL_BYTES)
    } else {
        ((WINDOW_BYTES / bound).clamp(1, MAX_WINDOW), usize::MAX)
    };
    let answer = |i: usize, line: RayLine, w: &mut dyn Write| -> std::io::Result<()> {
        let (ray, given) =
            match line.and_then(|r| Ok((make_ray::<T>(&r)?, (r.t_min, r.t_max_or_inf())))) {
                Ok(r) => r,
                Err(e) => return writeln!(w, "{}", error_line(i, &e)),
            };
        let result = match engine {
            Engine::Serial => {
                let mut m = grid.march(&ray);
                let (rest, streamed) = write_crossings(i, m.by_ref(), given, polar, spill, w)?;
                return finish_line(i, rest, streamed, m.error().map(|e| e.to_string()), w);
            }
            Engine::Separable if need <= 256 => {
                grid.separable::<256>(&ray).map_err(|e| e.to_string())
            }
            Engine::Separable if need <= 4096 => {
                grid.separable::<4096>(&ray).map_err(|e| e.to_string())
            }
            Engine::Separable => grid.separable_on_own_stack::<32768>(&ray),
        };
        match result {
            Ok(cs) => {
                let (rest, streamed) = write_crossings(i, cs.into_iter(), given, polar, spill, w)?;
                finish_line(i, rest, streamed, None, w)
            }
            Err(e) => writeln!(w, "{}", error_line(i, &e)),
        }
    };
    stream_answers(rays, out, window, "march", &answer)?;
    Ok(())
}

/// The most bytes one crossing takes in the output (`{"cell":[u32,u32,u32],"t_enter":f64,"t_exit":f64}`).
const CROSSING_BYTES: usize = 120;
/// Answers at most this long (by the grid's bound) are computed a window at a time in parallel.
const STREAM_ONE_RAY_BYTES: usize = 1 << 20;
/// The memory for one window of answers.
const WINDOW_BYTES: usize = 32 << 20;
/// The most rays in one window.
const MAX_WINDOW: usize = 4096;
/// When rays are answered one at a time, a ray's crossings are passed on to the output every this many bytes.
const SPILL_BYTES: usize = 1 << 16;

/// A crossing's `t` as written: the ray's given `t_min` or `t_max` (f64, as read) where `t` is that bound in the
/// march's precision, so that a ray ending inside the domain ends at its `t_max` bit for bit in every precision
/// (an `f32` march would otherwise print the bound rounded to `f32`); otherwise `t` itself.
fn t_out<T: Real>(t: T, (t_min, t_max): (f64, f64)) -> f64 {
    if t == T::from_f64(t_max) {
        t_max
    } else if t == T::from_f64(t_min) {
        t_min
    } else {
        t.to_f64()
    }
}

/// Writes `{"ray":i,"crossings":[` and the crossings to `out`, passing the text on every `spill` bytes; returns
/// the text not yet passed on and whether some was. `given` is the ray's `(t_min, t_max)` as read ([`t_out`]).
fn write_crossings<T: Real>(
    i: usize,
    crossings: impl Iterator<Item = CellCrossing<T>>,
    given: (f64, f64),
    polar: bool,
    spill: usize,
    out: &mut dyn Write,
) -> std::io::Result<(Vec<u8>, bool)> {
    let mut buf = Vec::with_capacity(256);
    write!(buf, "{{\"ray\":{i},\"crossings\":[")?;
    let mut streamed = false;
    for (k, c) in crossings.enumerate() {
        if k > 0 {
            buf.push(b',');
        }
        let [ci, cj, ck] = c.cell;
        if polar {
            write!(buf, "{{\"cell\":[{ci},{cj}],\"t_enter\":")?;
        } else {
            write!(buf, "{{\"cell\":[{ci},{cj},{ck}],\"t_enter\":")?;
        }
        serde_json::to_writer(&mut buf, &t_out(c.t_enter, given))?;
        buf.extend_from_slice(b",\"t_exit\":");
        serde_json::to_writer(&mut buf, &t_out(c.t_exit, given))?;
        buf.push(b'}');
        if buf.len() >= spill {
            out.write_all(&buf)?;
            buf.clear();
            streamed = true;
        }
    }
    Ok((buf, streamed))
}

/// Ends a ray's line: `]}`; or, when the march failed, the contract's error line — unless part of the crossings
/// was already written (a very long answer, see [`SPILL_BYTES`]): then the line keeps those crossings and gets
/// an `"error"` field after them.
fn finish_line(
    i: usize,
    mut rest: Vec<u8>,
    streamed: bool,
    error: Option<String>,
    out: &mut dyn Write,
) -> std::io::Result<()> {
    match error {
        None => rest.extend_from_slice(b"]}\n"),
        Some(e) if !streamed => return writeln!(out, "{}", error_line(i, &e)),
        Some(e) => {
            rest.extend_from_slice(b"],\"error\":");
            serde_json::to_writer(&mut rest, &e)?;
            rest.extend_from_slice(b"}\n");
        }
    }
    out.write_all(&rest)
}

/// The kernel ray for a rays-file line, or the message of the `{"ray": i, "error": ..}` line.
pub fn make_ray<T: Real>(r: &RaySpec) -> Result<Ray<T>, String> {
    let v = |a: [f64; 3]| [T::from_f64(a[0]), T::from_f64(a[1]), T::from_f64(a[2])];
    let t_max = T::from_f64(r.t_max_or_inf());
    Ray::new(v(r.origin), v(r.dir))
        .and_then(|ray| ray.with_interval(T::from_f64(r.t_min), t_max))
        .map_err(|e| e.to_string())
}
