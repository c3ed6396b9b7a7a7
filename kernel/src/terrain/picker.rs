//! The picker (Wartell et al. §3.5): a borrowed storage, the per-storage constants (global bound, zone volumes), and
//! the public entry points [`Picker::pick`], [`Picker::pick_t`] and [`Picker::line_of_sight`]. The phases of a pick
//! are in their own files (module docs of [`super`], "A pick, phase by phase").

use super::boxes::{LocalFrame, NodeBox};
use super::error::TerrainError;
use super::grid::{Grid, Node, NodeId};
use super::storage::{TerrainCaches, box_frame};
use super::walk::{PickStats, Zone, ZoneVolume};
use crate::geodesy::{
    Ellipsoid, HeightQuadBounds, QuadTrig, RelaxedVolume, SideWalls, sin_cos_deg, upper_spheroid,
};
use crate::ray::Ray;
use crate::real::Real;
use crate::surface::Spheroid;
use crate::vec3::V3;

/// The nearest intersection of a ray with the terrain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit<T> {
    /// Ray parameter (in the units of the ray's direction).
    pub t: T,
    /// The hit point, ECEF: `origin + t·dir` formed in double-double from the refined parameter and rounded once
    /// per coordinate (so it may differ from `ray.at(t)` by the rounding of `t·dir`; module docs, step 5; `hit.rs`).
    pub ecef: [T; 3],
    /// Geodetic latitude of the hit point, degrees.
    pub lat_deg: T,
    /// Longitude of the hit point, degrees in [−180, 180].
    pub lon_deg: T,
    /// Height of the hit point above the ellipsoid.
    pub h: T,
    /// The grid cell `[i, j]` whose triangle was hit: the first grid row and column of the traced cell, which
    /// spans `stride × stride` grid cells.
    pub cell: [u32; 2],
    /// The quadtree level of the node whose block was traced (the leaf's, or its resident ancestor's, §5).
    pub level: u8,
    /// The traced cell's size in grid steps: 1 at the DEM's own resolution, the block's
    /// [`TerrainStorage::block_stride`](crate::terrain::TerrainStorage::block_stride) for coarser blocks.
    pub stride: u32,
}

/// The picker: a borrowed storage plus the per-storage constants (global bound, zone volumes).
///
/// `STACK` is the capacity of the traversal stack (up to 3 entries per tree level plus 4); `ZONES` the maximum
/// number of zones. Both are fixed memory inside the picker and the call frame; exceeding them is an error (as is
/// a path with node boxes in more than 31 distinct frames below the grid's).
#[derive(Debug, Clone)]
pub struct Picker<'s, T, S, const STACK: usize = 64, const ZONES: usize = 64> {
    pub(super) storage: &'s S,
    pub(super) ellipsoid: Ellipsoid<T>,
    pub(super) grid: Grid<T>,
    /// Global height range over the zones.
    pub(super) h_max: T,
    /// The global clip `B^{h_max}` (§3.5), once there is a zone with data.
    pub(super) upper: Option<Spheroid<T>>,
    /// `(sin, cos)` of half a traced cell's longitude span, for cells of `2^k` grid steps.
    pub(super) half_cells: [(T, T); 32],
    /// The coarsest level whose blocks may stand in for missing finer ones (§5).
    pub(super) min_level: u8,
    pub(super) zones: [Option<Zone<T>>; ZONES],
    /// The zones' boxes (in the grid's frame) if the storage has them, compact for the per-ray scan.
    pub(super) zone_boxes: [Option<NodeBox>; ZONES],
    pub(super) zone_count: usize,
    /// The frame of the zones' boxes ([`box_frame`] without a parent).
    pub(super) grid_frame: LocalFrame<T>,
    /// The grid spans less than 30° both ways: its frame's boxes are tight enough on their own.
    pub(super) regional: bool,
    /// `2 e² (a²/b)(1 + e² a²/b²)`: beyond this distance from the axis a column's row planes are ordered
    /// ([`Picker::crossed_rows`]).
    pub(super) rows_ordered_beyond: T,
    /// `e² a²/b`: how far the apex of the pole's latitude cone lies from the centre, the farthest of any row's
    /// (the row planes' tolerance, [`Picker::crossed_rows`]).
    pub(super) pole_apex: T,
}

