//! Named hard cases with hand-derived expectations (light enough for Miri). The arbitrary-precision oracle
//! comparisons are in the host crate.

use super::*;
use crate::ray::Ray;
use core::f64::consts::PI;
use std::vec::Vec;

const R: [f64; 3] = [0.0, 0.5, 1.0];
const TH: [f64; 3] = [0.0, PI / 2.0, PI];
const PH: [f64; 3] = [0.0, PI, 2.0 * PI];

/// Marches with both engines (which must agree exactly) and returns the crossings.
fn march_s(r: &[f64], th: &[f64], ph: &[f64], ray: &Ray<f64>) -> Vec<CellCrossing<f64>> {
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(r, th, ph, &mut ws).unwrap();
    let mut m = g.march(ray);
    let a: Vec<_> = m.by_ref().collect();
    assert_eq!(m.error(), None);
    let b: Vec<_> = g.march_separable::<32>(ray).unwrap().collect();
    assert_eq!(a, b, "serial and separable differ");
    a
}

/// Checks cells exactly and t values to `tol` (relative to max(1, |t|)).
fn expect(got: &[CellCrossing<f64>], want: &[([u32; 3], f64, f64)], tol: f64) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, &(cell, a, b)) in got.iter().zip(want) {
        assert_eq!(g.cell, cell, "{got:?}");
        assert!(
            (g.t_enter - a).abs() <= tol * a.abs().max(1.0),
            "{g:?} vs {a}"
        );
        assert!(
            (g.t_exit - b).abs() <= tol * b.abs().max(1.0),
            "{g:?} vs {b}"
        );
    }
}

#[test]
fn ray_through_the_origin_steps_theta_then_phi_at_the_center() {
    let ray = Ray::new([-2.0, -2.0, -2.0], [1.0, 1.0, 1.0]).unwrap();
    let s3 = 3f64.sqrt();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 1, 1], 2.0 - 1.0 / s3, 2.0 - 0.5 / s3),
            ([0, 1, 1], 2.0 - 0.5 / s3, 2.0),
            ([0, 0, 1], 2.0, 2.0), // θ jumps to π − θ at the center ...
            ([0, 0, 0], 2.0, 2.0 + 0.5 / s3), // ... then φ by π
            ([1, 0, 0], 2.0 + 0.5 / s3, 2.0 + 1.0 / s3),
        ],
        1e-15,
    );
}

#[test]
fn ray_along_plus_z_axis_is_outside_below_the_center() {
    // On the −z axis θ = π, outside a grid whose last θ is π; on the +z axis θ = 0 and φ = 0 by convention.
    let ray = Ray::new([0.0, 0.0, -2.0], [0.0, 0.0, 1.0]).unwrap();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([0, 1, 0], 2.0, 2.0),
            ([0, 0, 0], 2.0, 2.5),
            ([1, 0, 0], 2.5, 3.0),
        ],
        0.0,
    );
}

#[test]
fn ray_along_minus_z_axis_leaves_the_domain_at_the_center() {
    let ray = Ray::new([0.0, 0.0, 2.0], [0.0, 0.0, -1.0]).unwrap();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 0, 0], 1.0, 1.5),
            ([0, 0, 0], 1.5, 2.0),
            ([0, 1, 0], 2.0, 2.0),
        ],
        0.0,
    );
}

#[test]
fn ray_in_the_plane_z0_has_theta_half_pi_cell() {
    let ray = Ray::new([-2.0, 0.3, 0.0], [1.0, 0.0, 0.0]).unwrap();
    let a = (1.0f64 - 0.09).sqrt();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 1, 0], 2.0 - a, 1.6),
            ([0, 1, 0], 1.6, 2.4),
            ([1, 1, 0], 2.4, 2.0 + a),
        ],
        1e-15,
    );
}

#[test]
fn ray_crossing_the_z_axis_off_the_origin_jumps_phi_by_pi() {
    let ray = Ray::new([-2.0, 0.0, 0.3], [1.0, 0.0, 0.0]).unwrap();
    let a = (1.0f64 - 0.09).sqrt();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 0, 1], 2.0 - a, 1.6),
            ([0, 0, 1], 1.6, 2.0),
            ([0, 0, 0], 2.0, 2.4),
            ([1, 0, 0], 2.4, 2.0 + a),
        ],
        1e-15,
    );
}

#[test]
fn ray_tangent_to_a_shell_stays_in_the_outer_cell() {
    // distance of the line from the center = |(0, 0.375, 0.5)| = 0.625 exactly: a touch, not an entry.
    let r = [0.0, 0.625, 1.0];
    let ray = Ray::new([-2.0, 0.375, 0.5], [1.0, 0.0, 0.0]).unwrap();
    let h = (1.0f64 - 0.390625).sqrt();
    let c = march_s(&r, &TH, &PH, &ray);
    expect(&c, &[([1, 0, 0], 2.0 - h, 2.0 + h)], 1e-15);
}

