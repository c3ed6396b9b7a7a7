//! Packs a DEM given as a `TERRAIN.json` (its heights in the `.f32` file it names, or inline) into the project's
//! lossless, self-describing `.dem.cc` format (see `curvicast_cli::formats::real_dem`), the ellipsoid and grid in
//! its header: `cargo run -p curvicast-host --example pack_dem -- TERRAIN.json SCALE OUT.dem.cc`, where every present height is a
//! multiple of `1/SCALE`.

use curvicast_cli::formats::real_dem::{decode, encode, fnv1a_f32};
use curvicast_cli::formats::terrain::load_terrain;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let [_, input, scale, output] = args.as_slice() else {
        anyhow::bail!("usage: pack_dem TERRAIN.json SCALE OUT.dem.cc");
    };
    let dem = load_terrain(std::path::Path::new(input)).map_err(|e| anyhow::anyhow!("{e}"))?;
    let packed = encode(&dem, scale.parse()?).map_err(anyhow::Error::msg)?;
    let back = decode(&packed).map_err(anyhow::Error::msg)?;
    let bits = |h: &[f32]| h.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    anyhow::ensure!(
        bits(&back.heights) == bits(&dem.heights)
            && (back.a, back.b, back.lat0, back.lon0, back.dlat, back.dlon)
                == (dem.a, dem.b, dem.lat0, dem.lon0, dem.dlat, dem.dlon),
        "round trip differs"
    );
    std::fs::write(output, &packed)?;
    println!(
        "{output}: {} bytes ({} x {} heights, FNV-1a 64 {:016x})",
        packed.len(),
        dem.rows,
        dem.cols,
        fnv1a_f32(&dem.heights)
    );
    Ok(())
}
