//! The formats the command reads: the JSON inputs of the command-line contract (grids, rays, terrains), the DEM
//! files (`.hgt`, single-band geographic GeoTIFF, `.dem.cc`) and the real DEMs shipped with the project.

pub mod dem_files;
pub mod real_dem;
pub mod spec;
pub mod terrain;
