//! The relaxed volume's walls where they decide the hull: its ends against the crossings of the walls the
//! docs name, with the tolerances they state.

use super::*;
use crate::geodesy::sin_cos_deg;

const TAU: f64 = 64.0 * f64::EPSILON;

/// A quad over 1° × 1° of WGS84 at heights −100 to 500 m, cells of 0.01°.
fn small_quad() -> (Ellipsoid<f64>, QuadTrig<f64>) {
    (
        Ellipsoid::wgs84(),
        QuadTrig::from_degrees(10.0, 11.0, 20.0, 21.0, 0.01),
    )
}

/// 60 km along the normal at the quad's middle (10.5°, 20.5°) from height `h`, down or up.
fn along_the_normal(e: &Ellipsoid<f64>, h: f64, down: bool) -> Ray<f64> {
    let n = e.normal_deg(10.5, 20.5);
    let dir = if down { n.negated() } else { n };
    Ray::new(e.geodetic_deg_to_ecef(10.5, 20.5, h), dir)
        .unwrap()
        .with_interval(0.0, 6.0e4)
        .unwrap()
}

/// The small quad's relaxed hull of `ray`, for heights −100 to 500 m.
fn relaxed_hull(e: &Ellipsoid<f64>, trig: &QuadTrig<f64>, ray: &Ray<f64>) -> Option<(f64, f64)> {
    relaxed_interval(e, trig, -100.0, 500.0, 0.01, 0.01, ray).unwrap()
}

/// The parameters where the ray (unit direction) is at distance `r` from the centre, nearer first.
fn sphere_roots(ray: &Ray<f64>, r: f64) -> (f64, f64) {
    let (o, d) = (ray.origin(), ray.dir());
    let od = o.dot(d);
    let root = (od * od - o.length_squared() + r * r).sqrt();
    (-od - root, -od + root)
}

#[test]
fn a_vertical_ray_down_ends_where_it_meets_the_lower_sphere_shrunk_by_the_slack() {
    let (e, trig) = small_quad();
    let volume = RelaxedVolume::new(&e, &trig, -100.0, 500.0, 0.01, 0.01).unwrap();
    let ray = along_the_normal(&e, 1.0e4, true);
    let (lo, hi) = relaxed_hull(&e, &trig, &ray).unwrap();
    assert_eq!(volume.interval(&ray), Some((lo, hi)));
    // Enters B^500 about 9.5 km down the ray (no more than that: B^h lies outside the parallel surface).
    assert!(lo > 9490.0 && lo <= 9500.0 + 1e-6, "{lo}");
    // Leaves the volume at the lower sphere, b − 100 m less the sagitta, shrunk by the rounding of the ray's
    // points over [lo, t_max] (the upper spheroid does not end the segment before it).
    let lower = volume.lower_r - ray_point_slack(&ray, lo, 6.0e4);
    let (enter, _) = sphere_roots(&ray, lower);
    assert!((hi - enter).abs() < 2.0e-8, "{hi} against {enter}");
}

#[test]
fn a_vertical_ray_up_from_inside_the_lower_sphere_begins_where_it_leaves_it() {
    let (e, trig) = small_quad();
    // 30 km below the surface at 10.5° is inside the sphere of radius about b.
    let ray = along_the_normal(&e, -3.0e4, false);
    let (lo, hi) = relaxed_hull(&e, &trig, &ray).unwrap();
    // It leaves B^500 about 30.5 km up.
    assert!(hi > 3.04e4 && hi < 3.06e4, "{hi}");
    let volume = RelaxedVolume::new(&e, &trig, -100.0, 500.0, 0.01, 0.01).unwrap();
    let lower = volume.lower_r - ray_point_slack(&ray, 0.0, hi);
    let (_, leave) = sphere_roots(&ray, lower);
    assert!((lo - leave).abs() < 2.0e-8, "{lo} against {leave}");
    // Wholly inside the lower sphere: no hull.
    let deep = ray.with_interval(0.0, 1.0e3).unwrap();
    assert_eq!(
        relaxed_interval(&e, &trig, -100.0, 500.0, 0.01, 0.01, &deep),
        Ok(None)
    );
}

