use super::*;

#[test]
fn hits_a_unit_triangle_from_both_sides() {
    let (v0, v1, v2) = (
        V3::new(0.0, 0.0, 0.0),
        V3::new(1.0, 0.0, 0.0),
        V3::new(0.0, 1.0, 0.0),
    );
    let down = WatertightRay::new(V3::new(0.25, 0.25, 2.0), V3::new(0.0, 0.0, -1.0)).unwrap();
    let (t, b) = down.intersect(v0, v1, v2, 0.0, 10.0).unwrap();
    assert_eq!(t, 2.0);
    assert!((b[0] - 0.5).abs() < 1e-15 && (b[1] - 0.25).abs() < 1e-15);
    let up = WatertightRay::new(V3::new(0.25, 0.25, -2.0), V3::new(0.0, 0.0, 1.0)).unwrap();
    assert_eq!(up.intersect(v0, v1, v2, 0.0, 10.0).unwrap().0, 2.0);
    let miss = WatertightRay::new(V3::new(0.75, 0.75, 2.0), V3::new(0.0, 0.0, -1.0)).unwrap();
    assert!(miss.intersect(v0, v1, v2, 0.0, 10.0).is_none());
    // Out of the interval.
    assert!(down.intersect(v0, v1, v2, 0.0, 1.5).is_none());
}

/// In `f32`, straight-down rays near the edge `P–Q` shared by two triangles, placed so that the scalar edge
/// function of that edge rounds to exactly 0 while its exact value (of the same rounded coordinates) does
/// not: the exact recomputation gives it its sign, so exactly one of the two triangles is hit (a 0 would
/// give the ray to both). Each triangle is tried with its vertices in all three rotations, so the edge is
/// `U`, `V` and `W` in turn.
#[test]
fn f32_edge_function_that_rounds_to_zero_takes_its_exact_sign() {
    let mut seed: u64 = 7;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut found = 0;
    for _ in 0..200_000 {
        let q = V3::new(1.0 + next(), 1.0 + next(), 0.0f32);
        let t = 0.25 + 0.5 * next();
        let o = V3::new(q.x * t, q.y * t, 1.0f32);
        // The sheared coordinates of P = 0 and Q relative to o (ray straight down: x' = y, y' = x).
        let (px, py) = (0.0 - o.y, 0.0 - o.x);
        let (qx, qy) = (q.y - o.y, q.x - o.x);
        let scalar = qx * py - qy * px;
        let exact = f64::from(qx) * f64::from(py) - f64::from(qy) * f64::from(px);
        if scalar != 0.0 || exact == 0.0 {
            continue;
        }
        found += 1;
        let p = V3::new(0.0f32, 0.0, 0.0);
        let (r1, r2) = (V3::new(-q.y, q.x, 0.0), V3::new(q.y, -q.x, 0.0));
        let ray = WatertightRay::new(o, V3::new(0.0, 0.0, -1.0)).unwrap();
        for k in 0..3 {
            let rot = |t: [V3<f32>; 3]| [t[k % 3], t[(k + 1) % 3], t[(k + 2) % 3]];
            let [a, b, c] = rot([p, q, r1]);
            let first = ray.intersect(a, b, c, 0.0, 10.0).is_some();
            let [a, b, c] = rot([q, p, r2]);
            let second = ray.intersect(a, b, c, 0.0, 10.0).is_some();
            assert!(
                first != second,
                "{o:?} {q:?}: {first} {second} (rotation {k})"
            );
        }
        if found == 20 {
            break;
        }
    }
    assert_eq!(found, 20, "rays with an edge function rounding to 0");
}

#[test]
fn barycentric_coordinates_of_a_triangle_twice_the_unit_size() {
    // det = 4 in the sheared frame: the coordinates are U, V, W divided by it (multiplying would give 16×).
    let (v0, v1, v2) = (
        V3::new(0.0, 0.0, 0.0),
        V3::new(2.0, 0.0, 0.0),
        V3::new(0.0, 2.0, 0.0),
    );
    let down = WatertightRay::new(V3::new(0.5, 0.5, 2.0), V3::new(0.0, 0.0, -1.0)).unwrap();
    let (t, b) = down.intersect(v0, v1, v2, 0.0, 10.0).unwrap();
    assert_eq!((t, b), (2.0, [0.5, 0.25, 0.25]));
}