#[test]
fn ray_through_an_edge_sphere_and_cone() {
    // through (0, 0.5, 0): on the sphere r = 0.5 and the plane θ = π/2 at t = 1 exactly
    let ray = Ray::new([-0.25, 1.5, -1.0], [0.25, -1.0, 1.0]).unwrap();
    let s = 7.1875f64.sqrt();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 1, 0], (5.125 - s) / 4.125, 1.0),
            ([0, 1, 0], 1.0, 1.0),
            ([0, 0, 0], 1.0, 3.0625 / 2.0625),
            ([1, 0, 0], 3.0625 / 2.0625, 1.5),
            ([1, 0, 1], 1.5, (5.125 + s) / 4.125),
        ],
        1e-15,
    );
}

#[test]
fn ray_through_a_corner_sphere_cone_and_half_plane() {
    // through (0.5, 0, 0) at t = 1: r = 0.5, θ = π/2 and φ = 0 at once; one index per crossing
    let ray = Ray::new([1.5, -1.0, -1.0], [-1.0, 1.0, 1.0]).unwrap();
    let s = 10f64.sqrt();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 1, 1], (7.0 - s) / 6.0, 1.0),
            ([0, 1, 1], 1.0, 1.0),
            ([0, 0, 1], 1.0, 1.0),
            ([0, 0, 0], 1.0, 4.0 / 3.0),
            ([1, 0, 0], 4.0 / 3.0, (7.0 + s) / 6.0),
        ],
        1e-15,
    );
}

#[test]
fn ray_starting_exactly_on_a_sphere_going_inward() {
    // |(0.25, 0.375, 0.75)| = 0.875 exactly
    let r = [0.0, 0.875, 2.0];
    let ray = Ray::new([0.25, 0.375, 0.75], [-1.0, 0.0, 0.0]).unwrap();
    let out = 0.25 + (4.0f64 - 0.703125).sqrt();
    let c = march_s(&r, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 0, 0], 0.0, 0.0),
            ([0, 0, 0], 0.0, 0.5),
            ([1, 0, 0], 0.5, out),
        ],
        1e-15,
    );
}

#[test]
fn ray_starting_exactly_on_the_theta_half_pi_plane_going_up() {
    let ray = Ray::new([0.3, 0.2, 0.0], [0.0, 0.0, 1.0]).unwrap();
    let top = (0.25f64 - 0.13).sqrt();
    let c = march_s(&R, &TH, &PH, &ray);
    assert_eq!(c[0].cell, [0, 1, 0]);
    assert_eq!((c[0].t_enter, c[0].t_exit), (0.0, 0.0));
    expect(
        &c[1..],
        &[
            ([0, 0, 0], 0.0, top),
            ([1, 0, 0], top, (1.0f64 - 0.13).sqrt()),
        ],
        1e-15,
    );
}

#[test]
fn ray_starting_exactly_on_an_azimuth_boundary() {
    // on the half-plane φ = π (x < 0, y = 0), moving toward y > 0 (φ decreasing into [0, π))
    let ray = Ray::new([-0.3, 0.0, 0.2], [0.0, 1.0, 0.0]).unwrap();
    let c = march_s(&R, &TH, &PH, &ray);
    // the stored boundary is at φ = fl(π), whose sine is 1.2e-16: the crossing is at t ≈ 4e-17, not 0
    assert_eq!((c[0].cell, c[0].t_enter), ([0, 0, 1], 0.0));
    assert!(c[0].t_exit < 1e-15);
    assert_eq!(c[1].cell, [0, 0, 0]);
    assert_eq!(c[1].t_enter, c[0].t_exit);
}

#[test]
fn segment_starting_and_ending_inside_one_cell() {
    let ray = Ray::new([0.1, 0.1, 0.1], [1.0, 0.0, 0.0])
        .unwrap()
        .with_interval(0.05, 0.1)
        .unwrap();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(&c, &[([0, 0, 0], 0.05, 0.1)], 0.0);
}

#[test]
fn ray_leaving_and_reentering_a_wedge_wider_than_pi() {
    // polar wedge φ ∈ [0, 3π/2] (the fourth quadrant is outside), disc r < 2
    let (r, ph) = ([0.0, 2.0], [0.0, 1.5 * PI]);
    let mut ws = [0.0; 8];
    let g = PolarGrid::new(&r, &ph, &mut ws).unwrap();
    let ray = Ray::new([-1.0, -1.5, 0.0], [1.0, 1.0, 0.0]).unwrap();
    let a: Vec<_> = g.march(&ray).collect();
    let b: Vec<_> = g.march_separable::<8>(&ray).unwrap().collect();
    assert_eq!(a, b);
    let out = (5.0 + 31f64.sqrt()) / 4.0;
    expect(&a, &[([0, 0, 0], 0.0, 1.0), ([0, 0, 0], 1.5, out)], 1e-15);
}

