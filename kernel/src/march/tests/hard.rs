//! Rays through the hard places of a grid: the center, the z axis, tangents, edges and corners, starting on
//! boundaries, huge and tiny scales.

use super::*;
use crate::ray::Ray;
use core::f64::consts::PI;
use std::vec::Vec;

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

/// A cone `θ0` (the first of 0.6, 0.61, … that has one) and a height `z0` for which the horizontal line `x = 1`,
/// `z = z0` along `+y` touches it exactly at `y = 0`: `sin²θ0 · z0² = cos²θ0`, so that the cone solver's
/// discriminant `s²(w_x² + w_y²) − c² w_z²`, with `w = p × d = (−z0, 0, 1)`, is exactly 0 (for about half of all
/// `θ0` one of the floats next to `cot θ0` is such a `z0`).
fn cone_touched_at_y0() -> (f64, f64) {
    let tangent = |theta0: f64| {
        let cone = crate::surface::AxialCone::from_zenith_rad(0.0, theta0).ok()?;
        let (c2, s2) = (cone.cos() * cone.cos(), cone.sin() * cone.sin());
        let z = cone.cos() / cone.sin();
        [
            z.next_down().next_down(),
            z.next_down(),
            z,
            z.next_up(),
            z.next_up().next_up(),
        ]
        .into_iter()
        .find(|&z0| s2 * (z0 * z0) == c2)
        .map(|z0| (theta0, z0))
    };
    (0..32)
        .find_map(|k| tangent(0.6 + 0.01 * f64::from(k)))
        .unwrap()
}

#[test]
fn ray_touching_the_cone_of_a_zenith_domain_from_inside_is_one_crossing() {
    // The domain is θ >= θ0 (outside the cone θ0, about 0.6) within r < 4. The horizontal line x = 1, z = z0,
    // along +y, has its smallest θ where y = 0 (t = 2), and there it touches that cone from the domain's side
    // (`cone_touched_at_y0`). The ray leaves the domain for no length at t = 2 and comes back into the same cell
    // at the same t: one crossing from its start inside the ball, not two.
    let (theta0, z0) = cone_touched_at_y0();
    let (r, th, ph) = ([0.0, 4.0], [theta0, PI], [-1.0, 2.0 * PI - 1.0]);
    let ray = Ray::new([1.0, -2.0, z0], [0.0, 1.0, 0.0]).unwrap();
    let h = (15.0 - z0 * z0).sqrt();
    let got = march_s(&r, &th, &ph, &ray);
    expect(&got, &[([0, 0, 0], 0.0, 2.0 + h)], 1e-15);
}

