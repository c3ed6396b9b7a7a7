//! Multi-resolution (module docs, "Multi-resolution"): a 9 × 9-vertex DEM whose zone (8 × 8 cells) has a block of
//! stride 2 and four children of 4 × 4 cells at stride 1, with residency and `min_level` chosen per test.

use super::*;
use build::{
    MultiRes, NodeRecord, Parts, SliceStorage, TreeStorage, build_multires_tree, build_tree,
    node_slots,
};
use core::sync::atomic::{AtomicBool, Ordering};
use std::vec;

/// Vertex rows and columns: 20 × 8 cells, so that the builder's 4 × 4-cell leaves (5 × 2) sit under three
/// zones, the first of them 8 × 8 cells with four children.
const ROWS: u32 = 21;
const COLS: u32 = 9;

/// Flat at 0 m except V(1, 4) at 300 m: on the border between the children of columns 0–3 and 4–7, a vertex
/// of the fine block that the zone's stride-2 block does not have.
struct Dem {
    grid: Grid<f64>,
    heights: Vec<f64>,
    nodes: Vec<NodeRecord<f64>>,
    tree: build::Tree,
    resident: Vec<AtomicBool>,
}

fn dem() -> Dem {
    dem_at(10.0)
}

/// [`dem`] with its first row at latitude `lat0`.
fn dem_at(lat0: f64) -> Dem {
    dem_peaked_at(lat0, [1, 4])
}

/// Flat at 0 m except vertex `[i, j]` at 300 m, the first row at latitude `lat0`.
fn dem_peaked_at(lat0: f64, peak: [u32; 2]) -> Dem {
    Dem::flat_with_peaks(lat0, [ROWS, COLS], 4, &[peak])
}

impl Dem {
    /// `rows × cols` vertices of 0.01° from (`lat0`, 20°), flat at 0 m except a 300 m vertex at each of `peaks`,
    /// in the builder's multi-resolution tree with leaves of `block × block` cells under their zones (one level),
    /// every node resident.
    fn flat_with_peaks(lat0: f64, [rows, cols]: [u32; 2], block: u32, peaks: &[[u32; 2]]) -> Dem {
        Dem::flat_on(grid(lat0, 20.0, 0.01, 0.01, rows, cols), block, peaks)
    }
    /// [`Dem::flat_with_peaks`] on any `grid`.
    fn flat_on(grid: Grid<f64>, block: u32, peaks: &[[u32; 2]]) -> Dem {
        let mut heights = vec![0.0; (grid.rows * grid.cols) as usize];
        for &[i, j] in peaks {
            heights[(i * grid.cols + j) as usize] = 300.0;
        }
        let d = Dem::new(grid, heights, block);
        assert_eq!(d.tree.depth(), 1);
        d
    }
    /// `rows × cols` vertices of 0.01° from (10°, 20°) whose heights vary at every vertex (so each stride is a
    /// different surface), in leaves of 4 × 4 cells.
    fn varied(rows: u32, cols: u32) -> Dem {
        let heights = (0..rows * cols)
            .map(|k| 40.0 * f64::from((k % cols * 3 + k / cols * 5) % 7))
            .collect();
        Dem::new(grid(10.0, 20.0, 0.01, 0.01, rows, cols), heights, 4)
    }
    /// `heights` on `grid` in the builder's multi-resolution tree with leaves of `block × block` cells, every
    /// node resident.
    fn new(grid: Grid<f64>, heights: Vec<f64>, block: u32) -> Dem {
        let mut nodes = vec![NodeRecord::EMPTY; node_slots(grid.rows, grid.cols, block)];
        let tree =
            build_multires_tree(&heights, &grid, block, MultiRes::default(), &mut nodes).unwrap();
        let resident = (0..tree.slots()).map(|_| AtomicBool::new(true)).collect();
        Dem {
            grid,
            heights,
            nodes,
            tree,
            resident,
        }
    }
    /// The paged storage: the builder's multi-resolution tree with this DEM's residency flags.
    fn paged(&self) -> SliceStorage<'_, f64, f64, (), AtomicBool> {
        let parts = Parts::new(&self.heights[..], &self.nodes[..]).with_resident(&self.resident);
        TreeStorage::with_buffers(Ellipsoid::wgs84(), self.grid, self.tree, parts).unwrap()
    }
    /// The child covering rows 0–3, columns 0–3.
    fn west_child(&self) -> NodeId {
        self.child([0, 4], [0, 4])
    }
    /// The child covering `rows` and `cols`.
    fn child(&self, rows: [u32; 2], cols: [u32; 2]) -> NodeId {
        self.node(1, rows, cols)
    }
    /// The node at depth `level` covering `rows` and `cols`.
    fn node(&self, level: u8, rows: [u32; 2], cols: [u32; 2]) -> NodeId {
        let k = self
            .nodes
            .iter()
            .position(|n| n.level == level && n.rows == rows && n.cols == cols);
        NodeId(k.unwrap() as u32)
    }
    fn evict(&self, id: NodeId) {
        self.resident[id.0 as usize].store(false, Ordering::Relaxed);
    }
}

