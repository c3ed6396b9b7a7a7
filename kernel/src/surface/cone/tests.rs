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

#[test]
fn crossing_where_the_cones_form_overflows_keeps_its_unrefined_root() {
    // A line 1e153 from the axis, steeper than the 45° cone by δ = 2⁻¹⁰, meets the upper nappe at
    // s = 1e153 / √(δ(2 + δ)) ≈ 2.3e154, where x² and z² overflow: Q there is ∞ − ∞, the Newton step NaN, and
    // the root must be kept as the quadratic gave it (a NaN step taken would lose the crossing). Unrefined, it
    // carries half of A's relative rounding (A = −c²(2δ + δ²) is a difference: about ε / 2δ = 1e-13).
    let delta = 2f64.powi(-10);
    let cone = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let r = Ray::new([0.0, 1e153, 0.0], [1.0, 0.0, 1.0 + delta]).unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!(n, 1, "{t:?}");
    let expected = 1e153 / (delta * (2.0 + delta)).sqrt();
    assert!((t[0] * t[0]).is_infinite());
    assert!((t[0] / expected - 1.0).abs() < 1e-12, "{t:?} {expected}");
    // from θ = 90° (positive side) into the nappe (θ < 45°)
    assert_eq!(s[0], Side::Negative);
}

#[test]
fn line_exactly_parallel_to_a_generator_crosses_each_nappe_once_at_its_linear_root() {
    // (cos, sin) = (±1, 1) normalised gives cos² = sin² exactly, so A = c²(d_x² + d_y²) − s² d_z² is exactly 0
    // for the generator directions (1, 0, ±1): the quadratic is linear, its second root NaN, and the one root
    // is kept on its own nappe. Upper: (t, 1, 3 + t) meets x² + y² = z² at t = −4/3 (z = 5/3), entering the
    // nappe (Q = c²(−6t − 8) decreases). Lower: the mirror image (t, 1, −3 − t), entering the lower nappe's
    // inside (larger θ).
    let line = |z: f64, dz: f64| {
        Ray::new([0.0, 1.0, z], [1.0, 0.0, dz])
            .unwrap()
            .with_interval(-10.0, 10.0)
            .unwrap()
    };
    let up = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let down = AxialCone::from_cos_sin(0.0, -1.0, 1.0).unwrap();
    assert_eq!(up.leading_coefficient(V3::new(1.0, 0.0, 1.0)).0, 0.0);
    let (t, s, n) = list(&up.crossings(&line(3.0, 1.0)));
    assert_eq!(n, 1, "{t:?}");
    assert!((t[0] + 4.0 / 3.0).abs() < 1e-15, "{t:?}");
    assert_eq!(s[0], Side::Negative);
    let (t, s, n) = list(&down.crossings(&line(-3.0, -1.0)));
    assert_eq!(n, 1, "{t:?}");
    assert!((t[0] + 4.0 / 3.0).abs() < 1e-15, "{t:?}");
    assert_eq!(s[0], Side::Positive);
    // and neither line meets the other nappe
    assert!(down.crossings(&line(3.0, 1.0)).is_empty());
    assert!(up.crossings(&line(-3.0, -1.0)).is_empty());
}

#[test]
fn tangent_line_climbing_along_the_cone_touches_it_behind_its_origin_on_either_nappe() {
    // In the tangent plane of the 45° cone along the generator through (2, 0, 2), spanned by (1, 0, 1) and
    // (0, 1, 0): the line (2, 0, 2) + u (0.5, 1, 0.5) touches the cone at u = 0 only. Started at u = 8, at
    // (6, 8, 6), it touches at t = −8, behind the origin, where z = 6 − 8 · 0.5 = 2: on the upper nappe.
    // Every product of q × d is exact and cos² = sin², so the discriminant is exactly 0.
    let up = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let r = Ray::new([6.0, 8.0, 6.0], [0.5, 1.0, 0.5])
        .unwrap()
        .with_interval(-20.0, 20.0)
        .unwrap();
    let (t, s, n) = list(&up.crossings(&r));
    assert_eq!(n, 2, "{t:?}");
    assert!(
        (t[0] + 8.0).abs() < 1e-14 && (t[1] + 8.0).abs() < 1e-14,
        "{t:?}"
    );
    // outside the nappe (θ > 45°), touching it and back
    assert_eq!(s, [Side::Negative, Side::Positive]);
    assert!(
        AxialCone::from_cos_sin(0.0, -1.0, 1.0)
            .unwrap()
            .crossings(&r)
            .is_empty()
    );
    // The mirror image touches the lower nappe at (2, 0, −2), from above it (θ < 135°, the negative side).
    let down = AxialCone::from_cos_sin(0.0, -1.0, 1.0).unwrap();
    let r = Ray::new([6.0, 8.0, -6.0], [0.5, 1.0, -0.5])
        .unwrap()
        .with_interval(-20.0, 20.0)
        .unwrap();
    let (t, s, n) = list(&down.crossings(&r));
    assert_eq!(n, 2, "{t:?}");
    assert!(
        (t[0] + 8.0).abs() < 1e-14 && (t[1] + 8.0).abs() < 1e-14,
        "{t:?}"
    );
    assert_eq!(s, [Side::Positive, Side::Negative]);
    assert!(up.crossings(&r).is_empty());
}

