//! DEM files read directly by `curvicast pick --dem FILE` (command-line contract), each into the same [`Dem`]
//! model as a `TERRAIN.json` file, with the georeference taken from the file itself:
//!
//! - **SRTM `.hgt`**: 1201 × 1201 (3″) or 3601 × 3601 (1″) big-endian `i16` samples, row 0 the northern edge,
//!   grid nodes on whole degrees; the south-west corner comes from the file name (`N36W118.hgt` covers 36–37°N,
//!   118–117°W); −32768 marks a void (nodata). Other sizes, a truncated file or a name without a corner are
//!   errors.
//! - **GeoTIFF**: one band of any integer or float sample type, read by the `tiff` crate (strips or tiles,
//!   uncompressed, deflate or LZW). The georeference is the first ModelTiepoint and the ModelPixelScale (or a
//!   ModelTransformation without rotation); the GeoKey directory must say a geographic CRS in degrees
//!   (GTModelTypeGeoKey = 2, or a GeographicTypeGeoKey without a projection) — a projected or geocentric CRS,
//!   another angular unit, or a missing georeference is an error. GTRasterTypeGeoKey decides where sample (0, 0)
//!   is: pixel-is-area (the default) puts the tie point on the pixel's corner, so the first sample's centre is
//!   half a pixel in from it; pixel-is-point puts it on the sample. GDAL_NODATA marks missing samples. The
//!   ellipsoid is the CRS's (WGS84 for EPSG:4326, GRS80 for 4269/4258/4283, Clarke 1866 for 4267, or the axes of a
//!   user-defined one).
//! - **The project's own `.dem.cc`** (see [`super::real_dem`]): a `CCDEM2` header with the grid size, the
//!   ellipsoid's semi-axes, the grid nodes' `lat0, lon0, dlat, dlon` (the terms of `TERRAIN.json`) and a nodata
//!   code, then the lossless heights. A `CCDEM1` file (no georeference in it) is an error saying to re-encode it.
//!
//! Heights are taken as meters above the ellipsoid (as the contract says for `--dem`). The format is told by the
//! file's first bytes (TIFF, `CCDEM`), else by the `.hgt` extension. Every error names the file.

use super::terrain::{Dem, TerrainError, WGS84_A, WGS84_B};
use std::io::{Read, Seek};
use std::path::Path;
use tiff::tags::Tag;

fn err(file: &Path, message: impl Into<String>) -> TerrainError {
    TerrainError {
        file: file.to_path_buf(),
        message: message.into(),
    }
}

/// Reads a DEM file of any of the formats above.
pub fn read_dem(path: &Path) -> Result<Dem, TerrainError> {
    let mut f =
        std::fs::File::open(path).map_err(|e| err(path, format!("cannot open DEM file: {e}")))?;
    let mut magic = [0u8; 8];
    let n = read_up_to(&mut f, &mut magic).map_err(|e| err(path, format!("cannot read: {e}")))?;
    let magic = &magic[..n];
    if magic.starts_with(b"II*\0") || magic.starts_with(b"MM\0*") {
        f.rewind()
            .map_err(|e| err(path, format!("cannot read: {e}")))?;
        return read_geotiff(path, std::io::BufReader::new(f));
    }
    if magic.starts_with(b"II+\0") || magic.starts_with(b"MM\0+") {
        f.rewind()
            .map_err(|e| err(path, format!("cannot read: {e}")))?;
        return read_geotiff(path, std::io::BufReader::new(f));
    }
    if magic.starts_with(b"CCDEM") {
        return read_dem_cc(path);
    }
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if ext.as_deref() == Some("hgt") {
        return read_hgt(path);
    }
    Err(err(
        path,
        "unknown DEM format: expected an SRTM .hgt tile, a GeoTIFF or a .dem.cc file",
    ))
}

