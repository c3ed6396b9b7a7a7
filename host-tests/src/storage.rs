//! The host's terrain storage for the kernel: [`DemStorage`], a [`Dem`] plus its max-height [`HeightPyramid`]
//! and its quadtree's node records, behind [`curvicast::terrain::TerrainStorage`] (single- and multi-resolution,
//! with paging for the multi-resolution experiments). It sits beside the scenes and the oracle, not in either:
//! it uses both (the scenes' DEM model; the multi-resolution oracle's tree description for
//! [`DemStorage::tree`]).

use crate::scenes::terrain::Dem;

/// The max-height pyramid of a DEM: for blocks of `block × block` cells, and for every coarser level (2 × 2
/// blocks of the level below), the maximum and minimum vertex height of the cells it covers — the "max height"
/// of seed 000 §3.1 that bounds a height-quad from above (and the minimum that bounds it from below).
///
/// Built in one linear pass over the heights (every vertex updates the at most four blocks whose cells it
/// touches), then a reduction over the blocks (a geometric series, O(rows·cols/block²)). The quads are aligned to
/// the DEM's own grid: block (bi, bj) covers cell rows `bi·block .. min((bi+1)·block, rows−1)` and the same for
/// columns; nothing is resampled. A node whose cells have no present vertex stores `max = −∞, min = +∞` (empty).
#[derive(Debug, Clone, PartialEq)]
pub struct HeightPyramid {
    /// Cells per block side.
    pub block: usize,
    /// Per level (0 = blocks), the node grid's (rows, cols).
    pub dims: Vec<(usize, usize)>,
    /// Per level, the maximum vertex height of each node, row-major.
    pub max: Vec<Vec<f32>>,
    /// Per level, the minimum vertex height of each node, row-major.
    pub min: Vec<Vec<f32>>,
}

impl HeightPyramid {
    /// Builds the pyramid over `dem` with blocks of `block × block` cells (`block ≥ 1`).
    pub fn build(dem: &Dem, block: usize) -> HeightPyramid {
        let block = block.max(1);
        let cr = dem.rows - 1;
        let cc = dem.cols - 1;
        let br = cr.div_ceil(block);
        let bc = cc.div_ceil(block);
        let mut max = vec![f32::NEG_INFINITY; br * bc];
        let mut min = vec![f32::INFINITY; br * bc];
        for i in 0..dem.rows {
            // Block rows whose cells use vertex row i: the block of cell row i, and of cell row i - 1.
            let bi_hi = (i.min(cr - 1)) / block;
            let bi_lo = (i.saturating_sub(1)) / block;
            let row = &dem.heights[i * dem.cols..(i + 1) * dem.cols];
            for (j, &h) in row.iter().enumerate() {
                if h.is_nan() {
                    continue;
                }
                let bj_hi = (j.min(cc - 1)) / block;
                let bj_lo = (j.saturating_sub(1)) / block;
                for bi in bi_lo..=bi_hi {
                    for bj in bj_lo..=bj_hi {
                        let k = bi * bc + bj;
                        if h > max[k] {
                            max[k] = h;
                        }
                        if h < min[k] {
                            min[k] = h;
                        }
                    }
                }
            }
        }
        let mut dims = vec![(br, bc)];
        let mut maxs = vec![max];
        let mut mins = vec![min];
        while let Some(&(r, c)) = dims.last() {
            if r <= 1 && c <= 1 {
                break;
            }
            let (pr, pc) = (r.div_ceil(2), c.div_ceil(2));
            let (lmax, lmin) = (&maxs[maxs.len() - 1], &mins[mins.len() - 1]);
            let mut nmax = vec![f32::NEG_INFINITY; pr * pc];
            let mut nmin = vec![f32::INFINITY; pr * pc];
            for i in 0..r {
                for j in 0..c {
                    let k = (i / 2) * pc + j / 2;
                    nmax[k] = nmax[k].max(lmax[i * c + j]);
                    nmin[k] = nmin[k].min(lmin[i * c + j]);
                }
            }
            dims.push((pr, pc));
            maxs.push(nmax);
            mins.push(nmin);
        }
        HeightPyramid {
            block,
            dims,
            max: maxs,
            min: mins,
        }
    }