#[test]
fn ray_exactly_through_an_edge_hits_the_closed_triangle_in_either_orientation() {
    let (v0, v1, v2) = (
        V3::new(0.0, 0.0, 0.0),
        V3::new(1.0, 0.0, 0.0),
        V3::new(0.0, 1.0, 0.0),
    );
    // Through the middle of v0–v1 (its edge function is exactly 0), from above and from below.
    for dz in [-1.0, 1.0] {
        let r = WatertightRay::new(V3::new(0.5, 0.0, -2.0 * dz), V3::new(0.0, 0.0, dz)).unwrap();
        assert!(
            r.intersect(v0, v1, v2, 0.0, 10.0).is_some(),
            "counter-clockwise, {dz}"
        );
        assert!(
            r.intersect(v0, v2, v1, 0.0, 10.0).is_some(),
            "clockwise, {dz}"
        );
    }
}

#[test]
fn triangle_seen_almost_edge_on_within_the_rounding_bound_is_a_miss() {
    // Sheared coordinates of magnitude 1 (six products of about 1), a sliver of width δ seen along the ray,
    // which passes exactly through its edge A–B: det = 4δ. At 7 ε of the products' sum it is within the
    // edge-on bound (8 ε): a miss; at 100 ε it is a triangle: a hit.
    let eps = f64::EPSILON;
    for (k, hits) in [(7.0, false), (100.0, true)] {
        let delta = k * eps * 6.0 / 4.0;
        let (a, b, c) = (
            V3::new(1.0, 1.0, 0.0),
            V3::new(-1.0, -1.0, 0.0),
            V3::new(1.0 - delta, 1.0 + delta, 0.0),
        );
        let r = WatertightRay::new(V3::new(0.0, 0.0, 1.0), V3::new(0.0, 0.0, -1.0)).unwrap();
        let hit =
            r.intersect(a, b, c, 0.0, 10.0).is_some() || r.intersect(a, c, b, 0.0, 10.0).is_some();
        assert_eq!(hit, hits, "det at {k} ε of the products");
    }
}

#[test]
fn border_edge_seen_from_the_far_side_of_the_earth_is_decided_by_the_exact_vertices() {
    // The band is relative to the origin's and the vertices' coordinates together: a ray from the Earth's
    // centre out to a wall at 6.4e6 m passing 1e-9 m below its bottom edge, whose exact vertices lie 3e-9 m
    // lower (the ray is inside the exact triangle): a hit when the edge is on the border.
    let y0 = 6.4e6 - 0.5;
    let (v0, v1, v2) = (
        V3::new(0.0, y0, 0.0),
        V3::new(1.0, y0, 0.0),
        V3::new(0.0, y0, 1.0),
    );
    let exact = [
        [Dd::from(0.0), Dd::from(y0), Dd::from(-3e-9)],
        [Dd::from(1.0), Dd::from(y0), Dd::from(-3e-9)],
        [Dd::from(0.0), Dd::from(y0), Dd::from(1.0)],
    ];
    let (o, d) = (V3::new(0.5, 0.0, -1e-9), V3::new(0.0, 1.0, 0.0));
    let r = WatertightRay::new(o, d).unwrap();
    let border = r.intersect_with_border(
        v0,
        v1,
        v2,
        0.0,
        1e7,
        sides(o, d, exact, [false, false, true]),
    );
    assert!(border.is_some());
    assert!(r.intersect(v0, v1, v2, 0.0, 1e7).is_none());
}