#[test]
fn vertical_ray_crosses_the_theta_half_pi_boundary() {
    let ray = Ray::new([0.25, 0.25, -1.0], [0.0, 0.0, 1.0]).unwrap();
    let (o, i) = (0.875f64.sqrt(), 0.125f64.sqrt());
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 1, 0], 1.0 - o, 1.0 - i),
            ([0, 1, 0], 1.0 - i, 1.0),
            ([0, 0, 0], 1.0, 1.0 + i),
            ([1, 0, 0], 1.0 + i, 1.0 + o),
        ],
        1e-15,
    );
}

#[test]
fn ray_parallel_to_a_cone_generator() {
    // cone θ = π/4 has cos = sin: the quadratic is linear; the line (t − 1, 0.25, t − 0.5) enters it once
    let th = [0.0, PI / 4.0, PI / 2.0, PI];
    let r = [0.0, 1.0];
    let ray = Ray::new([-1.0, 0.25, -0.5], [1.0, 0.0, 1.0]).unwrap();
    let s = 6.5f64.sqrt();
    let c = march_s(&r, &th, &PH, &ray);
    expect(
        &c,
        &[
            ([0, 2, 0], (3.0 - s) / 4.0, 0.5),
            ([0, 1, 0], 0.5, 0.8125),
            ([0, 0, 0], 0.8125, (3.0 + s) / 4.0),
        ],
        1e-14,
    );
}

#[test]
fn earth_scale_shells_of_one_meter_and_microradian_bands() {
    let r0 = 6.4e6;
    let r = [r0, r0 + 1.0, r0 + 2.0];
    let th = [PI / 2.0 - 1e-6, PI / 2.0, PI / 2.0 + 1e-6];
    let ph = [0.0, 1e-6];
    let (c, s) = (0.5e-6f64.cos(), 0.5e-6f64.sin());
    let ray = Ray::new([7e6 * c, 7e6 * s, 0.1], [-c, -s, 0.0]).unwrap();
    let got = march_s(&r, &th, &ph, &ray);
    assert_eq!(got.len(), 2, "{got:?}");
    assert_eq!(got[0].cell, [1, 0, 0]);
    assert_eq!(got[1].cell, [0, 0, 0]);
    // radial distance along the ray: s(r) = 7e6 − sqrt(r² − 0.01) (the line is 0.1 m off the center)
    let t = |rr: f64| 7e6 - (rr * rr - 0.01).sqrt();
    for (g, (a, b)) in got
        .iter()
        .zip([(t(r0 + 2.0), t(r0 + 1.0)), (t(r0 + 1.0), t(r0))])
    {
        assert!(
            (g.t_enter - a).abs() < 1e-6 && (g.t_exit - b).abs() < 1e-6,
            "{g:?}"
        );
    }
}

#[test]
fn micro_scale_grid_matches_unit_grid() {
    let k = 1e-6;
    let r = R.map(|x| x * k);
    let ray = Ray::new([-2.0 * k, 0.0, 0.3 * k], [1.0, 0.0, 0.0]).unwrap();
    let unit = march_s(
        &R,
        &TH,
        &PH,
        &Ray::new([-2.0, 0.0, 0.3], [1.0, 0.0, 0.0]).unwrap(),
    );
    let small = march_s(&r, &TH, &PH, &ray);
    assert_eq!(unit.len(), small.len());
    for (u, s) in unit.iter().zip(&small) {
        assert_eq!(u.cell, s.cell);
        assert!((u.t_enter * k - s.t_enter).abs() < 1e-15 * k * 4.0);
    }
}

#[test]
fn direction_lengths_1e_minus_30_and_1e30_scale_t_exactly() {
    let base = march_s(
        &R,
        &TH,
        &PH,
        &Ray::new([-2.0, 0.1, 0.3], [1.0, 0.2, 0.0]).unwrap(),
    );
    for s in [1e-30, 1e30] {
        let c = march_s(
            &R,
            &TH,
            &PH,
            &Ray::new([-2.0, 0.1, 0.3], [s, 0.2 * s, 0.0]).unwrap(),
        );
        assert_eq!(c.len(), base.len());
        for (a, b) in c.iter().zip(&base) {
            assert_eq!(a.cell, b.cell);
            assert!((a.t_enter * s - b.t_enter).abs() <= 1e-15 * b.t_enter.abs().max(1.0));
            assert!((a.t_exit * s - b.t_exit).abs() <= 1e-15 * b.t_exit.abs().max(1.0));
        }
    }
}

#[test]
fn f32_ray_through_the_origin_has_the_same_cells() {
    let (r, th, ph) = (
        R.map(|x| x as f32),
        TH.map(|x| x as f32),
        PH.map(|x| x as f32),
    );
    let mut ws = [0.0f32; 32];
    let g = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let ray = Ray::new([-2.0f32, -2.0, -2.0], [1.0, 1.0, 1.0]).unwrap();
    let cells: Vec<_> = g.march(&ray).map(|c| c.cell).collect();
    assert_eq!(
        cells,
        [[1, 1, 1], [0, 1, 1], [0, 0, 1], [0, 0, 0], [1, 0, 0]]
    );
}

