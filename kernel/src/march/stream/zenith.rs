//! The zenith stream (Hannasch Lemma 4: θ is ditone along a line): cones crossed in one direction, at most
//! one switch, and the repairs where the cone solver is blind; the second roots kept for the way back.

use super::state::{Kind, Stream, later, point_at, rounding_level};
use crate::march::axes::ZenithAxis;
use crate::ray::Line;
use crate::real::Real;
use crate::surface::{ConeRoots, Side};
use crate::vec3::V3;

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

/// Whether a root of cone `j` into `want` that the solver puts just behind the stream is to be crossed where the
/// stream stands, at `t`: the point there lies on the cone within rounding (a start on the cone that the band
/// test put on the other side), and θ moves toward `want` there clearly beyond the rounding of its rate, so the
/// line crosses the cone there rather than grazing it (a graze at θ's turn crosses nothing).
fn crossing_here<T: Real>(
    axis: &ZenithAxis<'_, T>,
    ray: &Line<T>,
    j: u32,
    want: Side,
    t: T,
) -> bool {
    let q = point_at(ray, t);
    let w = ray.p_cross_d();
    let v = V3::new(-w.y, w.x, T::ZERO);
    // θ rises where ⟨q | v⟩ < 0 (Lemma 2); its rounding is a few ε of |q|·|v| per term
    let f = q.dot(v);
    let tol = T::from_f64(16.0) * T::EPSILON * q.max_abs() * v.max_abs();
    let moving = if want == Side::Positive {
        f < -tol
    } else {
        f > tol
    };
    moving && axis.along_cone(j, q)
}

impl<T: Real> Stream<T> {
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
        // ⟨q + t d | v⟩ = f + t g changes sign once: at f = 0 the start is θ's turn, and θ is monotone after it
        // (so a start on a cone there, touching it, does not cross back at the start).
        let (up, switched) = if f < T::ZERO {
            (true, false)
        } else if f > T::ZERO {
            (false, false)
        } else {
            (g < T::ZERO, true)
        };
        (
            Stream {
                band,
                t: t0,
                kind: Kind::Zenith {
                    up,
                    switched,
                    left: zenith_event_bound(axis.len),
                },
            },
            band,
        )
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
                    // A touch from the positive side, met going down from band j + 1: the line stays in that
                    // band, which owns the point of contact on the cone (as the outer cell owns a sphere's), so
                    // it crosses nothing there. (Met going up, the touch is the crossing into that band of a
                    // stream that rounding started just below it.)
                    let n = if n == 2
                        && s0 == s1
                        && into1 == Side::Positive
                        && want == Side::Negative
                    {
                        0
                    } else {
                        n
                    };
                    let t_here = *t_own;
                    let ahead = |t: T| {
                        if t >= t_here {
                            Some(t)
                        } else {
                            crossing_here(axis, ray, j, want, t_here).then_some(t_here)
                        }
                    };
                    let t0 = ray.t_from_scaled(s0);
                    let first = if n >= 1 && into0 == want {
                        ahead(t0)
                    } else {
                        None
                    };
                    if let Some(t) = first {
                        hit = Some(t);
                        if n == 2 {
                            keep = Some((j, ray.t_from_scaled(s1), into1));
                        }
                    } else if n == 2 && into1 == want {
                        hit = ahead(ray.t_from_scaled(s1));
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
            // limit band, so there are at most as many repairs as bands. Where the stream stands on the cone
            // to cross, within rounding, the repair is there (a start between two roots the solver could not
            // tell apart, at θ's turn); elsewhere at the closest approach to the center.
            let cone = if target > b { b } else { b.wrapping_sub(1) };
            let t = if axis.along_cone(cone, point_at(ray, *t_own)) {
                *t_own
            } else {
                later(ray.t_closest(), *t_own)
            };
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn second_roots_keep_the_latest_eight_and_give_them_back_last_in_first_out() {
        let side = |k: u32| {
            if k % 3 == 0 {
                Side::Positive
            } else {
                Side::Negative
            }
        };
        let mut r = SecondRoots::<f64>::EMPTY;
        assert_eq!(r.last(), None);
        // eleven pushed: the ring keeps the latest eight (cones 3 to 10), each with its t and side
        for k in 0..11u32 {
            r.push(k, f64::from(k) + 0.5, side(k));
            assert_eq!(r.last(), Some((k, f64::from(k) + 0.5, side(k))));
        }
        assert_eq!(r.kept(), 8);
        for k in (3..11u32).rev() {
            assert_eq!(r.last(), Some((k, f64::from(k) + 0.5, side(k))));
            r.pop();
        }
        assert_eq!((r.kept(), r.last()), (0, None));
        // a cone whose index does not fit 16 bits is not kept; `clear` empties the ring
        r.push(1 << 16, 1.0, Side::Positive);
        assert_eq!(r.last(), None);
        r.push(7, 1.0, Side::Positive);
        r.push(8, 2.0, Side::Negative);
        r.clear();
        assert_eq!((r.kept(), r.last()), (0, None));
        // a slot reused for the same side keeps that side: sixteen entering the positive side, then sixteen the
        // negative, each read back as pushed
        for (k, s) in (0..32u32).map(|k| {
            (
                k,
                if k < 16 {
                    Side::Positive
                } else {
                    Side::Negative
                },
            )
        }) {
            r.push(k, f64::from(k), s);
            assert_eq!(r.last(), Some((k, f64::from(k), s)), "push {k}");
        }
    }
}
