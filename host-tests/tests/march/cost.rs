//! The cost of marching, counted through an instrumented scalar: at most one square root per radius or zenith
//! crossing and at most one division per azimuth crossing, on average over random rays through random
//! non-uniform grids (Hannasch: "both roots of one sphere from one square root"; the azimuth needs one
//! division per facet). The counts are exact (not timings).

use curvicast::march::{CellCrossing, CylindricalGrid, SphericalGrid};
use curvicast::ray::Ray;
use curvicast::real::Real;
use rand::{Rng, SeedableRng};
use std::cell::Cell;
use std::f64::consts::PI;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

thread_local! {
    static SQRTS: Cell<u64> = const { Cell::new(0) };
    static DIVS: Cell<u64> = const { Cell::new(0) };
}

fn count_division() {
    DIVS.with(|c| c.set(c.get() + 1));
}

fn counts() -> (u64, u64) {
    (SQRTS.with(|c| c.get()), DIVS.with(|c| c.get()))
}

/// f64 that counts its square roots and divisions.
#[derive(Debug, Clone, Copy, Default, PartialEq, PartialOrd)]
struct Counted(f64);

impl std::fmt::Display for Counted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

macro_rules! op {
    ($tr:ident, $m:ident, $tra:ident, $ma:ident, $op:tt, $count:literal) => {
        impl $tr for Counted {
            type Output = Counted;
            fn $m(self, o: Counted) -> Counted {
                if $count {
                    count_division();
                }
                Counted(self.0 $op o.0)
            }
        }
        impl $tra for Counted {
            fn $ma(&mut self, o: Counted) {
                if $count {
                    count_division();
                }
                self.0 = self.0 $op o.0;
            }
        }
    };
}
op!(Add, add, AddAssign, add_assign, +, false);
op!(Sub, sub, SubAssign, sub_assign, -, false);
op!(Mul, mul, MulAssign, mul_assign, *, false);
op!(Div, div, DivAssign, div_assign, /, true);

impl Neg for Counted {
    type Output = Counted;
    fn neg(self) -> Counted {
        Counted(-self.0)
    }
}

impl Real for Counted {
    const ZERO: Self = Counted(0.0);
    const ONE: Self = Counted(1.0);
    const TWO: Self = Counted(2.0);
    const HALF: Self = Counted(0.5);
    const PI: Self = Counted(PI);
    const FRAC_PI_2: Self = Counted(PI / 2.0);
    const EPSILON: Self = Counted(f64::EPSILON);
    const MAX: Self = Counted(f64::MAX);
    const MIN_POSITIVE: Self = Counted(f64::MIN_POSITIVE);
    const INFINITY: Self = Counted(f64::INFINITY);
    const NEG_INFINITY: Self = Counted(f64::NEG_INFINITY);
    const NAN: Self = Counted(f64::NAN);
    const MANTISSA_DIGITS: u32 = f64::MANTISSA_DIGITS;
    const NAME: &'static str = "f64-counted";
    fn from_f64(x: f64) -> Self {
        Counted(x)
    }
    fn to_f64(self) -> f64 {
        self.0
    }
    fn from_i32(n: i32) -> Self {
        Counted(n as f64)
    }
    fn sqrt(self) -> Self {
        SQRTS.with(|c| c.set(c.get() + 1));
        Counted(self.0.sqrt())
    }
    fn sin(self) -> Self {
        Counted(self.0.sin())
    }
    fn cos(self) -> Self {
        Counted(self.0.cos())
    }
    fn atan2(self, x: Self) -> Self {
        Counted(self.0.atan2(x.0))
    }
    fn mul_add(self, a: Self, b: Self) -> Self {
        Counted(self.0.mul_add(a.0, b.0))
    }
    fn scalbn(self, k: i32) -> Self {
        Counted(self.0 * 2f64.powi(k))
    }
    fn ilogb(self) -> i32 {
        if self.0 == 0.0 || !self.0.is_finite() {
            i32::MIN
        } else {
            self.0.abs().log2().floor() as i32
        }
    }
}

fn breakpoints(rng: &mut impl Rng, lo: f64, hi: f64, n: usize) -> Vec<Counted> {
    let w: Vec<f64> = (0..n).map(|_| 0.3 + rng.random::<f64>()).collect();
    let total: f64 = w.iter().sum();
    let mut v = vec![lo];
    let mut acc = lo;
    for x in &w {
        acc += (hi - lo) * x / total;
        v.push(acc);
    }
    *v.last_mut().unwrap() = hi;
    v.into_iter().map(Counted).collect()
}

