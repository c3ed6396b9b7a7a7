//! Terrain kernel tests: closed-form geometry, the traversal against a brute force over every triangle (same
//! triangle test on the same `f64` vertices, so the two must pick the same triangle; the kernel's hit parameter
//! is then refined in double-double, so `t` agrees to the size of the `f64` vertices' rounding, see
//! [`same_hit`]), and typed errors. The independent arbitrary-precision oracle lives in the host crate.

use super::*;
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
                for (tri, across) in [[v[0], v[1], v[2]], [v[0], v[2], v[3]]]
                    .into_iter()
                    .zip(across)
                {
                    let [Some(a), Some(b), Some(c)] = tri else {
                        continue;
                    };
                    let hi = best.map_or(ray.t_max(), |x| x.0);
                    let border = || across.map(|x| x.is_none());
                    if let Some((t, _)) = w.intersect_with_border(a, b, c, ray.t_min(), hi, border)
                    {
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
type Storage<'a> = build::SliceStorage<'a, f64, f64, Option<boxes::NodeBox>>;

/// A [`Surface`] and the kernel's builder's buffers over it, which [`TestDem::storage`] serves: the node
/// records of [`build::build_tree`] (leaves of `block × block` cells under the builder's zones) and, if asked
/// for, node boxes.
struct TestDem {
    surface: Surface,
    nodes: Vec<build::NodeRecord<f64, Option<boxes::NodeBox>>>,
    tree: build::Tree,
}

impl TestDem {
    /// A DEM without node boxes.
    fn new(grid: Grid<f64>, heights: Vec<f64>, block: u32) -> Self {
        Self::build(grid, heights, block, None)
    }

    /// A DEM whose every node has its box ([`build::build_boxes_sharing`]): a child's box in the frame of its
    /// parent's box when `share(its id)`, else in its parent's own frame (a zone's in the grid's).
    fn with_boxes(grid: Grid<f64>, heights: Vec<f64>, block: u32, share: fn(u32) -> bool) -> Self {
        Self::build(grid, heights, block, Some(share))
    }

    /// The one place the tests build a tree and boxes with the kernel's builder.
    fn build(
        grid: Grid<f64>,
        heights: Vec<f64>,
        block: u32,
        share: Option<fn(u32) -> bool>,
    ) -> Self {
        let surface = Surface {
            e: Ellipsoid::wgs84(),
            grid,
            heights,
        };
        let mut nodes =
            std::vec![build::NodeRecord::EMPTY; build::node_slots(grid.rows, grid.cols, block)];
        let tree = build::build_tree(&surface.heights, &grid, block, &mut nodes).unwrap();
        if let Some(share) = share {
            let (e, hs) = (&surface.e, &surface.heights);
            build::build_boxes_sharing(e, &grid, hs, tree, None, &mut nodes, |id, _| share(id.0))
                .unwrap();
        }
        TestDem {
            surface,
            nodes,
            tree,
        }
    }

    /// The storage over the buffers.
    fn storage(&self) -> Storage<'_> {
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

/// The builder's storage with [`TerrainStorage::cached_bounds`], which the builder does not provide (its
/// node boxes stand in for it): every node's [`quad_bounds`], by node id.
struct CachedBounds<'a> {
    inner: Storage<'a>,
    cache: Vec<Option<HeightQuadBounds<f64>>>,
}

impl<'a> CachedBounds<'a> {
    fn new(inner: Storage<'a>) -> Self {
        let (e, g) = (inner.ellipsoid(), inner.grid());
        let cache = (0..inner.tree().slots() as u32)
            .map(|k| quad_bounds(&e, &g, &inner.node(NodeId(k)).unwrap()).unwrap())
            .collect();
        CachedBounds { inner, cache }
    }
}

impl TerrainStorage<f64> for CachedBounds<'_> {
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
    fn cached_bounds(&self, id: NodeId) -> Option<HeightQuadBounds<f64>> {
        self.cache.get(id.0 as usize).copied().flatten()
    }
}

fn grid(
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

fn radial_ray(e: &Ellipsoid<f64>, lat: f64, lon: f64, h0: f64) -> Ray<f64> {
    let top = e.geodetic_deg_to_ecef(lat, lon, h0);
    let n = e.normal_rad(lat.to_radians(), lon.to_radians());
    Ray::new(top, n.negated()).unwrap()
}

#[test]
#[cfg_attr(miri, ignore)] // many picks: minutes under Miri; the light tests below cover the same code
fn flat_terrain_at_h0_hit_by_radial_rays_at_vertices() {
    let g = grid(45.0, 7.0, 0.01, 0.01, 9, 9);
    let dem = TestDem::new(g, std::vec![0.0; 81], 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    for i in 0..9 {
        for j in 0..9 {
            let (lat, lon) = (g.lat_deg(i), g.lon_deg(j));
            let hit = p
                .pick(&radial_ray(&dem.surface.e, lat, lon, 1000.0))
                .unwrap();
            let ray = radial_ray(&dem.surface.e, lat, lon, 1000.0);
            let what = std::format!("{i},{j}");
            same_hit(
                &ray,
                hit.map(|h| (h.t, h.cell)),
                dem.surface.brute(&ray),
                &what,
            );
            assert!(hit.is_some(), "{i},{j} missed");
            let hit = hit.unwrap();
            // A vertex at h = 0 lies 1000 m down the normal.
            assert!((hit.t - 1000.0).abs() < 1e-6, "{i},{j}: {}", hit.t);
            assert!(
                hit.h.abs() < 1e-6
                    && (hit.lat_deg - lat).abs() < 1e-9
                    && (hit.lon_deg - lon).abs() < 1e-9
            );
        }
    }
    // Cell centres: the chord plane dips below the ellipsoid by less than the sagitta (≈ D²/(8R) ≈ 0.02 m).
    let hit = p
        .pick(&radial_ray(&dem.surface.e, 45.035, 7.045, 1000.0))
        .unwrap()
        .unwrap();
    assert!(hit.h < 0.0 && hit.h > -0.05, "{}", hit.h);
    assert_eq!(hit.cell, [3, 4]);
}

#[test]
fn single_raised_vertex_peak_and_its_slopes() {
    let g = grid(-33.0, 151.0, -0.001, 0.001, 5, 5);
    let mut hs = std::vec![0.0; 25];
    hs[2 * 5 + 2] = 300.0;
    let dem = TestDem::new(g, hs, 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let (lat, lon) = (g.lat_deg(2), g.lon_deg(2));
    let hit = p
        .pick(&radial_ray(&dem.surface.e, lat, lon, 2000.0))
        .unwrap()
        .unwrap();
    assert!((hit.t - 1700.0).abs() < 1e-6 && (hit.h - 300.0).abs() < 1e-6);
    // Halfway to a neighbouring vertex along a grid line (an edge of the triangulation), the edge is straight:
    // the hit height is close to 150 m (the chord of the peak's edge, less the tiny curvature term).
    let hit = p
        .pick(&radial_ray(&dem.surface.e, lat, lon + 0.0005, 2000.0))
        .unwrap()
        .unwrap();
    assert!((hit.h - 150.0).abs() < 0.5, "{}", hit.h);
    let ray = radial_ray(&dem.surface.e, lat, lon + 0.0005, 2000.0);
    same_hit(
        &ray,
        Some((hit.t, hit.cell)),
        dem.surface.brute(&ray),
        "peak slope",
    );
}

#[test]
#[cfg_attr(miri, ignore)] // many picks: minutes under Miri; the light tests below cover the same code
fn ray_through_the_pole_row() {
    // A polar cap 80°..90° with 10° × 30° cells: the last row is the pole, where all vertices coincide.
    let g = grid(80.0, -180.0, 5.0, 30.0, 3, 13);
    let mut r = Lcg(7);
    let hs: Vec<f64> = (0..39)
        .map(|k| {
            if k >= 26 {
                250.0
            } else {
                100.0 + 900.0 * r.next()
            }
        })
        .collect();
    let dem = TestDem::new(g, hs, 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    // Straight down the z axis onto the pole vertex.
    let e = dem.surface.e;
    let ray = Ray::new([0.0, 0.0, e.b() + 10_000.0], [0.0, 0.0, -1.0]).unwrap();
    let hit = p.pick(&ray).unwrap().unwrap();
    assert!((hit.t - (10_000.0 - 250.0)).abs() < 1e-6, "{}", hit.t);
    assert!((hit.lat_deg - 90.0).abs() < 1e-9);
    // Rays across the pole, horizontally and obliquely, agree with the brute force.
    for k in 0..40 {
        let az = k as f64 * 0.157;
        let o = [
            -700_000.0 * az.cos(),
            -700_000.0 * az.sin(),
            e.b() - 20_000.0 + 1000.0 * k as f64,
        ];
        let d = [az.cos(), az.sin(), -0.02 + 0.001 * k as f64];
        let ray = Ray::new(o, d).unwrap();
        let got = p.pick(&ray).unwrap().map(|h| (h.t, h.cell));
        same_hit(
            &ray,
            got,
            dem.surface.brute(&ray),
            &std::format!("azimuth {az}"),
        );
    }
}

#[test]
fn steep_ray_across_a_latitude_border_at_80_degrees_finds_the_bulging_triangle() {
    // 1° cells, one cell per leaf: the quad border at 80° is a cone, the triangles below it are chords that
    // bulge north of it (the containment problem). A steep ray from the north aims at the bulge.
    let g = grid(78.0, 10.0, 1.0, 1.0, 5, 4);
    let dem = TestDem::new(g, std::vec![0.0; 20], 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    // The midpoint of the border edge V(2,1)–V(2,2) (lat 80°, lon 11°..12°) and a point just south of it on the
    // southern cell's triangle.
    let a = dem.surface.vertex(2, 1).unwrap();
    let b = dem.surface.vertex(2, 2).unwrap();
    let c = dem.surface.vertex(1, 2).unwrap();
    let target = a
        .scaled(0.49995)
        .plus(b.scaled(0.49995))
        .plus(c.scaled(0.0001));
    let geo = e.ecef_to_geodetic(target);
    assert!(
        geo.lat_rad.to_degrees() > 80.0,
        "the target is north of the 80° cone"
    );
    // A steep ray coming from the north-east, above the northern cells.
    let dir = V3::new(-0.3, 0.05, -1.0);
    let origin = target.add_scaled(-20_000.0, dir);
    let ray = Ray::new(origin, dir).unwrap();
    let hit = p.pick(&ray).unwrap().unwrap();
    same_hit(
        &ray,
        Some((hit.t, hit.cell)),
        dem.surface.brute(&ray),
        "steep ray",
    );
    assert_eq!(
        hit.cell[0], 1,
        "the triangle belongs to the southern row of cells"
    );
    assert!((hit.t - 20_000.0).abs() < 1e-6);
}

#[test]
fn nodata_vertex_removes_its_triangles() {
    let g = grid(0.0, 0.0, 0.01, 0.01, 3, 3);
    let mut hs = std::vec![0.0; 9];
    hs[4] = f64::NAN;
    let dem = TestDem::new(g, hs, 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    // Every triangle touches the centre vertex: nothing to hit.
    assert_eq!(
        p.pick(&radial_ray(&dem.surface.e, 0.005, 0.005, 100.0))
            .unwrap(),
        None
    );
}

#[test]
#[cfg_attr(miri, ignore)] // many picks: minutes under Miri; the light tests below cover the same code
fn line_of_sight_over_and_through_a_ridge() {
    let g = grid(10.0, 10.0, 0.001, 0.001, 3, 5);
    let hs = std::vec![
        0.0, 0.0, 800.0, 0.0, 0.0, 0.0, 0.0, 800.0, 0.0, 0.0, 0.0, 0.0, 800.0, 0.0, 0.0
    ];
    let dem = TestDem::new(g, hs, 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let west = e.geodetic_deg_to_ecef(10.001, 10.0, 100.0);
    let east = e.geodetic_deg_to_ecef(10.001, 10.004, 100.0);
    assert!(!p.line_of_sight(west, east).unwrap());
    let w_hi = e.geodetic_deg_to_ecef(10.001, 10.0, 1000.0);
    let e_hi = e.geodetic_deg_to_ecef(10.001, 10.004, 1000.0);
    assert!(p.line_of_sight(w_hi, e_hi).unwrap());
}

#[test]
fn pick_statistics_count_the_work() {
    // One-cell leaves two levels below the builder's zones (16 × 16 cells: 8 × 8, then 4 × 4 zones).
    let g = grid(0.0, 0.0, 0.01, 0.01, 17, 17);
    let dem = TestDem::new(g, std::vec![0.0; 289], 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let mut st = PickStats::default();
    let hit = p
        .pick_with_stats(&radial_ray(&dem.surface.e, 0.035, 0.045, 100.0), &mut st)
        .unwrap();
    assert!(hit.is_some());
    assert!(st.quads_visited >= 3, "{st:?}");
    assert!(
        st.triangle_pairs_visited >= 1 && st.triangle_pairs_visited <= 4,
        "{st:?}"
    );
    assert!(
        st.triangles_tested >= 1 && st.triangles_tested <= 8,
        "{st:?}"
    );
}

#[test]
fn typed_errors() {
    let bad = GridOnly(grid(0.0, 0.0, 0.0, 0.01, 3, 3));
    assert_eq!(
        Picker::<'_, f64, GridOnly>::new(&bad).err(),
        Some(TerrainError::InvalidGrid)
    );
    let deep = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 3, 3), std::vec![-7.0e6; 9], 2);
    assert_eq!(
        Picker::<'_, f64, Storage<'_>>::new(&deep.storage()).err(),
        Some(TerrainError::Geodesy(GeodesyError::HeightTooLow))
    );
    // The builder's records with one broken by hand: a child as large as its parent, under the ray's zone.
    let mut malformed = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 9, 9), std::vec![0.0; 81], 1);
    let zone = malformed
        .nodes
        .iter()
        .copied()
        .find(|n| {
            n.level == 0 && n.rows[0] <= 3 && 3 < n.rows[1] && n.cols[0] <= 3 && 3 < n.cols[1]
        })
        .unwrap();
    let child = &mut malformed.nodes[zone.kids[0] as usize];
    (child.rows, child.cols) = (zone.rows, zone.cols);
    let s = malformed.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    assert_eq!(
        p.pick(&radial_ray(&malformed.surface.e, 0.03, 0.03, 100.0)),
        Err(TerrainError::MalformedTree)
    );
    let ok = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 17, 17), std::vec![0.0; 289], 1);
    let s = ok.storage();
    let tiny: Picker<'_, f64, Storage<'_>, 2> = Picker::new(&s).unwrap();
    assert_eq!(
        tiny.pick(&radial_ray(&ok.surface.e, 0.03, 0.03, 100.0)),
        Err(TerrainError::StackFull)
    );
    let zones = TestDem::new(grid(0.0, 0.0, 0.01, 0.01, 9, 9), std::vec![0.0; 81], 2);
    assert_eq!(
        Picker::<'_, f64, Storage<'_>, 64, 8>::new(&zones.storage()).err(),
        Some(TerrainError::TooManyZones)
    );
}

#[test]
fn grid_of_80_degree_cells_is_triangle_too_large_not_height_too_low() {
    // 3 × 3 vertices 10° × 80° apart at the equator, flat at 0 m: the cells' diagonals (about 8 800 km) are
    // beyond the chord bound, and the heights are fine.
    let dem = TestDem::new(grid(-10.0, 0.0, 10.0, 80.0, 3, 3), std::vec![0.0; 9], 1);
    let e = dem.surface.e;
    let got = Picker::<'_, f64, Storage<'_>>::new(&dem.storage())
        .and_then(|p| p.pick(&radial_ray(&e, 0.0, 40.0, 1000.0)))
        .err();
    assert_eq!(
        got,
        Some(TerrainError::Geodesy(GeodesyError::TriangleTooLarge))
    );
    let text = std::format!("{}", got.unwrap());
    assert!(
        text.contains("70 degrees") && !text.contains("b^2/a (no"),
        "{text}"
    );
    // 60° cells are within the bound.
    let ok = TestDem::new(grid(-10.0, 0.0, 10.0, 60.0, 3, 3), std::vec![0.0; 9], 1);
    let s = ok.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    assert!(
        p.pick(&radial_ray(&e, 0.0, 40.0, 1000.0))
            .unwrap()
            .is_some()
    );
}

#[test]
fn grid_with_dlon_180_is_an_invalid_grid_whose_message_states_the_rules() {
    // The builder refuses the grid too (BuildError::InvalidGrid): the picker checks it over a bare grid.
    let dem = GridOnly(grid(-10.0, 0.0, 10.0, 180.0, 3, 2));
    let err = Picker::<'_, f64, GridOnly>::new(&dem).err();
    assert_eq!(err, Some(TerrainError::InvalidGrid));
    let text = std::format!("{}", err.unwrap());
    assert!(text.contains("0 < dlon < 180"), "{text}");
}

#[test]
fn ray_missing_everything_and_ray_starting_below_ground() {
    let g = grid(0.0, 0.0, 0.01, 0.01, 5, 5);
    let dem = TestDem::new(g, std::vec![100.0; 25], 2);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let up = radial_ray(&e, 0.02, 0.02, 1000.0);
    let away = Ray::new(up.origin(), up.dir().negated()).unwrap();
    assert_eq!(p.pick(&away).unwrap(), None);
    // From 10 m below the surface, straight up: hits the terrain from underneath at t = 10.
    let below = e.geodetic_deg_to_ecef(0.02, 0.02, 90.0);
    let n = e.normal_rad(0.02_f64.to_radians(), 0.02_f64.to_radians());
    let hit = p.pick(&Ray::new(below, n).unwrap()).unwrap().unwrap();
    assert!((hit.t - 10.0).abs() < 1e-6);
}

/// Fewest hits of the 300 rays per grid in `random_rays_agree_with_brute_force_on_rough_terrain` (measured: 217,
/// 238 and 255 for the three grids).
const HITS_ROUGH: usize = 200;

#[test]
#[cfg_attr(miri, ignore)]
fn random_rays_agree_with_brute_force_on_rough_terrain() {
    let mut r = Lcg(42);
    for (lat0_deg, dlat_deg, lon0_deg) in
        [(-30.0, 0.5, 170.0), (60.0, 1.0, -20.0), (-88.0, 1.0, 0.0)]
    {
        let g = grid(lat0_deg, lon0_deg, dlat_deg, 0.5, 12, 14);
        let hs: Vec<f64> = (0..12 * 14)
            .map(|_| {
                let u = r.next();
                if u < 0.03 {
                    f64::NAN
                } else {
                    -400.0 + 9000.0 * u * u
                }
            })
            .collect();
        // Spheroidal volumes, then node boxes, on the same rays.
        let plain = TestDem::new(g, hs.clone(), 2);
        // Boxes in their parents' frames, in one frame for the whole grid, and a mix of the two.
        let boxed = TestDem::with_boxes(g, hs.clone(), 2, |_| false);
        let one_frame = TestDem::with_boxes(g, hs.clone(), 2, |_| true);
        let mixed = TestDem::with_boxes(g, hs, 2, |k| k % 3 != 1);
        assert!(
            mixed
                .nodes
                .iter()
                .filter_map(|n| n.bbox)
                .any(|b| b.shared_frame)
        );
        let e = plain.surface.e;
        let rays: Vec<Ray<f64>> = (0..300)
            .map(|_| {
                let lat = lat0_deg + dlat_deg * 11.0 * r.next();
                let lon = lon0_deg + 0.5 * 13.0 * r.next();
                let target = e.geodetic_deg_to_ecef(lat, lon, 3000.0 * r.next());
                let dir = V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5);
                let dist = 100.0 + 3.0e5 * r.next() * r.next();
                Ray::new(target.add_scaled(-dist, dir), dir).unwrap()
            })
            .collect();
        for (name, dem) in [
            ("volumes", &plain),
            ("boxes", &boxed),
            ("boxes in one frame", &one_frame),
            ("boxes in mixed frames", &mixed),
        ] {
            let s = dem.storage();
            let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
            let mut hits = 0;
            for (k, ray) in rays.iter().enumerate() {
                let got = p.pick(ray).unwrap().map(|h| (h.t, h.cell));
                let what = std::format!("grid at {lat0_deg}, {name}, ray {k}");
                same_hit(ray, got, dem.surface.brute(ray), &what);
                hits += usize::from(got.is_some());
            }
            // Agreeing on misses alone proves nothing: most rays must hit.
            assert!(
                hits >= HITS_ROUGH,
                "grid at {lat0_deg}, {name}: {hits} hits of 300"
            );
        }
    }
}

#[test]
fn node_boxes_stand_in_for_the_volumes() {
    // A light version of the test above (runs under Miri): a few rays at a ridge, boxes from all vertices.
    let g = grid(-45.0, 30.0, 0.01, 0.01, 9, 9);
    let hs: Vec<f64> = (0..81)
        .map(|k| if k % 9 == 4 { 1500.0 } else { 200.0 })
        .collect();
    // Every other node's box in the frame of its parent's box (one-cell leaves: every zone has children).
    let dem = TestDem::with_boxes(g, hs, 1, |k| k % 2 == 0);
    assert!(dem.nodes.iter().all(|n| n.bbox.is_some()));
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    for k in 0..6 {
        let lat = -45.0 + 0.0125 * k as f64 + 0.001;
        let ray = radial_ray(&e, lat, 30.04, 4000.0);
        let mut stats = PickStats::default();
        let got = p
            .pick_with_stats(&ray, &mut stats)
            .unwrap()
            .map(|h| (h.t, h.cell));
        assert!(got.is_some() && stats.triangles_tested > 0, "ray {k}");
        same_hit(&ray, got, dem.surface.brute(&ray), &std::format!("ray {k}"));
        // Grazing along the ridge from 50 km away.
        let target = e.geodetic_deg_to_ecef(lat, 30.04, 1400.0);
        let east = V3::new(
            -(30.0_f64.to_radians().sin()),
            30.0_f64.to_radians().cos(),
            0.0,
        );
        let ray = Ray::new(target.add_scaled(-5.0e4, east), east).unwrap();
        let got = p.pick(&ray).unwrap().map(|h| (h.t, h.cell));
        same_hit(
            &ray,
            got,
            dem.surface.brute(&ray),
            &std::format!("grazing ray {k}"),
        );
    }
}

/// Fewest hits of the 200 rays per grid in `steep_rays_aimed_at_latitude_borders_from_60_to_89_degrees`
/// (measured: 198 to 200).
const HITS_STEEP: usize = 190;

#[test]
#[cfg_attr(miri, ignore)]
fn steep_rays_aimed_at_latitude_borders_from_60_to_89_degrees() {
    // Coarse 1° × 2° cells, one cell per leaf, so every row border is a quad border with a cone wall; rays aimed
    // at points just beside the border edges' midpoints (where the chords bulge across the cone), steeply.
    let mut r = Lcg(99);
    for (lat0_deg, dlat_deg) in [
        (60.0, 1.0),
        (80.0, 1.0),
        (89.0, -1.0),
        (-61.0, -1.0),
        (-85.0, 1.0),
    ] {
        let g = grid(lat0_deg, 30.0, dlat_deg, 2.0, 6, 6);
        let rows = g.rows;
        let hs: Vec<f64> = (0..36).map(|_| 2000.0 * r.next()).collect();
        let dem = TestDem::new(g, hs, 1);
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        let (mut tried, mut hits) = (0, 0);
        for k in 0..200 {
            let i = 1 + (k % (rows - 2));
            let j = (k / 3) % 5;
            let (Some(a), Some(b)) = (dem.surface.vertex(i, j), dem.surface.vertex(i, j + 1))
            else {
                continue;
            };
            let w = 0.3 + 0.4 * r.next();
            let target = a.scaled(w).plus(b.scaled(1.0 - w));
            let dir = V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5);
            let ray = Ray::new(target.add_scaled(-30_000.0 - 1e5 * r.next(), dir), dir).unwrap();
            let got = p.pick(&ray).unwrap().map(|h| (h.t, h.cell));
            same_hit(
                &ray,
                got,
                dem.surface.brute(&ray),
                &std::format!("lat0_deg {lat0_deg}, ray {k}"),
            );
            tried += 1;
            hits += usize::from(got.is_some());
        }
        // Agreeing on misses alone proves nothing: most rays must hit.
        assert!(
            tried >= 150 && hits >= HITS_STEEP,
            "lat0_deg {lat0_deg}: {hits} hits of {tried}"
        );
    }
}

#[test]
fn ray_from_below_hits_the_chord_dip_of_a_polar_triangle_below_its_lowest_vertex() {
    // Flat h = 0 polar cap of 5° × 30° cells: the pole triangles are chords ~500 km long whose centroids dip
    // kilometres below the sphere through the lowest vertex (radius b): §3.2's lower bound would cull them.
    let g = grid(80.0, 0.0, 5.0, 30.0, 3, 13);
    let dem = TestDem::new(g, std::vec![0.0; 39], 1);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let (a, b, c) = (
        dem.surface.vertex(1, 3).unwrap(),
        dem.surface.vertex(1, 4).unwrap(),
        dem.surface.vertex(2, 4).unwrap(),
    );
    let centroid = a.plus(b).plus(c).scaled(1.0 / 3.0);
    assert!(
        centroid.length() < dem.surface.e.b() - 1000.0,
        "the chord dips below radius b"
    );
    let up = centroid.scaled(1.0 / centroid.length());
    // A segment that stays inside the sphere of radius b: only the sagitta-lowered bound lets it in.
    let ray = Ray::new(centroid.add_scaled(-10_000.0, up), up)
        .unwrap()
        .with_interval(0.0, 10_500.0)
        .unwrap();
    assert!(V3::from(ray.at(10_500.0)).length() < dem.surface.e.b());
    let hit = p.pick(&ray).unwrap().unwrap();
    assert!((hit.t - 10_000.0).abs() < 1e-6, "{}", hit.t);
    assert_eq!(hit.cell, [1, 3]);
}

#[test]
#[cfg_attr(miri, ignore)] // many picks: minutes under Miri; the light tests below cover the same code
fn cached_bounds_give_identical_picks() {
    let mut r = Lcg(5);
    let g = grid(40.0, 100.0, -0.25, 0.25, 17, 17);
    let hs: Vec<f64> = (0..289).map(|_| 3000.0 * r.next()).collect();
    let dem = TestDem::new(g, hs, 2);
    let plain: Vec<Option<(f64, [u32; 2])>> = {
        let s = dem.storage();
        let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
        (0..60)
            .map(|k| {
                let ray = radial_ray(
                    &dem.surface.e,
                    36.02 + 0.06 * k as f64,
                    100.0 + 0.065 * k as f64,
                    5000.0,
                );
                p.pick(&ray).unwrap().map(|h| (h.t, h.cell))
            })
            .collect()
    };
    let s = CachedBounds::new(dem.storage());
    assert!(s.cache.iter().flatten().count() > 4);
    let p: Picker<'_, f64, CachedBounds<'_>> = Picker::new(&s).unwrap();
    for (k, want) in plain.iter().enumerate() {
        let ray = radial_ray(
            &dem.surface.e,
            36.02 + 0.06 * k as f64,
            100.0 + 0.065 * k as f64,
            5000.0,
        );
        assert_eq!(p.pick(&ray).unwrap().map(|h| (h.t, h.cell)), *want);
        let ray = radial_ray(
            &dem.surface.e,
            36.02 + 0.06 * k as f64,
            100.0 + 0.065 * k as f64,
            5000.0,
        );
        same_hit(
            &ray,
            *want,
            dem.surface.brute(&ray),
            &std::format!("ray {k}"),
        );
        assert!(want.is_some(), "ray {k}");
    }
}

/// The node slots of a 3 × 3-vertex DEM with blocks of 2 × 2 cells (one zone, one leaf).
const PEAK_SLOTS: usize = build::node_slots(3, 3, 2);

/// [`PEAK`] in `f32` through the kernel's builder: heights, and node records without boxes and with them
/// (built in `f64`).
struct PeakF32 {
    heights: [f32; 9],
    nodes: [build::NodeRecord<f32>; PEAK_SLOTS],
    boxed: [build::NodeRecord<f32, Option<boxes::NodeBox>>; PEAK_SLOTS],
    tree: build::Tree,
}

impl PeakF32 {
    fn grid() -> Grid<f32> {
        Grid {
            lat0_deg: 47.0,
            lon0_deg: 8.0,
            dlat_deg: 0.01,
            dlon_deg: 0.01,
            rows: 3,
            cols: 3,
        }
    }
    fn new() -> Self {
        let (heights, g) = (PEAK.map(|h| h as f32), Self::grid());
        let mut nodes = [build::NodeRecord::EMPTY; PEAK_SLOTS];
        let tree = build::build_tree(&heights, &g, 2, &mut nodes).unwrap();
        let mut boxed = [build::NodeRecord::EMPTY; PEAK_SLOTS];
        assert_eq!(build::build_tree(&heights, &g, 2, &mut boxed), Ok(tree));
        build::build_boxes(&Ellipsoid::wgs84(), &g, &heights, tree, None, &mut boxed).unwrap();
        PeakF32 {
            heights,
            nodes,
            boxed,
            tree,
        }
    }
    /// The storage without node boxes.
    fn plain(&self) -> build::SliceStorage<'_, f32> {
        build::SliceStorage::new(
            Ellipsoid::wgs84(),
            Self::grid(),
            &self.heights,
            &self.nodes,
            self.tree,
        )
        .unwrap()
    }
    /// The storage with the node box.
    fn boxed(&self) -> build::SliceStorage<'_, f32, f32, Option<boxes::NodeBox>> {
        build::SliceStorage::new(
            Ellipsoid::wgs84(),
            Self::grid(),
            &self.heights,
            &self.boxed,
            self.tree,
        )
        .unwrap()
    }
}