#[test]
fn cylinder_cells_and_wedge_across_phi_zero() {
    let (rho, ph, z) = ([0.5, 1.0, 2.0], [-0.5, 0.0, 0.5], [0.0, 1.0]);
    let mut ws = [0.0; 16];
    let g = CylindricalGrid::new(&rho, &ph, &z, &mut ws).unwrap();
    // along −x at y = −0.1, z = 0.5: inside the wedge φ ∈ [−0.5, 0) while x > 0.1 / tan 0.5
    let ray = Ray::new([3.0, -0.1, 0.5], [-1.0, 0.0, 0.0]).unwrap();
    let a: Vec<_> = g.march(&ray).collect();
    let b: Vec<_> = g.march_separable::<16>(&ray).unwrap().collect();
    assert_eq!(a, b);
    let cells: Vec<_> = a.iter().map(|c| c.cell).collect();
    // ρ = 2 at x = sqrt(4 − 0.01), ρ = 1 at sqrt(1 − 0.01), ρ = 0.5 at sqrt(0.25 − 0.01): y < 0 → φ ∈ [−0.5, 0)
    assert_eq!(cells, [[1, 0, 0], [0, 0, 0]]);
    assert!((a[0].t_enter - (3.0 - 3.99f64.sqrt())).abs() < 1e-15);
    assert!((a[1].t_exit - (3.0 - 0.24f64.sqrt())).abs() < 1e-15);
}

#[test]
fn separable_buffer_full_is_an_error_not_a_truncation() {
    let r: Vec<f64> = (0..20).map(|i| i as f64 * 0.05).collect();
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&r, &TH, &PH, &mut ws).unwrap();
    let ray = Ray::new([-2.0, 0.01, 0.01], [1.0, 0.0, 0.0]).unwrap();
    assert_eq!(
        g.march_separable::<4>(&ray).err(),
        Some(MarchError::BufferFull {
            axis: Axis::R,
            capacity: 4
        })
    );
    assert!(g.march_separable::<64>(&ray).is_ok());
}

#[test]
fn separable_filled_in_place_is_reused_across_hits_misses_and_a_full_buffer() {
    // One march reused: a ray through the center (a jump through every radius band), one that misses the
    // ball, one that overflows the 8-entry buffers, then a hit again. After each fill it must yield exactly what
    // the serial engine does (nothing after a miss or an error), never leftovers of the previous ray.
    let r: Vec<f64> = (0..8).map(|i| i as f64 / 7.0).collect();
    let many: Vec<f64> = (0..20).map(|i| i as f64 * 0.05).collect();
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&r, &TH, &PH, &mut ws).unwrap();
    let mut ws2 = [0.0; 64];
    let g_many = SphericalGrid::new(&many, &TH, &PH, &mut ws2).unwrap();
    let through = Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
    let miss = Ray::new([-2.0, 3.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
    let off = Ray::new([-2.0, 0.3, 0.4], [1.0, 0.1, -0.2]).unwrap();
    let overflow = Ray::new([-2.0, 0.01, 0.01], [1.0, 0.0, 0.0]).unwrap();
    let mut m = SeparableMarch::<f64, 16>::default();
    assert_eq!(m.by_ref().count(), 0);
    for ray in [&through, &miss, &off, &through] {
        g.march_separable_into(ray, &mut m).unwrap();
        let got: Vec<_> = m.by_ref().collect();
        let want: Vec<_> = g.march(ray).collect();
        assert_eq!(got, want);
        assert_eq!(m.error(), None);
    }
    assert_eq!(
        g_many.march_separable_into(&overflow, &mut m),
        Err(MarchError::BufferFull {
            axis: Axis::R,
            capacity: 16
        })
    );
    assert_eq!(m.listed(), [0, 0, 0]);
    assert_eq!(m.by_ref().count(), 0);
    g.march_separable_into(&off, &mut m).unwrap();
    let again: Vec<_> = m.by_ref().collect();
    assert!(!again.is_empty());
    assert_eq!(again, g.march(&off).collect::<Vec<_>>());
}

#[test]
fn grid_errors_name_axis_and_index() {
    let mut ws = [0.0; 64];
    let e =
        |r: &[f64], th: &[f64], ph: &[f64], ws: &mut [f64]| SphericalGrid::new(r, th, ph, ws).err();
    assert_eq!(
        e(&[0.0], &TH, &PH, &mut ws),
        Some(GridError::TooFewBreakpoints {
            axis: Axis::R,
            len: 1
        })
    );
    assert_eq!(
        e(&[0.0, 1.0, 1.0], &TH, &PH, &mut ws),
        Some(GridError::NotIncreasing {
            axis: Axis::R,
            index: 2
        })
    );
    assert_eq!(
        e(&[-1.0, 1.0], &TH, &PH, &mut ws),
        Some(GridError::OutOfRange {
            axis: Axis::R,
            index: 0
        })
    );
    assert_eq!(
        e(&R, &[0.0, 4.0], &PH, &mut ws),
        Some(GridError::OutOfRange {
            axis: Axis::Theta,
            index: 1
        })
    );
    assert_eq!(
        e(&R, &TH, &[0.0, f64::NAN], &mut ws),
        Some(GridError::NonFinite {
            axis: Axis::Phi,
            index: 1
        })
    );
    assert_eq!(
        e(&R, &TH, &[-1.0, 6.0], &mut ws),
        Some(GridError::OutOfRange {
            axis: Axis::Phi,
            index: 1
        })
    );
    assert_eq!(
        e(&R, &TH, &PH, &mut ws[..5]),
        Some(GridError::WorkspaceTooSmall)
    );
    let mut ws2 = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws2).unwrap();
    assert_eq!(
        g.with_center([f64::NAN, 0.0, 0.0]).err(),
        Some(GridError::NonFiniteCenter)
    );
    let msg = std::format!(
        "{}",
        GridError::NotIncreasing {
            axis: Axis::Theta,
            index: 3
        }
    );
    assert!(msg.contains("theta[3]"));
}

