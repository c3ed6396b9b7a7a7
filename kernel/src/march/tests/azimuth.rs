//! The azimuth stream's hard places: a line through the z axis jumping across several sectors (the walk, its way
//! round a full turn and round a wedge), a ray starting on the axis or on the plane x = 0, and a segment that
//! ends inside the ball after its last radius crossing.

use super::*;
use crate::ray::Ray;
use core::f64::consts::{FRAC_PI_2, PI};

/// Four sectors, a quarter turn each.
const QUARTERS: [f64; 5] = [0.0, FRAC_PI_2, PI, 3.0 * FRAC_PI_2, 2.0 * PI];

/// The line from (−3, −3, 0.25) along (1.5, 1.5, 0), through the axis point (0, 0, 0.25) at t = 2 (the direction
/// is not a power of two, so t is 2 only if the walk's t is computed right), and how far from t = 2 it meets the
/// spheres r = 0.5 and r = 1 (|t − 2|·1.5·√2 = √(r² − 0.0625)).
fn diagonal() -> (Ray<f64>, f64, f64) {
    let ray = Ray::new([-3.0, -3.0, 0.25], [1.5, 1.5, 0.0]).unwrap();
    let at = |r: f64| ((r * r - 0.0625) / 2.0).sqrt() / 1.5;
    (ray, at(0.5), at(1.0))
}

/// Marches [`diagonal`] through `phi` and checks its crossings: sector 2 up to the axis, the walk through sector
/// `between` in zero length there, sector 0 after. Returns them.
fn diagonal_walks_through(phi: &[f64], between: u32) -> std::vec::Vec<CellCrossing<f64>> {
    let (ray, h, g) = diagonal();
    let c = march_s(&R, &TH, phi, &ray);
    expect(
        &c,
        &[
            ([1, 0, 2], 2.0 - g, 2.0 - h),
            ([0, 0, 2], 2.0 - h, 2.0),
            ([0, 0, between], 2.0, 2.0),
            ([0, 0, 0], 2.0, 2.0 + h),
            ([1, 0, 0], 2.0 + h, 2.0 + g),
        ],
        1e-15,
    );
    c
}

#[test]
fn line_through_the_z_axis_walks_half_a_turn_through_the_counterclockwise_sector_between() {
    // From φ = 5π/4 to φ = π/4 across four quarter sectors: two steps either way round; the tie goes
    // counter-clockwise, through sector 3, in zero length.
    let c = diagonal_walks_through(&QUARTERS, 3);
    assert_eq!((c[1].t_exit, c[2].t_enter, c[2].t_exit), (2.0, 2.0, 2.0));
}

#[test]
fn line_through_the_z_axis_of_a_wedge_walks_round_the_inside_not_through_the_outside_sector() {
    // The wedge φ ∈ [0, 3π/2] (sector 3 is outside): the same jump from sector 2 to sector 0 goes clockwise, through
    // sector 1, although the tie alone would choose the way through the outside.
    diagonal_walks_through(&QUARTERS[..4], 1);
}

#[test]
fn ray_starting_on_the_z_axis_off_the_origin_starts_in_the_sector_of_its_direction() {
    // From the axis point (0, 0, 0.25) at t = 0 along φ = π/4: sector 0 from the start, no walk.
    let ray = Ray::new([0.0, 0.0, 0.25], [1.5, 1.5, 0.0]).unwrap();
    let (_, h, g) = diagonal();
    let c = march_s(&R, &TH, &QUARTERS, &ray);
    expect(&c, &[([0, 0, 0], 0.0, h), ([1, 0, 0], h, g)], 1e-15);
}

#[test]
fn ray_starting_on_the_plane_x_0_off_the_axis_is_in_the_sector_of_its_start() {
    // From (0, 0.5, 0.25), at φ = π/2, along +x: in the sector [0.3, 2) until it leaves the ball (the boundary
    // φ = 0.3 is met only beyond it), not in the sector of its direction (φ = 0, in [4, 0.3 + 2π)).
    let ph = [0.3, 2.0, 4.0, 0.3 + 2.0 * PI];
    let ray = Ray::new([0.0, 0.5, 0.25], [1.0, 0.0, 0.0]).unwrap();
    let c = march_s(&R, &TH, &ph, &ray);
    expect(&c, &[([1, 0, 0], 0.0, (1.0f64 - 0.3125).sqrt())], 1e-15);
}

#[test]
fn segment_ending_inside_the_ball_crosses_a_cone_after_its_last_radius_crossing() {
    // Down the vertical line x = 0, y = 0.1 from z = 0.7 to z = −0.3 (t_max = 1): into the ball r < 0.5 at
    // t = 0.7 − √0.24, across the plane θ = π/2 at t = 0.7, and it ends before reaching r = 0.5 again (t ≈ 1.19):
    // the march goes on after the radius stream's last event.
    let ray = Ray::new([0.0, 0.1, 0.7], [0.0, 0.0, -1.0])
        .unwrap()
        .with_interval(0.0, 1.0)
        .unwrap();
    let t1 = 0.7 - 0.24f64.sqrt();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(
        &c,
        &[
            ([1, 0, 0], 0.0, t1),
            ([0, 0, 0], t1, 0.7),
            ([0, 1, 0], 0.7, 1.0),
        ],
        1e-15,
    );
}

