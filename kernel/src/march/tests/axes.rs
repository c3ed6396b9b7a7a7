//! Locating points by signs (`march::axes`): a point brought to unit size exactly, whatever its scale, and the
//! zenith band of a point on the −z axis that the ray leaves.

use super::*;
use crate::march::axes::{ZenithAxis, unit_scaled};
use crate::vec3::V3;
use core::f64::consts::PI;

#[test]
fn unit_scaled_brings_a_subnormal_point_to_unit_size_exactly() {
    // 2^-1060 · (3, −1.5, 0.75): every component subnormal; times 2^1059 exactly (the largest into [1, 2)).
    let tiny = f64::from_bits(1 << 14); // 2^-1060
    let q = V3::new(3.0 * tiny, -1.5 * tiny, 0.75 * tiny);
    assert!(q.x < f64::MIN_POSITIVE);
    assert_eq!(unit_scaled(q), V3::new(1.5, -0.75, 0.375));
    // and a point whose largest component is normal only by a factor of two
    let q = V3::new(f64::MIN_POSITIVE * 2.0, -f64::MIN_POSITIVE, 0.0);
    assert_eq!(unit_scaled(q), V3::new(1.0, -0.5, 0.0));
}

#[test]
fn unit_scaled_leaves_zero_and_infinite_points_as_they_are() {
    assert_eq!(
        unit_scaled(V3::new(0.0, -0.0, 0.0)),
        V3::new(0.0, -0.0, 0.0)
    );
    let q = V3::new(f64::INFINITY, 1.0, -2.0);
    assert_eq!(unit_scaled(q), q);
}

#[test]
fn unit_scaled_keeps_a_component_that_scaling_flushes_as_the_smallest_subnormal() {
    // (2^1000, ±2^-1074, 0): scaling by 2^-1000 rounds the small components to 0; they are kept as ±2^-1074,
    // the smallest subnormal of their sign, not as any larger number.
    let big = f64::from_bits((1023 + 1000) << 52);
    let smallest = f64::from_bits(1);
    let got = unit_scaled(V3::new(big, smallest, -smallest));
    assert_eq!(got, V3::new(1.0, smallest, -smallest));
    assert_eq!(unit_scaled(V3::new(-big, 0.0, 3.0 * smallest)).z, smallest);
}

#[test]
fn point_on_the_minus_z_axis_that_the_ray_leaves_is_in_the_band_below_theta_pi() {
    // θ = π exactly is outside a grid whose last breakpoint is π; the ray leaving the axis is just below it.
    for theta in [&[0.0, PI / 2.0, PI][..], &[0.0, 1.0, 2.0, 3.0, PI]] {
        let mut buf = [0.0; 16];
        let mut ws = &mut buf[..];
        let axis = ZenithAxis::build(theta, &mut ws).unwrap();
        let n = u32::try_from(theta.len()).unwrap();
        for q in [
            V3::new(0.0, 0.0, -1.0),
            V3::new(0.0, 0.0, -1e-300),
            V3::new(0.0, -0.0, -3e300),
        ] {
            assert_eq!(axis.band_of(q, true), n - 1, "{q:?}");
            assert_eq!(axis.band_of(q, false), n, "{q:?}");
        }
        // on the +z axis the band of θ = 0 either way
        assert_eq!(axis.band_of(V3::new(0.0, 0.0, 2.0), true), 1);
        assert_eq!(axis.band_of(V3::new(0.0, 0.0, 2.0), false), 1);
    }
}

#[test]
fn ray_starting_on_the_minus_z_axis_going_sideways_is_inside_from_its_start() {
    // From (0, 0, −0.5), on the axis at θ = π (outside the grid) and on the sphere r = 0.5, along +x: inside at
    // once, in the outer shell's lower band, up to r = 1.
    let ray = Ray::new([0.0, 0.0, -0.5], [1.0, 0.0, 0.0]).unwrap();
    let c = march_s(&R, &TH, &PH, &ray);
    expect(&c, &[([1, 1, 0], 0.0, 0.75f64.sqrt())], 1e-15);
}

/// The zenith axis of `theta` in `buf`.
fn zenith<'a>(theta: &'a [f64], buf: &'a mut [f64]) -> ZenithAxis<'a, f64> {
    let mut ws = buf;
    ZenithAxis::build(theta, &mut ws).unwrap()
}

