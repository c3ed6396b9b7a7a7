//! The `no_std` quadtree builder (Wartell et al. §3.5, §4): from a DEM's heights, its [`Grid`](crate::terrain::Grid) and a block size, the
//! node records of a spheroidal height-augmented quadtree, written into a buffer the caller provides, and
//! [`SliceStorage`], the [`TerrainStorage`](crate::terrain::TerrainStorage) over those slices.
//!
//! # The tree
//!
//! Leaves are blocks of `block × block` cells (fewer in the last block row and column); a node one level up
//! covers 2 × 2 nodes of the level below, so every node boundary is a grid line of the DEM (a parallel or a
//! meridian through vertices) and nothing is resampled. Levels are built up to the first one with at most 4
//! rows and 8 columns of nodes: its nodes are the zones (§3.5: at most 8 × 4 = 32, bounded by parallels and
//! meridians, for a global grid or a regional one alike). A node's height range is taken over **every** vertex
//! of its cells, its border rows and columns included (the invariant [`Node`](crate::terrain::Node) states), a node without data is
//! left out of its parent's children, and a parent whose only child would cover the same cells takes that
//! child's children instead (the kernel requires children strictly smaller than their parent).
//!
//! # The records
//!
//! A node's id is its slot in the buffer: the levels from the leaves up, each stored by 2 × 2 groups, so that
//! the four children of a node have adjacent records (the traversal reads them one after the other). Slots of
//! a group that fall past a level's last row or column stay empty. [`node_slots`] gives the buffer's length,
//! a `const fn`, so that the buffer can be a static array. A record keeps its height range in the samples' type
//! and, if its type says so ([`BoxSlot`]), the node's box in local frames with the shared-frame rule, which
//! [`build_boxes`] fills (in `f64` as [`TerrainCaches::node_box`](crate::terrain::TerrainCaches::node_box) requires): 44 bytes with `f32` samples and
//! no box, 72 with a box (56 and 80 with `f64` samples). A tree without boxes costs neither their RAM nor the
//! traversal's box code.
//!
//! # Beyond the records
//!
//! What makes a storage fast, each into a buffer the caller provides (lengths from `const fn`s): the per-row
//! and per-column trigonometry the kernel asks for at every quad wall and vertex ([`trig_tables`]: exactly the
//! values [`TerrainStorage`](crate::terrain::TerrainStorage) requires). For the paged pyramid of §5, [`build_multires_tree`] builds the same tree
//! with a block per node at stride `2^k` and the branches of a [`MultiRes`] shape; residency flags
//! (`&[AtomicBool]`, one per slot) let the caller page blocks in and out, and a storage whose flags are `()`
//! ([`Residency`]) serves single-resolution trees without linking that code. [`TreeStorage`] serves all of it,
//! from borrowed slices ([`SliceStorage`], [`Parts`]) or from buffers the caller owns ([`Buffers`]), and checks
//! every length ([`BuildError::BufferLength`]).
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

mod storage;
mod tables;
mod tree;

pub use storage::{Buffers, Parts, Residency, SliceStorage, TreeStorage};
pub use tables::{TrigTables, build_boxes, build_boxes_sharing, build_windows, trig_tables};
pub use tree::{
    BoxSlot, BuildError, MultiRes, NodeRecord, Tree, build_multires_tree, build_tree,
    col_table_len, node_slots, row_table_len, window_slots,
};
