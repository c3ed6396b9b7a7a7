//! The terrain through the C interface: builds, picks, lines of sight and paging, against the Rust API.

use super::*;

/// A 9 × 9 DEM near (45° N, 7° E), 0.01° cells, heights `50 · ((3i + 5j) mod 7)` m.
fn dem() -> (curvicast_dem_grid_f64, Vec<f32>) {
    let g = curvicast_dem_grid_f64 {
        lat0_deg: 45.0,
        lon0_deg: 7.0,
        dlat_deg: 0.01,
        dlon_deg: 0.01,
        rows: 9,
        cols: 9,
    };
    let h = (0..81u32)
        .map(|k| 50.0 * ((3 * (k / 9) + 5 * (k % 9)) % 7) as f32)
        .collect();
    (g, h)
}

/// A ray from 5 km above (lat, lon) straight down.
fn down(lat: f64, lon: f64) -> curvicast_ray_f64 {
    let e = Ellipsoid::<f64>::wgs84();
    let from = e.geodetic_deg_to_ecef(lat, lon, 5000.0);
    let n = e.normal_deg(lat, lon);
    ray64([from.x, from.y, from.z], [-n.x, -n.y, -n.z])
}

#[test]
fn pick_on_a_small_dem_hits_at_its_height_and_line_of_sight_agrees() {
    let (g, heights) = dem();
    let slots = curvicast_node_slots(9, 9, 4);
    let mut nodes = vec![
        curvicast_node_record {
            opaque: [0xAB; CURVICAST_NODE_RECORD_WORDS]
        };
        slots
    ];
    let mut terrain = zeroed::<curvicast_terrain_f64>();
    let mut picker = zeroed::<curvicast_picker_f64>();
    let mut hit = curvicast_hit_f64::default();
    let ray = down(45.04, 7.04);
    let (mut t, mut cell, mut clear) = (0.0, [0u32; 2], true);
    // SAFETY: valid arrays and objects, alive for the test.
    unsafe {
        let s = curvicast_terrain_f64_build(
            &mut *terrain,
            &g,
            heights.as_ptr(),
            81,
            4,
            nodes.as_mut_ptr(),
            slots,
        );
        assert_eq!(s, S::CURVICAST_OK);
        assert_eq!(
            curvicast_picker_f64_init(&mut *picker, &*terrain, 0),
            S::CURVICAST_OK
        );
        assert_eq!(
            curvicast_picker_f64_pick(&*picker, &ray, &mut hit, null_mut()),
            S::CURVICAST_OK
        );
        assert!(
            (hit.lat_deg - 45.04).abs() < 1e-6 && (hit.lon_deg - 7.04).abs() < 1e-6,
            "{hit:?}"
        );
        assert!(
            (0.0..=300.0).contains(&hit.h) && (hit.t - (5000.0 - hit.h)).abs() < 1e-3,
            "{hit:?}"
        );
        assert_eq!(
            curvicast_picker_f64_pick_t(&*picker, &ray, &mut t, cell.as_mut_ptr(), null_mut()),
            S::CURVICAST_OK
        );
        assert!((t - hit.t).abs() < 1e-6 && cell == hit.cell);
        // Up: no hit.
        let up = ray64(ray.origin, ray.dir.map(|d| -d));
        assert_eq!(
            curvicast_picker_f64_pick(&*picker, &up, &mut hit, null_mut()),
            S::CURVICAST_NO_HIT
        );
        // The segment to just above the hit is clear, to just below it is not.
        let at = |s: f64| [0, 1, 2].map(|k| ray.origin[k] + s * hit.t * ray.dir[k]);
        let s = curvicast_picker_f64_line_of_sight(
            &*picker,
            ray.origin.as_ptr(),
            at(0.999).as_ptr(),
            &mut clear,
            null_mut(),
        );
        assert_eq!((s, clear), (S::CURVICAST_OK, true));
        let s = curvicast_picker_f64_line_of_sight(
            &*picker,
            ray.origin.as_ptr(),
            at(1.001).as_ptr(),
            &mut clear,
            null_mut(),
        );
        assert_eq!((s, clear), (S::CURVICAST_OK, false));
        let s = curvicast_picker_f64_line_of_sight(
            &*picker,
            null(),
            at(1.001).as_ptr(),
            &mut clear,
            null_mut(),
        );
        assert_eq!(s, S::CURVICAST_NULL_POINTER);
        let s = curvicast_picker_f64_line_of_sight(
            &*picker,
            ray.origin.as_ptr(),
            at(1.001).as_ptr(),
            null_mut(),
            null_mut(),
        );
        assert_eq!(s, S::CURVICAST_NULL_POINTER);
        assert_eq!(
            curvicast_picker_f64_pick(&*picker, &ray, null_mut(), null_mut()),
            S::CURVICAST_NULL_POINTER
        );
    }
}

