//! The subcommands of the `curvicast` command (see the command-line contract in the README).
//!
//! Shared rules: JSON in, JSON Lines out; one output line per input ray, in order; a malformed file or argument is
//! a one-line message on stderr naming the file, exit code 2, and nothing on stdout.

pub mod io;
pub mod march;
pub mod pick;
pub mod render;
pub mod tessellate;
