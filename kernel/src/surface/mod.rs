//! Ray ∩ one surface: every boundary surface that the spherical marcher (Hannasch) and the terrain traversal
//! (Wartell et al.) need, each in its own file behind one API shape, the [`Surface`] trait.
//!
//! | surface | file | Hannasch | Wartell et al. |
//! | --- | --- | --- | --- |
//! | [`Spheroid`] (a sphere when a = b) | `spheroid.rs` | radius shells r² (§4.3, Lemma 9) | upper bound B^h (§3.1.2), lower sphere (§3.2) |
//! | [`AxialCone`] | `cone.rs` | zenith cones (§4.4, Lemma 10) | latitude cones (§3.4, eq. 3.4-1) |
//! | [`HalfPlane`] | `half_plane.rs` | azimuth facets (§4.6) | meridian walls (§3.3, eq. 3.3-1) |
//! | [`PlaneZ`] | `plane_z.rs` | the cylinder's z facets (§3.3), θ = π/2 | — |
//!
//! Each solver returns the crossings that lie in the ray's `[t_min, t_max]` (ends included), sorted by `t`, each
//! with the [`Side`] the ray crosses *into*. "Positive" is the side the surface's normal points to, which is always
//! the side where the grid coordinate is larger: outside a spheroid, larger zenith angle θ for a cone (toward −z),
//! larger azimuth φ (counter-clockwise) for a half-plane, larger z for a plane.
//!
//! Conventions shared by every solver:
//! * A ray that only touches a surface (a double root: tangency) reports two crossings at the same `t`, into the
//!   other side and back, so a caller counting sides always stays consistent.
//! * A ray lying *in* a surface (a generator of a cone, a line in a half-plane's plane, a horizontal ray on a
//!   plane) reports no crossing: it never changes side.
//! * Roots are never computed by cancellation: the closest approach comes from `|p × d|²`, the quadratic formula
//!   is the stable one (the second root from the product of the roots), and the degenerate linear case (a ray
//!   parallel to a cone generator) falls out of the same formula without a special branch.
//! * All arithmetic is in the ray's exactly-rescaled direction (see [`crate::ray`]), so the results do not depend
//!   on the length of `d`.
//!
//! ```
//! use curvicast::ray::Ray;
//! use curvicast::surface::{Side, Spheroid, Surface};
//! let ray = Ray::new([-3.0_f64, 0.0, 0.0], [1.0, 0.0, 0.0])?;
//! let sphere = Spheroid::sphere(2.0)?;
//! let c = sphere.crossings(&ray);
//! assert_eq!(c.len(), 2);
//! assert_eq!((c[0].t, c[0].into), (1.0, Side::Negative)); // enters the ball
//! assert_eq!((c[1].t, c[1].into), (5.0, Side::Positive)); // leaves it
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

mod cone;
mod crossing;
mod half_plane;
mod plane_z;
mod spheroid;

pub use cone::AxialCone;
pub(crate) use cone::ConeRoots;
pub(crate) use crossing::sign_of;
pub use crossing::{Crossing, Crossings, Side, Surface, SurfaceError};
pub use half_plane::HalfPlane;
pub use plane_z::PlaneZ;
pub use spheroid::Spheroid;
pub(crate) use spheroid::{sphere_exit_root_signed, sphere_roots_signed, sphere_scaled_roots};
