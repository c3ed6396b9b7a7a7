use super::*;
use crate::surface::{Side, Surface};

mod hard_cases;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn wgs84_constants() {
    let e = Ellipsoid::<f64>::wgs84();
    assert_eq!(e.a(), 6378137.0);
    assert!(close(e.b(), 6356752.314245179, 1e-8));
    assert!(close(e.min_height(), -6335439.3272928195, 1e-6));
}

#[test]
fn forward_closed_forms_at_equator_and_pole() {
    let e = Ellipsoid::<f64>::wgs84();
    let p = e.geodetic_deg_to_ecef(0.0, 90.0, 10.0);
    assert_eq!(p.to_array(), [0.0, 6378147.0, 0.0]);
    let pole = e.geodetic_deg_to_ecef(90.0, 37.0, 0.0);
    assert_eq!(pole.x, 0.0);
    assert_eq!(pole.y, 0.0);
    assert!(close(pole.z, e.b(), 1e-8));
    let south = e.geodetic_deg_to_ecef(-90.0, -123.0, -5.0);
    assert_eq!((south.x, south.y), (0.0, 0.0));
    assert!(close(south.z, -(e.b() - 5.0), 1e-8));
}

#[test]
fn sin_cos_deg_exact_quadrants() {
    assert_eq!(sin_cos_deg(90.0_f64), (1.0, 0.0));
    assert_eq!(sin_cos_deg(-90.0_f64), (-1.0, 0.0));
    assert_eq!(sin_cos_deg(180.0_f64), (0.0, -1.0));
    assert_eq!(sin_cos_deg(270.0_f64), (-1.0, 0.0));
    assert_eq!(sin_cos_deg(-180.0_f64), (0.0, -1.0));
    let (s, c) = sin_cos_deg(30.0_f64);
    assert!(close(s, 0.5, 2e-16) && close(c, 0.75_f64.sqrt(), 2e-16));
    // Every zero is +0, whichever quadrant's sign flip made it (−0 == 0, so the bits are compared).
    for x in [
        0.0, -0.0, 90.0, -90.0, 180.0, -180.0, 270.0, -270.0, 360.0, 540.0_f64,
    ] {
        let (s, c) = sin_cos_deg(x);
        for v in [s, c].into_iter().filter(|v| *v == 0.0) {
            assert_eq!(v.to_bits(), 0.0_f64.to_bits(), "{x}: ({s:?}, {c:?})");
        }
        let (s, c) = sin_cos_deg(x as f32);
        for v in [s, c].into_iter().filter(|v| *v == 0.0) {
            assert_eq!(v.to_bits(), 0.0_f32.to_bits(), "{x} in f32: ({s:?}, {c:?})");
        }
    }
}

/// The `f32` sine and cosine of degrees (reduction, conversion to radians and `sin_cos_f32` all in `f32`)
/// against the `f64` ones of the same angles, in ulps of the `f32` result, on a sweep of [−720°, 720°]
/// (2¹⁶ + 1 angles; 2¹⁰ + 1 under Miri) and the multiples of 90°, which stay exact.
#[test]
fn sin_cos_deg_f32_within_2_ulp_of_f64() {
    let ulps = |got: f32, want: f64| {
        let w = want as f32;
        let ulp = f64::from(f32::from_bits(w.abs().to_bits() + 1) - w.abs());
        (f64::from(got) - want).abs() / ulp
    };
    let n: u32 = if cfg!(miri) { 1 << 8 } else { 1 << 16 };
    let mut worst = 0.0_f64;
    for i in 0..=n {
        let x = -720.0 + 1440.0 * (i as f32) / (n as f32);
        let (s, c) = sin_cos_deg(x);
        let (s64, c64) = sin_cos_deg(f64::from(x));
        worst = worst.max(ulps(s, s64)).max(ulps(c, c64));
    }
    std::println!("sin_cos_deg::<f32>: worst {worst:.3} ulp");
    assert!(worst <= 2.0, "{worst} ulp");
    for k in -8..=8 {
        let (s, c) = sin_cos_deg(90.0_f32 * k as f32);
        let (s64, c64) = sin_cos_deg(90.0 * f64::from(k));
        assert_eq!((f64::from(s), f64::from(c)), (s64, c64), "{k} × 90°");
    }
}