    /// The bytes the pyramid adds on top of the heights themselves (its max and min arrays).
    pub fn overhead_bytes(&self) -> usize {
        self.max
            .iter()
            .chain(self.min.iter())
            .map(|v| v.len() * std::mem::size_of::<f32>())
            .sum()
    }
}

/// The id slots of a pyramid level of `nr × nc` nodes stored by 2 × 2 groups ([`DemStorage`]'s ids).
fn level_len(nr: usize, nc: usize) -> usize {
    4 * nr.div_ceil(2) * nc.div_ceil(2)
}

/// The host's terrain storage for the kernel (seed 000 §3.5, §4): a [`Dem`] plus its [`HeightPyramid`], exposed
/// through [`curvicast::terrain::TerrainStorage`].
///
/// * Leaves are the pyramid's level-0 blocks of `block × block` cells (the last row/column of blocks may be
///   smaller); a quad at pyramid level k covers 2^k × 2^k blocks, so every quad boundary is a grid line of the DEM
///   (a meridian or a parallel through vertices): nothing is resampled and the kernel traces exactly the
///   contract's triangles. Cells outside the DEM do not exist; nodes with no present vertex are left out of their
///   parent's children.
/// * Zones (the roots, §3.5) are the nodes of the lowest pyramid level that has at most 4 rows and 8 columns of
///   nodes — at most 8 × 4 = 32 zones bounded by parallels and meridians of the grid, whether the DEM is global
///   (ETOPO20: 3 × 5 zones) or regional (Trinidad: 3 × 5 zones of its own extent).
/// * A node id is the node's slot in the pyramid's levels (concatenated from the leaves up; within a level by
///   2 × 2 groups, so that siblings are adjacent). Each node keeps one record formed at
///   build time — cell ranges, height range, child ids, level, and the node's box ([`curvicast::terrain::boxes`],
///   built bottom-up) — from which the kernel's
///   [`curvicast::terrain::Node`] is copied when asked for ([`DemStorage::overhead_bytes`] counts them). A parent
///   whose only child covers the same cells is skipped (the kernel requires children strictly smaller than their
///   parent).
#[derive(Debug)]
pub struct DemStorage<'a> {
    dem: &'a Dem,
    pyramid: HeightPyramid,
    offsets: Vec<usize>,
    zone_level: usize,
    zones: Vec<curvicast::terrain::NodeId>,
    /// `sin_cos_deg(lat_deg(i))` per vertex row and `sin_cos_deg(lon_deg(j))` per column, in `f64`: the
    /// kernel's `row_sin_cos` / `col_sin_cos` cache (16 bytes per row and per column).
    row_trig: Vec<(f64, f64)>,
    col_trig: Vec<(f64, f64)>,
    /// The kernel's `row_parallel` / `col_sin_cos_dd` per row and column, in `f64` pairs (for the refinement of
    /// the nearest hit: 64 bytes per row, 32 per column).
    row_dd: Vec<curvicast::terrain::Parallel<f64>>,
    col_dd: Vec<(curvicast::dd::Dd<f64>, curvicast::dd::Dd<f64>)>,
    /// Every node as the kernel asks for it, by id, formed once at build time (the kernel asks for a node at
    /// every quad it visits).
    records: Vec<NodeRecord>,
    /// Multi-resolution mode: node blocks subsample the DEM at `2^(pyramid level)` and are paged
    /// ([`MultiRes`]); `None` for the single-resolution tree.
    multires: Option<MultiRes>,
    /// Residency per node (multi-resolution mode; all resident otherwise).
    resident: Vec<std::sync::atomic::AtomicBool>,
}

