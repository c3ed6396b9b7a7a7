//! Global terrain picking on a spheroid (Wartell, Ribarsky, Hodges): the nearest
//! intersection of a ray with a regular geodetic DEM's triangles, through a spheroidal height-augmented quadtree.
//!
//! The caller owns the terrain: a [`TerrainStorage`] gives the grid ([`Grid`]), the heights and the quadtree's
//! nodes, and [`build`] builds that tree from a heights slice into caller-provided buffers ([`build::SliceStorage`]
//! serves it). A [`Picker`] borrows the storage and answers [`Picker::pick`] (the nearest [`Hit`], refined),
//! [`Picker::pick_t`] (the traversal's `t` and cell, unrefined) and [`Picker::line_of_sight`].
//!
//! # A pick, phase by phase
//!
//! Each phase has its own file, whose docs explain it (the files in the order a ray meets them):
//!
//! 1. **Global clip** (§3.5; `traverse.rs`): the ray is clipped to the upper spheroid `B^h` of the global maximum
//!    height.
//! 2. **Zones and quads** (§3.1–3.5; `traverse.rs`): the zones, then each zone's quadtree, nearest child first,
//!    against conservative volumes ([`crate::geodesy::HeightQuadBounds`], the relaxed test
//!    [`crate::geodesy::relaxed_interval`]) or node boxes in local frames ([`boxes`]). `traverse.rs` also states
//!    what is proven: the returned hit is the nearest one.
//! 3. **Leaf blocks** (§4; `leaf.rs`): the triangle pairs of a leaf, each in a volume bounded by two meridian
//!    planes and two row planes, walked column by column; the watertight triangle test ([`triangle`]).
//! 4. **Stitching** (§6; `stitch.rs`): a coarse cell next to finer data is re-triangulated so that no ray
//!    passes through the crack.
//! 5. **Refinement and the hit** (beyond the paper; `hit.rs`, `refine.rs`): the hit triangle's vertices
//!    recomputed in double-double ([`crate::dd`]) and `t` taken from its plane; the geodetic coordinates.
//!
//! # Multi-resolution (§5–§6)
//!
//! A storage may give every node a *block*: the DEM's vertices at a spacing of
//! [`TerrainStorage::block_stride`] grid steps within the node (coarser nodes subsample the finest data; a
//! vertex has one height), resident or not ([`TerrainStorage::is_resident`]). Branches may end at different
//! depths. The defaults (stride 1, always resident) give the single-resolution surface. Nodes shallower than
//! the picker's `min_level` ([`Picker::with_min_level`]) never stand in for missing finer blocks; from
//! `min_level` on, the nearest resident ancestor of a missing block answers for it with its own cells (§5, the
//! block subset of [`subset`]), and coarse cells next to finer ones are stitched (§6). A missing block that no
//! resident one can stand in for is reported as [`TerrainError::NeedsBlock`] if the ray reaches its node
//! before the nearest hit found elsewhere: the caller pages the block in and asks again. `traverse.rs` gives
//! the rules ("Which blocks are traced"), `stitch.rs` the continuity and its bounds; [`Hit::level`] and
//! [`Hit::stride`] say which block answered.
//!
//! ```
//! use curvicast::geodesy::Ellipsoid;
//! use curvicast::ray::Ray;
//! use curvicast::terrain::build::{NodeRecord, SliceStorage, build_tree, node_slots};
//! use curvicast::terrain::{Grid, Picker};
//!
//! // A 3 × 3-vertex DEM near (10°N, 20°E) with one raised vertex; blocks of 2 × 2 cells make it one zone that
//! // is also a leaf.
//! let grid = Grid { lat0_deg: 10.0, lon0_deg: 20.0, dlat_deg: 0.01, dlon_deg: 0.01, rows: 3, cols: 3 };
//! let heights = [0.0, 0.0, 0.0, 0.0, 500.0, 0.0, 0.0, 0.0, 0.0];
//! let mut nodes = [NodeRecord::<f64>::EMPTY; node_slots(3, 3, 2)];
//! let tree = build_tree(&heights, &grid, 2, &mut nodes)?;
//! let dem = SliceStorage::new(Ellipsoid::wgs84(), grid, &heights, &nodes, tree)?;
//! let picker: Picker<'_, f64, SliceStorage<'_, f64>> = Picker::new(&dem)?;
//! let e = Ellipsoid::<f64>::wgs84();
//! // Straight down onto the raised center vertex from 10 km.
//! let top = e.geodetic_deg_to_ecef(10.01, 20.01, 10_000.0);
//! let down = e.normal_deg(10.01, 20.01).negated();
//! let hit = picker.pick(&Ray::new(top, down)?)?.expect("the peak is below");
//! assert!((hit.t - 9_500.0).abs() < 1e-6 && (hit.h - 500.0).abs() < 1e-6);
//! assert_eq!(hit.level, 0);
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

