//! Double-double arithmetic in any binary scalar [`Real`]: a value is the unevaluated sum `hi + lo` of two scalars
//! with `|lo| ≤ ulp(hi)/2`, which carries about twice the scalar's precision (106 bits in `f64`, 48 in `f32`).
//!
//! The kernel uses it once per picked ray, to recompute the hit triangle's vertices to far below an ulp
//! ([`crate::terrain`]'s final refinement), so the code favours clarity over speed:
//!
//! * error-free transformations (Knuth's `two_sum`, Dekker's `fast_two_sum`, and Dekker's `two_prod` with Veltkamp
//!   splitting by `2^⌈p/2⌉ + 1`): they need only correctly rounded `+ − ×` (round to nearest), which every
//!   implementor of [`Real`] has, and no fused multiply-add (the fast-math scalar's `mul_add` is not fused, and
//!   a soft `f64` fma on a Cortex-M4F would be slow);
//! * `+ − × ÷ √` on pairs, with relative errors of a few `ε²` (`ε` the scalar's machine epsilon);
//! * [`sin_cos_deg`]: sine and cosine of an angle given in degrees as a pair: reduction modulo 90° in degrees
//!   (exact), conversion to radians by a double-double `π/180`, a Taylor series for the sine on `|x| ≤ π/4` (the
//!   number of terms chosen from `|x|` so that the truncation stays below `ε²/4`), and `cos x = √(1 − sin²x)`,
//!   which is well conditioned there (`cos x ≥ 1/√2`). Multiples of 90° are exact, as in the scalar
//!   `geodesy::sin_cos_deg`.
//!
//! Everything stays in the scalar's own arithmetic: the constants (the series' factors, the table of
//! [`sin_cos_deg`]'s reduction, `π/180`) are written as `f64` pairs and turned into `f32` pairs at compile time, and
//! the reductions round in the scalar, so a pick in `f32` runs no `f64` operation, which a single-precision FPU
//! (a Cortex-M4F) would do in software.
//!
//! Overflow and NaN propagate (a pair with a non-finite `hi` is meaningless); the callers check finiteness of the
//! final result. Products whose low part underflows lose that low part only.
//!
//! ```
//! use curvicast::dd::{Dd, sin_cos_deg};
//! // 0.1 + 0.2 exactly: the pair keeps the rounding error of the f64 sum.
//! let s = Dd::from(0.1_f64).plus(Dd::from(0.2));
//! assert_eq!(s.hi, 0.30000000000000004);
//! assert_eq!(s.lo, -2.7755575615628914e-17);
//! let (sin30, cos30) = sin_cos_deg(Dd::from(30.0_f64));
//! assert!(sin30.minus(Dd::from(0.5)).value().abs() < 1e-32);
//! assert!(cos30.times(cos30).minus(Dd::from(0.75)).value().abs() < 1e-31);
//! ```

use crate::real::Real;

/// A double-double number `hi + lo` (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Dd<T> {
    /// The leading part: the value rounded to the scalar.
    pub hi: T,
    /// The trailing part: `|lo| ≤ ulp(hi)/2`.
    pub lo: T,
}

/// `a + b` exactly, as a normalised pair (Knuth's two-sum; no condition on the magnitudes).
#[inline]
pub fn two_sum<T: Real>(a: T, b: T) -> Dd<T> {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    Dd { hi: s, lo: e }
}

/// `a + b` exactly when `|a| ≥ |b|` or `a = 0` (Dekker's fast two-sum).
#[inline]
fn fast_two_sum<T: Real>(a: T, b: T) -> Dd<T> {
    let s = a + b;
    Dd {
        hi: s,
        lo: b - (s - a),
    }
}

/// Veltkamp's splitting constant `2^⌈p/2⌉ + 1` for a `p`-bit significand.
#[inline]
fn splitter<T: Real>() -> T {
    // The two formats in use as constants (the branch folds at compile time); any other by scaling.
    match T::MANTISSA_DIGITS {
        53 => T::from_f64(134_217_729.0),
        24 => T::from_f64(4097.0),
        p => T::ONE.scalbn(i32::try_from(p.div_ceil(2)).unwrap_or(27)) + T::ONE,
    }
}

/// Splits `a` into `hi + lo` with each part fitting in half the significand, so that products of parts are exact.
#[inline]
fn split<T: Real>(a: T, c: T) -> (T, T) {
    let t = c * a;
    let hi = t - (t - a);
    (hi, a - hi)
}

