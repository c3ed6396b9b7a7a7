//! How a command of this project starts and ends, written once for the product's `curvicast` and the harness's
//! `curvicast-report` and `curvicast-march-oracle`: clap's errors as the contract's one line with exit code 2 (`--help` and
//! `--version` on stdout), and a result as an exit code (0 done, also for a closed pipe; 1 an error writing the
//! output; 2 a malformed argument or input file).

use super::OutputError;
use super::io::StreamError;
use std::process::ExitCode;

/// Parses the command line into `P`, or prints clap's error as one line on stderr (`--help` and `--version` on
/// stdout) and gives the exit code to return.
pub fn parse<P: clap::Parser>(name: &str) -> Result<P, ExitCode> {
    match P::try_parse() {
        Ok(p) => Ok(p),
        Err(e) if e.use_stderr() => {
            eprintln!("{}", one_line::<P>(&e, name));
            Err(ExitCode::from(2))
        }
        // --help and --version, on stdout; a failed write there (a closed pipe) is no reason to panic.
        Err(e) => {
            let _ = super::print_stdout(&e.render().to_string());
            Err(ExitCode::SUCCESS)
        }
    }
}

/// clap's error as the contract's one line (clap's own spans four or five: the message, a tip, the usage and a
/// pointer to `--help`).
fn one_line<P: clap::CommandFactory>(e: &clap::Error, name: &str) -> String {
    use clap::error::ErrorKind;
    let first = match e.kind() {
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let names: Vec<String> = P::command()
                .get_subcommands()
                .map(|c| c.get_name().to_string())
                .collect();
            format!("a subcommand is required ({})", names.join(", "))
        }
        _ => {
            // The message is the first paragraph (a list of missing arguments continues it on indented lines).
            let text = e.render().to_string();
            let paragraph: Vec<&str> = text
                .lines()
                .skip_while(|l| l.trim().is_empty())
                .take_while(|l| !l.trim().is_empty())
                .map(str::trim)
                .collect();
            let line = paragraph.join(" ");
            line.strip_prefix("error: ").unwrap_or(&line).to_string()
        }
    };
    format!("{name}: {first}; see '{name} --help'")
}

/// The exit code of a command's result, with its one-line message on stderr: 0 done, also when standard output
/// is a closed pipe (ended quietly, as Unix tools do); 1 an error writing the output; 2 anything else (a malformed
/// argument or input file).
pub fn exit_code(result: anyhow::Result<()>, name: &str) -> ExitCode {
    let Err(e) = result else {
        return ExitCode::SUCCESS;
    };
    let output = e
        .downcast_ref::<OutputError>()
        .or_else(|| e.downcast_ref::<StreamError>().and_then(|s| s.output()));
    match output {
        Some(out) if out.is_closed_pipe() => ExitCode::SUCCESS,
        Some(_) => {
            eprintln!("{name}: {e:#}");
            ExitCode::from(1)
        }
        None => {
            eprintln!("{name}: {e:#}");
            ExitCode::from(2)
        }
    }
}
