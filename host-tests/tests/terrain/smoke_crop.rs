//! The terrain part of the QEMU smoke test (`kernel/qemu-smoke/src/dem_crop.rs`), generated here: a crop of the
//! shipped Trinidad DEM around Blanca Peak (48 × 64 heights, integer metres) and rays over it with the terrain
//! oracle's answers. On the target the kernel builds its quadtree from the crop with `terrain::build` and picks
//! every ray in `f64` and `f32`.
//!
//! Every ray's origin and direction are rounded to `f32` before the oracle answers, so that the `f32` kernel gets
//! the very ray the oracle solved; what remains for `f32` is the rounding of its vertices (about 0.4 m per
//! coordinate at Earth scale) and of its arithmetic, which `TOL_F32` covers for these steep rays (at least 20°
//! above the horizon), while `f64` must agree within `TOL_F64`. The same rays are checked here against the
//! host's `f64` and `f32` kernel over the same builder, so a tolerance mistake shows up on the host too.
//!
//! Run with `CURVICAST_UPDATE_SMOKE=1` to rewrite the file; without it the test fails if the committed file differs
//! from what the oracle gives now.

use curvicast::Ray;
use curvicast::geodesy::Ellipsoid;
use curvicast::real::Real;
use curvicast::terrain::build::{NodeRecord, SliceStorage, build_tree, node_slots};
use curvicast::terrain::{Grid, Picker};
use curvicast_cli::formats::real_dem;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::Dem;
use curvicast_host::oracle::terrain::TerrainOracle;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The crop: first row and column in the Trinidad grid, and its size.
const ROW0: usize = 480;
const COL0: usize = 585;
const ROWS: usize = 48;
const COLS: usize = 64;
/// Leaf blocks of the tree built on the target.
const BLOCK: u32 = 8;
/// Tolerances on `t` (metres; the rays' directions are unit vectors).
const TOL_F64: f64 = curvicast_host::tolerances::TERRAIN_HIT_F64.bound;
const TOL_F32: f64 = curvicast_host::tolerances::TERRAIN_HIT_F32_SMOKE.bound;

fn crop() -> Dem {
    let t = real_dem::trinidad().expect("the shipped Trinidad DEM");
    let mut h = Vec::with_capacity(ROWS * COLS);
    for i in ROW0..ROW0 + ROWS {
        h.extend_from_slice(&t.heights[i * t.cols + COL0..i * t.cols + COL0 + COLS]);
    }
    let (lat0, lon0) = (t.lat(ROW0), t.lon(COL0));
    Dem::wgs84((lat0, lon0, t.dlat, t.dlon), (ROWS, COLS), h).expect("crop")
}

/// A unit vector rounded to `f32`, and a point rounded to `f32`.
fn f32_exact(v: [f64; 3]) -> [f64; 3] {
    v.map(|x| f64::from(x as f32))
}