/// The `f32` geodetic conversion (its cube root in `f32`, `cbrt_f32`) against the `f64` one of the same
/// ECEF points, near the WGS84 surface: latitude error in radians and height error in meters.
#[test]
fn reverse_f32_against_f64() {
    let (e32, e64) = (Ellipsoid::<f32>::wgs84(), Ellipsoid::<f64>::wgs84());
    let (mut dlat, mut dh) = (0.0_f64, 0.0_f64);
    // 200 points natively, every fourth under Miri (the whole took ten seconds there)
    for i in (0..200).step_by(if cfg!(miri) { 4 } else { 1 }) {
        let lat = -1.5 + 3.0 * f64::from(i) / 200.0;
        let lon = 0.1 * f64::from(i);
        let h = 9000.0 * f64::from(i % 7) - 3000.0;
        let p = e64.geodetic_rad_to_ecef(lat, lon, h);
        let p32 = V3::new(p.x as f32, p.y as f32, p.z as f32);
        let g32 = e32.ecef_to_geodetic(p32);
        let g64 = e64.ecef_to_geodetic(V3::new(
            f64::from(p32.x),
            f64::from(p32.y),
            f64::from(p32.z),
        ));
        dlat = dlat.max((f64::from(g32.lat_rad) - g64.lat_rad).abs());
        dh = dh.max((f64::from(g32.h) - g64.h).abs());
    }
    std::println!("ecef_to_geodetic::<f32>: worst latitude {dlat:.3e} rad, height {dh:.3} m");
    assert!(dlat <= 1e-6 && dh <= 2.0, "{dlat} rad, {dh} m");
}

#[test]
fn reverse_round_trip_assorted() {
    let e = Ellipsoid::<f64>::wgs84();
    for &(lat, lon, h) in &[
        (0.3, 0.1, 0.0),
        (-1.2, 2.9, 1234.5),
        (1.5, -3.0, -4000.0),
        (0.0, 0.0, 0.0),
        (-0.7, 1.0, 4.0e6),
        (0.9, -0.4, -4.5e6),
        (1e-9, 0.2, 300.0),
    ] {
        let g = e.ecef_to_geodetic(e.geodetic_rad_to_ecef(lat, lon, h));
        assert!(close(g.lat_rad, lat, 2e-15), "{lat} {}", g.lat_rad);
        assert!(close(g.lon_rad, lon, 2e-15));
        assert!(close(g.h, h, 2e-8), "{h} {}", g.h);
    }
}

#[test]
fn reverse_on_the_z_axis_and_at_the_center() {
    let e = Ellipsoid::<f64>::wgs84();
    let g = e.ecef_to_geodetic(V3::new(0.0, 0.0, 7.0e6));
    assert_eq!((g.lat_rad, g.lon_rad), (core::f64::consts::FRAC_PI_2, 0.0));
    assert!(close(g.h, 7.0e6 - e.b(), 1e-8));
    let g = e.ecef_to_geodetic(V3::new(0.0, 0.0, -100.0));
    assert_eq!(g.lat_rad, -core::f64::consts::FRAC_PI_2);
    assert!(close(g.h, 100.0 - e.b(), 1e-8));
    // The center: nearest surface points are the poles, h = −b.
    let g = e.ecef_to_geodetic(V3::new(0.0, 0.0, 0.0));
    assert!(close(g.h, -e.b(), 1e-8), "{}", g.h);
    assert!(close(g.lat_rad.abs(), core::f64::consts::FRAC_PI_2, 1e-12));
}

