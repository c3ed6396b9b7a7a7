//! What a storage may precompute beyond the node records (Wartell et al. §3.5; Wartell et al. cache the trigonometry
//! of the grid lines, §5 the per-block data of the paged pyramid): the per-row and per-column trigonometry the
//! kernel asks for ([`trig_tables`]; exactly the values the [`TerrainStorage`] docs require) and the per-node
//! boxes in local frames ([`build_boxes`]; beyond the paper, [`super::super::boxes`]), the tables into buffers
//! the caller provides, whose length a `const fn` gives ([`super::row_table_len`], [`super::col_table_len`]),
//! the boxes into the node records that keep them ([`super::BoxSlot`]).

use super::tree::{
    BoxSlot, BuildError, Levels, NodeRecord, Tree, check_records, col_table_len, level_slots,
    row_table_len, window_slots,
};
use crate::dd::Dd;
use crate::geodesy::{Ellipsoid, sin_cos_deg};
use crate::real::Real;
use crate::terrain::boxes::{BoxBuilder, NodeBox, shares_frame_with_children};
use crate::terrain::grid::{Grid, Node, NodeId};
use crate::terrain::parallel::{self, Parallel};
use crate::terrain::storage::{
    TerrainCaches, TerrainStorage, box_frame, node_box_of_vertices, node_frame, vertex_ecef,
};
use crate::terrain::windows::{WindowBox, window_ranges, windows_per_leaf};

/// The per-row and per-column trigonometry of a grid ([`trig_tables`]), borrowed: for every vertex row `i`,
/// [`TerrainCaches::row_sin_cos`] and [`TerrainCaches::row_parallel`]; for every column `j`,
/// [`TerrainCaches::col_sin_cos`] and [`TerrainCaches::col_sin_cos_dd`]. In `f64`, 16 + 64 bytes per row and
/// 16 + 32 per column.
#[derive(Debug)]
pub struct TrigTables<'a, T> {
    /// `sin_cos_deg(grid.lat_deg(i))` per row.
    pub row_sin_cos: &'a [(T, T)],
    /// `sin_cos_deg(grid.lon_deg(j))` per column.
    pub col_sin_cos: &'a [(T, T)],
    /// `row_parallel(&ellipsoid, &grid, i)` per row.
    pub row_parallel: &'a [Parallel<T>],
    /// `col_sin_cos_dd(&grid, j)` per column.
    pub col_sin_cos_dd: &'a [(Dd<T>, Dd<T>)],
}

impl<T> Clone for TrigTables<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for TrigTables<'_, T> {}

impl<T: Real> TrigTables<'_, T> {
    const ZERO: Dd<T> = Dd {
        hi: T::ZERO,
        lo: T::ZERO,
    };
    /// An initial value for the `row_parallel` buffer of [`trig_tables`] (any value will do: it is overwritten).
    pub const UNSET_PARALLEL: Parallel<T> = Parallel {
        n_cos: Self::ZERO,
        nb_sin: Self::ZERO,
        cos: Self::ZERO,
        sin: Self::ZERO,
    };
    /// An initial value for the `col_sin_cos_dd` buffer of [`trig_tables`].
    pub const UNSET_DD: (Dd<T>, Dd<T>) = (Self::ZERO, Self::ZERO);

    /// Whether the tables have one entry per row and per column of `grid`.
    pub fn fits(&self, grid: &Grid<T>) -> bool {
        let (r, c) = (row_table_len(grid.rows), col_table_len(grid.cols));
        self.row_sin_cos.len() == r
            && self.row_parallel.len() == r
            && self.col_sin_cos.len() == c
            && self.col_sin_cos_dd.len() == c
    }
}