/// The rays: straight down onto the crop's highest vertex and next to vertices on its outer edge and corner, a
/// camera 3 km above the north-west corner looking at points across the crop, one from below the surface
/// straight up, and one looking up from above (a miss).
fn rays(dem: &Dem) -> Vec<RaySpec> {
    let e = Ellipsoid::<f64>::wgs84();
    let at = |i: usize, j: usize, h: f64| e.geodetic_deg_to_ecef(dem.lat(i), dem.lon(j), h);
    let normal = |i: usize, j: usize| {
        let n = e.normal_rad(dem.lat(i).to_radians(), dem.lon(j).to_radians());
        [n.x, n.y, n.z]
    };
    let h = |i: usize, j: usize| f64::from(dem.height(i, j).expect("no nodata in the crop"));
    let (pi, pj) = (0..ROWS * COLS)
        .max_by(|&a, &b| dem.heights[a].total_cmp(&dem.heights[b]))
        .map(|k| (k / COLS, k % COLS))
        .expect("heights");
    let down = |i: usize, j: usize, above: f64| {
        let n = normal(i, j);
        let o = at(i, j, h(i, j) + above);
        RaySpec::new(f32_exact([o.x, o.y, o.z]), f32_exact(n.map(|x| -x)))
    };
    // Straight down 2 m inside the crop's outer edge or corner from vertex (i, j), `(di, dj)` inwards in degrees
    // of latitude and longitude: the ray rounded to f32 stays inside for the oracle, and the f32 kernel's
    // vertices (rounded by up to about 0.4 m) may put it just outside, where the border closure answers.
    let near_edge = |i: usize, j: usize, (di, dj): (f64, f64), above: f64| {
        let (lat, lon) = (dem.lat(i) + di, dem.lon(j) + dj);
        let n = e.normal_rad(lat.to_radians(), lon.to_radians());
        let o = e.geodetic_deg_to_ecef(lat, lon, h(i, j) + above);
        RaySpec::new(f32_exact([o.x, o.y, o.z]), f32_exact([-n.x, -n.y, -n.z]))
    };
    let inside = 2.0 / 111_000.0;
    let mut out = vec![
        down(pi, pj, 2000.0),
        near_edge(0, 17, (-inside, 0.0), 1500.0),
        near_edge(ROWS - 1, COLS - 1, (inside, -inside), 700.0),
        near_edge(21, 0, (0.0, inside), 1000.0),
    ];
    let cam = at(0, 0, 3000.0 + h(0, 0));
    for (i, j) in [(30, 40), (12, 50), (40, 10), (20, 30), (45, 60)] {
        let p = at(i, j, h(i, j) - 5.0);
        let d = [p.x - cam.x, p.y - cam.y, p.z - cam.z];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        out.push(RaySpec::new(
            f32_exact([cam.x, cam.y, cam.z]),
            f32_exact(d.map(|x| x / len)),
        ));
    }
    let (bi, bj) = (33, 44);
    let below = at(bi, bj, h(bi, bj) - 30.0);
    out.push(RaySpec::new(
        f32_exact([below.x, below.y, below.z]),
        f32_exact(normal(bi, bj)),
    ));
    let up = down(10, 10, 500.0);
    out.push(RaySpec::new(up.origin, up.dir.map(|x| -x)));
    out
}

/// The first hit's `t` of the kernel over the builder's tree, in precision `T`.
fn kernel_t<T: Real>(dem: &Dem, rays: &[RaySpec]) -> Vec<Option<f64>> {
    let grid = Grid {
        lat0_deg: T::from_f64(dem.lat0),
        lon0_deg: T::from_f64(dem.lon0),
        dlat_deg: T::from_f64(dem.dlat),
        dlon_deg: T::from_f64(dem.dlon),
        rows: ROWS as u32,
        cols: COLS as u32,
    };
    let heights: Vec<T> = dem
        .heights
        .iter()
        .map(|&h| T::from_f64(f64::from(h)))
        .collect();
    let mut nodes = vec![NodeRecord::<T>::EMPTY; node_slots(grid.rows, grid.cols, BLOCK)];
    let tree = build_tree(&heights, &grid, BLOCK, &mut nodes).expect("build");
    let s = SliceStorage::new(Ellipsoid::wgs84(), grid, &heights, &nodes, tree).expect("storage");
    let picker: Picker<'_, T, SliceStorage<'_, T>, 16, 32> = Picker::new(&s).expect("picker");
    rays.iter()
        .map(|r| {
            let ray = Ray::new(r.origin.map(T::from_f64), r.dir.map(T::from_f64)).expect("ray");
            picker.pick(&ray).expect("pick").map(|h| h.t.to_f64())
        })
        .collect()
}