pub mod boxes;
pub mod build;
mod hit;
mod leaf;
mod refine;
mod stitch;
mod storage;
pub mod subset;
mod traverse;
pub mod triangle;

pub use refine::{Parallel, col_sin_cos_dd, row_parallel};
pub use storage::{
    DEFAULT_ZONE_COLS, DEFAULT_ZONE_ROWS, Grid, Node, NodeId, TerrainStorage, vertex_ecef,
    zone_cells,
};

use crate::geodesy::{
    Ellipsoid, GeodesyError, HeightQuadBounds, QuadTrig, RelaxedVolume, SideWalls,
    relaxed_interval, sin_cos_deg, upper_spheroid,
};
use crate::interval::clip_half_space;
use crate::ray::{Ray, RayError};
use crate::real::Real;
use crate::sort::insertion_sort;
use crate::surface::{Side, Spheroid, Surface};
use crate::vec3::V3;
use boxes::{FrameRay, LocalFrame, NodeBox};
use core::cell::Cell;
use refine::{Tri, Vtx};
use triangle::{Edge, WatertightRay};

/// Why a pick failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TerrainError {
    /// The ray (or segment) is invalid.
    Ray(RayError),
    /// A bound could not be formed (heights at or below `−b²/a`, non-finite values, bad axes).
    Geodesy(GeodesyError),
    /// The grid is invalid (see [`Grid::validate`]).
    InvalidGrid,
    /// A node is missing, outside the grid, or not strictly inside its parent.
    MalformedTree,
    /// More zones than the picker's `ZONES` capacity.
    TooManyZones,
    /// The traversal stack (capacity `STACK`) is full: the tree is deeper than the picker was sized for.
    StackFull,
    /// The traversal visited more nodes than the grid can hold (a malformed tree).
    TraversalBound,
    /// The answer needs the block of this node, which is not resident, and no coarser resident block at or
    /// below the picker's `min_level` can stand in for it (§5): page it in and ask again. Reported only when
    /// the node could hold a hit nearer than any found.
    NeedsBlock(NodeId),
    /// The ray meets the terrain's bounding volume, but where its parameter `t` is beyond the largest finite
    /// value of the scalar type (a direction so short, like `[1e-308, 0, 0]` from a thousand kilometres away,
    /// that `t = distance / |d|` overflows), and no hit was found at a representable `t`. Answered as an error
    /// rather than as a miss.
    Unrepresentable,
}

impl core::fmt::Display for TerrainError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TerrainError::Ray(e) => write!(f, "invalid ray: {e}"),
            TerrainError::Geodesy(e) => write!(f, "invalid terrain bound: {e}"),
            TerrainError::InvalidGrid => f.write_str(
                "invalid DEM grid: it needs finite lat0, lon0, dlat and dlon, at least 2 rows and 2 columns, \
                 dlat != 0, 0 < dlon < 180 degrees and every row's latitude within [-90, 90]",
            ),
            TerrainError::MalformedTree => f.write_str("malformed terrain quadtree"),
            TerrainError::TooManyZones => f.write_str("more zones than the picker's capacity"),
            TerrainError::StackFull => {
                f.write_str("traversal stack full (tree deeper than capacity)")
            }
            TerrainError::TraversalBound => f.write_str("traversal exceeded its node bound"),
            TerrainError::NeedsBlock(id) => write!(f, "needs the block of node {}", id.0),
            TerrainError::Unrepresentable => f.write_str(
                "the ray meets the terrain where its t exceeds the largest finite value (direction too short)",
            ),
        }
    }
}

