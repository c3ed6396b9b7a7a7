//! `curvicast pick --dem FILE` (command-line contract): SRTM `.hgt`, single-band geographic GeoTIFF and the
//! project's `.dem.cc` (the georeference in its `CCDEM2` header) read with their own georeference, answering
//! exactly as `--terrain` does on the same heights; every malformed file is exit 2 with one stderr line naming it
//! and nothing on stdout.

use crate::support;

use curvicast_cli::formats::dem_files::{RasterType, read_dem, write_geotiff_i16};
use curvicast_cli::formats::real_dem::{data_dir, encode, etopo20, trinidad};
use curvicast_cli::formats::terrain::{Dem, WGS84_A, WGS84_B, geodetic_to_ecef_f64};
use std::path::{Path, PathBuf};
use support::run;

use crate::support::temp_dir as dir;

/// Rays over the DEM's area: straight down from 6 km above points between vertices, and oblique ones from 6 km
/// to 1 km above another point (ECEF, host f64).
fn rays_over(dem: &Dem, n: usize) -> String {
    let mut s = String::new();
    let (lat_span, lon_span) = (
        (dem.rows - 1) as f64 * dem.dlat,
        (dem.cols - 1) as f64 * dem.dlon,
    );
    for k in 0..n {
        let (u, v) = (
            (k as f64 * 0.618_034 + 0.13).fract(),
            (k as f64 * 0.414_214 + 0.29).fract(),
        );
        let (lat, lon) = (dem.lat0 + u * lat_span, dem.lon0 + v * lon_span);
        let p = geodetic_to_ecef_f64(dem.a, dem.b, lat, lon, 6000.0);
        let (lat2, lon2) = if k % 2 == 0 {
            (lat, lon)
        } else {
            (
                dem.lat0 + (1.0 - u) * lat_span,
                dem.lon0 + (1.0 - v) * lon_span,
            )
        };
        let q = geodetic_to_ecef_f64(dem.a, dem.b, lat2, lon2, 1000.0);
        s.push_str(&format!(
            "{{\"origin\": [{}, {}, {}], \"dir\": [{}, {}, {}]}}\n",
            p[0],
            p[1],
            p[2],
            q[0] - p[0],
            q[1] - p[1],
            q[2] - p[2]
        ));
    }
    s
}

fn hits(out: &str) -> usize {
    out.lines()
        .filter(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            v["hit"].is_object()
        })
        .count()
}

/// `--dem FILE` and `--terrain` of `same` (written as TERRAIN.json) give the same lines for the same rays.
fn assert_dem_agrees_with_terrain(dem_file: &Path, same: &Dem, d: &Path, rays: usize) {
    let json = d.join("same.json");
    same.write_terrain_json(&json).unwrap();
    let rays = rays_over(same, rays);
    let (c1, by_dem, e1) = run(&["pick", "--dem", dem_file.to_str().unwrap()], &rays);
    let (c2, by_terrain, e2) = run(&["pick", "--terrain", json.to_str().unwrap()], &rays);
    assert_eq!((c1, c2), (0, 0), "{e1} {e2}");
    assert_eq!(by_dem, by_terrain);
    let n = hits(&by_dem);
    assert!(n * 2 >= rays.lines().count(), "{n} hits: {by_dem}");
}

/// The Trinidad DEM's rows `i0..i0+rows`, columns `j0..j0+cols`.
fn trinidad_crop(i0: usize, j0: usize, rows: usize, cols: usize) -> Dem {
    let t = trinidad().unwrap();
    let mut h = Vec::with_capacity(rows * cols);
    for i in i0..i0 + rows {
        for j in j0..j0 + cols {
            h.push(t.height(i, j).unwrap());
        }
    }
    Dem::wgs84((t.lat(i0), t.lon(j0), t.dlat, t.dlon), (rows, cols), h).unwrap()
}

#[test]
fn shipped_geotiff_crop_of_trinidad_agrees_with_terrain_json_of_the_same_heights() {
    let tmp = dir("crop");
    let d = tmp.path();
    let tif = data_dir().join("trinidad_dem/blanca_crop.tif");
    let same = trinidad_crop(444, 553, 128, 128);
    assert_eq!(read_dem(&tif).unwrap(), same);
    assert_dem_agrees_with_terrain(&tif, &same, d, 200);
}