#[test]
fn ray_touching_the_cone_of_a_zenith_domain_on_an_azimuth_plane_changes_cell_there() {
    // As above, with a φ breakpoint at 0: where the ray touches the cone (t = 2, y = 0) it also crosses the plane
    // φ = 0. It leaves the domain for no length and comes back at the same t into the next φ cell: the crossing
    // of φ cell 0 ends at t = 2 and the next one starts there (before, the ray crosses φ = −1 where
    // y = tan(−1), from cell 1, which wraps round from 0 to 2π − 1).
    let (theta0, z0) = cone_touched_at_y0();
    let (r, th, ph) = ([0.0, 4.0], [theta0, PI], [-1.0, 0.0, 2.0 * PI - 1.0]);
    let ray = Ray::new([1.0, -2.0, z0], [0.0, 1.0, 0.0]).unwrap();
    let h = (15.0 - z0 * z0).sqrt();
    // tan(−1) correctly rounded, as a literal: under Miri the host's `tan` carries a random error of a few ulps,
    // enough to move the expected value past this test's 1e-15.
    let tan_minus_1 = -1.557_407_724_654_902_3_f64;
    let got = march_s(&r, &th, &ph, &ray);
    expect(
        &got,
        &[
            ([0, 0, 1], 0.0, 2.0 + tan_minus_1),
            ([0, 0, 0], 2.0 + tan_minus_1, 2.0),
            ([0, 0, 1], 2.0, 2.0 + h),
        ],
        1e-15,
    );
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

/// A fuzzer's case: a ray starting a subnormal distance (5e-324) above the plane of a zenith breakpoint within
/// 8 ε of π/2 (taken as the plane z = 0), going up. Locating the start by signs once scaled the point to unit
/// size, which rounded that height to 0 and put the start on the plane, in the band below it, while the cone
/// solver saw the plane crossed before the start: the march stayed in the band below until a topology repair
/// at the closest approach to the center. The crossings must be those from 1e-300 above.
#[test]
fn ray_starting_a_subnormal_above_the_equatorial_plane_going_up_stays_above_it() {
    let r = [0.0, 2.0];
    let ph = [-1.0, 0.2566366120274832, 5.283185307179586];
    // the breakpoint 3 ulps above π/2, and π/2 itself
    for th_eq in [1.5707963267948972, PI / 2.0] {
        let th = [0.0, 0.9436320296295498, th_eq, PI];
        let from = |z: f64| {
            let ray = Ray::new([-2.0, 0.0, z], [0.1, 0.0, 0.2]).unwrap();
            march_s(&r, &th, &ph, &ray)
        };
        let (tiny, clear) = (from(5e-324), from(1e-300));
        assert_eq!(tiny, clear, "θ = {th_eq}");
        let cells: Vec<_> = tiny.iter().map(|c| c.cell).collect();
        assert_eq!(cells, [[0, 1, 1], [0, 0, 1]], "θ = {th_eq}");
    }
}

/// The same for the azimuth: a ray starting a subnormal distance (−5e-324) below the half-plane φ = 0 (so at
/// φ = 2π less a subnormal angle) is in the last sector; going away from the half-plane it stays there, going
/// towards it it crosses into sector 0 at once (t = 2.5e-323). Scaled to unit size, the start had y = 0 and
/// was located in sector 0, where the half-plane solver saw it in the last one.
#[test]
fn ray_starting_a_subnormal_below_the_azimuth_zero_half_plane_is_in_the_last_sector() {
    let (r, th, ph) = ([0.0, 3.0], [0.0, PI / 2.0, PI], [0.0, PI, 2.0 * PI]);
    let away = Ray::new([2.0, -5e-324, 0.3], [-0.1, -0.2, 0.0]).unwrap();
    let out = 14.686440005914033;
    expect(
        &march_s(&r, &th, &ph, &away),
        &[([0, 0, 1], 0.0, out)],
        1e-15,
    );
    let towards = Ray::new([2.0, -5e-324, 0.3], [-0.1, 0.2, 0.0]).unwrap();
    let c = march_s(&r, &th, &ph, &towards);
    let cells: Vec<_> = c.iter().map(|c| c.cell).collect();
    assert_eq!(cells, [[0, 0, 1], [0, 0, 0]]);
    assert_eq!(
        (c[0].t_enter, c[0].t_exit, c[1].t_enter),
        (0.0, 2.5e-323, 2.5e-323)
    );
    assert!((c[1].t_exit - out).abs() < 1e-14);
}

#[test]
fn ray_starting_exactly_at_the_center_starts_in_the_cells_of_its_direction() {
    // From the origin along (1, 0.5, −0.25): θ and φ are those of the direction from t = 0 on, no walk of zero
    // length from the cells of −d.
    let ray = Ray::new([0.0, 0.0, 0.0], [1.0, 0.5, -0.25]).unwrap();
    let n = (1.0f64 + 0.25 + 0.0625).sqrt();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[([0, 1, 0], 0.0, 0.5 / n), ([1, 1, 0], 0.5 / n, 1.0 / n)],
        1e-15,
    );
}