/// Fills the trigonometry tables of `grid` on `ellipsoid` (each value computed as the trait's default computes
/// it, in `T`) and returns them borrowed, for [`super::Parts::trig`]. The row buffers must hold
/// [`super::row_table_len`]`(grid.rows)` entries, the column buffers [`super::col_table_len`]`(grid.cols)`
/// ([`BuildError::BufferLength`] otherwise; [`BuildError::InvalidGrid`] for an invalid grid).
pub fn trig_tables<'a, T: Real>(
    ellipsoid: &Ellipsoid<T>,
    grid: &Grid<T>,
    row_sin_cos: &'a mut [(T, T)],
    col_sin_cos: &'a mut [(T, T)],
    row_parallel: &'a mut [Parallel<T>],
    col_sin_cos_dd: &'a mut [(Dd<T>, Dd<T>)],
) -> Result<TrigTables<'a, T>, BuildError> {
    if !grid.validate() {
        return Err(BuildError::InvalidGrid);
    }
    let (r, c) = (row_table_len(grid.rows), col_table_len(grid.cols));
    if row_sin_cos.len() != r
        || row_parallel.len() != r
        || col_sin_cos.len() != c
        || col_sin_cos_dd.len() != c
    {
        return Err(BuildError::BufferLength);
    }
    for ((i, sc), par) in (0..grid.rows)
        .zip(row_sin_cos.iter_mut())
        .zip(row_parallel.iter_mut())
    {
        *sc = sin_cos_deg(grid.lat_deg(i));
        *par = parallel::row_parallel(ellipsoid, grid, i);
    }
    for ((j, sc), dd) in (0..grid.cols)
        .zip(col_sin_cos.iter_mut())
        .zip(col_sin_cos_dd.iter_mut())
    {
        *sc = sin_cos_deg(grid.lon_deg(j));
        *dd = parallel::col_sin_cos_dd(grid, j);
    }
    Ok(TrigTables {
        row_sin_cos,
        col_sin_cos,
        row_parallel,
        col_sin_cos_dd,
    })
}

/// Every node's box ([`super::super::boxes`]) into its record in `nodes` (the buffer [`super::build_tree`] or
/// [`super::build_multires_tree`] filled as `tree`, from `heights` on `grid`), with the host's frame rule: a
/// zone's box in the grid's frame, a child's in the frame of its parent's box where [`shares_frame_with_children`]
/// allows it, else in its parent's own frame. Computed in `f64` as [`TerrainCaches::node_box`] requires (an
/// `f32` grid and ellipsoid are converted exactly; `trig`, the tables of [`trig_tables`], spares the
/// trigonometry of every vertex in `f64`): a leaf's from every vertex of it with data
/// ([`node_box_of_vertices`]); a parent's from its children's boxes, their union where they share its frame,
/// their corners carried over from its own frame otherwise, so that a box contains its children's and thus all
/// of its vertices. Nodes without data, and those no zone reaches (the children a multi-resolution shape cut
/// off), get `None`. Cost: one pass over each leaf's vertices and one over the records.
pub fn build_boxes<T: Real, H: Real>(
    ellipsoid: &Ellipsoid<T>,
    grid: &Grid<T>,
    heights: &[H],
    tree: Tree,
    trig: Option<TrigTables<'_, T>>,
    nodes: &mut [NodeRecord<H, Option<NodeBox>>],
) -> Result<(), BuildError> {
    let g = grid_f64(grid);
    build_boxes_sharing(ellipsoid, grid, heights, tree, trig, nodes, |_, anchor| {
        shares_frame_with_children(&g, anchor)
    })
}

