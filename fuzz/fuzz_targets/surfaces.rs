//! Fuzz target `surfaces`: every solver of `curvicast::surface` (spheroid, axial cone, half-plane, plane z = c)
//! on arbitrary parameters and rays, in `f64`, `f32` and the fast-math `f32`.
//!
//! Checked on every input:
//! * nothing panics (libFuzzer reports a panic as a crash);
//! * constructors accept exactly the valid input (finite, non-zero direction, a sorted interval, `a >= b > 0`,
//!   `0 <= θ <= π`, ...) and reject the rest;
//! * no NaN comes out of valid input; every crossing lies in `[t_min, t_max]`; crossings are sorted; two crossings
//!   enter opposite sides; a plane or half-plane is crossed at most once.
//!
//! Checked where the input is well scaled (no overflow or underflow is possible inside the solver), against a
//! re-evaluation in double-double arithmetic that shares no code with the kernel:
//! * **backward error**: each returned point `p + t d` lies within `K·ε·S` of the surface (distance estimated as
//!   `|F| / |∇F|` of the surface's implicit equation, evaluated to ~106 bits), S the scale of the problem;
//!   on the cone it also lies on the cone's own nappe, on the half-plane on its own half;
//! * **count and sides** where the answer is well conditioned: for the plane, half-plane and spheroid, a root that
//!   lies clearly inside the interval (and, for a spheroid, a line that clearly cuts it: its closest approach is
//!   inside by more than the backward-error scale ε·S as well as by a relative margin) must be reported, with the
//!   right side, and one clearly outside must not.

#![no_main]

use arbitrary::Arbitrary;
use curvicast::F32Fast;
use curvicast::Real;
use curvicast::ray::Ray;
use curvicast::surface::{AxialCone, Crossings, HalfPlane, PlaneZ, Side, Spheroid, Surface};
use libfuzzer_sys::fuzz_target;

/// A number: raw bits (NaN, ±∞, subnormals, anything), a dyadic rational `m·2^e` (which makes exact geometry —
/// tangent rays, rays through an apex or along the axis, rays lying in a plane — likely), or a rational multiple
/// of π (right angles, 45° cones, ...).
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Num {
    Raw(f64),
    Dyadic(i16, i8),
    PiFrac(i8, u8),
}

impl Num {
    fn get(self) -> f64 {
        match self {
            Num::Raw(x) => x,
            Num::Dyadic(m, e) => f64::from(m) * 2f64.powi(i32::from(e)),
            Num::PiFrac(m, n) => core::f64::consts::PI * f64::from(m) / f64::from(n.max(1)),
        }
    }
}

#[derive(Arbitrary, Debug)]
enum Shape {
    /// `Spheroid::new(a, b)`.
    Spheroid(Num, Num),
    /// `AxialCone::from_zenith_rad(apex_z, theta)`.
    Cone(Num, Num),
    /// `HalfPlane::from_azimuth_rad(phi)`.
    HalfPlane(Num),
    /// `PlaneZ::new(c)`.
    PlaneZ(Num),
}

#[derive(Arbitrary, Debug)]
struct Input {
    shape: Shape,
    origin: [Num; 3],
    dir: [Num; 3],
    /// `(t_min, t_max)`; `None` is `[0, +∞)`.
    interval: Option<(Num, Num)>,
}

fuzz_target!(|input: Input| {
    run::<f64>(&input, 32.0, 100);
    run::<f32>(&input, 32.0, 20);
    // The fast backend: the same arithmetic with a few-ulp sqrt; its surfaces are checked as built (their own
    // cos/sin), so only the solver's error counts.
    run::<F32Fast>(&input, 128.0, 20);
});

// ---------------------------------------------------------------------------------------------------------------
// Double-double arithmetic (~106 bits), for the independent re-evaluation.

#[derive(Clone, Copy, Debug)]
struct Dd {
    hi: f64,
    lo: f64,
}

