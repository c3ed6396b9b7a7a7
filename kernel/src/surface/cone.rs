//! Ray ∩ axial cone: the points whose zenith angle, seen from an apex `(0, 0, k)` on the z axis, is θ.
//!
//! With `k = 0` this is Hannasch's zenith cone (Hannasch §4.4, Lemma 10; §4.5 notes that a single nappe is what a
//! grid needs). With `θ = π/2 − ψ` and `k = −N(ψ) e² sin ψ` it is Wartell's latitude cone `z = m r + k` of Wartell et al.
//! §3.4 (eq. 3.4-1: `m = tan ψ`, `k = Z_ψ − X_ψ m`), the locus of the spheroid normals at geodetic latitude ψ.
//! Only the cone's own nappe counts: `z > k` for θ < π/2, `z < k` for θ > π/2; θ = π/2 is the plane `z = k`.
//!
//! Writing `q = p − (0, 0, k)`, `c = cos θ`, `s = sin θ`, the double cone is `Q = c²(x² + y²) − s² z² = 0`, so
//!
//! ```text
//! A s² + 2 B s + C = 0,   A = c²(d_x² + d_y²) − s² d_z²,  B = c²(q_x d_x + q_y d_y) − s² q_z d_z,
//!                         C = c²(q_x² + q_y²) − s² q_z²,
//! B² − A C = c² (s² (w_x² + w_y²) − c² w_z²),   w = q × d.
//! ```
//!
//! The last identity (derived again here; Lemma 10 writes it as `‖p_z d − d_z p‖² − cos²θ (‖p‖²‖d‖² − ⟨p|d⟩²)`) is
//! what keeps the discriminant free of cancellation: `w_x, w_y` are the components of `p_z d − d_z p`, and
//! `w_z² + w_x² + w_y² = |q × d|²` replaces `‖p‖²‖d‖² − ⟨p|d⟩²`. The roots come from the stable formula; when the
//! ray is parallel to a generator (`A = 0`), the same formula gives the single linear root `−C / 2B` without a
//! special case. The side is decided from `Q`'s slope at the root and the nappe from the sign of `z − k` there.
//!
//! **Error bound** (S = max(|q|, |q + t d|)): `c², s²` are within 2ε of the true values (computed from θ, not as
//! `1 − c²`); `A, B, C` and the discriminant are sums of a few products with relative errors of a few ε of their
//! largest term `|q|²`. That alone would leave the point `ε|q|² / |∇Q|` off the cone, unbounded as the crossing
//! nears the apex (where `|∇Q| → 0`), so each simple root gets one Newton step on `Q` evaluated at the crossing
//! point; after it the computed point lies within a few `ε·S` of the cone (backward error; the host oracle
//! measures below `1 ε·S` in f64 over 100 000 random rays). Forward error along the ray is that divided by the
//! sine of the crossing angle: it grows only near tangency, where the problem itself is ill-conditioned.

use super::crossing::{Crossings, Side, Surface, SurfaceError, side_of_sign, stable_quadratic};
use crate::ray::{Line, Ray};
use crate::real::Real;
use crate::vec3::V3;

/// A single-nappe cone of zenith angle θ around the z axis with its apex at `(0, 0, apex_z)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxialCone<T> {
    apex_z: T,
    cos: T,
    sin: T,
    cos2: T,
    sin2: T,
}

