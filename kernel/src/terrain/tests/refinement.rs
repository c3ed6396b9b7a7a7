//! The refinement of the nearest hit (`refine.rs`): refined hits on their triangle's plane through the contract's
//! vertices in pairs (steep and grazing rays, through vertices and edge midpoints), the containment walk from each
//! neighbour, the tolerance beyond an edge, and no triangle outside the grid.

use super::*;

/// The ray's refined hit, the traversal's `t` (`pick_t`) and where the ray meets the plane of the hit cell's
/// triangle nearest the refined `t` (the one hit), through the contract's vertices in pairs; `None` on a miss.
fn against_exact_plane(
    dem: &TestDem,
    p: &Picker<'_, f64, Storage<'_>>,
    ray: &Ray<f64>,
) -> Option<(Hit<f64>, f64, f64)> {
    let (hit, (t_trav, _)) = (p.pick(ray).unwrap()?, p.pick_t(ray).unwrap()?);
    let [i, j] = hit.cell;
    let v = |i: u32, j: u32| dem.surface.vertex_dd(i, j).unwrap();
    let tris = [
        [v(i, j), v(i, j + 1), v(i + 1, j + 1)],
        [v(i, j), v(i + 1, j + 1), v(i + 1, j)],
    ];
    let t_exact = nearest_plane_t(ray, hit.t, tris);
    Some((hit, t_trav, t_exact))
}

/// The refinement (`refine.rs`): a hit's `t` is where the ray meets its triangle's plane through the contract's
/// vertices in pairs, to about the rounding of `t` itself. Checked against that plane intersection formed here in
/// pairs from the vertices (`Surface::vertex_dd`), for rays slanting down from 2 km above a rough 3″ terrain and
/// from 300 km away: within 1e-10 m (3.4e-13 m measured), where the traversal's own `t` (`pick_t`, from the
/// vertices rounded to `f64`) is off by up to 2.2e-9 m here (as is any hit left unrefined).
#[test]
fn refined_hits_lie_on_their_triangles_exact_plane_far_below_the_f64_vertices_rounding() {
    let (rows, cols) = (17, 17);
    let g = grid(46.0, 8.0, -1.0 / 1200.0, 1.0 / 1200.0, rows, cols);
    let mut r = Lcg(5);
    let hs: Vec<f64> = (0..rows * cols).map(|_| 800.0 + 600.0 * r.next()).collect();
    let dem = TestDem::new(g, hs, 4);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let (mut worst_refined, mut worst_traversal, mut hits) = (0.0_f64, 0.0_f64, 0);
    // (under Miri, whose interpreter is slow, the first six rays)
    let n = if cfg!(miri) { 6 } else { 60 };
    for k in 0..n {
        let lat = g.lat_deg(2) + (g.lat_deg(14) - g.lat_deg(2)) * r.next();
        let lon = g.lon_deg(2) + (g.lon_deg(14) - g.lon_deg(2)) * r.next();
        let target = e.geodetic_deg_to_ecef(lat, lon, 1000.0 * r.next());
        // downward, at random slants
        let up = e.normal_rad(lat.to_radians(), lon.to_radians());
        let dir = V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5).minus(up);
        let dist = if k % 2 == 0 { 2000.0 } else { 3.0e5 };
        let ray = Ray::new(target.add_scaled(-dist / dir.length(), dir), dir).unwrap();
        let Some((hit, t_trav, t_exact)) = against_exact_plane(&dem, &p, &ray) else {
            continue;
        };
        hits += 1;
        let len = ray.dir().length();
        worst_refined = worst_refined.max((hit.t - t_exact).abs() * len);
        worst_traversal = worst_traversal.max((t_trav - t_exact).abs() * len);
    }
    assert!(3 * hits >= 2 * n, "{hits} hits of {n}");
    assert!(worst_refined < 1e-10, "refined: {worst_refined} m");
    // (what the refinement improves on: the traversal's t is far coarser, so the bound above can fail)
    assert!(
        worst_traversal > 100.0 * worst_refined,
        "traversal {worst_traversal} m, refined {worst_refined} m"
    );
}

