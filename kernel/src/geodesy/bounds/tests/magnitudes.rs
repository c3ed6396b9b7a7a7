//! The bounds' values against their derivations (module docs, items 2–4) and each point test's tolerance from
//! both sides: a point a little inside the inflation of a wall is in the volume, one a little beyond it is not.

use super::*;

const EPS: f64 = f64::EPSILON;
/// The point tests' relative inflation, `64 ε`.
const TAU: f64 = 64.0 * EPS;

/// Where a point is put, in units of a test's tolerance beyond its wall, and whether it passes: on the wall, within
/// the inflation and beyond it.
const SIDES: [(f64, bool); 5] = [
    (0.0, true),
    (0.6, true),
    (0.8, true),
    (1.25, false),
    (2.0, false),
];

/// `x` lies in `[lo (1 + 8ε), lo (1 + 32ε)]`: a value with the bounds' `16 ε` margin over `lo`.
fn with_margin(x: f64, lo: f64) -> bool {
    x >= lo * (1.0 + 8.0 * EPS) && x <= lo * (1.0 + 32.0 * EPS)
}

#[test]
fn sagitta_bound_is_the_simple_one_above_its_depth_and_the_smaller_root_with_its_margin_below() {
    let e = Ellipsoid::<f64>::wgs84();
    let (a, b) = (e.a(), e.b());
    for &d in &[1.0, 100.0, 1.0e4, 1.0e5] {
        let d2 = d * d;
        // Lowest point at or above the ellipsoid: L = a/b², the bound L D²/6 as it stands.
        let simple = (a / (b * b)) * d2 / 6.0;
        for &h in &[simple, simple + 1.0e3, 1.0e5] {
            let s = chord_sagitta_bound(&e, d, h).unwrap();
            assert!(
                (s - simple).abs() <= 4.0 * EPS * simple,
                "d {d}, h {h}: {s} against {simple}"
            );
        }
        // Below: the smaller root of s (c − s) = D²/6, c = b²/a + h_min, formed without cancellation.
        for &h in &[0.0, -1.0e3, -1.0e5, -5.0e6] {
            let c = b * (b / a) + h;
            let root = (d2 / 3.0) / (c + (c * c - 2.0 * d2 / 3.0).sqrt());
            let s = chord_sagitta_bound(&e, d, h).unwrap();
            assert!(with_margin(s, root), "d {d}, h {h}: {s} against {root}");
        }
    }
}

#[test]
fn sagitta_bound_refuses_non_finite_input_the_evolute_height_and_a_chord_at_its_limit() {
    let e = Ellipsoid::<f64>::wgs84();
    for (d, h) in [
        (f64::NAN, 0.0),
        (f64::INFINITY, 0.0),
        (1.0, f64::NAN),
        (1.0, f64::NEG_INFINITY),
    ] {
        assert_eq!(
            chord_sagitta_bound(&e, d, h),
            Err(GeodesyError::NonFinite),
            "{d} {h}"
        );
    }
    // At exactly h = −b²/a, c = 0: no bound.
    assert_eq!(
        chord_sagitta_bound(&e, 1.0, e.min_height()),
        Err(GeodesyError::HeightTooLow)
    );
    // A chord exactly at the limit d = √1.5 c: on the unit sphere with h = 2, c = 3 and this d has d² = 13.5
    // exactly, so c² − 2d²/3 is exactly 0; one ulp shorter has a bound.
    let unit = Ellipsoid::new(1.0, 1.0).unwrap();
    let d = 3.674_234_614_174_767_3_f64;
    assert_eq!(d * d, 13.5);
    assert_eq!(
        chord_sagitta_bound(&unit, d, 2.0),
        Err(GeodesyError::TriangleTooLarge)
    );
    let shorter = chord_sagitta_bound(&unit, d.next_down(), 2.0).unwrap();
    assert!(shorter > 1.49 && shorter < 1.5 + 1e-6, "{shorter}");
}