#[test]
fn geotiff_pixel_is_area_puts_the_first_sample_half_a_pixel_in_from_the_tie_point() {
    let tmp = dir("area");
    let d = tmp.path();
    let same = trinidad_crop(100, 200, 40, 50);
    let t = trinidad().unwrap();
    for raster in [RasterType::PixelIsArea, RasterType::PixelIsPoint] {
        let tif = d.join(format!("{raster:?}.tif"));
        write_geotiff_i16(&t, 100..140, 200..250, raster, &tif).unwrap();
        let back = read_dem(&tif).unwrap();
        assert_eq!(back.heights, same.heights);
        assert_eq!(
            (back.rows, back.cols, back.dlat, back.dlon),
            (40, 50, same.dlat, same.dlon)
        );
        // Pixel-is-area stores the corner (lat0 − dlat/2, lon0 − dlon/2): one rounding each way.
        assert!(
            (back.lat0 - same.lat0).abs() < 1e-12,
            "{raster:?}: {} vs {}",
            back.lat0,
            same.lat0
        );
        assert!(
            (back.lon0 - same.lon0).abs() < 1e-12,
            "{raster:?}: {} vs {}",
            back.lon0,
            same.lon0
        );
        if raster == RasterType::PixelIsPoint {
            assert_eq!((back.lat0, back.lon0), (same.lat0, same.lon0));
        }
    }
    // Read as pixel-is-point, the pixel-is-area file would be half a pixel off: 1/2400° ≈ 46 m.
    let area = read_dem(&d.join("PixelIsArea.tif")).unwrap();
    let tie_lat = same.lat0 - 0.5 * same.dlat;
    assert!((area.lat0 - tie_lat).abs() > 4e-4);
}

/// A synthetic 3″ SRTM tile `N36W118.hgt` with a void block.
fn synthetic_hgt(d: &Path) -> (PathBuf, Dem) {
    let n = 1201;
    let mut bytes = Vec::with_capacity(n * n * 2);
    let mut heights = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let void = (600..610).contains(&i) && (600..612).contains(&j);
            let h: i16 = if void {
                -32768
            } else {
                (900.0 + 400.0 * (i as f64 / 37.0).sin() * (j as f64 / 53.0).cos()).round() as i16
            };
            bytes.extend_from_slice(&h.to_be_bytes());
            heights.push(if void { f32::NAN } else { f32::from(h) });
        }
    }
    let path = d.join("N36W118.hgt");
    std::fs::write(&path, &bytes).unwrap();
    let step = 1.0 / 1200.0;
    let dem = Dem::new(
        WGS84_A,
        WGS84_B,
        (37.0, -118.0, -step, step),
        (n, n),
        heights,
        None,
    )
    .unwrap();
    (path, dem)
}

#[test]
fn srtm_hgt_tile_reads_its_corner_from_the_name_and_agrees_with_terrain_json() {
    let tmp = dir("hgt");
    let d = tmp.path();
    let (path, same) = synthetic_hgt(d);
    let back = read_dem(&path).unwrap();
    assert_eq!(
        (back.lat0, back.lon0, back.rows, back.cols),
        (37.0, -118.0, 1201, 1201)
    );
    assert_eq!(back.height(605, 605), None, "void");
    assert_eq!(back.height(0, 0), Some(900.0));
    assert_eq!(back.heights.len(), same.heights.len());
    assert!(
        back.heights
            .iter()
            .zip(&same.heights)
            .all(|(a, b)| a == b || (a.is_nan() && b.is_nan()))
    );
    assert_dem_agrees_with_terrain(&path, &same, d, 100);
    // Lower-case names and southern/eastern tiles.
    let south = d.join("s01e010.hgt");
    std::fs::copy(&path, &south).unwrap();
    let s = read_dem(&south).unwrap();
    assert_eq!((s.lat0, s.lon0, s.lat(1200)), (0.0, 10.0, -1.0));
}

#[test]
fn srtm_one_arc_second_tile_has_3601_nodes_per_side() {
    let tmp = dir("hgt1");
    let d = tmp.path();
    let path = d.join("N00E000.hgt");
    let mut bytes = vec![0u8; 3601 * 3601 * 2];
    bytes[0..2].copy_from_slice(&1234i16.to_be_bytes());
    std::fs::write(&path, &bytes).unwrap();
    let dem = read_dem(&path).unwrap();
    assert_eq!(
        (dem.rows, dem.cols, dem.dlat, dem.dlon),
        (3601, 3601, -1.0 / 3600.0, 1.0 / 3600.0)
    );
    assert_eq!(
        (dem.lat0, dem.lon0, dem.height(0, 0)),
        (1.0, 0.0, Some(1234.0))
    );
}