/// A 2500 m peak in the middle of a 3 × 3 grid of 400 m (0.01° spacing from 47° N, 8° E).
const PEAK: [f64; 9] = [
    400.0, 400.0, 400.0, 400.0, 2500.0, 400.0, 400.0, 400.0, 400.0,
];

/// The hit of a ray straight down on [`PEAK`]'s summit from 10 km.
fn pick_down_on_the_peak<S: TerrainStorage<f32>>(p: &Picker<'_, f32, S>) -> Hit<f32> {
    let e = Ellipsoid::<f32>::wgs84();
    let top = e.geodetic_deg_to_ecef(47.01, 8.01, 10_000.0);
    let n = e.normal_rad(47.01_f32.to_radians(), 8.01_f32.to_radians());
    p.pick(&Ray::new(top, n.negated()).unwrap())
        .unwrap()
        .unwrap()
}

#[test]
fn f32_picker_with_a_box_built_in_f64_still_finds_the_peak() {
    // The box is exact for the f64 vertices; the f32 picker's vertices and frame differ by f32 rounding (0.5 m
    // at Earth scale), which the box test's tolerance covers.
    let peak = PeakF32::new();
    assert!(peak.boxed.iter().filter(|r| r.bbox.is_some()).count() == 1);
    let dem = peak.boxed();
    let p: Picker<'_, f32, _> = Picker::new(&dem).unwrap();
    let hit = pick_down_on_the_peak(&p);
    assert!((hit.h - 2500.0).abs() < 3.0, "{}", hit.h);
    // Near the corners (at the box's lowest points) the boxed picker answers as the plain one.
    let plain_dem = peak.plain();
    let plain: Picker<'_, f32, build::SliceStorage<'_, f32>> = Picker::new(&plain_dem).unwrap();
    let e = Ellipsoid::<f32>::wgs84();
    for (lat, lon) in [(47.0001, 8.0001), (47.0199, 8.0199), (47.0001, 8.0199)] {
        let top = e.geodetic_deg_to_ecef(lat, lon, 5_000.0);
        let n = e.normal_rad(lat.to_radians(), lon.to_radians());
        let ray = Ray::new(top, n.negated()).unwrap();
        let (got, want) = (p.pick(&ray).unwrap(), plain.pick(&ray).unwrap());
        assert!(
            got.is_some() && got == want,
            "{lat} {lon}: {got:?} vs {want:?}"
        );
    }
}

