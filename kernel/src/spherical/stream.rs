//! One coordinate's sequence of boundary crossings along a ray (Hannasch §3.1.1–3.1.2 for the separable form,
//! ch. 5 for the serial one): each stream yields `(t, new band)` events in nondecreasing `t`, one band step each.
//!
//! A stream's state is a few scalars; its next crossing is computed only when the previous one has been consumed
//! (the caller caches it), so each radius or zenith crossing costs one square root and each azimuth or z crossing
//! one division. The streams are independent of each other, which is what lets the serial and the separable engines interleave
//! the very same events and agree exactly.
//!
//! **Topology first.** Which boundary comes next is decided by logic that cannot step by more than one band:
//! * radius (ditone, Lemma 8): a descending phase (before the hinge, entering ever smaller spheres while the line
//!   meets them) and then an ascending phase (leaving ever larger spheres);
//! * zenith (ditone, Lemma 4): a first phase in the direction θ moves at the start (the sign of
//!   `⟨p + t d | d_z p − p_z d⟩`, Lemma 2), crossing the next cone's matching side, and at most one switch to the
//!   other direction when that cone is not reached (the hinge);
//! * azimuth (monotone, Lemma 6): the turning sense is the sign of `(p × d)_z`; the next boundary half-plane in
//!   that sense;
//! * height: the sign of `d_z`.
//!
//! The `t` of each event comes from the shared `surface` solvers and is clamped to be no smaller than the previous
//! event's, so a slightly inaccurate `t` can shorten a crossing to zero length but never reorder the cells.
//!
//! **Degenerate lines.** A line through the center (`p × d = 0`) keeps θ constant except for a jump from θ to
//! π − θ at the center; a line meeting the z axis keeps φ constant except for a jump by π there. Both jumps are
//! emitted as one band step per crossed boundary, all at the same `t` (zero-length crossings, Hannasch §3.1.4).
//! For the azimuth jump the walk goes the way round that stays inside a wedge when one does (a full turn: the
//! shorter way, counter-clockwise on a tie). A line parallel to the z axis keeps φ constant.

use super::axes::{AzimuthAxis, HeightAxis, RadialAxis, ZenithAxis};
use crate::ray::{Line, Scale};
use crate::real::Real;
use crate::surface::{
    ConeRoots, PlaneZ, Side, sign_of, sphere_exit_root_signed, sphere_roots_signed,
};
use crate::vec3::V3;

/// One event: the crossing's parameter `t` and the band (or sector) entered.
pub(crate) type Event<T> = (T, u32);

/// The parameter `t = num / den` of a plane crossing given in the scaled parameter of `ray` (`den > 0`): one
/// division (Hannasch §4.6). The exact rescaling is folded into the denominator (`den·2^e`, exact) when that
/// stays in the normal range, so the quotient is the correctly rounded `t` with no second rounding; otherwise
/// the scaled quotient is rescaled exactly.
#[inline(always)]
fn plane_t<T: Real>(num: T, den: T, ray: &Line<T>) -> T {
    if ray.scale_exponent() == 0 {
        return num / den;
    }
    let folded = ray.t_to_scaled(den); // den · 2^e, exact
    if folded >= T::MIN_POSITIVE && folded <= T::MAX {
        num / folded
    } else {
        ray.t_from_scaled(num / den)
    }
}

/// The later of a crossing's `t` and the stream's previous event `t_own` (never NaN): the clamp that keeps a
/// stream's events nondecreasing. A NaN `t` gives `t_own` (as `max` would), and so does a `t` equal to it (so
/// a root at −0 after a start at +0 stays +0): one comparison, the form of x86-64's `maxsd`.
#[inline(always)]
fn later<T: Real>(t: T, t_own: T) -> T {
    if t > t_own { t } else { t_own }
}

/// The state of one coordinate's stream: the band entered and the `t` of its last event (its start before the
/// first) — which, once the stream has produced an event, *is* that event: the engines read a coordinate's next
/// crossing from here, so it is stored once — and what the coordinate's kind needs to find the next one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Stream<T> {
    /// The band (or sector) entered at the last event.
    pub(crate) band: u32,
    /// The last event's parameter.
    pub(crate) t: T,
    kind: Kind<T>,
}

/// How many of a zenith stream's second roots are kept (a power of two, at most 8).
const SECOND_ROOTS: usize = 8;

