//! A fixed picking workload for instruction counting (callgrind): the report's terrain scene — the Trinidad
//! DEM, `N` rays from orbit or from a camera 2 km above ground — picked `PASSES` times with `Picker::pick` over
//! the host's `DemStorage` (node boxes and trigonometry tables) with leaf blocks of `BLOCK × BLOCK` cells.
//!
//! ```sh
//! cargo build --release -p curvicast-host --example pick_count
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/pick_count orbit 8 2000 1
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/pick_count orbit 8 2000 3
//! ```
//!
//! The difference of the two totals divided by `(3 − 1) · N` is the instructions per pick; loading the DEM,
//! building the storage and the rays cancel out.
//!
//! Arguments: `RAYS` (`orbit` or `camera`), `BLOCK`, `N` and `PASSES`.

use curvicast::ray::Ray;
use curvicast::terrain::Picker;
use curvicast_host::scenes::real_dem;
use curvicast_host::scenes::terrain_cases::{camera_rays, orbit_rays};
use curvicast_host::storage::DemStorage;
use std::hint::black_box;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [kind, block, n, passes] = args.as_slice() else {
        anyhow::bail!("usage: pick_count orbit|camera BLOCK N PASSES");
    };
    let (block, n, passes): (usize, usize, usize) = (block.parse()?, n.parse()?, passes.parse()?);
    let dem = real_dem::trinidad()?;
    let rays = match kind.as_str() {
        "orbit" => orbit_rays(&dem, n, 2),
        "camera" => camera_rays(&dem, n, 2000.0, 1),
        other => anyhow::bail!("unknown rays {other:?}: orbit or camera"),
    };
    let rays: Vec<Ray<f64>> = rays
        .iter()
        .map(|r| Ray::new(r.origin, r.dir))
        .collect::<Result<_, _>>()?;
    let storage = DemStorage::new(&dem, block);
    let picker: Picker<'_, f64, DemStorage<'_>> = Picker::new(&storage)?;
    let mut hits = 0usize;
    for _ in 0..passes {
        for r in &rays {
            if let Ok(Some(h)) = picker.pick(black_box(r)) {
                hits += 1;
                black_box(h);
            }
        }
    }
    println!("{kind} block {block}: {n} rays × {passes} passes, {hits} hits");
    Ok(())
}
