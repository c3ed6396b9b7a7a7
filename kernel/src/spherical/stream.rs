//! One coordinate's sequence of boundary crossings along a ray (seed 001 §3.1.1–3.1.2 for the separable form,
//! ch. 5 for the serial one): each stream yields `(t, new band)` events in nondecreasing `t`, one band step each.
//!
//! A stream's state is a few scalars; its next crossing is computed only when the previous one has been consumed
//! (the caller caches it), so each radius or zenith crossing costs one square root and each azimuth or z crossing
//! one division. The streams are independent of each other, which is what lets the serial and the separable
//! engines interleave the very same events and agree exactly.
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
//! emitted as one band step per crossed boundary, all at the same `t` (zero-length crossings, seed 001 §3.1.4).
//! For the azimuth jump the walk goes the way round that stays inside a wedge when one does (a full turn: the
//! shorter way, counter-clockwise on a tie). A line parallel to the z axis keeps φ constant.

use super::axes::{AzimuthAxis, HeightAxis, RadialAxis, ZenithAxis};
use crate::ray::Ray;
use crate::real::Real;
use crate::surface::{PlaneZ, Side, Spheroid, Surface};
use crate::vec3::V3;

/// One event: the crossing's `t` and the band (or sector) entered.
pub(crate) type Event<T> = (T, u32);

/// A run of band steps all at one `t` (a jump through the center or the z axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Walk<T> {
    t: T,
    remaining: u32,
    up: bool,
}

/// The state of one coordinate's stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Stream<T> {
    /// No events (a coordinate that is constant along the ray, or the absent third axis of a polar grid).
    Fixed,
    Radial {
        band: u32,
        t_own: T,
        hinge: T,
        descending: bool,
        /// The leaving root of the sphere last entered: `(sphere index, t)`.
        cache: Option<(u32, T)>,
    },
    Zenith {
        band: u32,
        t_own: T,
        up: bool,
        switched: bool,
        /// The other root of the cone last crossed: `(cone index, t, side entered)`.
        cache: Option<(u32, T, Side)>,
        walk: Option<Walk<T>>,
    },
    Azimuth {
        sector: u32,
        t_own: T,
        ccw: bool,
        walk: Option<Walk<T>>,
    },
    Height {
        band: u32,
        t_own: T,
        up: bool,
    },
}

/// The two roots of the ray with the sphere of radius `r` centred at the origin, in the caller's `t`
/// (one square root; `None` when the line misses it or `r = 0`).
#[inline]
fn sphere_roots<T: Real>(r: T, ray: &Ray<T>) -> Option<(T, T)> {
    if !(r > T::ZERO) {
        return None;
    }
    let (a, b) = Spheroid::sphere(r).ok()?.scaled_roots(ray)?;
    Some((ray.t_from_scaled(a), ray.t_from_scaled(b)))
}

/// `s mod nb` (0 when `nb = 0`).
#[inline]
fn cyc(s: u32, nb: u32) -> u32 {
    s.checked_rem(nb).unwrap_or(0)
}

/// The point of the ray at `t` (computed in the scaled parameter).
#[inline]
pub(crate) fn point_at<T: Real>(ray: &Ray<T>, t: T) -> V3<T> {
    ray.origin()
        .add_scaled(ray.t_to_scaled(t), ray.scaled_dir())
}

impl<T: Real> Stream<T> {
    /// The radius stream for a ray starting at `t0` (finite, or −∞).
    pub(crate) fn radial(axis: &RadialAxis<'_, T>, ray: &Ray<T>, t0: T) -> (Self, u32) {
        let hinge = ray.t_closest();
        let band = if t0.is_finite() {
            let q = point_at(ray, t0);
            axis.band_of_r2(q.length_squared())
        } else {
            axis.len
        };
        (
            Stream::Radial {
                band,
                t_own: t0,
                hinge,
                descending: t0 < hinge,
                cache: None,
            },
            band,
        )
    }

