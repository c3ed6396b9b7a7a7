//! What can go wrong in tessellation: [`TessellateError`], and the axis ratio beyond which the level of detail
//! refuses an ellipsoid.

/// The largest ratio of an ellipsoid's largest to smallest semi-axis that [`min_level`](super::lod::min_level) and
/// [`ellipsoid_worst_case`](super::lod::ellipsoid_worst_case) accept (`AxisRatioTooLarge` beyond). A fuzz input at 7e134 : 1 made the closest-point
/// solver report a zero deviation; the method is checked (against built polyhedra, and against the unpruned
/// walk) far below this limit.
pub const MAX_AXIS_RATIO: f64 = 1.0e6;

/// What can go wrong in [`chaikin`](super::chaikin), [`bevel`](super::bevel) and [`lod`](super::lod).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TessellateError {
    /// The level exceeds what the module supports ([`bevel::MAX_LEVEL`](super::bevel::MAX_LEVEL) or [`chaikin::MAX_LEVEL`](super::chaikin::MAX_LEVEL)).
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
    /// The ratio of the largest to the smallest semi-axis exceeds [`MAX_AXIS_RATIO`], the range in which
    /// [`lod::min_level`](super::lod::min_level) and [`lod::ellipsoid_worst_case`](super::lod::ellipsoid_worst_case) are verified (chapter 5); the builders of [`bevel`](super::bevel)
    /// accept any ratio.
    AxisRatioTooLarge,
    /// A control polygon is empty, has a non-finite point, or has an interior angle outside `(0, π)`.
    InvalidControlPolygon,
    /// A level-of-detail bound is NaN, out of its range, or the viewer is not outside the object.
    InvalidBound,
    /// The bound is valid but no level up to [`bevel::MAX_LEVEL`](super::bevel::MAX_LEVEL) meets it.
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
                MAX_AXIS_RATIO
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    /// Each error's message names what went wrong and carries its numbers.
    #[test]
    fn each_error_message_says_what_and_carries_its_numbers() {
        let level = TessellateError::LevelTooDeep { level: 13, max: 12 }.to_string();
        assert!(level.contains("13") && level.contains("12"), "{level}");
        let buffer = TessellateError::BufferTooSmall {
            buffer: "vertex",
            needed: 32,
            got: 8,
        }
        .to_string();
        assert!(
            buffer.contains("vertex") && buffer.contains("32") && buffer.contains('8'),
            "{buffer}"
        );
        for e in [
            TessellateError::InvalidShape,
            TessellateError::AxisRatioTooLarge,
            TessellateError::InvalidControlPolygon,
            TessellateError::InvalidBound,
            TessellateError::Unreachable,
            TessellateError::Internal,
        ] {
            assert!(e.to_string().len() > 10, "{e:?}");
        }
    }
}
