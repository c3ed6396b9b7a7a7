//! The azimuth stream (Hannasch Lemma 6: φ is monotone along a line): the next boundary half-plane in the
//! turning sense, and the jump of φ across the z axis as a walk.

use super::state::{
    Kind, Stream, cyc, cyclic_step, later, plane_t, point_at, rounding_level, sqrt_epsilon,
};
use crate::march::axes::AzimuthAxis;
use crate::ray::Line;
use crate::real::Real;

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

impl<T: Real> Stream<T> {
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
}

#[cfg(test)]
mod tests {
    //! `complete_azimuth` called directly: no march is known to reach its walk (the half-plane tests order the
    //! crossings of every line found so far), so its contract is checked on streams set up as a march would leave
    //! them, stopped in a sector other than the direction's with no boundary ahead.
    use super::*;
    use crate::ray::Ray;
    use core::f64::consts::{FRAC_PI_2, PI, TAU};
    use std::vec::Vec;

    /// Four sectors, a quarter turn each.
    const QUARTERS: [f64; 5] = [0.0, FRAC_PI_2, PI, 3.0 * FRAC_PI_2, TAU];
    /// Five sectors, with boundaries whose cosine and sine are both far from 0 and of either sign.
    const SKEWED: [f64; 6] = [0.0, 1.0, 2.0, 3.0, 4.5, TAU];

    /// Completes the stream of the line `origin + t dir` stopped in sector `band`, turning counter-clockwise or
    /// not, in a grid of outer radius 1, and walks it to its end with no `t_max`: what it returns, then each event
    /// `(t, sector)`.
    fn completion(
        phi: &[f64],
        origin: [f64; 3],
        dir: [f64; 3],
        band: u32,
        ccw: bool,
    ) -> (bool, Vec<(f64, u32)>) {
        let mut ws = [0.0; 16];
        let mut ws = &mut ws[..];
        let mut axis = AzimuthAxis::build(phi, &mut ws).unwrap();
        axis.scale = 1.0;
        let ray = Ray::new(origin, dir).unwrap();
        let mut stream = Stream {
            band,
            t: 0.0,
            kind: Kind::Azimuth {
                ccw,
                from: (1.0, 0.0),
                crossed: axis.boundaries,
            },
        };
        let walks = stream.complete_azimuth(&axis, ray.line(), f64::INFINITY);
        let mut events = Vec::new();
        let mut more = walks;
        while more {
            events.push((stream.t, stream.band));
            more = stream.next_walk(axis.boundaries, f64::INFINITY);
        }
        assert_eq!(stream.kind, Kind::Fixed);
        (walks, events)
    }

    /// The line from (−3, −1.5 + e, 0.25) along (1.5, 0.75, 0.1) passes the z axis at a distance 1.5e/|d_xy|:
    /// `(p × d)_z = −1.5e`. Near enough for the completion when `|(p × d)_z| ≤ 64 √ε · 3 · 1.5` (the origin's and
    /// the direction's largest horizontal components); returns `e` at `k` times that bound.
    fn offset_at(k: f64) -> f64 {
        k * 64.0 * sqrt_epsilon::<f64>() * 3.0 * 1.5 / 1.5
    }

    /// The closest approach of that line to the z axis: `t = −(p·d)/(d·d)` over x and y, written out.
    fn closest(e: f64) -> f64 {
        (3.0 * 1.5 + (1.5 - e) * 0.75) / (1.5 * 1.5 + 0.75 * 0.75)
    }

    #[test]
    fn line_passing_the_z_axis_within_the_completion_bound_walks_to_its_direction_in_the_turning_sense()
     {
        // From sector 2 (φ of −d, π + 0.46) to sector 0 (φ of d, 0.46): through sector 3 counter-clockwise,
        // through sector 1 clockwise, both at the closest approach to the axis.
        let e = offset_at(0.9);
        let o = [-3.0, -1.5 + e, 0.25];
        let d = [1.5, 0.75, 0.1];
        for (ccw, between) in [(true, 3), (false, 1)] {
            let (walks, ev) = completion(&QUARTERS, o, d, 2, ccw);
            assert!(walks, "ccw {ccw}");
            assert_eq!(ev.iter().map(|e| e.1).collect::<Vec<_>>(), [between, 0]);
            for (t, _) in ev {
                assert!(
                    (t - closest(e)).abs() <= 1e-14,
                    "{t} against {}",
                    closest(e)
                );
            }
        }
        // the same line, stopped in sector 1 turning clockwise: one step
        let (_, ev) = completion(&QUARTERS, o, d, 1, false);
        assert_eq!(ev.iter().map(|e| e.1).collect::<Vec<_>>(), [0]);
    }

    #[test]
    fn line_passing_the_z_axis_beyond_the_completion_bound_ends_where_its_half_plane_tests_left_it()
    {
        let (walks, ev) = completion(
            &QUARTERS,
            [-3.0, -1.5 + offset_at(1.1), 0.25],
            [1.5, 0.75, 0.1],
            2,
            true,
        );
        assert!(!walks);
        assert!(ev.is_empty());
        // and one within it already in its direction's sector: nothing to walk
        let (walks, ev) = completion(
            &QUARTERS,
            [-3.0, -1.5 + offset_at(0.5), 0.25],
            [1.5, 0.75, 0.1],
            0,
            true,
        );
        assert!(!walks);
        assert!(ev.is_empty());
    }

    /// The direction `k` times boundary `j`'s stored `(cos, sin)` of [`SKEWED`] (exactly on its line), from an
    /// origin 2 of it behind the axis and `2^-30` aside: completed from sector `band`.
    fn along_boundary(j: usize, k: f64, band: u32) -> (bool, Vec<(f64, u32)>) {
        let h = crate::surface::HalfPlane::from_azimuth_rad(SKEWED[j]).unwrap();
        let d = [k * h.cos(), k * h.sin(), 0.1];
        let o = [-2.0 * d[0], -2.0 * d[1] + libm::scalbn(1.0, -30), 0.25];
        completion(&SKEWED, o, d, band, true)
    }

    #[test]
    fn direction_exactly_on_a_boundary_line_ends_in_the_sector_it_approaches_without_a_walk() {
        // d along boundaries 3 (φ = 3: cos −0.99, sin 0.14), 4 (φ = 4.5: cos −0.21, sin −0.98) and 0 (φ = 0:
        // exactly (1, 0), so d has no y part), twice their (cos, sin); the stream stopped two sectors before: φ
        // tends to the boundary from one side, and the sector it ends in is the one the half-plane tests left (the
        // boundary itself is never crossed).
        for (j, band) in [(3, 1), (4, 2), (0, 3)] {
            let (walks, ev) = along_boundary(j, 2.0, band);
            assert!(!walks && ev.is_empty(), "boundary {j}: {ev:?}");
        }
    }

    #[test]
    fn direction_exactly_opposite_a_boundary_line_walks_to_its_sector() {
        // d = −2 (cos, sin) of boundary 1 (φ = 1): its direction is φ = 1 + π, in sector 3 ([3, 4.5)); from
        // sector 1, counter-clockwise through sector 2. (On the boundary's line, but not its half-plane.)
        let (walks, ev) = along_boundary(1, -2.0, 1);
        assert!(walks);
        assert_eq!(ev.iter().map(|e| e.1).collect::<Vec<_>>(), [2, 3]);
    }
}
