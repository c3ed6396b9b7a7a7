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
pub mod lod;

/// What can go wrong in [`chaikin`], [`bevel`] and [`lod`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TessellateError {
    /// The level exceeds what the module supports ([`bevel::MAX_LEVEL`] or [`chaikin::MAX_LEVEL`]).
    LevelTooDeep {
        /// The requested level.
        level: u32,
        /// The largest supported level.
        max: u32,
    },
    /// A caller-provided buffer is shorter than the const fn of the level says it must be.
    BufferTooSmall {
        /// Which buffer.
        buffer: &'static str,
        /// Its required length.
        needed: usize,
        /// Its actual length.
        got: usize,
    },
    /// A radius or semi-axis is not a positive finite number (or the result would not be finite).
    InvalidShape,
    /// The ratio of the largest to the smallest semi-axis exceeds [`lod::MAX_AXIS_RATIO`], the range in which
    /// [`lod::min_level`] and [`lod::ellipsoid_worst_case`] are verified (chapter 5); the builders of [`bevel`]
    /// accept any ratio.
    AxisRatioTooLarge,
    /// A control polygon is empty, has a non-finite point, or has an interior angle outside `(0, π)`.
    InvalidControlPolygon,
    /// A level-of-detail bound is NaN, out of its range, or the viewer is not outside the object.
    InvalidBound,
    /// The bound is valid but no level up to [`bevel::MAX_LEVEL`] meets it.
    Unreachable,
    /// An internal consistency check failed (a bug, reported instead of a panic).
    Internal,
}

impl core::fmt::Display for TessellateError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TessellateError::LevelTooDeep { level, max } => {
                write!(f, "level {level} exceeds the largest supported level {max}")
            }
            TessellateError::BufferTooSmall {
                buffer,
                needed,
                got,
            } => write!(f, "{buffer} buffer too small: needs {needed}, got {got}"),
            TessellateError::InvalidShape => {
                f.write_str("radius and semi-axes must be positive and finite")
            }
            TessellateError::AxisRatioTooLarge => write!(
                f,
                "the ratio of the largest to the smallest semi-axis exceeds {:e}, the range in which the level \
                 of detail is verified",
                lod::MAX_AXIS_RATIO
            ),
            TessellateError::InvalidControlPolygon => f.write_str(
                "control polygon must be non-empty, finite, with interior angles in (0, pi)",
            ),
            TessellateError::InvalidBound => f.write_str(
                "level-of-detail bound is NaN or out of range (or the viewer is not outside the object)",
            ),
            TessellateError::Unreachable => {
                f.write_str("no supported refinement level meets the bound")
            }
            TessellateError::Internal => f.write_str("internal consistency check failed"),
        }
    }
}

impl core::error::Error for TessellateError {}

/// Checks that a buffer holds at least `needed` items.
pub(crate) fn need(buffer: &'static str, needed: usize, got: usize) -> Result<(), TessellateError> {
    if got < needed {
        Err(TessellateError::BufferTooSmall {
            buffer,
            needed,
            got,
        })
    } else {
        Ok(())
    }
}
