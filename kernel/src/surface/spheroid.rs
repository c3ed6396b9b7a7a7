//! Ray ∩ spheroid `(x² + y²)/a² + z²/b² = 1` centred at the origin, `a ≥ b > 0`; a sphere when `a = b`.
//!
//! Hannasch §4.3 (Lemma 9) gives the sphere's roots as `t = −⟨p|d⟩/‖d‖² ± sqrt(...)`; we use the same pair in the
//! cancellation-free form. With the half-discriminant written through the closest approach,
//!
//! ```text
//! ‖d‖² t² + 2⟨p|d⟩ t + (‖p‖² − R²) = 0,      ⟨p|d⟩² − ‖d‖²(‖p‖² − R²) = ‖d‖² R² − |p × d|²,
//! ```
//!
//! the square root is taken of `‖d‖²R² − |p × d|²` (never of `⟨p|d⟩² − ‖d‖²‖p‖² + …`), and the two roots come from
//! one square root and two divisions by the stable formula. A spheroid is the sphere of radius `a` after scaling
//! z by `a/b` (Wartell et al. §3.1.2 builds its bounds B^h this way), which leaves `t` unchanged.
//!
//! **Error bound** (f64 or f32, correctly rounded sqrt; ε the unit roundoff of the type, S = max(|p|, |p + t d|, R)):
//! the inputs of the square root carry absolute errors below `6ε·‖d‖²·S²`, and each root is the exact root of a
//! quadratic whose coefficients are perturbed by at most that. The computed point therefore lies within about
//! `4ε·S` of the sphere (backward error); along the ray the error is that divided by the sine of the angle
//! between ray and surface, so it grows only in the near-tangent band, where the problem itself is
//! ill-conditioned. For `a ≠ b` the scaling of z adds one rounding (`ε·S`). The host oracle measures both.

use super::crossing::{
    Crossings, Side, Surface, SurfaceError, side_of_sign, sign_of, stable_quadratic_signed,
};
use crate::ray::{Line, Ray};
use crate::real::Real;
use crate::vec3::V3;

/// An origin-centred spheroid with equatorial semi-axis `a` and polar semi-axis `b` (`a ≥ b > 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spheroid<T> {
    a: T,
    b: T,
    /// `a²`.
    a2: T,
    /// `a / b`, the factor that turns the spheroid into the sphere of radius `a`; exactly 1 for a sphere.
    k: T,
}

impl<T: Real> Spheroid<T> {
    /// The spheroid with semi-axes `a` (equatorial) and `b` (polar).
    pub fn new(a: T, b: T) -> Result<Self, SurfaceError> {
        if !a.is_finite() || !b.is_finite() {
            return Err(SurfaceError::NonFinite);
        }
        if !(b > T::ZERO && a >= b) {
            return Err(SurfaceError::BadAxes);
        }
        let a2 = a * a;
        if !a2.is_finite() || a2 == T::ZERO {
            return Err(SurfaceError::BadAxes);
        }
        Ok(Spheroid {
            a,
            b,
            a2,
            k: if a == b { T::ONE } else { a / b },
        })
    }

    /// The sphere of radius `r > 0`.
    pub fn sphere(r: T) -> Result<Self, SurfaceError> {
        Self::new(r, r)
    }

    /// The equatorial semi-axis.
    #[inline]
    pub fn a(&self) -> T {
        self.a
    }
    /// The polar semi-axis.
    #[inline]
    pub fn b(&self) -> T {
        self.b
    }
    /// True when `a = b`.
    #[inline]
    pub fn is_sphere(&self) -> bool {
        self.k == T::ONE
    }

    /// Both roots of the ray with the spheroid in the ray's scaled parameter, `(entering, leaving)`, or `None` when
    /// the line misses it. Costs one square root and two divisions (plus the scaling of z for `a ≠ b`).
    #[inline]
    pub(crate) fn scaled_roots(&self, ray: &Ray<T>) -> Option<(T, T)> {
        if self.is_sphere() {
            return sphere_scaled_roots(self.a2, ray.line());
        }
        let (p, dd, pd, w) = {
            let mut p = ray.origin();
            let mut d = ray.scaled_dir();
            p.z *= self.k;
            d.z *= self.k;
            (p, d.length_squared(), p.dot(d), p.cross(d))
        };
        quadratic_roots(self.a2, p, dd, pd, w)
    }
}

