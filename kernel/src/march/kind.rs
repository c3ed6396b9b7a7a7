//! What a grid kind supplies to the marchers (Hannasch §3.3–3.4): which coordinates it has, in which slots of
//! the cell index, and whether its radius is measured from the center or from the z axis. The three kinds are
//! three types, so the engines are compiled once per kind a program uses and a program that marches spherical
//! grids only links no cylinder or polar code (on a Cortex-M4F: see docs/embedded.md).

use super::error::Axis;

/// Which coordinate a slot of the cell index holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SlotKind {
    Radial,
    Zenith,
    Azimuth,
    Height,
    Absent,
}

mod sealed {
    pub trait Sealed {}
}

/// A kind of grid: [`Spherical`], [`Cylindrical`] or [`Polar`]. Sealed: the marchers are written for these
/// three. Its constants are what the engines ask of a grid's kind; each is known at compile time, so the
/// branches for the other kinds are not compiled in.
pub trait GridKind: sealed::Sealed + Copy + core::fmt::Debug + Send + Sync + 'static {
    /// The kind's name as in the grid files (`"spherical"`, `"cylindrical"`, `"polar"`).
    const NAME: &'static str;
    /// The axis of each slot of the cell index (a polar grid's third slot is absent: it is always 0).
    const AXES: [Axis; 3];
    /// True when the radius is measured from the z axis (cylinder, polar): the radius stream then follows the
    /// ray's projection on z = 0.
    const FLAT_RADIUS: bool;
    /// True when the grid has a zenith angle θ (the sphere).
    const ZENITH: bool;
    /// True when the grid has a height z (the cylinder).
    const HEIGHT: bool;
}

/// Spherical grids (r, θ, φ): cell `[i, j, k]` (Hannasch ch. 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Spherical;

/// Cylindrical grids (ρ, φ, z): cell `[i, k, m]` (Hannasch §3.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Cylindrical;

/// 2-D polar grids (r, φ): cell `[i, k, 0]` (Hannasch §3.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Polar;

impl sealed::Sealed for Spherical {}
impl sealed::Sealed for Cylindrical {}
impl sealed::Sealed for Polar {}

impl GridKind for Spherical {
    const NAME: &'static str = "spherical";
    const AXES: [Axis; 3] = [Axis::R, Axis::Theta, Axis::Phi];
    const FLAT_RADIUS: bool = false;
    const ZENITH: bool = true;
    const HEIGHT: bool = false;
}

impl GridKind for Cylindrical {
    const NAME: &'static str = "cylindrical";
    const AXES: [Axis; 3] = [Axis::Rho, Axis::Phi, Axis::Z];
    const FLAT_RADIUS: bool = true;
    const ZENITH: bool = false;
    const HEIGHT: bool = true;
}

impl GridKind for Polar {
    const NAME: &'static str = "polar";
    const AXES: [Axis; 3] = [Axis::R, Axis::Phi, Axis::Z];
    const FLAT_RADIUS: bool = true;
    const ZENITH: bool = false;
    const HEIGHT: bool = false;
}

/// The coordinate of each slot of kind `K`'s cell index: the radius, then θ and φ (sphere), φ and z (cylinder),
/// or φ and nothing (polar).
pub(crate) const fn slots<K: GridKind>() -> [SlotKind; 3] {
    if K::ZENITH {
        [SlotKind::Radial, SlotKind::Zenith, SlotKind::Azimuth]
    } else if K::HEIGHT {
        [SlotKind::Radial, SlotKind::Azimuth, SlotKind::Height]
    } else {
        [SlotKind::Radial, SlotKind::Azimuth, SlotKind::Absent]
    }
}
