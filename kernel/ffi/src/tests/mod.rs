//! The boundary's checks, called as C calls them (raw pointers, lengths), and a few answers against the Rust
//! API. Run under Miri in CI, which checks the unsafe blocks of `lib.rs` on every path these tests take.

use crate::curvicast_status as S;
use crate::march::*;
use crate::picker::*;
use crate::terrain::*;
use crate::tessellate::*;
use crate::{curvicast_ray_f32, curvicast_ray_f64};
use core::f64::consts::PI;
use core::ptr::{null, null_mut};
use curvicast::geodesy::Ellipsoid;
use curvicast::march::SphericalGrid;
use curvicast::ray::Ray;
use std::vec;
use std::vec::Vec;

const R: [f64; 3] = [0.0, 0.5, 1.0];
const TH: [f64; 3] = [0.0, PI / 2.0, PI];
const PH: [f64; 3] = [0.0, PI, 2.0 * PI];

/// Storage of a C object, zeroed as a C static is.
fn zeroed<T>() -> std::boxed::Box<T> {
    // SAFETY: the storage types are arrays of integers (any bits valid).
    unsafe { std::boxed::Box::new_zeroed().assume_init() }
}

fn ray64(origin: [f64; 3], dir: [f64; 3]) -> curvicast_ray_f64 {
    curvicast_ray_f64 {
        origin,
        dir,
        t_min: 0.0,
        t_max: f64::INFINITY,
    }
}

/// The QEMU smoke test's grid, in `grid`.
fn smoke_grid(grid: &mut curvicast_grid_f64, ws: &mut [f64]) -> S {
    // SAFETY: valid arrays with their lengths; they outlive the uses in each test.
    unsafe {
        curvicast_spherical_grid_f64_init(
            grid,
            R.as_ptr(),
            3,
            TH.as_ptr(),
            3,
            PH.as_ptr(),
            3,
            null(),
            ws.as_mut_ptr(),
            ws.len(),
        )
    }
}

#[test]
fn march_through_the_smoke_grid_gives_the_rust_apis_crossings_one_by_one_and_in_batches() {
    let mut ws = [0.0; 15];
    let mut grid = zeroed::<curvicast_grid_f64>();
    assert_eq!(smoke_grid(&mut grid, &mut ws), S::CURVICAST_OK);
    let ray = ray64([-2.0, 0.25, 0.25], [1.0, 0.0, 0.0]);
    let mut march = zeroed::<curvicast_march_f64>();
    let mut got = Vec::new();
    let mut c = curvicast_crossing_f64::default();
    // SAFETY: valid pointers to live objects.
    unsafe {
        assert_eq!(
            curvicast_march_f64_begin(&mut *march, &*grid, &ray),
            S::CURVICAST_OK
        );
        while curvicast_march_f64_next(&mut *march, &mut c) == S::CURVICAST_OK {
            got.push(c);
        }
        // Once done, it stays done.
        assert_eq!(
            curvicast_march_f64_next(&mut *march, &mut c),
            S::CURVICAST_DONE
        );
    }
    let mut ws2 = [0.0; 15];
    let rust = SphericalGrid::new(&R, &TH, &PH, &mut ws2).unwrap();
    let want: Vec<curvicast_crossing_f64> = rust
        .march(&Ray::new([-2.0, 0.25, 0.25], [1.0, 0.0, 0.0]).unwrap())
        .map(Into::into)
        .collect();
    assert_eq!(got, want);
    assert_eq!(
        got.iter().map(|c| c.cell).collect::<Vec<_>>(),
        [[1, 0, 0], [0, 0, 0], [1, 0, 0]]
    );
    // In batches of two: 2 (OK), then 1 (DONE).
    let mut batch = [curvicast_crossing_f64::default(); 2];
    let mut written = 99;
    // SAFETY: as above.
    unsafe {
        assert_eq!(
            curvicast_march_f64_begin(&mut *march, &*grid, &ray),
            S::CURVICAST_OK
        );
        assert_eq!(
            curvicast_march_f64_fill(&mut *march, batch.as_mut_ptr(), 2, &mut written),
            S::CURVICAST_OK
        );
        assert_eq!((written, batch), (2, [want[0], want[1]]));
        assert_eq!(
            curvicast_march_f64_fill(&mut *march, batch.as_mut_ptr(), 2, &mut written),
            S::CURVICAST_DONE
        );
        assert_eq!((written, batch[0]), (1, want[2]));
        assert_eq!(
            curvicast_march_f64_fill(&mut *march, batch.as_mut_ptr(), 0, &mut written),
            S::CURVICAST_ZERO_CAPACITY
        );
    }
}

