//! The work of a pick, counted exactly ([`PickStats`]) on named rays: how many quads, triangle pairs and triangles
//! the traversal visits is part of what it must get right (a walk that visits more finds the same hit, slower), so
//! these counts are pinned. A change that alters them on purpose updates them here, and says why.

use super::*;

/// A rough regional DEM of 33 × 33 vertices (0.01° cells at 45° N, 7° E, heights 0–400 m from a fixed
/// sequence) in leaves of `block × block` cells, without node boxes (0), with each child's box in its parent's
/// own frame (1), with every box below the zones in its zone's frame (2), or with the zones' children's boxes in
/// the grid's frame and every deeper box in its parent's own (3: a node two levels down then needs a frame whose
/// parent did not form one).
fn rough(block: u32, boxes: u8) -> TestDem {
    let g = grid(45.0, 7.0, 0.01, 0.01, 33, 33);
    let mut r = Lcg(7);
    let hs: Vec<f64> = (0..33 * 33).map(|_| 400.0 * r.next()).collect();
    match boxes {
        0 => TestDem::new(g, hs, block),
        1 => TestDem::with_boxes(g, hs, block, |_, _| false),
        2 => TestDem::with_boxes(g, hs, block, |_, _| true),
        _ => TestDem::with_boxes(g, hs, block, |_, level| level == 1),
    }
}

/// A pinned row: the volumes' kind, the block, the ray, the hit's cell, and quads visited, triangle pairs visited,
/// triangles tested.
type Pinned = (u8, u32, usize, Option<[u32; 2]>, [u32; 3]);

/// The rays of these tests, from geodetic `from` to `to` (latitude, longitude in degrees, height in metres).
const RAYS: [([f64; 3], [f64; 3]); 4] = [
    // straight down onto a cell's middle
    ([45.155, 7.155, 2000.0], [45.155, 7.155, -100.0]),
    // from 1 km up in the south-west corner, shallow, north-east across several leaves
    ([45.005, 7.005, 1000.0], [45.3, 7.3, -500.0]),
    // the same, heading south-west from the north-east corner
    ([45.315, 7.315, 1000.0], [45.0, 7.0, -500.0]),
    // just above the highest vertex, west to east over the whole DEM: no hit, every quad on the way visited
    ([45.163, 6.95, 420.0], [45.163, 7.4, 405.0]),
];

