//! What every stream shares: its state (band, last event, kind), the helpers of the steps, and the walk
//! through a run of band steps at one `t` (Hannasch §3.1.4).

use crate::ray::Line;
use crate::real::Real;
use crate::vec3::V3;

/// One event: the crossing's parameter `t` and the band (or sector) entered.
pub(crate) type Event<T> = (T, u32);

/// The parameter `t = num / den` of a plane crossing given in the scaled parameter of `ray` (`den > 0`): one
/// division (Hannasch §4.6). The exact rescaling is folded into the denominator (`den·2^e`, exact) when that
/// stays in the normal range, so the quotient is the correctly rounded `t` with no second rounding; otherwise
/// the scaled quotient is rescaled exactly.
#[inline(always)]
pub(super) fn plane_t<T: Real>(num: T, den: T, ray: &Line<T>) -> T {
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
pub(super) fn later<T: Real>(t: T, t_own: T) -> T {
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
    pub(super) kind: Kind<T>,
}

/// What a stream of each kind keeps besides its band and `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Kind<T> {
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

/// True when a cross product (of largest component `w`) is at the level of its own rounding error for factors
/// of largest components `a` and `b`: the line then passes the center (or the z axis) within rounding, and the
/// sign of the cross product carries no information. Such lines are treated as passing exactly through it.
/// Max-norms, not squares, so that nothing underflows.
#[inline]
pub(super) fn rounding_level<T: Real>(w: T, a: T, b: T) -> bool {
    w.abs() <= T::EPSILON * T::from_f64(8.0) * a * b
}

/// About `sqrt(ε)` of the type (a power of two, computed without a square root).
#[inline]
pub(super) fn sqrt_epsilon<T: Real>() -> T {
    let half_digits = i32::try_from(T::MANTISSA_DIGITS.saturating_sub(1) / 2).unwrap_or(26);
    T::ONE.scalbn(half_digits.saturating_neg())
}

/// `s mod nb` (0 when `nb = 0`).
#[inline]
pub(super) fn cyc(s: u32, nb: u32) -> u32 {
    s.checked_rem(nb).unwrap_or(0)
}

/// The sector after (`ccw`) or before sector `s` of `nb`, cyclically.
#[inline(always)]
pub(super) fn cyclic_step(s: u32, ccw: bool, nb: u32) -> u32 {
    if ccw {
        cyc(s.wrapping_add(1), nb)
    } else {
        cyc(s.wrapping_add(nb).wrapping_sub(1), nb)
    }
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

    /// The next step of a walk, at the walk's `t` (clamped to the last event); false when the walk is done or
    /// its `t` lies past `t_max`. `nb` is the azimuth's boundary count (for a cyclic walk). Only a line through
    /// the center or the z axis walks. On 32-bit ARM the walk stays out of the engines' loops, which then keep more
    /// in registers (a Cortex-M4F's march-f32: 180.6 instructions per crossing instead of 181.5, and 192 bytes
    /// less code); elsewhere it is inlined (x86-64, the report's scene: 180.3 instead of 182.4).
    #[cfg_attr(target_arch = "arm", inline(never))]
    #[cfg_attr(not(target_arch = "arm"), inline(always))]
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
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `rounding_level` is `|w| ≤ 8 ε a b`: from both sides of that bound, with factors of different sizes and
    /// either sign of `w`.
    #[test]
    fn rounding_level_holds_up_to_8_eps_times_the_factors_and_no_further() {
        for (a, b) in [(1.0, 1.0), (3.0e6, 2.0e-3), (0.25, 5.0e8)] {
            let bound = 8.0 * f64::EPSILON * a * b;
            for w in [0.0, 0.5 * bound, 0.99 * bound, -0.99 * bound] {
                assert!(rounding_level(w, a, b), "{w} of {bound}");
            }
            for w in [1.01 * bound, -1.01 * bound, 2.0 * bound] {
                assert!(!rounding_level(w, a, b), "{w} of {bound}");
            }
        }
    }

    /// `sqrt_epsilon` is the power of two `2^−⌊(p − 1)/2⌋`, `p` the mantissa's digits: `2^−26` in `f64`,
    /// `2^−11` in `f32`.
    #[test]
    fn sqrt_epsilon_is_the_power_of_two_below_the_square_root_of_epsilon() {
        // exact powers of two (std's `powi` carries error under Miri)
        assert_eq!(sqrt_epsilon::<f64>(), 1.0 / 67_108_864.0);
        assert_eq!(sqrt_epsilon::<f32>(), 1.0 / 2048.0);
    }

    /// `later` keeps the previous event on a tie, so a root at −0 after a start at +0 stays +0, and a NaN root
    /// gives the previous event.
    #[test]
    fn later_keeps_the_previous_event_on_a_tie_and_for_nan() {
        assert_eq!(later(2.0, 1.0), 2.0);
        assert_eq!(later(1.0, 2.0), 2.0);
        assert_eq!(later(-0.0_f64, 0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(later(0.0_f64, -0.0).to_bits(), (-0.0f64).to_bits());
        assert_eq!(later(f64::NAN, 3.0), 3.0);
    }
}
