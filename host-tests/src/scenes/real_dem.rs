//! The real DEMs shipped with the project (`host-tests/data/`, see its README): the USGS 3″ Trinidad quadrangle
//! and the ETOPO 20′ global relief, as [`Dem`] models with the contract's surface.
//!
//! They are stored losslessly in a small format of our own, `.dem.cc` (no compression crate needed):
//!
//! ```text
//! magic  b"CCDEM1\0\0"
//! rows u32 LE, cols u32 LE, scale u32 LE     heights are integers q with h = q / scale exactly
//! fnv u64 LE                                 FNV-1a 64 of the decoded heights as little-endian f32 bytes
//! rows·cols residuals, zigzag LEB128         q(i,j) − q(i,j−1), or q(i,0) − q(i−1,0), or q(0,0)
//! ```
//!
//! Decoding checks the checksum, so the heights the kernel, the oracle and the baselines see are bit for bit the
//! `f32` values of the source files.

use super::terrain::Dem;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"CCDEM1\0\0";

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

/// Encodes a rows × cols grid of heights that are all multiples of `1/scale` (and not NaN).
pub fn encode(rows: usize, cols: usize, scale: u32, heights: &[f32]) -> Result<Vec<u8>, String> {
    if heights.len() != rows * cols {
        return Err(format!(
            "expected {} heights, got {}",
            rows * cols,
            heights.len()
        ));
    }
    let mut out = Vec::with_capacity(heights.len() + 32);
    out.extend_from_slice(MAGIC);
    for v in [rows as u32, cols as u32, scale] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&fnv1a_f32(heights).to_le_bytes());
    let q: Vec<i64> = heights
        .iter()
        .enumerate()
        .map(|(k, &h)| {
            let x = f64::from(h) * f64::from(scale);
            if x.is_finite() && x == x.round() && (x / f64::from(scale)) as f32 == h {
                Ok(x as i64)
            } else {
                Err(format!(
                    "height {h} at index {k} is not a multiple of 1/{scale}"
                ))
            }
        })
        .collect::<Result<_, _>>()?;
    for k in 0..q.len() {
        let pred = if k % cols != 0 {
            q[k - 1]
        } else if k >= cols {
            q[k - cols]
        } else {
            0
        };
        let r = q[k] - pred;
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

/// Decodes [`encode`]'s format into (rows, cols, heights), checking the checksum.
pub fn decode(bytes: &[u8]) -> Result<(usize, usize, Vec<f32>), String> {
    let head = bytes.get(..28).ok_or("file too short for the header")?;
    if &head[..8] != MAGIC {
        return Err("not a CCDEM1 file (bad magic)".into());
    }
    let u32_at = |o: usize| u32::from_le_bytes([head[o], head[o + 1], head[o + 2], head[o + 3]]);
    let (rows, cols, scale) = (u32_at(8) as usize, u32_at(12) as usize, u32_at(16));
    let mut sum = [0u8; 8];
    sum.copy_from_slice(&head[20..28]);
    let want = u64::from_le_bytes(sum);
    let n = rows.checked_mul(cols).ok_or("grid too large")?;
    let mut q = Vec::with_capacity(n);
    let mut it = bytes[28..].iter();
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
        let pred = if k % cols != 0 {
            q[k - 1]
        } else if k >= cols {
            q[k - cols]
        } else {
            0
        };
        q.push(pred + r);
    }
    if it.next().is_some() {
        return Err("trailing bytes after the data".into());
    }
    let heights: Vec<f32> = q
        .iter()
        .map(|&v| (v as f64 / f64::from(scale)) as f32)
        .collect();
    if fnv1a_f32(&heights) != want {
        return Err("checksum mismatch: the decoded heights differ from the source".into());
    }
    Ok((rows, cols, heights))
}

/// The directory of the shipped data (`host-tests/data`).
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data")
}

fn load(name: &str) -> anyhow::Result<(usize, usize, Vec<f32>)> {
    let path = data_dir().join(name);
    let bytes = std::fs::read(&path)
        .map_err(|e| anyhow::anyhow!("{}: cannot read: {e}", path.display()))?;
    decode(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

/// The USGS 3-arc-second Trinidad quadrangle DEM (Colorado / New Mexico): 1201 × 2401 grid nodes from 38°N
/// 106°W (row 0, north) to 37°N 104°W, spacing 1/1200°, integer meters 1359–4322 (Blanca Peak) on WGS84.
pub fn trinidad() -> anyhow::Result<Dem> {
    let (rows, cols, h) = load("trinidad_dem/trinidad.dem.cc")?;
    Dem::wgs84((38.0, -106.0, -1.0 / 1200.0, 1.0 / 1200.0), (rows, cols), h)
        .map_err(anyhow::Error::msg)
}

/// The ETOPO 20-arc-minute global relief: 540 × 1081 cell centres from 89.8333°N (row 0) to 89.8333°S, 1/3°
/// spacing, columns from 20.1667°E eastward, the last column repeating the first (lon0 + 360°) so that the surface
/// closes across the seam; meters (negative below sea level) on WGS84. The polar caps above |lat| = 89.8333° are
/// not covered by any cell.
pub fn etopo20() -> anyhow::Result<Dem> {
    let (rows, cols, h) = load("etopo20/etopo20.dem.cc")?;
    Dem::wgs84(
        (90.0 - 1.0 / 6.0, 20.0 + 1.0 / 6.0, -1.0 / 3.0, 1.0 / 3.0),
        (rows, cols),
        h,
    )
    .map_err(anyhow::Error::msg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codec_round_trips_and_detects_corruption() {
        let (rows, cols) = (7, 9);
        let h: Vec<f32> = (0..rows * cols)
            .map(|k| ((k * 7919 % 4001) as f32 - 2000.0) / 16.0)
            .collect();
        let bytes = encode(rows, cols, 16, &h).unwrap();
        let (r, c, back) = decode(&bytes).unwrap();
        assert_eq!((r, c), (rows, cols));
        assert_eq!(back, h);
        let mut bad = bytes.clone();
        let last = bad.len() - 1;
        bad[last] ^= 0x02;
        assert!(decode(&bad).is_err());
        assert!(
            encode(rows, cols, 8, &h).is_err(),
            "1/16 steps are not multiples of 1/8"
        );
    }

    #[test]
    fn shipped_dems_decode_with_documented_extremes() {
        let t = trinidad().unwrap();
        assert_eq!((t.rows, t.cols), (1201, 2401));
        assert_eq!(t.height_range(), Some((1359.0, 4322.0)));
        let e = etopo20().unwrap();
        assert_eq!((e.rows, e.cols), (540, 1081));
        assert_eq!(e.height_range(), Some((-9026.625, 6228.8125)));
        for i in 0..e.rows {
            assert_eq!(e.height(i, 0), e.height(i, 1080), "row {i} wraps");
        }
    }
}
