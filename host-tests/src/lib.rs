//! Host harness for curvicast: the independent oracle, scenes and case generators, baselines, the report, and the
//! implementation of the `curvicast` command. Everything here is `std`; the kernel never depends on it.
//!
//! * [`oracle`]: independent arbitrary-precision reference answers. The oracle never calls kernel code paths.
//! * [`scenes`]: the input formats of the command-line contract, analytic fields, real datasets, hard cases.
//! * [`baselines`]: what a user would otherwise do (Cartesian resampling, a general mesh ray caster, brute force).
//! * [`report`]: the speed-against-error report.
//! * [`cli`]: the subcommands of `curvicast`.

pub mod baselines;
pub mod cli;
pub mod oracle;
pub mod report;
pub mod scenes;
pub mod storage;