#[test]
fn ray_almost_in_the_plane_of_a_triangle_is_a_miss() {
    // The triangle lies in the plane x = 0; the ray starts in that plane (outside the triangle) and leaves
    // it at an angle of 1e-13, so it meets the plane only at its origin. The projection along the ray is
    // a segment and the edge functions are rounding noise: no hit.
    let (v0, v1, v2) = (
        V3::new(0.0, 0.0, 0.0),
        V3::new(0.0, 1.0, 0.0),
        V3::new(0.0, 0.3, 1.0),
    );
    for (o, d) in [
        (V3::new(0.0, -1.0, 0.25), V3::new(1e-13, 1.0, 0.0)),
        (V3::new(0.0, -5.0e6, 0.25), V3::new(-3e-13, 1.0, 1e-9)),
        (V3::new(0.0, 2.0, 0.1), V3::new(1e-14, -1.0, 0.05)),
    ] {
        let w = WatertightRay::new(o, d).unwrap();
        assert_eq!(w.intersect(v0, v1, v2, 0.0, 1e7), None, "{o:?} {d:?}");
    }
    // A polar sliver (two vertices on the z axis, 0.25 m apart, the third 457 km away) and a ray from the
    // z axis 5.4e9 m below, heading out almost in the sliver's meridian plane (a fuzz finding): U and W
    // round to exactly 0 and V to noise, which without the edge-on test reads as a hit at vertex B, at a
    // point of the ray 343 km from the axis.
    let w = WatertightRay::new(
        V3::new(0.0, -0.0, -5_362_342_899.685_755),
        V3::new(
            -240_033.236_469_758_65,
            245_013.668_449_579_42,
            5_355_995_345.833_253,
        ),
    )
    .unwrap();
    let sliver = [
        V3::new(-0.0, 0.0, -6_356_752.564_245_179),
        V3::new(-0.0, 0.0, -6_356_752.314_245_179),
        V3::new(
            -319_786.616_911_798_5,
            326_421.845_920_123_2,
            -6_337_689.425_257_364,
        ),
    ];
    assert_eq!(
        w.intersect(sliver[0], sliver[1], sliver[2], 0.0, 10.0),
        None
    );
}

#[test]
fn ray_through_shared_edge_hits_at_least_one_triangle() {
    // Quad split along its diagonal; rays exactly through the diagonal never slip through.
    let p = [
        V3::new(0.0, 0.0, 0.3),
        V3::new(1.0, 0.0, 0.1),
        V3::new(1.0, 1.0, 0.7),
        V3::new(0.0, 1.0, 0.2),
    ];
    for k in 0..=20 {
        let s = k as f64 / 20.0 * 0.999 + 0.0005;
        // The point (s, s) of the diagonal, approached vertically and obliquely.
        let z = 0.3 + (0.7 - 0.3) * s;
        for dir in [V3::new(0.0, 0.0, -1.0), V3::new(0.013, -0.007, -1.0)] {
            let o = V3::new(s, s, z).add_scaled(-5.0, dir);
            let r = WatertightRay::new(o, dir).unwrap();
            let h1 = r.intersect(p[0], p[1], p[2], 0.0, 10.0);
            let h2 = r.intersect(p[0], p[2], p[3], 0.0, 10.0);
            assert!(h1.is_some() || h2.is_some(), "slipped through at s = {s}");
        }
    }
}

/// The edges' answer of a caller whose triangle has the exact vertices `exact` and whose edges `border` have
/// no triangle across.
fn sides(
    o: V3<f64>,
    d: V3<f64>,
    exact: [[Dd<f64>; 3]; 3],
    border: [bool; 3],
) -> impl FnOnce([bool; 3]) -> [Edge; 3] {
    move |_near| {
        let inside = exact_edge_sides(o, d, &exact).unwrap();
        [0, 1, 2].map(|k| Edge::of(border[k], Some(inside[k])))
    }
}