/// The second roots of the cones a zenith stream has crossed, the latest last: `(cone, t, side entered)`. θ is
/// ditone along a line (Lemma 4), so the cones crossed before its turn are crossed back after it in the reverse
/// order, each at the other root of the solve that found its first crossing: a last-in-first-out stack of those
/// roots saves the second solve. Each kept root is the same bits a new solve of that cone gives (the solve is a
/// function of the line and the cone alone), so keeping or losing one changes no answer. A ring of
/// [`SECOND_ROOTS`] entries: when it is full, a push drops the oldest (the one needed last); a cone whose index
/// does not fit 16 bits is not kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SecondRoots<T> {
    t: [T; SECOND_ROOTS],
    cone: [u16; SECOND_ROOTS],
    /// Bit `k`: entry `k` enters the positive side.
    positive: u8,
    /// The ring's oldest entry and its number of entries.
    start: u8,
    len: u8,
}

impl<T: Real> SecondRoots<T> {
    /// No root kept.
    pub(crate) const EMPTY: Self = SecondRoots {
        t: [T::ZERO; SECOND_ROOTS],
        cone: [0; SECOND_ROOTS],
        positive: 0,
        start: 0,
        len: 0,
    };

    #[inline(always)]
    fn slot(&self, k: u8) -> usize {
        usize::from(self.start.wrapping_add(k)) & (SECOND_ROOTS - 1)
    }

    /// The latest root kept.
    #[inline(always)]
    fn last(&self) -> Option<(u32, T, Side)> {
        let k = self.slot(self.len.checked_sub(1)?);
        let side = Side::from_bool(self.positive & (1u8 << (k & 7)) != 0);
        Some((u32::from(*self.cone.get(k)?), *self.t.get(k)?, side))
    }

    #[inline(always)]
    fn pop(&mut self) {
        self.len = self.len.saturating_sub(1);
    }

    /// The number of roots kept.
    #[cfg(test)]
    pub(crate) fn kept(&self) -> u8 {
        self.len
    }

    #[inline(always)]
    fn clear(&mut self) {
        self.len = 0;
    }

    #[inline(always)]
    fn push(&mut self, cone: u32, t: T, side: Side) {
        let Ok(cone) = u16::try_from(cone) else {
            return;
        };
        if usize::from(self.len) == SECOND_ROOTS {
            self.start = self.start.wrapping_add(1);
            self.len = self.len.saturating_sub(1);
        }
        let k = self.slot(self.len);
        if let (Some(c), Some(x)) = (self.cone.get_mut(k), self.t.get_mut(k)) {
            (*c, *x) = (cone, t);
            let bit = 1u8 << (k & 7);
            self.positive = if side == Side::Positive {
                self.positive | bit
            } else {
                self.positive & !bit
            };
            self.len = self.len.saturating_add(1);
        }
    }
}

/// A cache index that matches no sphere (the radius stream's one-entry cache).
const NO_CACHE: u32 = u32::MAX;

/// What a stream of each kind keeps besides its band and `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind<T> {
    /// No further events (a coordinate that is constant along the ray, the absent third axis of a polar grid,
    /// or a stream that has ended).
    Fixed,
    Radial {
        descending: bool,
        /// The leaving root of the sphere last entered: its index (`NO_CACHE` when none) and `t`.
        cache_j: u32,
        cache_t: T,
        /// The band the stream started in: every sphere below it that the ascending phase leaves, the
        /// descending phase entered (one band per event), so its roots are known to be distinct and in order.
        start: u32,
    },
    Zenith {
        up: bool,
        switched: bool,
        /// Events left before [`zenith_event_bound`] is exceeded.
        left: u32,
    },
    Azimuth {
        ccw: bool,
        /// The horizontal direction where the remaining sweep of φ starts (the last boundary crossed).
        from: (T, T),
        /// Boundaries crossed so far: a sweep of less than π crosses each at most once, so never more than
        /// there are (a bound that also ends degenerate wedges whose boundaries round to one direction).
        crossed: u32,
    },
    Height {
        up: bool,
    },
    /// A zenith stream that exceeded its event bound: no further events, and the march stops with
    /// `MarchError::IterationBound`.
    Overrun,
    /// A run of band steps all at one `t`, the jump of θ through the center or of φ across the z axis (Hannasch
    /// §3.1.4), after which the stream ends: `remaining` steps up or down (`cyclic`: sectors, modulo the
    /// azimuth's boundary count).
    Walk {
        t: T,
        remaining: u32,
        up: bool,
        cyclic: bool,
    },
}

