//! The separable marcher (Hannasch §3): each coordinate's crossings listed first, then interleaved in
//! linear time.

use super::crossing::CellCrossing;
use super::emitter::Emitter;
use super::error::Axis;
use super::error::MarchError;
use super::event::{Rays, next_event, setup};
use super::kind::{GridKind, coordinates};
use super::stream::{Event, SecondRoots, Stream};
use super::tables::{Axes, CellRule};
use crate::ray::Ray;
use crate::real::Real;

/// The separable marcher (Hannasch §3): each coordinate's crossings are listed into a `heapless` buffer of
/// capacity `N`, then interleaved in linear time. Iterates the same [`CellCrossing`]s as `SerialMarch`.
///
/// Built by `Grid::march_separable`; a buffer that would overflow is
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
    pub(crate) fn new<K: GridKind>(axes: &Axes<'_, T>, ray: &Ray<T>) -> Result<Self, MarchError> {
        let mut m = Self::default();
        m.fill::<K>(axes, ray)?;
        Ok(m)
    }

    /// Lists the crossings of `ray` into `self`'s buffers in place (Hannasch §3), replacing what they held: the
    /// buffers are not moved or copied, so one march can be reused for many rays. On an error `self` is left
    /// empty (it yields nothing).
    pub(crate) fn fill<K: GridKind>(
        &mut self,
        axes: &Axes<'_, T>,
        ray: &Ray<T>,
    ) -> Result<(), MarchError> {
        for list in &mut self.lists {
            list.clear();
        }
        self.pos = [0; 3];
        self.em = None;
        self.rule = axes.rule;
        self.t_max = ray.t_max();
        self.finished = true;
        self.error = None;
        let result = self.fill_lists::<K>(axes, ray);
        if result.is_err() {
            for list in &mut self.lists {
                list.clear();
            }
        }
        result
    }

    fn fill_lists<K: GridKind>(
        &mut self,
        axes: &Axes<'_, T>,
        ray: &Ray<T>,
    ) -> Result<(), MarchError> {
        let m = self;
        let mut rays = Rays::of(ray);
        let mut streams = [Stream::fixed(0); 3];
        let mut cones = SecondRoots::EMPTY;
        let Some(t0) = setup::<T, K>(axes, ray, &mut rays, &mut streams, &mut cones)? else {
            return Ok(());
        };
        let bands = streams.map(|s| s.band);
        let mut t_end = ray.t_max();
        for slot in 0..3 {
            let list = m.lists.get_mut(slot).ok_or(MarchError::IterationBound)?;
            let mut last_band = bands.get(slot).copied().unwrap_or(0);
            let mut last_t = None;
            while next_event::<T, K>(axes, &rays, &mut streams, &mut cones, slot) {
                let Some(&Stream { t, band: b, .. }) = streams.get(slot) else {
                    break;
                };
                if slot > 0 && t > t_end {
                    break;
                }
                list.push((t, b)).map_err(|_| MarchError::BufferFull {
                    axis: coordinates::<K>(axes.coordinates)
                        .axes()
                        .get(slot)
                        .copied()
                        .unwrap_or(Axis::Z),
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
