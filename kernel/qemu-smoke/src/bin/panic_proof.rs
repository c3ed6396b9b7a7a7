//! The link-time panic-free proof for every public entry point of the kernel, in `f64` and `f32`.
//!
//! `curvicast-qemu-smoke` proves panic freedom for what its fixed cases call. This binary calls every public entry
//! point — surfaces, rays, geodesy and the height-quad bounds, the spherical, cylindrical and polar grids with the
//! serial and the separable engine, the terrain picker (`pick`, `pick_t`, `pick_with_stats`, `line_of_sight`,
//! with node boxes, multi-resolution strides, non-resident blocks and `min_level`), block subsets, node boxes,
//! edge-beveling, the a-priori level of detail (`lod`) and the rational Chaikin curves — on inputs read through
//! [`core::hint::black_box`], so that the optimiser knows nothing about them and must keep every branch the
//! kernel has for any input, and passes every result through `black_box` too, so that no call is dropped.
//!
//! Its `#[panic_handler]` calls a function defined nowhere, as the smoke binary's does: with `panic = "abort"`,
//! LTO and one codegen unit, `cargo build --release --bin curvicast-panic-proof` links only if no panic path is
//! reachable from any of these calls. Run on QEMU it prints one line and exits with status 0; the answers are not
//! checked here (the smoke test and the host suites check answers).

#![no_std]
#![no_main]
#![deny(unsafe_code)]

use core::hint::black_box;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio};
use curvicast::Real;
use curvicast::geodesy::{Ellipsoid, HeightQuadBounds};
use curvicast::march::{CylindricalGrid, PolarGrid, SphericalGrid};
use curvicast::ray::Ray;
use curvicast::surface::{AxialCone, HalfPlane, PlaneZ, Spheroid, Surface};
use curvicast::terrain::boxes::NodeBox;
use curvicast::terrain::subset::{BlockSubset, Quadrant};
use curvicast::terrain::{
    Grid, Node, NodeId, PickStats, Picker, TerrainCaches, TerrainStorage, node_box_of_vertices,
    zone_cells,
};
use curvicast::tessellate::bevel::{self, Face};
use curvicast::tessellate::chaikin::{self, Arc};
use curvicast::tessellate::lod::{self, Bound, Shape};
use curvicast::vec3::V3;

/// An opaque scalar: the optimiser cannot see the value.
fn o<T: Real>(x: f64) -> T {
    black_box(T::from_f64(black_box(x)))
}

/// An opaque point.
fn o3<T: Real>(v: [f64; 3]) -> [T; 3] {
    v.map(o::<T>)
}

/// Every surface's crossings, the ray's own queries, and the geodesy entry points.
fn surfaces_and_geodesy<T: Real>() {
    let Ok(ray) = Ray::new(o3::<T>([-3.0, 0.1, 0.2]), o3::<T>([1.0, 0.01, 0.02])) else {
        return;
    };
    let ray = ray.with_interval(o(0.0), o(1e3)).unwrap_or(ray);
    black_box((
        ray.at(o(0.5)),
        ray.t_closest(),
        ray.closest_distance_squared(),
    ));
    black_box(Ray::segment(o3::<T>([0.0; 3]), o3::<T>([1.0, 2.0, 3.0])).ok());
    if let Ok(s) = Spheroid::new(o(2.0), o(1.5)) {
        black_box(s.crossings(&ray));
    }
    if let Ok(c) = AxialCone::from_zenith_rad(o(0.3), o(1.1)) {
        black_box(c.crossings(&ray));
    }
    if let Ok(h) = HalfPlane::from_azimuth_rad(o(0.7)) {
        black_box(h.crossings(&ray));
    }
    if let Ok(p) = PlaneZ::new(o(0.25)) {
        black_box(p.crossings(&ray));
    }
    let Ok(e) = Ellipsoid::<T>::new(o(6_378_137.0), o(6_356_752.3)) else {
        return;
    };
    let p = e.geodetic_deg_to_ecef(o(36.0), o(-118.0), o(1000.0));
    black_box(e.ecef_to_geodetic(p));
    black_box(e.geodetic_rad_to_ecef(o(0.6), o(-2.0), o(10.0)));
    black_box(e.normal_rad(o(0.6), o(-2.0)));
    black_box(HeightQuadBounds::new(
        &e,
        o(36.0),
        o(36.5),
        o(-118.0),
        o(-117.5),
        o(-100.0),
        o(4000.0),
        o(0.01),
        o(0.01),
    ))
    .ok();
}

