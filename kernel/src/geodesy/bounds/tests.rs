use super::*;
use crate::geodesy::relaxed::{RelaxedVolume, relaxed_interval};

mod magnitudes;

#[test]
fn sagitta_of_a_chord_on_the_sphere_is_bounded() {
    // Sphere of radius R: a chord of length D between two points at height 0 dips by
    // R − sqrt(R² − D²/4) ≈ D²/(8R); the bound (for triangles, D²/(6R)) must exceed it.
    let r = 6.4e6_f64;
    let e = Ellipsoid::new(r, r).unwrap();
    for &d in &[10.0, 1000.0, 1.0e5] {
        let true_dip = r - (r * r - d * d / 4.0).sqrt();
        let s = chord_sagitta_bound(&e, d, 0.0).unwrap();
        assert!(s >= true_dip, "{d}: {s} < {true_dip}");
        assert!(s <= 2.0 * true_dip, "{d}: bound too loose");
    }
    // Equilateral triangle inscribed in a circle of radius ρ = D/√3: its centroid dips by
    // R − sqrt(R² − ρ²) ≈ D²/(6R), which the bound matches to first order.
    let d = 1.0e5;
    let dip = r - (r * r - d * d / 3.0).sqrt();
    let s = chord_sagitta_bound(&e, d, 0.0).unwrap();
    assert!(s >= dip && s <= dip * 1.01, "{s} vs {dip}");
}

#[test]
fn sagitta_rejects_depth_near_evolute() {
    let e = Ellipsoid::<f64>::wgs84();
    assert_eq!(
        chord_sagitta_bound(&e, 1.0e6, e.min_height() - 10.0),
        Err(GeodesyError::HeightTooLow)
    );
    // Just above −b²/a, a 1000 km chord is already beyond √1.5 (b²/a + h_min).
    assert_eq!(
        chord_sagitta_bound(&e, 1.0e6, e.min_height() + 10.0),
        Err(GeodesyError::TriangleTooLarge)
    );
    assert_eq!(
        HeightQuadBounds::new(&e, 0.0, 1.0, 0.0, 1.0, -7.0e6, 0.0, 0.1, 0.1),
        Err(GeodesyError::HeightTooLow)
    );
}

#[test]
fn upper_bound_eq_3_1_2_1_contains_the_true_parallel_surface() {
    let e = Ellipsoid::<f64>::wgs84();
    for &h in &[0.0, 8848.0, 1.0e5, -1.0e4, -5.0e6] {
        let q = HeightQuadBounds::new(&e, -90.0, 90.0, -180.0, 180.0, h, h, 1.0, 1.0).unwrap();
        for k in 0..=90 {
            let lat = -90.0 + 2.0 * k as f64;
            let p = e.geodetic_deg_to_ecef(lat, 10.0, h);
            assert!(q.contains(p), "h = {h}, lat = {lat}");
        }
    }
}

#[test]
fn bulging_triangle_at_80_degrees_is_inside_the_inflated_wall() {
    // A coarse (1°) cell along the north border at 80°: the midpoint of the border edge lies north of the
    // cone (the containment problem) but inside the inflated wall.
    let e = Ellipsoid::<f64>::wgs84();
    let q = HeightQuadBounds::new(&e, 79.0, 80.0, 10.0, 11.0, 0.0, 0.0, 1.0, 1.0).unwrap();
    let v0 = e.geodetic_deg_to_ecef(80.0, 10.0, 0.0);
    let v1 = e.geodetic_deg_to_ecef(80.0, 11.0, 0.0);
    let mid = v0.plus(v1).scaled(0.5);
    let g = e.ecef_to_geodetic(mid);
    assert!(
        g.lat_rad.to_degrees() > 80.0,
        "the chord bulges north of the wall"
    );
    assert!(q.contains(mid));
    // The uninflated cone excludes it.
    let (s, c) = sin_cos_deg(80.0);
    let cone = e.latitude_cone(s, c).unwrap();
    assert_eq!(cone.side_of(mid), Some(crate::surface::Side::Negative));
}

#[test]
fn radial_ray_interval_matches_heights() {
    let e = Ellipsoid::<f64>::wgs84();
    let q = HeightQuadBounds::new(&e, 10.0, 11.0, 20.0, 21.0, -100.0, 500.0, 0.01, 0.01).unwrap();
    let n = e.normal_rad(10.5_f64.to_radians(), 20.5_f64.to_radians());
    let top = e.geodetic_deg_to_ecef(10.5, 20.5, 10_000.0);
    let ray = Ray::new(top, n.negated())
        .unwrap()
        .with_interval(0.0, 20_000.0)
        .unwrap();
    let (t_in, t_out) = q.ray_interval(&ray).unwrap();
    // Enters B^500 at about 9500 m (B^h is slightly outside TB^h), leaves below −100 m.
    assert!(t_in > 9490.0 && t_in <= 9500.0 + 1e-6, "{t_in}");
    assert!(t_out >= 10_100.0, "{t_out}");
    // A ray passing outside the wedge misses.
    let far = e.geodetic_deg_to_ecef(10.5, 25.0, 10_000.0);
    let miss = Ray::new(far, n.negated())
        .unwrap()
        .with_interval(0.0, 20_000.0)
        .unwrap();
    assert_eq!(q.ray_interval(&miss), None);
}

