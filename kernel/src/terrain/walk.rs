//! The state of one pick (Wartell et al. §3.5–§6): the nearest candidate so far, the traced units and their
//! fallback sources, the traversal stack's entries, the zones' volumes and the per-ray counters. Private to the
//! picker's phases (`traverse.rs`, `leaf.rs`, `stitch.rs`, `hit.rs`), which share it through this module.

use super::grid::{Node, NodeId};
use super::refine::TriRef;
use super::triangle::WatertightRay;
use crate::geodesy::{HeightQuadBounds, RelaxedVolume};
use crate::ray::Ray;
use crate::real::Real;

/// Per-ray work counters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PickStats {
    /// Quads (zones included) whose volume the ray entered and that were visited.
    pub quads_visited: u32,
    /// Triangle pairs (cells) whose planar volume the ray crossed.
    pub triangle_pairs_visited: u32,
    /// Ray–triangle tests performed.
    pub triangles_tested: u32,
}

/// The nearest hit found so far during the traversal: its parameter and which triangle (the [`Hit`] is formed
/// once, after the traversal, from the refined parameter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Candidate<T> {
    pub(super) t: T,
    pub(super) cell: [u32; 2],
    pub(super) tri: TriRef,
    pub(super) unit: Unit,
}

/// A traced unit (§4, §5): a node's cell range traced with cells of `stride` grid steps from the block of the
/// node at `level` (the node's own, or its nearest resident ancestor's).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Unit {
    pub(super) rows: [u32; 2],
    pub(super) cols: [u32; 2],
    pub(super) stride: u32,
    pub(super) level: u8,
}

/// The resident block a subtree falls back to (§5): the nearest resident ancestor at or below `min_level`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Source {
    pub(super) stride: u32,
    pub(super) level: u8,
}

/// What the traversal does at a node (`traverse.rs`, "Which blocks are traced").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    /// Visit the children; the source they fall back to.
    Descend(Option<Source>),
    /// Trace this unit.
    Trace(Unit),
    /// The node's block is needed.
    Needs,
}

/// The traced unit covering a grid cell, for stitching ([`Picker::unit_at`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Lookup {
    Unit(Unit),
    /// No node covers the cell (no data there).
    Empty,
    Needs(NodeId),
}

/// A traced cell's grid ranges: rows `[i, i1]`, columns `[j, j1]` (corner vertices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct CellAt {
    pub(super) rows: [u32; 2],
    pub(super) cols: [u32; 2],
}

/// One side of a traced cell: along a row (`along_cols`: the points are columns) or a column, at row or column
/// `fixed`, from `from` to `to`; `across` is the neighbouring cells' row or column when the side is on the
/// unit's border.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct SideAt {
    pub(super) along_cols: bool,
    pub(super) fixed: u32,
    pub(super) from: u32,
    pub(super) to: u32,
    pub(super) across: Option<u32>,
}

/// The outcome of [`Picker::stitch`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Stitch {
    Plain,
    Done,
}

/// The per-ray state of a traversal: the ray, the nearest hit so far, the nearest needed block, the counters.
pub(super) struct Walk<'r, 'w, T> {
    pub(super) ray: &'r Ray<T>,
    pub(super) wray: &'r WatertightRay<T>,
    pub(super) best: &'w mut Option<Candidate<T>>,
    pub(super) pending: &'w mut Option<(T, NodeId)>,
    pub(super) stats: &'w mut PickStats,
}

impl<T: Real> Walk<'_, '_, T> {
    pub(super) fn best_t(&self) -> T {
        self.best.as_ref().map_or(T::INFINITY, |h| h.t)
    }
    /// Records that node `id`'s block is needed from parameter `t` on (the nearest such is kept).
    pub(super) fn need(&mut self, t: T, id: NodeId) {
        if self.pending.is_none_or(|(p, _)| t < p) {
            *self.pending = Some((t, id));
        }
    }
}

/// A zone: its root and how its volume is tested (the storage's cached volume, or the relaxed test of
/// [`relaxed_interval`] from the zone's trigonometry). Its box is kept apart ([`Picker`]'s `zone_boxes`).
pub(super) type Zone<T> = (NodeId, Node<T>, ZoneVolume<T>);

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum ZoneVolume<T> {
    Cached(HeightQuadBounds<T>),
    Relaxed(RelaxedVolume<T>),
}

/// A node on the traversal stack. The node itself is read from the storage when it is visited, and checked
/// then against its parent's ranges and stride.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Entry<T> {
    pub(super) id: NodeId,
    /// The parent's cell ranges (`None` for a zone).
    pub(super) parent: Option<([u32; 2], [u32; 2])>,
    pub(super) t_in: T,
    pub(super) t_out: T,
    /// The parent's block stride (`u32::MAX` for a zone).
    pub(super) parent_stride: u32,
    /// The source inherited from the parent.
    pub(super) src: Option<Source>,
    /// Where the node's box was tested: its index in the traversal's frames (0: the grid's frame).
    pub(super) frame: u8,
    /// The node's depth below its zone (0: the zone); its own frame goes to index `depth + 1`.
    pub(super) depth: u8,
}

/// The capacity of the traversal's stack of frames ([`boxes`], "Which frame"): node boxes in distinct frames
/// along one path from a zone, the grid's frame included.
pub(super) const FRAMES: usize = 32;