#[test]
fn size_of_the_serial_iterator() {
    let s64 = core::mem::size_of::<SerialMarch<'static, f64>>();
    let s32 = core::mem::size_of::<SerialMarch<'static, f32>>();
    std::println!("size_of SerialMarch: f64 {s64} bytes, f32 {s32} bytes");
    // measured: 480 and 288 (the ray's line in the grid's frame is 112 bytes of it in f64, the radius stream's
    // line 64, each stream 40, the zenith stream's kept second roots 88); the design goal of 192 and 128 is not
    // reached: what a march must carry is about 170 and 110 bytes, the rest saves work per crossing (docs/performance.md's
    // "How far the targets are")
    assert!(s64 <= 480 && s32 <= 288, "{s64} {s32}");
}

#[test]
fn tiny_direction_whose_t_overflows_is_an_error_not_a_miss() {
    // The line along +x from (-3, 0.1, 0.2) crosses the unit ball, but at t ≈ 2.2e308 and beyond: not finite.
    let ray = Ray::new([-3.0, 0.1, 0.2], [1e-308, 0.0, 0.0]).unwrap();
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws).unwrap();
    let mut m = g.march(&ray);
    let got: Vec<_> = m.by_ref().collect();
    assert_eq!(
        (got.as_slice(), m.error()),
        (&[][..], Some(MarchError::Unrepresentable))
    );
    assert_eq!(
        g.march_separable::<32>(&ray).err(),
        Some(MarchError::Unrepresentable)
    );
}

#[test]
fn vertical_tiny_direction_in_a_cylinder_stops_with_an_error_at_the_first_unrepresentable_t() {
    // A vertical line inside the cylinder (its radius never changes): z = 0 at t = 5e307, z = 4 at t = 4.5e308,
    // beyond the largest f64. The first crossing is correct and finite; the second cannot be expressed, whether
    // z = 4 is where the line leaves the domain or a boundary between two cells inside it.
    for z in [&[-1.0, 0.0, 4.0][..], &[-1.0, 0.0, 4.0, 5.0]] {
        let (rho, phi) = ([0.0, 1.0, 2.0], [0.0, PI, 2.0 * PI]);
        let mut ws = [0.0; 64];
        let g = CylindricalGrid::new(&rho, &phi, z, &mut ws).unwrap();
        let ray = Ray::new([0.5, 0.5, -0.5], [0.0, 0.0, 1e-308]).unwrap();
        let mut m = g.march(&ray);
        let serial: Vec<_> = m.by_ref().collect();
        assert_eq!(m.error(), Some(MarchError::Unrepresentable), "{z:?}");
        let mut s = g.march_separable::<32>(&ray).unwrap();
        let separable: Vec<_> = s.by_ref().collect();
        assert_eq!(s.error(), Some(MarchError::Unrepresentable));
        assert_eq!(serial, separable);
        assert_eq!(
            serial,
            [CellCrossing {
                cell: [0, 0, 0],
                t_enter: 0.0,
                t_exit: 0.5 / 1e-308
            }],
            "{z:?}"
        );
    }
}

/// A unit-sized direction (`s = t`, so the emitter does not test `t`) nearly parallel to the azimuth boundary
/// φ = 0, whose crossing of it lies at t ≈ 1e309 (not finite): that event comes after the ray leaves the outer
/// radius, which ends the march, so every crossing is finite and none is lost (both engines).
#[test]
fn unit_direction_whose_far_azimuth_crossing_overflows_gives_finite_crossings() {
    let ph = [0.0, PI / 2.0, PI, 1.5 * PI, 2.0 * PI];
    let ray = Ray::new([-2.0, 0.1, 0.3], [1.0, -1e-310, 0.0]).unwrap();
    let got = march_s(&R, &TH, &ph, &ray);
    let cells: Vec<_> = got.iter().map(|c| c.cell).collect();
    // outer shell, inner ball, outer shell in the upper half; φ from just below π to π/2 and on toward 0
    assert_eq!(
        cells,
        [[1, 0, 1], [0, 0, 1], [0, 0, 0], [1, 0, 0]],
        "{got:?}"
    );
    assert!(
        got.iter()
            .all(|c| c.t_enter.is_finite() && c.t_exit.is_finite())
    );
    let exit = 2.0 + (1.0f64 - 0.01 - 0.09).sqrt();
    assert!((got[3].t_exit - exit).abs() < 1e-15, "{got:?}");
}

