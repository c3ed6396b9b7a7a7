//! Fuzz target for spherical, cylindrical and polar marching (Hannasch): arbitrary grids (valid and invalid)
//! and rays. Checks: no panic, no hang (the iteration bound is never hit), crossings ordered and non-negative,
//! touching crossings differ in exactly one index by one step (φ wraps only on a full turn), the serial and
//! separable engines agree exactly, and (f64, well-conditioned crossings) interior points lie in the cell
//! reported, classified with `atan2` — a different logic from the kernel's sign tests.
#![no_main]

use curvicast::F32Fast;
use curvicast::march::{CellCrossing, CylindricalGrid, MarchError, PolarGrid, SphericalGrid};
use curvicast::ray::{Ray, RayError};
use curvicast::real::Real;
use libfuzzer_sys::fuzz_target;
use std::f64::consts::PI;

/// The decoded input. Layout (little-endian): bytes `kind, flags, interval, na, nb, nc` (counts taken mod 13),
/// then f64s: `a[na], b[nb], c[nc], center[3], origin[3], dir[3], t_min, t_max` (missing bytes read as 0), so
/// that seed inputs are easy to write by hand.
#[derive(Debug)]
struct Input {
    kind: u8,
    /// bit 0: sanitize the breakpoints into a valid grid; bit 1: f32; bit 2: f32-fast; bit 3: grid center
    flags: u8,
    a: Vec<f64>,
    b: Vec<f64>,
    c: Vec<f64>,
    center: [f64; 3],
    origin: [f64; 3],
    dir: [f64; 3],
    t_min: f64,
    t_max: f64,
    interval: bool,
}

/// Sorted, deduplicated, finite values clamped into `[lo, hi]`, at least two.
fn sanitize(v: &[f64], lo: f64, hi: f64) -> Vec<f64> {
    let mut out: Vec<f64> = v
        .iter()
        .take(12)
        .filter(|x| x.is_finite())
        .map(|x| lo + (hi - lo) * (x.abs().fract()))
        .collect();
    out.push(lo);
    out.push(hi);
    out.sort_by(f64::total_cmp);
    out.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * (hi - lo));
    out
}

fn phi_band(ph: &[f64], x: f64, y: f64, full: bool) -> Option<u32> {
    let (x, y) = if x == 0.0 && y == 0.0 {
        (1.0, 0.0)
    } else {
        (x, y)
    };
    let rel = (y.atan2(x) - ph[0]).rem_euclid(2.0 * PI);
    let n = ph.iter().map(|p| p - ph[0]).filter(|&b| b <= rel).count();
    if n >= 1 && n < ph.len() {
        Some(n as u32 - 1)
    } else if full {
        Some(ph.len() as u32 - 2)
    } else {
        None
    }
}

fn band(v: &[f64], x: f64) -> Option<u32> {
    let n = v.iter().filter(|&&b| b <= x).count();
    (n >= 1 && n < v.len()).then(|| n as u32 - 1)
}

fn check<T: Real>(cs: &[CellCrossing<T>], ray: &Ray<T>, phi_slot: usize, full: bool, nphi: u32) {
    let mut prev: Option<CellCrossing<T>> = None;
    for c in cs {
        assert!(c.t_enter <= c.t_exit, "{c:?}");
        assert!(c.t_enter >= ray.t_min() && c.t_exit <= ray.t_max(), "{c:?}");
        if let Some(p) = prev {
            assert!(c.t_enter >= p.t_exit, "{p:?} {c:?}");
            if c.t_enter == p.t_exit {
                let mut diffs = 0;
                for k in 0..3 {
                    let (a, b) = (p.cell[k], c.cell[k]);
                    if a != b {
                        diffs += 1;
                        // Known and documented: a line passing the z axis closer than t can resolve leaves a
                        // wedge and re-enters it within one rounding of t; the gap outside the wedge then has
                        // zero length and the φ index seems to jump across the outside sector.
                        let ok = a.abs_diff(b) == 1
                            || (k == phi_slot && full && a.abs_diff(b) == nphi - 1)
                            || (k == phi_slot && !full);
                        assert!(ok, "index {k} jumps: {p:?} {c:?}");
                    }
                }
                assert_eq!(diffs, 1, "{p:?} {c:?}");
            }
        }
        prev = Some(*c);
    }
}