impl<'s, T: Real, S: TerrainCaches<T>, const STACK: usize, const ZONES: usize>
    Picker<'s, T, S, STACK, ZONES>
{
    /// Checks the storage's grid and zones and precomputes the zone volumes. `min_level` is 0: any resident
    /// block may stand in for a missing finer one ([`Picker::with_min_level`]).
    pub fn new(storage: &'s S) -> Result<Self, TerrainError> {
        let ellipsoid = storage.ellipsoid();
        let grid = storage.grid();
        if !grid.validate() {
            return Err(TerrainError::InvalidGrid);
        }
        let n = storage.zone_count();
        if n > ZONES {
            return Err(TerrainError::TooManyZones);
        }
        let mut half_cells = [(T::ZERO, T::ONE); 32];
        let mut width = grid.dlon_deg.abs() * T::HALF;
        for h in &mut half_cells {
            *h = sin_cos_deg(width);
            width *= T::TWO;
        }
        let mut picker = Picker {
            storage,
            ellipsoid,
            grid,
            h_max: T::NEG_INFINITY,
            upper: None,
            half_cells,
            min_level: 0,
            zones: [None; ZONES],
            zone_boxes: [None; ZONES],
            zone_count: 0,
            grid_frame: box_frame(storage, &ellipsoid, None),
            rows_ordered_beyond: {
                let (e2, q) = (ellipsoid.e2(), ellipsoid.a() / ellipsoid.b());
                T::TWO * e2 * ellipsoid.a() * q * (T::ONE + e2 * q * q)
            },
            pole_apex: ellipsoid.e2() * ellipsoid.a() * (ellipsoid.a() / ellipsoid.b()),
            regional: {
                let span = |n: u32, step: T| T::from_f64(f64::from(n)) * step.abs();
                let lim = T::from_f64(30.0);
                span(grid.cell_rows(), grid.dlat_deg) < lim
                    && span(grid.cell_cols(), grid.dlon_deg) < lim
            },
        };
        for k in 0..n {
            let id = storage.zone(k).ok_or(TerrainError::MalformedTree)?;
            let node = storage.node(id).ok_or(TerrainError::MalformedTree)?;
            check_in_grid(&node, &grid)?;
            let stride = picker.stride_of(id, u32::MAX)?;
            let Some([lo, hi]) = node.heights else {
                continue; // a zone without data has no triangles
            };
            let b = match storage.cached_bounds(id).filter(|_| stride == 1) {
                Some(b) => ZoneVolume::Cached(b),
                None => ZoneVolume::Relaxed(RelaxedVolume::new(
                    &ellipsoid,
                    &node_trig(&grid, storage, &node, None, picker.half_cell(stride).1),
                    lo,
                    hi,
                    grid.dlat_deg * picker.scale(stride),
                    grid.dlon_deg * picker.scale(stride),
                )?),
            };
            picker.h_max = picker.h_max.max(hi);
            let k = picker.zone_count;
            if let (Some(slot), Some(bbox)) =
                (picker.zones.get_mut(k), picker.zone_boxes.get_mut(k))
            {
                *slot = Some((id, node, b));
                *bbox = storage.node_box(id);
                picker.zone_count = k.saturating_add(1);
            }
        }
        if picker.zone_count > 0 {
            picker.upper = Some(upper_spheroid(&ellipsoid, picker.h_max)?);
        }
        Ok(picker)
    }

    /// The picker with another `min_level` (Wartell et al. §5): blocks of nodes shallower than `min_level` never stand
    /// in for missing finer ones. 0 (the default) uses whatever is resident; the tree's depth asks for the
    /// finest blocks only. The module docs ("Multi-resolution") summarise the rules, `traverse.rs` gives them
    /// in full.
    #[must_use]
    pub fn with_min_level(mut self, min_level: u8) -> Self {
        self.min_level = min_level;
        self
    }

    /// The picker's `min_level`.
    pub fn min_level(&self) -> u8 {
        self.min_level
    }

    /// A node's block stride, checked: a power of two, at most `parent_stride`.
    pub(super) fn stride_of(&self, id: NodeId, parent_stride: u32) -> Result<u32, TerrainError> {
        let s = self.storage.block_stride(id);
        if s.is_power_of_two() && s <= parent_stride {
            Ok(s)
        } else {
            Err(TerrainError::MalformedTree)
        }
    }

    /// `stride` as a scalar.
    pub(super) fn scale(&self, stride: u32) -> T {
        T::from_f64(f64::from(stride))
    }

    /// `(sin, cos)` of half the longitude span of a traced cell `stride` grid steps wide (a power of two).
    pub(super) fn half_cell(&self, stride: u32) -> (T, T) {
        let k = usize::try_from(stride.trailing_zeros()).unwrap_or(0);
        self.half_cells.get(k).copied().unwrap_or((T::ZERO, T::ONE))
    }

    /// The nearest hit of `ray` with the terrain for `t_min ≤ t ≤ t_max`, or `None` (Wartell et al. §3.5, §4; the
    /// docs of `traverse.rs` state what is proven).
    ///
    /// ```
    /// # use curvicast::geodesy::Ellipsoid;
    /// # use curvicast::ray::Ray;
    /// # use curvicast::terrain::{Grid, Node, NodeId, Picker, TerrainCaches, TerrainStorage};
    /// /// Flat terrain at 100 m on a 2 × 2-cell grid straddling the antimeridian, one zone that is a leaf.
    /// struct Flat;
    /// impl TerrainStorage<f64> for Flat {
    ///     fn ellipsoid(&self) -> Ellipsoid<f64> { Ellipsoid::wgs84() }
    ///     fn grid(&self) -> Grid<f64> {
    ///         Grid { lat0_deg: -17.0, lon0_deg: 179.99, dlat_deg: 0.01, dlon_deg: 0.01, rows: 3, cols: 3 }
    ///     }
    ///     fn zone_count(&self) -> usize { 1 }
    ///     fn zone(&self, k: usize) -> Option<NodeId> { (k == 0).then_some(NodeId(0)) }
    ///     fn node(&self, _: NodeId) -> Option<Node<f64>> {
    ///         Some(Node { rows: [0, 2], cols: [0, 2], heights: Some([100.0, 100.0]), children: [None; 4], level: 0 })
    ///     }
    ///     fn height(&self, i: u32, j: u32) -> Option<f64> { (i < 3 && j < 3).then_some(100.0) }
    /// }
    /// // No precomputed values: the kernel computes them (see `TerrainCaches`).
    /// impl TerrainCaches<f64> for Flat {}
    /// let picker: Picker<'_, f64, Flat> = Picker::new(&Flat)?;
    /// let e = Ellipsoid::<f64>::wgs84();
    /// // A vertex of the grid (lat −16.99°, lon 180.00°), seen straight down from 1 km above the terrain.
    /// let from = e.geodetic_deg_to_ecef(-16.99, 180.0, 1100.0);
    /// let down = e.normal_deg(-16.99, 180.0).negated();
    /// let hit = picker.pick(&Ray::new(from, down)?)?.ok_or("no hit")?;
    /// assert!((hit.t - 1000.0).abs() < 1e-6 && (hit.h - 100.0).abs() < 1e-6);
    /// assert!((hit.lon_deg.abs() - 180.0).abs() < 1e-9 && hit.cell[1] <= 1);
    /// // Looking up from there: nothing.
    /// assert!(picker.pick(&Ray::new(from, down.negated())?)?.is_none());
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn pick(&self, ray: &Ray<T>) -> Result<Option<Hit<T>>, TerrainError> {
        let mut stats = PickStats::default();
        self.pick_with_stats(ray, &mut stats)
    }

    /// [`Picker::pick`], adding the work done to `stats`.
    pub fn pick_with_stats(
        &self,
        ray: &Ray<T>,
        stats: &mut PickStats,
    ) -> Result<Option<Hit<T>>, TerrainError> {
        let Some(unit) = unit_sized(ray)? else {
            return Ok(self.nearest(ray, stats)?.map(|c| self.make_hit(ray, c)));
        };
        let Some(c) = self.nearest(&unit, stats)? else {
            return Ok(None);
        };
        let hit = self.make_hit(&unit, c);
        Ok(t_of_unit_sized(ray, hit.t)?.map(|t| Hit { t, ..hit }))
    }

    /// The parameter `t` and the cell of the nearest hit as the traversal finds it, without [`Picker::pick`]'s
    /// refinement and geodetic coordinates: what a general ray caster's cast returns, for callers that need only
    /// the distance. The triangle is `pick`'s ([`Hit::cell`] is the same); `t` is the watertight test's on the
    /// scalar vertices, which are off by a few ulps of their coordinates, so along a ray of elevation ε over the
    /// triangle it errs by about that over `sin ε` (about 1e-9 m / sin ε at Earth scale in `f64`; `pick` removes
    /// this, `refine.rs` explains how).
    ///
    /// ```
    /// # use curvicast::geodesy::Ellipsoid;
    /// # use curvicast::ray::Ray;
    /// # use curvicast::terrain::{Grid, Node, NodeId, Picker, TerrainCaches, TerrainStorage};
    /// # struct Flat;
    /// # impl TerrainStorage<f64> for Flat {
    /// #     fn ellipsoid(&self) -> Ellipsoid<f64> { Ellipsoid::wgs84() }
    /// #     fn grid(&self) -> Grid<f64> {
    /// #         Grid { lat0_deg: -17.0, lon0_deg: 179.99, dlat_deg: 0.01, dlon_deg: 0.01, rows: 3, cols: 3 }
    /// #     }
    /// #     fn zone_count(&self) -> usize { 1 }
    /// #     fn zone(&self, k: usize) -> Option<NodeId> { (k == 0).then_some(NodeId(0)) }
    /// #     fn node(&self, _: NodeId) -> Option<Node<f64>> {
    /// #         Some(Node { rows: [0, 2], cols: [0, 2], heights: Some([100.0, 100.0]), children: [None; 4], level: 0 })
    /// #     }
    /// #     fn height(&self, i: u32, j: u32) -> Option<f64> { (i < 3 && j < 3).then_some(100.0) }
    /// # }
    /// # impl TerrainCaches<f64> for Flat {}
    /// // Flat terrain at 100 m (the grid of `pick`'s example), seen straight down from 1 km above it.
    /// let picker: Picker<'_, f64, Flat> = Picker::new(&Flat)?;
    /// let e = Ellipsoid::<f64>::wgs84();
    /// let from = e.geodetic_deg_to_ecef(-16.99, 180.0, 1100.0);
    /// let ray = Ray::new(from, e.normal_deg(-16.99, 180.0).negated())?;
    /// let (t, cell) = picker.pick_t(&ray)?.ok_or("no hit")?;
    /// let hit = picker.pick(&ray)?.ok_or("no hit")?;
    /// assert!((t - 1000.0).abs() < 1e-6 && cell == hit.cell);
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn pick_t(&self, ray: &Ray<T>) -> Result<Option<(T, [u32; 2])>, TerrainError> {
        let mut stats = PickStats::default();
        let Some(unit) = unit_sized(ray)? else {
            return Ok(self.nearest(ray, &mut stats)?.map(|c| (c.t, c.cell)));
        };
        let Some(c) = self.nearest(&unit, &mut stats)? else {
            return Ok(None);
        };
        Ok(t_of_unit_sized(ray, c.t)?.map(|t| (t, c.cell)))
    }

    /// Line of sight from `a` to `b` (ECEF): `true` when no terrain triangle meets the closed segment.
    pub fn line_of_sight(
        &self,
        a: impl Into<V3<T>>,
        b: impl Into<V3<T>>,
    ) -> Result<bool, TerrainError> {
        let seg = Ray::segment(a, b)?;
        // Only whether a triangle meets the segment matters: no hit point, so no refinement.
        let mut stats = PickStats::default();
        let Some(unit) = unit_sized(&seg)? else {
            return Ok(self.nearest(&seg, &mut stats)?.is_none());
        };
        Ok(match self.nearest(&unit, &mut stats)? {
            Some(c) => t_of_unit_sized(&seg, c.t)?.is_none(),
            None => true,
        })
    }
}

