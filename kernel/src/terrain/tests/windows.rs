//! Leaf windows (`windows.rs`): their split partitions a leaf's cells, their quantized boxes contain what they
//! bound, and picking by windows changes no answer, only the work.

use super::*;
use crate::terrain::boxes::{LocalFrame, NodeBox};
use crate::terrain::windows::{
    WINDOWS_PER_SIDE, WindowBox, window_ranges, windows_per_leaf, windows_per_side,
};

#[test]
fn window_ranges_partition_leaves_of_every_size_into_at_most_four_by_four() {
    assert_eq!(
        windows_per_leaf(4),
        0,
        "a 4 × 4 leaf is one window: none stored"
    );
    assert_eq!(
        (
            windows_per_side(0),
            windows_per_side(1),
            windows_per_side(17)
        ),
        (1, 1, 4)
    );
    assert_eq!(
        (
            windows_per_leaf(8),
            windows_per_leaf(16),
            windows_per_leaf(64)
        ),
        (4, 16, 16)
    );
    let sizes: &[u32] = if cfg!(miri) {
        &[1, 5, 9]
    } else {
        &[1, 2, 3, 4, 5, 7, 8, 9, 13, 16, 17, 33, 64]
    };
    for &rows in sizes {
        for &cols in sizes {
            let (r, c) = ([5, 5 + rows], [9, 9 + cols]);
            let (nr, nc) = (windows_per_side(rows), windows_per_side(cols));
            assert!((1..=WINDOWS_PER_SIDE).contains(&nr) && (1..=WINDOWS_PER_SIDE).contains(&nc));
            let n = (nr * nc) as usize;
            let mut seen = std::vec![0u8; (rows * cols) as usize];
            for k in 0..n {
                let (wr, wc) = window_ranges(r, c, k).unwrap();
                assert!(
                    wr[0] < wr[1] && wc[0] < wc[1],
                    "{rows} × {cols}, window {k} is empty"
                );
                // about 4 cells a side while there are at most 4 windows a side
                assert!(wr[1] - wr[0] <= rows.div_ceil(nr) && wc[1] - wc[0] <= cols.div_ceil(nc));
                for i in wr[0]..wr[1] {
                    for j in wc[0]..wc[1] {
                        seen[((i - r[0]) * cols + (j - c[0])) as usize] += 1;
                    }
                }
            }
            assert!(
                seen.iter().all(|&s| s == 1),
                "{rows} × {cols}: not a partition"
            );
            assert_eq!(window_ranges(r, c, n), None);
        }
    }
}

/// Boxes in f32 (as `BoxBuilder` rounds them) with a window inside a leaf: the leaf's faces from `lo`, extents
/// `size` (`0` for a flat axis), the window a random part of it.
fn leaf_and_window(r: &mut Lcg, lo: f32, size: f32) -> (NodeBox, NodeBox) {
    let mut leaf = NodeBox {
        lo: [0.0; 3],
        hi: [0.0; 3],
        shared_frame: false,
    };
    let mut win = leaf;
    for k in 0..3 {
        leaf.lo[k] = lo * (r.next() as f32 - 0.5);
        leaf.hi[k] = leaf.lo[k] + size * r.next() as f32;
        let (a, b) = (r.next() as f32, r.next() as f32);
        let at = |u: f32| leaf.lo[k] + (leaf.hi[k] - leaf.lo[k]) * u;
        win.lo[k] = at(a.min(b)).clamp(leaf.lo[k], leaf.hi[k]);
        win.hi[k] = at(a.max(b)).clamp(leaf.lo[k], leaf.hi[k]);
    }
    (leaf, win)
}

