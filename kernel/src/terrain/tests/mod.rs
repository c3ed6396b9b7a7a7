//! Terrain kernel tests: closed-form geometry, the traversal against a brute force over every triangle (same
//! triangle test on the same `f64` vertices, so the two must pick the same triangle; the kernel's hit parameter
//! is then refined in double-double, so `t` agrees to the size of the `f64` vertices' rounding, see
//! [`same_hit`]), and typed errors. The independent arbitrary-precision oracle lives in the host crate.

use super::triangle::{Edge, WatertightRay};
use super::windows::WindowBox;
use super::*;
use crate::geodesy::{Ellipsoid, GeodesyError, HeightQuadBounds, sin_cos_deg};
use crate::ray::Ray;
use crate::vec3::V3;
use std::vec::Vec;

/// The kernel's hit `got` and the brute force's `want` (both `(t, cell)`) are the same triangle, and their hit
/// points agree within 1 µm: the brute force's `t` comes from the `f64`-rounded vertices, the kernel's from the
/// refinement (`refine.rs`), which differ by the vertices' rounding (~1e-9 m) amplified at grazing incidence.
#[track_caller]
fn same_hit(
    ray: &Ray<f64>,
    got: Option<(f64, [u32; 2])>,
    want: Option<(f64, [u32; 2])>,
    what: &str,
) {
    let same = match (got, want) {
        (None, None) => true,
        (Some((tg, cg)), Some((tw, cw))) => {
            cg == cw && (tg - tw).abs() * ray.dir().length() <= 1e-6
        }
        _ => false,
    };
    assert!(same, "{what}: kernel {got:?} vs brute {want:?}");
}

/// A DEM as the brute force reads it: the ellipsoid, the grid and the heights (NaN: nodata).
struct Surface {
    e: Ellipsoid<f64>,
    grid: Grid<f64>,
    heights: Vec<f64>,
}

impl Surface {
    fn h(&self, i: u32, j: u32) -> Option<f64> {
        let v = *self
            .heights
            .get((i * self.grid.cols + j) as usize)
            .filter(|_| i < self.grid.rows && j < self.grid.cols)?;
        (!v.is_nan()).then_some(v)
    }

    fn vertex(&self, i: u32, j: u32) -> Option<V3<f64>> {
        let h = self.h(i, j)?;
        let (sl, cl) = sin_cos_deg(self.grid.lat_deg(i));
        let (so, co) = sin_cos_deg(self.grid.lon_deg(j));
        Some(self.e.ecef_from_sin_cos(sl, cl, so, co, h))
    }

    /// Vertex `(i, j)` in pairs, as the contract has it (the refinement's parallels and meridians).
    fn vertex_dd(&self, i: u32, j: u32) -> Option<[crate::dd::Dd<f64>; 3]> {
        let h = self.h(i, j)?;
        let (so, co) = parallel::col_sin_cos_dd(&self.grid, j);
        Some(parallel::row_parallel(&self.e, &self.grid, i).ecef(so, co, h))
    }

