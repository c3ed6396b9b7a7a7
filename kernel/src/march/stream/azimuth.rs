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