impl core::error::Error for TerrainError {}

impl From<RayError> for TerrainError {
    fn from(e: RayError) -> Self {
        TerrainError::Ray(e)
    }
}
impl From<GeodesyError> for TerrainError {
    fn from(e: GeodesyError) -> Self {
        TerrainError::Geodesy(e)
    }
}

/// The nearest intersection of a ray with the terrain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit<T> {
    /// Ray parameter (in the units of the ray's direction).
    pub t: T,
    /// The hit point, ECEF: `origin + t·dir` formed in double-double from the refined parameter and rounded once
    /// per coordinate (so it may differ from `ray.at(t)` by the rounding of `t·dir`; module docs, step 5; `hit.rs`).
    pub ecef: [T; 3],
    /// Geodetic latitude of the hit point, degrees.
    pub lat_deg: T,
    /// Longitude of the hit point, degrees in [−180, 180].
    pub lon_deg: T,
    /// Height of the hit point above the ellipsoid.
    pub h: T,
    /// The grid cell `[i, j]` whose triangle was hit: the first grid row and column of the traced cell, which
    /// spans `stride × stride` grid cells.
    pub cell: [u32; 2],
    /// The quadtree level of the node whose block was traced (the leaf's, or its resident ancestor's, §5).
    pub level: u8,
    /// The traced cell's size in grid steps: 1 at the DEM's own resolution, the block's
    /// [`TerrainStorage::block_stride`] for coarser blocks.
    pub stride: u32,
}

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
struct Candidate<T> {
    t: T,
    cell: [u32; 2],
    tri: TriRef,
    unit: Unit,
}

/// Which triangle a candidate is: one of a full-resolution cell's two (refined with the containment walk), or
/// any other by its vertices (coarse cells and stitched fans, refined without a walk).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum TriRef {
    Cell(Tri),
    Vertices([Vtx; 3]),
}

/// A traced unit (§4, §5): a node's cell range traced with cells of `stride` grid steps from the block of the
/// node at `level` (the node's own, or its nearest resident ancestor's).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Unit {
    rows: [u32; 2],
    cols: [u32; 2],
    stride: u32,
    level: u8,
}

/// The resident block a subtree falls back to (§5): the nearest resident ancestor at or below `min_level`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Source {
    stride: u32,
    level: u8,
}

/// What the traversal does at a node (`traverse.rs`, "Which blocks are traced").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    /// Visit the children; the source they fall back to.
    Descend(Option<Source>),
    /// Trace this unit.
    Trace(Unit),
    /// The node's block is needed.
    Needs,
}

/// The traced unit covering a grid cell, for stitching ([`Picker::unit_at`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Lookup {
    Unit(Unit),
    /// No node covers the cell (no data there).
    Empty,
    Needs(NodeId),
}

/// A traced cell's grid ranges: rows `[i, i1]`, columns `[j, j1]` (corner vertices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct CellAt {
    rows: [u32; 2],
    cols: [u32; 2],
}

/// One side of a traced cell: along a row (`along_cols`: the points are columns) or a column, at row or column
/// `fixed`, from `from` to `to`; `across` is the neighbouring cells' row or column when the side is on the
/// unit's border.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct SideAt {
    along_cols: bool,
    fixed: u32,
    from: u32,
    to: u32,
    across: Option<u32>,
}

/// The outcome of [`Picker::stitch`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stitch {
    Plain,
    Done,
}

/// The per-ray state of a traversal: the ray, the nearest hit so far, the nearest needed block, the counters.
struct Walk<'r, 'w, T> {
    ray: &'r Ray<T>,
    wray: &'r WatertightRay<T>,
    best: &'w mut Option<Candidate<T>>,
    pending: &'w mut Option<(T, NodeId)>,
    stats: &'w mut PickStats,
}

impl<T: Real> Walk<'_, '_, T> {
    fn best_t(&self) -> T {
        self.best.as_ref().map_or(T::INFINITY, |h| h.t)
    }
    /// Records that node `id`'s block is needed from parameter `t` on (the nearest such is kept).
    fn need(&mut self, t: T, id: NodeId) {
        if self.pending.is_none_or(|(p, _)| t < p) {
            *self.pending = Some((t, id));
        }
    }
}

