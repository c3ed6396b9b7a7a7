//! The geodetic conversions where their branches decide: inside the evolute (several normals through a point),
//! on the equatorial disc, at the centre of a sphere, a seeded longitude out to its series' limit, at 180° and
//! with seeds a turn off.

use super::*;

/// Unit normal at (φ, λ) from libm (not std: Miri perturbs std's transcendental results by a few ulps).
fn libm_normal(lat_deg: f64, lon_deg: f64) -> V3<f64> {
    let (p, l) = (lat_deg.to_radians(), lon_deg.to_radians());
    V3::new(
        libm::cos(p) * libm::cos(l),
        libm::cos(p) * libm::sin(l),
        libm::sin(p),
    )
}

#[test]
fn normal_deg_is_the_unit_normal_at_any_latitude_and_longitude() {
    let e = Ellipsoid::<f64>::wgs84();
    for (lat, lon) in [
        (30.0, 60.0),
        (-47.5, 123.25),
        (89.0, -170.0),
        (-5.0, -95.0),
        (60.0, 10.0),
    ] {
        let n = e.normal_deg(lat, lon);
        let want = libm_normal(lat, lon);
        assert!(
            n.minus(want).max_abs() <= 4.0 * f64::EPSILON,
            "{lat} {lon}: {n:?} against {want:?}"
        );
    }
}

#[test]
fn the_centre_of_a_sphere_is_at_minus_its_radius_below_the_equator() {
    let e = Ellipsoid::new(10.0_f64, 10.0).unwrap();
    assert_eq!(e.reverse_meridian(0.0, 0.0), (0.0, 1.0, -10.0));
}

#[test]
fn on_the_equatorial_disc_inside_the_evolute_the_foot_is_northern_and_mirrored_below_the_plane() {
    // R = N e² cos ψ, h = −N(1 − e²) at ψ = 30°; z so small that (z/a)² is 0, either side of the plane, and
    // both zeros.
    let e = Ellipsoid::<f64>::wgs84();
    let n = e.prime_vertical_radius(0.5);
    let r = n * e.e2() * 0.75_f64.sqrt();
    for (z, north) in [
        (0.0, true),
        (-0.0, true),
        (1.0e-200, true),
        (-1.0e-200, false),
    ] {
        let (s, c, h) = e.reverse_meridian(r, z);
        let want = if north { 0.5 } else { -0.5 };
        assert!(
            (s - want).abs() < 1e-9 && (c - 0.75_f64.sqrt()).abs() < 1e-9,
            "z {z:e}: {s} {c}"
        );
        assert!((h + n * (1.0 - e.e2())).abs() < 1e-6, "z {z:e}: {h}");
    }
}