#[test]
fn quantized_window_faces_contain_the_window_and_stay_near_the_leaf() {
    let mut r = Lcg(11);
    let n = if cfg!(miri) { 40 } else { 4000 };
    for case in 0..n {
        // frames near the origin and far from it (a grid's frame across a continent), wide and thin boxes,
        // flat axes, and windows that reach the leaf's faces
        let lo = [1.0, 3.0e3, 2.0e5, 6.0e6][case % 4];
        let size = [0.0, 0.25, 40.0, 3.0e3, 1.0e5][case % 5];
        let (leaf, win) = leaf_and_window(&mut r, lo, size);
        let q = WindowBox::quantize(&leaf, &win);
        let (lo64, hi64) = q.faces::<f64>(&leaf);
        let (lo32, hi32) = q.faces::<f32>(&leaf);
        for k in 0..3 {
            let (wl, wh) = (f64::from(win.lo[k]), f64::from(win.hi[k]));
            let (l, h) = (f64::from(leaf.lo[k]), f64::from(leaf.hi[k]));
            // The exact faces `l + (h − l)·q/255` hold the window: `(h − l)·q` against `255 (w − l)`, both
            // exact in f64 for f32 boxes (differences of f32 values, times 8-bit integers).
            let (ql, qh) = (f64::from(q.lo[k]), f64::from(q.hi[k]));
            assert!(
                (h - l) * ql <= 255.0 * (wl - l),
                "case {case} axis {k}: exact low face {q:?}"
            );
            assert!(
                (h - l) * qh >= 255.0 * (wh - l),
                "case {case} axis {k}: exact high face {q:?}"
            );
            assert!(
                lo64[k] <= wl && hi64[k] >= wh,
                "case {case} axis {k}: {q:?}"
            );
            assert!(
                f64::from(lo32[k]) <= wl && f64::from(hi32[k]) >= wh,
                "case {case} axis {k} (f32)"
            );
            // no looser than a 255th of the leaf beyond the window, and inside the leaf up to rounding
            let step = (h - l) / 255.0 + 1e-6 * (l.abs() + h.abs());
            assert!(
                wl - lo64[k] <= 2.0 * step && hi64[k] - wh <= 2.0 * step,
                "case {case} axis {k}"
            );
            assert!(
                lo64[k] >= l - step && hi64[k] <= h + step,
                "case {case} axis {k}"
            );
        }
    }
    // Window faces one f32 step inside a 255th of the leaf, where the first guess's rounding can land on the
    // wrong side of the face: the exact faces still hold the window.
    for span in [7.0f32, 3.0, 1.0e-3, 4097.0, 123_456.79] {
        let leaf = NodeBox {
            lo: [0.0, -span, 1000.0],
            hi: [span, 0.0, 1000.0 + span],
            shared_frame: false,
        };
        for q in 1..255u8 {
            let (mut lo, mut hi) = ([0.0f32; 3], [0.0f32; 3]);
            for k in 0..3 {
                let (l, h) = (f64::from(leaf.lo[k]), f64::from(leaf.hi[k]));
                let face = l + (h - l) * f64::from(q) / 255.0;
                // the f32 just inside the face from each side
                let f = face as f32;
                lo[k] = if f64::from(f) >= face {
                    f.next_down()
                } else {
                    f
                };
                hi[k] = if f64::from(f) <= face { f.next_up() } else { f };
            }
            for win in [
                NodeBox {
                    lo,
                    hi: leaf.hi,
                    shared_frame: false,
                },
                NodeBox {
                    lo: leaf.lo,
                    hi,
                    shared_frame: false,
                },
            ] {
                let w = WindowBox::quantize(&leaf, &win);
                for k in 0..3 {
                    let (l, h) = (f64::from(leaf.lo[k]), f64::from(leaf.hi[k]));
                    let (wl, wh) = (f64::from(win.lo[k]), f64::from(win.hi[k]));
                    let (ql, qh) = (f64::from(w.lo[k]), f64::from(w.hi[k]));
                    assert!(
                        (h - l) * ql <= 255.0 * (wl - l),
                        "span {span}, q {q}, axis {k}: {w:?}"
                    );
                    assert!(
                        (h - l) * qh >= 255.0 * (wh - l),
                        "span {span}, q {q}, axis {k}: {w:?}"
                    );
                }
            }
        }
    }
    // A leaf box from ∓2^-100 to 255, whose extent rounds to 255 in f64: a window face on the integer `q` lies just
    // outside the exact face `q` of 255ths (by 2^-100 (1 − q/255)), though the face computed in f64 is `q`
    // itself; the builder's slack moves it one step out.
    let tiny = 2.0f32.powi(-100);
    for q in 1..255u8 {
        let v = f32::from(q);
        let below = NodeBox {
            lo: [-tiny; 3],
            hi: [255.0; 3],
            shared_frame: false,
        };
        let w = WindowBox::quantize(
            &below,
            &NodeBox {
                hi: [v; 3],
                ..below
            },
        );
        assert!(w.hi.iter().all(|&h| h > q), "q {q}: {w:?}");
        let above = NodeBox {
            lo: [tiny; 3],
            hi: [255.0; 3],
            shared_frame: false,
        };
        let w = WindowBox::quantize(
            &above,
            &NodeBox {
                lo: [v; 3],
                ..above
            },
        );
        assert!(w.lo.iter().all(|&l| l < q), "q {q}: {w:?}");
    }
    // An empty window: no ray enters it, from inside the leaf or outside, along an axis or not.
    let (leaf, _) = leaf_and_window(&mut r, 100.0, 50.0);
    let (lo, hi) = WindowBox::EMPTY.faces::<f64>(&leaf);
    let frame = LocalFrame::at(6_378_137.0, (0.6, 0.8), (0.0, 1.0));
    for k in 0..if cfg!(miri) { 20 } else { 500 } {
        let o = frame.point(V3::new(
            300.0 * (r.next() - 0.5),
            300.0 * (r.next() - 0.5),
            300.0 * (r.next() - 0.5),
        ));
        let mut d = V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5);
        if k % 5 == 0 {
            d = V3::new(0.0, 0.0, -1.0);
        }
        let ray = Ray::new(o, d).unwrap();
        let fr = frame.ray(&ray, [-1.0e4, 1.0e4]);
        assert_eq!(fr.interval_of(lo, hi, [-1.0e4, 1.0e4]), None, "ray {k}");
    }
}