/// A zone: its root and how its volume is tested (the storage's cached volume, or the relaxed test of
/// [`relaxed_interval`] from the zone's trigonometry). Its box is kept apart ([`Picker`]'s `zone_boxes`).
type Zone<T> = (NodeId, Node<T>, ZoneVolume<T>);

#[derive(Debug, Clone, Copy, PartialEq)]
enum ZoneVolume<T> {
    Cached(HeightQuadBounds<T>),
    Relaxed(RelaxedVolume<T>),
}

/// A node on the traversal stack. The node itself is read from the storage when it is visited, and checked
/// then against its parent's ranges and stride.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry<T> {
    id: NodeId,
    /// The parent's cell ranges (`None` for a zone).
    parent: Option<([u32; 2], [u32; 2])>,
    t_in: T,
    t_out: T,
    /// The parent's block stride (`u32::MAX` for a zone).
    parent_stride: u32,
    /// The source inherited from the parent.
    src: Option<Source>,
    /// Where the node's box was tested: its index in the traversal's frames (0: the grid's frame).
    frame: u8,
    /// The node's depth below its zone (0: the zone); its own frame goes to index `depth + 1`.
    depth: u8,
}

/// The capacity of the traversal's stack of frames ([`boxes`], "Which frame"): node boxes in distinct frames
/// along one path from a zone, the grid's frame included.
const FRAMES: usize = 32;

/// The picker: a borrowed storage plus the per-storage constants (global bound, zone volumes).
///
/// `STACK` is the capacity of the traversal stack (up to 3 entries per tree level plus 4); `ZONES` the maximum
/// number of zones. Both are fixed memory inside the picker and the call frame; exceeding them is an error (as is
/// a path with node boxes in more than 31 distinct frames below the grid's).
#[derive(Debug, Clone)]
pub struct Picker<'s, T, S, const STACK: usize = 64, const ZONES: usize = 64> {
    storage: &'s S,
    ellipsoid: Ellipsoid<T>,
    grid: Grid<T>,
    /// Global height range over the zones.
    h_max: T,
    /// The global clip `B^{h_max}` (§3.5), once there is a zone with data.
    upper: Option<Spheroid<T>>,
    /// `(sin, cos)` of half a traced cell's longitude span, for cells of `2^k` grid steps.
    half_cells: [(T, T); 32],
    /// The coarsest level whose blocks may stand in for missing finer ones (§5).
    min_level: u8,
    zones: [Option<Zone<T>>; ZONES],
    /// The zones' boxes (in the grid's frame) if the storage has them, compact for the per-ray scan.
    zone_boxes: [Option<NodeBox>; ZONES],
    zone_count: usize,
    /// The frame of the zones' boxes ([`LocalFrame::for_box`] without a parent).
    grid_frame: LocalFrame<T>,
    /// The grid spans less than 30° both ways: its frame's boxes are tight enough on their own.
    regional: bool,
    /// `2 e² (a²/b)(1 + e² a²/b²)`: beyond this distance from the axis a column's row planes are ordered
    /// ([`Picker::crossed_rows`]).
    rows_ordered_beyond: T,
}