impl<T: Real> AxialCone<T> {
    /// The cone of zenith angle `theta` ∈ [0, π] (radians) with apex `(0, 0, apex_z)`.
    ///
    /// `theta` within `8ε` of π/2 (`T::FRAC_PI_2` and its neighbours) gives exactly the plane `z = apex_z`: its
    /// cosine is taken as 0, not as a rounding residue like `6e-17`. Such a cone differs from the plane by less
    /// than `8ε·ρ`, below the solvers' own backward error, and as a nearly flat cone its nappe could not be told
    /// apart from rounding (the `march` fuzz target found a wrong zenith band at θ = π/2 + 3 ulps).
    pub fn from_zenith_rad(apex_z: T, theta: T) -> Result<Self, SurfaceError> {
        if !theta.is_finite() || !apex_z.is_finite() {
            return Err(SurfaceError::NonFinite);
        }
        if !(theta >= T::ZERO && theta <= T::PI) {
            return Err(SurfaceError::AngleOutOfRange);
        }
        let (cos, sin) = if (theta - T::FRAC_PI_2).abs() <= T::from_f64(8.0) * T::EPSILON {
            (T::ZERO, T::ONE)
        } else if theta == T::PI {
            (-T::ONE, T::ZERO)
        } else {
            (theta.cos(), theta.sin())
        };
        Self::from_cos_sin(apex_z, cos, sin)
    }

    /// The cone whose zenith angle has cosine `cos` and sine `sin ≥ 0` (renormalised if `cos² + sin²` is not 1).
    pub fn from_cos_sin(apex_z: T, cos: T, sin: T) -> Result<Self, SurfaceError> {
        if !cos.is_finite() || !sin.is_finite() || !apex_z.is_finite() {
            return Err(SurfaceError::NonFinite);
        }
        let n2 = cos * cos + sin * sin;
        if sin < T::ZERO || !(n2 > T::ZERO) {
            return Err(SurfaceError::AngleOutOfRange);
        }
        let (cos, sin) = if n2 == T::ONE {
            (cos, sin)
        } else {
            let n = n2.sqrt();
            (cos / n, sin / n)
        };
        Ok(AxialCone {
            apex_z,
            cos,
            sin,
            cos2: cos * cos,
            sin2: sin * sin,
        })
    }

    /// The cone with apex at the origin from a `(cos θ, sin θ)` pair taken from a cone that was already built
    /// and validated (its [`AxialCone::cos`] and [`AxialCone::sin`]): no check and no renormalisation, so no square
    /// root and no division. The spherical marcher keeps its zenith breakpoints in this form (Hannasch §2) and
    /// rebuilds the cone it needs per crossing at the cost of two multiplications.
    #[inline]
    pub(crate) fn from_validated_unit_parts(cos: T, sin: T) -> Self {
        AxialCone {
            apex_z: T::ZERO,
            cos,
            sin,
            cos2: cos * cos,
            sin2: sin * sin,
        }
    }

    /// The height of the apex on the z axis.
    #[inline]
    pub fn apex_z(&self) -> T {
        self.apex_z
    }
    /// cos θ.
    #[inline]
    pub fn cos(&self) -> T {
        self.cos
    }
    /// sin θ.
    #[inline]
    pub fn sin(&self) -> T {
        self.sin
    }

    /// The leading coefficient `A = c²(d_x² + d_y²) − s² d_z²` of the crossing quadratic for the direction `d`
    /// (Hannasch §4.4), and whether it is clear of its own rounding, `|A| > 8ε (c²(d_x² + d_y²) + s² d_z²)`:
    /// when it is not, `d` is parallel to a generator of the double cone as far as the arithmetic can tell.
    #[inline]
    pub(crate) fn leading_coefficient(&self, d: V3<T>) -> (T, bool) {
        let horizontal = self.cos2 * (d.x * d.x + d.y * d.y);
        let vertical = self.sin2 * d.z * d.z;
        let a = horizontal - vertical;
        (
            a,
            a.abs() > T::from_f64(8.0) * T::EPSILON * (horizontal + vertical),
        )
    }