fn run<T: Real>(inp: &Input) {
    let sane = inp.flags & 1 != 0;
    let conv = |v: &[f64]| -> Vec<T> { v.iter().take(40).map(|&x| T::from_f64(x)).collect() };
    let v3 = |a: [f64; 3]| a.map(T::from_f64);
    let Ok(ray) = Ray::new(v3(inp.origin), v3(inp.dir)) else {
        return;
    };
    let ray = if inp.interval {
        match ray.with_interval(T::from_f64(inp.t_min), T::from_f64(inp.t_max)) {
            Ok(r) => r,
            Err(_) => return,
        }
    } else {
        ray
    };
    let center = if inp.flags & 8 != 0 {
        v3(inp.center)
    } else {
        [T::ZERO; 3]
    };
    let kind = inp.kind % 3;
    // A grid center so far from the origin that `origin − center` overflows is a typed error, not a crossing list.
    let o = ray.origin();
    let cz = if kind == 2 { T::ZERO } else { center[2] };
    let far = [o.x - center[0], o.y - center[1], o.z - cz]
        .iter()
        .any(|x| !x.is_finite());
    let expected_error = far.then_some(MarchError::Ray(RayError::NonFiniteOrigin));
    // a direction too short for its distance: crossings whose t overflows are a typed error
    let error_ok = |e: Option<MarchError>| {
        e == expected_error || (!far && e == Some(MarchError::Unrepresentable))
    };
    let (a, b, c) = if sane {
        match kind {
            0 => (
                sanitize(&inp.a, 0.0, 2.0),
                sanitize(&inp.b, 0.0, PI),
                sanitize(&inp.c, -1.0, -1.0 + 2.0 * PI),
            ),
            1 => (
                sanitize(&inp.a, 0.0, 2.0),
                sanitize(&inp.b, 0.5, 4.0),
                sanitize(&inp.c, -2.0, 2.0),
            ),
            _ => (
                sanitize(&inp.a, 0.3, 2.0),
                sanitize(&inp.b, -3.0, 3.0),
                vec![],
            ),
        }
    } else {
        (inp.a.clone(), inp.b.clone(), inp.c.clone())
    };
    let (ta, tb, tc) = (conv(&a), conv(&b), conv(&c));
    let mut ws = vec![T::ZERO; 256];
    let (serial, separable, phi_slot, phis): (Vec<_>, Result<Vec<_>, MarchError>, usize, &[T]) =
        match kind {
            0 => {
                let Ok(g) = SphericalGrid::new(&ta, &tb, &tc, &mut ws) else {
                    return;
                };
                let Ok(g) = g.with_center(center) else { return };
                let mut m = g.march(&ray);
                let s: Vec<_> = m.by_ref().collect();
                assert!(error_ok(m.error()), "{:?}", m.error());
                assert_eq!(folded(g.march(&ray)), s, "Iterator::fold against next");
                (
                    s,
                    g.march_separable::<256>(&ray).map(|m| m.collect()),
                    2,
                    &tc,
                )
            }
            1 => {
                let Ok(g) = CylindricalGrid::new(&ta, &tb, &tc, &mut ws) else {
                    return;
                };
                let Ok(g) = g.with_center(center) else { return };
                let mut m = g.march(&ray);
                let s: Vec<_> = m.by_ref().collect();
                assert!(error_ok(m.error()), "{:?}", m.error());
                assert_eq!(folded(g.march(&ray)), s, "Iterator::fold against next");
                (
                    s,
                    g.march_separable::<256>(&ray).map(|m| m.collect()),
                    1,
                    &tb,
                )
            }
            _ => {
                let Ok(g) = PolarGrid::new(&ta, &tb, &mut ws) else {
                    return;
                };
                let Ok(g) = g.with_center([center[0], center[1]]) else {
                    return;
                };
                let mut m = g.march(&ray);
                let s: Vec<_> = m.by_ref().collect();
                assert!(error_ok(m.error()), "{:?}", m.error());
                assert_eq!(folded(g.march(&ray)), s, "Iterator::fold against next");
                (
                    s,
                    g.march_separable::<256>(&ray).map(|m| m.collect()),
                    1,
                    &tb,
                )
            }
        };
    if let Ok(sep) = separable {
        assert_eq!(serial, sep);
    }
    let span = phis.last().map_or(0.0, |l| l.to_f64()) - phis.first().map_or(0.0, |f| f.to_f64());
    let full = span >= 2.0 * PI * (1.0 - 16.0 * f32::EPSILON as f64) && T::MANTISSA_DIGITS < 53
        || span >= 2.0 * PI - 1e-14;
    check(
        &serial,
        &ray,
        phi_slot,
        full,
        phis.len().saturating_sub(1) as u32,
    );
    // interior points of long crossings (f64 spherical grids only)
    if T::MANTISSA_DIGITS == 53 && kind == 0 && sane {
        let (o, d) = (ray.origin(), ray.dir());
        let (o, d) = (
            [o.x, o.y, o.z].map(|x| x.to_f64()),
            [d.x, d.y, d.z].map(|x| x.to_f64()),
        );
        let cen = center.map(|x| x.to_f64());
        let dl = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let scale = 2.0
            + (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt()
            + cen.iter().map(|x| x.abs()).sum::<f64>();
        for x in &serial {
            let (t0, t1) = (x.t_enter.to_f64(), x.t_exit.to_f64());
            // long against the grid and against the rounding of p + t d itself
            let long = (t1 - t0) * dl >= 1e-6 * scale
                && t1 - t0 >= 1e-6 * t0.abs().max(t1.abs())
                && t1 > t0;
            if !t1.is_finite() || !dl.is_finite() || !long {
                continue;
            }
            for f in [0.3, 0.7] {
                let t = t0 + f * (t1 - t0);
                let q = [
                    o[0] + t * d[0] - cen[0],
                    o[1] + t * d[1] - cen[1],
                    o[2] + t * d[2] - cen[2],
                ];
                let r = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
                let rho = q[0].hypot(q[1]);
                // atan2, not acos(z / r): acos is blind near θ = 0 and π (its argument within an ulp of ±1
                // leaves θ uncertain by about 1.5e-8), where a narrow cone is still well conditioned
                let th = rho.atan2(q[2]);
                // well conditioned only: away from the center, the z axis and every boundary
                let phi = q[1].atan2(q[0]);
                let tol = 1e-9;
                let near = r < tol * scale
                    || rho < tol * scale
                    || a.iter().any(|&x| (x - r).abs() < tol * scale)
                    || b.iter().any(|&x| (x - th).abs() < tol)
                    || c.iter().any(|&x| {
                        let e = (x - phi).rem_euclid(2.0 * PI);
                        e < tol || e > 2.0 * PI - tol
                    });
                if near {
                    continue;
                }
                let got =
                    (|| Some([band(&a, r)?, band(&b, th)?, phi_band(&c, q[0], q[1], full)?]))();
                assert_eq!(got, Some(x.cell), "{x:?} at {f}");
            }
        }
    }
}

impl Input {
    fn decode(data: &[u8]) -> Input {
        let byte = |i: usize| data.get(i).copied().unwrap_or(0);
        let mut pos = 6;
        let mut f = || {
            let mut b = [0u8; 8];
            for (k, x) in b.iter_mut().enumerate() {
                *x = data.get(pos + k).copied().unwrap_or(0);
            }
            pos += 8;
            f64::from_le_bytes(b)
        };
        let (na, nb, nc) = (
            byte(3) as usize % 13,
            byte(4) as usize % 13,
            byte(5) as usize % 13,
        );
        let a = (0..na).map(|_| f()).collect();
        let b = (0..nb).map(|_| f()).collect();
        let c = (0..nc).map(|_| f()).collect();
        let center = [f(), f(), f()];
        let origin = [f(), f(), f()];
        let dir = [f(), f(), f()];
        let (t_min, t_max) = (f(), f());
        Input {
            kind: byte(0),
            flags: byte(1),
            a,
            b,
            c,
            center,
            origin,
            dir,
            t_min,
            t_max,
            interval: byte(2) & 1 != 0,
        }
    }
}

/// The crossings through the serial march's own `Iterator::fold` (internal iteration), not through `next`.
fn folded<T: Real>(m: impl Iterator<Item = CellCrossing<T>>) -> Vec<CellCrossing<T>> {
    m.fold(Vec::new(), |mut v, c| {
        v.push(c);
        v
    })
}

fuzz_target!(|data: &[u8]| {
    let inp = Input::decode(data);
    if inp.flags & 2 != 0 {
        run::<f32>(&inp);
    } else if inp.flags & 4 != 0 {
        run::<F32Fast>(&inp);
    } else {
        run::<f64>(&inp);
    }
});