/// The line as the radius stream sees it: the invariants of the sphere quadratic `‖d‖² s² + 2⟨p|d⟩ s + ‖p‖² − r²`
/// (Hannasch §4.1, Lemma 8) in the ray's scaled parameter, formed once per ray, and the exact rescaling to `t`.
/// For the cylinder and the polar grid it is the line's projection on z = 0, with its own rescaling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RadialLine<T> {
    /// `‖p‖²`.
    pp: T,
    /// `|p × d|²`.
    ww: T,
    /// `⟨p|d⟩`.
    pd: T,
    /// `‖d‖²`.
    dd: T,
    /// The sign the stable quadratic gives its square root, `sign_of(⟨p|d⟩)` (taken once per ray).
    sign: T,
    scale: Scale<T>,
}

impl<T: Real> RadialLine<T> {
    /// The invariants of `ray` (as the sphere solver forms them, so that the roots are the same bits).
    pub(crate) fn of(ray: &Line<T>) -> Self {
        RadialLine {
            pp: ray.origin().length_squared(),
            ww: ray.p_cross_d().length_squared(),
            pd: ray.pd(),
            dd: ray.dd(),
            sign: sign_of(ray.pd()),
            scale: ray.scale(),
        }
    }

    /// The two roots with the sphere of squared radius `r2` centred at the origin, in the caller's `t` (one
    /// square root; `None` when the line misses it or `r2 = 0`).
    #[inline]
    fn sphere_roots(&self, r2: T) -> Option<(T, T)> {
        if !(r2 > T::ZERO) {
            return None;
        }
        let (a, b) = sphere_roots_signed(r2, self.pp, self.dd, self.pd, self.ww, self.sign)?;
        Some((self.scale.t_from_scaled(a), self.scale.t_from_scaled(b)))
    }

    /// The second of [`RadialLine::sphere_roots`], the same bits, for a sphere the line entered (its roots were
    /// found distinct and in order): one division, no test for a touch.
    #[inline]
    fn exit_of_entered(&self, r2: T) -> T {
        let s = sphere_exit_root_signed(r2, self.pp, self.dd, self.pd, self.ww, self.sign);
        self.scale.t_from_scaled(s)
    }

    /// A placeholder until the set-up forms the line (no arithmetic).
    pub(crate) fn unset(ray: &Line<T>) -> Self {
        RadialLine {
            pp: T::ZERO,
            ww: T::ZERO,
            pd: T::ZERO,
            dd: T::ZERO,
            sign: T::ONE,
            scale: ray.scale(),
        }
    }

    /// The exact rescaling between this line's scaled parameter and the ray's `t`.
    #[inline]
    pub(crate) fn scale(&self) -> Scale<T> {
        self.scale
    }

    /// True before the hinge of r (Lemma 8): `⟨p + t d | d⟩ < 0`, decided without a division. No branch for
    /// `t = ±∞` (a line's start): with a finite `⟨p|d⟩` the sum is then `±∞`, which is the test `t < 0`; an
    /// infinite `⟨p|d⟩` (NaN sum) needs `‖p‖² = ∞`, and then no sphere is entered either way.
    #[inline]
    fn before_hinge(&self, t: T) -> bool {
        self.pd + self.scale.t_to_scaled(t) * self.dd < T::ZERO
    }
}

/// The most events a zenith stream of `len` breakpoints may give: its bound on the engines' loops. The other
/// streams are bounded by construction (the radius band falls, then rises, one band per event; the azimuth
/// crosses each boundary at most once, then walks at most once round; the height band is monotone; a walk
/// counts its steps), so the serial engine needs no count of its own. The zenith stream's cone crossings are
/// as bounded (θ is ditone, Lemma 4: one switch of direction), but its repairs where the solver is blind
/// (see `next_zenith`) are argued, not counted by construction: this is the safety net that turns an
/// unforeseen loop there into `MarchError::IterationBound`. Each phase crosses each cone at most once and each
/// repair moves toward the limit band, so `4·len + 64` leaves a wide margin.
#[inline]
pub(crate) fn zenith_event_bound(len: u32) -> u32 {
    len.saturating_mul(4).saturating_add(64)
}

/// True when a cross product (of largest component `w`) is at the level of its own rounding error for factors
/// of largest components `a` and `b`: the line then passes the center (or the z axis) within rounding, and the
/// sign of the cross product carries no information. Such lines are treated as passing exactly through it.
/// Max-norms, not squares, so that nothing underflows.
#[inline]
fn rounding_level<T: Real>(w: T, a: T, b: T) -> bool {
    w.abs() <= T::EPSILON * T::from_f64(8.0) * a * b
}

/// About `sqrt(ε)` of the type (a power of two, computed without a square root).
#[inline]
fn sqrt_epsilon<T: Real>() -> T {
    let half_digits = i32::try_from(T::MANTISSA_DIGITS.saturating_sub(1) / 2).unwrap_or(26);
    T::ONE.scalbn(half_digits.saturating_neg())
}