/// [`build_boxes`] with another frame rule: `share(child, anchor)` says whether the box of `child` is in the
/// frame of its parent's box, whose anchor is `anchor` (`None`: the grid), rather than in its parent's own
/// frame. Any rule gives valid boxes; the kernel's tests and fuzz targets mix frames with it.
pub fn build_boxes_sharing<T: Real, H: Real>(
    ellipsoid: &Ellipsoid<T>,
    grid: &Grid<T>,
    heights: &[H],
    tree: Tree,
    trig: Option<TrigTables<'_, T>>,
    nodes: &mut [NodeRecord<H, Option<NodeBox>>],
    share: impl Fn(NodeId, Option<&Node<f64>>) -> bool,
) -> Result<(), BuildError> {
    let (view, levels) = view_of(ellipsoid, grid, heights, tree, trig, nodes.len())?;
    // Children have smaller ids than their parents (levels from the leaves up), so their boxes come first.
    for k in 0..tree.slots() {
        let id = NodeId(u32::try_from(k).map_err(|_| BuildError::BufferLength)?);
        let built = box_of(&view, &levels, nodes, id, &share);
        if let Some(out) = nodes.get_mut(k) {
            out.bbox = built;
        }
    }
    Ok(())
}

/// The window boxes of every full-resolution leaf (beyond the paper; [`crate::terrain::windows`]) into `out`
/// ([`window_slots`] records, [`windows_per_leaf`] per slot of the leaf level): each window's vertices with data
/// bounded in `f64` from [`vertex_ecef`] in the frame of the leaf's box, as the nodes' boxes are
/// ([`build_boxes`], which must have filled `nodes`), and quantized against the leaf's box
/// ([`WindowBox::quantize`]). Slots of leaves without a box, and windows without data, are
/// [`WindowBox::EMPTY`].
pub fn build_windows<T: Real, H: Real>(
    ellipsoid: &Ellipsoid<T>,
    grid: &Grid<T>,
    heights: &[H],
    tree: Tree,
    trig: Option<TrigTables<'_, T>>,
    nodes: &[NodeRecord<H, Option<NodeBox>>],
    out: &mut [WindowBox],
) -> Result<(), BuildError> {
    let (view, levels) = view_of(ellipsoid, grid, heights, tree, trig, nodes.len())?;
    if out.len() != window_slots(grid.rows, grid.cols, tree.block()) {
        return Err(BuildError::BufferLength);
    }
    // The frames the boxes were built in, from the flags `build_boxes` gave them.
    let shared = |kid: NodeId, _: Option<&Node<f64>>| {
        usize::try_from(kid.0)
            .ok()
            .and_then(|k| nodes.get(k))
            .and_then(|r| r.bbox)
            .is_some_and(|b| b.shared_frame)
    };
    let per_leaf = windows_per_leaf(tree.block());
    if per_leaf == 0 {
        return Ok(());
    }
    for (k, windows) in out.chunks_mut(per_leaf.max(1)).enumerate() {
        windows.fill(WindowBox::EMPTY);
        let id = NodeId(u32::try_from(k).map_err(|_| BuildError::BufferLength)?);
        let (Some(leaf), Some(n)) = (
            nodes.get(k).and_then(|r| r.bbox),
            node64(nodes, id).filter(|n| n.heights.is_some() && n.is_leaf()),
        ) else {
            continue;
        };
        let Some((anchor, _)) = frame_of(nodes, &levels, id, &shared) else {
            continue;
        };
        let frame = box_frame(
            &view,
            &view.ellipsoid,
            anchor.and_then(|a| node64(nodes, a)).as_ref(),
        );
        for (w, slot) in windows.iter_mut().enumerate() {
            let Some((rows, cols)) = window_ranges(n.rows, n.cols, w) else {
                break;
            };
            let mut b = BoxBuilder::default();
            for i in rows[0]..=rows[1] {
                for j in cols[0]..=cols[1] {
                    if let Some(p) = vertex_ecef(&view, &view.ellipsoid, i, j) {
                        b.add_point(&frame, p);
                    }
                }
            }
            if let Some(wb) = b.finish() {
                *slot = WindowBox::quantize(&leaf, &wb);
            }
        }
    }
    Ok(())
}

