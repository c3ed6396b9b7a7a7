//! ECEF → geodetic accuracy of the kernel against an independent arbitrary-precision inversion.
//!
//! The reference solves the exact meridian-plane equation in 128-bit arithmetic (astro-float) by Newton's method
//! on the cotangent κ = cot ψ of the latitude, which needs no trigonometry: for `z ≥ 0` the foot of the normal
//! satisfies
//!
//! ```text
//! H(κ) = R − z κ − e² a κ / sqrt(κ² + 1 − e²) = 0,   H'(κ) = −z − e² a (1 − e²) / (κ² + 1 − e²)^{3/2},
//! ```
//!
//! H is decreasing and convex on κ ≥ 0 with `H(0) = R ≥ 0`, so Newton from κ = 0 converges monotonically to the
//! unique root (a plain f64 Newton first, then 128-bit steps). Then `sin ψ = 1/sqrt(1 + κ²)`,
//! `cos ψ = κ/sqrt(1 + κ²)`, `h = R cos ψ + z sin ψ − a sqrt(1 − e² sin²ψ)`.
//!
//! Error measures (GeographicLib's `Geocentric` documents < 7 nm for |h| ≤ 5000 km):
//! * the round trip: the distance between the input point and the point the kernel's (ψ, λ, h) denotes,
//!   evaluated in 128-bit arithmetic (sin/cos of the kernel's angles in high precision);
//! * `|h_kernel − h_reference|`.

use astro_float::{BigFloat, Consts};
use curvicast::geodesy::Ellipsoid;
use curvicast::vec3::V3;
use curvicast_host::oracle::precise::{self, RM, to_f64, with_consts};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

const P: usize = 128;
const A: f64 = 6_378_137.0;
const F: f64 = 1.0 / 298.257_223_563;

fn bf(x: f64) -> BigFloat {
    precise::bf(x, P)
}

/// An `f64` angle in degrees, in radians in 128 bits.
fn deg(x: f64, cc: &mut Consts) -> BigFloat {
    bf(x).mul(&cc.pi(P, RM), P, RM).div(&bf(180.0), P, RM)
}

struct Reference {
    a: BigFloat,
    e2: BigFloat,
    e2m: BigFloat,
}

impl Reference {
    fn wgs84() -> Self {
        // e² = f(2 − f) with f = 1/298.257223563 exactly (the defining value), in 128 bits.
        let f = BigFloat::from_f64(1.0, P).div(&bf(298.257_223_563), P, RM);
        let e2 = f.mul(&bf(2.0).sub(&f, P, RM), P, RM);
        let e2m = bf(1.0).sub(&e2, P, RM);
        Reference { a: bf(A), e2, e2m }
    }

    /// (sin ψ, cos ψ, h) of the point at distance `r ≥ 0` from the axis and height `z`.
    fn solve(&self, r: f64, z: f64) -> (BigFloat, BigFloat, BigFloat) {
        let zs = z.abs();
        // f64 Newton from κ = 0 (monotone), then 128-bit Newton.
        let (a64, e2_64) = (A, F * (2.0 - F));
        let e2m64 = 1.0 - e2_64;
        let mut k = 0.0_f64;
        for _ in 0..200 {
            let q = k * k + e2m64;
            let hv = r - zs * k - e2_64 * a64 * k / q.sqrt();
            let dh = -zs - e2_64 * a64 * e2m64 / (q * q.sqrt());
            let next = k - hv / dh;
            if !next.is_finite() || (next - k).abs() <= 1e-17 * next.abs() {
                k = if next.is_finite() { next } else { k };
                break;
            }
            k = next;
        }
        let (rb, zb) = (bf(r), bf(zs));
        let ea = self.e2.mul(&self.a, P, RM);
        let mut kb = bf(k);
        for _ in 0..4 {
            let q = kb.mul(&kb, P, RM).add(&self.e2m, P, RM);
            let sq = q.sqrt(P, RM);
            let hv =
                rb.sub(&zb.mul(&kb, P, RM), P, RM)
                    .sub(&ea.mul(&kb, P, RM).div(&sq, P, RM), P, RM);
            let dh = zb
                .add(
                    &ea.mul(&self.e2m, P, RM).div(&q.mul(&sq, P, RM), P, RM),
                    P,
                    RM,
                )
                .neg();
            kb = kb.sub(&hv.div(&dh, P, RM), P, RM);
        }
        let one = bf(1.0);
        let norm = one.add(&kb.mul(&kb, P, RM), P, RM).sqrt(P, RM);
        let mut s = one.div(&norm, P, RM);
        let c = kb.div(&norm, P, RM);
        let w = one
            .sub(&self.e2.mul(&s.mul(&s, P, RM), P, RM), P, RM)
            .sqrt(P, RM);
        let h = rb
            .mul(&c, P, RM)
            .add(&zb.mul(&s, P, RM), P, RM)
            .sub(&self.a.mul(&w, P, RM), P, RM);
        if z < 0.0 {
            s = s.neg();
        }
        (s, c, h)
    }

