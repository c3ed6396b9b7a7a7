//! The quadtree's records and their build (the module docs of [`super`]): [`NodeRecord`], [`build_tree`],
//! [`build_multires_tree`], [`node_slots`] and what they share with the storage and the tables.

use crate::real::Real;
use crate::terrain::boxes::NodeBox;
use crate::terrain::grid::{Grid, Node, NodeId};
#[cfg(doc)]
use crate::terrain::storage::TerrainStorage;
use crate::terrain::windows::windows_per_leaf;

/// Why [`build_tree`] or [`SliceStorage::new`](crate::terrain::build::SliceStorage::new) refused its input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BuildError {
    /// The grid is invalid ([`Grid::validate`]).
    InvalidGrid,
    /// The heights slice does not hold `rows × cols` heights.
    HeightsLength,
    /// A height is infinite (a missing height is NaN), at `[row, column]`.
    InfiniteHeight([u32; 2]),
    /// The block size is 0, or a leaf block would span 180° of longitude or more (the kernel's meridian walls
    /// bound wedges narrower than a half-turn).
    InvalidBlock,
    /// The node buffer is shorter than [`node_slots`] of the grid and block.
    BufferTooSmall,
    /// The node records given to [`SliceStorage::new`](crate::terrain::build::SliceStorage::new) or [`build_boxes`](crate::terrain::build::build_boxes) are not the ones [`build_tree`] wrote
    /// for this grid.
    RecordsMismatch,
    /// A table or residency buffer does not have the length its `const fn` gives ([`node_slots`],
    /// [`row_table_len`], [`col_table_len`]).
    BufferLength,
    /// The multi-resolution shape is invalid (a fine region with a non-finite or reversed bound).
    InvalidShape,
    /// A multi-resolution tree given to a storage that serves single-resolution trees only (residency flags of
    /// type `()`, [`Residency`](crate::terrain::build::Residency)).
    SingleResolution,
}

impl core::fmt::Display for BuildError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BuildError::InvalidGrid => f.write_str("invalid DEM grid"),
            BuildError::HeightsLength => {
                f.write_str("the heights slice does not hold rows × cols heights")
            }
            BuildError::InfiniteHeight([i, j]) => {
                write!(f, "infinite height at row {i}, column {j}")
            }
            BuildError::InvalidBlock => {
                f.write_str("block size 0, or a block spanning 180° of longitude or more")
            }
            BuildError::BufferTooSmall => f.write_str("node buffer shorter than node_slots()"),
            BuildError::RecordsMismatch => f.write_str("node records not built for this grid"),
            BuildError::BufferLength => {
                f.write_str("table or residency buffer of the wrong length")
            }
            BuildError::InvalidShape => f.write_str("invalid multi-resolution shape"),
            BuildError::SingleResolution => {
                f.write_str("multi-resolution tree in a single-resolution storage")
            }
        }
    }
}

impl core::error::Error for BuildError {}

/// One node as [`build_tree`] stores it: cell ranges, the `[min, max]` of its vertex heights in the samples'
/// own type `H` (exact; `min > max`: no data, or an empty slot), child ids (`u32::MAX`: none), depth below its
/// zone, and what `X` keeps of its box ([`BoxSlot`]: nothing, or the box [`build_boxes`](crate::terrain::build::build_boxes) fills), so that the
/// traversal finds a node and its children's boxes in one record each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeRecord<H, X = ()> {
    /// Cell rows `[rows[0], rows[1])`.
    pub rows: [u32; 2],
    /// Cell columns `[cols[0], cols[1])`.
    pub cols: [u32; 2],
    /// `[min, max]` of the node's vertex heights; `min > max` when it has none.
    pub heights: [H; 2],
    /// Child ids, `u32::MAX` for none.
    pub kids: [u32; 4],
    /// Depth below the node's zone (zones are 0).
    pub level: u8,
    /// The node's box ([`TerrainCaches::node_box`](crate::terrain::TerrainCaches::node_box)), if `X` keeps one.
    pub bbox: X,
}

impl<H: Real, X: BoxSlot> NodeRecord<H, X> {
    /// An empty slot (the buffer's initial value).
    pub const EMPTY: Self = NodeRecord {
        rows: [0; 2],
        cols: [0; 2],
        heights: [H::INFINITY, H::NEG_INFINITY],
        kids: [u32::MAX; 4],
        level: 0,
        bbox: X::NONE,
    };