#[test]
fn march_in_single_precision_along_the_z_axis_crosses_the_north_and_south_cells() {
    let (r, th, ph) = (
        [0.0f32, 1.0],
        [0.0f32, 1.0, core::f32::consts::PI],
        [0.0f32, 6.2831855],
    );
    let mut ws = [0.0f32; 12];
    let mut grid = zeroed::<curvicast_grid_f32>();
    let mut march = zeroed::<curvicast_march_f32>();
    let ray = curvicast_ray_f32 {
        origin: [0.0, 0.0, -2.0],
        dir: [0.0, 0.0, 1.0],
        t_min: 0.0,
        t_max: f32::INFINITY,
    };
    let mut c = curvicast_crossing_f32::default();
    let mut cells = Vec::new();
    // SAFETY: valid arrays and objects.
    unsafe {
        let s = curvicast_spherical_grid_f32_init(
            &mut *grid,
            r.as_ptr(),
            2,
            th.as_ptr(),
            3,
            ph.as_ptr(),
            2,
            null(),
            ws.as_mut_ptr(),
            12,
        );
        assert_eq!(s, S::CURVICAST_OK);
        assert_eq!(
            curvicast_march_f32_begin(&mut *march, &*grid, &ray),
            S::CURVICAST_OK
        );
        while curvicast_march_f32_next(&mut *march, &mut c) == S::CURVICAST_OK {
            cells.push(c.cell);
        }
    }
    assert_eq!(cells, [[0, 1, 0], [0, 0, 0]]);
}

