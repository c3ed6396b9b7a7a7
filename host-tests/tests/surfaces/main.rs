//! The surfaces' ray intersections, the double-double arithmetic and the geodesy against arbitrary-precision oracles,
//! and the named hard cases.
//!
//! One test binary per subject (one link instead of one per file); each module is one suite.

#[path = "../support/mod.rs"]
mod support;

mod dd_oracle;
mod geodesy_oracle;
mod hard_cases;
mod oracle;