    /// The node the kernel's traversal reads ([`TerrainStorage::node`]), its height range in `T` (converted
    /// from `H` by rounding, which keeps the range that of the storage's converted heights).
    #[inline]
    pub fn node<T: Real>(&self) -> Node<T> {
        let [lo, hi] = self.heights;
        Node {
            rows: self.rows,
            cols: self.cols,
            heights: (lo <= hi).then(|| [T::from_f64(lo.to_f64()), T::from_f64(hi.to_f64())]),
            children: self.kids.map(|k| (k != u32::MAX).then_some(NodeId(k))),
            level: self.level,
        }
    }
}

/// What a [`NodeRecord`] keeps of its node's box (beyond the paper; [`super::boxes`](crate::terrain::boxes)): `()` for a tree without
/// boxes, which then costs neither RAM nor the traversal's box code (a `None` known at compile time), or
/// `Option<NodeBox>` (28 bytes) for one whose boxes [`build_boxes`](crate::terrain::build::build_boxes) fills.
pub trait BoxSlot: Copy + PartialEq + core::fmt::Debug + sealed::Sealed {
    /// An empty slot's value.
    const NONE: Self;
    /// The box, if the slot holds one.
    fn node_box(&self) -> Option<NodeBox>;
}

impl BoxSlot for () {
    const NONE: Self = ();
    #[inline]
    fn node_box(&self) -> Option<NodeBox> {
        None
    }
}

impl BoxSlot for Option<NodeBox> {
    const NONE: Self = None;
    #[inline]
    fn node_box(&self) -> Option<NodeBox> {
        *self
    }
}

mod sealed {
    /// [`super::BoxSlot`] is implemented by the kernel only.
    pub trait Sealed {}
    impl Sealed for () {}
    impl Sealed for Option<crate::terrain::boxes::NodeBox> {}
}

/// What [`build_tree`] built: where the zones are in the buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tree {
    /// Slot of the zone level's first group.
    pub(super) zone_offset: u32,
    /// The zone level's node rows and columns.
    pub(super) zone_dims: [u32; 2],
    /// Slots used (the rest of the buffer is untouched).
    pub(super) slots: u32,
    /// The block size.
    pub(super) block: u32,
    /// The zone level's index counted from the leaves (0: the zones are leaves).
    pub(super) top: u8,
    /// Built by [`build_multires_tree`]: every node has a block at stride `2^(its level above the leaves)`.
    pub(super) multires: bool,
}

impl Tree {
    /// The number of zones (quadtree roots): node rows times columns of the zone level.
    pub fn zone_count(&self) -> usize {
        let [r, c] = self.zone_dims;
        usize::try_from(u64::from(r).saturating_mul(u64::from(c))).unwrap_or(usize::MAX)
    }
    /// The number of node slots used.
    pub fn slots(&self) -> usize {
        usize::try_from(self.slots).unwrap_or(usize::MAX)
    }
    /// The leaf block size.
    pub fn block(&self) -> u32 {
        self.block
    }
    /// Whether the tree is multi-resolution ([`build_multires_tree`]).
    pub fn is_multires(&self) -> bool {
        self.multires
    }
    /// The depth of the leaves below the zones (zones are level 0).
    pub fn depth(&self) -> u32 {
        u32::from(self.top)
    }
    /// The block stride of a node at depth `level` below its zone in a multi-resolution tree, `2^(depth −
    /// level)` (Wartell et al. §5: the pyramid's subsampling; at most `2^31`), 1 in a single-resolution one.
    pub fn stride(&self, level: u8) -> u32 {
        if !self.multires {
            return 1;
        }
        1u32.checked_shl(u32::from(self.top.saturating_sub(level)).min(31))
            .unwrap_or(1)
    }
}

/// The length of the per-row tables of [`trig_tables`](crate::terrain::build::trig_tables): one entry per vertex row.
pub const fn row_table_len(rows: u32) -> usize {
    rows as usize
}

/// The length of the per-column tables of [`trig_tables`](crate::terrain::build::trig_tables): one entry per vertex column.
pub const fn col_table_len(cols: u32) -> usize {
    cols as usize
}

