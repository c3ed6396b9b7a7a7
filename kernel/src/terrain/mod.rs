//! Global terrain picking on a spheroid (Wartell, Ribarsky, Hodges): the nearest
//! intersection of a ray with a regular geodetic DEM's triangles, through a spheroidal height-augmented quadtree.
//!
//! The caller owns the terrain: a [`TerrainStorage`] gives the grid ([`Grid`]), the heights and the quadtree's
//! nodes ([`TerrainCaches`] what it may precompute to save the kernel work), and [`build`] builds that tree from a heights slice into caller-provided buffers ([`build::SliceStorage`]
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
//!    planes and two row planes, walked column by column; the watertight triangle test ([`triangle`]). With
//!    node boxes, a leaf may also have the boxes of its *windows* ([`windows`], beyond the paper): then only the
//!    windows the ray enters are walked.
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
//!
//! # Modules
//!
//! The data a storage gives is in `grid.rs` and its contracts in `storage.rs`; the picker and its entry points in
//! `picker.rs`, the state of one pick in `walk.rs`, and each phase in its own file as listed above. This file only
//! declares them and re-exports the public items.

pub mod boxes;
pub mod build;
mod error;
mod grid;
mod hit;
mod leaf;
mod parallel;
mod picker;
mod refine;
mod stitch;
mod storage;
pub mod subset;
mod traverse;
pub mod triangle;
mod walk;
pub mod windows;

pub use error::TerrainError;
pub use grid::{DEFAULT_ZONE_COLS, DEFAULT_ZONE_ROWS, Grid, Node, NodeId, zone_cells};
pub use parallel::{Parallel, col_sin_cos_dd, row_parallel};
pub use picker::{Hit, Picker, quad_bounds};
pub use storage::{
    TerrainCaches, TerrainStorage, box_frame, node_box_of_vertices, node_frame, ranges_frame,
    vertex_ecef,
};
pub use walk::PickStats;

#[cfg(test)]
mod tests;
