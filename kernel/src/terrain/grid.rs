//! The data of a terrain (Wartell et al. §3): the DEM's regular latitude/longitude [`Grid`], the quadtree's
//! [`Node`]s and their ids, and the zones of a grid ([`zone_cells`]).

use crate::real::Real;

/// The regular geodetic grid of a DEM (`pick` in the CLI contract): vertex `V(i, j)` is at latitude
/// `lat0_deg + i·dlat_deg`, longitude `lon0_deg + j·dlon_deg` (degrees), `0 ≤ i < rows`, `0 ≤ j < cols`. Cell `(i, j)`
/// (`i < rows − 1`, `j < cols − 1`) is the two triangles `(V(i,j), V(i,j+1), V(i+1,j+1))` and
/// `(V(i,j), V(i+1,j+1), V(i+1,j))`. `dlat_deg` may be negative; `dlon_deg` must be in `(0°, 180°)`; longitudes may run
/// past ±180°; latitudes stay within [−90°, 90°] (a row at ±90° is a pole).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid<T> {
    /// Latitude of row 0, degrees.
    pub lat0_deg: T,
    /// Longitude of column 0, degrees.
    pub lon0_deg: T,
    /// Row spacing, degrees (non-zero, either sign).
    pub dlat_deg: T,
    /// Column spacing, degrees (`0 < dlon_deg < 180`).
    pub dlon_deg: T,
    /// Number of vertex rows (≥ 2).
    pub rows: u32,
    /// Number of vertex columns (≥ 2).
    pub cols: u32,
}

impl<T: Real> Grid<T> {
    /// Latitude of vertex row `i`, degrees, clamped to ±90° (a last row computed as `90.000000000001` is the pole).
    #[inline]
    pub fn lat_deg(&self, i: u32) -> T {
        let ninety = T::from_f64(90.0);
        (self.lat0_deg + T::from_f64(f64::from(i)) * self.dlat_deg)
            .max(-ninety)
            .min(ninety)
    }
    /// Longitude of vertex column `j`, degrees (not wrapped).
    #[inline]
    pub fn lon_deg(&self, j: u32) -> T {
        self.lon0_deg + T::from_f64(f64::from(j)) * self.dlon_deg
    }
    /// Number of cell rows (`rows − 1`).
    #[inline]
    pub fn cell_rows(&self) -> u32 {
        self.rows.saturating_sub(1)
    }
    /// Number of cell columns (`cols − 1`).
    #[inline]
    pub fn cell_cols(&self) -> u32 {
        self.cols.saturating_sub(1)
    }
    /// Checks the grid: finite, `dlat_deg ≠ 0`, `0 < dlon_deg < 180`, at least 2×2 vertices, latitudes within ±90°
    /// (a rounding excess up to 1e-9° is accepted and clamped).
    pub fn validate(&self) -> bool {
        let finite = self.lat0_deg.is_finite()
            && self.lon0_deg.is_finite()
            && self.dlat_deg.is_finite()
            && self.dlon_deg.is_finite();
        if !finite || self.rows < 2 || self.cols < 2 {
            return false;
        }
        if self.dlat_deg == T::ZERO
            || !(self.dlon_deg > T::ZERO && self.dlon_deg < T::from_f64(180.0))
        {
            return false;
        }
        let lim = T::from_f64(90.0 + 1e-9);
        let last =
            self.lat0_deg + T::from_f64(f64::from(self.rows.saturating_sub(1))) * self.dlat_deg;
        self.lat0_deg.abs() <= lim && last.abs() <= lim && self.lon_deg(self.cols).is_finite()
    }
}

/// The id of a quadtree node, chosen by the storage (an index into its node array, typically).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub u32);

/// One node of the height-augmented quadtree (a spheroidal height-quad, §3): the cells it covers, in the DEM's
/// own grid indices, the range of its vertex heights, and its children.
///
/// Invariants the kernel checks (violations are [`super::TerrainError::MalformedTree`]): `rows[0] < rows[1] ≤
/// grid.rows − 1`, `cols[0] < cols[1] ≤ grid.cols − 1`; a child's ranges lie inside its parent's and are
/// strictly smaller. Invariants the kernel relies on (the storage must guarantee them): `heights` is
/// `Some([min, max])` over **every** vertex `V(i, j)` with `rows[0] ≤ i ≤ rows[1]`, `cols[0] ≤ j ≤ cols[1]`
/// that has data (the cells' corner vertices, boundary rows and columns included), `None` if none has; the
/// children together cover every cell of the node that has a triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node<T> {
    /// Cell rows `[rows[0], rows[1])`.
    pub rows: [u32; 2],
    /// Cell columns `[cols[0], cols[1])`.
    pub cols: [u32; 2],
    /// `[min, max]` of the node's vertex heights, `None` when all are nodata.
    pub heights: Option<[T; 2]>,
    /// Up to four children (any order); a node without children is a leaf whose cells the kernel traces
    /// (§4: a block of triangle pairs).
    pub children: [Option<NodeId>; 4],
    /// Depth of the node (zones are level 0); reported in [`super::Hit::level`].
    pub level: u8,
}

impl<T> Node<T> {
    /// True when the node has no children.
    pub fn is_leaf(&self) -> bool {
        self.children.iter().all(Option::is_none)
    }
}

/// The default number of zone rows (parallels) of [`zone_cells`]: 4 bands of 45° on a global grid.
pub const DEFAULT_ZONE_ROWS: u32 = 4;
/// The default number of zone columns (meridians) of [`zone_cells`]: 8 wedges of 45° on a global grid.
pub const DEFAULT_ZONE_COLS: u32 = 8;

/// The cell ranges `(rows, cols)` of zone `k` (row-major, `k < zone_rows · zone_cols`) when the grid's cells are
/// split into `zone_rows × zone_cols` zones along grid lines (§3.5: zones bounded by parallels and meridians).
/// For a global grid with the defaults this is the paper's 8 × 4 = 32 zones of 45° × 45°, snapped to the DEM's
/// own grid lines (nothing is resampled); for a regional DEM it splits the DEM's own extent. `None` when `k` is
/// out of range or the zone would be empty (more zones than cells). Keeping each zone's longitude span below
/// 180° lets the kernel use its meridian walls.
pub fn zone_cells<T: Real>(
    grid: &Grid<T>,
    zone_rows: u32,
    zone_cols: u32,
    k: u32,
) -> Option<([u32; 2], [u32; 2])> {
    let (a, b) = (k.checked_div(zone_cols)?, k.checked_rem(zone_cols)?);
    if a >= zone_rows {
        return None;
    }
    let split = |n: u32, parts: u32, i: u32| -> Option<u32> {
        let v = u64::from(n)
            .checked_mul(u64::from(i))?
            .checked_div(u64::from(parts))?;
        u32::try_from(v).ok()
    };
    let (cr, cc) = (grid.cell_rows(), grid.cell_cols());
    let rows = [
        split(cr, zone_rows, a)?,
        split(cr, zone_rows, a.checked_add(1)?)?,
    ];
    let cols = [
        split(cc, zone_cols, b)?,
        split(cc, zone_cols, b.checked_add(1)?)?,
    ];
    (rows[0] < rows[1] && cols[0] < cols[1]).then_some((rows, cols))
}
