use super::*;
use std::collections::HashMap;
use std::vec;
use std::vec::Vec;

fn build(level: u32, axes: [f64; 3]) -> (Vec<V3<f64>>, Vec<Face<f64>>) {
    let mut v = vec![V3::ZERO; vertex_count(level)];
    let mut f = vec![Face::EMPTY; face_count(level)];
    let c = bevel_ellipsoid(level, axes, &mut v, &mut f).unwrap();
    assert_eq!(c.vertices, v.len());
    assert_eq!(c.faces, f.len());
    (v, f)
}

/// Every directed edge appears once and its reverse once; V − E + F = 2.
fn check_closed(v: &[V3<f64>], f: &[Face<f64>], level: u32) {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for face in f {
        let r = face.vertex_indices();
        for k in 0..r.len() {
            let e = (r[k], r[(k + 1) % r.len()]);
            *directed.entry(e).or_default() += 1;
        }
    }
    for (&(a, b), &m) in &directed {
        assert_eq!(m, 1, "directed edge {a}->{b} used {m} times");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "edge {a}-{b} is not shared"
        );
    }
    let edges = directed.len() / 2;
    assert_eq!(edges, edge_count(level));
    let euler = v.len() as i64 - edges as i64 + f.len() as i64;
    assert_eq!(euler, 2);
}

#[test]
fn counts_follow_the_const_fns() {
    assert_eq!((vertex_count(0), edge_count(0), face_count(0)), (8, 12, 6));
    assert_eq!(
        (vertex_count(1), edge_count(1), face_count(1)),
        (32, 48, 18)
    );
    assert_eq!(face_count(MAX_LEVEL + 1), usize::MAX);
    for level in 0..=MAX_LEVEL {
        let (v, e, f) = (vertex_count(level), edge_count(level), face_count(level));
        assert_eq!(v as i64 - e as i64 + f as i64, 2);
        assert_eq!(2 * e, 3 * v); // valence three
    }
}

#[test]
fn level_zero_is_the_cube() {
    let (v, f) = build(0, [1.0, 1.0, 1.0]);
    for p in &v {
        assert_eq!(p.max_abs(), 1.0);
        assert!(p.x.abs() == 1.0 && p.y.abs() == 1.0 && p.z.abs() == 1.0);
    }
    for face in &f {
        assert_eq!(face.len, 4);
        assert_eq!(face.center.length(), 1.0);
    }
    check_closed(&v, &f, 0);
}

#[test]
fn level_one_has_the_papers_y_point_and_face_points() {
    // §4.3.4: at the cube corner (1,1,1): Y = (√2/2)(1,1,1), face points (1, √2−1, √2−1) and permutations.
    let (v, _) = build(1, [1.0, 1.0, 1.0]);
    let h = core::f64::consts::FRAC_1_SQRT_2;
    let q = core::f64::consts::SQRT_2 - 1.0;
    let want = [
        V3::new(h, h, h),
        V3::new(1.0, q, q),
        V3::new(q, 1.0, q),
        V3::new(q, q, 1.0),
    ];
    for w in want {
        let best = v
            .iter()
            .map(|p| p.minus(w).length())
            .fold(f64::INFINITY, f64::min);
        assert!(best < 1e-15, "{w:?} not found ({best})");
    }
}

#[test]
#[cfg_attr(miri, ignore)] // levels 0-8 are checked in host-tests/tests/tessellate/main.rs
fn faces_are_tangent_and_closed_levels_0_to_3() {
    for level in 0..=3 {
        for axes in [[1.0, 1.0, 1.0], [3.0, 2.0, 0.5]] {
            let (v, f) = build(level, axes);
            check_closed(&v, &f, level);
            let eps = f64::EPSILON * 3.0;
            for face in &f {
                // The center point is on the ellipsoid ...
                let c = face.center;
                let on =
                    (c.x / axes[0]).powi(2) + (c.y / axes[1]).powi(2) + (c.z / axes[2]).powi(2);
                assert!((on - 1.0).abs() < 4.0 * f64::EPSILON);
                // ... the normal is the surface normal there ...
                let g = V3::new(
                    c.x / axes[0].powi(2),
                    c.y / axes[1].powi(2),
                    c.z / axes[2].powi(2),
                );
                assert!(g.cross(face.normal).length() / g.length() < 4.0 * f64::EPSILON);
                // ... and every vertex lies in the tangent plane.
                for &i in face.vertex_indices() {
                    let d = v[i as usize].minus(c).dot(face.normal);
                    assert!(d.abs() <= 8.0 * eps, "level {level}: off plane by {d}");
                }
            }
            for p in &v {
                let s = (p.x / axes[0]).powi(2) + (p.y / axes[1]).powi(2) + (p.z / axes[2]).powi(2);
                assert!(s >= 1.0, "vertex inside the surface");
            }
        }
    }
}

