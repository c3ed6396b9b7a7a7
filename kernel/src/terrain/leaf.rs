//! Leaf tracing (Wartell et al. §4): a traced unit's cells walked column by column, clipped against their meridian and
//! row planes, culled by height, and their triangles tested.
//!
//! In a leaf, each cell (triangle pair) has its own volume bounded by four *planes*: the meridian planes of its
//! two columns and, for each of its two rows, the plane through the spheroid normals at the row's two grid
//! vertices (both normals of one latitude pass through the latitude cone's apex, so they are coplanar). All four
//! corner vertices lie in that convex volume, so both triangles do — exactly, with no containment problem at
//! this level — and neighbouring cells share their walls. Only the triangle pairs whose volume the ray crosses
//! are tested, with the watertight ray–triangle test ([`triangle`]). The paper steps from one pair's volume to
//! the next through the wall the ray leaves by; here the unit is walked by columns, in the order the ray
//! crosses them (the meridian walls clip the ray once per column), which visits the same pairs.
//!
//! Beyond the paper, two shortcuts: at full resolution, away from the axis, a column's row planes are ordered,
//! so only the rows between those of the column segment's two ends are visited ([`Picker::crossed_rows`]
//! states the bound); and a cell's two triangles are tested only when the ray's part inside the cell is not
//! wholly above (or below) its four corners in the unit's local frame — the triangles are their convex hull
//! (`cull.rs`; a cell the ray passes high above is skipped from its corner heights alone, before its vertices
//! are formed).
//! A coarse unit's border cells are stitched to finer neighbours (`stitch.rs`). A full-resolution leaf whose
//! storage gives its windows' boxes is walked window by window, only those the ray enters (`windows.rs`).
//!
//! # Cost
//!
//! Per leaf: a clip against two meridian planes per column (columns the ray misses are skipped), the rows the
//! column's segment can cross (a few plane signs from the previous column's row), two row planes per such
//! cell, the height cull, and the triangle test for what is left. No trigonometry is needed per ray when the
//! storage caches the sines and cosines of its rows and columns ([`TerrainCaches::row_sin_cos`]); the prime
//! vertical radius is computed once per row of a leaf.

use super::error::TerrainError;
use super::picker::{Picker, div_ceil_pow2};
use super::refine::{self, Tri, TriRef, Vtx};
use super::storage::{TerrainCaches, ranges_frame};
use super::triangle::Edge;
use super::walk::{Candidate, CellAt, Stitch, Unit, Walk};
use crate::geodesy::sin_cos_deg;
use crate::interval::clip_half_space;
use crate::ray::Ray;
use crate::real::Real;
use crate::vec3::V3;
use core::cell::Cell;
mod crossed;
mod cull;
use cull::HeightCull;