/// The shape of a multi-resolution tree ([`build_multires_tree`]; Wartell et al. §5, Fig. 11): branches stop at
/// `coarse_level` levels above the leaves outside `fine_region`, whose nodes go down to full resolution.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MultiRes<T> {
    /// `[lat_s, lat_n, lon_w, lon_e]`, degrees: nodes that meet this box go down to the leaves. `None`: every
    /// node does.
    pub fine_region: Option<[T; 4]>,
    /// The level above the leaves (0: the leaves) at which branches outside `fine_region` end.
    pub coarse_level: u32,
}

/// `⌈n / 2⌉`.
pub(super) const fn half_up(n: u32) -> u32 {
    (n >> 1).saturating_add(n & 1)
}

/// `⌈n / d⌉` for `d ≥ 1`.
pub(super) const fn div_up(n: u32, d: u32) -> u32 {
    match (n.checked_div(d), n.checked_rem(d)) {
        (Some(q), Some(r)) => q.saturating_add(if r > 0 { 1 } else { 0 }),
        _ => 0,
    }
}

/// The slots of a level of `r × c` nodes stored by 2 × 2 groups.
pub(super) const fn level_slots(r: u32, c: u32) -> u64 {
    (half_up(r) as u64)
        .saturating_mul(half_up(c) as u64)
        .saturating_mul(4)
}

/// Whether a level of `r × c` nodes is the zone level (at most 4 rows and 8 columns).
pub(super) const fn is_zone_level(r: u32, c: u32) -> bool {
    r <= 4 && c <= 8
}

/// The length of the node buffer [`build_tree`] needs for a grid of `rows × cols` vertices and leaf blocks of
/// `block × block` cells: the slots of every level from the leaves up to the zones, each level stored by 2 × 2
/// groups (about `4/3 · 4 · ⌈rows/2b⌉ · ⌈cols/2b⌉`, b = `block`). 0 for fewer than 2 rows or columns or a
/// block of 0.
pub const fn node_slots(rows: u32, cols: u32, block: u32) -> usize {
    if rows < 2 || cols < 2 || block == 0 {
        return 0;
    }
    let mut r = div_up(rows.saturating_sub(1), block);
    let mut c = div_up(cols.saturating_sub(1), block);
    let mut total: u64 = 0;
    // Each level halves both counts (rounding up), so 33 levels reach 1 × 1 from any u32.
    let mut k = 0u32;
    while k < 40 {
        total = total.saturating_add(level_slots(r, c));
        if is_zone_level(r, c) {
            break;
        }
        r = half_up(r);
        c = half_up(c);
        k = k.saturating_add(1);
    }
    if total > usize::MAX as u64 {
        usize::MAX
    } else {
        total as usize
    }
}

/// The length of the window buffer [`super::build_windows`] fills for a grid of `rows × cols` vertices and leaf
/// blocks of `block × block` cells: [`windows_per_leaf`] records per slot of the leaf level (the first slots of
/// the node buffer, [`node_slots`]). 0 where `node_slots` is.
pub const fn window_slots(rows: u32, cols: u32, block: u32) -> usize {
    if rows < 2 || cols < 2 || block == 0 {
        return 0;
    }
    let leaves = level_slots(
        div_up(rows.saturating_sub(1), block),
        div_up(cols.saturating_sub(1), block),
    );
    let total = leaves.saturating_mul(windows_per_leaf(block) as u64);
    if total > usize::MAX as u64 {
        usize::MAX
    } else {
        total as usize
    }
}

/// The node levels of a build: per level (0: leaves) its node rows and columns and its first slot.
pub(super) struct Levels {
    pub(super) dims: [[u32; 2]; 40],
    pub(super) offset: [u32; 40],
    pub(super) count: usize,
}

impl Levels {
    pub(super) fn new(grid_rows: u32, grid_cols: u32, block: u32) -> Option<Self> {
        let mut l = Levels {
            dims: [[0; 2]; 40],
            offset: [0; 40],
            count: 0,
        };
        let mut r = div_up(grid_rows.checked_sub(1)?, block);
        let mut c = div_up(grid_cols.checked_sub(1)?, block);
        let mut at: u64 = 0;
        for (dims, off) in l.dims.iter_mut().zip(l.offset.iter_mut()) {
            *dims = [r, c];
            *off = u32::try_from(at).ok()?;
            at = at.saturating_add(level_slots(r, c));
            l.count = l.count.saturating_add(1);
            if is_zone_level(r, c) {
                u32::try_from(at).ok()?;
                return Some(l);
            }
            r = half_up(r);
            c = half_up(c);
        }
        None
    }

