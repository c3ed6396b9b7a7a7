//! Rays through vertices on the border of the surface: the outer edge, the grid's corners, and the edges and
//! corners of nodata holes (triangles are closed; triangle.rs, "Edges on the border of the surface").

use super::*;

/// Straight-down rays through vertices on the border of the surface, on flat terrain of grids of several sizes,
/// places and heights: each must hit at its vertex (triangles are closed; triangle.rs, "Edges on the border of
/// the surface"), at `t` = 1000 m, and the brute force with the same border rule agrees.
fn assert_hits_down_through(dem: &TestDem, vertices: &[(u32, u32)], what: &str) -> usize {
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    for &(i, j) in vertices {
        let (lat, lon) = (dem.surface.grid.lat_deg(i), dem.surface.grid.lon_deg(j));
        let h = dem.surface.h(i, j).unwrap();
        let ray = radial_ray(&dem.surface.e, lat, lon, h + 1000.0);
        let hit = p.pick(&ray).unwrap();
        // Through a vertex the two may pick different triangles around it, at the same point.
        let brute = dem.surface.brute(&ray);
        assert!(
            brute.is_some(),
            "{what}: the brute force misses V({i}, {j})"
        );
        assert!(hit.is_some(), "{what}: ray down through V({i}, {j}) missed");
        let hit = hit.unwrap();
        assert!(
            (hit.t - 1000.0).abs() < 1e-6,
            "{what} V({i}, {j}): t = {}",
            hit.t
        );
        assert!(
            (hit.h - h).abs() < 1e-6,
            "{what} V({i}, {j}): h = {}",
            hit.h
        );
    }
    vertices.len()
}

/// The grids of the border-vertex tests: `(lat0_deg, lon0_deg, spacing, height)`, 9 × 9 vertices, rows southwards for
/// one of them.
const BORDER_GRIDS: [(f64, f64, f64, f64); 5] = [
    (45.0, 7.0, 0.01, 0.0),
    (-33.0, 151.0, -0.001, 250.0),
    (10.0, -120.0, 0.1, 1000.0),
    (60.0, 20.0, 1.0 / 1200.0, 17.0),
    (0.0, 0.0, 0.003, 3.0),
];

#[test]
#[cfg_attr(miri, ignore)] // 160 picks: minutes under Miri; the corner and hole tests cover the same code
fn rays_down_through_vertices_on_the_outer_edge_of_grids_hit() {
    let mut n = 0;
    for (lat0_deg, lon0_deg, d, h) in BORDER_GRIDS {
        let dem = TestDem::new(
            grid(lat0_deg, lon0_deg, d, d.abs(), 9, 9),
            std::vec![h; 81],
            2,
        );
        let edge: Vec<(u32, u32)> = (0..9)
            .flat_map(|i| (0..9).map(move |j| (i, j)))
            .filter(|&(i, j)| i == 0 || j == 0 || i == 8 || j == 8)
            .collect();
        n += assert_hits_down_through(
            &dem,
            &edge,
            &std::format!("grid at {lat0_deg}°, {lon0_deg}°"),
        );
    }
    assert_eq!(n, 160);
}

#[test]
#[cfg_attr(miri, ignore)] // 20 picks: over a minute under Miri; triangle.rs tests the border rule itself
fn rays_down_through_the_four_corner_vertices_of_grids_hit() {
    for (lat0_deg, lon0_deg, d, h) in BORDER_GRIDS {
        let dem = TestDem::new(
            grid(lat0_deg, lon0_deg, d, d.abs(), 9, 9),
            std::vec![h; 81],
            2,
        );
        let corners = [(0, 0), (0, 8), (8, 0), (8, 8)];
        assert_hits_down_through(
            &dem,
            &corners,
            &std::format!("corners at {lat0_deg}°, {lon0_deg}°"),
        );
    }
}

#[test]
#[cfg_attr(miri, ignore)] // dozens of picks or builds: minutes under Miri; triangle.rs and the builder's error test run there
fn rays_down_through_the_edge_vertices_of_a_one_vertex_nodata_hole_hit() {
    // Nodata at V(4, 4) removes its six triangles; the hole's edge is the hexagon of its neighbours (each a
    // corner of the hole's outline).
    for (lat0_deg, lon0_deg, d, h) in BORDER_GRIDS {
        let mut hs = std::vec![h; 81];
        hs[4 * 9 + 4] = f64::NAN;
        let dem = TestDem::new(grid(lat0_deg, lon0_deg, d, d.abs(), 9, 9), hs, 2);
        let ring = [(3, 3), (3, 4), (4, 5), (5, 5), (5, 4), (4, 3)];
        assert_hits_down_through(
            &dem,
            &ring,
            &std::format!("hole at {lat0_deg}°, {lon0_deg}°"),
        );
        // Straight down through the missing vertex: no triangle there.
        let ray = radial_ray(
            &dem.surface.e,
            dem.surface.grid.lat_deg(4),
            dem.surface.grid.lon_deg(4),
            h + 1000.0,
        );
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        assert_eq!(p.pick(&ray).unwrap(), None);
    }
}

#[test]
#[cfg_attr(miri, ignore)] // dozens of picks or builds: minutes under Miri; triangle.rs and the builder's error test run there
fn rays_down_through_the_edges_and_corners_of_a_square_nodata_hole_hit() {
    // Nodata at the 3 × 3 vertices V(3..=5, 3..=5): the hole's outline runs along rows 2 and 6 and columns 2
    // and 6 (straight edges, with corners at V(2, 2), V(2, 6), V(6, 2), V(6, 6)) and steps inwards along the
    // diagonals at V(2, 3) ... (the cells' diagonals keep some triangles).
    for (lat0_deg, lon0_deg, d, h) in BORDER_GRIDS {
        let mut hs = std::vec![h; 81];
        for i in 3..=5 {
            for j in 3..=5 {
                hs[i * 9 + j] = f64::NAN;
            }
        }
        let dem = TestDem::new(grid(lat0_deg, lon0_deg, d, d.abs(), 9, 9), hs, 2);
        let outline: Vec<(u32, u32)> = (2..=6)
            .flat_map(|i| (2..=6).map(move |j| (i, j)))
            .filter(|&(i, j)| i == 2 || j == 2 || i == 6 || j == 6)
            .collect();
        assert_eq!(outline.len(), 16);
        assert_hits_down_through(
            &dem,
            &outline,
            &std::format!("square hole at {lat0_deg}°, {lon0_deg}°"),
        );
    }
}