/// The roots of the ray with the origin-centred sphere of squared radius `r2 > 0` (finite), in the ray's scaled
/// parameter: [`Spheroid::scaled_roots`] for a sphere, bit for bit, without building the surface (the spherical
/// marcher keeps its radii squared, Hannasch §2, and solves one sphere per radius crossing).
#[inline]
pub(crate) fn sphere_scaled_roots<T: Real>(r2: T, ray: &Line<T>) -> Option<(T, T)> {
    quadratic_roots(r2, ray.origin(), ray.dd(), ray.pd(), ray.p_cross_d())
}

/// `‖d‖² s² + 2⟨p|d⟩ s + ‖p‖² − R² = 0` with the discriminant through the closest approach.
#[inline]
fn quadratic_roots<T: Real>(a2: T, p: V3<T>, dd: T, pd: T, w: V3<T>) -> Option<(T, T)> {
    sphere_roots_of(a2, p.length_squared(), dd, pd, w.length_squared())
}

/// The roots of `‖d‖² s² + 2⟨p|d⟩ s + ‖p‖² − R² = 0` (`R² = a2`) from the line's invariants `pp = ‖p‖²`,
/// `dd = ‖d‖²`, `pd = ⟨p|d⟩` and `ww = |p × d|²` (a caller that solves many spheres on one line forms them once),
/// in the order entry, exit; `None` when the line misses the sphere.
#[inline]
pub(crate) fn sphere_roots_of<T: Real>(a2: T, pp: T, dd: T, pd: T, ww: T) -> Option<(T, T)> {
    sphere_roots_signed(a2, pp, dd, pd, ww, sign_of(pd))
}

/// [`sphere_roots_of`] with the sign of `⟨p|d⟩` given, `sign = sign_of(pd)` (the same bits): a caller that
/// solves many spheres on one line takes it once.
#[inline]
pub(crate) fn sphere_roots_signed<T: Real>(
    a2: T,
    pp: T,
    dd: T,
    pd: T,
    ww: T,
    sign: T,
) -> Option<(T, T)> {
    // ⟨p|d⟩² − ‖d‖²(‖p‖² − R²) = ‖d‖² R² − |p × d|²: closest approach from the cross product.
    let disc = dd * a2 - ww;
    if !(disc >= T::ZERO) {
        return None;
    }
    let root = disc.sqrt();
    if near_vertex(pp, a2, dd, pd, root) {
        let (v, h) = (-pd / dd, root / dd);
        return Some((v - h, v + h));
    }
    let c = pp - a2;
    // ‖d‖² grows toward outside ⇒ the root where the quadratic decreases is the entry into the ball.
    let (s_in, s_out) = stable_quadratic_signed(dd, pd, c, root, sign);
    // Near tangency the two roots are equal within rounding, and the two roundings (q/a, c/q) can put them in
    // reverse order: that is a touch (the tangency convention of `surface`), reported at the parabola's vertex
    // −⟨p|d⟩/‖d‖², the closest approach, which lies between the exact roots. Not at the computed roots'
    // midpoint: `c/q` divides the rounding of `‖p‖² − R²` (up to ε‖p‖²) by a `q` that is tiny there, and can
    // land far from the touch (a fuzzer's f32 case: 307 m off a flat spheroid 44 km across).
    if s_in > s_out {
        let vertex = -pd / dd;
        return Some((vertex, vertex));
    }
    Some((s_in, s_out))
}

/// Whether a sphere's roots are better formed from the vertex: `|q| = |⟨p|d⟩| + √disc` (the stable formula's
/// divisor) below `√(ε ‖d‖² (‖p‖² + R²))`, a start within rounding of the line's closest approach on a line
/// within rounding of tangent. There `c/q` divides the rounding of `‖p‖² − R²` (up to ε(‖p‖² + R²)) by almost
/// nothing and can land anywhere (16 for a start 3e-17 inside a sphere of radius 2.07, on a tangent line), while
/// `−⟨p|d⟩/‖d‖² ± √disc/‖d‖²` is off by no more than the discriminant's rounding allows.
#[inline]
fn near_vertex<T: Real>(pp: T, a2: T, dd: T, pd: T, root: T) -> bool {
    let q = pd.abs() + root;
    q * q < T::EPSILON * dd * (pp + a2)
}

/// The exit root alone of [`sphere_roots_signed`], for a sphere whose two roots the caller knows to be distinct
/// and in order (it entered the ball at the first, from the same invariants): the same bits as that function's
/// second root, with one division instead of two and no test for a touch.
#[inline]
pub(crate) fn sphere_exit_root_signed<T: Real>(a2: T, pp: T, dd: T, pd: T, ww: T, sign: T) -> T {
    let root = (dd * a2 - ww).sqrt();
    if near_vertex(pp, a2, dd, pd, root) {
        return -pd / dd + root / dd;
    }
    // `stable_quadratic_signed`'s q, and of its two quotients the one it returns second for this sign
    let q = -(pd + sign * root);
    if sign > T::ZERO {
        (pp - a2) / q
    } else {
        q / dd
    }
}

