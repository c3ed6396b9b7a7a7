//! The kernel's builder (`build.rs`): well-formed trees, picks on its storage, typed errors, boxes and
//! trigonometry tables, the multi-resolution tree.

use super::*;

/// Every node record of the builder: ranges inside the grid, children strictly inside their parent, the
/// height range over every vertex of the node's cells (border rows and columns included), and the leaves
/// covering every cell that has a triangle exactly once.
fn check_built_tree(heights: &[f64], g: &Grid<f64>, block: u32) {
    use build::{NodeRecord, SliceStorage, build_tree, node_slots};
    let slots = node_slots(g.rows, g.cols, block);
    let mut nodes = std::vec![NodeRecord::<f64>::EMPTY; slots + 3];
    let tree = build_tree(heights, g, block, &mut nodes).unwrap();
    assert_eq!(tree.slots(), slots);
    assert!(
        nodes[slots..].iter().all(|n| *n == NodeRecord::EMPTY),
        "untouched tail"
    );
    let s = SliceStorage::new(Ellipsoid::wgs84(), *g, heights, &nodes, tree).unwrap();
    let h = |i: u32, j: u32| Some(heights[(i * g.cols + j) as usize]).filter(|h| !h.is_nan());
    let mut covered = std::vec![0u32; (g.cell_rows() * g.cell_cols()) as usize];
    let mut stack: Vec<NodeId> = (0..s.zone_count()).map(|k| s.zone(k).unwrap()).collect();
    assert!(stack.len() <= 32);
    while let Some(id) = stack.pop() {
        let n = s.node(id).unwrap();
        assert!(n.rows[0] < n.rows[1] && n.rows[1] <= g.cell_rows(), "{n:?}");
        assert!(n.cols[0] < n.cols[1] && n.cols[1] <= g.cell_cols(), "{n:?}");
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in n.rows[0]..=n.rows[1] {
            for j in n.cols[0]..=n.cols[1] {
                if let Some(v) = h(i, j) {
                    (lo, hi) = (lo.min(v), hi.max(v));
                }
            }
        }
        assert_eq!(
            n.heights,
            (lo <= hi).then_some([lo, hi]),
            "block {block} {n:?}"
        );
        if n.is_leaf() {
            for i in n.rows[0]..n.rows[1] {
                for j in n.cols[0]..n.cols[1] {
                    covered[(i * g.cell_cols() + j) as usize] += 1;
                }
            }
        }
        for c in n.children.iter().flatten() {
            let k = s.node(*c).unwrap();
            assert!(k.rows[0] >= n.rows[0] && k.rows[1] <= n.rows[1] && k.cols[0] >= n.cols[0]);
            assert!(k.cols[1] <= n.cols[1] && (k.rows, k.cols) != (n.rows, n.cols));
            assert!(k.level > n.level && k.heights.is_some());
            stack.push(*c);
        }
    }
    for i in 0..g.cell_rows() {
        for j in 0..g.cell_cols() {
            let [a, b, c, d] = [h(i, j), h(i, j + 1), h(i + 1, j + 1), h(i + 1, j)];
            let has = a.is_some() && c.is_some() && (b.is_some() || d.is_some());
            let n = covered[(i * g.cell_cols() + j) as usize];
            assert!(
                n <= 1 && (!has || n == 1),
                "block {block} cell ({i}, {j}): {n}"
            );
        }
    }
}

#[test]
#[cfg_attr(miri, ignore)] // dozens of picks or builds: minutes under Miri; triangle.rs and the builder's error test run there
fn builder_tree_is_well_formed_with_nodata_rows_and_odd_sizes() {
    let mut r = Lcg(9);
    for (rows, cols) in [(2, 2), (3, 17), (45, 70), (40, 9)] {
        let g = grid(60.0, 170.0, -0.3, 0.4, rows, cols);
        let mut hs: Vec<f64> = (0..rows * cols)
            .map(|_| {
                if r.next() < 0.05 {
                    f64::NAN
                } else {
                    -300.0 + 1000.0 * r.next()
                }
            })
            .collect();
        if rows > 20 {
            hs[(10 * cols) as usize..(15 * cols) as usize].fill(f64::NAN); // rows 10..15 missing
        }
        for block in [1, 3, 4, 16, 64] {
            check_built_tree(&hs, &g, block);
        }
    }
}

