//! Node boxes of [`DemStorage`] ([`curvicast::terrain::boxes`]): every box contains its node's vertices (and every
//! leaf window's box its window's, [`curvicast::terrain::windows`]), boxes are tight, and [`FrameRay::interval`](curvicast::terrain::boxes::FrameRay::interval) never drops a parameter whose point lies in the box.
//!
//! The vertices are formed here by a geodetic-to-ECEF conversion of this file's own (radians, `f64`), not by the
//! kernel's `vertex_ecef`; the two differ by rounding only (nanometres), far below the 1 µm allowed.

use curvicast::Ray;
use curvicast::geodesy::Ellipsoid;
use curvicast::terrain::boxes::{LocalFrame, NodeBox};
use curvicast::terrain::windows::{WindowBox, window_ranges, windows_per_leaf};
use curvicast::terrain::{Node, NodeId, TerrainCaches, TerrainStorage, box_frame};
use curvicast::vec3::V3;
use curvicast_cli::formats::real_dem;
use curvicast_cli::formats::terrain::Dem;
use curvicast_cli::storage::{DemStorage, MultiRes};
use curvicast_host::scenes::terrain_cases::{TerrainKind, synthetic};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How far (m) a vertex may lie outside its node's box: the rounding difference between this file's vertices and
/// the kernel's.
const INFLATE: f64 = 1e-6;

/// Geodetic (degrees, metres) to ECEF on the ellipsoid (a, b), written out here: N = a / √(1 − e² sin²φ),
/// x = (N + h) cos φ cos λ, y = (N + h) cos φ sin λ, z = (N (1 − e²) + h) sin φ.
fn ecef(a: f64, b: f64, lat_deg: f64, lon_deg: f64, h: f64) -> V3<f64> {
    let (sp, cp) = lat_deg.to_radians().sin_cos();
    let (sl, cl) = lon_deg.to_radians().sin_cos();
    let e2 = 1.0 - (b * b) / (a * a);
    let n = a / (1.0 - e2 * sp * sp).sqrt();
    V3::new(
        (n + h) * cp * cl,
        (n + h) * cp * sl,
        (n * (1.0 - e2) + h) * sp,
    )
}

fn ellipsoid(s: &DemStorage<'_>) -> Ellipsoid<f64> {
    TerrainStorage::<f64>::ellipsoid(s)
}

fn node(s: &DemStorage<'_>, id: NodeId) -> Node<f64> {
    TerrainStorage::<f64>::node(s, id).unwrap_or_else(|| panic!("node {} is missing", id.0))
}

/// Every node reachable from the zones with the anchor of its box's frame (the node whose own frame the box is
/// in, `None` for the grid's: [`box_frame`]), zones first. A zone's box is in the grid's frame; a
/// child's in its parent's own frame, or, if the box says `shared_frame`, in the frame of its parent's box.
fn all_nodes(s: &DemStorage<'_>) -> Vec<(NodeId, Node<f64>, Option<NodeId>)> {
    let mut stack: Vec<(NodeId, Option<NodeId>)> = (0..TerrainStorage::<f64>::zone_count(s))
        .map(|k| (TerrainStorage::<f64>::zone(s, k).expect("zone id"), None))
        .collect();
    let mut out = Vec::new();
    while let Some((id, anchor)) = stack.pop() {
        let n = node(s, id);
        for &c in n.children.iter().flatten() {
            let shared = TerrainCaches::<f64>::node_box(s, c).is_some_and(|b| b.shared_frame);
            stack.push((c, if shared { anchor } else { Some(id) }));
        }
        out.push((id, n, anchor));
    }
    out
}

fn inside(q: V3<f64>, b: &NodeBox, pad: f64) -> bool {
    [q.x, q.y, q.z]
        .into_iter()
        .zip(b.lo.iter().zip(&b.hi))
        .all(|(v, (&lo, &hi))| f64::from(lo) - pad <= v && v <= f64::from(hi) + pad)
}