/// Grazing rays (1e-3 to 3e-3 rad below the horizon) onto nearly flat 3″ terrain (1 000 m plus up to 0.2 m): the
/// traversal's `t` errs by the vertices' rounding over the sine of the incidence, micrometres here, and the
/// refinement must still put both `t` and the ECEF point on the triangle's plane through the contract's vertices
/// in pairs (`t` within 1e-10 m, 7.3e-12 m measured; the point within 2e-9 m of the ray at that `t`, two ulps of
/// Earth coordinates, where it lies exactly as measured), where the traversal's `t` is 7.5e-7 m off.
#[test]
fn refined_grazing_hits_lie_on_their_triangles_exact_plane_point_and_parameter() {
    let (rows, cols) = (17, 17);
    let g = grid(46.0, 8.0, -1.0 / 1200.0, 1.0 / 1200.0, rows, cols);
    let mut r = Lcg(11);
    let hs: Vec<f64> = (0..rows * cols).map(|_| 1000.0 + 0.2 * r.next()).collect();
    let dem = TestDem::new(g, hs, 4);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let (mut worst_t, mut worst_point, mut worst_traversal, mut hits) =
        (0.0_f64, 0.0_f64, 0.0_f64, 0);
    // (under Miri, whose interpreter is slow, the first six rays)
    let n = if cfg!(miri) { 6 } else { 40 };
    for _ in 0..n {
        let lat = g.lat_deg(4) + (g.lat_deg(12) - g.lat_deg(4)) * r.next();
        let lon = g.lon_deg(4) + (g.lon_deg(12) - g.lon_deg(4)) * r.next();
        let target = e.geodetic_deg_to_ecef(lat, lon, 1000.1);
        let up = e.normal_rad(lat.to_radians(), lon.to_radians());
        // a horizontal direction at a random azimuth, tilted down by 1e-3 to 3e-3 rad, from 300 m back (0.3 m
        // to 0.9 m above the target, over the highest vertex)
        let side = V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5);
        let flat = side.minus(up.scaled(side.dot(up)));
        let flat = flat.scaled(1.0 / flat.length());
        let dir = flat.add_scaled(-(1e-3 + 2e-3 * r.next()), up);
        let ray = Ray::new(target.add_scaled(-300.0, dir), dir).unwrap();
        let Some((hit, t_trav, t_exact)) = against_exact_plane(&dem, &p, &ray) else {
            continue;
        };
        hits += 1;
        let len = ray.dir().length();
        worst_t = worst_t.max((hit.t - t_exact).abs() * len);
        worst_traversal = worst_traversal.max((t_trav - t_exact).abs() * len);
        let on_ray = V3::from(ray.at(t_exact));
        worst_point = worst_point.max(V3::from(hit.ecef).minus(on_ray).length());
    }
    assert!(2 * hits >= n, "{hits} hits of {n}");
    assert!(worst_t < 1e-10, "refined t: {worst_t} m");
    assert!(worst_point < 2e-9, "refined point: {worst_point} m");
    // (the traversal's own t is far coarser at these incidences)
    assert!(worst_traversal > 1e-8, "traversal {worst_traversal} m");
}

/// The refinement's containment walk (`refine.rs`, "Ties"): started on a neighbour of the triangle a ray crosses,
/// across each of the three edges of either triangle of a cell, the walk steps across the one edge the start
/// plane's point lies beyond, to the crossed triangle, and the refined `t` lies on that triangle's plane through
/// the contract's vertices in pairs. Each ray descends along the normal through the crossed triangle's centroid on
/// rough 3.6″ terrain (the start triangles' planes differ from the crossed one's by tens of metres there).
#[test]
fn containment_walk_from_each_neighbour_steps_across_the_shared_edge_to_the_crossed_triangle() {
    use super::refine::{Tri, refine};
    let (rows, cols) = (6, 6);
    let g = grid(45.0, 7.0, 0.001, 0.001, rows, cols);
    let mut r = Lcg(9);
    let hs: Vec<f64> = (0..rows * cols).map(|_| 300.0 * r.next()).collect();
    let dem = TestDem::new(g, hs, 4);
    let s = dem.storage();
    let e = dem.surface.e;
    let v = |i: u32, j: u32| dem.surface.vertex_dd(i, j).unwrap();
    let (i, j) = (2, 2);
    // The crossed triangle's grid vertices, and its neighbours across its edges opposite v0, v1, v2 (written out
    // here rather than taken from the refinement's own `across`).
    let cases = [
        (
            Tri::First,
            [(i, j), (i, j + 1), (i + 1, j + 1)],
            [
                ([i, j + 1], Tri::Second),
                ([i, j], Tri::Second),
                ([i - 1, j], Tri::Second),
            ],
        ),
        (
            Tri::Second,
            [(i, j), (i + 1, j + 1), (i + 1, j)],
            [
                ([i + 1, j], Tri::First),
                ([i, j - 1], Tri::First),
                ([i, j], Tri::First),
            ],
        ),
    ];
    for (tri, corners, neighbours) in cases {
        let (lat, lon) = corners.iter().fold((0.0, 0.0), |(a, b), &(ci, cj)| {
            (a + g.lat_deg(ci) / 3.0, b + g.lon_deg(cj) / 3.0)
        });
        let ray = radial_ray(&e, lat, lon, 2000.0);
        let t_exact = dd_plane_t(&ray, corners.map(|(ci, cj)| v(ci, cj)));
        for (k, (start, start_tri)) in neighbours.into_iter().enumerate() {
            let refined = refine(&s, &g, &ray, t_exact, start, start_tri, &|_| true);
            assert!(
                refined.is_some_and(|(t, _)| (t - t_exact).abs() < 1e-10),
                "{tri:?} from across edge {k}: {refined:?}, t {t_exact}"
            );
        }
        // Started on the crossed triangle itself, no step.
        let (t, _) = refine(&s, &g, &ray, t_exact, [i, j], tri, &|_| true).unwrap();
        assert!((t - t_exact).abs() < 1e-10, "{tri:?}");
    }
}