    pub(super) fn dims(&self, level: usize) -> [u32; 2] {
        self.dims.get(level).copied().unwrap_or([0; 2])
    }

    /// The slot of node `(r, c)` of `level` (2 × 2 groups), `None` outside the level.
    pub(super) fn slot(&self, level: usize, r: u32, c: u32) -> Option<u32> {
        let [nr, nc] = *self.dims.get(level)?;
        if r >= nr || c >= nc {
            return None;
        }
        let group = (r >> 1).checked_mul(half_up(nc))?.checked_add(c >> 1)?;
        let within = ((r & 1) << 1) | (c & 1);
        self.offset
            .get(level)?
            .checked_add(group.checked_mul(4)?)?
            .checked_add(within)
    }

    /// The node of `level` at a slot, or `None` for an empty slot.
    pub(super) fn locate(&self, level: usize, slot: u32) -> Option<(u32, u32)> {
        let [_, nc] = *self.dims.get(level)?;
        let k = slot.checked_sub(*self.offset.get(level)?)?;
        let (group, within) = (k >> 2, k & 3);
        let gc = half_up(nc);
        let r = group
            .checked_div(gc)?
            .checked_mul(2)?
            .checked_add(within >> 1)?;
        let c = group
            .checked_rem(gc)?
            .checked_mul(2)?
            .checked_add(within & 1)?;
        let [nr, nc] = self.dims(level);
        (r < nr && c < nc).then_some((r, c))
    }
}

/// Builds the quadtree of a DEM into `nodes` (module docs): `heights` holds `grid.rows × grid.cols` heights,
/// row-major (`V(i, j)` at `i · cols + j`), NaN for nodata, in any scalar type (`f32` samples under an `f64`
/// tree, say: they are converted exactly); leaves are blocks of `block × block` cells. `nodes`
/// must be at least [`node_slots`]`(grid.rows, grid.cols, block)` long; slots past that are left untouched.
/// Cost: one pass over each leaf's vertices (`(1 + 1/block)²` per height) and one over the records.
pub fn build_tree<T: Real, H: Real, X: BoxSlot>(
    heights: &[H],
    grid: &Grid<T>,
    block: u32,
    nodes: &mut [NodeRecord<H, X>],
) -> Result<Tree, BuildError> {
    build(heights, grid, block, None, nodes)
}

/// Builds the multi-resolution quadtree of a DEM into `nodes` (Wartell et al. §5): the tree of [`build_tree`]
/// (same arguments, same records and ids), whose every node has its own block, a regular sub-grid of the DEM's
/// vertices at `2^k` grid steps, `k` its level above the leaves (the pyramid of §5: coarse blocks subsample the
/// finest data), and whose branches end at level `shape.coarse_level` outside `shape.fine_region`. A storage
/// over it with `AtomicBool` residency flags ([`TreeStorage`](crate::terrain::build::TreeStorage), [`Parts::with_resident`](crate::terrain::build::Parts::with_resident); empty: all resident)
/// reports those strides ([`super::TerrainStorage::block_stride`](crate::terrain::TerrainStorage::block_stride)) and which blocks are in memory.
pub fn build_multires_tree<T: Real, H: Real, X: BoxSlot>(
    heights: &[H],
    grid: &Grid<T>,
    block: u32,
    shape: MultiRes<T>,
    nodes: &mut [NodeRecord<H, X>],
) -> Result<Tree, BuildError> {
    if let Some([s, n, w, e]) = shape.fine_region {
        let finite = [s, n, w, e].iter().all(|v| v.is_finite());
        if !finite || s > n || w > e {
            return Err(BuildError::InvalidShape);
        }
    }
    build(heights, grid, block, Some(shape), nodes)
}