    /// Distance between the input (x, y, z) and the point (ψ, λ, h), angles in radians (128 bits, from the
    /// kernel's `f64` values by [`bf`] or [`deg`]), in 128-bit arithmetic.
    fn round_trip_error(
        &self,
        p: [f64; 3],
        lat: BigFloat,
        lon: BigFloat,
        h: f64,
        cc: &mut Consts,
    ) -> BigFloat {
        let (sl, cl) = (lat.sin(P, RM, cc), lat.cos(P, RM, cc));
        let (so, co) = (lon.sin(P, RM, cc), lon.cos(P, RM, cc));
        let one = bf(1.0);
        let w = one
            .sub(&self.e2.mul(&sl.mul(&sl, P, RM), P, RM), P, RM)
            .sqrt(P, RM);
        let n = self.a.div(&w, P, RM);
        let hb = bf(h);
        let rho = n.add(&hb, P, RM).mul(&cl, P, RM);
        let x = rho.mul(&co, P, RM);
        let y = rho.mul(&so, P, RM);
        let z = n.mul(&self.e2m, P, RM).add(&hb, P, RM).mul(&sl, P, RM);
        let dx = x.sub(&bf(p[0]), P, RM);
        let dy = y.sub(&bf(p[1]), P, RM);
        let dz = z.sub(&bf(p[2]), P, RM);
        dx.mul(&dx, P, RM)
            .add(&dy.mul(&dy, P, RM), P, RM)
            .add(&dz.mul(&dz, P, RM), P, RM)
            .sqrt(P, RM)
    }
}

#[derive(Clone, Copy)]
enum Kind {
    Uniform,
    NearPole,
    ZAxis,
    NearCenter,
}

fn point(kind: Kind, rng: &mut ChaCha8Rng) -> [f64; 3] {
    let e = Ellipsoid::<f64>::wgs84();
    match kind {
        Kind::Uniform => {
            let lat = (rng.random::<f64>() * 2.0 - 1.0).asin();
            let lon = (rng.random::<f64>() * 2.0 - 1.0) * core::f64::consts::PI;
            let h = (rng.random::<f64>() * 2.0 - 1.0) * 5.0e6;
            e.geodetic_rad_to_ecef(lat, lon, h).to_array()
        }
        Kind::NearPole => {
            let eps = 10f64.powf(-rng.random_range(1.0..14.0));
            let lat = (core::f64::consts::FRAC_PI_2 - eps)
                * if rng.random::<bool>() { 1.0 } else { -1.0 };
            let lon = (rng.random::<f64>() * 2.0 - 1.0) * core::f64::consts::PI;
            let h = (rng.random::<f64>() * 2.0 - 1.0) * 5.0e6;
            e.geodetic_rad_to_ecef(lat, lon, h).to_array()
        }
        Kind::ZAxis => {
            let z = (e.b() + (rng.random::<f64>() * 2.0 - 1.0) * 5.0e6)
                * if rng.random::<bool>() { 1.0 } else { -1.0 };
            [0.0, 0.0, z]
        }
        Kind::NearCenter => {
            let s = 10f64.powf(rng.random_range(-3.0..4.0));
            [
                (rng.random::<f64>() * 2.0 - 1.0) * s,
                (rng.random::<f64>() * 2.0 - 1.0) * s,
                (rng.random::<f64>() * 2.0 - 1.0) * s,
            ]
        }
    }
}

