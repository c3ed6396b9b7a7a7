//! The host's terrain storage for the kernel: [`DemStorage`], a thin owner of vectors around the kernel's
//! storage ([`curvicast::terrain::build::TreeStorage`]) over a [`Dem`]: the node records of the kernel's
//! builder with their boxes, the leaves' window boxes, the per-row and per-column trigonometry tables and, for a multi-resolution tree,
//! the residency flags (single- and multi-resolution, with paging for the multi-resolution experiments). It sits
//! beside the scenes and the oracle, not in either: it uses both (the scenes' DEM model; the multi-resolution
//! oracle's tree description for [`DemStorage::tree`]).

use crate::formats::terrain::Dem;
use curvicast::dd::Dd;
use curvicast::geodesy::Ellipsoid;
use curvicast::terrain::boxes::NodeBox;
use curvicast::terrain::build::{
    self, Buffers, NodeRecord, Parts, TreeStorage, TrigTables, node_slots,
};
use curvicast::terrain::windows::WindowBox;
use curvicast::terrain::{Grid, Node, NodeId, Parallel, TerrainCaches, TerrainStorage};
use std::sync::atomic::{AtomicBool, Ordering};

/// A node record of a [`DemStorage`]: height range in `f32` (the samples' type) and the node's box, 72 bytes.
type Record = NodeRecord<f32, Option<NodeBox>>;

/// The vectors behind a [`DemStorage`], lent to the kernel's storage as [`Parts`].
#[derive(Debug)]
struct DemBuffers<'a> {
    heights: &'a [f32],
    nodes: Vec<Record>,
    row_sin_cos: Vec<(f64, f64)>,
    col_sin_cos: Vec<(f64, f64)>,
    row_parallel: Vec<Parallel<f64>>,
    col_sin_cos_dd: Vec<(Dd<f64>, Dd<f64>)>,
    resident: Vec<AtomicBool>,
    windows: Vec<WindowBox>,
}

impl DemBuffers<'_> {
    fn trig(&self) -> TrigTables<'_, f64> {
        TrigTables {
            row_sin_cos: &self.row_sin_cos,
            col_sin_cos: &self.col_sin_cos,
            row_parallel: &self.row_parallel,
            col_sin_cos_dd: &self.col_sin_cos_dd,
        }
    }
}

impl Buffers<f64> for DemBuffers<'_> {
    type Height = f32;
    type Box = Option<NodeBox>;
    type Flag = AtomicBool;
    #[inline]
    fn parts(&self) -> Parts<'_, f64, f32, Option<NodeBox>, AtomicBool> {
        Parts {
            heights: self.heights,
            nodes: &self.nodes,
            trig: Some(self.trig()),
            resident: &self.resident,
            windows: &self.windows,
        }
    }
}

/// The host's terrain storage for the kernel (Wartell et al. §3.5, §4, §5): a [`Dem`] and the vectors the kernel's
/// builder fills ([`curvicast::terrain::build`]: the quadtree's node records with their boxes (shared-frame
/// rule), the trigonometry tables, residency flags), behind the kernel's own
/// [`curvicast::terrain::build::TreeStorage`]. The tree is the builder's: leaves of `block × block` cells,
/// zones at the first level of at most 4 × 8 nodes, ids by 2 × 2 groups from the leaves up.
#[derive(Debug)]
pub struct DemStorage<'a> {
    dem: &'a Dem,
    grid: Grid<f64>,
    ellipsoid: Ellipsoid<f64>,
    /// The kernel's storage; if the builder refused the DEM (an invalid grid), one over a 2 × 2 grid without
    /// data, so that the picker over this storage reports the DEM's grid's error ([`DemStorage::grid`] is the
    /// DEM's) and nothing else changes.
    storage: TreeStorage<f64, DemBuffers<'a>>,
    /// Why the builder refused the DEM, if it did.
    refused: Option<build::BuildError>,
}

