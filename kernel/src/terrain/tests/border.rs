//! Rays through vertices and edges on the border of the surface: the outer edge, the grid's corners, and the
//! edges and corners of nodata holes. Triangles are closed, and nothing outside them is hit (triangle.rs, "Edges
//! on the border of the surface"): each ray passes a stated distance inside or outside the exact triangles (their
//! vertices in pairs, as the contract defines them), far above the pair arithmetic's error and far below the
//! scalar vertices' rounding where that is the point.

use super::*;
use crate::dd::Dd;

/// The exact (pair) vertex `V(i, j)` rounded to scalars, which is within an ulp of the exact one.
fn exact(s: &Surface, (i, j): (u32, u32)) -> V3<f64> {
    let [x, y, z] = s.vertex_dd(i, j).unwrap().map(Dd::value);
    V3::new(x, y, z)
}

/// The triangles of the surface (their three vertices have data), as vertex index triples.
fn triangles(s: &Surface) -> Vec<[(u32, u32); 3]> {
    let (rows, cols) = (s.grid.rows, s.grid.cols);
    let mut out = Vec::new();
    for i in 0..rows - 1 {
        for j in 0..cols - 1 {
            for t in [
                [(i, j), (i, j + 1), (i + 1, j + 1)],
                [(i, j), (i + 1, j + 1), (i + 1, j)],
            ] {
                if t.iter().all(|&(a, b)| s.h(a, b).is_some()) {
                    out.push(t);
                }
            }
        }
    }
    out
}

/// A ray straight down onto point `p` from 1000 m above it along the ellipsoid normal there.
pub(super) fn ray_down_onto(e: &Ellipsoid<f64>, p: V3<f64>) -> Ray<f64> {
    let g = e.ecef_to_geodetic(p);
    let n = e.normal_rad(g.lat_rad, g.lon_rad);
    Ray::new(p.add_scaled(1000.0, n), n.negated()).unwrap()
}

/// Straight-down rays through points 10 nm from each given vertex towards the centroid of a triangle at it (inside
/// the closed triangles by far more than the rays' rounding, far less than the scalar vertices' rounding can
/// move an edge), on terrain of grids of several sizes, places and heights: each must hit at its vertex, at `t`
/// = 1000 m, and the brute force with the same border rule agrees. With `outside`, the same distance on the other
/// side of the vertex (outside a convex corner or a straight outer edge) must miss.
fn assert_hits_down_through(dem: &TestDem, vertices: &[(u32, u32)], what: &str) -> usize {
    assert_down_through(dem, vertices, what, false)
}

fn assert_down_through(dem: &TestDem, vertices: &[(u32, u32)], what: &str, outside: bool) -> usize {
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let tris = triangles(&dem.surface);
    for &(i, j) in vertices {
        let v = exact(&dem.surface, (i, j));
        let tri = tris.iter().find(|t| t.contains(&(i, j))).unwrap();
        let centroid = tri.iter().fold(V3::new(0.0, 0.0, 0.0), |c, &q| {
            c.add_scaled(1.0 / 3.0, exact(&dem.surface, q))
        });
        let towards = centroid.minus(v).scaled(1.0 / centroid.minus(v).length());
        let h = dem.surface.h(i, j).unwrap();
        let ray = ray_down_onto(&dem.surface.e, v.add_scaled(1e-8, towards));
        let hit = p.pick(&ray).unwrap();
        // Near a vertex the two may pick different triangles around it, at the same point.
        let brute = dem.surface.brute(&ray);
        assert!(
            brute.is_some(),
            "{what}: the brute force misses V({i}, {j})"
        );
        assert!(hit.is_some(), "{what}: ray down through V({i}, {j}) missed");
        let hit = hit.unwrap();
        assert!(
            (hit.t - 1000.0).abs() < 1e-6,
            "{what} V({i}, {j}): t = {}",
            hit.t
        );
        assert!(
            (hit.h - h).abs() < 1e-6,
            "{what} V({i}, {j}): h = {}",
            hit.h
        );
        if outside {
            let ray = ray_down_onto(&dem.surface.e, v.add_scaled(-1e-8, towards));
            assert_eq!(
                p.pick(&ray).unwrap(),
                None,
                "{what}: 10 nm outside V({i}, {j})"
            );
            assert_eq!(
                dem.surface.brute(&ray),
                None,
                "{what}: brute, 10 nm outside V({i}, {j})"
            );
        }
    }
    vertices.len()
}

