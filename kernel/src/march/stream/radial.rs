//! The radius stream (Hannasch §4.1, Lemma 8: r is ditone along a line): a descending phase entering ever
//! smaller spheres, then an ascending one leaving ever larger ones.

use super::state::{Kind, Stream, later, point_at};
use crate::march::axes::RadialAxis;
use crate::ray::{Line, Scale};
use crate::real::Real;
use crate::surface::{sign_of, sphere_exit_root_signed, sphere_roots_signed};

/// A cache index that matches no sphere (the radius stream's one-entry cache).
const NO_CACHE: u32 = u32::MAX;

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

impl<T: Real> Stream<T> {
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
}