#[test]
fn reverse_inside_the_evolute_on_the_equatorial_plane() {
    // R = N e² cos ψ, h = −N(1 − e²): take ψ = 30°.
    let e = Ellipsoid::<f64>::wgs84();
    let (s, c) = (0.5_f64, 0.75_f64.sqrt());
    let n = e.prime_vertical_radius(s);
    let g = e.ecef_to_geodetic(V3::new(n * e.e2() * c, 0.0, 0.0));
    assert!(
        close(g.lat_rad.abs(), core::f64::consts::FRAC_PI_6, 1e-9),
        "{}",
        g.lat_rad
    );
    assert!(close(g.h, -n * (1.0 - e.e2()), 1e-6));
}

#[test]
fn reverse_sphere_is_geocentric() {
    let e = Ellipsoid::new(10.0_f64, 10.0).unwrap();
    let g = e.ecef_to_geodetic(V3::new(3.0, 4.0, 12.0));
    assert!(close(g.h, 3.0, 1e-14));
    // libm, not std: Miri perturbs std's transcendental results by a few ulps.
    assert!(close(g.lat_rad, libm::atan2(12.0, 5.0), 1e-15));
}

#[test]
fn reverse_f32_is_close() {
    let e = Ellipsoid::<f32>::wgs84();
    let p = e.geodetic_rad_to_ecef(0.7, 0.2, 100.0);
    let g = e.ecef_to_geodetic(p);
    assert!(
        (g.lat_rad - 0.7).abs() < 1e-6 && (g.h - 100.0).abs() < 2.0,
        "{g:?}"
    );
}

#[test]
fn latitude_cone_contains_the_normal_line() {
    let e = Ellipsoid::<f64>::wgs84();
    let (s, c) = sin_cos_deg(52.0);
    let cone = e.latitude_cone(s, c).unwrap();
    let (xp, zp) = e.x_z_psi(s, c);
    // X_ψ, Z_ψ and the apex are collinear along the normal (eq. 3.4-1: k = Z − X tan ψ).
    assert!(close(cone.apex_z(), zp - xp * s / c, 1e-6));
    // A point on the normal line at height 3000 m lies on the cone; 1 m further north is on the negative side.
    let on = e.geodetic_deg_to_ecef(52.0, 10.0, 3000.0);
    let n = e.normal_rad(52.0_f64.to_radians(), 10.0_f64.to_radians());
    let north = V3::new(-s * n.x / c, -s * n.y / c, c);
    let inside = on.add_scaled(1.0, north);
    assert_eq!(cone.side_of(inside), Some(Side::Negative));
    assert_eq!(
        cone.side_of(on.add_scaled(-1.0, north)),
        Some(Side::Positive)
    );
}

#[test]
fn typed_errors() {
    assert_eq!(Ellipsoid::new(1.0, 2.0), Err(GeodesyError::BadAxes));
    assert_eq!(Ellipsoid::new(f64::NAN, 2.0), Err(GeodesyError::NonFinite));
    let e = Ellipsoid::<f64>::wgs84();
    assert_eq!(
        e.latitude_cone(0.0, -1.0),
        Err(GeodesyError::LatitudeOutOfRange)
    );
    assert_eq!(meridian_rad(f64::INFINITY), Err(GeodesyError::NonFinite));
}

#[test]
fn meridian_side_is_east() {
    let m = meridian_deg(10.0_f64).unwrap();
    let e = Ellipsoid::<f64>::wgs84();
    assert_eq!(
        m.side_of(e.geodetic_deg_to_ecef(0.0, 11.0, 0.0)),
        Some(Side::Positive)
    );
    assert_eq!(
        m.side_of(e.geodetic_deg_to_ecef(0.0, 9.0, 0.0)),
        Some(Side::Negative)
    );
}