impl<T: Real, S: TerrainCaches<T>, const STACK: usize, const ZONES: usize>
    Picker<'_, T, S, STACK, ZONES>
{
    /// Traces the cells of a unit (§4; §5 for a coarser block), column by column: each column of cells is
    /// clipped against its two meridian planes ([`Picker::clip_column`]), then each of its cells that the ray
    /// can reach against its two row planes, and the triangle pairs whose volume the ray crosses are tested
    /// ([`Picker::trace_column`]).
    #[inline(never)]
    pub(super) fn trace_unit(
        &self,
        u: &Unit,
        t_in: T,
        t_out: T,
        w: &mut Walk<'_, '_, T>,
    ) -> Result<(), TerrainError> {
        let trace = self.unit_trace(u, w.ray, t_in, t_out);
        // The cell row last located by `crossed_rows` in this unit.
        let mut row_hint = None;
        self.trace_window(&trace, (u.rows, u.cols), t_in, t_out, w, &mut row_hint)
    }

    /// The cells of a unit's window (its rows and columns `win`, the whole unit or one of a leaf's windows,
    /// `windows.rs`) that the ray crosses within `[t_in, t_out]`, column by column; `row_hint` the cell row last
    /// located in the unit.
    pub(super) fn trace_window(
        &self,
        trace: &UnitTrace<T>,
        (rows, cols): ([u32; 2], [u32; 2]),
        t_in: T,
        t_out: T,
        w: &mut Walk<'_, '_, T>,
        row_hint: &mut Option<i64>,
    ) -> Result<(), TerrainError> {
        let u = &trace.unit;
        let (k_first, k_end) = self.unit_columns(u, w.ray, t_in, t_out);
        // The window's columns, in cells of the stride from the unit's first column.
        let k_of = |c: u32| div_ceil_pow2(c.saturating_sub(u.cols[0]), u.stride);
        let (k_first, k_end) = (k_first.max(k_of(cols[0])), k_end.min(k_of(cols[1])));
        // The columns in the order the ray crosses them (longitude grows along the ray when `(o × d)_z > 0`), so
        // that a hit clips the columns after it. (The cells of a column are not: they are few, and walking them
        // in ray order cost more than it saved, measured.)
        let eastward = trace.az_rate > T::ZERO;
        for step in 0..k_end.saturating_sub(k_first) {
            let k = if eastward {
                k_first.saturating_add(step)
            } else {
                k_end.saturating_sub(1).saturating_sub(step)
            };
            if let Some(column) = self.clip_column(trace, k, t_in, t_out.min(w.best_t())) {
                self.trace_column(trace, &column, rows, w, row_hint)?;
            }
        }
        Ok(())
    }

    /// The constants of a unit's trace: the ray, the walls' tolerance, the row cache and the height cull's frame.
    #[inline]
    pub(super) fn unit_trace(&self, u: &Unit, ray: &Ray<T>, t_in: T, t_out: T) -> UnitTrace<T> {
        let (o, d) = (ray.origin(), ray.dir());
        let frame = ranges_frame(self.storage, &self.ellipsoid, u.rows, u.cols);
        let up_tol = T::from_f64(32.0)
            * T::EPSILON
            * ((o.x.abs() + o.y.abs() + o.z.abs())
                + t_in.abs().max(t_out.abs()) * (d.x.abs() + d.y.abs() + d.z.abs())
                + self.ellipsoid.a());
        UnitTrace {
            unit: *u,
            origin: o,
            dir: d,
            tau: T::from_f64(64.0) * T::EPSILON,
            north_up: self.grid.dlat_deg > T::ZERO,
            stitchable: u.stride > 1,
            rows: RowCache::new(u),
            cull: HeightCull::new(frame, (o, d), up_tol, self.ellipsoid.b()),
            az_rate: o.x * d.y - o.y * d.x,
        }
    }

    /// Column `k` of the unit (in cells of its stride from its first column) and the part of `[lo, hi]` that
    /// lies between its two meridian planes (§3.3 walls of the triangle pairs' volumes, §4), or `None` when the
    /// ray passes outside it there. The west wall is `n_w·P ≥ 0` with `n_w = (−sin λ_w, cos λ_w, 0)`, the east
    /// one `n_e·P ≤ 0`, each widened by the rounding of the coordinates.
    #[inline]
    fn clip_column(&self, tr: &UnitTrace<T>, k: u32, lo: T, hi: T) -> Option<Column<T>> {
        let (o, d) = (tr.origin, tr.dir);
        let stride = tr.unit.stride;
        let j = tr.unit.cols[0].saturating_add(k.saturating_mul(stride));
        let j1 = j.saturating_add(stride).min(tr.unit.cols[1]);
        let (sin_w, cos_w) = self.storage.col_sin_cos(j);
        let (sin_e, cos_e) = self.storage.col_sin_cos(j1);
        let (sin_half, cos_half) = if j1.saturating_sub(j) == stride {
            self.half_cell(stride)
        } else {
            sin_cos_deg(self.grid.dlon_deg * T::HALF * self.scale(j1.saturating_sub(j)))
        };
        // The cell's middle meridian λ_j + w/2 by the addition theorem (a few ulps; the row plane only needs its
        // direction, and the vertices' rounding is covered by `tau`).
        let (sin_m, cos_m) = (
            sin_w * cos_half + cos_w * sin_half,
            cos_w * cos_half - sin_w * sin_half,
        );
        let (mut lo, mut hi) = (lo, hi);
        let mag = (o.x.abs() + o.y.abs()) + (d.x.abs() + d.y.abs()) * (lo.abs().max(hi.abs()));
        let tol = tr.tau * mag;
        clip_half_space(
            &mut lo,
            &mut hi,
            cos_w * o.y - sin_w * o.x,
            cos_w * d.y - sin_w * d.x,
            tol,
        );
        clip_half_space(
            &mut lo,
            &mut hi,
            -(cos_e * o.y - sin_e * o.x),
            -(cos_e * d.y - sin_e * d.x),
            tol,
        );
        if !(lo <= hi) {
            return None;
        }
        Some(Column {
            cols: [j, j1],
            west: (sin_w, cos_w),
            east: (sin_e, cos_e),
            cos_half,
            lo,
            hi,
            radial: (cos_m * o.x + sin_m * o.y, cos_m * d.x + sin_m * d.y),
            row_mag: o.x.abs()
                + o.y.abs()
                + (d.x.abs() + d.y.abs() + d.z.abs()) * (lo.abs().max(hi.abs())),
        })
    }

    /// The triangle pairs of one column (§4, Fig. 9): each cell the ray can cross is clipped against its two
    /// row planes, a coarse unit's border cell is stitched to finer neighbours (§6; `stitch.rs`), a cell whose
    /// part of the ray passes wholly above or below its corners is skipped, and the rest have their two
    /// triangles tested.
    #[inline]
    fn trace_column(
        &self,
        tr: &UnitTrace<T>,
        col: &Column<T>,
        [win_first, win_end]: [u32; 2],
        w: &mut Walk<'_, '_, T>,
        row_hint: &mut Option<i64>,
    ) -> Result<(), TerrainError> {
        let u = &tr.unit;
        let [r0, r1] = u.rows;
        let [c0, c1] = u.cols;
        let [j, j1] = col.cols;
        let (first_row, end_row) = self.column_rows(tr, col, row_hint);
        // Only the window's rows (all of the unit's, or a leaf window's: `windows.rs`).
        let (first_row, end_row) = (first_row.max(win_first), end_row.min(win_end));
        // A column the ray passes high above is skipped from its heights alone, before its cells are clipped.
        if !tr.stitchable
            && end_row.saturating_sub(first_row) >= 2
            && self
                .column_height_max([first_row, end_row], col.cols)
                .is_some_and(|h| tr.cull.surely_above(h, col.lo, col.hi.min(w.best_t())))
        {
            return Ok(());
        }
        // Each row's values are fetched once, for its wall and its vertices.
        let mut row_a = self.row_at(&tr.rows, first_row);
        let mut wall_a = row_wall(tr, col, row_a, false);
        // The northern (higher-row) corners of the last cell traced in this column, reused as the next cell's
        // southern ones.
        let mut shared: Option<RowCorners<T>> = None;
        let mut i = first_row;
        while i < end_row {
            let i1 = i.saturating_add(u.stride).min(r1);
            let row_b = self.row_at(&tr.rows, i1);
            let wall_b = row_wall(tr, col, row_b, false);
            let (mut low, mut high) = (wall_a, wall_b);
            let (row_lo, row_hi) = (row_a, row_b);
            (wall_a, row_a) = (wall_b, row_b);
            let (row_i, row_i1) = (i, i1);
            i = i1;
            let border = row_i == r0 || row_i1 == r1 || j == c0 || j1 == c1;
            if tr.stitchable && border {
                low = border_wall(tr, col, row_lo, true);
                high = border_wall(tr, col, row_hi, false);
            }
            let Some((cell_lo, cell_hi)) =
                clip_cell(tr.north_up, low, high, col.lo, col.hi.min(w.best_t()))
            else {
                continue;
            };
            w.stats.triangle_pairs_visited = w.stats.triangle_pairs_visited.saturating_add(1);
            let cell = CellAt {
                rows: [row_i, row_i1],
                cols: [j, j1],
            };
            // A plain cell the ray passes high above is skipped from its heights alone, before its vertices are
            // formed ([`HeightCull::surely_above`]: it implies the cull below).
            let plain = !(tr.stitchable && border);
            if plain
                && self
                    .corner_height_max(cell.rows, cell.cols)
                    .is_some_and(|h| tr.cull.surely_above(h, cell_lo, cell_hi))
            {
                continue;
            }
            let reuse = shared.filter(|(r, _, _)| *r == row_i);
            let v00 = reuse.map_or_else(
                || self.grid_vertex(row_lo, row_i, j, col.west),
                |(_, a, _)| a,
            );
            let v11 = self.grid_vertex(row_hi, row_i1, j1, col.east);
            if tr.stitchable && border {
                match self.stitch(u, &cell, v00, v11, w, cell_lo)? {
                    Stitch::Done => continue,
                    Stitch::Plain => {}
                }
            }
            let v01 = reuse.map_or_else(
                || self.grid_vertex(row_lo, row_i, j1, col.east),
                |(_, _, b)| b,
            );
            let v10 = self.grid_vertex(row_hi, row_i1, j, col.west);
            shared = Some((row_i1, v10, v11));
            let corners = [v00, v01, v10, v11];
            if tr.cull.passes_clear_of(&corners, cell_lo, cell_hi) {
                continue;
            }
            self.test_triangle_pair(w, u, cell, corners);
        }
        Ok(())
    }

    /// The rows `[first, end)` of a column whose cells the ray can cross: at full resolution only the rows
    /// between those of the column segment's two ends ([`Picker::crossed_rows`]); coarse units, whose border
    /// cells have band walls, trace every row.
    #[inline]
    fn column_rows(
        &self,
        tr: &UnitTrace<T>,
        col: &Column<T>,
        row_hint: &mut Option<i64>,
    ) -> (u32, u32) {
        if tr.stitchable {
            return (tr.unit.rows[0], tr.unit.rows[1]);
        }
        let (o, d) = (tr.origin, tr.dir);
        let (radial_o, radial_d) = col.radial;
        let cos_half = col.cos_half;
        self.crossed_rows(
            &tr.unit,
            [col.lo, col.hi],
            col.radial,
            // `row_wall(i, false)` at `t`, without its tolerance (formed inline: the unused tolerance is not
            // optimised away and costs 3 % of a camera pick).
            &|i, t| {
                let (sin_lat, cos_lat, apex_z, _) = self.row_at(&tr.rows, i);
                cos_lat * cos_half * (o.z - apex_z) - sin_lat * radial_o
                    + t * (cos_lat * cos_half * d.z - sin_lat * radial_d)
            },
            margin_near(tr.tau, col.row_mag, o.z, self.pole_apex),
            row_hint,
        )
    }

    /// The highest height of a column's vertices on rows `[first, end]` (its cells `[first, end)`) and on
    /// meridians `j` and `j1`, or `None` unless all have data.
    #[inline]
    fn column_height_max(&self, [first, end]: [u32; 2], [j, j1]: [u32; 2]) -> Option<T> {
        let mut top = T::NEG_INFINITY;
        for i in first..=end {
            for jj in [j, j1] {
                let h = self.storage.height(i, jj).filter(|h: &T| h.is_finite())?;
                top = top.max(h);
            }
        }
        Some(top)
    }

    /// The highest of a cell's four corner heights, or `None` unless all four have data.
    #[inline(always)]
    fn corner_height_max(&self, [i, i1]: [u32; 2], [j, j1]: [u32; 2]) -> Option<T> {
        let h = |i, j| self.storage.height(i, j).filter(|h: &T| h.is_finite());
        let (a, b, c, d) = (h(i, j)?, h(i, j1)?, h(i1, j)?, h(i1, j1)?);
        Some(a.max(b).max(c.max(d)))
    }

    /// A lattice row's values, from the unit's cache when the row is one of its lattice rows.
    #[inline(always)]
    fn row_at(&self, rows: &RowCache<T>, i: u32) -> RowValues<T> {
        let Some(slot) = rows.slot(i) else {
            return self.row_values(i);
        };
        slot.get().unwrap_or_else(|| {
            let v = self.row_values(i);
            slot.set(Some(v));
            v
        })
    }

    /// Row `i`'s `(sin ψ, cos ψ, cone apex k, prime vertical radius N)`.
    #[inline]
    fn row_values(&self, i: u32) -> RowValues<T> {
        let (sin_lat, cos_lat) = self.storage.row_sin_cos(i);
        let e = &self.ellipsoid;
        (
            sin_lat,
            cos_lat,
            e.latitude_cone_apex(sin_lat),
            e.prime_vertical_radius(sin_lat),
        )
    }

    /// Grid vertex `(i, j)` in ECEF, `row` row `i`'s values and `j` a column meridian with `(sin λ, cos λ)` = `lon`;
    /// `None` where it has no data.
    #[inline(always)]
    fn grid_vertex(
        &self,
        row: RowValues<T>,
        i: u32,
        j: u32,
        (s_lon, c_lon): (T, T),
    ) -> Option<V3<T>> {
        let h = self.storage.height(i, j)?;
        if !h.is_finite() {
            return None;
        }
        let (sin_lat, cos_lat, _, prime_vertical) = row;
        Some(
            self.ellipsoid
                .ecef_from_parts(sin_lat, cos_lat, prime_vertical, s_lon, c_lon, h),
        )
    }

    /// The two triangles of a traced cell (§4's triangle pair: `V00 V01 V11` and `V00 V11 V10`), each tested if
    /// its three corners have data. The edges with no triangle across (triangle.rs, "Edges on the border of the
    /// surface") are asked only when the ray passes within rounding outside one; they are captured by value (a
    /// reference would keep these locals in memory through the column loop).
    #[inline]
    fn test_triangle_pair(
        &self,
        w: &mut Walk<'_, '_, T>,
        u: &Unit,
        cell: CellAt,
        [v00, v01, v10, v11]: [Option<V3<T>>; 4],
    ) {
        let s = u.stride;
        let origin_cell = [cell.rows[0], cell.cols[0]];
        if let (Some(a), Some(b), Some(c)) = (v00, v01, v11) {
            let no_second = v10.is_none();
            let border = move || self.border_edges(cell, s, true, no_second);
            self.test_triangle(
                w,
                [a, b, c],
                origin_cell,
                triangle_ref(cell, s, true),
                u,
                border,
            );
        }
        if let (Some(a), Some(b), Some(c)) = (v00, v11, v10) {
            let no_first = v01.is_none();
            let border = move || self.border_edges(cell, s, false, no_first);
            self.test_triangle(
                w,
                [a, b, c],
                origin_cell,
                triangle_ref(cell, s, false),
                u,
                border,
            );
        }
    }

    /// Which edges of a traced cell's first (`first`) or second triangle have no triangle across (triangle.rs,
    /// "Edges on the border of the surface"), in the order `b–c`, `c–a`, `a–b` of its vertices: the diagonal
    /// when the cell's other triangle is missing (`other_missing`), a side when it is on the grid's edge or
    /// when the third vertex of the triangle across, one `stride` further, has no data.
    pub(super) fn border_edges(
        &self,
        c: CellAt,
        stride: u32,
        first: bool,
        other_missing: bool,
    ) -> [bool; 3] {
        let ([i, i1], [j, j1]) = (c.rows, c.cols);
        let (last_row, last_col) = (self.grid.cell_rows(), self.grid.cell_cols());
        let has = |ii: u32, jj: u32| self.storage.height(ii, jj).is_some_and(T::is_finite);
        if first {
            // (V(i,j), V(i,j1), V(i1,j1)): column j1, the diagonal, row i.
            let east = j1 >= last_col || !has(i1, j1.saturating_add(stride).min(last_col));
            let south = i == 0 || !has(i.saturating_sub(stride), j);
            [east, other_missing, south]
        } else {
            // (V(i,j), V(i1,j1), V(i1,j)): row i1, column j, the diagonal.
            let north = i1 >= last_row || !has(i1.saturating_add(stride).min(last_row), j1);
            let west = j == 0 || !has(i, j.saturating_sub(stride));
            [north, west, other_missing]
        }
    }

    /// One watertight ray–triangle test, its edges on the border of the surface given by `border` (edges
    /// `b–c`, `c–a`, `a–b`; asked only for a ray passing within rounding of an edge, where the side of a border
    /// edge is then decided from the exact vertices, triangle.rs "Edges on the border of the surface"); a nearer
    /// hit becomes the candidate.
    #[inline]
    pub(super) fn test_triangle(
        &self,
        w: &mut Walk<'_, '_, T>,
        [a, b, c]: [V3<T>; 3],
        cell: [u32; 2],
        tri: TriRef,
        u: &Unit,
        border: impl FnOnce() -> [bool; 3],
    ) {
        w.stats.triangles_tested = w.stats.triangles_tested.saturating_add(1);
        let limit = w.best.as_ref().map_or(w.ray.t_max(), |h| h.t);
        // the watertight ray is sheared from the exactly rescaled direction (any direction length works, down
        // to subnormal ones): its parameter is the ray's scaled one
        let (lo, hi) = (w.ray.t_to_scaled(w.ray.t_min()), w.ray.t_to_scaled(limit));
        let ray = w.ray;
        let edges = move |near: [bool; 3]| {
            let open = border();
            if !near.iter().zip(open).any(|(&n, o)| n && o) {
                return [Edge::Shared; 3];
            }
            let inside = refine::exact_sides(self.storage, &self.grid, ray, cell, tri);
            [0, 1, 2].map(|k| {
                Edge::of(
                    open.get(k).is_some_and(|&o| o),
                    inside.and_then(|s| s.get(k).copied()),
                )
            })
        };
        if let Some(t) = w
            .wray
            .intersect_with_border(a, b, c, lo, hi, edges)
            .map(|(s, _)| w.ray.t_from_scaled(s))
        {
            // On a tie (the same `t` exactly, as on an edge two cells share), the lower column of the unit wins,
            // then the lower row, whichever order the columns and windows were walked in (`trace_unit`,
            // `windows.rs`): the answer of a walk from west to east and, in a column, from its first row.
            if w.best.as_ref().is_none_or(|h| {
                t < h.t
                    || (t == h.t
                        && h.unit == *u
                        && (cell.get(1), cell.first()) < (h.cell.get(1), h.cell.first()))
            }) {
                *w.best = Some(Candidate {
                    t,
                    cell,
                    tri,
                    unit: *u,
                });
            }
        }
    }
}