#[test]
fn f32_pick_of_a_peak() {
    let peak = PeakF32::new();
    let dem = peak.plain();
    let p: Picker<'_, f32, build::SliceStorage<'_, f32>> = Picker::new(&dem).unwrap();
    let hit = pick_down_on_the_peak(&p);
    // f32 ECEF coordinates are quantised to 0.5 m at Earth scale.
    assert!((hit.t - 7500.0).abs() < 3.0, "{}", hit.t);
    assert!((hit.h - 2500.0).abs() < 3.0, "{}", hit.h);
}

#[test]
fn default_zones_of_a_global_grid_are_45_degree_tiles_on_grid_lines() {
    // A global 1° grid: 181 rows (pole to pole), 361 columns (the last repeats the first).
    let g = grid(90.0, -180.0, -1.0, 1.0, 181, 361);
    let mut count = 0;
    for k in 0..DEFAULT_ZONE_ROWS * DEFAULT_ZONE_COLS {
        let (rows, cols) = zone_cells(&g, DEFAULT_ZONE_ROWS, DEFAULT_ZONE_COLS, k).unwrap();
        assert_eq!((rows[1] - rows[0], cols[1] - cols[0]), (45, 45));
        assert_eq!(g.lat_deg(rows[0]), 90.0 - 45.0 * (k / 8) as f64);
        assert_eq!(g.lon_deg(cols[0]), -180.0 + 45.0 * (k % 8) as f64);
        count += 1;
    }
    assert_eq!(count, 32);
    assert_eq!(zone_cells(&g, 4, 8, 32), None);
    // More zones than cells: empty zones are None.
    let tiny = grid(0.0, 0.0, 0.1, 0.1, 3, 3);
    assert_eq!(zone_cells(&tiny, 4, 1, 0), None);
    assert_eq!(zone_cells(&tiny, 4, 1, 1), Some(([0, 1], [0, 2])));
}