#[test]
fn tiny_direction_from_inside_the_ball_is_an_error() {
    // Starts inside the inner ball; it leaves that at t ≈ 1e308 (finite) and the outer ball at t ≈ 2.2e308
    // (not): the march is refused as a whole (the outer ball's exit is checked when the march starts).
    let ray = Ray::new([0.1, 0.1, 0.1], [4e-309, 0.0, 0.0]).unwrap();
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws).unwrap();
    let mut m = g.march(&ray);
    assert_eq!(m.by_ref().count(), 0);
    assert_eq!(m.error(), Some(MarchError::Unrepresentable));
    assert_eq!(
        g.march_separable::<32>(&ray).err(),
        Some(MarchError::Unrepresentable)
    );
}

#[test]
fn subnormal_direction_with_representable_t_marches_exactly_like_a_unit_one() {
    // A grid 2^-53 the size of the unit one and a direction 2^-1030 (components subnormal, all exact): every t is
    // the unit march's t times 2^977, bit for bit, and the cells are the same.
    // (powers of two from their bits: `powi` need not be exact, and under Miri it is not)
    let small =
        |v: &[f64]| -> Vec<f64> { v.iter().map(|x| x * f64::from_bits(970 << 52)).collect() };
    let (o, d) = ([-1.5, -0.25, -0.125], [1.0, 0.125, 0.09375]);
    let base = march_s(&R, &TH, &PH, &Ray::new(o, d).unwrap());
    assert!(base.len() >= 5, "{base:?}");
    let tiny = Ray::new(
        o.map(|x| x * f64::from_bits(970 << 52)), // 2^-53
        d.map(|x| x * f64::from_bits(1 << 44)),   // 2^-1030
    )
    .unwrap();
    assert!(tiny.dir().x < f64::MIN_POSITIVE);
    let c = march_s(&small(&R), &TH, &PH, &tiny);
    let k = f64::from_bits(2000 << 52); // 2^977
    let scaled: Vec<_> = base
        .iter()
        .map(|b| CellCrossing {
            cell: b.cell,
            t_enter: b.t_enter * k,
            t_exit: b.t_exit * k,
        })
        .collect();
    assert_eq!(c, scaled);
}

#[test]
fn ray_near_the_minus_z_axis_inside_a_cone_five_nanoradians_from_the_pole() {
    // cos²(π − 5e-9) rounds to 1: only sin² tells this cone from the −z axis. The ray starts at θ = π − 1e-8,
    // outside the narrow cone, and enters it where ρ / |z| = tan 5e-9, at z = −1.
    let th = [0.0, PI / 2.0, PI - 5e-9, PI];
    let ray = Ray::new([0.5e-8, 0.0, -0.5], [0.0, 0.0, -1.0]).unwrap();
    let c = march_s(&[0.0, 2.0], &th, &PH, &ray);
    // the f64 breakpoint is not π − 5e-9 to all digits (π itself rounds): the crossing where ρ / |z| = tan θ_2
    let z = 0.5e-8 * -th[2].cos() / th[2].sin();
    let out = (4.0f64 - 0.25e-16).sqrt() - 0.5;
    expect(
        &c,
        &[([0, 1, 0], 0.0, z - 0.5), ([0, 2, 0], z - 0.5, out)],
        1e-12,
    );
}

#[test]
fn ray_starting_inside_a_cone_five_nanoradians_from_the_plus_z_pole() {
    // the mirror image at the +z pole: θ = 2e-9 at the start, inside the cone θ = 5e-9 down to z = 0.4, then
    // across the plane z = 0 and out through the sphere r = 2 below it
    let th = [0.0, 5e-9, PI / 2.0, PI];
    let ray = Ray::new([0.2e-8, 0.0, 1.0], [0.0, 0.0, -1.0]).unwrap();
    let c = march_s(&[0.0, 2.0], &th, &PH, &ray);
    let z = 0.2e-8 * th[1].cos() / th[1].sin();
    expect(
        &c,
        &[
            ([0, 0, 0], 0.0, 1.0 - z),
            ([0, 1, 0], 1.0 - z, 1.0),
            ([0, 2, 0], 1.0, 3.0),
        ],
        1e-12,
    );
}