/// One node of a [`DemStorage`]: cell ranges, vertex height range (`[min, max]`, min > max when the node has
/// no data), child ids (`u32::MAX`: none), level (zones are 0) and the node's box: 72 bytes.
#[derive(Debug, Clone, Copy, PartialEq)]
struct NodeRecord {
    rows: [u32; 2],
    cols: [u32; 2],
    heights: [f32; 2],
    kids: [u32; 4],
    level: u8,
    /// The node's box (in the frame [`DemStorage::build_boxes`] gives it; [`curvicast::terrain::boxes`]), `None` without
    /// data.
    bbox: Option<curvicast::terrain::boxes::NodeBox>,
}

/// How [`DemStorage::multi_resolution`] shapes a multi-resolution tree (seed 000 §5, Fig. 11): every node has a
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
        let pyramid = HeightPyramid::build(dem, block.min(max_block));
        let mut offsets = Vec::with_capacity(pyramid.dims.len());
        let mut acc = 0;
        for &(r, c) in &pyramid.dims {
            offsets.push(acc);
            acc += level_len(r, c);
        }
        let zone_level = pyramid
            .dims
            .iter()
            .position(|&(r, c)| r <= 4 && c <= 8)
            .unwrap_or(pyramid.dims.len() - 1);
        let mut s = DemStorage {
            dem,
            pyramid,
            offsets,
            zone_level,
            zones: Vec::new(),
            row_trig: Vec::new(),
            col_trig: Vec::new(),
            row_dd: Vec::new(),
            col_dd: Vec::new(),
            records: Vec::new(),
            multires,
            resident: Vec::new(),
        };
        if multires.is_some() {
            s.resident = (0..s.node_count())
                .map(|_| std::sync::atomic::AtomicBool::new(true))
                .collect();
        }
        let mut kids = vec![[u32::MAX; 4]; s.node_count()];
        for (level, &(nr, nc)) in s.pyramid.dims.iter().enumerate().take(zone_level + 1) {
            for r in 0..nr {
                for c in 0..nc {
                    if let Some(m) = multires {
                        if level <= m.coarse_level && !s.meets_region(level, r, c, m.fine_region) {
                            continue; // a leaf of the coarse part of the tree
                        }
                    }
                    let slot = &mut kids[s.id(level, r, c).0 as usize];
                    for (k, kid) in slot.iter_mut().zip(s.children_of(level, r, c)) {
                        if let Some((l, x, y)) = kid {
                            *k = s.id(l, x, y).0;
                        }
                    }
                }
            }
        }
        s.records = kids
            .iter()
            .enumerate()
            .map(|(k, &kids)| {
                let Some((level, r, c)) = s.locate(curvicast::terrain::NodeId(k as u32)) else {
                    // A slot past the level's last row or column (see `id`): no node, no data.
                    return NodeRecord {
                        rows: [0; 2],
                        cols: [0; 2],
                        heights: [1.0, 0.0],
                        kids,
                        level: 0,
                        bbox: None,
                    };
                };
                let (rows, cols) = s.ranges(level, r, c);
                let nc = s.pyramid.dims[level].1;
                let (lo, hi) = (
                    s.pyramid.min[level][r * nc + c],
                    s.pyramid.max[level][r * nc + c],
                );
                NodeRecord {
                    rows,
                    cols,
                    heights: [lo, hi],
                    kids,
                    level: (zone_level - level).min(255) as u8,
                    bbox: None,
                }
            })
            .collect();
        let g: curvicast::terrain::Grid<f64> = curvicast::terrain::TerrainStorage::grid(&s);
        s.row_trig = (0..g.rows)
            .map(|i| curvicast::geodesy::sin_cos_deg(g.lat_deg(i)))
            .collect();
        s.col_trig = (0..g.cols)
            .map(|j| curvicast::geodesy::sin_cos_deg(g.lon_deg(j)))
            .collect();
        let e = curvicast::terrain::TerrainStorage::<f64>::ellipsoid(&s);
        s.row_dd = (0..g.rows)
            .map(|i| curvicast::terrain::row_parallel(&e, &g, i))
            .collect();
        s.col_dd = (0..g.cols)
            .map(|j| curvicast::terrain::col_sin_cos_dd(&g, j))
            .collect();
        let (zr, zc) = s.pyramid.dims[zone_level];
        for r in 0..zr {
            for c in 0..zc {
                if s.pyramid.max[zone_level][r * zc + c] >= s.pyramid.min[zone_level][r * zc + c] {
                    s.zones.push(s.id(zone_level, r, c));
                }
            }
        }
        s.build_boxes();
        // The records hold the height ranges now.
        s.pyramid.min = Vec::new();
        s.pyramid.max = Vec::new();
        s
    }

    /// Every node's box ([`curvicast::terrain::boxes`]): a zone's in the grid's frame, a child's in the frame of
    /// its parent's box where [`shares_frame_with_children`](curvicast::terrain::boxes::shares_frame_with_children)
    /// allows it, else in its parent's own frame. The frames are assigned top-down over the tree reachable from
    /// the zones; the boxes are built in one bottom-up pass: a leaf's from its vertices, a parent's from its
    /// children's boxes (children have smaller ids) — their union where they share its frame, the corners
    /// carried over from its own frame otherwise. A box thus contains its children's, so all of its vertices
    /// (the children cover every cell with data).
    fn build_boxes(&mut self) {
        use curvicast::terrain::boxes::{
            BoxBuilder, LocalFrame, NodeBox, shares_frame_with_children,
        };
        use curvicast::terrain::{NodeId, TerrainStorage};
        let e: curvicast::geodesy::Ellipsoid<f64> = self.ellipsoid();
        let grid = TerrainStorage::<f64>::grid(self);
        let node = |s: &Self, k: u32| TerrainStorage::<f64>::node(s, NodeId(k));
        // Per reachable node: the anchor of its box's frame (`None`: the grid) and whether it is its parent's
        // box frame.
        let mut frame: Vec<Option<(Option<u32>, bool)>> = vec![None; self.records.len()];
        let mut stack: Vec<(u32, Option<u32>, bool)> =
            self.zones.iter().map(|z| (z.0, None, false)).collect();
        while let Some((k, anchor, shared)) = stack.pop() {
            frame[k as usize] = Some((anchor, shared));
            let share =
                shares_frame_with_children(&grid, anchor.and_then(|a| node(self, a)).as_ref());
            for &c in self.records[k as usize]
                .kids
                .iter()
                .filter(|&&c| c != u32::MAX)
            {
                stack.push(if share {
                    (c, anchor, true)
                } else {
                    (c, Some(k), false)
                });
            }
        }
        for k in 0..self.records.len() {
            let (Some((anchor, shared)), Some(n)) = (
                frame[k],
                node(self, k as u32).filter(|n| n.heights.is_some()),
            ) else {
                continue;
            };
            let a = anchor.and_then(|a| node(self, a));
            self.records[k].bbox = if n.is_leaf() {
                NodeBox::of_vertices(self, &e, &n, a.as_ref(), shared)
            } else {
                let frame = LocalFrame::for_box(self, &e, a.as_ref());
                let own = LocalFrame::of(self, &e, &n);
                let (mut b, mut union) = (BoxBuilder::default(), None::<NodeBox>);
                for cid in n.children.iter().flatten() {
                    let Some(cb) = self.records[cid.0 as usize].bbox else {
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
                let carried = b.finish();
                match (union, carried) {
                    (Some(u), Some(c)) => Some(u.union(&c)),
                    (u, c) => u.or(c),
                }
                .map(|b| NodeBox {
                    shared_frame: shared,
                    ..b
                })
            };
        }
    }

    /// The DEM.
    pub fn dem(&self) -> &Dem {
        self.dem
    }

    /// Whether pyramid node (level, r, c) meets the box `[lat_s, lat_n, lon_w, lon_e]` (always, without one).
    fn meets_region(&self, level: usize, r: usize, c: usize, region: Option<[f64; 4]>) -> bool {
        let Some([lat_s, lat_n, lon_w, lon_e]) = region else {
            return true;
        };
        let (rows, cols) = self.ranges(level, r, c);
        let d = self.dem;
        let lat = |i: u32| d.lat0 + f64::from(i) * d.dlat;
        let lon = |j: u32| d.lon0 + f64::from(j) * d.dlon;
        let (la, lb) = (lat(rows[0]), lat(rows[1]));
        let (lo_a, lo_b) = (lon(cols[0]), lon(cols[1]));
        la.min(lb) <= lat_n && la.max(lb) >= lat_s && lo_a <= lon_e && lo_b >= lon_w
    }

    /// Marks node `id`'s block resident or not (multi-resolution mode; a single-resolution storage keeps every
    /// block resident and ignores this).
    pub fn set_resident(&self, id: curvicast::terrain::NodeId, resident: bool) {
        if self.multires.is_some() {
            if let Some(flag) = self.resident.get(id.0 as usize) {
                flag.store(resident, std::sync::atomic::Ordering::Relaxed);
            }
        }
    }

    /// The tree as plain data (for the multi-resolution oracle and for choosing residency): every node reachable
    /// from the zones, with its parent, level, ranges, stride and residency, in id order.
    pub fn tree(&self) -> Vec<crate::oracle::multires::TreeNode> {
        use curvicast::terrain::TerrainStorage;
        let mut out = Vec::new();
        let mut stack: Vec<(curvicast::terrain::NodeId, Option<u32>)> =
            self.zones.iter().map(|&z| (z, None)).collect();
        while let Some((id, parent)) = stack.pop() {
            let Some(n) = TerrainStorage::<f64>::node(self, id) else {
                continue;
            };
            out.push(crate::oracle::multires::TreeNode {
                id: id.0,
                parent,
                level: n.level,
                rows: n.rows,
                cols: n.cols,
                leaf: n.is_leaf(),
                stride: TerrainStorage::<f64>::block_stride(self, id),
                resident: TerrainStorage::<f64>::is_resident(self, id),
            });
            stack.extend(n.children.iter().flatten().map(|&c| (c, Some(id.0))));
        }
        out.sort_by_key(|x| x.id);
        out
    }

    /// Cells per leaf-block side.
    pub fn block(&self) -> usize {
        self.pyramid.block
    }

    /// Number of node records: the id slots of all pyramid levels from the leaves up to the zones (levels are
    /// stored by 2 × 2 groups, so a few slots past odd last rows and columns hold no node).
    pub fn node_count(&self) -> usize {
        self.offsets
            .get(self.zone_level + 1)
            .copied()
            .unwrap_or_else(|| {
                self.pyramid
                    .dims
                    .iter()
                    .map(|&(r, c)| level_len(r, c))
                    .sum()
            })
    }

    /// The depth of the tree: the level of the leaves below the zones (zones are level 0).
    pub fn depth(&self) -> u32 {
        self.zone_level as u32
    }

    /// The memory the tree adds to the heights, in bytes: one record per node (cell ranges, height range, child
    /// ids, level), the residency flags, the zone list, level offsets and the per-row / per-column sine and cosine
    /// tables.
    pub fn overhead_bytes(&self) -> usize {
        self.records.len() * std::mem::size_of::<NodeRecord>()
            + self.resident.len() * std::mem::size_of::<std::sync::atomic::AtomicBool>()
            + self.zones.len() * std::mem::size_of::<curvicast::terrain::NodeId>()
            + self.offsets.len() * std::mem::size_of::<usize>()
            + (self.row_trig.len() + self.col_trig.len()) * std::mem::size_of::<(f64, f64)>()
            + self.row_dd.len() * std::mem::size_of::<curvicast::terrain::Parallel<f64>>()
            + self.col_dd.len()
                * std::mem::size_of::<(curvicast::dd::Dd<f64>, curvicast::dd::Dd<f64>)>()
    }

    /// The memory of the heights themselves (`f32` per vertex), for comparison.
    pub fn heights_bytes(&self) -> usize {
        self.dem.heights.len() * std::mem::size_of::<f32>()
    }

    /// The id of pyramid node (level, r, c): levels are concatenated from the leaves up, and within a level the
    /// nodes are stored by 2 × 2 groups (row-major over the groups, then row-major inside a group), so that the
    /// four children of a node — one group of the level below — have consecutive ids and records: the traversal
    /// reads their boxes from adjacent cache lines. A level of `nr × nc` nodes has `level_len(nr, nc)` slots; the
    /// slots past an odd last row or column hold no node.
    fn id(&self, level: usize, r: usize, c: usize) -> curvicast::terrain::NodeId {
        let groups_per_row = self.pyramid.dims[level].1.div_ceil(2);
        let slot = 4 * (groups_per_row * (r / 2) + c / 2) + 2 * (r % 2) + c % 2;
        curvicast::terrain::NodeId((self.offsets[level] + slot) as u32)
    }

    /// The pyramid node (level, r, c) of an id ([`DemStorage::id`]), `None` for an unused slot.
    fn locate(&self, id: curvicast::terrain::NodeId) -> Option<(usize, usize, usize)> {
        let k = id.0 as usize;
        let level = self.offsets.iter().rposition(|&o| o <= k)?;
        if level > self.zone_level {
            return None;
        }
        let (nr, nc) = self.pyramid.dims[level];
        let local = k - self.offsets[level];
        let (group, inside) = (local / 4, local % 4);
        let groups_per_row = nc.div_ceil(2);
        let r = 2 * (group / groups_per_row) + inside / 2;
        let c = 2 * (group % groups_per_row) + inside % 2;
        (r < nr && c < nc).then_some((level, r, c))
    }

    /// Cell ranges `[r0, r1) × [c0, c1)` of pyramid node (level, r, c).
    fn ranges(&self, level: usize, r: usize, c: usize) -> ([u32; 2], [u32; 2]) {
        let span = self.pyramid.block << level;
        let (cr, cc) = (self.dem.rows - 1, self.dem.cols - 1);
        (
            [(r * span) as u32, ((r + 1) * span).min(cr) as u32],
            [(c * span) as u32, ((c + 1) * span).min(cc) as u32],
        )
    }

    fn has_data(&self, level: usize, r: usize, c: usize) -> bool {
        let (_, nc) = self.pyramid.dims[level];
        self.pyramid.max[level][r * nc + c] >= self.pyramid.min[level][r * nc + c]
    }

    /// The present children of (level, r, c), descending through children that cover the same cells (no
    /// allocation: this runs for every quad the kernel visits).
    fn children_of(&self, level: usize, r: usize, c: usize) -> [Option<(usize, usize, usize)>; 4] {
        let (mut level, mut r, mut c) = (level, r, c);
        let own = self.ranges(level, r, c);
        let mut out = [None; 4];
        while level > 0 {
            let (nr, nc) = self.pyramid.dims[level - 1];
            let mut n = 0;
            let mut only = (0, 0, 0);
            for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let (x, y) = (2 * r + a, 2 * c + b);
                if x < nr && y < nc {
                    n += 1;
                    only = (level - 1, x, y);
                }
            }
            if n == 1 && self.ranges(only.0, only.1, only.2) == own {
                (level, r, c) = only;
                continue;
            }
            let mut k = 0;
            for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let (x, y) = (2 * r + a, 2 * c + b);
                if x < nr && y < nc && self.has_data(level - 1, x, y) {
                    out[k] = Some((level - 1, x, y));
                    k += 1;
                }
            }
            break;
        }
        out
    }
}

