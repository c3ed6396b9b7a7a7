//! The real DEMs shipped with the project (`host-tests/data/`, see its README): the USGS 3″ Trinidad quadrangle
//! and the ETOPO 20′ global relief, as [`Dem`] models with the contract's surface.
//!
//! They are stored losslessly in a small self-describing format of our own, `.dem.cc` (no compression crate
//! needed), which `curvicast pick --dem` reads with the georeference from its header:
//!
//! ```text
//! magic  b"CCDEM2\0\0"
//! rows u32 LE, cols u32 LE, scale u32 LE     heights are integers q with h = q / scale exactly
//! a f64 LE, b f64 LE                         ellipsoid semi-axes (m)
//! lat0, lon0, dlat, dlon f64 LE              grid nodes in degrees, as in TERRAIN.json
//! nodata i64 LE                              the q of a missing vertex, or i64::MIN when none is missing
//! fnv u64 LE                                 FNV-1a 64 of the decoded heights as little-endian f32 bytes
//! rows·cols residuals, zigzag LEB128         q(i,j) − q(i,j−1), or q(i,0) − q(i−1,0), or q(0,0)
//! ```
//!
//! Decoding checks the checksum, so the heights the kernel, the oracle and the baselines see are bit for bit the
//! `f32` values of the source files (a missing vertex decodes as `f32::NAN`), and checks the georeference as
//! [`Dem::new`] does. The first version, `CCDEM1`, had no georeference in its header; it is rejected with a
//! message saying to re-encode it (`cargo run -p curvicast-host --example pack_dem`).

use super::terrain::{Dem, WGS84_A, WGS84_B};
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"CCDEM2\0\0";
/// Header bytes before the residuals: magic, three u32, six f64, the nodata i64 and the checksum.
const HEADER: usize = 8 + 3 * 4 + 6 * 8 + 8 + 8;
/// The nodata field's value when no vertex is missing.
const NO_NODATA: i64 = i64::MIN;
/// Largest |q| accepted, so that every q and every residual is exact in f64 and i64.
const Q_MAX: f64 = 4_503_599_627_370_496.0; // 2^52

