//! Arbitrary-precision reference answers for ray ∩ surface: spheroid (a sphere when `a = b`), axial cone (one
//! nappe), half-plane bounded by the z axis, plane `z = c` — the four families of the kernel's `surface` layer
//! (Hannasch §4.3–§4.6, Wartell et al. §3.1–§3.4).
//!
//! Everything is computed with [`astro_float`] at [`PRECISION`] bits from the exact `f64` inputs. The logic is the
//! oracle's own and deliberately naive, because in high precision naivety costs nothing:
//!
//! * each surface is an implicit polynomial `F(x) = 0` expanded along the ray into `A t² + 2 B t + C` term by term
//!   (no cross-product identity for the discriminant, no stable quadratic formula: at 256 bits the cancellation in
//!   `−B ± √(B² − AC)` costs a root only as many bits as its smallness relative to the ray's scale, far below
//!   the 200-bit margin over `f64` for any case that is not contrived);
//! * the spheroid is `b²(x² + y²) + a² z² − a² b²` (no rescaling of z);
//! * the cone's nappe is checked by evaluating the crossing point's height above the apex, its side by the sign of
//!   `d/dt cos θ(t)` (the zenith angle of the moving point), not by the slope of the quadratic;
//! * the half-plane's half is checked by evaluating the crossing point's coordinate along `(cos φ, sin φ)`;
//! * `cos θ`, `sin θ`, `cos φ`, `sin φ` are computed in high precision from the `f64` angle, so the oracle answers
//!   the question the caller asked (the surface at exactly that `f64` angle), not the kernel's rounded one.
//!
//! Conventions (those of the kernel's `surface` module, which are part of the specification):
//!
//! * crossings are reported for `t_min <= t <= t_max`, ends included, sorted by `t`, each with the side the ray
//!   enters (`into_positive`: outside a spheroid, larger zenith angle θ, larger azimuth φ, larger z);
//! * a tangency (a double root) is two crossings at the same `t`, into the other side and back;
//! * a ray lying in a surface reports nothing;
//! * the half-plane includes its edge, the z axis: a line meeting the axis crosses every half-plane there;
//! * a line through a cone's apex crosses there exactly when the directions `−d` and `+d` lie on different sides;
//!   a cone of θ = 0 or θ = π (a half-axis) is never crossed;
//! * the cone at θ equal to the nearest `f64` (or `f32`, see [`AngleType`]) to π/2 is exactly the plane `z = k`,
//!   and at θ equal to the nearest value to π it is exactly the half-axis: the kernel documents both special
//!   values, so the oracle follows them.
//!
//! Each crossing also carries the sine of the angle between the ray and the surface, `|n·d| / (|n| |d|)` with `n`
//! the surface normal at the crossing, from which callers define the near-tangent band (see the oracle test).
//!
//! ```
//! use curvicast_host::oracle::surfaces::{OracleRay, OracleSurface};
//! let sphere = OracleSurface::Spheroid { a: 2.0, b: 2.0 }.prepare();
//! let ray = OracleRay::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
//! let c = sphere.crossings(&ray);
//! assert_eq!(c.len(), 2);
//! assert_eq!((c[0].t_f64, c[0].into_positive), (1.0, false)); // enters the ball
//! assert_eq!((c[1].t_f64, c[1].into_positive), (5.0, true)); // leaves it
//! assert_eq!(c[0].sin_angle, 1.0); // head-on
//! ```

pub use super::precise::to_f64 as round_to_f64;
use super::precise::{RM, with_consts};
use astro_float::BigFloat;
use std::cmp::Ordering;

/// Working precision of the oracle, in bits.
///
/// Products of two `f64` are exact in 106 bits, so the coefficients of the expanded quadratics are exact at this
/// precision whenever the inputs' significant bits span at most about 150 binades, and their discriminants
/// whenever the coefficients are short: an exact tangency of simple data (the hard cases) is found as an exact
/// double root. Elsewhere the relative error of every coefficient is about 2^-250, far below the 2^-53 of the
/// kernel's best mode, and a root computed by cancellation (`−B + √(B² − AC)`) keeps more than 53 correct bits
/// unless it is 2^-190 times smaller than the ray's scale.
pub const PRECISION: usize = 256;

