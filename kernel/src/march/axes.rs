//! The breakpoint tables of one grid axis, in the pseudospherical form of Hannasch §2 (r², (cos θ, sin θ),
//! (cos φ, sin φ)), with their validation and the location of a point ("which band is it in", §3.1.3).
//!
//! Zenith angles are kept as `(cos θ, sin θ)`, not as §2's `sgnSqrCos θ = cos θ |cos θ|`: within about 1e-8
//! (f64) of a pole `cos² θ` rounds to 1 and no longer tells the cones apart, while `sin² θ` keeps every digit.
//!
//! A *band* is the number of breakpoints at or below the coordinate: band `b` with `1 <= b <= L − 1` (L
//! breakpoints) is cell `b − 1`; band 0 is below the first breakpoint and band L at or above the last (both
//! outside the domain). For the azimuth the bands are *sectors* between consecutive boundary half-planes, taken
//! cyclically (see [`AzimuthAxis`]).

use super::error::{Axis, GridError};
use crate::real::Real;
use crate::surface::{AxialCone, HalfPlane};
use crate::vec3::V3;

/// The length of a slice as a `u32` band count, or an error when the axis is absurdly long.
pub(crate) fn len_u32(axis: Axis, len: usize) -> Result<u32, GridError> {
    u32::try_from(len)
        .ok()
        .filter(|&n| n < u32::MAX / 4)
        .ok_or(GridError::TooManyBreakpoints { axis, len })
}

/// Checks: at least two values, all finite, strictly increasing.
pub(crate) fn check_sorted<T: Real>(axis: Axis, v: &[T]) -> Result<u32, GridError> {
    let n = len_u32(axis, v.len())?;
    if v.len() < 2 {
        return Err(GridError::TooFewBreakpoints { axis, len: v.len() });
    }
    for (index, x) in v.iter().enumerate() {
        if !x.is_finite() {
            return Err(GridError::NonFinite { axis, index });
        }
    }
    for (index, w) in v.windows(2).enumerate() {
        if let [a, b] = w {
            if !(a < b) {
                return Err(GridError::NotIncreasing {
                    axis,
                    index: index.saturating_add(1),
                });
            }
        }
    }
    Ok(n)
}

/// Takes `n` values off the front of the workspace.
pub(crate) fn take<'a, T>(ws: &mut &'a mut [T], n: usize) -> Option<&'a mut [T]> {
    let rest = core::mem::take(ws);
    if n > rest.len() {
        return None;
    }
    let (head, tail) = rest.split_at_mut(n);
    *ws = tail;
    Some(head)
}

/// The `(cos, sin)` pairs of an angular axis's breakpoints, interleaved in one slice (`cos_j` at `2j`, `sin_j`
/// at `2j + 1`), so that reading a pair costs one bounds check.
#[derive(Debug, Clone, Copy)]
pub(crate) struct UnitPairs<'a, T>(&'a [T]);

impl<'a, T: Real> UnitPairs<'a, T> {
    /// Takes `2n` values off the workspace and fills them with `pair(j)` for `j < n`; the first error of
    /// `pair` is returned.
    fn build<E>(
        ws: &mut &'a mut [T],
        n: usize,
        mut pair: impl FnMut(usize) -> Result<(T, T), E>,
        too_small: E,
    ) -> Result<Self, E> {
        let Some(out) = take(ws, n.saturating_mul(2)) else {
            return Err(too_small);
        };
        for (j, slot) in out.chunks_exact_mut(2).enumerate() {
            if let [c, s] = slot {
                (*c, *s) = pair(j)?;
            }
        }
        Ok(UnitPairs(out))
    }

    /// Pair `j`.
    #[inline(always)]
    pub(crate) fn get(&self, j: usize) -> Option<(T, T)> {
        let k = j.wrapping_mul(2);
        match self.0.get(k..k.wrapping_add(2)) {
            Some(&[c, s]) => Some((c, s)),
            _ => None,
        }
    }

