//! Which columns and rows of a traced unit the ray can cross (beyond the paper; Wartell et al. §4's walk visits the
//! same cells): the columns between those of the segment's two ends (`unit_columns`), and at full resolution,
//! away from the axis, the rows between those of a column segment's two ends (`crossed_rows`), so that the
//! leaf walk skips the rest.

use crate::ray::Ray;
use crate::real::Real;
use crate::terrain::picker::{Picker, div_ceil_pow2};
use crate::terrain::storage::TerrainCaches;
use crate::terrain::walk::Unit;
use crate::vec3::V3;
impl<T: Real, S: TerrainCaches<T>, const STACK: usize, const ZONES: usize>
    Picker<'_, T, S, STACK, ZONES>
{
    /// The cell rows `[first, end)` of a full-resolution unit that the ray can cross within one column on
    /// `[lo, hi]` (beyond the paper: the row loop skips the rest). The column's row planes all contain the
    /// direction perpendicular to its middle meridian, so each is a line `z = k + r tan ψ / cos(w/2)` in the
    /// `(r, z)` half-plane, `r` the distance from the axis along the middle meridian. Two such lines meet at
    /// `r* = Δk / Δ(tan ψ / cos(w/2))`; since `dk/dψ = −e² cos ψ (N + N' tan ψ)`, `r*` is at most
    /// `e² N cos³ψ (1 + e² N² sin²ψ / a²) ≤ e² (a²/b)(1 + e² a²/b²)` (43 km on WGS84). Beyond twice that the
    /// planes are ordered, so along a segment that stays there (`r` is linear in `t`: both ends are checked)
    /// the ray crosses each plane at most once and in order: the crossed cells are those between the cells of
    /// its two ends. Each end's cell comes from a binary search over the planes' sides; a side decided wrongly by
    /// rounding puts the end within a rounding distance of that plane, so a row of margin is added beyond a
    /// plane that an end of the outermost cells lies within `near` of (at least twice any row wall's tolerance
    /// over the segment): an end clear of it keeps the segment, linear in `t`, more than the wall's tolerance
    /// away, where the cell clip rejects the row beyond. Elsewhere (near the axis) every row is returned.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    pub(in crate::terrain) fn crossed_rows(
        &self,
        u: &Unit,
        [lo, hi]: [T; 2],
        (radial_o, radial_d): (T, T),
        plane: &impl Fn(u32, T) -> T,
        near: T,
        hint: &mut Option<i64>,
    ) -> (u32, u32) {
        let [r0, r1] = u.rows;
        let r_order = self.rows_ordered_beyond;
        let ordered = radial_o + lo * radial_d > r_order && radial_o + hi * radial_d > r_order;
        if !(ordered && lo.is_finite() && hi.is_finite()) {
            return (r0, r1);
        }
        let north_up = self.grid.dlat_deg > T::ZERO;
        // The columns are walked in ray order: the end at `lo` first, on the meridian shared with the previous
        // column, whose end at `hi` is the hint.
        let a = row_cell(plane, lo, *hint, u.rows, north_up);
        let b = row_cell(plane, hi, Some(a.cell), u.rows, north_up);
        *hint = Some(b.cell);
        let (low, high) = (a.cell.min(b.cell), a.cell.max(b.cell));
        let margin_below = (a.cell == low && !(a.below.abs() > near))
            || (b.cell == low && !(b.below.abs() > near));
        let margin_above = (a.cell == high && !(a.above.abs() > near))
            || (b.cell == high && !(b.above.abs() > near));
        let first = low
            .saturating_sub(i64::from(margin_below))
            .max(i64::from(r0));
        let end = high
            .saturating_add(1)
            .saturating_add(i64::from(margin_above))
            .min(i64::from(r1));
        match (u32::try_from(first), u32::try_from(end)) {
            (Ok(f), Ok(e)) if f <= e => (f, e),
            _ => (r0, r0),
        }
    }

    /// The unit's cell columns `[first, end)` (in cells of its stride from its first column) that the ray can
    /// cross within `[t_in, t_out]`. Both end points must lie in the half-space in front of the unit's middle
    /// meridian (`r_m > 0`), which is convex, so the whole segment does; there the azimuth is monotone along the
    /// line and every meridian of a unit narrower than 180° (minus a column) is within 90° of the middle one, so
    /// the side of a meridian plane, `cos λ_j·y − sin λ_j·x ≥ 0` (east of it), is monotone over the unit's
    /// meridians. Each end's column is found by a binary search over those sides, from the storage's
    /// trigonometry (the second end tries the first end's column before searching); the crossed columns lie
    /// between the two, plus one column of margin beyond a meridian that an end lies within rounding distance of
    /// (the cells beyond are convex hulls of vertices on or past that meridian, so an end clear of it keeps the
    /// segment out of them). Falls back to all columns otherwise.
    pub(in crate::terrain) fn unit_columns(
        &self,
        u: &Unit,
        ray: &Ray<T>,
        t_in: T,
        t_out: T,
    ) -> (u32, u32) {
        let [c0, c1] = u.cols;
        let n = div_ceil_pow2(c1.saturating_sub(c0), u.stride);
        let all = (0, n);
        let span = T::from_f64(f64::from(c1.saturating_sub(c0).saturating_add(u.stride)));
        if !(span * self.grid.dlon_deg < T::from_f64(180.0)) {
            return all;
        }
        let meridian = |k: u32| {
            self.storage
                .col_sin_cos(c0.saturating_add(k.saturating_mul(u.stride)).min(c1))
        };
        let (sm, cm) = meridian(n.wrapping_shr(1));
        let (o, d) = (ray.origin(), ray.dir());
        // The column loop's tolerance on the meridian planes (`trace_unit`): a side beyond it is decided alike
        // there.
        let tol = T::from_f64(64.0)
            * T::EPSILON
            * ((o.x.abs() + o.y.abs()) + (d.x.abs() + d.y.abs()) * t_in.abs().max(t_out.abs()));
        // The columns `[first, end)` around point `p`'s: its cell column (the last meridian `k ∈ [0, n]` it is
        // east of; `n`: east of the unit), widened by one on a side whose meridian it is within `tol` of. With
        // `hint` (the other end's column: a steep ray stays in it), that column is tried first.
        let columns = |p: V3<T>, hint: Option<u32>| -> Option<(u32, u32, u32)> {
            if !(cm * p.x + sm * p.y > T::ZERO) {
                return None;
            }
            let side = |k: u32| {
                let (sk, ck) = meridian(k);
                ck * p.y - sk * p.x
            };
            // `a < b = a + 1 ≤ n` with the point east of meridian `a` (or west of the unit when `a` is 0) and
            // not east of meridian `b`, and the two sides: the columns, and `a`.
            let cell = |a: u32, b: u32, sa: T, sb: T| {
                let west = u32::from(!(sa > tol));
                let east = u32::from(!(sb < -tol));
                (a.saturating_sub(west), b.saturating_add(east), a)
            };
            if let Some(a) = hint.filter(|&a| a < n) {
                let (sa, sb) = (side(a), side(a.saturating_add(1)));
                if (a == 0 || sa >= T::ZERO) && sb < T::ZERO {
                    return Some(cell(a, a.saturating_add(1), sa, sb));
                }
            }
            let (mut a, mut b) = (0u32, n);
            let mut sb = side(b);
            if sb >= T::ZERO {
                return Some((n.saturating_sub(1), n, n));
            }
            // Invariant: east of meridian `a` (or west of the unit when `a` is 0), not east of meridian `b`.
            let mut sa = T::NAN;
            while b.saturating_sub(a) > 1 {
                let m = a.wrapping_add(b.wrapping_sub(a).wrapping_shr(1));
                let s_m = side(m);
                if s_m >= T::ZERO {
                    (a, sa) = (m, s_m);
                } else {
                    (b, sb) = (m, s_m);
                }
            }
            if a == 0 {
                sa = side(0);
            }
            Some(cell(a, b, sa, sb))
        };
        let Some((fa, ea, a)) = columns(V3::from(ray.at(t_in)), None) else {
            return all;
        };
        let Some((fb, eb, _)) = columns(V3::from(ray.at(t_out)), Some(a)) else {
            return all;
        };
        (fa.min(fb), ea.max(eb).min(n))
    }
}

