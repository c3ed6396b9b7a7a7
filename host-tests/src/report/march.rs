//! Report section: marching (Hannasch, ch. 3, 5 and 6) — speed of the serial and separable engines in
//! f64, f32 and f32-fast on a 64³ full-sphere grid, side by side with their measured errors against the oracle,
//! and the Cartesian-resampling baseline (Amanatides–Woo DDA over an n³ voxel grid).

use super::{Options, Section};
use crate::march_run::{self as run, Engine, Precision, Rounded};
use crate::oracle::march::{KernelCrossing, MarchOracle, compare, same_sequence};
use crate::scenes::march_cases as mc;
use crate::scenes::marching::{Breakpoints, CELLS, GridLayout, parallel_rays, perspective_rays};
use curvicast::march::SeparableMarch;
use curvicast::ray::Ray;
use curvicast::real::{F32Fast, Real};
use curvicast_cli::formats::spec::{GridSpec, RaySpec};
use curvicast_cli::render::dda::{VoxelCrossing, VoxelGrid};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::time::Instant;

const SEPARABLE_N: usize = 512;

struct Timing {
    ns_per_ray: f64,
    ns_per_crossing: f64,
    crossings_per_ray: f64,
}

/// Times one engine and precision on `rays` through the scene's grid `kind`, under the report's one timing
/// policy: every method starts from the same `f64` ray records, builds its own ray inside the timed region, and
/// keeps the best of `reps` passes. The separable engine lists into one march reused across the rays
/// (`march_separable_into`), as a caller marching many rays does. A ray the kernel rejects or an engine error is
/// an error of the section (nothing is skipped silently).
fn time_engine<T: Real>(
    kind: GridLayout,
    rays: &[RaySpec],
    engine: Engine,
    reps: usize,
) -> anyhow::Result<Timing> {
    let mut breakpoints = Breakpoints::<T>::new(kind);
    let grid = breakpoints
        .grid()
        .map_err(|e| anyhow::anyhow!("{} benchmark grid in {}: {e}", kind.name(), T::NAME))?;
    let mut separable = SeparableMarch::<T, SEPARABLE_N>::default();
    let mut best = f64::INFINITY;
    let mut crossings = 0usize;
    let mut sink = 0.0f64;
    for _ in 0..reps.max(1) {
        crossings = 0;
        let mut failed: Option<(usize, String)> = None;
        let start = Instant::now();
        for (k, s) in rays.iter().enumerate() {
            let ray = match Ray::new(s.origin.map(T::from_f64), s.dir.map(T::from_f64)) {
                Ok(ray) => ray,
                Err(e) => {
                    failed.get_or_insert((k, format!("ray rejected: {e}")));
                    continue;
                }
            };
            match engine {
                Engine::Serial => {
                    // internal iteration (`fold_in_place`), the serial engine's fastest use
                    let mut march = grid.march(&ray);
                    (crossings, sink) = march.fold_in_place((crossings, sink), |(n, s), c| {
                        (n + 1, s + (c.t_exit - c.t_enter).to_f64())
                    });
                    if let Some(e) = march.error() {
                        failed.get_or_insert((k, e.to_string()));
                    }
                }
                Engine::Separable => match grid.march_separable_into(&ray, &mut separable) {
                    Ok(()) => {
                        for c in separable.by_ref() {
                            crossings += 1;
                            sink += (c.t_exit - c.t_enter).to_f64();
                        }
                    }
                    Err(e) => {
                        failed.get_or_insert((k, e.to_string()));
                    }
                },
            }
        }
        best = best.min(start.elapsed().as_secs_f64());
        if let Some((k, e)) = failed {
            anyhow::bail!(
                "{engine:?} {} on the {} grid: ray {k} of the benchmark failed: {e}",
                T::NAME,
                kind.name()
            );
        }
    }
    std::hint::black_box(sink);
    let n = rays.len().max(1) as f64;
    Ok(Timing {
        ns_per_ray: best * 1e9 / n,
        ns_per_crossing: best * 1e9 / crossings.max(1) as f64,
        crossings_per_ray: crossings as f64 / n,
    })
}

fn time_mode(
    kind: GridLayout,
    rays: &[RaySpec],
    e: Engine,
    p: Precision,
    reps: usize,
) -> anyhow::Result<Timing> {
    match p {
        Precision::F64 => time_engine::<f64>(kind, rays, e, reps),
        Precision::F32 => time_engine::<f32>(kind, rays, e, reps),
        Precision::F32Fast => time_engine::<F32Fast>(kind, rays, e, reps),
    }
}

/// Oracle errors of one mode on a sample of rays of the benchmark grid.
struct Accuracy {
    same: usize,
    n: usize,
    max_bwd: f64,
}