fn down_at(e: &Ellipsoid<f64>, lat: f64, lon: f64) -> Ray<f64> {
    radial_ray(e, lat, lon, 2000.0)
}

#[test]
fn missing_leaf_falls_back_to_the_zone_block_stitched_to_its_fine_neighbour() {
    let d = dem();
    d.evict(d.west_child());
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    // West of the border, inside the zone's coarse cell (rows 0–2, columns 2–4): traced from the zone.
    let west = p.pick(&down_at(&e, 10.01, 20.0399)).unwrap().unwrap();
    assert_eq!((west.level, west.stride, west.cell), (0, 2, [0, 2]));
    // Its fan reaches the fine vertex at 300 m: just west of V(1, 4) the surface is almost 300 m high (the
    // coarse cell's own triangles are flat at 0 m there).
    assert!(west.h > 290.0, "{west:?}");
    // East of the border: the resident fine child.
    let east = p.pick(&down_at(&e, 10.01, 20.0401)).unwrap().unwrap();
    assert_eq!((east.level, east.stride), (1, 1));
    assert!(east.h > 290.0, "{east:?}");
    // No crack: rays swept across the border around the T-junction all hit, at heights that vary
    // continuously.
    // (Under Miri a coarser sweep over the same span.)
    let (n, step) = if cfg!(miri) { (4, 1e-4) } else { (400, 1e-6) };
    let mut prev: Option<f64> = None;
    for k in 0..=n {
        let lon = 20.0398 + f64::from(k) * step;
        for lat in [10.0095, 10.01, 10.0105] {
            let h = p.pick(&down_at(&e, lat, lon)).unwrap().unwrap().h; // no crack
            if lat == 10.01 {
                if let Some(q) = prev {
                    assert!((h - q).abs() < 5.0 * step / 1e-6, "lon {lon}: {q} → {h}");
                }
                prev = Some(h);
            }
        }
    }
}

#[test]
fn missing_leaf_falls_back_to_the_zone_block_stitched_to_its_fine_neighbour_to_the_west() {
    // The mirror of the first test: the south-east child (rows 0–3, columns 4–7) evicted, its fine neighbour to
    // the west resident. Just east of V(1, 4) the coarse cell (rows 0–1, columns 4–5) is stitched to it along its
    // west side.
    let d = dem();
    d.evict(d.child([0, 4], [4, 8]));
    coarse_and_fine_beside_the_peak(&d, [10.01, 20.0401], [0, 4], [10.01, 20.0399]);
}

#[test]
fn missing_leaf_falls_back_to_the_zone_block_stitched_to_its_fine_neighbour_to_the_north() {
    // As above across a parallel: V(4, 1) at 300 m lies on row 4, between the south-west child (rows 0–3,
    // evicted) and its fine neighbour to the north (rows 4–7), at a column the zone's stride-2 block does not
    // have. The coarse cell south of it (rows 2–3, columns 0–1) is stitched to it along its north side.
    let d = dem_peaked_at(10.0, [4, 1]);
    d.evict(d.west_child());
    coarse_and_fine_beside_the_peak(&d, [10.0399, 20.01], [2, 0], [10.0401, 20.01]);
}

/// Rays straight down at `coarse` and at `fine` (`[lat, lon]`, degrees), either side of the 300 m vertex on the
/// border between an evicted child and its resident fine neighbour: the first hits the zone's stride-2 block in
/// `cell`, the second the fine child, and both are almost 300 m high (the coarse cell's fan reaches the fine
/// vertex; its own triangles are flat at 0 m there).
fn coarse_and_fine_beside_the_peak(d: &Dem, coarse: [f64; 2], cell: [u32; 2], fine: [f64; 2]) {
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    let c = p.pick(&down_at(&e, coarse[0], coarse[1])).unwrap().unwrap();
    assert_eq!((c.level, c.stride, c.cell), (0, 2, cell));
    assert!(c.h > 290.0, "{c:?}");
    let f = p.pick(&down_at(&e, fine[0], fine[1])).unwrap().unwrap();
    assert_eq!((f.level, f.stride), (1, 1));
    assert!(f.h > 290.0, "{f:?}");
}

#[test]
fn needs_block_below_min_level_and_full_resolution_when_all_resident() {
    let d = dem();
    let w = d.west_child();
    d.evict(w);
    let s = d.paged();
    let e = Ellipsoid::wgs84();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let p = p.with_min_level(1);
    assert_eq!(
        p.pick(&down_at(&e, 10.01, 20.01)),
        Err(TerrainError::NeedsBlock(w))
    );
    // A ray that never reaches the missing child is answered.
    let far = p.pick(&down_at(&e, 10.06, 20.06)).unwrap().unwrap();
    assert_eq!((far.level, far.stride), (1, 1));
    // Everything resident: the full-resolution surface, as the single-resolution storage gives it.
    d.resident[w.0 as usize].store(true, Ordering::Relaxed);
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let mut nodes = vec![NodeRecord::<f64>::EMPTY; node_slots(ROWS, COLS, 4)];
    let tree = build_tree(&d.heights, &d.grid, 4, &mut nodes).unwrap();
    let flat = SliceStorage::new(Ellipsoid::wgs84(), d.grid, &d.heights, &nodes, tree).unwrap();
    let single: Picker<'_, f64, _> = Picker::new(&flat).unwrap();
    for (lat, lon) in [
        (10.01, 20.04),
        (10.013, 20.0399),
        (10.055, 20.011),
        (10.001, 20.079),
    ] {
        let r = down_at(&e, lat, lon);
        let (a, b) = (
            p.pick(&r).unwrap().unwrap(),
            single.pick(&r).unwrap().unwrap(),
        );
        assert_eq!((a.t, a.cell, a.stride), (b.t, b.cell, 1));
    }
}

