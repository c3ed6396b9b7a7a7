//! Crack stitching between blocks of different resolution (Wartell et al. §6).
//!
//! **Continuity.** Where a region traced with coarse cells borders a finer one (`traverse.rs`, "Which blocks
//! are traced"), the finer side's vertices on the shared border are T-junctions of the coarse edge, and a ray
//! could pass through the crack between the coarse chord and the finer polyline. The coarse border cell is
//! therefore re-triangulated (the "artificial polygons between blocks" option of §6, as a fan): from the middle
//! `M` of its diagonal `V00–V11` to its corners and to every vertex that a finer neighbouring region has on its
//! sides, side by side. Both sides then share every edge exactly (same vertices, same rounding), so the
//! watertight triangle test lets no ray through. A cell without such vertices keeps its two triangles. The
//! surface intersected is thus: every traced cell's two triangles, except stitched cells, which are their fans.
//! The host's multi-resolution oracle builds exactly this surface with logic of its own. The neighbours' regions
//! come from the same rules, followed down the one path to a neighbouring cell (O(depth) per side of a coarse
//! border cell that the ray crosses). Limitation: a global grid's closing meridian (its last column repeating
//! the first) is treated as an edge of the DEM, with no stitching across it.
//!
//! **Bounds.** A node's volume bounds the coarsest cells traced under it: its own block's (a resident node's
//! descendants are finer), or its source's when it falls back. A stitched cell's vertices on its rows lie on
//! the latitude cones between its meridians, and a cone's arc bulges across the cell's chord plane on one side
//! (the southern side for ψ > 0, the northern for ψ < 0) — near a pole, where a coarse cell can be hundreds of
//! times wider than tall, even across the opposite row's chord plane. So both row walls of a coarse region's
//! border cells bound the whole latitude band in the cell's wedge: the cone's tangent plane along the middle
//! meridian on the convex side, the chord plane on the other (`leaf.rs`, `border_wall`).