    /// The number of pairs.
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.0.len() / 2
    }
}

/// The number of breakpoints `<= x` in a sorted slice (binary search, no arithmetic on `T`).
#[inline]
fn count_le<T: Real>(v: &[T], x: T) -> u32 {
    u32::try_from(v.partition_point(|&b| b <= x)).unwrap_or(u32::MAX)
}

/// The end of the prefix of `lo..hi` on which `holds` is true (it is true on a prefix), by bisection.
#[inline(always)]
fn bisect(mut lo: usize, mut hi: usize, mut holds: impl FnMut(usize) -> bool) -> usize {
    while lo < hi {
        let mid = lo.wrapping_add(hi.wrapping_sub(lo) / 2);
        if holds(mid) {
            lo = mid.wrapping_add(1);
        } else {
            hi = mid;
        }
    }
    lo
}

/// `q` times the power of two that brings its largest component into `[1, 2)`: directions are located by signs
/// of products, which must not underflow for tiny or overflow for huge coordinates. Exact, except that scaling
/// down rounds a component far below the largest (a subnormal beside one of 2, say) to fewer bits; one that would
/// round to zero is kept as the smallest subnormal of its sign instead, so that no component changes its sign or
/// becomes zero. (The side tests are then those of the exact point: a component rounded away would have put a
/// point on a boundary plane that the crossing solvers, which take the coordinates unscaled, see it off.) Out of
/// line in a build for size: it runs when a ray is located, not per crossing, and inlined into each of its
/// callers it took 2 KB of a Cortex-M4F march firmware's code at opt "s".
#[cfg_attr(curvicast_small_code, inline(never))]
#[cfg_attr(not(curvicast_small_code), inline)]
pub(crate) fn unit_scaled<T: Real>(q: V3<T>) -> V3<T> {
    let m = q.max_abs();
    let scaled = if let Some((_, inv)) = m.binade() {
        q.scaled(inv) // each product is what `scalbn` gives
    } else if m == T::ZERO || !m.is_finite() {
        return q;
    } else {
        q.scalbn(m.ilogb().saturating_neg())
    };
    // 2^-1074 in f64, 2^-149 in f32: the products are exact
    let tiny = T::MIN_POSITIVE * T::EPSILON;
    let keep = |s: T, x: T| {
        if s == T::ZERO && x != T::ZERO {
            tiny.with_sign_of(x)
        } else {
            s
        }
    };
    V3::new(
        keep(scaled.x, q.x),
        keep(scaled.y, q.y),
        keep(scaled.z, q.z),
    )
}

/// Radius breakpoints (`r` of a sphere grid, `ρ` of a cylinder grid, `r` of a polar grid) with their squares.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RadialAxis<'a, T> {
    /// `r²`, the pseudospherical form (Hannasch §2, §4.1).
    pub r2: &'a [T],
    /// Number of breakpoints.
    pub len: u32,
}

impl<'a, T: Real> RadialAxis<'a, T> {
    pub(crate) fn build(axis: Axis, r: &'a [T], ws: &mut &'a mut [T]) -> Result<Self, GridError> {
        let len = check_sorted(axis, r)?;
        if let Some(&r0) = r.first() {
            if r0 < T::ZERO {
                return Err(GridError::OutOfRange { axis, index: 0 });
            }
        }
        let out = take(ws, r.len()).ok_or(GridError::WorkspaceTooSmall)?;
        for (index, (o, &x)) in out.iter_mut().zip(r).enumerate() {
            *o = x * x;
            if !o.is_finite() {
                return Err(GridError::OutOfRange { axis, index });
            }
        }
        Ok(RadialAxis { r2: out, len })
    }

    /// The band of a point at squared distance `r2` from the center.
    #[inline]
    pub(crate) fn band_of_r2(&self, r2: T) -> u32 {
        count_le(self.r2, r2)
    }
}

