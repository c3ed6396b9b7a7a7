//! Fuzz target for multi-resolution terrain picking (Wartell et al. §5–§6): small random DEMs (3–17 × 3–17 vertices,
//! or 5–33 × 3–17, anywhere on the globe, poles and the antimeridian included, nodata vertices and nodata
//! patches), the kernel's builder's multi-resolution tree over them (`build_multires_tree`: leaves of 1–4 cells
//! under up to 8 × 4 zones, up to level 3, every node with a block at stride `2^(its level above the leaves)`,
//! branches ending at a coarse level outside a fine region), random residency flags, a random `min_level` and a
//! random ray.
//!
//! The target builds, in `f64` and with logic of its own, the surface that the tree, the residency and
//! `min_level` select (the kernel's module docs, "Multi-resolution"):
//!
//! 1. per leaf, walking its path from the zone: a node shallower than `min_level` is passed, and if it is the
//!    leaf its own block answers (it must be resident); from `min_level` on, a resident node becomes the source
//!    and a resident leaf answers with its own block; a missing node without a source needs its own block; a
//!    missing node with a source is passed if it has children and all of them lie on the source's lattice,
//!    and is otherwise traced whole with the source's block (its own block is needed if it is off the lattice);
//! 2. the traced regions are painted on a per-cell map;
//! 3. a region's border cell whose side has vertices of a finer region across it (strictly inside the side) is
//!    the fan from the middle of its diagonal through its corners and those vertices; other cells are their two
//!    triangles; triangles with a nodata vertex are absent.
//!
//! Checked on every input: nothing panics; the kernel returns `Ok` or `NeedsBlock(id)` with `id` a non-resident
//! node whose block the construction needs. When the construction needs no block, the kernel must answer, and
//! agree with an `f64` brute force over that surface by `pick`'s geometric criteria:
//!
//! * no false hit: a kernel hit point must lie within 1 mm (plus rounding of the point itself) of some triangle;
//! * no miss: if the brute force finds a hit at a non-grazing angle whose point lies at least 1 mm inside a
//!   triangle (from every edge), the kernel must return a hit no farther than it (within 1 mm).
//!
//! Bit 3 of `fine` (unused by the spacing) doubles the grid's rows, so that trees reach level 3 (strides up
//! to 8). Bit 4 makes the storage provide node boxes ([`TerrainCaches::node_box`], the builder's
//! `build_boxes_sharing`: each contains every vertex of its node's range, not only its block's samples), so
//! that half of the inputs run the traversal's box tests and half its spheroidal volumes; bits 5–7 choose which
//! boxes are in their parent's box frame rather than their parent's own.
#![no_main]

use arbitrary::Arbitrary;
use curvicast::Ray;
use curvicast::geodesy::Ellipsoid;
use curvicast::terrain::boxes::NodeBox;
use curvicast::terrain::build::{
    Buffers, MultiRes, NodeRecord, Parts, TreeStorage, build_boxes_sharing, build_multires_tree,
    node_slots,
};
use curvicast::terrain::{Grid, Node, NodeId, Picker, TerrainError, TerrainStorage};
use libfuzzer_sys::fuzz_target;
use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::AtomicBool;

/// The most vertices along a side of the grid's heights (a grid of doubled rows repeats them).
const MAX_SIDE: usize = 17;