#[test]
fn border_edge_of_earth_scale_triangle_is_decided_by_the_exact_vertices() {
    // Scalar vertices at Earth-scale coordinates, the edge v0–v1 along y = y0; a ray straight down through a
    // point `gap` m outside (y0 − gap). The exact vertices of that edge lie `shift` m further out (the scalar
    // ones are their rounding). Exactly inside the closed triangle: a hit on the edge; exactly outside: a
    // miss, however close; a shared edge: the scalar decision (its neighbour answers).
    // A cell-sized triangle (1 km edges), so that the band scales with the edge's length.
    let y0 = 6.4e6 - 0.5;
    let (v0, v1, v2) = (
        V3::new(0.0, y0, 10.0),
        V3::new(1000.0, y0, 10.0),
        V3::new(0.0, y0 + 1000.0, 10.0),
    );
    let exact = |shift: f64| {
        let p = |v: V3<f64>, dy: f64| [Dd::from(v.x), Dd::from(v.y).plus_t(dy), Dd::from(v.z)];
        [p(v0, -shift), p(v1, -shift), p(v2, 0.0)]
    };
    let one_ulp = 2f64.powi(-30); // the ulp of y0
    for (gap, shift, border, hits) in [
        // 1 ulp outside the scalar edge, 2 ulps inside the exact one: closed on the border only.
        (one_ulp, 3.0 * one_ulp, [false, false, true], true),
        (one_ulp, 3.0 * one_ulp, [true, true, false], false),
        // 1 ulp outside both: outside the exact triangle, a miss on the border too (a widened tolerance
        // would take it).
        (one_ulp, 0.0, [false, false, true], false),
        // 1 ulp inside the scalar edge, 1 ulp outside the exact one: a miss on the border, a hit if shared.
        (-one_ulp, -2.0 * one_ulp, [false, false, true], false),
        (-one_ulp, -2.0 * one_ulp, [false, false, false], true),
        // On the exact edge: closed, a hit.
        (0.0, 0.0, [false, false, true], true),
        // Far outside: no question asked.
        (1e-6, 0.0, [true, true, true], false),
    ] {
        let (o, d) = (V3::new(500.0, y0 - gap, 20.0), V3::new(0.0, 0.0, -1.0));
        let r = WatertightRay::new(o, d).unwrap();
        let hit =
            r.intersect_with_border(v0, v1, v2, 0.0, 100.0, sides(o, d, exact(shift), border));
        assert_eq!(hit.is_some(), hits, "{gap} {shift} {border:?}");
        if let Some((t, _)) = hit {
            assert!((t - 10.0).abs() < 1e-12, "{t}");
        }
    }
}

/// The edges a ray is asked about (`near`), answered `Shared` (the scalar decision stands); `None` when it
/// passes no edge within the band and is not asked.
fn asked(r: &WatertightRay<f64>, [v0, v1, v2]: [V3<f64>; 3]) -> Option<[bool; 3]> {
    let asked = core::cell::Cell::new(None);
    let _ = r.intersect_with_border(v0, v1, v2, 0.0, 10.0, |near| {
        asked.set(Some(near));
        [Edge::Shared; 3]
    });
    asked.get()
}

/// The triangle `[p, q, r]` with its vertices rotated `k` places: the edge `p–q` is then the edge of index
/// `2 − k` (`v1–v2`, `v2–v0`, `v0–v1`).
fn rotated<V: Copy>(t: [V; 3], k: usize) -> [V; 3] {
    [t[k % 3], t[(k + 1) % 3], t[(k + 2) % 3]]
}

/// An isosceles triangle at z = 0 over the point (0, 0): its base `p–q`, 8 long along x (`along_x`) or y,
/// at `offset` from the point (positive: the point lies outside the base), and its apex `height` beyond the
/// base.
fn isosceles(along_x: bool, offset: f64, height: f64) -> [V3<f64>; 3] {
    let at = |along: f64, across: f64| {
        if along_x {
            V3::new(along, across, 0.0)
        } else {
            V3::new(across, along, 0.0)
        }
    };
    [at(-4.0, offset), at(4.0, offset), at(0.0, offset + height)]
}

#[test]
fn each_edge_is_asked_about_within_64_eps_m_times_its_length_in_the_sheared_frame() {
    // A ray straight down from (0, 0, 0.25) past the base of an isosceles triangle (8 long, along x or y,
    // the ray a distance δ outside it): m = 0.25 + 8 (the origin's largest coordinate plus the vertices'
    // largest one relative to it), the base's edge function 8δ, its band 64 ε m · 8 (the sheared frame is
    // the world's, with x and y swapped). The ray is asked about the base at δ = 64 ε m / 2 and not at
    // 2 · 64 ε m, whichever place the base has in the vertex order (the other edges are 3.6 away).
    let band = 64.0 * f64::EPSILON * (0.25 + 8.0);
    let r = WatertightRay::new(V3::new(0.0, 0.0, 0.25), V3::new(0.0, 0.0, -1.0)).unwrap();
    for along_x in [true, false] {
        for k in 0..3 {
            let mut expected = [false; 3];
            expected[2 - k] = true;
            for side in [1.0, -1.0] {
                let near = rotated(isosceles(along_x, side * 0.5 * band, 8.0), k);
                assert_eq!(asked(&r, near), Some(expected), "{along_x} {k} {side}");
                let clear = rotated(isosceles(along_x, side * 2.0 * band, 8.0), k);
                assert_eq!(asked(&r, clear), None, "{along_x} {k} {side}");
            }
        }
    }
}