/// How [`DemStorage::multi_resolution`] shapes a multi-resolution tree (Wartell et al. §5, Fig. 11): every node has a
/// block of `block × block` cells that subsamples the DEM at `2^k` grid steps (`k` its pyramid level, 0 at the
/// full-resolution leaves), and branches stop at pyramid level `coarse_level` outside `fine_region`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MultiRes {
    /// `[lat_s, lat_n, lon_w, lon_e]` (degrees): nodes that meet this box go down to full resolution. `None`:
    /// everywhere.
    pub fine_region: Option<[f64; 4]>,
    /// The pyramid level at which branches outside `fine_region` end (0: full depth everywhere).
    pub coarse_level: usize,
}

impl<'a> DemStorage<'a> {
    /// Builds the storage over `dem` with leaf blocks of `block × block` cells (the contract's `--block`, default
    /// 16; values below 1 are taken as 1). On very coarse grids the block is reduced so that a leaf spans less
    /// than 180° of longitude (the kernel's meridian walls bound wedges narrower than a half-turn).
    pub fn new(dem: &'a Dem, block: usize) -> DemStorage<'a> {
        Self::build(dem, block, None)
    }

    /// The multi-resolution storage over `dem` (module docs of [`curvicast::terrain`], "Multi-resolution"):
    /// every node has its own block subsampled at `2^k` grid steps, all resident until marked otherwise
    /// ([`DemStorage::set_resident`]), and the tree is shaped by `shape`.
    pub fn multi_resolution(dem: &'a Dem, block: usize, shape: MultiRes) -> DemStorage<'a> {
        Self::build(dem, block, Some(shape))
    }

    fn build(dem: &'a Dem, block: usize, multires: Option<MultiRes>) -> DemStorage<'a> {
        let max_block = ((180.0 / dem.dlon).ceil() as usize)
            .saturating_sub(1)
            .max(1);
        let block = u32::try_from(block.clamp(1, max_block)).unwrap_or(u32::MAX);
        let grid = Grid {
            lat0_deg: dem.lat0,
            lon0_deg: dem.lon0,
            dlat_deg: dem.dlat,
            dlon_deg: dem.dlon,
            rows: dem.rows as u32,
            cols: dem.cols as u32,
        };
        let e = Ellipsoid::new(dem.a, dem.b).unwrap_or_else(|_| Ellipsoid::wgs84());
        let (storage, refused) = match Self::build_storage(&dem.heights, &grid, &e, block, multires)
        {
            Ok(s) => (s, None),
            Err(why) => {
                static NODATA: [f32; 4] = [f32::NAN; 4];
                let g = Grid {
                    lat0_deg: 0.0,
                    lon0_deg: 0.0,
                    dlat_deg: 1.0,
                    dlon_deg: 1.0,
                    rows: 2,
                    cols: 2,
                };
                let s = Self::build_storage(&NODATA, &g, &e, 1, None)
                    .expect("a 2 × 2 grid without data builds");
                (s, Some(why))
            }
        };
        DemStorage {
            dem,
            grid,
            ellipsoid: e,
            storage,
            refused,
        }
    }

    /// Why the builder refused the DEM (its grid is invalid: the picker says why), `None` if it did not.
    pub fn refused(&self) -> Option<build::BuildError> {
        self.refused
    }

    /// The builder's tree, tables and boxes in vectors (module docs).
    fn build_storage(
        heights: &'a [f32],
        grid: &Grid<f64>,
        e: &Ellipsoid<f64>,
        block: u32,
        multires: Option<MultiRes>,
    ) -> Result<TreeStorage<f64, DemBuffers<'a>>, build::BuildError> {
        let slots = node_slots(grid.rows, grid.cols, block);
        let mut nodes = vec![NodeRecord::EMPTY; slots];
        let tree = match multires {
            None => build::build_tree(heights, grid, block, &mut nodes),
            Some(m) => build::build_multires_tree(
                heights,
                grid,
                block,
                build::MultiRes {
                    fine_region: m.fine_region,
                    coarse_level: u32::try_from(m.coarse_level).unwrap_or(u32::MAX),
                },
                &mut nodes,
            ),
        }?;
        let (rows, cols) = (
            build::row_table_len(grid.rows),
            build::col_table_len(grid.cols),
        );
        let mut b = DemBuffers {
            heights,
            nodes,
            row_sin_cos: vec![(0.0, 0.0); rows],
            col_sin_cos: vec![(0.0, 0.0); cols],
            row_parallel: vec![TrigTables::<f64>::UNSET_PARALLEL; rows],
            col_sin_cos_dd: vec![TrigTables::<f64>::UNSET_DD; cols],
            resident: Vec::new(),
            windows: vec![WindowBox::EMPTY; build::window_slots(grid.rows, grid.cols, block)],
        };
        build::trig_tables(
            e,
            grid,
            &mut b.row_sin_cos,
            &mut b.col_sin_cos,
            &mut b.row_parallel,
            &mut b.col_sin_cos_dd,
        )?;
        let trig = TrigTables {
            row_sin_cos: &b.row_sin_cos,
            col_sin_cos: &b.col_sin_cos,
            row_parallel: &b.row_parallel,
            col_sin_cos_dd: &b.col_sin_cos_dd,
        };
        build::build_boxes(e, grid, heights, tree, Some(trig), &mut b.nodes)?;
        build::build_windows(e, grid, heights, tree, Some(trig), &b.nodes, &mut b.windows)?;
        if multires.is_some() {
            b.resident = (0..slots).map(|_| AtomicBool::new(true)).collect();
        }
        TreeStorage::with_buffers(*e, *grid, tree, b)
    }

    /// The DEM.
    pub fn dem(&self) -> &Dem {
        self.dem
    }

    /// The kernel's storage, `None` if the builder refused the DEM.
    fn kernel(&self) -> Option<&TreeStorage<f64, DemBuffers<'a>>> {
        self.refused.is_none().then_some(&self.storage)
    }

    /// Marks node `id`'s block resident or not (multi-resolution mode; a single-resolution storage keeps every
    /// block resident and ignores this).
    pub fn set_resident(&self, id: NodeId, resident: bool) {
        let flags = self.kernel().map_or(&[][..], |s| &s.buffers().resident[..]);
        if let Some(flag) = flags.get(id.0 as usize) {
            flag.store(resident, Ordering::Relaxed);
        }
    }

    /// The tree as plain data (for choosing residency, and for the harness's multi-resolution oracle): every
    /// node with data reachable from the zones, with its parent, level, ranges, stride and residency, in id order.
    pub fn tree(&self) -> Vec<TreeNode> {
        let mut out = Vec::new();
        let Some(s) = self.kernel() else {
            return Vec::new();
        };
        let mut stack: Vec<(NodeId, Option<u32>)> = (0..s.zone_count())
            .filter_map(|k| s.zone(k))
            .map(|z| (z, None))
            .collect();
        while let Some((id, parent)) = stack.pop() {
            let Some(n) = s.node(id).filter(|n| n.heights.is_some()) else {
                continue;
            };
            out.push(TreeNode {
                id: id.0,
                parent,
                level: n.level,
                rows: n.rows,
                cols: n.cols,
                leaf: n.is_leaf(),
                stride: s.block_stride(id),
                resident: s.is_resident(id),
            });
            stack.extend(n.children.iter().flatten().map(|&c| (c, Some(id.0))));
        }
        out.sort_by_key(|x| x.id);
        out
    }

    /// Cells per leaf-block side.
    pub fn block(&self) -> usize {
        self.kernel().map_or(1, |s| s.tree().block() as usize)
    }

    /// Number of node records: the id slots of all levels from the leaves up to the zones (levels are stored by
    /// 2 × 2 groups, so a few slots past odd last rows and columns hold no node).
    pub fn node_count(&self) -> usize {
        self.kernel().map_or(0, |s| s.tree().slots())
    }

    /// The depth of the tree: the level of the leaves below the zones (zones are level 0).
    pub fn depth(&self) -> u32 {
        self.kernel().map_or(0, |s| s.tree().depth())
    }

    /// The memory the tree adds to the heights, in bytes: one record (with its box) per node slot, the residency
    /// flags, the leaves' window boxes, and the per-row / per-column trigonometry tables.
    pub fn overhead_bytes(&self) -> usize {
        let Some(b) = self.kernel().map(TreeStorage::buffers) else {
            return 0;
        };
        b.nodes.len() * std::mem::size_of::<Record>()
            + b.resident.len() * std::mem::size_of::<AtomicBool>()
            + b.windows.len() * std::mem::size_of::<WindowBox>()
            + (b.row_sin_cos.len() + b.col_sin_cos.len()) * std::mem::size_of::<(f64, f64)>()
            + b.row_parallel.len() * std::mem::size_of::<Parallel<f64>>()
            + b.col_sin_cos_dd.len() * std::mem::size_of::<(Dd<f64>, Dd<f64>)>()
    }

    /// The memory of the heights themselves (`f32` per vertex), for comparison.
    pub fn heights_bytes(&self) -> usize {
        self.dem.heights.len() * std::mem::size_of::<f32>()
    }
}

impl TerrainStorage<f64> for DemStorage<'_> {
    fn ellipsoid(&self) -> Ellipsoid<f64> {
        self.ellipsoid
    }
    fn grid(&self) -> Grid<f64> {
        self.grid
    }
    fn zone_count(&self) -> usize {
        self.storage.zone_count()
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        self.storage.zone(k)
    }
    #[inline]
    fn node(&self, id: NodeId) -> Option<Node<f64>> {
        self.storage.node(id)
    }
    #[inline]
    fn height(&self, i: u32, j: u32) -> Option<f64> {
        self.storage.height(i, j)
    }
    #[inline]
    fn is_resident(&self, id: NodeId) -> bool {
        self.storage.is_resident(id)
    }
    #[inline]
    fn block_stride(&self, id: NodeId) -> u32 {
        self.storage.block_stride(id)
    }
}

