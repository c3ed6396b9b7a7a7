//! Terrain scenes: the `TERRAIN.json` format of `curvicast pick` (command-line contract), its validation and the
//! regular latitude/longitude DEM model (the quadtree the host builds over it is in [`crate::storage`]).
//!
//! The surface (contract, and Wartell et al. §4): vertex V(i, j) is the geodetic point
//! (lat0 + i·dlat, lon0 + j·dlon, h(i, j)) converted to ECEF on the given ellipsoid; grid cell (i, j) is the two
//! triangles (V(i,j), V(i,j+1), V(i+1,j+1)) and (V(i,j), V(i+1,j+1), V(i+1,j)). A vertex whose height is the
//! file's `nodata` value or NaN makes its adjacent triangles absent; in the model such vertices are stored as NaN.
//!
//! Heights are stored as `f32` (the file format's type; inline heights are rounded to the nearest `f32` when
//! read), so the kernel, the oracle and every baseline see exactly the same numbers.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The WGS84 semi-major axis in meters.
pub const WGS84_A: f64 = 6_378_137.0;
/// The WGS84 semi-minor axis in meters (b = a(1 − f), f = 1/298.257223563).
pub const WGS84_B: f64 = 6_356_752.314_245_179;

/// An error in a terrain file: the file and what is wrong with it (printed as `FILE: message`).
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainError {
    /// The file that is wrong (the JSON file, or the heights file it names).
    pub file: PathBuf,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for TerrainError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.file.display(), self.message)
    }
}

impl std::error::Error for TerrainError {}

/// The ellipsoid of a terrain file: `"WGS84"` or `{"a": .., "b": ..}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum EllipsoidSpec {
    /// A named ellipsoid (only `"WGS84"` is known).
    Named(String),
    /// Semi-axes in meters (equatorial `a`, polar `b`, a ≥ b > 0).
    Axes {
        /// Equatorial semi-axis.
        a: f64,
        /// Polar semi-axis.
        b: f64,
    },
}

/// The `grid` object of a terrain file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridFileSpec {
    /// Latitude of row 0 (degrees).
    pub lat0: f64,
    /// Longitude of column 0 (degrees).
    pub lon0: f64,
    /// Latitude step per row (degrees, nonzero, may be negative).
    pub dlat: f64,
    /// Longitude step per column (degrees, positive).
    pub dlon: f64,
    /// Number of rows (≥ 2).
    pub rows: usize,
    /// Number of columns (≥ 2).
    pub cols: usize,
    /// Path of the little-endian `f32` heights, relative to the JSON file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heights: Option<String>,
    /// Heights inline, row-major (`null` is a missing vertex).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heights_inline: Option<Vec<Option<f64>>>,
}

/// A whole `TERRAIN.json` file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainFileSpec {
    /// The ellipsoid.
    pub ellipsoid: EllipsoidSpec,
    /// The grid.
    pub grid: GridFileSpec,
    /// The height value that marks a missing vertex (NaN always does).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nodata: Option<f64>,
}

/// A regular latitude/longitude DEM on an ellipsoid: the validated model behind a `TERRAIN.json` file.
///
/// Invariants (checked by [`Dem::new`]): `a ≥ b > 0` finite; `rows, cols ≥ 2`; `dlat ≠ 0`, `dlon > 0`, all
/// finite; every row latitude within [−90, 90]; the longitude span `(cols − 1)·dlon ≤ 360`; `heights.len() =
/// rows·cols`; every height is NaN (missing) or finite and above −b²/a (Wartell et al., Appendix A2).
#[derive(Debug, Clone, PartialEq)]
pub struct Dem {
    /// Equatorial semi-axis (m).
    pub a: f64,
    /// Polar semi-axis (m).
    pub b: f64,
    /// Latitude of row 0 (degrees).
    pub lat0: f64,
    /// Longitude of column 0 (degrees).
    pub lon0: f64,
    /// Latitude step (degrees).
    pub dlat: f64,
    /// Longitude step (degrees).
    pub dlon: f64,
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// Heights above the ellipsoid (m), row-major; NaN marks a missing vertex.
    pub heights: Vec<f32>,
}