/// The DEM in `f64` and the tree's levels, for building boxes, after checking the buffers' lengths (`nodes`
/// records, and the tables if given).
fn view_of<'a, T: Real, H: Real>(
    ellipsoid: &Ellipsoid<T>,
    grid: &Grid<T>,
    heights: &'a [H],
    tree: Tree,
    trig: Option<TrigTables<'a, T>>,
    nodes: usize,
) -> Result<(View64<'a, T, H>, Levels), BuildError> {
    check_records(heights, grid, &tree, nodes)?;
    if trig.is_some_and(|t| !t.fits(grid)) {
        return Err(BuildError::BufferLength);
    }
    let view = View64 {
        ellipsoid: Ellipsoid::new(ellipsoid.a().to_f64(), ellipsoid.b().to_f64())
            .map_err(|_| BuildError::InvalidGrid)?,
        grid: grid_f64(grid),
        heights,
        trig: trig.filter(|_| T::MANTISSA_DIGITS == 53),
    };
    let levels = Levels::new(grid.rows, grid.cols, tree.block()).ok_or(BuildError::InvalidBlock)?;
    Ok((view, levels))
}

/// Node `id`'s box (see [`build_boxes`]), its children's boxes already in `nodes`.
fn box_of<H: Real>(
    view: &View64<'_, impl Real, H>,
    levels: &Levels,
    nodes: &[NodeRecord<H, Option<NodeBox>>],
    id: NodeId,
    share: &impl Fn(NodeId, Option<&Node<f64>>) -> bool,
) -> Option<NodeBox> {
    let n = node64(nodes, id).filter(|n| n.heights.is_some())?;
    let (anchor, shared) = frame_of(nodes, levels, id, share)?;
    let a = anchor.and_then(|a| node64(nodes, a));
    if n.is_leaf() {
        return node_box_of_vertices(view, &view.ellipsoid, &n, a.as_ref(), shared);
    }
    let frame = box_frame(view, &view.ellipsoid, a.as_ref());
    let own = node_frame(view, &view.ellipsoid, &n);
    let (mut b, mut union) = (BoxBuilder::default(), None::<NodeBox>);
    for cid in n.children.iter().flatten() {
        let child = usize::try_from(cid.0).ok().and_then(|c| nodes.get(c));
        let Some(cb) = child.and_then(|c| c.bbox) else {
            continue;
        };
        if cb.shared_frame {
            union = Some(union.map_or(cb, |u| u.union(&cb)));
        } else {
            for q in cb.corners() {
                b.add_point(&frame, own.point(q));
            }
        }
    }
    match (union, b.finish()) {
        (Some(u), Some(c)) => Some(u.union(&c)),
        (u, c) => u.or(c),
    }
    .map(|b| NodeBox {
        shared_frame: shared,
        ..b
    })
}

/// Node `id` of the records, in `f64`.
fn node64<H: Real, X: BoxSlot>(nodes: &[NodeRecord<H, X>], id: NodeId) -> Option<Node<f64>> {
    nodes.get(usize::try_from(id.0).ok()?).map(NodeRecord::node)
}

