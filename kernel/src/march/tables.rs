//! The tables of a grid as the engines see them: its axes, its center and the rule that says which bands
//! form a cell of the domain.

use super::axes::{AzimuthAxis, HeightAxis, RadialAxis, ZenithAxis};
use super::kind::{Coordinates, SlotKind};
use crate::real::Real;
use crate::vec3::V3;

/// The tables of a grid, as the engines see them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Axes<'a, T> {
    pub radial: RadialAxis<'a, T>,
    pub zenith: Option<ZenithAxis<'a, T>>,
    pub azimuth: AzimuthAxis<'a, T>,
    pub height: Option<HeightAxis<'a, T>>,
    pub center: V3<T>,
    /// The grid's coordinates (what its kind supplies; read by the engines of `Dynamic`).
    pub coordinates: Coordinates,
    /// The cell rule, formed once with the grid.
    pub rule: CellRule,
}

/// What decides whether a set of bands is a cell of the domain, and which: per slot, the inside bands are
/// `first .. first + count` and band `b` is cell index `b − first` (a banded coordinate: bands 1 to L − 1 of L
/// breakpoints; the azimuth: every sector but the outside one of a wedge; an absent slot: its one band 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct CellRule {
    first: [u32; 3],
    count: [u32; 3],
}

impl CellRule {
    /// The cell index of `band` in `slot`, or `None` when that band is outside the domain (band 0 and the top
    /// band of a banded coordinate, the outside sector of a wedge). One subtraction and one comparison; the
    /// slot's two entries are read by index once the slot is known (a `match` on the slot let the separable
    /// engine hoist all six entries onto its stack on every call).
    #[inline(always)]
    pub(crate) fn index(&self, slot: usize, band: u32) -> Option<u32> {
        let (Some(&first), Some(&count)) = (self.first.get(slot), self.count.get(slot)) else {
            return None;
        };
        let i = band.wrapping_sub(first);
        (i < count).then_some(i)
    }
}

impl CellRule {
    /// True while the radius band (slot 0) is at or beyond the outer radius.
    #[inline]
    pub(crate) fn beyond_outer_radius(&self, band: u32) -> bool {
        band >= self.first[0].saturating_add(self.count[0])
    }
}

impl<'a, T: Real> Axes<'a, T> {
    /// The tables of a grid of `coordinates`, centred at the origin.
    pub(crate) fn new(
        coordinates: Coordinates,
        radial: RadialAxis<'a, T>,
        zenith: Option<ZenithAxis<'a, T>>,
        azimuth: AzimuthAxis<'a, T>,
        height: Option<HeightAxis<'a, T>>,
    ) -> Self {
        let mut axes = Axes {
            radial,
            zenith,
            azimuth,
            height,
            center: V3::ZERO,
            coordinates,
            rule: CellRule {
                first: [0; 3],
                count: [u32::MAX; 3],
            },
        };
        axes.rule = axes.cell_rule(coordinates.slots);
        axes
    }

    fn cell_rule(&self, slots: [SlotKind; 3]) -> CellRule {
        let mut rule = self.rule;
        for ((f, c), k) in rule
            .first
            .iter_mut()
            .zip(rule.count.iter_mut())
            .zip(slots.iter())
        {
            let banded = |len: u32| (1, len.saturating_sub(1));
            (*f, *c) = match k {
                SlotKind::Radial => banded(self.radial.len),
                SlotKind::Zenith => banded(self.zenith.map_or(0, |z| z.len)),
                SlotKind::Azimuth => (0, self.azimuth.sectors),
                SlotKind::Height => banded(self.height.map_or(0, |h| h.len)),
                SlotKind::Absent => (0, u32::MAX),
            };
        }
        rule
    }
}