#[test]
fn null_misaligned_and_short_arguments_of_a_grid_are_statuses() {
    let mut ws = [0.0f64; 16];
    let mut grid = zeroed::<curvicast_grid_f64>();
    let init =
        |grid: *mut curvicast_grid_f64, r: *const f64, nr: usize, ws: *mut f64, nws: usize| {
            // SAFETY: each pointer is NULL, misaligned, or valid for its length.
            unsafe {
                curvicast_spherical_grid_f64_init(
                    grid,
                    r,
                    nr,
                    TH.as_ptr(),
                    3,
                    PH.as_ptr(),
                    3,
                    null(),
                    ws,
                    nws,
                )
            }
        };
    let ws_ptr = ws.as_mut_ptr();
    assert_eq!(
        init(null_mut(), R.as_ptr(), 3, ws_ptr, 15),
        S::CURVICAST_NULL_POINTER
    );
    assert_eq!(
        init(&mut *grid, null(), 3, ws_ptr, 15),
        S::CURVICAST_NULL_POINTER
    );
    assert_eq!(
        init(&mut *grid, null(), 0, ws_ptr, 15),
        S::CURVICAST_GRID_TOO_FEW_BREAKPOINTS
    );
    assert_eq!(
        init(&mut *grid, R.as_ptr(), 3, null_mut(), 15),
        S::CURVICAST_NULL_POINTER
    );
    assert_eq!(
        init(&mut *grid, R.as_ptr(), 3, ws_ptr, 14),
        S::CURVICAST_GRID_WORKSPACE_TOO_SMALL
    );
    let misaligned_r = R.as_ptr().cast::<u8>().wrapping_add(1).cast::<f64>();
    assert_eq!(
        init(&mut *grid, misaligned_r, 3, ws_ptr, 15),
        S::CURVICAST_MISALIGNED
    );
    let misaligned_grid = (&mut *grid as *mut curvicast_grid_f64)
        .cast::<u8>()
        .wrapping_add(4)
        .cast();
    assert_eq!(
        init(misaligned_grid, R.as_ptr(), 3, ws_ptr, 15),
        S::CURVICAST_MISALIGNED
    );
    assert_eq!(
        init(&mut *grid, R.as_ptr(), usize::MAX / 4, ws_ptr, 15),
        S::CURVICAST_BUFFER_TOO_LARGE
    );
    // A center that is not finite; a grid whose init failed is not a grid.
    let center = [f64::NAN, 0.0, 0.0];
    // SAFETY: valid arrays.
    let s = unsafe {
        curvicast_spherical_grid_f64_init(
            &mut *grid,
            R.as_ptr(),
            3,
            TH.as_ptr(),
            3,
            PH.as_ptr(),
            3,
            center.as_ptr(),
            ws_ptr,
            15,
        )
    };
    assert_eq!(s, S::CURVICAST_GRID_NON_FINITE_CENTER);
    let mut march = zeroed::<curvicast_march_f64>();
    let ray = ray64([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    // SAFETY: valid pointers.
    unsafe {
        assert_eq!(
            curvicast_march_f64_begin(&mut *march, &*grid, &ray),
            S::CURVICAST_NOT_INITIALIZED
        );
    }
}

#[test]
fn a_march_used_before_begin_or_with_null_arguments_answers_a_status() {
    let mut ws = [0.0; 15];
    let mut grid = zeroed::<curvicast_grid_f64>();
    assert_eq!(smoke_grid(&mut grid, &mut ws), S::CURVICAST_OK);
    let mut march = zeroed::<curvicast_march_f64>();
    let mut c = curvicast_crossing_f64::default();
    let mut written = 0usize;
    let bad_ray = ray64([-2.0, 0.0, 0.0], [0.0, 0.0, 0.0]);
    // SAFETY: NULL or valid pointers.
    unsafe {
        assert_eq!(
            curvicast_march_f64_next(&mut *march, &mut c),
            S::CURVICAST_NOT_INITIALIZED
        );
        assert_eq!(
            curvicast_march_f64_next(null_mut(), &mut c),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            curvicast_march_f64_begin(&mut *march, &*grid, null()),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            curvicast_march_f64_begin(&mut *march, null(), &bad_ray),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            curvicast_march_f64_begin(&mut *march, &*grid, &bad_ray),
            S::CURVICAST_RAY_ZERO_DIRECTION
        );
        // The failed begin left the march uninitialized, not half-made.
        assert_eq!(
            curvicast_march_f64_next(&mut *march, &mut c),
            S::CURVICAST_NOT_INITIALIZED
        );
        let ray = ray64([-2.0, 0.1, 0.1], [1.0, 0.0, 0.0]);
        assert_eq!(
            curvicast_march_f64_begin(&mut *march, &*grid, &ray),
            S::CURVICAST_OK
        );
        assert_eq!(
            curvicast_march_f64_next(&mut *march, null_mut()),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            curvicast_march_f64_fill(&mut *march, &mut c, 1, null_mut()),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            curvicast_march_f64_fill(&mut *march, null_mut(), 1, &mut written),
            S::CURVICAST_NULL_POINTER
        );
    }
}

#[test]
fn cylindrical_and_polar_grids_report_their_own_errors() {
    let (rho, phi, z) = ([0.0, 1.0], [0.0, 2.0 * PI], [1.0, 0.0]);
    let mut ws = [0.0; 8];
    let mut grid = zeroed::<curvicast_grid_f64>();
    // SAFETY: valid arrays.
    unsafe {
        let s = curvicast_cylindrical_grid_f64_init(
            &mut *grid,
            rho.as_ptr(),
            2,
            phi.as_ptr(),
            2,
            z.as_ptr(),
            2,
            null(),
            ws.as_mut_ptr(),
            8,
        );
        assert_eq!(s, S::CURVICAST_GRID_NOT_INCREASING);
        let s = curvicast_polar_grid_f64_init(
            &mut *grid,
            rho.as_ptr(),
            2,
            phi.as_ptr(),
            2,
            null(),
            ws.as_mut_ptr(),
            5,
        );
        assert_eq!(s, S::CURVICAST_GRID_WORKSPACE_TOO_SMALL);
        let s = curvicast_polar_grid_f64_init(
            &mut *grid,
            rho.as_ptr(),
            2,
            phi.as_ptr(),
            2,
            null(),
            ws.as_mut_ptr(),
            6,
        );
        assert_eq!(s, S::CURVICAST_OK);
    }
    assert_eq!(curvicast_polar_workspace_len(2, 2), 6);
    assert_eq!(curvicast_cylindrical_workspace_len(2, 2), 6);
    assert_eq!(curvicast_spherical_workspace_len(3, 3, 3), 15);
}

#[test]
fn levels_and_bevels_answer_through_the_boundary_with_statuses_for_bad_buffers() {
    let mut level = 99;
    let sphere = [1.0f64; 3];
    // SAFETY: NULL or valid arrays.
    unsafe {
        assert_eq!(
            curvicast_level_for_deviation_f64(sphere.as_ptr(), 1e-2, &mut level),
            S::CURVICAST_OK
        );
        let want = curvicast::tessellate::lod::min_level(
            curvicast::tessellate::lod::Shape::Sphere(1.0),
            curvicast::tessellate::lod::Bound::MaxDeviation(1e-2),
        );
        assert_eq!(Ok(level), want);
        assert_eq!(
            curvicast_level_for_deviation_f64(null(), 1e-2, &mut level),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            curvicast_level_for_deviation_f64(sphere.as_ptr(), 1e-2, null_mut()),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            curvicast_level_for_dihedral_f64(sphere.as_ptr(), 4.0, &mut level),
            S::CURVICAST_TESSELLATE_INVALID_BOUND
        );
        assert_eq!(
            curvicast_level_for_screen_f64(sphere.as_ptr(), 0.5, 1e-3, &mut level),
            S::CURVICAST_TESSELLATE_INVALID_BOUND
        );
    }
    let (nv, nf) = (
        curvicast_bevel_vertex_count(1),
        curvicast_bevel_face_count(1),
    );
    assert_eq!((nv, nf), (32, 18));
    assert_eq!(
        (
            curvicast_bevel_vertex_count(13),
            curvicast_bevel_face_count(13)
        ),
        (0, 0)
    );
    let mut v = vec![curvicast_vec3_f32::default(); nv];
    let mut f = vec![curvicast_face_f32::default(); nf];
    let axes = [3.0f32, 2.0, 1.0];
    // SAFETY: valid arrays with lengths up to theirs.
    unsafe {
        let (vp, fp) = (v.as_mut_ptr(), f.as_mut_ptr());
        assert_eq!(
            curvicast_bevel_ellipsoid_f32(1, axes.as_ptr(), vp, nv - 1, fp, nf),
            S::CURVICAST_TESSELLATE_BUFFER_TOO_SMALL
        );
        assert_eq!(
            curvicast_bevel_ellipsoid_f32(1, axes.as_ptr(), vp, nv, fp, nf - 1),
            S::CURVICAST_TESSELLATE_BUFFER_TOO_SMALL
        );
        assert_eq!(
            curvicast_bevel_ellipsoid_f32(1, axes.as_ptr(), null_mut(), nv, fp, nf),
            S::CURVICAST_NULL_POINTER
        );
        assert_eq!(
            curvicast_bevel_ellipsoid_f32(13, axes.as_ptr(), vp, nv, fp, nf),
            S::CURVICAST_TESSELLATE_LEVEL_TOO_DEEP
        );
        let odd = fp.cast::<u8>().wrapping_add(1).cast();
        assert_eq!(
            curvicast_bevel_ellipsoid_f32(1, axes.as_ptr(), vp, nv, odd, nf - 1),
            S::CURVICAST_MISALIGNED
        );
        assert_eq!(
            curvicast_bevel_ellipsoid_f32(1, axes.as_ptr(), vp, nv, fp, nf),
            S::CURVICAST_OK
        );
    }
    // The sphere entry is the ellipsoid of three equal axes.
    let mut v2 = vec![curvicast_vec3_f32::default(); nv];
    let mut f2 = vec![curvicast_face_f32::default(); nf];
    let mut v3 = v2.clone();
    let mut f3 = f2.clone();
    let sphere = [2.5f32; 3];
    // SAFETY: valid arrays with their lengths.
    unsafe {
        let s = curvicast_bevel_sphere_f32(1, 2.5, v2.as_mut_ptr(), nv, f2.as_mut_ptr(), nf);
        assert_eq!(s, S::CURVICAST_OK);
        let s = curvicast_bevel_ellipsoid_f32(
            1,
            sphere.as_ptr(),
            v3.as_mut_ptr(),
            nv,
            f3.as_mut_ptr(),
            nf,
        );
        assert_eq!(s, S::CURVICAST_OK);
    }
    assert_eq!((v2, f2), (v3, f3));
    // Every face's center lies on the ellipsoid, every face has 4 or 6 vertices.
    for face in &f {
        let c = face.center;
        let on = (c.x / 3.0).powi(2) + (c.y / 2.0).powi(2) + c.z.powi(2);
        assert!(
            (on - 1.0).abs() < 1e-5 && (face.len == 4 || face.len == 6),
            "{face:?}"
        );
    }
}

#[test]
fn wgs84_to_ecef_is_the_kernels_conversion_and_null_is_a_status() {
    let mut p = [0.0f64; 3];
    // SAFETY: NULL or a valid array of 3.
    unsafe {
        assert_eq!(
            curvicast_wgs84_to_ecef_f64(45.04, 7.04, 5000.0, p.as_mut_ptr()),
            S::CURVICAST_OK
        );
        assert_eq!(
            curvicast_wgs84_to_ecef_f64(45.04, 7.04, 5000.0, null_mut()),
            S::CURVICAST_NULL_POINTER
        );
    }
    let q = Ellipsoid::<f64>::wgs84().geodetic_deg_to_ecef(45.04, 7.04, 5000.0);
    assert_eq!(p, [q.x, q.y, q.z]);
    let mut p32 = [0.0f32; 3];
    // SAFETY: a valid array of 3.
    let s = unsafe { curvicast_wgs84_to_ecef_f32(-80.0, 179.5, 0.0, p32.as_mut_ptr()) };
    assert_eq!(s, S::CURVICAST_OK);
    let q = Ellipsoid::<f32>::wgs84().geodetic_deg_to_ecef(-80.0, 179.5, 0.0);
    assert_eq!(p32, [q.x, q.y, q.z]);
}

mod terrain;
