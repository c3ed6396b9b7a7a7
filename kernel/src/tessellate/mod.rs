//! Rational corner-cutting and edge-beveling (the edge-beveling thesis): circles and ellipses from a square's control polygon,
//! spheres and ellipsoids from a cube, at exactly the level of detail a scene needs, in fixed memory.
//!
//! * [`chaikin`]: the 2-D rational Chaikin refinement (§3.2–3.3) with the non-stationary parameter
//!   `t_k / (1 − t_k) = cos((π − α) / 2^(k+1))` (eq. 3.1); ellipses by scaling (§3.4) and sheared circles and
//!   ellipses (§3.6) as affine images of the square.
//! * [`bevel`]: the 3-D edge-beveling algorithm (§4.3.4): the cube `(±1, ±1, ±1)` refined into polyhedra whose
//!   every face is tangent to the inscribed sphere at the face's center point; the box `(±A, ±B, ±C)` into
//!   polyhedra tangent to the ellipsoid (§4.4). Counts per level are `const fn`s; output goes into caller buffers.
//! * [`lod`]: the a-priori level of detail (chapter 5): the smallest level that meets a smallest dihedral angle,
//!   a largest deviation, or a screen-space error, found by following the worst case from one refinement to the
//!   next — without building any level.
//!
//! Why edge-beveling and not Doo's algorithm: §4.2 shows that no Doo weight keeps both the Type **E** faces and
//! the Type **V** faces tangent to the sphere; the test `doo_type_v_face_leaves_the_tangent_planes` in
//! [`bevel`] re-derives that.
//!
//! ```
//! use curvicast::tessellate::{bevel, lod};
//! // The smallest level whose faces meet at no less than 170° on a sphere of radius 2 ...
//! let level = lod::min_level(lod::Shape::Sphere(2.0_f64), lod::Bound::MinDihedral(170.0_f64.to_radians()))?;
//! assert_eq!(level, 4);
//! // ... built into fixed buffers sized by the const fns.
//! let mut vertices = [curvicast::V3::ZERO; bevel::vertex_count(4)];
//! let mut faces = [bevel::Face::EMPTY; bevel::face_count(4)];
//! let counts = bevel::bevel_sphere(level, 2.0_f64, &mut vertices, &mut faces)?;
//! assert_eq!((counts.vertices, counts.faces), (2048, 1026));
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

pub mod bevel;
pub mod chaikin;
mod error;
pub mod lod;

pub use error::TessellateError;