fn render(dem: &Dem, rays: &[RaySpec], t: &[Option<f64>]) -> String {
    let mut s = String::new();
    s.push_str(
        "//! Generated by `cargo test -p curvicast-host --release --test terrain smoke_crop` (set CURVICAST_UPDATE_SMOKE=1\n\
         //! to rewrite). A crop of the shipped Trinidad DEM (USGS, public domain; see host-tests/data/README.md) and\n\
         //! rays over it with the host terrain oracle's answers. Do not edit by hand.\n\n",
    );
    let _ = writeln!(
        s,
        "/// Vertex rows and columns of the crop (Trinidad rows {ROW0}.., columns {COL0}..)."
    );
    let _ = writeln!(s, "pub const ROWS: u32 = {ROWS};");
    let _ = writeln!(s, "/// Vertex columns of the crop.");
    let _ = writeln!(s, "pub const COLS: u32 = {COLS};");
    let _ = writeln!(s, "/// Leaf block size of the tree built on the target.");
    let _ = writeln!(s, "pub const BLOCK: u32 = {BLOCK};");
    let _ = writeln!(
        s,
        "/// `[lat0, lon0, dlat, dlon]` of the crop's grid, degrees."
    );
    let _ = writeln!(
        s,
        "pub const GRID: [f64; 4] = [\n    {:?},\n    {:?},\n    {:?},\n    {:?},\n];",
        dem.lat0, dem.lon0, dem.dlat, dem.dlon
    );
    let _ = writeln!(s, "/// Tolerances on `t` in metres: `[f64, f32]`.");
    let _ = writeln!(s, "pub const TOL: [f64; 2] = [{TOL_F64:?}, {TOL_F32:?}];");
    let _ = writeln!(s, "/// Heights in metres, row-major (row 0 north).");
    let _ = writeln!(s, "#[rustfmt::skip]");
    let _ = writeln!(s, "pub static HEIGHTS: [i16; {}] = [", ROWS * COLS);
    for row in dem.heights.chunks(16) {
        let line: Vec<String> = row.iter().map(|&h| format!("{}", h as i16)).collect();
        let _ = writeln!(s, "    {},", line.join(", "));
    }
    s.push_str("];\n\n");
    s.push_str("/// A ray (unit direction, exact in `f32`) and the oracle's `t` of its first hit (`None`: no hit).\n");
    s.push_str("pub struct CropRay {\n    /// Origin, ECEF metres.\n    pub origin: [f64; 3],\n");
    s.push_str("    /// Direction (unit).\n    pub dir: [f64; 3],\n    /// The oracle's answer.\n");
    s.push_str("    pub t: Option<f64>,\n}\n\n");
    s.push_str("/// The rays.\n#[rustfmt::skip]\npub static RAYS: [CropRay; ");
    let _ = writeln!(s, "{}] = [", rays.len());
    for (r, t) in rays.iter().zip(t) {
        let _ = writeln!(
            s,
            "    CropRay {{ origin: {:?}, dir: {:?}, t: {:?} }},",
            r.origin, r.dir, t
        );
    }
    s.push_str("];\n");
    s
}

fn target_file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../kernel/qemu-smoke/src/dem_crop.rs")
}

#[test]
fn qemu_smoke_trinidad_crop_matches_the_oracle_and_the_host_kernel() {
    let dem = crop();
    assert!(
        dem.heights
            .iter()
            .all(|h| h.is_finite() && h.fract() == 0.0 && h.abs() < 32767.0)
    );
    let rays = rays(&dem);
    let oracle = TerrainOracle::new(&dem);
    let truth: Vec<Option<f64>> = rays.iter().map(|r| oracle.pick(r).map(|h| h.t)).collect();
    // The cases the smoke test needs: hits next to the edge and corner vertices, a hit from below, a miss.
    assert_eq!(
        truth.iter().filter(|t| t.is_some()).count(),
        rays.len() - 1,
        "{truth:?}"
    );
    assert!(truth.last().is_some_and(Option::is_none));
    for (precision, got, tol) in [
        ("f64", kernel_t::<f64>(&dem, &rays), TOL_F64),
        ("f32", kernel_t::<f32>(&dem, &rays), TOL_F32),
    ] {
        let mut worst = 0.0_f64;
        for (k, (g, w)) in got.iter().zip(&truth).enumerate() {
            let ok = match (g, w) {
                (None, None) => true,
                (Some(g), Some(w)) => {
                    worst = worst.max((g - w).abs());
                    (g - w).abs() <= tol / 4.0
                }
                _ => false,
            };
            assert!(
                ok,
                "{precision} ray {k}: kernel {g:?}, oracle {w:?} (a quarter of the tolerance {tol})"
            );
        }
        println!(
            "{precision}: {} rays, worst |t − t_oracle| {worst:.3e} m",
            rays.len()
        );
    }
    let text = render(&dem, &rays, &truth);
    let path = target_file();
    if std::env::var_os("CURVICAST_UPDATE_SMOKE").is_some() {
        std::fs::write(&path, &text).expect("write dem_crop.rs");
    } else {
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text,
            "{} is stale: run with CURVICAST_UPDATE_SMOKE=1",
            path.display()
        );
    }
}
