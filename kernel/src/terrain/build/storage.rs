//! [`TreeStorage`]: the one [`TerrainStorage`] over a tree [`build_tree`](super::build_tree) or
//! [`build_multires_tree`](super::build_multires_tree) wrote (Wartell et al. §3.5, §4, §5), with the node boxes its
//! records may keep ([`build_boxes`](super::build_boxes)), per-row and per-column trigonometry
//! ([`trig_tables`](super::trig_tables)) and residency flags of the multi-resolution tree. The buffers are
//! borrowed slices ([`SliceStorage`]: a static array will do) or owned by the caller's own type
//! ([`Buffers`]), so that a host can keep them in vectors and still use this implementation.

use super::tables::TrigTables;
use super::tree::{BoxSlot, BuildError, NodeRecord, Tree, check_records, half_up, window_slots};
use crate::dd::Dd;
use crate::geodesy::Ellipsoid;
use crate::real::Real;
use crate::terrain::boxes::NodeBox;
use crate::terrain::grid::{Grid, Node, NodeId};
use crate::terrain::parallel::{Parallel, col_sin_cos_dd, row_parallel};
use crate::terrain::storage::{TerrainCaches, TerrainStorage};
use crate::terrain::windows::{WindowBox, windows_per_leaf};
use core::sync::atomic::{AtomicBool, Ordering};

/// The buffers of a [`TreeStorage`], borrowed: the heights (`H`: the samples' own scalar type, converted
/// exactly), the node records (`X`: with or without boxes, [`BoxSlot`]), and the optional parts. An empty
/// `resident` slice means every block resident (`R`: [`Residency`]); `trig: None` means the kernel computes the
/// trigonometry when it asks.
#[derive(Debug)]
pub struct Parts<'a, T, H, X = (), R = ()> {
    /// `rows × cols` heights, row-major, NaN for nodata.
    pub heights: &'a [H],
    /// The records of [`build_tree`](super::build_tree), [`node_slots`](super::node_slots) of them.
    pub nodes: &'a [NodeRecord<H, X>],
    /// The tables of [`trig_tables`](super::trig_tables), or `None`.
    pub trig: Option<TrigTables<'a, T>>,
    /// Per-node residency of a multi-resolution tree's blocks ([`node_slots`](super::node_slots) flags, indexed
    /// by node id), or empty (all resident). The caller pages blocks in and out by setting them (Wartell et al. §5);
    /// the picker reports a block it needs that is not resident as
    /// [`TerrainError::NeedsBlock`](crate::terrain::error::TerrainError::NeedsBlock).
    pub resident: &'a [R],
    /// The leaves' window boxes of [`build_windows`](super::build_windows), [`window_slots`](super::window_slots)
    /// of them, or empty (none: each leaf is traced whole).
    pub windows: &'a [WindowBox],
}

impl<T, H, X, R> Clone for Parts<'_, T, H, X, R> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T, H, X, R> Copy for Parts<'_, T, H, X, R> {}

impl<'a, T, H, X> Parts<'a, T, H, X> {
    /// Heights and node records only (a single-resolution tree, [`Residency`]).
    pub fn new(heights: &'a [H], nodes: &'a [NodeRecord<H, X>]) -> Self {
        Parts {
            heights,
            nodes,
            trig: None,
            resident: &[],
            windows: &[],
        }
    }

    /// These parts with residency flags (`AtomicBool`: a multi-resolution tree's, [`Residency`]).
    pub fn with_resident<R: Residency>(self, resident: &'a [R]) -> Parts<'a, T, H, X, R> {
        Parts {
            heights: self.heights,
            nodes: self.nodes,
            trig: self.trig,
            resident,
            windows: self.windows,
        }
    }
}

impl<'a, T, H, X, R> Parts<'a, T, H, X, R> {
    /// These parts with the leaves' window boxes ([`build_windows`](super::build_windows)).
    pub fn with_windows(self, windows: &'a [WindowBox]) -> Self {
        Parts { windows, ..self }
    }
}

/// Who owns a [`TreeStorage`]'s buffers: anything that can lend them as [`Parts`] (the slices themselves, or a
/// host's struct of vectors). The storage checks their lengths once, when it is made, so an owner must not
/// change them afterwards.
pub trait Buffers<T> {
    /// The samples' scalar type.
    type Height: Real;
    /// What a node record keeps of its box.
    type Box: BoxSlot;
    /// The residency flags' type.
    type Flag: Residency;
    /// The buffers, borrowed.
    fn parts(&self) -> Parts<'_, T, Self::Height, Self::Box, Self::Flag>;
}

impl<T, H: Real, X: BoxSlot, R: Residency> Buffers<T> for Parts<'_, T, H, X, R> {
    type Height = H;
    type Box = X;
    type Flag = R;
    #[inline]
    fn parts(&self) -> Parts<'_, T, H, X, R> {
        *self
    }
}