/// A DEM of `rows × cols` vertices from a fixed sequence (heights 0–400 m, a few missing) at `(lat0, lon0)` with
/// steps `(dlat, dlon)`.
fn rough(
    r: &mut Lcg,
    (lat0, lon0, dlat, dlon): (f64, f64, f64, f64),
    rows: u32,
    cols: u32,
) -> (Grid<f64>, Vec<f64>) {
    let g = grid(lat0, lon0, dlat, dlon, rows, cols);
    let hs = (0..rows * cols)
        .map(|_| {
            let u = r.next();
            if u < 0.01 { f64::NAN } else { 400.0 * u }
        })
        .collect();
    (g, hs)
}

/// Rays a camera 1.5 km above the DEM sends across it (shallow, in every direction), rays straight down, rays from
/// orbit, and rays skimming the terrain just above its highest vertex.
fn rays(r: &mut Lcg, e: &Ellipsoid<f64>, g: &Grid<f64>, n: usize) -> Vec<Ray<f64>> {
    let span = |k: u32, step: f64| step * f64::from(k - 1);
    let (lat_span, lon_span) = (span(g.rows, g.dlat_deg), span(g.cols, g.dlon_deg));
    let at = |r: &mut Lcg| {
        (
            g.lat0_deg + lat_span * r.next(),
            g.lon0_deg + lon_span * r.next(),
        )
    };
    (0..n)
        .map(|k| {
            let (lat, lon) = at(r);
            let (lat1, lon1) = at(r);
            match k % 4 {
                0 => ray_between(e, [lat, lon, 1500.0], [lat1, lon1, -200.0]),
                1 => radial_ray(e, lat, lon, 3000.0),
                2 => ray_between(e, [lat, lon, 2.0e7], [lat1, lon1, 0.0]),
                _ => ray_between(e, [lat, lon, 410.0], [lat1, lon1, 395.0]),
            }
        })
        .collect()
}

/// Rough DEMs in leaves of 8 × 8 cells (2 × 2 windows) and 16 × 16 (4 × 4), at mid-latitude, across the
/// antimeridian, on the equator (a window's border row on it) and near the north pole: `pick` and `pick_t` by
/// windows give the same answers, bit for bit, as without them, and cross fewer triangle pairs.
#[test]
#[cfg_attr(miri, ignore)]
fn picks_by_leaf_windows_equal_picks_of_whole_leaves_on_rough_terrain() {
    let mut r = Lcg(5);
    let places = [
        ("45° N", (45.0, 7.0, 0.01, 0.01)),
        ("across the antimeridian", (-33.0, 179.8, 0.01, 0.01)),
        ("on the equator", (-0.04, 20.0, 0.01, 0.01)),
        ("near the north pole", (89.5, -10.0, 0.01, 0.5)),
    ];
    for (place, at) in places {
        let (g, hs) = rough(&mut r, at, 41, 41);
        for block in [8, 16] {
            let dem = TestDem::with_boxes(g, hs.clone(), block, |_, level| level == 1);
            let (with, without) = (dem.storage(), dem.storage_without_windows());
            let p: Picker<'_, f64, Storage<'_>> = Picker::new(&with).unwrap();
            let q: Picker<'_, f64, Storage<'_>> = Picker::new(&without).unwrap();
            let e = dem.surface.e;
            let (mut pairs, mut pairs_whole, mut hits) = (0, 0, 0);
            for (k, ray) in rays(&mut r, &e, &g, 800).iter().enumerate() {
                let what = std::format!("{place}, block {block}, ray {k}");
                let (mut a, mut b) = (PickStats::default(), PickStats::default());
                let got = p.pick_with_stats(ray, &mut a).unwrap();
                assert_eq!(got, q.pick_with_stats(ray, &mut b).unwrap(), "{what}");
                assert_eq!(p.pick_t(ray).unwrap(), q.pick_t(ray).unwrap(), "{what}");
                pairs += a.triangle_pairs_visited;
                pairs_whole += b.triangle_pairs_visited;
                hits += usize::from(got.is_some());
            }
            assert!(hits > 400, "{place}, block {block}: {hits} hits");
            assert!(
                pairs < pairs_whole,
                "{place}, block {block}: {pairs} pairs by windows, {pairs_whole} whole"
            );
        }
    }
}