#[test]
fn ray_through_the_center_within_rounding_walks_there_like_an_exact_one() {
    // p = −3 d with d = (0.3, 0.1, 0.7), each rounded: p × d (of the direction scaled to (0.6, 0.2, 1.4)) is a
    // rounding residue (about 6e-17), not 0. The line is taken as passing through the center (θ from that of −d
    // to that of d, φ by π) at t = 3.
    let theta = [0.0, 0.5, 1.0, PI / 2.0, 2.0, PI];
    let ray = Ray::new([-0.9, -0.3, -2.1], [0.3, 0.1, 0.7]).unwrap();
    let w = ray.line().p_cross_d();
    assert!(w != crate::vec3::V3::new(0.0, 0.0, 0.0), "{w:?}");
    let n = (0.09f64 + 0.01 + 0.49).sqrt();
    let c = march_s(&R, &theta, &PH, &ray);
    let got: Vec<_> = c.iter().map(|x| x.cell).collect();
    // −d is at θ ≈ 2.72 (band 4), d at θ ≈ 0.42 (band 0): the zenith walk passes bands 3, 2 and 1 at t = 3
    assert_eq!(
        got,
        [
            [1, 4, 1],
            [0, 4, 1],
            [0, 3, 1],
            [0, 2, 1],
            [0, 1, 1],
            [0, 0, 1],
            [0, 0, 0],
            [1, 0, 0]
        ],
        "{c:?}"
    );
    let at = |r: f64| r / n;
    expect(
        &c[..2],
        &[
            ([1, 4, 1], 3.0 - at(1.0), 3.0 - at(0.5)),
            ([0, 4, 1], 3.0 - at(0.5), 3.0),
        ],
        1e-15,
    );
}

/// A skew line below the equator, `z = −1`, `y = 1`, along x: θ rises from 101.1° across the cones of 120° and
/// 130° to its largest, 135°, where it passes closest to the z axis, and comes back down across them in the
/// reverse order. At the start θ is rising (⟨p|v⟩ < 0) while the turn lies ahead (⟨d|v⟩ > 0): the stream must
/// search upward first.
#[test]
fn skew_line_below_the_equator_whose_zenith_rises_across_two_cones_turns_and_comes_back() {
    let th: std::vec::Vec<f64> = [0.0, 100.0, 120.0, 130.0, 180.0]
        .iter()
        .map(|d| d * PI / 180.0)
        .collect();
    let ray = Ray::new([-5.0, 1.0, -1.0], [1.0, 0.0, 0.0])
        .unwrap()
        .with_interval(0.0, 10.0)
        .unwrap();
    let got = march_s(&[0.0, 10.0], &th, &[0.0, 2.0 * PI], &ray);
    // (t − 5)² = tan²(180° − θ) − 1 on the cone of zenith angle θ.
    let at = |deg: f64| {
        let tan = libm::tan((180.0 - deg) * PI / 180.0);
        (tan * tan - 1.0).sqrt()
    };
    let (a, b) = (at(120.0), at(130.0));
    expect(
        &got,
        &[
            ([0, 1, 0], 0.0, 5.0 - a),
            ([0, 2, 0], 5.0 - a, 5.0 - b),
            ([0, 3, 0], 5.0 - b, 5.0 + b),
            ([0, 2, 0], 5.0 + b, 5.0 + a),
            ([0, 1, 0], 5.0 + a, 10.0),
        ],
        1e-14,
    );
}

/// Segments ending exactly on a boundary: on the sphere of radius 1.25 (`(0, 0.75, 0)` along x, `t_max = 1`, all
/// exact in binary) and on the plane θ = π/2 (`z` from 0.5 down to 0). The end point belongs to the cell beyond
/// (cells are half-open: a point on a sphere is in the outer band, on a cone in the band of larger θ), so the
/// march ends with a zero-length crossing of that cell at `t_max`.
#[test]
fn segment_ending_exactly_on_a_sphere_or_the_equator_plane_ends_in_the_cell_beyond_with_zero_length()
 {
    let ray = Ray::new([0.0, 0.75, 0.0], [1.0, 0.0, 0.0])
        .unwrap()
        .with_interval(0.0, 1.0)
        .unwrap();
    let got = march_s(&[0.0, 0.5, 1.25, 2.0], &[0.0, PI], &[0.0, 2.0 * PI], &ray);
    expect(&got, &[([1, 0, 0], 0.0, 1.0), ([2, 0, 0], 1.0, 1.0)], 0.0);
    let ray = Ray::new([0.3, 0.0, 0.5], [0.0, 0.0, -1.0])
        .unwrap()
        .with_interval(0.0, 0.5)
        .unwrap();
    let got = march_s(&[0.0, 2.0], &[0.0, PI / 2.0, PI], &[0.0, 2.0 * PI], &ray);
    expect(&got, &[([0, 0, 0], 0.0, 0.5), ([0, 1, 0], 0.5, 0.5)], 0.0);
}

