//! The two engines over the per-coordinate streams: the serial one (Hannasch ch. 5, constant memory, lazy) and
//! the separable one (§3: each coordinate's crossings listed first, then interleaved in linear time), plus the
//! shared part that turns band changes into cell crossings.
//!
//! Both engines interleave the same three event streams (see `stream.rs`) in the same order — by `t`, and at
//! equal `t` by coordinate (radius first, then the grid's second and third coordinate) — so they agree exactly.

use super::axes::{AzimuthAxis, HeightAxis, RadialAxis, ZenithAxis};
use super::stream::{Event, RadialLine, SecondRoots, StepKind, Stream};
use super::{Axis, CellCrossing, MarchError};
use crate::ray::{Line, Ray};
use crate::real::Real;
use crate::surface::sphere_scaled_roots;
use crate::vec3::V3;

/// Which coordinate a slot of the cell index holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SlotKind {
    Radial,
    Zenith,
    Azimuth,
    Height,
    Absent,
}

/// The tables of a grid, as the engines see them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Axes<'a, T> {
    pub radial: RadialAxis<'a, T>,
    pub zenith: Option<ZenithAxis<'a, T>>,
    pub azimuth: AzimuthAxis<'a, T>,
    pub height: Option<HeightAxis<'a, T>>,
    pub center: V3<T>,
    /// True for the cylinder and the polar grid: the radius is measured from the z axis.
    pub flat_radius: bool,
    pub slots: [SlotKind; 3],
    /// The cell rule, formed once with the grid.
    rule: CellRule,
}

/// What decides whether a set of bands is a cell of the domain, and which: per slot, the inside bands are
/// `first .. first + count` and band `b` is cell index `b − first` (a banded coordinate: bands 1 to L − 1 of L
/// breakpoints; the azimuth: every sector but the outside one of a wedge; an absent slot: its one band 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct CellRule {
    first: [u32; 3],
    count: [u32; 3],
}

impl CellRule {
    /// The cell index of `band` in `slot`, or `None` when that band is outside the domain (band 0 and the top
    /// band of a banded coordinate, the outside sector of a wedge). One subtraction and one comparison; the
    /// slot's two entries are read by index once the slot is known (a `match` on the slot let the separable
    /// engine hoist all six entries onto its stack on every call).
    #[inline(always)]
    fn index(&self, slot: usize, band: u32) -> Option<u32> {
        let (Some(&first), Some(&count)) = (self.first.get(slot), self.count.get(slot)) else {
            return None;
        };
        let i = band.wrapping_sub(first);
        (i < count).then_some(i)
    }
}

impl<'a, T: Real> Axes<'a, T> {
    /// The tables of a grid centred at the origin.
    pub(crate) fn new(
        radial: RadialAxis<'a, T>,
        zenith: Option<ZenithAxis<'a, T>>,
        azimuth: AzimuthAxis<'a, T>,
        height: Option<HeightAxis<'a, T>>,
        flat_radius: bool,
        slots: [SlotKind; 3],
    ) -> Self {
        let mut axes = Axes {
            radial,
            zenith,
            azimuth,
            height,
            center: V3::ZERO,
            flat_radius,
            slots,
            rule: CellRule {
                first: [0; 3],
                count: [u32::MAX; 3],
            },
        };
        axes.rule = axes.cell_rule();
        axes
    }

    fn cell_rule(&self) -> CellRule {
        let mut rule = self.rule;
        for ((f, c), k) in rule
            .first
            .iter_mut()
            .zip(rule.count.iter_mut())
            .zip(self.slots.iter())
        {
            let banded = |len: u32| (1, len.saturating_sub(1));
            (*f, *c) = match k {
                SlotKind::Radial => banded(self.radial.len),
                SlotKind::Zenith => banded(self.zenith.map_or(0, |z| z.len)),
                SlotKind::Azimuth => (0, self.azimuth.sectors),
                SlotKind::Height => banded(self.height.map_or(0, |h| h.len)),
                SlotKind::Absent => (0, u32::MAX),
            };
        }
        rule
    }

    fn axis_name(&self, slot: usize) -> Axis {
        match self.slots.get(slot) {
            Some(SlotKind::Radial) if self.flat_radius => Axis::Rho,
            Some(SlotKind::Radial) => Axis::R,
            Some(SlotKind::Zenith) => Axis::Theta,
            Some(SlotKind::Azimuth) => Axis::Phi,
            _ => Axis::Z,
        }
    }
}

