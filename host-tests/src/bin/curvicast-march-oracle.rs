//! `curvicast-march-oracle [--rays N] [--seed S]`: marching against the independent oracle on random rays over
//! random grids (both engines, every precision). Exit code 1 when an f64 ray fails the criterion or any list
//! breaks the contract's invariants, otherwise as the product's ([`curvicast_cli::cli::exit`]).

use clap::Parser;
use curvicast_cli::cli::{exit, print_stdout};
use std::process::ExitCode;

/// Marching against the independent oracle on random rays over random grids (both engines, every precision);
/// exit code 1 when an f64 ray fails the criterion or any list breaks the contract's invariants.
#[derive(Parser)]
#[command(name = "curvicast-march-oracle", version)]
struct Args {
    /// Number of random rays (20 per random grid).
    #[arg(long, default_value_t = 200_000)]
    rays: usize,
    /// Seed of the generator.
    #[arg(long, default_value_t = 7)]
    seed: u64,
}

fn main() -> ExitCode {
    let args: Args = match exit::parse("curvicast-march-oracle") {
        Ok(a) => a,
        Err(code) => return code,
    };
    let (text, ok) = curvicast_host::report::march::oracle_suite_text(args.rays, args.seed);
    match print_stdout(&text) {
        Ok(()) => ExitCode::from(u8::from(!ok)),
        // A closed pipe ends quietly, with the suite's own exit code.
        Err(e) if e.is_closed_pipe() => ExitCode::from(u8::from(!ok)),
        Err(e) => exit::exit_code(Err(e.into()), "curvicast-march-oracle"),
    }
}