/// Twice a bound on the tolerance of every row wall of a column ([`row_wall`]'s `τ (row_mag + |o_z − k|)`, with
/// `|k|` at most `pole_apex`, the apex of the pole's latitude cone): how near a row plane an end of a column's
/// segment must lie for [`Picker::crossed_rows`] to add the row beyond it.
#[inline(always)]
pub(in crate::terrain) fn margin_near<T: Real>(tau: T, row_mag: T, o_z: T, pole_apex: T) -> T {
    T::TWO * tau * (row_mag + (o_z.abs() + pole_apex))
}

/// Row plane of a column (§4: the plane through the spheroid normals at the row's vertices on the column's two
/// meridians, which both pass through the latitude cone's apex `(0, 0, k_i)`), for the row with values `row`:
/// `m = (−sin ψ cos λm, −sin ψ sin λm, cos ψ cos(w/2))` with `λm` the column's middle meridian and `w` its width,
/// and `m·(P − k ẑ) > 0` north of it. With `tangent`, `cos(w/2)` is replaced by 1: the plane tangent to the
/// latitude cone along the middle meridian, which bounds the cone's arc over the cell from the other side
/// (stitched sides, [`border_wall`]).
#[inline(always)]
fn row_wall<T: Real>(
    tr: &UnitTrace<T>,
    col: &Column<T>,
    row: RowValues<T>,
    tangent: bool,
) -> Wall<T> {
    let (o, d) = (tr.origin, tr.dir);
    let (radial_o, radial_d) = col.radial;
    let (sin_lat, cos_lat, apex_z, _) = row;
    let cos_half = if tangent { T::ONE } else { col.cos_half };
    let z_above_apex = o.z - apex_z;
    Wall {
        at_origin: cos_lat * cos_half * z_above_apex - sin_lat * radial_o,
        rate: cos_lat * cos_half * d.z - sin_lat * radial_d,
        tol: tr.tau * (col.row_mag + z_above_apex.abs()),
    }
}