/// Max round-trip error and max |Δh| (meters) over `n` points of one kind.
fn measure(kind: Kind, n: usize, seed: u64) -> (f64, f64, [f64; 3]) {
    let chunks: Vec<u64> = (0..16).collect();
    let per = n.div_ceil(16);
    chunks
        .par_iter()
        .map(|&c| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(1000).wrapping_add(c));
            let r = Reference::wgs84();
            let e = Ellipsoid::<f64>::wgs84();
            let mut worst = (0.0_f64, 0.0_f64, [0.0; 3]);
            for _ in 0..per {
                let p = point(kind, &mut rng);
                let g = e.ecef_to_geodetic(V3::from(p));
                assert!(
                    g.lat_rad.is_finite() && g.lon_rad.is_finite() && g.h.is_finite(),
                    "{p:?}"
                );
                let rt = to_f64(&with_consts(|cc| {
                    r.round_trip_error(p, bf(g.lat_rad), bf(g.lon_rad), g.h, cc)
                }));
                let (_, _, h_ref) = r.solve(p[0].hypot(p[1]), p[2]);
                let dh = to_f64(&bf(g.h).sub(&h_ref, P, RM)).abs();
                if rt > worst.0 {
                    worst.2 = p;
                }
                worst.0 = worst.0.max(rt);
                worst.1 = worst.1.max(dh);
            }
            worst
        })
        .reduce(
            || (0.0, 0.0, [0.0; 3]),
            |a, b| {
                if a.0 >= b.0 {
                    (a.0, a.1.max(b.1), a.2)
                } else {
                    (b.0, a.1.max(b.1), b.2)
                }
            },
        )
}

/// GeographicLib's documented bound for the reverse conversion, |h| ≤ 5000 km.
const BOUND: f64 = curvicast_host::tolerances::GEODESY_ROUND_TRIP.bound;

#[test]
fn reverse_uniform_points_heights_within_5000_km() {
    let (rt, dh, at) = measure(Kind::Uniform, 80_000, 1);
    println!("uniform: max round-trip error {rt:.3e} m, max |dh| {dh:.3e} m (at {at:?})");
    assert!(
        rt < BOUND && dh < BOUND,
        "round trip {rt:e}, dh {dh:e} at {at:?}"
    );
}

#[test]
fn reverse_points_near_the_poles() {
    let (rt, dh, at) = measure(Kind::NearPole, 16_000, 2);
    println!("near poles: max round-trip error {rt:.3e} m, max |dh| {dh:.3e} m (at {at:?})");
    assert!(
        rt < BOUND && dh < BOUND,
        "round trip {rt:e}, dh {dh:e} at {at:?}"
    );
}

#[test]
fn reverse_points_on_the_z_axis() {
    let (rt, dh, at) = measure(Kind::ZAxis, 4_000, 3);
    println!("z axis: max round-trip error {rt:.3e} m, max |dh| {dh:.3e} m (at {at:?})");
    assert!(
        rt < BOUND && dh < BOUND,
        "round trip {rt:e}, dh {dh:e} at {at:?}"
    );
}

#[test]
fn reverse_points_near_the_center() {
    // Heights near −b here (beyond GeographicLib's ±5000 km range): the same bound is asserted.
    let (rt, dh, at) = measure(Kind::NearCenter, 4_000, 4);
    println!("near center: max round-trip error {rt:.3e} m, max |dh| {dh:.3e} m (at {at:?})");
    assert!(
        rt < BOUND && dh < BOUND,
        "round trip {rt:e}, dh {dh:e} at {at:?}"
    );
}