#[test]
fn ray_starting_exactly_on_the_azimuth_zero_boundary_going_clockwise_crosses_it_at_once() {
    // From (0.3, 0, 0.2), on the half-plane φ = 0 (stored exactly as (1, 0)), along −y: in sector 0 for no
    // length, then in sector 1 ([π, 2π)). Along +y it stays in sector 0.
    let at = |r: f64| (r * r - 0.13).sqrt();
    let cw = Ray::new([0.3, 0.0, 0.2], [0.0, -1.0, 0.0]).unwrap();
    let c = march_s(&R, &TH, &PH, &cw);
    expect(
        &c,
        &[
            ([0, 0, 0], 0.0, 0.0),
            ([0, 0, 1], 0.0, at(0.5)),
            ([1, 0, 1], at(0.5), at(1.0)),
        ],
        1e-15,
    );
    let ccw = Ray::new([0.3, 0.0, 0.2], [0.0, 1.0, 0.0]).unwrap();
    let c = march_s(&R, &TH, &PH, &ccw);
    expect(
        &c,
        &[([0, 0, 0], 0.0, at(0.5)), ([1, 0, 0], at(0.5), at(1.0))],
        1e-15,
    );
}

/// From half of boundary φ = 4 stored (cos, sin) (both negative, the sine larger: on that half-plane exactly,
/// z = 0.2), clockwise along (sin, −cos): in its sector [4, 2π) for no length, then in [2, 4) until it leaves the
/// ball at t = √0.71 (φ falls towards 4 − π/2 and is 2.97 there). The arc test's tie (the start on the boundary's
/// own half) is decided by the sign of cos·x + sin·y, here of a sum of two positive squares.
#[test]
fn ray_starting_exactly_on_an_azimuth_boundary_with_negative_cosine_and_sine_going_clockwise_crosses_it_at_once()
 {
    let ph = [0.0, 2.0, 4.0, 2.0 * PI];
    let h = crate::surface::HalfPlane::from_azimuth_rad(4.0).unwrap();
    let (c, s) = (h.cos(), h.sin());
    let ray = Ray::new([0.5 * c, 0.5 * s, 0.2], [s, -c, 0.0]).unwrap();
    let out = 0.71f64.sqrt();
    expect(
        &march_s(&R, &TH, &ph, &ray),
        &[([1, 0, 2], 0.0, 0.0), ([1, 0, 1], 0.0, out)],
        1e-15,
    );
}

/// Boundaries at 0 and 5.5 (a full turn): the sector [0, 5.5) is wider than 3π/2. From (0.5 cos 0.2, 0.5 sin 0.2,
/// 0.2) counter-clockwise along the tangent, φ rises towards 0.2 + π/2 and never reaches 5.5, although that
/// boundary's direction is within 90° of the start's (it lies 5.3 ahead in the turning sense, 1 behind): one
/// sector until the ray leaves the ball.
#[test]
fn ray_in_a_sector_wider_than_three_quarter_turns_never_reaches_its_next_boundary() {
    let ph = [0.0, 5.5, 2.0 * PI];
    let (s0, c0) = libm::sincos(0.2);
    let ray = Ray::new([0.5 * c0, 0.5 * s0, 0.2], [-s0, c0, 0.0]).unwrap();
    expect(
        &march_s(&R, &TH, &ph, &ray),
        &[([1, 0, 0], 0.0, 0.71f64.sqrt())],
        1e-15,
    );
}

#[test]
fn ray_parallel_to_an_azimuth_boundary_plane_never_crosses_it() {
    // Along +x at y = 0.1: φ falls from about π toward 0 but never reaches the half-plane φ = 0, parallel to
    // the line (and the march ends without an error).
    let ray = Ray::new([-2.0, 0.1, 0.2], [1.0, 0.0, 0.0]).unwrap();
    let c = march_s(&R, &TH, &PH, &ray);
    let (a, b) = ((1.0f64 - 0.05).sqrt(), (0.25f64 - 0.05).sqrt());
    expect(
        &c,
        &[
            ([1, 0, 0], 2.0 - a, 2.0 - b),
            ([0, 0, 0], 2.0 - b, 2.0 + b),
            ([1, 0, 0], 2.0 + b, 2.0 + a),
        ],
        1e-15,
    );
}

#[test]
fn segment_ending_exactly_on_an_azimuth_boundary_and_one_ending_before_it() {
    // From (0.3, 0.2, 0.2) along −y: the half-plane φ = 0 at t = 0.2. A segment ending there enters sector 1 for no
    // length at its end; one ending at t = 0.15 stays in sector 0.
    let ray = |t_max: f64| {
        Ray::new([0.3, 0.2, 0.2], [0.0, -1.0, 0.0])
            .unwrap()
            .with_interval(0.0, t_max)
            .unwrap()
    };
    let c = march_s(&R, &TH, &PH, &ray(0.2));
    expect(&c, &[([0, 0, 0], 0.0, 0.2), ([0, 0, 1], 0.2, 0.2)], 1e-15);
    let c = march_s(&R, &TH, &PH, &ray(0.15));
    expect(&c, &[([0, 0, 0], 0.0, 0.15)], 1e-15);
}
