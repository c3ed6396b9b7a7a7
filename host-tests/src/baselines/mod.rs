//! Baselines: what a user would otherwise do, measured in the same run as the kernel. The Cartesian resampling
//! with Amanatides–Woo is part of the product (`curvicast render`'s `{"cartesian": N}` method,
//! `curvicast_cli::render::dda`); the general mesh ray caster and the brute force are here.

pub mod terrain;