#[test]
fn ray_over_a_missing_block_before_its_hit_in_a_resident_one_needs_the_block() {
    // The west child missing below `min_level` (no block to fall back to). A ray from 250 m above it, inside its
    // volume (the child's border vertex V(1, 4) is 300 m high), descending eastwards along row 2 onto the flat
    // ground of the resident child east of it: the resident child holds a hit, but the missing block comes first
    // along the ray and could hold a nearer one, so the answer is the block it needs. Once it is resident, the hit.
    let d = dem();
    let w = d.west_child();
    d.evict(w);
    let s = d.paged();
    let e = Ellipsoid::wgs84();
    let ray = ray_between(&e, [10.02, 20.005, 250.0], [10.02, 20.07, 0.0]);
    let p = Picker::<'_, f64, _>::new(&s).unwrap().with_min_level(1);
    assert_eq!(p.pick(&ray), Err(TerrainError::NeedsBlock(w)));
    assert_eq!(p.pick_t(&ray), Err(TerrainError::NeedsBlock(w)));
    d.resident[w.0 as usize].store(true, Ordering::Relaxed);
    let hit = p.pick(&ray).unwrap().unwrap();
    assert_eq!((hit.level, hit.stride), (1, 1));
    assert!(hit.cell[1] >= 4 && hit.h.abs() < 1e-6, "{hit:?}");
}

#[test]
fn ray_in_the_sag_beside_a_fine_vertex_on_the_parallel_shared_with_a_coarse_block_hits_its_stitched_fan()
 {
    // A child missing, so that its cells are traced from the zone's stride-2 block and stitched to the
    // resident fine child across row 4. V(4, 1), a vertex of the fine child on the shared parallel, lies on the
    // latitude cone, which at the middle meridian of the coarse column 0–2 bulges equatorward of the coarse
    // cell's chord plane through V(4, 0) and V(4, 2) (by about 1.7 cm along the plane's normal for these 2 km
    // cells). The coarse cell's stitched fan reaches V(4, 1), so a ray 0.2 to
    // 5 mm from it, on the coarse side, meets the fan between the chord plane and the fine cells' walls: only
    // the coarse cell's wall on that row taken as the cone's tangent plane (its band's convex side: the
    // southern wall in the north, the northern wall in the south) lets the traversal test that fan. North:
    // the child of rows 4–8 missing, rays north of V(4, 1) at 10.04°; south: the child of rows 0–4 missing,
    // rays south of V(4, 1) at −10.16°. The terrain is flat at 0 m there.
    // (one distance under Miri)
    let distances: &[f64] = if cfg!(miri) {
        &[0.001]
    } else {
        &[0.0002, 0.001, 0.005]
    };
    // (a planar triangle lies below the spheroid between its vertices: 1.3 µm at 5 mm from one here)
    stitched_fan_hits(
        [(10.0, [4, 8], [4, 0], 1.0), (-10.2, [0, 4], [2, 0], -1.0)],
        20.01,
        distances,
        [1e-4, 1e-3],
    );
}

#[test]
fn ray_beside_the_fine_chord_on_the_parallel_shared_with_a_coarse_block_hits_its_stitched_fan() {
    // The test above from the other side of the shared parallel: the coarse block equatorward of row 4 (north:
    // the child of rows 0–4 missing; south: the child of rows 4–8), and rays on
    // the coarse side of the parallel midway between V(4, 1) and V(4, 2) (20.015° E). There the coarse cell's
    // wall on row 4 must be its chord plane (the band's concave side): the cone's tangent plane along the
    // coarse column's middle meridian (20.01° E) passes 4 mm on the coarse side of these points (the cone
    // falls away from it by 1 − cos 0.005°), so a coarse cell bounded by it would not test the fan there, while
    // the points lie on the coarse side of the fine cells' walls too (the parallel bulges 4 mm equatorward of
    // the fine chord's plane midway). Rays 0.2 to 2 mm from the parallel; the fan's triangle sags up to 2 cm
    // below the flat 0 m spheroid there.
    let distances: &[f64] = if cfg!(miri) {
        &[0.001]
    } else {
        &[0.0002, 0.001, 0.002]
    };
    stitched_fan_hits(
        [(10.0, [0, 4], [2, 0], -1.0), (-10.2, [4, 8], [4, 0], 1.0)],
        20.015,
        distances,
        [0.05, 0.05],
    );
}