/// Fewest hits of the 40 rays of each kind in `global_grid_with_32_zones_agrees_with_brute_force` (measured: 28
/// from below the surface, 35 to 40 for the others).
const HITS_GLOBAL_PER_KIND: usize = 25;

#[test]
#[cfg_attr(miri, ignore)]
fn global_grid_with_32_zones_agrees_with_brute_force() {
    // A global 5.625° grid from pole to pole whose last column repeats the first (longitudes run to +180):
    // the builder's leaves of 2 × 2 cells under its 8 × 4 zones, which are the 45° tiles of zone_cells; rays
    // from orbit, across the antimeridian, over and through the poles, from below the surface and toward the
    // center.
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
    let dem = TestDem::new(g, hs, 2);
    let s = dem.storage();
    assert_eq!(s.zone_count(), 32);
    for k in 0..32 {
        let zone = s.node(s.zone(k).unwrap()).unwrap();
        let tile = zone_cells(&g, DEFAULT_ZONE_ROWS, DEFAULT_ZONE_COLS, k as u32).unwrap();
        assert_eq!((zone.rows, zone.cols), tile);
        assert!(!zone.is_leaf());
    }
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    // Hits per kind of ray (k % 6): each kind must reach the surface, or it tests nothing.
    let mut hits = [0usize; 6];
    for k in 0..240 {
        let (origin, dir) = match k % 6 {
            // From orbit (4e7 m) toward a random surface point.
            0 => {
                let o = e.geodetic_deg_to_ecef(
                    180.0 * r.next() - 90.0,
                    360.0 * r.next() - 180.0,
                    4.0e7,
                );
                let t =
                    e.geodetic_deg_to_ecef(180.0 * r.next() - 90.0, 360.0 * r.next() - 180.0, 0.0);
                (o, t.minus(o))
            }
            // Across the antimeridian at low altitude.
            1 => {
                let lat = 160.0 * r.next() - 80.0;
                let o = e.geodetic_deg_to_ecef(lat, 170.0, 20_000.0 + 50_000.0 * r.next());
                let t = e.geodetic_deg_to_ecef(lat + 4.0 * r.next() - 2.0, -170.0, 0.0);
                (o, t.minus(o))
            }
            // Over the poles.
            2 => {
                let s = if r.next() < 0.5 { 1.0 } else { -1.0 };
                let o = e.geodetic_deg_to_ecef(s * 75.0, 360.0 * r.next() - 180.0, 1.0e5);
                let t = e.geodetic_deg_to_ecef(
                    s * (85.0 + 5.0 * r.next()),
                    360.0 * r.next() - 180.0,
                    0.0,
                );
                (o, t.minus(o))
            }
            // Through the pole's vertex, from above.
            3 => {
                let s = if r.next() < 0.5 { 1.0 } else { -1.0 };
                let o = V3::new(
                    3.0e5 * (r.next() - 0.5),
                    3.0e5 * (r.next() - 0.5),
                    s * 6.5e6,
                );
                (o, V3::new(0.0, 0.0, -s))
            }
            // From 2 km below the surface, upward or sideways.
            4 => {
                let (la, lo) = (170.0 * r.next() - 85.0, 360.0 * r.next() - 180.0);
                let o = e.geodetic_deg_to_ecef(la, lo, -5000.0);
                (o, V3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5))
            }
            // Toward the Earth's center.
            _ => {
                let o = e.geodetic_deg_to_ecef(
                    180.0 * r.next() - 90.0,
                    360.0 * r.next() - 180.0,
                    1.0e6,
                );
                (o, o.negated())
            }
        };
        let ray = Ray::new(origin, dir).unwrap();
        let got = p.pick(&ray).unwrap().map(|h| (h.t, h.cell));
        same_hit(&ray, got, dem.surface.brute(&ray), &std::format!("ray {k}"));
        hits[k % 6] += usize::from(got.is_some());
    }
    assert!(hits.iter().all(|&h| h >= HITS_GLOBAL_PER_KIND), "{hits:?}");
}