/// The cone of zenith angle `theta` as the grid stores it: `(sin θ, cos θ)`.
fn cone_pair(theta: f64) -> (f64, f64) {
    let cone = crate::surface::AxialCone::from_zenith_rad(0.0, theta).unwrap();
    (cone.sin(), cone.cos())
}

/// Cones at 0.5, 1, 2 and 2.5 rad, radii 0.5 and 2, one φ cell.
const TOUCH_TH: [f64; 6] = [0.0, 0.5, 1.0, 2.0, 2.5, PI];
const TOUCH_R: [f64; 3] = [0.0, 0.5, 2.0];
const ONE_PHI: [f64; 2] = [0.0, 2.0 * PI];

#[test]
fn ray_starting_on_a_cone_above_the_equator_tangent_to_it_stays_in_the_band_above() {
    // From (sin 1, 0, cos 1) along ±y: θ is smallest at the start, on the cone θ = 1, and rises (the line lies
    // in θ ≥ 1). The point of contact belongs to the band above the cone, so the ray never leaves that band:
    // one crossing, not a zero-length visit to the band below and back.
    let (s, c) = cone_pair(1.0);
    for dy in [1.0, -1.0] {
        let ray = Ray::new([s, 0.0, c], [0.0, dy, 0.0]).unwrap();
        let got = march_s(&TOUCH_R, &TOUCH_TH, &ONE_PHI, &ray);
        expect(&got, &[([1, 2, 0], 0.0, 3f64.sqrt())], 1e-15);
    }
}

#[test]
fn ray_starting_on_a_cone_below_the_equator_tangent_to_it_leaves_its_band_once() {
    // From (sin 2, 0, cos 2) along ±y: θ is largest at the start, on the cone θ = 2, and falls. The start
    // belongs to the band above the cone (θ ≥ 2): a zero-length crossing there, then the band below, once.
    let (s, c) = cone_pair(2.0);
    for dy in [1.0, -1.0] {
        let ray = Ray::new([s, 0.0, c], [0.0, dy, 0.0]).unwrap();
        let got = march_s(&TOUCH_R, &TOUCH_TH, &ONE_PHI, &ray);
        expect(
            &got,
            &[([1, 3, 0], 0.0, 0.0), ([1, 2, 0], 0.0, 3f64.sqrt())],
            1e-15,
        );
    }
}

#[test]
fn ray_touching_a_cone_above_the_equator_between_two_bands_crosses_nothing_there() {
    // From (sin 1, −1, cos 1) along +y: θ falls to 1 at t = 1, touching the cone θ = 1 from the band above it,
    // which owns the point of contact, and rises again: one crossing, as for a touch of a sphere.
    let (s, c) = cone_pair(1.0);
    let ray = Ray::new([s, -1.0, c], [0.0, 1.0, 0.0]).unwrap();
    let got = march_s(&TOUCH_R, &TOUCH_TH, &ONE_PHI, &ray);
    expect(&got, &[([1, 2, 0], 0.0, 1.0 + 3f64.sqrt())], 1e-15);
}

#[test]
fn ray_touching_a_cone_below_the_equator_between_two_bands_visits_the_band_above_for_no_length() {
    // From (sin 2, −1, cos 2) along +y: θ rises to 2 at t = 1, touching the cone θ = 2 from the band below it.
    // The point of contact belongs to the band above: a zero-length crossing of it at t = 1.
    let (s, c) = cone_pair(2.0);
    let ray = Ray::new([s, -1.0, c], [0.0, 1.0, 0.0]).unwrap();
    let got = march_s(&TOUCH_R, &TOUCH_TH, &ONE_PHI, &ray);
    let end = 1.0 + 3f64.sqrt();
    expect(
        &got,
        &[
            ([1, 2, 0], 0.0, 1.0),
            ([1, 3, 0], 1.0, 1.0),
            ([1, 2, 0], 1.0, end),
        ],
        1e-15,
    );
}

