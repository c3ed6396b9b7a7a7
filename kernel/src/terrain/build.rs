//! The `no_std` quadtree builder (seed 000 §3.5, §4): from a DEM's heights, its [`Grid`] and a block size, the
//! node records of a spheroidal height-augmented quadtree, written into a buffer the caller provides, and
//! [`SliceStorage`], the [`TerrainStorage`] over those slices.
//!
//! # The tree
//!
//! Leaves are blocks of `block × block` cells (fewer in the last block row and column); a node one level up
//! covers 2 × 2 nodes of the level below, so every node boundary is a grid line of the DEM (a parallel or a
//! meridian through vertices) and nothing is resampled. Levels are built up to the first one with at most 4
//! rows and 8 columns of nodes: its nodes are the zones (§3.5: at most 8 × 4 = 32, bounded by parallels and
//! meridians, for a global grid or a regional one alike). A node's height range is taken over **every** vertex
//! of its cells, its border rows and columns included (the invariant [`Node`] states), a node without data is
//! left out of its parent's children, and a parent whose only child would cover the same cells takes that
//! child's children instead (the kernel requires children strictly smaller than their parent).
//!
//! # The records
//!
//! A node's id is its slot in the buffer: the levels from the leaves up, each stored by 2 × 2 groups, so that
//! the four children of a node have adjacent records (the traversal reads them one after the other). Slots of
//! a group that fall past a level's last row or column stay empty. [`node_slots`] gives the buffer's length,
//! a `const fn`, so that the buffer can be a static array; [`NodeRecord`] is 56 bytes in `f64` and 44 in `f32`.
//!
//! ```
//! use curvicast::geodesy::Ellipsoid;
//! use curvicast::ray::Ray;
//! use curvicast::terrain::build::{NodeRecord, SliceStorage, build_tree, node_slots};
//! use curvicast::terrain::{Grid, Picker};
//!
//! // A 33 × 33-vertex DEM near (46°N, 8°E) at 3″ spacing: a cone-shaped hill, 900 m at its top.
//! const ROWS: u32 = 33;
//! const COLS: u32 = 33;
//! const BLOCK: u32 = 8;
//! let grid = Grid { lat0_deg: 46.0, lon0_deg: 8.0, dlat_deg: 1.0 / 1200.0, dlon_deg: 1.0 / 1200.0, rows: ROWS, cols: COLS };
//! let mut heights = [0.0_f64; (ROWS * COLS) as usize];
//! for (k, h) in heights.iter_mut().enumerate() {
//!     let (i, j) = ((k as f64 / COLS as f64).floor(), (k % COLS as usize) as f64);
//!     *h = (900.0 - 60.0 * ((i - 16.0).powi(2) + (j - 16.0).powi(2)).sqrt()).max(0.0);
//! }
//! // The node records go into a buffer whose length a const fn gives: no allocator needed.
//! let mut nodes = [NodeRecord::<f64>::EMPTY; node_slots(ROWS, COLS, BLOCK)];
//! let tree = build_tree(&heights, &grid, BLOCK, &mut nodes)?;
//! let storage = SliceStorage::new(Ellipsoid::wgs84(), grid, &heights, &nodes, tree)?;
//! let picker: Picker<'_, f64, SliceStorage<'_, f64>> = Picker::new(&storage)?;
//! // Straight down onto the top of the hill from 2 km above the ellipsoid.
//! let e = Ellipsoid::<f64>::wgs84();
//! let (lat, lon) = (grid.lat_deg(16), grid.lon_deg(16));
//! let down = e.normal_deg(lat, lon).negated();
//! let hit = picker.pick(&Ray::new(e.geodetic_deg_to_ecef(lat, lon, 2000.0), down)?)?.ok_or("no hit")?;
//! assert!((hit.h - 900.0).abs() < 1e-6 && (hit.t - 1100.0).abs() < 1e-6);
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

use super::{Grid, Node, NodeId, TerrainStorage};
use crate::geodesy::Ellipsoid;
use crate::real::Real;

/// Why [`build_tree`] or [`SliceStorage::new`] refused its input.
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
    /// The node records given to [`SliceStorage::new`] are not the ones [`build_tree`] wrote for this grid.
    RecordsMismatch,
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
        }
    }
}