/// The grids of the border-vertex tests: `(lat0_deg, lon0_deg, spacing, height)`, 9 × 9 vertices, rows southwards for
/// one of them.
const BORDER_GRIDS: [(f64, f64, f64, f64); 5] = [
    (45.0, 7.0, 0.01, 0.0),
    (-33.0, 151.0, -0.001, 250.0),
    (10.0, -120.0, 0.1, 1000.0),
    (60.0, 20.0, 1.0 / 1200.0, 17.0),
    (0.0, 0.0, 0.003, 3.0),
];

#[test]
#[cfg_attr(miri, ignore)] // 160 picks: minutes under Miri; the corner and hole tests cover the same code
fn rays_down_through_vertices_on_the_outer_edge_of_grids_hit() {
    let mut n = 0;
    for (lat0_deg, lon0_deg, d, h) in BORDER_GRIDS {
        let dem = TestDem::new(
            grid(lat0_deg, lon0_deg, d, d.abs(), 9, 9),
            std::vec![h; 81],
            2,
        );
        let edge: Vec<(u32, u32)> = (0..9)
            .flat_map(|i| (0..9).map(move |j| (i, j)))
            .filter(|&(i, j)| i == 0 || j == 0 || i == 8 || j == 8)
            .collect();
        n += assert_down_through(
            &dem,
            &edge,
            &std::format!("grid at {lat0_deg}°, {lon0_deg}°"),
            true,
        );
    }
    assert_eq!(n, 160);
}

#[test]
#[cfg_attr(miri, ignore)] // 20 picks: over a minute under Miri; triangle.rs tests the border rule itself
fn rays_down_through_the_four_corner_vertices_of_grids_hit() {
    for (lat0_deg, lon0_deg, d, h) in BORDER_GRIDS {
        let dem = TestDem::new(
            grid(lat0_deg, lon0_deg, d, d.abs(), 9, 9),
            std::vec![h; 81],
            2,
        );
        let corners = [(0, 0), (0, 8), (8, 0), (8, 8)];
        assert_down_through(
            &dem,
            &corners,
            &std::format!("corners at {lat0_deg}°, {lon0_deg}°"),
            true,
        );
    }
}

#[test]
#[cfg_attr(miri, ignore)] // dozens of picks or builds: minutes under Miri; triangle.rs and the builder's error test run there
fn rays_down_through_the_edge_vertices_of_a_one_vertex_nodata_hole_hit() {
    // Nodata at V(4, 4) removes its six triangles; the hole's edge is the hexagon of its neighbours (each a
    // corner of the hole's outline).
    for (lat0_deg, lon0_deg, d, h) in BORDER_GRIDS {
        let mut hs = std::vec![h; 81];
        hs[4 * 9 + 4] = f64::NAN;
        let dem = TestDem::new(grid(lat0_deg, lon0_deg, d, d.abs(), 9, 9), hs, 2);
        let ring = [(3, 3), (3, 4), (4, 5), (5, 5), (5, 4), (4, 3)];
        assert_hits_down_through(
            &dem,
            &ring,
            &std::format!("hole at {lat0_deg}°, {lon0_deg}°"),
        );
        // Straight down through the missing vertex: no triangle there.
        let ray = radial_ray(
            &dem.surface.e,
            dem.surface.grid.lat_deg(4),
            dem.surface.grid.lon_deg(4),
            h + 1000.0,
        );
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        assert_eq!(p.pick(&ray).unwrap(), None);
    }
}