#[test]
fn line_flatter_than_a_generator_only_by_rounding_meets_its_nappe_near_and_very_far_in_order() {
    // d = (1, 0, 1 − 2⁻⁵²) against the 45° cone: A = c²(1 − (1 − 2⁻⁵²)²) ≈ 2⁻⁵², within the rounding of its
    // terms, so the roots' nappes come from z at each root. The line (−3 + t, 1, t(1 − 2⁻⁵²)) enters the upper
    // nappe at t ≈ 5/3 (the root of the linear part, (−4/3, 1, 5/3)) and leaves it at t = −2B/A − 5/3 ≈ 6·2⁵¹,
    // where the cone's form is evaluated with an error of ε|x|² ≈ 1e17 (so that root is known only roughly).
    let cone = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let dz = 1.0 - f64::EPSILON;
    assert!(!cone.leading_coefficient(V3::new(1.0, 0.0, dz)).1);
    let r = Ray::new([-3.0, 1.0, 0.0], [1.0, 0.0, dz]).unwrap();
    let (t, s, n) = list(&cone.crossings(&r));
    assert_eq!(n, 2, "{t:?}");
    // the near root of Q = c²((t − 3)² + 1 − t²(1 − 2⁻⁵²)²) = 0, from the exact A = c²·2⁻⁵¹(1 − 2⁻⁵³)
    let a = f64::EPSILON * 2.0 * (1.0 - f64::EPSILON / 2.0);
    let near = 10.0 / (3.0 + (9.0 - 10.0 * a).sqrt());
    assert!((t[0] - near).abs() < 1e-14, "{t:?} {near}");
    let far = 6.0 / a;
    assert!(t[1] > 0.5 * far && t[1] < 2.0 * far, "{t:?} {far}");
    assert_eq!(s, [Side::Negative, Side::Positive]);
}

/// The roots of `Q(t) = x² + y² − z²` on the line `o + t d` (the 45° cone of equal cos and sin), in pairs from
/// `B² − AC` (not the kernel's way), in increasing order.
fn roots_on_45_degree_cone_in_pairs(o: V3<f64>, d: V3<f64>) -> (f64, f64) {
    use crate::dd::Dd;
    let f = Dd::from;
    let dot = |u: V3<f64>, v: V3<f64>| {
        f(u.x)
            .times(f(v.x))
            .plus(f(u.y).times(f(v.y)))
            .minus(f(u.z).times(f(v.z)))
    };
    let (a, b, c) = (dot(d, d), dot(o, d), dot(o, o));
    let root = b.times(b).minus(a.times(c)).sqrt();
    let t0 = b.negated().minus(root).over(a).value();
    let t1 = b.negated().plus(root).over(a).value();
    (t0.min(t1), t0.max(t1))
}

#[test]
fn nearly_tangent_line_keeps_its_crossings_where_a_newton_step_would_overshoot() {
    // A line nearly tangent to the 45° cone (found by a search over such lines): its crossings are 2.25e-8
    // apart at t ≈ 11.1, where Q's rounding (a few ε|x|², about 3e-16) exceeds Q anywhere between them (at most
    // A (2.25e-8 / 2)² ≈ 6e-17). The computed roots lie near the vertex of Q, where its slope is small, so a
    // Newton step from them would be a few separations long; it is refused (longer than a quarter of the roots'
    // separation) and the crossings stay within half their separation of the exact ones (taken, the steps put
    // them about 9e-8 away).
    let cone = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let o = V3::new(12.304705035591121, -7.086985287629517, -8.85260302793772);
    let d = V3::new(-1.123556069581938, 0.7389101816360119, 0.8990920409055886);
    let (t0, t1) = roots_on_45_degree_cone_in_pairs(o, d);
    let separation = t1 - t0;
    assert!(separation > 2e-8 && separation < 2.5e-8, "{t0} {t1}");
    let (t, s, n) = list(&cone.crossings(&Ray::new(o, d).unwrap()));
    assert_eq!(n, 2, "{t:?}");
    assert!(
        (t[0] - t0).abs() < 0.5 * separation && (t[1] - t1).abs() < 0.5 * separation,
        "{t:?} against {t0} {t1}"
    );
    assert_eq!(s, [Side::Negative, Side::Positive]);
}

