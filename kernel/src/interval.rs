//! Parameter intervals along a ray: clipping `[lo, hi]` by a half-space (the geodesy bounds' walls, the terrain
//! leaf cells' walls).

use crate::real::Real;

/// Clips `[lo, hi]` to `{t : s0 + t·sd ≥ −tol}` (a half-space along the ray; also the leaf cells' walls).
#[inline]
pub(crate) fn clip_half_space<T: Real>(lo: &mut T, hi: &mut T, s0: T, sd: T, tol: T) {
    let s0 = s0 + tol;
    if sd == T::ZERO {
        if s0 < T::ZERO {
            *hi = T::NEG_INFINITY;
        }
        return;
    }
    let t = -s0 / sd;
    if sd > T::ZERO {
        *lo = lo.max(t);
    } else {
        *hi = hi.min(t);
    }
}
