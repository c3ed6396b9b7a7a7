use super::*;
use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

fn list(c: &Crossings<f64>) -> ([f64; 2], [Side; 2], usize) {
    let mut t = [f64::NAN; 2];
    let mut s = [Side::Negative; 2];
    for (i, x) in c.iter().enumerate() {
        t[i] = x.t;
        s[i] = x.into;
    }
    (t, s, c.len())
}

#[test]
fn horizontal_ray_through_45_degree_cone() {
    // cone θ = 45°, apex at origin; ray along x at height z = 1 crosses it at x = −1 and x = +1.
    let cone = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let r = Ray::new([-3.0, 0.0, 1.0], [1.0, 0.0, 0.0]).unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!(n, 2);
    assert!(
        (t[0] - 2.0).abs() < 1e-15 && (t[1] - 4.0).abs() < 1e-15,
        "{t:?}"
    );
    // outside the cone (θ > 45°) → inside (θ < 45°) → outside
    assert_eq!(s, [Side::Negative, Side::Positive]);
}

#[test]
fn lower_nappe_only() {
    // θ = 135°: only z < 0. A ray at z = +1 never meets it.
    let cone = AxialCone::from_zenith_rad(0.0, 3.0 * FRAC_PI_4).unwrap();
    let r = Ray::new([-3.0, 0.0, 1.0], [1.0, 0.0, 0.0]).unwrap();
    assert!(cone.crossings(&r).is_empty());
    let r = Ray::new([-3.0, 0.0, -1.0], [1.0, 0.0, 0.0]).unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!(n, 2);
    assert!((t[0] - 2.0).abs() < 1e-15 && (t[1] - 4.0).abs() < 1e-15);
    // at z < 0, far from the axis θ < 135° (negative side), near the axis θ > 135° (positive side)
    assert_eq!(s, [Side::Positive, Side::Negative]);
}

#[test]
fn ray_along_z_axis_through_apex() {
    let cone = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let down = Ray::new([0.0, 0.0, 2.0], [0.0, 0.0, -1.0]).unwrap();
    let (t, s, n) = list(&cone.crossings(&down));
    assert_eq!((n, t[0], s[0]), (1, 2.0, Side::Positive));
    let up = Ray::new([0.0, 0.0, -2.0], [0.0, 0.0, 1.0]).unwrap();
    let (t, s, n) = list(&cone.crossings(&up));
    assert_eq!((n, t[0], s[0]), (1, 2.0, Side::Negative));
}