/// The distance from `(r, z)` to the meridian ellipse, by brute force: the nearest of 4 001 samples of the
/// latitude, then a golden-section search on either side of it.
fn distance_to_the_ellipse(e: &Ellipsoid<f64>, r: f64, z: f64) -> f64 {
    let dist = |psi: f64| {
        let (s, c) = (libm::sin(psi), libm::cos(psi));
        let n = e.prime_vertical_radius(s);
        libm::hypot(r - n * c, z - n * (1.0 - e.e2()) * s)
    };
    let half = core::f64::consts::FRAC_PI_2;
    let step = 2.0 * half / 4000.0;
    let best = (0..=4000)
        .map(|k| -half + step * k as f64)
        .min_by(|a, b| dist(*a).total_cmp(&dist(*b)))
        .unwrap();
    let (mut lo, mut hi) = ((best - step).max(-half), (best + step).min(half));
    let g = (5.0_f64.sqrt() - 1.0) / 2.0;
    for _ in 0..200 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if dist(x1) < dist(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    dist((lo + hi) / 2.0)
}

#[test]
#[cfg_attr(miri, ignore)]
fn deep_inside_the_evolute_the_closed_form_finds_the_nearest_of_the_several_feet() {
    // Within about a e² (43 km) of the centre several normals pass through a point; the height is minus the
    // distance to the nearest foot. Points on a grid over that region (both signs of z, on the axis and on the
    // equatorial plane), and on the ellipse p + q = e⁴ where the cubic's r is 0.
    let e = Ellipsoid::<f64>::wgs84();
    let a = e.a();
    let e2 = e.e2();
    let mut points = std::vec::Vec::new();
    for i in 0..=12 {
        for j in -12..=12 {
            points.push((6.0e4 * i as f64 / 12.0, 6.0e4 * j as f64 / 12.0));
        }
    }
    for k in 0..=16 {
        let t = core::f64::consts::FRAC_PI_2 * k as f64 / 16.0;
        // p = (R/a)², q = (1 − e²)(z/a)²: p + q = e⁴ at R = a e² cos t, z = a e² sin t / √(1 − e²).
        points.push((
            a * e2 * libm::cos(t),
            a * e2 * libm::sin(t) / (1.0 - e2).sqrt(),
        ));
    }
    for (r, z) in points {
        let (s, c, h) = e.reverse_meridian(r, z);
        let n = e.prime_vertical_radius(s);
        let back = (n * c + h * c, n * (1.0 - e2) * s + h * s);
        assert!(
            (back.0 - r).abs() < 1e-7 && (back.1 - z).abs() < 1e-7,
            "({r}, {z}): ({s}, {c}, {h}) maps back to {back:?}"
        );
        let nearest = distance_to_the_ellipse(&e, r, z);
        assert!(
            (h + nearest).abs() < 1e-7,
            "({r}, {z}): h {h}, nearest foot {nearest} away"
        );
    }
}

#[test]
fn a_seeded_longitude_is_the_arctangent_to_a_few_ulps_out_to_the_series_limit() {
    // Seeded at λ₀ = 0 the longitude is the series alone: against libm's arctangent, within 4 ulps of the result
    // (the series' last term, w⁹/9, is about 30 ulps there).
    let e = Ellipsoid::<f64>::wgs84();
    let (sl, cl) = sin_cos_deg(0.0);
    for w in [0.005, -0.01, 0.015, 0.0199, -0.0199] {
        let p = V3::new(e.a(), e.a() * w, 0.0);
        let (_, lon, _) = e
            .ecef_to_geodetic_near(p, (0.0, sl, cl), (0.0, sl, cl))
            .unwrap();
        let want = libm::atan(w).to_degrees();
        let ulp = f64::from_bits(want.abs().to_bits() + 1) - want.abs();
        assert!(
            (lon - want).abs() <= 4.0 * ulp,
            "w {w}: {lon} against {want}"
        );
    }
}

#[test]
fn a_seeded_longitude_of_180_stays_and_seeds_a_turn_or_more_off_are_refused() {
    let e = Ellipsoid::<f64>::wgs84();
    let p = e.geodetic_deg_to_ecef(10.0, 180.0, 0.0);
    assert_eq!(p.y, 0.0);
    let (sl, cl) = sin_cos_deg(10.0);
    let (so, co) = sin_cos_deg(180.0);
    let seeded = |lon0: f64| e.ecef_to_geodetic_near(p, (10.0, sl, cl), (lon0, so, co));
    let (lat, lon, h) = seeded(180.0).unwrap();
    assert_eq!(lon, 180.0);
    assert!((lat - 10.0).abs() < 1e-13 && h.abs() < 1e-8, "{lat} {h}");
    // The same meridian given as −180° is wrapped to 180°; as −540° or 900° the sum is a turn or more outside
    // (−180°, 180°] after its one wrap.
    assert_eq!(seeded(-180.0).map(|g| g.1), Some(180.0));
    assert_eq!(seeded(-540.0), None);
    assert_eq!(seeded(900.0), None);
}

#[test]
fn a_seed_whose_latitude_in_degrees_is_not_finite_gives_none() {
    let e = Ellipsoid::<f64>::wgs84();
    let p = e.geodetic_deg_to_ecef(45.0, 10.0, 100.0);
    let (sl, cl) = sin_cos_deg(45.0);
    let (so, co) = sin_cos_deg(10.0);
    assert!(
        e.ecef_to_geodetic_near(p, (45.0, sl, cl), (10.0, so, co))
            .is_some()
    );
    for lat0 in [f64::NAN, f64::INFINITY] {
        assert_eq!(
            e.ecef_to_geodetic_near(p, (lat0, sl, cl), (10.0, so, co)),
            None,
            "{lat0}"
        );
    }
}

#[test]
fn a_seeded_latitude_near_the_equator_agrees_with_the_closed_form_to_1e_16_rad_out_to_the_step_limit()
 {
    // Seeded on the equator, the latitude is the sum of Newton's steps alone (no seed's rounding to hide in):
    // the series of sin δ must hold to its δ⁷ term (5e-16 rad at δ = 0.02, about 130 ulps of the result).
    let e = Ellipsoid::<f64>::wgs84();
    let (s0, c0) = sin_cos_deg(0.0);
    let (so, co) = sin_cos_deg(0.3);
    let mut worst = 0.0_f64;
    for lat in [-1.1, -0.6, 0.25, 0.9, 1.1] {
        for h in [0.0, 5.0e3] {
            let p = e.geodetic_deg_to_ecef(lat, 0.3, h);
            let want = e.ecef_to_geodetic(p);
            let (got, _, got_h) = e
                .ecef_to_geodetic_near(p, (0.0, s0, c0), (0.3, so, co))
                .unwrap();
            let err = (got.to_radians() - want.lat_rad).abs();
            worst = worst.max(err);
            assert!(
                err <= 1e-16,
                "{lat}° at {h} m: {got}° against {}°",
                want.lat_rad.to_degrees()
            );
            assert!(
                (got_h - want.h).abs() < 1e-8,
                "{lat}° at {h} m: h {got_h} against {}",
                want.h
            );
        }
    }
    std::println!("seeded on the equator: worst latitude {worst:.2e} rad");
}