/// Shallow rays in the equator's plane (`z = 0`, as are the vertices of the equator's row) onto a DEM whose leaves
/// of 8 × 8 one-degree cells have a window border on the equator: a ray meets the edge that rows 3 and 4 share,
/// often at exactly the same `t` in both cells' triangles, and its windows may be walked upper one first. The
/// tie still goes to the lower row, as in a walk of the whole leaf (before that rule, 123 of these 4 000 rays got
/// row 4 by windows).
#[test]
fn rays_in_the_equators_plane_across_a_window_border_row_keep_the_lower_row_on_an_exact_tie() {
    let mut r = Lcg(9);
    let g = grid(-4.0, 20.0, 1.0, 1.0, 17, 17);
    let hs: Vec<f64> = (0..17 * 17).map(|_| 3000.0 * r.next()).collect();
    let dem = TestDem::with_boxes(g, hs, 8, |_, level| level == 1);
    let (with, without) = (dem.storage(), dem.storage_without_windows());
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&with).unwrap();
    let q: Picker<'_, f64, Storage<'_>> = Picker::new(&without).unwrap();
    let e = dem.surface.e;
    let n = if cfg!(miri) { 4 } else { 4000 };
    let mut on_border = 0;
    for k in 0..n {
        let lon = 20.5 + 15.0 * r.next();
        let target = e.geodetic_deg_to_ecef(0.0, lon, 0.0);
        let from =
            e.geodetic_deg_to_ecef(0.0, lon - 2.0 + 4.0 * r.next(), 1.0e4 + 3.0e5 * r.next());
        let d = target.minus(from);
        let ray = Ray::new(V3::new(from.x, from.y, 0.0), V3::new(d.x, d.y, 0.0)).unwrap();
        let got = p.pick(&ray).unwrap();
        assert_eq!(got, q.pick(&ray).unwrap(), "ray {k}");
        assert_eq!(p.pick_t(&ray).unwrap(), q.pick_t(&ray).unwrap(), "ray {k}");
        on_border += usize::from(got.is_some_and(|h| h.cell[0] == 3 && h.ecef[2] == 0.0));
    }
    assert!(
        on_border * 4 >= n,
        "{on_border} of {n} hits on the border row"
    );
}

/// The window buffer has [`build::window_slots`] records, or the builder and the storage refuse it; leaves of at
/// most 4 × 4 cells have none.
#[test]
fn window_buffers_of_the_wrong_length_are_refused() {
    let mut r = Lcg(3);
    let (g, hs) = rough(&mut r, (10.0, 10.0, 0.01, 0.01), 20, 20);
    let e = Ellipsoid::wgs84();
    // (under Miri, whose interpreter is slow, the leaves of 8 × 8 cells only)
    let blocks: &[(u32, usize)] = if cfg!(miri) {
        &[(8, 64)]
    } else {
        &[(4, 0), (8, 64), (16, 64)]
    };
    for &(block, want) in blocks {
        let mut nodes = std::vec![build::NodeRecord::EMPTY; build::node_slots(20, 20, block)];
        let tree = build::build_tree(&hs, &g, block, &mut nodes).unwrap();
        build::build_boxes(&e, &g, &hs, tree, None, &mut nodes).unwrap();
        // 19 × 19 cells: 3 × 3 leaves of 8 × 8 in 4 groups of 2 × 2 slots, 4 windows each; 2 × 2 leaves of
        // 16 × 16 in one group, 16 windows each
        let n = build::window_slots(20, 20, block);
        assert_eq!(n, want, "block {block}");
        for len in [n + 1, n.saturating_sub(1)] {
            if len == n {
                continue;
            }
            let mut wrong = std::vec![WindowBox::EMPTY; len];
            assert_eq!(
                build::build_windows(&e, &g, &hs, tree, None, &nodes, &mut wrong),
                Err(build::BuildError::BufferLength),
                "block {block}, {len} records"
            );
            let parts = build::Parts::new(&hs[..], &nodes[..]).with_windows(&wrong);
            assert_eq!(
                build::TreeStorage::with_buffers(e, g, tree, parts).err(),
                Some(build::BuildError::BufferLength)
            );
        }
        let mut right = std::vec![WindowBox::EMPTY; n];
        build::build_windows(&e, &g, &hs, tree, None, &nodes, &mut right).unwrap();
        // Each leaf's first records are its windows' (a leaf at the DEM's edge has fewer), the rest empty.
        let per_leaf = windows_per_leaf(block);
        for (k, records) in right.chunks(per_leaf.max(1)).enumerate() {
            let node = nodes[k].node::<f64>();
            let count = if node.heights.is_some() && node.is_leaf() {
                let side = |[a, b]: [u32; 2]| windows_per_side(b - a);
                (side(node.rows) * side(node.cols)) as usize
            } else {
                0
            };
            let filled = records.iter().filter(|w| **w != WindowBox::EMPTY).count();
            assert_eq!(filled, count, "block {block}, slot {k}");
            assert!(records[count..].iter().all(|w| *w == WindowBox::EMPTY));
        }
    }
}