/// The row wall of a border cell of a coarse unit, which may be stitched (§6, the containment problem of §4 at a
/// block's border): vertices of a finer neighbour on its rows lie on the latitude cones between its meridians,
/// and near a pole a cell far wider than tall has cone arcs that sag across even the opposite row's chord plane.
/// So both row walls of such a cell bound the whole latitude band in the wedge: the chord plane where the band
/// lies on its concave side (a northern wall with ψ > 0, a southern one with ψ < 0), the tangent plane along the
/// middle meridian where it lies on the convex side (a southern wall with ψ > 0, a northern one with ψ < 0).
/// `low`: the cell's lower-row wall.
#[inline(always)]
fn border_wall<T: Real>(
    tr: &UnitTrace<T>,
    col: &Column<T>,
    row: RowValues<T>,
    low: bool,
) -> Wall<T> {
    let south = low == tr.north_up;
    let sin_lat = row.0;
    row_wall(
        tr,
        col,
        row,
        (south && sin_lat > T::ZERO) || (!south && sin_lat < T::ZERO),
    )
}

/// The per-unit constants of a leaf trace (§4).
pub(super) struct UnitTrace<T> {
    unit: Unit,
    origin: V3<T>,
    dir: V3<T>,
    /// The walls' tolerance relative to the coordinates' magnitude (64 ε).
    tau: T,
    /// Rows run northwards (`dlat_deg > 0`).
    north_up: bool,
    /// A coarse unit (stride above 1), whose border cells may be stitched.
    stitchable: bool,
    rows: RowCache<T>,
    cull: HeightCull<T>,
    /// The sign of the azimuth's rate along the ray, `(o × d)_z`.
    az_rate: T,
}

