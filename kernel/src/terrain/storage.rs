//! What the kernel asks of a terrain (Wartell et al. §3, §5): the kernel does not own terrain. A storage gives the
//! DEM's regular latitude/longitude grid, its vertex heights and a height-augmented quadtree over the grid's cells
//! ([`TerrainStorage`], the data contract), and may give precomputed values that save the kernel work
//! ([`TerrainCaches`]). Also here: what the kernel computes from a storage's caches and a storage's build step
//! must compute the same way (a vertex in ECEF, the frame of a node's box, the box of a node's vertices).

use super::boxes::{BoxBuilder, LocalFrame, NodeBox};
#[cfg(doc)]
use super::error::TerrainError;
use super::grid::{Grid, Node, NodeId};
use super::parallel::{Parallel, col_sin_cos_dd, row_parallel};
use super::windows::WindowBox;
use crate::dd::Dd;
use crate::geodesy::{Ellipsoid, HeightQuadBounds, sin_cos_deg};
use crate::real::Real;
use crate::vec3::V3;

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
///
/// This is the data contract: what a storage must give. What it may give besides, to save the kernel work, is
/// [`TerrainCaches`], which a [`Picker`](super::Picker) also requires; a storage without caches implements it
/// with an empty body (`impl TerrainCaches<f64> for MyDem {}`), and every default computes what the cache would
/// hold.
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
    /// cannot replace by a coarser resident one is reported as [`TerrainError::NeedsBlock`].
    fn is_resident(&self, _id: NodeId) -> bool {
        true
    }
    /// The spacing of node `id`'s block samples, in grid steps: a power of two (default 1, the DEM's own
    /// resolution). The block's vertices are `V(i, j)` with `i` a multiple of the stride or the grid's last
    /// row, likewise `j`, within the node's range; its cells are `stride × stride` grid cells (fewer at the
    /// grid's last row and column), each split into two triangles like a grid cell. Requirements (violations
    /// are [`TerrainError::MalformedTree`]): a node's ranges start on multiples of its stride and end
    /// on one or at the grid's last cell; a child's stride is at most its parent's. A vertex has one height
    /// whichever block holds it ([`TerrainStorage::height`]): coarse blocks subsample the finest data, as
    /// the paper's pyramid does.
    fn block_stride(&self, _id: NodeId) -> u32 {
        1
    }
}

