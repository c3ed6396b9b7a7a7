use super::Real;

fn check_basic<T: Real>() {
    assert_eq!(T::from_f64(9.0).sqrt(), T::from_f64(3.0));
    assert_eq!(T::from_f64(-2.5).abs(), T::from_f64(2.5));
    assert!(!T::INFINITY.is_finite());
    assert!(T::NAN.is_nan());
    assert_eq!(T::ONE.scalbn(10), T::from_f64(1024.0));
    assert_eq!(T::from_f64(1000.0).ilogb(), 9);
    assert_eq!(T::from_f64(3.0).min(T::from_f64(-1.0)), T::from_f64(-1.0));
    assert_eq!(T::from_f64(3.0).max(T::NAN), T::from_f64(3.0));
    assert_eq!(
        T::from_f64(2.0).with_sign_of(T::from_f64(-0.1)),
        T::from_f64(-2.0)
    );
}

#[test]
fn f64_basics() {
    check_basic::<f64>();
    assert_eq!(<f64 as Real>::sqrt(2.0), core::f64::consts::SQRT_2);
}

/// The error of `sin_cos_f32` in ulps of the `f32` result, against the double-precision values.
fn sin_cos_f32_ulps(x: f32) -> (f64, f64) {
    let (s, c) = super::sin_cos_f32(x);
    let ulps = |got: f32, want: f64| {
        let w = want as f32;
        let ulp = f64::from(f32::from_bits(w.abs().to_bits() + 1) - w.abs());
        (f64::from(got) - want).abs() / ulp
    };
    let x = f64::from(x);
    (ulps(s, libm::sin(x)), ulps(c, libm::cos(x)))
}

#[test]
fn sin_cos_f32_within_1_05_ulp_on_a_sweep() {
    let mut worst = 0.0_f64;
    // 2¹⁶ points over [−6399, 6399] (2¹⁰ + 1 under Miri), plus the quadrant points and their neighbours.
    let n: u16 = if cfg!(miri) { 1 << 10 } else { u16::MAX };
    let sweep = (0..=n).map(|i| -6399.0 + 12_798.0 * f32::from(i) / f32::from(n));
    let quadrants = (-8..=8).filter(|&k| k != 0).flat_map(|k| {
        let x = k as f32 * core::f32::consts::FRAC_PI_2;
        [
            f32::from_bits(x.to_bits().wrapping_sub(1)),
            x,
            f32::from_bits(x.to_bits() + 1),
        ]
    });
    for x in sweep.chain(quadrants) {
        let (es, ec) = sin_cos_f32_ulps(x);
        assert!(es <= 1.05 && ec <= 1.05, "{x}: {es} / {ec} ulp");
        worst = worst.max(es).max(ec);
    }
    assert!(worst > 0.0, "the sweep must see rounding");
}

#[test]
fn sin_cos_f32_special_values() {
    use super::sin_cos_f32;
    assert_eq!(sin_cos_f32(0.0), (0.0, 1.0));
    assert!(sin_cos_f32(-0.0).0.is_sign_negative());
    for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let (s, c) = sin_cos_f32(x);
        assert!(s.is_nan() && c.is_nan());
    }
    // Huge angles stay on the unit circle (the exact reduction modulo f32's 2π).
    for x in [1e10_f32, -3.0e38, f32::MAX, 7.946_028e28] {
        let (s, c) = sin_cos_f32(x);
        assert!((s * s + c * c - 1.0).abs() <= 4.0 * f32::EPSILON, "{x}");
    }
}

/// Every `f32` in [0, 6400) (about 1.17e9 values; a few minutes in release): the figure quoted in
/// `sin_cos_f32`'s docs (measured: 0.995 ulp for sin at x = 476.74, 1.037 ulp for cos at x = 5643.09). `cargo test --release -p curvicast --lib sin_cos_f32_exhaustive -- --ignored`.
#[test]
#[ignore = "exhaustive over 1.17e9 inputs"]
fn sin_cos_f32_exhaustive_error() {
    let (mut ws, mut wc) = ((0.0_f64, 0.0_f32), (0.0_f64, 0.0_f32));
    let end = 6400.0_f32.to_bits();
    for b in 0..end {
        let x = f32::from_bits(b);
        let (es, ec) = sin_cos_f32_ulps(x);
        if es > ws.0 {
            ws = (es, x);
        }
        if ec > wc.0 {
            wc = (ec, x);
        }
    }
    std::println!("sin_cos_f32 on [0, 6400): max {ws:?} ulp (sin), {wc:?} ulp (cos), (ulp, at x)");
    let (ws, wc) = (ws.0, wc.0);
    assert!(
        ws <= 1.05 && wc <= 1.05,
        "max {ws:.3} ulp (sin), {wc:.3} ulp (cos)"
    );
}

