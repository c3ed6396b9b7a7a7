use super::*;

#[test]
fn rounding_to_f64_is_nearest() {
    for x in [
        1.0,
        3.0,
        -5.5e-300,
        1e300,
        0.1,
        -7.0e-12,
        f64::MAX,
        f64::MIN_POSITIVE,
    ] {
        assert_eq!(round_to_f64(&BigFloat::from_f64(x, PRECISION)), x);
    }
    // 1/3 rounds to the f64 nearest 1/3; 1 + 2^-53 (a tie) rounds to even (1); 1 + 2^-53 + 2^-100 rounds up.
    let third = H::f(1.0).div(&H::f(3.0));
    assert_eq!(third.to_f64(), 1.0 / 3.0);
    let tie = H::f(1.0).add(&H::f(2f64.powi(-53)));
    assert_eq!(tie.to_f64(), 1.0);
    let above = tie.add(&H::f(2f64.powi(-100)));
    assert_eq!(above.to_f64(), 1.0 + f64::EPSILON);
}

#[test]
fn newton_sqrt_has_full_precision() {
    for x in [2.0, 0.5, 3.0e-300, 7.0e250, 1.0 / 3.0] {
        let h = H::f(x);
        let r = h.sqrt();
        // r² − x, relative to x, is at the level of the working precision
        let rel = r.sq().sub(&h).div(&h).abs();
        let bound = H::f(2f64.powi(-(PRECISION as i32) + 4));
        assert!(
            rel.cmp(&bound) != Ordering::Greater,
            "sqrt({x}) off by {rel:?}"
        );
        assert_eq!(r.to_f64(), x.sqrt());
    }
    assert_eq!(H::f(4.0).sqrt().to_f64(), 2.0);
    assert!(H::f(0.0).sqrt().is_zero());
}

#[test]
fn sphere_tangent_is_a_double_root() {
    let s = OracleSurface::Spheroid { a: 1.0, b: 1.0 }.prepare();
    let c = s.crossings(&OracleRay::new([-5.0, 1.0, 0.0], [1.0, 0.0, 0.0]));
    assert_eq!(c.len(), 2);
    assert_eq!((c[0].t_f64, c[0].into_positive), (5.0, false));
    assert_eq!((c[1].t_f64, c[1].into_positive), (5.0, true));
}

#[test]
fn cone_45_degrees_closed_form() {
    let cone = OracleSurface::Cone {
        apex_z: 0.0,
        theta: std::f64::consts::FRAC_PI_4,
        angles: AngleType::F64,
    }
    .prepare();
    let c = cone.crossings(&OracleRay::new([-3.0, 0.0, 1.0], [1.0, 0.0, 0.0]));
    assert_eq!(c.len(), 2);
    // FRAC_PI_4 is not exactly π/4: the crossings are within 1e-15 of 2 and 4.
    assert!((c[0].t_f64 - 2.0).abs() < 1e-15 && (c[1].t_f64 - 4.0).abs() < 1e-15);
    assert!(!c[0].into_positive && c[1].into_positive);
    assert!((c[0].sin_angle - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
}

#[test]
fn half_plane_other_half_and_axis() {
    let h = OracleSurface::HalfPlane { phi: 0.0 }.prepare();
    assert!(
        h.crossings(&OracleRay::new([-2.0, -1.0, 0.0], [0.0, 1.0, 0.0]))
            .is_empty()
    );
    let c = h.crossings(&OracleRay::new([2.0, -1.0, 0.0], [0.0, 1.0, 0.0]));
    assert_eq!((c.len(), c[0].t_f64, c[0].into_positive), (1, 1.0, true));
    for phi in [0.5, 2.0, 4.0] {
        let h = OracleSurface::HalfPlane { phi }.prepare();
        let c = h.crossings(&OracleRay::new([-1.0, -1.0, 5.0], [1.0, 1.0, 0.0]));
        assert_eq!(c.len(), 1, "phi {phi}");
    }
}

#[test]
fn cone_line_through_the_apex_at_a_non_dyadic_ratio() {
    // q = d / 3 exactly in direction (q = (1, 2, 3), d = (3, 6, 9)): through the apex at t = −1/3 (behind the
    // origin), so nothing for t ≥ 0; on [−1, 1] one crossing, into the cone (d is 37° from +z).
    let cone = OracleSurface::Cone {
        apex_z: 0.0,
        theta: 1.0,
        angles: AngleType::F64,
    }
    .prepare();
    let mut ray = OracleRay::new([1.0, 2.0, 3.0], [3.0, 6.0, 9.0]);
    assert!(cone.crossings(&ray).is_empty());
    ray.t_min = -1.0;
    let c = cone.crossings(&ray);
    assert_eq!(c.len(), 1);
    assert_eq!((c[0].t_f64, c[0].into_positive), (-1.0 / 3.0, false));
}

#[test]
fn distances() {
    let cone = OracleSurface::Cone {
        apex_z: 1.0,
        theta: std::f64::consts::FRAC_PI_2,
        angles: AngleType::F64,
    }
    .prepare();
    assert_eq!(cone.distance_of_point([3.0, 4.0, 3.0]), 2.0);
    let s = OracleSurface::Spheroid { a: 2.0, b: 1.0 }.prepare();
    // first order: the relative error is of the order of the distance over the radius of curvature
    assert!((s.distance_of_point([0.0, 0.0, 1.0 + 1e-6]) - 1e-6).abs() < 1e-11);
    let h = OracleSurface::HalfPlane { phi: 0.0 }.prepare();
    assert_eq!(h.distance_of_point([-3.0, 4.0, 1.0]), 5.0);
    assert_eq!(h.distance_of_point([3.0, -4.0, 1.0]), 4.0);
}