impl<'s, T: Real, S: TerrainStorage<T>, const STACK: usize, const ZONES: usize>
    Picker<'s, T, S, STACK, ZONES>
{
    /// Checks the storage's grid and zones and precomputes the zone volumes. `min_level` is 0: any resident
    /// block may stand in for a missing finer one ([`Picker::with_min_level`]).
    pub fn new(storage: &'s S) -> Result<Self, TerrainError> {
        let ellipsoid = storage.ellipsoid();
        let grid = storage.grid();
        if !grid.validate() {
            return Err(TerrainError::InvalidGrid);
        }
        let n = storage.zone_count();
        if n > ZONES {
            return Err(TerrainError::TooManyZones);
        }
        let mut half_cells = [(T::ZERO, T::ONE); 32];
        let mut width = grid.dlon_deg.abs() * T::HALF;
        for h in &mut half_cells {
            *h = sin_cos_deg(width);
            width *= T::TWO;
        }
        let mut picker = Picker {
            storage,
            ellipsoid,
            grid,
            h_max: T::NEG_INFINITY,
            upper: None,
            half_cells,
            min_level: 0,
            zones: [None; ZONES],
            zone_boxes: [None; ZONES],
            zone_count: 0,
            grid_frame: LocalFrame::for_box(storage, &ellipsoid, None),
            rows_ordered_beyond: {
                let (e2, q) = (ellipsoid.e2(), ellipsoid.a() / ellipsoid.b());
                T::TWO * e2 * ellipsoid.a() * q * (T::ONE + e2 * q * q)
            },
            regional: {
                let span = |n: u32, step: T| T::from_f64(f64::from(n)) * step.abs();
                let lim = T::from_f64(30.0);
                span(grid.cell_rows(), grid.dlat_deg) < lim
                    && span(grid.cell_cols(), grid.dlon_deg) < lim
            },
        };
        for k in 0..n {
            let id = storage.zone(k).ok_or(TerrainError::MalformedTree)?;
            let node = storage.node(id).ok_or(TerrainError::MalformedTree)?;
            check_in_grid(&node, &grid)?;
            let stride = picker.stride_of(id, u32::MAX)?;
            let Some([lo, hi]) = node.heights else {
                continue; // a zone without data has no triangles
            };
            let b = match storage.cached_bounds(id).filter(|_| stride == 1) {
                Some(b) => ZoneVolume::Cached(b),
                None => ZoneVolume::Relaxed(RelaxedVolume::new(
                    &ellipsoid,
                    &node_trig(&grid, storage, &node, None, picker.half_cell(stride).1),
                    lo,
                    hi,
                    grid.dlat_deg * picker.scale(stride),
                    grid.dlon_deg * picker.scale(stride),
                )?),
            };
            picker.h_max = picker.h_max.max(hi);
            let k = picker.zone_count;
            if let (Some(slot), Some(bbox)) =
                (picker.zones.get_mut(k), picker.zone_boxes.get_mut(k))
            {
                *slot = Some((id, node, b));
                *bbox = storage.node_box(id);
                picker.zone_count = k.saturating_add(1);
            }
        }
        if picker.zone_count > 0 {
            picker.upper = Some(upper_spheroid(&ellipsoid, picker.h_max)?);
        }
        Ok(picker)
    }

    /// The picker with another `min_level` (Wartell et al. §5): blocks of nodes shallower than `min_level` never stand
    /// in for missing finer ones. 0 (the default) uses whatever is resident; the tree's depth asks for the
    /// finest blocks only. The module docs ("Multi-resolution") summarise the rules, `traverse.rs` gives them
    /// in full.
    #[must_use]
    pub fn with_min_level(mut self, min_level: u8) -> Self {
        self.min_level = min_level;
        self
    }

    /// The picker's `min_level`.
    pub fn min_level(&self) -> u8 {
        self.min_level
    }

    /// A node's block stride, checked: a power of two, at most `parent_stride`.
    fn stride_of(&self, id: NodeId, parent_stride: u32) -> Result<u32, TerrainError> {
        let s = self.storage.block_stride(id);
        if s.is_power_of_two() && s <= parent_stride {
            Ok(s)
        } else {
            Err(TerrainError::MalformedTree)
        }
    }

    /// `stride` as a scalar.
    fn scale(&self, stride: u32) -> T {
        T::from_f64(f64::from(stride))
    }

    /// `(sin, cos)` of half the longitude span of a traced cell `stride` grid steps wide (a power of two).
    fn half_cell(&self, stride: u32) -> (T, T) {
        let k = usize::try_from(stride.trailing_zeros()).unwrap_or(0);
        self.half_cells.get(k).copied().unwrap_or((T::ZERO, T::ONE))
    }

    /// The nearest hit of `ray` with the terrain for `t_min ≤ t ≤ t_max`, or `None` (Wartell et al. §3.5, §4; the
    /// docs of `traverse.rs` state what is proven).
    ///
    /// ```
    /// # use curvicast::geodesy::Ellipsoid;
    /// # use curvicast::ray::Ray;
    /// # use curvicast::terrain::{Grid, Node, NodeId, Picker, TerrainStorage};
    /// /// Flat terrain at 100 m on a 2 × 2-cell grid straddling the antimeridian, one zone that is a leaf.
    /// struct Flat;
    /// impl TerrainStorage<f64> for Flat {
    ///     fn ellipsoid(&self) -> Ellipsoid<f64> { Ellipsoid::wgs84() }
    ///     fn grid(&self) -> Grid<f64> {
    ///         Grid { lat0_deg: -17.0, lon0_deg: 179.99, dlat_deg: 0.01, dlon_deg: 0.01, rows: 3, cols: 3 }
    ///     }
    ///     fn zone_count(&self) -> usize { 1 }
    ///     fn zone(&self, k: usize) -> Option<NodeId> { (k == 0).then_some(NodeId(0)) }
    ///     fn node(&self, _: NodeId) -> Option<Node<f64>> {
    ///         Some(Node { rows: [0, 2], cols: [0, 2], heights: Some([100.0, 100.0]), children: [None; 4], level: 0 })
    ///     }
    ///     fn height(&self, i: u32, j: u32) -> Option<f64> { (i < 3 && j < 3).then_some(100.0) }
    /// }
    /// let picker: Picker<'_, f64, Flat> = Picker::new(&Flat)?;
    /// let e = Ellipsoid::<f64>::wgs84();
    /// // A vertex of the grid (lat −16.99°, lon 180.00°), seen straight down from 1 km above the terrain.
    /// let from = e.geodetic_deg_to_ecef(-16.99, 180.0, 1100.0);
    /// let down = e.normal_deg(-16.99, 180.0).negated();
    /// let hit = picker.pick(&Ray::new(from, down)?)?.ok_or("no hit")?;
    /// assert!((hit.t - 1000.0).abs() < 1e-6 && (hit.h - 100.0).abs() < 1e-6);
    /// assert!((hit.lon_deg.abs() - 180.0).abs() < 1e-9 && hit.cell[1] <= 1);
    /// // Looking up from there: nothing.
    /// assert!(picker.pick(&Ray::new(from, down.negated())?)?.is_none());
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn pick(&self, ray: &Ray<T>) -> Result<Option<Hit<T>>, TerrainError> {
        let mut stats = PickStats::default();
        self.pick_with_stats(ray, &mut stats)
    }

    /// [`Picker::pick`], adding the work done to `stats`.
    pub fn pick_with_stats(
        &self,
        ray: &Ray<T>,
        stats: &mut PickStats,
    ) -> Result<Option<Hit<T>>, TerrainError> {
        let Some(unit) = unit_sized(ray)? else {
            return Ok(self.nearest(ray, stats)?.map(|c| self.make_hit(ray, c)));
        };
        let Some(c) = self.nearest(&unit, stats)? else {
            return Ok(None);
        };
        let hit = self.make_hit(&unit, c);
        Ok(t_of_unit_sized(ray, hit.t)?.map(|t| Hit { t, ..hit }))
    }

    /// The parameter `t` and the cell of the nearest hit as the traversal finds it, without [`Picker::pick`]'s
    /// refinement and geodetic coordinates: what a general ray caster's cast returns, for callers that need only
    /// the distance. The triangle is `pick`'s ([`Hit::cell`] is the same); `t` is the watertight test's on the
    /// scalar vertices, which are off by a few ulps of their coordinates, so along a ray of elevation ε over the
    /// triangle it errs by about that over `sin ε` (about 1e-9 m / sin ε at Earth scale in `f64`; `pick` removes
    /// this, `refine.rs` explains how).
    ///
    /// ```
    /// # use curvicast::geodesy::Ellipsoid;
    /// # use curvicast::ray::Ray;
    /// # use curvicast::terrain::{Grid, Node, NodeId, Picker, TerrainStorage};
    /// # struct Flat;
    /// # impl TerrainStorage<f64> for Flat {
    /// #     fn ellipsoid(&self) -> Ellipsoid<f64> { Ellipsoid::wgs84() }
    /// #     fn grid(&self) -> Grid<f64> {
    /// #         Grid { lat0_deg: -17.0, lon0_deg: 179.99, dlat_deg: 0.01, dlon_deg: 0.01, rows: 3, cols: 3 }
    /// #     }
    /// #     fn zone_count(&self) -> usize { 1 }
    /// #     fn zone(&self, k: usize) -> Option<NodeId> { (k == 0).then_some(NodeId(0)) }
    /// #     fn node(&self, _: NodeId) -> Option<Node<f64>> {
    /// #         Some(Node { rows: [0, 2], cols: [0, 2], heights: Some([100.0, 100.0]), children: [None; 4], level: 0 })
    /// #     }
    /// #     fn height(&self, i: u32, j: u32) -> Option<f64> { (i < 3 && j < 3).then_some(100.0) }
    /// # }
    /// // Flat terrain at 100 m (the grid of `pick`'s example), seen straight down from 1 km above it.
    /// let picker: Picker<'_, f64, Flat> = Picker::new(&Flat)?;
    /// let e = Ellipsoid::<f64>::wgs84();
    /// let from = e.geodetic_deg_to_ecef(-16.99, 180.0, 1100.0);
    /// let ray = Ray::new(from, e.normal_deg(-16.99, 180.0).negated())?;
    /// let (t, cell) = picker.pick_t(&ray)?.ok_or("no hit")?;
    /// let hit = picker.pick(&ray)?.ok_or("no hit")?;
    /// assert!((t - 1000.0).abs() < 1e-6 && cell == hit.cell);
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn pick_t(&self, ray: &Ray<T>) -> Result<Option<(T, [u32; 2])>, TerrainError> {
        let mut stats = PickStats::default();
        let Some(unit) = unit_sized(ray)? else {
            return Ok(self.nearest(ray, &mut stats)?.map(|c| (c.t, c.cell)));
        };
        let Some(c) = self.nearest(&unit, &mut stats)? else {
            return Ok(None);
        };
        Ok(t_of_unit_sized(ray, c.t)?.map(|t| (t, c.cell)))
    }

    /// Line of sight from `a` to `b` (ECEF): `true` when no terrain triangle meets the closed segment.
    pub fn line_of_sight(
        &self,
        a: impl Into<V3<T>>,
        b: impl Into<V3<T>>,
    ) -> Result<bool, TerrainError> {
        let seg = Ray::segment(a, b)?;
        // Only whether a triangle meets the segment matters: no hit point, so no refinement.
        let mut stats = PickStats::default();
        let Some(unit) = unit_sized(&seg)? else {
            return Ok(self.nearest(&seg, &mut stats)?.is_none());
        };
        Ok(match self.nearest(&unit, &mut stats)? {
            Some(c) => t_of_unit_sized(&seg, c.t)?.is_none(),
            None => true,
        })
    }
}

