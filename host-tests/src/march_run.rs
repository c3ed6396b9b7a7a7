//! The kernel's marchers run on the scenes' grids and rays ([`GridSpec`], [`RaySpec`]) in either engine and in
//! `f64`, `f32` or fast-math `f32`, and compared with the oracle ([`crate::oracle::march`]): what the marching
//! tests and the report share. It sits beside the scenes and the oracle, not in either (like
//! [`curvicast_cli::storage`] for terrain): the scenes are data and generators, the oracle never calls the kernel, and
//! this module uses both.

use crate::oracle::march::{KernelCrossing, MarchOracle, Mismatch, compare};
use curvicast::march::{CylindricalGrid, PolarGrid, SphericalGrid};
use curvicast::ray::Ray;
use curvicast::real::{F32Fast, Real};
use curvicast_cli::formats::spec::{GridSpec, RaySpec};

pub use curvicast_cli::precision::{Engine, Precision};

/// The inputs as the kernel of a precision sees them (values rounded to `f32` where it is `f32`), so that the
/// oracle measures the engine and not the rounding of its input.
pub trait Rounded {
    /// The grid with its breakpoints and center in the precision.
    fn round_grid(self, g: &GridSpec) -> GridSpec;
    /// The ray with its origin, direction and interval in the precision.
    fn round_ray(self, r: &RaySpec) -> RaySpec;
}

impl Rounded for Precision {
    fn round_grid(self, g: &GridSpec) -> GridSpec {
        if self == Precision::F64 {
            return g.clone();
        }
        let v = |x: &Vec<f64>| x.iter().map(|&a| a as f32 as f64).collect::<Vec<_>>();
        match g {
            GridSpec::Spherical {
                center,
                r,
                theta,
                phi,
            } => GridSpec::Spherical {
                center: center.map(|c| c.map(|a| a as f32 as f64)),
                r: v(r),
                theta: v(theta),
                phi: v(phi),
            },
            GridSpec::Cylindrical {
                center,
                rho,
                phi,
                z,
            } => GridSpec::Cylindrical {
                center: center.map(|c| c.map(|a| a as f32 as f64)),
                rho: v(rho),
                phi: v(phi),
                z: v(z),
            },
            GridSpec::Polar { center, r, phi } => GridSpec::Polar {
                center: center.map(|c| c.map(|a| a as f32 as f64)),
                r: v(r),
                phi: v(phi),
            },
        }
    }
    fn round_ray(self, r: &RaySpec) -> RaySpec {
        if self == Precision::F64 {
            return *r;
        }
        let f = |a: f64| a as f32 as f64;
        RaySpec {
            origin: r.origin.map(f),
            dir: r.dir.map(f),
            t_min: f(r.t_min),
            t_max: r.t_max.map(f),
        }
    }
}

/// Capacity of the separable engine's per-coordinate buffers in these tests.
pub const SEPARABLE_CAPACITY: usize = 512;

/// Runs one engine on one ray; an error names what the kernel rejected or why the march stopped.
pub fn run_engine(
    grid: &GridSpec,
    ray: &RaySpec,
    engine: Engine,
    precision: Precision,
) -> Result<Vec<KernelCrossing>, String> {
    match precision {
        Precision::F64 => run_typed::<f64>(grid, ray, engine),
        Precision::F32 => run_typed::<f32>(grid, ray, engine),
        Precision::F32Fast => run_typed::<F32Fast>(grid, ray, engine),
    }
}

fn conv<T: Real>(v: &[f64]) -> Vec<T> {
    v.iter().map(|&a| T::from_f64(a)).collect()
}

fn collect<T: Real>(
    it: impl Iterator<Item = curvicast::march::CellCrossing<T>>,
) -> Vec<KernelCrossing> {
    it.map(|c| KernelCrossing {
        cell: c.cell,
        t_enter: c.t_enter.to_f64(),
        t_exit: c.t_exit.to_f64(),
    })
    .collect()
}

