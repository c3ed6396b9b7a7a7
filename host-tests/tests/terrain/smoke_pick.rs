//! The QEMU smoke test's slanted terrain pick (`pick_case` in `kernel/qemu-smoke/src/main.rs`) is checked on the
//! target against `PEAK_SLOPE_T` and `PEAK_SLOPE_H`, written in that file. This test computes them again with the
//! independent terrain oracle (256-bit brute force over the DEM's triangles) and fails if the file disagrees.

use curvicast::geodesy::Ellipsoid;
use curvicast::vec3::V3;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::Dem;
use curvicast_host::oracle::terrain::TerrainOracle;
use std::path::PathBuf;

/// The value of `const NAME: f64 = ...;` in the smoke test's source.
fn constant(src: &str, name: &str) -> f64 {
    let key = format!("const {name}: f64 = ");
    let at = src.find(&key).unwrap_or_else(|| panic!("{name} not found")) + key.len();
    let end = at + src[at..].find(';').unwrap();
    src[at..end].trim().replace('_', "").parse().unwrap()
}

#[test]
fn smoke_slope_pick_expectation_is_the_oracles() {
    // The smoke test's DEM: 3 × 3 vertices at (10°N, 20°E), 0.01° apart, 0 m but the center vertex at 500 m.
    let mut heights = vec![0.0_f32; 9];
    heights[4] = 500.0;
    let dem = Dem::wgs84((10.0, 20.0, 0.01, 0.01), (3, 3), heights).unwrap();
    // Its ray, built as the target builds it in f64: from (10°, 20.004°, 1000 m) toward (10.01°, 20.01°, 250 m).
    let e = Ellipsoid::<f64>::wgs84();
    let from = e.geodetic_deg_to_ecef(10.0, 20.004, 1000.0);
    let to = e.geodetic_deg_to_ecef(10.01, 20.01, 250.0);
    let dir = to.minus(from);
    let hit = TerrainOracle::new(&dem)
        .pick(&RaySpec::new(from.to_array(), dir.to_array()))
        .expect("the slanted ray hits the slope");
    let h = e.ecef_to_geodetic(V3::from(hit.point)).h;
    let src = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../kernel/qemu-smoke/src/main.rs"),
    )
    .unwrap();
    let (t_file, h_file) = (
        constant(&src, "PEAK_SLOPE_T"),
        constant(&src, "PEAK_SLOPE_H"),
    );
    println!("oracle: t = {:?}, h = {h:?}", hit.t);
    assert!((t_file - hit.t).abs() <= 1e-12, "{t_file} vs {}", hit.t);
    assert!((h_file - h).abs() <= 1e-6, "{h_file} vs {h}");
    // Well inside the slope, not at its ends: a hit at 0 < h < 500 m alone would not say so much.
    assert!(h > 50.0 && h < 450.0, "{h}");
}
