//! Coarse cells on every side of a missing leaf (multi-resolution, Wartell et al. §6): which of a coarse unit's
//! cells are stitched, and the fine cells beside a missing block.

use super::*;

/// 64 × 64 cells in leaves of 8 × 8 (zones of 16 × 16, each with a stride-2 block over its four leaves), flat at
/// 0 m except one 300 m vertex on each side of the leaf over rows and columns 8–16, at a row or column that the
/// zone's stride-2 block does not have: V(8, 11) south, V(16, 13) north, V(11, 8) west, V(13, 16) east. That
/// leaf's neighbours on its south and west sides are in its own zone, those on its north and east in others.
fn ringed() -> Dem {
    Dem::flat_with_peaks(10.0, [65, 65], 8, &[[8, 11], [16, 13], [11, 8], [13, 16]])
}

/// [`ringed`] with its leaf over rows and columns 8–16 missing: that area is traced from the zone's stride-2
/// block, 4 × 4 coarse cells, every neighbour finer. Rays straight down beside each 300 m vertex, inside the
/// coarse cell in the middle of that side (which touches no other side of the missing leaf), hit its fan almost
/// 300 m high: each side's cells are stitched, whichever of the leaf's sides they lie on. A cell in the middle
/// touches none and keeps its two flat triangles.
#[test]
fn coarse_cells_in_the_middle_of_each_side_of_a_missing_leaf_are_stitched_to_the_fine_neighbour_there()
 {
    let d = ringed();
    d.evict(d.child([8, 16], [8, 16]));
    let s = d.paged();
    let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
    let e = Ellipsoid::wgs84();
    let sides = [
        ("south", [10.0801, 20.11], [8, 10]),
        ("north", [10.1599, 20.13], [14, 12]),
        ("west", [10.11, 20.0801], [10, 8]),
        ("east", [10.13, 20.1599], [12, 14]),
    ];
    for (side, [lat, lon], cell) in sides {
        let hit = p.pick(&down_at(&e, lat, lon)).unwrap().unwrap();
        assert_eq!(
            (hit.cell, hit.stride, hit.level),
            (cell, 2, 0),
            "{side}: {hit:?}"
        );
        assert!(hit.h > 290.0, "{side}: {hit:?}");
    }
    let middle = p.pick(&down_at(&e, 10.121, 20.121)).unwrap().unwrap();
    assert_eq!((middle.cell, middle.stride), ([12, 12], 2), "{middle:?}");
    assert!(middle.h.abs() < 0.05, "{middle:?}");
}

/// [`ringed`] with its leaf over rows and columns 8–16 missing below `min_level` (no block to fall back to): rays
/// straight down onto the cells of its four fine neighbours along their shared sides hit them. The missing leaf
/// is not on their way, and a full-resolution cell is never stitched (only a coarse one looks across its sides
/// for a neighbour's vertices, and so for a missing block).
#[test]
fn straight_down_rays_onto_full_resolution_cells_beside_a_missing_leaf_below_min_level_hit_them() {
    let d = ringed();
    d.evict(d.child([8, 16], [8, 16]));
    let s = d.paged();
    let p = Picker::<'_, f64, _>::new(&s).unwrap().with_min_level(1);
    let e = Ellipsoid::wgs84();
    let cells = [
        ([10.0795, 20.125], [7, 12]),
        ([10.1605, 20.125], [16, 12]),
        ([10.125, 20.0795], [12, 7]),
        ([10.125, 20.1605], [12, 16]),
    ];
    for ([lat, lon], cell) in cells {
        let hit = p.pick(&down_at(&e, lat, lon)).unwrap().unwrap();
        assert_eq!((hit.cell, hit.stride, hit.level), (cell, 1, 1), "{hit:?}");
    }
}