/// Outside the grid the refinement has no triangle: a cell in the grid's last row or column of vertices (whose
/// far corners would be past the grid) and a triangle with a vertex one column or one row past the grid give no
/// refined hit and no exact sides (the traversal never asks for them; the refinement's own range checks and the
/// storage's, whose height is `None` out of range, each ensure it).
#[test]
fn refinement_of_a_cell_or_vertex_outside_the_grid_is_none() {
    use super::refine::{Tri, TriRef, Vtx, exact_sides, refine};
    let (rows, cols) = (5, 5);
    let g = grid(45.0, 7.0, 0.001, 0.001, rows, cols);
    let dem = TestDem::new(g, std::vec![100.0; (rows * cols) as usize], 2);
    let s = dem.storage();
    let ray = radial_ray(&dem.surface.e, g.lat_deg(1), g.lon_deg(1), 1000.0);
    for tri in [Tri::First, Tri::Second] {
        // cell [1, 1] is inside and refines; cells on the last column or row of vertices do not
        assert!(refine(&s, &g, &ray, 900.0, [1, 1], tri, &|_| true).is_some());
        for cell in [[1, cols - 1], [rows - 1, 1]] {
            assert_eq!(
                refine(&s, &g, &ray, 900.0, cell, tri, &|_| true),
                None,
                "{cell:?}"
            );
        }
    }
    let inside = [Vtx::Grid(1, 1), Vtx::Grid(1, 2), Vtx::Grid(2, 2)];
    assert!(exact_sides(&s, &g, &ray, [1, 1], TriRef::Vertices(inside)).is_some());
    for past in [Vtx::Grid(1, cols), Vtx::Grid(rows, 1)] {
        let tri = TriRef::Vertices([Vtx::Grid(1, 1), past, Vtx::Grid(2, 2)]);
        assert_eq!(exact_sides(&s, &g, &ray, [1, 1], tri), None, "{past:?}");
    }
}