impl<T: curvicast::Real> curvicast::terrain::TerrainStorage<T> for DemStorage<'_> {
    fn ellipsoid(&self) -> curvicast::geodesy::Ellipsoid<T> {
        curvicast::geodesy::Ellipsoid::new(T::from_f64(self.dem.a), T::from_f64(self.dem.b))
            .unwrap_or_else(|_| curvicast::geodesy::Ellipsoid::wgs84())
    }

    fn grid(&self) -> curvicast::terrain::Grid<T> {
        curvicast::terrain::Grid {
            lat0_deg: T::from_f64(self.dem.lat0),
            lon0_deg: T::from_f64(self.dem.lon0),
            dlat_deg: T::from_f64(self.dem.dlat),
            dlon_deg: T::from_f64(self.dem.dlon),
            rows: self.dem.rows as u32,
            cols: self.dem.cols as u32,
        }
    }

    fn zone_count(&self) -> usize {
        self.zones.len()
    }

    fn zone(&self, k: usize) -> Option<curvicast::terrain::NodeId> {
        self.zones.get(k).copied()
    }

    fn node(&self, id: curvicast::terrain::NodeId) -> Option<curvicast::terrain::Node<T>> {
        let n = self.records.get(id.0 as usize)?;
        Some(curvicast::terrain::Node {
            rows: n.rows,
            cols: n.cols,
            heights: (n.heights[1] >= n.heights[0])
                .then(|| n.heights.map(|h| T::from_f64(f64::from(h)))),
            children: n
                .kids
                .map(|k| (k != u32::MAX).then_some(curvicast::terrain::NodeId(k))),
            level: n.level,
        })
    }

    fn height(&self, i: u32, j: u32) -> Option<T> {
        self.dem
            .height(i as usize, j as usize)
            .map(|h| T::from_f64(f64::from(h)))
    }

    fn node_box(
        &self,
        id: curvicast::terrain::NodeId,
    ) -> Option<curvicast::terrain::boxes::NodeBox> {
        self.records.get(id.0 as usize)?.bbox
    }

    fn is_resident(&self, id: curvicast::terrain::NodeId) -> bool {
        self.multires.is_none()
            || self
                .resident
                .get(id.0 as usize)
                .is_none_or(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    }

    fn block_stride(&self, id: curvicast::terrain::NodeId) -> u32 {
        if self.multires.is_none() {
            return 1;
        }
        self.locate(id)
            .map_or(1, |(level, _, _)| 1 << level.min(31))
    }

    // The tables hold the `f64` values; other scalar types compute their own (the kernel requires exactly
    // `sin_cos_deg` in `T`).
    fn row_sin_cos(&self, i: u32) -> (T, T) {
        match self.row_trig.get(i as usize) {
            Some(&(s, c)) if T::MANTISSA_DIGITS == 53 => (T::from_f64(s), T::from_f64(c)),
            _ => curvicast::geodesy::sin_cos_deg(
                <Self as curvicast::terrain::TerrainStorage<T>>::grid(self).lat_deg(i),
            ),
        }
    }

    fn col_sin_cos(&self, j: u32) -> (T, T) {
        match self.col_trig.get(j as usize) {
            Some(&(s, c)) if T::MANTISSA_DIGITS == 53 => (T::from_f64(s), T::from_f64(c)),
            _ => curvicast::geodesy::sin_cos_deg(
                <Self as curvicast::terrain::TerrainStorage<T>>::grid(self).lon_deg(j),
            ),
        }
    }

    fn row_parallel(&self, i: u32) -> curvicast::terrain::Parallel<T> {
        use curvicast::terrain::TerrainStorage;
        match self.row_dd.get(i as usize) {
            Some(p) if T::MANTISSA_DIGITS == 53 => curvicast::terrain::Parallel {
                n_cos: dd_as(p.n_cos),
                nb_sin: dd_as(p.nb_sin),
                cos: dd_as(p.cos),
                sin: dd_as(p.sin),
            },
            _ => curvicast::terrain::row_parallel(
                &TerrainStorage::<T>::ellipsoid(self),
                &TerrainStorage::<T>::grid(self),
                i,
            ),
        }
    }

    fn col_sin_cos_dd(&self, j: u32) -> (curvicast::dd::Dd<T>, curvicast::dd::Dd<T>) {
        match self.col_dd.get(j as usize) {
            Some(&(s, c)) if T::MANTISSA_DIGITS == 53 => (dd_as(s), dd_as(c)),
            _ => curvicast::terrain::col_sin_cos_dd(
                &<Self as curvicast::terrain::TerrainStorage<T>>::grid(self),
                j,
            ),
        }
    }
}