#[test]
fn upper_spheroid_has_the_axes_of_eq_3_1_2_1_either_side_of_the_ellipsoid_and_a_sphere_above_b() {
    let e = Ellipsoid::<f64>::wgs84();
    let (a, b) = (e.a(), e.b());
    let axes = |h: f64| {
        let u = upper_spheroid(&e, h).unwrap();
        (u.a(), u.b())
    };
    for h in [0.0, 8848.0, 1.0e5, b] {
        assert_eq!(axes(h), (a + h, b + h * (a / b)), "h = {h}");
    }
    for h in [-1.0e3, -1.0e6, 0.999 * e.min_height()] {
        assert_eq!(axes(h), (a + h * (b / a), b + h), "h = {h}");
    }
    // Above h = b the axes of eq. 3.1.2-1 would be prolate: the sphere of the larger one.
    let h = 2.0 * b;
    assert_eq!(axes(h), (b + h * (a / b), b + h * (a / b)));
    assert_eq!(
        upper_spheroid(&e, e.min_height()),
        Err(GeodesyError::HeightTooLow)
    );
    assert_eq!(upper_spheroid(&e, f64::NAN), Err(GeodesyError::NonFinite));
}

#[test]
fn latitude_bulge_bound_is_the_smoothness_bound_with_its_margin_and_infinite_off_the_axis_distance()
{
    for (sin, d, r) in [(0.5, 1.0e3, 6.0e6), (-0.9, 1.0e5, 1.0e6), (1.0, 10.0, 3.0)] {
        let exact = sin.abs() * d * d / (6.0 * r);
        let s = latitude_bulge_bound(sin, d, r);
        assert!(with_margin(s, exact), "{s} against {exact}");
    }
    // No distance to the axis: no bound, even where the numerator is 0.
    assert_eq!(latitude_bulge_bound(0.0, 0.0, 0.0), f64::INFINITY);
    assert_eq!(latitude_bulge_bound(0.5, 1.0, -1.0), f64::INFINITY);
}

#[test]
fn quad_trig_holds_its_boundaries_and_its_wedge_has_walls_below_180_degrees_only_where_asked() {
    let (sw, cw) = sin_cos_deg(20.0);
    let (se, ce) = sin_cos_deg(30.0);
    let mut t = QuadTrig::from_degrees(0.0, 10.0, 20.0, 30.0, 0.1);
    assert_eq!((t.west, t.east, t.span_deg), ((sw, cw), (se, ce), 10.0));
    assert_eq!((t.south, t.north), (sin_cos_deg(0.0), sin_cos_deg(10.0)));
    assert_eq!(t.cos_half_cell_dlon, sin_cos_deg(0.05).1);
    assert_eq!(
        QuadTrig::from_degrees(0.0, 1.0, 2.0, 3.0, -0.1).cos_half_cell_dlon,
        sin_cos_deg(0.05).1
    );
    assert_eq!(t.wedge(), Ok([Some((cw, sw)), Some((ce, se))]));
    t.walls.east = false;
    assert_eq!(t.wedge(), Ok([Some((cw, sw)), None]));
    t.walls = SideWalls {
        west: false,
        ..SideWalls::ALL
    };
    assert_eq!(t.wedge(), Ok([None, Some((ce, se))]));
    // A quad one meridian wide keeps both walls; from 180° on there are none.
    let line = QuadTrig::from_degrees(0.0, 10.0, 20.0, 20.0, 0.1);
    assert_eq!(line.wedge(), Ok([Some((cw, sw)), Some((cw, sw))]));
    for (w, e) in [(-90.0, 90.0), (-180.0, 180.0)] {
        assert_eq!(
            QuadTrig::from_degrees(0.0, 10.0, w, e, 0.1).wedge(),
            Ok([None, None])
        );
    }
    assert!(
        QuadTrig::from_degrees(0.0, 10.0, -90.0, 89.999, 0.1)
            .wedge()
            .unwrap()[0]
            .is_some()
    );
    // Longitudes at any multiple of 360° offset: a quad whose east boundary is 90° · 2¹⁰¹⁷ (sine and cosine exactly
    // 0 and 1) spans more than 180° and has no meridian walls; its trigonometry's sum stays finite.
    let e = Ellipsoid::<f64>::wgs84();
    let far_east = libm::scalbn(90.0, 1017); // exact (std's powi carries error under Miri)
    assert_eq!(sin_cos_deg(far_east), (0.0, 1.0));
    let wide = HeightQuadBounds::new(&e, 0.0, 10.0, 0.0, far_east, 0.0, 100.0, 1.0, 1.0).unwrap();
    assert_eq!(wide.wedge, [None, None]);
    // A pole is on every meridian wall: a polar quad holds it, whatever its wedge.
    let polar = HeightQuadBounds::new(&e, 80.0, 90.0, 10.0, 20.0, 0.0, 500.0, 0.1, 0.1).unwrap();
    let pole = e.geodetic_deg_to_ecef(90.0, 15.0, 100.0);
    assert_eq!((pole.x, pole.y), (0.0, 0.0));
    assert!(polar.contains(pole));
    let backwards = QuadTrig::from_degrees(0.0, 10.0, 30.0, 20.0, 0.1);
    assert_eq!(backwards.wedge(), Err(GeodesyError::NonFinite));
    for k in 0..5 {
        let mut bad = QuadTrig::from_degrees(0.0, 10.0, 20.0, 30.0, 0.1);
        match k {
            0 => bad.west.0 = f64::NAN,
            1 => bad.west.1 = f64::INFINITY,
            2 => bad.east.0 = f64::NEG_INFINITY,
            3 => bad.east.1 = f64::NAN,
            _ => bad.span_deg = f64::INFINITY,
        }
        assert_eq!(bad.wedge(), Err(GeodesyError::NonFinite), "field {k}");
    }
}