/// `a · b` exactly, as a normalised pair (Dekker's two-product; exact unless the product overflows or its low part
/// underflows).
#[inline]
pub fn two_prod<T: Real>(a: T, b: T) -> Dd<T> {
    let c = splitter::<T>();
    let p = a * b;
    let (ah, al) = split(a, c);
    let (bh, bl) = split(b, c);
    let e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    Dd { hi: p, lo: e }
}

impl<T: Real> From<T> for Dd<T> {
    #[inline]
    fn from(x: T) -> Self {
        Dd { hi: x, lo: T::ZERO }
    }
}

impl<T: Real> Dd<T> {
    /// The pair `hi + lo`, normalised.
    #[inline]
    pub fn new(hi: T, lo: T) -> Self {
        two_sum(hi, lo)
    }

    /// 1.
    #[inline]
    pub fn one() -> Self {
        Dd::from(T::ONE)
    }

    /// The value rounded to the scalar.
    #[inline]
    pub fn value(self) -> T {
        self.hi + self.lo
    }

    /// `−self`.
    #[inline]
    pub fn negated(self) -> Self {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    /// `self + o` (relative error ≤ 3ε² away from cancellation; the accurate two-sum-based addition).
    #[inline]
    pub fn plus(self, o: Self) -> Self {
        let s = two_sum(self.hi, o.hi);
        let t = two_sum(self.lo, o.lo);
        let s = fast_two_sum(s.hi, s.lo + t.hi);
        fast_two_sum(s.hi, s.lo + t.lo)
    }

    /// `self − o`.
    #[inline]
    pub fn minus(self, o: Self) -> Self {
        self.plus(o.negated())
    }

    /// `self + b` for a scalar `b`.
    #[inline]
    pub fn plus_t(self, b: T) -> Self {
        let s = two_sum(self.hi, b);
        fast_two_sum(s.hi, s.lo + self.lo)
    }

    /// `self · o`.
    #[inline]
    pub fn times(self, o: Self) -> Self {
        let p = two_prod(self.hi, o.hi);
        fast_two_sum(p.hi, p.lo + (self.hi * o.lo + self.lo * o.hi))
    }

    /// `self · b` for a scalar `b`.
    #[inline]
    pub fn times_t(self, b: T) -> Self {
        let p = two_prod(self.hi, b);
        fast_two_sum(p.hi, p.lo + self.lo * b)
    }

    /// `self / o` (three quotient digits; NaN or ±∞ when `o` is 0).
    #[inline]
    pub fn over(self, o: Self) -> Self {
        let q1 = self.hi / o.hi;
        let r = self.minus(o.times_t(q1));
        let q2 = r.hi / o.hi;
        let r = r.minus(o.times_t(q2));
        let q3 = r.hi / o.hi;
        fast_two_sum(q1, q2).plus_t(q3)
    }

    /// `self / b` for a scalar `b`.
    #[inline]
    pub fn over_t(self, b: T) -> Self {
        let q1 = self.hi / b;
        let r = self.minus(two_prod(q1, b));
        let q2 = r.hi / b;
        let r = r.minus(two_prod(q2, b));
        let q3 = r.hi / b;
        fast_two_sum(q1, q2).plus_t(q3)
    }

    /// `√self`: the scalar square root refined by one Newton step `r ← r + (x − r²)/(2r)` in pairs (from a
    /// root with relative error δ the step leaves about δ²/2: pair precision after a correctly rounded root, and
    /// about 2⁻⁴⁴ after the few-ulp fast-math `f32` root). `0` for `0`, NaN for negative values.
    #[inline]
    pub fn sqrt(self) -> Self {
        if !(self.hi > T::ZERO) {
            return Dd::from(self.hi.sqrt());
        }
        let r = self.hi.sqrt();
        let e = self.minus(two_prod(r, r));
        Dd::from(r).plus_t(e.hi / (r + r))
    }
}

/// `π/180` rounded to a pair of `f64`s (leading part, trailing part).
const RAD_PER_DEG: (f64, f64) = (1.745_329_251_994_329_5e-2, 2.948_652_270_870_168_7e-19);

/// A constant given as a pair of `f64`s, as a pair of `f32`s: leading part the `f32` rounding of the value,
/// trailing part the rest rounded, accurate to about `2⁻⁴⁸` relative. Evaluated at compile time (the tables
/// below), so that an `f32` program converts no `f64` at run time (software on a single-precision FPU).
const fn f32_pair((hi64, lo64): (f64, f64)) -> (f32, f32) {
    #[allow(clippy::cast_possible_truncation)]
    let hi = hi64 as f32;
    #[allow(clippy::cast_possible_truncation)]
    let lo = ((hi64 - hi as f64) + lo64) as f32;
    (hi, lo)
}

/// [`f32_pair`] of every entry of a table (at compile time).
// Const evaluation: an index out of range would be a compile error, and `i < N` holds.
#[allow(clippy::indexing_slicing, clippy::arithmetic_side_effects)]
const fn f32_pairs<const N: usize, const M: usize>(
    t: [[(f64, f64); M]; N],
) -> [[(f32, f32); M]; N] {
    let mut out = [[(0.0_f32, 0.0_f32); M]; N];
    let mut i = 0;
    while i < N {
        let mut j = 0;
        while j < M {
            out[i][j] = f32_pair(t[i][j]);
            j += 1;
        }
        i += 1;
    }
    out
}

/// A constant as a pair of scalars, from its `f64` pair and its `f32` pair ([`f32_pair`]): the `f32` pair for
/// a single-precision scalar (the choice folds at compile time), else the `f64` pair rounded.
#[inline]
fn pair_of<T: Real>((hi64, lo64): (f64, f64), (hi32, lo32): (f32, f32)) -> Dd<T> {
    if T::MANTISSA_DIGITS == f32::MANTISSA_DIGITS {
        return Dd {
            hi: T::from_f32(hi32),
            lo: T::from_f32(lo32),
        };
    }
    let hi = T::from_f64(hi64);
    let lo = T::from_f64((hi64 - hi.to_f64()) + lo64);
    Dd { hi, lo }
}

/// [`RAD_PER_DEG`] as `f32`s.
const RAD_PER_DEG_F32: (f32, f32) = f32_pair(RAD_PER_DEG);

/// The Horner factors `1/((2k)(2k+1))`, `k = 1, 2, …`, of the sine's Taylor series, as `f64` pairs.
const SIN_STEPS: [(f64, f64); 18] = [
    (0.16666666666666666, 9.25185853854297e-18),
    (0.05, -2.7755575615628915e-18),
    (0.023809523809523808, 1.32169407693471e-18),
    (0.013888888888888888, 7.709882115452476e-19),
    (0.00909090909090909, 4.415659757031872e-19),
    (0.00641025641025641, 2.2240044563805217e-19),
    (0.004761904761904762, -4.295505750037808e-19),
    (0.003676470588235294, 5.102127870520021e-20),
    (0.0029239766081871343, 1.6231330769373633e-19),
    (0.002380952380952381, -2.147752875018904e-19),
    (0.001976284584980237, 1.3370398332627564e-19),
    (0.0016666666666666668, -1.0697461435190311e-19),
    (0.0014245014245014246, -7.104458680104445e-20),
    (0.0012315270935960591, -1.3886333243656708e-20),
    (0.001075268817204301, 9.326470300950576e-22),
    (0.000946969696969697, -2.6283689029951623e-20),
    (0.0008403361344537816, -5.029240329512592e-20),
    (0.0007507507507507507, 6.511724759672699e-21),
];

/// [`SIN_STEPS`] as `f32` pairs.
const SIN_STEPS_F32: [[(f32, f32); 18]; 1] = f32_pairs([SIN_STEPS]);

/// The `k`-th Horner factor of [`SIN_STEPS`] (`k ≥ 1`; 0 beyond the table) as a pair of scalars.
#[inline]
fn sin_step<T: Real>(k: u32) -> Dd<T> {
    let i = usize::try_from(k).unwrap_or(0).saturating_sub(1);
    match (SIN_STEPS.get(i), SIN_STEPS_F32[0].get(i)) {
        (Some(&p64), Some(&p32)) => pair_of(p64, p32),
        _ => Dd::from(T::ZERO),
    }
}

/// The most Taylor terms of [`sin_cos_deg`] (the `f64` pair needs 14 at `|x| = π/4`).
const MAX_TERMS: u32 = 18;

/// `(sin k/16, cos k/16)`, `k = 0, …, 13`, as `f64` pairs: the table of [`sin_cos_small`]'s reduction.
const SIXTEENTHS: [[(f64, f64); 2]; 14] = [
    [(0.0, 0.0), (1.0, 0.0)],
    [
        (0.0624593178423802, -2.040259504585711e-18),
        (0.9980475107000991, 3.3232291674141346e-17),
    ],
    [
        (0.12467473338522769, -2.925947496057858e-18),
        (0.992197667229329, 4.754870575189364e-17),
    ],
    [
        (0.18640329676226988, 2.3493796901281573e-18),
        (0.9824733131012553, -3.919920375420088e-17),
    ],
    [
        (0.24740395925452294, -7.53102495590706e-18),
        (0.9689124217106447, 5.071436662403936e-17),
    ],
    [
        (0.30743851458038085, 1.1004366442765296e-19),
        (0.9515679480481722, -3.8614834675674123e-17),
    ],
    [
        (0.36627252908604757, -9.938814562106524e-18),
        (0.9305076219123143, 4.488760003328074e-18),
    ],
    [
        (0.42367625720393803, -2.331800700068871e-17),
        (0.9058136834259364, 4.2864666490805214e-17),
    ],
    [
        (0.479425538604203, -5.103969860556013e-18),
        (0.8775825618903728, -4.2623149864279997e-17),
    ],
    [
        (0.5333026735360201, 5.129318115032044e-17),
        (0.8459244992310679, 1.549506647350329e-17),
    ],
    [
        (0.5850972729404622, -5.4883972461161805e-17),
        (0.8109631195052179, -3.091333486122179e-17),
    ],
    [
        (0.6346070800152693, -3.4568582392624965e-17),
        (0.7728349461524715, 4.231014921891023e-17),
    ],
    [
        (0.6816387600233341, 4.410467313197903e-17),
        (0.7316888688738209, -1.0475824306512768e-17),
    ],
    [
        (0.7260086552607126, -1.573621815339587e-17),
        (0.6876855622205048, 3.5430696752823923e-17),
    ],
];

/// [`SIXTEENTHS`] as `f32` pairs.
const SIXTEENTHS_F32: [[(f32, f32); 2]; 14] = f32_pairs(SIXTEENTHS);

/// `(sin x, cos x)` for `|x| ≤ π/4` (a little more is harmless): `x = k/16 + y` with `|y| ≤ 1/32`, the
/// tabulated `(sin, cos)(k/16)` rotated by [`sin_cos_taylor`]`(y)` (three pair levels instead of seven).
fn sin_cos_small<T: Real>(x: Dd<T>) -> (Dd<T>, Dd<T>) {
    let sixteen = T::from_i32(16);
    let kf = (x.hi * sixteen).round();
    // |kf| ≤ 13 for |x| ≤ π/4 (anything else falls back to the plain series, which converges for any x); the
    // index is found by comparison, so that no conversion leaves the scalar.
    let index =
        (1..SIXTEENTHS.len()).find(|&i| T::from_i32(i32::try_from(i).unwrap_or(0)) == kf.abs());
    let entry = index.and_then(|i| Some((*SIXTEENTHS.get(i)?, *SIXTEENTHS_F32.get(i)?)));
    match entry {
        Some(([st, ct], [st32, ct32])) => {
            let y = x.minus(Dd::from(kf / sixteen));
            let st = pair_of::<T>(st, st32);
            let st = if kf < T::ZERO { st.negated() } else { st };
            rotate((st, pair_of(ct, ct32)), sin_cos_taylor(y))
        }
        None => sin_cos_taylor(x),
    }
}

/// `(sin x, cos x)` by the Taylor series (any `x`; used for `|x| ≤ π/4`, mostly `|x| ≤ 1/32`).
///
/// Horner's scheme `sin x = x (1 − x²/(2·3) (1 − x²/(4·5) (1 − …)))`. The inner levels whose term
/// `x^{2k}/(2k+1)!` is below `ε` are summed in plain scalars, as the small difference `u_k = acc_k − 1` (their
/// rounding, `ε |u_k|`, reaches the result scaled by the term: below `ε²`); the outer levels in pairs.
fn sin_cos_taylor<T: Real>(x: Dd<T>) -> (Dd<T>, Dd<T>) {
    let x2 = x.times(x);
    // Levels: keep k ≤ K with x^{2K}/(2K+1)! ≥ ε²/4 (the first omitted term is below that, relative to x);
    // levels from `k_pair` on (term below ε) in scalars.
    let eps = T::EPSILON;
    let tol = T::from_f64(0.25) * eps * eps;
    let mut term = T::ONE;
    let mut k_max = MAX_TERMS;
    let mut k_pair = MAX_TERMS;
    for k in 1..=MAX_TERMS {
        term *= x2.hi * sin_step::<T>(k).hi;
        if term < eps && k_pair == MAX_TERMS {
            k_pair = k;
        }
        if !(term >= tol) {
            k_max = k;
            break;
        }
    }
    let mut u = T::ZERO;
    for k in (k_pair..=k_max).rev() {
        let c = sin_step::<T>(k).hi;
        u = -(x2.hi * c) * (T::ONE + u);
    }
    let mut acc = Dd::one().plus_t(u);
    for k in (1..k_pair.min(k_max.saturating_add(1))).rev() {
        let c = sin_step(k);
        acc = Dd::one().minus(x2.times(c).times(acc));
    }
    let s = x.times(acc);
    let c = Dd::one().minus(s.times(s)).sqrt();
    (s, c)
}

/// `(sin(x + δ), cos(x + δ))` from `(sin x, cos x)` and `(sin δ, cos δ)` (angle addition; absolute error a few
/// `ε²`).
#[inline]
pub fn rotate<T: Real>((s, c): (Dd<T>, Dd<T>), (sd, cd): (Dd<T>, Dd<T>)) -> (Dd<T>, Dd<T>) {
    (
        s.times(cd).plus(c.times(sd)),
        c.times(cd).minus(s.times(sd)),
    )
}

/// `(sin x, cos x)` of an angle `x` in degrees, as pairs, with relative errors of a few `ε²` (module docs).
/// Multiples of 90° are exact (`sin_cos_deg(90°) = (1, 0)`), so a pole row lies exactly on the z axis. Non-finite
/// input gives NaN.
pub fn sin_cos_deg<T: Real>(deg: Dd<T>) -> (Dd<T>, Dd<T>) {
    let nan = Dd::from(T::NAN);
    if !deg.hi.is_finite() || !deg.lo.is_finite() {
        return (nan, nan);
    }
    // Nearest multiple of 90°; `r = deg − 90 q` is exact for any grid angle (while `90 q` is exact: |deg| up to
    // about 1e7 degrees in f32). Everything in the scalar's own arithmetic.
    let ninety = T::from_i32(90);
    let q = (deg.hi / ninety).round();
    let r = deg.minus(Dd::from(q * ninety));
    let (s, c) = sin_cos_small(r.times(pair_of(RAD_PER_DEG, RAD_PER_DEG_F32)));
    // q mod 4: q − 4 round(q/4) is exact, an integer in [−2, 2].
    let four = T::from_i32(4);
    let q4 = q - four * (q / four).round();
    let half = T::HALF;
    // 0: (s, c); 1 (or −3): (c, −s); ±2: (−s, −c); −1 (or 3): (−c, s).
    if q4.abs() < half {
        (s, c)
    } else if (q4 - T::ONE).abs() < half {
        (c, s.negated())
    } else if (q4 + T::ONE).abs() < half {
        (c.negated(), s)
    } else {
        (s.negated(), c.negated())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_free_transformations() {
        let s = two_sum(1.0_f64, 1e-20);
        assert_eq!((s.hi, s.lo), (1.0, 1e-20));
        // (1 + 2^-30)² = 1 + 2^-29 + 2^-60: the last term is the product's rounding error.
        let a = 1.0 + libm::scalbn(1.0, -30);
        let p = two_prod(a, a);
        assert_eq!(
            (p.hi, p.lo),
            (1.0 + libm::scalbn(1.0, -29), libm::scalbn(1.0, -60))
        );
        let a = 1.0_f32 + libm::scalbnf(1.0, -13);
        let p = two_prod(a, a);
        assert_eq!(
            (p.hi, p.lo),
            (1.0 + libm::scalbnf(1.0, -12), libm::scalbnf(1.0, -26))
        );
        assert_eq!(splitter::<f64>(), 134_217_729.0);
        assert_eq!(splitter::<f32>(), 4097.0);
    }

    #[test]
    fn arithmetic_identities_to_pair_precision() {
        // 1/3 · 3 = 1, √2² = 2, (1/10)·10 = 1 to ~1e-31.
        let third = Dd::one().over(Dd::from(3.0_f64));
        assert!(third.times_t(3.0).minus(Dd::one()).value().abs() < 1e-31);
        assert_eq!(third.hi, 1.0 / 3.0);
        let r2 = Dd::from(2.0_f64).sqrt();
        assert!(r2.times(r2).minus(Dd::from(2.0)).value().abs() < 1e-31);
        // √2 = 1.41421356237309504880168872420969807857 (known digits): the trailing part 9.667e-17.
        assert_eq!(r2.hi, core::f64::consts::SQRT_2);
        assert!((r2.lo - (-9.667_293_313_452_913e-17)).abs() < 1e-31);
        let tenth = Dd::one().over_t(10.0_f64);
        assert!(tenth.times_t(10.0).minus(Dd::one()).value().abs() < 1e-31);
        assert_eq!(Dd::from(0.0_f64).sqrt(), Dd::from(0.0));
        assert!(Dd::from(-1.0_f64).sqrt().hi.is_nan());
        // f32 pairs: about 2^-46.
        let third = Dd::one().over(Dd::from(3.0_f32));
        assert!(third.times_t(3.0).minus(Dd::one()).value().abs() < 1e-13);
        let r2 = Dd::from(2.0_f32).sqrt();
        assert!(r2.times(r2).minus(Dd::from(2.0)).value().abs() < 1e-13);
    }

    #[test]
    fn sin_cos_deg_known_values() {
        let exact = |d: f64, s: f64, c: f64| {
            let (ss, cc) = sin_cos_deg(Dd::from(d));
            assert_eq!((ss.hi, ss.lo, cc.hi, cc.lo), (s, 0.0, c, 0.0), "{d}°");
        };
        exact(0.0, 0.0, 1.0);
        exact(90.0, 1.0, 0.0);
        exact(-90.0, -1.0, 0.0);
        exact(180.0, 0.0, -1.0);
        exact(270.0, -1.0, 0.0);
        exact(-360.0, 0.0, 1.0);
    }

    #[test]
    fn sin_cos_deg_against_closed_forms() {
        // sin 30° = 1/2, cos 30° = √3/2, sin 45° = √2/2, sin 60° = √3/2: to ~1e-32.
        let half_sqrt3 = Dd::from(3.0_f64).sqrt().times_t(0.5);
        let half_sqrt2 = Dd::from(2.0_f64).sqrt().times_t(0.5);
        let close = |a: Dd<f64>, b: Dd<f64>| a.minus(b).value().abs() < 2e-32;
        let (s, c) = sin_cos_deg(Dd::from(30.0_f64));
        assert!(close(s, Dd::from(0.5)) && close(c, half_sqrt3));
        let (s, c) = sin_cos_deg(Dd::from(45.0_f64));
        assert!(close(s, half_sqrt2) && close(c, half_sqrt2));
        let (s, c) = sin_cos_deg(Dd::from(-120.0_f64));
        assert!(close(s, half_sqrt3.negated()) && close(c, Dd::from(-0.5)));
        let (s, c) = sin_cos_deg(Dd::from(420.0_f64));
        assert!(close(s, half_sqrt3) && close(c, Dd::from(0.5)));
        // A pair argument: 1e-20° more than 30° moves the sine by cos30°·π/180·1e-20 (to pair precision of 0.5).
        let (s, _) = sin_cos_deg(Dd::new(30.0_f64, 1e-20));
        let ds = s.minus(Dd::from(0.5)).value();
        let want = 0.75_f64.sqrt() * RAD_PER_DEG.0 * 1e-20;
        assert!((ds - want).abs() < 1e-32, "{ds} vs {want}");
        // f32 pairs.
        let (s, c) = sin_cos_deg(Dd::from(30.0_f32));
        assert!(s.minus(Dd::from(0.5)).value().abs() < 1e-13);
        assert!((c.value() - 0.866_025_4).abs() < 1e-7);
        assert!(sin_cos_deg(Dd::from(f64::NAN)).0.hi.is_nan());
        assert!(sin_cos_deg(Dd::from(f32::INFINITY)).1.hi.is_nan());
    }
}
