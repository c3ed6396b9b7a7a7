//! The serial marcher (Hannasch ch. 5): constant memory, lazy.

use super::crossing::CellCrossing;
use super::emitter::Emitter;
use super::error::MarchError;
use super::event::{Rays, next_event, next_event_outlined, setup};
use super::kind::GridKind;
use super::stream::{SecondRoots, Stream};
use super::tables::Axes;
use crate::ray::Ray;
use crate::real::Real;
use core::marker::PhantomData;

/// The serial marcher (Hannasch ch. 5): an `Iterator` of [`CellCrossing`]s in increasing `t`, computed lazily in
/// constant memory. Each coordinate's next crossing is computed once and cached until that coordinate's index
/// changes.
///
/// Built by `Grid::march`; `K` is the grid's kind. When the ray is invalid for the grid or
/// a bound is exceeded, iteration stops and [`SerialMarch::error`] says why.
#[derive(Debug, Clone)]
pub struct SerialMarch<'g, T, K> {
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
    kind: PhantomData<K>,
}

impl<'g, T: Real, K: GridKind> SerialMarch<'g, T, K> {
    pub(crate) fn new(axes: &'g Axes<'g, T>, ray: &Ray<T>) -> Self {
        // (a march that does not start has no stream live and a closed emitter)
        let mut rays = Rays::of(ray);
        let mut streams = [Stream::fixed(0); 3];
        let mut cones = SecondRoots::EMPTY;
        let (t0, error) = match setup::<T, K>(axes, ray, &mut rays, &mut streams, &mut cones) {
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
                if next_event_outlined::<T, K>(axes, &rays, &mut streams, &mut cones, slot) {
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
            kind: PhantomData,
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

impl<T: Real, K: GridKind> Iterator for SerialMarch<'_, T, K> {
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

impl<T: Real, K: GridKind> SerialMarch<'_, T, K> {
    /// Folds the remaining crossings in order, like [`Iterator::fold`], but borrowing the march, so that
    /// [`SerialMarch::error`] can be read afterwards. This is internal iteration: the whole march runs in one
    /// loop instead of handing each crossing out through `next` (on the report's scene about 1 % fewer
    /// instructions per crossing than a `for` loop; the answers are the same).
    ///
    /// ```
    /// use curvicast::{march::SphericalGrid, ray::Ray};
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
    /// use curvicast::{march::{CellCrossing, SphericalGrid}, ray::Ray};
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
            let ended = !next_event::<T, K>(
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