/// Checks every node of `s` (see the test below); returns (vertex checks, nodes with a box).
fn check_boxes_contain_vertices(name: &str, dem: &Dem, s: &DemStorage<'_>) -> (usize, usize) {
    let e = ellipsoid(s);
    let lat: Vec<f64> = (0..dem.rows).map(|i| dem.lat(i)).collect();
    let lon: Vec<f64> = (0..dem.cols).map(|j| dem.lon(j)).collect();
    let mut seen = vec![false; dem.rows * dem.cols];
    let (mut checks, mut boxed, mut windows) = (0usize, 0usize, 0usize);
    let mut worst = f64::NEG_INFINITY; // largest excess of a vertex over its box (negative: inside)
    for (id, n, anchor) in all_nodes(s) {
        let bx = TerrainCaches::<f64>::node_box(s, id);
        let Some(bx) = bx else {
            assert!(
                n.heights.is_none(),
                "{name}: node {} (rows {:?}, cols {:?}) has data but no box",
                id.0,
                n.rows,
                n.cols
            );
            continue;
        };
        boxed += 1;
        let frame = box_frame::<f64, _>(s, &e, anchor.map(|p| node(s, p)).as_ref());
        windows += check_windows_contain_vertices(name, dem, s, id, &n, &bx, &frame);
        for i in n.rows[0]..=n.rows[1] {
            for j in n.cols[0]..=n.cols[1] {
                let (i, j) = (i as usize, j as usize);
                let Some(h) = dem.height(i, j) else { continue };
                let p = ecef(dem.a, dem.b, lat[i], lon[j], f64::from(h));
                let q = frame.coords(p);
                for (k, v) in [q.x, q.y, q.z].into_iter().enumerate() {
                    worst = worst
                        .max(f64::from(bx.lo[k]) - v)
                        .max(v - f64::from(bx.hi[k]));
                }
                assert!(
                    inside(q, &bx, INFLATE),
                    "{name}: vertex ({i}, {j}) at lat {}, lon {}, h {h} is outside the box of node {} (rows {:?}, \
                     cols {:?}, level {}): frame coordinates {q:?}, box {bx:?}",
                    lat[i],
                    lon[j],
                    id.0,
                    n.rows,
                    n.cols,
                    n.level
                );
                seen[i * dem.cols + j] = true;
                checks += 1;
            }
        }
    }
    let with_data = (0..dem.rows)
        .flat_map(|i| (0..dem.cols).map(move |j| (i, j)))
        .filter(|&(i, j)| dem.height(i, j).is_some())
        .count();
    let covered = seen.iter().filter(|&&x| x).count();
    assert!(with_data > 0, "{name}: the DEM has no data");
    assert_eq!(
        covered, with_data,
        "{name}: the zones' nodes must cover every vertex with data"
    );
    // Every vertex is checked once per level of the tree at least (a zone and each node under it down to a leaf).
    assert!(
        checks >= with_data,
        "{name}: {checks} checks for {with_data} vertices"
    );
    // Every full-resolution leaf has windows, so in a tree of those only every vertex is in one (the coarse
    // leaves of a multi-resolution tree have none).
    let coarse_leaves = all_nodes(s)
        .iter()
        .filter(|(id, n, _)| n.is_leaf() && TerrainStorage::<f64>::block_stride(s, *id) > 1)
        .count();
    let want = match (windows_per_leaf(s.block() as u32), coarse_leaves) {
        (0, _) => 0, // leaves of at most 4 × 4 cells: one window each, none stored
        (_, 0) => with_data,
        _ => 1,
    };
    assert!(
        windows >= want && (want > 0 || windows == 0),
        "{name}: {windows} window checks for {with_data} vertices"
    );
    eprintln!(
        "{name}: {boxed} boxes, {checks} vertex checks over {with_data} vertices, {windows} in windows, worst \
         excess {worst:.3e} m"
    );
    (checks, boxed)
}