/// The same line as `ray` with the direction [`Ray::scaled_dir`] (exactly `ray`'s times a power of two, its
/// largest component in `[1/2, 2)`) when `ray`'s own direction is far from unit size (a component beyond 2^±32),
/// `None` otherwise. The traversal multiplies the direction with Earth-sized coordinates and with `t`; a
/// subnormal direction (seen down to the smallest, 5e-324) or a huge one would lose bits there or overflow,
/// while at unit size every product is ordinary and `t` converts back exactly ([`t_of_unit_sized`]).
pub(super) fn unit_sized<T: Real>(ray: &Ray<T>) -> Result<Option<Ray<T>>, TerrainError> {
    if ray.scale_exponent().unsigned_abs() <= 32 {
        return Ok(None);
    }
    // The interval scales exactly too (unless `t_min` overflows: then no `t` of the ray is representable).
    let unit = Ray::new(ray.origin(), ray.scaled_dir())?
        .with_interval(ray.t_to_scaled(ray.t_min()), ray.t_to_scaled(ray.t_max()))
        .map_err(|_| TerrainError::Unrepresentable)?;
    Ok(Some(unit))
}

/// The caller's `t` of a hit at `s` on [`unit_sized`]'s ray: `None` beyond `ray`'s `t_max` (the scaled bound
/// may have overflowed), [`TerrainError::Unrepresentable`] when `t` itself overflows.
pub(super) fn t_of_unit_sized<T: Real>(ray: &Ray<T>, s: T) -> Result<Option<T>, TerrainError> {
    let t = ray.t_from_scaled(s);
    if t > ray.t_max() {
        Ok(None)
    } else if t == T::INFINITY {
        Err(TerrainError::Unrepresentable)
    } else {
        Ok(Some(t))
    }
}