/// The element of [`Parts::resident`]: `AtomicBool` for a storage that serves multi-resolution trees
/// ([`build_multires_tree`](super::build_multires_tree)) with blocks paged in and out, or `()` for one that
/// serves single-resolution trees only: every block resident at stride 1, known when the kernel is compiled,
/// so that a program without paging links none of the multi-resolution fallback and stitching.
pub trait Residency: sealed::Sealed {
    /// Whether a storage with these flags serves multi-resolution trees.
    const MULTIRES: bool;
    /// Whether the flag says resident.
    fn is_set(&self) -> bool;
}

impl Residency for () {
    const MULTIRES: bool = false;
    #[inline]
    fn is_set(&self) -> bool {
        true
    }
}

impl Residency for AtomicBool {
    const MULTIRES: bool = true;
    #[inline]
    fn is_set(&self) -> bool {
        self.load(Ordering::Relaxed)
    }
}

mod sealed {
    /// [`super::Residency`] is implemented by the kernel only.
    pub trait Sealed {}
    impl Sealed for () {}
    impl Sealed for core::sync::atomic::AtomicBool {}
}

/// The [`TerrainStorage`] over a built tree and its buffers (module docs). Use [`SliceStorage`] for
/// borrowed slices.
#[derive(Debug, Clone, Copy)]
pub struct TreeStorage<T, B> {
    ellipsoid: Ellipsoid<T>,
    grid: Grid<T>,
    tree: Tree,
    buffers: B,
}

/// The [`TreeStorage`] over borrowed slices: everything borrowed, nothing allocated. `H` is the samples' type,
/// `X` what the records keep of their boxes (`()`: none; `Option<NodeBox>`: [`build_boxes`](super::build_boxes)),
/// `R` the residency flags' (`()`: a single-resolution tree; `AtomicBool`: [`Residency`]).
pub type SliceStorage<'a, T, H = T, X = (), R = ()> = TreeStorage<T, Parts<'a, T, H, X, R>>;

impl<'a, T: Real, H: Real, X: BoxSlot> TreeStorage<T, Parts<'a, T, H, X>> {
    /// The storage over `heights` (as given to [`build_tree`](super::build_tree)) and `nodes` (its buffer, as it
    /// wrote it), on `ellipsoid`, without tables or residency flags (a single-resolution tree). Checks the grid
    /// and heights again and that the buffer holds the tree's slots.
    pub fn new(
        ellipsoid: Ellipsoid<T>,
        grid: Grid<T>,
        heights: &'a [H],
        nodes: &'a [NodeRecord<H, X>],
        tree: Tree,
    ) -> Result<Self, BuildError> {
        Self::with_buffers(ellipsoid, grid, tree, Parts::new(heights, nodes))
    }
}

impl<T: Real, B: Buffers<T>> TreeStorage<T, B> {
    /// The storage over `buffers`, on `ellipsoid`: checks the grid and heights again ([`BuildError`]), that
    /// the node buffer holds the tree's slots, that every optional buffer has its `const fn`'s length, and that
    /// a multi-resolution tree comes with flags that serve one ([`Residency::MULTIRES`]).
    pub fn with_buffers(
        ellipsoid: Ellipsoid<T>,
        grid: Grid<T>,
        tree: Tree,
        buffers: B,
    ) -> Result<Self, BuildError> {
        let p = buffers.parts();
        check_records(p.heights, &grid, &tree, p.nodes.len())?;
        if !(p.resident.is_empty() || p.resident.len() == tree.slots())
            || !(p.windows.is_empty()
                || p.windows.len() == window_slots(grid.rows, grid.cols, tree.block()))
        {
            return Err(BuildError::BufferLength);
        }
        if tree.is_multires() && !B::Flag::MULTIRES {
            return Err(BuildError::SingleResolution);
        }
        if let Some(t) = p.trig {
            if !t.fits(&grid) {
                return Err(BuildError::BufferLength);
            }
        }
        Ok(TreeStorage {
            ellipsoid,
            grid,
            tree,
            buffers,
        })
    }

    /// What the builder built.
    pub fn tree(&self) -> Tree {
        self.tree
    }

    /// The buffers.
    pub fn buffers(&self) -> &B {
        &self.buffers
    }

    /// The record of node `id`.
    #[inline]
    pub fn record(&self, id: NodeId) -> Option<&NodeRecord<B::Height, B::Box>> {
        self.buffers.parts().nodes.get(usize::try_from(id.0).ok()?)
    }
}