/// Zenith breakpoints θ ∈ [0, π] with the `(cos θ, sin θ)` pair of each cone.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ZenithAxis<'a, T> {
    pub theta: &'a [T],
    /// `(cos θ_j, sin θ_j)`.
    pub dirs: UnitPairs<'a, T>,
    pub len: u32,
    /// The grid's outer radius: the length scale below which a line counts as passing through the center.
    pub scale: T,
}

impl<'a, T: Real> ZenithAxis<'a, T> {
    pub(crate) fn build(theta: &'a [T], ws: &mut &'a mut [T]) -> Result<Self, GridError> {
        let axis = Axis::Theta;
        let len = check_sorted(axis, theta)?;
        let dirs = UnitPairs::build(
            ws,
            theta.len(),
            |index| {
                // π/2 and π give exact (0, 1) and (−1, 0): θ = π/2 is exactly the plane z = 0.
                let th = theta.get(index).copied().unwrap_or(T::ZERO);
                let cone = AxialCone::from_zenith_rad(T::ZERO, th)
                    .map_err(|_| GridError::OutOfRange { axis, index })?;
                Ok((cone.cos(), cone.sin()))
            },
            GridError::WorkspaceTooSmall,
        )?;
        Ok(ZenithAxis {
            theta,
            dirs,
            len,
            scale: T::ZERO,
        })
    }

    /// The cone of breakpoint `j` (no validation, no square root: the pair was validated at construction).
    #[inline]
    pub(crate) fn cone(&self, j: u32) -> Option<AxialCone<T>> {
        let (c, s) = self.dirs.get(j as usize)?;
        Some(AxialCone::from_validated_unit_parts(c, s))
    }

    /// The band of the direction of `q` (from the center), `q ≠ 0`: the number of breakpoints with
    /// `θ_j <= θ(q)`. With `ρ² = q_x² + q_y²` that is `q_z <= 0 or cos²θ_j ρ² >= sin²θ_j q_z²` for θ_j < π/2,
    /// `q_z <= 0` for θ_j = π/2 and `q_z < 0 and cos²θ_j ρ² <= sin²θ_j q_z²` for θ_j > π/2 (no division, no
    /// square root). This is the form of the cone's own equation ([`AxialCone`]), well conditioned at both poles;
    /// the two are evaluated separately and agree up to rounding, not bit for bit.
    ///
    /// `leave_axis`: the ray leaves the −z axis (its direction has a horizontal part), so a point on that axis
    /// (`ρ²` zero or underflowed) gets the band just below θ = π (the right limit along the ray), not that of
    /// θ = π itself.
    // Out of line in a build for size: it runs when a ray is located or repaired, and the zenith stream's set-up
    // asks it up to three times (on a Cortex-M4F, inlined there it took 1.3 KB more code at opt "s"; at opt 3
    // out of line cost 2 instructions per crossing).
    #[cfg_attr(curvicast_small_code, inline(never))]
    #[cfg_attr(not(curvicast_small_code), inline)]
    pub(crate) fn band_of(&self, q: V3<T>, leave_axis: bool) -> u32 {
        let q = unit_scaled(q);
        let rho2 = q.x * q.x + q.y * q.y;
        let z2 = q.z * q.z;
        if leave_axis && q.z < T::ZERO && rho2 == T::ZERO {
            return u32::try_from(self.theta.partition_point(|&t| t < T::PI)).unwrap_or(u32::MAX);
        }
        let (up, down) = (q.z > T::ZERO, q.z < T::ZERO);
        // θ_j <= θ(q) holds for a prefix of the breakpoints
        let band = bisect(0, self.dirs.len(), |j| {
            let Some((c, s)) = self.dirs.get(j) else {
                return false;
            };
            // θ = π/2 by the sign of z itself: z² may underflow where z does not
            if c > T::ZERO {
                !up || c * c * rho2 >= s * s * z2
            } else if c < T::ZERO {
                down && c * c * rho2 <= s * s * z2
            } else {
                !up
            }
        });
        u32::try_from(band).unwrap_or(u32::MAX)
    }

