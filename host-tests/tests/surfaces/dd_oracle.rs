//! The kernel's double-double arithmetic (`curvicast::dd`, used to refine terrain hits) against 256-bit
//! astro-float: `sin`/`cos` of angles in degrees given as pairs, and the geodetic → ECEF conversion of a parallel,
//! in `f64` pairs (about 106 bits). Criterion: relative errors below 4e-31 (pair precision is
//! 2⁻¹⁰⁶ ≈ 1.2e-32; each step of the chain adds a few of those; measured worst 3.5e-32).

use astro_float::{BigFloat, Consts};
use curvicast::dd::{Dd, sin_cos_deg};
use curvicast::geodesy::Ellipsoid;
use curvicast::terrain::Parallel;
use curvicast_host::oracle::precise::{self, RM, to_f64, with_consts};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const P: usize = 256;

fn bf(x: f64) -> BigFloat {
    precise::bf(x, P)
}

/// The exact value of a pair.
fn pair(x: Dd<f64>) -> BigFloat {
    bf(x.hi).add(&bf(x.lo), P, RM)
}

/// `|x − want|` in f64.
fn err(x: Dd<f64>, want: &BigFloat) -> f64 {
    to_f64(&pair(x).sub(want, P, RM)).abs()
}

/// 256-bit sin and cos of an angle in degrees.
fn sin_cos_exact(deg: &BigFloat, cc: &mut Consts) -> (BigFloat, BigFloat) {
    let rad = deg.mul(&cc.pi(P, RM), P, RM).div(&bf(180.0), P, RM);
    (rad.sin(P, RM, cc), rad.cos(P, RM, cc))
}

/// A random pair: `hi` uniform in `[lo_deg, hi_deg]`, `lo` a random fraction of half an ulp of `hi`.
fn random_pair(r: &mut ChaCha8Rng, lo_deg: f64, hi_deg: f64) -> Dd<f64> {
    let hi: f64 = r.random_range(lo_deg..hi_deg);
    let half_ulp = f64::EPSILON * hi.abs() * 0.5;
    Dd::new(hi, r.random_range(-0.99..0.99) * half_ulp)
}

#[test]
fn pair_sin_cos_of_degrees_within_a_few_1e_30() {
    let mut r = ChaCha8Rng::seed_from_u64(17);
    let mut worst = 0.0_f64;
    for k in 0..3000 {
        let x = match k % 3 {
            0 => random_pair(&mut r, -400.0, 400.0),
            1 => random_pair(&mut r, -1e-3, 1e-3),
            // Within 1e-6° of a multiple of 45° (the ends of the Taylor range and the quadrant switches).
            _ => {
                let m = f64::from(r.random_range(-8..=8_i32)) * 45.0;
                Dd::from(m).plus(random_pair(&mut r, -1e-6, 1e-6))
            }
        };
        let (s, c) = sin_cos_deg(x);
        let (se, ce) = with_consts(|cc| sin_cos_exact(&pair(x), cc));
        // Relative to the value, down to 1e-3 (below that, the absolute error of the small value itself is
        // what matters: relative to its own size, measured by the second entry of the sample set).
        let rel = |e: f64, v: &BigFloat| e / to_f64(v).abs().max(1e-12);
        let (es, ec) = (rel(err(s, &se), &se), rel(err(c, &ce), &ce));
        assert!(es <= 4e-31 && ec <= 4e-31, "{x:?}: sin {es:e}, cos {ec:e}");
        worst = worst.max(es).max(ec);
    }
    eprintln!("pair sin/cos: worst relative error {worst:.3e}");
    // Multiples of 90° are exact.
    for m in [
        -360.0, -270.0, -180.0, -90.0, 0.0, 90.0, 180.0, 270.0, 360.0, 720.0,
    ] {
        let (s, c) = sin_cos_deg(Dd::from(m));
        let (se, ce) = with_consts(|cc| sin_cos_exact(&bf(m), cc));
        assert!(err(s, &se) < 1e-60 && err(c, &ce) < 1e-60, "{m}°");
    }
}

#[test]
fn pair_ecef_of_grid_vertices_within_a_few_1e_30() {
    let e = Ellipsoid::<f64>::wgs84();
    let (a, b) = (bf(e.a()), bf(e.b()));
    let (a2, b2) = (a.mul(&a, P, RM), b.mul(&b, P, RM));
    let mut r = ChaCha8Rng::seed_from_u64(23);
    let mut worst = 0.0_f64;
    for _ in 0..2000 {
        let lat = random_pair(&mut r, -90.0, 90.0);
        let lon = random_pair(&mut r, -180.0, 540.0);
        let h: f64 = f64::from(r.random_range(-11_000.0..9_000.0_f32));
        let (sl, cl) = sin_cos_deg(lon);
        let p = Parallel::new(&e, lat).ecef(sl, cl, h);
        // Exact: N = a²/D, D = sqrt(a² cos²φ + b² sin²φ); X = (N + h) cosφ cosλ, …, Z = (N b²/a² + h) sinφ.
        let (sp, cp) = with_consts(|cc| sin_cos_exact(&pair(lat), cc));
        let (so, co) = with_consts(|cc| sin_cos_exact(&pair(lon), cc));
        let d = a2
            .mul(&cp.mul(&cp, P, RM), P, RM)
            .add(&b2.mul(&sp.mul(&sp, P, RM), P, RM), P, RM)
            .sqrt(P, RM);
        let hb = bf(h);
        let rho = a2.div(&d, P, RM).add(&hb, P, RM).mul(&cp, P, RM);
        let want = [
            rho.mul(&co, P, RM),
            rho.mul(&so, P, RM),
            b2.div(&d, P, RM).add(&hb, P, RM).mul(&sp, P, RM),
        ];
        let scale = 6.4e6;
        let rel = (0..3)
            .map(|k| err(p[k], &want[k]) / scale)
            .fold(0.0, f64::max);
        assert!(rel <= 4e-31, "lat {lat:?} lon {lon:?} h {h}: {rel:e}");
        worst = worst.max(rel);
    }
    eprintln!("pair ECEF: worst error {worst:.3e} of the Earth radius");
}