#[test]
fn ray_through_apex_staying_outside() {
    // Horizontal through the apex of a 45° cone: θ = 90° on both sides: no crossing.
    let cone = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let r = Ray::new([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
    assert!(cone.crossings(&r).is_empty());
}

#[test]
fn ray_parallel_to_generator_is_linear() {
    // Generator direction of the 45° cone is (1, 0, 1); a parallel ray offset in y crosses once.
    let cone = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let r = Ray::new([0.0, 1.0, -1.0], [1.0, 0.0, 1.0]).unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    // point p + t d = (t, 1, t − 1): c²(t² + 1) = s²(t − 1)² ⇒ t² + 1 = t² − 2t + 1 ⇒ t = 0, but z = −1 < 0
    // (lower nappe): no crossing of the upper nappe.
    assert_eq!(n, 0, "{t:?} {s:?}");
    let r = Ray::new([0.0, 1.0, 3.0], [1.0, 0.0, 1.0]).unwrap();
    // (t, 1, t + 3): t² + 1 = (t + 3)² ⇒ 1 = 6t + 9 ⇒ t = −4/3, z = 5/3 > 0 but t < 0: filtered. Full line:
    let r = r.with_interval(-10.0, 10.0).unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!(n, 1);
    assert!((t[0] + 4.0 / 3.0).abs() < 1e-15, "{t:?}");
    // moving along +d the point goes from θ > 45° ... to inside: (t→∞: direction (1,0,1) is on the cone) —
    // Q = c²ρ² − s²z² = (t² + 1 − (t + 3)²)/2 = (−6t − 8)/2 decreases: into the negative side.
    assert_eq!(s[0], Side::Negative);
}

#[test]
fn ray_along_generator_reports_nothing() {
    let cone = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let r = Ray::new([1.0, 0.0, 1.0], [1.0, 0.0, 1.0])
        .unwrap()
        .with_interval(-5.0, 5.0)
        .unwrap();
    assert!(cone.crossings(&r).is_empty());
}

#[test]
fn half_pi_is_exactly_the_plane() {
    let cone = AxialCone::from_zenith_rad(0.5, FRAC_PI_2).unwrap();
    assert_eq!(cone.cos(), 0.0);
    let r = Ray::new([0.3, 0.2, 2.0], [0.1, 0.0, -1.0]).unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!((n, t[0], s[0]), (1, 1.5, Side::Positive));
}

#[test]
fn apex_offset_latitude_cone() {
    // ψ = 30° latitude cone of a sphere-like setup with apex at z = −1: θ = 60°.
    let cone = AxialCone::from_zenith_rad(-1.0, PI / 3.0).unwrap();
    // the generator through (√3, 0, 0) (since tan 30° · √3 = 1 = z − k): a radial ray from far outside
    let r = Ray::new([10.0, 0.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!(n, 2);
    let x0 = 3.0_f64.sqrt();
    assert!(
        (t[0] - (10.0 - x0)).abs() < 1e-14 && (t[1] - (10.0 + x0)).abs() < 1e-14,
        "{t:?}"
    );
    assert_eq!(s, [Side::Negative, Side::Positive]);
}

#[test]
fn tangent_touch_is_two_crossings() {
    // A line in the tangent plane of the 45° cone along the generator through (1, 0, 1). (cos, sin) = (1, 1)
    // normalised gives exactly equal cos² and sin², so the double root is exact.
    let cone = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let r = Ray::new([1.0, -2.0, 1.0], [0.0, 1.0, 0.0]).unwrap();
    // points (1, t − 2, 1): ρ² = 1 + (t−2)² ≥ 1 = z²: touches at t = 2 from the outside (θ ≥ 45°).
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!(n, 2, "{t:?}");
    assert_eq!(t, [2.0, 2.0]);
    assert_eq!(s, [Side::Negative, Side::Positive]);
}

#[test]
fn crossing_near_apex_seen_from_far_origin_is_refined() {
    // Regression: the crossing lies 0.022 from the apex while the origin is 1.1 away. Without the Newton step
    // at the crossing, the rounding of C at the origin (ε|q|²) divided by the small |∇Q| there put the point
    // 10.8 ε·S off the cone and t 27 ulps off (forward error 24 ε·S). The expected t is the 256-bit oracle's.
    let cone = AxialCone::from_zenith_rad(0.5267998051560774, 2.0648687785548936).unwrap();
    let r = Ray::new(
        [
            0.6286096275634043,
            -0.9245109205653476,
            -0.06658909448084649,
        ],
        [-0.48592690623839413, 0.7414626547130231, 0.462718244139454],
    )
    .unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!(n, 2);
    assert_eq!(s, [Side::Positive, Side::Negative]);
    let scale = 1.1199574159823074;
    // the first crossing is nearly tangent (sin of the crossing angle 0.0128): its bound is divided by that
    assert!(
        (t[0] - 5.998468605465881e-1).abs() <= 4.0 * f64::EPSILON * scale / 0.0128,
        "{t:?}"
    );
    assert!(
        (t[1] - 1.260267547988992).abs() <= 4.0 * f64::EPSILON * scale,
        "{t:?}"
    );
}

#[test]
fn steep_ray_through_a_nearly_flat_cone_keeps_the_crossing_of_its_own_nappe() {
    // θ = π/2 − 1e-9: the nappes are within 1e-9·ρ of the plane z = 0. A vertical line at ρ = 1e-6 from 100
    // above meets the upper nappe at z = +1e-15 and the lower at z = −1e-15; both roots round to t = 100,
    // where the computed z is exactly 0, so the sign of z cannot say which root is whose and the upper
    // cone's crossing used to be dropped. The line is steeper than the cone (A < 0): one root per nappe, the
    // earlier (higher, d_z < 0) one on the upper nappe.
    let up = AxialCone::from_zenith_rad(0.0, FRAC_PI_2 - 1e-9).unwrap();
    let down = AxialCone::from_zenith_rad(0.0, FRAC_PI_2 + 1e-9).unwrap();
    let r = Ray::new([1e-6, 0.0, 100.0], [0.0, 0.0, -1.0]).unwrap();
    let (t, s, n) = list(&up.crossings(&r));
    assert_eq!(n, 1, "{t:?}");
    assert_eq!((t[0], s[0]), (100.0, Side::Positive)); // into larger θ
    let (t, s, n) = list(&down.crossings(&r));
    assert_eq!(n, 1, "{t:?}");
    assert_eq!((t[0], s[0]), (100.0, Side::Positive));
    // and going up
    let r = Ray::new([1e-6, 0.0, -100.0], [0.0, 0.0, 1.0]).unwrap();
    let (t, s, n) = list(&up.crossings(&r));
    assert_eq!((n, t[0], s[0]), (1, 100.0, Side::Negative));
    let (t, s, n) = list(&down.crossings(&r));
    assert_eq!((n, t[0], s[0]), (1, 100.0, Side::Negative));
}

#[test]
fn flat_ray_passing_the_apex_within_rounding_meets_one_nappe_twice() {
    // A line flatter than a 45° cone passing 1e-14 above its apex, seen from 100 away: both roots are near
    // the apex (|z| ~ 1e-14, the rounding of z there is ~1e-14 too). The line is flatter than the cone
    // (A > 0), so it enters and leaves the nappe its closest approach to the apex lies on: the upper one.
    let up = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let down = AxialCone::from_zenith_rad(0.0, 3.0 * FRAC_PI_4).unwrap();
    let r = Ray::new([-100.0, 0.0, 1e-14 + 0.5], [1.0, 0.0, -0.005]).unwrap();
    // closest approach to the apex: z = (0.5 + 1e-14) − 0.005·100 (rounded) > 0 at x ≈ 0
    let (_, s, n) = list(&up.crossings(&r));
    assert_eq!(n, 2);
    assert_eq!(s, [Side::Negative, Side::Positive]);
    assert_eq!(down.crossings(&r).len(), 0);
}

#[test]
fn zenith_a_few_ulps_from_half_pi_is_exactly_the_plane() {
    let near = f64::from_bits(core::f64::consts::FRAC_PI_2.to_bits() + 3);
    assert_eq!(AxialCone::from_zenith_rad(0.0, near).unwrap().cos(), 0.0);
    let far = f64::from_bits(core::f64::consts::FRAC_PI_2.to_bits() + 64);
    assert!(AxialCone::from_zenith_rad(0.0, far).unwrap().cos() < 0.0);
}

#[test]
fn side_of_points() {
    let cone = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    assert_eq!(cone.side_of(V3::new(0.0, 0.0, 1.0)), Some(Side::Negative));
    assert_eq!(cone.side_of(V3::new(1.0, 0.0, 0.0)), Some(Side::Positive));
    assert_eq!(cone.side_of(V3::new(1.0, 0.0, 1.0)), None);
    assert_eq!(cone.side_of(V3::new(1.0, 0.0, -1.0)), Some(Side::Positive));
    assert_eq!(cone.side_of(V3::ZERO), None);
}

#[test]
fn bad_angles_are_errors() {
    assert_eq!(
        AxialCone::from_zenith_rad(0.0, -0.1),
        Err(SurfaceError::AngleOutOfRange)
    );
    assert_eq!(
        AxialCone::from_zenith_rad(0.0, 4.0),
        Err(SurfaceError::AngleOutOfRange)
    );
    assert_eq!(
        AxialCone::from_zenith_rad(f64::NAN, 1.0),
        Err(SurfaceError::NonFinite)
    );
    assert_eq!(
        AxialCone::from_cos_sin(0.0, 0.5, -0.5),
        Err(SurfaceError::AngleOutOfRange)
    );
}

#[test]
fn ray_parallel_to_a_generator_in_its_tangent_plane_never_touches() {
    // Found by the `surfaces` fuzz target: the line (−π, y0 + u, y0 + u) is parallel to the generator
    // (0, 1, 1) of the 45° cone and lies in the tangent plane along it, so it never meets the cone. A = c² − s²
    // is rounding noise there, the discriminant is 0, and a spurious touch at t = 0 used to be reported.
    // The cone is given by equal cos and sin, so that it is 45° exactly in f32 (its f32 sine and cosine of the
    // rounded π/4 may differ by an ulp, which tilts it enough for this line to cross it, 5000 units away).
    let y0 = 0.000_476_792_28;
    let h = core::f32::consts::FRAC_1_SQRT_2;
    let cone = AxialCone::from_cos_sin(0.0_f32, h, h).unwrap();
    let r = Ray::new([-core::f32::consts::PI, y0, y0], [0.0, 43690.0, 43690.0]).unwrap();
    assert!(cone.crossings(&r).is_empty(), "{:?}", cone.crossings(&r));
    let cone = AxialCone::from_zenith_rad(0.0_f64, FRAC_PI_4).unwrap();
    let r = Ray::new([-PI, f64::from(y0), f64::from(y0)], [0.0, 1.0, 1.0]).unwrap();
    assert!(cone.crossings(&r).is_empty(), "{:?}", cone.crossings(&r));
}

#[test]
fn tangent_ray_touches_at_the_point_of_tangency_f32() {
    // Found by the `surfaces` fuzz target: a ray along x at y = z = 341 touches the 45° cone at x = 0. C's two
    // terms cancel there, and the double root used to be taken as C/q, which put the touch at x ≈ 2.
    let cone = AxialCone::from_zenith_rad(0.0_f32, core::f32::consts::FRAC_PI_4).unwrap();
    let r = Ray::new([-1.0 / 256.0, 341.0, 341.0], [341.0_f32, 0.0, 0.0]).unwrap();
    for c in &cone.crossings(&r) {
        let x = -1.0 / 256.0 + c.t * 341.0;
        assert!(x.abs() <= 0.2, "touch at x = {x}");
    }
}

#[test]
fn zenith_angles_outside_zero_to_pi_are_refused_even_where_their_sine_is_positive() {
    // sin(−4) and sin(7) are positive: only the range test refuses these.
    for theta in [-4.0, 7.0, -0.1, 3.2] {
        assert_eq!(
            AxialCone::from_zenith_rad(0.0, theta),
            Err(SurfaceError::AngleOutOfRange),
            "{theta}"
        );
    }
    assert_eq!(
        AxialCone::from_zenith_rad(0.0, f64::NAN),
        Err(SurfaceError::NonFinite)
    );
    assert_eq!(
        AxialCone::from_zenith_rad(f64::INFINITY, 1.0),
        Err(SurfaceError::NonFinite)
    );
}

#[test]
fn each_non_finite_part_of_a_cos_sin_cone_is_refused_alone() {
    assert_eq!(
        AxialCone::from_cos_sin(0.0, f64::NAN, 1.0),
        Err(SurfaceError::NonFinite)
    );
    assert_eq!(
        AxialCone::from_cos_sin(0.0, 0.5, f64::INFINITY),
        Err(SurfaceError::NonFinite)
    );
    assert_eq!(
        AxialCone::from_cos_sin(f64::NAN, 0.5, 0.5),
        Err(SurfaceError::NonFinite)
    );
    assert_eq!(
        AxialCone::from_cos_sin(0.0, 0.5, -0.5),
        Err(SurfaceError::AngleOutOfRange)
    );
    assert_eq!(
        AxialCone::from_cos_sin(0.0, 0.0, 0.0),
        Err(SurfaceError::AngleOutOfRange)
    );
}

#[test]
fn a_non_unit_cos_sin_pair_is_renormalised_and_a_unit_one_kept() {
    let c = AxialCone::from_cos_sin(0.0, 3.0, 4.0).unwrap();
    assert_eq!((c.cos(), c.sin()), (0.6, 0.8));
    let u = AxialCone::from_cos_sin(0.0, 0.6, 0.8).unwrap();
    assert_eq!((u.cos(), u.sin()), (0.6, 0.8));
}

#[test]
fn a_direction_is_parallel_to_a_generator_only_within_rounding_of_its_size() {
    // θ = 45°: the generator (1, 0, 1), at a scale of 1000; A ≈ −1e6 δ against the bound 8ε · 1e6.
    let cone = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let flag = |delta: f64| {
        cone.leading_coefficient(V3::new(1e3, 0.0, 1e3 * (1.0 + delta)))
            .1
    };
    assert!(!flag(4e-16), "within rounding: parallel");
    assert!(flag(1e-13), "clear of rounding: not parallel");
    assert!(flag(-1e-13));
}

#[test]
fn side_of_points_for_the_degenerate_cones_theta_zero_and_pi() {
    // θ = 0 is the +z half-axis, θ = π the −z half-axis: every other point has a larger, resp. smaller, θ.
    let up = AxialCone::from_zenith_rad(0.0, 0.0).unwrap();
    assert_eq!((up.cos(), up.sin()), (1.0, 0.0));
    assert_eq!(up.side_of(V3::new(0.0, 0.0, 1.0)), None);
    assert_eq!(up.side_of(V3::new(0.0, 0.0, -1.0)), Some(Side::Positive));
    assert_eq!(up.side_of(V3::new(1.0, 0.0, 1.0)), Some(Side::Positive));
    assert_eq!(up.side_of(V3::new(0.0, 0.0, 0.0)), None); // the apex
    let down = AxialCone::from_zenith_rad(0.0, PI).unwrap();
    assert_eq!((down.cos(), down.sin()), (-1.0, 0.0));
    assert_eq!(down.side_of(V3::new(0.0, 0.0, -1.0)), None);
    assert_eq!(down.side_of(V3::new(0.0, 0.0, 1.0)), Some(Side::Negative));
    assert_eq!(down.side_of(V3::new(1.0, 0.0, 0.0)), Some(Side::Negative));
    assert_eq!(down.side_of(V3::new(1.0, 0.0, -1.0)), Some(Side::Negative));
}

#[test]
fn side_of_points_for_cones_opening_up_flat_and_down() {
    let p = |x: f64, z: f64| V3::new(x, 0.0, z);
    // θ = π/4: larger θ (outside, below) is positive.
    let up = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    assert_eq!(up.side_of(p(1.0, 0.0)), Some(Side::Positive));
    assert_eq!(up.side_of(p(0.1, 1.0)), Some(Side::Negative));
    assert_eq!(up.side_of(p(1.0, -1.0)), Some(Side::Positive));
    // θ = π/2 is the plane z = apex: above is the smaller θ.
    let flat = AxialCone::from_zenith_rad(1.0, FRAC_PI_2).unwrap();
    assert_eq!(flat.side_of(p(3.0, 2.0)), Some(Side::Negative));
    assert_eq!(flat.side_of(p(3.0, 0.0)), Some(Side::Positive));
    // θ = 3π/4: points above it (θ smaller) are negative, inside the lower nappe positive.
    let down = AxialCone::from_zenith_rad(0.0, 3.0 * FRAC_PI_4).unwrap();
    assert_eq!(down.side_of(p(1.0, 0.0)), Some(Side::Negative));
    assert_eq!(down.side_of(p(0.1, -1.0)), Some(Side::Positive));
    assert_eq!(down.side_of(p(1.0, 1.0)), Some(Side::Negative));
    assert_eq!(down.side_of(p(1.0, -0.5)), Some(Side::Negative));
}

#[test]
fn a_ray_through_the_apex_changes_side_there_at_its_own_parameter() {
    // Inside the upper nappe after the apex (θ ≈ 14°), outside before it: the apex is a crossing at t = 3.
    // Every product here is exact, so the line passes through the apex exactly (q × d = 0).
    let cone = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let r = Ray::new([-0.75, 0.0, -3.0], [0.25, 0.0, 1.0]).unwrap();
    let c = cone.crossings(&r);
    assert_eq!(c.len(), 1, "{c:?}");
    assert!(
        (c[0].t - 3.0).abs() < 1e-12 && c[0].into == Side::Negative,
        "{c:?}"
    );
}

#[test]
fn a_ray_tangent_to_a_generator_reports_only_finite_crossings_at_the_touch() {
    // θ = π/4, the line (1, y, 1) touches the generator (1, 0, 1) at y = 0: Q = y²/2, a double root where the
    // slope is 0 (the Newton step there is 0/0 and must not be taken).
    let cone = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let r = Ray::new([1.0, -1.0, 1.0], [0.0, 1.0, 0.0]).unwrap();
    let c = cone.crossings(&r);
    assert!(c.iter().all(|x| (x.t - 1.0).abs() < 1e-9), "{c:?}");
}