impl Dem {
    /// Checks the invariants listed on [`Dem`] and builds the model; `nodata` values become NaN.
    pub fn new(
        a: f64,
        b: f64,
        (lat0, lon0, dlat, dlon): (f64, f64, f64, f64),
        (rows, cols): (usize, usize),
        mut heights: Vec<f32>,
        nodata: Option<f64>,
    ) -> Result<Dem, String> {
        if !(a.is_finite() && b.is_finite() && b > 0.0 && a >= b) {
            return Err(format!(
                "ellipsoid needs finite semi-axes a >= b > 0, got a = {a}, b = {b}"
            ));
        }
        for (name, v) in [
            ("lat0", lat0),
            ("lon0", lon0),
            ("dlat", dlat),
            ("dlon", dlon),
        ] {
            if !v.is_finite() {
                return Err(format!("grid.{name} must be a finite number, got {v}"));
            }
        }
        if dlat == 0.0 {
            return Err("grid.dlat must be nonzero".into());
        }
        if dlon <= 0.0 {
            return Err(format!("grid.dlon must be positive, got {dlon}"));
        }
        if rows < 2 || cols < 2 {
            return Err(format!(
                "grid needs at least 2 rows and 2 columns (one cell), got {rows} x {cols}"
            ));
        }
        if rows > u32::MAX as usize || cols > u32::MAX as usize {
            return Err(format!("grid of {rows} x {cols} is too large"));
        }
        let n = rows
            .checked_mul(cols)
            .ok_or_else(|| format!("grid of {rows} x {cols} is too large"))?;
        if heights.len() != n {
            return Err(format!(
                "expected rows*cols = {n} heights, got {}",
                heights.len()
            ));
        }
        for i in [0, rows - 1] {
            let lat = lat0 + i as f64 * dlat;
            if !(-90.0..=90.0).contains(&lat) {
                return Err(format!(
                    "row {i} is at latitude {lat}, outside [-90, 90] (lat0 = {lat0}, dlat = {dlat})"
                ));
            }
        }
        let span = (cols - 1) as f64 * dlon;
        if span > 360.0 {
            return Err(format!(
                "longitude span (cols-1)*dlon = {span} degrees exceeds 360"
            ));
        }
        let floor = -b * b / a;
        // Heights are f32 (the heights file's type, and inline heights rounded to it): `nodata` is compared as the
        // f32 it rounds to, so that a value f32 cannot hold exactly (−9999.9) still marks its vertices.
        let nodata = nodata.map(|nd| nd as f32);
        for (k, h) in heights.iter_mut().enumerate() {
            if h.is_nan() || nodata.is_some_and(|nd| *h == nd) {
                *h = f32::NAN;
                continue;
            }
            if !h.is_finite() || f64::from(*h) <= floor {
                return Err(format!(
                    "height {h} at row {}, column {} is not finite or not above -b^2/a = {floor}",
                    k / cols,
                    k % cols
                ));
            }
        }
        Ok(Dem {
            a,
            b,
            lat0,
            lon0,
            dlat,
            dlon,
            rows,
            cols,
            heights,
        })
    }

    /// A DEM on WGS84.
    pub fn wgs84(
        geo: (f64, f64, f64, f64),
        shape: (usize, usize),
        heights: Vec<f32>,
    ) -> Result<Dem, String> {
        Dem::new(WGS84_A, WGS84_B, geo, shape, heights, None)
    }

    /// Latitude of row `i` in degrees: `lat0 + i·dlat`.
    pub fn lat(&self, i: usize) -> f64 {
        self.lat0 + i as f64 * self.dlat
    }

    /// Longitude of column `j` in degrees: `lon0 + j·dlon`.
    pub fn lon(&self, j: usize) -> f64 {
        self.lon0 + j as f64 * self.dlon
    }

    /// The height of vertex (i, j), `None` when missing or outside the grid.
    pub fn height(&self, i: usize, j: usize) -> Option<f32> {
        if i >= self.rows || j >= self.cols {
            return None;
        }
        let h = *self.heights.get(i * self.cols + j)?;
        (!h.is_nan()).then_some(h)
    }

    /// Number of cells, `(rows − 1)·(cols − 1)`.
    pub fn cell_count(&self) -> usize {
        (self.rows - 1) * (self.cols - 1)
    }

    /// Whether cell (i, j)'s two triangles are both present (triangle `k` = 0 or 1, see the module docs); the
    /// triangles of a cell can be present separately: use [`Dem::triangle`].
    pub fn triangle(&self, i: usize, j: usize, k: usize) -> Option<[(usize, usize); 3]> {
        if i + 1 >= self.rows || j + 1 >= self.cols {
            return None;
        }
        let v = if k == 0 {
            [(i, j), (i, j + 1), (i + 1, j + 1)]
        } else {
            [(i, j), (i + 1, j + 1), (i + 1, j)]
        };
        v.iter()
            .all(|&(r, c)| self.height(r, c).is_some())
            .then_some(v)
    }

