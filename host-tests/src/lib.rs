//! The harness that judges curvicast: the independent oracles, scenes and hard-case generators, baselines, the
//! report and the tolerance table; its tests and benches live beside it. It depends on the product
//! (`curvicast_cli`: the `curvicast` command, the file formats, the DEM readers) and on the kernel, never the
//! reverse.
//!
//! * [`oracle`]: independent arbitrary-precision reference answers. The oracle never calls kernel code paths.
//! * [`scenes`]: analytic fields, the report's marching scene, real datasets' cases, hard cases.
//! * [`march_run`]: the kernel's marchers run on the scenes' grids and rays and compared with the oracle.
//! * [`baselines`]: what a user would otherwise do (a general mesh ray caster, brute force).
//! * [`report`]: the speed-against-error report (`curvicast-report`).
//! * [`tolerances`]: every bound the oracle suites assert, with what was measured.

pub mod baselines;
pub mod march_run;
pub mod oracle;
pub mod report;
pub mod scenes;
pub mod tolerances;
