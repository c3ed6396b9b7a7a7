//! Scenes: analytic fields, the report's marching scene and the generators of hard cases (the formats they are
//! written in are the product's, `curvicast_cli::formats`).

pub mod march_cases;
pub mod marching;
pub mod terrain_cases;