    /// The side of a point given relative to the apex.
    fn side_of_relative(&self, q: V3<T>) -> Option<Side> {
        let (c, s) = (self.cos, self.sin);
        let rho2 = q.x * q.x + q.y * q.y;
        if rho2 == T::ZERO && q.z == T::ZERO {
            return None; // the apex
        }
        if s == T::ZERO {
            // θ = 0 (c = 1): only the +z half-axis is on the cone; θ = π: only the −z half-axis.
            let on_axis = rho2 == T::ZERO && (q.z > T::ZERO) == (c > T::ZERO);
            return if on_axis {
                None
            } else {
                Some(Side::from_bool(c > T::ZERO))
            };
        }
        if c == T::ZERO {
            return side_of_sign(-q.z); // larger θ is below the plane
        }
        // θ(q) > θ_cone  ⇔  cos θ(q) < c  ⇔  q_z < c |q|.
        let q_ang = self.cos2 * rho2 - self.sin2 * q.z * q.z; // > 0 ⇔ |cos θ(q)| < |c|
        if c > T::ZERO {
            if q.z <= T::ZERO {
                Some(Side::Positive)
            } else {
                side_of_sign(q_ang)
            }
        } else if q.z >= T::ZERO {
            Some(Side::Negative)
        } else {
            side_of_sign(-q_ang)
        }
    }
}

/// A line's crossings with a cone in the scaled parameter: the first `n` of `s`, with the side each enters
/// (arrays, not pairs, so that no padding is copied with them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ConeRoots<T> {
    pub(crate) s: [T; 2],
    pub(crate) into: [Side; 2],
    pub(crate) n: usize,
}

impl<T: Real> ConeRoots<T> {
    const NONE: Self = ConeRoots {
        s: [T::ZERO; 2],
        into: [Side::Negative; 2],
        n: 0,
    };
    #[inline(always)]
    fn of(roots: [(T, Side); 2], n: usize) -> Self {
        let [(s0, i0), (s1, i1)] = roots;
        ConeRoots {
            s: [s0, s1],
            into: [i0, i1],
            n,
        }
    }
}

impl<T: Real> AxialCone<T> {
    /// The crossings of the line `ray` (a ray's line, without its interval) with the cone in the *scaled*
    /// parameter (see [`Ray::t_from_scaled`]), in increasing order, with the side each enters: the first `n` of
    /// the pair. [`Surface::crossings`] is this, cut to the ray's interval; the spherical marcher takes the one
    /// crossing it needs from here without building a [`Crossings`].
    #[inline(never)]
    pub(crate) fn scaled_crossings(&self, ray: &Line<T>) -> ConeRoots<T> {
        let d = ray.scaled_dir();
        let (q, w) = if self.apex_z == T::ZERO {
            (ray.origin(), ray.p_cross_d())
        } else {
            let mut q = ray.origin();
            q.z -= self.apex_z;
            (q, q.cross(d))
        };
        if self.sin != T::ZERO && w == V3::ZERO {
            // The line passes through the apex (or starts there): Q = A (s − s_apex)², no simple root. It changes
            // side at the apex exactly when the directions −d and +d lie on different sides.
            let before = self.side_of_relative(d.negated());
            let after = self.side_of_relative(d);
            return match (before, after) {
                (Some(b), Some(a)) if a != b => {
                    let s_apex = -q.dot(d) / ray.dd();
                    ConeRoots::of([(s_apex, a), (s_apex, a)], 1)
                }
                _ => ConeRoots::NONE,
            };
        }
        self.crossings_past_apex(q, w, d)
    }

    /// [`AxialCone::scaled_crossings`] of a cone whose apex is the origin (as the spherical grid's zenith cones
    /// are: `apex_z` is not read) for a line that does not pass through it, `p × d ≠ 0` (as the zenith stream
    /// knows from its start): the same crossings, without the two tests.
    #[inline(never)]
    pub(crate) fn scaled_crossings_past_origin(&self, ray: &Line<T>) -> ConeRoots<T> {
        self.crossings_past_apex(ray.origin(), ray.p_cross_d(), ray.scaled_dir())
    }

