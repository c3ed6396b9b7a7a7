//! The traversal (Wartell et al. §3.5, §5): the global clip and the zones in order of entry (`nearest`); a zone's
//! quadtree visited depth first, nearest child first, with an explicit stack; what to do at a node under
//! multi-resolution paging; the traced unit that covers a cell.
//!
//! # Zones and quads
//!
//! **Zones** come from the storage ([`TerrainStorage::zone`]), aligned to the DEM's grid (for a global DEM the
//! storage typically uses 8 × 4 = 32 zones bounded by meridians and parallels; a regional DEM its own extent).
//! Each zone's volume is tested against the ray (after the global clip to `B^{h_max}`) and the zones are
//! visited in order of entry.
//!
//! **Quads** (§3.1–3.5): each node's volume is a [`HeightQuadBounds`] — meridian wedge, latitude cones, upper
//! spheroid `B^{h_max}`, lower sphere — and the ray's parameter hull inside it comes from the crossings of those
//! walls (the §3.5 "side interval against `B^h` interval" test, generalised so that a volume entered twice
//! yields one hull over both visits). The traversal itself tests zones and children against a relaxed, convex
//! superset of that volume ([`crate::geodesy::relaxed_interval`]: each latitude cone replaced by a plane
//! bounding its side, so the hull needs no point tests), and a child only against its walls on the parent's
//! internal partition ([`crate::geodesy::SideWalls`]). Children are visited nearest entry first, with an
//! explicit stack of fixed capacity (the const generic `STACK`; no recursion).
//!
//! This replaces the paper's sequential stepping between children (the child entered from `side_in` and the
//! internal partition half-spaces, the next child from `side_out`, the 3-or-4-side exit rule): those rules
//! assume that the quads' walls partition space, which the *conservative* volumes needed for triangles (the
//! containment problem of §4, below) no longer do — inflated neighbours overlap. Ordering by the entry
//! parameter gives the same visiting order where the volumes do not overlap (the zone or quad containing the
//! origin has entry `t_min` and is visited first; the next one is the one whose wall the ray crosses next),
//! handles a quad the ray enters twice (one hull over both visits), and is what the no-miss proof below needs.
//! Traversal ends when no pending quad can be entered before the best hit, or at `t_global_exit`.
//!
//! When the storage gives node boxes ([`TerrainCaches::node_box`]; beyond the paper), zones and children are
//! tested against those instead: a box around all of the node's vertices in a local frame ([`boxes`]: its
//! parent's, or the one its parent's box is in, down from nodes narrow enough to share one), so that the ray is
//! moved into each frame once and each child costs three slabs — a small fraction of the relaxed test — and,
//! for a node a few kilometres across, the tighter bound. (A global grid's zones, whose boxes lie in one frame
//! for the whole grid, are clipped by their volumes too.)
//!
//! # No misses: what is proven
//!
//! The paper's walls are not walls for triangles: a planar triangle dips below its vertices (so §3.2's sphere
//! through the lowest vertex is not a lower bound) and, along a latitude border, bulges across the cone wall into
//! the neighbouring quad (§4's containment problem, Fig. 10); the paper then stops at the first quad with a hit.
//! Here instead:
//!
//! * every quad's volume provably contains all of its triangles ([`crate::geodesy::HeightQuadBounds`] derives
//!   the sagitta bound for the lower wall and the bulge bound for the latitude walls from the curvature of the
//!   height and cone functions; meridian walls and the upper bound are exact for triangles by convexity), and
//!   the relaxed volume the traversal tests contains those triangles too (each of its planes bounds a cone's
//!   side, on the quad's wedge; [`crate::geodesy::relaxed_interval`]); a node box ([`boxes`]) contains all of
//!   the node's vertices, hence the convex hull of any triangle traced under it, with no curvature bound needed;
//! * every cell's planar volume contains its two triangles exactly; the rows a column's segment skips lie
//!   beyond the planes it does not cross, and a cell skipped by the height cull has its corners' convex hull
//!   wholly on one side of the ray's part in the cell (both tests inflated by the rounding; `leaf.rs`);
//! * the traversal keeps the best hit `t*` found so far and discards a quad only when its entry parameter exceeds
//!   `t*`, and stops only when no pending quad or zone can start before `t*`.
//!
//! Hence a triangle hit at `t < t*` lies in some quad whose interval contains `t`, which is never discarded, down
//! to its leaf and its cell, which is tested: the returned hit is the **nearest** one (up to the floating-point
//! tolerance of the point tests, which inflate every wall by a few ulps of the coordinates, and the rounding of
//! the triangle test itself). Overlapping inflated volumes only cost extra tests, never a miss. CesiumJS's picking
//! returns the first tile with a hit (its issue #3423); this traversal cannot.
//!
//! # Which blocks are traced (multi-resolution, §5)
//!
//! The traversal descends from the zones. A node shallower than the picker's `min_level`
//! ([`Picker::with_min_level`]) is only passed through, unless it is a leaf: then its own block is traced, or
//! [`TerrainError::NeedsBlock`] is reported if it is missing. From `min_level` on, a resident node becomes the
//! *source*: the nearest resident ancestor of everything below it (§5). A resident leaf traces its own block.
//! Below a missing block the traversal goes on down as long as the source's cells fit inside the children
//! (their ranges fall on the source's sample lattice), so that a deeper resident block still answers for its own
//! region; a missing leaf, or a missing node whose children are smaller than the source's cells, is traced whole
//! with the source's block — the part of the source's block over the node, cells `(r − r_A)/s_A` of the source
//! `A` (the §5 block subset: for a leaf `k` levels below `A`, [`subset::BlockSubset`]'s rectangle after `k`
//! steps, `B >> k` cells wide). So a source cell is never split: where it is larger than the leaves below it
//! (the paper's "at least one cell"), it answers for all of them, and resident blocks inside it are not used.
//! That keeps the traced regions disjoint — a coarse cell never overlaps finer data — so the surface is one
//! sheet. A missing node without a source (at `min_level`), or off its source's lattice, needs its own block.
//!
//! **`NeedsBlock`.** A missing block is reported only if the ray reaches its node before the nearest hit found
//! elsewhere: the answer depends on it. The caller pages the block in and asks again.
//!
//! # Cost
//!
//! Per child of a visited quad, only along the part of the ray inside the parent: with node boxes, three slabs
//! (the ray is rotated into each frame once: on a regional DEM once per zone or per ray); without them, the
//! child's walls on the parent's internal partition: the internal meridian plane (a division), then the rest of
//! the relaxed volume (the internal latitude plane, the upper spheroid, the lower sphere), each step only if the
//! interval is still non-empty. [`PickStats`] counts quads, triangle pairs (cells whose planar volume the ray
//! crosses) and triangles tested per ray.