impl core::error::Error for BuildError {}

/// One node as [`build_tree`] stores it: cell ranges, the `[min, max]` of its vertex heights (`min > max`:
/// no data, or an empty slot), child ids (`u32::MAX`: none) and depth below its zone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeRecord<T> {
    /// Cell rows `[rows[0], rows[1])`.
    pub rows: [u32; 2],
    /// Cell columns `[cols[0], cols[1])`.
    pub cols: [u32; 2],
    /// `[min, max]` of the node's vertex heights; `min > max` when it has none.
    pub heights: [T; 2],
    /// Child ids, `u32::MAX` for none.
    pub kids: [u32; 4],
    /// Depth below the node's zone (zones are 0).
    pub level: u8,
}

impl<T: Real> NodeRecord<T> {
    /// An empty slot (the buffer's initial value).
    pub const EMPTY: Self = NodeRecord {
        rows: [0; 2],
        cols: [0; 2],
        heights: [T::INFINITY, T::NEG_INFINITY],
        kids: [u32::MAX; 4],
        level: 0,
    };

    /// The node the kernel's traversal reads ([`TerrainStorage::node`]).
    pub fn node(&self) -> Node<T> {
        let [lo, hi] = self.heights;
        Node {
            rows: self.rows,
            cols: self.cols,
            heights: (lo <= hi).then_some([lo, hi]),
            children: self.kids.map(|k| (k != u32::MAX).then_some(NodeId(k))),
            level: self.level,
        }
    }
}

/// What [`build_tree`] built: where the zones are in the buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tree {
    /// Slot of the zone level's first group.
    zone_offset: u32,
    /// The zone level's node rows and columns.
    zone_dims: [u32; 2],
    /// Slots used (the rest of the buffer is untouched).
    slots: u32,
    /// The block size.
    block: u32,
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
}

/// `⌈n / 2⌉`.
const fn half_up(n: u32) -> u32 {
    (n >> 1).saturating_add(n & 1)
}

/// `⌈n / d⌉` for `d ≥ 1`.
const fn div_up(n: u32, d: u32) -> u32 {
    match (n.checked_div(d), n.checked_rem(d)) {
        (Some(q), Some(r)) => q.saturating_add(if r > 0 { 1 } else { 0 }),
        _ => 0,
    }
}

/// The slots of a level of `r × c` nodes stored by 2 × 2 groups.
const fn level_slots(r: u32, c: u32) -> u64 {
    (half_up(r) as u64)
        .saturating_mul(half_up(c) as u64)
        .saturating_mul(4)
}

