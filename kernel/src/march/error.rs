//! The axes as errors name them, and why a grid could not be built or a march completed.

use crate::ray::RayError;

/// A coordinate axis of a grid, as named in errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The spherical or polar radius.
    R,
    /// The zenith angle.
    Theta,
    /// The azimuth.
    Phi,
    /// The cylindrical radius.
    Rho,
    /// The cylinder's height.
    Z,
}

impl Axis {
    /// The axis's name as in the grid files (`"r"`, `"theta"`, `"phi"`, `"rho"`, `"z"`).
    pub fn name(self) -> &'static str {
        match self {
            Axis::R => "r",
            Axis::Theta => "theta",
            Axis::Phi => "phi",
            Axis::Rho => "rho",
            Axis::Z => "z",
        }
    }
}

/// Why a grid could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridError {
    /// Fewer than two breakpoints on an axis.
    TooFewBreakpoints {
        /// The axis.
        axis: Axis,
        /// How many there are.
        len: usize,
    },
    /// More breakpoints than a `u32` cell index can address.
    TooManyBreakpoints {
        /// The axis.
        axis: Axis,
        /// How many there are.
        len: usize,
    },
    /// A breakpoint is not larger than the one before it.
    NotIncreasing {
        /// The axis.
        axis: Axis,
        /// The index of the offending breakpoint.
        index: usize,
    },
    /// A breakpoint is NaN or infinite.
    NonFinite {
        /// The axis.
        axis: Axis,
        /// The index of the offending breakpoint.
        index: usize,
    },
    /// A breakpoint is out of its range: `r[0] < 0` (or `r²` overflows), θ outside [0, π], or the φ breakpoints
    /// span more than 2π (reported at the last index).
    OutOfRange {
        /// The axis.
        axis: Axis,
        /// The index of the offending breakpoint.
        index: usize,
    },
    /// The center is not finite.
    NonFiniteCenter,
    /// The workspace is shorter than the grid's `workspace_len`.
    WorkspaceTooSmall,
}

impl core::fmt::Display for GridError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            GridError::TooFewBreakpoints { axis, len } => write!(
                f,
                "{}: needs at least 2 breakpoints, got {len}",
                axis.name()
            ),
            GridError::TooManyBreakpoints { axis, len } => {
                write!(f, "{}: too many breakpoints ({len})", axis.name())
            }
            GridError::NotIncreasing { axis, index } => write!(
                f,
                "{}[{index}]: breakpoints must be strictly increasing",
                axis.name()
            ),
            GridError::NonFinite { axis, index } => {
                write!(f, "{}[{index}]: breakpoint is not finite", axis.name())
            }
            GridError::OutOfRange { axis, index } => write!(
                f,
                "{}[{index}]: breakpoint out of range ({})",
                axis.name(),
                match axis {
                    Axis::R | Axis::Rho => "radii must be >= 0 with a finite square",
                    Axis::Theta => "zenith angles must lie in [0, pi]",
                    Axis::Phi => "azimuths may span at most 2 pi",
                    Axis::Z => "heights must be finite",
                }
            ),
            GridError::NonFiniteCenter => f.write_str("center is not finite"),
            GridError::WorkspaceTooSmall => {
                f.write_str("workspace is shorter than the grid's workspace_len")
            }
        }
    }
}

impl core::error::Error for GridError {}

/// Why a march could not be completed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MarchError {
    /// A separable engine's buffer for one coordinate is full (its capacity `N` is too small for this ray).
    BufferFull {
        /// The coordinate whose crossings did not fit.
        axis: Axis,
        /// The capacity.
        capacity: usize,
    },
    /// More zenith events than the grid's size allows: a safety net that turns an unforeseen loop into an error
    /// (the other coordinates' events are bounded by construction). The serial engine stops with it after the
    /// crossings before it; the separable engine returns it at construction.
    IterationBound,
    /// The ray could not be expressed relative to the grid's center (it overflows).
    Ray(RayError),
    /// The ray crosses the domain, but its parameter `t` there is beyond the largest finite value of the scalar
    /// type (a direction so short, like `[1e-308, 0, 0]` from a few units away, that `t = distance / |d|`
    /// overflows). Answered as an error rather than as a miss or as crossings at `t = ∞`.
    Unrepresentable,
}

impl core::fmt::Display for MarchError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            MarchError::BufferFull { axis, capacity } => write!(
                f,
                "separable march: more than {capacity} {} crossings",
                axis.name()
            ),
            MarchError::IterationBound => f.write_str("march exceeded its iteration bound"),
            MarchError::Ray(e) => write!(f, "ray relative to the grid center: {e}"),
            MarchError::Unrepresentable => f.write_str(
                "the ray crosses the grid where its t exceeds the largest finite value (direction too short)",
            ),
        }
    }
}

impl core::error::Error for MarchError {}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    /// Each march error says what went wrong, naming the coordinate and the capacity where it has them.
    #[test]
    fn march_errors_say_what_went_wrong() {
        let full = MarchError::BufferFull {
            axis: Axis::Theta,
            capacity: 16,
        };
        assert_eq!(
            full.to_string(),
            "separable march: more than 16 theta crossings"
        );
        assert_eq!(
            MarchError::IterationBound.to_string(),
            "march exceeded its iteration bound"
        );
        assert_eq!(
            MarchError::Ray(RayError::NonFiniteOrigin).to_string(),
            "ray relative to the grid center: ray origin is not finite"
        );
        assert!(
            MarchError::Unrepresentable.to_string().starts_with(
                "the ray crosses the grid where its t exceeds the largest finite value"
            )
        );
    }
}