#[test]
#[cfg_attr(miri, ignore)] // 600 picks with a brute force each
fn builder_storage_picks_agree_with_brute_force() {
    let mut r = Lcg(77);
    for (lat0_deg, dlat_deg, lon0_deg, block) in
        [(-30.0, 0.5, 170.0, 2), (46.0, -1.0 / 1200.0, 8.0, 4)]
    {
        let g = grid(lat0_deg, lon0_deg, dlat_deg, dlat_deg.abs(), 17, 23);
        let hs: Vec<f64> = (0..17 * 23)
            .map(|_| {
                if r.next() < 0.03 {
                    f64::NAN
                } else {
                    -400.0 + 3000.0 * r.next()
                }
            })
            .collect();
        let dem = TestDem::new(g, hs, block);
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        let e = dem.surface.e;
        for _ in 0..300 {
            let lat = lat0_deg + dlat_deg * 16.0 * r.next();
            let lon = lon0_deg + dlat_deg.abs() * 22.0 * r.next();
            let target = e.geodetic_deg_to_ecef(lat, lon, 3000.0 * r.next());
            let dir = V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5);
            let ray = Ray::new(target.add_scaled(-(100.0 + 3.0e4 * r.next()), dir), dir).unwrap();
            let got = p.pick(&ray).unwrap().map(|h| (h.t, h.cell));
            same_hit(&ray, got, dem.surface.brute(&ray), "builder storage");
        }
    }
}

#[test]
fn builder_rejects_bad_input_with_typed_errors() {
    use build::{BuildError, NodeRecord, SliceStorage, build_tree, node_slots};
    let g = grid(10.0, 20.0, 0.01, 0.01, 5, 6);
    let hs = std::vec![1.0; 30];
    let mut nodes = std::vec![NodeRecord::<f64>::EMPTY; node_slots(5, 6, 2)];
    let err = |hs: &[f64], g: &Grid<f64>, block, nodes: &mut [NodeRecord<f64>]| {
        build_tree(hs, g, block, nodes).unwrap_err()
    };
    assert_eq!(err(&hs[..29], &g, 2, &mut nodes), BuildError::HeightsLength);
    let mut inf = hs.clone();
    inf[13] = f64::INFINITY;
    assert_eq!(
        err(&inf, &g, 2, &mut nodes),
        BuildError::InfiniteHeight([2, 1])
    );
    assert_eq!(err(&hs, &g, 0, &mut nodes), BuildError::InvalidBlock);
    assert_eq!(
        err(&hs, &Grid { dlon_deg: 0.0, ..g }, 2, &mut nodes),
        BuildError::InvalidGrid
    );
    let wide = grid(0.0, 0.0, 10.0, 100.0, 3, 3);
    assert_eq!(
        err(&hs[..9], &wide, 2, &mut nodes),
        BuildError::InvalidBlock
    );
    let short = nodes.len() - 1;
    assert_eq!(
        err(&hs, &g, 2, &mut nodes[..short]),
        BuildError::BufferTooSmall
    );
    let tree = build_tree(&hs, &g, 2, &mut nodes).unwrap();
    let other = grid(10.0, 20.0, 0.01, 0.01, 9, 6);
    let e = Ellipsoid::wgs84();
    let mismatch = SliceStorage::new(e, other, &[1.0; 54], &nodes, tree).unwrap_err();
    assert_eq!(mismatch, BuildError::RecordsMismatch);
    assert!(SliceStorage::new(e, g, &hs, &nodes[..short], tree).is_err());
    // Boxes need the records of this tree and grid, and tables of the grid's lengths.
    let mut boxed = std::vec![NodeRecord::EMPTY; node_slots(5, 6, 2)];
    let tree = build_tree(&hs, &g, 2, &mut boxed).unwrap();
    let boxes =
        |g: &Grid<f64>, hs: &[f64], nodes: &mut [NodeRecord<f64, Option<boxes::NodeBox>>]| {
            build::build_boxes(&e, g, hs, tree, None, nodes).unwrap_err()
        };
    assert_eq!(
        boxes(&other, &[1.0; 54], &mut boxed),
        BuildError::RecordsMismatch
    );
    assert_eq!(
        boxes(&g, &hs, &mut boxed[..short]),
        BuildError::BufferTooSmall
    );
    assert_eq!(boxes(&g, &hs[..29], &mut boxed), BuildError::HeightsLength);
    let (mut rs, mut cs) = (std::vec![(0.0, 0.0); 4], std::vec![(0.0, 0.0); 6]);
    let mut rp = std::vec![build::TrigTables::<f64>::UNSET_PARALLEL; 4];
    let mut cd = std::vec![build::TrigTables::<f64>::UNSET_DD; 6];
    let wrong = build::TrigTables {
        row_sin_cos: &rs,
        col_sin_cos: &cs,
        row_parallel: &rp,
        col_sin_cos_dd: &cd,
    };
    assert_eq!(
        build::build_boxes(&e, &g, &hs, tree, Some(wrong), &mut boxed),
        Err(BuildError::BufferLength)
    );
    assert_eq!(
        build::trig_tables(&e, &g, &mut rs, &mut cs, &mut rp, &mut cd).err(),
        Some(BuildError::BufferLength)
    );
    // The sizes of a record, for the RAM a build needs per height: heights in the samples' type, the box in
    // the record only if its type keeps one.
    assert_eq!(core::mem::size_of::<NodeRecord<f64>>(), 56);
    assert_eq!(core::mem::size_of::<NodeRecord<f32>>(), 44);
    assert_eq!(
        core::mem::size_of::<NodeRecord<f32, Option<boxes::NodeBox>>>(),
        72
    );
    assert_eq!(
        core::mem::size_of::<NodeRecord<f64, Option<boxes::NodeBox>>>(),
        80
    );
}