/// An `f64` pair as a pair of `T` (used only when `T` is `f64`, so the conversion is exact).
fn dd_as<T: curvicast::Real>(x: curvicast::dd::Dd<f64>) -> curvicast::dd::Dd<T> {
    curvicast::dd::Dd {
        hi: T::from_f64(x.hi),
        lo: T::from_f64(x.lo),
    }
}

/// A storage whose blocks are the base's plus those paged in while answering one ray ([`pick_paging_in`]).
pub struct Paged<'b, 'd> {
    base: &'b DemStorage<'d>,
    paged: std::cell::RefCell<Vec<curvicast::terrain::NodeId>>,
}

impl curvicast::terrain::TerrainStorage<f64> for Paged<'_, '_> {
    fn ellipsoid(&self) -> curvicast::geodesy::Ellipsoid<f64> {
        self.base.ellipsoid()
    }
    fn grid(&self) -> curvicast::terrain::Grid<f64> {
        self.base.grid()
    }
    fn zone_count(&self) -> usize {
        curvicast::terrain::TerrainStorage::<f64>::zone_count(self.base)
    }
    fn zone(&self, k: usize) -> Option<curvicast::terrain::NodeId> {
        curvicast::terrain::TerrainStorage::<f64>::zone(self.base, k)
    }
    fn node(&self, id: curvicast::terrain::NodeId) -> Option<curvicast::terrain::Node<f64>> {
        self.base.node(id)
    }
    fn height(&self, i: u32, j: u32) -> Option<f64> {
        self.base.height(i, j)
    }
    fn is_resident(&self, id: curvicast::terrain::NodeId) -> bool {
        curvicast::terrain::TerrainStorage::<f64>::is_resident(self.base, id)
            || self.paged.borrow().contains(&id)
    }
    fn block_stride(&self, id: curvicast::terrain::NodeId) -> u32 {
        curvicast::terrain::TerrainStorage::<f64>::block_stride(self.base, id)
    }
    fn row_sin_cos(&self, i: u32) -> (f64, f64) {
        self.base.row_sin_cos(i)
    }
    fn col_sin_cos(&self, j: u32) -> (f64, f64) {
        self.base.col_sin_cos(j)
    }
    fn node_box(
        &self,
        id: curvicast::terrain::NodeId,
    ) -> Option<curvicast::terrain::boxes::NodeBox> {
        curvicast::terrain::TerrainStorage::<f64>::node_box(self.base, id)
    }
    fn row_parallel(&self, i: u32) -> curvicast::terrain::Parallel<f64> {
        self.base.row_parallel(i)
    }
    fn col_sin_cos_dd(&self, j: u32) -> (curvicast::dd::Dd<f64>, curvicast::dd::Dd<f64>) {
        self.base.col_sin_cos_dd(j)
    }
}