/// The cell row of a unit's column containing a point, and that point's signed distances to the cell's two
/// planes ([`row_cell`]).
#[derive(Clone, Copy)]
struct RowCell<T> {
    /// The last row plane the point lies past, or `r0 − 1` (before the unit).
    cell: i64,
    /// `plane(cell, t)` and `plane(cell + 1, t)`; infinite beyond the unit's first or last plane.
    below: T,
    above: T,
}

/// The cell row of a unit's column containing the point at `t` ([`Picker::crossed_rows`]): the last row plane
/// `i` in `[r0, r1]` that the point lies on the increasing-row side of (rows increase northwards when
/// `north_up`), or `r0 − 1` (before the unit); `plane` the planes' signed distances. From `hint` (the cell found
/// last in this unit: the ray crosses few rows per column) a few steps, else a binary search. Out of line: inlined
/// into `crossed_rows`, it costs about 1 % more instructions per camera pick (callgrind).
#[inline(never)]
fn row_cell<T: Real>(
    plane: &impl Fn(u32, T) -> T,
    t: T,
    hint: Option<i64>,
    [r0, r1]: [u32; 2],
    north_up: bool,
) -> RowCell<T> {
    let (first_plane, last_plane) = (i64::from(r0), i64::from(r1));
    let side = |i: i64| past_plane(plane, i, t, [r0, r1], north_up);
    // The answer a: past plane a, not past plane a + 1, a in [r0 − 1, r1].
    if let Some(h) = hint {
        let a = h.max(first_plane.saturating_sub(1)).min(last_plane);
        let (mut lower, mut upper) = (side(a), side(a.saturating_add(1)));
        let mut a = a;
        for _ in 0..4 {
            if !lower.0 {
                a = a.saturating_sub(1);
                (lower, upper) = (side(a), lower);
            } else if upper.0 {
                a = a.saturating_add(1);
                (lower, upper) = (upper, side(a.saturating_add(1)));
            } else {
                return RowCell {
                    cell: a,
                    below: lower.1,
                    above: upper.1,
                };
            }
        }
    }
    let (mut a, mut b) = (first_plane.saturating_sub(1), last_plane);
    // The values at planes `a` and `b + 1`, as the search decides them.
    let (mut below, mut above) = (T::INFINITY, T::INFINITY);
    while a < b {
        let m = a.saturating_add(b.saturating_sub(a).saturating_add(1).wrapping_shr(1));
        let (past, value) = side(m);
        if past {
            (a, below) = (m, value);
        } else {
            (b, above) = (m.saturating_sub(1), value);
        }
    }
    RowCell {
        cell: a,
        below,
        above,
    }
}

