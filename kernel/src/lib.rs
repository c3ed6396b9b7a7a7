//! # curvicast
//!
//! Ray casting through curved coordinate systems, for constrained targets: `#![no_std]`, no `alloc`, no
//! `unsafe`, no panics, fixed memory.
//!
//! * [`surface`]: ray ∩ sphere/spheroid, axial cone, half-plane through the z axis, plane `z = c` — the one
//!   geometry layer that every traversal shares.
//! * [`geodesy`]: the ellipsoid, geodetic ↔ ECEF (GeographicLib-grade reverse conversion), latitude cones,
//!   meridians and the conservative bounding volume of a spheroidal height-quad (Wartell et al. §3).
//! * [`terrain`]: the nearest hit of a ray with a regular geodetic DEM through a height-augmented quadtree that
//!   the caller stores behind [`terrain::TerrainStorage`] (Wartell et al.), never missing a hit.
//! * [`spherical`]: marching through spherical, cylindrical and polar grids (Hannasch), serial and separable.
//! * [`tessellate`]: rational corner-cutting and edge-beveling of circles, ellipses, spheres and ellipsoids at
//!   the level a scene needs (the edge-beveling thesis).
//! * [`ray`]: the ray and its invariants; [`real`]: the scalar trait (`f64`, `f32`, and a fast-math `f32`).
//!
//! The papers this crate implements are cited in each module's docs: Hannasch, *Spherical Ray-Tracing*
//! for marching; Wartell, Ribarsky, Hodges, *Efficient Ray Intersection with Global Terrain using
//! Spheroidal Height-Augmented Quadtrees* for terrain; a thesis on rational corner-cutting
//! and edge-beveling ("the edge-beveling thesis") for tessellation.
//!
//! ```
//! use curvicast::{ray::Ray, surface::{AxialCone, Surface}};
//! // Where does a ray cross the 60° zenith cone?
//! let ray = Ray::new([-4.0_f64, 0.0, 1.0], [1.0, 0.0, 0.0])?;
//! let cone = AxialCone::from_zenith_rad(0.0, core::f64::consts::FRAC_PI_3)?;
//! let ts: Vec<f64> = cone.crossings(&ray).iter().map(|c| c.t).collect();
//! assert_eq!(ts.len(), 2);
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing,
    clippy::arithmetic_side_effects,
    clippy::unreachable,
    clippy::todo,
    clippy::unimplemented
)]
// `!(x >= 0)` is how the kernel says "negative or NaN": intended, not a readability slip.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
#![cfg_attr(
    test,
    allow(
        clippy::unwrap_used,
        clippy::indexing_slicing,
        clippy::arithmetic_side_effects
    )
)]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

pub mod dd;
pub mod geodesy;
mod interval;
pub mod ray;
pub mod real;
mod sort;
pub mod spherical;
pub mod surface;
pub mod terrain;
pub mod tessellate;
pub mod vec3;

pub use ray::{Ray, RayError};

#[cfg(feature = "fast-math")]
pub use real::F32Fast;
pub use real::Real;
pub use vec3::V3;

/// Helpers shared by the kernel's unit tests.
#[cfg(test)]
pub(crate) mod test_util {
    /// A xorshift generator of uniform numbers in `[0, 1)` (53 bits), reproducible from `seed` (nonzero).
    pub(crate) fn xorshift_uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }
}
