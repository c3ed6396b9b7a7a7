//! Picks on small grids with closed-form answers (flat terrain, a peak, the pole row, a latitude border,
//! nodata, line of sight), the work counters, and typed errors.

use super::*;

#[test]
#[cfg_attr(miri, ignore)] // many picks: minutes under Miri; the light tests below cover the same code
fn flat_terrain_at_h0_hit_by_radial_rays_at_vertices() {
    let g = grid(45.0, 7.0, 0.01, 0.01, 9, 9);
    let dem = TestDem::new(g, std::vec![0.0; 81], 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    // The inner vertices: the outer edge's are the border tests' (tests/border.rs), where a ray straight down
    // through a vertex built in scalars passes up to its rounding outside the exact triangles.
    for i in 1..8 {
        for j in 1..8 {
            let (lat, lon) = (g.lat_deg(i), g.lon_deg(j));
            let hit = p
                .pick(&radial_ray(&dem.surface.e, lat, lon, 1000.0))
                .unwrap();
            let ray = radial_ray(&dem.surface.e, lat, lon, 1000.0);
            let what = std::format!("{i},{j}");
            same_hit(
                &ray,
                hit.map(|h| (h.t, h.cell)),
                dem.surface.brute(&ray),
                &what,
            );
            assert!(hit.is_some(), "{i},{j} missed");
            let hit = hit.unwrap();
            // A vertex at h = 0 lies 1000 m down the normal.
            assert!((hit.t - 1000.0).abs() < 1e-6, "{i},{j}: {}", hit.t);
            assert!(
                hit.h.abs() < 1e-6
                    && (hit.lat_deg - lat).abs() < 1e-9
                    && (hit.lon_deg - lon).abs() < 1e-9
            );
        }
    }
    // Cell centres: the chord plane dips below the ellipsoid by less than the sagitta (≈ D²/(8R) ≈ 0.02 m).
    let hit = p
        .pick(&radial_ray(&dem.surface.e, 45.035, 7.045, 1000.0))
        .unwrap()
        .unwrap();
    assert!(hit.h < 0.0 && hit.h > -0.05, "{}", hit.h);
    assert_eq!(hit.cell, [3, 4]);
}

#[test]
fn single_raised_vertex_peak_and_its_slopes() {
    let g = grid(-33.0, 151.0, -0.001, 0.001, 5, 5);
    let mut hs = std::vec![0.0; 25];
    hs[2 * 5 + 2] = 300.0;
    let dem = TestDem::new(g, hs, 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let (lat, lon) = (g.lat_deg(2), g.lon_deg(2));
    let hit = p
        .pick(&radial_ray(&dem.surface.e, lat, lon, 2000.0))
        .unwrap()
        .unwrap();
    assert!((hit.t - 1700.0).abs() < 1e-6 && (hit.h - 300.0).abs() < 1e-6);
    // Halfway to a neighbouring vertex along a grid line (an edge of the triangulation), the edge is straight:
    // the hit height is close to 150 m (the chord of the peak's edge, less the tiny curvature term).
    let hit = p
        .pick(&radial_ray(&dem.surface.e, lat, lon + 0.0005, 2000.0))
        .unwrap()
        .unwrap();
    assert!((hit.h - 150.0).abs() < 0.5, "{}", hit.h);
    let ray = radial_ray(&dem.surface.e, lat, lon + 0.0005, 2000.0);
    same_hit(
        &ray,
        Some((hit.t, hit.cell)),
        dem.surface.brute(&ray),
        "peak slope",
    );
}

#[test]
#[cfg_attr(miri, ignore)] // many picks: minutes under Miri; the light tests below cover the same code
fn ray_through_the_pole_row() {
    // A polar cap 80°..90° with 10° × 30° cells: the last row is the pole, where all vertices coincide.
    let g = grid(80.0, -180.0, 5.0, 30.0, 3, 13);
    let mut r = Lcg(7);
    let hs: Vec<f64> = (0..39)
        .map(|k| {
            if k >= 26 {
                250.0
            } else {
                100.0 + 900.0 * r.next()
            }
        })
        .collect();
    let dem = TestDem::new(g, hs, 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    // Straight down the z axis onto the pole vertex.
    let e = dem.surface.e;
    let ray = Ray::new([0.0, 0.0, e.b() + 10_000.0], [0.0, 0.0, -1.0]).unwrap();
    let hit = p.pick(&ray).unwrap().unwrap();
    assert!((hit.t - (10_000.0 - 250.0)).abs() < 1e-6, "{}", hit.t);
    assert!((hit.lat_deg - 90.0).abs() < 1e-9);
    // Rays across the pole, horizontally and obliquely, agree with the brute force.
    for k in 0..40 {
        let az = k as f64 * 0.157;
        let o = [
            -700_000.0 * az.cos(),
            -700_000.0 * az.sin(),
            e.b() - 20_000.0 + 1000.0 * k as f64,
        ];
        let d = [az.cos(), az.sin(), -0.02 + 0.001 * k as f64];
        let ray = Ray::new(o, d).unwrap();
        let got = p.pick(&ray).unwrap().map(|h| (h.t, h.cell));
        same_hit(
            &ray,
            got,
            dem.surface.brute(&ray),
            &std::format!("azimuth {az}"),
        );
    }
}

#[test]
fn steep_ray_across_a_latitude_border_at_80_degrees_finds_the_bulging_triangle() {
    // 1° cells, one cell per leaf: the quad border at 80° is a cone, the triangles below it are chords that
    // bulge north of it (the containment problem). A steep ray from the north aims at the bulge.
    let g = grid(78.0, 10.0, 1.0, 1.0, 5, 4);
    let dem = TestDem::new(g, std::vec![0.0; 20], 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    // The midpoint of the border edge V(2,1)–V(2,2) (lat 80°, lon 11°..12°) and a point just south of it on the
    // southern cell's triangle.
    let a = dem.surface.vertex(2, 1).unwrap();
    let b = dem.surface.vertex(2, 2).unwrap();
    let c = dem.surface.vertex(1, 2).unwrap();
    let target = a
        .scaled(0.49995)
        .plus(b.scaled(0.49995))
        .plus(c.scaled(0.0001));
    let geo = e.ecef_to_geodetic(target);
    assert!(
        geo.lat_rad.to_degrees() > 80.0,
        "the target is north of the 80° cone"
    );
    // A steep ray coming from the north-east, above the northern cells.
    let dir = V3::new(-0.3, 0.05, -1.0);
    let origin = target.add_scaled(-20_000.0, dir);
    let ray = Ray::new(origin, dir).unwrap();
    let hit = p.pick(&ray).unwrap().unwrap();
    same_hit(
        &ray,
        Some((hit.t, hit.cell)),
        dem.surface.brute(&ray),
        "steep ray",
    );
    assert_eq!(
        hit.cell[0], 1,
        "the triangle belongs to the southern row of cells"
    );
    assert!((hit.t - 20_000.0).abs() < 1e-6);
}

#[test]
fn nodata_vertex_removes_its_triangles() {
    let g = grid(0.0, 0.0, 0.01, 0.01, 3, 3);
    let mut hs = std::vec![0.0; 9];
    hs[4] = f64::NAN;
    let dem = TestDem::new(g, hs, 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    // Every triangle touches the centre vertex: nothing to hit.
    assert_eq!(
        p.pick(&radial_ray(&dem.surface.e, 0.005, 0.005, 100.0))
            .unwrap(),
        None
    );
}

#[test]
#[cfg_attr(miri, ignore)] // many picks: minutes under Miri; the light tests below cover the same code
fn line_of_sight_over_and_through_a_ridge() {
    let g = grid(10.0, 10.0, 0.001, 0.001, 3, 5);
    let hs = std::vec![
        0.0, 0.0, 800.0, 0.0, 0.0, 0.0, 0.0, 800.0, 0.0, 0.0, 0.0, 0.0, 800.0, 0.0, 0.0
    ];
    let dem = TestDem::new(g, hs, 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let west = e.geodetic_deg_to_ecef(10.001, 10.0, 100.0);
    let east = e.geodetic_deg_to_ecef(10.001, 10.004, 100.0);
    assert!(!p.line_of_sight(west, east).unwrap());
    let w_hi = e.geodetic_deg_to_ecef(10.001, 10.0, 1000.0);
    let e_hi = e.geodetic_deg_to_ecef(10.001, 10.004, 1000.0);
    assert!(p.line_of_sight(w_hi, e_hi).unwrap());
}

#[test]
fn pick_statistics_count_the_work() {
    // One-cell leaves two levels below the builder's zones (16 × 16 cells: 8 × 8, then 4 × 4 zones).
    let g = grid(0.0, 0.0, 0.01, 0.01, 17, 17);
    let dem = TestDem::new(g, std::vec![0.0; 289], 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let mut st = PickStats::default();
    let hit = p
        .pick_with_stats(&radial_ray(&dem.surface.e, 0.035, 0.045, 100.0), &mut st)
        .unwrap();
    assert!(hit.is_some());
    assert!(st.quads_visited >= 3, "{st:?}");
    assert!(
        st.triangle_pairs_visited >= 1 && st.triangle_pairs_visited <= 4,
        "{st:?}"
    );
    assert!(
        st.triangles_tested >= 1 && st.triangles_tested <= 8,
        "{st:?}"
    );
}

#[test]
fn normal_on_a_parallel_at_a_column_middle_crosses_only_the_cell_south_of_the_row_chord() {
    // An 8 × 8-cell leaf at 30° N. The normal line through a point of parallel 4 on the middle meridian of a
    // column lies on the latitude cone, which bulges south of the row's chord plane there (by about 1 cm along
    // the plane's normal for these 1 km cells): so the ray crosses the cell south of row 4 only, clear of the
    // northern cell's wall by far more than the walls' rounding tolerance (about 1e-7 m). Column 3 is inside
    // the leaf, column 0 on its western border. The count pins the walls: a tolerance of metres, or a
    // full-resolution border cell bounded by the cone's tangent plane (which a coarse unit's stitched border
    // cells use, and which this normal lies on), would add the northern cell.
    let g = grid(30.0, 10.0, 0.01, 0.01, 17, 17);
    let dem = TestDem::new(g, std::vec![0.0; 289], 8);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    for col in [3u32, 0] {
        let lon = 10.0 + 0.01 * (f64::from(col) + 0.5);
        let ray = radial_ray(&dem.surface.e, 30.04, lon, 100.0);
        let mut st = PickStats::default();
        let hit = p.pick_with_stats(&ray, &mut st).unwrap().unwrap();
        assert_eq!(hit.cell, [3, col], "column {col}: {st:?}");
        assert_eq!(st.triangle_pairs_visited, 1, "column {col}: {st:?}");
        if cfg!(miri) {
            continue; // the brute force over the 512 triangles takes most of a minute there
        }
        same_hit(
            &ray,
            Some((hit.t, hit.cell)),
            dem.surface.brute(&ray),
            &std::format!("normal on parallel 4, column {col}"),
        );
    }
}

/// The hit and the work of the ray from `from` to `to` (geodetic: latitude, longitude in degrees, height) over
/// flat 0 m terrain at 30° N, 10° E in 8 × 8-cell leaves of 0.01° cells, whose first leaf's box a 300 m peak at
/// V(7, 7) makes tall; checked against the brute force (`what` names the ray).
fn pick_beside_a_peak(from: [f64; 3], to: [f64; 3], what: &str) -> (Hit<f64>, PickStats) {
    let g = grid(30.0, 10.0, 0.01, 0.01, 17, 17);
    let mut heights = std::vec![0.0; 289];
    heights[7 * 17 + 7] = 300.0;
    let dem = TestDem::new(g, heights, 8);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let ray = ray_between(&dem.surface.e, from, to);
    let mut st = PickStats::default();
    let hit = p.pick_with_stats(&ray, &mut st).unwrap().unwrap();
    // (under Miri the brute force over the 512 triangles takes most of a minute)
    if !cfg!(miri) {
        same_hit(&ray, Some((hit.t, hit.cell)), dem.surface.brute(&ray), what);
    }
    (hit, st)
}

#[test]
fn shallow_ray_over_flat_cells_tests_the_triangles_of_the_cell_it_reaches_only() {
    // A ray from 100 m above the flat terrain descending eastwards at about 1 in 29 onto the middle of cell
    // (2, 3): it crosses cells 0 to 3 of row 2 inside the leaf's box, the first three wholly above their corners
    // (the height cull skips them), so only the last cell's two triangles are tested.
    let (hit, st) = pick_beside_a_peak(
        [30.025, 10.005, 100.0],
        [30.025, 10.035, 0.0],
        "shallow ray",
    );
    assert_eq!(hit.cell, [2, 3], "{st:?}");
    assert!(st.triangle_pairs_visited >= 4, "{st:?}");
    assert_eq!(st.triangles_tested, 2, "{st:?}");
}

#[test]
fn ray_descending_north_over_two_columns_skips_the_first_from_its_heights_alone() {
    // A ray from 100 m above the flat terrain descending north-eastwards onto cell (3, 2): it crosses column 1
    // over rows 0 and 1, at 100 m to 50 m, then column 2 over rows 2 and 3. Column 1 lies wholly below the ray
    // (its heights alone say so), so its cells are not even clipped: the cells visited are column 2's two.
    let (hit, st) = pick_beside_a_peak(
        [30.005, 10.015, 100.0],
        [30.035, 10.025, 0.0],
        "ray over two columns",
    );
    assert_eq!(hit.cell, [3, 2], "{st:?}");
    assert_eq!(st.triangle_pairs_visited, 2, "{st:?}");
    assert_eq!(st.triangles_tested, 2, "{st:?}");
}

#[test]
fn ray_descending_westward_through_the_peak_stops_at_its_first_hit_in_ray_order() {
    // A ray from 200 m above the flat terrain, east of the peak's leaf, descending westwards along row 6 (at
    // 30.0675° N) to the ground at column 3: it enters the peak's eastern slope in column 7 (cell (6, 7)), leaves
    // its western slope in column 6 and would meet the ground again in column 3, all in the first leaf. The leaf's
    // columns are walked in the order the ray crosses them, from the east: after the hit in column 7 every later
    // column lies beyond it. Walked from the west, columns 3 and 6 would be visited (and column 3's triangles hit)
    // before column 7.
    let (hit, st) = pick_beside_a_peak(
        [30.0675, 10.1, 200.0],
        [30.0675, 10.03, 0.0],
        "westward ray through the peak",
    );
    assert_eq!(hit.cell, [6, 7], "{st:?}");
    assert_eq!(st.triangle_pairs_visited, 1, "{st:?}");
    assert_eq!(st.triangles_tested, 2, "{st:?}");
}

#[test]
fn typed_errors() {
    let bad = GridOnly(grid(0.0, 0.0, 0.0, 0.01, 3, 3));
    assert_eq!(
        Picker::<'_, f64, GridOnly>::new(&bad).err(),
        Some(TerrainError::InvalidGrid)
    );
    let deep = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 3, 3), std::vec![-7.0e6; 9], 2);
    assert_eq!(
        Picker::<'_, f64, Storage<'_>>::new(&deep.storage()).err(),
        Some(TerrainError::Geodesy(GeodesyError::HeightTooLow))
    );
    // The builder's records with one broken by hand: a child as large as its parent, under the ray's zone.
    let mut malformed = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 9, 9), std::vec![0.0; 81], 1);
    let zone = malformed
        .nodes
        .iter()
        .copied()
        .find(|n| {
            n.level == 0 && n.rows[0] <= 3 && 3 < n.rows[1] && n.cols[0] <= 3 && 3 < n.cols[1]
        })
        .unwrap();
    let child = &mut malformed.nodes[zone.kids[0] as usize];
    (child.rows, child.cols) = (zone.rows, zone.cols);
    let s = malformed.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    assert_eq!(
        p.pick(&radial_ray(&malformed.surface.e, 0.03, 0.03, 100.0)),
        Err(TerrainError::MalformedTree)
    );
    let ok = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 17, 17), std::vec![0.0; 289], 1);
    let s = ok.storage();
    let tiny: Picker<'_, f64, Storage<'_>, 2> = Picker::new(&s).unwrap();
    assert_eq!(
        tiny.pick(&radial_ray(&ok.surface.e, 0.03, 0.03, 100.0)),
        Err(TerrainError::StackFull)
    );
    let zones = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 9, 9), std::vec![0.0; 81], 2);
    assert_eq!(
        Picker::<'_, f64, Storage<'_>, 64, 8>::new(&zones.storage()).err(),
        Some(TerrainError::TooManyZones)
    );
}