#[derive(Debug, Arbitrary)]
struct Input {
    lat0: u16,
    lon0: i16,
    dlat: i16,
    dlon: u16,
    /// Divides both spacings by `2^(fine % 8)`; bits 3–7: see the module docs.
    fine: u8,
    rows: u8,
    cols: u8,
    /// The height unit (see below).
    hstep: u8,
    heights: [i8; MAX_SIDE * MAX_SIDE],
    /// Single nodata vertices (indices past the grid are ignored).
    holes: [u16; 6],
    /// A nodata rectangle of vertices `[i0, j0, di, dj]` (it may empty whole nodes).
    hole_rect: Option<[u8; 4]>,
    /// A multiple of 3: the full tree everywhere; else branches outside the fine region end at the coarse
    /// level (`tree`).
    zones: u8,
    /// The leaf block (`tree[0]`), the fine region's rows and columns as fractions of the grid's
    /// (`tree[1..5]`), and the coarse level (`tree[5]`).
    tree: [u8; 48],
    /// Non-resident nodes: bit `id % 128`; with `sparse`, only where `absent_and` has the bit too.
    absent: u128,
    absent_and: u128,
    sparse: bool,
    all_resident: bool,
    min_level: u8,
    /// Origin above the grid (else anywhere on the globe).
    above: bool,
    origin_lat: i16,
    origin_lon: i16,
    origin_h: i32,
    target: [u8; 2],
    target_h: i16,
    jitter: [i16; 3],
    t_max: Option<u16>,
}

/// The buffers of the storage, owned: heights (NaN: nodata), the builder's node records with their boxes (none
/// unless asked for) and residency flags, by node id.
struct Owned {
    heights: Vec<f64>,
    nodes: Vec<NodeRecord<f64, Option<NodeBox>>>,
    resident: Vec<AtomicBool>,
}

impl Buffers<f64> for Owned {
    type Height = f64;
    type Box = Option<NodeBox>;
    type Flag = AtomicBool;
    fn parts(&self) -> Parts<'_, f64, f64, Option<NodeBox>, AtomicBool> {
        Parts::new(&self.heights, &self.nodes).with_resident(&self.resident)
    }
}

/// The storage: the kernel's [`TreeStorage`] over [`Owned`].
type Storage = TreeStorage<f64, Owned>;

/// The one place the target builds its storage: the builder's multi-resolution tree of `heights` with leaves of
/// `block` cells and `shape`, node boxes if `share` is given (a child's box in the frame of its parent's box
/// where `share(id)`), and each node's residency from `resident(id)`.
fn storage(
    grid: Grid<f64>,
    heights: Vec<f64>,
    block: u32,
    shape: MultiRes<f64>,
    share: Option<&dyn Fn(NodeId) -> bool>,
    resident: impl Fn(NodeId) -> bool,
) -> Storage {
    let e = Ellipsoid::wgs84();
    let mut nodes = vec![NodeRecord::EMPTY; node_slots(grid.rows, grid.cols, block)];
    let tree = build_multires_tree(&heights, &grid, block, shape, &mut nodes)
        .expect("the builder refused a valid DEM");
    if let Some(share) = share {
        build_boxes_sharing(&e, &grid, &heights, tree, None, &mut nodes, |id, _| {
            share(id)
        })
        .expect("node boxes");
    }
    let resident = (0..tree.slots() as u32)
        .map(|k| AtomicBool::new(resident(NodeId(k))))
        .collect();
    let owned = Owned {
        heights,
        nodes,
        resident,
    };
    TreeStorage::with_buffers(e, grid, tree, owned).expect("storage over the builder's buffers")
}

/// The oracle's copy of the tree, read from the storage once by walking down from its zones: the nodes with
/// data (the kernel skips a zone without data, the builder leaves such children out), with their strides,
/// parents and residency, indexed in the order found (children as those indices, `id` the storage's ids); and
/// its own heights.
struct Tree {
    grid: Grid<f64>,
    h: Vec<Option<f64>>,
    nodes: Vec<Node<f64>>,
    id: Vec<u32>,
    stride: Vec<u32>,
    parent: Vec<Option<usize>>,
    resident: Vec<bool>,
}