/// The two tests above: for each `(lat0, missing, coarse_cell, away)` of [`dem_at`]`(lat0)`, the child of rows
/// `missing` (columns 0–4) evicted, rays straight down from 2 km onto longitude `lon`, `m` metres of each of
/// `distances` from row 4 (towards `away`: +1 north, −1 south), each hit the zone's stride-2 block in
/// `coarse_cell` with `|h|` and `|t − 2000|` within `[h_tol, t_tol]`.
fn stitched_fan_hits(
    cases: [(f64, [u32; 2], [u32; 2], f64); 2],
    lon: f64,
    distances: &[f64],
    [h_tol, t_tol]: [f64; 2],
) {
    for (lat0, missing, coarse_cell, away) in cases {
        let d = dem_at(lat0);
        d.evict(d.child(missing, [0, 4]));
        let s = d.paged();
        let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
        let e = Ellipsoid::wgs84();
        let lat4 = lat0 + 0.04;
        for &m in distances {
            // metres as degrees of latitude (1° is about 110.6 km there)
            let ray = down_at(&e, lat4 + away * m / 110_600.0, lon);
            let what = std::format!("{m} m from row 4 at {lat4}°, {lon}°");
            let hit = p.pick(&ray).unwrap();
            assert!(hit.is_some(), "{what}: no hit");
            let hit = hit.unwrap();
            assert_eq!(
                (hit.level, hit.stride, hit.cell),
                (0, 2, coarse_cell),
                "{what}: {hit:?}"
            );
            assert!(hit.h.abs() < h_tol, "{what}: {hit:?}");
            assert!((hit.t - 2000.0).abs() < t_tol, "{what}: {hit:?}");
        }
    }
}

#[test]
fn low_ray_over_flat_coarse_corners_hits_the_stitched_fan_rising_to_a_fine_peak() {
    // The child of rows 0–4, columns 0–3 missing: the coarse cell of rows 0–2, columns 2–4 (corners all at 0 m)
    // is stitched to the fine vertex V(1, 4) at 300 m on its eastern side, so its fan rises to 300 m there. A ray
    // from 350 m up, west of it, descending eastwards at about 1 in 30 towards a point of that fan 1 m below its
    // top (it meets the fan 1.2 m below, just beyond that point) passes far above the coarse cell's four corners: the cell must still be traced through its fan, not
    // skipped by the height cull of plain cells (the fan's vertices are not the cell's corners).
    let d = dem();
    d.evict(d.west_child());
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    let from = e.geodetic_deg_to_ecef(10.01, 20.025, 350.0);
    let to = e.geodetic_deg_to_ecef(10.01, 20.0399, 299.0);
    let ray = Ray::new(from, to.minus(from)).unwrap();
    let hit = p.pick(&ray).unwrap();
    assert!(hit.is_some(), "no hit");
    let hit = hit.unwrap();
    assert_eq!((hit.level, hit.stride, hit.cell), (0, 2, [0, 2]), "{hit:?}");
    assert!(hit.h > 290.0 && hit.t < 1.01, "{hit:?}");
}

/// The refinement of hits on a coarse block's cells (`refine.rs`, `refine_vertices`: coarse cells and stitched
/// fans have no containment walk): the west child missing, rays slanting down from 2 km and 300 km onto the
/// zone's stride-2 cell of rows 0–2, columns 0–2 (on the grid's edges: no finer neighbour to stitch to). Each
/// hit's `t` is where the ray meets its coarse triangle's plane through the contract's vertices in pairs, within
/// 1e-10 m, where the traversal's `t` (`pick_t`, from the vertices rounded to `f64`) is off by far more.
#[test]
fn refined_hits_on_a_coarse_blocks_cell_lie_on_its_triangles_exact_plane() {
    let d = dem();
    d.evict(d.west_child());
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    let v = |i: u32, j: u32| {
        let h = d.heights[(i * COLS + j) as usize];
        let (so, co) = parallel::col_sin_cos_dd(&d.grid, j);
        parallel::row_parallel(&e, &d.grid, i).ecef(so, co, h)
    };
    let tris = [[v(0, 0), v(0, 2), v(2, 2)], [v(0, 0), v(2, 2), v(2, 0)]];
    let mut r = Lcg(17);
    let (mut worst_refined, mut worst_traversal) = (0.0_f64, 0.0_f64);
    // (under Miri, whose interpreter is slow, the first four rays)
    let n = if cfg!(miri) { 4 } else { 40 };
    for k in 0..n {
        let lat = d.grid.lat_deg(0) + 0.002 + 0.016 * r.next();
        let lon = d.grid.lon_deg(0) + 0.002 + 0.016 * r.next();
        let target = e.geodetic_deg_to_ecef(lat, lon, 0.0);
        let up = e.normal_rad(lat.to_radians(), lon.to_radians());
        let dir = V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5).minus(up);
        let dist = if k % 2 == 0 { 2000.0 } else { 3.0e5 };
        let ray = Ray::new(target.add_scaled(-dist / dir.length(), dir), dir).unwrap();
        let hit = p.pick(&ray).unwrap().unwrap();
        let (t_trav, _) = p.pick_t(&ray).unwrap().unwrap();
        assert_eq!(
            (hit.level, hit.stride, hit.cell),
            (0, 2, [0, 0]),
            "ray {k}: {hit:?}"
        );
        let t_exact = nearest_plane_t(&ray, hit.t, tris);
        let len = ray.dir().length();
        worst_refined = worst_refined.max((hit.t - t_exact).abs() * len);
        worst_traversal = worst_traversal.max((t_trav - t_exact).abs() * len);
    }
    assert!(worst_refined < 1e-10, "refined: {worst_refined} m");
    assert!(
        worst_traversal > 100.0 * worst_refined,
        "traversal {worst_traversal} m, refined {worst_refined} m"
    );
}