#[test]
fn ray_entering_the_ball_just_outside_a_cone_five_nanoradians_from_the_minus_z_pole() {
    // from far below along +z at ρ = 1.02e-8 (direction a hair off the axis): the cone θ = π − 5e-9 meets this
    // line at |z| ≈ 2.04, outside the ball of radius 2, so the whole chord inside is outside the cone
    let th = [0.0, PI / 2.0, PI - 5e-9, PI];
    let ray = Ray::new([1.02e-8, 0.0, -10.0], [1e-19, 0.0, 1.0]).unwrap();
    let c = march_s(&[0.0, 2.0], &th, &PH, &ray);
    expect(
        &c,
        &[([0, 1, 0], 8.0, 10.0), ([0, 0, 0], 10.0, 12.0)],
        1e-12,
    );
}

#[test]
fn sector_lookup_with_the_half_turn_split_matches_testing_each_boundary() {
    use super::axes::AzimuthAxis;
    // a full turn, a wedge across φ = 0, and breakpoints within rounding of φ_0 + π (where the split is decided
    // by the same sign test as each boundary's own)
    let full: Vec<f64> = (0..=64).map(|i| f64::from(i) * (2.0 * PI / 64.0)).collect();
    let wedge: Vec<f64> = (0..=64)
        .map(|i| -1.0 + f64::from(i) * (5.0 / 64.0))
        .collect();
    let ulps = |k: i64| f64::from_bits((0.25 + PI).to_bits().wrapping_add_signed(k));
    let near_pi = [0.25, ulps(-2), ulps(-1), ulps(0), ulps(1), ulps(2), 5.5];
    for phi in [&full[..], &wedge[..], &near_pi[..]] {
        let mut buf = [0.0; 2 * 65];
        let mut ws = &mut buf[..];
        let axis = AzimuthAxis::build(phi, &mut ws).unwrap();
        let plain = axis.without_half_split();
        // directions all round, each boundary's own direction and its neighbours, and the zero vector
        // (fewer under Miri, whose interpreter is slow)
        let (n, near) = if cfg!(miri) { (64, 1) } else { (4096, 3) };
        let mut dirs: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let a = f64::from(i) * (2.0 * PI / f64::from(n));
                (a.cos(), a.sin())
            })
            .collect();
        for &p in phi.iter().chain([phi[0] + PI].iter()) {
            for k in -near..=near {
                let a = f64::from_bits(p.to_bits().wrapping_add_signed(k));
                dirs.push((a.cos(), a.sin()));
                dirs.push((a.cos() * 1e-300, a.sin() * 1e-300));
            }
        }
        dirs.push((0.0, 0.0));
        for (x, y) in dirs {
            assert_eq!(
                axis.sector_of(x, y),
                plain.sector_of(x, y),
                "{phi:?} at ({x}, {y})"
            );
        }
    }
}

/// 65 zenith breakpoints, uniform in [0, π]: 64 cones.
fn sixty_four_cones() -> Vec<f64> {
    (0..=64).map(|i| f64::from(i) * (PI / 64.0)).collect()
}

/// The zenith axis of `theta` in `buf` (two values per breakpoint), with a unit length scale.
fn zenith_axis<'a>(theta: &'a [f64], buf: &'a mut [f64]) -> super::axes::ZenithAxis<'a, f64> {
    let mut ws = buf;
    let mut axis = super::axes::ZenithAxis::build(theta, &mut ws).unwrap();
    axis.scale = 1.0;
    axis
}

#[test]
fn kept_second_roots_of_cones_give_the_same_zenith_events_as_solving_each_cone_again() {
    use super::stream::{SecondRoots, Stream};
    // 64 cones; lines passing the z axis at small distances, so that θ turns and many cones are crossed twice
    let theta = sixty_four_cones();
    let mut buf = [0.0; 2 * 65];
    let axis = zenith_axis(&theta, &mut buf);
    let mut unit = crate::test_util::xorshift_uniform(0x2545_f491_4f6c_dd1d);
    let mut uniform = move || unit() * 2.0 - 1.0;
    let rays = if cfg!(miri) { 8 } else { 400 };
    let mut most_kept = 0;
    for _ in 0..rays {
        let near = 10f64.powf(-6.0 * uniform().abs());
        let origin = [-2.0, near * uniform(), 2.0 * uniform()];
        let dir = [1.0, 0.3 * uniform(), 0.5 * uniform()];
        let ray = Ray::new(origin, dir).unwrap();
        let (mut kept, _) = Stream::zenith(&axis, ray.line(), 0.0);
        let mut solved = kept;
        let mut roots = SecondRoots::EMPTY;
        for _ in 0..300 {
            let a = kept.next_zenith(&axis, ray.line(), f64::INFINITY, &mut roots);
            // a new, empty stack for each step of this one: every cone is solved
            let mut none_kept = SecondRoots::EMPTY;
            let b = solved.next_zenith(&axis, ray.line(), f64::INFINITY, &mut none_kept);
            assert_eq!(a, b, "{ray:?}");
            assert_eq!(
                (kept.t.to_bits(), kept.band),
                (solved.t.to_bits(), solved.band),
                "{ray:?}"
            );
            most_kept = most_kept.max(roots.kept());
            if !a {
                break;
            }
        }
    }
    // the stack was used, up to its capacity
    assert_eq!(most_kept, 8);
}

