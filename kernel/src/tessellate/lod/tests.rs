use super::super::bevel::tangent_planes_meet;
use super::ellipsoid::{decide_by_walk, decide_cheaply, leaf_at, witness_targets};
use super::*;
use crate::vec3::V3;

#[test]
fn worst_case_matches_the_papers_numbers() {
    // Level 0: the cube (dihedral 90°, corner at √3); level 1: dihedral 120° (the new faces' normals are 60°
    // apart, §4.3.3 cos a' = 1/2).
    let w0 = worst_case::<f64>(0).unwrap();
    assert!((w0.min_dihedral - core::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert!((w0.max_deviation - (3f64.sqrt() - 1.0)).abs() < 1e-15);
    let w1 = worst_case::<f64>(1).unwrap();
    assert!((w1.min_dihedral.to_degrees() - 120.0).abs() < 1e-12);
    // The Y-point (√2/2)(1,1,1) of §4.3.4 is the farthest vertex: √6/2 − 1.
    assert!((w1.max_deviation - (6f64.sqrt() / 2.0 - 1.0)).abs() < 1e-15);
    for k in 1..=MAX_LEVEL {
        let a = worst_case::<f64>(k - 1).unwrap();
        let b = worst_case::<f64>(k).unwrap();
        assert!(b.min_dihedral > a.min_dihedral && b.max_deviation < a.max_deviation);
        // From level 2 on, the side roughly halves.
        if k >= 2 {
            assert!((b.max_normal_angle / a.max_normal_angle - 0.5).abs() < 0.07);
        }
    }
}

#[test]
fn f32_and_f64_agree() {
    for k in 0..=MAX_LEVEL {
        let a = worst_case::<f64>(k).unwrap();
        let b = worst_case::<f32>(k).unwrap();
        assert!(((b.max_deviation as f64) / a.max_deviation - 1.0).abs() < 1e-5);
        assert!(((b.max_normal_angle as f64) / a.max_normal_angle - 1.0).abs() < 1e-5);
    }
}

#[test]
fn bounds_pick_the_first_level_that_meets_them() {
    let deg = |d: f64| d.to_radians();
    let lvl = |b| min_level(Shape::Sphere(1.0_f64), b).unwrap();
    assert_eq!(lvl(Bound::MinDihedral(deg(90.0))), 0);
    assert_eq!(lvl(Bound::MinDihedral(deg(90.1))), 1);
    assert_eq!(lvl(Bound::MinDihedral(deg(120.1))), 2);
    assert_eq!(lvl(Bound::MaxDeviation(f64::INFINITY)), 0);
    assert_eq!(lvl(Bound::MaxDeviation(0.2248)), 1);
    assert_eq!(lvl(Bound::MaxDeviation(0.2247)), 2);
    // Radius scales the deviation.
    assert_eq!(
        min_level(Shape::Sphere(10.0_f64), Bound::MaxDeviation(2.248)).unwrap(),
        1
    );
    // Equal axes are a sphere.
    let b = Bound::MaxDeviation(1e-3);
    assert_eq!(
        min_level(Shape::Ellipsoid([2.0_f64, 2.0, 2.0]), b).unwrap(),
        min_level(Shape::Sphere(2.0_f64), b).unwrap()
    );
}

/// Distance from `y` to the spheroid with equatorial radius `a` and polar `c`, in closed form for a point in
/// the meridian plane by a different route: bisection on the angle of the closest point (normal through `y`).
fn spheroid_distance(a: f64, c: f64, rho: f64, z: f64) -> f64 {
    let foot = |t: f64| (a * t.cos(), c * t.sin());
    // The normal at foot(t) passes through y where g(t) = 0 (t in [0, π/2] for the first quadrant).
    let g = |t: f64| {
        let (x, w) = foot(t);
        let (nx, nw) = (x / (a * a), w / (c * c));
        (rho - x) * nw - (z - w) * nx
    };
    let (mut lo, mut hi) = (0.0_f64, core::f64::consts::FRAC_PI_2);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if (g(lo) > 0.0) == (g(m) > 0.0) {
            lo = m;
        } else {
            hi = m;
        }
    }
    let (x, w) = foot(0.5 * (lo + hi));
    ((rho - x).powi(2) + (z - w).powi(2)).sqrt()
}

#[test]
fn closest_point_distance_matches_a_meridian_bisection() {
    let (e, hi) = Ell::new([3.0_f64, 3.0, 1.0]).unwrap();
    assert_eq!(hi, 3.0);
    for (px, pz) in [
        (1.0_f64, 0.01),
        (0.3, 0.999),
        (0.8, 0.8),
        (1.0001, 0.0),
        (0.0, 1.2),
    ] {
        let p = V3::new(px, 0.0, pz);
        let want = spheroid_distance(1.0, 1.0 / 3.0, px, pz / 3.0);
        let got = e.distance(p);
        assert!(
            (got - want).abs() <= 1e-12 * want.max(1e-3),
            "{px} {pz}: {got} vs {want}"
        );
        // The bracket of vertex_meets agrees with the solved distance on both sides.
        assert!(e.vertex_meets(p, want * (1.0 + 1e-9)));
        assert!(!e.vertex_meets(p, want * (1.0 - 1e-9)));
    }
    assert_eq!(e.distance(V3::new(0.5, 0.5, 0.0)), 0.0); // inside
}

#[test]
fn witness_triangles_are_lattice_leaves() {
    // Each witness target lies strictly inside exactly one leaf, whose corners are unit center points.
    for level in 0..=4 {
        let (t, len) = witness_targets(level).unwrap();
        for &target in &t[..len] {
            assert_eq!(target.iter().sum::<i64>(), 3 << level, "{target:?}");
            let c = leaf_at::<f64>(level, target).unwrap();
            for v in c {
                assert!((v.length() - 1.0).abs() < 1e-15);
            }
        }
    }
    // The tip witness at level 3 is the corner triangle at +x: its vertex is (1, tan(θ/2), tan(θ/2)).
    let c = leaf_at::<f64>(3, [22, 1, 1]).unwrap();
    let p = tangent_planes_meet(c[0], c[1], c[2]).unwrap();
    let tau = (core::f64::consts::PI / 32.0).tan();
    assert!((p.x - 1.0).abs() < 1e-14 && (p.y - tau).abs() < 1e-14 && (p.z - tau).abs() < 1e-14);
}

/// The smallest level by the unpruned walk of [`ellipsoid_worst_case`].
fn by_full_walk(axes: [f64; 3], ok: impl Fn(&EllipsoidWorstCase<f64>) -> bool, top: u32) -> u32 {
    (0..=top)
        .find(|&k| ok(&ellipsoid_worst_case(axes, k).unwrap()))
        .unwrap_or(top + 1)
}

#[test]
fn ellipsoid_level_agrees_with_the_unpruned_walk() {
    let top = if cfg!(miri) { 2 } else { 4 };
    // (Under Miri the first ellipsoid only: each takes about 9 s there.)
    let shapes: &[[f64; 3]] = if cfg!(miri) {
        &[[3.0, 2.0, 1.0]]
    } else {
        &[[3.0, 2.0, 1.0], [1.0, 1.0, 0.3], [1.0, 4.0, 1.0]]
    };
    for &axes in shapes {
        let worst: [EllipsoidWorstCase<f64>; 5] = core::array::from_fn(|k| {
            ellipsoid_worst_case(axes, k.min(top as usize) as u32).unwrap()
        });
        for k in 0..top as usize {
            // Bounds halfway between consecutive levels' exact values: the answer is k + 1.
            let dev = 0.5 * (worst[k].max_deviation + worst[k + 1].max_deviation);
            assert_eq!(
                min_level(Shape::Ellipsoid(axes), Bound::MaxDeviation(dev)),
                Ok(k as u32 + 1)
            );
            assert_eq!(
                by_full_walk(axes, |w| w.max_deviation <= dev, top),
                k as u32 + 1
            );
            let phi = 0.5 * (worst[k].min_dihedral + worst[k + 1].min_dihedral);
            assert_eq!(
                min_level(Shape::Ellipsoid(axes), Bound::MinDihedral(phi)),
                Ok(k as u32 + 1)
            );
        }
    }
}

#[test]
#[cfg_attr(miri, ignore)]
fn ellipsoid_walk_decides_levels_the_witnesses_leave_open() {
    // Bounds just above each level's exact worst value, where only the walk can show that the level meets.
    let axes = [3.0_f64, 2.0, 1.0];
    let (e, hi) = Ell::new(axes).unwrap();
    for k in 2..=6u32 {
        let w = ellipsoid_worst_case(axes, k).unwrap();
        let below = ellipsoid_worst_case(axes, k - 1).unwrap();
        for f in [1e-9, 1e-6, 1e-3] {
            let limit = w.max_deviation * (1.0 + f) / hi;
            assert_eq!(decide_cheaply(&e, k, EllTest::Deviation(limit)), Ok(None));
            let limit = w.max_normal_angle * (1.0 + f);
            assert_eq!(decide_cheaply(&e, k, EllTest::NormalAngle(limit)), Ok(None));
            let b = Bound::MaxDeviation(w.max_deviation * (1.0 + f));
            assert!(below.max_deviation > w.max_deviation * (1.0 + f));
            assert_eq!(min_level(Shape::Ellipsoid(axes), b), Ok(k), "{b:?}");
            let a = w.max_normal_angle * (1.0 + f);
            let b = Bound::MinDihedral(core::f64::consts::PI - a);
            assert_eq!(min_level(Shape::Ellipsoid(axes), b), Ok(k), "{b:?}");
        }
    }
}

/// The exhaustive octant walk alone (`decide_by_walk`, without the witnesses that decide most levels before it):
/// for a bound just below a level's exact worst deviation or normal angle (by the unpruned walk of
/// [`ellipsoid_worst_case`]) it finds the violation, and just above it finds none, for three ellipsoids (one
/// long axis, one short, all three different) at levels 1 to 5. A bound that cleared a subtree holding the worst
/// vertex or edge would answer "meets" below it.
#[test]
#[cfg_attr(miri, ignore)]
fn the_octant_walk_alone_finds_each_levels_worst_case_and_nothing_past_it() {
    for axes in [[3.0_f64, 2.0, 1.0], [1.0, 1.0, 0.3], [1.0, 4.0, 1.0]] {
        let (e, hi) = Ell::new(axes).unwrap();
        for k in 1..=5u32 {
            let w = ellipsoid_worst_case(axes, k).unwrap();
            for f in [1e-9, 1e-6, 1e-3] {
                for (factor, meets) in [(1.0 - f, false), (1.0 + f, true)] {
                    let dev = EllTest::Deviation(w.max_deviation * factor / hi);
                    assert_eq!(
                        decide_by_walk(&e, k, dev),
                        Ok(meets),
                        "{axes:?} {k} {dev:?}"
                    );
                    let angle = EllTest::NormalAngle(w.max_normal_angle * factor);
                    assert_eq!(
                        decide_by_walk(&e, k, angle),
                        Ok(meets),
                        "{axes:?} {k} {angle:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn ellipsoid_f32_gives_the_f64_level() {
    let axes = [3.0_f64, 2.0, 1.0];
    let w = [
        ellipsoid_worst_case(axes, 2).unwrap(),
        ellipsoid_worst_case(axes, 3).unwrap(),
    ];
    let dev = 0.5 * (w[0].max_deviation + w[1].max_deviation);
    let axes32 = axes.map(|a| a as f32);
    assert_eq!(
        min_level(Shape::Ellipsoid(axes32), Bound::MaxDeviation(dev as f32)),
        Ok(3)
    );
}

#[test]
fn impossible_requests_are_typed_errors() {
    let s = Shape::Sphere(1.0_f64);
    for b in [
        Bound::MinDihedral(f64::NAN),
        Bound::MinDihedral(core::f64::consts::PI),
        Bound::MinDihedral(-0.1),
        Bound::MaxDeviation(0.0),
        Bound::MaxDeviation(f64::NAN),
        Bound::ScreenSpace {
            distance: 0.5,
            pixel_angle: 1e-3,
        },
        Bound::ScreenSpace {
            distance: 5.0,
            pixel_angle: 0.0,
        },
    ] {
        assert_eq!(min_level(s, b), Err(TessellateError::InvalidBound), "{b:?}");
    }
    assert_eq!(
        min_level(Shape::Sphere(1.0_f64), Bound::MaxDeviation(1e-300)),
        Err(TessellateError::Unreachable)
    );
    assert_eq!(
        min_level(Shape::Sphere(-1.0_f64), Bound::MaxDeviation(1.0)),
        Err(TessellateError::InvalidShape)
    );
    assert_eq!(
        min_level(
            Shape::Ellipsoid([1.0_f64, f64::MAX, f64::MIN_POSITIVE]),
            Bound::MaxDeviation(1.0)
        ),
        Err(TessellateError::AxisRatioTooLarge)
    );
    // Beyond MAX_AXIS_RATIO (a fuzz input at 7e134 : 1 had the solver report a zero deviation).
    assert_eq!(
        min_level(
            Shape::Ellipsoid([
                1.0000000006402843_f64,
                7.268387242956069e134,
                0.1511801481283328
            ]),
            Bound::MaxDeviation(0.01)
        ),
        Err(TessellateError::AxisRatioTooLarge)
    );
    assert!(
        min_level(
            Shape::Ellipsoid([1.0_f64, 0.9e6, 1.0]),
            Bound::MaxDeviation(1.0)
        )
        .is_ok()
    );
    // The squared axis ratio must stay a normal number.
    assert_eq!(
        min_level(
            Shape::Ellipsoid([1.0_f64, 1e200, 1.0]),
            Bound::MaxDeviation(1.0)
        ),
        Err(TessellateError::AxisRatioTooLarge)
    );
    assert!(
        min_level(
            Shape::Ellipsoid([1.0_f64, 0.9e6, 1.0]),
            Bound::MaxDeviation(1e7)
        )
        .is_ok()
    );
}

#[test]
fn screen_space_error_is_the_inverse_of_the_allowed_deviation() {
    let (r, d, p) = (1.0_f64, 10.0, 1e-3);
    let s = (p / 2.0).sin();
    let allowed = 2.0 * (d - r) * s / (1.0 + 2.0 * s);
    assert!((screen_space_error(r, d, allowed) - p).abs() < 1e-15);
    assert_eq!(screen_space_error(r, 1.0, 0.1), core::f64::consts::PI);
}

#[test]
fn screen_space_bound_picks_the_first_level_whose_deviation_subtends_at_most_a_pixel() {
    // Spheres of radius 1 and 6.4e6 seen from 1.5 to 1e4 radii away with pixels of 1e-2 to 1e-5 rad: the level
    // returned is the first whose worst deviation (`worst_case`, times the radius) subtends at most a pixel by
    // `screen_space_error`, and the level before it subtends more.
    for r in [1.0_f64, 6.4e6] {
        for d in [1.5, 3.0, 40.0, 1.0e4] {
            for p in [1e-2, 1e-3, 3e-4, 1e-5] {
                let b = Bound::ScreenSpace {
                    distance: d * r,
                    pixel_angle: p,
                };
                let k = min_level(Shape::Sphere(r), b).unwrap();
                let seen = |k: u32| {
                    screen_space_error(r, d * r, r * worst_case::<f64>(k).unwrap().max_deviation)
                };
                assert!(
                    seen(k) <= p,
                    "r {r} d {d} p {p}: level {k} subtends {}",
                    seen(k)
                );
                if k > 0 {
                    assert!(
                        seen(k - 1) > p,
                        "r {r} d {d} p {p}: level {} already subtends {}",
                        k - 1,
                        seen(k - 1)
                    );
                }
            }
        }
    }
    // At the distance from which level 3's worst deviation subtends exactly a pixel of 1e-2 rad (the inverse of
    // `screen_space_error`: d = r + e (1 + 2 sin(p/2)) / (2 sin(p/2))), a little farther level 3 is enough and a
    // little nearer it is not.
    let (p, dev) = (1e-2_f64, worst_case::<f64>(3).unwrap().max_deviation);
    let s = (p / 2.0).sin();
    let at = 1.0 + dev * (1.0 + 2.0 * s) / (2.0 * s);
    let level_from = |d: f64| {
        min_level(
            Shape::Sphere(1.0_f64),
            Bound::ScreenSpace {
                distance: d,
                pixel_angle: p,
            },
        )
    };
    assert_eq!(level_from(at * (1.0 + 1e-9)), Ok(3));
    assert_eq!(level_from(at * (1.0 - 1e-9)), Ok(4));
    // The same request on a spheroid with equal axes, and the eye or the pixel out of range.
    let b = Bound::ScreenSpace {
        distance: 10.0,
        pixel_angle: 1e-3,
    };
    assert_eq!(
        min_level(Shape::Ellipsoid([2.0_f64, 2.0, 2.0]), b),
        min_level(Shape::Sphere(2.0_f64), b)
    );
    for (distance, pixel_angle) in [
        (10.0, 0.0),
        (10.0, -1e-3),
        (10.0, 3.2),
        (2.0, 1e-3),
        (1.5, 1e-3),
        (f64::INFINITY, 1e-3),
    ] {
        assert_eq!(
            min_level(
                Shape::Sphere(2.0_f64),
                Bound::ScreenSpace {
                    distance,
                    pixel_angle
                }
            ),
            Err(TessellateError::InvalidBound),
            "distance {distance}, pixel {pixel_angle}"
        );
    }
}

/// `vertex_meets`' cheap bounds decide only what the closest point would: for points a relative 1e-6 to 1e-1
/// outside the unit sphere in many directions, mapped onto three ellipsoids, a limit 1e-6 above the point's
/// distance (`Ell::distance`, checked against a bisection in `closest_point_distance_matches_a_meridian_bisection`)
/// is met and one 1e-6 below it is not (the distance itself is known to about `ε / excess` relatively: `|p|² − 1`
/// cancels); a point inside the sphere meets every limit from 0.
#[test]
fn vertex_test_agrees_with_the_closest_point_just_above_and_below_its_distance() {
    let mut next = crate::test_util::xorshift_uniform(11);
    for axes in [[3.0_f64, 2.0, 1.0], [1.0, 1.0, 0.3], [1.0, 4.0, 1.0]] {
        let (e, _) = Ell::new(axes).unwrap();
        for k in 0..300 {
            let dir = V3::new(next() - 0.5, next() - 0.5, next() - 0.5);
            let dir = dir.scaled(1.0 / dir.length());
            let excess = 10f64.powf(-6.0 + 5.0 * f64::from(k % 6) / 5.0);
            let p = dir.scaled(1.0 + excess);
            let d = e.distance(p);
            assert!(d > 0.0, "{axes:?} {p:?}");
            assert!(e.vertex_meets(p, d * (1.0 + 1e-6)), "{axes:?} {p:?} {d}");
            assert!(!e.vertex_meets(p, d * (1.0 - 1e-6)), "{axes:?} {p:?} {d}");
            assert!(
                e.vertex_meets(dir.scaled(1.0 - excess), 0.0),
                "{axes:?} {dir:?}"
            );
        }
    }
}

/// The requests refused at their boundaries: a sphere of radius 0 (not positive), a screen-space bound whose
/// allowed deviation underflows to 0 (a subnormal pixel angle with the eye 2^-40 radii off the bounding sphere);
/// and `screen_space_error`'s saturation at π when the deviation subtends half a radian's sine of 1 or more (the
/// eye closer to the polyhedron than half the deviation) or the eye touches it.
#[test]
fn zero_radius_an_underflowing_allowed_deviation_and_a_saturated_screen_error() {
    assert_eq!(
        min_level(Shape::Sphere(0.0_f64), Bound::MaxDeviation(0.1)),
        Err(TessellateError::InvalidShape)
    );
    let b = Bound::ScreenSpace {
        distance: 1.0 + 2f64.powi(-40),
        pixel_angle: 1e-320,
    };
    assert_eq!(
        min_level(Shape::Sphere(1.0_f64), b),
        Err(TessellateError::InvalidBound)
    );
    let pi = core::f64::consts::PI;
    // d − r − e = 0.1 and e / (2 · 0.1) = 4.5: saturated; d − r − e = 0: the eye on the polyhedron
    assert_eq!(screen_space_error(1.0_f64, 2.0, 0.9), pi);
    assert_eq!(screen_space_error(1.0_f64, 2.0, 1.0), pi);
    // e / (2 (d − r − e)) = 0.5: 2·asin(0.5) = π/3
    assert!((screen_space_error(1.0_f64, 2.0, 0.5) - pi / 3.0).abs() < 1e-15);
}