impl TerrainCaches<f64> for DemStorage<'_> {
    #[inline]
    fn window_boxes(&self, id: NodeId) -> &[WindowBox] {
        self.storage.window_boxes(id)
    }
    #[inline]
    fn row_sin_cos(&self, i: u32) -> (f64, f64) {
        self.storage.row_sin_cos(i)
    }
    #[inline]
    fn col_sin_cos(&self, j: u32) -> (f64, f64) {
        self.storage.col_sin_cos(j)
    }
    fn row_parallel(&self, i: u32) -> Parallel<f64> {
        self.storage.row_parallel(i)
    }
    fn col_sin_cos_dd(&self, j: u32) -> (Dd<f64>, Dd<f64>) {
        self.storage.col_sin_cos_dd(j)
    }
    #[inline]
    fn node_box(&self, id: NodeId) -> Option<NodeBox> {
        self.storage.node_box(id)
    }
}

/// The kernel's storage is `f64`; an `f32` picker (the box tests check `f32` rays) reads the same records
/// (their heights are `f32`), boxes and heights and computes its own trigonometry (the kernel requires exactly
/// `sin_cos_deg` in `f32`), as the trait's defaults do.
impl TerrainStorage<f32> for DemStorage<'_> {
    fn ellipsoid(&self) -> Ellipsoid<f32> {
        let e = self.ellipsoid;
        Ellipsoid::new(e.a() as f32, e.b() as f32).unwrap_or_else(|_| Ellipsoid::wgs84())
    }
    fn grid(&self) -> Grid<f32> {
        let g = self.grid;
        Grid {
            lat0_deg: g.lat0_deg as f32,
            lon0_deg: g.lon0_deg as f32,
            dlat_deg: g.dlat_deg as f32,
            dlon_deg: g.dlon_deg as f32,
            rows: g.rows,
            cols: g.cols,
        }
    }
    fn zone_count(&self) -> usize {
        self.storage.zone_count()
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        self.storage.zone(k)
    }
    fn node(&self, id: NodeId) -> Option<Node<f32>> {
        self.storage.record(id).map(NodeRecord::node)
    }
    fn height(&self, i: u32, j: u32) -> Option<f32> {
        self.storage.height(i, j).map(|h| h as f32)
    }
    fn is_resident(&self, id: NodeId) -> bool {
        self.storage.is_resident(id)
    }
    fn block_stride(&self, id: NodeId) -> u32 {
        self.storage.block_stride(id)
    }
}