#[test]
fn shipped_dem_cc_files_read_with_their_own_header_as_the_shipped_loaders() {
    let tmp = dir("shipped-cc");
    let d = tmp.path();
    let file = data_dir().join("trinidad_dem/trinidad.dem.cc");
    let t = trinidad().unwrap();
    assert_eq!(read_dem(&file).unwrap(), t);
    assert_eq!(
        (t.lat0, t.lon0, t.dlat, t.dlon),
        (38.0, -106.0, -1.0 / 1200.0, 1.0 / 1200.0)
    );
    assert_dem_agrees_with_terrain(&file, &t, d, 100);
    let file = data_dir().join("etopo20/etopo20.dem.cc");
    let e = etopo20().unwrap();
    assert_eq!(read_dem(&file).unwrap(), e);
    assert_eq!(
        (e.lat0, e.lon0, e.dlat, e.dlon),
        (90.0 - 1.0 / 6.0, 20.0 + 1.0 / 6.0, -1.0 / 3.0, 1.0 / 3.0)
    );
    assert_dem_agrees_with_terrain(&file, &e, d, 100);
}

#[test]
fn dem_cc_with_missing_vertices_agrees_with_terrain_json_with_the_same_holes() {
    let tmp = dir("holes-cc");
    let d = tmp.path();
    let mut dem = trinidad_crop(444, 553, 64, 64);
    for i in 10..30 {
        for j in 20..26 {
            dem.heights[i * dem.cols + j] = f32::NAN;
        }
    }
    dem.heights[0] = f32::NAN;
    let file = d.join("holes.dem.cc");
    std::fs::write(&file, encode(&dem, 1).unwrap()).unwrap();
    let back = read_dem(&file).unwrap();
    let bits = |h: &[f32]| h.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&back.heights), bits(&dem.heights));
    assert_eq!((back.height(0, 0), back.height(15, 22)), (None, None));
    assert_dem_agrees_with_terrain(&file, &dem, d, 200);
}

