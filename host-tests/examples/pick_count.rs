//! A fixed picking workload for instruction counting (callgrind): the report's terrain scene — the Trinidad DEM
//! (1201 × 2401 vertices) under the host's `DemStorage` with node boxes and leaf blocks of `BLOCK × BLOCK` cells,
//! and the report's rays from a camera 2 km above the ground or from orbit — picked `passes` times.
//!
//! ```sh
//! cargo build --release -p curvicast-host --example pick_count
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/pick_count orbit 8 2000 1
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/pick_count orbit 8 2000 3
//! ```
//!
//! The difference of the two totals, divided by `(3 − 1) · N`, is the instructions per pick (`Picker::pick`: the
//! traversal, the refinement and the geodetic coordinates); loading the DEM, building the tree and forming the
//! rays cancel out.
//!
//! Arguments: `RAYS` (`camera`, `orbit`, or `random`: the terrain oracle's random rays from above, half of them
//! with a finite `t_max`), `BLOCK` (cells per leaf side), `N` (rays), `PASSES`, and optionally `multires`: a
//! multi-resolution tree, full resolution only over the middle ninth of the DEM and blocks two levels coarser
//! elsewhere, so that coarse cells are stitched to finer ones. The last line printed is a checksum of every
//! answer of the first pass (each hit's `t`, ECEF point, geodetic coordinates, cell, level and stride, bit for
//! bit), for comparing two builds of the kernel.

use curvicast::ray::Ray;
use curvicast::terrain::Picker;
use curvicast_host::scenes::real_dem;
use curvicast_host::scenes::terrain_cases::{camera_rays, orbit_rays, random_rays};
use curvicast_host::storage::{DemStorage, MultiRes};
use std::hash::{DefaultHasher, Hash, Hasher};
use std::hint::black_box;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (kind, block, n, passes, multires) = match args.as_slice() {
        [_, kind, block, n, passes] => (kind, block, n, passes, false),
        [_, kind, block, n, passes, tree] if tree == "multires" => (kind, block, n, passes, true),
        _ => anyhow::bail!("usage: pick_count camera|orbit|random BLOCK N PASSES [multires]"),
    };
    let (block, n, passes): (usize, usize, usize) = (block.parse()?, n.parse()?, passes.parse()?);
    let dem = real_dem::trinidad()?;
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
    let picker: Picker<'_, f64, DemStorage<'_>> = Picker::new(&storage)?;
    let (mut hits, mut errors) = (0usize, 0usize);
    let mut checksum = DefaultHasher::new();
    for pass in 0..passes {
        for ray in &rays {
            let answer = black_box(picker.pick(black_box(ray)));
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
    println!("{kind}, block {block}: {n} rays × {passes} passes, {hits} hits, {errors} errors");
    println!("checksum {:016x}", checksum.finish());
    Ok(())
}