/// `s mod nb` (0 when `nb = 0`).
#[inline]
fn cyc(s: u32, nb: u32) -> u32 {
    s.checked_rem(nb).unwrap_or(0)
}

/// The sector after (`ccw`) or before sector `s` of `nb`, cyclically.
#[inline(always)]
fn cyclic_step(s: u32, ccw: bool, nb: u32) -> u32 {
    if ccw {
        cyc(s.wrapping_add(1), nb)
    } else {
        cyc(s.wrapping_add(nb).wrapping_sub(1), nb)
    }
}

/// The way round from sector `from` to sector `to` for a jump of φ taken in zero length: the one that does not
/// pass the outside sector of a wedge when there is one (there is when both ends are inside), else `prefer`
/// (the turning sense) if given, else the shorter (counter-clockwise on a tie). Returns `(ccw, steps)`.
fn walk_way<T: Real>(
    axis: &AzimuthAxis<'_, T>,
    from: u32,
    to: u32,
    prefer: Option<bool>,
) -> (bool, u32) {
    let nb = axis.boundaries.max(1);
    let ccw_steps = cyc(to.wrapping_sub(from).wrapping_add(nb), nb);
    let cw_steps = cyc(from.wrapping_sub(to).wrapping_add(nb), nb);
    let shorter = prefer.unwrap_or(ccw_steps <= cw_steps);
    let ccw = if axis.full {
        shorter
    } else {
        let out = axis.sectors;
        let passes = |steps: u32, dir_ccw: bool| -> bool {
            let mut s = from;
            for _ in 1..steps {
                s = cyclic_step(s, dir_ccw, nb);
                if s == out {
                    return true;
                }
            }
            false
        };
        if passes(ccw_steps, true) {
            false
        } else if passes(cw_steps, false) {
            true
        } else {
            shorter
        }
    };
    (ccw, if ccw { ccw_steps } else { cw_steps })
}

/// The point of the ray at `t` (computed in the scaled parameter).
#[inline]
pub(crate) fn point_at<T: Real>(ray: &Line<T>, t: T) -> V3<T> {
    ray.origin()
        .add_scaled(ray.t_to_scaled(t), ray.scaled_dir())
}

/// The step a stream takes next: its coordinate's kind, `None` once it has ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum StepKind {
    Radial,
    Zenith,
    Azimuth,
    Height,
    Walk,
    None,
}

impl<T: Real> Stream<T> {
    /// The step this stream takes next (its own tag: the engines dispatch on it, not on the grid's slots).
    #[inline(always)]
    pub(crate) fn step_kind(&self) -> StepKind {
        match self.kind {
            Kind::Radial { .. } => StepKind::Radial,
            Kind::Zenith { .. } => StepKind::Zenith,
            Kind::Azimuth { .. } => StepKind::Azimuth,
            Kind::Height { .. } => StepKind::Height,
            Kind::Walk { .. } => StepKind::Walk,
            Kind::Fixed | Kind::Overrun => StepKind::None,
        }
    }

    /// The same zenith stream with only `n` events left before its bound (to test the bound).
    #[cfg(test)]
    pub(crate) fn with_events_left(mut self, n: u32) -> Self {
        if let Kind::Zenith { left, .. } = &mut self.kind {
            *left = n;
        }
        self
    }

    /// True when this stream ended by exceeding its event bound (see [`zenith_event_bound`]).
    #[inline]
    pub(crate) fn overran(&self) -> bool {
        matches!(self.kind, Kind::Overrun)
    }

    /// A stream without events, in `band`.
    #[inline]
    pub(crate) fn fixed(band: u32) -> Self {
        Stream {
            band,
            t: T::ZERO,
            kind: Kind::Fixed,
        }
    }

    /// The radius stream for a ray starting at `t0` (finite, or −∞); `line` is [`RadialLine::of`] `ray`.
    pub(crate) fn radial(
        axis: &RadialAxis<'_, T>,
        ray: &Line<T>,
        line: &RadialLine<T>,
        t0: T,
    ) -> (Self, u32) {
        let r2 = if t0.is_finite() {
            point_at(ray, t0).length_squared()
        } else {
            T::INFINITY
        };
        // a start point too far to represent (p + t d overflows to ∞ or NaN) is outside the outer radius
        let band = if r2.is_finite() {
            axis.band_of_r2(r2)
        } else {
            axis.len
        };
        (
            Stream {
                band,
                t: t0,
                kind: Kind::Radial {
                    descending: line.before_hinge(t0),
                    cache_j: NO_CACHE,
                    cache_t: T::ZERO,
                    start: band,
                },
            },
            band,
        )
    }

