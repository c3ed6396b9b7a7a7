//! A fixed picking workload for instruction counting (callgrind): one of the report's terrain scenes — the Trinidad
//! DEM (1201 × 2401 vertices), or with `dem=synthetic` the quick report's synthetic fractal DEM (1024 × 1024) —
//! under the host's `DemStorage` with node boxes and leaf blocks of `BLOCK × BLOCK` cells, and the report's rays
//! from a camera 2 km above the ground or from orbit, picked `passes` times.
//!
//! ```sh
//! cargo build --release -p curvicast-host --example pick_count
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/pick_count orbit 8 2000 1
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/pick_count orbit 8 2000 3
//! ```
//!
//! `host-tests/examples/pick_phases.sh` runs this under callgrind on the report's Trinidad rows and splits the
//! instructions per pick by phase (set-up, quads, box tests, leaf cells, triangles, refinement, geodetic output).
//!
//! The difference of the two totals, divided by `(3 − 1) · N`, is the instructions per pick (`Picker::pick`: the
//! traversal, the refinement and the geodetic coordinates); loading the DEM, building the tree and forming the
//! rays cancel out.
//!
//! Arguments: `RAYS` (`camera`, `orbit`, or `random`: the terrain oracle's random rays from above, half of them
//! with a finite `t_max`), `BLOCK` (cells per leaf side), `N` (rays), `PASSES`, and optionally `multires`: a
//! multi-resolution tree, full resolution only over the middle ninth of the DEM and blocks two levels coarser
//! elsewhere, so that coarse cells are stitched to finer ones; optionally `dem=trinidad` (the default) or
//! `dem=synthetic`; and optionally which of the storage's caches
//! ([`TerrainCaches`]) the picker sees, to measure what each saves: `caches=all` (the default), `no-trig` (no
//! per-row and per-column sines and cosines), `no-dd` (no double-double parallels and meridians), `no-boxes` (no
//! node boxes, so no leaf windows either: the spheroidal volumes, each built on every visit), `no-windows` (node
//! boxes, but each leaf walked whole), `bounds` (no node boxes, the volumes cached per node) or `none`. The last line printed is a checksum of every
//! answer of the first pass (each hit's `t`, ECEF point, geodetic coordinates, cell, level and stride, bit for
//! bit), for comparing two builds of the kernel.

use curvicast::dd::Dd;
use curvicast::geodesy::{Ellipsoid, HeightQuadBounds};
use curvicast::ray::Ray;
use curvicast::terrain::boxes::NodeBox;
use curvicast::terrain::windows::WindowBox;
use curvicast::terrain::{
    Grid, Node, NodeId, Parallel, PickStats, Picker, TerrainCaches, TerrainStorage, quad_bounds,
};
use curvicast_cli::formats::real_dem;
use curvicast_cli::storage::{DemStorage, MultiRes};
use curvicast_host::scenes::terrain_cases::{
    TerrainKind, camera_rays, orbit_rays, random_rays, synthetic,
};
use std::hash::{DefaultHasher, Hash, Hasher};
use std::hint::black_box;