#[test]
fn volume_entered_twice_yields_one_hull_over_both_visits() {
    // The band 70°..80° (all longitudes, so no wedge) at heights 0..400 km: a segment over the polar cap
    // from (75°, 0°, 300 km) to (75°, 180°, 300 km) starts in the band, crosses the cap north of 80° (outside
    // the band, but above the ground) and enters the band again on the far side.
    let e = Ellipsoid::<f64>::wgs84();
    let q = HeightQuadBounds::new(&e, 70.0, 80.0, -180.0, 180.0, 0.0, 4.0e5, 0.5, 0.5).unwrap();
    let a = e.geodetic_deg_to_ecef(75.0, 0.0, 3.0e5);
    let b = e.geodetic_deg_to_ecef(75.0, 180.0, 3.0e5);
    let ray = Ray::segment(a, b).unwrap();
    let (t_in, t_out) = q.ray_interval(&ray).unwrap();
    // Both visits lie in the hull, and the middle of the chord is outside the band (north of 80°).
    assert!(q.contains(V3::from(ray.at(0.0))) && q.contains(V3::from(ray.at(1.0))));
    assert!(!q.contains(V3::from(ray.at(0.5))));
    assert!(t_in <= 1e-12 && t_out >= 1.0 - 1e-12, "{t_in} {t_out}");
    // The gap between the two visits is the latitude wall's doing: the middle is above ground, north of 80°.
    let mid = e.ecef_to_geodetic(V3::from(ray.at(0.5)));
    assert!(
        mid.lat_rad.to_degrees() > 80.0 && mid.h > 0.0 && mid.h < 4.0e5,
        "{mid:?}"
    );
}

#[test]
#[cfg_attr(miri, ignore)]
fn hull_covers_every_sampled_point_inside_the_volume() {
    // Quads from the equator to the poles (wide and narrow wedges, negative heights), rays from above, from
    // below and grazing: every sample the point test puts inside lies in the two-stage hull, and the hull is
    // not looser than the samples by more than one step at either end.
    let e = Ellipsoid::<f64>::wgs84();
    let mut rnd = crate::test_util::xorshift_uniform(0x9e37_79b9_7f4a_7c15);
    let mut checked = 0;
    for _ in 0..300 {
        let lat_s = -90.0 + 170.0 * rnd();
        let lat_n = (lat_s + 0.01 + 20.0 * rnd()).min(90.0);
        let lon_w = -180.0 + 360.0 * rnd();
        let lon_e = lon_w + 0.01 + 200.0 * rnd();
        let h_lo = -500.0 + 1000.0 * rnd();
        let h_hi = h_lo + 5000.0 * rnd();
        let Ok(q) = HeightQuadBounds::new(&e, lat_s, lat_n, lon_w, lon_e, h_lo, h_hi, 0.1, 0.1)
        else {
            continue;
        };
        let (lat, lon) = (
            lat_s + (lat_n - lat_s) * rnd(),
            lon_w + (lon_e - lon_w) * rnd(),
        );
        let target = e.geodetic_deg_to_ecef(lat, lon, h_lo + (h_hi - h_lo) * rnd());
        let from = e.geodetic_deg_to_ecef(
            lat + 4.0 * (rnd() - 0.5),
            lon + 4.0 * (rnd() - 0.5),
            -2.0e4 + 1.0e5 * rnd(),
        );
        let ray = Ray::segment(from, target.add_scaled(1.0, target.minus(from))).unwrap();
        let hull = q.ray_interval(&ray);
        // The traversal's relaxed child test, with all walls and with a random subset of them.
        let mut trig = QuadTrig::from_degrees(lat_s, lat_n, lon_w, lon_e, 0.1);
        let relaxed_all = relaxed_interval(&e, &trig, h_lo, h_hi, 0.1, 0.1, &ray).unwrap();
        trig.walls = SideWalls {
            west: rnd() < 0.5,
            east: rnd() < 0.5,
            south: rnd() < 0.5,
            north: rnd() < 0.5,
        };
        let relaxed_some = relaxed_interval(&e, &trig, h_lo, h_hi, 0.1, 0.1, &ray).unwrap();
        // The volume formed once (a picker's zones) gives the same interval as the lazy test.
        let formed = RelaxedVolume::new(&e, &trig, h_lo, h_hi, 0.1, 0.1).unwrap();
        assert_eq!(formed.interval(&ray), relaxed_some);
        let n = 400;
        let inside: std::vec::Vec<f64> = (0..=n)
            .map(|k| k as f64 / n as f64)
            .filter(|&t| q.contains(V3::from(ray.at(t))))
            .collect();
        let (Some(&a), Some(&b)) = (inside.first(), inside.last()) else {
            continue;
        };
        assert!(hull.is_some(), "no hull, but t = {a} is inside");
        let (t_in, t_out) = hull.unwrap();
        checked += 1;
        assert!(
            t_in <= a && b <= t_out,
            "hull {t_in}..{t_out} misses {a}..{b}"
        );
        assert!(t_in >= a - 1.0 / n as f64 && t_out <= b + 1.0 / n as f64);
        for (what, r) in [("all walls", relaxed_all), ("some walls", relaxed_some)] {
            assert!(
                r.is_some_and(|(lo, hi)| lo <= a && b <= hi),
                "relaxed ({what}) {r:?} misses {a}..{b}"
            );
        }
    }
    assert!(checked > 100, "{checked}");
}