/// A high-precision number (a thin wrapper for readable arithmetic).
#[derive(Clone, Debug)]
struct H(BigFloat);

impl H {
    fn f(x: f64) -> H {
        H(BigFloat::from_f64(x, PRECISION))
    }
    fn zero() -> H {
        H::f(0.0)
    }
    fn add(&self, o: &H) -> H {
        H(self.0.add(&o.0, PRECISION, RM))
    }
    fn sub(&self, o: &H) -> H {
        H(self.0.sub(&o.0, PRECISION, RM))
    }
    fn mul(&self, o: &H) -> H {
        H(self.0.mul(&o.0, PRECISION, RM))
    }
    fn div(&self, o: &H) -> H {
        H(self.0.div(&o.0, PRECISION, RM))
    }
    fn sq(&self) -> H {
        self.mul(self)
    }
    fn neg(&self) -> H {
        H(self.0.neg())
    }
    fn abs(&self) -> H {
        if self.is_neg() {
            self.neg()
        } else {
            self.clone()
        }
    }
    /// Square root by Newton's iteration from an `f64` estimate (53 → 106 → 212 → 424 bits), much faster than
    /// the library's correctly rounded one; the result is within one unit of the last of [`PRECISION`] bits.
    fn sqrt(&self) -> H {
        if self.is_zero() {
            return H::zero();
        }
        if self.is_neg() {
            return H(BigFloat::nan(None));
        }
        let Some(e) = self.0.exponent() else {
            return H(BigFloat::nan(None));
        };
        // x = 0.m · 2^e; scale by an even power of 2 into [0.5, 2).
        let half_e = e.div_euclid(2);
        let mut xs = self.0.clone();
        xs.set_exponent(e - 2 * half_e);
        let mut y = BigFloat::from_f64(round_to_f64(&xs).sqrt(), PRECISION);
        if let Some(ye) = y.exponent() {
            y.set_exponent(ye + half_e);
        }
        let mut y = H(y);
        for _ in 0..3 {
            let mut s = y.add(&self.div(&y)).0;
            if let Some(se) = s.exponent() {
                s.set_exponent(se - 1);
            }
            y = H(s);
        }
        y
    }
    fn is_zero(&self) -> bool {
        self.0.is_zero()
    }
    fn is_neg(&self) -> bool {
        !self.0.is_zero() && self.0.is_negative()
    }
    fn is_pos(&self) -> bool {
        !self.0.is_zero() && self.0.is_positive()
    }
    fn cmp(&self, o: &H) -> Ordering {
        match self.0.cmp(&o.0) {
            Some(x) if x < 0 => Ordering::Less,
            Some(x) if x > 0 => Ordering::Greater,
            _ => Ordering::Equal,
        }
    }
    fn cos(&self) -> H {
        with_consts(|cc| H(self.0.cos(PRECISION, RM, cc)))
    }
    fn sin(&self) -> H {
        with_consts(|cc| H(self.0.sin(PRECISION, RM, cc)))
    }
    fn to_f64(&self) -> f64 {
        round_to_f64(&self.0)
    }
}

/// Which scalar type's special angle values the kernel under test recognises exactly (π/2 and π for a cone).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AngleType {
    /// The kernel ran in `f64`: θ = `f64::consts::FRAC_PI_2` is the exact plane, `f64::consts::PI` the half-axis.
    F64,
    /// The kernel ran in `f32` (exact or fast): the `f32` constants, given here widened to `f64`.
    F32,
}

impl AngleType {
    /// Which type's special angles the kernel treats exactly in a precision.
    pub fn of(p: curvicast_cli::precision::Precision) -> AngleType {
        match p {
            curvicast_cli::precision::Precision::F64 => AngleType::F64,
            _ => AngleType::F32,
        }
    }
}