    /// Brute force over every triangle with the same watertight test: the nearest `t` and its cell.
    fn brute(&self, ray: &Ray<f64>) -> Option<(f64, [u32; 2])> {
        let w = WatertightRay::new(ray.origin(), ray.dir()).unwrap();
        let mut best: Option<(f64, [u32; 2])> = None;
        for i in 0..self.grid.rows - 1 {
            for j in 0..self.grid.cols - 1 {
                let v = [
                    self.vertex(i, j),
                    self.vertex(i, j + 1),
                    self.vertex(i + 1, j + 1),
                    self.vertex(i + 1, j),
                ];
                // The third vertex of the triangle across each edge (`None` off the grid): an edge without
                // one is on the border of the surface.
                let (lr, lc) = (self.grid.rows - 1, self.grid.cols - 1);
                let at = |ok: bool, i: u32, j: u32| if ok { self.vertex(i, j) } else { None };
                let across = [
                    [
                        at(j + 1 < lc, i + 1, j + 2),
                        v[3],
                        at(i > 0, i.wrapping_sub(1), j),
                    ],
                    [
                        at(i + 1 < lr, i + 2, j + 1),
                        at(j > 0, i, j.wrapping_sub(1)),
                        v[1],
                    ],
                ];
                let corners = [(i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j)];
                for ((tri, across), k) in [[v[0], v[1], v[2]], [v[0], v[2], v[3]]]
                    .into_iter()
                    .zip(across)
                    .zip([[0, 1, 2], [0, 2, 3]])
                {
                    let [Some(a), Some(b), Some(c)] = tri else {
                        continue;
                    };
                    let hi = best.map_or(ray.t_max(), |x| x.0);
                    // A border edge's side from the exact vertices (triangle.rs, "Edges on the border of
                    // the surface").
                    let edges = |_near: [bool; 3]| {
                        let exact = k.map(|q| corners[q]).map(|(ii, jj)| self.vertex_dd(ii, jj));
                        let inside = match exact {
                            [Some(p), Some(q), Some(r)] => {
                                triangle::exact_edge_sides(ray.origin(), ray.dir(), &[p, q, r])
                            }
                            _ => None,
                        };
                        [0, 1, 2].map(|e| Edge::of(across[e].is_none(), inside.map(|s| s[e])))
                    };
                    if let Some((t, _)) = w.intersect_with_border(a, b, c, ray.t_min(), hi, edges) {
                        if best.is_none_or(|x| t < x.0) {
                            best = Some((t, [i, j]));
                        }
                    }
                }
            }
        }
        best
    }
}

/// The storage the tests pick on: the kernel's builder's ([`build::SliceStorage`]).
pub(super) type Storage<'a> = build::SliceStorage<'a, f64, f64, Option<boxes::NodeBox>>;

/// A [`Surface`] and the kernel's builder's buffers over it, which [`TestDem::storage`] serves: the node
/// records of [`build::build_tree`] (leaves of `block × block` cells under the builder's zones) and, if asked
/// for, node boxes.
pub(super) struct TestDem {
    surface: Surface,
    nodes: Vec<build::NodeRecord<f64, Option<boxes::NodeBox>>>,
    tree: build::Tree,
    /// The leaves' window boxes, with the node boxes ([`build::build_windows`]).
    windows: Vec<WindowBox>,
}

impl TestDem {
    /// A DEM without node boxes.
    pub(super) fn new(grid: Grid<f64>, heights: Vec<f64>, block: u32) -> Self {
        Self::build(grid, heights, block, None)
    }

    /// A DEM whose every node has its box ([`build::build_boxes_sharing`]): a child's box in the frame of its
    /// parent's box when `share(its id, its level)`, else in its parent's own frame (a zone's in the grid's).
    fn with_boxes(
        grid: Grid<f64>,
        heights: Vec<f64>,
        block: u32,
        share: fn(u32, u8) -> bool,
    ) -> Self {
        Self::build(grid, heights, block, Some(share))
    }

    /// The one place the tests build a tree and boxes with the kernel's builder.
    fn build(
        grid: Grid<f64>,
        heights: Vec<f64>,
        block: u32,
        share: Option<fn(u32, u8) -> bool>,
    ) -> Self {
        let surface = Surface {
            e: Ellipsoid::wgs84(),
            grid,
            heights,
        };
        let mut nodes =
            std::vec![build::NodeRecord::EMPTY; build::node_slots(grid.rows, grid.cols, block)];
        let tree = build::build_tree(&surface.heights, &grid, block, &mut nodes).unwrap();
        let mut windows = Vec::new();
        if let Some(share) = share {
            let (e, hs) = (&surface.e, &surface.heights);
            let levels: Vec<u8> = nodes.iter().map(|n| n.level).collect();
            let level = |id: NodeId| levels.get(id.0 as usize).copied().unwrap_or(0);
            build::build_boxes_sharing(e, &grid, hs, tree, None, &mut nodes, |id, _| {
                share(id.0, level(id))
            })
            .unwrap();
            windows = std::vec![WindowBox::EMPTY; build::window_slots(grid.rows, grid.cols, block)];
            build::build_windows(e, &grid, hs, tree, None, &nodes, &mut windows).unwrap();
        }
        TestDem {
            surface,
            nodes,
            tree,
            windows,
        }
    }