/// Index changes per slot between touching crossings, and the number of separate runs.
fn changes(cs: &[CellCrossing<Counted>]) -> ([u64; 3], u64) {
    let mut ch = [0u64; 3];
    let mut runs = 0;
    for (i, c) in cs.iter().enumerate() {
        match i.checked_sub(1).map(|j| cs[j]) {
            Some(p) if p.t_exit == c.t_enter => {
                for (n, (a, b)) in ch.iter_mut().zip(p.cell.iter().zip(c.cell.iter())) {
                    if a != b {
                        *n += 1;
                    }
                }
            }
            _ => runs += 1,
        }
    }
    (ch, runs)
}

fn random_ray(rng: &mut impl Rng, from: f64) -> Ray<Counted> {
    // from a random point on a sphere of radius `from` toward a random point in the unit ball
    let dir = |rng: &mut dyn rand::RngCore| loop {
        let v = [
            rng.random::<f64>() * 2.0 - 1.0,
            rng.random::<f64>() * 2.0 - 1.0,
            rng.random::<f64>() * 2.0 - 1.0,
        ];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.1 && n <= 1.0 {
            return [v[0] / n, v[1] / n, v[2] / n];
        }
    };
    let a = dir(rng);
    let b = dir(rng);
    let s = rng.random::<f64>();
    let o = [a[0] * from, a[1] * from, a[2] * from];
    let target = [b[0] * s, b[1] * s, b[2] * s];
    let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
    Ray::new(o.map(Counted), d.map(Counted)).unwrap()
}

#[test]
fn spherical_one_sqrt_per_radius_or_zenith_crossing() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x5eed);
    let (mut sq, mut rt_cross, mut dv, mut all_cross) = (0u64, 0u64, 0u64, 0u64);
    for g in 0..20 {
        let r = breakpoints(&mut rng, 0.0, 1.0, 8 + g % 24);
        let th = breakpoints(&mut rng, 0.0, PI, 6 + g % 20);
        let ph = breakpoints(&mut rng, 0.0, 2.0 * PI, 5 + g % 30);
        let mut ws = vec![
            Counted(0.0);
            SphericalGrid::<Counted>::workspace_len(r.len(), th.len(), ph.len())
        ];
        let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
        for _ in 0..500 {
            let ray = random_ray(&mut rng, 3.0);
            let (s0, d0) = counts();
            let cs: Vec<_> = grid.march(&ray).collect();
            let (s1, d1) = counts();
            let (ch, runs) = changes(&cs);
            sq += s1 - s0;
            dv += d1 - d0;
            all_cross += ch[0] + ch[1] + ch[2] + 2 * runs;
            // full θ and φ ranges: every entry to and exit from the domain is through the outer sphere
            rt_cross += ch[0] + ch[1] + 2 * runs;
        }
    }
    let sqrt_per = sq as f64 / rt_cross as f64;
    println!(
        "r/θ crossings {rt_cross}, sqrt {sq} ({sqrt_per:.3} per crossing); all crossings {all_cross}, divisions \
         {dv} ({:.3} per crossing, not asserted: the zenith roots' refinement divides)",
        dv as f64 / all_cross as f64
    );
    assert!(rt_cross > 10_000);
    assert!(
        sqrt_per <= 1.0,
        "{sqrt_per} square roots per radius/zenith crossing"
    );
}

