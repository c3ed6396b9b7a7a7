//! A fixed marching workload for instruction counting (callgrind): the report's scene — a 64³ full-sphere grid,
//! `m²` parallel rays with direction (1, 0.15, 0.1) — marched `passes` times.
//!
//! ```sh
//! cargo build --release -p curvicast-host --example march_count
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/march_count f64 serial uniform 64 1
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/march_count f64 serial uniform 64 3
//! ```
//!
//! The difference of the two totals, divided by `(3 − 1) ·` the crossings printed, is the instructions per
//! crossing with the per-ray set-up amortised in (the grid and ray construction cancel out).
//!
//! Arguments: `PRECISION` (`f64`, `f32`, `f32-fast`), `ENGINE` (`serial`, or `separable`: one march filled in
//! place for each ray), `GRID` (`uniform`: the report's grid; `nonuniform`: random breakpoints; `partial`: a
//! shell r ∈ [0.3, 1], θ ∈ [0.4, 2.6], φ ∈ [−1, 4]), `M` (rays per side) and `PASSES`.

use curvicast::F32Fast;
use curvicast::ray::Ray;
use curvicast::real::Real;
use curvicast::spherical::{SeparableMarch, SphericalGrid};
use rand::{Rng, SeedableRng};
use std::f64::consts::{PI, TAU};
use std::hint::black_box;

const CELLS: usize = 64;

fn uniform(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect()
}

/// `n` cells from `lo` to `hi` with random (seeded) widths between 0.25 and 1.75 times the mean.
fn random(n: usize, lo: f64, hi: f64, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<f64> {
    let w: Vec<f64> = (0..n).map(|_| rng.random_range(0.25..1.75)).collect();
    let total: f64 = w.iter().sum();
    let mut out = vec![lo];
    let mut acc = 0.0;
    for x in &w[..n - 1] {
        acc += x;
        out.push(lo + (hi - lo) * acc / total);
    }
    out.push(hi);
    out
}

fn grid_breakpoints(kind: &str) -> [Vec<f64>; 3] {
    match kind {
        "uniform" => [
            uniform(CELLS, 0.0, 1.0),
            uniform(CELLS, 0.0, PI),
            uniform(CELLS, 0.0, TAU),
        ],
        "nonuniform" => {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(16);
            [
                random(CELLS, 0.0, 1.0, &mut rng),
                random(CELLS, 0.0, PI, &mut rng),
                random(CELLS, 0.0, TAU, &mut rng),
            ]
        }
        "partial" => [
            uniform(CELLS, 0.3, 1.0),
            uniform(CELLS, 0.4, 2.6),
            uniform(CELLS, -1.0, 4.0),
        ],
        _ => panic!("GRID is uniform, nonuniform or partial"),
    }
}

/// The report's parallel rays: `m²` origins on a square of side 2.1 across the ball, 3 units back along d.
fn parallel_rays(m: usize) -> Vec<([f64; 3], [f64; 3])> {
    let d = [1.0, 0.15, 0.1];
    let n = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let d = d.map(|a: f64| a / n.sqrt());
    let u = {
        let w = [-d[1], d[0], 0.0];
        let l = (w[0] * w[0] + w[1] * w[1]).sqrt();
        w.map(|a| a / l)
    };
    let v = [
        d[1] * u[2] - d[2] * u[1],
        d[2] * u[0] - d[0] * u[2],
        d[0] * u[1] - d[1] * u[0],
    ];
    let mut out = Vec::with_capacity(m * m);
    for i in 0..m {
        for j in 0..m {
            let a = -1.05 + 2.1 * (i as f64 + 0.5) / m as f64;
            let b = -1.05 + 2.1 * (j as f64 + 0.5) / m as f64;
            out.push(([0, 1, 2].map(|k| a * u[k] + b * v[k] - 3.0 * d[k]), d));
        }
    }
    out
}

fn run<T: Real>(engine: &str, kind: &str, m: usize, passes: usize) {
    let conv = |v: &Vec<f64>| v.iter().map(|&a| T::from_f64(a)).collect::<Vec<T>>();
    let [r, th, ph] = grid_breakpoints(kind);
    let (r, th, mut ph) = (conv(&r), conv(&th), conv(&ph));
    if kind != "partial" {
        if let Some(last) = ph.last_mut() {
            *last = T::PI + T::PI; // a full turn in T
        }
    }
    let mut ws = vec![T::ZERO; SphericalGrid::<T>::workspace_len(r.len(), th.len(), ph.len())];
    let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).expect("valid grid");
    let rays: Vec<Ray<T>> = parallel_rays(m)
        .iter()
        .map(|(o, d)| Ray::new(o.map(T::from_f64), d.map(T::from_f64)).expect("valid ray"))
        .collect();
    let mut crossings = 0usize;
    let mut acc = T::ZERO;
    // the separable engine's buffers, filled in place for each ray
    let mut separable = SeparableMarch::<T, 512>::default();
    for _ in 0..passes {
        for ray in &rays {
            match engine {
                "serial" => {
                    for c in grid.march(black_box(ray)) {
                        acc += c.t_exit - c.t_enter;
                        crossings += 1;
                    }
                }
                "separable" => {
                    grid.march_separable_into(black_box(ray), &mut separable)
                        .expect("fits 512");
                    for c in separable.by_ref() {
                        acc += c.t_exit - c.t_enter;
                        crossings += 1;
                    }
                }
                _ => panic!("ENGINE is serial or separable"),
            }
        }
    }
    black_box(acc);
    println!(
        "{} {engine} {kind} {m}^2 rays x {passes} passes: {crossings} crossings ({} per pass, {:.2} per ray)",
        T::NAME,
        crossings / passes.max(1),
        crossings as f64 / (passes.max(1) * rays.len()) as f64
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, precision, engine, kind, m, passes] = args.as_slice() else {
        eprintln!(
            "usage: march_count f64|f32|f32-fast serial|separable uniform|nonuniform|partial M PASSES"
        );
        std::process::exit(2);
    };
    let m: usize = m.parse().expect("M is a number");
    let passes: usize = passes.parse().expect("PASSES is a number");
    match precision.as_str() {
        "f64" => run::<f64>(engine, kind, m, passes),
        "f32" => run::<f32>(engine, kind, m, passes),
        "f32-fast" => run::<F32Fast>(engine, kind, m, passes),
        _ => panic!("PRECISION is f64, f32 or f32-fast"),
    }
}