/// The same line as `ray` with the direction [`Ray::scaled_dir`] (exactly `ray`'s times a power of two, its
/// largest component in `[1/2, 2)`) when `ray`'s own direction is far from unit size (a component beyond 2^±32),
/// `None` otherwise. The traversal multiplies the direction with Earth-sized coordinates and with `t`; a
/// subnormal direction (seen down to the smallest, 5e-324) or a huge one would lose bits there or overflow,
/// while at unit size every product is ordinary and `t` converts back exactly ([`t_of_unit_sized`]).
fn unit_sized<T: Real>(ray: &Ray<T>) -> Result<Option<Ray<T>>, TerrainError> {
    if ray.scale_exponent().unsigned_abs() <= 32 {
        return Ok(None);
    }
    // The interval scales exactly too (unless `t_min` overflows: then no `t` of the ray is representable).
    let unit = Ray::new(ray.origin(), ray.scaled_dir())?
        .with_interval(ray.t_to_scaled(ray.t_min()), ray.t_to_scaled(ray.t_max()))
        .map_err(|_| TerrainError::Unrepresentable)?;
    Ok(Some(unit))
}

/// The caller's `t` of a hit at `s` on [`unit_sized`]'s ray: `None` beyond `ray`'s `t_max` (the scaled bound
/// may have overflowed), [`TerrainError::Unrepresentable`] when `t` itself overflows.
fn t_of_unit_sized<T: Real>(ray: &Ray<T>, s: T) -> Result<Option<T>, TerrainError> {
    let t = ray.t_from_scaled(s);
    if t > ray.t_max() {
        Ok(None)
    } else if t == T::INFINITY {
        Err(TerrainError::Unrepresentable)
    } else {
        Ok(Some(t))
    }
}