/// Runs `pick --dem FILE` and checks the contract's usage error: exit 2, nothing on stdout, one stderr line that
/// names `names` and says `what`.
fn assert_bad_dem(file: &Path, names: &Path, what: &str) {
    let ray = "{\"origin\": [0, 0, 7000000], \"dir\": [0, 0, -1]}\n";
    let (code, out, err) = run(&["pick", "--dem", file.to_str().unwrap()], ray);
    assert_eq!(code, 2, "{}: {err}", file.display());
    assert!(out.is_empty(), "{out}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(names.to_str().unwrap()), "{err}");
    assert!(err.contains(what), "expected {what:?} in: {err}");
}

#[test]
fn malformed_hgt_tiles_exit_2_naming_the_file() {
    let tmp = dir("bad-hgt");
    let d = tmp.path();
    let good = vec![0u8; 1201 * 1201 * 2];
    let truncated = d.join("N36W118.hgt");
    std::fs::write(&truncated, &good[..good.len() - 1]).unwrap();
    assert_bad_dem(&truncated, &truncated, "2884801 bytes is not an SRTM tile");
    let small = d.join("N10E010.hgt");
    std::fs::write(&small, [0u8; 1000]).unwrap();
    assert_bad_dem(&small, &small, "1000 bytes is not an SRTM tile");
    for name in [
        "tile.hgt",
        "N36X118.hgt",
        "N90W118.hgt",
        "N36E180.hgt",
        "N36W118x.hgt",
    ] {
        let p = d.join(name);
        std::fs::write(&p, &good).unwrap();
        assert_bad_dem(&p, &p, "south-west corner");
    }
    let unknown = d.join("heights.bin");
    std::fs::write(&unknown, &good).unwrap();
    assert_bad_dem(&unknown, &unknown, "unknown DEM format");
    let missing = d.join("N00E000.hgt");
    assert_bad_dem(&missing, &missing, "cannot open");
}

/// A 4 × 3 GeoTIFF with the given GeoKey directory, tie point and pixel scale (each optional).
fn geotiff(path: &Path, keys: Option<&[u16]>, tie: Option<&[f64]>, scale: Option<&[f64]>) {
    use tiff::encoder::{TiffEncoder, colortype::GrayI16};
    use tiff::tags::Tag;
    let f = std::fs::File::create(path).unwrap();
    let mut enc = TiffEncoder::new(std::io::BufWriter::new(f)).unwrap();
    let mut img = enc.new_image::<GrayI16>(4, 3).unwrap();
    if let Some(k) = keys {
        img.encoder().write_tag(Tag::GeoKeyDirectoryTag, k).unwrap();
    }
    if let Some(t) = tie {
        img.encoder().write_tag(Tag::ModelTiepointTag, t).unwrap();
    }
    if let Some(s) = scale {
        img.encoder().write_tag(Tag::ModelPixelScaleTag, s).unwrap();
    }
    img.write_data(&[100i16; 12]).unwrap();
}

const TIE: &[f64] = &[0.0, 0.0, 0.0, -118.0, 37.0, 0.0];
const SCALE: &[f64] = &[0.001, 0.001, 0.0];
const GEOGRAPHIC: &[u16] = &[1, 1, 0, 2, 1024, 0, 1, 2, 2048, 0, 1, 4326];

#[test]
fn small_geotiffs_read_their_georeference_nodata_and_ellipsoid() {
    let tmp = dir("small-tif");
    let d = tmp.path();
    let p = d.join("ok.tif");
    geotiff(&p, Some(GEOGRAPHIC), Some(TIE), Some(SCALE));
    let dem = read_dem(&p).unwrap();
    // Pixel-is-area by default: the first sample is half a pixel east and south of the tie point.
    assert_eq!(
        (dem.rows, dem.cols, dem.dlat, dem.dlon),
        (3, 4, -0.001, 0.001)
    );
    assert!((dem.lat0 - 36.9995).abs() < 1e-12 && (dem.lon0 - -117.9995).abs() < 1e-12);
    assert_eq!((dem.a, dem.b), (WGS84_A, WGS84_B));
    // NAD83 is on GRS80; a user-defined ellipsoid by its axes; GDAL_NODATA makes a vertex missing.
    let nad83 = d.join("nad83.tif");
    geotiff(
        &nad83,
        Some(&[1, 1, 0, 2, 1024, 0, 1, 2, 2048, 0, 1, 4269]),
        Some(TIE),
        Some(SCALE),
    );
    assert_eq!(read_dem(&nad83).unwrap().b, 6_356_752.314_140_356);
    let nodata = d.join("nodata.tif");
    {
        use tiff::encoder::{TiffEncoder, colortype::GrayI16};
        use tiff::tags::Tag;
        let f = std::fs::File::create(&nodata).unwrap();
        let mut enc = TiffEncoder::new(f).unwrap();
        let mut img = enc.new_image::<GrayI16>(4, 3).unwrap();
        let t = img.encoder();
        t.write_tag(Tag::GeoKeyDirectoryTag, GEOGRAPHIC).unwrap();
        t.write_tag(Tag::ModelTiepointTag, TIE).unwrap();
        t.write_tag(Tag::ModelPixelScaleTag, SCALE).unwrap();
        t.write_tag(Tag::GdalNodata, "-9999").unwrap();
        img.write_data(&[1, 2, 3, 4, 5, -9999, 7, 8, 9, 10, 11, 12])
            .unwrap();
    }
    let dem = read_dem(&nodata).unwrap();
    assert_eq!((dem.height(1, 0), dem.height(1, 1)), (Some(5.0), None));
}

#[test]
fn malformed_geotiffs_exit_2_naming_the_file() {
    let tmp = dir("bad-tif");
    let d = tmp.path();
    /// File name, GeoKeys, tie point, pixel scale, and what the message says.
    type Case<'a> = (
        &'a str,
        Option<&'a [u16]>,
        Option<&'a [f64]>,
        Option<&'a [f64]>,
        &'a str,
    );
    let cases: [Case<'_>; 6] = [
        (
            "utm.tif",
            Some(&[1, 1, 0, 2, 1024, 0, 1, 1, 3072, 0, 1, 32613]),
            Some(TIE),
            Some(SCALE),
            "projected CRS (EPSG:32613)",
        ),
        (
            "nogeokeys.tif",
            None,
            Some(TIE),
            Some(SCALE),
            "no GeoKeyDirectory",
        ),
        (
            "notie.tif",
            Some(GEOGRAPHIC),
            None,
            Some(SCALE),
            "no georeference",
        ),
        (
            "radians.tif",
            Some(&[
                1, 1, 0, 3, 1024, 0, 1, 2, 2048, 0, 1, 4326, 2054, 0, 1, 9101,
            ]),
            Some(TIE),
            Some(SCALE),
            "angular unit",
        ),
        (
            "raster7.tif",
            Some(&[1, 1, 0, 3, 1024, 0, 1, 2, 1025, 0, 1, 7, 2048, 0, 1, 4326]),
            Some(TIE),
            Some(SCALE),
            "GTRasterTypeGeoKey 7",
        ),
        (
            "tokyo.tif",
            Some(&[1, 1, 0, 2, 1024, 0, 1, 2, 2048, 0, 1, 4301]),
            Some(TIE),
            Some(SCALE),
            "EPSG:4301 is not supported",
        ),
    ];
    for (name, keys, tie, scale, what) in cases {
        let p = d.join(name);
        geotiff(&p, keys, tie, scale);
        assert_bad_dem(&p, &p, what);
    }
    // A truncated file: the shipped crop cut short.
    let crop = std::fs::read(data_dir().join("trinidad_dem/blanca_crop.tif")).unwrap();
    let cut = d.join("cut.tif");
    std::fs::write(&cut, &crop[..crop.len() / 2]).unwrap();
    assert_bad_dem(&cut, &cut, "cut.tif: ");
    // Three bands are not a DEM.
    let rgb = d.join("rgb.tif");
    {
        use tiff::encoder::{TiffEncoder, colortype::RGB8};
        let f = std::fs::File::create(&rgb).unwrap();
        let mut enc = TiffEncoder::new(f).unwrap();
        enc.write_image::<RGB8>(2, 2, &[0u8; 12]).unwrap();
    }
    assert_bad_dem(&rgb, &rgb, "one band");
}