fn build<T: Real, H: Real, X: BoxSlot>(
    heights: &[H],
    grid: &Grid<T>,
    block: u32,
    shape: Option<MultiRes<T>>,
    nodes: &mut [NodeRecord<H, X>],
) -> Result<Tree, BuildError> {
    check_heights(heights, grid)?;
    if block == 0 || !(grid.dlon_deg * T::from_f64(f64::from(block)) < T::from_f64(180.0)) {
        return Err(BuildError::InvalidBlock);
    }
    let levels = Levels::new(grid.rows, grid.cols, block).ok_or(BuildError::InvalidBlock)?;
    let slots = node_slots(grid.rows, grid.cols, block);
    let nodes = nodes.get_mut(..slots).ok_or(BuildError::BufferTooSmall)?;
    let top = levels.count.saturating_sub(1);
    let height = |i: u32, j: u32| -> Option<H> {
        let k = u64::from(i)
            .checked_mul(u64::from(grid.cols))?
            .checked_add(u64::from(j))?;
        let k = usize::try_from(k).ok()?;
        heights.get(k).copied().filter(|h| !h.is_nan())
    };
    let (last_row, last_col) = (grid.cell_rows(), grid.cell_cols());
    for level in 0..levels.count {
        let depth = u8::try_from(top.saturating_sub(level)).unwrap_or(u8::MAX);
        let first = levels.offset.get(level).copied().unwrap_or(0);
        let [nr, nc] = levels.dims(level);
        let len = u32::try_from(level_slots(nr, nc)).map_err(|_| BuildError::InvalidBlock)?;
        for slot in first..first.saturating_add(len) {
            let Some((r, c)) = levels.locate(level, slot) else {
                continue; // an empty slot of a group past the level's last row or column
            };
            let record = if level == 0 {
                let rows = [
                    r.saturating_mul(block),
                    r.saturating_add(1).saturating_mul(block).min(last_row),
                ];
                let cols = [
                    c.saturating_mul(block),
                    c.saturating_add(1).saturating_mul(block).min(last_col),
                ];
                let mut range = [H::INFINITY, H::NEG_INFINITY];
                for i in rows[0]..=rows[1] {
                    for j in cols[0]..=cols[1] {
                        if let Some(h) = height(i, j) {
                            range = [range[0].min(h), range[1].max(h)];
                        }
                    }
                }
                NodeRecord {
                    rows,
                    cols,
                    heights: range,
                    kids: [u32::MAX; 4],
                    level: depth,
                    bbox: X::NONE,
                }
            } else {
                parent_record(&levels, nodes, level, r, c, depth)
            };
            if let Some(out) = usize::try_from(slot).ok().and_then(|k| nodes.get_mut(k)) {
                *out = record;
            }
        }
    }
    if let Some(shape) = shape {
        prune_coarse(&levels, nodes, grid, &shape);
    }
    let zone_dims = levels.dims(top);
    Ok(Tree {
        zone_offset: levels.offset.get(top).copied().unwrap_or(0),
        zone_dims,
        slots: u32::try_from(slots).map_err(|_| BuildError::InvalidBlock)?,
        block,
        top: u8::try_from(top).map_err(|_| BuildError::InvalidBlock)?,
        multires: shape.is_some(),
    })
}

/// Ends the branches of a multi-resolution tree outside the fine region at the coarse level: the nodes at or
/// below it that do not meet the region lose their children. Runs after the whole tree is built, so that a
/// parent that took over the children of its only child (module docs) keeps them, as a coarse node's block
/// does not depend on the level below.
fn prune_coarse<T: Real, H, X>(
    levels: &Levels,
    nodes: &mut [NodeRecord<H, X>],
    grid: &Grid<T>,
    shape: &MultiRes<T>,
) {
    let Some([lat_s, lat_n, lon_w, lon_e]) = shape.fine_region else {
        return; // full depth everywhere
    };
    let coarse = usize::try_from(shape.coarse_level).unwrap_or(usize::MAX);
    for level in 0..levels.count.min(coarse.saturating_add(1)) {
        let first = levels.offset.get(level).copied().unwrap_or(0);
        let [nr, nc] = levels.dims(level);
        let len = u32::try_from(level_slots(nr, nc)).unwrap_or(0);
        for slot in first..first.saturating_add(len) {
            if levels.locate(level, slot).is_none() {
                continue;
            }
            let Some(rec) = usize::try_from(slot).ok().and_then(|k| nodes.get_mut(k)) else {
                continue;
            };
            let (la, lb) = (grid.lat_deg(rec.rows[0]), grid.lat_deg(rec.rows[1]));
            let (wa, wb) = (grid.lon_deg(rec.cols[0]), grid.lon_deg(rec.cols[1]));
            let meets = la.min(lb) <= lat_n && la.max(lb) >= lat_s && wa <= lon_e && wb >= lon_w;
            if !meets {
                rec.kids = [u32::MAX; 4];
            }
        }
    }
}