/// `⌈n / s⌉` for a power of two `s`, by shifts (no division, so no panic path).
fn div_ceil_pow2(n: u32, s: u32) -> u32 {
    let q = n.checked_shr(s.trailing_zeros()).unwrap_or(0);
    q.saturating_add(u32::from(n & s.wrapping_sub(1) != 0))
}

fn check_in_grid<T: Real>(n: &Node<T>, g: &Grid<T>) -> Result<(), TerrainError> {
    let ok = n.rows[0] < n.rows[1]
        && n.rows[1] <= g.cell_rows()
        && n.cols[0] < n.cols[1]
        && n.cols[1] <= g.cell_cols();
    if ok {
        Ok(())
    } else {
        Err(TerrainError::MalformedTree)
    }
}

/// A child lies inside its parent's ranges `rows`, `cols` and is strictly smaller.
fn check_child<T: Real>(rows: [u32; 2], cols: [u32; 2], c: &Node<T>) -> Result<(), TerrainError> {
    let inside = c.rows[0] >= rows[0]
        && c.rows[1] <= rows[1]
        && c.cols[0] >= cols[0]
        && c.cols[1] <= cols[1]
        && c.rows[0] < c.rows[1]
        && c.cols[0] < c.cols[1];
    let smaller = c.rows != rows || c.cols != cols;
    if inside && smaller {
        Ok(())
    } else {
        Err(TerrainError::MalformedTree)
    }
}