#[test]
fn cbrt_f32_within_1_ulp_on_a_sweep() {
    let mut worst = 0.0_f64;
    // 2¹⁸ bit patterns over every binade (2¹⁰ under Miri), normal and subnormal, both signs.
    let shift = if cfg!(miri) { 22 } else { 14 };
    for i in 0..(1u32 << (32 - shift)) {
        let x = f32::from_bits((i << shift) | (i.wrapping_mul(0x9E37_79B1) >> (32 - shift)));
        if !x.is_finite() {
            continue;
        }
        let got = super::cbrt_f32(x);
        let want = libm::cbrt(f64::from(x));
        let w = want as f32;
        let ulp = f64::from(f32::from_bits(w.abs().to_bits() + 1) - w.abs());
        let err = (f64::from(got) - want).abs() / ulp;
        assert!(
            err <= 1.0,
            "cbrt({x:e}) = {got:e}, want {want:e}: {err} ulp"
        );
        worst = worst.max(err);
    }
    std::println!("cbrt_f32: worst {worst:.3} ulp");
    assert!(worst > 0.0, "the sweep must see rounding");
    assert_eq!(super::cbrt_f32(27.0), 3.0);
    assert_eq!(super::cbrt_f32(-8.0), -2.0);
    assert!(super::cbrt_f32(-0.0).is_sign_negative());
    assert!(super::cbrt_f32(f32::NAN).is_nan());
    assert_eq!(super::cbrt_f32(f32::NEG_INFINITY), f32::NEG_INFINITY);
}

/// `binade` against libm's `ilogb` and `scalbn` (its generic default), on every binade of each type, both
/// ends of each, and the values it must refuse (zero, subnormals, the top binade, negatives, ∞, NaN).
fn check_binade<T: Real>(bits_of: impl Fn(T) -> u64) {
    let reference = |x: T| -> Option<(i32, T)> {
        if !(x >= T::MIN_POSITIVE && x < T::MAX) || x.ilogb() == T::MAX.ilogb() {
            return None;
        }
        Some((x.ilogb(), T::ONE.scalbn(-x.ilogb())))
    };
    let same = |a: Option<(i32, T)>, b: Option<(i32, T)>| match (a, b) {
        (Some((e, x)), Some((f, y))) => e == f && bits_of(x) == bits_of(y),
        (None, None) => true,
        _ => false,
    };
    // Every binade; under Miri every eighth (the same code path, 8 times fewer steps of the interpreter).
    let stride = if cfg!(miri) { 8 } else { 1 };
    let mut x = T::MIN_POSITIVE.scalbn(-20);
    let mut count = 0;
    while x.is_finite() {
        for v in [
            x,
            x * T::from_f64(1.5),
            x * T::TWO * (T::ONE - T::EPSILON),
            -x,
        ] {
            assert!(same(v.binade(), reference(v)), "{}", v.to_f64());
            count += 1;
        }
        x = x.scalbn(stride);
    }
    assert!(count >= 4 * (254 + 20) / stride);
    for v in [
        T::ZERO,
        T::MAX,
        T::INFINITY,
        T::NEG_INFINITY,
        T::NAN,
        T::ONE,
    ] {
        assert!(same(v.binade(), reference(v)), "{}", v.to_f64());
    }
    assert_eq!(T::ONE.binade().map(|(e, _)| e), Some(0));
    assert_eq!(T::MAX.binade(), None);
}

#[test]
fn binade_matches_ilogb_and_scalbn_on_every_binade() {
    check_binade::<f64>(f64::to_bits);
    check_binade::<f32>(|x| u64::from(x.to_bits()));
}

#[test]
fn f32_basics() {
    check_basic::<f32>();
    assert_eq!(<f32 as Real>::sqrt(2.0), core::f32::consts::SQRT_2);
}