impl Tree {
    fn read(s: &Storage, h: Vec<Option<f64>>) -> Self {
        let mut t = Tree {
            grid: s.grid(),
            h,
            nodes: Vec::new(),
            id: Vec::new(),
            stride: Vec::new(),
            parent: Vec::new(),
            resident: Vec::new(),
        };
        let mut todo: Vec<(NodeId, Option<usize>)> = (0..s.zone_count())
            .filter_map(|k| s.zone(k))
            .map(|z| (z, None))
            .collect();
        // Each node is reached once (the children partition their parent), so this visits at most every slot.
        while let Some((id, parent)) = todo.pop() {
            let node = s.node(id).expect("a node the tree links to");
            if node.heights.is_none() {
                continue;
            }
            let k = t.nodes.len();
            t.nodes.push(node);
            t.id.push(id.0);
            t.stride.push(s.block_stride(id));
            t.parent.push(parent);
            t.resident.push(s.is_resident(id));
            todo.extend(node.children.iter().flatten().map(|&c| (c, Some(k))));
        }
        let index: BTreeMap<u32, usize> = t.id.iter().enumerate().map(|(k, &id)| (id, k)).collect();
        for n in &mut t.nodes {
            for c in &mut n.children {
                *c = c.and_then(|c| index.get(&c.0)).map(|&k| NodeId(k as u32));
            }
        }
        t
    }

    fn height(&self, i: u32, j: u32) -> Option<f64> {
        if i >= self.grid.rows || j >= self.grid.cols {
            return None;
        }
        self.h
            .get((i * self.grid.cols + j) as usize)
            .copied()
            .flatten()
    }
}

/// A traced region: cell ranges and the stride of the block that traces it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Region {
    rows: [u32; 2],
    cols: [u32; 2],
    stride: u32,
}

/// What [`regions`] returns.
type Regions = Result<(Vec<Region>, Vec<Option<usize>>), BTreeSet<u32>>;

/// Rule 1 for every leaf: the traced regions and the per-cell paint, or the ids of every block needed.
fn regions(t: &Tree, min_level: u8) -> Regions {
    let cc = t.grid.cols - 1;
    let cr = t.grid.rows - 1;
    let mut paint = vec![None; (cr * cc) as usize];
    let mut regs: Vec<Region> = Vec::new();
    let mut needs = BTreeSet::new();
    let own = |k: usize| Region {
        rows: t.nodes[k].rows,
        cols: t.nodes[k].cols,
        stride: t.stride[k],
    };
    for (leaf, node) in t.nodes.iter().enumerate() {
        if !node.children.iter().all(Option::is_none) {
            continue;
        }
        let mut path = vec![leaf];
        while let Some(p) = path.last().and_then(|&k| t.parent[k]) {
            path.push(p);
        }
        path.reverse();
        let on = |m: &Node<f64>, s: u32| {
            let fits = |r: [u32; 2], last: u32| {
                r[0].is_multiple_of(s) && (r[1].is_multiple_of(s) || r[1] == last)
            };
            fits(m.rows, cr) && fits(m.cols, cc)
        };
        let mut src: Option<usize> = None;
        let mut reg = None;
        let mut need = None;
        for &k in &path {
            let n = &t.nodes[k];
            let is_leaf = n.children.iter().all(Option::is_none);
            if n.level < min_level {
                if is_leaf {
                    if t.resident[k] {
                        reg = Some(own(k));
                    } else {
                        need = Some(k);
                    }
                }
                continue;
            }
            if t.resident[k] {
                if is_leaf {
                    reg = Some(own(k));
                    break;
                }
                src = Some(k);
                continue;
            }
            let Some(a) = src else {
                need = Some(k);
                break;
            };
            let s = t.stride[a];
            if !is_leaf
                && n.children
                    .iter()
                    .flatten()
                    .all(|c| on(&t.nodes[c.0 as usize], s))
            {
                continue;
            }
            if on(n, s) {
                reg = Some(Region {
                    rows: n.rows,
                    cols: n.cols,
                    stride: s,
                });
            } else {
                need = Some(k);
            }
            break;
        }
        if let Some(k) = need {
            needs.insert(t.id[k]);
            continue;
        }
        let Some(reg) = reg else { continue };
        let k = regs.iter().position(|r| *r == reg).unwrap_or_else(|| {
            regs.push(reg);
            regs.len() - 1
        });
        for i in node.rows[0]..node.rows[1] {
            for j in node.cols[0]..node.cols[1] {
                paint[(i * cc + j) as usize] = Some(k);
            }
        }
    }
    if needs.is_empty() {
        Ok((regs, paint))
    } else {
        Err(needs)
    }
}