/// Checks that each window box of leaf `id` (if it has them) contains every vertex of its window, in the frame
/// of the leaf's box `bx`, and that the windows partition the leaf's cells; returns the vertex checks.
fn check_windows_contain_vertices(
    name: &str,
    dem: &Dem,
    s: &DemStorage<'_>,
    id: NodeId,
    n: &Node<f64>,
    bx: &NodeBox,
    frame: &LocalFrame<f64>,
) -> usize {
    let wins = TerrainCaches::<f64>::window_boxes(s, id);
    if wins.is_empty() {
        return 0;
    }
    assert!(n.is_leaf(), "{name}: node {} has windows", id.0);
    let mut cells = vec![0u8; ((n.rows[1] - n.rows[0]) * (n.cols[1] - n.cols[0])) as usize];
    let mut checks = 0;
    for (k, wb) in wins.iter().enumerate() {
        let Some((rows, cols)) = window_ranges(n.rows, n.cols, k) else {
            assert_eq!(*wb, WindowBox::EMPTY, "{name}: node {} window {k}", id.0);
            continue;
        };
        for i in rows[0]..rows[1] {
            for j in cols[0]..cols[1] {
                cells[((i - n.rows[0]) * (n.cols[1] - n.cols[0]) + (j - n.cols[0])) as usize] += 1;
            }
        }
        let (lo, hi) = wb.faces::<f64>(bx);
        for i in rows[0]..=rows[1] {
            for j in cols[0]..=cols[1] {
                let (i, j) = (i as usize, j as usize);
                let Some(h) = dem.height(i, j) else { continue };
                let q = frame.coords(ecef(dem.a, dem.b, dem.lat(i), dem.lon(j), f64::from(h)));
                let inside = [q.x, q.y, q.z]
                    .into_iter()
                    .zip(lo.iter().zip(&hi))
                    .all(|(v, (&l, &h))| l - INFLATE <= v && v <= h + INFLATE);
                assert!(
                    inside,
                    "{name}: vertex ({i}, {j}) is outside window {k} ({rows:?}, {cols:?}) of node {}: {q:?}, \
                     faces {lo:?} {hi:?}",
                    id.0
                );
                checks += 1;
            }
        }
    }
    assert!(
        cells.iter().all(|&c| c == 1),
        "{name}: the windows of node {} do not partition its cells",
        id.0
    );
    checks
}

/// Makes vertices missing: a rectangle of rows × cols (whole nodes empty) and scattered single vertices.
fn punch_holes(dem: &mut Dem, rect: ([usize; 2], [usize; 2]), every: usize) {
    for i in rect.0[0]..rect.0[1] {
        for j in rect.1[0]..rect.1[1] {
            dem.heights[i * dem.cols + j] = f32::NAN;
        }
    }
    for k in (0..dem.heights.len()).step_by(every) {
        dem.heights[k] = f32::NAN;
    }
}