#[test]
fn zenith_stream_past_its_event_bound_stops_the_march_with_an_iteration_bound_error() {
    use super::stream::{SecondRoots, Stream, zenith_event_bound};
    // a line that crosses 20 cones of 64: the stream's own bound is far from reached
    let theta = sixty_four_cones();
    let mut buf = [0.0; 2 * 65];
    let axis = zenith_axis(&theta, &mut buf);
    let ray = Ray::new([-2.0, 0.1, 0.3], [1.0, 0.0, 0.0]).unwrap();
    let run = |s: &mut Stream<f64>| {
        let mut roots = SecondRoots::EMPTY;
        let mut n = 0u32;
        while s.next_zenith(&axis, ray.line(), f64::INFINITY, &mut roots) {
            n += 1;
            assert!(n <= 1000);
        }
        n
    };
    let (start, _) = Stream::zenith(&axis, ray.line(), 0.0);
    let mut whole = start;
    let events = run(&mut whole);
    assert!(events >= 10 && events < zenith_event_bound(65), "{events}");
    assert!(!whole.overran());
    // with 3 events left: 3 events, then an overrun
    let mut cut = start.with_events_left(3);
    assert_eq!(run(&mut cut), 3);
    assert!(cut.overran());

    // in the serial engine: the crossings before the overrun are the whole march's first ones, then the error
    let (r, th, ph) = (
        [0.0, 0.5, 1.0],
        theta.clone(),
        [0.0, PI / 2.0, PI, 1.5 * PI, 2.0 * PI],
    );
    let mut ws = std::vec![0.0; SphericalGrid::<f64>::workspace_len(3, 65, 5)];
    let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let whole: Vec<_> = grid.march(&ray).collect();
    let mut march = grid.march(&ray).with_zenith_events_left(2);
    let cut: Vec<_> = march.by_ref().collect();
    assert_eq!(march.error(), Some(MarchError::IterationBound));
    assert!(
        cut.len() >= 2 && cut.len() < whole.len(),
        "{} {}",
        cut.len(),
        whole.len()
    );
    assert_eq!(cut[..], whole[..cut.len()]);
    let mut full = grid.march(&ray);
    assert_eq!(full.by_ref().count(), whole.len());
    assert_eq!(full.error(), None);
}

/// A direction of unit size (largest component in [1/2, 2)) is kept as given (`s = t`), any other is scaled by
/// a power of two: the solvers' expressions are homogeneous in the direction, so a march along `d · 2^k` must
/// give the cells of the march along `d` and its `t` divided by `2^k`, bit for bit, whichever way each ray was
/// scaled (both engines, on a grid with a shell, both poles, cones near the pole and a wedge across φ = 0).
#[test]
fn unit_sized_direction_kept_as_given_marches_like_its_power_of_two_multiples() {
    let r = [0.2, 0.35, 0.5, 0.8, 1.0];
    let th = [0.0, 1e-3, 0.9, PI / 2.0, 2.0, PI];
    let ph = [-0.5, 0.7, 2.0, 3.5];
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let march = |ray: &Ray<f64>| -> Vec<CellCrossing<f64>> {
        let mut m = g.march(ray);
        let a: Vec<_> = m.by_ref().collect();
        assert_eq!(m.error(), None);
        let b: Vec<_> = g.march_separable::<64>(ray).unwrap().collect();
        assert_eq!(a, b, "serial and separable differ");
        a
    };
    let mut unit = crate::test_util::xorshift_uniform(0x5ca1_ab1e);
    let mut v = move || unit() * 4.0 - 2.0;
    // 2^k exactly (`powi` need not be exact, and under Miri it is not)
    let pow2 = |k: i32| f64::from_bits(u64::try_from(1023 + k).unwrap() << 52);
    let rays = if cfg!(miri) { 10 } else { 2_000 };
    let mut compared = 0;
    for i in 0..rays {
        let o = [v(), v(), v()];
        // toward a point near the center (most rays cross the grid), at unit size
        let to = [v() * 0.3, v() * 0.3, v() * 0.3];
        let d = [to[0] - o[0], to[1] - o[1], to[2] - o[2]];
        let n = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        let d = d.map(|x| x / n * [1.0, 0.9, 1.9][i % 3]);
        let base_ray = Ray::new(o, d).unwrap();
        assert_eq!(base_ray.scale_exponent(), 0);
        let base = march(&base_ray);
        for k in [-40, -2, 2, 40] {
            let ray = Ray::new(o, d.map(|x| x * pow2(k))).unwrap();
            assert_ne!(ray.scale_exponent(), 0);
            let scaled: Vec<_> = march(&ray)
                .into_iter()
                .map(|c| CellCrossing {
                    cell: c.cell,
                    t_enter: c.t_enter * pow2(k),
                    t_exit: c.t_exit * pow2(k),
                })
                .collect();
            assert_eq!(scaled, base, "ray {i}, k = {k}");
            compared += base.len();
        }
    }
    assert!(compared > rays * 10, "{compared}");
}