#[test]
fn grid_of_80_degree_cells_is_triangle_too_large_not_height_too_low() {
    // 3 × 3 vertices 10° × 80° apart at the equator, flat at 0 m: the cells' diagonals (about 8 800 km) are
    // beyond the chord bound, and the heights are fine.
    let dem = TestDem::new(grid(-10.0, 0.0, 10.0, 80.0, 3, 3), std::vec![0.0; 9], 1);
    let e = dem.surface.e;
    let got = Picker::<'_, f64, Storage<'_>>::new(&dem.storage())
        .and_then(|p| p.pick(&radial_ray(&e, 0.0, 40.0, 1000.0)))
        .err();
    assert_eq!(
        got,
        Some(TerrainError::Geodesy(GeodesyError::TriangleTooLarge))
    );
    let text = std::format!("{}", got.unwrap());
    assert!(
        text.contains("70 degrees") && !text.contains("b^2/a (no"),
        "{text}"
    );
    // 60° cells are within the bound.
    let ok = TestDem::new(grid(-10.0, 0.0, 10.0, 60.0, 3, 3), std::vec![0.0; 9], 1);
    let s = ok.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    assert!(
        p.pick(&radial_ray(&e, 0.0, 40.0, 1000.0))
            .unwrap()
            .is_some()
    );
}