fn accuracy(g: &GridSpec, sample: &[RaySpec], e: Engine, p: Precision) -> Accuracy {
    let g = p.round_grid(g);
    let Ok(o) = MarchOracle::new_for(&g, p.eps()) else {
        return Accuracy {
            same: 0,
            n: 0,
            max_bwd: f64::NAN,
        };
    };
    let res: Vec<(bool, f64)> = sample
        .par_iter()
        .map(|r0| {
            let r = p.round_ray(r0);
            let reference = o.march(&r);
            match run::run_engine(&g, &r, e, p) {
                Ok(k) => match compare(&o, &reference, &k, p.eps(), None) {
                    Ok(s) => (true, s.max_backward_eps),
                    Err(_) => (false, 0.0),
                },
                Err(_) => (false, 0.0),
            }
        })
        .collect();
    Accuracy {
        same: res.iter().filter(|x| x.0).count(),
        n: res.len(),
        max_bwd: res.iter().map(|x| x.1).fold(0.0, f64::max),
    }
}

fn voxel_list(v: &[VoxelCrossing]) -> Vec<KernelCrossing> {
    v.iter()
        .map(|c| KernelCrossing {
            cell: c.cell,
            t_enter: c.t_enter,
            t_exit: c.t_exit,
        })
        .collect()
}

/// The marching section of the report.
pub fn section(opts: &Options) -> anyhow::Result<Section> {
    let quick = opts.quick;
    let m = if quick { 64 } else { 256 };
    let reps = if quick { 1 } else { 3 };
    let grid = GridLayout::Uniform.spec();
    let parallel = parallel_rays(m);
    let views = [
        ("parallel", GridLayout::Uniform, parallel.clone()),
        ("parallel", GridLayout::NonUniform, parallel.clone()),
        ("parallel", GridLayout::Partial, parallel),
        (
            "perspective from 3R",
            GridLayout::Uniform,
            perspective_rays(m),
        ),
    ];
    let n_acc = if quick { 120 } else { 1000 };
    let mut md = String::new();
    writeln!(
        md,
        "Grids: {c}³ cells, uniform in r ∈ [0, 1], θ ∈ [0, π], φ ∈ [0, 2π]; the same ranges with random (seeded) \
         non-uniform breakpoints; and a partial domain (shell r ∈ [0.3, 1], zenith band θ ∈ [0.4, 2.6], wedge \
         φ ∈ [−1, 4]), uniform. Views: {m}² parallel rays (direction (1, 0.15, 0.1)) on each grid and a {m}² \
         perspective view from 3R on the uniform grid. Times are the best of {reps} run(s) on one core, every \
         method (each engine and precision, and the DDA baseline) starting from the same f64 ray records and \
         building its own rays inside the timed region; the serial engine runs its internal iteration \
         (`fold_in_place`, about 1 % fewer instructions than a `for` loop over `next`); the separable engine \
         (N = {SEPARABLE_N}) lists into one march reused across the rays (`march_separable_into`). A ray an engine rejects fails the report. The \
         oracle columns are measured on {n_acc} rays of the parallel view of the uniform grid (\"same cells\": \
         identical cell sequence after dropping crossings shorter than 1e-7·L; \"max bwd\": largest distance of \
         a crossing point from its surface, in eps·L of that precision). Instruction counts of the same scenes: \
         `host-tests/examples/march_count.rs`.\n",
        c = CELLS
    )?;
    let sample: Vec<RaySpec> = {
        let all = &views[0].2;
        let step = (all.len() / n_acc).max(1);
        all.iter().step_by(step).take(n_acc).copied().collect()
    };
    md.push_str("| view | grid | engine | precision | crossings/ray | ns/ray | ns/crossing | same cells (oracle) | max bwd (eps·L) |\n");
    md.push_str("|---|---|---|---|---:|---:|---:|---:|---:|\n");
    let mut serial_f64 = [f64::NAN; 4];
    for (vi, (vname, kind, rays)) in views.iter().enumerate() {
        for &(e, p) in &run::ALL_MODES {
            let t = time_mode(*kind, rays, e, p, reps)?;
            if e == Engine::Serial && p == Precision::F64 {
                serial_f64[vi] = t.ns_per_ray;
            }
            let acc_txt = if vi == 0 {
                let a = accuracy(&grid, &sample, e, p);
                format!(
                    "{}/{} ({:.1} %) | {:.2}",
                    a.same,
                    a.n,
                    100.0 * a.same as f64 / a.n.max(1) as f64,
                    a.max_bwd
                )
            } else {
                "(see uniform parallel) | ".to_string()
            };
            writeln!(
                md,
                "| {vname} | {} | {e:?} | {} | {:.1} | {:.0} | {:.1} | {acc_txt} |",
                kind.describe(),
                p.name(),
                t.crossings_per_ray,
                t.ns_per_ray,
                t.ns_per_crossing
            )?;
        }
    }
    // the baseline
    md.push_str("\nBaseline: the cell index field resampled onto n³ voxels (not timed, done once), marched with the \
                 Amanatides–Woo DDA, each voxel mapped back to the spherical cell of its center.\n\n");
    md.push_str("| view | voxels | ns/ray | vs serial f64 | same cells as oracle |\n|---|---|---:|---:|---:|\n");
    let GridSpec::Spherical { r, theta, phi, .. } = &grid else {
        anyhow::bail!("benchmark grid is spherical");
    };
    let o = MarchOracle::new(&grid).map_err(|e| anyhow::anyhow!("{e}"))?;
    let references: Vec<_> = sample.par_iter().map(|r| o.march(r)).collect();
    for n in [64usize, 128] {
        let vg = VoxelGrid::resample([0.0; 3], r, theta, phi, n);
        let same = sample
            .iter()
            .zip(&references)
            .filter(|(ray, reference)| {
                let mut out = Vec::new();
                vg.march(ray.origin, ray.dir, ray.t_min, ray.t_max_or_inf(), &mut out);
                same_sequence(reference, &voxel_list(&out))
            })
            .count();
        for (vi, (vname, kind, rays)) in views.iter().enumerate() {
            if *kind != GridLayout::Uniform {
                continue;
            }
            let mut out = Vec::new();
            let mut best = f64::INFINITY;
            let mut sink = 0usize;
            for _ in 0..reps {
                let start = Instant::now();
                for ray in rays {
                    vg.march(ray.origin, ray.dir, ray.t_min, ray.t_max_or_inf(), &mut out);
                    sink += out.len();
                }
                best = best.min(start.elapsed().as_secs_f64());
            }
            std::hint::black_box(sink);
            let ns = best * 1e9 / rays.len() as f64;
            writeln!(
                md,
                "| {vname} | {n}³ | {ns:.0} | {:.2}× | {} |",
                ns / serial_f64[vi],
                if vi == 0 {
                    format!(
                        "{same}/{} ({:.1} %)",
                        sample.len(),
                        100.0 * same as f64 / sample.len().max(1) as f64
                    )
                } else {
                    "(see parallel)".into()
                }
            )?;
        }
    }
    // the random suite
    let n_suite = if quick { 1000 } else { 20_000 };
    let inputs = mc::random_suite_inputs(n_suite, 99);
    let rows = run::run_suite(&inputs, &run::ALL_MODES);
    writeln!(
        md,
        "\nRandom suite: {n_suite} random rays over {} random non-uniform full and partial grids (spherical, \
         cylindrical, polar). The full 200 000-ray suite: `curvicast-march-oracle --rays 200000`.\n",
        inputs.len()
    )?;
    md.push_str("| engine | precision | same cells | identical incl. ties | within 16 eps·L | structure violations | errors | max bwd (eps·L) | max fwd (eps·L) |\n");
    md.push_str("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for r in &rows {
        let pct = |x: usize| 100.0 * x as f64 / r.rays.max(1) as f64;
        writeln!(
            md,
            "| {:?} | {} | {:.2} % | {:.2} % | {:.2} % | {} | {} | {:.2} | {:.2} |",
            r.engine.unwrap_or(Engine::Serial),
            r.precision.map(|p| p.name()).unwrap_or("?"),
            pct(r.same_sequence),
            pct(r.identical_raw),
            pct(r.within_backward_bound),
            r.structure_violations,
            r.engine_errors,
            r.max_backward_eps,
            r.max_forward_eps
        )?;
    }
    Ok(Section {
        title: "Marching through spherical grids (Hannasch)".into(),
        markdown: md,
    })
}