#[test]
fn missing_inner_node_lets_its_resident_leaves_answer_and_a_missing_leaf_below_it_falls_back_to_the_zone()
 {
    // 65 × 65 vertices: zones of 16 × 16 cells (block stride 4) over nodes of 8 × 8 cells (stride 2) over leaves
    // of 4 × 4 cells (stride 1). Heights vary at every vertex, so each stride is a different surface.
    let d = Dem::varied(65, 65);
    assert_eq!(d.tree.depth(), 2);
    // The zone's first inner node (rows and columns 0–7) missing, and one of its leaves (rows 4–7, columns 0–3).
    d.evict(d.node(1, [0, 8], [0, 8]));
    d.evict(d.node(2, [4, 8], [0, 4]));
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    // Under the missing inner node a resident leaf answers with its own block ...
    let leaf = p.pick(&down_at(&e, 10.015, 20.015)).unwrap().unwrap();
    assert_eq!((leaf.level, leaf.stride, leaf.cell), (2, 1, [1, 1]));
    // ... and the missing leaf is traced with the nearest resident ancestor's block, the zone's (stride 4).
    let coarse = p.pick(&down_at(&e, 10.055, 20.015)).unwrap().unwrap();
    assert_eq!((coarse.level, coarse.stride, coarse.cell), (0, 4, [4, 0]));
}

/// [`Dem::varied`] with 129 × 129 vertices: zones of 32 × 32 cells (block stride 8) over nodes of 16 × 16
/// (stride 4), 8 × 8 (stride 2) and leaves of 4 × 4 (stride 1). With the first zone's node of rows and
/// columns 0–15 missing and its child of rows and columns 0–7 too, the source is the zone's stride-8 block. Its
/// cells (8 grid steps) fit the first node's children (rows and columns 0–7 and 8–15), so the traversal goes on
/// down; they do not fit the second node's (0–3 and 4–7), so that node is traced whole with the zone's block, although its
/// leaves are resident (descending to them would also trace the deeper blocks' cells under a coarser parent's).
#[test]
fn missing_node_whose_children_are_off_the_sources_lattice_is_traced_whole_with_the_source_block() {
    let d = Dem::varied(129, 129);
    assert_eq!(d.tree.depth(), 3);
    d.evict(d.node(1, [0, 16], [0, 16]));
    d.evict(d.node(2, [0, 8], [0, 8]));
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    // Over the second node: the zone's block (stride 8, its cell of rows and columns 0–7).
    let coarse = p.pick(&down_at(&e, 10.015, 20.025)).unwrap().unwrap();
    assert_eq!((coarse.level, coarse.stride, coarse.cell), (0, 8, [0, 0]));
    // Over the first node's next child (rows 0–7, columns 8–15, resident): its resident leaves.
    let own = p.pick(&down_at(&e, 10.015, 20.105)).unwrap().unwrap();
    assert_eq!((own.level, own.stride), (3, 1));
}

/// One zone that is a resident leaf over cell rows `rows` and columns `cols` of a `grid`, its block of stride
/// `stride`, flat at 100 m: a tree made by hand (the builder's are always on their lattice).
struct OneLeaf {
    grid: Grid<f64>,
    rows: [u32; 2],
    cols: [u32; 2],
    stride: u32,
}

impl TerrainStorage<f64> for OneLeaf {
    fn ellipsoid(&self) -> Ellipsoid<f64> {
        Ellipsoid::wgs84()
    }
    fn grid(&self) -> Grid<f64> {
        self.grid
    }
    fn zone_count(&self) -> usize {
        1
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        (k == 0).then_some(NodeId(0))
    }
    fn node(&self, id: NodeId) -> Option<Node<f64>> {
        (id == NodeId(0)).then_some(Node {
            rows: self.rows,
            cols: self.cols,
            heights: Some([100.0, 100.0]),
            children: [None; 4],
            level: 0,
        })
    }
    fn height(&self, i: u32, j: u32) -> Option<f64> {
        (i < self.grid.rows && j < self.grid.cols).then_some(100.0)
    }
    fn block_stride(&self, _: NodeId) -> u32 {
        self.stride
    }
}