    /// The zenith stream for a ray starting at the finite `t0`.
    /// (Kept out of line, as is `azimuth`: their temporaries then live in their own frames, not in the set-up's
    /// for the whole set-up; on a Cortex-M4F one march's stack drops from 1 396 to 1 312 bytes.)
    #[inline(never)]
    pub(crate) fn zenith(axis: &ZenithAxis<'_, T>, ray: &Line<T>, t0: T) -> (Self, u32) {
        let w = ray.p_cross_d();
        let d = ray.scaled_dir();
        let p = ray.origin();
        if p.z == T::ZERO && d.z == T::ZERO {
            // a line in the plane z = 0: θ = π/2 throughout
            let band = axis.band_of(V3::new(T::ONE, T::ZERO, T::ZERO), false);
            return (Stream::fixed(band), band);
        }
        // p × d = 0, or its horizontal part is 0 (which for a line not in the plane z = 0 means p × d is a
        // rounding residue): the line passes through the center.
        if (w.x == T::ZERO && w.y == T::ZERO)
            || rounding_level(w.max_abs(), p.max_abs().max(axis.scale), d.max_abs())
        {
            // The line passes through the center: θ is that of −d before it and of +d after it.
            let t_c = ray.t_from_scaled(-ray.pd() / ray.dd());
            let after = axis.band_of(d, false);
            if !(t_c > t0) {
                return (Stream::fixed(after), after);
            }
            let before = axis.band_of(d.negated(), false);
            return (
                Stream {
                    band: before,
                    t: t0,
                    kind: Kind::Walk {
                        t: t_c,
                        remaining: after.abs_diff(before),
                        up: after > before,
                        cyclic: false,
                    },
                },
                before,
            );
        }
        let q = point_at(ray, t0);
        let leaves_axis = d.x != T::ZERO || d.y != T::ZERO;
        let band = if q == V3::ZERO {
            axis.band_of(d, false)
        } else {
            axis.band_of(q, leaves_axis)
        };
        // v = d_z p − p_z d = e_z × (p × d) = (−w_y, w_x, 0); θ rises where ⟨p + t d | v⟩ < 0 (Lemma 2).
        let v = V3::new(-w.y, w.x, T::ZERO);
        let f = q.dot(v);
        let g = d.dot(v);
        let up = if f < T::ZERO {
            true
        } else if f > T::ZERO {
            false
        } else {
            g < T::ZERO
        };
        (
            Stream {
                band,
                t: t0,
                kind: Kind::Zenith {
                    up,
                    switched: false,
                    left: zenith_event_bound(axis.len),
                },
            },
            band,
        )
    }

    /// The azimuth stream for a ray starting at the finite `t0`.
    #[inline(never)]
    pub(crate) fn azimuth(axis: &AzimuthAxis<'_, T>, ray: &Line<T>, t0: T) -> (Self, u32) {
        let d = ray.scaled_dir();
        let p = ray.origin();
        if d.x == T::ZERO && d.y == T::ZERO {
            let sector = axis.sector_of(p.x, p.y); // parallel to the z axis
            return (Stream::fixed(sector), sector);
        }
        let wz = ray.p_cross_d().z;
        let (pm, dm) = (
            p.x.abs().max(p.y.abs()).max(axis.scale),
            d.x.abs().max(d.y.abs()),
        );
        if rounding_level(wz, pm, dm) {
            // The line meets the z axis: φ is that of −d before, of +d after.
            let s_a = -(p.x * d.x + p.y * d.y) / (d.x * d.x + d.y * d.y);
            let t_a = ray.t_from_scaled(s_a);
            if !t_a.is_finite() {
                // d's horizontal part is too small to place the axis crossing: parallel to the z axis
                let sector = axis.sector_of(p.x, p.y);
                return (Stream::fixed(sector), sector);
            }
            let after = axis.sector_of(d.x, d.y);
            if !(t_a > t0) {
                return (Stream::fixed(after), after);
            }
            let before = axis.sector_of(-d.x, -d.y);
            let (ccw, steps) = walk_way(axis, before, after, None);
            return (
                Stream {
                    band: before,
                    t: t0,
                    kind: Kind::Walk {
                        t: t_a,
                        remaining: steps,
                        up: ccw,
                        cyclic: true,
                    },
                },
                before,
            );
        }
        let q = point_at(ray, t0);
        let on_axis = q.x == T::ZERO && q.y == T::ZERO;
        let sector = if on_axis {
            axis.sector_of(d.x, d.y)
        } else {
            axis.sector_of(q.x, q.y)
        };
        let from = if on_axis { (-d.x, -d.y) } else { (q.x, q.y) };
        let stream = if axis.boundaries <= 1 && axis.full {
            Stream::fixed(sector) // one sector all round: no boundary to cross
        } else {
            Stream {
                band: sector,
                t: t0,
                kind: Kind::Azimuth {
                    ccw: wz > T::ZERO,
                    from,
                    crossed: 0,
                },
            }
        };
        (stream, sector)
    }

