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
}

impl<T: Real> HeightCull<T> {
    /// The cull of a unit whose frame is `frame` (at its middle vertex, on a spheroid of polar semi-axis `b` and
    /// the frame's equatorial one), for the ray `(origin, direction)`, with the up coordinates' rounding `tol`.
    pub(super) fn new(frame: LocalFrame<T>, (o, d): (V3<T>, V3<T>), tol: T, b: T) -> Self {
        HeightCull {
            frame,
            up_origin: frame.up(o),
            up_rate: frame.up_dir(d),
            tol,
            spheroid_top: frame.spheroid_top(b) + T::from_f64(64.0) * T::EPSILON * frame.a(),
        }
    }

    /// Whether the ray's part `[clo, chi]` in a cell passes above every vertex of height at most `h_max`, from
    /// the heights alone. A vertex `P + h n` (`P` on the spheroid, `n` its normal) lies on the boundary of the
    /// spheroid's parallel body at signed distance `h` (outer for `h ≥ 0`; inner for `h < 0`, which is that
    /// parallel body while `|h|` is below the smallest radius of curvature `b²/a`, as the picker requires of
    /// every height), whose support function is the spheroid's plus `h`: so its up coordinate is at most
    /// `top + h` ([`LocalFrame::spheroid_top`]), plus `128 ε |h|` for `|u|` within a few ε of 1, and `64 ε a`
    /// (in `top`) for the rounding of the vertices' up coordinates. So it implies
    /// [`HeightCull::passes_clear_of`]'s "above" for the cell's corners, and skipping the cell on it changes no
    /// answer.
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
        self.spheroid_top + h_max + T::from_f64(128.0) * T::EPSILON * h_max.abs()
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

    /// The up coordinates' rounding tolerance (for the leaf walk's tests).
    #[cfg(test)]
    pub(super) fn tol(&self) -> T {
        self.tol
    }
}

#[cfg(test)]
mod tests;
