//! Global terrain picking on a spheroid (seeds 000 and 003, Wartell, Ribarsky, Hodges): the nearest
//! intersection of a ray with a regular geodetic DEM's triangles, through a spheroidal height-augmented quadtree.
//!
//! # The algorithm
//!
//! 1. **Global clip** (§3.5): the ray is clipped to the upper spheroid `B^h` of the global maximum height; its exit
//!    is `t_global_exit`.
//! 2. **Zones** come from the storage ([`TerrainStorage::zone`]), aligned to the DEM's grid (for a global DEM the
//!    storage typically uses 8 × 4 = 32 zones bounded by meridians and parallels; a regional DEM its own extent).
//!    Each zone's volume is tested against the ray and the zones are visited in order of entry.
//! 3. **Quads** (§3.1–3.5): each node's volume is a [`HeightQuadBounds`] — meridian wedge, latitude cones,
//!    upper spheroid `B^{h_max}`, lower sphere — and the ray's parameter hull inside it comes from the crossings
//!    of those walls (the §3.5 "side interval against `B^h` interval" test, generalised so that a volume entered
//!    twice yields one hull over both visits). The traversal itself tests zones and children against a relaxed,
//!    convex superset of that volume ([`crate::geodesy::relaxed_interval`]: each latitude cone replaced by a
//!    plane bounding its side, so the hull needs no point tests), and a child only against its walls on the
//!    parent's internal partition ([`crate::geodesy::SideWalls`]). Children are visited nearest entry first,
//!    with an explicit stack of fixed capacity (the const generic `STACK`; no recursion).
//!    This replaces the paper's sequential stepping between children (the child entered from `side_in` and the
//!    internal partition half-spaces, the next child from `side_out`, the 3-or-4-side exit rule): those rules
//!    assume that the quads' walls partition space, which the *conservative* volumes needed for triangles (item 5
//!    below) no longer do — inflated neighbours overlap. Ordering by the entry parameter gives the same visiting
//!    order where the volumes do not overlap (the zone or quad containing the origin has entry `t_min` and is
//!    visited first; the next one is the one whose wall the ray crosses next), handles a quad the ray enters
//!    twice (one hull over both visits), and is what the no-miss proof below needs. Traversal ends when no
//!    pending quad can be entered before the best hit, or at `t_global_exit`. When the storage gives node
//!    boxes ([`TerrainStorage::node_box`]; beyond the paper), zones and children are tested against those
//!    instead: a box around all of the node's vertices in a local frame ([`boxes`]: its parent's, or the one
//!    its parent's box is in, down from nodes narrow enough to share one), so that the ray is moved into each
//!    frame once and each child costs three slabs — a small fraction of the relaxed test — and, for a node a
//!    few kilometres across, the tighter bound. (A global grid's zones, whose boxes lie in one frame for the
//!    whole grid, are clipped by their volumes too.)
//! 4. **Leaf blocks** (§4): in a leaf, each cell (triangle pair) has its own volume bounded by four *planes*: the
//!    meridian planes of its two columns and, for each of its two rows, the plane through the spheroid normals at
//!    the row's two grid vertices (both normals of one latitude pass through the latitude cone's apex, so they
//!    are coplanar). All four corner vertices lie in that convex volume, so both triangles do — exactly, with no
//!    containment problem at this level — and neighbouring cells share their walls. Only the triangle pairs
//!    whose volume the ray crosses are tested, with the watertight ray–triangle test ([`triangle`]). Beyond the
//!    paper, two shortcuts: at full resolution, away from the axis, a column's row planes are ordered, so only
//!    the rows between those of the column segment's two ends are visited (`crossed_rows` states the bound);
//!    and a cell's two triangles are tested only when the ray's part inside the cell is not wholly above (or
//!    below) its four corners in the unit's local frame — the triangles are their convex hull.
//! 5. **Refinement of the nearest hit** (beyond the paper; once per ray, after the traversal): the traversal's
//!    vertices carry a few ulps of rounding, which a grazing ray amplifies by `1 / sin(elevation)` along itself
//!    (1.4 µm at 0.15° and 150 km in `f64`). The hit triangle's vertices are recomputed in double-double
//!    ([`crate::dd`]) and `t` is taken from its plane, with a containment walk at edge and vertex ties and a
//!    guard that keeps the traversal's `t` if the refinement is not sound (`refine.rs` documents all three).
//!    [`Hit::cell`] and [`Hit::level`] are the traversal's; [`Hit::t`], [`Hit::ecef`] and the geodetic
//!    coordinates are the refined ones. In `f64` the hit point is then within about 1e-9 m of the exact
//!    surface's (the host oracle's worst over 187 000 rays: 3.5e-9 m). The geodetic coordinates come from
//!    [`Ellipsoid::ecef_to_geodetic_near`] seeded at the hit cell's corner vertex (no arctangent or cube root;
//!    the closed form where the seed does not apply). [`Picker::pick_t`] stops before this step.
//!
//! # No misses: what is proven
//!
//! The paper's walls are not walls for triangles: a planar triangle dips below its vertices (so §3.2's sphere
//! through the lowest vertex is not a lower bound) and, along a latitude border, bulges across the cone wall into
//! the neighbouring quad (§4's containment problem, Fig. 10); the paper then stops at the first quad with a hit.
//! Here instead:
//!
//! * every quad's volume provably contains all of its triangles ([`crate::geodesy::HeightQuadBounds`] derives
//!   the sagitta bound for the lower wall and the bulge bound for the latitude walls from the curvature of the
//!   height and cone functions; meridian walls and the upper bound are exact for triangles by convexity), and
//!   the relaxed volume the traversal tests contains those triangles too (each of its planes bounds a cone's
//!   side, on the quad's wedge; [`crate::geodesy::relaxed_interval`]);
//!   A node box ([`boxes`]) contains all of the node's vertices, hence the convex hull of any triangle traced
//!   under it, with no curvature bound needed;
//! * every cell's planar volume contains its two triangles exactly; the rows a column's segment skips lie
//!   beyond the planes it does not cross, and a cell skipped by the height cull has its corners' convex hull
//!   wholly on one side of the ray's part in the cell (both tests inflated by the rounding);
//! * the traversal keeps the best hit `t*` found so far and discards a quad only when its entry parameter exceeds
//!   `t*`, and stops only when no pending quad or zone can start before `t*`.
//!
//! Hence a triangle hit at `t < t*` lies in some quad whose interval contains `t`, which is never discarded, down
//! to its leaf and its cell, which is tested: the returned hit is the **nearest** one (up to the floating-point
//! tolerance of the point tests, which inflate every wall by a few ulps of the coordinates, and the rounding of
//! the triangle test itself). Overlapping inflated volumes only cost extra tests, never a miss. CesiumJS's picking
//! returns the first tile with a hit (its issue #3423); this traversal cannot.
//!
//! # Multi-resolution (§5–§6)
//!
//! A storage may give every node a *block*: the DEM's vertices at a spacing of
//! [`TerrainStorage::block_stride`] grid steps within the node (coarser nodes subsample the finest data; a
//! vertex has one height), resident or not ([`TerrainStorage::is_resident`]). Branches may end at different
//! depths. The defaults (stride 1, always resident) give the single-resolution surface above.
//!
//! **Which blocks are traced.** The traversal descends from the zones. A node shallower than the picker's
//! `min_level` ([`Picker::with_min_level`]) is only passed through, unless it is a leaf: then its own block is
//! traced, or [`TerrainError::NeedsBlock`] is reported if it is missing. From `min_level` on, a resident node
//! becomes the *source*: the nearest resident ancestor of everything below it (§5). A resident leaf traces its
//! own block. Below a missing block the traversal goes on down as long as the source's cells fit inside the
//! children (their ranges fall on the source's sample lattice), so that a deeper resident block still answers
//! for its own region; a missing leaf, or a missing node whose children are smaller than the source's cells, is
//! traced whole with the source's block — the part of the source's block over the node, cells `(r − r_A)/s_A`
//! of the source `A` (the §5 block subset: for a leaf `k` levels below `A`, [`subset::BlockSubset`]'s
//! rectangle after `k` steps, `B >> k` cells wide). So a source cell is never split: where it is larger than
//! the leaves below it (the paper's "at least one cell"), it answers for all of them, and resident blocks
//! inside it are not used. That keeps the traced regions disjoint — a coarse cell never overlaps finer data —
//! so the surface is one sheet. A missing node without a source (at `min_level`), or off its source's lattice,
//! needs its own block.
//!
//! **`NeedsBlock`.** A missing block is reported only if the ray reaches its node before the nearest hit found
//! elsewhere: the answer depends on it. The caller pages the block in and asks again.
//!
//! **Continuity (§6).** Where a region traced with coarse cells borders a finer one, the finer side's vertices
//! on the shared border are T-junctions of the coarse edge, and a ray could pass through the crack between the
//! coarse chord and the finer polyline. The coarse border cell is therefore re-triangulated (the "artificial
//! polygons between blocks" option of §6, as a fan): from the middle `M` of its diagonal `V00–V11` to its
//! corners and to every vertex that a finer neighbouring region has on its sides, side by side. Both sides then
//! share every edge exactly (same vertices, same rounding), so the watertight triangle test lets no ray
//! through. A cell without such vertices keeps its two triangles. The surface intersected is thus: every traced
//! cell's two triangles, except stitched cells, which are their fans. The host's multi-resolution oracle builds
//! exactly this surface with logic of its own. The neighbours' regions come from the same rules, followed down
//! the one path to a neighbouring cell (O(depth) per side of a coarse border cell that the ray crosses).
//! Limitation: a global grid's closing meridian (its last column repeating the first) is treated as an edge of
//! the DEM, with no stitching across it.
//!
//! **Bounds.** A node's volume bounds the coarsest cells traced under it: its own block's (a resident node's
//! descendants are finer), or its source's when it falls back. A stitched cell's vertices on its rows lie on
//! the latitude cones between its meridians, and a cone's arc bulges across the cell's chord plane on one side
//! (the southern side for ψ > 0, the northern for ψ < 0) — near a pole, where a coarse cell can be hundreds of
//! times wider than tall, even across the opposite row's chord plane. So both row walls of a coarse region's
//! border cells bound the whole latitude band in the cell's wedge: the cone's tangent plane along the middle
//! meridian on the convex side, the chord plane on the other.
//!
//! **Refinement.** Coarse and stitched hits are refined like full-resolution ones, without the containment walk
//! (a refined point beyond an edge keeps the traversal's hit), and the walk of a full-resolution hit steps only
//! into cells traced at full resolution. [`Hit::level`] and [`Hit::stride`] say which block answered.
//!
//! # Cost
//!
//! Per child of a visited quad, only along the part of the ray inside the parent: with node boxes, three slabs
//! (the ray is rotated into each frame once: on a regional DEM once per zone or per ray); without them, the
//! child's walls on the parent's internal partition: the internal meridian plane (a division), then the rest of
//! the relaxed volume (the internal latitude plane, the upper spheroid, the lower sphere), each step only if the
//! interval is still non-empty.
//! Per leaf: a clip against two meridian planes per column (columns the ray misses are skipped), the rows the
//! column's segment can cross (a few plane signs from the previous column's row), two row planes per such
//! cell, the height cull, and the triangle test for what is left. No trigonometry is needed per ray when the
//! storage caches the sines and cosines of its rows and columns ([`TerrainStorage::row_sin_cos`]) and, for the
//! refinement, their double-double parallels and meridians ([`TerrainStorage::row_parallel`]); the prime
//! vertical radius is computed once per row of a leaf. [`PickStats`] counts quads, triangle pairs (cells whose
//! planar volume the ray crosses) and triangles tested per ray.
//!
//! ```
//! use curvicast::geodesy::Ellipsoid;
//! use curvicast::ray::Ray;
//! use curvicast::terrain::{Grid, Node, NodeId, Picker, TerrainStorage};
//!
//! /// A 3 × 3-vertex DEM near (10°N, 20°E) with one raised vertex, as one zone that is also a leaf.
//! struct Tiny([f64; 9]);
//! impl TerrainStorage<f64> for Tiny {
//!     fn ellipsoid(&self) -> Ellipsoid<f64> { Ellipsoid::wgs84() }
//!     fn grid(&self) -> Grid<f64> {
//!         Grid { lat0: 10.0, lon0: 20.0, dlat: 0.01, dlon: 0.01, rows: 3, cols: 3 }
//!     }
//!     fn zone_count(&self) -> usize { 1 }
//!     fn zone(&self, k: usize) -> Option<NodeId> { (k == 0).then_some(NodeId(0)) }
//!     fn node(&self, id: NodeId) -> Option<Node<f64>> {
//!         (id == NodeId(0)).then_some(Node {
//!             rows: [0, 2], cols: [0, 2], heights: Some([0.0, 500.0]), children: [None; 4], level: 0,
//!         })
//!     }
//!     fn height(&self, i: u32, j: u32) -> Option<f64> {
//!         self.0.get(usize::try_from(i * 3 + j).ok()?).copied()
//!     }
//! }
//!
//! let dem = Tiny([0.0, 0.0, 0.0, 0.0, 500.0, 0.0, 0.0, 0.0, 0.0]);
//! let picker: Picker<'_, f64, Tiny> = Picker::new(&dem)?;
//! let e = Ellipsoid::<f64>::wgs84();
//! // Straight down onto the raised center vertex from 10 km.
//! let top = e.geodetic_deg_to_ecef(10.01, 20.01, 10_000.0);
//! let down = e.normal(10.01_f64.to_radians(), 20.01_f64.to_radians()).negated();
//! let hit = picker.pick(&Ray::new(top, down)?)?.expect("the peak is below");
//! assert!((hit.t - 9_500.0).abs() < 1e-6 && (hit.h - 500.0).abs() < 1e-6);
//! assert_eq!(hit.level, 0);
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