    /// The height stream for a ray starting at `t0` (finite or −∞).
    pub(crate) fn height(axis: &HeightAxis<'_, T>, ray: &Line<T>, t0: T) -> (Self, u32) {
        let dz = ray.scaled_dir().z;
        let band = if t0.is_finite() {
            axis.band_of(point_at(ray, t0).z)
        } else if dz > T::ZERO {
            0
        } else {
            axis.len
        };
        if dz == T::ZERO {
            let band = axis.band_of(ray.origin().z);
            return (Stream::fixed(band), band);
        }
        (
            Stream {
                band,
                t: t0,
                kind: Kind::Height { up: dz > T::ZERO },
            },
            band,
        )
    }

    /// Advances to the next radius event (at most one square root); false when there is none up to the ray's
    /// `t_max`.
    #[inline(always)]
    pub(crate) fn next_radial(
        &mut self,
        axis: &RadialAxis<'_, T>,
        line: &RadialLine<T>,
        t_max: T,
    ) -> bool {
        let Kind::Radial {
            descending,
            cache_j,
            cache_t,
            start,
        } = &mut self.kind
        else {
            return false;
        };
        let (band, t_own) = (&mut self.band, &mut self.t);
        if *descending {
            let inner = band.checked_sub(1);
            let hit = match inner {
                Some(j) if line.before_hinge(*t_own) => axis
                    .r2
                    .get(j as usize)
                    .and_then(|&r2| line.sphere_roots(r2))
                    // a touch (double root) does not enter: the touching point has r = r_j, which belongs
                    // to the outer band (half-open cells)
                    .filter(|&(t_in, t_out)| t_in < t_out)
                    .map(|roots| (j, roots)),
                _ => None,
            };
            match hit {
                Some((j, (t_in, t_out))) => {
                    let t = later(t_in, *t_own);
                    if t > t_max {
                        self.kind = Kind::Fixed;
                        return false;
                    }
                    *band = j;
                    *t_own = t;
                    (*cache_j, *cache_t) = (j, t_out);
                    return true;
                }
                None => *descending = false,
            }
        }
        // ascending: leave the sphere of the band's upper radius
        let j = *band;
        if j >= axis.len {
            self.kind = Kind::Fixed;
            return false;
        }
        let t_out = if *cache_j == j {
            *cache_t
        } else if j < *start {
            // entered on the way in: only its exit root is solved again
            axis.r2
                .get(j as usize)
                .map_or(*t_own, |&r2| line.exit_of_entered(r2))
        } else {
            axis.r2
                .get(j as usize)
                .and_then(|&r2| line.sphere_roots(r2))
                .map_or(*t_own, |(_, t_out)| t_out)
        };
        *cache_j = NO_CACHE;
        let t = later(t_out, *t_own);
        if t > t_max {
            self.kind = Kind::Fixed;
            return false;
        }
        let nb = j.saturating_add(1);
        *band = nb;
        *t_own = t;
        true
    }

