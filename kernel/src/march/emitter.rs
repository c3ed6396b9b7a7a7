//! Band changes into cell crossings, shared by both engines.

use super::crossing::CellCrossing;
use super::tables::CellRule;
use crate::real::Real;

/// The bits of [`Emitter::outside`] that say which slots' bands are outside the domain.
const SLOTS: u8 = 0b111;

/// The bit of [`Emitter::outside`] set for a whole march in which an event's `t` may not be finite, so that
/// every event takes the checked path. That needs a ray whose `t = s·2^-e` can overflow where `s` does not
/// (`e < 0`, a direction scaled up). Otherwise every event inside the domain has a finite `t`: it lies before the
/// ray leaves the outer radius (which ends the march), and that `t` is at most the finite `s` of its root.
pub(crate) const CHECK_T: u8 = 0x80;

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
    pub(crate) unrepresentable: bool,
}

impl<T: Real> Emitter<T> {
    pub(crate) fn new(rule: &CellRule, bands: [u32; 3], t0: T, check_t: bool) -> Self {
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
    pub(crate) fn take_pending(&mut self) -> Option<CellCrossing<T>> {
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
    pub(crate) fn on(
        &mut self,
        rule: &CellRule,
        t: T,
        slot: usize,
        band: u32,
    ) -> Option<CellCrossing<T>> {
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
            // (in a build for size the cells are compared element by element: an array's `==` links `memcmp`,
            // 116 B on the M4F, while at opt 3 the element-wise forms cost 1.9 to 6.3 instructions per crossing)
            Some((cell, t_exit))
                if (if cfg!(curvicast_small_code) {
                    cell.iter().eq(&self.cell)
                } else {
                    cell == self.cell
                }) && t_exit == t =>
            {
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
    pub(crate) fn close(&mut self) {
        self.outside = 0xff;
    }

    /// The end of the march at `t_end`: the crossing in progress, or the held one (taken: a second call gives
    /// nothing).
    pub(crate) fn finish(&mut self, t_end: T) -> Option<CellCrossing<T>> {
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