    /// One Newton step on the cone's quadratic form at the point `q + s d` (see `crossings_past_apex`), taken only
    /// when it is finite and at most a quarter of `gap`, the separation of the roots (a NaN `gap`, the linear
    /// case: any finite step).
    #[cfg_attr(curvicast_small_code, inline(never))]
    #[cfg_attr(not(curvicast_small_code), inline(always))]
    fn newton_step(&self, q: V3<T>, d: V3<T>, s: T, gap: T) -> T {
        let (c2, s2) = (self.cos2, self.sin2);
        let x = V3::new(q.x + s * d.x, q.y + s * d.y, q.z + s * d.z);
        let qx = c2 * (x.x * x.x + x.y * x.y) - s2 * x.z * x.z;
        let half_slope = c2 * (x.x * d.x + x.y * d.y) - s2 * x.z * d.z;
        let step = qx / (half_slope + half_slope);
        if step.is_finite() && !(step.abs() * T::from_i32(4) > gap) {
            s - step
        } else {
            s
        }
    }

    /// The crossings of the line `q + s d` (`q` relative to the apex, `w = q × d ≠ 0`) in the scaled parameter:
    /// the body of [`AxialCone::scaled_crossings`] (Hannasch §4.4, Lemma 10).
    #[inline(always)]
    fn crossings_past_apex(&self, q: V3<T>, w: V3<T>, d: V3<T>) -> ConeRoots<T> {
        let no_roots = ConeRoots::NONE;
        let (c2, s2) = (self.cos2, self.sin2);
        if self.sin == T::ZERO {
            return no_roots; // a half-axis: a line can touch it but never changes side
        }
        if self.cos == T::ZERO {
            // θ = π/2: the plane z = k, with the larger θ below it.
            if d.z == T::ZERO {
                return no_roots;
            }
            let root = (-q.z / d.z, Side::from_bool(d.z < T::ZERO));
            return ConeRoots::of([root, root], 1);
        }
        let (a, a_clear) = self.leading_coefficient(d);
        let b = c2 * (q.x * d.x + q.y * d.y) - s2 * q.z * d.z;
        let cc = c2 * (q.x * q.x + q.y * q.y) - s2 * q.z * q.z;
        let disc = s2 * (w.x * w.x + w.y * w.y) - c2 * w.z * w.z;
        if !(disc >= T::ZERO) {
            return no_roots;
        }
        let root_d = self.cos.abs() * disc.sqrt();
        let (s_dec, s_inc) = stable_quadratic(a, b, cc, root_d);
        // One Newton step on Q at each returned point. A, B, C are evaluated at the origin, where Q's terms are as
        // large as |q|², so their rounding (ε|q|²) reaches the root divided by |∇Q| at the crossing — which is
        // proportional to the crossing's distance from the apex. Re-evaluated at the crossing x, Q's rounding is
        // ε|x|², and the step leaves the point within O(ε S) of the cone however close to the apex it lies. The step
        // is taken only when it stays within a quarter of the roots' separation (so a near-double root is never
        // pushed into the other root's basin) and is finite. A root that is not returned is not refined.
        let gap = (s_inc - s_dec).abs(); // (in the branch with `root_d ≠ 0`, where `refine` is used)
        let refine = |s: T| self.newton_step(q, d, s, gap);
        // On the upper nappe (c > 0) the positive side (larger θ) is Q > 0; on the lower nappe it is Q < 0.
        let upper = self.cos > T::ZERO;
        let into_when_q_rises = Side::from_bool(upper);
        let on_nappe = |s: T| {
            let z = q.z + s * d.z;
            if upper { z > T::ZERO } else { z < T::ZERO }
        };
        let mut roots = [(T::ZERO, Side::Negative); 2];
        let mut n = 0usize;
        if root_d == T::ZERO {
            // A line parallel to a generator (A = 0 up to rounding) with a zero discriminant lies in the tangent
            // plane along that generator and never meets the cone (the line through the apex was handled above):
            // no crossing, not a touch at the meaningless root of a noise-sized A.
            if !a_clear {
                return no_roots;
            }
            // Tangent along a generator: a touch, from the side the line is on (the sign of A) and back. The double
            // root is taken as −B/A: the other form, C/q, divides C (whose two terms cancel on a tangent line) by
            // a small q and can land far from the point of tangency.
            let s_touch = -b / a;
            if on_nappe(s_touch) {
                let line_side = if a > T::ZERO {
                    into_when_q_rises
                } else {
                    into_when_q_rises.flip()
                };
                roots = [(s_touch, line_side.flip()), (s_touch, line_side)];
                n = 2;
            }
        } else {
            // Which nappe each root lies on. Evaluating z at a root fails near the apex, where z is a difference
            // of nearly equal terms (a line passing the apex within rounding, or a nearly flat cone, whose
            // crossings all have |z| ~ |cos θ|·ρ): the sign can come out wrong and a crossing be lost or doubled.
            // When A is clearly nonzero the nappes follow from signs computed without that cancellation, and the
            // roots are told apart by their kind (where Q decreases or increases), not by their computed values,
            // which may coincide or swap there:
            // * A < 0 (the line is steeper than the cone): it runs from inside one nappe to inside the other, Q
            //   rises through its first root (s_inc) and falls through its second (s_dec), one root per nappe;
            //   the upper one is the one with the larger z, the second when d_z > 0 (A < 0 implies d_z ≠ 0);
            // * A > 0 (flatter): it enters (s_dec) and leaves (s_inc) one nappe, the one its midpoint −B/A is on,
            //   and A·z(−B/A) = A q_z − B d_z = c²((d_x² + d_y²) q_z − (q_x d_x + q_y d_y) d_z) = c² (d × w)_z
            //   with w = q × d (the s² terms cancel exactly): that nappe is the sign of (d × w)_z, the side of the
            //   plane z = k on which the line's closest approach to the apex lies.
            // Only when A is within rounding of 0 (the line nearly parallel to a generator, one root far away) or
            // (d × w)_z is 0 is z evaluated at the roots.
            let dxw_z = d.x * w.y - d.y * w.x;
            let dec = (s_dec, into_when_q_rises.flip());
            let inc = (s_inc, into_when_q_rises);
            if a_clear && a < T::ZERO {
                let (s, side) = if (d.z > T::ZERO) == upper { dec } else { inc };
                let keep = (refine(s), side);
                if keep.0.is_finite() {
                    roots = [keep, keep];
                    n = 1;
                }
            } else if a_clear && dxw_z != T::ZERO {
                let (s_dec, s_inc) = (refine(s_dec), refine(s_inc));
                if (dxw_z > T::ZERO) == upper && s_dec.is_finite() && s_inc.is_finite() {
                    // entry before exit; two roots that rounding put in reverse order are a touch (midpoint)
                    let (s0, s1) = if s_dec <= s_inc {
                        (s_dec, s_inc)
                    } else {
                        let mid = s_dec * T::HALF + s_inc * T::HALF;
                        (mid, mid)
                    };
                    roots = [(s0, dec.1), (s1, inc.1)];
                    n = 2;
                }
            } else {
                let (dec, inc) = ((refine(s_dec), dec.1), (refine(s_inc), inc.1));
                let (lo, hi) = if dec.0 <= inc.0 {
                    (dec, inc)
                } else {
                    (inc, dec)
                };
                for (s, side) in [lo, hi] {
                    if s.is_finite() && on_nappe(s) {
                        if let Some(slot) = roots.get_mut(n) {
                            *slot = (s, side);
                            n = n.saturating_add(1);
                        }
                    }
                }
            }
        }
        ConeRoots::of(roots, n)
    }
}

impl<T: Real> Surface<T> for AxialCone<T> {
    fn crossings(&self, ray: &Ray<T>) -> Crossings<T> {
        let r = self.scaled_crossings(ray.line());
        let roots = [(r.s[0], r.into[0]), (r.s[1], r.into[1])];
        Crossings::from_scaled_roots(ray, roots.get(..r.n).unwrap_or(&[]))
    }

    fn side_of(&self, point: V3<T>) -> Option<Side> {
        self.side_of_relative(V3::new(point.x, point.y, point.z - self.apex_z))
    }
}

#[cfg(test)]
mod tests;