#[test]
fn ray_starting_on_a_zenith_domains_last_cone_tangent_to_it_outside_the_domain_crosses_nothing() {
    // A domain of θ in [0.5, 1): from (sin 1, 0, cos 1) along ±y, θ rises from 1, so no point of the ray lies in
    // the domain (the start, at θ = 1, is outside it). From the first cone's point instead, θ rises from 0.5
    // through the domain until it reaches 1, where cos θ = cos 1: at t² = (cos 0.5 / cos 1)² − 1.
    let th = [0.5, 1.0];
    let (s1, c1) = cone_pair(1.0);
    let (s0, c0) = cone_pair(0.5);
    let leave = ((c0 / c1) * (c0 / c1) - 1.0).sqrt();
    for dy in [1.0, -1.0] {
        let outside = Ray::new([s1, 0.0, c1], [0.0, dy, 0.0]).unwrap();
        assert_eq!(march_s(&TOUCH_R, &th, &ONE_PHI, &outside), []);
        let inside = Ray::new([s0, 0.0, c0], [0.0, dy, 0.0]).unwrap();
        let got = march_s(&TOUCH_R, &th, &ONE_PHI, &inside);
        expect(&got, &[([1, 0, 0], 0.0, leave)], 1e-14);
    }
}

/// The parameter where the ray leaves the sphere of radius `r` about the origin (the larger root).
fn sphere_exit(ray: &Ray<f64>, r: f64) -> f64 {
    let (o, d) = (ray.origin(), ray.dir());
    let (a, b) = (d.dot(d), o.dot(d));
    (-b + (b * b - a * (o.dot(o) - r * r)).sqrt()) / a
}

#[test]
fn ray_starting_at_thetas_turn_just_inside_a_zenith_domains_first_cone_is_inside_from_its_start() {
    // A domain of θ in [0.234, 2.213). The ray starts at θ's turn on the cone 0.234, within rounding of it (a
    // start made in double precision from sin and cos of 0.234), and θ rises from there: the ray is inside from
    // t = 0 (by a 200-bit evaluation along it). The band test puts the start just outside, and no root of that
    // cone lies past it: the repair toward the band of the direction is made where the stream stands on the
    // cone within rounding, at the start. (It used to be made at the closest approach to the center,
    // t = 0.079.)
    let ray = Ray::new(
        [
            -0.189_571_444_826_286_82,
            -0.155_424_122_683_362_45,
            1.028_418_927_211_274_7,
        ],
        [
            0.647_484_861_056_789_4,
            -0.762_277_200_409_813_5,
            -0.073_046_873_852_698_69,
        ],
    )
    .unwrap();
    let got = march_s(&[0.0, 2.87], &[0.234, 2.213], &ONE_PHI, &ray);
    expect(&got, &[([0, 0, 0], 0.0, sphere_exit(&ray, 2.87))], 1e-15);
}

#[test]
fn ray_starting_at_thetas_turn_within_rounding_of_a_cone_below_the_equator_leaves_its_band_at_the_start()
 {
    // Cones at 1.584, 1.604 and 2.816. The ray starts at θ's turn 2e-18 rad above the cone 1.604 (by a 200-bit
    // evaluation), in the band above it, and θ falls from there: it is in the band below from t ≈ 1e-8 until θ
    // reaches 1.584 at t = 1.49834681648918. The solver sees no root of that cone (its discriminant rounds
    // below 0), so the stream has no crossing to take; the repair that moves it a band toward the band of the
    // direction is made where it stands on the cone, at the start (it used to be made at the closest approach
    // to the center, t = 1.089, so the ray was in the wrong band up to there).
    let ray = Ray::new(
        [
            -1.720_542_736_172_401_5,
            -1.335_380_725_780_967,
            -0.072_342_853_775_578_68,
        ],
        [
            1.419_178_687_843_992_5,
            -0.164_376_013_847_288_17,
            0.033_891_392_589_579_03,
        ],
    )
    .unwrap();
    let got = march_s(&[0.0, 2.61], &[1.584, 1.604, 2.816], &ONE_PHI, &ray);
    expect(
        &got,
        &[
            ([0, 1, 0], 0.0, 0.0),
            ([0, 0, 0], 0.0, 1.498_346_816_489_18),
        ],
        1e-15,
    );
}