/// The azimuth's own cost, isolated: one shell `[0, 1]` and the full zenith range, so the only other divisions
/// are the outer sphere's root pair (exactly two divisions for its one square root, both roots reported: the
/// entry and the exit); the zenith cones' root refinement (see `surface/cone.rs`) is not involved.
///
/// The serial engine keeps each coordinate's next crossing, already divided (a division is one instruction;
/// keeping it undivided cost more in comparisons than it saved), so each ray pays for one azimuth crossing that is
/// looked at but never reached — the one beyond the domain's exit. Asserted: divisions per azimuth crossing after
/// charging the sphere's two to its two crossings and that one look-ahead to its ray, and divisions per reported
/// crossing of any kind with only the look-ahead charged to the ray.
#[test]
fn spherical_one_division_per_azimuth_crossing() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0xa21);
    let (mut sq, mut dv, mut phi_cross, mut r_cross, mut n_rays) = (0u64, 0u64, 0u64, 0u64, 0u64);
    let r = [Counted(0.0), Counted(1.0)];
    let th = [Counted(0.0), Counted(PI)];
    for g in 0..20 {
        let ph = breakpoints(&mut rng, 0.0, 2.0 * PI, 5 + g % 30);
        let mut ws = vec![
            Counted(0.0);
            SphericalGrid::<Counted>::workspace_len(r.len(), th.len(), ph.len())
        ];
        let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
        for _ in 0..500 {
            let ray = random_ray(&mut rng, 3.0);
            let (s0, d0) = counts();
            let cs: Vec<_> = grid.march(&ray).collect();
            let (s1, d1) = counts();
            let (ch, runs) = changes(&cs);
            sq += s1 - s0;
            dv += d1 - d0;
            phi_cross += ch[2];
            // every run enters and leaves through the outer sphere (the rays start outside it)
            r_cross += ch[0] + 2 * runs;
            n_rays += 1;
        }
    }
    let per_phi = dv.saturating_sub(2 * sq + n_rays) as f64 / phi_cross as f64;
    let per_any = dv.saturating_sub(n_rays) as f64 / (phi_cross + r_cross) as f64;
    println!(
        "rays {n_rays}: divisions {dv}, square roots {sq}; φ crossings {phi_cross}, r crossings {r_cross}; \
         {per_phi:.3} divisions per φ crossing (the sphere's 2 per square root charged to its crossings, one \
         look-ahead per ray), {per_any:.3} divisions per reported crossing of any kind (one look-ahead per ray \
         deducted)"
    );
    assert!(phi_cross > 10_000);
    assert!(per_phi <= 1.0, "{per_phi} divisions per azimuth crossing");
    assert!(per_any <= 1.0, "{per_any} divisions per reported crossing");
}

/// The same count for the cylinder: one ρ shell and one z slab, so almost every event is an azimuth crossing.
/// The ρ solver's divisions (exactly two per square root: both roots of the pair, whether or not both are
/// reported — a ray that starts inside the cylinder or leaves it through a z plane does not report one of them)
/// are its own cost, and each ray pays one look-ahead division for each of its two plane coordinates (φ and z:
/// the crossing after the last one reached); every other division must be a reported plane crossing (φ, or z
/// where a run enters or leaves through a z plane).
#[test]
fn cylindrical_azimuth_costs_one_division_per_crossing() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let rho = [Counted(0.0), Counted(1.0)];
    let z = [Counted(-10.0), Counted(10.0)];
    let ph = breakpoints(&mut rng, -1.0, -1.0 + 2.0 * PI, 200);
    let mut ws = vec![Counted(0.0); CylindricalGrid::<Counted>::workspace_len(2, ph.len())];
    let grid = CylindricalGrid::new(&rho, &ph, &z, &mut ws).unwrap();
    let (mut dv, mut sq, mut phi_cross, mut z_cross, mut all_cross) =
        (0u64, 0u64, 0u64, 0u64, 0u64);
    let n = 2000u64;
    for _ in 0..n {
        let ray = random_ray(&mut rng, 3.0);
        let (s0, d0) = counts();
        let cs: Vec<_> = grid.march(&ray).collect();
        let (s1, d1) = counts();
        let (ch, runs) = changes(&cs);
        phi_cross += ch[1];
        // the ends of the runs that lie on a z plane (z changes inside: none, there is one slab)
        let on_z_plane = |t: Counted| (ray.at(t)[2].0.abs() - 10.0).abs() < 1e-9;
        for (i, c) in cs.iter().enumerate() {
            let starts_run = i == 0 || cs[i - 1].t_exit != c.t_enter;
            let ends_run = i + 1 == cs.len() || cs[i + 1].t_enter != c.t_exit;
            z_cross += u64::from(starts_run && on_z_plane(c.t_enter));
            z_cross += u64::from(ends_run && on_z_plane(c.t_exit));
        }
        all_cross += ch[0] + ch[1] + ch[2] + 2 * runs;
        dv += d1 - d0;
        sq += s1 - s0;
    }
    let planes = dv.saturating_sub(2 * sq + 2 * n);
    let per_plane = planes as f64 / (phi_cross + z_cross) as f64;
    let per_any = dv as f64 / all_cross as f64;
    println!(
        "rays {n}: divisions {dv}, square roots {sq}; φ crossings {phi_cross}, z crossings {z_cross}; \
         {planes} divisions besides the ρ solver's 2 per square root and the 2 look-aheads per ray: \
         {per_plane:.4} per φ or z crossing; all divisions over all run ends and index changes {per_any:.4} (not \
         asserted: a run that starts at t_min counts as a crossing, a ρ root never reported costs a division)"
    );
    assert!(phi_cross > 50_000);
    assert!(per_plane <= 1.0, "{per_plane}");
}
