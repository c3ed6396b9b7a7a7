//! Ray ∩ plane `z = c`: the z facets of the cylindrical grid (Hannasch §3.3) and any horizontal plane.
//!
//! `t = (c − p_z) / d_z`: one subtraction and one division, so the computed point is within `ε(|c| + |p_z|)` of
//! the plane in z (backward error ≤ 2ε·S), and the crossing side is the sign of `d_z`.

use super::crossing::{Crossings, Side, Surface, SurfaceError, side_of_sign};
use crate::ray::{Line, Ray};
use crate::real::Real;
use crate::vec3::V3;

/// The plane `z = c`; its positive side is `z > c`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneZ<T> {
    z: T,
}

impl<T: Real> PlaneZ<T> {
    /// The plane `z = c`.
    pub fn new(c: T) -> Result<Self, SurfaceError> {
        if !c.is_finite() {
            return Err(SurfaceError::NonFinite);
        }
        Ok(PlaneZ { z: c })
    }
    /// Its height.
    #[inline]
    pub fn z(&self) -> T {
        self.z
    }
    /// The crossing in the ray's scaled parameter, or `None` for a horizontal ray.
    #[inline]
    pub(crate) fn scaled_root(&self, ray: &Line<T>) -> Option<(T, Side)> {
        self.scaled_root_fraction(ray)
            .map(|(num, den, side)| (num / den, side))
    }

    /// The crossing in the ray's scaled parameter as the fraction `num / den` with `den > 0`, not yet divided
    /// (the marcher divides it itself, folding in the ray's exact rescaling); `num / den` is bit for bit
    /// [`PlaneZ::scaled_root`]'s value. `None` for a horizontal ray (or a NaN direction component).
    #[inline]
    pub(crate) fn scaled_root_fraction(&self, ray: &Line<T>) -> Option<(T, T, Side)> {
        let dz = ray.scaled_dir().z;
        let num = self.z - ray.origin().z;
        if dz > T::ZERO {
            Some((num, dz, Side::Positive))
        } else if dz < T::ZERO {
            Some((-num, -dz, Side::Negative))
        } else {
            None
        }
    }
}

impl<T: Real> Surface<T> for PlaneZ<T> {
    fn crossings(&self, ray: &Ray<T>) -> Crossings<T> {
        match self.scaled_root(ray.line()) {
            Some(root) => Crossings::from_scaled_roots(ray, &[root]),
            None => Crossings::NONE,
        }
    }
    fn side_of(&self, point: V3<T>) -> Option<Side> {
        side_of_sign(point.z - self.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_up_and_down() {
        let p = PlaneZ::new(1.0).unwrap();
        let up = Ray::new([0.0, 0.0, 0.0], [0.0, 3.0, 4.0]).unwrap();
        let c = p.crossings(&up);
        assert_eq!((c[0].t, c[0].into), (0.25, Side::Positive));
        let down = Ray::new([5.0, 0.0, 3.0], [0.0, 0.0, -1.0]).unwrap();
        assert_eq!(p.crossings(&down)[0].into, Side::Negative);
        let flat = Ray::new([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]).unwrap();
        assert!(p.crossings(&flat).is_empty());
    }

    #[test]
    fn ray_starting_on_plane_is_at_t0() {
        let p = PlaneZ::new(2.0).unwrap();
        let r = Ray::new([1.0, 1.0, 2.0], [0.0, 0.0, -1.0]).unwrap();
        assert_eq!(p.crossings(&r)[0].t, 0.0);
    }

    #[test]
    fn height_and_a_crossing_whose_direction_is_not_a_power_of_two() {
        let p = PlaneZ::new(3.0).unwrap();
        assert_eq!(p.z(), 3.0);
        // dz = 3 is rescaled to 1.5, not 1: the root must divide by it.
        let r = Ray::new([0.0, 0.0, 0.0], [0.0, 0.0, 3.0]).unwrap();
        let c = p.crossings(&r);
        assert_eq!((c.len(), c[0].t), (1, 1.0));
    }

    #[test]
    fn a_horizontal_ray_has_no_root_and_points_lie_above_below_or_on_the_plane() {
        let p = PlaneZ::new(1.0).unwrap();
        let flat = Ray::new([0.0, 0.0, 0.5], [1.0, 2.0, 0.0]).unwrap();
        assert_eq!(p.scaled_root_fraction(flat.line()), None);
        assert!(p.crossings(&flat).is_empty());
        assert_eq!(p.side_of(V3::new(0.0, 0.0, 2.0)), Some(Side::Positive));
        assert_eq!(p.side_of(V3::new(0.0, 0.0, 0.0)), Some(Side::Negative));
        assert_eq!(p.side_of(V3::new(5.0, -3.0, 1.0)), None);
    }
}