#[test]
fn ray_starting_within_rounding_inside_the_outer_sphere_on_a_tangent_line_leaves_at_once() {
    // A shell of radii 1.16 and 2.07. The start is 3e-17 inside the outer sphere, at the line's closest
    // approach to the center (a tangent made in double precision), so the ray leaves the grid within 1e-8 (by a
    // 200-bit evaluation). The sphere's discriminant rounds to 0 and ⟨p|d⟩ to 6e-17: the stable formula's
    // other root, (‖p‖² − R²)/q, divided a rounding residue by that and put the exit at t = 16, far outside.
    let ray = Ray::new(
        [
            -0.495_461_563_738_870_46,
            -1.022_644_868_616_464,
            1.730_206_725_090_920_3,
        ],
        [
            -1.102_488_796_872_608_7,
            0.101_684_370_644_019_72,
            -0.255_607_504_601_652_3,
        ],
    )
    .unwrap();
    let got = march_s(&[1.16, 2.07], &[0.0, PI], &ONE_PHI, &ray);
    expect(&got, &[([0, 0, 0], 0.0, 0.0)], 0.0);
}

#[test]
fn ray_starting_within_rounding_inside_a_shells_inner_sphere_on_a_tangent_line_enters_the_shell_at_once()
 {
    // The same shell. The start is 1e-16 inside the inner sphere (in the hole), at the line's closest approach:
    // the ray is in the shell from t < 1e-7 until it leaves the outer sphere. It used to be marched as in the
    // hole up to t = 16, missing the shell.
    let ray = Ray::new(
        [
            -0.064_931_201_077_070_12,
            0.074_151_157_206_739_38,
            1.155_805_150_106_016,
        ],
        [
            0.415_617_231_506_453_36,
            1.805_556_092_186_211,
            -0.092_487_516_254_309_7,
        ],
    )
    .unwrap();
    let got = march_s(&[1.16, 2.07], &[0.0, PI], &ONE_PHI, &ray);
    expect(&got, &[([0, 0, 0], 0.0, sphere_exit(&ray, 2.07))], 1e-15);
}

#[test]
fn ray_starting_within_rounding_of_a_cone_below_the_equator_and_crossing_it_is_above_it_from_its_start()
 {
    // Cones at 1.604 and 2.816. The start lies on the cone 2.816 within rounding (1.5e-16 rad above the stored
    // breakpoint, by a 200-bit evaluation) and the ray crosses the cone there, into the band above, until θ comes
    // back below 2.816 at t = 0.344825737659845675; it leaves the ball at t = 1.268180220261427639. The band test
    // puts the start just below the cone, and the solver's root into the band above lies just before the start:
    // it is crossed at the start (a zero-length crossing of the band below first), where the ray used to stay in
    // the band below throughout.
    let ray = Ray::new(
        [
            0.383_584_294_226_147_7,
            -0.325_588_862_354_782_35,
            -1.490_294_795_344_858_9,
        ],
        [
            -2.279_543_362_199_768_7,
            0.623_778_554_590_778_6,
            0.736_858_007_032_056_6,
        ],
    )
    .unwrap();
    let got = march_s(&[0.0, 2.61], &[1.604, 2.816, PI], &ONE_PHI, &ray);
    let (back, out) = (0.344_825_737_659_845_7, 1.268_180_220_261_427_6);
    expect(
        &got,
        &[
            ([0, 0, 0], 0.0, 0.0),
            ([0, 1, 0], 0.0, back),
            ([0, 0, 0], back, out),
        ],
        1e-15,
    );
}

