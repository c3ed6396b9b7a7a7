//! Ray marching through spherical, cylindrical and 2-D polar grids (Hannasch: Hannasch, *Spherical
//! Ray-Tracing*).
//!
//! Given a grid with non-uniform breakpoints and a ray, the marchers list every cell the ray crosses, in
//! increasing `t`, with the exact entry and exit parameters ([`CellCrossing`]). Two engines give identical
//! answers:
//!
//! * the **serial** engine ([`SphericalGrid::march`], ch. 5) is a lazy [`Iterator`] with constant-size state:
//!   each coordinate's next crossing is computed once (one square root per radius or zenith crossing, one
//!   division per azimuth crossing) and cached until that coordinate's index changes;
//! * the **separable** engine ([`SphericalGrid::march_separable`], §3) lists each coordinate's crossings into
//!   `heapless` buffers of capacity `N` and interleaves them in linear time; a full buffer is an error.
//!
//! # Semantics
//!
//! Cells are half-open: `[i, j, k]` is `r[i] <= r < r[i+1]`, `theta[j] <= θ < theta[j+1]`,
//! `phi[k] <= φ < phi[k+1]` (φ modulo 2π). The output is exactly the parts of the ray with `t_min <= t <= t_max`
//! inside the domain, ordered by `t`. Consecutive crossings either touch (`t_exit` = next `t_enter`) and differ
//! in exactly one index by one step (the φ index wraps only when φ spans a full turn), or are separated by a gap
//! outside the domain. Where the ray passes exactly through an edge or a corner, through the z axis (φ jumps by
//! π) or through the center (θ jumps to π − θ), each index change is its own crossing, with zero-length crossings
//! between (§3.1.4). A point exactly on the z axis has φ = 0, a point on the −z axis θ = π.
//!
//! Known limit of floating point: a line that leaves a wedge and comes back within one rounding of `t` (it passes
//! the z axis closer than `t` can resolve) shows a zero-length gap, so the two crossings around it touch while
//! their φ indices differ by more than one step.
//!
//! # Numerics: topology first
//!
//! Which boundary comes next is decided by the ditone/monotone structure of each coordinate along the line
//! (Lemmas 4, 5, 6, 8), with robust signs; the `t` values come from the shared [`crate::surface`] solvers and
//! are clamped to be nondecreasing. A slightly inaccurate `t` therefore never reorders cells; at worst it turns
//! a crossing of rounding-level length into a zero-length one.
//!
//! # Samplers
//!
//! A march is an ordinary iterator, so samplers are iterator adapters. Consumers that take the whole march
//! (`sum`, `fold`, `for_each`, `count`, and adapters such as `map(..).sum()`) run the serial engine's internal
//! iteration, about 1 % fewer instructions per crossing than a `for` loop over `next`;
//! [`SerialMarch::fold_in_place`] does the same and keeps the march for [`SerialMarch::error`]. A projection
//! (§6.1: Σ value × length):
//!
//! ```
//! use curvicast::{ray::Ray, spherical::SphericalGrid};
//! use core::f64::consts::PI;
//! let (r, theta, phi) = ([0.0, 0.5, 1.0], [0.0, PI / 2.0, PI], [0.0, PI, 2.0 * PI]);
//! let mut ws = [0.0; SphericalGrid::<f64>::workspace_len(3, 3, 3)];
//! let grid = SphericalGrid::new(&r, &theta, &phi, &mut ws)?;
//! let density = |cell: [u32; 3]| if cell[0] == 0 { 2.0 } else { 1.0 }; // denser core
//! let ray = Ray::new([-2.0, 0.0, 0.3], [1.0, 0.0, 0.0])?;
//! let column: f64 = grid.march(&ray).map(|c| density(c.cell) * (c.t_exit - c.t_enter)).sum();
//! let (outer, inner) = (2.0 * (1.0f64 - 0.09).sqrt(), 2.0 * (0.25f64 - 0.09).sqrt());
//! assert!((column - (outer + inner)).abs() < 1e-12);
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```
//!
//! Early termination (front-to-back compositing stops when the opacity reaches 1):
//!
//! ```
//! # use curvicast::{ray::Ray, spherical::SphericalGrid};
//! # use core::f64::consts::PI;
//! # let (r, theta, phi) = ([0.0, 0.5, 1.0], [0.0, PI / 2.0, PI], [0.0, PI, 2.0 * PI]);
//! # let mut ws = [0.0; SphericalGrid::<f64>::workspace_len(3, 3, 3)];
//! # let grid = SphericalGrid::new(&r, &theta, &phi, &mut ws)?;
//! let ray = Ray::new([-2.0, 0.0, 0.3], [1.0, 0.0, 0.0])?;
//! let mut opacity = 0.0_f64;
//! let mut visited = 0;
//! for c in grid.march(&ray) {
//!     visited += 1;
//!     let alpha = (4.0 * (c.t_exit - c.t_enter)).min(1.0); // a very absorbing medium
//!     opacity += (1.0 - opacity) * alpha;
//!     if opacity >= 1.0 - 1e-9 {
//!         break; // nothing behind can be seen: the remaining cells are never computed
//!     }
//! }
//! assert!(visited < grid.march(&ray).count());
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

mod axes;
mod engine;
mod grid;
mod stream;

pub use engine::{SeparableMarch, SerialMarch};
pub use grid::{CylindricalGrid, PolarGrid, SphericalGrid};

use crate::ray::RayError;

/// One cell crossed by a ray: its index and the parameters where the ray enters and leaves it.
///
/// The index is `[i, j, k]` for a spherical grid (r, θ, φ), `[i, k, m]` for a cylindrical one (ρ, φ, z) and
/// `[i, k, 0]` for a polar one (r, φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellCrossing<T> {
    /// The cell index.
    pub cell: [u32; 3],
    /// Where the ray enters the cell (in the caller's units of `t`).
    pub t_enter: T,
    /// Where it leaves (`t_exit >= t_enter`; equal for a zero-length crossing at a tie).
    pub t_exit: T,
}

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
mod tests;