impl Dd {
    fn n(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }
    fn two_sum(a: f64, b: f64) -> Dd {
        let s = a + b;
        let bb = s - a;
        Dd {
            hi: s,
            lo: (a - (s - bb)) + (b - bb),
        }
    }
    fn fast_two_sum(a: f64, b: f64) -> Dd {
        let s = a + b;
        Dd {
            hi: s,
            lo: b - (s - a),
        }
    }
    fn add(self, o: Dd) -> Dd {
        let s = Dd::two_sum(self.hi, o.hi);
        let t = Dd::two_sum(self.lo, o.lo);
        let v = Dd::fast_two_sum(s.hi, s.lo + t.hi);
        Dd::fast_two_sum(v.hi, v.lo + t.lo)
    }
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
    fn sub(self, o: Dd) -> Dd {
        self.add(o.neg())
    }
    fn mul(self, o: Dd) -> Dd {
        let p = self.hi * o.hi;
        let e = self.hi.mul_add(o.hi, -p) + (self.hi * o.lo + self.lo * o.hi);
        Dd::fast_two_sum(p, e)
    }
    fn div(self, o: Dd) -> Dd {
        let q1 = self.hi / o.hi;
        let r = self.sub(o.mul(Dd::n(q1)));
        let q2 = r.hi / o.hi;
        Dd::fast_two_sum(q1, q2)
    }
    fn f(self) -> f64 {
        self.hi + self.lo
    }
}

type V = [Dd; 3];