/// Rays through grid vertices and edge midpoints, where the triangles that share the point each see it on an
/// edge, within rounding outside or inside: straight down onto rough 3.6″ terrain, and grazing (0.1° below the
/// horizon, from 2 km away) onto nearly flat terrain, where a plane's point slides along it by the miss over the
/// sine of the incidence. The containment walk's tolerance (`16 ε ‖p‖∞`) settles the refinement, and the refined
/// `t` lies on one of their planes through the contract's vertices in pairs (within 1e-10 m), where the traversal's
/// `t` is off by the `f64` vertices' rounding.
#[test]
fn refined_hits_through_vertices_and_edge_midpoints_settle_on_a_plane_that_shares_the_point() {
    let (rows, cols) = (8, 8);
    let g = grid(45.0, 7.0, 0.001, 0.001, rows, cols);
    for (relief, grazing) in [(300.0, false), (0.2, true)] {
        let mut r = Lcg(17);
        let hs: Vec<f64> = (0..rows * cols)
            .map(|_| 1000.0 + relief * r.next())
            .collect();
        let dem = TestDem::new(g, hs, 4);
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        let e = dem.surface.e;
        let v = |i: u32, j: u32| dem.surface.vertex_dd(i, j).unwrap();
        let vf = |i: u32, j: u32| dem.surface.vertex(i, j).unwrap();
        let (mut worst, mut worst_traversal) = (0.0_f64, 0.0_f64);
        // (under Miri, whose interpreter is slow, the vertices of one cell)
        let span = if cfg!(miri) { 2..4 } else { 2..6 };
        for i in span.clone() {
            for j in span.clone() {
                // the vertex, and the midpoints of the edges north, east and north-east (the diagonal) of it
                for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let target = vf(i, j).plus(vf(i + di, j + dj)).scaled(0.5);
                    let (lat, lon) = (g.lat_deg(i).to_radians(), g.lon_deg(j).to_radians());
                    let up = e.normal_rad(lat, lon);
                    let dir = if grazing {
                        let east = V3::new(-lon.sin(), lon.cos(), 0.0);
                        let north = up.cross(east);
                        east.scaled(0.6)
                            .add_scaled(0.8, north)
                            .add_scaled(-(0.1_f64.to_radians().tan()), up)
                    } else {
                        up.negated()
                    };
                    let ray =
                        Ray::new(target.add_scaled(-2000.0 / dir.length(), dir), dir).unwrap();
                    let hit = p.pick(&ray).unwrap().unwrap();
                    let (t_trav, _) = p.pick_t(&ray).unwrap().unwrap();
                    // the planes of the eight triangles of the four cells around vertex (i, j)
                    let mut planes = Vec::new();
                    for (ci, cj) in [(i - 1, j - 1), (i - 1, j), (i, j - 1), (i, j)] {
                        planes.push(dd_plane_t(
                            &ray,
                            [v(ci, cj), v(ci, cj + 1), v(ci + 1, cj + 1)],
                        ));
                        planes.push(dd_plane_t(
                            &ray,
                            [v(ci, cj), v(ci + 1, cj + 1), v(ci + 1, cj)],
                        ));
                    }
                    let len = ray.dir().length();
                    let t_near = |t: f64| {
                        planes
                            .iter()
                            .map(|tp| (tp - t).abs() * len)
                            .fold(f64::INFINITY, f64::min)
                    };
                    worst = worst.max(t_near(hit.t));
                    worst_traversal = worst_traversal.max(t_near(t_trav));
                }
            }
        }
        assert!(worst < 1e-10, "grazing {grazing}: refined {worst} m");
        assert!(
            worst_traversal > 1e-10,
            "grazing {grazing}: traversal {worst_traversal} m"
        );
    }
}

/// The refined point's tolerance beyond a triangle's edge (`16 ε ‖p‖∞`, 1.6e-8 m here): a ray along the
/// triangle's normal through a point 5e-9 m outside the grid's outer edge is refined, as a full-resolution cell's
/// triangle (`refine`, whose walk finds no triangle across that edge) and given by its vertices (`refine_vertices`,
/// coarse cells' and fans' triangles); one through a point 1e-6 m outside is not (the traversal's hit is kept).
#[test]
fn refinement_accepts_a_plane_point_within_its_tolerance_beyond_an_outer_edge_and_no_further() {
    use super::refine::{Tri, Vtx, refine, refine_vertices};
    let (rows, cols) = (5, 5);
    let g = grid(45.0, 7.0, 0.001, 0.001, rows, cols);
    let mut r = Lcg(3);
    let hs: Vec<f64> = (0..rows * cols).map(|_| 100.0 + 50.0 * r.next()).collect();
    let dem = TestDem::new(g, hs, 2);
    let s = dem.storage();
    let vf = |i: u32, j: u32| dem.surface.vertex(i, j).unwrap();
    // Cell [0, 1]'s first triangle V(0,1) V(0,2) V(1,2): its edge a–b lies on the grid's first row.
    let (a, b, c) = (vf(0, 1), vf(0, 2), vf(1, 2));
    let n = b.minus(a).cross(c.minus(a));
    let up = n.scaled(1.0 / n.length());
    let out = up.cross(b.minus(a));
    let out = out.scaled(1.0 / out.length());
    let out = if out.dot(c.minus(a)) > 0.0 {
        out.negated()
    } else {
        out
    };
    let middle = a.plus(b).scaled(0.5);
    for (offset, kept) in [(5e-9, true), (1e-6, false)] {
        let target = middle.add_scaled(offset, out);
        let ray = Ray::new(target.add_scaled(1000.0, up), up.negated()).unwrap();
        let full = refine(&s, &g, &ray, 1000.0, [0, 1], Tri::First, &|_| true);
        let vertices = [Vtx::Grid(0, 1), Vtx::Grid(0, 2), Vtx::Grid(1, 2)];
        let coarse = refine_vertices(&s, &g, &ray, 1000.0, vertices);
        assert_eq!(full.is_some(), kept, "{offset} m outside: {full:?}");
        assert_eq!(coarse.is_some(), kept, "{offset} m outside: {coarse:?}");
    }
}