/// What a storage may precompute to save the kernel work (beyond the paper), each with a default that computes
/// the value itself. Every method's answer **must** be exactly what its default returns (or, for the two
/// volumes, `None` or a volume that contains the node): the kernel builds walls, vertices and bounds from these
/// values, and a different value voids the no-miss guarantee or changes answers.
///
/// What each saves, in instructions per pick (callgrind, `Picker::pick` on the report's terrain scene: the
/// Trinidad DEM, 16 × 16-cell leaves, 2 000 rays from a camera 2 km up / from orbit, every other cache of the
/// host's storage kept; `pick_count RAYS 16 2000 PASSES caches=VARIANT`, host-tests/examples, 3 passes minus 1):
///
/// | the storage gives | camera 2 km up | orbit |
/// | --- | ---: | ---: |
/// | every cache below but [`cached_bounds`](Self::cached_bounds) (the host's storage) | 43 522 | 11 542 |
/// | without [`row_sin_cos`](Self::row_sin_cos) and [`col_sin_cos`](Self::col_sin_cos) | 57 288 | 15 590 |
/// | without [`row_parallel`](Self::row_parallel) and [`col_sin_cos_dd`](Self::col_sin_cos_dd) | 48 593 | 17 125 |
/// | without [`node_box`](Self::node_box) (spheroidal volumes, relaxed test) | 83 951 | 29 292 |
/// | without node boxes, with [`cached_bounds`](Self::cached_bounds) | 103 672 | 41 937 |
/// | no caches at all (`impl TerrainCaches<f64> for MyDem {}`) | 137 013 | 54 495 |
///
/// The answers are bit for bit the same in every row.
pub trait TerrainCaches<T: Real>: TerrainStorage<T> {
    /// `(sin, cos)` of the latitude of vertex row `i`: [`sin_cos_deg`]`(grid.lat_deg(i))`, from a per-row table
    /// (one entry per row: a few kilobytes). Spares the kernel the trigonometry of every quad wall and vertex:
    /// with [`TerrainCaches::col_sin_cos`], 24 % of a pick from 2 km up and 26 % from orbit (the table above).
    /// Both the walls and the triangles' vertices are built from it, so it must be exactly that value.
    fn row_sin_cos(&self, i: u32) -> (T, T) {
        sin_cos_deg(self.grid().lat_deg(i))
    }
    /// `(sin, cos)` of the longitude of vertex column `j`: [`sin_cos_deg`]`(grid.lon_deg(j))`, from a per-column
    /// table like [`TerrainCaches::row_sin_cos`] (the savings are those two's together).
    fn col_sin_cos(&self, j: u32) -> (T, T) {
        sin_cos_deg(self.grid().lon_deg(j))
    }
    /// Node `id`'s spheroidal volume, [`quad_bounds`](super::quad_bounds)`(&ellipsoid, &grid, &node)`,
    /// precomputed once per node (or `None`; any other volume voids the no-miss guarantee). The kernel then tests
    /// a node without a box against this volume instead of the relaxed test it forms per visit
    /// ([`crate::geodesy::relaxed_interval`]). On the report's scene that costs more than it saves: 23 % more per
    /// pick from 2 km up and 43 % from orbit than the relaxed test (the table above), and node boxes are far
    /// cheaper than either. Kept for storages that cannot give boxes and trace few nodes per ray.
    fn cached_bounds(&self, _id: NodeId) -> Option<HeightQuadBounds<T>> {
        None
    }
    /// The parallel of vertex row `i` in double-double, [`row_parallel`]`(&ellipsoid, &grid, i)`, from a per-row
    /// table (64 bytes per row in `f64`), for the refinement of the nearest hit: spares it two double-double
    /// sines per ray. With [`TerrainCaches::col_sin_cos_dd`], 10 % of a pick from 2 km up and 33 % from orbit
    /// (where a pick is mostly its refinement). Must be exactly that value.
    fn row_parallel(&self, i: u32) -> Parallel<T> {
        row_parallel(&self.ellipsoid(), &self.grid(), i)
    }
    /// `(sin, cos)` of the longitude of vertex column `j` in double-double, [`col_sin_cos_dd`]`(&grid, j)`, from a
    /// per-column table like [`TerrainCaches::row_parallel`] (the savings are those two's together).
    fn col_sin_cos_dd(&self, j: u32) -> (Dd<T>, Dd<T>) {
        col_sin_cos_dd(&self.grid(), j)
    }
    /// Node `id`'s box (beyond the paper; [`super::boxes`]): a box in its parent's own local frame, or in the
    /// frame of its parent's box when [`NodeBox::shared_frame`] says so (a zone's in the grid's frame;
    /// [`box_frame`]), that contains every vertex of the node with data, as [`node_box_of_vertices`] forms it
    /// from [`vertex_ecef`] in `f64` (or a box containing that one). The traversal then tests the node with three
    /// slabs instead of its spheroidal volume: 48 % of a pick from 2 km up and 61 % from orbit (the table above),
    /// at 28 bytes more per node record ([`super::build`]). It must contain those vertices (or be `None`): a
    /// smaller box voids the no-miss guarantee.
    fn node_box(&self, _id: NodeId) -> Option<NodeBox> {
        None
    }
    /// The boxes of full-resolution leaf `id`'s windows (beyond the paper; [`super::windows`]), in the order of
    /// [`window_ranges`](super::windows::window_ranges), each containing every vertex of its window with data in the frame of the leaf's
    /// [`TerrainCaches::node_box`], relative to that box, as [`super::build::build_windows`] forms them (or
    /// boxes containing those); empty for none (other nodes, or a storage without them), and a leaf given fewer
    /// boxes than it has windows is walked whole. The leaf walk then traces only the windows the ray enters. A
    /// smaller box voids the no-miss guarantee.
    fn window_boxes(&self, _id: NodeId) -> &[WindowBox] {
        &[]
    }
}