use super::error::TerrainError;
use super::grid::NodeId;
use super::picker::{Picker, div_ceil_pow2};
use super::refine::{TriRef, Vtx};
use super::storage::{TerrainCaches, vertex_ecef};
use super::walk::{CellAt, Lookup, SideAt, Stitch, Unit, Walk};
use crate::real::Real;
use crate::vec3::V3;
impl<T: Real, S: TerrainCaches<T>, const STACK: usize, const ZONES: usize>
    Picker<'_, T, S, STACK, ZONES>
{
    /// Stitching of a coarse cell on its unit's border (this file's docs, "Continuity"): when a neighbouring
    /// unit is finer along a side, that unit's vertices on the side are T-junctions of the coarse edge, and the
    /// cell is triangulated instead as a fan from the middle `M` of its diagonal `V00–V11` through its corners
    /// and every such vertex, so that the two sides share every edge exactly. `Plain` when no side has such a
    /// vertex (or a diagonal corner is nodata: the cell has no triangle then); `Done` after testing the fan, or
    /// when a neighbour's block is needed (recorded at `t_cell`).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn stitch(
        &self,
        u: &Unit,
        cell: &CellAt,
        v00: Option<V3<T>>,
        v11: Option<V3<T>>,
        w: &mut Walk<'_, '_, T>,
        t_cell: T,
    ) -> Result<Stitch, TerrainError> {
        let (Some(p00), Some(p11)) = (v00, v11) else {
            return Ok(Stitch::Plain);
        };
        let sides = self.cell_sides(u, cell);
        let mut any = false;
        for side in &sides {
            if let Some(id) = self.side_extras(u.stride, side, &mut |_| any = true)? {
                w.need(t_cell, id);
                return Ok(Stitch::Done);
            }
        }
        if !any {
            return Ok(Stitch::Plain);
        }
        let m = p00.plus(p11).scaled(T::HALF);
        let [i, i1] = cell.rows;
        let [j, j1] = cell.cols;
        let mid = Vtx::Mid([i, j, i1, j1]);
        // The four sides from corner to corner, each with its extra vertices in increasing order.
        for side in sides {
            let at = |p: u32| {
                if side.along_cols {
                    (side.fixed, p)
                } else {
                    (p, side.fixed)
                }
            };
            let mut prev = at(side.from);
            // A side on the grid's outer edge has no triangle across its fan edges.
            let last = if side.along_cols {
                self.grid.cell_rows()
            } else {
                self.grid.cell_cols()
            };
            let outer = [side.fixed == 0 || side.fixed >= last, false, false];
            let mut fan = |p: u32| {
                let cur = at(p);
                if let (Some(a), Some(b)) = (self.vertex(prev.0, prev.1), self.vertex(cur.0, cur.1))
                {
                    let refs =
                        TriRef::Vertices([mid, Vtx::Grid(prev.0, prev.1), Vtx::Grid(cur.0, cur.1)]);
                    self.test_triangle(w, [m, a, b], [i, j], refs, u, move || outer);
                }
                prev = cur;
            };
            // Needs were ruled out by the first pass; a side without `across` has no extra vertices.
            let _ = self.side_extras(u.stride, &side, &mut fan)?;
            fan(side.to);
        }
        Ok(Stitch::Done)
    }

    /// Grid vertex `V(i, j)` from the storage's trigonometry (the same arithmetic as the traced cells' vertices,
    /// so that shared vertices are bit-identical); `None` for nodata.
    pub(super) fn vertex(&self, i: u32, j: u32) -> Option<V3<T>> {
        vertex_ecef(self.storage, &self.ellipsoid, i, j)
    }

    /// The four sides of a cell, from corner to corner (low row, high row, low column, high column); `across` is
    /// set on the sides that lie on the unit's border and have a neighbouring cell row or column in the grid.
    pub(super) fn cell_sides(&self, u: &Unit, c: &CellAt) -> [SideAt; 4] {
        let [i, i1] = c.rows;
        let [j, j1] = c.cols;
        let g = &self.grid;
        let row = |fixed: u32, across: Option<u32>| SideAt {
            along_cols: true,
            fixed,
            from: j,
            to: j1,
            across,
        };
        let col = |fixed: u32, across: Option<u32>| SideAt {
            along_cols: false,
            fixed,
            from: i,
            to: i1,
            across,
        };
        [
            row(i, (i == u.rows[0]).then(|| i.checked_sub(1)).flatten()),
            row(i1, (i1 == u.rows[1] && i1 < g.cell_rows()).then_some(i1)),
            col(j, (j == u.cols[0]).then(|| j.checked_sub(1)).flatten()),
            col(j1, (j1 == u.cols[1] && j1 < g.cell_cols()).then_some(j1)),
        ]
    }

    /// Calls `emit(p)`, in increasing order, for every vertex strictly inside a coarse cell's side (of a cell
    /// `stride` steps wide) that a finer neighbouring unit has on it: the points of its sample lattice. Returns
    /// the node whose block is needed to know the neighbour, if any.
    pub(super) fn side_extras(
        &self,
        stride: u32,
        side: &SideAt,
        emit: &mut impl FnMut(u32),
    ) -> Result<Option<NodeId>, TerrainError> {
        let Some(across) = side.across else {
            return Ok(None);
        };
        let (from, to) = (side.from, side.to);
        let mut k = from;
        let mut last = from;
        while k < to {
            let look = if side.along_cols {
                self.unit_at(across, k)?
            } else {
                self.unit_at(k, across)?
            };
            match look {
                Lookup::Needs(id) => return Ok(Some(id)),
                Lookup::Empty => k = k.saturating_add(1),
                Lookup::Unit(n) => {
                    let range = if side.along_cols { n.cols } else { n.rows };
                    let end = range[1].min(to);
                    if n.stride < stride {
                        let mut p = div_ceil_pow2(k, n.stride).saturating_mul(n.stride);
                        while p <= end && p < to {
                            if p > last {
                                emit(p);
                                last = p;
                            }
                            p = p.saturating_add(n.stride);
                        }
                    }
                    k = end.max(k.saturating_add(1));
                }
            }
        }
        Ok(None)
    }
}
