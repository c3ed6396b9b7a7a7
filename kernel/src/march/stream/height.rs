//! The height stream of a cylindrical grid (Hannasch §3.3): z is monotone along a line, one division per
//! plane crossed.

use super::state::{Kind, Stream, later, plane_t, point_at};
use crate::march::axes::HeightAxis;
use crate::ray::Line;
use crate::real::Real;
use crate::surface::PlaneZ;

impl<T: Real> Stream<T> {
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