/// Grid vertex `V(i, j)` in ECEF from the storage's trigonometry, `None` for nodata: the arithmetic of every
/// vertex the kernel traces (and of the vertices a storage bounds with [`TerrainCaches::node_box`]).
pub fn vertex_ecef<T: Real, S: TerrainCaches<T> + ?Sized>(
    storage: &S,
    ellipsoid: &Ellipsoid<T>,
    i: u32,
    j: u32,
) -> Option<V3<T>> {
    let h = storage.height(i, j).filter(|h| h.is_finite())?;
    let (sl, cl) = storage.row_sin_cos(i);
    let (so, co) = storage.col_sin_cos(j);
    let n = ellipsoid.prime_vertical_radius(sl);
    Some(ellipsoid.ecef_from_parts(sl, cl, n, so, co, h))
}

/// The frame of `node`'s box when the node is its anchor ([`super::boxes`], "Which frame"): east, north, up at
/// vertex row `⌊(r₀ + r₁)/2⌋`, column `⌊(c₀ + c₁)/2⌋`, from the storage's trigonometry
/// ([`TerrainCaches::row_sin_cos`], [`TerrainCaches::col_sin_cos`]).
pub fn node_frame<T: Real, S: TerrainCaches<T> + ?Sized>(
    storage: &S,
    ellipsoid: &Ellipsoid<T>,
    node: &Node<T>,
) -> LocalFrame<T> {
    ranges_frame(storage, ellipsoid, node.rows, node.cols)
}

/// The frame a node's box is expressed in, from its *anchor* ([`super::boxes`], "Which frame"): the anchor's own
/// frame ([`node_frame`]), or for `None` (a zone, or a node every ancestor of which passed its frame down) the
/// frame of the whole grid.
pub fn box_frame<T: Real, S: TerrainCaches<T> + ?Sized>(
    storage: &S,
    ellipsoid: &Ellipsoid<T>,
    anchor: Option<&Node<T>>,
) -> LocalFrame<T> {
    match anchor {
        Some(p) => node_frame(storage, ellipsoid, p),
        None => {
            let g = storage.grid();
            ranges_frame(storage, ellipsoid, [0, g.cell_rows()], [0, g.cell_cols()])
        }
    }
}

/// [`node_frame`] for a node's ranges.
pub fn ranges_frame<T: Real, S: TerrainCaches<T> + ?Sized>(
    storage: &S,
    ellipsoid: &Ellipsoid<T>,
    rows: [u32; 2],
    cols: [u32; 2],
) -> LocalFrame<T> {
    let mid = |[a, b]: [u32; 2]| a.wrapping_add(b.wrapping_sub(a).wrapping_shr(1));
    LocalFrame::at(
        ellipsoid.a(),
        storage.row_sin_cos(mid(rows)),
        storage.col_sin_cos(mid(cols)),
    )
}

/// The box of `node`'s vertices with data in the frame of `anchor` ([`box_frame`]), built in `f64` from
/// [`vertex_ecef`] (a storage's build step: it visits every vertex of the node), with [`NodeBox::shared_frame`]
/// set to `shared_frame`: the anchor must be the parent (`false`) or the anchor of the parent's box (`true`).
/// `None` if the node has no vertex with data.
pub fn node_box_of_vertices<S: TerrainCaches<f64> + ?Sized>(
    storage: &S,
    ellipsoid: &Ellipsoid<f64>,
    node: &Node<f64>,
    anchor: Option<&Node<f64>>,
    shared_frame: bool,
) -> Option<NodeBox> {
    let frame = box_frame(storage, ellipsoid, anchor);
    let mut b = BoxBuilder::default();
    for i in node.rows[0]..=node.rows[1] {
        for j in node.cols[0]..=node.cols[1] {
            if let Some(p) = vertex_ecef(storage, ellipsoid, i, j) {
                b.add_point(&frame, p);
            }
        }
    }
    b.finish().map(|b| NodeBox { shared_frame, ..b })
}