/// The hit and the work of each ray on [`rough`] with leaves of 2 × 2, 4 × 4 and 8 × 8 cells, with the three
/// kinds of volumes (spheroidal, boxes in their parents' frames, in their zones' frames, and mixed), against the brute
/// force. The rows: volumes, block, ray (index into [`RAYS`]), the hit's cell, and quads visited, triangle pairs
/// visited, triangles tested. With node boxes and leaves of 8 × 8 cells the leaves have windows (`windows.rs`):
/// the ray just above the terrain then crosses 12 triangle pairs instead of the 19 of its leaves' whole walk.
#[test]
fn rays_straight_down_shallow_both_ways_and_just_above_the_terrain_do_the_pinned_work() {
    let want: [Pinned; 48] = [
        (0, 2, 0, Some([15, 15]), [3, 1, 2]),
        (0, 2, 1, Some([13, 13]), [7, 5, 10]),
        (0, 2, 2, Some([15, 15]), [11, 7, 4]),
        (0, 2, 3, None, [11, 8, 8]),
        (0, 4, 0, Some([15, 15]), [2, 1, 2]),
        (0, 4, 1, Some([13, 13]), [4, 5, 10]),
        (0, 4, 2, Some([15, 15]), [6, 5, 4]),
        (0, 4, 3, None, [7, 12, 8]),
        (0, 8, 0, Some([15, 15]), [1, 1, 2]),
        (0, 8, 1, Some([13, 13]), [1, 5, 10]),
        (0, 8, 2, Some([15, 15]), [3, 5, 4]),
        (0, 8, 3, None, [4, 27, 8]),
        (1, 2, 0, Some([15, 15]), [3, 1, 2]),
        (1, 2, 1, Some([13, 13]), [7, 5, 10]),
        (1, 2, 2, Some([15, 15]), [11, 7, 4]),
        (1, 2, 3, None, [11, 8, 8]),
        (1, 4, 0, Some([15, 15]), [2, 1, 2]),
        (1, 4, 1, Some([13, 13]), [4, 5, 10]),
        (1, 4, 2, Some([15, 15]), [6, 5, 4]),
        (1, 4, 3, None, [6, 12, 8]),
        (1, 8, 0, Some([15, 15]), [1, 1, 2]),
        (1, 8, 1, Some([13, 13]), [1, 5, 10]),
        (1, 8, 2, Some([15, 15]), [3, 5, 4]),
        (1, 8, 3, None, [3, 12, 8]),
        (2, 2, 0, Some([15, 15]), [3, 1, 2]),
        (2, 2, 1, Some([13, 13]), [7, 5, 10]),
        (2, 2, 2, Some([15, 15]), [11, 7, 4]),
        (2, 2, 3, None, [10, 8, 8]),
        (2, 4, 0, Some([15, 15]), [2, 1, 2]),
        (2, 4, 1, Some([13, 13]), [4, 5, 10]),
        (2, 4, 2, Some([15, 15]), [6, 5, 4]),
        (2, 4, 3, None, [6, 12, 8]),
        (2, 8, 0, Some([15, 15]), [1, 1, 2]),
        (2, 8, 1, Some([13, 13]), [1, 5, 10]),
        (2, 8, 2, Some([15, 15]), [3, 5, 4]),
        (2, 8, 3, None, [3, 12, 8]),
        (3, 2, 0, Some([15, 15]), [3, 1, 2]),
        (3, 2, 1, Some([13, 13]), [7, 5, 10]),
        (3, 2, 2, Some([15, 15]), [11, 7, 4]),
        (3, 2, 3, None, [10, 8, 8]),
        (3, 4, 0, Some([15, 15]), [2, 1, 2]),
        (3, 4, 1, Some([13, 13]), [4, 5, 10]),
        (3, 4, 2, Some([15, 15]), [6, 5, 4]),
        (3, 4, 3, None, [6, 12, 8]),
        (3, 8, 0, Some([15, 15]), [1, 1, 2]),
        (3, 8, 1, Some([13, 13]), [1, 5, 10]),
        (3, 8, 2, Some([15, 15]), [3, 5, 4]),
        (3, 8, 3, None, [3, 12, 8]),
    ];
    // (under Miri, whose interpreter is slow, leaves of 4 × 4 cells under spheroidal volumes and mixed frames only)
    let (kinds, blocks): (&[u8], &[u32]) = if cfg!(miri) {
        (&[0, 3], &[4])
    } else {
        (&[0, 1, 2, 3], &[2, 4, 8])
    };
    for &boxes in kinds {
        for &block in blocks {
            let dem = rough(block, boxes);
            let s = dem.storage();
            let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
            let e = dem.surface.e;
            for (k, &(from, to)) in RAYS.iter().enumerate() {
                let ray = ray_between(&e, from, to);
                let (hit, work) = pick_counted(&p, &ray);
                let got = (boxes, block, k, hit.map(|h| h.cell), work);
                assert!(want.contains(&got), "{got:?}");
                // (under Miri the brute force over the 2 048 triangles takes minutes)
                if !cfg!(miri) {
                    same_hit(
                        &ray,
                        hit.map(|h| (h.t, h.cell)),
                        dem.surface.brute(&ray),
                        "pinned work",
                    );
                }
            }
        }
    }
}

