//! The multi-resolution terrain oracle (Wartell et al. §5–§6): the nearest intersection of a ray with the surface that
//! a multi-resolution tree, a residency pattern and a `min_level` select, by brute force over every triangle of
//! that surface, decided in arbitrary precision.
//!
//! The surface (the kernel's module docs, "Multi-resolution", state the same rules; this module derives it
//! with logic of its own, from plain tree data and the DEM):
//!
//! 1. **Per leaf, walking its path from the zone down.** A node shallower than `min_level` is passed; if it
//!    is the leaf, its own block answers (it must be resident). From `min_level` on, a resident node becomes the
//!    source, and a resident leaf answers with its own block. A missing node without a source needs its own
//!    block. A missing node with a source `A` is passed when it has children and all of them have ranges on
//!    `A`'s sample lattice; otherwise (a leaf, or children smaller than `A`'s cells) its whole region is traced
//!    with `A`'s block (cells `stride(A)` grid steps wide) if its own ranges are on that lattice, and its block
//!    is needed if not.
//! 2. **Painting.** Each traced region is painted onto a full-resolution cell map; a region is a set of
//!    `stride × stride` cells (fewer at the grid's last row and column).
//! 3. **Stitching.** For each cell on the border of its region, each side is compared, fine cell by fine cell,
//!    with the painted regions across it: every sample of a finer region across that lies strictly inside the
//!    side is a vertex of the side. A cell with such vertices is the fan from the middle `M` of its diagonal
//!    `V(i,j)–V(i1,j1)` through its corners and those vertices, side by side; otherwise its two triangles
//!    `(V00, V01, V11)`, `(V00, V11, V10)`. Triangles with a missing vertex are absent.
//! 4. **Intersection** as in [`super::terrain`]: an `f64` ball filter with a wide margin, then the exact test
//!    at 256 bits in order of ball entry, both faces counting.

use super::terrain::{Exact, P, RM, ball_entry, bf, intersect_exact, to_f64};
use astro_float::BigFloat;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::Dem;
use std::collections::{BTreeSet, HashMap};

pub use curvicast_cli::storage::TreeNode;

/// A vertex of the oracle's surface: a grid vertex or the middle of two.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum V {
    Grid(usize, usize),
    Mid(usize, usize, usize, usize),
}

/// One traced region: ranges, stride and the level of the block's node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct Region {
    rows: [u32; 2],
    cols: [u32; 2],
    stride: u32,
    level: u8,
}

/// The oracle's answer for one ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultiResHit {
    /// The ray parameter, rounded from 256 bits.
    pub t: f64,
    /// The hit point, rounded from 256 bits.
    pub point: [f64; 3],
    /// The traced cell's first row and column.
    pub cell: [u32; 2],
    /// The traced cell's stride.
    pub stride: u32,
    /// The level of the block's node.
    pub level: u8,
}

/// One triangle of the surface: its vertices, their `f64` positions, its cell and the cell's region.
type Triangle = ([V; 3], [[f64; 3]; 3], [u32; 2], Region);

/// The surface of one tree, residency and `min_level`, ready for rays.
pub struct MultiResOracle<'a> {
    dem: &'a Dem,
    exact: Exact,
    tris: Vec<Triangle>,
    stitched_cells: usize,
}