/// Whether a level of `r × c` nodes is the zone level (at most 4 rows and 8 columns).
const fn is_zone_level(r: u32, c: u32) -> bool {
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

/// The node levels of a build: per level (0: leaves) its node rows and columns and its first slot.
struct Levels {
    dims: [[u32; 2]; 40],
    offset: [u32; 40],
    count: usize,
}

impl Levels {
    fn new(grid_rows: u32, grid_cols: u32, block: u32) -> Option<Self> {
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

    fn dims(&self, level: usize) -> [u32; 2] {
        self.dims.get(level).copied().unwrap_or([0; 2])
    }

    /// The slot of node `(r, c)` of `level` (2 × 2 groups), `None` outside the level.
    fn slot(&self, level: usize, r: u32, c: u32) -> Option<u32> {
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
    fn locate(&self, level: usize, slot: u32) -> Option<(u32, u32)> {
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
/// row-major (`V(i, j)` at `i · cols + j`), NaN for nodata; leaves are blocks of `block × block` cells. `nodes`
/// must be at least [`node_slots`]`(grid.rows, grid.cols, block)` long; slots past that are left untouched.
/// Cost: one pass over each leaf's vertices (`(1 + 1/block)²` per height) and one over the records.
pub fn build_tree<T: Real>(
    heights: &[T],
    grid: &Grid<T>,
    block: u32,
    nodes: &mut [NodeRecord<T>],
) -> Result<Tree, BuildError> {
    check_heights(heights, grid)?;
    if block == 0 || !(grid.dlon_deg * T::from_f64(f64::from(block)) < T::from_f64(180.0)) {
        return Err(BuildError::InvalidBlock);
    }
    let levels = Levels::new(grid.rows, grid.cols, block).ok_or(BuildError::InvalidBlock)?;
    let slots = node_slots(grid.rows, grid.cols, block);
    let nodes = nodes.get_mut(..slots).ok_or(BuildError::BufferTooSmall)?;
    let top = levels.count.saturating_sub(1);
    let height = |i: u32, j: u32| -> Option<T> {
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
                let mut range = [T::INFINITY, T::NEG_INFINITY];
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
                }
            } else {
                parent_record(&levels, nodes, level, r, c, depth)
            };
            if let Some(out) = usize::try_from(slot).ok().and_then(|k| nodes.get_mut(k)) {
                *out = record;
            }
        }
    }
    let zone_dims = levels.dims(top);
    Ok(Tree {
        zone_offset: levels.offset.get(top).copied().unwrap_or(0),
        zone_dims,
        slots: u32::try_from(slots).map_err(|_| BuildError::InvalidBlock)?,
        block,
    })
}

/// The record of node `(r, c)` of `level ≥ 1`, from its 2 × 2 children's records below it: the union of their
/// ranges and height ranges, and the children with data; a single child (which covers the same cells) is
/// replaced by its own children.
fn parent_record<T: Real>(
    levels: &Levels,
    nodes: &[NodeRecord<T>],
    level: usize,
    r: u32,
    c: u32,
    depth: u8,
) -> NodeRecord<T> {
    let record = |slot: u32| {
        usize::try_from(slot)
            .ok()
            .and_then(|k| nodes.get(k))
            .copied()
    };
    let below = level.saturating_sub(1);
    let mut kids = [u32::MAX; 4];
    let mut n = 0usize;
    let mut rec = NodeRecord::<T> {
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

/// Checks the grid and the heights: `rows × cols` of them, none infinite.
fn check_heights<T: Real>(heights: &[T], grid: &Grid<T>) -> Result<(), BuildError> {
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

/// The [`TerrainStorage`] over a DEM's heights and the node records [`build_tree`] wrote: everything borrowed,
/// nothing allocated. Its trigonometry is the trait's default (computed when the kernel asks).
#[derive(Debug, Clone, Copy)]
pub struct SliceStorage<'a, T> {
    ellipsoid: Ellipsoid<T>,
    grid: Grid<T>,
    heights: &'a [T],
    nodes: &'a [NodeRecord<T>],
    tree: Tree,
}

impl<'a, T: Real> SliceStorage<'a, T> {
    /// The storage over `heights` (as given to [`build_tree`]) and `nodes` (its buffer, as it wrote it), on
    /// `ellipsoid`. Checks the grid and heights again and that the buffer holds the tree's slots.
    pub fn new(
        ellipsoid: Ellipsoid<T>,
        grid: Grid<T>,
        heights: &'a [T],
        nodes: &'a [NodeRecord<T>],
        tree: Tree,
    ) -> Result<Self, BuildError> {
        check_heights(heights, &grid)?;
        if node_slots(grid.rows, grid.cols, tree.block) != tree.slots() {
            return Err(BuildError::RecordsMismatch);
        }
        let nodes = nodes
            .get(..tree.slots())
            .ok_or(BuildError::BufferTooSmall)?;
        Ok(SliceStorage {
            ellipsoid,
            grid,
            heights,
            nodes,
            tree,
        })
    }

    /// The tree's node records.
    pub fn records(&self) -> &'a [NodeRecord<T>] {
        self.nodes
    }
}

impl<T: Real> TerrainStorage<T> for SliceStorage<'_, T> {
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
    fn node(&self, id: NodeId) -> Option<Node<T>> {
        let rec = self.nodes.get(usize::try_from(id.0).ok()?)?;
        Some(rec.node())
    }
    fn height(&self, i: u32, j: u32) -> Option<T> {
        if i >= self.grid.rows || j >= self.grid.cols {
            return None;
        }
        let k = u64::from(i)
            .checked_mul(u64::from(self.grid.cols))?
            .checked_add(u64::from(j))?;
        let h = *self.heights.get(usize::try_from(k).ok()?)?;
        (!h.is_nan()).then_some(h)
    }
}