#[cfg(feature = "fast-math")]
#[test]
fn f32_fast_is_close_not_exact() {
    use super::F32Fast;
    for x in [2.0_f32, 1e-30, 3.5, 1e30, 0.7] {
        let s = F32Fast(x).sqrt().0;
        let e = libm::sqrtf(x);
        assert!((s - e).abs() <= 4.0 * f32::EPSILON * e, "{x}: {s} vs {e}");
    }
    assert_eq!(F32Fast(0.0).sqrt().0, 0.0);
    assert!(F32Fast(-1.0).sqrt().is_nan());
    assert_eq!(F32Fast(1.5) * F32Fast(2.0), F32Fast(3.0));
}

#[cfg(feature = "fast-math")]
#[test]
fn f32_fast_sin_cos_of_huge_angles_stay_on_the_unit_circle() {
    // Found by the `surfaces` fuzz target: HalfPlane::<F32Fast>::from_azimuth_rad(7.9e28) was rejected as
    // non-finite while micromath's sin/cos (whose argument reduction saturates an i32 cast) were in use.
    // Below 6400 the values are within about an ulp of libm's; above, the `f32` sine and cosine are those of a
    // point within half an ulp of x (an ulp of 1e10 is 1024), so only the unit circle is checked there.
    use super::F32Fast;
    for x in [4096.5_f32, -5000.0, 1e10, -1.4e10, 7.946_028e28, 3.0e38] {
        let (s, c) = (F32Fast(x).sin().0, F32Fast(x).cos().0);
        // F32Fast's sin and cos are the `f32` backend's, bit for bit (their accuracy is tested above).
        assert_eq!(s.to_bits(), super::sin_f32(x).to_bits(), "sin {x}: {s}");
        assert_eq!(c.to_bits(), super::cos_f32(x).to_bits(), "cos {x}: {c}");
        if x.abs() < 6400.0 {
            assert!((s - libm::sinf(x)).abs() <= 2e-6, "sin {x}: {s}");
            assert!((c - libm::cosf(x)).abs() <= 2e-6, "cos {x}: {c}");
        }
        assert!(
            (s * s + c * c - 1.0).abs() <= 4.0 * f32::EPSILON,
            "{x}: {s}, {c}"
        );
    }
    assert!(crate::surface::HalfPlane::from_azimuth_rad(F32Fast(7.946_028e28)).is_ok());
    assert!(F32Fast(f32::INFINITY).sin().is_nan());
}

/// The exact reduction modulo `f32`'s 2π is `fmodf`'s, bit for bit: every binade from 6400 to `f32::MAX`, its
/// ends and multiples of 2π in it, random mantissas, and values below 6400 from 0 up, both signs.
#[test]
fn rem_tau_f32_is_fmodf_bit_for_bit_from_0_to_the_largest_f32() {
    let tau = core::f32::consts::TAU;
    let mut seed = 0x2545_f491_u32;
    let check = |x: f32| {
        for x in [x, -x] {
            let (ours, libm) = (super::rem_tau_f32(x), libm::fmodf(x, tau));
            assert_eq!(
                ours.to_bits(),
                libm.to_bits(),
                "x = {x:e}: {ours:e} against fmodf's {libm:e}"
            );
        }
    };
    check(6400.0);
    check(f32::MAX);
    // below 6400 too (not called there): zero, subnormal, below and at 2π, just above
    for x in [
        0.0,
        f32::from_bits(1),
        f32::MIN_POSITIVE,
        1.0,
        6.0,
        tau,
        6.5,
        12.6,
        100.0,
        6399.0,
    ] {
        check(x);
    }
    for e in 12..=127 {
        let lo = libm::ldexpf(1.0, e);
        check(lo);
        check(f32::from_bits(lo.to_bits() - 1).max(6400.0));
        check(f32::from_bits(lo.to_bits() | 0x007f_ffff));
        // 2π·2^j and its neighbours: remainders 0 and the smallest and largest ones
        let multiple = libm::ldexpf(tau, e - 2);
        for m in [
            multiple,
            f32::from_bits(multiple.to_bits() - 1),
            f32::from_bits(multiple.to_bits() + 1),
        ] {
            if m >= 6400.0 && m.is_finite() {
                check(m);
            }
        }
        // (under Miri, 20 per binade)
        for _ in 0..if cfg!(miri) { 20 } else { 2000 } {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            check(f32::from_bits(lo.to_bits() | (seed & 0x007f_ffff)));
        }
    }
}