fn read_up_to(f: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match f.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

/// The south-west corner (latitude, longitude in whole degrees) of an SRTM tile from its file name, such as
/// `N36W118.hgt` or `s01e010.hgt` (letters in either case).
pub fn hgt_corner(path: &Path) -> Option<(i32, i32)> {
    let name = path.file_name()?.to_str()?;
    let b = name.as_bytes();
    let digits = |s: &[u8]| -> Option<i32> {
        s.iter().try_fold(0i32, |acc, &c| {
            c.is_ascii_digit().then(|| acc * 10 + i32::from(c - b'0'))
        })
    };
    let ns = match b.first()?.to_ascii_uppercase() {
        b'N' => 1,
        b'S' => -1,
        _ => return None,
    };
    let lat = ns * digits(b.get(1..3)?)?;
    let ew = match b.get(3)?.to_ascii_uppercase() {
        b'E' => 1,
        b'W' => -1,
        _ => return None,
    };
    let lon = ew * digits(b.get(4..7)?)?;
    let rest = name.get(7..)?.to_ascii_lowercase();
    (rest == ".hgt" && (-90..=89).contains(&lat) && (-180..=179).contains(&lon))
        .then_some((lat, lon))
}

/// Reads an SRTM `.hgt` tile (see the module docs).
pub fn read_hgt(path: &Path) -> Result<Dem, TerrainError> {
    let (lat, lon) = hgt_corner(path).ok_or_else(|| {
        err(
            path,
            "cannot tell the SRTM tile's south-west corner from the file name (expected a name like N36W118.hgt)",
        )
    })?;
    let bytes = std::fs::read(path).map_err(|e| err(path, format!("cannot read: {e}")))?;
    let n = match bytes.len() {
        2_884_802 => 1201,
        25_934_402 => 3601,
        len => {
            return Err(err(
                path,
                format!(
                    "{len} bytes is not an SRTM tile: expected 1201 x 1201 (2884802 bytes, 3\") or 3601 x 3601 \
                     (25934402 bytes, 1\") big-endian 16-bit samples"
                ),
            ));
        }
    };
    let heights: Vec<f32> = bytes
        .chunks_exact(2)
        .map(|c| match i16::from_be_bytes([c[0], c[1]]) {
            -32768 => f32::NAN,
            h => f32::from(h),
        })
        .collect();
    let step = 1.0 / (n - 1) as f64;
    Dem::new(
        WGS84_A,
        WGS84_B,
        (f64::from(lat) + 1.0, f64::from(lon), -step, step),
        (n, n),
        heights,
        None,
    )
    .map_err(|m| err(path, m))
}

/// Reads a `.dem.cc` file: heights, ellipsoid and grid all from the file (see [`super::real_dem`]).
pub fn read_dem_cc(path: &Path) -> Result<Dem, TerrainError> {
    let bytes = std::fs::read(path).map_err(|e| err(path, format!("cannot read: {e}")))?;
    super::real_dem::decode(&bytes).map_err(|m| err(path, m))
}

/// GeoKey ids (GeoTIFF 1.1, OGC 19-008r4 §7).
mod key {
    pub const MODEL_TYPE: u16 = 1024;
    pub const RASTER_TYPE: u16 = 1025;
    pub const GEOGRAPHIC_TYPE: u16 = 2048;
    pub const GEOG_ANGULAR_UNITS: u16 = 2054;
    pub const GEOG_ELLIPSOID: u16 = 2056;
    pub const GEOG_SEMI_MAJOR_AXIS: u16 = 2057;
    pub const GEOG_SEMI_MINOR_AXIS: u16 = 2058;
    pub const GEOG_INV_FLATTENING: u16 = 2059;
    pub const PROJECTED_CS_TYPE: u16 = 3072;
}

/// A GeoKey's value: a short stored in the directory, or doubles from GeoDoubleParams.
#[derive(Debug, Clone, PartialEq)]
enum GeoKey {
    Short(u16),
    Doubles(Vec<f64>),
    Other,
}

/// Reads the GeoKey directory (`[version, revision, minor, count, (id, location, count, value) × count]`).
fn geo_keys(dir: &[u16], doubles: &[f64]) -> Result<Vec<(u16, GeoKey)>, String> {
    let head = dir
        .get(..4)
        .ok_or("GeoKeyDirectory is shorter than its header")?;
    if head[0] != 1 {
        return Err(format!("GeoKeyDirectory version {} is not 1", head[0]));
    }
    let n = usize::from(head[3]);
    let entries = dir
        .get(4..4 + 4 * n)
        .ok_or("GeoKeyDirectory is shorter than its key count says")?;
    entries
        .chunks_exact(4)
        .map(|e| {
            let (id, loc, count, value) = (e[0], e[1], usize::from(e[2]), usize::from(e[3]));
            let v = match loc {
                0 => GeoKey::Short(e[3]),
                34736 => GeoKey::Doubles(
                    doubles
                        .get(value..value + count)
                        .ok_or_else(|| format!("GeoKey {id} points past GeoDoubleParams"))?
                        .to_vec(),
                ),
                _ => GeoKey::Other,
            };
            Ok((id, v))
        })
        .collect()
}

/// The semi-axes (a, b) of a geographic CRS's ellipsoid, from its GeoKeys.
fn geotiff_ellipsoid(keys: &[(u16, GeoKey)]) -> Result<(f64, f64), String> {
    let short = |id| {
        keys.iter().find_map(|(k, v)| match v {
            GeoKey::Short(s) if *k == id => Some(*s),
            _ => None,
        })
    };
    let double = |id| {
        keys.iter().find_map(|(k, v)| match v {
            GeoKey::Doubles(d) if *k == id => d.first().copied(),
            _ => None,
        })
    };
    const GRS80: (f64, f64) = (6_378_137.0, 6_356_752.314_140_356);
    const CLARKE_1866: (f64, f64) = (6_378_206.4, 6_356_583.8);
    match short(key::GEOGRAPHIC_TYPE) {
        Some(4326) => return Ok((WGS84_A, WGS84_B)),
        Some(4269 | 4258 | 4283) => return Ok(GRS80),
        Some(4267) => return Ok(CLARKE_1866),
        None | Some(32767) => {}
        Some(code) => {
            return Err(format!(
                "geographic CRS EPSG:{code} is not supported (known: 4326 WGS84, 4269/4258/4283 GRS80, 4267 \
                 Clarke 1866, or a user-defined ellipsoid given by its axes)"
            ));
        }
    }
    match short(key::GEOG_ELLIPSOID) {
        Some(7030) => return Ok((WGS84_A, WGS84_B)),
        Some(7019) => return Ok(GRS80),
        Some(7008) => return Ok(CLARKE_1866),
        None | Some(32767) => {}
        Some(code) => return Err(format!("ellipsoid EPSG:{code} is not supported")),
    }
    match (
        double(key::GEOG_SEMI_MAJOR_AXIS),
        double(key::GEOG_SEMI_MINOR_AXIS),
        double(key::GEOG_INV_FLATTENING),
    ) {
        (Some(a), Some(b), _) => Ok((a, b)),
        (Some(a), None, Some(0.0)) => Ok((a, a)),
        (Some(a), None, Some(f)) => Ok((a, a * (1.0 - 1.0 / f))),
        _ if short(key::GEOGRAPHIC_TYPE).is_none() && short(key::GEOG_ELLIPSOID).is_none() => {
            Err("the GeoKeys name no geographic CRS or ellipsoid".into())
        }
        _ => Err("a user-defined ellipsoid without its semi-major axis and semi-minor axis or flattening".into()),
    }
}

/// Reads a single-band geographic GeoTIFF (see the module docs).
pub fn read_geotiff<R: Read + Seek>(path: &Path, reader: R) -> Result<Dem, TerrainError> {
    let e = |m: String| err(path, m);
    let tiff_err = |what: &str, t: tiff::TiffError| err(path, format!("{what}: {t}"));
    let mut limits = tiff::decoder::Limits::default();
    limits.decoding_buffer_size = 1 << 30;
    let mut d = tiff::decoder::Decoder::new(reader)
        .map_err(|t| tiff_err("not a readable TIFF", t))?
        .with_limits(limits);
    let (w, h) = d
        .dimensions()
        .map_err(|t| tiff_err("not a readable TIFF", t))?;
    match d
        .colortype()
        .map_err(|t| tiff_err("not a readable TIFF", t))?
    {
        tiff::ColorType::Gray(_) => {}
        other => {
            return Err(e(format!(
                "a DEM GeoTIFF has one band of samples; this one is {other:?}"
            )));
        }
    }
    let find_f64s =
        |d: &mut tiff::decoder::Decoder<R>, tag| -> Result<Option<Vec<f64>>, TerrainError> {
            d.find_tag(tag)
                .map_err(|t| tiff_err("unreadable GeoTIFF tag", t))?
                .map(|v| v.into_f64_vec())
                .transpose()
                .map_err(|t| tiff_err("unreadable GeoTIFF tag", t))
        };
    let dir: Vec<u16> = d
        .find_tag(Tag::GeoKeyDirectoryTag)
        .map_err(|t| tiff_err("unreadable GeoKeyDirectory", t))?
        .ok_or_else(|| {
            e("no georeference: the TIFF has no GeoKeyDirectory, so its CRS is unknown".into())
        })?
        .into_u16_vec()
        .map_err(|t| tiff_err("unreadable GeoKeyDirectory", t))?;
    let doubles = find_f64s(&mut d, Tag::GeoDoubleParamsTag)?.unwrap_or_default();
    let keys = geo_keys(&dir, &doubles).map_err(e)?;
    let short = |id| {
        keys.iter().find_map(|(k, v)| match v {
            GeoKey::Short(s) if *k == id => Some(*s),
            _ => None,
        })
    };
    if let Some(p) = short(key::PROJECTED_CS_TYPE) {
        return Err(e(format!(
            "projected CRS (EPSG:{p}): pick needs a geographic CRS (latitude and longitude in degrees)"
        )));
    }
    match short(key::MODEL_TYPE) {
        Some(2) => {}
        None if short(key::GEOGRAPHIC_TYPE).is_some() => {}
        Some(1) => {
            return Err(e(
                "projected CRS: pick needs a geographic CRS (latitude and longitude in degrees)"
                    .into(),
            ));
        }
        Some(3) => {
            return Err(e(
                "geocentric CRS: pick needs a geographic CRS (latitude and longitude in degrees)"
                    .into(),
            ));
        }
        Some(t) => return Err(e(format!("unknown GTModelTypeGeoKey {t}"))),
        None => return Err(e("unknown CRS: the GeoKeys give no model type".into())),
    }
    if let Some(u) = short(key::GEOG_ANGULAR_UNITS)
        && u != 9102
    {
        return Err(e(format!(
            "geographic angular unit EPSG:{u} is not supported (degrees, 9102, only)"
        )));
    }
    let (a, b) = geotiff_ellipsoid(&keys).map_err(e)?;
    let pixel_is_area = match short(key::RASTER_TYPE) {
        None | Some(1) => true,
        Some(2) => false,
        Some(t) => return Err(e(format!("unknown GTRasterTypeGeoKey {t}"))),
    };
    // Where raster point (0, 0) — the corner of the first pixel — maps, and the steps along columns and rows.
    let tie = find_f64s(&mut d, Tag::ModelTiepointTag)?;
    let scale = find_f64s(&mut d, Tag::ModelPixelScaleTag)?;
    let transform = find_f64s(&mut d, Tag::ModelTransformationTag)?;
    let (lon_at_0, lat_at_0, dlon, dlat) = match (tie, scale, transform) {
        (Some(t), Some(s), _) if t.len() >= 6 && s.len() >= 2 => {
            // Raster point (t0, t1) is model point (t3, t4).
            let (sx, sy) = (s[0], s[1]);
            (t[3] - t[0] * sx, t[4] + t[1] * sy, sx, -sy)
        }
        (Some(_), Some(_), _) => {
            return Err(e(
                "ModelTiepoint needs 6 values and ModelPixelScale 3".into()
            ));
        }
        (_, _, Some(m)) if m.len() == 16 => {
            if m[1] != 0.0 || m[4] != 0.0 {
                return Err(e(
                    "ModelTransformation with rotation or shear is not supported".into(),
                ));
            }
            (m[3], m[7], m[0], m[5])
        }
        _ => {
            return Err(e(
                "no georeference: needs the ModelTiepoint and ModelPixelScale tags".into(),
            ));
        }
    };
    if !(dlon.is_finite() && dlon > 0.0 && dlat.is_finite() && dlat != 0.0) {
        return Err(e(format!(
            "pixel size must be finite with a positive longitude step, got {dlon} x {}",
            -dlat
        )));
    }
    let half = if pixel_is_area { 0.5 } else { 0.0 };
    let (lat0, lon0) = (lat_at_0 + half * dlat, lon_at_0 + half * dlon);
    let nodata: Option<f64> = match d
        .find_tag(Tag::GdalNodata)
        .map_err(|t| tiff_err("unreadable GDAL_NODATA", t))?
    {
        None => None,
        Some(v) => {
            let s = v
                .into_string()
                .map_err(|t| tiff_err("unreadable GDAL_NODATA", t))?;
            let s = s.trim_matches(|c: char| c == '\0' || c.is_whitespace());
            Some(
                s.parse::<f64>()
                    .map_err(|_| e(format!("GDAL_NODATA {s:?} is not a number")))?,
            )
        }
    };
    let image = d
        .read_image()
        .map_err(|t| tiff_err("cannot read the samples", t))?;
    // A sample equal to nodata (compared in the sample's own type) becomes NaN.
    fn conv<S: Copy + PartialEq>(v: Vec<S>, nd: Option<S>, f: impl Fn(S) -> f32) -> Vec<f32> {
        v.into_iter()
            .map(|s| if Some(s) == nd { f32::NAN } else { f(s) })
            .collect()
    }
    let int = |nd: Option<f64>| nd.filter(|x| x.fract() == 0.0);
    use tiff::decoder::DecodingResult as D;
    let heights = match image {
        D::U8(v) => conv(
            v,
            int(nodata).and_then(|x| u8::try_from(x as i64).ok()),
            f32::from,
        ),
        D::I8(v) => conv(
            v,
            int(nodata).and_then(|x| i8::try_from(x as i64).ok()),
            f32::from,
        ),
        D::U16(v) => conv(
            v,
            int(nodata).and_then(|x| u16::try_from(x as i64).ok()),
            f32::from,
        ),
        D::I16(v) => conv(
            v,
            int(nodata).and_then(|x| i16::try_from(x as i64).ok()),
            f32::from,
        ),
        D::U32(v) => conv(
            v,
            int(nodata).and_then(|x| u32::try_from(x as i64).ok()),
            |s| s as f32,
        ),
        D::I32(v) => conv(
            v,
            int(nodata).and_then(|x| i32::try_from(x as i64).ok()),
            |s| s as f32,
        ),
        D::U64(v) => conv(v, int(nodata).map(|x| x as u64), |s| s as f32),
        D::I64(v) => conv(v, int(nodata).map(|x| x as i64), |s| s as f32),
        D::F16(v) => conv(
            v.into_iter().map(|s| s.to_f32()).collect(),
            nodata.map(|x| x as f32),
            |s| s,
        ),
        D::F32(v) => conv(v, nodata.map(|x| x as f32), |s| s),
        D::F64(v) => conv(v, nodata, |s| s as f32),
    };
    Dem::new(
        a,
        b,
        (lat0, lon0, dlat, dlon),
        (h as usize, w as usize),
        heights,
        None,
    )
    .map_err(e)
}

/// How a written GeoTIFF places its samples (GTRasterTypeGeoKey).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RasterType {
    /// The tie point is the first pixel's corner; sample centres are half a pixel in (code 1).
    PixelIsArea,
    /// The tie point is the first sample (code 2).
    PixelIsPoint,
}

