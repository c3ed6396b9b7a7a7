//! A multi-resolution DEM near the south pole. There the spheroid lies only tens of metres above the radius
//! `b` of the lower sphere that bounds a node's volume from below (`b + h_min` minus the sag bound of the cells
//! traced under it), so that bound decides which rays enter a child's volume: a missing leaf traced with its
//! zone's stride-2 block needs the bound of those coarse cells, not of its own.

use super::*;

/// 8 × 36 cells of 0.5° × 0.25° from 85.5° S southwards, flat at 0 m, in leaves of 4 × 4 cells: the first
/// zone (cell rows and columns 0–7: 85.5° S to 89.5° S, 20° E to 22° E) has a stride-2 block over four leaves.
/// The sag bound of the full-resolution cells is about 103 m, that of the stride-2 cells about 410 m
/// (`geodesy::chord_sagitta_bound` of their longest edge); at 86° S the spheroid lies 104 m above radius `b`,
/// at 87° S 58 m.
fn polar() -> Dem {
    Dem::flat_on(grid(-85.5, 20.0, -0.5, 0.25, 9, 37), 4, &[])
}

/// Level rays (the same height at both ends) under the first zone: 200 m down along 87° S across its columns
/// 0–7, and 370 m and 470 m down along 86.2° S across the west leaf (columns 0–3).
fn level_rays(e: &Ellipsoid<f64>) -> [Ray<f64>; 3] {
    [
        ray_between(e, [-87.0, 20.05, -200.0], [-87.0, 21.95, -200.0]),
        ray_between(e, [-86.2, 20.02, -370.0], [-86.2, 20.98, -370.0]),
        ray_between(e, [-86.2, 20.02, -470.0], [-86.2, 20.98, -470.0]),
    ]
}

/// The west leaf missing: its area is traced with the zone's stride-2 block, whose 1° × 0.5° cells dip up to
/// about 245 m below their flat vertices. A ray descending from 230 m to 255 m down along 86° S, the middle of
/// the coarse cell over rows and columns 0–1 (on the grid's edges, so not stitched), stays more than 103 m under
/// the spheroid's radius `b` (below the leaf's own cells' sag bound) and meets that cell more than 200 m down,
/// exactly on its plane (its four vertices, in pairs, are coplanar: an isosceles trapezoid). The leaf's volume
/// must bound the coarse cells' sag: with its own cells' bound the ray passes under it. The same with a storage
/// that caches node bounds (those of each node's own cells, so not usable for the coarse block).
#[test]
fn ray_near_the_pole_below_a_missing_leafs_own_sag_bound_hits_its_coarse_cell() {
    let d = polar();
    d.evict(d.west_child());
    let e = Ellipsoid::wgs84();
    let cols = d.grid.cols;
    let v = |i: u32, j: u32| {
        let h = d.heights[(i * cols + j) as usize];
        let (so, co) = parallel::col_sin_cos_dd(&d.grid, j);
        parallel::row_parallel(&e, &d.grid, i).ecef(so, co, h)
    };
    let tris = [[v(0, 0), v(0, 2), v(2, 2)], [v(0, 0), v(2, 2), v(2, 0)]];
    let ray = ray_between(&e, [-86.0, 20.02, -230.0], [-86.0, 20.48, -255.0]);
    let plain = d.paged();
    let cached = CachedBounds::new(d.paged(), d.tree.slots());
    let hits = [
        Picker::<'_, f64, _>::new(&plain)
            .unwrap()
            .pick(&ray)
            .unwrap(),
        Picker::<'_, f64, _>::new(&cached)
            .unwrap()
            .pick(&ray)
            .unwrap(),
    ];
    for hit in hits {
        let hit = hit.unwrap();
        assert_eq!((hit.level, hit.stride, hit.cell), (0, 2, [0, 0]), "{hit:?}");
        assert!(hit.h < -200.0, "{hit:?}");
        let t_exact = nearest_plane_t(&ray, hit.t, tris);
        assert!(
            (hit.t - t_exact).abs() * ray.dir().length() < 1e-9,
            "{hit:?}, plane at {t_exact}"
        );
    }
}

/// The work of the level rays (quads visited, triangle pairs visited, triangles tested), every block resident
/// and with the west leaf missing, on the plain storage and on one with cached bounds: which children's volumes
/// they enter depends on each lower sphere's radius. 200 m and 370 m down they pass under the leaves' own
/// cells' sag bound but not under the stride-2 block's, so a resident leaf's volume bounded by its parent's
/// coarser cells adds work; 470 m down, along the missing leaf, they pass under the stride-2 block's bound
/// with its cells' longitude span halved but not with the span doubled.
#[test]
fn level_rays_under_polar_terrain_do_the_pinned_work() {
    let e = Ellipsoid::wgs84();
    let rays = level_rays(&e);
    let all = polar();
    let missing = polar();
    missing.evict(missing.west_child());
    let cases: [(&Dem, usize, [u32; 3]); 3] = [
        (&all, 0, [10, 17, 0]),
        (&all, 1, [8, 9, 10]),
        (&missing, 2, [7, 5, 7]),
    ];
    for (d, k, work) in cases {
        let plain = d.paged();
        let cached = CachedBounds::new(d.paged(), d.tree.slots());
        let (hit, w) = pick_counted(&Picker::<'_, f64, _>::new(&plain).unwrap(), &rays[k]);
        assert_eq!((hit, w), (None, work), "ray {k}, plain");
        let (hit, w) = pick_counted(&Picker::<'_, f64, _>::new(&cached).unwrap(), &rays[k]);
        assert_eq!((hit, w), (None, work), "ray {k}, cached bounds");
    }
}