#[test]
fn flat_line_whose_two_roots_round_in_reverse_order_touches_the_cone_at_their_midpoint() {
    // The line (−18, −9, 4.5 + 2⁻⁵⁰) + t (1, 0.5, −0.25) is flatter than the 45° cone and passes 2⁻⁵⁰
    // (8.9e-16) above its apex at t = 18: it enters and leaves the upper nappe at t = 18 − 1.0e-15 and
    // 18 + 6.5e-16, both within half an ulp of 18 (3.6e-15). The computed roots come out as 18 + 1 ulp and 18,
    // in reverse order, and the pair is reported as a touch at their midpoint, 18 (rounded to even), the entry
    // first. z is exactly 0 at 18 + 1 ulp and 8.9e-16 at 18, so telling the nappe from z at the roots (rather
    // than from the sign of (d × w)_z) would keep only the root at 18, one crossing.
    let up = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let z0 = f64::from_bits(4.5f64.to_bits() + 1); // 4.5 + 2⁻⁵⁰
    let r = Ray::new([-18.0, -9.0, z0], [1.0, 0.5, -0.25]).unwrap();
    let raw = up.scaled_crossings(r.line());
    assert_eq!(raw.n, 2);
    assert_eq!(raw.s, [18.0, 18.0]);
    assert_eq!(raw.into, [Side::Negative, Side::Positive]);
    let (t, _, n) = list(&up.crossings(&r));
    assert_eq!((n, t), (2, [18.0, 18.0]));
    // the lower nappe is not met
    let down = AxialCone::from_zenith_rad(0.0, 3.0 * FRAC_PI_4).unwrap();
    assert!(down.crossings(&r).is_empty());
}

#[test]
fn tangent_line_touching_one_nappe_within_rounding_of_the_apex_is_not_reported_on_the_other() {
    // In the tangent plane x = z of the 45° cone: the line (1, 1 − 2⁻⁵³, 1) + t (1, 1, 1) touches the upper
    // nappe at t = −(1 − 2⁻⁵³), at (2⁻⁵³, 0, 2⁻⁵³), within 2⁻⁵² of the apex. Every product of q × d is exact, so the
    // discriminant is exactly 0, and the touch's computed z is exactly 0 (B rounds to c², the touch to t = −1):
    // it is not on the lower nappe, which must not report it. The mirror image touches the lower nappe at
    // (2⁻⁵³, 0, −2⁻⁵³), which the upper nappe must not report. (On its own nappe the touch is lost within
    // rounding of the apex; a touch changes no side.)
    let y0 = 1.0 - f64::EPSILON / 2.0;
    let up = AxialCone::from_cos_sin(0.0, 1.0, 1.0).unwrap();
    let down = AxialCone::from_cos_sin(0.0, -1.0, 1.0).unwrap();
    let touching_upper = Ray::new([1.0, y0, 1.0], [1.0, 1.0, 1.0])
        .unwrap()
        .with_interval(-10.0, 10.0)
        .unwrap();
    assert!(down.crossings(&touching_upper).is_empty());
    let touching_lower = Ray::new([1.0, y0, -1.0], [1.0, 1.0, -1.0])
        .unwrap()
        .with_interval(-10.0, 10.0)
        .unwrap();
    assert!(up.crossings(&touching_lower).is_empty());
    // Both lines lie in their tangent planes exactly (q × d ≠ 0 and the discriminant 0), so each meets the
    // cone at most in its touch.
    for (cone, r) in [(up, touching_upper), (down, touching_lower)] {
        assert!(cone.crossings(&r).iter().all(|c| (c.t + 1.0).abs() < 1e-15));
    }
}

#[test]
fn line_parallel_to_a_generator_whose_quadratic_overflows_reports_no_crossing_at_infinity() {
    // The line (t, 0, 1e200 + t) is parallel to the generator (1, 0, 1) of the 45° cone (A is rounding noise:
    // cos π/4 and sin π/4 differ by an ulp) and meets the other generator at t = −5e199. Its C and
    // discriminant overflow (C = −∞, the discriminant +∞), the roots come out as NaN and +∞, and neither may
    // be reported, though +∞ lies on the upper nappe's side (z = +∞) and in the ray's interval.
    let cone = AxialCone::from_zenith_rad(0.0, FRAC_PI_4).unwrap();
    let r = Ray::new([0.0, 0.0, 1e200], [1.0, 0.0, 1.0]).unwrap();
    let raw = cone.scaled_crossings(r.line());
    assert!(raw.s[..raw.n].iter().all(|s| s.is_finite()), "{raw:?}");
    assert!(cone.crossings(&r).iter().all(|c| c.t.is_finite()));
}