fn main() -> anyhow::Result<()> {
    let mut args: Vec<String> = std::env::args().collect();
    let mut option = |name: &str, default: &str| match args.iter().position(|a| a.starts_with(name))
    {
        Some(k) => args.remove(k)[name.len()..].to_string(),
        None => default.to_string(),
    };
    let caches = option("caches=", "all");
    let dem_name = option("dem=", "trinidad");
    let (kind, block, n, passes, multires) = match args.as_slice() {
        [_, kind, block, n, passes] => (kind, block, n, passes, false),
        [_, kind, block, n, passes, tree] if tree == "multires" => (kind, block, n, passes, true),
        _ => anyhow::bail!(
            "usage: pick_count camera|orbit|random BLOCK N PASSES [multires] [dem=trinidad|synthetic] [caches=all|no-trig|no-dd|no-boxes|no-windows|bounds|none]"
        ),
    };
    let (block, n, passes): (usize, usize, usize) = (block.parse()?, n.parse()?, passes.parse()?);
    let dem = match dem_name.as_str() {
        "trinidad" => real_dem::trinidad()?,
        "synthetic" => synthetic(
            TerrainKind::Fractal,
            (36.0, -118.0, -1.0 / 1200.0, 1.0 / 1200.0),
            (1024, 1024),
            42,
        ),
        other => anyhow::bail!("unknown DEM {other:?} (trinidad or synthetic)"),
    };
    let specs = match kind.as_str() {
        "camera" => camera_rays(&dem, n, 2000.0, 1),
        "orbit" => orbit_rays(&dem, n, 2),
        "random" => random_rays(&dem, n, 3),
        other => anyhow::bail!("unknown ray set {other:?} (camera, orbit or random)"),
    };
    let rays = specs
        .iter()
        .map(|r| Ray::new(r.origin, r.dir)?.with_interval(r.t_min, r.t_max_or_inf()))
        .collect::<Result<Vec<Ray<f64>>, _>>()?;
    let storage = if multires {
        let (lat, lon) = (dem.lat(dem.rows / 2), dem.lon(dem.cols / 2));
        let (dlat, dlon) = (
            dem.dlat.abs() * dem.rows as f64 / 6.0,
            dem.dlon * dem.cols as f64 / 6.0,
        );
        let shape = MultiRes {
            fine_region: Some([lat - dlat, lat + dlat, lon - dlon, lon + dlon]),
            coarse_level: 2,
        };
        DemStorage::multi_resolution(&dem, block, shape)
    } else {
        DemStorage::new(&dem, block)
    };
    let (hits, errors, checksum) = match caches.as_str() {
        "all" => run(&Caches::<ALL>::of(&storage), &rays, passes)?,
        "no-trig" => run(&Caches::<{ ALL & !TRIG }>::of(&storage), &rays, passes)?,
        "no-dd" => run(&Caches::<{ ALL & !DD }>::of(&storage), &rays, passes)?,
        "no-boxes" => run(
            &Caches::<{ ALL & !BOXES & !WINDOWS }>::of(&storage),
            &rays,
            passes,
        )?,
        "no-windows" => run(&Caches::<{ ALL & !WINDOWS }>::of(&storage), &rays, passes)?,
        "bounds" => run(
            &Caches::<{ ALL & !BOXES | BOUNDS }>::of(&storage),
            &rays,
            passes,
        )?,
        "none" => run(&Caches::<0>::of(&storage), &rays, passes)?,
        other => anyhow::bail!("unknown caches variant {other:?}"),
    };
    println!(
        "{kind}, block {block}, caches {caches}: {n} rays × {passes} passes, {hits} hits, {errors} errors"
    );
    println!("checksum {checksum:016x}");
    Ok(())
}

/// Picks every ray `passes` times: (hits, errors, checksum of the first pass's answers).
fn run<S: TerrainCaches<f64>>(
    storage: &S,
    rays: &[Ray<f64>],
    passes: usize,
) -> anyhow::Result<(usize, usize, u64)> {
    let picker: Picker<'_, f64, S> = Picker::new(storage)?;
    let (mut hits, mut errors) = (0usize, 0usize);
    let mut checksum = DefaultHasher::new();
    let mut stats = PickStats::default();
    for pass in 0..passes {
        for ray in rays {
            let answer = black_box(picker.pick_with_stats(black_box(ray), &mut stats));
            hits += usize::from(matches!(answer, Ok(Some(_))));
            errors += usize::from(answer.is_err());
            if pass == 0 {
                match answer {
                    Ok(Some(h)) => {
                        [
                            h.t, h.ecef[0], h.ecef[1], h.ecef[2], h.lat_deg, h.lon_deg, h.h,
                        ]
                        .map(f64::to_bits)
                        .hash(&mut checksum);
                        (h.cell, h.level, h.stride).hash(&mut checksum);
                    }
                    Ok(None) => 0u8.hash(&mut checksum),
                    Err(e) => e.to_string().hash(&mut checksum),
                }
            }
        }
    }
    let per_pick = |x: u32| f64::from(x) / (rays.len() * passes).max(1) as f64;
    println!(
        "per pick: {:.2} quads visited, {:.2} triangle pairs visited, {:.2} triangles tested",
        per_pick(stats.quads_visited),
        per_pick(stats.triangle_pairs_visited),
        per_pick(stats.triangles_tested)
    );
    Ok((hits, errors, checksum.finish()))
}