/// The ray's line in the grid's frame, `rel` (relative to the center: the solvers report every crossing of the
/// whole line, so that the streams can check their topology against the limit at infinity), the ray's `t_max`
/// (which cuts the events), and the line as the radius stream sees it (`rel` itself for the sphere grid, its
/// projection on z = 0 for the cylinder and the polar grid).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rays<T> {
    rel: Line<T>,
    t_max: T,
    radial: RadialLine<T>,
}

impl<T: Real> Rays<T> {
    /// Before the set-up: the caller's ray's line and `t_max` (the set-up replaces them, also when it then fails).
    fn of(ray: &Ray<T>) -> Self {
        Rays {
            rel: *ray.line(),
            t_max: ray.t_max(),
            radial: RadialLine::unset(ray.line()),
        }
    }
    #[inline(always)]
    fn t_max(&self) -> T {
        self.t_max
    }
    /// True when an event's `t` may fail to be finite (see [`CHECK_T`]): the line's or the radius line's
    /// `t = s·2^-e` can overflow where `s` does not.
    fn t_may_overflow(&self) -> bool {
        self.rel.scale().enlarges() || self.radial.scale().enlarges()
    }
}

/// As [`next_event`], kept out of line: for the set-up (each stream's first event), so that the streams' code is
/// inlined only into the engines' loops, not a second time into the set-up (on a Cortex-M4F each inlined copy of
/// the radius, zenith and azimuth steps costs about 2 KB of code).
#[inline(never)]
fn next_event_outlined<T: Real>(
    axes: &Axes<'_, T>,
    rays: &Rays<T>,
    streams: &mut [Stream<T>; 3],
    roots: &mut SecondRoots<T>,
    slot: usize,
) -> bool {
    next_event(axes, rays, streams, roots, slot)
}

/// Advances slot `slot`'s stream to its next event (then its `t` and `band`); false when it has none. Inlined
/// into the engines' loops, with the radius, zenith and azimuth steps (the cone solver stays out of line).
#[inline(always)]
fn next_event<T: Real>(
    axes: &Axes<'_, T>,
    rays: &Rays<T>,
    streams: &mut [Stream<T>; 3],
    roots: &mut SecondRoots<T>,
    slot: usize,
) -> bool {
    let Some(s) = streams.get_mut(slot) else {
        return false;
    };
    match s.step_kind() {
        StepKind::Radial => s.next_radial(&axes.radial, &rays.radial, rays.t_max()),
        StepKind::Zenith => axes
            .zenith
            .as_ref()
            .is_some_and(|z| s.next_zenith(z, &rays.rel, rays.t_max(), roots)),
        StepKind::Azimuth => s.next_azimuth(&axes.azimuth, &rays.rel, rays.t_max()),
        StepKind::Height => axes
            .height
            .as_ref()
            .is_some_and(|h| s.next_height(h, &rays.rel, rays.t_max())),
        StepKind::Walk => s.next_walk(axes.azimuth.boundaries.max(1), rays.t_max()),
        StepKind::None => false,
    }
}

/// False when the line crosses the outer radius (sphere, or cylinder for the flat ray) and the ray's interval
/// reaches a part of it where `t` is not finite: the scaled roots are finite, but `t = s·2^-e` overflows (a
/// direction too short for its distance). Every crossing of the domain lies within the outer radius, so
/// otherwise each `t` an engine reports is finite.
fn outer_ball_representable<T: Real>(
    axes: &Axes<'_, T>,
    ray: &Line<T>,
    t_min: T,
    t_max: T,
) -> bool {
    let Some(&r2) = axes.radial.r2.last() else {
        return true;
    };
    // Cheap bound first (no square root, no division): a point of the ball has |s| ≤ 2(|p| + R) (the scaled
    // direction is at least 1/2 long), and |p| + R ≤ 2 max|p_i| + max(1, R²); with a factor 2 for rounding.
    let bound = (ray.origin().max_abs() * T::TWO + r2.max(T::ONE)) * (T::TWO + T::TWO);
    if ray.t_from_scaled(bound).is_finite() {
        return true;
    }
    match sphere_scaled_roots(r2, ray) {
        Some((s_in, s_out)) if s_in < s_out => {
            let (t_in, t_out) = (ray.t_from_scaled(s_in), ray.t_from_scaled(s_out));
            !((t_out == T::INFINITY && t_max == T::INFINITY)
                || (t_in == T::NEG_INFINITY && t_min == T::NEG_INFINITY))
        }
        _ => true,
    }
}

