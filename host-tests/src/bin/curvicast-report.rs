//! `curvicast-report [--quick] [--out DIR]`: the scene suite, its speed-against-error tables on stdout and
//! `report.md`, plots and images in `DIR` (default `out/`); `--quick` finishes in under a minute on two cores
//! (the command-line contract, "report"). Exit codes as the product's ([`curvicast_cli::cli::exit`]).

use clap::Parser;
use curvicast_cli::cli::exit;
use std::path::PathBuf;
use std::process::ExitCode;

/// Run the scene suite: speed-against-error tables on stdout, report.md and plots in DIR.
#[derive(Parser)]
#[command(name = "curvicast-report", version)]
struct Args {
    /// Small sizes (under a minute on two cores).
    #[arg(long)]
    quick: bool,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

fn main() -> ExitCode {
    let args: Args = match exit::parse("curvicast-report") {
        Ok(a) => a,
        Err(code) => return code,
    };
    let result = curvicast_host::report::run(&curvicast_host::report::Options {
        quick: args.quick,
        out_dir: args.out,
    })
    .map(|_| ());
    exit::exit_code(result, "curvicast-report")
}
