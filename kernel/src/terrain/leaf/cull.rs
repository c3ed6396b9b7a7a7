//! The leaf walk's height cull (beyond the paper; `leaf.rs`): a cell whose part of the ray passes wholly above or
//! below its corners is skipped, first from its corner heights alone, then from its vertices.

use crate::real::Real;
use crate::terrain::boxes::LocalFrame;
use crate::vec3::V3;

/// The height cull (beyond the paper): in the unit's local frame, a cell whose part of the ray lies wholly above
/// (or below) its four corners' up coordinates cannot meet its triangles, the convex hulls of those corners. The
/// tolerance covers the rounding of both sides' up coordinates, like the node boxes'.
pub(super) struct HeightCull<T> {
    frame: LocalFrame<T>,
    /// The ray's up coordinate at its origin and its rate along the ray.
    up_origin: T,
    up_rate: T,
    tol: T,
    /// The spheroid's highest up coordinate in the frame ([`LocalFrame::spheroid_top`]) plus `64 ε a`.
    spheroid_top: T,
    /// A lower bound of the cosine of the tilt of any of the unit's normals from the frame's up axis.
    cos_tilt: T,
}

impl<T: Real> HeightCull<T> {
    /// The cull of a unit whose frame is `frame` (at its middle vertex, on a spheroid of polar semi-axis `b` and
    /// the frame's equatorial one), for the ray `(origin, direction)`, with the up coordinates' rounding `tol` and
    /// `cos_tilt` a lower bound of the cosine of the angle between the frame's up axis and any normal of the unit.
    pub(super) fn new(
        frame: LocalFrame<T>,
        (o, d): (V3<T>, V3<T>),
        tol: T,
        b: T,
        cos_tilt: T,
    ) -> Self {
        HeightCull {
            frame,
            up_origin: frame.up(o),
            up_rate: frame.up_dir(d),
            tol,
            spheroid_top: frame.spheroid_top(b) + T::from_f64(64.0) * T::EPSILON * frame.a(),
            cos_tilt,
        }
    }

    /// Whether the ray's part `[clo, chi]` in a cell passes above every vertex of height at most `h_max`, from
    /// the heights alone: a vertex `P + h n` (`P` on the spheroid, `n` its normal) has up coordinate
    /// `u·P − a + h u·n ≤ top + h u·n`, with `u·n ≤ |u|` (within a few ε of 1) for `h ≥ 0` and
    /// `u·n ≥ cos_tilt` for `h < 0`; the bound adds `64 ε (a + |h|)` for the rounding of the vertices' up
    /// coordinates. So it implies [`HeightCull::passes_clear_of`]'s "above" for the cell's corners, and skipping
    /// the cell on it changes no answer.
    #[inline(always)]
    pub(super) fn surely_above(&self, h_max: T, cell_lo: T, cell_hi: T) -> bool {
        let (up_lo, up_hi) = (
            self.up_origin + cell_lo * self.up_rate,
            self.up_origin + cell_hi * self.up_rate,
        );
        up_lo.min(up_hi) > self.top_of(h_max) + self.tol
    }

    /// An upper bound of the up coordinate of every vertex of the unit of height at most `h_max`, as
    /// [`HeightCull::passes_clear_of`] computes them ([`HeightCull::surely_above`] says why).
    #[inline(always)]
    fn top_of(&self, h_max: T) -> T {
        let eps64 = T::from_f64(64.0) * T::EPSILON;
        let rise = if h_max >= T::ZERO {
            h_max * (T::ONE + eps64)
        } else {
            h_max * self.cos_tilt
        };
        self.spheroid_top + rise + eps64 * h_max.abs()
    }

    /// Whether the ray's part `[clo, chi]` in a cell passes wholly above or below the cell's corners (those
    /// with data).
    #[inline(always)]
    pub(super) fn passes_clear_of(
        &self,
        corners: &[Option<V3<T>>; 4],
        cell_lo: T,
        cell_hi: T,
    ) -> bool {
        let (mut z_min, mut z_max) = (T::INFINITY, T::NEG_INFINITY);
        for v in corners.iter().flatten() {
            // (comparisons, not `min`/`max`: the up coordinates are never NaN, and these are cheaper)
            let z = self.frame.up(*v);
            if z < z_min {
                z_min = z;
            }
            if z > z_max {
                z_max = z;
            }
        }
        let (up_lo, up_hi) = (
            self.up_origin + cell_lo * self.up_rate,
            self.up_origin + cell_hi * self.up_rate,
        );
        up_lo.min(up_hi) > z_max + self.tol || up_lo.max(up_hi) < z_min - self.tol
    }
}

/// [`cos_tilt`] for a unit of vertex rows `rows` and columns `cols` (inclusive ranges) on a grid of steps
/// `dlat_deg` and `dlon_deg`: its latitude and longitude spans from the middle vertex (its frame's,
/// [`crate::terrain::storage::ranges_frame`]) to the farthest row and column.
pub(super) fn unit_cos_tilt<T: Real>(
    rows: [u32; 2],
    cols: [u32; 2],
    dlat_deg: T,
    dlon_deg: T,
) -> T {
    let half = |[a, b]: [u32; 2]| {
        let n = b.saturating_sub(a);
        T::from_f64(f64::from(n.saturating_sub(n / 2)))
    };
    cos_tilt(half(rows) * dlat_deg, half(cols) * dlon_deg)
}

/// A lower bound of the cosine of the angle between the normals at two points whose latitudes differ by
/// `dlat_deg` and longitudes by `dlon_deg` (degrees): `1 − θ²/2` with `θ = |Δφ| + |Δλ|` in radians (which bounds
/// that angle), widened by a millionth for rounding. Valid for any `θ`.
pub(super) fn cos_tilt<T: Real>(dlat_deg: T, dlon_deg: T) -> T {
    let theta = (dlat_deg.abs() + dlon_deg.abs())
        * T::from_f64(core::f64::consts::PI / 180.0 * (1.0 + 1e-6));
    T::ONE - T::HALF * theta * theta
}

#[cfg(test)]
mod tests;