/// The radius stream at the start `t_min` of `radial_ray` (the ray in the grid's frame, or its projection on
/// z = 0 for a cylinder or polar grid), with the line's invariants written to `line`. Out of line: its
/// temporaries stay out of the set-up's frame.
#[inline(never)]
fn radial_start<T: Real>(
    axes: &Axes<'_, T>,
    radial_ray: &Line<T>,
    line: &mut RadialLine<T>,
    t_min: T,
    t_max: T,
) -> Result<(Stream<T>, u32), MarchError> {
    *line = RadialLine::of(radial_ray);
    if !outer_ball_representable(axes, radial_ray, t_min, t_max) {
        return Err(MarchError::Unrepresentable);
    }
    Ok(Stream::radial(&axes.radial, radial_ray, line, t_min))
}

/// [`radial_start`] on the projection of `ray` on z = 0 (cylinder and polar grids), from `rel`, its line in the
/// grid's frame; `Ok(None)` for a vertical line, whose distance from the axis does not change. Out of line: the
/// projected ray lives in its own frame.
#[inline(never)]
fn flat_radial_start<T: Real>(
    axes: &Axes<'_, T>,
    ray: &Ray<T>,
    rel: &Line<T>,
    line: &mut RadialLine<T>,
) -> Result<Option<(Stream<T>, u32)>, MarchError> {
    let (p, d) = (rel.origin(), ray.dir());
    let Ok(flat) = Ray::new(V3::new(p.x, p.y, T::ZERO), V3::new(d.x, d.y, T::ZERO))
        .and_then(|r| r.with_interval(ray.t_min(), T::INFINITY))
    else {
        return Ok(None);
    };
    radial_start(axes, flat.line(), line, ray.t_min(), ray.t_max()).map(Some)
}

/// Locates the ray, finds where it enters the outer radius, and starts the other coordinates there: fills in
/// `rays` and `streams` (in place: a march's state is not moved around) and returns the start `t`. The
/// streams' bands are the bands at the start. `Ok(None)` when the ray cannot meet the domain.
///
/// Not inlined: its temporaries (each coordinate's start) then live in its own frame, which is gone before the
/// march's first crossing, instead of in the caller's for the whole march. The ray in the grid's frame is formed
/// in place in `rays`, and the radius stream's start (with the projected ray of a cylinder or polar grid) out of
/// line, so that no copy of a ray sits in this frame (on a Cortex-M4F this halved its frame).
#[inline(never)]
fn setup<T: Real>(
    axes: &Axes<'_, T>,
    ray: &Ray<T>,
    rays: &mut Rays<T>,
    streams: &mut [Stream<T>; 3],
    roots: &mut SecondRoots<T>,
) -> Result<Option<T>, MarchError> {
    // the ray's line in the grid's frame, formed in place (no copies of it in this frame)
    rays.rel = *ray.line();
    rays.rel.recenter(axes.center).map_err(MarchError::Ray)?;
    rays.t_max = ray.t_max();
    let t_min = ray.t_min();
    let radial = if axes.flat_radius {
        flat_radial_start(axes, ray, &rays.rel, &mut rays.radial)?
    } else {
        Some(radial_start(
            axes,
            &rays.rel,
            &mut rays.radial,
            t_min,
            rays.t_max,
        )?)
    };
    let radial_moves = radial.is_some();
    let (mut rs, mut rband) = radial.unwrap_or_else(|| {
        // a vertical line in a cylinder or polar grid: its distance from the axis is constant
        let p = rays.rel.origin();
        let band = axes.radial.band_of_r2(p.x * p.x + p.y * p.y);
        (Stream::fixed(band), band)
    });
    let mut t0 = t_min;
    if rband >= axes.radial.len {
        let [s0, ..] = streams;
        *s0 = rs;
        if !next_event_outlined(axes, rays, streams, roots, 0) {
            return Ok(None);
        }
        let [s0, ..] = streams;
        rs = *s0;
        t0 = rs.t;
        rband = rs.band;
        if !t0.is_finite() {
            // the line enters the outer radius where t overflows: a crossing that t cannot express
            return Err(MarchError::Unrepresentable);
        }
    }
    if !radial_moves && rband == 0 {
        return Ok(None); // a vertical line inside the hole of a cylinder grid
    }
    if let Some(s) = streams.get_mut(0) {
        *s = rs;
    }
    for slot in 1..3 {
        let (s, _) = match axes.slots.get(slot) {
            Some(SlotKind::Zenith) => match axes.zenith.as_ref() {
                Some(z) if t0.is_finite() => Stream::zenith(z, &rays.rel, t0),
                _ => (Stream::fixed(0), 0),
            },
            Some(SlotKind::Azimuth) => Stream::azimuth(&axes.azimuth, &rays.rel, t0),
            Some(SlotKind::Height) => match axes.height.as_ref() {
                Some(h) => Stream::height(h, &rays.rel, t0),
                None => (Stream::fixed(0), 0),
            },
            _ => (Stream::fixed(0), 0),
        };
        if let Some(sl) = streams.get_mut(slot) {
            *sl = s;
        }
    }
    Ok(Some(t0))
}