    /// The ECEF position of vertex (i, j) in `f64` (host arithmetic, for baselines and generators; the oracle
    /// recomputes vertices in arbitrary precision). `None` for a missing vertex.
    pub fn vertex_ecef(&self, i: usize, j: usize) -> Option<[f64; 3]> {
        let h = f64::from(self.height(i, j)?);
        Some(geodetic_to_ecef_f64(
            self.a,
            self.b,
            self.lat(i),
            self.lon(j),
            h,
        ))
    }

    /// Minimum and maximum of the present heights (`None` when every vertex is missing).
    pub fn height_range(&self) -> Option<(f32, f32)> {
        let mut it = self.heights.iter().copied().filter(|h| !h.is_nan());
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), h| (lo.min(h), hi.max(h))))
    }

    /// The contract's file form of this DEM with the heights in an external file named `heights_name`.
    pub fn to_spec(&self, heights_name: &str) -> TerrainFileSpec {
        let ellipsoid = if self.a == WGS84_A && self.b == WGS84_B {
            EllipsoidSpec::Named("WGS84".into())
        } else {
            EllipsoidSpec::Axes {
                a: self.a,
                b: self.b,
            }
        };
        TerrainFileSpec {
            ellipsoid,
            grid: GridFileSpec {
                lat0: self.lat0,
                lon0: self.lon0,
                dlat: self.dlat,
                dlon: self.dlon,
                rows: self.rows,
                cols: self.cols,
                heights: Some(heights_name.into()),
                heights_inline: None,
            },
            nodata: None,
        }
    }

    /// Writes `json_path` (TERRAIN.json) and the heights next to it as `<stem>.f32` (little-endian, row-major,
    /// NaN for missing vertices), so that `curvicast pick --terrain json_path` reads back exactly this DEM.
    pub fn write_terrain_json(&self, json_path: &Path) -> std::io::Result<()> {
        let stem = json_path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "terrain".into());
        let heights_name = format!("{stem}.f32");
        let dir = json_path.parent().unwrap_or(Path::new("."));
        let mut bytes = Vec::with_capacity(self.heights.len() * 4);
        for h in &self.heights {
            bytes.extend_from_slice(&h.to_le_bytes());
        }
        std::fs::write(dir.join(&heights_name), bytes)?;
        let text = serde_json::to_string_pretty(&self.to_spec(&heights_name))
            .map_err(std::io::Error::other)?;
        std::fs::write(json_path, text)
    }
}

