//! Writes the shipped GeoTIFF crop of the Trinidad DEM (`host-tests/data/trinidad_dem/blanca_crop.tif`, see the
//! data README): `cargo run --release --example write_geotiff_crop -- OUT.tif`. Rows 444..572 and columns
//! 553..681 of the 3″ grid (128 × 128 nodes around Blanca Peak), `i16` meters, pixel-is-point, EPSG:4326.

use curvicast_cli::formats::dem_files::{RasterType, read_dem, write_geotiff_i16};
use curvicast_cli::formats::real_dem::trinidad;

/// The crop's rows and columns in the Trinidad grid.
const ROWS: std::ops::Range<usize> = 444..572;
const COLS: std::ops::Range<usize> = 553..681;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let [_, out] = args.as_slice() else {
        anyhow::bail!("usage: write_geotiff_crop OUT.tif");
    };
    let dem = trinidad()?;
    let path = std::path::Path::new(out);
    write_geotiff_i16(&dem, ROWS, COLS, RasterType::PixelIsPoint, path)
        .map_err(anyhow::Error::msg)?;
    let back = read_dem(path)?;
    for (k, h) in back.heights.iter().enumerate() {
        let (i, j) = (ROWS.start + k / back.cols, COLS.start + k % back.cols);
        anyhow::ensure!(dem.height(i, j) == Some(*h), "sample ({i}, {j}) differs");
    }
    anyhow::ensure!(
        (back.lat0, back.lon0) == (dem.lat(ROWS.start), dem.lon(COLS.start)),
        "georeference differs"
    );
    println!(
        "{out}: {} bytes, {} x {} heights",
        std::fs::metadata(path)?.len(),
        back.rows,
        back.cols
    );
    Ok(())
}
