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
}

/// `⌈n / s⌉` for a power of two `s`, by shifts (no division, so no panic path).
fn div_ceil_pow2(n: u32, s: u32) -> u32 {
    let q = n.checked_shr(s.trailing_zeros()).unwrap_or(0);
    q.saturating_add(u32::from(n & s.wrapping_sub(1) != 0))
}

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