#[test]
fn ray_from_5e9_m_away_hits_a_vertical_sliver_at_the_south_pole() {
    // Row 0 is the south pole with two different heights (63.75 m and 0 m) at the same point, so the triangle
    // (0,0)–(0,1)–(1,1) stands vertically on the pole. The ray comes from 5.3e9 m away on the far side and
    // ends 1 m beside the pole vertex (fuzz finding).
    let g = grid(-90.0, -225.588_888_888_888_9, 0.0005, 0.0001, 2, 9);
    let mut hs = std::vec![0.0; 18];
    for (k, h) in [
        (0, 63.75),
        (12, 576.0),
        (13, 3183.75),
        (14, -2425.5),
        (15, -2720.25),
        (16, 6095.75),
        (17, -5076.0),
    ] {
        hs[k] = h;
    }
    let dem = TestDem::new(g, hs, 8);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let ray = Ray::new(
        [
            -38_322_603.592_089_176,
            4_295_866_701.003_452,
            -3_131_154_834.841_433_5,
        ],
        [
            38_322_603.592_089_176,
            -4_295_866_702.003_452,
            3_124_798_082.527_188_3,
        ],
    )
    .unwrap();
    let want = dem.surface.brute(&ray);
    assert!(want.is_some());
    let got = p.pick(&ray).unwrap().map(|h| (h.t, h.cell));
    same_hit(&ray, got, want, "sliver at the south pole");
}

