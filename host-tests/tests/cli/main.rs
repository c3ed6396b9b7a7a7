//! The `curvicast` command as the command-line contract states it: each subcommand's answers and errors, streaming,
//! numbers read and written bit for bit, and every documented example.
//!
//! One test binary per subject (one link instead of one per file); each module is one suite.

#[path = "../support/mod.rs"]
mod support;

mod docs_examples;
mod harness;
mod march;
mod numbers;
mod pick;
mod pick_dem;
mod render;
mod render_cylindrical_polar;
mod streaming;