#[test]
fn ray_starting_within_rounding_of_a_cone_above_the_equator_and_crossing_it_is_below_it_from_its_start()
 {
    // Cones at 0.491, 1.321 and 2.334. The start lies 3e-17 rad above the cone 1.321 (by a 200-bit evaluation),
    // and θ falls from there: the ray is in the band below from its start until it leaves the ball at
    // t = 0.339013285822405165. The band test puts the start above the cone, and the solver's root into the band
    // below lies just before the start: it is crossed at the start, where the ray used to stay above throughout.
    let ray = Ray::new(
        [
            -0.713_540_398_321_645_8,
            1.676_585_367_781_244_3,
            0.464_865_325_119_332_5,
        ],
        [
            -0.191_016_475_646_174_63,
            1.060_923_210_735_788_2,
            0.272_249_609_186_612_1,
        ],
    )
    .unwrap();
    let got = march_s(&[0.0, 2.25], &[0.491, 1.321, 2.334], &ONE_PHI, &ray);
    let out = 0.339_013_285_822_405_2;
    expect(&got, &[([0, 1, 0], 0.0, 0.0), ([0, 0, 0], 0.0, out)], 1e-15);
}

#[test]
fn ray_grazing_a_cone_below_the_equator_at_its_start_within_rounding_crosses_nothing_there() {
    // Cones at 0.616, 1.888, 2.107, 2.178 and 2.926, a wedge of φ in [0, 4.56). The start lies on the cone
    // 1.888 within rounding, at θ's turn (the line tangent to the cone there), and on the plane φ = 0, which the
    // ray leaves at once (φ falls below 0): one zero-length crossing at the start. The solver's roots of that
    // cone lie within rounding of the start; θ does not move there, so none of them is crossed at the start.
    // The same scaled by 2^10 (origin, direction and radii, exactly), where θ's rate and its rounding grow as the
    // cube of the scale.
    let th = [0.616, 1.888, 2.107, 2.178, 2.926];
    for k in [1.0, 1024.0] {
        let ray = Ray::new(
            [
                0.443_985_799_725_125_53 * k,
                0.0,
                -0.145_755_589_342_567_22 * k,
            ],
            [
                -0.195_943_748_597_085_52 * k,
                -k,
                0.064_326_148_657_100_4 * k,
            ],
        )
        .unwrap();
        let got = march_s(&[0.0, 2.34 * k], &th, &[0.0, 2.65, 4.56], &ray);
        expect(&got, &[([0, 0, 0], 0.0, 0.0)], 0.0);
    }
}

#[test]
fn ray_grazing_a_cone_above_the_equator_at_its_start_within_rounding_stays_in_its_band_at_every_scale()
 {
    // Cones at 0.491, 1.321 and 2.334. The start lies on the cone 1.321 within rounding, at θ's turn, on the
    // side of the band above it, where the ray stays until it leaves the ball. The solver's roots of that cone
    // lie within rounding of the start, and θ's rate there is within its rounding of 0 (but not 0): none is
    // crossed. The same with the origin and radii, or the direction, scaled by 2^10 (exactly): the rate's
    // rounding scales as the rate does.
    let th = [0.491, 1.321, 2.334];
    let origin = [
        -0.737_441_231_190_581_4,
        1.476_846_204_517_984_4,
        0.421_141_279_484_492_9,
    ];
    let dir = [
        1.542_045_276_192_049_8,
        -0.849_746_808_975_424_4,
        -0.369_708_867_441_910_4,
    ];
    for (k, m) in [(1.0, 1.0), (1024.0, 1.0), (1.0, 1024.0)] {
        let ray = Ray::new(origin.map(|x| x * k), dir.map(|x| x * m)).unwrap();
        let got = march_s(&[0.0, 2.25 * k], &th, &ONE_PHI, &ray);
        expect(
            &got,
            &[([0, 1, 0], 0.0, sphere_exit(&ray, 2.25 * k))],
            1e-15,
        );
    }
}