    /// The next zenith event (at most one square root in the common case, two at a hinge not reached through a
    /// cached root), or `None`. Inlined into the engines' loops like the radius and azimuth steps (the cone
    /// solver itself stays out of line).
    #[inline(always)]
    pub(crate) fn next_zenith(
        &mut self,
        axis: &ZenithAxis<'_, T>,
        ray: &Line<T>,
        t_max: T,
        roots: &mut SecondRoots<T>,
    ) -> bool {
        let Kind::Zenith { up, switched, left } = &mut self.kind else {
            return false;
        };
        if *left == 0 {
            self.kind = Kind::Overrun;
            return false;
        }
        *left = left.wrapping_sub(1);
        let (band, t_own) = (&mut self.band, &mut self.t);
        for _ in 0..2 {
            // the cone to cross and the side to enter (band 0 has no cone below it, band `len` none above)
            let (j, want) = if *up {
                (*band, Side::Positive)
            } else {
                (band.wrapping_sub(1), Side::Negative)
            };
            if j < axis.len {
                // the other root of this cone, kept when it was solved (the latest kept root: θ turns once, so
                // the cones crossed before its turn are crossed back in the reverse order), or a solve: the
                // first root entering `want` at or after the stream's last event, and the root after it (kept:
                // the line may cross the same cone back later)
                let mut hit = None;
                let mut keep = None;
                let kept = roots
                    .last()
                    .filter(|&(kj, kt, ks)| kj == j && ks == want && kt >= *t_own);
                if let Some((_, kt, _)) = kept {
                    hit = Some(kt);
                } else if let Some(cone) = axis.cone(j) {
                    let ConeRoots {
                        s: [s0, s1],
                        into: [into0, into1],
                        n,
                    } = cone.scaled_crossings_past_origin(ray);
                    let t0 = ray.t_from_scaled(s0);
                    if n >= 1 && into0 == want && t0 >= *t_own {
                        hit = Some(t0);
                        if n == 2 {
                            keep = Some((j, ray.t_from_scaled(s1), into1));
                        }
                    } else if n == 2 && into1 == want {
                        let t1 = ray.t_from_scaled(s1);
                        if t1 >= *t_own {
                            hit = Some(t1);
                        }
                    }
                }
                if let Some(t) = hit {
                    if t > t_max {
                        self.kind = Kind::Fixed;
                        return false;
                    }
                    if kept.is_some() {
                        roots.pop();
                    } else if let Some((kj, kt, ks)) = keep {
                        roots.push(kj, kt, ks);
                    }
                    *band = if *up { j.saturating_add(1) } else { j };
                    *t_own = t;
                    return true;
                }
            }
            if *switched {
                break;
            }
            *switched = true;
            *up = !*up;
        }
        // No further cone is crossed. Topology check: far along the ray θ tends to the zenith angle of d, so
        // the band must end as the band of d. Where the cone solver is blind (a line passing the apex of a cone
        // within rounding, where the nappe of a root cannot be told), the missing crossings are completed here,
        // at the closest approach to the center. Not when d lies within rounding of the cone between the two
        // bands: a line parallel to a generator approaches that cone from one side without crossing it.
        let target = axis.band_of(ray.scaled_dir(), true);
        let b = *band;
        let on_limit_boundary =
            b.abs_diff(target) == 1 && axis.along_cone(b.min(target), ray.scaled_dir());
        if target != b && !on_limit_boundary {
            // One band toward the limit, then the ordinary search resumes in that direction only (so the
            // remaining cones are still crossed where the solver sees them). Each repair moves toward the
            // limit band, so there are at most as many repairs as bands.
            let t = later(ray.t_closest(), *t_own);
            if !(t <= t_max) {
                self.kind = Kind::Fixed;
                return false;
            }
            *up = target > b;
            *switched = true;
            roots.clear();
            *band = if *up {
                b.saturating_add(1)
            } else {
                b.saturating_sub(1)
            };
            *t_own = t;
            return true;
        }
        self.kind = Kind::Fixed;
        false
    }

    /// The next azimuth event (one division); false when there is none.
    #[inline(always)]
    pub(crate) fn next_azimuth(
        &mut self,
        axis: &AzimuthAxis<'_, T>,
        ray: &Line<T>,
        t_max: T,
    ) -> bool {
        let Kind::Azimuth { ccw, from, crossed } = &mut self.kind else {
            return false;
        };
        let (sector, t_own) = (&mut self.band, &mut self.t);
        let nb = axis.boundaries.max(1);
        let step = |s: u32, ccw: bool| cyclic_step(s, ccw, nb);
        let j = if *ccw { step(*sector, true) } else { *sector };
        // Topology first: the boundary is crossed only if its direction lies in the arc that φ still sweeps,
        // from the current point's direction to the direction of d (less than π, Lemma 6). Sign tests only.
        // The arc starts at the last boundary crossed (exact stored directions, robust even when the line passes
        // within rounding of the z axis), or at the start point's direction.
        let (fx, fy) = *from;
        let d = ray.scaled_dir();
        let plane = axis.plane(j);
        let (bc, bs) = (plane.cos(), plane.sin());
        let sg = if *ccw { T::ONE } else { -T::ONE };
        let f_b = (fx * bs - fy * bc) * sg;
        let b_d = (bc * d.y - bs * d.x) * sg;
        let ahead =
            b_d > T::ZERO && (f_b > T::ZERO || (f_b == T::ZERO && fx * bc + fy * bs > T::ZERO));
        if !ahead || *crossed >= axis.boundaries {
            return self.complete_azimuth(axis, ray, t_max);
        }
        // The line meets boundary j's half-plane ahead (the arc test above), going the way `b_d` says.
        let (num, den) = plane.scaled_root_fraction_ahead(ray, sg);
        // (`num` is never NaN: the origin and the boundary's direction are finite, and so is each product)
        let t = later(plane_t(num, den, ray), *t_own);
        if t > t_max {
            self.kind = Kind::Fixed;
            return false;
        }
        // counter-clockwise the sector entered is the one after boundary j, which is j itself
        *sector = if *ccw { j } else { step(*sector, false) };
        *t_own = t;
        *from = (bc, bs);
        *crossed = crossed.wrapping_add(1); // below `boundaries` (tested above)
        true
    }