impl<T: Real> Surface<T> for Spheroid<T> {
    fn crossings(&self, ray: &Ray<T>) -> Crossings<T> {
        match self.scaled_roots(ray) {
            Some((s_in, s_out)) => Crossings::from_scaled_roots(
                ray,
                &[(s_in, Side::Negative), (s_out, Side::Positive)],
            ),
            None => Crossings::NONE,
        }
    }

    fn side_of(&self, point: V3<T>) -> Option<Side> {
        let z = point.z * self.k;
        side_of_sign(point.x * point.x + point.y * point.y + z * z - self.a2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ts<T: Real>(c: &Crossings<T>) -> [(f64, Side); 2] {
        let mut out = [(f64::NAN, Side::Negative); 2];
        for (o, x) in out.iter_mut().zip(c.iter()) {
            *o = (x.t.to_f64(), x.into);
        }
        out
    }

    /// The radius stream solves a sphere it entered again on the way out for its exit root alone
    /// (`sphere_exit_root_signed`): that must be the full solve's second root, bit for bit, whenever the full
    /// solve found the roots distinct and in order — on lines in both directions past the center, from near and
    /// far, at near-tangent radii and at tiny and huge scales.
    fn check_exit_root_alone<T: Real>(bits: impl Fn(T) -> u64) {
        let mut unit = crate::test_util::xorshift_uniform(0x9e37_79b9_7f4a_7c15);
        let mut uniform = move || unit() * 2.0 - 1.0;
        let mut compared = 0;
        // 20 000 lines natively; 300 under Miri, where each takes about 7 ms (the whole run took minutes).
        let n = if cfg!(miri) { 300 } else { 20_000 };
        for i in 0..n {
            let scale = [1.0, 1e-12, 1e12][i % 3];
            let mut v = || T::from_f64(uniform());
            let p = V3::new(v(), v(), v()).scaled(T::from_f64(3.0 * scale));
            let d = V3::new(v(), v(), v());
            let Ok(ray) = Ray::new(p, d) else {
                continue;
            };
            let line = ray.line();
            let (pp, dd, pd, ww) = (
                line.origin().length_squared(),
                line.dd(),
                line.pd(),
                line.p_cross_d().length_squared(),
            );
            // the squared distance of the line from the center, and radii around it (near-tangent ones first)
            let closest2 = ww / dd;
            let r2 = closest2
                * T::from_f64(1.0 + [1e-15, 1e-7, 0.01, 1.0, 9.0][i % 5] * uniform().abs());
            let sign = sign_of(pd);
            if let Some((a, b)) = sphere_roots_signed(r2, pp, dd, pd, ww, sign) {
                if a < b {
                    let alone = sphere_exit_root_signed(r2, pp, dd, pd, ww, sign);
                    assert_eq!(bits(alone), bits(b), "{p:?} r2 {}", r2.to_f64());
                    compared += 1;
                }
            }
        }
        assert!(compared > n * 3 / 4, "{compared} of {n}");
    }

    #[test]
    fn exit_root_alone_is_the_second_root_of_every_sphere_entered() {
        check_exit_root_alone::<f64>(f64::to_bits);
        check_exit_root_alone::<f32>(|x| u64::from(x.to_bits()));
    }

    #[test]
    fn unit_sphere_through_center() {
        let r = Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        let c = Spheroid::sphere(1.0).unwrap().crossings(&r);
        assert_eq!(ts(&c), [(1.0, Side::Negative), (3.0, Side::Positive)]);
    }

    #[test]
    fn starting_inside_reports_only_the_exit() {
        let r = Ray::new([0.0, 0.0, 0.0], [0.0, 0.0, 2.0]).unwrap();
        let c = Spheroid::sphere(1.0).unwrap().crossings(&r);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].t, c[0].into), (0.5, Side::Positive));
    }

    #[test]
    fn ray_starting_exactly_on_sphere_includes_t0() {
        let r = Ray::new([3.0, 4.0, 0.0], [-3.0, -4.0, 0.0]).unwrap();
        let c = Spheroid::sphere(5.0).unwrap().crossings(&r);
        assert_eq!(ts(&c), [(0.0, Side::Negative), (2.0, Side::Positive)]);
    }

    #[test]
    fn tangent_ray_touches_twice_at_one_t() {
        let r = Ray::new([-5.0, 1.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        let c = Spheroid::sphere(1.0).unwrap().crossings(&r);
        assert_eq!(ts(&c), [(5.0, Side::Negative), (5.0, Side::Positive)]);
        let r = Ray::new([-5.0, 1.0 + 1e-12, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert!(Spheroid::sphere(1.0).unwrap().crossings(&r).is_empty());
    }

    #[test]
    fn interval_filters_roots() {
        let r = Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0])
            .unwrap()
            .with_interval(1.5, 10.0)
            .unwrap();
        let c = Spheroid::sphere(1.0).unwrap().crossings(&r);
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].t, 3.0);
    }

    #[test]
    fn spheroid_poles_and_equator() {
        let s = Spheroid::new(2.0, 1.0).unwrap();
        let down = Ray::new([0.0, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
        assert_eq!(
            ts(&s.crossings(&down)),
            [(4.0, Side::Negative), (6.0, Side::Positive)]
        );
        let across = Ray::new([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert_eq!(
            ts(&s.crossings(&across)),
            [(3.0, Side::Negative), (7.0, Side::Positive)]
        );
        assert_eq!(s.side_of(V3::new(0.0, 0.0, 1.0)), None);
        assert_eq!(s.side_of(V3::new(1.9, 0.0, 0.1)), Some(Side::Negative));
    }

    #[test]
    fn huge_and_tiny_scales() {
        for scale in [1e8_f64, 1e-8] {
            let r = Ray::new([-3.0 * scale, 0.6 * scale, 0.0], [1.0, 0.0, 0.0]).unwrap();
            let c = Spheroid::sphere(scale).unwrap().crossings(&r);
            assert_eq!(c.len(), 2);
            assert!((c[0].t - 2.2 * scale).abs() <= 4.0 * f64::EPSILON * 3.0 * scale);
            assert!((c[1].t - 3.8 * scale).abs() <= 4.0 * f64::EPSILON * 3.0 * scale);
        }
    }

    #[test]
    fn direction_length_does_not_matter() {
        let s = Spheroid::sphere(1.0_f32).unwrap();
        for len in [1e-30_f32, 1.0, 1e30] {
            let r = Ray::new([-2.0, 0.0, 0.0], [len, 0.0, 0.0]).unwrap();
            let c = s.crossings(&r);
            assert_eq!(c.len(), 2);
            assert!((c[0].t * len - 1.0).abs() <= 2.0 * f32::EPSILON);
            assert!((c[1].t * len - 3.0).abs() <= 6.0 * f32::EPSILON);
        }
    }

    #[test]
    fn bad_axes_are_errors() {
        assert_eq!(Spheroid::new(1.0, 2.0), Err(SurfaceError::BadAxes));
        assert_eq!(Spheroid::sphere(0.0), Err(SurfaceError::BadAxes));
        assert_eq!(Spheroid::sphere(f64::NAN), Err(SurfaceError::NonFinite));
        assert_eq!(Spheroid::sphere(1e200), Err(SurfaceError::BadAxes));
    }

    #[test]
    fn near_tangent_steep_ray_keeps_its_two_roots_sorted_f32() {
        // Found by the `surfaces` fuzz target: a ray grazing the unit sphere at (1, 0, 0), its direction almost
        // along +z and huge (5e29). The two roots are equal within rounding and the stable formula's two roundings
        // (q/a and c/q) used to return them in reverse order.
        let r = Ray::new(
            [1.0_f32, 0.0, -0.5],
            [-core::f32::consts::PI, 10922.5, 4.885_607_7e29],
        )
        .unwrap();
        let c = Spheroid::sphere(1.0_f32).unwrap().crossings(&r);
        assert_eq!(c.len(), 2);
        assert!(c[0].t <= c[1].t, "{c:?}");
        assert_eq!((c[0].into, c[1].into), (Side::Negative, Side::Positive));
    }

    #[test]
    fn near_tangent_roots_in_reverse_order_are_reported_as_a_touch_at_the_closest_approach() {
        // The fuzz-found grazing ray above: the stable formula's two roundings put the roots in reverse order.
        let r = Ray::new(
            [1.0_f32, 0.0, -0.5],
            [-core::f32::consts::PI, 10922.5, 4.885_607_7e29],
        )
        .unwrap();
        let line = r.line();
        let (pp, dd, pd) = (line.origin().length_squared(), line.dd(), line.pd());
        let ww = line.p_cross_d().length_squared();
        let disc = dd - ww;
        let (s_in, s_out) = crate::surface::crossing::stable_quadratic_signed(
            dd,
            pd,
            pp - 1.0,
            disc.sqrt(),
            crate::surface::crossing::sign_of(pd),
        );
        assert!(s_in > s_out, "not a reversed pair: {s_in} {s_out}");
        let vertex = -pd / dd;
        assert_eq!(sphere_roots_of(1.0, pp, dd, pd, ww), Some((vertex, vertex)));
        // the touch lies on the unit sphere to the solver's error bound (S = 1 here)
        let (o, d) = (line.origin(), line.scaled_dir());
        let at = [o.x, o.y, o.z]
            .iter()
            .zip([d.x, d.y, d.z])
            .map(|(&o, d)| f64::from(o) + f64::from(vertex) * f64::from(d))
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        assert!((at - 1.0).abs() < 8.0 * f64::from(f32::EPSILON), "{at}");
    }

    #[test]
    fn a_sphere_knows_it_is_one_and_a_spheroid_does_not() {
        assert!(Spheroid::sphere(2.0_f64).unwrap().is_sphere());
        assert!(!Spheroid::new(2.0_f64, 1.5).unwrap().is_sphere());
    }

    /// A fuzzer's case: a line passing 0.8 mm outside a flat f32 spheroid (a = 43 690, b = 2 730.625) at its
    /// equator, 44 km from the centre, where `f32` cannot tell a touch from a miss. The computed roots came out
    /// reversed, and their midpoint (one of them was `‖p‖² − R²`'s rounding, 128, over a tiny `q`) put the touch
    /// 307 m off the surface. A crossing reported there must lie on the spheroid within its error bound.
    #[test]
    fn near_tangent_line_at_a_flat_f32_spheroids_equator_touches_it_on_the_surface() {
        let (a, b) = (43_690.0_f32, 2_730.625_f32);
        let s = Spheroid::new(a, b).unwrap();
        let ray = Ray::new(
            [43_690.0_f32, -0.012_319_971, -core::f32::consts::FRAC_PI_6],
            [0.0, 10.0, 0.0],
        )
        .unwrap();
        for c in s.crossings(&ray).iter() {
            let p = ray.at(c.t).map(f64::from);
            let k = f64::from(a) / f64::from(b);
            let r = (p[0] * p[0] + p[1] * p[1] + (p[2] * k) * (p[2] * k)).sqrt();
            // 8 ε S with S the scale (44 km): 2 cm
            assert!(
                (r - f64::from(a)).abs() < 0.03,
                "t {}: {} m off",
                c.t,
                r - f64::from(a)
            );
        }
    }

    /// Sphere roots from the invariants (`a2 = R²`, `pp`, `dd`, `pd`, `ww`) on either side of `near_vertex`. With
    /// `R² = 4`, `‖d‖² = 4` its bound `ε ‖d‖² (‖p‖² + R²)` is about 7.1e-15.
    #[test]
    fn sphere_roots_within_rounding_of_a_tangent_lines_closest_approach_are_the_vertex_plus_minus_half_the_separation()
     {
        // disc = 16 − ww = 2^-48, √disc = 2^-24; 2^-50 is ‖p‖² − R² in the second case.
        let (ww, two_m24, two_m50) = (
            16.0 - 3.552_713_678_800_501e-15,
            5.960_464_477_539_063e-8,
            8.881_784_197_001_252e-16,
        );
        // |⟨p|d⟩| + √disc = 1e-8 + 2^-24, squared 4.8e-15: below the bound. The roots are −⟨p|d⟩/‖d‖² ∓
        // √disc/‖d‖² (the stable formula would give 0 for the first: ‖p‖² − R² is 0 here).
        let pd = -1e-8;
        let (v, h) = (1e-8 / 4.0, 1.490_116_119_384_765_6e-8); // 2^-24 / 4
        let got = sphere_roots_signed(4.0, 4.0, 4.0, pd, ww, -1.0);
        assert_eq!(got, Some((v - h, v + h)));
        assert_eq!(sphere_exit_root_signed(4.0, 4.0, 4.0, pd, ww, -1.0), v + h);
        // |⟨p|d⟩| + √disc = 4e-8 + 2^-24, squared 9.9e-15: above it (|⟨p|d⟩| − √disc would be below, and so
        // would a bound of ε ‖d‖² ‖p‖² R², 1.4e-14). The stable formula: q = −(⟨p|d⟩ − √disc), the entry
        // (‖p‖² − R²)/q, the exit q/‖d‖².
        let (pd, pp) = (-4e-8, 4.0 + two_m50);
        let q = 4e-8 + two_m24;
        let got = sphere_roots_signed(4.0, pp, 4.0, pd, ww, -1.0);
        assert_eq!(got, Some((two_m50 / q, q / 4.0)));
        assert_eq!(sphere_exit_root_signed(4.0, pp, 4.0, pd, ww, -1.0), q / 4.0);
    }
}