/// A surface, with the same parameters as the kernel's constructors (all `f64`; an `f32` case passes its values
/// widened exactly).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OracleSurface {
    /// `(x² + y²)/a² + z²/b² = 1`, centred at the origin (`a >= b > 0`).
    Spheroid {
        /// Equatorial semi-axis.
        a: f64,
        /// Polar semi-axis.
        b: f64,
    },
    /// The points at zenith angle `theta` from +z seen from the apex `(0, 0, apex_z)`, one nappe.
    Cone {
        /// Height of the apex.
        apex_z: f64,
        /// Zenith angle in `[0, π]`.
        theta: f64,
        /// Which type's special values of θ are exact.
        angles: AngleType,
    },
    /// `{(ρ cos φ, ρ sin φ, z) : ρ >= 0}`.
    HalfPlane {
        /// Azimuth φ (any finite angle).
        phi: f64,
    },
    /// The plane `z = c`.
    PlaneZ {
        /// Its height.
        c: f64,
    },
}

/// A ray `p + t d`, `t_min <= t <= t_max`, in exact `f64` data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OracleRay {
    /// `p`.
    pub origin: [f64; 3],
    /// `d` (any nonzero length).
    pub dir: [f64; 3],
    /// Lower end of the interval.
    pub t_min: f64,
    /// Upper end (may be +∞).
    pub t_max: f64,
}

impl OracleRay {
    /// The ray for `0 <= t < ∞`.
    pub fn new(origin: [f64; 3], dir: [f64; 3]) -> Self {
        OracleRay {
            origin,
            dir,
            t_min: 0.0,
            t_max: f64::INFINITY,
        }
    }

    /// `|d|` (to `f64` accuracy).
    pub fn dir_len(&self) -> f64 {
        norm_f64(self.dir)
    }

    /// `max(|p|, |p + t d|)` for an exact `f64` `t` (to `f64` accuracy; the point is formed in high precision):
    /// the scale of the error unit `ε·S`.
    pub fn scale_at(&self, t: f64) -> f64 {
        let x = point(&hv(self.origin), &hv(self.dir), &H::f(t));
        norm_f64(self.origin).max(norm_f64(x.each_ref().map(H::to_f64)))
    }

    /// `|t_kernel − t| · |d|` in high precision (rounded to `f64`): the forward error as a distance along the ray.
    pub fn forward_error(&self, t: &BigFloat, t_kernel: f64) -> f64 {
        H::f(t_kernel).sub(&H(t.clone())).abs().to_f64() * self.dir_len()
    }

    fn contains(&self, t: &H) -> bool {
        let lo = self.t_min == f64::NEG_INFINITY || t.cmp(&H::f(self.t_min)) != Ordering::Less;
        let hi = self.t_max == f64::INFINITY || t.cmp(&H::f(self.t_max)) != Ordering::Greater;
        lo && hi
    }
}

/// One crossing found by the oracle.
#[derive(Debug, Clone)]
pub struct OracleCrossing {
    /// The ray parameter in [`PRECISION`] bits.
    pub t: BigFloat,
    /// `t` rounded to the nearest `f64`.
    pub t_f64: f64,
    /// Whether the ray enters the positive side here.
    pub into_positive: bool,
    /// The sine of the angle between ray and surface, `|n·d| / (|n| |d|)`, in `[0, 1]`; 0 for a tangency and at a
    /// cone's apex (where the normal is undefined).
    pub sin_angle: f64,
}

type V = [H; 3];