impl TerrainCaches<f64> for OneLeaf {}

#[test]
fn coarse_block_off_its_lattice_is_a_malformed_tree_and_one_ending_on_the_grids_last_odd_row_is_not()
 {
    // A stride-2 block must start on even rows and columns and end on even ones or on the grid's last: a ray
    // straight down onto its middle gets `MalformedTree` unless it does, and the flat surface otherwise.
    let e = Ellipsoid::wgs84();
    let ray = radial_ray(&e, 10.035, 20.035, 1000.0);
    let answer = |vertex_rows: u32, rows: [u32; 2], cols: [u32; 2]| {
        let s = OneLeaf {
            grid: grid(10.0, 20.0, 0.01, 0.01, vertex_rows, 9),
            rows,
            cols,
            stride: 2,
        };
        let p: Picker<'_, f64, OneLeaf> = Picker::new(&s).unwrap();
        p.pick(&ray).map(|h| h.map(|h| (h.cell, h.stride)))
    };
    // On the lattice: 8 × 8 cells; 7 rows of cells, the last (odd) one the grid's.
    assert_eq!(answer(9, [0, 8], [0, 8]), Ok(Some(([2, 2], 2))));
    assert_eq!(answer(8, [0, 7], [0, 8]), Ok(Some(([2, 2], 2))));
    // Off it: starting on an odd row or column; ending on an odd row that is not the grid's last.
    assert_eq!(answer(9, [1, 8], [0, 8]), Err(TerrainError::MalformedTree));
    assert_eq!(answer(9, [0, 8], [1, 8]), Err(TerrainError::MalformedTree));
    assert_eq!(answer(9, [0, 7], [0, 8]), Err(TerrainError::MalformedTree));
}

/// The work of rays over the zone's coarse cells stitched to the fine child east of them (the west child
/// missing), pinned as in `work.rs`: straight down just west of the 300 m vertex and in a coarse cell north of it,
/// a ray along row 1 from the west onto the fan's slope, and a shallow one from the north-west across the
/// coarse cells onto the fine child's slope. The rows: ray, hit cell and stride, quads visited,
/// triangle pairs visited, triangles tested (a stitched cell's fan triangles included).
#[test]
fn rays_over_stitched_coarse_cells_do_the_pinned_work() {
    // ray, the hit's cell and stride, and the work
    type Pinned = (usize, Option<([u32; 2], u32)>, [u32; 3]);
    let want: [Pinned; 4] = [
        (0, Some(([0, 2], 2)), [2, 1, 5]),
        (1, Some(([2, 2], 2)), [2, 1, 6]),
        (2, Some(([0, 2], 2)), [2, 2, 5]),
        (3, Some(([1, 4], 1)), [3, 4, 18]),
    ];
    let d = dem();
    d.evict(d.west_child());
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    let rays = [
        ([10.01, 20.0399, 2000.0], [10.01, 20.0399, -100.0]),
        ([10.025, 20.025, 2000.0], [10.025, 20.025, -100.0]),
        ([10.011, 20.001, 400.0], [10.011, 20.06, -100.0]),
        ([10.035, 20.002, 150.0], [10.005, 20.07, 0.0]),
    ];
    for (k, &(from, to)) in rays.iter().enumerate() {
        let (hit, work) = pick_counted(&p, &ray_between(&e, from, to));
        let got = (k, hit.map(|h| (h.cell, h.stride)), work);
        assert!(want.contains(&got), "{got:?}");
    }
}

/// The west child missing, the zone's stride-2 cell over rows 2–4, columns 0–2 is stitched to the fine child
/// north of it; its west side lies on the grid's west edge, so the fan triangle `M V(2, 0) V(4, 0)` (`M` the
/// middle of the cell's diagonal) has an outer edge with no triangle across. Straight-down rays onto points swept
/// across that edge's middle in steps of 0.5 nm from 4 nm outside to 4 nm inside (within the scalar vertices'
/// rounding) must hit exactly when, by the contract's vertices in pairs, they pass through the closed triangle
/// (as `border.rs` sweeps the outer edges of full-resolution cells): the fan's outer edge is decided exactly too.
#[test]
#[cfg_attr(miri, ignore)] // 17 picks and pair arithmetic: slow there, and border.rs covers the exact test itself
fn rays_swept_across_a_stitched_coarse_cells_outer_edge_hit_exactly_the_closed_fan_triangle() {
    use super::border::{dd3, ray_down_onto, side_along};
    let d = dem();
    d.evict(d.west_child());
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let surface = Surface {
        e: Ellipsoid::wgs84(),
        grid: d.grid,
        heights: d.heights.clone(),
    };
    let pair = |i: u32, j: u32| surface.vertex_dd(i, j).unwrap();
    let (da, db, corner) = (pair(2, 0), pair(4, 0), pair(4, 2));
    let dm = [0, 1, 2].map(|k| da[k].plus(corner[k]).times_t(0.5));
    let [va, vb, vm] = [da, db, dm].map(|q| V3::new(q[0].value(), q[1].value(), q[2].value()));
    let e = vb.minus(va);
    let foot = va.add_scaled(vm.minus(va).dot(e) / e.dot(e), e);
    let inward = vm.minus(foot).scaled(1.0 / vm.minus(foot).length());
    let mid = va.add_scaled(0.5, e);
    let (mut hits, mut misses) = (0, 0);
    for step in -8..=8 {
        let ray = ray_down_onto(&surface.e, mid.add_scaled(0.5e-9 * f64::from(step), inward));
        let side = side_along(&ray, da, db, dd3(ray.origin()));
        let third = side_along(&ray, da, db, dm);
        let inside = side == 0.0 || (side > 0.0) == (third > 0.0);
        let hit = p.pick(&ray).unwrap();
        assert_eq!(hit.is_some(), inside, "{step} × 0.5 nm: {hit:?}");
        if let Some(h) = hit {
            assert_eq!((h.cell, h.stride), ([2, 0], 2), "{step} × 0.5 nm");
            hits += 1;
        } else {
            misses += 1;
        }
    }
    assert!(hits > 0 && misses > 0, "{hits} hits, {misses} misses");
}