#[test]
fn builder_boxes_and_trig_tables_give_the_bare_storages_picks() {
    use build::{NodeRecord, Parts, SliceStorage, TreeStorage, TrigTables, build_tree, node_slots};
    let mut r = Lcg(91);
    // (Under Miri a smaller grid and a few rays: the equality of the two storages' picks is checked there.)
    let (rows, cols) = if cfg!(miri) { (9, 11) } else { (17, 23) };
    let g = grid(46.0, 8.0, -1.0 / 1200.0, 1.0 / 1200.0, rows, cols);
    let hs: Vec<f32> = (0..rows * cols)
        .map(|_| {
            if r.next() < 0.03 {
                f32::NAN
            } else {
                (-400.0 + 3000.0 * r.next()) as f32
            }
        })
        .collect();
    let e = Ellipsoid::wgs84();
    let mut nodes = std::vec![NodeRecord::EMPTY; node_slots(rows, cols, 2)];
    let tree = build_tree(&hs, &g, 2, &mut nodes).unwrap();
    let bare: SliceStorage<'_, f64, f32> = SliceStorage::new(e, g, &hs, &nodes, tree).unwrap();
    let (nr, nc) = (build::row_table_len(rows), build::col_table_len(cols));
    let (mut rs, mut cs) = (std::vec![(0.0, 0.0); nr], std::vec![(0.0, 0.0); nc]);
    let mut rp = std::vec![TrigTables::<f64>::UNSET_PARALLEL; nr];
    let mut cd = std::vec![TrigTables::<f64>::UNSET_DD; nc];
    let trig = build::trig_tables(&e, &g, &mut rs, &mut cs, &mut rp, &mut cd).unwrap();
    for i in 0..rows {
        assert_eq!(trig.row_sin_cos[i as usize], sin_cos_deg(g.lat_deg(i)));
        assert_eq!(trig.row_parallel[i as usize], row_parallel(&e, &g, i));
    }
    // The same records with boxes, built from the tables and without them (the tables hold the same values).
    let mut boxed = std::vec![NodeRecord::EMPTY; tree.slots()];
    assert_eq!(build_tree(&hs, &g, 2, &mut boxed), Ok(tree));
    let mut untabled = boxed.clone();
    build::build_boxes(&e, &g, &hs, tree, Some(trig), &mut boxed).unwrap();
    build::build_boxes(&e, &g, &hs, tree, None, &mut untabled).unwrap();
    assert_eq!(boxed, untabled);
    assert!(boxed.iter().filter(|r| r.bbox.is_some()).count() > 4);
    assert!(
        boxed
            .iter()
            .zip(&nodes)
            .all(|(b, n)| b.node::<f64>() == n.node::<f64>())
    );
    let parts = Parts {
        trig: Some(trig),
        ..Parts::new(&hs[..], &boxed[..])
    };
    let full = TreeStorage::with_buffers(e, g, tree, parts).unwrap();
    assert!(full.node_box(NodeId(0)).is_some() && bare.node_box(NodeId(0)).is_none());
    // Wrong lengths are typed errors.
    let short = Parts {
        trig: Some(TrigTables {
            col_sin_cos: &trig.col_sin_cos[1..],
            ..trig
        }),
        ..parts
    };
    assert_eq!(
        TreeStorage::with_buffers(e, g, tree, short).err(),
        Some(build::BuildError::BufferLength)
    );
    let (p0, p1) = (
        Picker::<'_, f64, _>::new(&bare).unwrap(),
        Picker::<'_, f64, _>::new(&full).unwrap(),
    );
    let mut hits = 0;
    let n = if cfg!(miri) { 4 } else { 300 };
    for _ in 0..n {
        let lat = 46.0 - f64::from(rows - 1) / 1200.0 * r.next();
        let lon = 8.0 + f64::from(cols - 1) / 1200.0 * r.next();
        let target = e.geodetic_deg_to_ecef(lat, lon, 3000.0 * r.next());
        let dir = V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5);
        let ray = Ray::new(target.add_scaled(-(100.0 + 3.0e4 * r.next()), dir), dir).unwrap();
        let (a, b) = (p0.pick(&ray).unwrap(), p1.pick(&ray).unwrap());
        assert_eq!(a.map(|h| (h.t, h.cell)), b.map(|h| (h.t, h.cell)));
        hits += usize::from(a.is_some());
    }
    assert!(cfg!(miri) || hits > n / 6, "{hits} hits of {n}");
}