#[test]
fn a_ray_with_an_infinite_end_has_no_relaxed_hull() {
    let (e, trig) = small_quad();
    let n = e.normal_deg(10.5, 20.5);
    let ray = Ray::new(e.geodetic_deg_to_ecef(10.5, 20.5, 1.0e4), n.negated()).unwrap();
    assert_eq!(ray.t_max(), f64::INFINITY);
    assert_eq!(
        relaxed_interval(&e, &trig, -100.0, 500.0, 0.01, 0.01, &ray),
        Ok(None)
    );
    let volume = RelaxedVolume::new(&e, &trig, -100.0, 500.0, 0.01, 0.01).unwrap();
    assert_eq!(volume.interval(&ray), None);
}

#[test]
fn a_half_turn_quad_is_tested_against_its_full_volume() {
    // 180° exactly: the wedge is not convex, so no chord planes; the full volume's hull.
    let e = Ellipsoid::<f64>::wgs84();
    let trig = QuadTrig::from_degrees(10.0, 30.0, -90.0, 90.0, 0.5);
    let full = HeightQuadBounds::from_trig(&e, &trig, 0.0, 2000.0, 0.5, 0.5).unwrap();
    let mut hulls = 0;
    for (lat, lon) in [(20.0, 0.0), (15.0, -80.0), (25.0, 60.0)] {
        let n = e.normal_deg(lat, lon);
        let ray = Ray::new(e.geodetic_deg_to_ecef(lat, lon, 1.0e4), n.negated())
            .unwrap()
            .with_interval(0.0, 2.0e4)
            .unwrap();
        let hull = full.ray_interval(&ray);
        hulls += usize::from(hull.is_some());
        assert_eq!(
            relaxed_interval(&e, &trig, 0.0, 2000.0, 0.5, 0.5, &ray),
            Ok(hull)
        );
    }
    assert_eq!(hulls, 3);
    // A chord at 1 km from 35° to 31° north, beside the quad: under its height walls, but north of its
    // latitude walls all along.
    let north = Ray::segment(
        e.geodetic_deg_to_ecef(35.0, 0.0, 1.0e3),
        e.geodetic_deg_to_ecef(31.0, 0.0, 1.0e3),
    )
    .unwrap();
    assert_eq!(full.ray_interval(&north), None);
    assert_eq!(
        relaxed_interval(&e, &trig, 0.0, 2000.0, 0.5, 0.5, &north),
        Ok(None)
    );
}

#[test]
fn the_middle_meridians_half_span_cosine_is_lowered_by_8_eps() {
    for (w, e, half) in [
        (20.0, 50.0, 15.0),
        (-170.0, 5.0, 87.5),
        (0.0, 0.5, 0.25),
        (-30.0, 30.0, 30.0),
    ] {
        let trig = QuadTrig::from_degrees(0.0, 1.0, w, e, 0.01);
        let (cm, sm, ch) = middle_meridian(&trig);
        let (s, c) = sin_cos_deg((w + e) / 2.0);
        assert!(
            (cm - c).abs() <= 4.0 * f64::EPSILON && (sm - s).abs() <= 4.0 * f64::EPSILON,
            "{w}..{e}"
        );
        let exact = sin_cos_deg(half).1;
        let lowered = (exact - ch) / f64::EPSILON;
        assert!(
            (4.0..=12.0).contains(&lowered),
            "{w}..{e}: {lowered} ε below"
        );
    }
}

/// The flattened quad of the bounds' tests (b = a/2: the cones' apexes millions of metres from the centre) and
/// its latitude walls.
fn flat_walls() -> (QuadTrig<f64>, WallApex<f64>, WallApex<f64>) {
    let e = Ellipsoid::new(6.0e6, 3.0e6).unwrap();
    let trig = QuadTrig::from_degrees(30.0, 45.0, 20.0, 50.0, 0.01);
    let lat = LatitudeParts::new(&e, &trig, -500.0, 500.0, 0.01, 0.01).unwrap();
    (trig, lat.south.unwrap(), lat.north.unwrap())
}