/// `⌈n / s⌉` for a power of two `s`, by shifts (no division, so no panic path).
pub(super) fn div_ceil_pow2(n: u32, s: u32) -> u32 {
    let q = n.checked_shr(s.trailing_zeros()).unwrap_or(0);
    q.saturating_add(u32::from(n & s.wrapping_sub(1) != 0))
}

pub(super) fn check_in_grid<T: Real>(n: &Node<T>, g: &Grid<T>) -> Result<(), TerrainError> {
    let ok = n.rows[0] < n.rows[1]
        && n.rows[1] <= g.cell_rows()
        && n.cols[0] < n.cols[1]
        && n.cols[1] <= g.cell_cols();
    if ok {
        Ok(())
    } else {
        Err(TerrainError::MalformedTree)
    }
}

/// A child lies inside its parent's ranges `rows`, `cols` and is strictly smaller.
pub(super) fn check_child<T: Real>(
    rows: [u32; 2],
    cols: [u32; 2],
    c: &Node<T>,
) -> Result<(), TerrainError> {
    let inside = c.rows[0] >= rows[0]
        && c.rows[1] <= rows[1]
        && c.cols[0] >= cols[0]
        && c.cols[1] <= cols[1]
        && c.rows[0] < c.rows[1]
        && c.cols[0] < c.cols[1];
    let smaller = c.rows != rows || c.cols != cols;
    if inside && smaller {
        Ok(())
    } else {
        Err(TerrainError::MalformedTree)
    }
}