#[test]
#[cfg_attr(miri, ignore)] // dozens of picks or builds: minutes under Miri; triangle.rs and the builder's error test run there
fn rays_down_through_the_edges_and_corners_of_a_square_nodata_hole_hit() {
    // Nodata at the 3 × 3 vertices V(3..=5, 3..=5): the hole's outline runs along rows 2 and 6 and columns 2
    // and 6 (straight edges, with corners at V(2, 2), V(2, 6), V(6, 2), V(6, 6)) and steps inwards along the
    // diagonals at V(2, 3) ... (the cells' diagonals keep some triangles).
    for (lat0_deg, lon0_deg, d, h) in BORDER_GRIDS {
        let mut hs = std::vec![h; 81];
        for i in 3..=5 {
            for j in 3..=5 {
                hs[i * 9 + j] = f64::NAN;
            }
        }
        let dem = TestDem::new(grid(lat0_deg, lon0_deg, d, d.abs(), 9, 9), hs, 2);
        let outline: Vec<(u32, u32)> = (2..=6)
            .flat_map(|i| (2..=6).map(move |j| (i, j)))
            .filter(|&(i, j)| i == 2 || j == 2 || i == 6 || j == 6)
            .collect();
        assert_eq!(outline.len(), 16);
        assert_hits_down_through(
            &dem,
            &outline,
            &std::format!("square hole at {lat0_deg}°, {lon0_deg}°"),
        );
    }
}

/// The grids of the border-edge tests: `(lat0_deg, lon0_deg, dlat_deg, dlon_deg)` of 9 × 9 vertices: mid-latitude
/// rows northwards and southwards, the polar cap below −80° (its northern edge a parallel, cells of 1/12° × 1/3°),
/// the cap's other edge at −80° seen from the north (rows northwards from −80.667°), and cells of 1/8° × 1° ending
/// 0.125° below the north pole.
const EDGE_GRIDS: [(f64, f64, f64, f64); 5] = [
    (45.0, 7.0, 0.01, 0.01),
    (-33.0, 151.0, -0.001, 0.001),
    (-80.0, 17.0, -1.0 / 12.0, 1.0 / 3.0),
    (-80.0 - 8.0 / 12.0, -179.0, 1.0 / 12.0, 1.0 / 3.0),
    (88.875, -3.0, 0.125, 1.0),
];

/// Whether the edge `a–b` of a triangle has a triangle across it (both share the edge).
fn shared(tris: &[[(u32, u32); 3]], a: (u32, u32), b: (u32, u32)) -> usize {
    tris.iter()
        .filter(|t| t.contains(&a) && t.contains(&b))
        .count()
}

/// For every edge on the border of the surface (the outer edge, a nodata hole's edge), straight-down rays onto
/// points a fraction `f` of the triangle's height over that edge inside it and outside it, at the edge's middle
/// and near its ends, for f = 1e-4, 1e-6 and 1e-9: inside hits at the point, outside misses. The points are
/// formed from the exact vertices, so that the edge is the chord of the contract's triangle (poleward of a
/// parallel edge's latitude by its sagitta, 4.7 m at mid-edge on the polar cap's cells).
fn assert_both_sides_of_border_edges(dem: &TestDem, what: &str) -> usize {
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let tris = triangles(&dem.surface);
    let mut n = 0;
    for t in &tris {
        for k in 0..3 {
            let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            if shared(&tris, a, b) > 1 {
                continue;
            }
            let [va, vb, vc] = [a, b, c].map(|q| exact(&dem.surface, q));
            if va == vb {
                continue; // an edge of pole-row vertices has no length
            }
            for along in [0.5, 0.1, 0.9] {
                let q = va.add_scaled(along, vb.minus(va));
                // The foot of the perpendicular from c, so that "a fraction of the height" is measured across the edge.
                let e = vb.minus(va);
                let foot = va.add_scaled(vc.minus(va).dot(e) / e.dot(e), e);
                let up = vc.minus(foot);
                for f in [1e-4, 1e-6, 1e-9] {
                    let inside = ray_down_onto(&dem.surface.e, q.add_scaled(f, up));
                    let hit = p.pick(&inside).unwrap();
                    assert!(
                        hit.is_some_and(|h| (h.t - 1000.0).abs() < 1e-6),
                        "{what}: {f} inside the edge V{a:?}–V{b:?} at {along}: {hit:?}"
                    );
                    let outside = ray_down_onto(&dem.surface.e, q.add_scaled(-f, up));
                    let hit = p.pick(&outside).unwrap();
                    assert!(
                        hit.is_none(),
                        "{what}: {f} outside the edge V{a:?}–V{b:?} at {along}: {hit:?}"
                    );
                    n += 2;
                }
            }
        }
    }
    n
}