/// Distance from `p` to the closed triangle `v` (the nearest of its interior and its three edges).
fn distance_to_triangle(p: V3<f64>, v: [V3<f64>; 3]) -> f64 {
    let n = v[1].minus(v[0]).cross(v[2].minus(v[0]));
    let inside = (0..3).all(|k| {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        b.minus(a).cross(p.minus(a)).dot(n) >= 0.0
    });
    let mut best = if inside && n.length() > 0.0 {
        (p.minus(v[0]).dot(n) / n.length()).abs()
    } else {
        f64::INFINITY
    };
    for k in 0..3 {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        let e = b.minus(a);
        let s = (p.minus(a).dot(e) / e.dot(e)).clamp(0.0, 1.0);
        best = best.min(p.minus(a.add_scaled(s, e)).length());
    }
    best
}

#[test]
fn ray_almost_in_the_meridian_plane_of_polar_sliver_triangles() {
    // Cells 4.1° tall and 0.0001° wide from the south pole: each triangle with two pole vertices lies in a
    // meridian plane, and the ray (from the z axis 5.4e9 m away) almost lies in that plane too. The triangle
    // test used to read the rounding noise of that edge-on view as a hit 7.7 km from any triangle (fuzz
    // finding); the hit must lie on a triangle of its cell.
    let g = grid(-90.0, -225.588_888_888_888_9, 4.0965, 0.0001, 2, 9);
    let hs = std::vec![
        63.75, 0.0, 0.0, 0.0, 0.0, 0.25, 0.0, 0.0, 704.0, 0.0, 0.0, 0.5, 576.0, 3183.75, -2425.5,
        -2720.25, 6093.75, -5076.0,
    ];
    let dem = TestDem::new(g, hs, 8);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let ray = Ray::new(
        [0.0, -0.0, -5_362_342_899.685_755],
        [
            -240_033.236_469_758_65,
            245_013.668_449_579_42,
            5_355_995_345.833_253,
        ],
    )
    .unwrap();
    // The ray does cross the fan of slivers further out.
    let hit = p.pick(&ray).unwrap().unwrap();
    let [i, j] = hit.cell;
    let v = |a: u32, b: u32| dem.surface.vertex(a, b).unwrap();
    let near = [
        [v(i, j), v(i, j + 1), v(i + 1, j + 1)],
        [v(i, j), v(i + 1, j + 1), v(i + 1, j)],
    ]
    .iter()
    .map(|&tri| distance_to_triangle(V3::from(hit.ecef), tri))
    .fold(f64::INFINITY, f64::min);
    assert!(
        near < 1e-3,
        "hit {hit:?} is {near} m from its cell's triangles"
    );
    same_hit(
        &ray,
        Some((hit.t, hit.cell)),
        dem.surface.brute(&ray),
        "sliver fan",
    );
}