use super::boxes::FrameRay;
use super::error::TerrainError;
use super::grid::{Grid, Node, NodeId};
use super::picker::{Picker, check_child, node_trig};
use super::storage::{TerrainCaches, node_frame};
use super::triangle::WatertightRay;
use super::walk::{
    Candidate, Entry, FRAMES, Lookup, PickStats, Source, Step, Unit, Walk, ZoneVolume,
};
use crate::geodesy::relaxed_interval;
use crate::ray::{Ray, RayError};
use crate::real::Real;
use crate::sort::insertion_sort;
use crate::surface::{Side, Surface};
use crate::vec3::V3;
impl<T: Real, S: TerrainCaches<T>, const STACK: usize, const ZONES: usize>
    Picker<'_, T, S, STACK, ZONES>
{
    /// The traversal (phases 1–4 of the module docs): the nearest triangle, before the refinement.
    pub(super) fn nearest(
        &self,
        ray: &Ray<T>,
        stats: &mut PickStats,
    ) -> Result<Option<Candidate<T>>, TerrainError> {
        // 1. Global clip to B^{h_max}: [t_enter, t_global_exit].
        let Some(upper) = &self.upper else {
            return Ok(None); // no zone with data
        };
        let cr = upper.crossings(ray);
        let inside0 = upper.side_of(V3::from(ray.at(ray.t_min()))) != Some(Side::Positive);
        let mut t_enter = if inside0 { Some(ray.t_min()) } else { None };
        let mut t_exit = ray.t_max();
        for c in &cr {
            match c.into {
                Side::Negative => {
                    if t_enter.is_none() {
                        t_enter = Some(c.t);
                    }
                }
                Side::Positive => {
                    if t_enter.is_some() {
                        t_exit = c.t;
                    }
                }
            }
        }
        let Some(t_enter) = t_enter else {
            return Ok(None);
        };
        if t_enter == T::INFINITY {
            // the line enters the volume where t overflows (a direction too short for its distance)
            return Err(TerrainError::Unrepresentable);
        }
        // A line that leaves the volume where t overflows is searched up to the largest finite t; if no hit is
        // found there, the answer is not representable (below).
        let beyond = t_exit == T::INFINITY;
        let t_exit = if beyond { T::MAX } else { t_exit };
        // Inflate the clip by a few ulps ([`inflated_clip`]): the triangle test decides hits, the clip only
        // culls. (No ray is known whose hit needs the slack: the zones' and cells' own intervals carry their
        // own tolerances; it keeps the clip from being the one bound without any.)
        let (t_lo, t_hi) = inflated_clip(ray, t_enter, t_exit);
        if !t_hi.is_finite() || !(t_lo <= t_hi) {
            return Ok(None);
        }
        let clipped = ray.with_interval(t_lo, t_hi)?;
        // sheared from the exactly rescaled direction, in the ray's scaled parameter (`leaf::test_triangle`)
        let wray = WatertightRay::new(ray.origin(), ray.scaled_dir())
            .ok_or(TerrainError::Ray(RayError::ZeroDirection))?;

        // 2. Zones in order of entry.
        let mut order: heapless::Vec<(usize, T, T), ZONES> = heapless::Vec::new();
        let grid_ray = self.grid_frame.ray(ray, [t_lo, t_hi]);
        for (k, bbox) in self.zone_boxes.iter().enumerate().take(self.zone_count) {
            let volume = |r: &Ray<T>| match self.zones.get(k) {
                Some(Some((_, _, ZoneVolume::Cached(b)))) => b.ray_interval(r),
                Some(Some((_, _, ZoneVolume::Relaxed(v)))) => v.interval(r),
                _ => None,
            };
            // The box in the grid's frame is tight for a regional grid; across a global one its faces tilt by up
            // to 180°, so the zone's own volume then clips what the box leaves.
            let interval = match bbox {
                Some(b) if self.regional => grid_ray.interval(b, [t_lo, t_hi]),
                Some(b) => grid_ray
                    .interval(b, [t_lo, t_hi])
                    .and_then(|(a, c)| clipped.with_interval(a, c).ok())
                    .and_then(|r| volume(&r)),
                None => volume(&clipped),
            };
            if let Some((a, c)) = interval {
                // At most `ZONES` zones (checked by `new`), so the push cannot fail.
                let _ = order.push((k, a, c));
            }
        }
        insertion_sort(&mut order, |x, y| x.1 < y.1);

        let mut best: Option<Candidate<T>> = None;
        let mut pending: Option<(T, NodeId)> = None;
        let mut budget = node_budget(&self.grid, self.zone_count);
        for &(k, a, c) in order.iter() {
            if let Some(h) = &best {
                if a > h.t {
                    break;
                }
            }
            let Some(Some((id, _, _))) = self.zones.get(k) else {
                continue;
            };
            let root = Entry {
                id: *id,
                parent: None,
                t_in: a,
                t_out: c,
                parent_stride: u32::MAX,
                src: None,
                frame: 0,
                depth: 0,
            };
            let mut walk = Walk {
                ray,
                wray: &wray,
                best: &mut best,
                pending: &mut pending,
                stats,
            };
            self.traverse(root, &grid_ray, &mut walk, &mut budget)?;
        }
        // A missing block matters only if it could hold a hit before the nearest one found.
        match (pending, &best) {
            (Some((t, id)), Some(h)) if t <= h.t => Err(TerrainError::NeedsBlock(id)),
            (Some((_, id)), None) => Err(TerrainError::NeedsBlock(id)),
            (None, None) if beyond => Err(TerrainError::Unrepresentable),
            _ => Ok(best),
        }
    }

    /// Depth-first, nearest-child-first traversal of one zone with an explicit stack. `grid_ray` is the ray in
    /// the grid's frame, where the zones' boxes are.
    ///
    /// With node boxes, the ray is moved into each frame that boxes are in once ([`boxes`], "Which frame"): a
    /// node's own frame is kept at index `depth + 1` of an array of frames and its children's entries refer to
    /// the index their boxes were tested in ([`Entry::frame`]). Only nodes at depth `d` write index `d + 1`
    /// (below it they only fill slots that no entry refers to), and a node at depth `d` is visited only after
    /// the whole subtree of every node visited before it at depth `d` or deeper (those were pushed above it on
    /// the stack, or descend from nodes that were): so no pending entry still refers to the index it overwrites.
    // Out of line (like `trace_unit` and `crossed_rows`): inlined into `nearest`, the three cost about 5 % more
    // instructions per pick (callgrind).
    #[inline(never)]
    pub(super) fn traverse(
        &self,
        root: Entry<T>,
        grid_ray: &FrameRay<T>,
        w: &mut Walk<'_, '_, T>,
        budget: &mut u64,
    ) -> Result<(), TerrainError> {
        let ray = w.ray;
        let mut stack: heapless::Vec<Entry<T>, STACK> = heapless::Vec::new();
        stack.push(root).map_err(|_| TerrainError::StackFull)?;
        let mut frames: heapless::Vec<FrameRay<T>, FRAMES> = heapless::Vec::new();
        frames
            .push(*grid_ray)
            .map_err(|_| TerrainError::StackFull)?;
        while let Some(e) = stack.pop() {
            let best_t = w.best_t();
            if e.t_in > best_t {
                continue;
            }
            *budget = budget.checked_sub(1).ok_or(TerrainError::TraversalBound)?;
            let node = self.storage.node(e.id).ok_or(TerrainError::MalformedTree)?;
            if let Some((rows, cols)) = e.parent {
                check_child(rows, cols, &node)?;
            }
            let stride = self.stride_of(e.id, e.parent_stride)?;
            if node.heights.is_none() {
                continue;
            }
            w.stats.quads_visited = w.stats.quads_visited.saturating_add(1);
            let t_out = e.t_out.min(best_t);
            let src = match self.step(e.id, &node, stride, e.src)? {
                Step::Trace(unit) => {
                    // A full-resolution leaf by its windows when the storage gives their boxes (`windows.rs`),
                    // in the frame its own box was tested in. (Every traced unit has its node's ranges, `step`;
                    // a coarser stride is a source's block, whose cells the windows do not follow.)
                    let windows = self.storage.window_boxes(e.id);
                    let own = unit.stride == 1;
                    match (
                        self.storage.node_box(e.id),
                        frames.get(usize::from(e.frame)),
                    ) {
                        (Some(b), Some(f)) if own && !windows.is_empty() => {
                            self.trace_windows(&unit, &b, f, windows, e.t_in, t_out, w)?;
                        }
                        _ => self.trace_unit(&unit, e.t_in, t_out, w)?,
                    }
                    continue;
                }
                Step::Needs => {
                    w.need(e.t_in, e.id);
                    continue;
                }
                Step::Descend(src) => src,
            };
            // Children go straight onto the stack, then are sorted there, nearest entry on top.
            let span = [e.t_in.max(ray.t_min()), t_out.max(e.t_in).min(ray.t_max())];
            let first = stack.len();
            let depth = e.depth.checked_add(1).ok_or(TerrainError::StackFull)?;
            // This node's own frame, at index `depth` once a child's box needs it.
            let mut own_ready = false;
            for cid in node.children.iter().flatten() {
                let (interval, frame) = match self.storage.node_box(*cid) {
                    // The box holds all of the child's vertices, so every triangle traced under it.
                    Some(b) => {
                        let k = if b.shared_frame { e.frame } else { depth };
                        if !b.shared_frame && !own_ready {
                            let own = usize::from(depth);
                            frames.truncate(own);
                            while frames.len() < own {
                                // Filler below the own frame, never referred to.
                                let last = *frames.last().ok_or(TerrainError::MalformedTree)?;
                                frames.push(last).map_err(|_| TerrainError::StackFull)?;
                            }
                            let f = node_frame(self.storage, &self.ellipsoid, &node);
                            frames
                                .push(f.ray(ray, span))
                                .map_err(|_| TerrainError::StackFull)?;
                            own_ready = true;
                        }
                        let f = frames
                            .get(usize::from(k))
                            .ok_or(TerrainError::MalformedTree)?;
                        (f.interval(&b, span), k)
                    }
                    None => {
                        let child = self.storage.node(*cid).ok_or(TerrainError::MalformedTree)?;
                        check_child(node.rows, node.cols, &child)?;
                        let Some([lo, hi]) = child.heights else {
                            continue;
                        };
                        let c_stride = self.stride_of(*cid, stride)?;
                        let [a, c] = span;
                        let sub = ray.with_interval(a, c)?;
                        let v =
                            self.volume_interval(*cid, &child, &node, c_stride, src, lo, hi, &sub)?;
                        (v, e.frame)
                    }
                };
                if let Some((t_in, t_out)) = interval {
                    let child = Entry {
                        id: *cid,
                        parent: Some((node.rows, node.cols)),
                        t_in,
                        t_out,
                        parent_stride: stride,
                        src,
                        frame,
                        depth,
                    };
                    stack.push(child).map_err(|_| TerrainError::StackFull)?;
                }
            }
            let kids = stack.get_mut(first..).unwrap_or(&mut []);
            insertion_sort(kids, |x, y| x.t_in > y.t_in);
        }
        Ok(())
    }

    /// The hull of `sub` in a child's spheroidal volume (a storage without node boxes): the storage's cached
    /// volume or the relaxed test, from its walls on the parent's partition. The volume bounds the coarsest
    /// cells traced under the child: its own block's, or the source's when the child falls back to it.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn volume_interval(
        &self,
        id: NodeId,
        child: &Node<T>,
        parent: &Node<T>,
        stride: u32,
        src: Option<Source>,
        lo: T,
        hi: T,
        sub: &Ray<T>,
    ) -> Result<Option<(T, T)>, TerrainError> {
        let falls_back = child.level >= self.min_level && !self.storage.is_resident(id);
        let vol = match src {
            Some(s) if falls_back => s.stride,
            _ => stride,
        };
        if let Some(b) = self.storage.cached_bounds(id).filter(|_| vol == 1) {
            return Ok(b.ray_interval(sub));
        }
        Ok(relaxed_interval(
            &self.ellipsoid,
            &node_trig(
                &self.grid,
                self.storage,
                child,
                Some(parent),
                self.half_cell(vol).1,
            ),
            lo,
            hi,
            self.grid.dlat_deg * self.scale(vol),
            self.grid.dlon_deg * self.scale(vol),
            sub,
        )?)
    }

    /// What to do at a node (this file's docs, "Which blocks are traced"): `stride` is its block stride, `src` the source
    /// inherited from its parent.
    #[inline(always)]
    pub(super) fn step(
        &self,
        id: NodeId,
        node: &Node<T>,
        stride: u32,
        src: Option<Source>,
    ) -> Result<Step, TerrainError> {
        let own = Unit {
            rows: node.rows,
            cols: node.cols,
            stride,
            level: node.level,
        };
        let resident = self.storage.is_resident(id);
        if node.level < self.min_level {
            // Above min_level a block is used only by a leaf, for itself.
            return Ok(match (node.is_leaf(), resident) {
                (false, _) => Step::Descend(None),
                (true, true) => Step::Trace(self.aligned(own).ok_or(TerrainError::MalformedTree)?),
                (true, false) => Step::Needs,
            });
        }
        if resident {
            return Ok(if node.is_leaf() {
                Step::Trace(self.aligned(own).ok_or(TerrainError::MalformedTree)?)
            } else {
                Step::Descend(Some(Source {
                    stride,
                    level: node.level,
                }))
            });
        }
        // Not resident. Without a source its own block is needed. With one, the traversal goes on down while the
        // source's cells fit inside the children (a deeper resident block may answer there); otherwise the node
        // is traced whole with the source's block: the subset that covers it (§5), on the source's lattice
        // (if not, its own block is needed).
        let Some(s) = src else {
            return Ok(Step::Needs);
        };
        if !node.is_leaf() && self.children_on_lattice(node, s.stride)? {
            return Ok(Step::Descend(src));
        }
        Ok(self
            .aligned(Unit {
                stride: s.stride,
                level: s.level,
                ..own
            })
            .map_or(Step::Needs, Step::Trace))
    }

    /// Whether every child with data of `node` has ranges on the lattice of `stride`.
    pub(super) fn children_on_lattice(
        &self,
        node: &Node<T>,
        stride: u32,
    ) -> Result<bool, TerrainError> {
        for cid in node.children.iter().flatten() {
            let c = self.storage.node(*cid).ok_or(TerrainError::MalformedTree)?;
            let on = self
                .aligned(Unit {
                    rows: c.rows,
                    cols: c.cols,
                    stride,
                    level: c.level,
                })
                .is_some();
            if c.heights.is_some() && !on {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The unit if its ranges start on multiples of its stride and end on one or at the grid's last cell.
    pub(super) fn aligned(&self, u: Unit) -> Option<Unit> {
        if u.stride == 1 {
            return Some(u);
        }
        let fits = |r: [u32; 2], last: u32| {
            let [a, b] = r;
            a.checked_rem(u.stride) == Some(0) && (b.checked_rem(u.stride) == Some(0) || b == last)
        };
        (fits(u.rows, self.grid.cell_rows()) && fits(u.cols, self.grid.cell_cols())).then_some(u)
    }

    /// The traced unit that covers grid cell `(i, j)` under the current residency: the traversal's own rules,
    /// followed down the one path that holds the cell.
    pub(super) fn unit_at(&self, i: u32, j: u32) -> Result<Lookup, TerrainError> {
        let holds = |n: &Node<T>| {
            (n.rows[0]..n.rows[1]).contains(&i) && (n.cols[0]..n.cols[1]).contains(&j)
        };
        let Some((mut id, mut node)) = self
            .zones
            .iter()
            .take(self.zone_count)
            .flatten()
            .find(|(_, n, _)| holds(n))
            .map(|(id, n, _)| (*id, *n))
        else {
            return Ok(Lookup::Empty);
        };
        let mut stride = self.stride_of(id, u32::MAX)?;
        let mut src = None;
        // Children are strictly smaller, so a path has at most 64 nodes within u32 ranges.
        for _ in 0..64 {
            match self.step(id, &node, stride, src)? {
                Step::Trace(u) => return Ok(Lookup::Unit(u)),
                Step::Needs => return Ok(Lookup::Needs(id)),
                Step::Descend(s) => src = s,
            }
            let mut next = None;
            for cid in node.children.iter().flatten() {
                let child = self.storage.node(*cid).ok_or(TerrainError::MalformedTree)?;
                if holds(&child) {
                    check_child(node.rows, node.cols, &child)?;
                    next = Some((*cid, child));
                    break;
                }
            }
            let Some((cid, child)) = next else {
                return Ok(Lookup::Empty);
            };
            if child.heights.is_none() {
                return Ok(Lookup::Empty);
            }
            stride = self.stride_of(cid, stride)?;
            (id, node) = (cid, child);
        }
        Err(TerrainError::TraversalBound)
    }
}

/// The most nodes a well-formed forest over this grid can have (each node has ≥ 1 cell and children are
/// strictly smaller; a quadtree has fewer than 4/3 nodes per leaf) with generous slack.
fn node_budget<T: Real>(g: &Grid<T>, zones: usize) -> u64 {
    let cells = u64::from(g.cell_rows()).saturating_mul(u64::from(g.cell_cols()));
    cells
        .saturating_mul(4)
        .saturating_add(u64::try_from(zones).unwrap_or(u64::MAX))
        .saturating_add(16)
}

/// The global clip `[t_enter, t_exit]` widened by `64 ε (|t_enter| + |t_exit|)` at either end, then cut to the
/// ray's interval and to the largest finite `t`.
#[inline]
fn inflated_clip<T: Real>(ray: &Ray<T>, t_enter: T, t_exit: T) -> (T, T) {
    let slack = T::from_f64(64.0) * T::EPSILON * (t_enter.abs() + t_exit.abs());
    let t_lo = (t_enter - slack).max(ray.t_min());
    let t_hi = (t_exit + slack).min(ray.t_max()).min(T::MAX);
    (t_lo, t_hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The clip's slack is `64 ε (|t_enter| + |t_exit|)` at both ends (exactly, for ends whose sum and slack
    /// are exact), inside the ray's own interval.
    #[test]
    fn the_global_clip_widens_by_64_eps_times_the_ends_magnitudes_inside_the_rays_interval() {
        let ray = Ray::new([1.0e7, 0.0, 0.0], [-1.0, 0.0, 0.0])
            .and_then(|r| r.with_interval(f64::NEG_INFINITY, f64::INFINITY))
            .unwrap();
        // 3 · 2^20 and 5 · 2^20: the slack is 64 ε · 2^23 = 2^-23 exactly
        let (a, b) = (3.0 * 1_048_576.0, 5.0 * 1_048_576.0);
        let slack = 1.0 / 8_388_608.0;
        assert_eq!(inflated_clip(&ray, a, b), (a - slack, b + slack));
        // either end's sign does not shrink the slack
        assert_eq!(inflated_clip(&ray, -a, b), (-a - slack, b + slack));
        // cut to the ray's interval where it ends within the slack
        let inner = slack / 2.0;
        let seg = ray.with_interval(a - inner, b + inner).unwrap();
        assert_eq!(inflated_clip(&seg, a, b), (a - inner, b + inner));
        // and to the largest finite t
        assert_eq!(inflated_clip(&ray, a, f64::MAX).1, f64::MAX);
    }
}
