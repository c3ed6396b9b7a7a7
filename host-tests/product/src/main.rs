//! The `curvicast` command: `march`, `pick`, `render` and `tessellate`. See the command-line contract,
//! docs/formats.md. (The report and the marching oracle's command are the harness's, package `curvicast-host`.)
//!
//! Exit codes: 0 done (also when standard output is a closed pipe), 2 a malformed argument or input file (one line
//! on stderr), 1 an error writing the output ([`curvicast_cli::cli::exit`]).

fn main() -> std::process::ExitCode {
    curvicast_cli::cli::command::main()
}