    /// The storage over the buffers (with the leaves' windows, if built).
    pub(super) fn storage(&self) -> Storage<'_> {
        let s = &self.surface;
        let parts = build::Parts::new(&s.heights[..], &self.nodes[..]).with_windows(&self.windows);
        build::TreeStorage::with_buffers(s.e, s.grid, self.tree, parts).unwrap()
    }

    /// The storage without the leaves' windows.
    pub(super) fn storage_without_windows(&self) -> Storage<'_> {
        let s = &self.surface;
        build::SliceStorage::new(s.e, s.grid, &s.heights, &self.nodes, self.tree).unwrap()
    }
}

/// A storage of a grid alone, without zones: the builder refuses an invalid grid
/// ([`build::BuildError::InvalidGrid`]), so the picker's own check of the grid is tested over this.
struct GridOnly(Grid<f64>);

impl TerrainStorage<f64> for GridOnly {
    fn ellipsoid(&self) -> Ellipsoid<f64> {
        Ellipsoid::wgs84()
    }
    fn grid(&self) -> Grid<f64> {
        self.0
    }
    fn zone_count(&self) -> usize {
        0
    }
    fn zone(&self, _: usize) -> Option<NodeId> {
        None
    }
    fn node(&self, _: NodeId) -> Option<Node<f64>> {
        None
    }
    fn height(&self, _: u32, _: u32) -> Option<f64> {
        None
    }
}

impl TerrainCaches<f64> for GridOnly {}

/// A storage with [`TerrainCaches::cached_bounds`], which the builder does not provide (its node boxes stand
/// in for it): every node's [`quad_bounds`] (its own cells', stride 1), by node id, for the first `slots` ids.
struct CachedBounds<S> {
    inner: S,
    cache: Vec<Option<HeightQuadBounds<f64>>>,
}

impl<S: TerrainStorage<f64>> CachedBounds<S> {
    fn new(inner: S, slots: usize) -> Self {
        let (e, g) = (inner.ellipsoid(), inner.grid());
        let cache = (0..slots as u32)
            .map(|k| quad_bounds(&e, &g, &inner.node(NodeId(k)).unwrap()).unwrap())
            .collect();
        CachedBounds { inner, cache }
    }
}

impl<S: TerrainStorage<f64>> TerrainStorage<f64> for CachedBounds<S> {
    fn ellipsoid(&self) -> Ellipsoid<f64> {
        self.inner.ellipsoid()
    }
    fn grid(&self) -> Grid<f64> {
        self.inner.grid()
    }
    fn zone_count(&self) -> usize {
        self.inner.zone_count()
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        self.inner.zone(k)
    }
    fn node(&self, id: NodeId) -> Option<Node<f64>> {
        self.inner.node(id)
    }
    fn height(&self, i: u32, j: u32) -> Option<f64> {
        self.inner.height(i, j)
    }
    fn is_resident(&self, id: NodeId) -> bool {
        self.inner.is_resident(id)
    }
    fn block_stride(&self, id: NodeId) -> u32 {
        self.inner.block_stride(id)
    }
}

impl<S: TerrainStorage<f64>> TerrainCaches<f64> for CachedBounds<S> {
    fn cached_bounds(&self, id: NodeId) -> Option<HeightQuadBounds<f64>> {
        self.cache.get(id.0 as usize).copied().flatten()
    }
}

pub(super) fn grid(
    lat0_deg: f64,
    lon0_deg: f64,
    dlat_deg: f64,
    dlon_deg: f64,
    rows: u32,
    cols: u32,
) -> Grid<f64> {
    Grid {
        lat0_deg,
        lon0_deg,
        dlat_deg,
        dlon_deg,
        rows,
        cols,
    }
}