    /// Whether the direction `d` lies on cone `k` within the rounding of its equation (`d` parallel to a
    /// generator, as far as the arithmetic can tell, by the cone solver's own test
    /// [`AxialCone::leading_coefficient`]) on the cone's own nappe.
    pub(crate) fn along_cone(&self, k: u32, d: V3<T>) -> bool {
        let Some(cone) = self.cone(k) else {
            return false;
        };
        let d = unit_scaled(d);
        let c = cone.cos();
        let nappe = c == T::ZERO || (d.z > T::ZERO) == (c > T::ZERO);
        nappe && !cone.leading_coefficient(d).1
    }
}

/// Azimuth breakpoints as the boundary half-planes `(cos φ_j, sin φ_j)`, taken cyclically.
///
/// With `m + 1` breakpoints, the domain has `m` sectors. When the breakpoints span a full turn (2π) the last
/// boundary is the first one again, there are `nb = m` boundaries and every sector is inside; otherwise there are
/// `nb = m + 1` boundaries and sector `m` (from `φ_m` round to `φ_0 + 2π`) is the outside of the wedge. A wedge
/// wider than π is the union of two half-spaces (Hannasch §3.1.3); the sector logic here never needs to say so.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AzimuthAxis<'a, T> {
    /// `(cos φ_j, sin φ_j)`.
    dirs: UnitPairs<'a, T>,
    /// Number of sectors inside the domain (`m`).
    pub sectors: u32,
    /// Number of boundary half-planes (`m` for a full turn, `m + 1` for a wedge).
    pub boundaries: u32,
    pub full: bool,
    /// The grid's outer radius: the length scale below which a line counts as meeting the z axis.
    pub scale: T,
    /// The boundaries at π or more counter-clockwise from boundary 0 ([`AzimuthAxis::lower_half_excluded`]) as
    /// an index range: they are `half_from..boundaries` (computed once; `u32::MAX` in the unlikely case that
    /// rounding makes them no such suffix, and then the search tests each boundary it visits).
    half_from: u32,
}

impl<'a, T: Real> AzimuthAxis<'a, T> {
    pub(crate) fn build(phi: &'a [T], ws: &mut &'a mut [T]) -> Result<Self, GridError> {
        let axis = Axis::Phi;
        let len = check_sorted(axis, phi)?;
        let n = phi.len();
        let (first, last) = match (phi.first(), phi.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => return Err(GridError::TooFewBreakpoints { axis, len: n }),
        };
        let two_pi = T::PI + T::PI;
        let tol = two_pi * T::EPSILON * T::from_f64(8.0);
        let span = last - first;
        if !span.is_finite() || span > two_pi + tol {
            return Err(GridError::OutOfRange {
                axis,
                index: n.saturating_sub(1),
            });
        }
        let full = span >= two_pi - tol;
        let dirs = UnitPairs::build(
            ws,
            n,
            |index| {
                let p = phi.get(index).copied().unwrap_or(T::ZERO);
                let h = HalfPlane::from_azimuth_rad(p)
                    .map_err(|_| GridError::NonFinite { axis, index })?;
                Ok((h.cos(), h.sin()))
            },
            GridError::WorkspaceTooSmall,
        )?;
        let sectors = len.saturating_sub(1);
        let mut axis = AzimuthAxis {
            dirs,
            sectors,
            boundaries: if full { sectors } else { len },
            full,
            scale: T::ZERO,
            half_from: u32::MAX,
        };
        axis.half_from = axis.half_suffix();
        Ok(axis)
    }