impl TerrainCaches<f32> for DemStorage<'_> {
    fn node_box(&self, id: NodeId) -> Option<NodeBox> {
        self.storage.node_box(id)
    }
    fn window_boxes(&self, id: NodeId) -> &[WindowBox] {
        self.storage.window_boxes(id)
    }
}

/// A storage whose blocks are the base's plus those paged in while answering one ray ([`pick_paging_in`]).
pub struct Paged<'b, 'd> {
    base: &'b DemStorage<'d>,
    paged: std::cell::RefCell<Vec<curvicast::terrain::NodeId>>,
}

impl TerrainStorage<f64> for Paged<'_, '_> {
    fn ellipsoid(&self) -> Ellipsoid<f64> {
        self.base.ellipsoid()
    }
    fn grid(&self) -> Grid<f64> {
        self.base.grid()
    }
    fn zone_count(&self) -> usize {
        TerrainStorage::<f64>::zone_count(self.base)
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        TerrainStorage::<f64>::zone(self.base, k)
    }
    fn node(&self, id: NodeId) -> Option<Node<f64>> {
        self.base.node(id)
    }
    fn height(&self, i: u32, j: u32) -> Option<f64> {
        self.base.height(i, j)
    }
    fn is_resident(&self, id: NodeId) -> bool {
        TerrainStorage::<f64>::is_resident(self.base, id) || self.paged.borrow().contains(&id)
    }
    fn block_stride(&self, id: NodeId) -> u32 {
        TerrainStorage::<f64>::block_stride(self.base, id)
    }
}