/// The conservative bounding volume of a node (`traverse.rs`, "Zones and quads"; [`HeightQuadBounds`]), as the kernel builds it from
/// the node's grid ranges and height range. `Ok(None)` for a node without data. Storages that cache volumes
/// ([`TerrainStorage::cached_bounds`]) must store exactly this value.
pub fn quad_bounds<T: Real>(
    e: &Ellipsoid<T>,
    g: &Grid<T>,
    n: &Node<T>,
) -> Result<Option<HeightQuadBounds<T>>, TerrainError> {
    let Some([lo, hi]) = n.heights else {
        return Ok(None);
    };
    let la = g.lat_deg(n.rows[0]);
    let lb = g.lat_deg(n.rows[1]);
    let (lat_s, lat_n) = if la <= lb { (la, lb) } else { (lb, la) };
    let lon_w = g.lon_deg(n.cols[0]);
    let lon_e = g.lon_deg(n.cols[1]);
    Ok(Some(HeightQuadBounds::new(
        e, lat_s, lat_n, lon_w, lon_e, lo, hi, g.dlat_deg, g.dlon_deg,
    )?))
}

/// The boundary trigonometry of a node, read from the storage ([`TerrainStorage::row_sin_cos`],
/// [`TerrainStorage::col_sin_cos`]). With a `parent`, the walls on the parent's sides are left out
/// ([`SideWalls`]).
fn node_trig<T: Real, S: TerrainStorage<T>>(
    g: &Grid<T>,
    storage: &S,
    n: &Node<T>,
    parent: Option<&Node<T>>,
    cos_half_cell_dlon: T,
) -> QuadTrig<T> {
    let ra = storage.row_sin_cos(n.rows[0]);
    let rb = storage.row_sin_cos(n.rows[1]);
    // A side is outer when the parent has the same side.
    let outer = |side: fn(&Node<T>) -> u32| parent.is_some_and(|p| side(p) == side(n));
    let (first_row, last_row) = (!outer(|m| m.rows[0]), !outer(|m| m.rows[1]));
    // Rows may run southwards (dlat_deg < 0): the southern wall is the one of smaller latitude.
    let (south, north, south_inner, north_inner) = if g.dlat_deg > T::ZERO {
        (ra, rb, first_row, last_row)
    } else {
        (rb, ra, last_row, first_row)
    };
    QuadTrig {
        south,
        north,
        west: storage.col_sin_cos(n.cols[0]),
        east: storage.col_sin_cos(n.cols[1]),
        span_deg: g.lon_deg(n.cols[1]) - g.lon_deg(n.cols[0]),
        cos_half_cell_dlon,
        walls: SideWalls {
            west: !outer(|m| m.cols[0]),
            east: !outer(|m| m.cols[1]),
            south: south_inner,
            north: north_inner,
        },
    }
}

#[cfg(test)]
mod tests;