/// A quad of a strongly flattened ellipsoid (b = a/2, so that the latitude cones' apexes lie millions of metres
/// from the centre, as far as the points of the walls are from the axis): latitudes 30° to 45°, longitudes 20° to
/// 50°, heights −500 to 500 m, cells of 0.01°.
fn flat_quad() -> (Ellipsoid<f64>, HeightQuadBounds<f64>) {
    let e = Ellipsoid::new(6.0e6, 3.0e6).unwrap();
    let q = HeightQuadBounds::new(&e, 30.0, 45.0, 20.0, 50.0, -500.0, 500.0, 0.01, 0.01).unwrap();
    (e, q)
}

/// `p` moved along `n`, the unit gradient of `value`, until `value(p)` is `target` (two linear steps).
fn moved_to(p: V3<f64>, n: V3<f64>, target: f64, value: impl Fn(V3<f64>) -> f64) -> V3<f64> {
    let p = p.add_scaled(target - value(p), n);
    p.add_scaled(target - value(p), n)
}

#[test]
fn meridian_walls_let_a_point_in_within_64_eps_of_its_x_and_y_and_no_further() {
    let (e, q) = flat_quad();
    let [west, east] = q.wedge;
    let ((cw, sw), (ce, se)) = (west.unwrap(), east.unwrap());
    let tol = |p: V3<f64>| TAU * (p.x.abs() + p.y.abs());
    // Inside where c·y − s·x ≥ 0 for the western wall, ≤ 0 for the eastern; its gradient is (−s, c, 0).
    let west = |p: V3<f64>| cw * p.y - sw * p.x;
    let on_west = e.geodetic_deg_to_ecef(40.0, 20.0, 0.0);
    let out_west = V3::new(-sw, cw, 0.0);
    let east = |p: V3<f64>| ce * p.y - se * p.x;
    let on_east = e.geodetic_deg_to_ecef(40.0, 50.0, 0.0);
    let out_east = V3::new(-se, ce, 0.0);
    for k in [0.0, 0.6, 0.8] {
        let p = moved_to(on_west, out_west, -k * tol(on_west), west);
        assert!(
            q.contains(p),
            "{k} of the tolerance west of the western wall"
        );
        let p = moved_to(on_east, out_east, k * tol(on_east), east);
        assert!(
            q.contains(p),
            "{k} of the tolerance east of the eastern wall"
        );
    }
    for k in [1.25, 2.0, 1.0e6] {
        let p = moved_to(on_west, out_west, -k * tol(on_west), west);
        assert!(
            !q.contains(p),
            "{k} of the tolerance west of the western wall"
        );
        let p = moved_to(on_east, out_east, k * tol(on_east), east);
        assert!(
            !q.contains(p),
            "{k} of the tolerance east of the eastern wall"
        );
    }
}

