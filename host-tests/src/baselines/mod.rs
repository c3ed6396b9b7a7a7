//! Baselines: what a user would otherwise do, measured in the same run as the kernel.

pub mod dda;
pub mod terrain;