/// Picks `ray` as a caller of a paging storage does (seed 000 §5): on `NeedsBlock` the node's block is paged in
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
    fn pyramid_matches_direct_block_maxima() {
        let (rows, cols) = (37, 53);
        let h: Vec<f32> = (0..rows * cols)
            .map(|k| ((k * 7919) % 1000) as f32 - 300.0)
            .collect();
        let mut d = Dem::wgs84((0.0, 0.0, 0.01, 0.01), (rows, cols), h).unwrap();
        d.heights[100] = f32::NAN;
        for block in [1, 4, 16] {
            let p = HeightPyramid::build(&d, block);
            let (br, bc) = p.dims[0];
            for bi in 0..br {
                for bj in 0..bc {
                    let mut mx = f32::NEG_INFINITY;
                    let mut mn = f32::INFINITY;
                    for i in bi * block..=((bi + 1) * block).min(rows - 1) {
                        for j in bj * block..=((bj + 1) * block).min(cols - 1) {
                            if let Some(h) = d.height(i, j) {
                                mx = mx.max(h);
                                mn = mn.min(h);
                            }
                        }
                    }
                    assert_eq!(p.max[0][bi * bc + bj], mx);
                    assert_eq!(p.min[0][bi * bc + bj], mn);
                }
            }
            let top = p.max.last().unwrap();
            assert_eq!(top.len(), 1);
            assert_eq!(top[0], d.height_range().unwrap().1);
            assert!(p.overhead_bytes() > 0);
        }
    }

    #[test]
    fn storage_tree_is_well_formed_and_covers_every_triangle_once() {
        use curvicast::terrain::TerrainStorage;
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