/// A stride-2 block over 8 × 7 cells: its last column is one cell wide (longitudes 20.06° to 20.07°), so its
/// middle meridian and half width are not the full columns' (`clip_column`). Its row walls are the chord planes
/// through that column's own ends. Rays straight down (along the normal, so parallel to the walls) either side
/// of each of its rows, near both ends and in the middle of the column, hit the cell they are over, at its flat
/// 100 m (to the triangles' sag below the spheroid, a few cm): 1.1 mm and 1.1 cm south of the parallel, and north
/// of the chord, which lies poleward of the parallel by its sag (4 mm at the middle, 0.2 mm 0.0001° from an
/// end): 1.1 mm and 1.1 cm north near the ends, 1.1 cm at the middle. (A chord through a column twice as wide,
/// from 20.06° to 20.08°, would lie 8 mm further north at the middle and 16 mm near the east end.)
#[test]
fn straight_down_rays_either_side_of_a_row_in_a_coarse_blocks_narrow_last_column_hit_the_cell_below_them()
 {
    let s = OneLeaf {
        grid: grid(10.0, 20.0, 0.01, 0.01, 9, 8),
        rows: [0, 8],
        cols: [0, 7],
        stride: 2,
    };
    let p: Picker<'_, f64, OneLeaf> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    // 1e-8° and 1e-7° of latitude: 1.1 mm and 1.1 cm
    let near_end: &[f64] = &[-1e-7, -1e-8, 1e-8, 1e-7];
    let middle: &[f64] = &[-1e-7, -1e-8, 1e-7];
    let lons: &[(f64, &[f64])] = if cfg!(miri) {
        &[(20.0699, near_end)]
    } else {
        &[(20.0601, near_end), (20.065, middle), (20.0699, near_end)]
    };
    for &(lon, offsets) in lons {
        for row in [2u32, 4, 6] {
            let lat_row = 10.0 + 0.01 * f64::from(row);
            for &dlat in offsets {
                let hit = p
                    .pick(&radial_ray(&e, lat_row + dlat, lon, 1000.0))
                    .unwrap();
                let want = if dlat < 0.0 { row - 2 } else { row };
                assert!(hit.is_some(), "{lon} {lat_row} {dlat}: no hit");
                let h = hit.unwrap();
                assert_eq!((h.cell, h.stride), ([want, 6], 2), "{lon} {lat_row} {dlat}");
                assert!((h.h - 100.0).abs() < 0.2, "{lon} {lat_row} {dlat}: {h:?}");
            }
        }
    }
}

/// A stride-4 block over 8 × 7 cells: its last column is three cells wide (longitudes 20.04° to 20.07°), and as
/// the grid's last it is a border column, whose row walls are the tangent plane along its middle meridian and the
/// chord plane through its own ends (`border_wall`). Rays almost level, from 99.99 m to 99.9 m high, along the
/// column 4.4 cm south of its middle row (latitude 10.04° − 4e-7°), either way, do pinned work (`work.rs`): the
/// eastward one crosses one triangle pair, under the surface; the westward one crosses three and hits the
/// western column (its line runs on beyond the segment given). The northern cell's tangent wall lies south of
/// the row by the parallel's sag over half the column (about 3.7 cm at its ends), so the rays stay outside it.
/// A half width taken from a column of the full stride, or any other, moves that wall's meridian: a ninth of the
/// half width puts it along 20.0417°, 13 cm south of the row at the far end, and the eastward ray then visits
/// the northern cell too.
#[test]
fn level_rays_along_a_coarse_blocks_narrow_last_column_south_of_a_row_do_the_pinned_work() {
    let s = OneLeaf {
        grid: grid(10.0, 20.0, 0.01, 0.01, 9, 8),
        rows: [0, 8],
        cols: [0, 7],
        stride: 4,
    };
    let p: Picker<'_, f64, OneLeaf> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    let lat = 10.04 - 4e-7;
    let cases = [
        ((20.0401, 20.0699), None, [1, 1, 2]),
        ((20.0699, 20.0401), Some(([0, 0], 4)), [1, 3, 6]),
    ];
    for ((a, b), want_hit, want_work) in cases {
        let (hit, work) = pick_counted(&p, &ray_between(&e, [lat, a, 99.99], [lat, b, 99.9]));
        assert_eq!(
            (hit.map(|h| (h.cell, h.stride)), work),
            (want_hit, want_work),
            "from {a}° to {b}°"
        );
    }
}