/// Sine and cosine of an angle in degrees, exact at multiples of 90° (so a row at ±90° is exactly on the axis).
pub fn sincos_deg(x: f64) -> (f64, f64) {
    let r = x.rem_euclid(360.0);
    let q = (r / 90.0).round();
    let rem = (r - 90.0 * q).to_radians();
    let (s, c) = rem.sin_cos();
    match (q as i64).rem_euclid(4) {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// Geodetic (lat, lon in degrees, h in meters) to ECEF on the ellipsoid with semi-axes `a ≥ b`, in `f64`:
/// N = a²/√(a²cos²φ + b²sin²φ), x = (N + h) cosφ cosλ, y = (N + h) cosφ sinλ, z = (N b²/a² + h) sinφ.
pub fn geodetic_to_ecef_f64(a: f64, b: f64, lat: f64, lon: f64, h: f64) -> [f64; 3] {
    let (sp, cp) = sincos_deg(lat);
    let (sl, cl) = sincos_deg(lon);
    let n = a * a / ((a * cp).hypot(b * sp));
    [
        (n + h) * cp * cl,
        (n + h) * cp * sl,
        (n * (b * b) / (a * a) + h) * sp,
    ]
}

fn err(file: &Path, message: impl Into<String>) -> TerrainError {
    TerrainError {
        file: file.to_path_buf(),
        message: message.into(),
    }
}

/// Reads and validates a `TERRAIN.json` file (and the heights file it names). Every error names the file that is
/// wrong and what is wrong with it.
pub fn load_terrain(json_path: &Path) -> Result<Dem, TerrainError> {
    let text = std::fs::read_to_string(json_path)
        .map_err(|e| err(json_path, format!("cannot read terrain file: {e}")))?;
    let spec: TerrainFileSpec = serde_json::from_str(&text)
        .map_err(|e| err(json_path, format!("invalid terrain file: {e}")))?;
    let dir = json_path.parent().unwrap_or(Path::new("."));
    dem_from_spec(&spec, dir).map_err(|(file, m)| err(file.as_deref().unwrap_or(json_path), m))
}

/// Builds the model from a parsed file; `dir` resolves the heights path. An error names the heights file when
/// the problem is in it (`Some(path)`), otherwise the JSON file (`None`).
pub fn dem_from_spec(spec: &TerrainFileSpec, dir: &Path) -> Result<Dem, (Option<PathBuf>, String)> {
    let (a, b) = match &spec.ellipsoid {
        EllipsoidSpec::Named(n) if n.eq_ignore_ascii_case("WGS84") => (WGS84_A, WGS84_B),
        EllipsoidSpec::Named(n) => {
            return Err((
                None,
                format!("unknown ellipsoid {n:?} (use \"WGS84\" or {{\"a\": .., \"b\": ..}})"),
            ));
        }
        EllipsoidSpec::Axes { a, b } => (*a, *b),
    };
    let g = &spec.grid;
    if let Some(nd) = spec.nodata
        && !nd.is_finite()
    {
        return Err((None, format!("nodata must be a finite number, got {nd}")));
    }
    let n = g.rows.checked_mul(g.cols).ok_or((
        None,
        format!("grid of {} x {} is too large", g.rows, g.cols),
    ))?;
    let heights: Vec<f32> = match (&g.heights, &g.heights_inline) {
        (Some(_), Some(_)) => {
            return Err((
                None,
                "grid has both \"heights\" and \"heights_inline\"; give one".into(),
            ));
        }
        (None, None) => {
            return Err((
                None,
                "grid needs \"heights\" (a file) or \"heights_inline\"".into(),
            ));
        }
        (None, Some(v)) => v.iter().map(|h| h.map_or(f32::NAN, |x| x as f32)).collect(),
        (Some(name), None) => {
            let path = dir.join(name);
            let bytes = std::fs::read(&path)
                .map_err(|e| (Some(path.clone()), format!("cannot read heights: {e}")))?;
            if Some(bytes.len()) != n.checked_mul(4) {
                return Err((
                    Some(path),
                    format!(
                        "expected rows*cols*4 = {} bytes of little-endian f32 ({} x {}), found {} bytes",
                        n.saturating_mul(4),
                        g.rows,
                        g.cols,
                        bytes.len()
                    ),
                ));
            }
            bytes
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect()
        }
    };
    Dem::new(
        a,
        b,
        (g.lat0, g.lon0, g.dlat, g.dlon),
        (g.rows, g.cols),
        heights,
        spec.nodata,
    )
    .map_err(|m| (None, m))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(rows: usize, cols: usize, h: f32) -> Dem {
        Dem::wgs84((10.0, 20.0, 0.5, 0.5), (rows, cols), vec![h; rows * cols]).unwrap()
    }

    #[test]
    fn sincos_deg_is_exact_at_quadrants() {
        assert_eq!(sincos_deg(90.0), (1.0, 0.0));
        assert_eq!(sincos_deg(-90.0), (-1.0, 0.0));
        assert_eq!(sincos_deg(180.0), (0.0, -1.0));
        assert_eq!(sincos_deg(540.0), (0.0, -1.0));
        let (s, c) = sincos_deg(30.0);
        assert!((s - 0.5).abs() < 2.3e-16 && (c - 0.75f64.sqrt()).abs() < 2.3e-16);
    }

    #[test]
    fn nodata_that_f32_cannot_hold_exactly_still_marks_its_vertex() {
        let mut hs = vec![1000.0f32; 9];
        hs[4] = -9999.9f64 as f32;
        let d = Dem::new(
            6378137.0,
            6356752.0,
            (-80.0, 0.0, -0.5, 0.5),
            (3, 3),
            hs,
            Some(-9999.9),
        )
        .unwrap();
        assert_eq!(d.height(1, 1), None);
        assert_eq!(d.height(1, 2), Some(1000.0));
    }

    #[test]
    fn pole_row_vertices_coincide() {
        let d = Dem::wgs84((90.0, 0.0, -1.0, 10.0), (3, 37), vec![5.0; 3 * 37]).unwrap();
        let p = d.vertex_ecef(0, 0).unwrap();
        for j in 0..37 {
            assert_eq!(d.vertex_ecef(0, j).unwrap(), p);
        }
        assert_eq!(p[0], 0.0);
        assert_eq!(p[1], 0.0);
        assert_eq!(p[2], WGS84_B + 5.0);
    }

    #[test]
    fn validation_messages_say_what_is_wrong() {
        let h = vec![0.0; 4];
        let e = Dem::wgs84((89.5, 0.0, 1.0, 1.0), (2, 2), h.clone()).unwrap_err();
        assert!(e.contains("outside [-90, 90]"), "{e}");
        let e = Dem::wgs84((0.0, 0.0, 1.0, -1.0), (2, 2), h.clone()).unwrap_err();
        assert!(e.contains("dlon"), "{e}");
        let e = Dem::wgs84((0.0, 0.0, 0.0, 1.0), (2, 2), h.clone()).unwrap_err();
        assert!(e.contains("dlat"), "{e}");
        let e = Dem::wgs84((0.0, 0.0, 1.0, 1.0), (2, 3), h.clone()).unwrap_err();
        assert!(e.contains("rows*cols"), "{e}");
        let e = Dem::wgs84((0.0, 0.0, 1.0, 200.0), (2, 3), vec![0.0; 6]).unwrap_err();
        assert!(e.contains("exceeds 360"), "{e}");
        let e = Dem::wgs84((0.0, 0.0, 1.0, 1.0), (2, 2), vec![0.0, -7e6, 0.0, 0.0]).unwrap_err();
        assert!(e.contains("-b^2/a"), "{e}");
        let e = Dem::new(1.0, 2.0, (0.0, 0.0, 1.0, 1.0), (2, 2), h, None).unwrap_err();
        assert!(e.contains("a >= b"), "{e}");
    }

    #[test]
    fn nodata_becomes_missing_and_removes_adjacent_triangles() {
        let mut h = vec![1.0; 9];
        h[4] = -32768.0;
        let d = Dem::new(
            WGS84_A,
            WGS84_B,
            (0.0, 0.0, 1.0, 1.0),
            (3, 3),
            h,
            Some(-32768.0),
        )
        .unwrap();
        assert_eq!(d.height(1, 1), None);
        for i in 0..2 {
            for j in 0..2 {
                for k in 0..2 {
                    let tri = if k == 0 {
                        [(i, j), (i, j + 1), (i + 1, j + 1)]
                    } else {
                        [(i, j), (i + 1, j + 1), (i + 1, j)]
                    };
                    let uses = tri.contains(&(1, 1));
                    assert_eq!(d.triangle(i, j, k).is_none(), uses, "{i} {j} {k}");
                }
            }
        }
        let mut h = vec![1.0; 9];
        h[2] = f32::NAN; // vertex (0, 2): only cell (0, 1)'s first triangle uses it
        let d = Dem::wgs84((0.0, 0.0, 1.0, 1.0), (3, 3), h).unwrap();
        assert!(d.triangle(0, 1, 0).is_none());
        assert!(d.triangle(0, 1, 1).is_some());
        assert!(d.triangle(0, 0, 0).is_some());
    }

    #[test]
    fn terrain_json_round_trip_and_errors_name_the_file() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let mut d = flat(4, 5, 100.0);
        d.heights[7] = f32::NAN;
        let json = dir.join("t.json");
        d.write_terrain_json(&json).unwrap();
        let back = load_terrain(&json).unwrap();
        assert_eq!(back.rows, 4);
        assert!(back.heights[7].is_nan());
        assert_eq!(back.heights[8], 100.0);
        std::fs::write(dir.join("t.f32"), [0u8; 12]).unwrap();
        let e = load_terrain(&json).unwrap_err();
        assert_eq!(e.file, dir.join("t.f32"));
        assert!(e.message.contains("bytes"), "{e}");
        std::fs::write(&json, "{\"ellipsoid\": \"Mars\"}").unwrap();
        let e = load_terrain(&json).unwrap_err();
        assert_eq!(e.file, json);
        let inline = r#"{"ellipsoid": {"a": 10.0, "b": 10.0}, "grid": {"lat0": 0, "lon0": 0, "dlat": 1,
            "dlon": 1, "rows": 2, "cols": 2, "heights_inline": [1, null, 3, -9]}, "nodata": -9}"#;
        std::fs::write(&json, inline).unwrap();
        let d = load_terrain(&json).unwrap();
        assert_eq!(d.height(0, 0), Some(1.0));
        assert_eq!(d.height(0, 1), None);
        assert_eq!(d.height(1, 1), None);
    }
}
