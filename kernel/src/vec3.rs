//! A minimal 3-vector generic over [`Real`], used inside the kernel.
//!
//! Its operations are named methods rather than operator overloads, so that the kernel's lint against
//! arithmetic side effects stays meaningful for everything that is not a float.
//!
//! `glam` vectors are the API boundary (`DVec3`, `Vec3` convert into `[f64; 3]` / `[f32; 3]`, which convert into
//! [`V3`]); `glam` has no vector generic over the scalar, so the kernel keeps this small one for its generic code.

use crate::real::Real;

/// A 3-vector of [`Real`]s, laid out as C's `T[3]` (`repr(C)`: the C interface writes arrays of them).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct V3<T> {
    /// x.
    pub x: T,
    /// y.
    pub y: T,
    /// z.
    pub z: T,
}

impl<T: Real> V3<T> {
    /// The vector (x, y, z).
    #[inline]
    pub const fn new(x: T, y: T, z: T) -> Self {
        V3 { x, y, z }
    }
    /// The zero vector.
    pub const ZERO: Self = V3 {
        x: T::ZERO,
        y: T::ZERO,
        z: T::ZERO,
    };
    /// Dot product.
    #[inline]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Cross product; each component is a difference of two products, accurate relative to `|self|·|o|`.
    #[inline]
    pub fn cross(self, o: Self) -> Self {
        V3 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }
    /// Squared length.
    #[inline]
    pub fn length_squared(self) -> T {
        self.dot(self)
    }
    /// Length (one square root).
    #[inline]
    pub fn length(self) -> T {
        self.length_squared().sqrt()
    }
    /// The largest absolute component.
    #[cfg_attr(curvicast_small_code, inline(never))]
    #[cfg_attr(not(curvicast_small_code), inline)]
    pub fn max_abs(self) -> T {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }
    /// True when every component is finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
    /// Each component times `2^k` (exact unless it overflows or becomes subnormal).
    #[inline]
    pub fn scalbn(self, k: i32) -> Self {
        V3 {
            x: self.x.scalbn(k),
            y: self.y.scalbn(k),
            z: self.z.scalbn(k),
        }
    }
    /// The components as an array.
    #[inline]
    pub fn to_array(self) -> [T; 3] {
        [self.x, self.y, self.z]
    }
    /// `self + o`.
    #[inline]
    pub fn plus(self, o: Self) -> Self {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
    /// `self − o`.
    #[inline]
    pub fn minus(self, o: Self) -> Self {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
    /// `−self`.
    #[inline]
    pub fn negated(self) -> Self {
        V3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
    /// `s · self`.
    #[inline]
    pub fn scaled(self, s: T) -> Self {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
    /// `self + t * d`.
    #[inline]
    pub fn add_scaled(self, t: T, d: Self) -> Self {
        V3 {
            x: self.x + t * d.x,
            y: self.y + t * d.y,
            z: self.z + t * d.z,
        }
    }
}

impl<T: Real> From<[T; 3]> for V3<T> {
    #[inline]
    fn from([x, y, z]: [T; 3]) -> Self {
        V3 { x, y, z }
    }
}

impl<T: Real> From<V3<T>> for [T; 3] {
    #[inline]
    fn from(v: V3<T>) -> Self {
        v.to_array()
    }
}

impl From<glam::DVec3> for V3<f64> {
    #[inline]
    fn from(v: glam::DVec3) -> Self {
        V3 {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

impl From<glam::Vec3> for V3<f32> {
    #[inline]
    fn from(v: glam::Vec3) -> Self {
        V3 {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::V3;

    #[test]
    fn cross_and_dot() {
        let a = V3::new(1.0, 2.0, 3.0);
        let b = V3::new(-2.0, 0.5, 4.0);
        let c = a.cross(b);
        assert_eq!(c, V3::new(6.5, -10.0, 4.5));
        assert_eq!(c.dot(a), 0.0);
        assert_eq!(c.dot(b), 0.0);
        assert_eq!(a.length_squared(), 14.0);
        assert_eq!(V3::new(3.0, -4.0, 0.0).length(), 5.0);
    }
}