/// The bits of [`Emitter::outside`] that say which slots' bands are outside the domain.
const SLOTS: u8 = 0b111;

/// The bit of [`Emitter::outside`] set for a whole march in which an event's `t` may not be finite, so that
/// every event takes the checked path. That needs a ray whose `t = s·2^-e` can overflow where `s` does not
/// (`e < 0`, a direction scaled up). Otherwise every event inside the domain has a finite `t`: it lies before the
/// ray leaves the outer radius (which ends the march), and that `t` is at most the finite `s` of its root.
const CHECK_T: u8 = 0x80;

/// Turns band changes into cell crossings. A crossing that ends inside the domain is final at once (the next one
/// is another cell); one that ends by leaving the domain is held until the ray comes back, so that a zero-length
/// excursion out of the domain (a touch of its boundary from inside) that returns to the same cell is merged away.
///
/// The cell is kept up to date one slot at a time: `cell[s]` is the index of slot `s`'s band and bit `s` of
/// `outside` is set while that band is outside the domain, so an event costs one band lookup, not a
/// re-evaluation of the whole cell rule. With [`CHECK_T`] in the same byte, an event of a ray inside the domain
/// is told to need nothing more by one test of that byte.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Emitter<T> {
    cell: [u32; 3],
    outside: u8,
    /// Where the crossing in progress began (while outside: where the held crossing began).
    seg_start: T,
    /// The cell and exit of the crossing that ended by leaving the domain, while the ray is outside (its entry
    /// is `seg_start`).
    pending: Option<([u32; 3], T)>,
    /// Set when an event inside the domain has a `t` that is not finite (see [`MarchError::Unrepresentable`]).
    unrepresentable: bool,
}

impl<T: Real> Emitter<T> {
    fn new(rule: &CellRule, bands: [u32; 3], t0: T, check_t: bool) -> Self {
        let mut em = Emitter {
            cell: [0; 3],
            outside: if check_t { CHECK_T } else { 0 },
            seg_start: t0,
            pending: None,
            unrepresentable: false,
        };
        for (slot, &b) in bands.iter().enumerate() {
            em.set(rule, slot, b);
        }
        em
    }

    /// Slot `slot` enters `band`.
    #[inline(always)]
    fn set(&mut self, rule: &CellRule, slot: usize, band: u32) {
        let bit = 1u8 << (slot & 7);
        match rule.index(slot, band) {
            Some(i) => {
                match slot {
                    0 => self.cell[0] = i,
                    1 => self.cell[1] = i,
                    _ => self.cell[2] = i,
                }
                self.outside &= !bit;
            }
            None => self.outside |= bit,
        }
    }

    /// The crossing that ends at `t`, where slot `slot` enters the band of cell index `i` inside the domain.
    #[inline(always)]
    fn cross(&mut self, t: T, slot: usize, i: u32) -> CellCrossing<T> {
        let c = CellCrossing {
            cell: self.cell,
            t_enter: self.seg_start,
            t_exit: t,
        };
        if let Some(x) = self.cell.get_mut(slot) {
            *x = i;
        }
        self.seg_start = t;
        c
    }

    /// The held crossing, if any (taken).
    #[inline]
    fn take_pending(&mut self) -> Option<CellCrossing<T>> {
        self.pending.take().map(|(cell, t_exit)| CellCrossing {
            cell,
            t_enter: self.seg_start,
            t_exit,
        })
    }