/// Where `ray` meets the plane through the vertices `(a, b, c)` (in pairs), computed in pairs: `t = n·(a − o) /
/// n·d` with `n = (b − a) × (c − a)`. The refinement's answer, found independently (`refine.rs` takes one step
/// from the traversal's `t` with a scalar normal).
fn dd_plane_t(ray: &Ray<f64>, [a, b, c]: [[crate::dd::Dd<f64>; 3]; 3]) -> f64 {
    use crate::dd::Dd;
    let dd = |x: f64| Dd::from(x);
    let sub = |x: [Dd<f64>; 3], y: [Dd<f64>; 3]| [0, 1, 2].map(|k| x[k].minus(y[k]));
    let (u, v) = (sub(b, a), sub(c, a));
    let n = [
        u[1].times(v[2]).minus(u[2].times(v[1])),
        u[2].times(v[0]).minus(u[0].times(v[2])),
        u[0].times(v[1]).minus(u[1].times(v[0])),
    ];
    let (o, d) = (ray.origin(), ray.dir());
    let ao = sub(a, [dd(o.x), dd(o.y), dd(o.z)]);
    let dot = |x: [Dd<f64>; 3], y: [Dd<f64>; 3]| {
        x[0].times(y[0])
            .plus(x[1].times(y[1]))
            .plus(x[2].times(y[2]))
    };
    dot(n, ao).over(dot(n, [dd(d.x), dd(d.y), dd(d.z)])).value()
}

/// Of a cell's two triangles (vertices in pairs), where `ray` meets the plane of the one whose [`dd_plane_t`] is
/// nearest to `t`: the plane a refined hit at `t` lies on.
fn nearest_plane_t(ray: &Ray<f64>, t: f64, tris: [[[crate::dd::Dd<f64>; 3]; 3]; 2]) -> f64 {
    tris.map(|tri| dd_plane_t(ray, tri))
        .into_iter()
        .min_by(|a, b| (a - t).abs().total_cmp(&(b - t).abs()))
        .unwrap_or(f64::NAN)
}

/// A small deterministic generator (no external crates in the kernel's tests).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The ray from geodetic `from` to geodetic `to` (latitude and longitude in degrees, height in metres).
fn ray_between(e: &Ellipsoid<f64>, from: [f64; 3], to: [f64; 3]) -> Ray<f64> {
    let [a, b] = [from, to].map(|[lat, lon, h]| e.geodetic_deg_to_ecef(lat, lon, h));
    Ray::new(a, b.minus(a)).unwrap()
}

/// A pick and its work ([`PickStats`]): quads visited, triangle pairs visited, triangles tested.
fn pick_counted<S: TerrainCaches<f64>>(
    p: &Picker<'_, f64, S>,
    ray: &Ray<f64>,
) -> (Option<Hit<f64>>, [u32; 3]) {
    let mut st = PickStats::default();
    let hit = p.pick_with_stats(ray, &mut st).unwrap();
    let work = [
        st.quads_visited,
        st.triangle_pairs_visited,
        st.triangles_tested,
    ];
    (hit, work)
}

/// A global 5.625° grid from pole to pole (33 × 65 vertices) whose last column repeats the first (longitudes run
/// to +180), heights −3 km to 6 km from a fixed sequence, one height per pole; and the sequence, to go on with.
fn global_relief() -> (Grid<f64>, Vec<f64>, Lcg) {
    let (rows, cols) = (33, 65);
    let g = grid(-90.0, -180.0, 5.625, 5.625, rows as u32, cols as u32);
    let mut r = Lcg(2024);
    let mut hs: Vec<f64> = (0..rows * cols)
        .map(|_| -3000.0 + 9000.0 * r.next())
        .collect();
    for i in 0..rows {
        hs[i * cols + cols - 1] = hs[i * cols]; // the repeated column
    }
    for j in 0..cols {
        hs[j] = hs[0]; // one height per pole
        hs[(rows - 1) * cols + j] = hs[(rows - 1) * cols];
    }
    (g, hs, r)
}

fn radial_ray(e: &Ellipsoid<f64>, lat: f64, lon: f64, h0: f64) -> Ray<f64> {
    let top = e.geodetic_deg_to_ecef(lat, lon, h0);
    let n = e.normal_rad(lat.to_radians(), lon.to_radians());
    Ray::new(top, n.negated()).unwrap()
}

mod border;
mod builder;
mod global;
mod multires;
mod picks;
mod refinement;
mod rough;
mod rows;
mod windows;
mod work;