#[test]
fn f32_build_is_tangent() {
    let level = 2;
    let mut v = vec![V3::<f32>::ZERO; vertex_count(level)];
    let mut f = vec![Face::<f32>::EMPTY; face_count(level)];
    bevel_sphere(level, 2.0_f32, &mut v, &mut f).unwrap();
    for face in &f {
        for &i in face.vertex_indices() {
            let d = v[i as usize].minus(face.center).dot(face.normal);
            assert!(d.abs() <= 8.0 * f32::EPSILON * 2.0, "{d}");
        }
    }
}

#[test]
fn typed_errors_for_impossible_requests() {
    let mut v = vec![V3::<f64>::ZERO; 8];
    let mut f = vec![Face::<f64>::EMPTY; 6];
    assert_eq!(
        bevel_sphere(1, 1.0, &mut v, &mut f),
        Err(TessellateError::BufferTooSmall {
            buffer: "vertex",
            needed: 32,
            got: 8
        })
    );
    assert_eq!(
        bevel_sphere(MAX_LEVEL + 1, 1.0, &mut v, &mut f),
        Err(TessellateError::LevelTooDeep {
            level: MAX_LEVEL + 1,
            max: MAX_LEVEL
        })
    );
    // MAX_LEVEL itself is accepted: only the buffers are too short for it.
    assert!(matches!(
        bevel_sphere(MAX_LEVEL, 1.0, &mut v, &mut f),
        Err(TessellateError::BufferTooSmall {
            buffer: "vertex",
            ..
        })
    ));
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            bevel_ellipsoid(0, [1.0, bad, 1.0], &mut v, &mut f),
            Err(TessellateError::InvalidShape)
        );
    }
    let mut f_short = vec![Face::<f64>::EMPTY; 5];
    assert!(matches!(
        bevel_sphere(0, 1.0, &mut v, &mut f_short),
        Err(TessellateError::BufferTooSmall { buffer: "face", .. })
    ));
}

/// The plane through three points, as (unit normal, distance from the origin).
fn plane(a: V3<f64>, b: V3<f64>, c: V3<f64>) -> (V3<f64>, f64) {
    let n = normalized(b.minus(a).cross(c.minus(a))).unwrap();
    let n = if n.dot(a) < 0.0 { n.negated() } else { n };
    (n, n.dot(a))
}

#[test]
fn doo_type_v_face_leaves_the_tangent_planes() {
    // §4.2: Doo's face point from the cube vertex P0 = (1,1,1) toward the center of the adjacent face x = 1 is
    // (1 − t)·P0 + t·(1,0,0) = (1, 1 − t, 1 − t); likewise for the faces y = 1 and z = 1.
    let p0 = V3::new(1.0, 1.0, 1.0);
    let centers = [
        V3::new(1.0, 0.0, 0.0),
        V3::new(0.0, 1.0, 0.0),
        V3::new(0.0, 0.0, 1.0),
    ];
    let doo = |t: f64, c: V3<f64>| p0.scaled(1.0 - t).add_scaled(t, c);
    // The weight that puts the Type E faces on the sphere: their face points are where the plane of the face
    // x = 1 meets the tangent planes at the geodesic midpoints (√2/2)(1,0,1) and (√2/2)(1,1,0).
    let h = core::f64::consts::FRAC_1_SQRT_2;
    let meet = tangent_planes_meet(
        V3::new(1.0, 0.0, 0.0),
        V3::new(h, 0.0, h),
        V3::new(h, h, 0.0),
    )
    .unwrap();
    let t_e = 1.0 - meet.y; // (1, 1 − t, 1 − t)
    assert!((t_e - (2.0 - core::f64::consts::SQRT_2)).abs() < 1e-15);
    assert!(meet.minus(doo(t_e, centers[0])).length() < 1e-15);
    // With that weight the Type V face (the triangle of the three face points) is not tangent: its plane is
    // ≈ 1.0556 from the center (the paper's number), so it cuts no tangent plane of the unit sphere.
    let (nv, dv) = plane(
        doo(t_e, centers[0]),
        doo(t_e, centers[1]),
        doo(t_e, centers[2]),
    );
    assert!((dv - 1.0556).abs() < 1e-4, "{dv}");
    assert!(
        nv.minus(V3::new(1.0, 1.0, 1.0).scaled(1.0 / 3f64.sqrt()))
            .length()
            < 1e-15
    );
    // And no weight works: for every t, the Type E face replacing the edge (1,1,1)–(−1,1,1) and the Type V
    // face cannot both touch the sphere (their tangency weights are 2 − √2 and (3 − √3)/2).
    let mut best = f64::INFINITY;
    for s in 1..1000 {
        let t = s as f64 / 1000.0;
        let on_y = |x: f64| V3::new(x * (1.0 - t), 1.0, 1.0 - t); // face y = 1, near (±1,1,1)
        let on_z = |x: f64| V3::new(x * (1.0 - t), 1.0 - t, 1.0); // face z = 1
        let (_, de) = plane(on_y(1.0), on_z(1.0), on_y(-1.0));
        let (_, dv) = plane(doo(t, centers[0]), doo(t, centers[1]), doo(t, centers[2]));
        best = best.min((de - 1.0).abs().max((dv - 1.0).abs()));
    }
    assert!(
        best > 0.02,
        "some Doo weight puts both faces on the sphere: {best}"
    );
}