/// The global 5.625° grid of [`global_relief`] in leaves of 2 × 2 cells under the builder's 8 × 4 zones, with
/// node boxes: a zone is clipped by its box in the grid's frame and then by its own volume (a global grid's boxes
/// tilt by up to 180°). Rays from orbit straight down, across the antimeridian, and toward the north pole, landing just
/// short of it; the rows: ray, hit cell, quads visited, triangle pairs visited, triangles tested.
#[test]
#[cfg_attr(miri, ignore)] // building the global grid's boxes takes minutes there
fn rays_from_orbit_over_a_global_grid_do_the_pinned_work() {
    let want: [(usize, Option<[u32; 2]>, [u32; 3]); 3] = [
        (0, Some([21, 39]), [3, 1, 2]),
        (1, Some([16, 1]), [3, 1, 2]),
        (2, Some([29, 32]), [3, 1, 2]),
    ];
    let (g, hs, _) = global_relief();
    let dem = TestDem::with_boxes(g, hs, 2, |_, _| false);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let rays = [
        ([30.0, 40.0, 3.0e7], [30.0, 40.0, 0.0]),
        ([-10.0, 170.0, 2.0e6], [5.0, -170.0, 0.0]),
        ([60.0, 1.0, 1.0e6], [70.0, 179.0, 0.0]),
    ];
    for (k, &(from, to)) in rays.iter().enumerate() {
        let ray = ray_between(&e, from, to);
        let (hit, work) = pick_counted(&p, &ray);
        let got = (k, hit.map(|h| h.cell), work);
        assert!(want.contains(&got), "{got:?}");
        if !cfg!(miri) {
            same_hit(
                &ray,
                hit.map(|h| (h.t, h.cell)),
                dem.surface.brute(&ray),
                "global pinned work",
            );
        }
    }
}

/// Rays passing just outside the regional DEM of [`rough`] (leaves of 4 × 4 cells, with node boxes), level
/// with its highest vertices, inside the zone's box in the grid's frame but outside its volume: 2 m north of
/// the northern edge heading east, and 1.1 m east of the eastern edge heading north. A regional grid's zones are
/// clipped by their boxes alone (tight there, where a global grid's tilt), so the traversal enters the zone and
/// the boxes below it before finding nothing: pinned, as above (volumes, ray, quads visited, triangle pairs
/// visited, triangles tested).
#[test]
fn rays_just_outside_a_regional_dems_edges_enter_its_zones_box_and_do_the_pinned_work() {
    let want: [(u8, usize, [u32; 3]); 6] = [
        (1, 0, [1, 0, 0]),
        (1, 1, [10, 0, 0]),
        (2, 0, [3, 0, 0]),
        (2, 1, [10, 0, 0]),
        (3, 0, [3, 0, 0]),
        (3, 1, [10, 0, 0]),
    ];
    let rays = [
        ([45.320018, 7.25, 345.0], [45.320018, 7.35, 337.0]),
        ([44.9856, 7.32001, 382.0], [45.0856, 7.32001, 368.0]),
    ];
    let kinds: &[u8] = if cfg!(miri) { &[3] } else { &[1, 2, 3] };
    for &boxes in kinds {
        let dem = rough(4, boxes);
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        let e = dem.surface.e;
        for (k, &(from, to)) in rays.iter().enumerate() {
            let (hit, work) = pick_counted(&p, &ray_between(&e, from, to));
            assert!(hit.is_none(), "{boxes} {k}: {hit:?}");
            assert!(want.contains(&(boxes, k, work)), "{:?}", (boxes, k, work));
        }
    }
}

/// A ray descending eastward into a cell of [`rough`] (leaves of 4 × 4 cells, no boxes) 1.1 mm north of row 16,
/// the southern border of a leaf, from 410 m to 0 m over 0.0029° of longitude: pinned, as above. A
/// full-resolution leaf's border cells keep the chord planes of their rows as walls, shared with the cells
/// across; only a coarse unit's border cells (which may be stitched) take the wider walls of `border_wall`, and
/// with those here the height cull would pass two more triangles.
#[test]
fn ray_along_a_full_resolution_leafs_border_row_does_the_pinned_work() {
    let dem = rough(4, 0);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let lat = 45.16 + 1e-8;
    let ray = ray_between(&e, [lat, 7.1201, 410.0], [lat, 7.123, 0.0]);
    let (hit, work) = pick_counted(&p, &ray);
    assert_eq!((hit.map(|h| h.cell), work), (Some([15, 12]), [4, 2, 2]));
    if !cfg!(miri) {
        same_hit(
            &ray,
            hit.map(|h| (h.t, h.cell)),
            dem.surface.brute(&ray),
            "along a border row",
        );
    }
}