/// One column of a unit's cells (a strip between two meridian planes) and the part `[lo, hi]` of the ray
/// between them.
struct Column<T> {
    cols: [u32; 2],
    /// `(sin λ, cos λ)` of the western and eastern meridians.
    west: (T, T),
    east: (T, T),
    /// `cos(w/2)`, `w` the column's longitude width.
    cos_half: T,
    lo: T,
    hi: T,
    /// The ray's distance from the axis along the middle meridian at the origin and its rate along the ray,
    /// `(cos λm, sin λm)·(o, d)`: the row planes' parts that do not depend on the row.
    radial: (T, T),
    /// The coordinates' magnitude over the segment, to which the row walls' tolerance is relative.
    row_mag: T,
}

/// A plane wall of a cell's volume along the ray: `at_origin + t·rate` is positive on its northern side (scaled
/// by the plane normal's length), `tol` the rounding that may be on it.
#[derive(Clone, Copy)]
struct Wall<T> {
    at_origin: T,
    rate: T,
    tol: T,
}

/// The part of the column's `[lo, hi]` inside a cell: north of its southern row wall and south of its northern
/// one (`low`, `high`: the walls of its lower and higher row), or `None` when the ray passes outside the cell.
#[inline(always)]
fn clip_cell<T: Real>(north_up: bool, low: Wall<T>, high: Wall<T>, lo: T, hi: T) -> Option<(T, T)> {
    let (mut cell_lo, mut cell_hi) = (lo, hi);
    let (south, north) = if north_up { (low, high) } else { (high, low) };
    clip_half_space(
        &mut cell_lo,
        &mut cell_hi,
        south.at_origin,
        south.rate,
        south.tol,
    );
    clip_half_space(
        &mut cell_lo,
        &mut cell_hi,
        -north.at_origin,
        -north.rate,
        north.tol,
    );
    (cell_lo <= cell_hi).then_some((cell_lo, cell_hi))
}