#[test]
fn node_boxes_contain_every_vertex_of_their_node() {
    let mut cases: Vec<(&str, Dem, usize)> = vec![
        (
            "fractal mid-latitude",
            synthetic(TerrainKind::Fractal, (45.0, 7.0, 0.01, 0.01), (130, 170), 1),
            16,
        ),
        (
            "spiky 80-89.9N",
            synthetic(TerrainKind::Spiky, (80.0, -30.0, 0.1, 0.7), (100, 120), 2),
            8,
        ),
        (
            "fractal to the north pole, 2-degree columns all round",
            synthetic(TerrainKind::Fractal, (60.0, -180.0, 0.5, 2.0), (61, 181), 3),
            4,
        ),
        (
            "negative heights across the antimeridian",
            synthetic(
                TerrainKind::Negative,
                (-20.0, 179.0, 0.02, 0.02),
                (90, 110),
                4,
            ),
            16,
        ),
        (
            "fractal, negative dlat, southern high latitudes",
            synthetic(
                TerrainKind::Fractal,
                (-70.0, 100.0, -0.2, 0.5),
                (100, 90),
                5,
            ),
            8,
        ),
        (
            "flat, coarse cells (block reduced below 180 degrees)",
            synthetic(TerrainKind::Flat, (-60.0, -170.0, 3.0, 40.0), (41, 10), 6),
            16,
        ),
    ];
    let mut holes = synthetic(
        TerrainKind::Fractal,
        (30.0, 140.0, -0.005, 0.005),
        (150, 150),
        7,
    );
    punch_holes(&mut holes, ([20, 70], [40, 110]), 13);
    cases.push(("fractal with nodata holes", holes, 8));
    let mut sparse = synthetic(TerrainKind::Spiky, (-5.0, -75.0, 0.003, 0.003), (64, 64), 8);
    punch_holes(&mut sparse, ([0, 64], [0, 30]), 3);
    cases.push(("spiky, half empty, every third vertex missing", sparse, 4));
    let etopo = real_dem::etopo20().expect("the shipped ETOPO20 DEM loads");
    cases.push(("ETOPO20 (global)", etopo, 16));

    let mut total = 0;
    for (name, dem, block) in &cases {
        let s = DemStorage::new(dem, *block);
        let (checks, boxed) = check_boxes_contain_vertices(name, dem, &s);
        assert!(boxed >= TerrainStorage::<f64>::zone_count(&s), "{name}");
        total += checks;
    }

    // Multi-resolution trees: coarse leaves outside a fine region (their boxes bound all their grid vertices,
    // not only their blocks' samples).
    let multi = synthetic(
        TerrainKind::Fractal,
        (-48.0, 10.0, 0.003, 0.003),
        (161, 161),
        9,
    );
    let fine_region = Some([-47.8, -47.6, 10.1, 10.25]);
    for coarse_level in [1, 2] {
        let s = DemStorage::multi_resolution(
            &multi,
            8,
            MultiRes {
                fine_region,
                coarse_level,
            },
        );
        let name = format!("multi-resolution, coarse level {coarse_level}");
        let coarse_leaves = all_nodes(&s)
            .iter()
            .filter(|(id, n, _)| n.is_leaf() && TerrainStorage::<f64>::block_stride(&s, *id) > 1)
            .count();
        assert!(coarse_leaves > 0, "{name}: the tree has no coarse leaf");
        total += check_boxes_contain_vertices(&name, &multi, &s).0;
    }
    let etopo = &cases.last().expect("etopo case").1;
    let s = DemStorage::multi_resolution(
        etopo,
        16,
        MultiRes {
            fine_region: Some([60.0, 89.9, -10.0, 40.0]),
            coarse_level: 2,
        },
    );
    total += check_boxes_contain_vertices("ETOPO20 multi-resolution", etopo, &s).0;
    let vertices: usize = cases.iter().map(|(_, d, _)| d.rows * d.cols).sum();
    assert!(total >= vertices, "{total} checks for {vertices} vertices");
}

