//! What a grid kind supplies to the marchers (Hannasch §3.3–3.4): which coordinates it has, in which slots of
//! the cell index, and whether its radius is measured from the center or from the z axis. The three kinds are
//! three types, so the engines are compiled once per kind a program marches, each with only its own
//! coordinates' steps: a program that marches spherical grids only links no cylinder or polar code. A fourth,
//! [`Dynamic`], leaves the choice to each grid at run time: one marcher for all three kinds, the smallest code
//! when a program marches more than one (the C interface).

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

/// The coordinates of a grid kind: what the engines ask of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Coordinates {
    pub(crate) slots: [SlotKind; 3],
    axes: [Axis; 3],
    flat_radius: bool,
}

impl Coordinates {
    pub(crate) const SPHERICAL: Coordinates = Coordinates {
        slots: [SlotKind::Radial, SlotKind::Zenith, SlotKind::Azimuth],
        axes: [Axis::R, Axis::Theta, Axis::Phi],
        flat_radius: false,
    };
    pub(crate) const CYLINDRICAL: Coordinates = Coordinates {
        slots: [SlotKind::Radial, SlotKind::Azimuth, SlotKind::Height],
        axes: [Axis::Rho, Axis::Phi, Axis::Z],
        flat_radius: true,
    };
    pub(crate) const POLAR: Coordinates = Coordinates {
        slots: [SlotKind::Radial, SlotKind::Azimuth, SlotKind::Absent],
        axes: [Axis::R, Axis::Phi, Axis::Z],
        flat_radius: true,
    };

    /// The axis of each slot of the cell index (a polar grid's third slot is absent: its index is always 0).
    pub const fn axes(&self) -> [Axis; 3] {
        self.axes
    }

    /// True when the radius is measured from the z axis (cylinder, polar): the radius stream then follows the
    /// ray's projection on z = 0.
    pub const fn flat_radius(&self) -> bool {
        self.flat_radius
    }

    /// True when the kind has a zenith angle θ (the sphere).
    pub const fn zenith(&self) -> bool {
        matches!(self.slots[1], SlotKind::Zenith)
    }

    /// True when the kind has a height z (the cylinder).
    pub const fn height(&self) -> bool {
        matches!(self.slots[2], SlotKind::Height)
    }
}

mod sealed {
    pub trait Sealed {}
}

/// A kind of grid: [`Spherical`], [`Cylindrical`], [`Polar`], or [`Dynamic`] (any of them, chosen by the grid at
/// run time). Sealed: the marchers are written for these.
pub trait GridKind: sealed::Sealed + Copy + core::fmt::Debug + Send + Sync + 'static {
    /// The kind's name as in the grid files (`"spherical"`, `"cylindrical"`, `"polar"`; `"dynamic"`).
    const NAME: &'static str;
    /// The kind's coordinates, known at compile time; `None` for [`Dynamic`], where each grid's own decide.
    const COORDINATES: Option<Coordinates>;
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

/// Any of the three kinds, decided by each grid at run time (`Grid::into_dynamic`):
/// one marcher whose steps switch on the grid's coordinates, as every marcher did before the kinds were types.
/// Its answers are the typed kind's, bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Dynamic;

impl sealed::Sealed for Spherical {}
impl sealed::Sealed for Cylindrical {}
impl sealed::Sealed for Polar {}
impl sealed::Sealed for Dynamic {}

impl GridKind for Spherical {
    const NAME: &'static str = "spherical";
    const COORDINATES: Option<Coordinates> = Some(Coordinates::SPHERICAL);
}

impl GridKind for Cylindrical {
    const NAME: &'static str = "cylindrical";
    const COORDINATES: Option<Coordinates> = Some(Coordinates::CYLINDRICAL);
}

impl GridKind for Polar {
    const NAME: &'static str = "polar";
    const COORDINATES: Option<Coordinates> = Some(Coordinates::POLAR);
}

impl GridKind for Dynamic {
    const NAME: &'static str = "dynamic";
    const COORDINATES: Option<Coordinates> = None;
}

/// The coordinates of kind `K`'s grids: its constant coordinates, or (for [`Dynamic`]) `own`, the grid's. Inlined, so
/// that for a typed kind every test of the result is decided at compile time.
#[inline(always)]
pub(crate) fn coordinates<K: GridKind>(own: Coordinates) -> Coordinates {
    match K::COORDINATES {
        Some(s) => s,
        None => own,
    }
}

/// True when kind `K`'s grids may have a zenith stream: decided at compile time for a typed kind, true for
/// [`Dynamic`] (whose grids' own axes decide).
#[inline(always)]
pub(crate) fn may_have_zenith<K: GridKind>() -> bool {
    K::COORDINATES.is_none_or(|s| s.zenith())
}

/// As [`may_have_zenith`], for a height stream.
#[inline(always)]
pub(crate) fn may_have_height<K: GridKind>() -> bool {
    K::COORDINATES.is_none_or(|s| s.height())
}