fn hv(a: [f64; 3]) -> V {
    [H::f(a[0]), H::f(a[1]), H::f(a[2])]
}
fn dot(a: &V, b: &V) -> H {
    a[0].mul(&b[0]).add(&a[1].mul(&b[1])).add(&a[2].mul(&b[2]))
}
fn point(p: &V, d: &V, t: &H) -> V {
    [
        p[0].add(&t.mul(&d[0])),
        p[1].add(&t.mul(&d[1])),
        p[2].add(&t.mul(&d[2])),
    ]
}
/// `|n·d| / (|n| |d|)` (0 when `n` is zero), evaluated in `f64` from the rounded components: it classifies
/// crossings (the near-tangent band), where an absolute error of 1e-15 is irrelevant.
fn sin_between(n: &V, d: &V) -> f64 {
    sin_f64(n.each_ref().map(H::to_f64), d.each_ref().map(H::to_f64))
}

fn sin_f64(n: [f64; 3], d: [f64; 3]) -> f64 {
    let (Some(n), Some(d)) = (normalized(n), normalized(d)) else {
        return 0.0;
    };
    (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).abs().min(1.0)
}

/// The unit vector along `v` (computed without overflow or underflow), or `None` for the zero vector.
fn normalized(v: [f64; 3]) -> Option<[f64; 3]> {
    let m = v[0].abs().max(v[1].abs()).max(v[2].abs());
    if m.is_nan() || m <= 0.0 || !m.is_finite() {
        return None;
    }
    let u = v.map(|x| x / m);
    let n = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    Some(u.map(|x| x / n))
}

/// `|v|` in `f64` without overflow or underflow.
fn norm_f64(v: [f64; 3]) -> f64 {
    let m = v[0].abs().max(v[1].abs()).max(v[2].abs());
    if m.is_nan() || m <= 0.0 || !m.is_finite() {
        return m;
    }
    let u = v.map(|x| x / m);
    m * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt()
}

/// The cone's mode after the kernel's documented special values of θ.
#[derive(Debug, Clone)]
enum ConeShape {
    /// θ = 0 or π: a half-axis, never crossed.
    Axis,
    /// θ is exactly π/2: the plane `z = k`, larger θ below.
    Plane,
    /// A proper cone with `c = cos θ ≠ 0`, `s = sin θ > 0`.
    Proper { c: H, s: H, c2: H, s2: H },
}

#[derive(Debug, Clone)]
enum Prepared {
    Spheroid { a: H, b: H, a2: H, b2: H },
    Cone { k: H, shape: ConeShape },
    HalfPlane { cos: H, sin: H },
    PlaneZ { c: H },
}

/// A surface with its high-precision constants (cos/sin of its angle) computed once.
#[derive(Debug, Clone)]
pub struct PreparedSurface {
    surface: OracleSurface,
    p: Prepared,
}

impl OracleSurface {
    /// Computes the surface's high-precision constants (for a cone or half-plane, the cosine and sine of the
    /// angle at [`PRECISION`] bits, which is the costly part).
    pub fn prepare(&self) -> PreparedSurface {
        let p = match *self {
            OracleSurface::Spheroid { a, b } => {
                let (a, b) = (H::f(a), H::f(b));
                Prepared::Spheroid {
                    a2: a.sq(),
                    b2: b.sq(),
                    a,
                    b,
                }
            }
            OracleSurface::Cone {
                apex_z,
                theta,
                angles,
            } => {
                let (half_pi, pi) = match angles {
                    AngleType::F64 => (std::f64::consts::FRAC_PI_2, std::f64::consts::PI),
                    AngleType::F32 => (
                        std::f32::consts::FRAC_PI_2 as f64,
                        std::f32::consts::PI as f64,
                    ),
                };
                let shape = if theta == 0.0 || theta == pi {
                    ConeShape::Axis
                } else if theta == half_pi {
                    ConeShape::Plane
                } else {
                    let th = H::f(theta);
                    let (c, s) = (th.cos(), th.sin());
                    ConeShape::Proper {
                        c2: c.sq(),
                        s2: s.sq(),
                        c,
                        s,
                    }
                };
                Prepared::Cone {
                    k: H::f(apex_z),
                    shape,
                }
            }
            OracleSurface::HalfPlane { phi } => {
                let ph = H::f(phi);
                Prepared::HalfPlane {
                    cos: ph.cos(),
                    sin: ph.sin(),
                }
            }
            OracleSurface::PlaneZ { c } => Prepared::PlaneZ { c: H::f(c) },
        };
        PreparedSurface { surface: *self, p }
    }
}