pub mod boxes;
pub mod build;
mod refine;
mod storage;
pub mod subset;
pub mod triangle;

pub use refine::{col_sin_cos_dd, row_parallel};
pub use storage::{
    DEFAULT_ZONE_COLS, DEFAULT_ZONE_ROWS, Grid, Node, NodeId, TerrainStorage, vertex_ecef,
    zone_cells,
};

use crate::geodesy::{
    Ellipsoid, GeodesyError, HeightQuadBounds, QuadTrig, RelaxedVolume, SideWalls, clip_half_space,
    insertion_sort, relaxed_interval, sin_cos_deg, upper_spheroid,
};
use crate::ray::{Ray, RayError};
use crate::real::Real;
use crate::surface::{Side, Spheroid, Surface};
use crate::vec3::V3;
use boxes::{FrameRay, LocalFrame, NodeBox};
use core::cell::Cell;
use refine::{Tri, Vtx};
use triangle::WatertightRay;

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
}

impl core::fmt::Display for TerrainError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TerrainError::Ray(e) => write!(f, "invalid ray: {e}"),
            TerrainError::Geodesy(e) => write!(f, "invalid terrain bound: {e}"),
            TerrainError::InvalidGrid => f.write_str("invalid DEM grid"),
            TerrainError::MalformedTree => f.write_str("malformed terrain quadtree"),
            TerrainError::TooManyZones => f.write_str("more zones than the picker's capacity"),
            TerrainError::StackFull => {
                f.write_str("traversal stack full (tree deeper than capacity)")
            }
            TerrainError::TraversalBound => f.write_str("traversal exceeded its node bound"),
            TerrainError::NeedsBlock(id) => write!(f, "needs the block of node {}", id.0),
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
    /// per coordinate (so it may differ from `ray.at(t)` by the rounding of `t·dir`; module docs, step 5).
    pub ecef: [T; 3],
    /// Geodetic latitude of the hit point, degrees.
    pub lat: T,
    /// Longitude of the hit point, degrees in [−180, 180].
    pub lon: T,
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