/// The exact vertices (pairs) of `t` with those of its base `p–q` moved by `dy` across it (away from the
/// apex for `dy < 0`).
fn with_base_moved(t: [V3<f64>; 3], along_x: bool, dy: f64) -> [[Dd<f64>; 3]; 3] {
    let exact = |v: V3<f64>, d: f64| {
        let [x, y, z] = [v.x, v.y, v.z].map(Dd::from);
        if along_x {
            [x, y.plus_t(d), z]
        } else {
            [x.plus_t(d), y, z]
        }
    };
    [exact(t[0], dy), exact(t[1], dy), exact(t[2], 0.0)]
}

#[test]
fn gap_on_a_border_edge_is_closed_on_a_triangle_but_not_on_a_sliver() {
    // A ray straight down half a band outside the base of an isosceles triangle whose exact base lies a
    // band further out (the ray is inside the exact, closed triangle): on a border base the gap is closed,
    // a hit at t = 0.25 on the triangle 8 high, and a miss on the sliver 0.004 high (twice its area,
    // 0.032, is below 1e-3 times its longest edge squared, 0.064: closing would move the hit along it by
    // its length over its width).
    let band = 64.0 * f64::EPSILON * (0.25 + 8.0);
    let o = V3::new(0.0, 0.0, 0.25);
    let d = V3::new(0.0, 0.0, -1.0);
    let r = WatertightRay::new(o, d).unwrap();
    for along_x in [true, false] {
        for k in 0..3 {
            let mut border = [false; 3];
            border[2 - k] = true;
            for (height, hits) in [(8.0, true), (0.004, false)] {
                let t = isosceles(along_x, 0.5 * band, height);
                let exact = rotated(with_base_moved(t, along_x, -band), k);
                let [v0, v1, v2] = rotated(t, k);
                let hit =
                    r.intersect_with_border(v0, v1, v2, 0.0, 10.0, sides(o, d, exact, border));
                assert_eq!(hit.is_some(), hits, "{along_x} {k} {height}");
                if let Some((t, _)) = hit {
                    assert_eq!(t, 0.25);
                }
                // a shared base: the scalar decision, a miss
                let [v0, v1, v2] = rotated(t, k);
                assert!(r.intersect(v0, v1, v2, 0.0, 10.0).is_none());
            }
        }
    }
}

#[test]
fn ray_just_inside_a_border_edge_keeps_its_barycentric_coordinate_on_a_triangle_and_a_sliver() {
    // A ray straight down half a band inside the border base of an isosceles triangle (exact and scalar
    // vertices alike): the edge is asked about and found inside, and the right-signed edge function is kept
    // (nothing is closed): the coordinate of the apex is δ / height, not 0, and the sliver 0.004 high is hit
    // as well as the triangle 8 high.
    let band = 64.0 * f64::EPSILON * (0.25 + 8.0);
    let delta = 0.5 * band;
    let o = V3::new(0.0, 0.0, 0.25);
    let d = V3::new(0.0, 0.0, -1.0);
    let r = WatertightRay::new(o, d).unwrap();
    for along_x in [true, false] {
        for k in 0..3 {
            let mut border = [false; 3];
            border[2 - k] = true;
            for height in [8.0, 0.004] {
                let t = isosceles(along_x, -delta, height);
                let exact = rotated(with_base_moved(t, along_x, 0.0), k);
                let [v0, v1, v2] = rotated(t, k);
                let hit =
                    r.intersect_with_border(v0, v1, v2, 0.0, 10.0, sides(o, d, exact, border));
                assert!(hit.is_some(), "{along_x} {k} {height}: a miss");
                let (t, b) = hit.unwrap();
                assert!((t - 0.25).abs() < 1e-15, "{t}");
                // the apex, opposite the base, is v_(2 − k) of the rotated triangle
                let apex = (2 + 3 - k) % 3;
                let expected = delta / height;
                assert!(
                    (b[apex] / expected - 1.0).abs() < 1e-9,
                    "{along_x} {k} {height}: {b:?} against {expected}"
                );
            }
        }
    }
}