    /// The zenith stream for a ray starting at the finite `t0`.
    pub(crate) fn zenith(axis: &ZenithAxis<'_, T>, ray: &Ray<T>, t0: T) -> (Self, u32) {
        let w = ray.p_cross_d();
        let d = ray.scaled_dir();
        if w == V3::ZERO {
            // The line passes through the center: θ is that of −d before it and of +d after it.
            let t_c = ray.t_from_scaled(-ray.pd() / ray.dd());
            let after = axis.band_of(d, false);
            if !(t_c > t0) {
                return (Stream::Fixed, after);
            }
            let before = axis.band_of(d.negated(), false);
            return (
                Stream::Zenith {
                    band: before,
                    t_own: t0,
                    up: after > before,
                    switched: true,
                    cache: None,
                    walk: Some(Walk {
                        t: t_c,
                        remaining: after.abs_diff(before),
                        up: after > before,
                    }),
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
        let (up, constant) = if f < T::ZERO {
            (true, false)
        } else if f > T::ZERO {
            (false, false)
        } else if g != T::ZERO {
            (g < T::ZERO, false)
        } else {
            (true, true) // v = 0: a line in the plane z = 0, θ = π/2 throughout
        };
        if constant {
            return (Stream::Fixed, band);
        }
        (
            Stream::Zenith {
                band,
                t_own: t0,
                up,
                switched: false,
                cache: None,
                walk: None,
            },
            band,
        )
    }

    /// The azimuth stream for a ray starting at the finite `t0`.
    pub(crate) fn azimuth(axis: &AzimuthAxis<'_, T>, ray: &Ray<T>, t0: T) -> (Self, u32) {
        let d = ray.scaled_dir();
        let p = ray.origin();
        if d.x == T::ZERO && d.y == T::ZERO {
            return (Stream::Fixed, axis.sector_of(p.x, p.y)); // parallel to the z axis
        }
        let wz = ray.p_cross_d().z;
        if wz == T::ZERO {
            // The line meets the z axis: φ is that of −d before, of +d after.
            let s_a = -(p.x * d.x + p.y * d.y) / (d.x * d.x + d.y * d.y);
            let t_a = ray.t_from_scaled(s_a);
            let after = axis.sector_of(d.x, d.y);
            if !(t_a > t0) {
                return (Stream::Fixed, after);
            }
            let before = axis.sector_of(-d.x, -d.y);
            let nb = axis.boundaries.max(1);
            let ccw_steps = cyc(after.wrapping_sub(before).wrapping_add(nb), nb);
            let cw_steps = cyc(before.wrapping_sub(after).wrapping_add(nb), nb);
            let ccw = if axis.full {
                ccw_steps <= cw_steps
            } else {
                // Go the way round that does not pass the outside sector (there is one when both ends are in).
                let out = axis.sectors;
                let passes = |from: u32, steps: u32, dir_ccw: bool| -> bool {
                    let mut s = from;
                    for _ in 1..steps {
                        s = if dir_ccw {
                            cyc(s.wrapping_add(1), nb)
                        } else {
                            cyc(s.wrapping_add(nb).wrapping_sub(1), nb)
                        };
                        if s == out {
                            return true;
                        }
                    }
                    false
                };
                if passes(before, ccw_steps, true) {
                    false
                } else if passes(before, cw_steps, false) {
                    true
                } else {
                    ccw_steps <= cw_steps
                }
            };
            let steps = if ccw { ccw_steps } else { cw_steps };
            return (
                Stream::Azimuth {
                    sector: before,
                    t_own: t0,
                    ccw,
                    walk: Some(Walk {
                        t: t_a,
                        remaining: steps,
                        up: ccw,
                    }),
                },
                before,
            );
        }
        let q = point_at(ray, t0);
        let sector = if q.x == T::ZERO && q.y == T::ZERO {
            axis.sector_of(d.x, d.y)
        } else {
            axis.sector_of(q.x, q.y)
        };
        let stream = if axis.boundaries <= 1 && axis.full {
            Stream::Fixed // one sector all round: no boundary to cross
        } else {
            Stream::Azimuth {
                sector,
                t_own: t0,
                ccw: wz > T::ZERO,
                walk: None,
            }
        };
        (stream, sector)
    }

    /// The height stream for a ray starting at `t0` (finite or −∞).
    pub(crate) fn height(axis: &HeightAxis<'_, T>, ray: &Ray<T>, t0: T) -> (Self, u32) {
        let dz = ray.scaled_dir().z;
        let band = if t0.is_finite() {
            axis.band_of(point_at(ray, t0).z)
        } else if dz > T::ZERO {
            0
        } else {
            axis.len
        };
        if dz == T::ZERO {
            return (Stream::Fixed, axis.band_of(ray.origin().z));
        }
        (
            Stream::Height {
                band,
                t_own: t0,
                up: dz > T::ZERO,
            },
            band,
        )
    }

    /// The next radius event (at most one square root), or `None` when there is none up to the ray's `t_max`.
    pub(crate) fn next_radial(
        &mut self,
        axis: &RadialAxis<'_, T>,
        ray: &Ray<T>,
    ) -> Option<Event<T>> {
        let Stream::Radial {
            band,
            t_own,
            hinge,
            descending,
            cache,
        } = self
        else {
            return None;
        };
        let t_max = ray.t_max();
        if *descending {
            let inner = band.checked_sub(1);
            let hit = match inner {
                Some(j) if *t_own < *hinge => axis
                    .r
                    .get(j as usize)
                    .and_then(|&r| sphere_roots(r, ray))
                    .map(|roots| (j, roots)),
                _ => None,
            };
            match hit {
                Some((j, (t_in, t_out))) => {
                    let t = t_in.max(*t_own);
                    if t > t_max {
                        *self = Stream::Fixed;
                        return None;
                    }
                    *band = j;
                    *t_own = t;
                    *cache = Some((j, t_out));
                    return Some((t, j));
                }
                None => *descending = false,
            }
        }
        // ascending: leave the sphere of the band's upper radius
        let j = *band;
        if j >= axis.len {
            *self = Stream::Fixed;
            return None;
        }
        let t_out = match *cache {
            Some((k, t)) if k == j => t,
            _ => axis
                .r
                .get(j as usize)
                .and_then(|&r| sphere_roots(r, ray))
                .map_or(*t_own, |(_, t_out)| t_out),
        };
        *cache = None;
        let t = t_out.max(*t_own);
        if t > t_max {
            *self = Stream::Fixed;
            return None;
        }
        let nb = j.saturating_add(1);
        *band = nb;
        *t_own = t;
        Some((t, nb))
    }

    /// The next zenith event (at most one square root in the common case, two at a hinge not reached through a
    /// cached root), or `None`.
    pub(crate) fn next_zenith(
        &mut self,
        axis: &ZenithAxis<'_, T>,
        ray: &Ray<T>,
    ) -> Option<Event<T>> {
        let Stream::Zenith {
            band,
            t_own,
            up,
            switched,
            cache,
            walk,
        } = self
        else {
            return None;
        };
        let t_max = ray.t_max();
        if let Some(w) = walk {
            if w.remaining == 0 || w.t > t_max {
                *self = Stream::Fixed;
                return None;
            }
            w.remaining = w.remaining.saturating_sub(1);
            *band = if w.up {
                band.saturating_add(1)
            } else {
                band.saturating_sub(1)
            };
            let t = w.t.max(*t_own);
            *t_own = t;
            return Some((t, *band));
        }
        for _ in 0..2 {
            // the cone to cross and the side to enter
            let (cone_j, want) = if *up {
                (
                    if *band < axis.len { Some(*band) } else { None },
                    Side::Positive,
                )
            } else {
                (band.checked_sub(1), Side::Negative)
            };
            let mut found: Option<(T, Option<(T, Side)>)> = None;
            if let Some(j) = cone_j {
                match *cache {
                    Some((k, t, s)) if k == j && s == want && t >= *t_own => {
                        found = Some((t, None))
                    }
                    _ => {
                        if let Some(cone) = axis.cone(j) {
                            let cs = cone.crossings(ray);
                            let mut it = cs.iter();
                            for c in it.by_ref() {
                                if c.into == want && c.t >= *t_own {
                                    found = Some((c.t, None));
                                    break;
                                }
                            }
                            if let (Some(f), Some(next)) = (found.as_mut(), it.next()) {
                                f.1 = Some((next.t, next.into));
                            }
                        }
                    }
                }
                if let (Some((t, other)), Some(j)) = (found, cone_j) {
                    if t > t_max {
                        *self = Stream::Fixed;
                        return None;
                    }
                    *cache = other.map(|(t2, s2)| (j, t2, s2));
                    *band = if *up { j.saturating_add(1) } else { j };
                    *t_own = t;
                    return Some((t, *band));
                }
            }
            if *switched {
                break;
            }
            *switched = true;
            *up = !*up;
        }
        *self = Stream::Fixed;
        None
    }

    /// The next azimuth event (one division), or `None`.
    pub(crate) fn next_azimuth(
        &mut self,
        axis: &AzimuthAxis<'_, T>,
        ray: &Ray<T>,
    ) -> Option<Event<T>> {
        let Stream::Azimuth {
            sector,
            t_own,
            ccw,
            walk,
        } = self
        else {
            return None;
        };
        let nb = axis.boundaries.max(1);
        let t_max = ray.t_max();
        let step = |s: u32, ccw: bool| -> u32 {
            if ccw {
                cyc(s.wrapping_add(1), nb)
            } else {
                cyc(s.wrapping_add(nb).wrapping_sub(1), nb)
            }
        };
        if let Some(w) = walk {
            if w.remaining == 0 || w.t > t_max {
                *self = Stream::Fixed;
                return None;
            }
            w.remaining = w.remaining.saturating_sub(1);
            *sector = step(*sector, w.up);
            let t = w.t.max(*t_own);
            *t_own = t;
            return Some((t, *sector));
        }
        let j = if *ccw { step(*sector, true) } else { *sector };
        let root = axis.plane(j).and_then(|h| h.scaled_root(ray));
        match root {
            Some((s, _)) => {
                let t = ray.t_from_scaled(s).max(*t_own);
                if t > t_max || t.is_nan() {
                    *self = Stream::Fixed;
                    return None;
                }
                *sector = step(*sector, *ccw);
                *t_own = t;
                Some((t, *sector))
            }
            None => {
                *self = Stream::Fixed;
                None
            }
        }
    }

    /// The next height event (one division), or `None`.
    pub(crate) fn next_height(
        &mut self,
        axis: &HeightAxis<'_, T>,
        ray: &Ray<T>,
    ) -> Option<Event<T>> {
        let Stream::Height { band, t_own, up } = self else {
            return None;
        };
        let j = if *up {
            if *band >= axis.len { None } else { Some(*band) }
        } else {
            band.checked_sub(1)
        };
        let root = j.and_then(|j| {
            let z = *axis.z.get(j as usize)?;
            PlaneZ::new(z).ok()?.scaled_root(ray)
        });
        match (j, root) {
            (Some(j), Some((s, _))) => {
                let t = ray.t_from_scaled(s).max(*t_own);
                if t > ray.t_max() || t.is_nan() {
                    *self = Stream::Fixed;
                    return None;
                }
                *band = if *up { j.saturating_add(1) } else { j };
                *t_own = t;
                Some((t, *band))
            }
            _ => {
                *self = Stream::Fixed;
                None
            }
        }
    }
}
