//! The worst case of the unit sphere's polyhedron at one level (the edge-beveling thesis, chapter 5): the
//! recursion of [`super`]'s module docs.

use crate::real::Real;
use crate::tessellate::bevel::MAX_LEVEL;
use crate::tessellate::error::TessellateError;

/// The worst case of the unit sphere's polyhedron at one level (chapter 5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorstCase<T> {
    /// `u = 1 − cos s`, `s` the largest angle between the normals of adjacent faces.
    pub one_minus_cos: T,
    /// The largest angle between the normals of adjacent faces, radians (`π −` the smallest dihedral angle).
    pub max_normal_angle: T,
    /// The smallest dihedral angle between adjacent faces, radians.
    pub min_dihedral: T,
    /// The largest distance between the polyhedron and the unit sphere.
    pub max_deviation: T,
}

pub(super) fn worst_from_u<T: Real>(u: T) -> WorstCase<T> {
    let s = (u * (T::TWO - u)).sqrt().atan2(T::ONE - u);
    let three = T::from_i32(3);
    let den = three - T::TWO * u;
    let dev = (T::TWO * u / den) / ((three / den).sqrt() + T::ONE);
    WorstCase {
        one_minus_cos: u,
        max_normal_angle: s,
        min_dihedral: T::PI - s,
        max_deviation: dev,
    }
}

pub(super) fn next_u<T: Real>(u: T) -> T {
    u / (T::TWO * (T::TWO - u))
}

/// The worst case of the unit sphere's polyhedron at `level`, by the recursion of the module docs.
///
/// # Errors
/// [`TessellateError::LevelTooDeep`] above [`MAX_LEVEL`].
pub fn worst_case<T: Real>(level: u32) -> Result<WorstCase<T>, TessellateError> {
    if level > MAX_LEVEL {
        return Err(TessellateError::LevelTooDeep {
            level,
            max: MAX_LEVEL,
        });
    }
    let mut u = T::ONE;
    for _ in 0..level {
        u = next_u(u);
    }
    Ok(worst_from_u(u))
}