/// What the traversal does at a node (module docs, "Multi-resolution").
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
        let mut width = grid.dlon.abs() * T::HALF;
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
                span(grid.cell_rows(), grid.dlat) < lim && span(grid.cell_cols(), grid.dlon) < lim
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
                    grid.dlat * picker.scale(stride),
                    grid.dlon * picker.scale(stride),
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

    /// The picker with another `min_level` (seed 000 §5): blocks of nodes shallower than `min_level` never stand
    /// in for missing finer ones. 0 (the default) uses whatever is resident; the tree's depth asks for the
    /// finest blocks only. The module docs ("Multi-resolution") give the rules.
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

    /// The nearest hit of `ray` with the terrain for `t_min ≤ t ≤ t_max`, or `None` (seed 000 §3.5, §4; the
    /// module docs state what is proven).
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
    ///         Grid { lat0: -17.0, lon0: 179.99, dlat: 0.01, dlon: 0.01, rows: 3, cols: 3 }
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
    /// let down = e.normal((-16.99_f64).to_radians(), 180.0_f64.to_radians()).negated();
    /// let hit = picker.pick(&Ray::new(from, down)?)?.ok_or("no hit")?;
    /// assert!((hit.t - 1000.0).abs() < 1e-6 && (hit.h - 100.0).abs() < 1e-6);
    /// assert!((hit.lon.abs() - 180.0).abs() < 1e-9 && hit.cell[1] <= 1);
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
        Ok(self.nearest(ray, stats)?.map(|c| self.make_hit(ray, c)))
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
    /// #         Grid { lat0: -17.0, lon0: 179.99, dlat: 0.01, dlon: 0.01, rows: 3, cols: 3 }
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
    /// let ray = Ray::new(from, e.normal((-16.99_f64).to_radians(), 180.0_f64.to_radians()).negated())?;
    /// let (t, cell) = picker.pick_t(&ray)?.ok_or("no hit")?;
    /// let hit = picker.pick(&ray)?.ok_or("no hit")?;
    /// assert!((t - 1000.0).abs() < 1e-6 && cell == hit.cell);
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn pick_t(&self, ray: &Ray<T>) -> Result<Option<(T, [u32; 2])>, TerrainError> {
        let mut stats = PickStats::default();
        Ok(self.nearest(ray, &mut stats)?.map(|c| (c.t, c.cell)))
    }

    /// The traversal (steps 1–4 of the module docs): the nearest triangle, before the refinement.
    fn nearest(
        &self,
        ray: &Ray<T>,
        stats: &mut PickStats,
    ) -> Result<Option<Candidate<T>>, TerrainError> {
        // 1. Global clip to B^{h_max}: [t_enter, t_global_exit].
        let Some(upper) = &self.upper else {
            return Ok(None); // no zone with data
        };
        let cr = upper.crossings(ray);
        let inside0 = upper.side_of(V3::from(ray.at(ray.t_min()))) != Some(Side::Positive);
        let mut t_enter = if inside0 { Some(ray.t_min()) } else { None };
        let mut t_exit = ray.t_max();
        for c in &cr {
            match c.into {
                Side::Negative => {
                    if t_enter.is_none() {
                        t_enter = Some(c.t);
                    }
                }
                Side::Positive => {
                    if t_enter.is_some() {
                        t_exit = c.t;
                    }
                }
            }
        }
        let Some(t_enter) = t_enter else {
            return Ok(None);
        };
        // Inflate the clip by a few ulps: the triangle test decides hits, the clip only culls.
        let slack = T::from_f64(64.0) * T::EPSILON * (t_enter.abs() + t_exit.abs());
        let t_lo = (t_enter - slack).max(ray.t_min());
        let t_hi = (t_exit + slack).min(ray.t_max());
        if !t_hi.is_finite() || !(t_lo <= t_hi) {
            return Ok(None);
        }
        let clipped = ray.with_interval(t_lo, t_hi)?;
        let wray = WatertightRay::new(ray.origin(), ray.dir())
            .ok_or(TerrainError::Ray(RayError::ZeroDirection))?;

        // 2. Zones in order of entry.
        let mut order: heapless::Vec<(usize, T, T), ZONES> = heapless::Vec::new();
        let grid_ray = self.grid_frame.ray(ray, [t_lo, t_hi]);
        for (k, bbox) in self.zone_boxes.iter().enumerate().take(self.zone_count) {
            let volume = |r: &Ray<T>| match self.zones.get(k) {
                Some(Some((_, _, ZoneVolume::Cached(b)))) => b.ray_interval(r),
                Some(Some((_, _, ZoneVolume::Relaxed(v)))) => v.interval(r),
                _ => None,
            };
            // The box in the grid's frame is tight for a regional grid; across a global one its faces tilt by up
            // to 180°, so the zone's own volume then clips what the box leaves.
            let interval = match bbox {
                Some(b) if self.regional => grid_ray.interval(b, [t_lo, t_hi]),
                Some(b) => grid_ray
                    .interval(b, [t_lo, t_hi])
                    .and_then(|(a, c)| clipped.with_interval(a, c).ok())
                    .and_then(|r| volume(&r)),
                None => volume(&clipped),
            };
            if let Some((a, c)) = interval {
                // At most `ZONES` zones (checked by `new`), so the push cannot fail.
                let _ = order.push((k, a, c));
            }
        }
        insertion_sort(&mut order, |x, y| x.1 < y.1);

        let mut best: Option<Candidate<T>> = None;
        let mut pending: Option<(T, NodeId)> = None;
        let mut budget = node_budget(&self.grid, self.zone_count);
        for &(k, a, c) in order.iter() {
            if let Some(h) = &best {
                if a > h.t {
                    break;
                }
            }
            let Some(Some((id, _, _))) = self.zones.get(k) else {
                continue;
            };
            let root = Entry {
                id: *id,
                parent: None,
                t_in: a,
                t_out: c,
                parent_stride: u32::MAX,
                src: None,
                frame: 0,
                depth: 0,
            };
            let mut walk = Walk {
                ray,
                wray: &wray,
                best: &mut best,
                pending: &mut pending,
                stats,
            };
            self.traverse(root, &grid_ray, &mut walk, &mut budget)?;
        }
        // A missing block matters only if it could hold a hit before the nearest one found.
        match (pending, &best) {
            (Some((t, id)), Some(h)) if t <= h.t => Err(TerrainError::NeedsBlock(id)),
            (Some((_, id)), None) => Err(TerrainError::NeedsBlock(id)),
            _ => Ok(best),
        }
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
        Ok(self.nearest(&seg, &mut stats)?.is_none())
    }

    /// Depth-first, nearest-child-first traversal of one zone with an explicit stack. `grid_ray` is the ray in
    /// the grid's frame, where the zones' boxes are.
    ///
    /// With node boxes, the ray is moved into each frame that boxes are in once ([`boxes`], "Which frame"): a
    /// node's own frame is kept at index `depth + 1` of an array of frames and its children's entries refer to
    /// the index their boxes were tested in ([`Entry::frame`]). Only nodes at depth `d` write index `d + 1`
    /// (below it they only fill slots that no entry refers to), and a node at depth `d` is visited only after
    /// the whole subtree of every node visited before it at depth `d` or deeper (those were pushed above it on
    /// the stack, or descend from nodes that were): so no pending entry still refers to the index it overwrites.
    // Out of line (like `trace_unit` and `crossed_rows`): inlined into `nearest`, the three cost about 5 % more
    // instructions per pick (callgrind).
    #[inline(never)]
    fn traverse(
        &self,
        root: Entry<T>,
        grid_ray: &FrameRay<T>,
        w: &mut Walk<'_, '_, T>,
        budget: &mut u64,
    ) -> Result<(), TerrainError> {
        let ray = w.ray;
        let mut stack: heapless::Vec<Entry<T>, STACK> = heapless::Vec::new();
        stack.push(root).map_err(|_| TerrainError::StackFull)?;
        let mut frames: heapless::Vec<FrameRay<T>, FRAMES> = heapless::Vec::new();
        frames
            .push(*grid_ray)
            .map_err(|_| TerrainError::StackFull)?;
        while let Some(e) = stack.pop() {
            let best_t = w.best_t();
            if e.t_in > best_t {
                continue;
            }
            *budget = budget.checked_sub(1).ok_or(TerrainError::TraversalBound)?;
            let node = self.storage.node(e.id).ok_or(TerrainError::MalformedTree)?;
            if let Some((rows, cols)) = e.parent {
                check_child(rows, cols, &node)?;
            }
            let stride = self.stride_of(e.id, e.parent_stride)?;
            if node.heights.is_none() {
                continue;
            }
            w.stats.quads_visited = w.stats.quads_visited.saturating_add(1);
            let t_out = e.t_out.min(best_t);
            let src = match self.step(e.id, &node, stride, e.src)? {
                Step::Trace(unit) => {
                    self.trace_unit(&unit, e.t_in, t_out, w)?;
                    continue;
                }
                Step::Needs => {
                    w.need(e.t_in, e.id);
                    continue;
                }
                Step::Descend(src) => src,
            };
            // Children go straight onto the stack, then are sorted there, nearest entry on top.
            let span = [e.t_in.max(ray.t_min()), t_out.max(e.t_in).min(ray.t_max())];
            let first = stack.len();
            let depth = e.depth.checked_add(1).ok_or(TerrainError::StackFull)?;
            // This node's own frame, at index `depth` once a child's box needs it.
            let mut own_ready = false;
            for cid in node.children.iter().flatten() {
                let (interval, frame) = match self.storage.node_box(*cid) {
                    // The box holds all of the child's vertices, so every triangle traced under it.
                    Some(b) => {
                        let k = if b.shared_frame { e.frame } else { depth };
                        if !b.shared_frame && !own_ready {
                            let own = usize::from(depth);
                            frames.truncate(own);
                            while frames.len() < own {
                                // Filler below the own frame, never referred to.
                                let last = *frames.last().ok_or(TerrainError::MalformedTree)?;
                                frames.push(last).map_err(|_| TerrainError::StackFull)?;
                            }
                            let f = LocalFrame::of(self.storage, &self.ellipsoid, &node);
                            frames
                                .push(f.ray(ray, span))
                                .map_err(|_| TerrainError::StackFull)?;
                            own_ready = true;
                        }
                        let f = frames
                            .get(usize::from(k))
                            .ok_or(TerrainError::MalformedTree)?;
                        (f.interval(&b, span), k)
                    }
                    None => {
                        let child = self.storage.node(*cid).ok_or(TerrainError::MalformedTree)?;
                        check_child(node.rows, node.cols, &child)?;
                        let Some([lo, hi]) = child.heights else {
                            continue;
                        };
                        let c_stride = self.stride_of(*cid, stride)?;
                        let [a, c] = span;
                        let sub = ray.with_interval(a, c)?;
                        let v =
                            self.volume_interval(*cid, &child, &node, c_stride, src, lo, hi, &sub)?;
                        (v, e.frame)
                    }
                };
                if let Some((t_in, t_out)) = interval {
                    let child = Entry {
                        id: *cid,
                        parent: Some((node.rows, node.cols)),
                        t_in,
                        t_out,
                        parent_stride: stride,
                        src,
                        frame,
                        depth,
                    };
                    stack.push(child).map_err(|_| TerrainError::StackFull)?;
                }
            }
            let kids = stack.get_mut(first..).unwrap_or(&mut []);
            insertion_sort(kids, |x, y| x.t_in > y.t_in);
        }
        Ok(())
    }

    /// The hull of `sub` in a child's spheroidal volume (a storage without node boxes): the storage's cached
    /// volume or the relaxed test, from its walls on the parent's partition. The volume bounds the coarsest
    /// cells traced under the child: its own block's, or the source's when the child falls back to it.
    #[allow(clippy::too_many_arguments)]
    fn volume_interval(
        &self,
        id: NodeId,
        child: &Node<T>,
        parent: &Node<T>,
        stride: u32,
        src: Option<Source>,
        lo: T,
        hi: T,
        sub: &Ray<T>,
    ) -> Result<Option<(T, T)>, TerrainError> {
        let falls_back = child.level >= self.min_level && !self.storage.is_resident(id);
        let vol = match src {
            Some(s) if falls_back => s.stride,
            _ => stride,
        };
        if let Some(b) = self.storage.cached_bounds(id).filter(|_| vol == 1) {
            return Ok(b.ray_interval(sub));
        }
        Ok(relaxed_interval(
            &self.ellipsoid,
            &node_trig(
                &self.grid,
                self.storage,
                child,
                Some(parent),
                self.half_cell(vol).1,
            ),
            lo,
            hi,
            self.grid.dlat * self.scale(vol),
            self.grid.dlon * self.scale(vol),
            sub,
        )?)
    }

    /// What to do at a node (module docs, "Multi-resolution"): `stride` is its block stride, `src` the source
    /// inherited from its parent.
    #[inline(always)]
    fn step(
        &self,
        id: NodeId,
        node: &Node<T>,
        stride: u32,
        src: Option<Source>,
    ) -> Result<Step, TerrainError> {
        let own = Unit {
            rows: node.rows,
            cols: node.cols,
            stride,
            level: node.level,
        };
        let resident = self.storage.is_resident(id);
        if node.level < self.min_level {
            // Above min_level a block is used only by a leaf, for itself.
            return Ok(match (node.is_leaf(), resident) {
                (false, _) => Step::Descend(None),
                (true, true) => Step::Trace(self.aligned(own).ok_or(TerrainError::MalformedTree)?),
                (true, false) => Step::Needs,
            });
        }
        if resident {
            return Ok(if node.is_leaf() {
                Step::Trace(self.aligned(own).ok_or(TerrainError::MalformedTree)?)
            } else {
                Step::Descend(Some(Source {
                    stride,
                    level: node.level,
                }))
            });
        }
        // Not resident. Without a source its own block is needed. With one, the traversal goes on down while the
        // source's cells fit inside the children (a deeper resident block may answer there); otherwise the node
        // is traced whole with the source's block: the subset that covers it (§5), on the source's lattice
        // (if not, its own block is needed).
        let Some(s) = src else {
            return Ok(Step::Needs);
        };
        if !node.is_leaf() && self.children_on_lattice(node, s.stride)? {
            return Ok(Step::Descend(src));
        }
        Ok(self
            .aligned(Unit {
                stride: s.stride,
                level: s.level,
                ..own
            })
            .map_or(Step::Needs, Step::Trace))
    }

    /// Whether every child with data of `node` has ranges on the lattice of `stride`.
    fn children_on_lattice(&self, node: &Node<T>, stride: u32) -> Result<bool, TerrainError> {
        for cid in node.children.iter().flatten() {
            let c = self.storage.node(*cid).ok_or(TerrainError::MalformedTree)?;
            let on = self
                .aligned(Unit {
                    rows: c.rows,
                    cols: c.cols,
                    stride,
                    level: c.level,
                })
                .is_some();
            if c.heights.is_some() && !on {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The unit if its ranges start on multiples of its stride and end on one or at the grid's last cell.
    fn aligned(&self, u: Unit) -> Option<Unit> {
        if u.stride == 1 {
            return Some(u);
        }
        let fits = |r: [u32; 2], last: u32| {
            let [a, b] = r;
            a.checked_rem(u.stride) == Some(0) && (b.checked_rem(u.stride) == Some(0) || b == last)
        };
        (fits(u.rows, self.grid.cell_rows()) && fits(u.cols, self.grid.cell_cols())).then_some(u)
    }

    /// The traced unit that covers grid cell `(i, j)` under the current residency: the traversal's own rules,
    /// followed down the one path that holds the cell.
    fn unit_at(&self, i: u32, j: u32) -> Result<Lookup, TerrainError> {
        let holds = |n: &Node<T>| {
            (n.rows[0]..n.rows[1]).contains(&i) && (n.cols[0]..n.cols[1]).contains(&j)
        };
        let Some((mut id, mut node)) = self
            .zones
            .iter()
            .take(self.zone_count)
            .flatten()
            .find(|(_, n, _)| holds(n))
            .map(|(id, n, _)| (*id, *n))
        else {
            return Ok(Lookup::Empty);
        };
        let mut stride = self.stride_of(id, u32::MAX)?;
        let mut src = None;
        // Children are strictly smaller, so a path has at most 64 nodes within u32 ranges.
        for _ in 0..64 {
            match self.step(id, &node, stride, src)? {
                Step::Trace(u) => return Ok(Lookup::Unit(u)),
                Step::Needs => return Ok(Lookup::Needs(id)),
                Step::Descend(s) => src = s,
            }
            let mut next = None;
            for cid in node.children.iter().flatten() {
                let child = self.storage.node(*cid).ok_or(TerrainError::MalformedTree)?;
                if holds(&child) {
                    check_child(node.rows, node.cols, &child)?;
                    next = Some((*cid, child));
                    break;
                }
            }
            let Some((cid, child)) = next else {
                return Ok(Lookup::Empty);
            };
            if child.heights.is_none() {
                return Ok(Lookup::Empty);
            }
            stride = self.stride_of(cid, stride)?;
            (id, node) = (cid, child);
        }
        Err(TerrainError::TraversalBound)
    }

    /// Traces the cells of a unit (§4; §5 for a coarser block): clip per column of cells against its meridian
    /// planes, per cell against its two row planes (planes through the spheroid normals at the cell's corner
    /// vertices), then the watertight test. A coarse cell on the unit's border whose neighbour is finer is
    /// stitched to it (module docs, "Multi-resolution").
    #[inline(never)]
    fn trace_unit(
        &self,
        u: &Unit,
        t_in: T,
        t_out: T,
        w: &mut Walk<'_, '_, T>,
    ) -> Result<(), TerrainError> {
        let g = &self.grid;
        let e = &self.ellipsoid;
        let ray = w.ray;
        let o = ray.origin();
        let d = ray.dir();
        let tau = T::from_f64(64.0) * T::EPSILON;
        let s = u.stride;
        let [r0, r1] = u.rows;
        let [c0, c1] = u.cols;
        let step = |i: u32, end: u32| i.saturating_add(s).min(end);
        let north_up = g.dlat > T::ZERO;
        // Per-unit cache of the lattice rows' values (sin ψ, cos ψ, cone apex k, prime vertical radius N) for
        // units up to ROW_CACHE − 1 cells tall, filled as rows are first asked for (a ray from above needs few).
        let rows_cache: [Cell<Option<RowValues<T>>>; ROW_CACHE] =
            core::array::from_fn(|_| Cell::new(None));
        let n_rows = div_ceil_pow2(r1.saturating_sub(r0), s);
        let row_vals = |i: u32| -> RowValues<T> {
            let (sp, cp) = self.storage.row_sin_cos(i);
            (
                sp,
                cp,
                e.latitude_cone_apex(sp),
                e.prime_vertical_radius(sp),
            )
        };
        // Strides are powers of two: lattice row k·s is entry k, the last row entry n_rows.
        let shift = s.trailing_zeros();
        let mask = s.wrapping_sub(1);
        let row_at = |i: u32| -> RowValues<T> {
            let k = i.wrapping_sub(r0);
            let entry = if k & mask == 0 {
                k.wrapping_shr(shift)
            } else if i == r1 {
                n_rows
            } else {
                u32::MAX
            };
            let Some(slot) = usize::try_from(entry).ok().and_then(|k| rows_cache.get(k)) else {
                return row_vals(i);
            };
            slot.get().unwrap_or_else(|| {
                let v = row_vals(i);
                slot.set(Some(v));
                v
            })
        };
        let stitchable = s > 1;
        // Height cull (beyond the paper): in the unit's local frame, a cell whose part of the ray lies wholly
        // above (or below) its four corners' up coordinates cannot meet its triangles, the convex hulls of those
        // corners. The tolerance covers the rounding of both sides' up coordinates, like the node boxes'.
        let frame = LocalFrame::of_ranges(self.storage, e, u.rows, u.cols);
        let (z0, zd) = (frame.up(o), frame.up_dir(d));
        let z_tol = T::from_f64(32.0)
            * T::EPSILON
            * ((o.x.abs() + o.y.abs() + o.z.abs())
                + t_in.abs().max(t_out.abs()) * (d.x.abs() + d.y.abs() + d.z.abs())
                + e.a());
        let (k_first, k_end) = self.unit_columns(u, ray, t_in, t_out);
        // The cell row last located by `crossed_rows` in this unit, and the sign of the azimuth's rate along the
        // ray, (o × d)_z.
        let mut row_hint = None;
        let az_rate = o.x * d.y - o.y * d.x;
        for k in k_first..k_end {
            let j = c0.saturating_add(k.saturating_mul(s));
            let j1 = step(j, c1);
            let (sw, cw) = self.storage.col_sin_cos(j);
            let (se, ce) = self.storage.col_sin_cos(j1);
            let (s_half, c_half) = if j1.saturating_sub(j) == s {
                self.half_cell(s)
            } else {
                sin_cos_deg(g.dlon * T::HALF * self.scale(j1.saturating_sub(j)))
            };
            // The cell's middle meridian λ_j + w/2 by the addition theorem (a few ulps; the row plane only
            // needs its direction, and the vertices' rounding is covered by `tau`).
            let (sm, cm) = (sw * c_half + cw * s_half, cw * c_half - sw * s_half);
            let mut lo = t_in;
            let mut hi = t_out.min(w.best_t());
            // West wall: n_w·P ≥ 0, n_w = (−sin λ_w, cos λ_w, 0); east wall: n_e·P ≤ 0.
            let mag = (o.x.abs() + o.y.abs()) + (d.x.abs() + d.y.abs()) * (lo.abs().max(hi.abs()));
            let tol = tau * mag;
            clip_half_space(
                &mut lo,
                &mut hi,
                cw * o.y - sw * o.x,
                cw * d.y - sw * d.x,
                tol,
            );
            clip_half_space(
                &mut lo,
                &mut hi,
                -(ce * o.y - se * o.x),
                -(ce * d.y - se * d.x),
                tol,
            );
            if !(lo <= hi) {
                continue;
            }
            // Row plane i at this column: m = (−sin ψ cos λm, −sin ψ sin λm, cos ψ cos(w/2)), through (0,0,k_i);
            // m·(P − k ẑ) > 0 is north of it. With `tangent`, cos(w/2) is replaced by 1: the plane tangent to
            // the latitude cone along the middle meridian, which bounds the cone's arc over the cell from the
            // other side (stitched sides). The parts that do not depend on the row are formed once per column.
            let (radial_o, radial_d) = (cm * o.x + sm * o.y, cm * d.x + sm * d.y);
            let mag = o.x.abs()
                + o.y.abs()
                + (d.x.abs() + d.y.abs() + d.z.abs()) * (lo.abs().max(hi.abs()));
            let row_plane = |i: u32, tangent: bool| -> (T, T, T) {
                let (sp, cp, kz, _) = row_at(i);
                let ch = if tangent { T::ONE } else { c_half };
                let qz = o.z - kz;
                (
                    cp * ch * qz - sp * radial_o,
                    cp * ch * d.z - sp * radial_d,
                    tau * (mag + qz.abs()),
                )
            };
            // A border cell of a coarse unit may be stitched: vertices of a finer neighbour on its rows lie on
            // the latitude cones between its meridians, and near a pole a cell far wider than tall has cone arcs
            // that sag across even the opposite row's chord plane. So both row walls of such a cell bound the
            // whole latitude band in the wedge: the chord plane where the band lies on its concave side (a
            // northern wall with ψ > 0, a southern one with ψ < 0), the tangent plane along the middle meridian
            // where it lies on the convex side (a southern wall with ψ > 0, a northern one with ψ < 0).
            let border_plane = |i: u32, low: bool| -> (T, T, T) {
                let south = low == north_up;
                let sp = row_at(i).0;
                row_plane(i, (south && sp > T::ZERO) || (!south && sp < T::ZERO))
            };
            // At full resolution only the rows between those of the column segment's two ends are crossed
            // (`crossed_rows`); coarse units, whose border cells have band walls, trace every row.
            let (first_row, end_row) = if stitchable {
                (r0, r1)
            } else {
                self.crossed_rows(
                    u,
                    [lo, hi],
                    (radial_o, radial_d),
                    az_rate,
                    // `row_plane(i, false)` at `t`, without its tolerance (formed inline: the unused
                    // tolerance is not optimised away and costs 3 % of a camera pick).
                    &|i, t| {
                        let (sp, cp, kz, _) = row_at(i);
                        cp * c_half * (o.z - kz) - sp * radial_o
                            + t * (cp * c_half * d.z - sp * radial_d)
                    },
                    &mut row_hint,
                )
            };
            let mut plane_a = row_plane(first_row, false);
            // The northern (higher-row) corners of the last cell traced in this column, reused as the next
            // cell's southern ones.
            let mut shared: Option<RowCorners<T>> = None;
            let mut i = first_row;
            while i < end_row {
                let i1 = step(i, r1);
                let plane_b = row_plane(i1, false);
                let mut low = plane_a;
                let mut high = plane_b;
                plane_a = plane_b;
                let (row_i, row_i1) = (i, i1);
                i = i1;
                let border = row_i == r0 || row_i1 == r1 || j == c0 || j1 == c1;
                if stitchable && border {
                    low = border_plane(row_i, true);
                    high = border_plane(row_i1, false);
                }
                let (mut clo, mut chi) = (lo, hi.min(w.best_t()));
                // The cell lies north of its southern row plane and south of its northern one.
                let (south, north) = if north_up { (low, high) } else { (high, low) };
                clip_half_space(&mut clo, &mut chi, south.0, south.1, south.2);
                clip_half_space(&mut clo, &mut chi, -north.0, -north.1, north.2);
                if !(clo <= chi) {
                    continue;
                }
                w.stats.triangle_pairs_visited = w.stats.triangle_pairs_visited.saturating_add(1);
                // Vertex (ii, jj) of this column's west (jj = j) or east (jj = j1) meridian.
                let vtx = |ii: u32, jj: u32, (s_lon, c_lon): (T, T)| -> Option<V3<T>> {
                    let h = self.storage.height(ii, jj)?;
                    if !h.is_finite() {
                        return None;
                    }
                    let (sl, cl, _, n) = row_at(ii);
                    Some(e.ecef_from_parts(sl, cl, n, s_lon, c_lon, h))
                };
                let cell = CellAt {
                    rows: [row_i, row_i1],
                    cols: [j, j1],
                };
                let reuse = shared.filter(|(r, _, _)| *r == row_i);
                let v00 = reuse.map_or_else(|| vtx(row_i, j, (sw, cw)), |(_, a, _)| a);
                let v11 = vtx(row_i1, j1, (se, ce));
                if stitchable && border {
                    match self.stitch(u, &cell, v00, v11, w, clo)? {
                        Stitch::Done => continue,
                        Stitch::Plain => {}
                    }
                }
                let v01 = reuse.map_or_else(|| vtx(row_i, j1, (se, ce)), |(_, _, b)| b);
                let v10 = vtx(row_i1, j, (sw, cw));
                shared = Some((row_i1, v10, v11));
                let (mut z_min, mut z_max) = (T::INFINITY, T::NEG_INFINITY);
                for v in [v00, v01, v10, v11].iter().flatten() {
                    let z = frame.up(*v);
                    z_min = z_min.min(z);
                    z_max = z_max.max(z);
                }
                let (za, zb) = (z0 + clo * zd, z0 + chi * zd);
                if za.min(zb) > z_max + z_tol || za.max(zb) < z_min - z_tol {
                    continue;
                }
                let refs = |first: bool| {
                    if s == 1 {
                        TriRef::Cell(if first { Tri::First } else { Tri::Second })
                    } else if first {
                        TriRef::Vertices([
                            Vtx::Grid(row_i, j),
                            Vtx::Grid(row_i, j1),
                            Vtx::Grid(row_i1, j1),
                        ])
                    } else {
                        TriRef::Vertices([
                            Vtx::Grid(row_i, j),
                            Vtx::Grid(row_i1, j1),
                            Vtx::Grid(row_i1, j),
                        ])
                    }
                };
                // The edges with no triangle across (triangle.rs, "Edges on the border of the surface"), asked
                // only when the ray passes within rounding outside one. Captured by value (a reference would
                // keep these locals in memory through the column loop).
                if let (Some(a), Some(b), Some(c)) = (v00, v01, v11) {
                    let no_second = v10.is_none();
                    let border = move || self.border_edges(cell, s, true, no_second);
                    self.test_triangle(w, [a, b, c], [row_i, j], refs(true), u, border);
                }
                if let (Some(a), Some(b), Some(c)) = (v00, v11, v10) {
                    let no_first = v01.is_none();
                    let border = move || self.border_edges(cell, s, false, no_first);
                    self.test_triangle(w, [a, b, c], [row_i, j], refs(false), u, border);
                }
            }
        }
        Ok(())
    }

    /// The cell rows `[first, end)` of a full-resolution unit that the ray can cross within one column on
    /// `[lo, hi]` (beyond the paper: the row loop skips the rest). The column's row planes all contain the
    /// direction perpendicular to its middle meridian, so each is a line `z = k + r tan ψ / cos(w/2)` in the
    /// `(r, z)` half-plane, `r` the distance from the axis along the middle meridian. Two such lines meet at
    /// `r* = Δk / Δ(tan ψ / cos(w/2))`; since `dk/dψ = −e² cos ψ (N + N' tan ψ)`, `r*` is at most
    /// `e² N cos³ψ (1 + e² N² sin²ψ / a²) ≤ e² (a²/b)(1 + e² a²/b²)` (43 km on WGS84). Beyond twice that the
    /// planes are ordered, so along a segment that stays there (`r` is linear in `t`: both ends are checked)
    /// the ray crosses each plane at most once and in order: the crossed cells are those between the cells of
    /// its two ends. Each end's cell comes from a binary search over the planes' sides; a side decided wrongly by
    /// rounding puts the end within a rounding distance of that plane, so one row of margin on each side
    /// covers it. Elsewhere (near the axis) every row is returned.
    #[inline(never)]
    fn crossed_rows(
        &self,
        u: &Unit,
        [lo, hi]: [T; 2],
        (radial_o, radial_d): (T, T),
        az_rate: T,
        plane: &impl Fn(u32, T) -> T,
        hint: &mut Option<i64>,
    ) -> (u32, u32) {
        let [r0, r1] = u.rows;
        let r_order = self.rows_ordered_beyond;
        let ordered = radial_o + lo * radial_d > r_order && radial_o + hi * radial_d > r_order;
        if !(ordered && lo.is_finite() && hi.is_finite()) {
            return (r0, r1);
        }
        // The cell containing the point at `t`: the last plane i in [r0, r1] that the point lies on the
        // increasing-row side of (rows increase northwards when dlat > 0), or r0 − 1 (before the unit).
        let north_up = self.grid.dlat > T::ZERO;
        let (first_plane, last_plane) = (i64::from(r0), i64::from(r1));
        let cell_of = |t: T, hint: Option<i64>| -> i64 {
            // Whether the point lies past plane i (true before the unit's first plane, false after its last).
            let after = |i: i64| {
                if i < first_plane {
                    return true;
                }
                let Some(i) = u32::try_from(i).ok().filter(|&i| i <= r1) else {
                    return false;
                };
                let north = plane(i, t) >= T::ZERO;
                north == north_up
            };
            // From the hint (the cell found last in this unit: the ray crosses few rows per column), a few
            // steps; else a binary search. The answer a: after(a), !after(a + 1), a in [r0 − 1, r1].
            if let Some(h) = hint {
                let mut a = h.max(first_plane.saturating_sub(1)).min(last_plane);
                for _ in 0..4 {
                    if !after(a) {
                        a = a.saturating_sub(1);
                    } else if after(a.saturating_add(1)) {
                        a = a.saturating_add(1);
                    } else {
                        return a;
                    }
                }
            }
            let (mut a, mut b) = (first_plane.saturating_sub(1), last_plane);
            while a < b {
                let m = a.saturating_add(b.saturating_sub(a).saturating_add(1).wrapping_shr(1));
                if after(m) {
                    a = m;
                } else {
                    b = m.saturating_sub(1);
                }
            }
            a
        };
        // The end on the column's western meridian first: it is shared with the previous column, whose eastern
        // end is the hint (longitude grows along the ray when (o × d)_z > 0).
        let east_at_hi = az_rate > T::ZERO;
        let (t_west, t_east) = if east_at_hi { (lo, hi) } else { (hi, lo) };
        let ca = cell_of(t_west, *hint);
        let cb = cell_of(t_east, Some(ca));
        *hint = Some(cb);
        let first = ca.min(cb).saturating_sub(1).max(i64::from(r0));
        let end = ca.max(cb).saturating_add(2).min(i64::from(r1));
        match (u32::try_from(first), u32::try_from(end)) {
            (Ok(f), Ok(e)) if f <= e => (f, e),
            _ => (r0, r0),
        }
    }

    /// Which edges of a traced cell's first (`first`) or second triangle have no triangle across (triangle.rs,
    /// "Edges on the border of the surface"), in the order `b–c`, `c–a`, `a–b` of its vertices: the diagonal
    /// when the cell's other triangle is missing (`other_missing`), a side when it is on the grid's edge or
    /// when the third vertex of the triangle across, one `stride` further, has no data.
    fn border_edges(&self, c: CellAt, stride: u32, first: bool, other_missing: bool) -> [bool; 3] {
        let ([i, i1], [j, j1]) = (c.rows, c.cols);
        let (last_row, last_col) = (self.grid.cell_rows(), self.grid.cell_cols());
        let has = |ii: u32, jj: u32| self.storage.height(ii, jj).is_some_and(T::is_finite);
        if first {
            // (V(i,j), V(i,j1), V(i1,j1)): column j1, the diagonal, row i.
            let east = j1 >= last_col || !has(i1, j1.saturating_add(stride).min(last_col));
            let south = i == 0 || !has(i.saturating_sub(stride), j);
            [east, other_missing, south]
        } else {
            // (V(i,j), V(i1,j1), V(i1,j)): row i1, column j, the diagonal.
            let north = i1 >= last_row || !has(i1.saturating_add(stride).min(last_row), j1);
            let west = j == 0 || !has(i, j.saturating_sub(stride));
            [north, west, other_missing]
        }
    }

    /// One watertight ray–triangle test, its edges on the border of the surface given by `border` (edges
    /// `b–c`, `c–a`, `a–b`; asked only for a ray passing within rounding outside an edge); a nearer hit becomes
    /// the candidate.
    #[inline]
    fn test_triangle(
        &self,
        w: &mut Walk<'_, '_, T>,
        [a, b, c]: [V3<T>; 3],
        cell: [u32; 2],
        tri: TriRef,
        u: &Unit,
        border: impl FnOnce() -> [bool; 3],
    ) {
        w.stats.triangles_tested = w.stats.triangles_tested.saturating_add(1);
        let limit = w.best.as_ref().map_or(w.ray.t_max(), |h| h.t);
        if let Some((t, _)) = w
            .wray
            .intersect_with_border(a, b, c, w.ray.t_min(), limit, border)
        {
            if w.best.as_ref().is_none_or(|h| t < h.t) {
                *w.best = Some(Candidate {
                    t,
                    cell,
                    tri,
                    unit: *u,
                });
            }
        }
    }

    /// Stitching of a coarse cell on its unit's border (module docs, "Multi-resolution"): when a neighbouring
    /// unit is finer along a side, that unit's vertices on the side are T-junctions of the coarse edge, and the
    /// cell is triangulated instead as a fan from the middle `M` of its diagonal `V00–V11` through its corners
    /// and every such vertex, so that the two sides share every edge exactly. `Plain` when no side has such a
    /// vertex (or a diagonal corner is nodata: the cell has no triangle then); `Done` after testing the fan, or
    /// when a neighbour's block is needed (recorded at `t_cell`).
    #[allow(clippy::too_many_arguments)]
    fn stitch(
        &self,
        u: &Unit,
        cell: &CellAt,
        v00: Option<V3<T>>,
        v11: Option<V3<T>>,
        w: &mut Walk<'_, '_, T>,
        t_cell: T,
    ) -> Result<Stitch, TerrainError> {
        let (Some(p00), Some(p11)) = (v00, v11) else {
            return Ok(Stitch::Plain);
        };
        let sides = self.cell_sides(u, cell);
        let mut any = false;
        for side in &sides {
            if let Some(id) = self.side_extras(u.stride, side, &mut |_| any = true)? {
                w.need(t_cell, id);
                return Ok(Stitch::Done);
            }
        }
        if !any {
            return Ok(Stitch::Plain);
        }
        let m = p00.plus(p11).scaled(T::HALF);
        let [i, i1] = cell.rows;
        let [j, j1] = cell.cols;
        let mid = Vtx::Mid([i, j, i1, j1]);
        // The four sides from corner to corner, each with its extra vertices in increasing order.
        for side in sides {
            let at = |p: u32| {
                if side.along_cols {
                    (side.fixed, p)
                } else {
                    (p, side.fixed)
                }
            };
            let mut prev = at(side.from);
            // A side on the grid's outer edge has no triangle across its fan edges.
            let last = if side.along_cols {
                self.grid.cell_rows()
            } else {
                self.grid.cell_cols()
            };
            let outer = [side.fixed == 0 || side.fixed >= last, false, false];
            let mut fan = |p: u32| {
                let cur = at(p);
                if let (Some(a), Some(b)) = (self.vertex(prev.0, prev.1), self.vertex(cur.0, cur.1))
                {
                    let refs =
                        TriRef::Vertices([mid, Vtx::Grid(prev.0, prev.1), Vtx::Grid(cur.0, cur.1)]);
                    self.test_triangle(w, [m, a, b], [i, j], refs, u, move || outer);
                }
                prev = cur;
            };
            // Needs were ruled out by the first pass; a side without `across` has no extra vertices.
            let _ = self.side_extras(u.stride, &side, &mut fan)?;
            fan(side.to);
        }
        Ok(Stitch::Done)
    }

    /// Grid vertex `V(i, j)` from the storage's trigonometry (the same arithmetic as the traced cells' vertices,
    /// so that shared vertices are bit-identical); `None` for nodata.
    fn vertex(&self, i: u32, j: u32) -> Option<V3<T>> {
        vertex_ecef(self.storage, &self.ellipsoid, i, j)
    }

    /// The four sides of a cell, from corner to corner (low row, high row, low column, high column); `across` is
    /// set on the sides that lie on the unit's border and have a neighbouring cell row or column in the grid.
    fn cell_sides(&self, u: &Unit, c: &CellAt) -> [SideAt; 4] {
        let [i, i1] = c.rows;
        let [j, j1] = c.cols;
        let g = &self.grid;
        let row = |fixed: u32, across: Option<u32>| SideAt {
            along_cols: true,
            fixed,
            from: j,
            to: j1,
            across,
        };
        let col = |fixed: u32, across: Option<u32>| SideAt {
            along_cols: false,
            fixed,
            from: i,
            to: i1,
            across,
        };
        [
            row(i, (i == u.rows[0]).then(|| i.checked_sub(1)).flatten()),
            row(i1, (i1 == u.rows[1] && i1 < g.cell_rows()).then_some(i1)),
            col(j, (j == u.cols[0]).then(|| j.checked_sub(1)).flatten()),
            col(j1, (j1 == u.cols[1] && j1 < g.cell_cols()).then_some(j1)),
        ]
    }

    /// Calls `emit(p)`, in increasing order, for every vertex strictly inside a coarse cell's side (of a cell
    /// `stride` steps wide) that a finer neighbouring unit has on it: the points of its sample lattice. Returns
    /// the node whose block is needed to know the neighbour, if any.
    fn side_extras(
        &self,
        stride: u32,
        side: &SideAt,
        emit: &mut impl FnMut(u32),
    ) -> Result<Option<NodeId>, TerrainError> {
        let Some(across) = side.across else {
            return Ok(None);
        };
        let (from, to) = (side.from, side.to);
        let mut k = from;
        let mut last = from;
        while k < to {
            let look = if side.along_cols {
                self.unit_at(across, k)?
            } else {
                self.unit_at(k, across)?
            };
            match look {
                Lookup::Needs(id) => return Ok(Some(id)),
                Lookup::Empty => k = k.saturating_add(1),
                Lookup::Unit(n) => {
                    let range = if side.along_cols { n.cols } else { n.rows };
                    let end = range[1].min(to);
                    if n.stride < stride {
                        let mut p = div_ceil_pow2(k, n.stride).saturating_mul(n.stride);
                        while p <= end && p < to {
                            if p > last {
                                emit(p);
                                last = p;
                            }
                            p = p.saturating_add(n.stride);
                        }
                    }
                    k = end.max(k.saturating_add(1));
                }
            }
        }
        Ok(None)
    }

    /// The unit's cell columns `[first, end)` (in cells of its stride from its first column) that the ray can
    /// cross within `[t_in, t_out]`. Both end points must lie in the half-space in front of the unit's middle
    /// meridian (`r_m > 0`), which is convex, so the whole segment does; there the azimuth is monotone along the
    /// line and every meridian of a unit narrower than 180° (minus a column) is within 90° of the middle one, so
    /// the side of a meridian plane, `cos λ_j·y − sin λ_j·x ≥ 0` (east of it), is monotone over the unit's
    /// meridians. Each end's column is found by a binary search over those sides, from the storage's
    /// trigonometry (the second end tries the first end's column before searching); the crossed columns lie
    /// between the two, plus one column of margin beyond a meridian that an end lies within rounding distance of
    /// (the cells beyond are convex hulls of vertices on or past that meridian, so an end clear of it keeps the
    /// segment out of them). Falls back to all columns otherwise.
    fn unit_columns(&self, u: &Unit, ray: &Ray<T>, t_in: T, t_out: T) -> (u32, u32) {
        let [c0, c1] = u.cols;
        let n = div_ceil_pow2(c1.saturating_sub(c0), u.stride);
        let all = (0, n);
        let span = T::from_f64(f64::from(c1.saturating_sub(c0).saturating_add(u.stride)));
        if !(span * self.grid.dlon < T::from_f64(180.0)) {
            return all;
        }
        let meridian = |k: u32| {
            self.storage
                .col_sin_cos(c0.saturating_add(k.saturating_mul(u.stride)).min(c1))
        };
        let (sm, cm) = meridian(n.wrapping_shr(1));
        let (o, d) = (ray.origin(), ray.dir());
        // The column loop's tolerance on the meridian planes (`trace_unit`): a side beyond it is decided alike
        // there.
        let tol = T::from_f64(64.0)
            * T::EPSILON
            * ((o.x.abs() + o.y.abs()) + (d.x.abs() + d.y.abs()) * t_in.abs().max(t_out.abs()));
        // The columns `[first, end)` around point `p`'s: its cell column (the last meridian `k ∈ [0, n]` it is
        // east of; `n`: east of the unit), widened by one on a side whose meridian it is within `tol` of. With
        // `hint` (the other end's column: a steep ray stays in it), that column is tried first.
        let columns = |p: V3<T>, hint: Option<u32>| -> Option<(u32, u32, u32)> {
            if !(cm * p.x + sm * p.y > T::ZERO) {
                return None;
            }
            let side = |k: u32| {
                let (sk, ck) = meridian(k);
                ck * p.y - sk * p.x
            };
            // `a < b = a + 1 ≤ n` with the point east of meridian `a` (or west of the unit when `a` is 0) and
            // not east of meridian `b`, and the two sides: the columns, and `a`.
            let cell = |a: u32, b: u32, sa: T, sb: T| {
                let west = u32::from(!(sa > tol));
                let east = u32::from(!(sb < -tol));
                (a.saturating_sub(west), b.saturating_add(east), a)
            };
            if let Some(a) = hint.filter(|&a| a < n) {
                let (sa, sb) = (side(a), side(a.saturating_add(1)));
                if (a == 0 || sa >= T::ZERO) && sb < T::ZERO {
                    return Some(cell(a, a.saturating_add(1), sa, sb));
                }
            }
            let (mut a, mut b) = (0u32, n);
            let mut sb = side(b);
            if sb >= T::ZERO {
                return Some((n.saturating_sub(1), n, n));
            }
            // Invariant: east of meridian `a` (or west of the unit when `a` is 0), not east of meridian `b`.
            let mut sa = T::NAN;
            while b.saturating_sub(a) > 1 {
                let m = a.wrapping_add(b.wrapping_sub(a).wrapping_shr(1));
                let s_m = side(m);
                if s_m >= T::ZERO {
                    (a, sa) = (m, s_m);
                } else {
                    (b, sb) = (m, s_m);
                }
            }
            if a == 0 {
                sa = side(0);
            }
            Some(cell(a, b, sa, sb))
        };
        let Some((fa, ea, a)) = columns(V3::from(ray.at(t_in)), None) else {
            return all;
        };
        let Some((fb, eb, _)) = columns(V3::from(ray.at(t_out)), Some(a)) else {
            return all;
        };
        (fa.min(fb), ea.max(eb).min(n))
    }

    /// The [`Hit`] of the traversal's nearest triangle, with its parameter and point refined in double-double
    /// (see `refine`'s docs: the vertices recomputed far below an ulp, `t` from the triangle's plane; the
    /// unrefined values are kept when the refinement's guard rejects it).
    fn make_hit(&self, ray: &Ray<T>, c: Candidate<T>) -> Hit<T> {
        let g = &self.grid;
        let refined = match c.tri {
            TriRef::Cell(tri) => {
                // The walk may leave the unit only into cells traced at full resolution.
                let fine = |[i, j]: [u32; 2]| {
                    let inside = (c.unit.rows[0]..c.unit.rows[1]).contains(&i)
                        && (c.unit.cols[0]..c.unit.cols[1]).contains(&j);
                    inside || matches!(self.unit_at(i, j), Ok(Lookup::Unit(u)) if u.stride == 1)
                };
                refine::refine(self.storage, g, ray, c.t, c.cell, tri, &fine)
            }
            TriRef::Vertices(v) => refine::refine_vertices(self.storage, g, ray, c.t, v),
        };
        let (t, p) = refined.unwrap_or((c.t, ray.at(c.t)));
        let (cell, level) = (c.cell, c.unit.level);
        // Geodetic coordinates from the cell's corner vertex as the seed (its trigonometry is the storage's),
        // else by the closed form.
        let [i, j] = cell;
        let (sl, cl) = self.storage.row_sin_cos(i);
        let (so, co) = self.storage.col_sin_cos(j);
        let near = self.ellipsoid.ecef_to_geodetic_near(
            V3::from(p),
            (g.lat_deg(i), sl, cl),
            (g.lon_deg(j), so, co),
        );
        let (lat, lon, h) = near.unwrap_or_else(|| {
            let geo = self.ellipsoid.ecef_to_geodetic(V3::from(p));
            let deg = T::from_f64(180.0) / T::PI;
            (geo.lat * deg, geo.lon * deg, geo.h)
        });
        Hit {
            t,
            ecef: p,
            lat,
            lon,
            h,
            cell,
            level,
            stride: c.unit.stride,
        }
    }
}

/// `⌈n / s⌉` for a power of two `s`, by shifts (no division, so no panic path).
fn div_ceil_pow2(n: u32, s: u32) -> u32 {
    let q = n.checked_shr(s.trailing_zeros()).unwrap_or(0);
    q.saturating_add(u32::from(n & s.wrapping_sub(1) != 0))
}

/// A row of a column's traced cells: the row index and the corners on its west and east meridians.
type RowCorners<T> = (u32, Option<V3<T>>, Option<V3<T>>);

/// A lattice row's `(sin ψ, cos ψ, cone apex k, prime vertical radius N)`.
type RowValues<T> = (T, T, T, T);

/// Rows of a leaf whose trigonometry is cached per leaf (leaves up to 64 cells tall).
const ROW_CACHE: usize = 65;

/// The most nodes a well-formed forest over this grid can have (each node has ≥ 1 cell and children are
/// strictly smaller; a quadtree has fewer than 4/3 nodes per leaf) with generous slack.
fn node_budget<T: Real>(g: &Grid<T>, zones: usize) -> u64 {
    let cells = u64::from(g.cell_rows()).saturating_mul(u64::from(g.cell_cols()));
    cells
        .saturating_mul(4)
        .saturating_add(u64::try_from(zones).unwrap_or(u64::MAX))
        .saturating_add(16)
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

/// The conservative bounding volume of a node (module docs; [`HeightQuadBounds`]), as the kernel builds it from
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
        e, lat_s, lat_n, lon_w, lon_e, lo, hi, g.dlat, g.dlon,
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
    // Rows may run southwards (dlat < 0): the southern wall is the one of smaller latitude.
    let (south, north, south_inner, north_inner) = if g.dlat > T::ZERO {
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