#[test]
fn grid_with_dlon_180_is_an_invalid_grid_whose_message_states_the_rules() {
    // The builder refuses the grid too (BuildError::InvalidGrid): the picker checks it over a bare grid.
    let dem = GridOnly(grid(-10.0, 0.0, 10.0, 180.0, 3, 2));
    let err = Picker::<'_, f64, GridOnly>::new(&dem).err();
    assert_eq!(err, Some(TerrainError::InvalidGrid));
    let text = std::format!("{}", err.unwrap());
    assert!(text.contains("0 < dlon < 180"), "{text}");
}

#[test]
fn ray_missing_everything_and_ray_starting_below_ground() {
    let g = grid(0.0, 0.0, 0.01, 0.01, 5, 5);
    let dem = TestDem::new(g, std::vec![100.0; 25], 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let up = radial_ray(&e, 0.02, 0.02, 1000.0);
    let away = Ray::new(up.origin(), up.dir().negated()).unwrap();
    assert_eq!(p.pick(&away).unwrap(), None);
    // From 10 m below the surface, straight up: hits the terrain from underneath at t = 10.
    let below = e.geodetic_deg_to_ecef(0.02, 0.02, 90.0);
    let n = e.normal_rad(0.02_f64.to_radians(), 0.02_f64.to_radians());
    let hit = p.pick(&Ray::new(below, n).unwrap()).unwrap().unwrap();
    assert!((hit.t - 10.0).abs() < 1e-6);
}

#[test]
fn ray_segment_ending_above_the_terrains_volume_is_a_miss_not_an_error() {
    // Flat at 100 m: straight down from 1 km, the segment t in [0, 500] ends 500 m above the ground, before the
    // ray reaches the terrain's upper bound; its clip to that bound is empty.
    let dem = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 5, 5), std::vec![100.0; 25], 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let down = radial_ray(&dem.surface.e, 0.02, 0.02, 1000.0);
    assert_eq!(p.pick(&down.with_interval(0.0, 500.0).unwrap()), Ok(None));
    // The whole ray hits at t = 900.
    let hit = p.pick(&down).unwrap().unwrap();
    assert!((hit.t - 900.0).abs() < 1e-6, "{hit:?}");
}