fn run_typed<T: Real>(
    g: &GridSpec,
    r: &RaySpec,
    engine: Engine,
) -> Result<Vec<KernelCrossing>, String> {
    let origin: [T; 3] = r.origin.map(T::from_f64);
    let dir: [T; 3] = r.dir.map(T::from_f64);
    let ray = Ray::new(origin, dir)
        .and_then(|ray| ray.with_interval(T::from_f64(r.t_min), T::from_f64(r.t_max_or_inf())))
        .map_err(|e| format!("ray: {e}"))?;
    macro_rules! go {
        ($grid:expr) => {{
            let grid = $grid;
            match engine {
                Engine::Serial => {
                    let mut it = grid.march(&ray);
                    let v = collect(it.by_ref());
                    match it.error() {
                        Some(e) => Err(format!("serial march: {e}")),
                        None => Ok(v),
                    }
                }
                Engine::Separable => grid
                    .march_separable::<SEPARABLE_CAPACITY>(&ray)
                    .map(collect)
                    .map_err(|e| format!("separable march: {e}")),
            }
        }};
    }
    match g {
        GridSpec::Spherical {
            center,
            r,
            theta,
            phi,
        } => {
            let (r, th, ph) = (conv::<T>(r), conv::<T>(theta), conv::<T>(phi));
            let mut ws =
                vec![T::ZERO; SphericalGrid::<T>::workspace_len(r.len(), th.len(), ph.len())];
            let grid = SphericalGrid::new(&r, &th, &ph, &mut ws)
                .and_then(|g| g.with_center(center.unwrap_or([0.0; 3]).map(T::from_f64)))
                .map_err(|e| format!("grid: {e}"))?;
            go!(grid)
        }
        GridSpec::Cylindrical {
            center,
            rho,
            phi,
            z,
        } => {
            let (rho, ph, z) = (conv::<T>(rho), conv::<T>(phi), conv::<T>(z));
            let mut ws = vec![T::ZERO; CylindricalGrid::<T>::workspace_len(rho.len(), ph.len())];
            let grid = CylindricalGrid::new(&rho, &ph, &z, &mut ws)
                .and_then(|g| g.with_center(center.unwrap_or([0.0; 3]).map(T::from_f64)))
                .map_err(|e| format!("grid: {e}"))?;
            go!(grid)
        }
        GridSpec::Polar { center, r, phi } => {
            let (r, ph) = (conv::<T>(r), conv::<T>(phi));
            let mut ws = vec![T::ZERO; PolarGrid::<T>::workspace_len(r.len(), ph.len())];
            let grid = PolarGrid::new(&r, &ph, &mut ws)
                .and_then(|g| g.with_center(center.unwrap_or([0.0; 2]).map(T::from_f64)))
                .map_err(|e| format!("grid: {e}"))?;
            go!(grid)
        }
    }
}

/// Results of one engine in one precision over a set of rays.
#[derive(Debug, Clone, Default)]
pub struct SuiteRow {
    /// The engine.
    pub engine: Option<Engine>,
    /// The precision.
    pub precision: Option<Precision>,
    /// Rays run.
    pub rays: usize,
    /// Rays whose cell sequence equals the oracle's after dropping crossings shorter than `1e-7·L`.
    pub same_sequence: usize,
    /// Rays whose cell sequence equals the oracle's without dropping anything.
    pub identical_raw: usize,
    /// Rays whose every crossing point lies within `16·eps·L` of its boundary surface.
    pub within_backward_bound: usize,
    /// Rays that pass the whole criterion (structure, sequence, backward bound).
    pub pass: usize,
    /// Rays breaking a structural invariant of the contract.
    pub structure_violations: usize,
    /// Rays the engine refused or stopped on with an error.
    pub engine_errors: usize,
    /// Largest backward error seen, in `eps·L`.
    pub max_backward_eps: f64,
    /// Largest forward error of t seen (matched clean ends), in `eps·L / |d|`.
    pub max_forward_eps: f64,
    /// Crossings the engine produced in total.
    pub crossings: usize,
    /// The first few failures, described.
    pub failures: Vec<String>,
}