const TRIG: u8 = 1;
const DD: u8 = 2;
const BOXES: u8 = 4;
const BOUNDS: u8 = 8;
const WINDOWS: u8 = 16;
const ALL: u8 = TRIG | DD | BOXES | WINDOWS;

/// The host's storage with only the caches of `M` (bits [`TRIG`], [`DD`], [`BOXES`], [`BOUNDS`]); the others
/// fall back to the trait's defaults, which compute the value on every call.
struct Caches<'s, 'd, const M: u8> {
    base: &'s DemStorage<'d>,
    /// Each node's volume, when `M` has [`BOUNDS`] (what [`TerrainCaches::cached_bounds`] must return).
    bounds: Vec<Option<HeightQuadBounds<f64>>>,
}

impl<'s, 'd, const M: u8> Caches<'s, 'd, M> {
    fn of(base: &'s DemStorage<'d>) -> Self {
        let bounds = if M & BOUNDS != 0 {
            let (e, g) = (base.ellipsoid(), base.grid());
            (0..base.node_count())
                .map(|k| {
                    let node = base.node(NodeId(u32::try_from(k).ok()?))?;
                    quad_bounds(&e, &g, &node).ok().flatten()
                })
                .collect()
        } else {
            Vec::new()
        };
        Caches { base, bounds }
    }
}

impl<const M: u8> TerrainStorage<f64> for Caches<'_, '_, M> {
    fn ellipsoid(&self) -> Ellipsoid<f64> {
        self.base.ellipsoid()
    }
    fn grid(&self) -> Grid<f64> {
        self.base.grid()
    }
    fn zone_count(&self) -> usize {
        TerrainStorage::<f64>::zone_count(self.base)
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        TerrainStorage::<f64>::zone(self.base, k)
    }
    fn node(&self, id: NodeId) -> Option<Node<f64>> {
        self.base.node(id)
    }
    fn height(&self, i: u32, j: u32) -> Option<f64> {
        self.base.height(i, j)
    }
    fn is_resident(&self, id: NodeId) -> bool {
        TerrainStorage::<f64>::is_resident(self.base, id)
    }
    fn block_stride(&self, id: NodeId) -> u32 {
        TerrainStorage::<f64>::block_stride(self.base, id)
    }
}

impl<const M: u8> TerrainCaches<f64> for Caches<'_, '_, M> {
    fn row_sin_cos(&self, i: u32) -> (f64, f64) {
        if M & TRIG != 0 {
            self.base.row_sin_cos(i)
        } else {
            curvicast::geodesy::sin_cos_deg(self.grid().lat_deg(i))
        }
    }
    fn col_sin_cos(&self, j: u32) -> (f64, f64) {
        if M & TRIG != 0 {
            self.base.col_sin_cos(j)
        } else {
            curvicast::geodesy::sin_cos_deg(self.grid().lon_deg(j))
        }
    }
    fn cached_bounds(&self, id: NodeId) -> Option<HeightQuadBounds<f64>> {
        self.bounds
            .get(usize::try_from(id.0).ok()?)
            .copied()
            .flatten()
    }
    fn row_parallel(&self, i: u32) -> Parallel<f64> {
        if M & DD != 0 {
            self.base.row_parallel(i)
        } else {
            curvicast::terrain::row_parallel(&self.ellipsoid(), &self.grid(), i)
        }
    }
    fn col_sin_cos_dd(&self, j: u32) -> (Dd<f64>, Dd<f64>) {
        if M & DD != 0 {
            self.base.col_sin_cos_dd(j)
        } else {
            curvicast::terrain::col_sin_cos_dd(&self.grid(), j)
        }
    }
    fn node_box(&self, id: NodeId) -> Option<NodeBox> {
        if M & BOXES != 0 {
            TerrainCaches::<f64>::node_box(self.base, id)
        } else {
            None
        }
    }
    fn window_boxes(&self, id: NodeId) -> &[WindowBox] {
        if M & WINDOWS != 0 {
            TerrainCaches::<f64>::window_boxes(self.base, id)
        } else {
            &[]
        }
    }
}