/// Writes rows `rows` and columns `cols` of a north-up `dem` (negative `dlat`) as a single-band `i16` GeoTIFF in
/// EPSG:4326 (deflate-compressed), with GDAL_NODATA −32768 for missing vertices. Heights must be integers in the
/// `i16` range. For tests and the shipped crop (the example `write_geotiff_crop`).
pub fn write_geotiff_i16(
    dem: &Dem,
    rows: std::ops::Range<usize>,
    cols: std::ops::Range<usize>,
    raster: RasterType,
    out: &Path,
) -> Result<(), String> {
    use tiff::encoder::{Compression, DeflateLevel, TiffEncoder, colortype::GrayI16};
    if dem.dlat >= 0.0 || dem.a != WGS84_A || dem.b != WGS84_B {
        return Err("only north-up DEMs on WGS84 are written".into());
    }
    if rows.end > dem.rows || cols.end > dem.cols || rows.len() < 2 || cols.len() < 2 {
        return Err("crop outside the DEM".into());
    }
    let mut data = Vec::with_capacity(rows.len() * cols.len());
    for i in rows.clone() {
        for j in cols.clone() {
            let v = match dem.height(i, j) {
                None => -32768,
                Some(h) if h.fract() == 0.0 && h > -32768.0 && h <= 32767.0 => h as i16,
                Some(h) => return Err(format!("height {h} at ({i}, {j}) is not an i16")),
            };
            data.push(v);
        }
    }
    let (lat, lon) = (dem.lat(rows.start), dem.lon(cols.start));
    let (tie_x, tie_y, raster_code) = match raster {
        RasterType::PixelIsPoint => (lon, lat, 2u16),
        RasterType::PixelIsArea => (lon - 0.5 * dem.dlon, lat - 0.5 * dem.dlat, 1u16),
    };
    let file = std::fs::File::create(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut enc = TiffEncoder::new(std::io::BufWriter::new(file))
        .map_err(|e| e.to_string())?
        .with_compression(Compression::Deflate(DeflateLevel::Best));
    let mut img = enc
        .new_image::<GrayI16>(cols.len() as u32, rows.len() as u32)
        .map_err(|e| e.to_string())?;
    let t = img.encoder();
    let geokeys: [u16; 16] = [
        1,
        1,
        0,
        3, // version 1.1.0, three keys
        key::MODEL_TYPE,
        0,
        1,
        2, // geographic
        key::RASTER_TYPE,
        0,
        1,
        raster_code, //
        key::GEOGRAPHIC_TYPE,
        0,
        1,
        4326, // WGS 84
    ];
    let w = |r: tiff::TiffResult<()>| r.map_err(|e| e.to_string());
    w(t.write_tag(Tag::ModelPixelScaleTag, &[dem.dlon, -dem.dlat, 0.0][..]))?;
    w(t.write_tag(
        Tag::ModelTiepointTag,
        &[0.0, 0.0, 0.0, tie_x, tie_y, 0.0][..],
    ))?;
    w(t.write_tag(Tag::GeoKeyDirectoryTag, &geokeys[..]))?;
    w(t.write_tag(Tag::GdalNodata, "-32768"))?;
    img.write_data(&data).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hgt_names_give_the_south_west_corner() {
        let c = |n: &str| hgt_corner(Path::new(n));
        assert_eq!(c("N36W118.hgt"), Some((36, -118)));
        assert_eq!(c("dir/s01e010.HGT"), Some((-1, 10)));
        assert_eq!(c("S90W180.hgt"), Some((-90, -180)));
        assert_eq!(c("N89E179.hgt"), Some((89, 179)));
        for bad in [
            "N90E000.hgt",
            "N00E180.hgt",
            "X36W118.hgt",
            "N3aW118.hgt",
            "N36W118.tif",
            "N36W118.hgt.gz",
            "N36W11.hgt",
            "",
        ] {
            assert_eq!(c(bad), None, "{bad}");
        }
    }

    #[test]
    fn geokey_directory_reads_shorts_and_doubles_and_rejects_short_directories() {
        let dir = [1, 1, 0, 2, 1024, 0, 1, 2, 2057, 34736, 1, 1];
        let keys = geo_keys(&dir, &[0.0, 6_378_000.0]).unwrap();
        assert_eq!(
            keys,
            vec![
                (1024, GeoKey::Short(2)),
                (2057, GeoKey::Doubles(vec![6_378_000.0]))
            ]
        );
        assert!(geo_keys(&dir[..10], &[0.0, 1.0]).is_err());
        assert!(geo_keys(&dir, &[0.0]).is_err(), "points past the doubles");
        assert!(geo_keys(&[2, 1, 0, 0], &[]).is_err(), "version 2");
        let user = [
            (2048, GeoKey::Short(32767)),
            (2057, GeoKey::Doubles(vec![6_378_000.0])),
            (2059, GeoKey::Doubles(vec![300.0])),
        ];
        let (a, b) = geotiff_ellipsoid(&user).unwrap();
        assert_eq!((a, b), (6_378_000.0, 6_378_000.0 * (1.0 - 1.0 / 300.0)));
    }
}
