//! The storage trait: the kernel does not own terrain (Wartell et al. §3, §5). A storage gives the kernel the DEM's
//! regular latitude/longitude grid, its vertex heights, and a height-augmented quadtree over the grid's cells.

use super::Parallel;
use crate::dd::Dd;
use crate::geodesy::{Ellipsoid, HeightQuadBounds, sin_cos_deg};
use crate::real::Real;

/// The regular geodetic grid of a DEM (`pick` in the CLI contract): vertex `V(i, j)` is at latitude
/// `lat0_deg + i·dlat_deg`, longitude `lon0_deg + j·dlon_deg` (degrees), `0 ≤ i < rows`, `0 ≤ j < cols`. Cell `(i, j)`
/// (`i < rows − 1`, `j < cols − 1`) is the two triangles `(V(i,j), V(i,j+1), V(i+1,j+1))` and
/// `(V(i,j), V(i+1,j+1), V(i+1,j))`. `dlat_deg` may be negative; `dlon_deg` must be in `(0°, 180°)`; longitudes may run
/// past ±180°; latitudes stay within [−90°, 90°] (a row at ±90° is a pole).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid<T> {
    /// Latitude of row 0, degrees.
    pub lat0_deg: T,
    /// Longitude of column 0, degrees.
    pub lon0_deg: T,
    /// Row spacing, degrees (non-zero, either sign).
    pub dlat_deg: T,
    /// Column spacing, degrees (`0 < dlon_deg < 180`).
    pub dlon_deg: T,
    /// Number of vertex rows (≥ 2).
    pub rows: u32,
    /// Number of vertex columns (≥ 2).
    pub cols: u32,
}

impl<T: Real> Grid<T> {
    /// Latitude of vertex row `i`, degrees, clamped to ±90° (a last row computed as `90.000000000001` is the pole).
    #[inline]
    pub fn lat_deg(&self, i: u32) -> T {
        let ninety = T::from_f64(90.0);
        (self.lat0_deg + T::from_f64(f64::from(i)) * self.dlat_deg)
            .max(-ninety)
            .min(ninety)
    }
    /// Longitude of vertex column `j`, degrees (not wrapped).
    #[inline]
    pub fn lon_deg(&self, j: u32) -> T {
        self.lon0_deg + T::from_f64(f64::from(j)) * self.dlon_deg
    }
    /// Number of cell rows (`rows − 1`).
    #[inline]
    pub fn cell_rows(&self) -> u32 {
        self.rows.saturating_sub(1)
    }
    /// Number of cell columns (`cols − 1`).
    #[inline]
    pub fn cell_cols(&self) -> u32 {
        self.cols.saturating_sub(1)
    }
    /// Checks the grid: finite, `dlat_deg ≠ 0`, `0 < dlon_deg < 180`, at least 2×2 vertices, latitudes within ±90°
    /// (a rounding excess up to 1e-9° is accepted and clamped).
    pub fn validate(&self) -> bool {
        let finite = self.lat0_deg.is_finite()
            && self.lon0_deg.is_finite()
            && self.dlat_deg.is_finite()
            && self.dlon_deg.is_finite();
        if !finite || self.rows < 2 || self.cols < 2 {
            return false;
        }
        if self.dlat_deg == T::ZERO
            || !(self.dlon_deg > T::ZERO && self.dlon_deg < T::from_f64(180.0))
        {
            return false;
        }
        let lim = T::from_f64(90.0 + 1e-9);
        let last =
            self.lat0_deg + T::from_f64(f64::from(self.rows.saturating_sub(1))) * self.dlat_deg;
        self.lat0_deg.abs() <= lim && last.abs() <= lim && self.lon_deg(self.cols).is_finite()
    }
}

/// The id of a quadtree node, chosen by the storage (an index into its node array, typically).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub u32);

/// One node of the height-augmented quadtree (a spheroidal height-quad, §3): the cells it covers, in the DEM's
/// own grid indices, the range of its vertex heights, and its children.
///
/// Invariants the kernel checks (violations are [`super::TerrainError::MalformedTree`]): `rows[0] < rows[1] ≤
/// grid.rows − 1`, `cols[0] < cols[1] ≤ grid.cols − 1`; a child's ranges lie inside its parent's and are
/// strictly smaller. Invariants the kernel relies on (the storage must guarantee them): `heights` is
/// `Some([min, max])` over **every** vertex `V(i, j)` with `rows[0] ≤ i ≤ rows[1]`, `cols[0] ≤ j ≤ cols[1]`
/// that has data (the cells' corner vertices, boundary rows and columns included), `None` if none has; the
/// children together cover every cell of the node that has a triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node<T> {
    /// Cell rows `[rows[0], rows[1])`.
    pub rows: [u32; 2],
    /// Cell columns `[cols[0], cols[1])`.
    pub cols: [u32; 2],
    /// `[min, max]` of the node's vertex heights, `None` when all are nodata.
    pub heights: Option<[T; 2]>,
    /// Up to four children (any order); a node without children is a leaf whose cells the kernel traces
    /// (§4: a block of triangle pairs).
    pub children: [Option<NodeId>; 4],
    /// Depth of the node (zones are level 0); reported in [`super::Hit::level`].
    pub level: u8,
}