#[test]
fn zenith_band_of_points_just_either_side_of_every_cone_at_every_scale() {
    // Points at θ_j ± 1e-6 and ± 1e-3 round every breakpoint (both nappes, the plane θ = π/2), in three
    // azimuths and at scales from subnormal to 1e300: the band is the number of breakpoints at or below θ.
    let theta = [0.0, 0.3, 1.0, 1.5, PI / 2.0, 1.7, 2.0, 2.8, PI];
    let mut buf = [0.0; 32];
    let axis = zenith(&theta, &mut buf);
    let mut checked = 0;
    for &tj in &theta {
        for delta in [-1e-3, -1e-6, 1e-6, 1e-3] {
            let t = tj + delta;
            if !(t > 0.0 && t < PI) {
                continue;
            }
            let want = u32::try_from(theta.iter().filter(|&&b| b <= t).count()).unwrap();
            for phi in [0.0_f64, 1.0, 4.0] {
                for scale in [1e-310, 1e-300, 1.0, 1e300] {
                    let q = V3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos());
                    let q = V3::new(q.x * scale, q.y * scale, q.z * scale);
                    assert_eq!(
                        axis.band_of(q, false),
                        want,
                        "θ {t}, φ {phi}, scale {scale}"
                    );
                    assert_eq!(axis.band_of(q, true), want, "θ {t}, φ {phi}, scale {scale}");
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 300, "{checked}");
}

#[test]
fn direction_along_a_cone_generator_on_its_own_nappe_only() {
    let q = PI / 4.0;
    let theta = [0.0, q, PI / 2.0, 3.0 * q, PI];
    let mut buf = [0.0; 16];
    let axis = zenith(&theta, &mut buf);
    let (s, c) = (q.sin(), q.cos());
    // θ = π/4 (k = 1): its upper nappe's generator, not the lower nappe's, not a steeper direction
    assert!(axis.along_cone(1, V3::new(s, 0.0, c)));
    assert!(axis.along_cone(1, V3::new(0.0, -3.0 * s, 3.0 * c)));
    assert!(!axis.along_cone(1, V3::new(s, 0.0, -c)));
    assert!(!axis.along_cone(1, V3::new(1.0, 0.0, 2.0)));
    // θ = 3π/4 (k = 3): the lower nappe's generator only
    assert!(axis.along_cone(3, V3::new(s, 0.0, -c)));
    assert!(!axis.along_cone(3, V3::new(s, 0.0, c)));
    assert!(!axis.along_cone(3, V3::new(1.0, 0.0, -2.0)));
    // θ = π/2 (k = 2), the plane: horizontal directions, and those tilted below the rounding of its equation
    for d in [
        V3::new(1.0, 0.0, 0.0),
        V3::new(0.0, -1.0, 1e-200),
        V3::new(1.0, 1.0, -1e-200),
    ] {
        assert!(axis.along_cone(2, d), "{d:?}");
    }
    assert!(!axis.along_cone(2, V3::new(1.0, 0.0, 0.5)));
    assert!(!axis.along_cone(2, V3::new(1.0, 0.0, -0.5)));
    // no cone 5
    assert!(!axis.along_cone(5, V3::new(1.0, 0.0, 0.0)));
}

#[test]
fn point_exactly_on_the_line_of_boundary_zero_is_in_its_sector_and_the_opposite_one_half_a_turn_on()
{
    // Boundary 0 at φ0 (not a multiple of π/2: both of its stored components are inexact), the point k·(cos φ0,
    // sin φ0) lies exactly on its line (a power-of-two multiple: the cross product is exactly 0), on boundary 0
    // itself for k > 0 (sector 0), opposite for k < 0, at φ0 + π (sector 2 of [φ0, φ0 + 1, φ0 + 3, φ0 + 5]).
    use crate::march::axes::AzimuthAxis;
    for phi0 in [2.0, 2.5, -1.0, 0.7, 4.0] {
        let phi = [phi0, phi0 + 1.0, phi0 + 3.0, phi0 + 5.0];
        let mut buf = [0.0; 16];
        let mut ws = &mut buf[..];
        let axis = AzimuthAxis::build(&phi, &mut ws).unwrap();
        let plane = axis.plane(0);
        let (c0, s0) = (plane.cos(), plane.sin());
        for k in [0.5, 2.0, 1024.0] {
            assert_eq!(axis.sector_of(k * c0, k * s0), 0, "φ0 {phi0}, k {k}");
            assert_eq!(axis.sector_of(-k * c0, -k * s0), 2, "φ0 {phi0}, k {k}");
        }
    }
}

#[test]
fn azimuth_span_over_a_full_turn_by_rounding_is_a_full_turn_and_beyond_it_an_error() {
    // The span may exceed 2π by 8 ε · 2π (the rounding of the breakpoints); exactly that much is still a full turn.
    use crate::march::axes::AzimuthAxis;
    let two_pi = PI + PI;
    let tol = two_pi * f64::EPSILON * 8.0;
    for (last, full) in [
        (two_pi, true),
        (two_pi + 5.0 * f64::EPSILON * two_pi, true),
        (two_pi + tol, true),
        (two_pi - 0.5, false),
    ] {
        let phi = [0.0, 1.0, last];
        let mut buf = [0.0; 8];
        let mut ws = &mut buf[..];
        let axis = AzimuthAxis::build(&phi, &mut ws).unwrap();
        assert_eq!(axis.full, full, "{last}");
    }
    let phi = [0.0, 1.0, two_pi + 4.0 * tol];
    let mut buf = [0.0; 8];
    let mut ws = &mut buf[..];
    assert!(AzimuthAxis::build(&phi, &mut ws).is_err());
}

/// An axis of `u32::MAX / 4` breakpoints or more is refused before anything is read (the band and event counts
/// stay far from overflowing `u32`); one fewer is accepted.
#[test]
fn axis_of_a_quarter_of_u32_max_breakpoints_is_refused_and_one_fewer_accepted() {
    let limit = (u32::MAX / 4) as usize;
    assert_eq!(
        crate::march::axes::len_u32(Axis::Phi, limit),
        Err(GridError::TooManyBreakpoints {
            axis: Axis::Phi,
            len: limit
        })
    );
    assert_eq!(
        crate::march::axes::len_u32(Axis::Phi, limit - 1),
        Ok(u32::MAX / 4 - 1)
    );
}