/// [`Ellipsoid::ecef_to_geodetic_near`], the conversion of terrain hits seeded from a grid vertex: points at
/// terrain heights (−500 m to 9 km) in cells of 1″, 3″, 30″, 1/3° and 1°, seeded from the cell's corner; every
/// tenth point within 0.05° of a pole, every tenth seeded from a longitude written past ±180° (a grid across the
/// antimeridian). The same bound as the closed form; the seed may be declined (the caller then uses the closed
/// form) only for the 1° cells, whose far corners lie beyond its 0.02 rad reach.
#[test]
fn reverse_near_a_seed_vertex_at_terrain_heights() {
    use curvicast::geodesy::sin_cos_deg;
    let spacings = [1.0 / 3600.0, 3.0 / 3600.0, 30.0 / 3600.0, 1.0 / 3.0, 1.0];
    let results: Vec<(f64, f64, usize, usize)> = (0..16u64)
        .into_par_iter()
        .map(|chunk| {
            let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0000 + chunk);
            let r = Reference::wgs84();
            let e = Ellipsoid::<f64>::wgs84();
            let (mut rt_max, mut dh_max, mut declined, mut declined_fine) =
                (0.0_f64, 0.0_f64, 0, 0);
            for k in 0..1500 {
                let d = spacings[k % spacings.len()];
                let lat = if k % 10 == 3 {
                    (90.0 - rng.random::<f64>() * 0.05)
                        * if rng.random::<bool>() { 1.0 } else { -1.0 }
                } else {
                    rng.random_range(-89.0..89.0)
                };
                let lon = rng.random_range(-180.0..180.0);
                let h = rng.random_range(-500.0..9000.0);
                let p = e.geodetic_deg_to_ecef(lat, lon, h).to_array();
                // The cell's corner on the grid of spacing d through (0°, 0°), inside ±90°.
                let lat0 = ((lat / d).floor() * d).clamp(-90.0, 90.0);
                let mut lon0 = (lon / d).floor() * d;
                if k % 10 == 7 {
                    lon0 += if lon0 < 0.0 { 360.0 } else { -360.0 };
                }
                let (sl, cl) = sin_cos_deg(lat0);
                let (so, co) = sin_cos_deg(lon0);
                let Some((glat, glon, gh)) =
                    e.ecef_to_geodetic_near(V3::from(p), (lat0, sl, cl), (lon0, so, co))
                else {
                    declined += 1;
                    if d < 1.0 {
                        declined_fine += 1;
                    }
                    continue;
                };
                assert!(glon > -180.0 && glon <= 180.0, "longitude {glon} for {lon}");
                let rt = to_f64(&with_consts(|cc| {
                    let (lat_r, lon_r) = (deg(glat, cc), deg(glon, cc));
                    r.round_trip_error(p, lat_r, lon_r, gh, cc)
                }));
                let (_, _, h_ref) = r.solve(p[0].hypot(p[1]), p[2]);
                let dh = to_f64(&bf(gh).sub(&h_ref, P, RM)).abs();
                assert!(
                    rt < BOUND && dh < BOUND,
                    "({lat}, {lon}, {h}) seeded at ({lat0}, {lon0}): round trip {rt:e}, dh {dh:e}"
                );
                rt_max = rt_max.max(rt);
                dh_max = dh_max.max(dh);
            }
            (rt_max, dh_max, declined, declined_fine)
        })
        .collect();
    let rt = results.iter().map(|r| r.0).fold(0.0, f64::max);
    let dh = results.iter().map(|r| r.1).fold(0.0, f64::max);
    let declined: usize = results.iter().map(|r| r.2).sum();
    let declined_fine: usize = results.iter().map(|r| r.3).sum();
    println!(
        "seeded: max round-trip error {rt:.3e} m, max |dh| {dh:.3e} m, {declined} of 24000 declined \
         ({declined_fine} in cells under 1°)"
    );
    assert_eq!(declined_fine, 0, "the seed was declined in cells under 1°");
}