/// The three grids, each with both engines, draining every iterator.
fn grids<T: Real>() {
    let Ok(ray) = Ray::new(o3::<T>([-2.0, 0.25, 0.25]), o3::<T>([1.0, 0.01, -0.02])) else {
        return;
    };
    let r = [o(0.0), o(0.5), o(0.75), o(1.0)];
    let th = [o(0.0), o(0.8), o(1.6), o(3.1)];
    let ph = [o(-0.5), o(1.0), o(3.0), o(5.7)];
    let z = [o(-1.0), o(0.0), o(0.5), o(1.0)];
    let mut ws = [T::ZERO; SphericalGrid::<f64>::workspace_len(4, 4, 4)];
    if let Ok(g) = SphericalGrid::new(&r, &th, &ph, &mut ws) {
        let g = g.with_center(o3::<T>([0.0, 0.1, 0.0])).unwrap_or(g);
        black_box(g.shape());
        let mut m = g.march(&ray);
        for c in &mut m {
            black_box(c);
        }
        black_box(m.error());
        if let Ok(s) = g.march_separable::<16>(&ray) {
            for c in s {
                black_box(c);
            }
        }
    }
    let mut ws = [T::ZERO; CylindricalGrid::<f64>::workspace_len(4, 4)];
    if let Ok(g) = CylindricalGrid::new(&r, &ph, &z, &mut ws) {
        let mut m = g.march(&ray);
        for c in &mut m {
            black_box(c);
        }
        black_box(m.error());
        if let Ok(s) = g.march_separable::<16>(&ray) {
            for c in s {
                black_box(c);
            }
        }
    }
    let mut ws = [T::ZERO; PolarGrid::<f64>::workspace_len(4, 4)];
    if let Ok(g) = PolarGrid::new(&r, &ph, &mut ws) {
        let g = g.with_center([o(0.1), o(0.0)]).unwrap_or(g);
        let mut m = g.march(&ray);
        for c in &mut m {
            black_box(c);
        }
        black_box(m.error());
        if let Ok(s) = g.march_separable::<16>(&ray) {
            for c in s {
                black_box(c);
            }
        }
    }
}

/// Vertices per side of the opaque DEM.
const N: u32 = 5;
/// Nodes: a zone (0) and its four children (1–4).
const NODES: usize = 5;

/// A 5 × 5-vertex DEM whose every answer comes through `black_box`: grid, heights, tree, residency, strides
/// and boxes, so that every branch of the traversal stays reachable.
struct Opaque {
    boxes: [Option<NodeBox>; NODES],
}

impl<T: Real> TerrainStorage<T> for Opaque {
    fn ellipsoid(&self) -> Ellipsoid<T> {
        black_box(Ellipsoid::wgs84())
    }
    fn grid(&self) -> Grid<T> {
        Grid {
            lat0_deg: o(10.0),
            lon0_deg: o(20.0),
            dlat_deg: o(0.01),
            dlon_deg: o(0.01),
            rows: black_box(N),
            cols: black_box(N),
        }
    }
    fn zone_count(&self) -> usize {
        black_box(1)
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        black_box((k == 0).then_some(NodeId(0)))
    }
    fn node(&self, id: NodeId) -> Option<Node<T>> {
        let (rows, cols) = match black_box(id.0) {
            0 => ([0, 4], [0, 4]),
            1 => ([0, 2], [0, 2]),
            2 => ([0, 2], [2, 4]),
            3 => ([2, 4], [0, 2]),
            4 => ([2, 4], [2, 4]),
            _ => return None,
        };
        let children = if id.0 == 0 {
            [1, 2, 3, 4].map(|k| Some(NodeId(k)))
        } else {
            [None; 4]
        };
        black_box(Some(Node {
            rows,
            cols,
            heights: Some([o(-50.0), o(700.0)]),
            children,
            level: u8::from(id.0 != 0),
        }))
    }
    fn height(&self, i: u32, j: u32) -> Option<T> {
        black_box((i < N && j < N).then(|| o(f64::from(i.wrapping_mul(7) ^ j.wrapping_mul(13)))))
    }
    fn is_resident(&self, id: NodeId) -> bool {
        black_box(id.0 != 3)
    }
    fn block_stride(&self, id: NodeId) -> u32 {
        black_box(if id.0 == 0 { 2 } else { 1 })
    }
}