/// Which triangle of a traced cell `first` names (`V00 V01 V11`, else `V00 V11 V10`): by its half of the cell
/// at full resolution, by its grid vertices in a coarser block.
#[inline(always)]
fn triangle_ref(cell: CellAt, stride: u32, first: bool) -> TriRef {
    let ([i, i1], [j, j1]) = (cell.rows, cell.cols);
    if stride == 1 {
        TriRef::Cell(if first { Tri::First } else { Tri::Second })
    } else if first {
        TriRef::Vertices([Vtx::Grid(i, j), Vtx::Grid(i, j1), Vtx::Grid(i1, j1)])
    } else {
        TriRef::Vertices([Vtx::Grid(i, j), Vtx::Grid(i1, j1), Vtx::Grid(i1, j)])
    }
}

/// A unit's cache of its lattice rows' values ([`RowValues`]) for units up to `ROW_CACHE − 1` cells tall,
/// filled as rows are first asked for (a ray from above needs few).
struct RowCache<T> {
    slots: [Cell<Option<RowValues<T>>>; ROW_CACHE],
    /// The unit's first and last rows.
    rows: [u32; 2],
    /// The entry of the last row (the unit's height in cells of its stride, rounded up).
    last_entry: u32,
    /// The stride's `log2` and `stride − 1` (strides are powers of two).
    shift: u32,
    mask: u32,
}