impl TerrainCaches<f64> for Paged<'_, '_> {
    fn row_sin_cos(&self, i: u32) -> (f64, f64) {
        self.base.row_sin_cos(i)
    }
    fn col_sin_cos(&self, j: u32) -> (f64, f64) {
        self.base.col_sin_cos(j)
    }
    fn node_box(&self, id: NodeId) -> Option<NodeBox> {
        TerrainCaches::<f64>::node_box(self.base, id)
    }
    fn window_boxes(&self, id: NodeId) -> &[WindowBox] {
        TerrainCaches::<f64>::window_boxes(self.base, id)
    }
    fn row_parallel(&self, i: u32) -> Parallel<f64> {
        self.base.row_parallel(i)
    }
    fn col_sin_cos_dd(&self, j: u32) -> (Dd<f64>, Dd<f64>) {
        self.base.col_sin_cos_dd(j)
    }
}

/// Picks `ray` as a caller of a paging storage does (Wartell et al. §5): on `NeedsBlock` the node's block is paged in
/// (for this ray only: a [`Paged`] overlay of `storage`) and the ray asked again, until it is answered. Returns
/// the answer and the number of blocks paged in.
pub fn pick_paging_in(
    picker: &curvicast::terrain::Picker<'_, f64, DemStorage<'_>>,
    storage: &DemStorage<'_>,
    ray: &curvicast::Ray<f64>,
) -> Result<(Option<curvicast::terrain::Hit<f64>>, usize), curvicast::terrain::TerrainError> {
    use curvicast::terrain::{Picker, TerrainError};
    let first = match picker.pick(ray) {
        Err(TerrainError::NeedsBlock(id)) => id,
        other => return other.map(|h| (h, 0)),
    };
    let paged = Paged {
        base: storage,
        paged: std::cell::RefCell::new(vec![first]),
    };
    let p = Picker::<f64, Paged<'_, '_>>::new(&paged)?.with_min_level(picker.min_level());
    // Every retry pages in one more node, so this ends within the tree's size.
    for _ in 0..=storage.node_count() {
        match p.pick(ray) {
            Err(TerrainError::NeedsBlock(id)) => paged.paged.borrow_mut().push(id),
            other => return other.map(|h| (h, paged.paged.borrow().len())),
        }
    }
    Err(TerrainError::TraversalBound)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn storage_tree_is_well_formed_and_covers_every_triangle_once() {
        let (rows, cols) = (45, 70);
        let mut h: Vec<f32> = (0..rows * cols)
            .map(|k| ((k * 7919) % 1000) as f32 - 300.0)
            .collect();
        for k in (0..rows * cols).step_by(97) {
            h[k] = f32::NAN;
        }
        for k in 0..cols * 5 {
            h[10 * cols + k] = f32::NAN; // rows 10..15 missing entirely
        }
        let d = Dem::wgs84((60.0, 170.0, 0.3, 0.4), (rows, cols), h).unwrap();
        for block in [1, 3, 4, 16, 64] {
            let s = DemStorage::new(&d, block);
            let mut covered = vec![0u32; (rows - 1) * (cols - 1)];
            let mut stack: Vec<curvicast::terrain::NodeId> = (0
                ..TerrainStorage::<f64>::zone_count(&s))
                .map(|k| TerrainStorage::<f64>::zone(&s, k).unwrap())
                .collect();
            assert!(stack.len() <= 32);
            let mut seen = 0;
            while let Some(id) = stack.pop() {
                seen += 1;
                let n: curvicast::terrain::Node<f64> = s.node(id).unwrap();
                let mut lo = f64::INFINITY;
                let mut hi = f64::NEG_INFINITY;
                for i in n.rows[0]..=n.rows[1] {
                    for j in n.cols[0]..=n.cols[1] {
                        if let Some(v) = d.height(i as usize, j as usize) {
                            lo = lo.min(f64::from(v));
                            hi = hi.max(f64::from(v));
                        }
                    }
                }
                assert_eq!(
                    n.heights,
                    (hi >= lo).then_some([lo, hi]),
                    "block {block} node {n:?}"
                );
                if n.is_leaf() {
                    for i in n.rows[0]..n.rows[1] {
                        for j in n.cols[0]..n.cols[1] {
                            covered[i as usize * (cols - 1) + j as usize] += 1;
                        }
                    }
                }
                for c in n.children.iter().flatten() {
                    let k: curvicast::terrain::Node<f64> = s.node(*c).unwrap();
                    assert!(k.rows[0] >= n.rows[0] && k.rows[1] <= n.rows[1]);
                    assert!(k.cols[0] >= n.cols[0] && k.cols[1] <= n.cols[1]);
                    assert!((k.rows, k.cols) != (n.rows, n.cols), "child equals parent");
                    assert!(k.level > n.level);
                    stack.push(*c);
                }
            }
            assert!(seen <= s.node_count());
            for i in 0..rows - 1 {
                for j in 0..cols - 1 {
                    let has = d.triangle(i, j, 0).is_some() || d.triangle(i, j, 1).is_some();
                    let c = covered[i * (cols - 1) + j];
                    assert!(
                        c <= 1 && (!has || c == 1),
                        "block {block} cell ({i}, {j}): {c}"
                    );
                }
            }
            if block >= 16 {
                assert!(s.overhead_bytes() < s.heights_bytes());
            }
        }
    }
}

/// One node of a multi-resolution tree, as plain data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TreeNode {
    /// Its id.
    pub id: u32,
    /// Its parent's id (`None` for a zone).
    pub parent: Option<u32>,
    /// Its level (zones are 0).
    pub level: u8,
    /// Cell rows `[r0, r1)`.
    pub rows: [u32; 2],
    /// Cell columns `[c0, c1)`.
    pub cols: [u32; 2],
    /// Whether it has no children.
    pub leaf: bool,
    /// Its block's sample spacing in grid steps.
    pub stride: u32,
    /// Whether its block is resident.
    pub resident: bool,
}