/// The window buffer's length: none for a grid of fewer than 2 rows or columns or a block of 0 (as for the
/// nodes), else `windows_per_leaf` records per slot of the leaf level.
#[test]
fn window_slots_count_the_leaf_levels_slots_times_the_windows_per_leaf() {
    assert_eq!(
        build::window_slots(2, 9, 8),
        16,
        "one 1 × 8-cell leaf in a group of 2 × 2 slots"
    );
    assert_eq!(build::window_slots(9, 2, 8), 16);
    assert_eq!(build::window_slots(2, 2, 16), 64);
    assert_eq!(build::window_slots(1, 9, 8), 0);
    assert_eq!(build::window_slots(9, 1, 8), 0);
    assert_eq!(build::window_slots(9, 9, 0), 0);
    assert_eq!(
        build::window_slots(9, 9, 4),
        0,
        "leaves of 4 × 4 cells have no windows"
    );
    assert_eq!(build::window_slots(1025, 1025, 8), 128 * 128 * 4);
}

/// A storage that gives only the first `n` window boxes of each leaf (a caller's storage may hold fewer than
/// the leaf has windows).
struct FewWindows<'a>(Storage<'a>, usize);

impl TerrainStorage<f64> for FewWindows<'_> {
    fn ellipsoid(&self) -> Ellipsoid<f64> {
        self.0.ellipsoid()
    }
    fn grid(&self) -> Grid<f64> {
        self.0.grid()
    }
    fn zone_count(&self) -> usize {
        self.0.zone_count()
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        self.0.zone(k)
    }
    fn node(&self, id: NodeId) -> Option<Node<f64>> {
        self.0.node(id)
    }
    fn height(&self, i: u32, j: u32) -> Option<f64> {
        self.0.height(i, j)
    }
}

impl TerrainCaches<f64> for FewWindows<'_> {
    fn node_box(&self, id: NodeId) -> Option<NodeBox> {
        self.0.node_box(id)
    }
    fn window_boxes(&self, id: NodeId) -> &[WindowBox] {
        let all = self.0.window_boxes(id);
        all.get(..self.1.min(all.len())).unwrap_or(&[])
    }
}

/// A leaf whose storage gives fewer window boxes than it has windows is walked whole: no window's cells are lost.
#[test]
fn a_leaf_with_fewer_window_boxes_than_windows_is_walked_whole() {
    let mut r = Lcg(17);
    let (g, hs) = rough(&mut r, (45.0, 7.0, 0.01, 0.01), 25, 25);
    let dem = TestDem::with_boxes(g, hs, 8, |_, _| false);
    let whole = dem.storage_without_windows();
    let q: Picker<'_, f64, Storage<'_>> = Picker::new(&whole).unwrap();
    let e = dem.surface.e;
    let rays = rays(&mut r, &e, &g, if cfg!(miri) { 4 } else { 400 });
    for n in [1, 3] {
        let few = FewWindows(dem.storage(), n);
        let p: Picker<'_, f64, FewWindows<'_>> = Picker::new(&few).unwrap();
        for (k, ray) in rays.iter().enumerate() {
            assert_eq!(
                p.pick(ray).unwrap(),
                q.pick(ray).unwrap(),
                "{n} boxes, ray {k}"
            );
        }
    }
}
