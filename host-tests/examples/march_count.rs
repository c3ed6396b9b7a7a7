//! A fixed marching workload for instruction counting (callgrind): the report's marching scene
//! (`curvicast_host::scenes::marching`: a 64³ grid, `m²` parallel rays with direction (1, 0.15, 0.1)) marched
//! `passes` times.
//!
//! ```sh
//! cargo build --release -p curvicast-host --example march_count
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/march_count f64 serial uniform 64 1
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/march_count f64 serial uniform 64 3
//! ```
//!
//! The difference of the two totals, divided by `(3 − 1) ·` the crossings printed, is the instructions per
//! crossing with the per-ray set-up amortised in (the grid and ray construction cancel out). The `separable`
//! engine also prints the events (band changes, the steps of either engine): on a partial domain some events
//! emit no crossing (a ray inside the hole of a shell or outside a wedge), so there the cost per event differs
//! from the cost per crossing.
//!
//! Arguments: `PRECISION` (`f64`, `f32`, `f32-fast`), `ENGINE` (`serial`: a `for` loop over the serial
//! march; `serial-fold`: the same march consumed by `Iterator::fold`, its internal iteration; `separable`: one march filled in
//! place for each ray; `batch`: the serial engine through `curvicast_cli::batch::march_batch`, on
//! `RAYON_NUM_THREADS` threads), `GRID` (`uniform`: the report's grid; `nonuniform`: random breakpoints; `partial`: a
//! shell r ∈ [0.3, 1], θ ∈ [0.4, 2.6], φ ∈ [−1, 4]), `M` (rays per side) and `PASSES`.

use curvicast::F32Fast;
use curvicast::march::SeparableMarch;
use curvicast::real::Real;
use curvicast_cli::batch::march_batch;
use curvicast_host::scenes::marching::{Breakpoints, GridLayout, parallel_rays, rays_in};
use std::hint::black_box;

fn run<T: Real>(engine: &str, kind: GridLayout, m: usize, passes: usize) {
    let mut breakpoints = Breakpoints::<T>::new(kind);
    let grid = breakpoints.grid().expect("valid grid");
    let rays = rays_in::<T>(&parallel_rays(m)).expect("valid rays");
    let mut crossings = 0usize;
    // the separable engine's events (band changes of the three coordinates, each a step of the serial engine
    // too), so that a cost per crossing can be read as a cost per event where some events emit no crossing
    let mut events = 0usize;
    let mut acc = T::ZERO;
    // the separable engine's buffers, filled in place for each ray
    let mut separable = SeparableMarch::<T, 512>::default();
    for _ in 0..passes {
        if engine == "batch" {
            // the whole image at once across rayon's pool (`RAYON_NUM_THREADS` threads)
            let per_ray = march_batch(&grid, black_box(&rays), |_, m| {
                m.fold((T::ZERO, 0usize), |(a, n), c| {
                    (a + (c.t_exit - c.t_enter), n + 1)
                })
            });
            for (a, n) in per_ray {
                acc += a;
                crossings += n;
            }
            continue;
        }
        for ray in &rays {
            match engine {
                "serial" => {
                    for c in grid.march(black_box(ray)) {
                        acc += c.t_exit - c.t_enter;
                        crossings += 1;
                    }
                }
                "serial-fold" => {
                    // internal iteration: the march's own loop (`Iterator::fold`) calls back per crossing
                    let (a, n) = grid
                        .march(black_box(ray))
                        .fold((T::ZERO, 0usize), |(a, n), c| {
                            (a + (c.t_exit - c.t_enter), n + 1)
                        });
                    acc += a;
                    crossings += n;
                }
                "separable" => {
                    grid.march_separable_into(black_box(ray), &mut separable)
                        .expect("fits 512");
                    events += separable.listed().iter().sum::<usize>();
                    for c in separable.by_ref() {
                        acc += c.t_exit - c.t_enter;
                        crossings += 1;
                    }
                }
                _ => panic!("ENGINE is serial, serial-fold, separable or batch"),
            }
        }
    }
    black_box(acc);
    println!(
        "{} {engine} {} {m}^2 rays x {passes} passes: {crossings} crossings ({} per pass, {:.2} per ray)",
        T::NAME,
        kind.name(),
        crossings / passes.max(1),
        crossings as f64 / (passes.max(1) * rays.len()) as f64
    );
    if events > 0 {
        println!(
            "{events} events ({:.3} per crossing)",
            events as f64 / crossings.max(1) as f64
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, precision, engine, kind, m, passes] = args.as_slice() else {
        eprintln!(
            "usage: march_count f64|f32|f32-fast serial|serial-fold|separable|batch uniform|nonuniform|partial M PASSES"
        );
        std::process::exit(2);
    };
    let kind = GridLayout::from_name(kind).expect("GRID is uniform, nonuniform or partial");
    let m: usize = m.parse().expect("M is a number");
    let passes: usize = passes.parse().expect("PASSES is a number");
    match precision.as_str() {
        "f64" => run::<f64>(engine, kind, m, passes),
        "f32" => run::<f32>(engine, kind, m, passes),
        "f32-fast" => run::<F32Fast>(engine, kind, m, passes),
        _ => panic!("PRECISION is f64, f32 or f32-fast"),
    }
}