impl<T: Real, B: Buffers<T>> TerrainStorage<T> for TreeStorage<T, B> {
    fn ellipsoid(&self) -> Ellipsoid<T> {
        self.ellipsoid
    }
    fn grid(&self) -> Grid<T> {
        self.grid
    }
    fn zone_count(&self) -> usize {
        self.tree.zone_count()
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        let [_, zc] = self.tree.zone_dims;
        let k = u32::try_from(k).ok()?;
        let (r, c) = (k.checked_div(zc)?, k.checked_rem(zc)?);
        let group = (r >> 1).checked_mul(half_up(zc))?.checked_add(c >> 1)?;
        let slot = self
            .tree
            .zone_offset
            .checked_add(group.checked_mul(4)?)?
            .checked_add(((r & 1) << 1) | (c & 1))?;
        (usize::try_from(k).ok()? < self.zone_count()).then_some(NodeId(slot))
    }
    #[inline]
    fn node(&self, id: NodeId) -> Option<Node<T>> {
        self.record(id).map(NodeRecord::node)
    }
    #[inline]
    fn height(&self, i: u32, j: u32) -> Option<T> {
        if i >= self.grid.rows || j >= self.grid.cols {
            return None;
        }
        // Exact: `i·cols + j < rows·cols`, the heights' length (checked when the storage was made).
        let k = usize::try_from(i)
            .ok()?
            .wrapping_mul(usize::try_from(self.grid.cols).ok()?)
            .wrapping_add(usize::try_from(j).ok()?);
        let h = *self.buffers.parts().heights.get(k)?;
        (!h.is_nan()).then(|| T::from_f64(h.to_f64()))
    }
    #[inline]
    fn is_resident(&self, id: NodeId) -> bool {
        if !B::Flag::MULTIRES {
            return true;
        }
        usize::try_from(id.0)
            .ok()
            .and_then(|k| self.buffers.parts().resident.get(k))
            .is_none_or(Residency::is_set)
    }
    #[inline]
    fn block_stride(&self, id: NodeId) -> u32 {
        if !B::Flag::MULTIRES || !self.tree.is_multires() {
            return 1;
        }
        self.record(id).map_or(1, |r| self.tree.stride(r.level))
    }
}

impl<T: Real, B: Buffers<T>> TerrainCaches<T> for TreeStorage<T, B> {
    // Out of line: inlined, the lookup grows the kernel's per-row cache closure in its leaf walk past
    // what the compiler inlines there (callgrind: 1 500 more instructions per camera pick).
    #[inline(never)]
    fn row_sin_cos(&self, i: u32) -> (T, T) {
        let cached = self
            .buffers
            .parts()
            .trig
            .and_then(|t| t.row_sin_cos.get(usize::try_from(i).ok()?).copied());
        cached.unwrap_or_else(|| sin_cos_deg_cold(self.grid.lat_deg(i)))
    }
    // Out of line: inlined, the lookup grows the kernel's per-row cache closure in its leaf walk past
    // what the compiler inlines there (callgrind: 1 500 more instructions per camera pick).
    #[inline(never)]
    fn col_sin_cos(&self, j: u32) -> (T, T) {
        let cached = self
            .buffers
            .parts()
            .trig
            .and_then(|t| t.col_sin_cos.get(usize::try_from(j).ok()?).copied());
        cached.unwrap_or_else(|| sin_cos_deg_cold(self.grid.lon_deg(j)))
    }
    fn row_parallel(&self, i: u32) -> Parallel<T> {
        let cached = self
            .buffers
            .parts()
            .trig
            .and_then(|t| t.row_parallel.get(usize::try_from(i).ok()?).copied());
        cached.unwrap_or_else(|| row_parallel(&self.ellipsoid, &self.grid, i))
    }
    fn col_sin_cos_dd(&self, j: u32) -> (Dd<T>, Dd<T>) {
        let cached = self
            .buffers
            .parts()
            .trig
            .and_then(|t| t.col_sin_cos_dd.get(usize::try_from(j).ok()?).copied());
        cached.unwrap_or_else(|| col_sin_cos_dd(&self.grid, j))
    }
    #[inline]
    fn node_box(&self, id: NodeId) -> Option<NodeBox> {
        self.record(id).and_then(|r| r.bbox.node_box())
    }
    #[inline]
    fn window_boxes(&self, id: NodeId) -> &[WindowBox] {
        let n = windows_per_leaf(self.tree.block());
        let windows = self.buffers.parts().windows;
        usize::try_from(id.0)
            .ok()
            .and_then(|k| k.checked_mul(n))
            .and_then(|a| windows.get(a..a.checked_add(n)?))
            .unwrap_or(&[])
    }
}

/// [`crate::geodesy::sin_cos_deg`] out of line: the path of a storage without tables, kept out of the
/// per-vertex code of a storage with them (which the kernel inlines into its leaf walk).
#[cold]
#[inline(never)]
fn sin_cos_deg_cold<T: Real>(deg: T) -> (T, T) {
    crate::geodesy::sin_cos_deg(deg)
}