impl PreparedSurface {
    /// The surface this was prepared from.
    pub fn surface(&self) -> OracleSurface {
        self.surface
    }

    /// The crossings of `ray` with the surface inside `[t_min, t_max]`, sorted by `t` (see the module docs).
    pub fn crossings(&self, ray: &OracleRay) -> Vec<OracleCrossing> {
        let p = hv(ray.origin);
        let d = hv(ray.dir);
        // (t, into_positive, sin_angle)
        let mut raw: Vec<(H, bool, f64)> = match &self.p {
            Prepared::Spheroid { a2, b2, .. } => spheroid_roots(a2, b2, &p, &d),
            Prepared::Cone { k, shape } => cone_roots(k, shape, &p, &d),
            Prepared::HalfPlane { cos, sin } => half_plane_roots(cos, sin, &p, &d),
            Prepared::PlaneZ { c } => {
                if d[2].is_zero() {
                    vec![]
                } else {
                    let t = c.sub(&p[2]).div(&d[2]);
                    let n = [H::zero(), H::zero(), H::f(1.0)];
                    vec![(t, d[2].is_pos(), sin_between(&n, &d))]
                }
            }
        };
        raw.retain(|(t, _, _)| ray.contains(t));
        // Stable sort keeps the (into, back) order of a double root.
        raw.sort_by(|x, y| x.0.cmp(&y.0));
        raw.into_iter()
            .map(|(t, into_positive, sin_angle)| OracleCrossing {
                t_f64: t.to_f64(),
                t: t.0,
                into_positive,
                sin_angle,
            })
            .collect()
    }

    /// The sine of the angle between the ray and the surface's normal field evaluated at `p + t d` (the point need
    /// not lie on the surface): what a crossing reported at `t` by someone else would have. 0 where the normal is
    /// undefined (a cone's apex).
    pub fn sin_angle_at(&self, ray: &OracleRay, t: f64) -> f64 {
        let p = hv(ray.origin);
        let d = hv(ray.dir);
        let x = point(&p, &d, &H::f(t));
        match &self.p {
            Prepared::Spheroid { a2, b2, .. } => {
                sin_between(&[b2.mul(&x[0]), b2.mul(&x[1]), a2.mul(&x[2])], &d)
            }
            Prepared::Cone { k, shape } => match shape {
                ConeShape::Axis => 0.0,
                ConeShape::Plane => sin_between(&[H::zero(), H::zero(), H::f(1.0)], &d),
                ConeShape::Proper { c2, s2, .. } => {
                    let z = x[2].sub(k);
                    sin_between(&[c2.mul(&x[0]), c2.mul(&x[1]), s2.mul(&z).neg()], &d)
                }
            },
            Prepared::HalfPlane { cos, sin } => {
                sin_between(&[sin.neg(), cos.clone(), H::zero()], &d)
            }
            Prepared::PlaneZ { .. } => sin_between(&[H::zero(), H::zero(), H::f(1.0)], &d),
        }
    }

    /// The distance from `p + t d` to where the surface's own decisions switch: for a cone the plane `z = k`
    /// through its apex, which separates its nappe from the other one (near the apex, and anywhere near that plane
    /// for a cone close to θ = π/2, the nappe of a crossing is decided by the sign of a tiny `z − k`); for a
    /// half-plane its bounding z axis; `+∞` for a spheroid, a plane, or the cone at exactly θ = π/2 (no edge).
    pub fn edge_distance_at(&self, ray: &OracleRay, t: f64) -> f64 {
        let x = point(&hv(ray.origin), &hv(ray.dir), &H::f(t));
        match &self.p {
            Prepared::Cone {
                shape: ConeShape::Plane,
                ..
            } => f64::INFINITY, // θ = π/2 exactly: a plane, no nappe to decide
            Prepared::Cone { k, .. } => x[2].sub(k).abs().to_f64(),
            Prepared::HalfPlane { .. } => norm_f64([x[0].to_f64(), x[1].to_f64(), 0.0]),
            Prepared::Spheroid { .. } | Prepared::PlaneZ { .. } => f64::INFINITY,
        }
    }