/// Multi-resolution (module docs, "Multi-resolution"): a 9 × 9-vertex DEM whose zone (8 × 8 cells) has a block of
/// stride 2 and four children of 4 × 4 cells at stride 1, with residency and `min_level` chosen per test.
mod multires {
    use super::*;
    use build::{
        MultiRes, NodeRecord, Parts, SliceStorage, TreeStorage, build_multires_tree, build_tree,
        node_slots,
    };
    use core::sync::atomic::{AtomicBool, Ordering};
    use std::vec;

    /// Vertex rows and columns: 20 × 8 cells, so that the builder's 4 × 4-cell leaves (5 × 2) sit under three
    /// zones, the first of them 8 × 8 cells with four children.
    const ROWS: u32 = 21;
    const COLS: u32 = 9;

    /// Flat at 0 m except V(1, 4) at 300 m: on the border between the children of columns 0–3 and 4–7, a vertex
    /// of the fine block that the zone's stride-2 block does not have.
    struct Dem {
        grid: Grid<f64>,
        heights: Vec<f64>,
        nodes: Vec<NodeRecord<f64>>,
        tree: build::Tree,
        resident: Vec<AtomicBool>,
    }

    fn dem() -> Dem {
        let mut heights = vec![0.0; (ROWS * COLS) as usize];
        heights[9 + 4] = 300.0;
        let grid = grid(10.0, 20.0, 0.01, 0.01, ROWS, COLS);
        let mut nodes = vec![NodeRecord::EMPTY; node_slots(ROWS, COLS, 4)];
        let tree =
            build_multires_tree(&heights, &grid, 4, MultiRes::default(), &mut nodes).unwrap();
        assert_eq!(tree.depth(), 1);
        let resident = (0..tree.slots()).map(|_| AtomicBool::new(true)).collect();
        Dem {
            grid,
            heights,
            nodes,
            tree,
            resident,
        }
    }