/// Heights of a 9 × 9 grid with relief (hundreds of metres), NaN where `hole(i, j)`.
fn relief(hole: impl Fn(usize, usize) -> bool) -> Vec<f64> {
    (0..81)
        .map(|k| {
            let (i, j) = (k / 9, k % 9);
            if hole(i, j) {
                f64::NAN
            } else {
                300.0 + 200.0 * (0.7 * i as f64).sin() * (1.3 * j as f64).cos()
            }
        })
        .collect()
}

#[test]
#[cfg_attr(miri, ignore)] // thousands of picks: hours under Miri; triangle.rs tests the edge rule itself there
fn rays_1e4_1e6_1e9_of_a_cell_inside_and_outside_outer_parallel_and_meridian_edges_and_corners() {
    for (lat0, lon0, dlat, dlon) in EDGE_GRIDS {
        let dem = TestDem::new(grid(lat0, lon0, dlat, dlon, 9, 9), relief(|_, _| false), 2);
        let n = assert_both_sides_of_border_edges(&dem, &std::format!("grid at {lat0}°, {lon0}°"));
        assert!(n >= 32 * 18, "{n}");
    }
}

#[test]
#[cfg_attr(miri, ignore)] // thousands of picks: hours under Miri; triangle.rs tests the edge rule itself there
fn rays_1e4_1e6_1e9_of_a_cell_inside_and_outside_the_edges_of_nodata_holes() {
    for (lat0, lon0, dlat, dlon) in EDGE_GRIDS {
        // A one-vertex hole, a 2 × 2 hole and a hole at the grid's corner.
        let hole = |i: usize, j: usize| {
            (i, j) == (2, 2) || ((5..=6).contains(&i) && (4..=5).contains(&j)) || (i, j) == (8, 8)
        };
        let dem = TestDem::new(grid(lat0, lon0, dlat, dlon, 9, 9), relief(hole), 2);
        let n = assert_both_sides_of_border_edges(&dem, &std::format!("holes at {lat0}°, {lon0}°"));
        assert!(n >= 32 * 18, "{n}");
    }
}

/// The reported case: the polar cap's northern edge at −80° (cells of 1/12° × 1/3°), a ray from far away (the
/// scalar test's rounding there is metres) aimed 1e-4 of a cell outside that edge at the terrain's height: no hit.
#[test]
fn ray_from_far_away_aimed_just_outside_the_polar_caps_edge_misses() {
    let dem = TestDem::new(
        grid(-80.0, 0.0, -1.0 / 12.0, 1.0 / 3.0, 2, 2),
        std::vec![1000.0; 4],
        2,
    );
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = &dem.surface.e;
    for (lon, dist) in [
        (0.0, 2e14),
        (1.0 / 6.0, 1e15),
        (1e-3, 1e13),
        (1.0 / 6.0, 1e7),
    ] {
        let lat = -80.0 + 1e-4 / 12.0;
        let target = e.geodetic_deg_to_ecef(lat, lon, 1000.0);
        let n = e.normal_deg(lat, lon);
        let ray = Ray::new(target.add_scaled(dist, n), n.negated()).unwrap();
        assert_eq!(p.pick(&ray).unwrap(), None, "lon {lon}, from {dist} m");
        // And from as far, half a cell inside the edge is a hit.
        let (lat, lon) = (-80.0 - 0.5 / 12.0, 1.0 / 6.0);
        let inside = e.geodetic_deg_to_ecef(lat, lon, 1000.0);
        let n = e.normal_deg(lat, lon);
        let ray = Ray::new(inside.add_scaled(dist, n), n.negated()).unwrap();
        assert!(p.pick(&ray).unwrap().is_some(), "inside, from {dist} m");
    }
}

