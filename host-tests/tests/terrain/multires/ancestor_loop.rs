use super::*;

fn setup(dem: &Dem) -> DemStorage<'_> {
    DemStorage::multi_resolution(
        dem,
        8,
        MultiRes {
            fine_region: None,
            coarse_level: 0,
        },
    )
}

/// A ray straight down onto the middle of leaf `leaf`.
fn down_onto(dem: &Dem, leaf: &TreeNode) -> RaySpec {
    let fi = f64::from(leaf.rows[0] + leaf.rows[1]) / 2.0 + 0.37;
    let fj = f64::from(leaf.cols[0] + leaf.cols[1]) / 2.0 + 0.21;
    let (lat, lon) = (dem.lat0 + fi * dem.dlat, dem.lon0 + fj * dem.dlon);
    let top = geodetic_to_ecef_f64(dem.a, dem.b, lat, lon, 9000.0);
    let bottom = geodetic_to_ecef_f64(dem.a, dem.b, lat, lon, -1000.0);
    RaySpec::new(top, [0, 1, 2].map(|a| bottom[a] - top[a]))
}

fn path(tree: &[TreeNode], leaf: &TreeNode) -> Vec<TreeNode> {
    let mut p = vec![*leaf];
    while let Some(q) = p.last().and_then(|n| n.parent) {
        p.push(*tree.iter().find(|n| n.id == q).expect("parent"));
    }
    p.reverse();
    p
}

fn a_deep_leaf(tree: &[TreeNode]) -> TreeNode {
    let depth = tree.iter().map(|n| n.level).max().expect("nodes");
    *tree
        .iter()
        .filter(|n| n.leaf && n.level == depth)
        .nth(5)
        .expect("leaves")
}

fn check_against_oracle(dem: &Dem, s: &DemStorage<'_>, min_level: u8, r: &RaySpec, hit: &Hit<f64>) {
    let o = MultiResOracle::new(dem, &s.tree(), min_level)
        .expect("surface")
        .pick(r)
        .expect("oracle hit");
    assert!(dist(o.point, hit.ecef) < TOL, "{hit:?} vs {o:?}");
    assert_eq!((o.level, o.stride), (hit.level, hit.stride));
}

#[test]
fn resident_leaf_uses_its_own_block() {
    let dem = dem_at(45.0, 7.0, 97, 11);
    let s = setup(&dem);
    let tree = s.tree();
    let leaf = a_deep_leaf(&tree);
    let r = down_onto(&dem, &leaf);
    let hit = pick(&s, 0, &r).expect("answer").expect("hit");
    assert_eq!((hit.level, hit.stride), (leaf.level, 1));
    check_against_oracle(&dem, &s, 0, &r, &hit);
}

#[test]
fn resident_parent_stands_in_for_a_missing_leaf() {
    let dem = dem_at(45.0, 7.0, 97, 11);
    let s = setup(&dem);
    let tree = s.tree();
    let leaf = a_deep_leaf(&tree);
    s.set_resident(NodeId(leaf.id), false);
    let parent = path(&tree, &leaf)[leaf.level as usize - 1];
    let r = down_onto(&dem, &leaf);
    let hit = pick(&s, 0, &r).expect("answer").expect("hit");
    assert_eq!((hit.level, hit.stride), (parent.level, parent.stride));
    assert_eq!(parent.stride, 2);
    check_against_oracle(&dem, &s, 0, &r, &hit);
}

#[test]
fn only_the_zone_resident_traces_the_zone_block() {
    let dem = dem_at(45.0, 7.0, 97, 11);
    let s = setup(&dem);
    let tree = s.tree();
    for n in &tree {
        s.set_resident(NodeId(n.id), n.parent.is_none());
    }
    let leaf = a_deep_leaf(&tree);
    let zone = path(&tree, &leaf)[0];
    let r = down_onto(&dem, &leaf);
    let hit = pick(&s, 0, &r).expect("answer").expect("hit");
    assert_eq!((hit.level, hit.stride), (0, zone.stride));
    assert!(zone.stride >= 4);
    check_against_oracle(&dem, &s, 0, &r, &hit);
}