    /// The distance from `p + t d` (computed in high precision for the exact `f64` `t`) to the surface, rounded to
    /// `f64`: the backward error of a crossing reported at `t`.
    ///
    /// Exact for the sphere, the cone (distance to its single nappe), the half-plane and the plane; for a spheroid
    /// with `a ≠ b` it is the first-order distance `|F| / |∇F|`, whose relative error is of the order of the
    /// distance over the radius of curvature (negligible for the distances of interest, ≤ 1e-5 of the size).
    pub fn distance_at(&self, ray: &OracleRay, t: f64) -> f64 {
        let x = point(&hv(ray.origin), &hv(ray.dir), &H::f(t));
        self.distance(&x).to_f64()
    }

    /// The distance of the exact `f64` point `x` from the surface (see [`PreparedSurface::distance_at`]).
    pub fn distance_of_point(&self, x: [f64; 3]) -> f64 {
        self.distance(&hv(x)).to_f64()
    }

    fn distance(&self, x: &V) -> H {
        match &self.p {
            Prepared::Spheroid { a, b, a2, b2 } => {
                if a.cmp(b) == Ordering::Equal {
                    return dot(x, x).sqrt().sub(a).abs();
                }
                let rho2 = x[0].sq().add(&x[1].sq());
                let f = b2.mul(&rho2).add(&a2.mul(&x[2].sq())).sub(&a2.mul(b2));
                let g = [b2.mul(&x[0]), b2.mul(&x[1]), a2.mul(&x[2])];
                let gn = dot(&g, &g).sqrt().mul(&H::f(2.0));
                if gn.is_zero() {
                    return b.clone(); // the centre
                }
                f.abs().div(&gn)
            }
            Prepared::Cone { k, shape } => {
                let q = [x[0].clone(), x[1].clone(), x[2].sub(k)];
                let rho = q[0].sq().add(&q[1].sq()).sqrt();
                let (c, s) = match shape {
                    ConeShape::Axis => {
                        // the half-axis of direction (0, 0, ±1)
                        let up = match self.surface {
                            OracleSurface::Cone { theta, .. } => theta == 0.0,
                            _ => true,
                        };
                        return if q[2].is_pos() == up || q[2].is_zero() {
                            rho
                        } else {
                            dot(&q, &q).sqrt()
                        };
                    }
                    ConeShape::Plane => (H::zero(), H::f(1.0)),
                    ConeShape::Proper { c, s, .. } => (c.clone(), s.clone()),
                };
                // In the meridian half-plane of the point, the nappe is the half-line along g = (s, c) in
                // (ρ, z); the distance to it is |q × g| when the projection on g is >= 0, else |q|.
                let along = rho.mul(&s).add(&q[2].mul(&c));
                if along.is_neg() {
                    dot(&q, &q).sqrt()
                } else {
                    rho.mul(&c).sub(&q[2].mul(&s)).abs()
                }
            }
            Prepared::HalfPlane { cos, sin } => {
                let along = cos.mul(&x[0]).add(&sin.mul(&x[1]));
                if along.is_neg() {
                    x[0].sq().add(&x[1].sq()).sqrt()
                } else {
                    cos.mul(&x[1]).sub(&sin.mul(&x[0])).abs()
                }
            }
            Prepared::PlaneZ { c } => x[2].sub(c).abs(),
        }
    }
}

mod roots;
use roots::*;

#[cfg(test)]
mod tests;