#[test]
fn malformed_dem_cc_files_exit_2_naming_the_file() {
    let tmp = dir("bad-cc");
    let d = tmp.path();
    let heights: Vec<f32> = (0..12).map(|k| 100.0 + k as f32).collect();
    let dem = Dem::wgs84((37.0, -118.0, -0.001, 0.001), (3, 4), heights).unwrap();
    let bytes = encode(&dem, 1).unwrap();
    let ok = d.join("ok.dem.cc");
    std::fs::write(&ok, &bytes).unwrap();
    assert_eq!(read_dem(&ok).unwrap(), dem);
    assert_eq!(dem.height(2, 3), Some(111.0));
    let write = |name: &str, b: &[u8]| {
        let p = d.join(name);
        std::fs::write(&p, b).unwrap();
        p
    };
    // The georeference's f64 fields a, b, lat0, lon0, dlat, dlon start at bytes 20, 28, .., 60.
    let with = |name: &str, offset: usize, v: f64| {
        let mut b = bytes.clone();
        b[offset..offset + 8].copy_from_slice(&v.to_le_bytes());
        write(name, &b)
    };
    let cut = write("cut.dem.cc", &bytes[..bytes.len() - 3]);
    assert_bad_dem(&cut, &cut, "truncated data");
    let short = write("short.dem.cc", &bytes[..40]);
    assert_bad_dem(&short, &short, "truncated header");
    let f = with("dlon-negative.dem.cc", 60, -0.001);
    assert_bad_dem(&f, &f, "dlon must be positive");
    let f = with("dlon-zero.dem.cc", 60, 0.0);
    assert_bad_dem(&f, &f, "dlon must be positive");
    let f = with("dlon-nan.dem.cc", 60, f64::NAN);
    assert_bad_dem(&f, &f, "dlon must be a finite number");
    let f = with("lat0-past-pole.dem.cc", 36, 95.0);
    assert_bad_dem(&f, &f, "outside [-90, 90]");
    let f = with("b-above-a.dem.cc", 28, 7.0e6);
    assert_bad_dem(&f, &f, "semi-axes");
    let mut v1 = bytes.clone();
    v1[5] = b'1';
    let f = write("version1.dem.cc", &v1);
    assert_bad_dem(&f, &f, "no georeference");
}

#[test]
fn dem_and_terrain_are_mutually_exclusive_and_one_is_required() {
    let tif = data_dir().join("trinidad_dem/blanca_crop.tif");
    let t = tif.to_str().unwrap();
    let (code, out, err) = run(&["pick", "--dem", t, "--terrain", "x.json"], "");
    assert_eq!((code, out.is_empty()), (2, true), "{err}");
    assert!(err.contains("--terrain") && err.contains("--dem"), "{err}");
    let (code, out, err) = run(&["pick"], "");
    assert_eq!((code, out.is_empty()), (2, true), "{err}");
    assert!(err.contains("--terrain"), "{err}");
}