impl<T> Node<T> {
    /// True when the node has no children.
    pub fn is_leaf(&self) -> bool {
        self.children.iter().all(Option::is_none)
    }
}

/// Terrain storage for the kernel's traversal (Wartell et al. §3.5, §4).
///
/// The kernel never allocates and never owns terrain: it asks the storage for the grid, for the zones (the roots
/// of the quadtrees, §3.5; e.g. 8 × 4 = 32 zones bounded by meridians and parallels for a global DEM, or the
/// DEM's own extent split as the storage likes — zones must not overlap in cells), for nodes, and for vertex
/// heights. Zones and quads are ranges of the DEM's own cells, so nothing is resampled and the surface the
/// kernel intersects is exactly the contract's triangles.
///
/// Multi-resolution and paging (Wartell et al. §5): every node may have a *block*, its own regular sub-grid of the DEM's
/// vertices at a spacing of [`TerrainStorage::block_stride`] grid steps, resident in memory or not
/// ([`TerrainStorage::is_resident`]). A single-resolution storage keeps the defaults (stride 1, always
/// resident) and the kernel traces every leaf's full-resolution cells. The surface a multi-resolution storage
/// gives is stated in the module docs of [`super`] ("Multi-resolution").
pub trait TerrainStorage<T: Real> {
    /// The reference ellipsoid.
    fn ellipsoid(&self) -> Ellipsoid<T>;
    /// The DEM grid.
    fn grid(&self) -> Grid<T>;
    /// The number of zones (quadtree roots).
    fn zone_count(&self) -> usize;
    /// The root node of zone `k < zone_count()`.
    fn zone(&self, k: usize) -> Option<NodeId>;
    /// A node by id.
    fn node(&self, id: NodeId) -> Option<Node<T>>;
    /// The height of vertex `V(i, j)`, `None` for nodata (or NaN), or out of range. The kernel asks only for
    /// vertices of resident blocks.
    fn height(&self, i: u32, j: u32) -> Option<T>;
    /// Whether node `id`'s block is in memory (default: always). The kernel never blocks: a block it needs and
    /// cannot replace by a coarser resident one is reported as [`super::TerrainError::NeedsBlock`].
    fn is_resident(&self, _id: NodeId) -> bool {
        true
    }
    /// The spacing of node `id`'s block samples, in grid steps: a power of two (default 1, the DEM's own
    /// resolution). The block's vertices are `V(i, j)` with `i` a multiple of the stride or the grid's last
    /// row, likewise `j`, within the node's range; its cells are `stride × stride` grid cells (fewer at the
    /// grid's last row and column), each split into two triangles like a grid cell. Requirements (violations
    /// are [`super::TerrainError::MalformedTree`]): a node's ranges start on multiples of its stride and end
    /// on one or at the grid's last cell; a child's stride is at most its parent's. A vertex has one height
    /// whichever block holds it ([`TerrainStorage::height`]): coarse blocks subsample the finest data, as
    /// the paper's pyramid does.
    fn block_stride(&self, _id: NodeId) -> u32 {
        1
    }
    /// `(sin, cos)` of the latitude of vertex row `i`: [`sin_cos_deg`]`(grid.lat_deg(i))`. A storage may return
    /// it from a per-row table (one entry per row: a few kilobytes), which spares the kernel the trigonometry of
    /// every quad wall and vertex; it **must** return exactly that value (both the walls and the triangles'
    /// vertices are built from it).
    fn row_sin_cos(&self, i: u32) -> (T, T) {
        sin_cos_deg(self.grid().lat_deg(i))
    }
    /// `(sin, cos)` of the longitude of vertex column `j`: [`sin_cos_deg`]`(grid.lon_deg(j))`; may be cached per
    /// column like [`TerrainStorage::row_sin_cos`], with the same requirement.
    fn col_sin_cos(&self, j: u32) -> (T, T) {
        sin_cos_deg(self.grid().lon_deg(j))
    }
    /// Optional cache of the node's bounding volume. A storage may precompute, once per node,
    /// [`super::quad_bounds`]`(&ellipsoid, &grid, &node)` and return it here, which saves the kernel building it
    /// on every visit (about a fifth of the per-ray work). It **must** be exactly that value (or `None`): any other
    /// volume voids the no-miss guarantee.
    fn cached_bounds(&self, _id: NodeId) -> Option<HeightQuadBounds<T>> {
        None
    }
    /// The parallel of vertex row `i` in double-double, for the refinement of the nearest hit:
    /// [`super::row_parallel`]`(&ellipsoid, &grid, i)`. May be cached per row (64 bytes per row in `f64`) like
    /// [`TerrainStorage::row_sin_cos`], which spares the refinement two double-double sines per ray; it **must**
    /// return exactly that value.
    fn row_parallel(&self, i: u32) -> Parallel<T> {
        super::row_parallel(&self.ellipsoid(), &self.grid(), i)
    }
    /// `(sin, cos)` of the longitude of vertex column `j` in double-double: [`super::col_sin_cos_dd`]`(&grid,
    /// j)`; may be cached per column, with the same requirement.
    fn col_sin_cos_dd(&self, j: u32) -> (Dd<T>, Dd<T>) {
        super::col_sin_cos_dd(&self.grid(), j)
    }
    /// Optional box of the node (beyond the paper; [`super::boxes`]): a box in its parent's own local frame, or
    /// in the frame of its parent's box when [`super::boxes::NodeBox::shared_frame`] says so (a zone's in the
    /// grid's frame; [`super::boxes::LocalFrame::for_box`]), that contains every vertex of the node with data, as
    /// [`super::boxes::NodeBox::of_vertices`] forms it from [`super::vertex_ecef`] in `f64` (or a box containing
    /// that one). The traversal then tests the node against its box instead of its spheroidal volume, which is
    /// several times cheaper. It **must** contain those vertices (or be `None`): a smaller box voids the no-miss
    /// guarantee.
    fn node_box(&self, _id: NodeId) -> Option<super::boxes::NodeBox> {
        None
    }
}