/// `ecef_to_geodetic_near` against the closed form (Vermeille's, `ecef_to_geodetic`): points from pole to pole,
/// either side of the antimeridian, from 400 m below the ellipsoid to 100 km above it, each seeded at itself,
/// one 3″ cell away, 1/3° away and 1° away in both coordinates, either way, with the seeds' longitudes in
/// (−180°, 180°] (Newton's steps and the longitude's series carry the difference). Both agree to 1e-13° (about
/// 11 nm) and 2e-8 m in height (measured: 2.1e-14°, about an ulp of the angle, and 3.2e-9 m); a seed beyond the
/// 0.02 rad steps gives `None`.
#[test]
fn reverse_seeded_near_agrees_with_the_closed_form_from_pole_to_pole_and_across_the_antimeridian() {
    let e = Ellipsoid::<f64>::wgs84();
    let mut worst = [0.0f64; 3];
    for lat in [-89.5, -60.25, -30.0, -0.001, 0.0, 15.5, 45.0004, 75.0, 89.2] {
        for lon in [-179.9995, -117.9993, 0.0, 0.004, 90.5, 179.9993] {
            for h in [-400.0, 0.0, 812.3, 8848.0, 1.0e5] {
                let p = e.geodetic_deg_to_ecef(lat, lon, h);
                let g = e.ecef_to_geodetic(p);
                let (lat_c, lon_c) = (g.lat_rad.to_degrees(), g.lon_rad.to_degrees());
                // seeds east and west of the point, their longitudes in (−180°, 180°] (so that the seeded sum
                // passes ±180° next to the antimeridian)
                for d in [
                    0.0,
                    1.0 / 1200.0,
                    -1.0 / 1200.0,
                    1.0 / 3.0,
                    -1.0 / 3.0,
                    1.0,
                    -1.0,
                ] {
                    let lat0 = (lat - d).clamp(-89.99, 89.99);
                    let lon0 = match lon + d {
                        x if x > 180.0 => x - 360.0,
                        x if x <= -180.0 => x + 360.0,
                        x => x,
                    };
                    let (sl, cl) = sin_cos_deg(lat0);
                    let (so, co) = sin_cos_deg(lon0);
                    let near = e.ecef_to_geodetic_near(p, (lat0, sl, cl), (lon0, so, co));
                    assert!(
                        near.is_some(),
                        "{lat} {lon} {h} seeded at {lat0} {lon0}: None"
                    );
                    let (la, lo, hh) = near.unwrap();
                    let dlon = match lo - lon_c {
                        x if x > 180.0 => x - 360.0,
                        x if x < -180.0 => x + 360.0,
                        x => x,
                    };
                    let err = [(la - lat_c).abs(), dlon.abs(), (hh - g.h).abs()];
                    for (w, x) in worst.iter_mut().zip(err) {
                        *w = w.max(x);
                    }
                    assert!(
                        err[0] <= 1e-13 && err[1] <= 1e-13 && err[2] <= 2e-8,
                        "{lat} {lon} {h} seeded at {lat0} {lon0}: {err:?}"
                    );
                    assert!(lo > -180.0 && lo <= 180.0, "{lo}");
                }
            }
        }
    }
    std::println!("seeded against closed form: worst |Δlat|, |Δlon| (deg), |Δh| (m): {worst:?}");
    // Seeds too far: 1.5° off in longitude (beyond 0.02 rad), and in latitude.
    let p = e.geodetic_deg_to_ecef(45.0, 10.0, 100.0);
    let (sl, cl) = sin_cos_deg(45.0);
    let (so, co) = sin_cos_deg(11.5);
    assert_eq!(
        e.ecef_to_geodetic_near(p, (45.0, sl, cl), (11.5, so, co)),
        None
    );
    let (sl, cl) = sin_cos_deg(46.5);
    let (so, co) = sin_cos_deg(10.0);
    assert_eq!(
        e.ecef_to_geodetic_near(p, (46.5, sl, cl), (10.0, so, co)),
        None
    );
}