#[test]
fn latitude_walls_let_a_point_in_within_64_eps_of_z_apex_and_axis_distance_plus_the_slack_and_no_further()
 {
    let (e, q) = flat_quad();
    let (south, north) = (q.south.unwrap(), q.north.unwrap());
    // f's gradient is the unit vector (−sin ψ x/r, −sin ψ y/r, cos ψ): toward higher latitude.
    let up = |w: &LatWall<f64>, p: V3<f64>| {
        let r = (p.x * p.x + p.y * p.y).sqrt();
        V3::new(-w.sin * p.x / r, -w.sin * p.y / r, w.cos)
    };
    for (w, lat, outward) in [(south, 30.0, -1.0), (north, 45.0, 1.0)] {
        let on = e.geodetic_deg_to_ecef(lat, 35.0, 0.0);
        // The magnitude the docs give for f's rounding: |z| + |k| + r.
        let m = on.z.abs() + w.apex.abs() + on.x.hypot(on.y);
        let n = up(&w, on).scaled(outward);
        let f = |p: V3<f64>| w.f(p).0 * outward;
        for slack in [0.0, 1.0e-3] {
            let tol = TAU * m + slack;
            for (k, inside) in SIDES {
                let p = moved_to(on, n, k * tol, f);
                assert_eq!(
                    q.inside_walls(p, slack),
                    inside,
                    "lat {lat}, slack {slack}: {k} of the tolerance"
                );
                if slack == 0.0 {
                    assert_eq!(q.contains(p), inside, "lat {lat}: {k} of the tolerance");
                }
            }
        }
    }
}

#[test]
fn lower_sphere_lets_a_point_in_within_64_eps_of_its_radius_squared_plus_the_slack_and_no_further()
{
    let (e, q) = flat_quad();
    let r = q.lower_radius();
    // The lower sphere lies below the quad's lowest vertex by the sagitta bound.
    assert!(r > 0.0 && r < e.b() - 500.0, "{r}");
    // Deep below the surface the latitude cones cross (b = a/2): the same quad without them, so that only the
    // lower sphere decides.
    let mut trig = QuadTrig::from_degrees(30.0, 45.0, 20.0, 50.0, 0.01);
    trig.walls = SideWalls {
        south: false,
        north: false,
        ..SideWalls::ALL
    };
    let q = HeightQuadBounds::from_trig(&e, &trig, -500.0, 500.0, 0.01, 0.01).unwrap();
    assert_eq!(q.lower_radius(), r);
    let n = e.normal_deg(40.0, 35.0);
    let at = |radius: f64| n.scaled(radius);
    for (k, inside) in SIDES {
        let p = at(r * (1.0 - k * TAU).sqrt());
        assert_eq!(q.inside_walls(p, 0.0), inside, "{k} of the tolerance");
    }
    // With a slack, the sphere shrinks by it.
    for (below, inside) in [
        (0.5e-3, true),
        (0.9e-3, true),
        (1.1e-3, false),
        (2.0e-3, false),
    ] {
        assert_eq!(
            q.inside_walls(at(r - below), 1.0e-3),
            inside,
            "{below} m below"
        );
    }
}

#[test]
fn the_ray_points_slack_is_64_eps_of_the_origins_and_the_farthest_steps_coordinates() {
    let ray = Ray::new(V3::new(3.0e6, -5.0e6, 7.0e6), V3::new(-0.25, 0.5, -0.125)).unwrap();
    for (lo, hi) in [(0.0, 1.0e6), (-4.0e6, 2.0e6), (-1.0e3, 3.0e7)] {
        let far = f64::max(lo.abs(), hi.abs());
        let expected = TAU * (1.5e7 + 0.875 * far);
        let slack = ray_point_slack(&ray, lo, hi);
        assert!(
            (slack - expected).abs() <= 4.0 * EPS * expected,
            "{lo} {hi}: {slack} against {expected}"
        );
    }
}