impl<T: Real> RowCache<T> {
    fn new(u: &Unit) -> Self {
        let [r0, r1] = u.rows;
        RowCache {
            slots: core::array::from_fn(|_| Cell::new(None)),
            rows: u.rows,
            last_entry: div_ceil_pow2(r1.saturating_sub(r0), u.stride),
            shift: u.stride.trailing_zeros(),
            mask: u.stride.wrapping_sub(1),
        }
    }

    /// Row `i`'s slot: lattice row `k·stride` is entry `k`, the unit's last row entry `last_entry`; `None` for
    /// other rows and beyond the cache.
    #[inline(always)]
    fn slot(&self, i: u32) -> Option<&Cell<Option<RowValues<T>>>> {
        let k = i.wrapping_sub(self.rows[0]);
        let entry = if k & self.mask == 0 {
            k.wrapping_shr(self.shift)
        } else if i == self.rows[1] {
            self.last_entry
        } else {
            u32::MAX
        };
        usize::try_from(entry).ok().and_then(|k| self.slots.get(k))
    }
}

/// A row of a column's traced cells: the row index and the corners on its west and east meridians.
type RowCorners<T> = (u32, Option<V3<T>>, Option<V3<T>>);

/// A lattice row's `(sin ψ, cos ψ, cone apex k, prime vertical radius N)`.
type RowValues<T> = (T, T, T, T);

/// Rows of a leaf whose trigonometry is cached per leaf (leaves up to 64 cells tall).
const ROW_CACHE: usize = 65;

#[cfg(test)]
mod tests;