fn dot(a: V, b: V) -> Dd {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

fn cross(a: V, b: V) -> V {
    [
        a[1].mul(b[2]).sub(a[2].mul(b[1])),
        a[2].mul(b[0]).sub(a[0].mul(b[2])),
        a[0].mul(b[1]).sub(a[1].mul(b[0])),
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn dv(a: [f64; 3]) -> V {
    a.map(Dd::n)
}

// ---------------------------------------------------------------------------------------------------------------

/// The surface built in precision `T`, with its parameters read back as `f64` (exact).
enum Built<T: Real> {
    Spheroid(Spheroid<T>, f64, f64),
    Cone(AxialCone<T>, f64, f64, f64),
    HalfPlane(HalfPlane<T>, f64, f64),
    PlaneZ(PlaneZ<T>, f64),
}

fn finite(x: f64) -> bool {
    x.is_finite()
}

/// True when every non-zero magnitude is within `[2^-l, 2^l]`: no intermediate of the solver can overflow or
/// underflow, so the error bound applies.
fn well_scaled(xs: &[f64], l: i32) -> bool {
    let (lo, hi) = (2f64.powi(-l), 2f64.powi(l));
    xs.iter()
        .all(|&x| x == 0.0 || (x.abs() >= lo && x.abs() <= hi))
}

fn run<T: Real>(input: &Input, k_tol: f64, l: i32) {
    let eps = T::EPSILON.to_f64();
    // Inputs as the kernel sees them (rounded to T), and those same values exactly as f64.
    let r = |n: Num| T::from_f64(n.get());
    let o = input.origin.map(r);
    let d = input.dir.map(r);
    let of = o.map(T::to_f64);
    let df = d.map(T::to_f64);

    let ray = Ray::new(o, d);
    let valid_ray = of.iter().chain(df.iter()).all(|&x| finite(x)) && df.iter().any(|&x| x != 0.0);
    assert_eq!(ray.is_ok(), valid_ray, "Ray::new({of:?}, {df:?}) = {ray:?}");
    let Ok(mut ray) = ray else { return };
    if let Some((a, b)) = input.interval {
        let (a, b) = (r(a), r(b));
        let (af, bf) = (a.to_f64(), b.to_f64());
        let valid = !af.is_nan()
            && !bf.is_nan()
            && af <= bf
            && af < f64::INFINITY
            && bf > f64::NEG_INFINITY;
        match ray.with_interval(a, b) {
            Ok(rr) => {
                assert!(valid, "with_interval({af}, {bf}) accepted");
                ray = rr;
            }
            Err(_) => {
                assert!(!valid, "with_interval({af}, {bf}) rejected");
                return;
            }
        }
    }
    let (t_min, t_max) = (ray.t_min().to_f64(), ray.t_max().to_f64());

    let built: Built<T> = match input.shape {
        Shape::Spheroid(a, b) => {
            let (a, b) = (r(a), r(b));
            let (af, bf) = (a.to_f64(), b.to_f64());
            let s = Spheroid::new(a, b);
            // a² must not overflow or vanish in T either.
            let valid = finite(af) && finite(bf) && bf > 0.0 && af >= bf && {
                let a2 = a * a;
                a2.is_finite() && a2 != T::ZERO
            };
            assert_eq!(s.is_ok(), valid, "Spheroid::new({af}, {bf}) = {s:?}");
            let Ok(s) = s else { return };
            Built::Spheroid(s, af, bf)
        }
        Shape::Cone(k, theta) => {
            let (k, theta) = (r(k), r(theta));
            let (kf, thf) = (k.to_f64(), theta.to_f64());
            let c = AxialCone::from_zenith_rad(k, theta);
            let valid = finite(kf) && finite(thf) && (0.0..=T::PI.to_f64()).contains(&thf);
            assert_eq!(
                c.is_ok(),
                valid,
                "AxialCone::from_zenith_rad({kf}, {thf}) = {c:?}"
            );
            let Ok(c) = c else { return };
            let (cf, sf) = (c.cos().to_f64(), c.sin().to_f64());
            assert!(
                sf >= 0.0 && (cf * cf + sf * sf - 1.0).abs() <= 8.0 * eps,
                "cone cos/sin {cf} {sf}"
            );
            Built::Cone(c, kf, cf, sf)
        }
        Shape::HalfPlane(phi) => {
            let phi = r(phi);
            let pf = phi.to_f64();
            let h = HalfPlane::from_azimuth_rad(phi);
            assert_eq!(
                h.is_ok(),
                finite(pf),
                "HalfPlane::from_azimuth_rad({pf}) = {h:?}"
            );
            let Ok(h) = h else { return };
            let (cf, sf) = (h.cos().to_f64(), h.sin().to_f64());
            assert!(
                (cf * cf + sf * sf - 1.0).abs() <= 8.0 * eps,
                "half-plane cos/sin {cf} {sf}"
            );
            Built::HalfPlane(h, cf, sf)
        }
        Shape::PlaneZ(c) => {
            let c = r(c);
            let cf = c.to_f64();
            let p = PlaneZ::new(c);
            assert_eq!(p.is_ok(), finite(cf), "PlaneZ::new({cf}) = {p:?}");
            let Ok(p) = p else { return };
            Built::PlaneZ(p, cf)
        }
    };

    let xs: Crossings<T> = match &built {
        Built::Spheroid(s, ..) => s.crossings(&ray),
        Built::Cone(c, ..) => c.crossings(&ray),
        Built::HalfPlane(h, ..) => h.crossings(&ray),
        Built::PlaneZ(p, ..) => p.crossings(&ray),
    };
    let ts: Vec<f64> = xs.iter().map(|c| c.t.to_f64()).collect();
    let sides: Vec<Side> = xs.iter().map(|c| c.into).collect();
    let ctx = || {
        format!(
            "{} {ts:?} {sides:?} ray {of:?} + t {df:?} in [{t_min}, {t_max}]",
            T::NAME
        )
    };

    // Invariants on every valid input.
    for &t in &ts {
        assert!(!t.is_nan(), "NaN crossing: {}", ctx());
        assert!(
            t_min <= t && t <= t_max,
            "crossing outside the interval: {}",
            ctx()
        );
    }
    if ts.len() == 2 {
        assert!(ts[0] <= ts[1], "unsorted: {}", ctx());
        assert_ne!(
            sides[0],
            sides[1],
            "two crossings into the same side: {}",
            ctx()
        );
    }
    if matches!(built, Built::HalfPlane(..) | Built::PlaneZ(..)) {
        assert!(ts.len() <= 1, "a plane crossed twice: {}", ctx());
    }

    // Independent re-evaluation, where the input is well scaled.
    let params: Vec<f64> = match &built {
        Built::Spheroid(_, a, b) => vec![*a, *b],
        // cos and sin multiply the coordinates (and are squared by the cone's solver): a tiny one (an angle within
        // 1e-30 of a multiple of π/2) underflows.
        Built::Cone(_, k, c, s) => vec![*k, *c, *s],
        Built::HalfPlane(_, c, s) => vec![*c, *s],
        Built::PlaneZ(_, c) => vec![*c],
    };
    let scalars: Vec<f64> = of
        .iter()
        .chain(df.iter())
        .chain(params.iter())
        .copied()
        .collect();
    if !well_scaled(&scalars, l) || ts.iter().any(|t| !t.is_finite()) {
        return;
    }
    let (p, dvec) = (dv(of), dv(df));
    let point = |t: f64| -> V { [0, 1, 2].map(|i| p[i].add(Dd::n(t).mul(dvec[i]))) };
    let pf = |x: V| x.map(Dd::f);
    let dn = norm(df);

    match built {
        Built::Spheroid(_, a, b) => {
            // The sphere of radius a after scaling z by k = a/b (the kernel's own reduction, Wartell et al. §3.1.2).
            let k = Dd::n(a).div(Dd::n(b));
            let scale = |x: V| [x[0], x[1], x[2].mul(k)];
            let (ps, ds) = (scale(p), scale(dvec));
            let a2 = Dd::n(a).mul(Dd::n(a));
            let big_s0 = norm(pf(ps)).max(a);
            for (i, &t) in ts.iter().enumerate() {
                let x = scale(point(t));
                let g = dot(x, x).sub(a2);
                let nx = norm(pf(x));
                let dist = g.f().abs() / (nx + a);
                let big_s = big_s0.max(nx);
                assert!(
                    dist <= k_tol * eps * big_s,
                    "spheroid crossing {i} is {dist} off (S {big_s}): {}",
                    ctx()
                );
            }
            // Count and sides where the line clearly cuts or clearly misses the spheroid.
            let dd = dot(ds, ds);
            let w = cross(ps, ds);
            let disc = dd.mul(a2).sub(dot(w, w)).f();
            let dd_f = dd.f();
            let rel = disc / (dd_f * a2.f());
            let margin = 1e3 * eps * big_s0 / dd_f.sqrt();
            // "Clearly" also in absolute terms: the closest approach h (scaled space) must differ from a by more
            // than the backward-error scale, or a sphere far smaller than ε·S (seen from 1e30 away) would count.
            let h = (dot(w, w).f() / dd_f).max(0.0).sqrt();
            let clear = 1e3 * eps * big_s0;
            if rel < -1e-6 && h > a + clear {
                assert!(
                    ts.is_empty(),
                    "spheroid: a clear miss reported as a hit: {}",
                    ctx()
                );
            } else if rel > 1e-6 && h < a - clear {
                let pd = dot(ps, ds).f();
                let sq = disc.sqrt();
                let roots = [
                    ((-pd - sq) / dd_f, Side::Negative),
                    ((-pd + sq) / dd_f, Side::Positive),
                ];
                expect_roots(&roots, margin, t_min, t_max, &ts, &sides, &ctx);
            }
        }
        Built::Cone(_, kz, c, s) => {
            // Distance from q (relative to the apex) to the double cone, exactly: |q| sin Δ, Δ the angle between
            // q and the nearest generator (capped at π/2, where the apex is nearest). The point is evaluated in
            // double-double; the angles in f64 (absolute error a few ε, i.e. a few ε·|q| of distance).
            let theta = s.atan2(c);
            let big_s0 = norm(of).max(kz.abs());
            for (i, &t) in ts.iter().enumerate() {
                let x = point(t);
                let q = [x[0], x[1], x[2].sub(Dd::n(kz))];
                let rho = q[0].mul(q[0]).add(q[1].mul(q[1])).f().sqrt();
                let qz = q[2].f();
                let qn = norm(pf(q));
                let theta_q = rho.atan2(qz);
                let half_pi = core::f64::consts::FRAC_PI_2;
                let delta = (theta_q - theta)
                    .abs()
                    .min((theta_q - (core::f64::consts::PI - theta)).abs())
                    .min(half_pi);
                let dist = qn * delta.sin();
                let big_s = big_s0.max(norm(pf(x))).max(qn);
                let tol = k_tol * eps * big_s;
                assert!(
                    dist <= tol,
                    "cone crossing {i} is {dist} off (S {big_s}, tol {tol}): {}",
                    ctx()
                );
                if c != 0.0 {
                    assert!(
                        qz * c.signum() >= -tol,
                        "cone crossing {i} on the wrong nappe (z - k = {qz}): {}",
                        ctx()
                    );
                }
            }
        }
        Built::HalfPlane(_, c, s) => {
            let (cd, sd) = (Dd::n(c), Dd::n(s));
            let normal_dot = |v: V| cd.mul(v[1]).sub(sd.mul(v[0]));
            let along = |v: V| cd.mul(v[0]).add(sd.mul(v[1]));
            let big_s0 = norm(of);
            for (i, &t) in ts.iter().enumerate() {
                let x = point(t);
                let dist = normal_dot(x).f().abs();
                let big_s = big_s0.max(norm(pf(x)));
                let tol = k_tol * eps * big_s;
                assert!(
                    dist <= tol,
                    "half-plane crossing {i} is {dist} off (S {big_s}): {}",
                    ctx()
                );
                // Which half is a forward error: along the plane, the point's error is the backward error
                // divided by the sine of the angle between ray and plane.
                let sin_angle = normal_dot(dvec).f().abs() / dn;
                let a = along(x).f();
                assert!(
                    a >= -tol / sin_angle,
                    "half-plane crossing {i} on the other half ({a}, sin angle {sin_angle}): {}",
                    ctx()
                );
            }
            let nd = normal_dot(dvec).f();
            if nd.abs() >= 1e-3 * dn {
                let t_star = normal_dot(p).neg().f() / nd;
                let a_star = along(point(t_star)).f();
                let side = if nd > 0.0 {
                    Side::Positive
                } else {
                    Side::Negative
                };
                let margin = 1e3 * eps * big_s0.max(t_star.abs() * dn);
                if a_star < -margin {
                    assert!(
                        ts.is_empty(),
                        "half-plane: the other half reported as a crossing: {}",
                        ctx()
                    );
                } else if a_star > margin {
                    expect_roots(
                        &[(t_star, side)],
                        margin / nd.abs(),
                        t_min,
                        t_max,
                        &ts,
                        &sides,
                        &ctx,
                    );
                }
            }
        }
        Built::PlaneZ(_, cz) => {
            let big_s0 = norm(of).max(cz.abs());
            for (i, &t) in ts.iter().enumerate() {
                let x = point(t);
                let dist = x[2].sub(Dd::n(cz)).f().abs();
                let big_s = big_s0.max(norm(pf(x)));
                assert!(
                    dist <= k_tol * eps * big_s,
                    "plane crossing {i} is {dist} off (S {big_s}): {}",
                    ctx()
                );
            }
            let dz = df[2];
            if dz == 0.0 {
                assert!(
                    ts.is_empty(),
                    "plane: a horizontal ray crossed it: {}",
                    ctx()
                );
            } else if dz.abs() >= 1e-3 * dn {
                let t_star = Dd::n(cz).sub(p[2]).f() / dz;
                let side = if dz > 0.0 {
                    Side::Positive
                } else {
                    Side::Negative
                };
                let margin = 1e3 * eps * big_s0 / dz.abs();
                expect_roots(&[(t_star, side)], margin, t_min, t_max, &ts, &sides, &ctx);
            }
        }
    }
}

/// Compares the kernel's crossings with reference roots (sorted, with the side entered), where each reference
/// root is clearly inside (must be reported) or clearly outside (must not be) `[t_min, t_max]` by `margin`.
/// Skips the comparison when any root is within `margin` of an end.
fn expect_roots(
    roots: &[(f64, Side)],
    margin: f64,
    t_min: f64,
    t_max: f64,
    ts: &[f64],
    sides: &[Side],
    ctx: &dyn Fn() -> String,
) {
    let mut want = Vec::new();
    for &(t, side) in roots {
        let inside = t > t_min + margin && t < t_max - margin;
        let outside = t < t_min - margin || t > t_max + margin;
        if !inside && !outside {
            return;
        }
        if inside {
            want.push((t, side));
        }
    }
    assert_eq!(
        ts.len(),
        want.len(),
        "expected crossings {want:?} (margin {margin}): {}",
        ctx()
    );
    for (i, (&(t, side), (&got_t, &got_side))) in want.iter().zip(ts.iter().zip(sides)).enumerate()
    {
        assert_eq!(got_side, side, "crossing {i}: wrong side: {}", ctx());
        assert!(
            (got_t - t).abs() <= margin,
            "crossing {i}: t = {got_t}, expected {t} ± {margin}: {}",
            ctx()
        );
    }
}