impl<'a> MultiResOracle<'a> {
    /// Builds the surface, or returns the id of a node whose block the surface needs (rule 1).
    pub fn new(dem: &'a Dem, nodes: &[TreeNode], min_level: u8) -> Result<MultiResOracle<'a>, u32> {
        let by_id: HashMap<u32, &TreeNode> = nodes.iter().map(|n| (n.id, n)).collect();
        let mut children: HashMap<u32, Vec<TreeNode>> = HashMap::new();
        for n in nodes {
            if let Some(p) = n.parent {
                children.entry(p).or_default().push(*n);
            }
        }
        let (cr, cc) = (dem.rows - 1, dem.cols - 1);
        let mut paint: Vec<Option<usize>> = vec![None; cr * cc];
        let mut regions: Vec<Region> = Vec::new();
        let mut index: HashMap<Region, usize> = HashMap::new();
        for leaf in nodes.iter().filter(|n| n.leaf) {
            // The path from the zone down to the leaf.
            let mut path = vec![*leaf];
            while let Some(p) = path.last().and_then(|n| n.parent) {
                path.push(**by_id.get(&p).expect("parent in the tree"));
            }
            path.reverse();
            let region = leaf_region(&path, &children, min_level, (cr, cc))?;
            let k = *index.entry(region).or_insert_with(|| {
                regions.push(region);
                regions.len() - 1
            });
            for i in leaf.rows[0]..leaf.rows[1] {
                for j in leaf.cols[0]..leaf.cols[1] {
                    paint[i as usize * cc + j as usize] = Some(k);
                }
            }
        }
        let region_at = |i: i64, j: i64| -> Option<Region> {
            if i < 0 || j < 0 || i >= cr as i64 || j >= cc as i64 {
                return None;
            }
            paint[i as usize * cc + j as usize].map(|k| regions[k])
        };
        let mut tris = Vec::new();
        let mut stitched_cells = 0;
        let present = |i: usize, j: usize| dem.height(i, j).is_some();
        for reg in &regions {
            let s = reg.stride;
            let mut i = reg.rows[0];
            while i < reg.rows[1] {
                let i1 = (i + s).min(reg.rows[1]);
                let mut j = reg.cols[0];
                while j < reg.cols[1] {
                    let j1 = (j + s).min(reg.cols[1]);
                    // Vertices of finer regions strictly inside each side on the region's border.
                    // Sides: (fixed is a row?, fixed, from, to, the neighbouring cells' row or column).
                    let mut sides: Vec<(bool, u32, u32, u32, BTreeSet<u32>)> = vec![
                        (true, i, j, j1, BTreeSet::new()),
                        (true, i1, j, j1, BTreeSet::new()),
                        (false, j, i, i1, BTreeSet::new()),
                        (false, j1, i, i1, BTreeSet::new()),
                    ];
                    let across = [
                        (i == reg.rows[0]).then_some(i as i64 - 1),
                        (i1 == reg.rows[1]).then_some(i1 as i64),
                        (j == reg.cols[0]).then_some(j as i64 - 1),
                        (j1 == reg.cols[1]).then_some(j1 as i64),
                    ];
                    for (side, acr) in sides.iter_mut().zip(across) {
                        let Some(a) = acr else { continue };
                        let (row_side, _, from, to, pts) = side;
                        for k in *from..*to {
                            let nb = if *row_side {
                                region_at(a, k as i64)
                            } else {
                                region_at(k as i64, a)
                            };
                            let Some(nb) = nb else { continue };
                            if nb.stride >= s {
                                continue;
                            }
                            let (lo, hi) = if *row_side {
                                (nb.cols[0], nb.cols[1])
                            } else {
                                (nb.rows[0], nb.rows[1])
                            };
                            let mut p = lo.max(*from).div_ceil(nb.stride) * nb.stride;
                            while p <= hi.min(*to) {
                                if p > *from && p < *to {
                                    pts.insert(p);
                                }
                                p += nb.stride;
                            }
                        }
                    }
                    let (iu, ju, i1u, j1u) = (i as usize, j as usize, i1 as usize, j1 as usize);
                    let stitched = sides.iter().any(|s| !s.4.is_empty())
                        && present(iu, ju)
                        && present(i1u, j1u);
                    let mut add = |v: [V; 3]| {
                        let ok = v.iter().all(|x| match *x {
                            V::Grid(a, b) => present(a, b),
                            V::Mid(a, b, c, d) => present(a, b) && present(c, d),
                        });
                        if ok {
                            let f = v.map(|x| f64_vertex(dem, x));
                            tris.push((v, f, [i, j], *reg));
                        }
                    };
                    if stitched {
                        stitched_cells += 1;
                        let m = V::Mid(iu, ju, i1u, j1u);
                        for (row_side, fixed, from, to, pts) in &sides {
                            let at = |p: u32| {
                                if *row_side {
                                    V::Grid(*fixed as usize, p as usize)
                                } else {
                                    V::Grid(p as usize, *fixed as usize)
                                }
                            };
                            let mut prev = at(*from);
                            for &p in pts.iter().chain(std::iter::once(to)) {
                                add([m, prev, at(p)]);
                                prev = at(p);
                            }
                        }
                    } else {
                        add([V::Grid(iu, ju), V::Grid(iu, j1u), V::Grid(i1u, j1u)]);
                        add([V::Grid(iu, ju), V::Grid(i1u, j1u), V::Grid(i1u, ju)]);
                    }
                    j = j1;
                }
                i = i1;
            }
        }
        Ok(MultiResOracle {
            dem,
            exact: Exact::new(dem),
            tris,
            stitched_cells,
        })
    }

    /// The number of stitched cells (coarse cells fanned to finer neighbours).
    pub fn stitched_cells(&self) -> usize {
        self.stitched_cells
    }

    fn exact_vertex(&self, v: V) -> [BigFloat; 3] {
        let h = |i: usize, j: usize| self.dem.heights[i * self.dem.cols + j];
        match v {
            V::Grid(i, j) => self.exact.vertex(i, j, h(i, j)),
            V::Mid(a, b, c, d) => {
                let p = self.exact.vertex(a, b, h(a, b));
                let q = self.exact.vertex(c, d, h(c, d));
                let half = bf(0.5);
                [0, 1, 2].map(|k| p[k].add(&q[k], P, RM).mul(&half, P, RM))
            }
        }
    }

    /// The nearest hit of `ray` with the surface for `t_min ≤ t ≤ t_max`, or `None`.
    pub fn pick(&self, ray: &RaySpec) -> Option<MultiResHit> {
        let (o, d) = (ray.origin, ray.dir);
        let (t0, t1) = (ray.t_min, ray.t_max_or_inf());
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if dd.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
            || t0.partial_cmp(&t1).is_none_or(|c| c.is_gt())
        {
            return None;
        }
        let mut cands: Vec<(f64, usize)> = self
            .tris
            .iter()
            .enumerate()
            .filter_map(|(k, (_, f, _, _))| ball_entry(f, &o, &d, dd, t0, t1).map(|te| (te, k)))
            .collect();
        cands.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let ob = o.map(bf);
        let db = d.map(bf);
        let (t0b, t1b) = (bf(t0), t1.is_finite().then(|| bf(t1)));
        let mut best: Option<(BigFloat, f64, usize)> = None;
        for &(te, k) in &cands {
            if let Some((_, bt, _)) = &best
                && te > *bt + 1e-9 * bt.abs() + 1e-9
            {
                break;
            }
            let v = self.tris[k].0.map(|x| self.exact_vertex(x));
            let Some(t) = intersect_exact(&ob, &db, &v, &t0b, t1b.as_ref()) else {
                continue;
            };
            if best
                .as_ref()
                .is_none_or(|(bt, ..)| t.cmp(bt).is_some_and(|c| c < 0))
            {
                let tf = to_f64(&t);
                best = Some((t, tf, k));
            }
        }
        best.map(|(t, tf, k)| {
            let (_, _, cell, reg) = self.tris[k];
            MultiResHit {
                t: tf,
                point: [0, 1, 2].map(|a| to_f64(&ob[a].add(&t.mul(&db[a], P, RM), P, RM))),
                cell,
                stride: reg.stride,
                level: reg.level,
            }
        })
    }
}

/// Rule 1 for one leaf, walking its `path` from the zone: the region that answers for it, or the node whose
/// block is needed.
fn leaf_region(
    path: &[TreeNode],
    children: &HashMap<u32, Vec<TreeNode>>,
    min_level: u8,
    (cr, cc): (usize, usize),
) -> Result<Region, u32> {
    let own = |n: &TreeNode| Region {
        rows: n.rows,
        cols: n.cols,
        stride: n.stride,
        level: n.level,
    };
    let on = |n: &TreeNode, s: u32| {
        let fits =
            |r: [u32; 2], last: usize| r[0] % s == 0 && (r[1] % s == 0 || r[1] as usize == last);
        fits(n.rows, cr) && fits(n.cols, cc)
    };
    let mut src: Option<TreeNode> = None;
    for n in path {
        if n.level < min_level {
            if n.leaf {
                return if n.resident { Ok(own(n)) } else { Err(n.id) };
            }
            continue;
        }
        if n.resident {
            if n.leaf {
                return Ok(own(n));
            }
            src = Some(*n);
            continue;
        }
        let Some(a) = src else { return Err(n.id) };
        let kids = children.get(&n.id).map_or(&[][..], |v| &v[..]);
        if !n.leaf && kids.iter().all(|c| on(c, a.stride)) {
            continue;
        }
        if !on(n, a.stride) {
            return Err(n.id);
        }
        return Ok(Region {
            rows: n.rows,
            cols: n.cols,
            stride: a.stride,
            level: a.level,
        });
    }
    unreachable!("a path ends at its leaf")
}

/// A vertex in `f64` (for the filter only).
fn f64_vertex(dem: &Dem, v: V) -> [f64; 3] {
    let g = |i: usize, j: usize| dem.vertex_ecef(i, j).unwrap_or([f64::NAN; 3]);
    match v {
        V::Grid(i, j) => g(i, j),
        V::Mid(a, b, c, d) => {
            let (p, q) = (g(a, b), g(c, d));
            [0, 1, 2].map(|k| 0.5 * (p[k] + q[k]))
        }
    }
}