    /// The event of `slot` entering `band` at `t`. The streams' events come in nondecreasing `t`, none
    /// before the start `t0` and none past `t_max` (each stream takes the larger of a solver's root and its own
    /// previous event, and stops past `t_max`), so the crossings need no clamping.
    #[inline(always)]
    fn on(&mut self, rule: &CellRule, t: T, slot: usize, band: u32) -> Option<CellCrossing<T>> {
        // Inside to inside (every event of a ray inside a full grid): the crossing ends here, nothing is held.
        // `t` is finite unless `CHECK_T` is set.
        if self.outside == 0 {
            if let Some(i) = rule.index(slot, band) {
                return Some(self.cross(t, slot, i));
            }
        }
        let was_inside = self.outside & SLOTS == 0;
        if was_inside && t.is_finite() {
            // the same with `CHECK_T` set (or a band outside: then the ray leaves the domain, below)
            if let Some(i) = rule.index(slot, band) {
                return Some(self.cross(t, slot, i));
            }
        }
        let before = self.cell;
        self.set(rule, slot, band);
        if !was_inside && self.outside & SLOTS != 0 {
            return None;
        }
        if !t.is_finite() {
            // the scaled parameter is finite (the solvers return no other) but t = s·2^-e overflows
            self.unrepresentable = true;
            return None;
        }
        if was_inside {
            // left the domain (an event that stays inside took the fast path above): held until the ray comes
            // back (it may come back into this cell at this t)
            self.pending = Some((before, t));
            return None;
        }
        // back into the domain: the held crossing continues if this is the same cell at the same t (a touch of
        // the boundary from inside), else it is final
        match self.pending {
            Some((cell, t_exit)) if cell == self.cell && t_exit == t => {
                self.pending = None;
                None
            }
            _ => {
                let p = self.take_pending();
                self.seg_start = t;
                p
            }
        }
    }

    /// Ends the crossing in progress without giving it (a march that stops at an error or never starts): only
    /// the held crossing, if any, is left for [`Emitter::finish`].
    fn close(&mut self) {
        self.outside = 0xff;
    }

    /// The end of the march at `t_end`: the crossing in progress, or the held one (taken: a second call gives
    /// nothing).
    fn finish(&mut self, t_end: T) -> Option<CellCrossing<T>> {
        if self.outside & SLOTS != 0 {
            return self.take_pending();
        }
        let t_exit = t_end.max(self.seg_start);
        self.close();
        Some(CellCrossing {
            cell: self.cell,
            t_enter: self.seg_start,
            t_exit,
        })
    }
}

impl CellRule {
    /// True while the radius band (slot 0) is at or beyond the outer radius.
    #[inline]
    fn beyond_outer_radius(&self, band: u32) -> bool {
        band >= self.first[0].saturating_add(self.count[0])
    }
}

/// The serial marcher (Hannasch ch. 5): an `Iterator` of [`CellCrossing`]s in increasing `t`, computed lazily in
/// constant memory. Each coordinate's next crossing is computed once and cached until that coordinate's index
/// changes.
///
/// Built by `SphericalGrid::march` (and the cylindrical and polar grids' `march`). When the ray is invalid for
/// the grid or a bound is exceeded, iteration stops and [`SerialMarch::error`] says why.
#[derive(Debug, Clone)]
pub struct SerialMarch<'g, T> {
    axes: &'g Axes<'g, T>,
    rays: Rays<T>,
    /// Each coordinate's stream, at its next event while it is live.
    streams: [Stream<T>; 3],
    /// The zenith stream's kept second roots.
    cones: SecondRoots<T>,
    em: Emitter<T>,
    /// Bit `s` is set while stream `s` is live; 0 once the march is over (every stream ended, or it stopped).
    live: u8,
    error: Option<MarchError>,
}

impl<'g, T: Real> SerialMarch<'g, T> {
    pub(crate) fn new(axes: &'g Axes<'g, T>, ray: &Ray<T>) -> Self {
        // (a march that does not start has no stream live and a closed emitter)
        let mut rays = Rays::of(ray);
        let mut streams = [Stream::fixed(0); 3];
        let mut cones = SecondRoots::EMPTY;
        let (t0, error) = match setup(axes, ray, &mut rays, &mut streams, &mut cones) {
            Ok(t0) => (t0, None),
            Err(e) => (None, Some(e)),
        };
        let mut em = Emitter::new(
            &axes.rule,
            streams.map(|s| s.band),
            t0.unwrap_or(T::ZERO),
            rays.t_may_overflow(),
        );
        if t0.is_none() {
            em.close();
        }
        let mut live = 0u8;
        if t0.is_some() {
            for slot in 0..3 {
                // its first event, or it ends
                if next_event_outlined(axes, &rays, &mut streams, &mut cones, slot) {
                    live |= 1u8 << slot;
                }
            }
        }
        SerialMarch {
            axes,
            rays,
            streams,
            cones,
            em,
            live,
            error,
        }
    }