#[test]
#[cfg_attr(miri, ignore)] // a 33 × 65 build: seconds under Miri; the paging tests run the strides and flags there
fn multires_builder_reports_strides_and_residency_flags() {
    use build::{MultiRes, NodeRecord, Parts, TreeStorage, build_multires_tree, node_slots};
    use core::sync::atomic::{AtomicBool, Ordering};
    let g = grid(46.0, 8.0, -1.0 / 1200.0, 1.0 / 1200.0, 33, 65);
    let hs: Vec<f64> = (0..33 * 65).map(|k| (k % 97) as f64).collect();
    let mut nodes = std::vec![NodeRecord::<f64>::EMPTY; node_slots(33, 65, 2)];
    // Fine only in the north-west corner; elsewhere branches end one level above the leaves.
    let shape = MultiRes {
        fine_region: Some([46.0 - 4.0 / 1200.0, 46.0, 8.0, 8.0 + 4.0 / 1200.0]),
        coarse_level: 1,
    };
    let tree = build_multires_tree(&hs, &g, 2, shape, &mut nodes).unwrap();
    let flags: Vec<AtomicBool> = (0..tree.slots()).map(|_| AtomicBool::new(true)).collect();
    let parts = Parts::new(&hs[..], &nodes[..]).with_resident(&flags);
    let s = TreeStorage::with_buffers(Ellipsoid::wgs84(), g, tree, parts).unwrap();
    // A storage whose residency flags are `()` serves single-resolution trees only.
    assert_eq!(
        build::SliceStorage::new(Ellipsoid::wgs84(), g, &hs, &nodes, tree).err(),
        Some(build::BuildError::SingleResolution)
    );
    let (mut fine_leaves, mut coarse_leaves) = (0, 0);
    for k in 0..tree.slots() as u32 {
        let n = s.node(NodeId(k)).unwrap();
        if n.heights.is_none() {
            continue;
        }
        let stride = s.block_stride(NodeId(k));
        assert_eq!(stride, 1 << (tree.depth() - u32::from(n.level)));
        // Ranges start on multiples of the stride (the kernel's requirement).
        assert!(n.rows[0] % stride == 0 && n.cols[0] % stride == 0);
        if n.is_leaf() && stride == 1 {
            fine_leaves += 1;
        } else if n.is_leaf() {
            coarse_leaves += 1;
        }
    }
    assert!(fine_leaves > 0 && coarse_leaves > 0);
    assert!(s.is_resident(NodeId(0)));
    flags[0].store(false, Ordering::Relaxed);
    assert!(!s.is_resident(NodeId(0)));
    let bad = MultiRes {
        fine_region: Some([1.0, 0.0, 0.0, 1.0]),
        coarse_level: 1,
    };
    assert_eq!(
        build_multires_tree(&hs, &g, 2, bad, &mut nodes).err(),
        Some(build::BuildError::InvalidShape)
    );
}