/// FNV-1a 64 over the little-endian bytes of `heights`.
pub fn fnv1a_f32(heights: &[f32]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for v in heights {
        for b in v.to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// The residual of vertex `k` is taken against this earlier vertex's q (0 for the first vertex).
fn predictor(q: &[i64], k: usize, cols: usize) -> i64 {
    if k % cols != 0 {
        q[k - 1]
    } else if k >= cols {
        q[k - cols]
    } else {
        0
    }
}

/// Encodes a DEM whose present heights are all multiples of `1/scale`, with its ellipsoid and grid; missing
/// (NaN) vertices get a nodata q below every present one.
pub fn encode(dem: &Dem, scale: u32) -> Result<Vec<u8>, String> {
    let (rows, cols) = (dem.rows, dem.cols);
    if scale == 0 {
        return Err("scale must be positive".into());
    }
    if dem.heights.len() != rows * cols || cols == 0 {
        return Err(format!(
            "expected {} heights, got {}",
            rows * cols,
            dem.heights.len()
        ));
    }
    let present: Vec<Option<i64>> = dem
        .heights
        .iter()
        .enumerate()
        .map(|(k, &h)| {
            let x = f64::from(h) * f64::from(scale);
            if h.is_nan() {
                Ok(None)
            } else if x.abs() <= Q_MAX
                && x == x.round()
                && ((x as i64 as f64 / f64::from(scale)) as f32).to_bits() == h.to_bits()
            {
                // The bit comparison is decode's own conversion: it also turns away -0.0, which would decode as +0.0.
                Ok(Some(x as i64))
            } else {
                Err(format!(
                    "height {h:?} at index {k} is not stored exactly as a multiple of 1/{scale}"
                ))
            }
        })
        .collect::<Result<_, _>>()?;
    let nodata = if present.contains(&None) {
        present.iter().flatten().fold(0, |m, &v| m.min(v)) - 1
    } else {
        NO_NODATA
    };
    let q: Vec<i64> = present.iter().map(|v| v.unwrap_or(nodata)).collect();
    let decoded: Vec<f32> = dem
        .heights
        .iter()
        .map(|&h| if h.is_nan() { f32::NAN } else { h })
        .collect();
    let mut out = Vec::with_capacity(q.len() + HEADER);
    out.extend_from_slice(MAGIC);
    for v in [rows as u32, cols as u32, scale] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for v in [dem.a, dem.b, dem.lat0, dem.lon0, dem.dlat, dem.dlon] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&nodata.to_le_bytes());
    out.extend_from_slice(&fnv1a_f32(&decoded).to_le_bytes());
    for k in 0..q.len() {
        let r = q[k] - predictor(&q, k, cols);
        let mut z = ((r << 1) ^ (r >> 63)) as u64;
        loop {
            let byte = (z & 0x7f) as u8;
            z >>= 7;
            if z == 0 {
                out.push(byte);
                break;
            }
            out.push(byte | 0x80);
        }
    }
    Ok(out)
}

/// A `.dem.cc` file's contents as stored, before any check of the georeference: the grid's shape, the header's
/// semi-axes and `(lat0, lon0, dlat, dlon)`, and the decoded values (NaN where missing).
#[derive(Debug, Clone, PartialEq)]
pub struct Packed {
    /// Rows and columns.
    pub shape: (usize, usize),
    /// The ellipsoid's semi-axes `a`, `b` (m).
    pub axes: (f64, f64),
    /// `(lat0, lon0, dlat, dlon)` in degrees.
    pub georeference: (f64, f64, f64, f64),
    /// The values, row-major, bit for bit those encoded (checked by the checksum).
    pub values: Vec<f32>,
}

/// Decodes [`encode`]'s format into a [`Dem`] with the header's ellipsoid and grid, checking the checksum and
/// the georeference; every error is one line.
pub fn decode(bytes: &[u8]) -> Result<Dem, String> {
    let p = decode_packed(bytes)?;
    Dem::new(p.axes.0, p.axes.1, p.georeference, p.shape, p.values, None)
        .map_err(|m| format!("invalid georeference or heights in the CCDEM2 file: {m}"))
}

/// Decodes [`encode`]'s format, checking the header's size and the checksum but not the georeference: for
/// gridded data other than a DEM stored the same way (the ocean temperature levels, stacked by depth).
pub fn decode_packed(bytes: &[u8]) -> Result<Packed, String> {
    if bytes.starts_with(b"CCDEM1") {
        return Err(
            "a CCDEM1 file, whose header holds no georeference: re-encode it as CCDEM2 \
                    (cargo run -p curvicast-host --example pack_dem)"
                .into(),
        );
    }
    if !bytes.starts_with(MAGIC) {
        return Err("not a CCDEM2 file (bad magic)".into());
    }
    let head = bytes.get(..HEADER).ok_or_else(|| {
        format!(
            "truncated header: {} bytes, a CCDEM2 header has {HEADER}",
            bytes.len()
        )
    })?;
    let word = |o: usize| -> [u8; 8] {
        let mut w = [0u8; 8];
        w.copy_from_slice(&head[o..o + 8]);
        w
    };
    let u32_at = |o: usize| u32::from_le_bytes([head[o], head[o + 1], head[o + 2], head[o + 3]]);
    let f64_at = |k: usize| f64::from_le_bytes(word(20 + 8 * k));
    let (rows, cols, scale) = (u32_at(8) as usize, u32_at(12) as usize, u32_at(16));
    let (a, b) = (f64_at(0), f64_at(1));
    let geo = (f64_at(2), f64_at(3), f64_at(4), f64_at(5));
    let nodata = i64::from_le_bytes(word(68));
    let want = u64::from_le_bytes(word(76));
    if scale == 0 {
        return Err("scale 0 in the header".into());
    }
    let data = &bytes[HEADER..];
    let n = rows
        .checked_mul(cols)
        .filter(|&n| n <= data.len())
        .ok_or_else(|| {
            format!(
                "truncated data: the header says {rows} x {cols} heights, {} bytes follow",
                data.len()
            )
        })?;
    let mut q = Vec::with_capacity(n);
    let mut it = data.iter();
    for k in 0..n {
        let mut z: u64 = 0;
        let mut shift = 0;
        loop {
            let b = *it.next().ok_or("truncated data")?;
            if shift > 63 {
                return Err("corrupt varint".into());
            }
            z |= u64::from(b & 0x7f) << shift;
            shift += 7;
            if b & 0x80 == 0 {
                break;
            }
        }
        let r = (z >> 1) as i64 ^ -((z & 1) as i64);
        let v = predictor(&q, k, cols)
            .checked_add(r)
            .ok_or("corrupt data: a height overflows")?;
        q.push(v);
    }
    if it.next().is_some() {
        return Err("trailing bytes after the data".into());
    }
    let heights: Vec<f32> = q
        .iter()
        .map(|&v| {
            if v == nodata {
                f32::NAN
            } else {
                (v as f64 / f64::from(scale)) as f32
            }
        })
        .collect();
    if fnv1a_f32(&heights) != want {
        return Err("checksum mismatch: the decoded heights differ from the source".into());
    }
    Ok(Packed {
        shape: (rows, cols),
        axes: (a, b),
        georeference: geo,
        values: heights,
    })
}

/// The directory of the shipped data (`host-tests/data`).
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

/// Decodes a shipped file and checks that its header carries the documented georeference on WGS84.
fn load(name: &str, (lat0, lon0, dlat, dlon): (f64, f64, f64, f64)) -> anyhow::Result<Dem> {
    let path = data_dir().join(name);
    let bytes = std::fs::read(&path)
        .map_err(|e| anyhow::anyhow!("{}: cannot read: {e}", path.display()))?;
    let dem = decode(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    anyhow::ensure!(
        (dem.a, dem.b, dem.lat0, dem.lon0, dem.dlat, dem.dlon)
            == (WGS84_A, WGS84_B, lat0, lon0, dlat, dlon),
        "{}: the header's georeference differs from the documented one",
        path.display()
    );
    Ok(dem)
}

/// The USGS 3-arc-second Trinidad quadrangle DEM (Colorado / New Mexico): 1201 × 2401 grid nodes from 38°N
/// 106°W (row 0, north) to 37°N 104°W, spacing 1/1200°, integer meters 1359–4322 (Blanca Peak) on WGS84.
pub fn trinidad() -> anyhow::Result<Dem> {
    load(
        "trinidad_dem/trinidad.dem.cc",
        (38.0, -106.0, -1.0 / 1200.0, 1.0 / 1200.0),
    )
}

/// The ETOPO 20-arc-minute global relief: 540 × 1081 cell centres from 89.8333°N (row 0) to 89.8333°S, 1/3°
/// spacing, columns from 20.1667°E eastward, the last column repeating the first (lon0 + 360°) so that the surface
/// closes across the seam; meters (negative below sea level) on WGS84. The polar caps above |lat| = 89.8333° are
/// not covered by any cell.
pub fn etopo20() -> anyhow::Result<Dem> {
    load(
        "etopo20/etopo20.dem.cc",
        (90.0 - 1.0 / 6.0, 20.0 + 1.0 / 6.0, -1.0 / 3.0, 1.0 / 3.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small_dem(rows: usize, cols: usize) -> Dem {
        let h: Vec<f32> = (0..rows * cols)
            .map(|k| ((k * 7919 % 4001) as f32 - 2000.0) / 16.0)
            .collect();
        Dem::new(
            6_378_000.0,
            6_357_000.0,
            (37.5, -118.25, -0.125, 0.0625),
            (rows, cols),
            h,
            None,
        )
        .unwrap()
    }

    #[test]
    fn codec_round_trips_heights_and_georeference_and_detects_corruption() {
        let dem = small_dem(7, 9);
        let bytes = encode(&dem, 16).unwrap();
        assert_eq!(&bytes[..8], b"CCDEM2\0\0");
        assert_eq!(decode(&bytes).unwrap(), dem);
        let mut bad = bytes.clone();
        let last = bad.len() - 1;
        bad[last] ^= 0x02;
        assert!(decode(&bad).unwrap_err().contains("checksum"));
        assert!(
            encode(&dem, 8).is_err(),
            "1/16 steps are not multiples of 1/8"
        );
        let mut negative_zero = dem.clone();
        negative_zero.heights[3] = -0.0;
        assert!(encode(&negative_zero, 16).unwrap_err().contains("-0.0"));
    }

    #[test]
    fn codec_round_trips_missing_vertices_as_nodata() {
        let mut dem = small_dem(4, 5);
        dem.heights[0] = f32::NAN;
        dem.heights[13] = f32::NAN;
        let back = decode(&encode(&dem, 16).unwrap()).unwrap();
        let bits = |d: &Dem| d.heights.iter().map(|h| h.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&dem));
        assert_eq!((back.height(0, 0), back.height(2, 3)), (None, None));
        assert_eq!(back.height(3, 4), dem.height(3, 4));
    }

    #[test]
    fn header_with_bad_georeference_or_truncated_is_rejected_in_one_line() {
        let bytes = encode(&small_dem(3, 4), 16).unwrap();
        let with = |offset: usize, v: f64| {
            let mut b = bytes.clone();
            b[offset..offset + 8].copy_from_slice(&v.to_le_bytes());
            decode(&b).unwrap_err()
        };
        // a, b, lat0, lon0, dlat, dlon at bytes 20, 28, .., 60.
        assert!(with(60, -0.0625).contains("dlon must be positive"));
        assert!(with(60, 0.0).contains("dlon must be positive"));
        assert!(with(60, f64::NAN).contains("dlon must be a finite"));
        assert!(with(36, f64::NAN).contains("lat0 must be a finite"));
        assert!(with(52, 0.0).contains("dlat must be nonzero"));
        assert!(with(28, 7e6).contains("semi-axes"));
        assert!(
            decode(&bytes[..50])
                .unwrap_err()
                .contains("truncated header")
        );
        let mut huge = bytes.clone();
        huge[8..16].copy_from_slice(&[0xff; 8]);
        assert!(decode(&huge).unwrap_err().contains("truncated data"));
        let mut v1 = bytes.clone();
        v1[5] = b'1';
        assert!(decode(&v1).unwrap_err().contains("re-encode"));
        for e in [with(60, f64::NAN), decode(&bytes[..9]).unwrap_err()] {
            assert!(!e.contains('\n'), "{e}");
        }
    }

    #[test]
    fn shipped_dems_decode_with_documented_extremes() {
        let t = trinidad().unwrap();
        assert_eq!((t.rows, t.cols), (1201, 2401));
        assert_eq!(t.height_range(), Some((1359.0, 4322.0)));
        let e = etopo20().unwrap();
        assert_eq!((e.rows, e.cols), (540, 1081));
        assert_eq!(e.height_range(), Some((-9026.625, 6228.8125)));
        // The checksums of the source float32 files (README: their SHA-256 are those of the original files).
        assert_eq!(fnv1a_f32(&t.heights), 0xb0b8_a600_ba8b_0d18);
        assert_eq!(fnv1a_f32(&e.heights), 0x4ca7_c4da_43ce_539b);
        for i in 0..e.rows {
            assert_eq!(e.height(i, 0), e.height(i, 1080), "row {i} wraps");
        }
    }
}