/// Whether the point at `t` lies past row plane `i` of a unit with rows `[r0, r1]` (on its increasing-row side;
/// true before the unit's first plane, false after its last), `plane` the plane's signed distance, and that
/// distance (infinite beyond the unit's planes).
#[inline(always)]
fn past_plane<T: Real>(
    plane: &impl Fn(u32, T) -> T,
    i: i64,
    t: T,
    [r0, r1]: [u32; 2],
    north_up: bool,
) -> (bool, T) {
    if i < i64::from(r0) {
        return (true, T::INFINITY);
    }
    let Some(i) = u32::try_from(i).ok().filter(|&i| i <= r1) else {
        return (false, T::INFINITY);
    };
    let value = plane(i, t);
    ((value >= T::ZERO) == north_up, value)
}

#[cfg(test)]
mod tests {
    use super::{RowCell, row_cell};

    /// Row planes at `t = i` (north of plane `i` for `t ≥ i` when `north_up`, south of it otherwise), rows
    /// `[2, 10]`: the cell found, from no hint and from hints on either side, and the distances to its planes.
    #[test]
    fn row_cell_of_points_inside_on_planes_and_beyond_the_unit_with_their_plane_distances() {
        for north_up in [true, false] {
            let sign = if north_up { 1.0 } else { -1.0 };
            let plane = |i: u32, t: f64| sign * (t - f64::from(i));
            let cell = |t: f64, hint: Option<i64>| -> RowCell<f64> {
                row_cell(&plane, t, hint, [2, 10], north_up)
            };
            for hint in [None, Some(0), Some(5), Some(9), Some(30)] {
                let c = cell(6.25, hint);
                assert_eq!(c.cell, 6, "{north_up} {hint:?}");
                assert_eq!((c.below, c.above), (sign * 0.25, sign * -0.75));
                // On plane 7 itself: its north side when rows run north (0 ≥ 0), its south side otherwise
                let c = cell(7.0, hint);
                assert_eq!(c.cell, if north_up { 7 } else { 6 }, "{north_up} {hint:?}");
                // Before the first plane and past the last: no plane beyond, so an infinite distance.
                let c = cell(1.5, hint);
                assert_eq!((c.cell, c.below), (1, f64::INFINITY));
                assert_eq!(c.above, sign * -0.5);
                let c = cell(10.5, hint);
                assert_eq!((c.cell, c.above), (10, f64::INFINITY));
                assert_eq!(c.below, sign * 0.5);
            }
        }
    }
}