impl<T: Real> TerrainCaches<T> for Opaque {
    fn node_box(&self, id: NodeId) -> Option<NodeBox> {
        black_box(
            self.boxes
                .get(usize::try_from(id.0).ok()?)
                .copied()
                .flatten(),
        )
    }
}

/// Node boxes built as a storage builds them, from the opaque vertices.
fn opaque_dem() -> Opaque {
    let plain = Opaque {
        boxes: [None; NODES],
    };
    let e = Ellipsoid::<f64>::wgs84();
    let zone = TerrainStorage::<f64>::node(&plain, NodeId(0));
    let mut boxes = [None; NODES];
    for (k, b) in boxes.iter_mut().enumerate() {
        let id = NodeId(u32::try_from(k).unwrap_or(u32::MAX));
        if let Some(n) = TerrainStorage::<f64>::node(&plain, id) {
            let shared = black_box(k % 2 == 1);
            let anchor = if k == 0 || shared {
                None
            } else {
                zone.as_ref()
            };
            *b = node_box_of_vertices(&plain, &e, &n, anchor, shared);
        }
    }
    Opaque {
        boxes: black_box(boxes),
    }
}

/// Every picker entry point, with and without boxes, at two `min_level`s; block subsets and zone cells.
fn terrain<T: Real>(dem: &Opaque) {
    let e = Ellipsoid::<T>::wgs84();
    let top = e.geodetic_deg_to_ecef(o(10.02), o(20.02), o(5000.0));
    let Ok(ray) = Ray::new(top, o3::<T>([-0.3, -0.2, -0.9])) else {
        return;
    };
    let plain = Opaque {
        boxes: [None; NODES],
    };
    for storage in [dem, &plain] {
        let Ok(p) = Picker::<'_, T, Opaque, 16, 4>::new(storage) else {
            continue;
        };
        let p = p.with_min_level(black_box(1));
        black_box(p.min_level());
        black_box(p.pick(&ray)).ok();
        black_box(p.pick_t(&ray)).ok();
        let mut stats = PickStats::default();
        black_box(p.pick_with_stats(&ray, &mut stats)).ok();
        black_box(stats);
        let low = e.geodetic_deg_to_ecef(o(10.0), o(20.0), o(100.0));
        black_box(p.line_of_sight(top, low)).ok();
    }
    let g: Grid<T> = TerrainStorage::<T>::grid(dem);
    black_box(g.validate());
    black_box(zone_cells(&g, black_box(2), black_box(2), black_box(3)));
    if let Ok(b) = BlockSubset::new(black_box(16)) {
        black_box(b.step_up(Quadrant::new(black_box(true), black_box(false)))).ok();
    }
    black_box(BlockSubset::of_descendant(
        black_box(16),
        black_box(3),
        black_box(5),
        black_box(2),
    ))
    .ok();
}

/// Level of the beveled buffers below.
const BEVEL_LEVEL: u32 = 2;
/// Level of the Chaikin buffers below.
const CURVE_LEVEL: u32 = 3;