#[test]
fn a_meridian_plane_clips_the_ray_at_64_eps_of_its_x_and_y_and_farthest_step_beyond_it() {
    // A ray along the western wall's gradient (−sin λ, cos λ, 0) from 1 km outside it, with the wall at 35°
    // so that |x| and |y| differ: clipped where c·y − s·x = −64 ε (|o_x| + |o_y| + (|d_x| + |d_y|) t_abs).
    let (s, c) = sin_cos_deg(35.0);
    let grad = V3::new(-s, c, 0.0);
    let wall = |p: V3<f64>| c * p.y - s * p.x;
    let on = V3::new(4.0e6 * c, 4.0e6 * s, 3.0e6);
    let o = on.add_scaled(-1.0e3 - wall(on), grad);
    for t_max in [2.0e3, 1.0e6, 4.0e6] {
        let ray = Ray::new(o, grad)
            .unwrap()
            .with_interval(0.0, t_max)
            .unwrap();
        let (mut lo, mut hi) = (0.0, t_max);
        assert!(clip_wedge(&mut lo, &mut hi, [Some((c, s)), None], &ray));
        let tol = TAU * ((o.x.abs() + o.y.abs()) + (grad.x.abs() + grad.y.abs()) * t_max);
        let expected = (-tol - wall(o)) / (c * c + s * s);
        assert!(
            (lo - expected).abs() < 2.0e-9,
            "t_max {t_max}: {lo} against {expected} (tol {tol})"
        );
        assert_eq!(hi, t_max);
    }
}

#[test]
fn the_convex_stage_needs_a_finite_interval() {
    let e = Ellipsoid::<f64>::wgs84();
    let q = HeightQuadBounds::new(&e, 10.0, 11.0, 20.0, 21.0, -100.0, 500.0, 0.01, 0.01).unwrap();
    let top = e.geodetic_deg_to_ecef(10.5, 20.5, 1.0e4);
    let down = e.normal_deg(10.5, 20.5).negated();
    let ray = Ray::new(top, down).unwrap();
    assert_eq!(convex_interval(q.upper(), q.wedge, &ray), None);
    assert_eq!(q.ray_interval(&ray), None);
    let segment = ray.with_interval(0.0, 2.0e4).unwrap();
    assert!(convex_interval(q.upper(), q.wedge, &segment).is_some());
}

#[test]
fn a_segment_that_crosses_no_wall_is_judged_by_its_middle_not_by_an_end_within_the_tolerance() {
    // From just inside the lower sphere (by half the ray's point slack, so that the end itself passes the
    // inflated test) straight down, deeper into it: no wall is crossed, and the segment lies below the quad.
    let e = Ellipsoid::<f64>::wgs84();
    let q = HeightQuadBounds::new(&e, 10.0, 11.0, 20.0, 21.0, -100.0, 500.0, 0.01, 0.01).unwrap();
    let dir = e.normal_deg(10.5, 20.5);
    let probe = Ray::new(dir.scaled(q.lower_radius()), dir.negated())
        .unwrap()
        .with_interval(0.0, 100.0)
        .unwrap();
    let slack = ray_point_slack(&probe, 0.0, 100.0);
    let ray = Ray::new(dir.scaled(q.lower_radius() - 0.5 * slack), dir.negated())
        .unwrap()
        .with_interval(0.0, 100.0)
        .unwrap();
    assert!(q.inside_walls(V3::from(ray.at(0.0)), slack));
    assert!(!q.inside_walls(V3::from(ray.at(50.0)), slack));
    assert_eq!(q.walls_interval(&ray, 0.0, 100.0), None);
    // A point interval there is judged by that point.
    assert_eq!(q.walls_interval(&ray, 0.0, 0.0), Some((0.0, 0.0)));
}

#[test]
fn a_segment_that_never_meets_the_upper_spheroid_is_inside_within_the_points_slack_above_it() {
    // A 1 mm segment along the equator's tangent at height h above B^0 (the ellipsoid itself): no crossing, so
    // its middle decides, inflated by 64 ε and by the slack of the ray's points (about 1.3e-7 m here).
    let e = Ellipsoid::<f64>::wgs84();
    let upper = upper_spheroid(&e, 0.0).unwrap();
    let segment = |h: f64| {
        Ray::new(V3::new(e.a() + h, -0.5e-3, 0.0), V3::new(0.0, 1.0, 0.0))
            .unwrap()
            .with_interval(0.0, 1.0e-3)
            .unwrap()
    };
    let allowed = TAU * e.b() / 2.0 + ray_point_slack(&segment(0.0), 0.0, 1.0e-3);
    for (k, inside) in [(0.5, true), (0.8, true), (1.25, false), (2.0, false)] {
        let ray = segment(k * allowed);
        let (mut lo, mut hi) = (0.0, 1.0e-3);
        assert_eq!(
            clip_upper(&mut lo, &mut hi, &upper, &ray),
            inside,
            "{k} of the allowance"
        );
    }
}