#[test]
fn leaf_boxes_of_trinidad_like_terrain_share_the_grid_frame_and_hug_their_corners() {
    // 3″ spacing (1/1200°) from 38°N 106°W southwards, heights shifted to Trinidad's 1.4–4.3 km, 16-cell blocks:
    // a leaf spans about 1.5 × 1.2 km, over which the Earth's curvature drops the ground by about 4 cm. The DEM
    // spans 0.27° × 0.4°, so every box is in the grid's frame (`shares_frame_with_children`), tilted against
    // a leaf's horizon by at most 0.25°.
    let mut dem = synthetic(
        TerrainKind::Fractal,
        (38.0, -106.0, -1.0 / 1200.0, 1.0 / 1200.0),
        (321, 481),
        11,
    );
    for h in &mut dem.heights {
        *h = 1400.0 + 1.6 * (*h + 200.0).max(0.0);
    }
    let s = DemStorage::new(&dem, 16);
    let e = ellipsoid(&s);
    let frame = box_frame::<f64, _>(&s, &e, None);
    let (mut leaves, mut worst_hull, mut worst_up) = (0, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for (id, n, anchor) in all_nodes(&s) {
        assert_eq!(anchor, None, "node {} is not in the grid's frame", id.0);
        if !n.is_leaf() {
            continue;
        }
        let [hmin, hmax] = n.heights.expect("no nodata here");
        let bx = TerrainCaches::<f64>::node_box(&s, id).expect("a leaf with data has a box");
        // The hull of the leaf's corners at its lowest and highest heights (this file's vertices): the box may
        // exceed it by the curvature of the ground between the corners (4 cm up, less sideways) and the f32
        // rounding, 10 cm in all.
        let corner = |i: u32, j: u32, h: f64| {
            ecef(dem.a, dem.b, dem.lat(i as usize), dem.lon(j as usize), h)
        };
        let mut hull = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
        for i in n.rows {
            for j in n.cols {
                for h in [hmin, hmax] {
                    let q = frame.coords(corner(i, j, h));
                    for (k, v) in [q.x, q.y, q.z].into_iter().enumerate() {
                        hull[k] = [hull[k][0].min(v), hull[k][1].max(v)];
                    }
                }
            }
        }
        for (k, [lo, hi]) in hull.into_iter().enumerate() {
            let extent = f64::from(bx.hi[k]) - f64::from(bx.lo[k]);
            let over = extent - (hi - lo);
            worst_hull = worst_hull.max(over);
            assert!(
                over <= 0.1,
                "leaf {} (rows {:?}, cols {:?}), axis {k}: box extent {extent} m for a corner hull of {} m",
                id.0,
                n.rows,
                n.cols,
                hi - lo
            );
        }
        // The up extent against the height range: the tilt adds at most the leaf's width times the tilt.
        let up = f64::from(bx.hi[2]) - f64::from(bx.lo[2]);
        let width = (hull[0][1] - hull[0][0]).hypot(hull[1][1] - hull[1][0]);
        worst_up = worst_up.max(up - (hmax - hmin));
        assert!(
            up - (hmax - hmin) <= 0.1 + width * 0.25_f64.to_radians(),
            "leaf {}: box up-extent {up} m for heights {hmin}..{hmax} m",
            id.0
        );
        leaves += 1;
    }
    assert_eq!(leaves, 20 * 30, "16-cell leaves of 320 × 480 cells");
    eprintln!(
        "{leaves} leaves: box extents exceed the corner hull by at most {worst_hull:.3} m; up-extent exceeds the \
         height range by at most {worst_up:.3} m"
    );
}

#[test]
fn wide_nodes_keep_their_own_frames_down_to_a_degree() {
    // 0.02° cells, 8-cell leaves (0.16°), a grid of 4.8° × 6.4°: boxes are in their parents' own frames down to
    // the children of nodes of at most a degree; below those, children share their parent's box frame, whose
    // anchor spans at most 1°.
    let dem = synthetic(
        TerrainKind::Fractal,
        (20.0, 30.0, 0.02, 0.02),
        (241, 321),
        12,
    );
    let s = DemStorage::new(&dem, 8);
    let g = TerrainStorage::<f64>::grid(&s);
    let (mut shared, mut own) = (0, 0);
    for (id, _, anchor) in all_nodes(&s) {
        let Some(a) = anchor else { continue };
        let a = node(&s, a);
        let span = |[x, y]: [u32; 2], step: f64| f64::from(y - x) * step.abs();
        let b = TerrainCaches::<f64>::node_box(&s, id).expect("data everywhere");
        if b.shared_frame {
            shared += 1;
            assert!(
                span(a.rows, g.dlat_deg) <= 1.0 && span(a.cols, g.dlon_deg) <= 1.0,
                "node {}: shares the frame of a {}° × {}° anchor",
                id.0,
                span(a.rows, g.dlat_deg),
                span(a.cols, g.dlon_deg)
            );
        } else {
            own += 1;
        }
    }
    assert!(shared > 0 && own > 0, "{shared} shared, {own} own frames");
}

/// A random unit vector (uniform on the sphere).
fn unit(rng: &mut impl Rng) -> V3<f64> {
    loop {
        let v = V3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v.scaled(1.0 / l);
        }
    }
}