/// The frame of node `id`'s box: its anchor (`None`: the grid) and whether it is its parent's box frame, found
/// on the way down from its zone (the children partition their parent's cells, so one contains the node's);
/// `None` if no zone reaches the node. At most one step per level.
fn frame_of<H: Real, X: BoxSlot>(
    nodes: &[NodeRecord<H, X>],
    levels: &Levels,
    id: NodeId,
    share: &impl Fn(NodeId, Option<&Node<f64>>) -> bool,
) -> Option<(Option<NodeId>, bool)> {
    let target = node64(nodes, id)?;
    // The node's level and position, then its zone: the node at the top level above it.
    let level = (0..levels.count).rev().find(|&l| {
        let len = u32::try_from(level_slots_of(levels, l)).unwrap_or(0);
        levels
            .offset
            .get(l)
            .and_then(|&o| id.0.checked_sub(o))
            .is_some_and(|k| k < len)
    })?;
    let (r, c) = levels.locate(level, id.0)?;
    let top = levels.count.checked_sub(1)?;
    let up = u32::try_from(top.checked_sub(level)?).ok()?;
    let mut cur = NodeId(levels.slot(top, r.checked_shr(up)?, c.checked_shr(up)?)?);
    if cur == id {
        return Some((None, false));
    }
    let inside = |n: &Node<f64>| {
        n.rows[0] <= target.rows[0]
            && target.rows[1] <= n.rows[1]
            && n.cols[0] <= target.cols[0]
            && target.cols[1] <= n.cols[1]
    };
    let mut anchor: Option<NodeId> = None;
    for _ in 0..levels.count {
        let node = node64(nodes, cur)?;
        let kid = node
            .children
            .into_iter()
            .flatten()
            .find(|&k| node64(nodes, k).is_some_and(|n| inside(&n)))?;
        let anchor_node = anchor.and_then(|a| node64(nodes, a));
        let shared = share(kid, anchor_node.as_ref());
        if kid == id {
            return Some(if shared {
                (anchor, true)
            } else {
                (Some(cur), false)
            });
        }
        if !shared {
            anchor = Some(cur);
        }
        cur = kid;
    }
    None
}

/// The slots of level `l`.
fn level_slots_of(levels: &Levels, l: usize) -> u64 {
    let [r, c] = levels.dims(l);
    level_slots(r, c)
}

/// A grid in `f64` (exact from `f32`).
fn grid_f64<T: Real>(g: &Grid<T>) -> Grid<f64> {
    Grid {
        lat0_deg: g.lat0_deg.to_f64(),
        lon0_deg: g.lon0_deg.to_f64(),
        dlat_deg: g.dlat_deg.to_f64(),
        dlon_deg: g.dlon_deg.to_f64(),
        rows: g.rows,
        cols: g.cols,
    }
}

/// The DEM in `f64`, for building boxes: heights converted, the trigonometry computed in `f64` (or read from
/// `f64` tables, which hold the same values). Its vertices are all the boxes need; it has no nodes.
struct View64<'a, T, H> {
    ellipsoid: Ellipsoid<f64>,
    grid: Grid<f64>,
    heights: &'a [H],
    trig: Option<TrigTables<'a, T>>,
}

impl<T: Real, H: Real> TerrainStorage<f64> for View64<'_, T, H> {
    fn ellipsoid(&self) -> Ellipsoid<f64> {
        self.ellipsoid
    }
    fn grid(&self) -> Grid<f64> {
        self.grid
    }
    fn zone_count(&self) -> usize {
        0 // never picked
    }
    fn zone(&self, _: usize) -> Option<NodeId> {
        None
    }
    fn node(&self, _: NodeId) -> Option<Node<f64>> {
        None
    }
    fn height(&self, i: u32, j: u32) -> Option<f64> {
        if i >= self.grid.rows || j >= self.grid.cols {
            return None;
        }
        let k = u64::from(i)
            .checked_mul(u64::from(self.grid.cols))?
            .checked_add(u64::from(j))?;
        let h = self.heights.get(usize::try_from(k).ok()?)?.to_f64();
        (!h.is_nan()).then_some(h)
    }
}

impl<T: Real, H: Real> TerrainCaches<f64> for View64<'_, T, H> {
    fn row_sin_cos(&self, i: u32) -> (f64, f64) {
        let cached = self
            .trig
            .and_then(|t| t.row_sin_cos.get(usize::try_from(i).ok()?).copied());
        cached.map_or_else(
            || sin_cos_deg(self.grid.lat_deg(i)),
            |(s, c)| (s.to_f64(), c.to_f64()),
        )
    }
    fn col_sin_cos(&self, j: u32) -> (f64, f64) {
        let cached = self
            .trig
            .and_then(|t| t.col_sin_cos.get(usize::try_from(j).ok()?).copied());
        cached.map_or_else(
            || sin_cos_deg(self.grid.lon_deg(j)),
            |(s, c)| (s.to_f64(), c.to_f64()),
        )
    }
}