/// Runs the random suite of `n` rays and renders it as text (the `curvicast-march-oracle` command); returns the
/// text and whether every f64 ray passed the criterion with no structural violation in any precision.
pub fn oracle_suite_text(n: usize, seed: u64) -> (String, bool) {
    let inputs = mc::random_suite_inputs(n, seed);
    let rows = run::run_suite(&inputs, &run::ALL_MODES);
    let mut s = String::new();
    let mut ok = true;
    for r in &rows {
        let p = r.precision.unwrap_or(Precision::F64);
        let _ = writeln!(
            s,
            "{:?}/{}: {} rays; same cells {}; identical incl. ties {}; within 16 eps·L {}; pass {}; structure \
             violations {}; errors {}; max backward {:.2} eps·L; max forward {:.2} eps·L",
            r.engine.unwrap_or(Engine::Serial),
            p.name(),
            r.rays,
            r.same_sequence,
            r.identical_raw,
            r.within_backward_bound,
            r.pass,
            r.structure_violations,
            r.engine_errors,
            r.max_backward_eps,
            r.max_forward_eps
        );
        if (p == Precision::F64 && r.pass != r.rays)
            || r.structure_violations > 0
            || r.engine_errors > 0
        {
            ok = false;
            for f in &r.failures {
                let _ = writeln!(s, "  failure: {f}");
            }
        }
    }
    (s, ok)
}