/// A hit's geodetic coordinates describe its ECEF point, also where the cell's corner is too far for the seeded
/// form (`Ellipsoid::ecef_to_geodetic_near`, up to 1.1° away) and the closed form answers: cells of 3°.
#[test]
fn geodetic_output_of_a_hit_1_5_degrees_from_its_cells_corner_is_its_ecef_point() {
    let g = grid(30.0, 10.0, 3.0, 3.0, 4, 4);
    let dem = TestDem::new(g, std::vec![500.0; 16], 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    for (lat, lon) in [(31.5, 11.5), (34.4, 16.6), (30.2, 17.9)] {
        let hit = p.pick(&radial_ray(&e, lat, lon, 5000.0)).unwrap().unwrap();
        let back = e.geodetic_deg_to_ecef(hit.lat_deg, hit.lon_deg, hit.h);
        let p_hit = V3::from(hit.ecef);
        assert!(back.minus(p_hit).length() < 1e-6, "({lat}, {lon}): {hit:?}");
        // the chord plane of a 3° cell passes up to some kilometres below the spheroid at 500 m
        assert!(
            (lat - hit.lat_deg).abs() < 0.1 && (lon - hit.lon_deg).abs() < 0.1 && hit.h < 500.0
        );
    }
}

#[test]
fn straight_down_rays_on_the_antimeridian_keep_the_western_column_on_an_exact_tie() {
    // A sloping 5 × 5-vertex DEM whose column meridian 2 is the antimeridian, where the rays' and the vertices'
    // y coordinates are exactly 0: a ray straight down that meridian in row 0 (every 0.001°) meets the edge that
    // columns 1 and 2 share, and for three of these nine rays both triangles give exactly the same `t`. Such a
    // ray has no azimuth rate ((o × d)_z = 0), so its columns are walked from the east; the tie still goes to the
    // western column, as in a walk from west to east, for `pick` and `pick_t` alike. (Column 1's `t` is never
    // the larger one for these rays.)
    let g = grid(-17.0, 179.98, 0.01, 0.01, 5, 5);
    let heights: Vec<f64> = (0..25u32)
        .map(|k| 100.0 + 7.0 * f64::from(k % 5) + 3.0 * f64::from(k / 5))
        .collect();
    let dem = TestDem::new(g, heights, 4);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    for k in 1..10 {
        let lat = -17.0 + 0.001 * f64::from(k);
        let from = e.geodetic_deg_to_ecef(lat, 180.0, 1100.0);
        let ray = Ray::new(from, e.normal_deg(lat, 180.0).negated()).unwrap();
        let hit = p.pick(&ray).unwrap().unwrap();
        let (_, cell) = p.pick_t(&ray).unwrap().unwrap();
        assert_eq!((hit.cell, cell), ([0, 1], [0, 1]), "latitude {lat}");
    }
}

/// The global clip to `B^{h_max}` is widened by `64 ε (|t_enter| + |t_exit|)`: on the equator `B^{h_max}` passes
/// through a vertex at `h_max` (its equatorial radius is `a + h`), so a ray straight down onto such a peak from far
/// away meets it within the vertex's rounding of where it enters `B^{h_max}`, and one from inside the peak's hill
/// straight up meets it where it leaves; both must hit it, at peaks of several longitudes (the rounding falls either
/// way) and from 10 km to 20 000 km.
#[test]
fn rays_onto_an_equatorial_peak_at_the_highest_height_hit_it_where_they_cross_the_global_bound() {
    let (mut checked, mut grazing_hits) = (0, 0);
    // Two of the eight under Miri (each pick is slow there).
    let lons: &[f64] = if cfg!(miri) {
        &[10.37, -99.9]
    } else {
        &[0.004, 10.37, 33.3, 71.01, 123.456, 179.5, -45.55, -99.9]
    };
    for &lon in lons {
        // 3 × 3 vertices 0.01° apart around (0°, lon); the middle one, the peak, is the highest at 800 m.
        let mut h = std::vec![100.0; 9];
        h[4] = 800.0;
        let dem = TestDem::new(grid(-0.01, lon - 0.01, 0.01, 0.01, 3, 3), h, 2);
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        let e = dem.surface.e;
        let peak = dem.surface.vertex(1, 1).unwrap();
        let n = e.normal_deg(0.0, lon);
        for dist in [1.0e4, 1.0e6, 2.0e7] {
            let down = Ray::new(peak.add_scaled(dist, n), n.negated()).unwrap();
            let hit = p.pick(&down).unwrap();
            assert!(
                hit.is_some_and(|h| (h.t - dist).abs() < 1e-6),
                "lon {lon}, down from {dist} m: {hit:?}"
            );
            // From below the hill's surface, up through the peak and out of B^{h_max} there.
            let up = Ray::new(peak.add_scaled(-1.0, n), n)
                .unwrap()
                .with_interval(0.0, dist)
                .unwrap();
            let hit = p.pick(&up).unwrap();
            assert!(
                hit.is_some_and(|h| (h.t - 1.0).abs() < 1e-6),
                "lon {lon}, up: {hit:?}"
            );
            checked += 1;
        }
        // Level with the peak, grazing it: the ray touches B^{h_max} there, entering and leaving it at once.
        let east = V3::new(-n.y, n.x, 0.0);
        for k in -4..=4 {
            let o = peak
                .add_scaled(-1.0e4, east)
                .add_scaled(f64::from(k) * 2.0e-9, n);
            let ray = Ray::new(o, east).unwrap();
            let got = p.pick(&ray).unwrap().map(|h| (h.t, h.cell));
            same_hit(
                &ray,
                got,
                dem.surface.brute(&ray),
                &std::format!("lon {lon}, grazing at {k}"),
            );
            grazing_hits += usize::from(got.is_some());
        }
    }
    assert_eq!(checked, 3 * lons.len());
    std::println!(
        "grazing rays that hit: {grazing_hits} of {}",
        9 * lons.len()
    );
}