/// The conservative bounding volume of a node (`traverse.rs`, "Zones and quads"; [`HeightQuadBounds`]), as the kernel builds it from
/// the node's grid ranges and height range. `Ok(None)` for a node without data. Storages that cache volumes
/// ([`TerrainCaches::cached_bounds`]) must store exactly this value.
pub fn quad_bounds<T: Real>(
    e: &Ellipsoid<T>,
    g: &Grid<T>,
    n: &Node<T>,
) -> Result<Option<HeightQuadBounds<T>>, TerrainError> {
    let Some([lo, hi]) = n.heights else {
        return Ok(None);
    };
    let la = g.lat_deg(n.rows[0]);
    let lb = g.lat_deg(n.rows[1]);
    let (lat_s, lat_n) = if la <= lb { (la, lb) } else { (lb, la) };
    let lon_w = g.lon_deg(n.cols[0]);
    let lon_e = g.lon_deg(n.cols[1]);
    Ok(Some(HeightQuadBounds::new(
        e, lat_s, lat_n, lon_w, lon_e, lo, hi, g.dlat_deg, g.dlon_deg,
    )?))
}

/// The boundary trigonometry of a node, read from the storage ([`TerrainCaches::row_sin_cos`],
/// [`TerrainCaches::col_sin_cos`]). With a `parent`, the walls on the parent's sides are left out
/// ([`SideWalls`]).
pub(super) fn node_trig<T: Real, S: TerrainCaches<T>>(
    g: &Grid<T>,
    storage: &S,
    n: &Node<T>,
    parent: Option<&Node<T>>,
    cos_half_cell_dlon: T,
) -> QuadTrig<T> {
    let ra = storage.row_sin_cos(n.rows[0]);
    let rb = storage.row_sin_cos(n.rows[1]);
    // A side is outer when the parent has the same side.
    let outer = |side: fn(&Node<T>) -> u32| parent.is_some_and(|p| side(p) == side(n));
    let (first_row, last_row) = (!outer(|m| m.rows[0]), !outer(|m| m.rows[1]));
    // Rows may run southwards (dlat_deg < 0): the southern wall is the one of smaller latitude.
    let (south, north, south_inner, north_inner) = if g.dlat_deg > T::ZERO {
        (ra, rb, first_row, last_row)
    } else {
        (rb, ra, last_row, first_row)
    };
    QuadTrig {
        south,
        north,
        west: storage.col_sin_cos(n.cols[0]),
        east: storage.col_sin_cos(n.cols[1]),
        span_deg: g.lon_deg(n.cols[1]) - g.lon_deg(n.cols[0]),
        cos_half_cell_dlon,
        walls: SideWalls {
            west: !outer(|m| m.cols[0]),
            east: !outer(|m| m.cols[1]),
            south: south_inner,
            north: north_inner,
        },
    }
}
