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
    let mut heights = vec![0.0; (ROWS * COLS) as usize];
    heights[9 + 4] = 300.0;
    let grid = grid(10.0, 20.0, 0.01, 0.01, ROWS, COLS);
    let mut nodes = vec![NodeRecord::EMPTY; node_slots(ROWS, COLS, 4)];
    let tree = build_multires_tree(&heights, &grid, 4, MultiRes::default(), &mut nodes).unwrap();
    assert_eq!(tree.depth(), 1);
    let resident = (0..tree.slots()).map(|_| AtomicBool::new(true)).collect();
    Dem {
        grid,
        heights,
        nodes,
        tree,
        resident,
    }
}

impl Dem {
    /// The paged storage: the builder's multi-resolution tree with this DEM's residency flags.
    fn paged(&self) -> SliceStorage<'_, f64, f64, (), AtomicBool> {
        let parts = Parts::new(&self.heights[..], &self.nodes[..]).with_resident(&self.resident);
        TreeStorage::with_buffers(Ellipsoid::wgs84(), self.grid, self.tree, parts).unwrap()
    }
    /// The child covering rows 0–3, columns 0–3.
    fn west_child(&self) -> NodeId {
        let k = self
            .nodes
            .iter()
            .position(|n| n.level == 1 && n.rows == [0, 4] && n.cols == [0, 4]);
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
