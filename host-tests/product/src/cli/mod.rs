//! The subcommands of the `curvicast` command (see the command-line contract, docs/formats.md).
//!
//! Shared rules: JSON in, JSON Lines out; one output line per input ray, in order; a malformed file or argument is
//! a one-line message on stderr naming the file, exit code 2, and nothing on stdout. An error on output (a full
//! disk, a closed pipe) ends the command with an [`OutputError`], never a panic: a one-line message and exit
//! code 1, or, for a closed pipe, silently (as Unix tools do).

pub mod command;
pub mod exit;
pub mod io;
pub mod march;
pub mod pick;
pub mod render;
pub mod tessellate;

use std::io::Write;

/// Writing to standard output failed (a full disk, a closed pipe, ...).
#[derive(Debug)]
pub struct OutputError(pub std::io::Error);

impl OutputError {
    /// True when the reader went away (a closed pipe, as in `curvicast march ... | head -1`): the command then ends
    /// without a message.
    pub fn is_closed_pipe(&self) -> bool {
        self.0.kind() == std::io::ErrorKind::BrokenPipe
    }
}

impl std::fmt::Display for OutputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "cannot write to standard output: {}", self.0)
    }
}

impl std::error::Error for OutputError {}

/// Writes `text` to standard output and flushes it, so that an error shows here and not at exit.
pub fn print_stdout(text: &str) -> Result<(), OutputError> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(OutputError)
}

/// Standard output for a command that has more to do after printing (the report writes `report.md` after its
/// tables): the first write error is kept and later text is dropped, so the command can finish its files and then
/// return the error with [`Stdout::finish`].
#[derive(Debug, Default)]
pub struct Stdout {
    failed: Option<OutputError>,
}

impl Stdout {
    /// Prints `text` unless an earlier write failed.
    pub fn print(&mut self, text: &str) {
        if self.failed.is_none() {
            self.failed = print_stdout(text).err();
        }
    }

    /// The first write error, if any.
    pub fn finish(self) -> Result<(), OutputError> {
        self.failed.map_or(Ok(()), Err)
    }
}
