//! Scenes: the JSON input formats of the command-line contract, analytic fields, real datasets and generators of
//! hard cases.

pub mod dem_files;
pub mod march_cases;
pub mod marching;
pub mod real_dem;
pub mod spec;
pub mod terrain;
pub mod terrain_cases;