    /// No further boundary is ahead. Topology check: far along the ray φ tends to the azimuth of d, so the
    /// sector must end as the sector of d (unless d lies exactly on a boundary, approached from one side). When
    /// the line passes within rounding of the z axis the half-plane tests cannot order the crossings there; they
    /// are completed here, at the closest approach to the axis, in the turning sense.
    fn complete_azimuth(&mut self, axis: &AzimuthAxis<'_, T>, ray: &Line<T>, t_max: T) -> bool {
        let Kind::Azimuth { ccw, .. } = self.kind else {
            return false;
        };
        let d = ray.scaled_dir();
        let p = ray.origin();
        // the cheap tests first: a line that passes the z axis clearly (every ordinary ray) ends here
        let near_axis = ray.p_cross_d().z.abs()
            <= sqrt_epsilon::<T>()
                * T::from_f64(64.0)
                * p.x.abs().max(p.y.abs()).max(axis.scale)
                * d.x.abs().max(d.y.abs());
        if !near_axis {
            self.kind = Kind::Fixed;
            return false;
        }
        let target = axis.sector_of(d.x, d.y);
        let (way, steps) = walk_way(axis, self.band, target, Some(ccw));
        // d on a boundary's direction (approached from one side): a scan of the boundaries, made only when there
        // is a walk to take (in f32 about 3 % of this scene's rays end near enough to the axis to come here)
        let on_boundary = || {
            (0..axis.boundaries).any(|k| {
                let (c, s) = axis.dir_of(k);
                c * d.y - s * d.x == T::ZERO && c * d.x + s * d.y > T::ZERO
            })
        };
        if steps == 0 || on_boundary() {
            self.kind = Kind::Fixed;
            return false;
        }
        let s_a = -(p.x * d.x + p.y * d.y) / (d.x * d.x + d.y * d.y);
        self.kind = Kind::Walk {
            t: ray.t_from_scaled(s_a),
            remaining: steps,
            up: way,
            cyclic: true,
        };
        self.next_walk(axis.boundaries.max(1), t_max)
    }

    /// The next step of a walk, at the walk's `t` (clamped to the last event); false when the walk is done or
    /// its `t` lies past `t_max`. `nb` is the azimuth's boundary count (for a cyclic walk).
    #[inline(always)]
    pub(crate) fn next_walk(&mut self, nb: u32, t_max: T) -> bool {
        let Kind::Walk {
            t,
            remaining,
            up,
            cyclic,
        } = &mut self.kind
        else {
            return false;
        };
        if *remaining == 0 || *t > t_max {
            self.kind = Kind::Fixed;
            return false;
        }
        *remaining = remaining.saturating_sub(1);
        self.band = if *cyclic {
            cyclic_step(self.band, *up, nb)
        } else if *up {
            self.band.saturating_add(1)
        } else {
            self.band.saturating_sub(1)
        };
        self.t = later(*t, self.t);
        true
    }

    /// The next height event (one division); false when there is none.
    pub(crate) fn next_height(
        &mut self,
        axis: &HeightAxis<'_, T>,
        ray: &Line<T>,
        t_max: T,
    ) -> bool {
        let Kind::Height { up } = &mut self.kind else {
            return false;
        };
        let (band, t_own) = (&mut self.band, &mut self.t);
        let j = if *up {
            if *band >= axis.len { None } else { Some(*band) }
        } else {
            band.checked_sub(1)
        };
        let root = j.and_then(|j| {
            let z = *axis.z.get(j as usize)?;
            PlaneZ::new(z).ok()?.scaled_root_fraction(ray)
        });
        match (j, root) {
            (Some(j), Some((num, den, _))) => {
                let t = later(plane_t(num, den, ray), *t_own);
                if t > t_max || num.is_nan() {
                    self.kind = Kind::Fixed;
                    return false;
                }
                *band = if *up { j.saturating_add(1) } else { j };
                *t_own = t;
                true
            }
            _ => {
                self.kind = Kind::Fixed;
                false
            }
        }
    }
}