/// A random point of the box, in frame coordinates: each coordinate at a face (lo or hi) or uniform between.
fn point_in_box(rng: &mut impl Rng, b: &NodeBox) -> V3<f64> {
    let mut c = [0.0; 3];
    for (k, v) in c.iter_mut().enumerate() {
        let (lo, hi) = (f64::from(b.lo[k]), f64::from(b.hi[k]));
        *v = match rng.random_range(0..4) {
            0 => lo,
            1 => hi,
            _ => rng.random_range(lo..=hi),
        };
    }
    V3::new(c[0], c[1], c[2])
}

/// A random direction: uniform, along an ECEF axis (so that some frame components are exactly zero), or along
/// the box's own axes (grazing its faces); scaled by 10^[-3, 3].
fn direction(rng: &mut impl Rng, frame: &LocalFrame<f64>, at: V3<f64>) -> V3<f64> {
    let d = match rng.random_range(0..6) {
        0 => {
            let mut a = [0.0; 3];
            a[rng.random_range(0..3)] = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            V3::from(a)
        }
        1 => {
            let mut a = [0.0; 3];
            a[rng.random_range(0..3)] = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let p = frame.point(at);
            let d = frame.point(at.plus(V3::from(a).scaled(1000.0))).minus(p);
            d.scaled(1.0 / d.length())
        }
        _ => unit(rng),
    };
    d.scaled(10f64.powf(rng.random_range(-3.0..3.0)))
}