#[test]
fn needs_block_when_the_node_at_min_level_is_not_resident() {
    let dem = dem_at(45.0, 7.0, 97, 11);
    let s = setup(&dem);
    let tree = s.tree();
    let leaf = a_deep_leaf(&tree);
    let p = path(&tree, &leaf);
    // Level 1 and everything below it missing on this path; the zone resident.
    for n in &p[1..] {
        s.set_resident(NodeId(n.id), false);
    }
    let r = down_onto(&dem, &leaf);
    // min_level 0: the zone stands in.
    let hit = pick(&s, 0, &r).expect("answer").expect("hit");
    assert_eq!(hit.level, 0);
    // min_level 1: the zone may not; the node at level 1 is needed.
    assert_eq!(
        pick(&s, 1, &r),
        Err(TerrainError::NeedsBlock(NodeId(p[1].id)))
    );
    // Paged in, it answers, and its own missing child falls back to it.
    s.set_resident(NodeId(p[1].id), true);
    let hit = pick(&s, 1, &r).expect("answer").expect("hit");
    assert_eq!((hit.level, hit.stride), (1, p[1].stride));
    check_against_oracle(&dem, &s, 1, &r, &hit);
}

#[test]
fn resident_block_below_a_missing_one_answers_for_its_region() {
    let dem = dem_at(45.0, 7.0, 97, 11);
    let s = setup(&dem);
    let tree = s.tree();
    let leaf = a_deep_leaf(&tree);
    let p = path(&tree, &leaf);
    // The zone and the leaf resident, everything between missing.
    for n in &tree {
        s.set_resident(NodeId(n.id), n.parent.is_none() || n.id == leaf.id);
    }
    let r = down_onto(&dem, &leaf);
    let hit = pick(&s, 0, &r).expect("answer").expect("hit");
    assert_eq!((hit.level, hit.stride), (leaf.level, 1));
    check_against_oracle(&dem, &s, 0, &r, &hit);
    // A sibling leaf under the same missing parent falls back to the zone.
    let sibling = *tree
        .iter()
        .find(|n| n.leaf && n.parent == leaf.parent && n.id != leaf.id)
        .expect("a sibling");
    let r = down_onto(&dem, &sibling);
    let hit = pick(&s, 0, &r).expect("answer").expect("hit");
    assert_eq!((hit.level, hit.stride), (0, p[0].stride));
    check_against_oracle(&dem, &s, 0, &r, &hit);
}

/// 4-cell blocks: the zone's cells (8 grid steps) are larger than the leaves (4 cells), so with the zone as
/// the source a leaf's parent is traced whole from the zone and a resident leaf inside it is not used (a
/// source cell is never split).
#[test]
fn source_cells_larger_than_the_leaves_are_not_split() {
    let dem = dem_at(45.0, 7.0, 97, 11);
    let s = DemStorage::multi_resolution(
        &dem,
        4,
        MultiRes {
            fine_region: None,
            coarse_level: 0,
        },
    );
    let tree = s.tree();
    let leaf = a_deep_leaf(&tree);
    let p = path(&tree, &leaf);
    assert!(
        p[0].stride > leaf.rows[1] - leaf.rows[0],
        "zone cells larger than a leaf"
    );
    for n in &tree {
        s.set_resident(NodeId(n.id), n.parent.is_none() || n.id == leaf.id);
    }
    let r = down_onto(&dem, &leaf);
    let hit = pick(&s, 0, &r).expect("answer").expect("hit");
    assert_eq!((hit.level, hit.stride), (0, p[0].stride));
    check_against_oracle(&dem, &s, 0, &r, &hit);
}

#[test]
fn leaf_shallower_than_min_level_uses_its_own_block() {
    let dem = dem_at(45.0, 7.0, 97, 11);
    // Leaves at pyramid level 2 (kernel level 1) outside a small box.
    let box_ = [45.0, 45.02, 7.0, 7.02];
    let s = DemStorage::multi_resolution(
        &dem,
        8,
        MultiRes {
            fine_region: Some(box_),
            coarse_level: 2,
        },
    );
    let tree = s.tree();
    let depth = tree.iter().map(|n| n.level).max().expect("nodes");
    let shallow = *tree
        .iter()
        .rfind(|n| n.leaf && n.level < depth)
        .expect("a coarse leaf");
    let r = down_onto(&dem, &shallow);
    // Every inner node not resident: irrelevant, the leaves are at or above min_level = depth.
    for n in &tree {
        s.set_resident(NodeId(n.id), n.leaf);
    }
    let hit = pick(&s, depth, &r).expect("answer").expect("hit");
    assert_eq!((hit.level, hit.stride), (shallow.level, shallow.stride));
    check_against_oracle(&dem, &s, depth, &r, &hit);
    // The leaf itself missing: its block is needed, whatever its ancestors hold.
    s.set_resident(NodeId(shallow.id), false);
    assert_eq!(
        pick(&s, depth, &r),
        Err(TerrainError::NeedsBlock(NodeId(shallow.id)))
    );
}