    /// The first boundary (from 1) that is at π or more counter-clockwise from boundary 0, when all the
    /// boundaries after it are as well and none before it is (the boundaries are sorted counter-clockwise, so
    /// this holds unless rounding decides two boundaries within rounding of φ_0 + π the other way round);
    /// otherwise `u32::MAX`.
    fn half_suffix(&self) -> u32 {
        let mut first = None;
        for j in 1..self.boundaries {
            let (c, s) = self.dir_of(j);
            match (self.lower_half_excluded(c, s), first) {
                (true, None) => first = Some(j),
                (false, Some(_)) => return u32::MAX,
                _ => {}
            }
        }
        first.unwrap_or(self.boundaries)
    }

    /// The boundary half-plane `j` (cyclic index below `boundaries`).
    #[inline]
    pub(crate) fn plane(&self, j: u32) -> HalfPlane<T> {
        let (c, s) = self.dir(j as usize);
        HalfPlane::from_validated_unit_parts(c, s)
    }

    /// `(cos, sin)` of the boundary `j` (cyclic index below `boundaries`).
    #[inline]
    pub(crate) fn dir_of(&self, j: u32) -> (T, T) {
        self.dir(j as usize)
    }

    /// The same axis with the half-turn split of [`AzimuthAxis::sector_of`] switched off (each boundary that the
    /// search visits is tested instead), to check that the two agree.
    #[cfg(test)]
    pub(crate) fn without_half_split(mut self) -> Self {
        self.half_from = u32::MAX;
        self
    }

    /// `(cos, sin)` of boundary `j`.
    #[inline]
    fn dir(&self, j: usize) -> (T, T) {
        self.dirs.get(j).unwrap_or((T::ONE, T::ZERO))
    }

    /// Is the direction `(x, y)` at an angle of π or more counter-clockwise from boundary 0? The same sign test
    /// decides it for points and for boundaries, so the two are ordered consistently even where the test is
    /// ill-conditioned (directions within rounding of φ_0 + π).
    #[inline]
    fn lower_half_excluded(&self, x: T, y: T) -> bool {
        let (c0, s0) = self.dir(0);
        let cr0 = c0 * y - s0 * x;
        cr0 < T::ZERO || (cr0 == T::ZERO && c0 * x + s0 * y < T::ZERO)
    }

    /// The sector of the horizontal direction `(x, y)`; the zero vector counts as φ = 0 (the `atan2(0, 0)`
    /// convention for points on the z axis). Sign tests only (no division, no trigonometry).
    pub(crate) fn sector_of(&self, x: T, y: T) -> u32 {
        let (x, y) = if x == T::ZERO && y == T::ZERO {
            (T::ONE, T::ZERO)
        } else {
            let v = unit_scaled(V3::new(x, y, T::ZERO));
            (v.x, v.y)
        };
        let half_v = self.lower_half_excluded(x, y);
        let split = self.half_from as usize;
        // v is at or after boundary j (counter-clockwise from boundary 0): true for a prefix of the boundaries
        let at_or_after = |j: usize| -> bool {
            let Some((c, s)) = self.dirs.get(j) else {
                return false;
            };
            let hj = if self.half_from == u32::MAX {
                j != 0 && self.lower_half_excluded(c, s)
            } else {
                j >= split
            };
            if hj != half_v {
                return half_v;
            }
            c * y - s * x >= T::ZERO
        };
        // the first boundary that v is not at or after, less one
        let after = bisect(1, self.boundaries as usize, at_or_after);
        u32::try_from(after.wrapping_sub(1)).unwrap_or(0)
    }
}

/// Plain breakpoints of the cylinder's z axis (planes `z = z_m`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct HeightAxis<'a, T> {
    pub z: &'a [T],
    pub len: u32,
}

impl<'a, T: Real> HeightAxis<'a, T> {
    pub(crate) fn build(z: &'a [T]) -> Result<Self, GridError> {
        let len = check_sorted(Axis::Z, z)?;
        Ok(HeightAxis { z, len })
    }
    #[inline]
    pub(crate) fn band_of(&self, z: T) -> u32 {
        count_le(self.z, z)
    }
}