/// Rays through random points of the boxes of `s`'s nodes, from origins 1 m to 4·10⁷ m away along the ray (before
/// the point, or beyond it with the point at a negative parameter), restricted to random finite intervals that
/// contain the point's parameter, in the picker's scalar type `T`; returns the number of rays checked.
///
/// The points are formed in `f64` by the `f64` frame; in `T` the ray's origin, direction and parameter are
/// rounded to `T`, which moves the ray's point by the rounding that the box test's inflation covers.
fn check_box_intervals<T: curvicast::Real + std::fmt::Debug>(
    name: &str,
    s: &DemStorage<'_>,
    seed: u64,
    per_node: usize,
) -> usize
where
    for<'d> DemStorage<'d>: TerrainCaches<T>,
{
    let e = ellipsoid(s);
    let e_t = TerrainStorage::<T>::ellipsoid(s);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let nodes = all_nodes(s);
    let (mut checked, mut clipped) = (0, 0);
    for (id, n, anchor) in &nodes {
        let Some(b) = TerrainCaches::<f64>::node_box(s, *id) else {
            continue;
        };
        let frame = box_frame::<f64, _>(s, &e, anchor.map(|p| node(s, p)).as_ref());
        let anchor_t = anchor.map(|p| TerrainStorage::<T>::node(s, p).expect("node"));
        let frame_t = box_frame::<T, _>(s, &e_t, anchor_t.as_ref());
        for _ in 0..per_node {
            let q = point_in_box(&mut rng, &b);
            let p = frame.point(q);
            let dir = direction(&mut rng, &frame, q);
            let dist = 10f64.powf(rng.random_range(0.0..7.6)); // 1 m to 4·10⁷ m
            let t = dist / dir.length();
            let behind = rng.random_bool(0.2);
            let (o, t) = if behind {
                (p.add_scaled(t, dir), -t)
            } else {
                (p.add_scaled(-t, dir), t)
            };
            let (t_lo, t_hi) = match rng.random_range(0..4) {
                0 => (0.0, 2.0 * t),
                1 => (t, t),
                2 => (
                    t * rng.random_range(0.0..1.0),
                    t * rng.random_range(1.0..2.0),
                ),
                _ => (t - t.abs() * 1e-9, t + t.abs() * 1e-9),
            };
            let (t_lo, t_hi) = (t_lo.min(t_hi), t_lo.max(t_hi));
            let v = |x: V3<f64>| V3::new(T::from_f64(x.x), T::from_f64(x.y), T::from_f64(x.z));
            let ray = Ray::<T>::new(v(o), v(dir))
                .and_then(|r| r.with_interval(T::from_f64(t_lo), T::from_f64(t_hi)))
                .expect("valid ray");
            let tt = T::from_f64(t);
            let got = frame_t
                .ray(&ray, [ray.t_min(), ray.t_max()])
                .interval(&b, [ray.t_min(), ray.t_max()]);
            assert!(
                got.is_some_and(|(lo, hi)| lo <= tt && tt <= hi),
                "{name} ({}): node {} (rows {:?}, cols {:?}) box {b:?}: the ray from {o:?} along {dir:?} on \
                 [{t_lo}, {t_hi}] passes through the box point {q:?} (frame) at t = {t}, but the box test gives \
                 {got:?}",
                std::any::type_name::<T>(),
                id.0,
                n.rows,
                n.cols
            );
            // Count the intervals that the box actually clipped (so that the check is not vacuous).
            if got.is_some_and(|(lo, hi)| lo > ray.t_min() || hi < ray.t_max()) {
                clipped += 1;
            }
            checked += 1;
        }
    }
    assert!(
        clipped * 4 >= checked,
        "{name} ({}): only {clipped} of {checked} intervals were clipped by the box",
        std::any::type_name::<T>()
    );
    eprintln!(
        "{name} ({}): {checked} rays, {clipped} intervals clipped",
        std::any::type_name::<T>()
    );
    checked
}

fn interval_storages() -> Vec<(&'static str, Dem, usize, usize)> {
    vec![
        (
            "ETOPO20",
            real_dem::etopo20().expect("the shipped ETOPO20 DEM loads"),
            16,
            40,
        ),
        (
            "spiky 80-90N",
            synthetic(
                TerrainKind::Spiky,
                (80.0, -180.0, 0.05, 0.5),
                (201, 721),
                21,
            ),
            8,
            40,
        ),
        (
            "3-arc-second fractal",
            synthetic(
                TerrainKind::Fractal,
                (38.0, -106.0, -1.0 / 1200.0, 1.0 / 1200.0),
                (257, 257),
                22,
            ),
            16,
            200,
        ),
    ]
}

/// Runs [`check_box_intervals`] in scalar type `T` over every storage of [`interval_storages`] (seeds from
/// `seed`); the number of rays checked.
fn check_all_box_intervals<T: curvicast::Real + std::fmt::Debug>(seed: u64) -> usize
where
    for<'d> DemStorage<'d>: TerrainCaches<T>,
{
    let mut total = 0;
    for (k, (name, dem, block, per_node)) in interval_storages().into_iter().enumerate() {
        let s = DemStorage::new(&dem, block);
        let n = check_box_intervals::<T>(name, &s, seed + k as u64, per_node);
        assert!(n >= 10_000, "{name}: only {n} rays");
        total += n;
    }
    total
}

#[test]
fn box_interval_is_conservative_for_rays_through_box_points() {
    eprintln!(
        "{} f64 rays through box points",
        check_all_box_intervals::<f64>(100)
    );
}

#[test]
fn box_interval_is_conservative_for_f32_rays_through_box_points() {
    eprintln!(
        "{} f32 rays through box points",
        check_all_box_intervals::<f32>(200)
    );
}