type P3 = [f64; 3];

/// One side of a traced cell: along a row (the points are columns) or a column, at row or column `fixed`, from
/// corner `ends[0]` to corner `ends[1]`; `across` is the neighbouring cells' row or column; `extra` the vertices
/// of finer regions strictly inside it.
struct Side {
    along_row: bool,
    fixed: u32,
    ends: [u32; 2],
    across: i64,
    extra: BTreeSet<u32>,
}

/// Rules 2–3: every triangle of the surface, in `f64`.
fn triangles(
    t: &Tree,
    regs: &[Region],
    paint: &[Option<usize>],
    vert: &impl Fn(u32, u32) -> Option<P3>,
) -> Vec<[P3; 3]> {
    let (cr, cc) = (t.grid.rows - 1, t.grid.cols - 1);
    let region_at = |i: i64, j: i64| -> Option<Region> {
        if i < 0 || j < 0 || i >= i64::from(cr) || j >= i64::from(cc) {
            return None;
        }
        paint[(i * i64::from(cc) + j) as usize].map(|k| regs[k])
    };
    let mut out = Vec::new();
    for reg in regs {
        let s = reg.stride;
        let mut i = reg.rows[0];
        while i < reg.rows[1] {
            let i1 = (i + s).min(reg.rows[1]);
            let mut j = reg.cols[0];
            while j < reg.cols[1] {
                let j1 = (j + s).min(reg.cols[1]);
                // The four sides, corner to corner; `across` only on the region's border.
                let border = [
                    i == reg.rows[0],
                    i1 == reg.rows[1],
                    j == reg.cols[0],
                    j1 == reg.cols[1],
                ];
                let mut sides = [
                    (true, i, [j, j1], i64::from(i) - 1),
                    (true, i1, [j, j1], i64::from(i1)),
                    (false, j, [i, i1], i64::from(j) - 1),
                    (false, j1, [i, i1], i64::from(j1)),
                ]
                .map(|(along_row, fixed, ends, across)| Side {
                    along_row,
                    fixed,
                    ends,
                    across,
                    extra: BTreeSet::new(),
                });
                for (side, _) in sides.iter_mut().zip(border).filter(|x| x.1) {
                    let [from, to] = side.ends;
                    for k in from..to {
                        let nb = if side.along_row {
                            region_at(side.across, i64::from(k))
                        } else {
                            region_at(i64::from(k), side.across)
                        };
                        let Some(nb) = nb.filter(|nb| nb.stride < s) else {
                            continue;
                        };
                        let [lo, hi] = if side.along_row { nb.cols } else { nb.rows };
                        let mut p = lo.div_ceil(nb.stride) * nb.stride;
                        while p <= hi {
                            if p > from && p < to {
                                side.extra.insert(p);
                            }
                            p += nb.stride;
                        }
                    }
                }
                let (v00, v11) = (vert(i, j), vert(i1, j1));
                let any = sides.iter().any(|x| !x.extra.is_empty());
                match (v00, v11) {
                    (Some(a), Some(b)) if any => {
                        let m = [0, 1, 2].map(|k| (a[k] + b[k]) * 0.5);
                        for side in &sides {
                            let at = |p: u32| {
                                if side.along_row {
                                    vert(side.fixed, p)
                                } else {
                                    vert(p, side.fixed)
                                }
                            };
                            let mut prev = at(side.ends[0]);
                            for p in side.extra.iter().copied().chain([side.ends[1]]) {
                                let cur = at(p);
                                if let (Some(x), Some(y)) = (prev, cur) {
                                    out.push([m, x, y]);
                                }
                                prev = cur;
                            }
                        }
                    }
                    _ => {
                        let (v01, v10) = (vert(i, j1), vert(i1, j));
                        for tri in [[v00, v01, v11], [v00, v11, v10]] {
                            if let [Some(x), Some(y), Some(z)] = tri {
                                out.push([x, y, z]);
                            }
                        }
                    }
                }
                j = j1;
            }
            i = i1;
        }
    }
    out
}

fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: P3) -> f64 {
    dot(a, a).sqrt()
}

/// The ray's crossing of the triangle's plane: (t, sin of the angle between ray and plane), or `None` when
/// the ray is parallel to it. The origin is taken relative to `v[0]` first.
fn plane_crossing(o: P3, d: P3, v: [P3; 3]) -> Option<(f64, f64)> {
    let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    let nd = dot(n, d);
    if nd == 0.0 || !nd.is_finite() {
        return None;
    }
    let t = -dot(n, sub(o, v[0])) / nd;
    Some((t, nd.abs() / (norm(n) * norm(d))))
}

/// Signed in-plane distances of `p` from the triangle's three edge lines (positive inside).
fn edge_distances(p: P3, v: [P3; 3]) -> [f64; 3] {
    let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    let nn = norm(n);
    let mut out = [0.0; 3];
    for (k, slot) in out.iter_mut().enumerate() {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        let e = sub(b, a);
        *slot = dot(cross(e, sub(p, a)), n) / (nn * norm(e));
    }
    out
}

/// Distance from `p` to the (closed) triangle.
fn distance_to_triangle(p: P3, v: [P3; 3]) -> f64 {
    let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    let nn = norm(n);
    let mut best = f64::INFINITY;
    // The segments.
    for k in 0..3 {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        let e = sub(b, a);
        let ee = dot(e, e);
        let s = if ee > 0.0 {
            (dot(sub(p, a), e) / ee).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + s * e[0], a[1] + s * e[1], a[2] + s * e[2]];
        best = best.min(norm(sub(p, q)));
    }
    // The interior, when the projection falls inside.
    if nn > 0.0 && edge_distances(p, v).iter().all(|&x| x >= 0.0) {
        best = best.min((dot(sub(p, v[0]), n) / nn).abs());
    }
    best
}