/// Grid vertex `V(i, j)` in ECEF from the storage's trigonometry, `None` for nodata: the arithmetic of every
/// vertex the kernel traces (and of the vertices a storage bounds with [`TerrainStorage::node_box`]).
pub fn vertex_ecef<T: Real, S: TerrainStorage<T> + ?Sized>(
    storage: &S,
    ellipsoid: &Ellipsoid<T>,
    i: u32,
    j: u32,
) -> Option<crate::vec3::V3<T>> {
    let h = storage.height(i, j).filter(|h| h.is_finite())?;
    let (sl, cl) = storage.row_sin_cos(i);
    let (so, co) = storage.col_sin_cos(j);
    let n = ellipsoid.prime_vertical_radius(sl);
    Some(ellipsoid.ecef_from_parts(sl, cl, n, so, co, h))
}

/// The default number of zone rows (parallels) of [`zone_cells`]: 4 bands of 45° on a global grid.
pub const DEFAULT_ZONE_ROWS: u32 = 4;
/// The default number of zone columns (meridians) of [`zone_cells`]: 8 wedges of 45° on a global grid.
pub const DEFAULT_ZONE_COLS: u32 = 8;

/// The cell ranges `(rows, cols)` of zone `k` (row-major, `k < zone_rows · zone_cols`) when the grid's cells are
/// split into `zone_rows × zone_cols` zones along grid lines (§3.5: zones bounded by parallels and meridians).
/// For a global grid with the defaults this is the paper's 8 × 4 = 32 zones of 45° × 45°, snapped to the DEM's
/// own grid lines (nothing is resampled); for a regional DEM it splits the DEM's own extent. `None` when `k` is
/// out of range or the zone would be empty (more zones than cells). Keeping each zone's longitude span below
/// 180° lets the kernel use its meridian walls.
pub fn zone_cells<T: Real>(
    grid: &Grid<T>,
    zone_rows: u32,
    zone_cols: u32,
    k: u32,
) -> Option<([u32; 2], [u32; 2])> {
    let (a, b) = (k.checked_div(zone_cols)?, k.checked_rem(zone_cols)?);
    if a >= zone_rows {
        return None;
    }
    let split = |n: u32, parts: u32, i: u32| -> Option<u32> {
        let v = u64::from(n)
            .checked_mul(u64::from(i))?
            .checked_div(u64::from(parts))?;
        u32::try_from(v).ok()
    };
    let (cr, cc) = (grid.cell_rows(), grid.cell_cols());
    let rows = [
        split(cr, zone_rows, a)?,
        split(cr, zone_rows, a.checked_add(1)?)?,
    ];
    let cols = [
        split(cc, zone_cols, b)?,
        split(cc, zone_cols, b.checked_add(1)?)?,
    ];
    (rows[0] < rows[1] && cols[0] < cols[1]).then_some((rows, cols))
}