    /// The march with its zenith stream (slot 1) `n` events from its bound (to test the bound).
    #[cfg(test)]
    pub(crate) fn with_zenith_events_left(mut self, n: u32) -> Self {
        if let Some(s) = self.streams.get_mut(1) {
            *s = s.with_events_left(n);
        }
        self
    }

    /// Why the march stopped early, if it did: the ray could not be put into the grid's frame
    /// ([`MarchError::Ray`]) or the iteration bound was exceeded ([`MarchError::IterationBound`]). The crossings
    /// returned before an error are correct.
    pub fn error(&self) -> Option<MarchError> {
        self.error
    }
}

impl<T: Real> Iterator for SerialMarch<'_, T> {
    type Item = CellCrossing<T>;

    fn next(&mut self) -> Option<CellCrossing<T>> {
        self.step()
    }

    /// Internal iteration (what `for_each`, `sum`, `count` and adapters such as `map(..).sum()` use): see
    /// [`SerialMarch::fold_in_place`].
    fn fold<B, F>(mut self, init: B, f: F) -> B
    where
        F: FnMut(B, CellCrossing<T>) -> B,
    {
        self.fold_in_place(init, f)
    }
}

impl<T: Real> SerialMarch<'_, T> {
    /// Folds the remaining crossings in order, like [`Iterator::fold`], but borrowing the march, so that
    /// [`SerialMarch::error`] can be read afterwards. This is internal iteration: the whole march runs in one
    /// loop instead of handing each crossing out through `next` (on the report's scene about 1 % fewer
    /// instructions per crossing than a `for` loop; the answers are the same).
    ///
    /// ```
    /// use curvicast::{ray::Ray, spherical::SphericalGrid};
    /// use core::f64::consts::PI;
    /// let (r, theta, phi) = ([0.0, 0.5, 1.0], [0.0, PI / 2.0, PI], [0.0, PI, 2.0 * PI]);
    /// let mut ws = [0.0; SphericalGrid::<f64>::workspace_len(3, 3, 3)];
    /// let grid = SphericalGrid::new(&r, &theta, &phi, &mut ws)?;
    /// let ray = Ray::new([-2.0, 0.0, 0.3], [1.0, 0.0, 0.0])?;
    /// let mut march = grid.march(&ray);
    /// let length = march.fold_in_place(0.0, |sum, c| sum + (c.t_exit - c.t_enter));
    /// assert_eq!(march.error(), None);
    /// assert!((length - 2.0 * (1.0f64 - 0.09).sqrt()).abs() < 1e-12);
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn fold_in_place<B>(&mut self, init: B, mut f: impl FnMut(B, CellCrossing<T>) -> B) -> B {
        let mut acc = init;
        while let Some(c) = self.step() {
            acc = f(acc, c);
        }
        acc
    }

    /// The next crossings into `out`, in order, as many as fit or remain; returns how many were written (fewer
    /// than `out.len()` only when the march is over: then [`SerialMarch::error`] says whether it ended or
    /// stopped). Internal iteration in batches, for callers that take crossings into a buffer (the C interface,
    /// a firmware's DMA list): the loop runs inside the march, as in [`SerialMarch::fold_in_place`].
    ///
    /// ```
    /// use curvicast::{ray::Ray, spherical::{CellCrossing, SphericalGrid}};
    /// use core::f64::consts::PI;
    /// let (r, theta, phi) = ([0.0, 0.5, 1.0], [0.0, PI / 2.0, PI], [0.0, PI, 2.0 * PI]);
    /// let mut ws = [0.0; SphericalGrid::<f64>::workspace_len(3, 3, 3)];
    /// let grid = SphericalGrid::new(&r, &theta, &phi, &mut ws)?;
    /// let ray = Ray::new([-2.0, 0.25, 0.25], [1.0, 0.0, 0.0])?;
    /// let mut march = grid.march(&ray);
    /// let mut batch = [CellCrossing { cell: [0; 3], t_enter: 0.0, t_exit: 0.0 }; 2];
    /// assert_eq!(march.next_into(&mut batch), 2); // outer shell, inner ball
    /// assert_eq!(march.next_into(&mut batch), 1); // outer shell again, and the march is over
    /// assert_eq!((batch[0].cell, march.error()), ([1, 0, 0], None));
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn next_into<C: From<CellCrossing<T>>>(&mut self, out: &mut [C]) -> usize {
        let mut slots = out.iter_mut();
        let mut n = 0usize;
        if slots.len() > 0 {
            // Each crossing taken has a slot: the loop stops after filling the last one.
            self.for_each_while(|c| match slots.next() {
                Some(slot) => {
                    *slot = c.into();
                    n = n.saturating_add(1);
                    slots.len() > 0
                }
                None => false,
            });
        }
        n
    }

    /// Calls `f` on the remaining crossings in order until it returns `false` (internal iteration with an early
    /// stop; the loop runs inside the march, as in [`SerialMarch::fold_in_place`]).
    #[inline(always)]
    pub fn for_each_while(&mut self, mut f: impl FnMut(CellCrossing<T>) -> bool) {
        while let Some(c) = self.step() {
            if !f(c) {
                break;
            }
        }
    }

    /// The next crossing (the body of `next`, inlined into `fold` as well).
    #[inline(always)]
    fn step(&mut self) -> Option<CellCrossing<T>> {
        loop {
            // the earliest of the live streams' next events; the first slot on a tie
            let [s0, s1, s2] = &self.streams;
            let (mut slot, mut t, mut band) = (3usize, s0.t, s0.band);
            if self.live & 1 != 0 {
                slot = 0;
            }
            if self.live & 2 != 0 && (slot == 3 || s1.t < t) {
                (slot, t, band) = (1, s1.t, s1.band);
            }
            if self.live & 4 != 0 && (slot == 3 || s2.t < t) {
                (slot, t, band) = (2, s2.t, s2.band);
            }
            if slot == 3 {
                // the march is over: the crossing in progress, or the held one (then nothing)
                return self.em.finish(self.rays.t_max());
            }
            let ended = !next_event(
                self.axes,
                &self.rays,
                &mut self.streams,
                &mut self.cones,
                slot,
            );
            if ended {
                self.live &= !(1u8 << slot);
                if self.streams.get(slot).is_some_and(Stream::overran) {
                    // (every stream but the zenith one is bounded by construction: `zenith_event_bound`)
                    self.error = Some(MarchError::IterationBound);
                    self.stop();
                    continue;
                }
            }
            if slot == 0 && ended && self.axes.rule.beyond_outer_radius(band) {
                self.live = 0; // left the outer radius for good (this event is the last)
            }
            let out = self.em.on(&self.axes.rule, t, slot, band);
            if out.is_some() {
                return out; // (a crossing is never given with `unrepresentable` set)
            }
            if self.em.unrepresentable {
                self.error = Some(MarchError::Unrepresentable);
                self.stop();
            }
        }
    }

    /// Stops the march at an error: no further event, and the crossing in progress is not given (the held one
    /// is).
    #[cold]
    fn stop(&mut self) {
        self.live = 0;
        self.em.close();
    }
}