/// Runs the engine/precision pairs over the inputs against the oracle (in parallel) and tabulates the results.
pub fn run_suite(
    inputs: &[(GridSpec, Vec<RaySpec>)],
    modes: &[(Engine, Precision)],
) -> Vec<SuiteRow> {
    use rayon::prelude::*;
    let bound = crate::tolerances::MARCH_F64_BOUNDARY.bound;
    let per_grid: Vec<Vec<SuiteRow>> = inputs
        .par_iter()
        .map(|(g0, rays)| {
            let mut rows: Vec<SuiteRow> = modes
                .iter()
                .map(|&(e, p)| SuiteRow {
                    engine: Some(e),
                    precision: Some(p),
                    ..Default::default()
                })
                .collect();
            let mut oracles: Vec<(Precision, GridSpec, Option<MarchOracle>)> = Vec::new();
            for &(_, p) in modes {
                if !oracles.iter().any(|o| o.0 == p) {
                    let g = p.round_grid(g0);
                    let o = MarchOracle::new_for(&g, p.eps()).ok();
                    oracles.push((p, g, o));
                }
            }
            for ray0 in rays {
                for (p, g, o) in &oracles {
                    let Some(o) = o else { continue };
                    let ray = p.round_ray(ray0);
                    let reference = o.march(&ray);
                    for (row, &(e, mp)) in rows.iter_mut().zip(modes) {
                        if mp != *p {
                            continue;
                        }
                        row.rays += 1;
                        let k = match run_engine(g, &ray, e, mp) {
                            Ok(k) => k,
                            Err(msg) => {
                                row.engine_errors += 1;
                                if row.failures.len() < 5 {
                                    row.failures
                                        .push(format!("{msg}\n  grid {g:?}\n  ray {ray:?}"));
                                }
                                continue;
                            }
                        };
                        row.crossings += k.len();
                        match compare(o, &reference, &k, mp.eps(), None) {
                            Ok(s) => {
                                row.same_sequence += 1;
                                row.identical_raw += usize::from(s.identical_raw);
                                let ok_b = s.max_backward_eps <= bound;
                                row.within_backward_bound += usize::from(ok_b);
                                row.pass += usize::from(ok_b);
                                row.max_backward_eps = row.max_backward_eps.max(s.max_backward_eps);
                                row.max_forward_eps = row.max_forward_eps.max(s.max_forward_eps);
                                if !ok_b && row.failures.len() < 5 {
                                    row.failures.push(format!(
                                        "backward error {:.1} eps·L\n  grid {g:?}\n  ray {ray:?}",
                                        s.max_backward_eps
                                    ));
                                }
                            }
                            Err(m) => {
                                if matches!(m, Mismatch::Structure(_)) {
                                    row.structure_violations += 1;
                                }
                                if row.failures.len() < 5 {
                                    row.failures
                                        .push(format!("{m}\n  grid {g:?}\n  ray {ray:?}"));
                                }
                            }
                        }
                    }
                }
            }
            rows
        })
        .collect();
    let mut total: Vec<SuiteRow> = modes
        .iter()
        .map(|&(e, p)| SuiteRow {
            engine: Some(e),
            precision: Some(p),
            ..Default::default()
        })
        .collect();
    for rows in per_grid {
        for (t, r) in total.iter_mut().zip(rows) {
            t.rays += r.rays;
            t.same_sequence += r.same_sequence;
            t.identical_raw += r.identical_raw;
            t.within_backward_bound += r.within_backward_bound;
            t.pass += r.pass;
            t.structure_violations += r.structure_violations;
            t.engine_errors += r.engine_errors;
            t.crossings += r.crossings;
            t.max_backward_eps = t.max_backward_eps.max(r.max_backward_eps);
            t.max_forward_eps = t.max_forward_eps.max(r.max_forward_eps);
            for f in r.failures {
                if t.failures.len() < 5 {
                    t.failures.push(f);
                }
            }
        }
    }
    total
}

/// All engine × precision pairs.
pub const ALL_MODES: [(Engine, Precision); 6] = [
    (Engine::Serial, Precision::F64),
    (Engine::Separable, Precision::F64),
    (Engine::Serial, Precision::F32),
    (Engine::Separable, Precision::F32),
    (Engine::Serial, Precision::F32Fast),
    (Engine::Separable, Precision::F32Fast),
];