#[test]
fn a_latitude_plane_clips_the_ray_at_64_eps_of_the_coordinates_apex_and_farthest_step_beyond_it() {
    // The south wall of a northern quad is replaced by its tangent plane along the middle meridian,
    // g = (z − k) cos ψ − sin ψ (x cos λm + y sin λm) ≥ 0; a ray along g's unit gradient from 1 km below
    // it is clipped where g = −tol.
    let (trig, south, _) = flat_walls();
    let (cm, sm, ch) = middle_meridian(&trig);
    let grad = V3::new(-south.sin * cm, -south.sin * sm, south.cos);
    let g = |p: V3<f64>| south.cos * (p.z - south.apex) - south.sin * (cm * p.x + sm * p.y);
    // A point of the plane about over the wall (radial 5.8e6 m, z 0.8e6 m), then 1 km below it.
    let on = V3::new(5.8e6 * cm, 5.8e6 * sm, 0.8e6);
    let on = on.add_scaled(-g(on), grad);
    let o = on.add_scaled(-1.0e3, grad);
    for t_max in [2.0e3, 1.0e6, 4.0e6] {
        let ray = Ray::new(o, grad)
            .unwrap()
            .with_interval(0.0, t_max)
            .unwrap();
        let (mut lo, mut hi) = (0.0, t_max);
        assert!(clip_latitude_planes(
            &mut lo,
            &mut hi,
            &ray,
            (cm, sm, ch),
            Some(south),
            None
        ));
        let d1 = grad.x.abs() + grad.y.abs() + grad.z.abs();
        let qz = o.z - south.apex;
        let tol = TAU * (o.x.abs() + o.y.abs() + qz.abs() + south.apex.abs() + d1 * t_max);
        let expected = (-tol - g(o)) / grad.dot(grad);
        assert!(
            (lo - expected).abs() < 5.0e-9,
            "t_max {t_max}: {lo} against {expected} (tol {tol})"
        );
        assert_eq!(hi, t_max);
    }
}

#[test]
fn without_a_half_span_cosine_only_the_tangent_plane_clips() {
    // cos(Δλ/2) rounded to 0 or below (a span within rounding of 180°): the chord plane is left out, the
    // tangent plane kept. A ray on the far side of the axis from the middle meridian is outside both.
    let (_, south, north) = flat_walls();
    let ray = Ray::new(V3::new(-1.0e6, -2.0e6, 1.0e5), V3::new(0.0, 1.0, 0.0))
        .unwrap()
        .with_interval(0.0, 4.0e6)
        .unwrap();
    for ch in [0.0, -1.0e-17] {
        let (mut lo, mut hi) = (0.0, 4.0e6);
        assert!(clip_latitude_planes(
            &mut lo,
            &mut hi,
            &ray,
            (1.0, 0.0, ch),
            None,
            Some(north)
        ));
        assert_eq!(
            (lo, hi),
            (0.0, 4.0e6),
            "the north wall's chord plane left out ({ch})"
        );
        let (mut lo, mut hi) = (0.0, 4.0e6);
        let below = Ray::new(
            V3::new(1.0e6, -2.0e6, south.apex - 1.0e6),
            V3::new(0.0, 1.0, 0.0),
        )
        .unwrap()
        .with_interval(0.0, 4.0e6)
        .unwrap();
        assert!(!clip_latitude_planes(
            &mut lo,
            &mut hi,
            &below,
            (1.0, 0.0, ch),
            Some(south),
            None
        ));
    }
    // With the walls on (a span of 30°) the same first ray is clipped away by the chord plane.
    let trig = QuadTrig::from_degrees(30.0, 45.0, -15.0, 15.0, 0.01);
    let middle = middle_meridian(&trig);
    let (mut lo, mut hi) = (0.0, 4.0e6);
    assert!(!clip_latitude_planes(
        &mut lo,
        &mut hi,
        &ray,
        middle,
        None,
        Some(north)
    ));
}