/// The separable marcher (Hannasch §3): each coordinate's crossings are listed into a `heapless` buffer of
/// capacity `N`, then interleaved in linear time. Iterates the same [`CellCrossing`]s as [`SerialMarch`].
///
/// Built by `SphericalGrid::march_separable::<N>` (and the other grids'); a buffer that would overflow is
/// [`MarchError::BufferFull`] at construction, never a truncated answer.
#[derive(Debug, Clone)]
pub struct SeparableMarch<T, const N: usize> {
    lists: [heapless::Vec<Event<T>, N>; 3],
    pos: [usize; 3],
    em: Option<Emitter<T>>,
    rule: CellRule,
    t_max: T,
    finished: bool,
    error: Option<MarchError>,
}

impl<T: Real, const N: usize> Default for SeparableMarch<T, N> {
    /// An empty march (it yields nothing), to be filled in place by a grid's `march_separable_into`.
    fn default() -> Self {
        SeparableMarch {
            lists: [
                heapless::Vec::new(),
                heapless::Vec::new(),
                heapless::Vec::new(),
            ],
            pos: [0; 3],
            em: None,
            rule: CellRule::default(),
            t_max: T::ZERO,
            finished: true,
            error: None,
        }
    }
}

impl<T: Real, const N: usize> SeparableMarch<T, N> {
    pub(crate) fn new(axes: &Axes<'_, T>, ray: &Ray<T>) -> Result<Self, MarchError> {
        let mut m = Self::default();
        m.fill(axes, ray)?;
        Ok(m)
    }