fuzz_target!(|inp: Input| {
    // Bit 3 of `fine`: twice the rows (more than 16 cell rows: one-cell leaves three levels below the zones).
    let rows = match 3 + u32::from(inp.rows % 15) {
        n if inp.fine & 0x08 != 0 => 2 * n - 1,
        n => n,
    };
    let cols = 3 + u32::from(inp.cols % 15);
    let fine = f64::from(1u32 << (inp.fine % 8));
    // Up to ±2.7° and 5.5°: a zone (at most 12 cells wide) spans less than 90° of longitude, and a cell of the
    // coarsest blocks (8 grid steps) less than 45° of arc, whose chords the kernel's volumes can bound.
    let dlat = f64::from(inp.dlat) / 12000.0 / fine;
    let dlon = (1e-4 + f64::from(inp.dlon) / 12000.0) / fine;
    if dlat == 0.0 {
        return;
    }
    // Row 0 placed so that every row lies within ±90° (the ends reach the poles).
    let span = f64::from(rows - 1) * dlat;
    let (lo, hi) = (-90.0 - span.min(0.0), 90.0 - span.max(0.0));
    let lat0 = lo + f64::from(inp.lat0) / f64::from(u16::MAX) * (hi - lo);
    let lon0 = f64::from(inp.lon0) / 90.0;
    let grid = Grid {
        lat0_deg: lat0,
        lon0_deg: lon0,
        dlat_deg: dlat,
        dlon_deg: dlon,
        rows,
        cols,
    };
    if !grid.validate() {
        return;
    }
    let n = (rows * cols) as usize;
    // The height unit: absolute (up to 63 m, heights up to 8 km whatever the spacing), or relative to the
    // spacing (slopes up to about 2).
    let cell_m = 111_000.0 * dlat.abs().min(dlon);
    let unit = if inp.hstep >= 0xc0 {
        f64::from(inp.hstep & 0x3f)
    } else {
        (f64::from(inp.hstep) / 192.0 * cell_m / 128.0).min(63.0)
    };
    let mut h: Vec<Option<f64>> = (0..n)
        .map(|k| Some(f64::from(inp.heights[k % (MAX_SIDE * MAX_SIDE)]) * unit))
        .collect();
    for k in inp.holes {
        if let Some(x) = h.get_mut(usize::from(k)) {
            *x = None;
        }
    }
    if let Some([i0, j0, di, dj]) = inp.hole_rect {
        let (i0, j0) = (u32::from(i0) % rows, u32::from(j0) % cols);
        for i in i0..(i0 + 1 + u32::from(di) % 6).min(rows) {
            for j in j0..(j0 + 1 + u32::from(dj) % 6).min(cols) {
                h[(i * cols + j) as usize] = None;
            }
        }
    }
    let (cr, cc) = (rows - 1, cols - 1);
    let b = inp.tree;
    let block = 1 + u32::from(b[0] % 4);
    // The fine region: rows and columns between two fractions of the grid's each.
    let shape = if inp.zones.is_multiple_of(3) {
        MultiRes::default()
    } else {
        let at = |x: u8, n: u32| u32::from(x) * n / 255;
        let (i0, i1) = (at(b[1], cr), at(b[2], cr));
        let (j0, j1) = (at(b[3].min(b[4]), cc), at(b[3].max(b[4]), cc));
        let (la, lb) = (grid.lat_deg(i0), grid.lat_deg(i1));
        MultiRes {
            fine_region: Some([la.min(lb), la.max(lb), grid.lon_deg(j0), grid.lon_deg(j1)]),
            coarse_level: u32::from(b[5] % 4),
        }
    };
    let share = inp.fine >> 5;
    let shared = move |id: NodeId| (share >> (id.0 % 3)) & 1 == 1;
    let resident = |id: NodeId| {
        let bit = |m: u128| (m >> (id.0 % 128)) & 1 == 1;
        inp.all_resident || !(bit(inp.absent) && (!inp.sparse || bit(inp.absent_and)))
    };
    let heights = h.iter().map(|v| v.unwrap_or(f64::NAN)).collect();
    let boxes = (inp.fine & 0x10 != 0).then_some(&shared as &dyn Fn(NodeId) -> bool);
    let s = storage(grid, heights, block, shape, boxes, resident);
    let t = Tree::read(&s, h);
    let depth = t.nodes.iter().map(|n| n.level).max().unwrap_or(0);
    let min_level = inp.min_level % (depth + 1);

    let e = Ellipsoid::<f64>::wgs84();
    let picker = match Picker::<'_, f64, Storage>::new(&s) {
        Ok(p) => p.with_min_level(min_level),
        Err(err) => panic!("a valid storage was rejected: {err:?}"),
    };

    // The ray: from anywhere on the globe, or from above the grid, towards a point of the grid.
    let o = if inp.above {
        let oi = f64::from(inp.origin_lat as u16) / f64::from(u16::MAX) * f64::from(cr);
        let oj = f64::from(inp.origin_lon as u16) / f64::from(u16::MAX) * f64::from(cc);
        e.geodetic_deg_to_ecef(
            (lat0 + oi * dlat).clamp(-90.0, 90.0),
            lon0 + oj * dlon,
            f64::from((inp.origin_h % 100_000).abs()),
        )
    } else {
        let olat = (f64::from(inp.origin_lat) / 360.0).clamp(-90.0, 90.0);
        e.geodetic_deg_to_ecef(
            olat,
            f64::from(inp.origin_lon) / 90.0,
            f64::from(inp.origin_h) * 4.0,
        )
    };
    let ti = f64::from(inp.target[0]) / 255.0 * f64::from(cr);
    let tj = f64::from(inp.target[1]) / 255.0 * f64::from(cc);
    // Near the terrain there: the height of the nearest vertex, mostly lowered.
    let near = t.height(ti.round() as u32, tj.round() as u32);
    let tp = e.geodetic_deg_to_ecef(
        (lat0 + ti * dlat).clamp(-90.0, 90.0),
        lon0 + tj * dlon,
        near.unwrap_or(0.0) + (f64::from(inp.target_h) / 4096.0 - 2.0) * unit,
    );
    let o = [o.x, o.y, o.z];
    let mut d = [tp.x - o[0], tp.y - o[1], tp.z - o[2]];
    for (c, j) in d.iter_mut().zip(inp.jitter) {
        *c += f64::from(j) / 16384.0 * cell_m; // up to 2 cells off the target
    }
    let t_max = inp.t_max.map_or(f64::INFINITY, |m| f64::from(m) / 1000.0);
    let Ok(ray) = Ray::new(o, d).and_then(|r| r.with_interval(0.0, t_max)) else {
        return;
    };
    let res = picker.pick(&ray);

    let (regs, paint) = match regions(&t, min_level) {
        Ok(x) => x,
        Err(needs) => {
            match res {
                Ok(_) => {}
                Err(TerrainError::NeedsBlock(id)) => assert!(
                    needs.contains(&id.0) && !s.is_resident(id),
                    "NeedsBlock({}) is not a needed block: {needs:?}",
                    id.0
                ),
                Err(err) => panic!("unexpected error {err:?}"),
            }
            return;
        }
    };
    let hit = match res {
        Ok(h) => h,
        Err(err) => panic!("the surface needs no block, yet the kernel says {err:?}"),
    };

    let vert = |i: u32, j: u32| {
        let hh = t.height(i, j)?;
        let p = e.geodetic_deg_to_ecef(grid.lat_deg(i), grid.lon_deg(j), hh);
        Some([p.x, p.y, p.z])
    };
    let tris = triangles(&t, &regs, &paint, &vert);

    // Brute force over every triangle of the surface. Lengths are in metres; `slack` covers the rounding of a
    // point of the ray, which grows with the distance of the origin.
    let dl = norm(d);
    let slack = 1e-3 + 1e-12 * norm(o);
    let at = |tt: f64| [o[0] + tt * d[0], o[1] + tt * d[1], o[2] + tt * d[2]];
    let mut nearest_to_hit = f64::INFINITY;
    let mut strict: Option<f64> = None;
    for &v in &tris {
        if let Some(h) = &hit {
            nearest_to_hit = nearest_to_hit.min(distance_to_triangle(at(h.t), v));
        }
        let Some((tt, sin)) = plane_crossing(o, d, v) else {
            continue;
        };
        let tol_t = (slack + 1e-12 * tt.abs() * dl) / dl;
        if sin > 1e-3
            && tt > tol_t
            && tt < t_max - tol_t
            && edge_distances(at(tt), v).iter().all(|&x| x >= 1e-3 + slack)
        {
            strict = Some(strict.map_or(tt, |s: f64| s.min(tt)));
        }
    }
    if let Some(h) = &hit {
        let tol = slack + 1e-12 * h.t.abs() * dl;
        assert!(
            nearest_to_hit <= tol,
            "false hit at t = {} (stride {}, level {}, cell {:?}): the nearest triangle is {nearest_to_hit} m away",
            h.t,
            h.stride,
            h.level,
            h.cell
        );
    }
    if let Some(tb) = strict {
        let tk = hit.map(|h| h.t);
        let tol_t = (slack + 1e-12 * tb.abs() * dl) / dl;
        assert!(
            tk.is_some_and(|tk| tk <= tb + tol_t),
            "miss: brute force hits at t = {tb}, kernel {tk:?}"
        );
    }
});