#[test]
fn short_or_missing_terrain_buffers_are_statuses() {
    let (g, heights) = dem();
    let slots = curvicast_node_slots(9, 9, 4);
    let mut nodes = vec![
        curvicast_node_record {
            opaque: [0; CURVICAST_NODE_RECORD_WORDS]
        };
        slots
    ];
    let mut terrain = zeroed::<curvicast_terrain_f64>();
    let mut picker = zeroed::<curvicast_picker_f64>();
    let shape = curvicast_multires_f64 {
        has_fine_region: false,
        fine_region: [0.0; 4],
        coarse_level: 1,
    };
    let resident = vec![true; slots];
    // SAFETY: NULL, or valid arrays with lengths up to theirs.
    unsafe {
        let np = nodes.as_mut_ptr();
        let build = |t: *mut _, h: *const f32, nh, n, nn| {
            curvicast_terrain_f64_build(t, &g, h, nh, 4, n, nn)
        };
        assert_eq!(
            build(&mut *terrain, heights.as_ptr(), 80, np, slots),
            S::CURVICAST_BUILD_HEIGHTS_LENGTH
        );
        assert_eq!(
            build(&mut *terrain, heights.as_ptr(), 81, np, slots - 1),
            S::CURVICAST_BUILD_BUFFER_TOO_SMALL
        );
        assert_eq!(
            build(&mut *terrain, null(), 81, np, slots),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            build(&mut *terrain, heights.as_ptr(), 81, null_mut(), slots),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            build(null_mut(), heights.as_ptr(), 81, np, slots),
            S::CURVICAST_NULL_POINTER
        );
        let odd = heights.as_ptr().cast::<u8>().wrapping_add(2).cast::<f32>();
        assert_eq!(
            build(&mut *terrain, odd, 80, np, slots),
            S::CURVICAST_MISALIGNED
        );
        // The failed builds left no terrain.
        assert_eq!(
            curvicast_picker_f64_init(&mut *picker, &*terrain, 0),
            S::CURVICAST_NOT_INITIALIZED
        );
        let s = curvicast_terrain_f64_build_multires(
            &mut *terrain,
            &g,
            heights.as_ptr(),
            81,
            4,
            &shape,
            np,
            slots,
            resident.as_ptr(),
            1,
        );
        assert_eq!(s, S::CURVICAST_BUILD_BUFFER_LENGTH);
        let s = curvicast_terrain_f64_build_multires(
            &mut *terrain,
            &g,
            heights.as_ptr(),
            81,
            4,
            null(),
            np,
            slots,
            resident.as_ptr(),
            slots,
        );
        assert_eq!(s, S::CURVICAST_NULL_POINTER);
        let bad = curvicast_dem_grid_f64 { dlon_deg: 0.0, ..g };
        let s =
            curvicast_terrain_f64_build(&mut *terrain, &bad, heights.as_ptr(), 81, 4, np, slots);
        assert_eq!(s, S::CURVICAST_BUILD_INVALID_GRID);
        let s = curvicast_terrain_f64_build(&mut *terrain, &g, heights.as_ptr(), 81, 0, np, slots);
        assert_eq!(s, S::CURVICAST_BUILD_INVALID_BLOCK);
    }
}

#[test]
fn a_multiresolution_pick_asks_for_each_missing_block_by_node_and_then_hits() {
    let (g, heights) = dem();
    let slots = curvicast_node_slots(9, 9, 2);
    let mut nodes = vec![
        curvicast_node_record {
            opaque: [0; CURVICAST_NODE_RECORD_WORDS]
        };
        slots
    ];
    let mut resident = vec![false; slots];
    let mut terrain = zeroed::<curvicast_terrain_f64>();
    let mut picker = zeroed::<curvicast_picker_f64>();
    let shape = curvicast_multires_f64 {
        has_fine_region: false,
        fine_region: [0.0; 4],
        coarse_level: 0,
    };
    let ray = down(45.033, 7.051);
    let mut hit = curvicast_hit_f64::default();
    let mut asked = Vec::new();
    // SAFETY: valid arrays and objects; the flags change only between calls.
    unsafe {
        let s = curvicast_terrain_f64_build_multires(
            &mut *terrain,
            &g,
            heights.as_ptr(),
            81,
            2,
            &shape,
            nodes.as_mut_ptr(),
            slots,
            resident.as_ptr(),
            slots,
        );
        assert_eq!(s, S::CURVICAST_OK);
        // min_level 2: blocks of the two levels nearest the zones never stand in for finer ones.
        assert_eq!(
            curvicast_picker_f64_init(&mut *picker, &*terrain, 2),
            S::CURVICAST_OK
        );
        let mut node = u32::MAX;
        loop {
            match curvicast_picker_f64_pick(&*picker, &ray, &mut hit, &mut node) {
                S::CURVICAST_TERRAIN_NEEDS_BLOCK => {
                    assert!(
                        !asked.contains(&node) && (node as usize) < slots,
                        "{node} {asked:?}"
                    );
                    asked.push(node);
                    *resident.as_mut_ptr().add(node as usize) = true;
                }
                s => {
                    assert_eq!(s, S::CURVICAST_OK);
                    break;
                }
            }
            assert!(asked.len() <= slots);
        }
    }
    assert!(!asked.is_empty());
    assert_eq!(hit.stride, 1);
    assert!(
        (hit.lat_deg - 45.033).abs() < 1e-6 && (hit.lon_deg - 7.051).abs() < 1e-6,
        "{hit:?}"
    );
}