    /// Lists the crossings of `ray` into `self`'s buffers in place (Hannasch §3), replacing what they held: the
    /// buffers are not moved or copied, so one march can be reused for many rays. On an error `self` is left
    /// empty (it yields nothing).
    pub(crate) fn fill(&mut self, axes: &Axes<'_, T>, ray: &Ray<T>) -> Result<(), MarchError> {
        for list in &mut self.lists {
            list.clear();
        }
        self.pos = [0; 3];
        self.em = None;
        self.rule = axes.rule;
        self.t_max = ray.t_max();
        self.finished = true;
        self.error = None;
        let result = self.fill_lists(axes, ray);
        if result.is_err() {
            for list in &mut self.lists {
                list.clear();
            }
        }
        result
    }

    fn fill_lists(&mut self, axes: &Axes<'_, T>, ray: &Ray<T>) -> Result<(), MarchError> {
        let m = self;
        let mut rays = Rays::of(ray);
        let mut streams = [Stream::fixed(0); 3];
        let mut cones = SecondRoots::EMPTY;
        let Some(t0) = setup(axes, ray, &mut rays, &mut streams, &mut cones)? else {
            return Ok(());
        };
        let bands = streams.map(|s| s.band);
        let mut t_end = ray.t_max();
        for slot in 0..3 {
            let list = m.lists.get_mut(slot).ok_or(MarchError::IterationBound)?;
            let mut last_band = bands.get(slot).copied().unwrap_or(0);
            let mut last_t = None;
            while next_event(axes, &rays, &mut streams, &mut cones, slot) {
                let Some(&Stream { t, band: b, .. }) = streams.get(slot) else {
                    break;
                };
                if slot > 0 && t > t_end {
                    break;
                }
                list.push((t, b)).map_err(|_| MarchError::BufferFull {
                    axis: axes.axis_name(slot),
                    capacity: N,
                })?;
                last_band = b;
                last_t = Some(t);
            }
            if streams.get(slot).is_some_and(Stream::overran) {
                return Err(MarchError::IterationBound);
            }
            if slot == 0 && last_band >= axes.radial.len {
                if let Some(t) = last_t {
                    t_end = t; // left the outer radius for good: nothing after matters
                }
            }
        }
        m.em = Some(Emitter::new(&axes.rule, bands, t0, rays.t_may_overflow()));
        m.finished = false;
        Ok(())
    }

    /// Why the march stopped early, if it did: a crossing whose `t` is not representable
    /// ([`MarchError::Unrepresentable`]; the other errors are returned at construction). The crossings returned
    /// before an error are correct, and the serial engine stops at the same point with the same error.
    pub fn error(&self) -> Option<MarchError> {
        self.error
    }

    /// The number of crossings listed per coordinate (for sizing `N`).
    pub fn listed(&self) -> [usize; 3] {
        let mut out = [0usize; 3];
        for (o, l) in out.iter_mut().zip(self.lists.iter()) {
            *o = l.len();
        }
        out
    }
}

impl<T: Real, const N: usize> Iterator for SeparableMarch<T, N> {
    type Item = CellCrossing<T>;

    /// Inlined into the caller's loop (the interleave of three lists and the emitter: no stream code).
    #[inline]
    fn next(&mut self) -> Option<CellCrossing<T>> {
        let em = self.em.as_mut()?;
        loop {
            if self.finished {
                return em.take_pending();
            }
            // each list's next event; the earliest, the first slot on a tie
            let [l0, l1, l2] = &self.lists;
            let [p0, p1, p2] = self.pos;
            let (mut slot, mut t, mut band) = (3usize, T::ZERO, 0u32);
            if let Some(&(t0, b0)) = l0.get(p0) {
                (slot, t, band) = (0, t0, b0);
            }
            if let Some(&(t1, b1)) = l1.get(p1) {
                if slot == 3 || t1 < t {
                    (slot, t, band) = (1, t1, b1);
                }
            }
            if let Some(&(t2, b2)) = l2.get(p2) {
                if slot == 3 || t2 < t {
                    (slot, t, band) = (2, t2, b2);
                }
            }
            match slot {
                0 => self.pos[0] = p0.wrapping_add(1),
                1 => self.pos[1] = p1.wrapping_add(1),
                2 => self.pos[2] = p2.wrapping_add(1),
                _ => {
                    self.finished = true;
                    if let Some(c) = em.finish(self.t_max) {
                        return Some(c);
                    }
                    continue;
                }
            }
            let out = em.on(&self.rule, t, slot, band);
            if out.is_some() {
                return out; // (a crossing is never given with `unrepresentable` set)
            }
            if em.unrepresentable {
                self.error = Some(MarchError::Unrepresentable);
                self.finished = true;
            }
        }
    }
}