#[test]
fn center_point_formula_derived_again() {
    // §4.3.4: C = (1 − t)·P_p + t·(C0 + C1)/2 with P_p the edge point; the point on the sphere needs
    // t = 1 / (1 + cos(ψ/2)), ψ the angle between the normals. The paper's t = 1/(1 + cos((π − ψ)/2)) agrees
    // only at ψ = π/2.
    for (c0, c1) in [
        (V3::new(1.0_f64, 0.0, 0.0), V3::new(0.0, 1.0, 0.0)),
        (
            V3::new(1.0, 0.0, 0.0),
            normalized(V3::new(1.0, 1.0, 0.0)).unwrap(),
        ),
        (
            normalized(V3::new(1.0, 1.0, 0.0)).unwrap(),
            normalized(V3::new(1.0, 0.2, 0.9)).unwrap(),
        ),
    ] {
        let psi = c0.cross(c1).length().atan2(c0.dot(c1));
        let mid = c0.plus(c1).scaled(0.5);
        // On both tangent planes, above the midpoint. Tolerances are a few tens of ulps: Miri perturbs the
        // results of libm functions (atan2, cos) by a few ulps on purpose.
        let edge_point = mid.scaled(1.0 / mid.length_squared());
        assert!((edge_point.dot(c0) - 1.0).abs() < 1e-14);
        let t = 1.0 / (1.0 + (psi / 2.0).cos());
        let c = edge_point.scaled(1.0 - t).add_scaled(t, mid);
        let geodesic_mid = normalized(c0.plus(c1)).unwrap();
        assert!(c.minus(geodesic_mid).length() < 1e-14, "{psi}");
        let t_paper = 1.0 / (1.0 + ((core::f64::consts::PI - psi) / 2.0).cos());
        let same = (t_paper - t).abs() < 1e-12;
        assert_eq!(same, (psi - core::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}

#[cfg(feature = "fast-math")]
#[test]
fn f32_fast_build_is_tangent() {
    use crate::real::F32Fast;
    let level = 2;
    let mut v = vec![V3::<F32Fast>::ZERO; vertex_count(level)];
    let mut f = vec![Face::<F32Fast>::EMPTY; face_count(level)];
    let one = F32Fast::from_f64(1.0);
    bevel_ellipsoid(level, [one, one, one], &mut v, &mut f).unwrap();
    check_closed_generic(&f, v.len(), level);
    let mut worst = 0.0_f64;
    for face in &f {
        for &i in face.vertex_indices() {
            let d = v[i as usize].minus(face.center).dot(face.normal).to_f64();
            worst = worst.max(d.abs() / f64::from(f32::EPSILON));
        }
    }
    assert!(worst <= 8.0, "{worst} eps");
}

#[cfg(feature = "fast-math")]
fn check_closed_generic<T: Real>(f: &[Face<T>], nv: usize, level: u32) {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for face in f {
        let r = face.vertex_indices();
        for k in 0..r.len() {
            *directed.entry((r[k], r[(k + 1) % r.len()])).or_default() += 1;
        }
    }
    assert!(
        directed
            .iter()
            .all(|(&(a, b), &m)| m == 1 && directed.get(&(b, a)) == Some(&1))
    );
    assert_eq!(directed.len() / 2, edge_count(level));
    assert_eq!(nv, vertex_count(level));
}

/// `tangent_planes_meet` solves `n_i·P = 1` for its three normals whatever their lengths (the planes tangent to
/// the unit sphere at unit normals; the lengths' defects `1 − |n|²` are carried so that nothing cancels): for
/// normals spread about 1 and 0.1 rad apart and up to 10 % off unit length, and 1e-2 and 1e-4 rad apart and up
/// to 1e-6 and 1e-9 off it (the rounding of unit normals and more), each residual `n_i·P − 1` is within 8 ulps
/// of `|n_i|·|P|` (1.35 measured).
#[test]
fn tangent_planes_meet_solves_each_planes_equation_for_normals_off_unit_length() {
    let mut next = crate::test_util::xorshift_uniform(7);
    for (spread, off_unit) in [(1.0, 0.1), (0.1, 0.1), (1e-2, 1e-6), (1e-4, 1e-9)] {
        for _ in 0..50 {
            let axis = V3::new(next() - 0.5, next() - 0.5, next() - 0.5);
            let axis = axis.scaled(1.0 / axis.length());
            let mut n = [V3::<f64>::ZERO; 3];
            for v in &mut n {
                let off = V3::new(next() - 0.5, next() - 0.5, next() - 0.5).scaled(spread);
                let dir = axis.plus(off);
                *v = dir.scaled((1.0 + off_unit * (2.0 * next() - 1.0)) / dir.length());
            }
            let [a, b, c] = n;
            let p = tangent_planes_meet(a, b, c).unwrap();
            for v in n {
                let residual = (v.dot(p) - 1.0).abs();
                assert!(
                    residual <= 8.0 * f64::EPSILON * v.length() * p.length(),
                    "spread {spread}: {residual} for {v:?}, P {p:?}"
                );
            }
        }
    }
}

/// Every face's ring is counter-clockwise seen from outside (`Face::vertices`' contract): its vector area
/// `½ Σ v_k × v_{k+1}` points along the face's outward normal, for the sphere and an ellipsoid at levels 0 to 3
/// (a consistent orientation alone, which `check_closed` checks, would also hold for every ring reversed).
#[test]
fn every_faces_ring_runs_counter_clockwise_seen_from_outside() {
    for axes in [[1.0, 1.0, 1.0], [3.0, 2.0, 0.5]] {
        for level in 0..=3 {
            let (v, f) = build(level, axes);
            for face in &f {
                let ring: Vec<V3<f64>> = face
                    .vertex_indices()
                    .iter()
                    .map(|&i| v[i as usize])
                    .collect();
                let area = (0..ring.len()).fold(V3::ZERO, |s, k| {
                    s.plus(ring[k].cross(ring[(k + 1) % ring.len()]).scaled(0.5))
                });
                let along = area.dot(face.normal) / area.length();
                assert!(along > 0.999, "{axes:?} {level}: {along} for {face:?}");
            }
        }
    }
}

/// `normalized` scales before it divides, so huge and tiny vectors (whose squared length would overflow or
/// underflow) give their unit direction too; zero and non-finite ones give `None`.
#[test]
fn normalized_gives_the_unit_direction_of_huge_and_tiny_vectors() {
    let h = core::f64::consts::FRAC_1_SQRT_2;
    for scale in [1.0, 1e300, 1e-300] {
        let n = normalized(V3::new(scale, 0.0, -scale)).unwrap();
        assert!(
            (n.x - h).abs() < 1e-15 && n.y == 0.0 && (n.z + h).abs() < 1e-15,
            "{scale}: {n:?}"
        );
    }
    assert_eq!(normalized(V3::<f64>::ZERO), None);
    assert_eq!(normalized(V3::new(f64::INFINITY, 0.0, 0.0)), None);
    assert_eq!(normalized(V3::new(1.0, f64::NAN, 0.0)), None);
}

/// The numbering a caller indexes by: vertices octant by octant (octant `k` negates x when bit 0 of `k` is set,
/// y for bit 1, z for bit 2), and each face's ring counter-clockwise from the direction `−u`, where
/// `u = n × e` and `e` is the coordinate axis least aligned with the face's center `n` (x, then y, on ties).
#[test]
fn vertices_come_octant_by_octant_and_each_ring_starts_after_its_tangent_axis() {
    let (v, _) = build(0, [1.0, 1.0, 1.0]);
    for (k, p) in v.iter().enumerate() {
        let sign = |bit: usize| if k & bit == 0 { 1.0 } else { -1.0 };
        assert_eq!((p.x, p.y, p.z), (sign(1), sign(2), sign(4)), "vertex {k}");
    }
    for level in 0..=2 {
        let (v, f) = build(level, [1.0, 1.0, 1.0]);
        for face in &f {
            let n = face.center;
            let (ax, ay, az) = (n.x.abs(), n.y.abs(), n.z.abs());
            let e = if ax <= ay && ax <= az {
                V3::new(1.0, 0.0, 0.0)
            } else if ay <= az {
                V3::new(0.0, 1.0, 0.0)
            } else {
                V3::new(0.0, 0.0, 1.0)
            };
            let u = normalized(n.cross(e)).unwrap();
            let w = n.cross(u);
            let angles: Vec<f64> = face
                .vertex_indices()
                .iter()
                .map(|&i| {
                    let d = v[i as usize].minus(n);
                    libm::atan2(d.dot(w), d.dot(u))
                })
                .collect();
            assert!(
                angles.windows(2).all(|p| p[0] < p[1]),
                "level {level}, face at {n:?}: angles {angles:?}"
            );
        }
    }
}