/// A missing block after the hit, in a zone visited before the zone of the hit: the ray runs level at 1 m,
/// eastward along the border of the first two zones (10.08°), 4.4 cm south of it, from the west edge. Its
/// line is a chord of the parallel, so it bulges north across the border into the second zone and dips to the
/// ground there; after the hit it would come back south, into the first zone's south-east child, which is
/// missing below `min_level`. The first zone is entered first and the missing child recorded, at its entry
/// beyond the hit; the answer is the hit, not the block (`nearest`: a missing block matters only before the
/// nearest hit).
#[test]
fn missing_block_entered_beyond_the_hit_in_a_zone_visited_first_does_not_replace_the_hit() {
    let d = dem();
    d.evict(d.child([4, 8], [4, 8]));
    let s = d.paged();
    let p = Picker::<'_, f64, _>::new(&s).unwrap().with_min_level(1);
    let e = Ellipsoid::wgs84();
    let lat = 10.08 - 4e-7;
    let ray = ray_between(&e, [lat, 20.0, 1.0], [lat, 20.08, 1.0]);
    let hit = p.pick(&ray).unwrap().unwrap();
    assert_eq!((hit.cell, hit.stride, hit.level), ([8, 1], 1, 1), "{hit:?}");
    // on the flat ground, to the triangles' sag below the spheroid (2 cm)
    assert!(hit.lat_deg > 10.08 && hit.h.abs() < 0.05, "{hit:?}");
    assert_eq!(p.pick_t(&ray).map(|t| t.map(|t| t.1)), Ok(Some(hit.cell)));
}

/// The west child missing, its area traced from the zone's stride-2 block: the full-resolution cell (3, 4) east
/// of the border meets the coarse cell (rows 2–4, columns 2–4) across its west side, the meridian 20.04°.
/// Grazing rays from the west (1 m up, 2.2 km away) aimed at points swept across that side in steps of 1 nm,
/// from 40 nm west to 40 nm east of it, meet the surface at a tie of the two cells. A hit on cell (3, 4) is
/// refined on that cell's triangles only: its `t` is where the ray meets one of their planes (computed in pairs,
/// within 1e-10 m), or, when the refined point lies beyond the side and the containment walk would have to step
/// into the coarse cell (whose triangles are not the full-resolution ones), the traversal's own `t`.
#[test]
fn grazing_hits_at_the_side_of_a_full_resolution_cell_shared_with_a_coarse_cell_are_refined_on_its_own_triangles()
 {
    let d = dem();
    d.evict(d.west_child());
    let s = d.paged();
    let p = Picker::<'_, f64, _>::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    let surface = Surface {
        e,
        grid: d.grid,
        heights: d.heights.clone(),
    };
    let pair = |i: u32, j: u32| surface.vertex_dd(i, j).unwrap();
    let tris = [
        [pair(3, 4), pair(3, 5), pair(4, 5)],
        [pair(3, 4), pair(4, 5), pair(4, 4)],
    ];
    let v = |i: u32, j: u32| {
        e.geodetic_deg_to_ecef(10.0 + 0.01 * f64::from(i), 20.0 + 0.01 * f64::from(j), 0.0)
    };
    let (a, b) = (v(3, 4), v(4, 4));
    let east = v(3, 5).minus(a);
    let east = east.scaled(1.0 / east.length());
    let o = e.geodetic_deg_to_ecef(10.033, 20.02, 1.0);
    let step = if cfg!(miri) { 10 } else { 1 };
    let (mut on_plane, mut kept) = (0, 0);
    for k in (-40..=40).step_by(step) {
        let target = a
            .add_scaled(0.3, b.minus(a))
            .add_scaled(1e-9 * f64::from(k), east);
        let ray = Ray::new(o, target.minus(o)).unwrap();
        let hit = p.pick(&ray).unwrap().unwrap();
        if (hit.cell, hit.stride) != ([3, 4], 1) {
            continue;
        }
        let traversal = p.pick_t(&ray).unwrap().unwrap().0;
        let plane = nearest_plane_t(&ray, hit.t, tris);
        let off = (hit.t - plane).abs() * ray.dir().length();
        if off <= 1e-10 {
            on_plane += 1;
        } else {
            assert_eq!(hit.t, traversal, "{k} nm: {off} m off the cell's planes");
            kept += 1;
        }
    }
    assert!(
        on_plane > 0 && (kept > 0 || cfg!(miri)),
        "{on_plane} refined, {kept} kept"
    );
}

mod polar;
mod sides;
