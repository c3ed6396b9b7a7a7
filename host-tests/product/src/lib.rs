//! The `curvicast` command, as a library: the subcommands (`march`, `pick`, `render`, `tessellate`), the file
//! formats of the command-line contract, the DEM readers, the host's terrain storage, and batches of rays across
//! cores. It depends on the kernel and maintained crates only; the harness that judges it (oracles, baselines, the
//! report, the tests) is the package `curvicast-host`, which depends on this one, never the reverse.
//!
//! * [`formats`]: the JSON input formats (grids, rays, terrains), the DEM files (`.hgt`, GeoTIFF, `.dem.cc`) and
//!   the shipped real DEMs.
//! * [`storage`]: the quadtree the host builds over a DEM for the kernel's picker (single and multi-resolution).
//! * [`precision`]: the scalar and the engine, one type each.
//! * [`batch`]: many rays marched at once across cores (rayon).
//! * [`render`]: images of fields on spherical, cylindrical and polar grids, native and Cartesian (`curvicast render`).
//! * [`cli`]: the subcommands of `curvicast`.

pub mod batch;
pub mod cli;
pub mod formats;
pub mod precision;
pub mod render;
pub mod storage;