#[test]
fn exact_edge_sides_of_a_ray_through_a_vertex_count_it_on_both_edges() {
    let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]].map(|p| p.map(Dd::from));
    let down = V3::new(0.0, 0.0, -1.0);
    // Through v0: on edges v2–v0 and v0–v1, inside v1–v2.
    assert_eq!(
        exact_edge_sides(V3::new(0.0, 0.0, 1.0), down, &v),
        Some([true; 3])
    );
    // 1e-20 outside v0 towards −x: outside v2–v0 only; 1e-300 is within the pair arithmetic's error bound,
    // on the edge.
    assert_eq!(
        exact_edge_sides(V3::new(-1e-20, 0.0, 1.0), down, &v),
        Some([true, false, true])
    );
    assert_eq!(
        exact_edge_sides(V3::new(-1e-300, 0.0, 1.0), down, &v),
        Some([true; 3])
    );
    // In the triangle's plane: no orientation.
    assert_eq!(
        exact_edge_sides(V3::new(-1.0, 0.5, 0.0), V3::new(1.0, 0.0, 0.0), &v),
        None
    );
}

#[test]
fn exact_edge_sides_counts_a_ray_on_the_edge_within_its_error_bound_and_outside_beyond_it() {
    // The triangle (1, 0, 0), (2, 0, 0), (1, 1, 0) with its edge v2–v0 moved out to x = 1 + ξ (pairs), and the
    // line from (0, −0.75, 4) along (1, 1, −4) through (1, 0.25, 0), a distance ξ outside that edge in the
    // plane: its side value there is d · ((v2 − o) × (v0 − o)) = 4ξ. The bound is 256 ε² ‖d‖₁ (‖v2 − o‖∞ +
    // M)(‖v0 − o‖∞ + M) = 256 ε² · 6 · (4 + 2)² (M = 2, the largest vertex coordinate): at 0.9 times it the
    // line is on the edge, at 1.1 times outside; the other two edges are far.
    let bound = 256.0 * f64::EPSILON * f64::EPSILON * 6.0 * 36.0;
    let (o, d) = (V3::new(0.0, -0.75, 4.0), V3::new(1.0, 1.0, -4.0));
    for (k, on_edge) in [(0.9, true), (1.1, false)] {
        let xi = k * bound / 4.0;
        let x = Dd::new(1.0, xi);
        let v = [
            [x, Dd::from(0.0), Dd::from(0.0)],
            [Dd::from(2.0), Dd::from(0.0), Dd::from(0.0)],
            [x, Dd::from(1.0), Dd::from(0.0)],
        ];
        assert_eq!(
            exact_edge_sides(o, d, &v),
            Some([true, on_edge, true]),
            "{k} times the bound"
        );
    }
}

#[test]
fn line_within_the_error_bound_of_the_triangles_plane_has_no_orientation() {
    // The unit triangle at z = 0 and the line from (−1, 0.25, 0) along (1, 0, η), rising out of the plane
    // at slope η: the three side values are η times the signed areas 1.75, −1 and 0.25, their sum (the
    // orientation) η. Their error bounds, 256 ε² ‖d‖₁ (‖v_a − o‖∞ + M)(‖v_b − o‖∞ + M) with M = 1, are
    // 256 ε² · (6, 4, 6), 2⁻⁹² together (all exact here): at 0.75 and at exactly 1 times that the line has
    // no orientation (a tie counts as within the error), at 1.25 times it has one.
    let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]].map(|p| p.map(Dd::from));
    let bound = 256.0 * f64::EPSILON * f64::EPSILON * (6.0 + 4.0 + 6.0);
    // (2⁻⁹² from its bits: `powi` need not be exact, and under Miri it is not)
    assert_eq!(bound, f64::from_bits((1023 - 92) << 52));
    let o = V3::new(-1.0, 0.25, 0.0);
    for (k, oriented) in [(0.75, false), (1.0, false), (1.25, true)] {
        let d = V3::new(1.0, 0.0, k * bound);
        assert_eq!(exact_edge_sides(o, d, &v).is_some(), oriented, "{k}");
    }
}

#[test]
fn degenerate_triangle_and_zero_direction() {
    let v = V3::new(1.0, 1.0, 1.0);
    let r = WatertightRay::new(V3::new(1.0, 1.0, 5.0), V3::new(0.0, 0.0, -1.0)).unwrap();
    assert!(r.intersect(v, v, v, 0.0, 10.0).is_none());
    assert!(WatertightRay::new(V3::new(0.0, 0.0, 0.0), V3::new(0.0, 0.0, 0.0)).is_none());
}