/// Edge-beveling.
fn bevel<T: Real>() {
    let level = black_box(BEVEL_LEVEL);
    let mut v = [V3::<T>::ZERO; bevel::vertex_count(BEVEL_LEVEL)];
    let mut f = [Face::<T>::EMPTY; bevel::face_count(BEVEL_LEVEL)];
    black_box(bevel::bevel_sphere(level, o(2.0), &mut v, &mut f)).ok();
    black_box(bevel::bevel_ellipsoid(
        level,
        o3::<T>([3.0, 2.0, 1.0]),
        &mut v,
        &mut f,
    ))
    .ok();
    black_box(&v);
    black_box(&f);
}

/// The a-priori level of detail.
fn level_of_detail<T: Real>() {
    let shapes = [
        Shape::Sphere(o::<T>(2.0)),
        Shape::Ellipsoid(o3::<T>([3.0, 2.0, 1.0])),
    ];
    for shape in shapes {
        for bound in [
            Bound::MinDihedral(o(2.9)),
            Bound::MaxDeviation(o(0.01)),
            Bound::ScreenSpace {
                distance: o(10.0),
                pixel_angle: o(0.001),
            },
        ] {
            black_box(lod::min_level(shape, bound)).ok();
        }
    }
    black_box(lod::worst_case::<T>(black_box(3))).ok();
    black_box(lod::ellipsoid_worst_case(
        o3::<T>([3.0, 2.0, 1.0]),
        black_box(2),
    ))
    .ok();
    black_box(lod::screen_space_error(o::<T>(1.0), o(10.0), o(0.01)));
}

/// The rational Chaikin curves.
fn curves<T: Real>() {
    let level = black_box(CURVE_LEVEL);
    let mut out = [[T::ZERO; 2]; chaikin::square_len(CURVE_LEVEL)];
    let c = [o::<T>(0.5), o(-1.0)];
    black_box(chaikin::circle(c, o(2.0), level, &mut out)).ok();
    black_box(chaikin::ellipse(c, o(3.0), o(1.0), level, &mut out)).ok();
    black_box(chaikin::sheared_ellipse(
        c,
        o(3.0),
        o(1.0),
        o(0.5),
        level,
        &mut out,
    ))
    .ok();
    let m = [[o(2.0), o(0.5)], [o(0.0), o(1.0)]];
    black_box(chaikin::affine_circle(c, m, level, &mut out)).ok();
    let corners = [[o(-2.0), o(-1.0)], [o(2.0), o(-1.0)], [o(0.0), o(2.5)]];
    let empty = Arc {
        start: [T::ZERO; 2],
        corner: [T::ZERO; 2],
        alpha: T::ONE,
    };
    let mut arcs = [empty; 3];
    if let Ok(n) = chaikin::arcs_of_tangential_polygon([o(0.0), o(0.0)], &corners, &mut arcs) {
        let mut pts = [[T::ZERO; 2]; chaikin::closed_len(3, CURVE_LEVEL)];
        black_box(chaikin::refine_closed(
            arcs.get(..n).unwrap_or(&[]),
            level,
            &mut pts,
        ))
        .ok();
        black_box(&pts);
    }
    black_box(&out);
}

#[entry]
fn main() -> ! {
    surfaces_and_geodesy::<f64>();
    surfaces_and_geodesy::<f32>();
    grids::<f64>();
    grids::<f32>();
    let dem = opaque_dem();
    terrain::<f64>(&dem);
    terrain::<f32>(&dem);
    bevel::<f64>();
    bevel::<f32>();
    level_of_detail::<f64>();
    level_of_detail::<f32>();
    curves::<f64>();
    curves::<f32>();
    if let Ok(mut out) = hio::hstdout() {
        out.write_all(b"curvicast panic-proof: every public entry point ran (f64 and f32)\n")
            .ok();
    }
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi();
    }
}

/// Reached only through a panic path: the link fails ("undefined symbol: curvicast_panic_path_is_reachable")
/// whenever any panic path survives optimisation.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    #[allow(unsafe_code)]
    unsafe extern "Rust" {
        safe fn curvicast_panic_path_is_reachable() -> !;
    }
    curvicast_panic_path_is_reachable()
}
