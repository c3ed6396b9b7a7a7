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
//! # Grid kinds
//!
//! A grid's kind is a type: [`Grid`]`<'a, T, K>` with `K` one of [`Spherical`], [`Cylindrical`] and [`Polar`]
//! ([`GridKind`]: which coordinate each slot of the cell index holds, and whether the radius is measured from
//! the z axis), with [`SphericalGrid`], [`CylindricalGrid`] and [`PolarGrid`] its aliases. Each kind's marcher is
//! compiled with only its own coordinates' steps, so a program that marches spheres only links no cylinder or
//! polar code. When the kind is read at run time (a grid file), [`AnyGrid`] holds any of the three, each
//! marching with its own marcher; [`Grid::into_dynamic`] gives instead one marcher for every kind, which
//! switches on the grid's coordinates as it steps ([`Dynamic`]: the smallest code when a program marches
//! several kinds). All of them give the same crossings, bit for bit.
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
//! use curvicast::{march::SphericalGrid, ray::Ray};
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
//! # use curvicast::{march::SphericalGrid, ray::Ray};
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

mod any;
mod axes;
mod crossing;
mod emitter;
mod error;
mod event;
mod grid;
mod kind;
mod separable;
mod serial;
mod stream;
mod tables;

pub use any::{AnyGrid, AnyMarch};
pub use crossing::CellCrossing;
pub use error::{Axis, GridError, MarchError};
pub use grid::{CylindricalGrid, Grid, PolarGrid, SphericalGrid};
pub use kind::{Coordinates, Cylindrical, Dynamic, GridKind, Polar, Spherical};
pub use separable::SeparableMarch;
pub use serial::SerialMarch;

#[cfg(test)]
mod tests;