/// The record of node `(r, c)` of `level ≥ 1`, from its 2 × 2 children's records below it: the union of their
/// ranges and height ranges, and the children with data; a single child (which covers the same cells) is
/// replaced by its own children.
fn parent_record<H: Real, X: BoxSlot>(
    levels: &Levels,
    nodes: &[NodeRecord<H, X>],
    level: usize,
    r: u32,
    c: u32,
    depth: u8,
) -> NodeRecord<H, X> {
    let record = |slot: u32| {
        usize::try_from(slot)
            .ok()
            .and_then(|k| nodes.get(k))
            .copied()
    };
    let below = level.saturating_sub(1);
    let mut kids = [u32::MAX; 4];
    let mut n = 0usize;
    let mut rec = NodeRecord::<H, X> {
        level: depth,
        ..NodeRecord::EMPTY
    };
    let mut ranges: Option<([u32; 2], [u32; 2])> = None;
    for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
        let (cr, cc) = (
            r.saturating_mul(2).saturating_add(a),
            c.saturating_mul(2).saturating_add(b),
        );
        let Some(k) = levels.slot(below, cr, cc) else {
            continue;
        };
        let Some(child) = record(k) else {
            continue;
        };
        ranges = Some(match ranges {
            None => (child.rows, child.cols),
            Some((rows, cols)) => (
                [rows[0].min(child.rows[0]), rows[1].max(child.rows[1])],
                [cols[0].min(child.cols[0]), cols[1].max(child.cols[1])],
            ),
        });
        let [lo, hi] = child.heights;
        rec.heights = [rec.heights[0].min(lo), rec.heights[1].max(hi)];
        if lo <= hi {
            if let Some(slot) = kids.get_mut(n) {
                *slot = k;
                n = n.saturating_add(1);
            }
        }
    }
    let Some((rows, cols)) = ranges else {
        return rec;
    };
    rec.rows = rows;
    rec.cols = cols;
    // A child with the parent's own cells (the only one the level below has here) hands over its children.
    if let [only, u32::MAX, u32::MAX, u32::MAX] = kids {
        if let Some(child) = record(only).filter(|ch| ch.rows == rows && ch.cols == cols) {
            kids = child.kids;
        }
    }
    rec.kids = kids;
    rec
}

/// Checks the grid and the heights ([`check_heights`]), that `tree` was built for the grid, and that a node
/// buffer of `len` records holds its slots.
pub(super) fn check_records<T: Real, H: Real>(
    heights: &[H],
    grid: &Grid<T>,
    tree: &Tree,
    len: usize,
) -> Result<(), BuildError> {
    check_heights(heights, grid)?;
    if node_slots(grid.rows, grid.cols, tree.block) != tree.slots() {
        return Err(BuildError::RecordsMismatch);
    }
    if len < tree.slots() {
        return Err(BuildError::BufferTooSmall);
    }
    Ok(())
}

/// Checks the grid and the heights: `rows × cols` of them, none infinite.
fn check_heights<T: Real, H: Real>(heights: &[H], grid: &Grid<T>) -> Result<(), BuildError> {
    if !grid.validate() {
        return Err(BuildError::InvalidGrid);
    }
    let n = u64::from(grid.rows).saturating_mul(u64::from(grid.cols));
    if u64::try_from(heights.len()).ok() != Some(n) {
        return Err(BuildError::HeightsLength);
    }
    let cols = usize::try_from(grid.cols).map_err(|_| BuildError::HeightsLength)?;
    for (row, chunk) in heights.chunks(cols.max(1)).enumerate() {
        if let Some(j) = chunk.iter().position(|h| !h.is_finite() && !h.is_nan()) {
            let at = |k: usize| u32::try_from(k).unwrap_or(u32::MAX);
            return Err(BuildError::InfiniteHeight([at(row), at(j)]));
        }
    }
    Ok(())
}