    impl Dem {
        /// The paged storage: the builder's multi-resolution tree with this DEM's residency flags.
        fn paged(&self) -> SliceStorage<'_, f64, f64, (), AtomicBool> {
            let parts =
                Parts::new(&self.heights[..], &self.nodes[..]).with_resident(&self.resident);
            TreeStorage::with_buffers(Ellipsoid::wgs84(), self.grid, self.tree, parts).unwrap()
        }
        /// The child covering rows 0–3, columns 0–3.
        fn west_child(&self) -> NodeId {
            let k = self
                .nodes
                .iter()
                .position(|n| n.level == 1 && n.rows == [0, 4] && n.cols == [0, 4]);
            NodeId(k.unwrap() as u32)
        }
        fn evict(&self, id: NodeId) {
            self.resident[id.0 as usize].store(false, Ordering::Relaxed);
        }
    }

    fn down_at(e: &Ellipsoid<f64>, lat: f64, lon: f64) -> Ray<f64> {
        radial_ray(e, lat, lon, 2000.0)
    }

    #[test]
    fn missing_leaf_falls_back_to_the_zone_block_stitched_to_its_fine_neighbour() {
        let d = dem();
        d.evict(d.west_child());
        let s = d.paged();
        let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
        let e = Ellipsoid::wgs84();
        // West of the border, inside the zone's coarse cell (rows 0–2, columns 2–4): traced from the zone.
        let west = p.pick(&down_at(&e, 10.01, 20.0399)).unwrap().unwrap();
        assert_eq!((west.level, west.stride, west.cell), (0, 2, [0, 2]));
        // Its fan reaches the fine vertex at 300 m: just west of V(1, 4) the surface is almost 300 m high (the
        // coarse cell's own triangles are flat at 0 m there).
        assert!(west.h > 290.0, "{west:?}");
        // East of the border: the resident fine child.
        let east = p.pick(&down_at(&e, 10.01, 20.0401)).unwrap().unwrap();
        assert_eq!((east.level, east.stride), (1, 1));
        assert!(east.h > 290.0, "{east:?}");
        // No crack: rays swept across the border around the T-junction all hit, at heights that vary
        // continuously.
        // (Under Miri a coarser sweep over the same span.)
        let (n, step) = if cfg!(miri) { (8, 5e-5) } else { (400, 1e-6) };
        let mut prev: Option<f64> = None;
        for k in 0..=n {
            let lon = 20.0398 + f64::from(k) * step;
            for lat in [10.0095, 10.01, 10.0105] {
                let h = p.pick(&down_at(&e, lat, lon)).unwrap().unwrap().h; // no crack
                if lat == 10.01 {
                    if let Some(q) = prev {
                        assert!((h - q).abs() < 5.0 * step / 1e-6, "lon {lon}: {q} → {h}");
                    }
                    prev = Some(h);
                }
            }
        }
    }

    #[test]
    fn needs_block_below_min_level_and_full_resolution_when_all_resident() {
        let d = dem();
        let w = d.west_child();
        d.evict(w);
        let s = d.paged();
        let e = Ellipsoid::wgs84();
        let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
        let p = p.with_min_level(1);
        assert_eq!(
            p.pick(&down_at(&e, 10.01, 20.01)),
            Err(TerrainError::NeedsBlock(w))
        );
        // A ray that never reaches the missing child is answered.
        let far = p.pick(&down_at(&e, 10.06, 20.06)).unwrap().unwrap();
        assert_eq!((far.level, far.stride), (1, 1));
        // Everything resident: the full-resolution surface, as the single-resolution storage gives it.
        d.resident[w.0 as usize].store(true, Ordering::Relaxed);
        let p: Picker<'_, f64, _> = Picker::new(&s).unwrap();
        let mut nodes = vec![NodeRecord::<f64>::EMPTY; node_slots(ROWS, COLS, 4)];
        let tree = build_tree(&d.heights, &d.grid, 4, &mut nodes).unwrap();
        let flat = SliceStorage::new(Ellipsoid::wgs84(), d.grid, &d.heights, &nodes, tree).unwrap();
        let single: Picker<'_, f64, _> = Picker::new(&flat).unwrap();
        for (lat, lon) in [
            (10.01, 20.04),
            (10.013, 20.0399),
            (10.055, 20.011),
            (10.001, 20.079),
        ] {
            let r = down_at(&e, lat, lon);
            let (a, b) = (
                p.pick(&r).unwrap().unwrap(),
                single.pick(&r).unwrap().unwrap(),
            );
            assert_eq!((a.t, a.cell, a.stride), (b.t, b.cell, 1));
        }
    }
}

/// Straight-down rays through vertices on the border of the surface, on flat terrain of grids of several sizes,
/// places and heights: each must hit at its vertex (triangles are closed; triangle.rs, "Edges on the border of
/// the surface"), at `t` = 1000 m, and the brute force with the same border rule agrees.
fn assert_hits_down_through(dem: &TestDem, vertices: &[(u32, u32)], what: &str) -> usize {
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    for &(i, j) in vertices {
        let (lat, lon) = (dem.surface.grid.lat_deg(i), dem.surface.grid.lon_deg(j));
        let h = dem.surface.h(i, j).unwrap();
        let ray = radial_ray(&dem.surface.e, lat, lon, h + 1000.0);
        let hit = p.pick(&ray).unwrap();
        // Through a vertex the two may pick different triangles around it, at the same point.
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
        n += assert_hits_down_through(
            &dem,
            &edge,
            &std::format!("grid at {lat0_deg}°, {lon0_deg}°"),
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
        assert_hits_down_through(
            &dem,
            &corners,
            &std::format!("corners at {lat0_deg}°, {lon0_deg}°"),
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
