//! The product's `curvicast` command, built in the harness's package so that its integration tests can run it
//! (Cargo gives a test the paths of its own package's binaries only): the same code as `curvicast`
//! ([`curvicast_cli::cli::command::main`]).

fn main() -> std::process::ExitCode {
    curvicast_cli::cli::command::main()
}