/// A point in pairs.
pub(super) fn dd3(v: V3<f64>) -> [Dd<f64>; 3] {
    [v.x, v.y, v.z].map(Dd::from)
}

/// The side of the line `a–b` on which `x` lies, seen along `ray` (pairs throughout): the sign of
/// `((b − a) × (x − a)) · d`, rounded to a scalar once.
pub(super) fn side_along(ray: &Ray<f64>, a: [Dd<f64>; 3], b: [Dd<f64>; 3], x: [Dd<f64>; 3]) -> f64 {
    let sub = |x: [Dd<f64>; 3], y: [Dd<f64>; 3]| [0, 1, 2].map(|k| x[k].minus(y[k]));
    let (u, v, d) = (sub(b, a), sub(x, a), dd3(ray.dir()));
    let n = [
        u[1].times(v[2]).minus(u[2].times(v[1])),
        u[2].times(v[0]).minus(u[0].times(v[2])),
        u[0].times(v[1]).minus(u[1].times(v[0])),
    ];
    n[0].times(d[0])
        .plus(n[1].times(d[1]))
        .plus(n[2].times(d[2]))
        .value()
}

/// For every edge on the outer border of a grid, straight-down rays onto points swept across the edge's middle
/// in steps of 0.5 nm from 4 nm outside to 4 nm inside: within the scalar vertices' rounding (about 1 nm at
/// Earth scale), where the watertight test on `f64` vertices cannot tell the side and the exact decision of
/// `refine::exact_sides` must. Each ray must hit exactly when, by the contract's vertices in pairs, it passes
/// through the closed triangle at that edge: seen along the ray, on the third vertex's side of the edge or on
/// the edge (a sign of `((b − a) × (o − a)) · d`, formed here in pairs).
#[test]
#[cfg_attr(miri, ignore)] // hundreds of picks
fn rays_swept_across_outer_edges_within_the_vertices_rounding_hit_exactly_the_closed_triangles() {
    let (mut hits, mut misses) = (0, 0);
    for (lat0, lon0, dlat, dlon) in EDGE_GRIDS {
        let dem = TestDem::new(grid(lat0, lon0, dlat, dlon, 9, 9), relief(|_, _| false), 2);
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        let tris = triangles(&dem.surface);
        for t in &tris {
            for k in 0..3 {
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let [va, vb, vc] = [a, b, c].map(|q| exact(&dem.surface, q));
                if shared(&tris, a, b) > 1 || va == vb {
                    continue;
                }
                let [da, db, dc] = [a, b, c].map(|q| dem.surface.vertex_dd(q.0, q.1).unwrap());
                let e = vb.minus(va);
                let foot = va.add_scaled(vc.minus(va).dot(e) / e.dot(e), e);
                let inward = vc.minus(foot).scaled(1.0 / vc.minus(foot).length());
                let mid = va.add_scaled(0.5, e);
                for step in -8..=8 {
                    let ray = ray_down_onto(
                        &dem.surface.e,
                        mid.add_scaled(0.5e-9 * f64::from(step), inward),
                    );
                    let side = side_along(&ray, da, db, dd3(ray.origin()));
                    let third = side_along(&ray, da, db, dc);
                    let inside = side == 0.0 || (side > 0.0) == (third > 0.0);
                    let hit = p.pick(&ray).unwrap();
                    assert_eq!(
                        hit.is_some(),
                        inside,
                        "grid at {lat0}°, {lon0}°: {step} × 0.5 nm across V{a:?}–V{b:?}: {hit:?}"
                    );
                    if inside { hits += 1 } else { misses += 1 }
                }
            }
        }
    }
    // the sweep straddles the edges: both answers occur
    assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
}
