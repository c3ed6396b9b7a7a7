//! Host harness for curvicast: the independent oracle, scenes and case generators, baselines, the report, and the
//! implementation of the `curvicast` command. Everything here is `std`; the kernel never depends on it.
//!
//! * [`oracle`]: independent arbitrary-precision reference answers. The oracle never calls kernel code paths.
//! * [`scenes`]: the input formats of the command-line contract, analytic fields, real datasets, hard cases.
//! * [`march_run`]: the kernel's marchers run on the scenes' grids and rays and compared with the oracle.
//! * [`batch`]: many rays marched at once across cores (rayon).
//! * [`baselines`]: what a user would otherwise do (Cartesian resampling, a general mesh ray caster, brute force).
//! * [`render`]: images of fields on spherical, cylindrical and polar grids, native and Cartesian (`curvicast render`).
//! * [`report`]: the speed-against-error report.
//! * [`cli`]: the subcommands of `curvicast`.

pub mod baselines;
pub mod batch;
pub mod cli;
pub mod march_run;
pub mod oracle;
pub mod render;
pub mod report;
pub mod scenes;
pub mod storage;
pub mod tolerances;
