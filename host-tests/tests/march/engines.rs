//! Kernel marching engines on random grids and rays: the serial and separable engines agree exactly, the
//! output obeys the contract's structure (ordered, touching crossings differ by one index step, gaps only
//! outside the domain), and every crossing's midpoint lies in the cell reported (classified here with
//! `acos`/`atan2` in f64, a different logic from the kernel's sign tests). The arbitrary-precision oracle
//! comparisons live in their own suite.

use curvicast::march::{CellCrossing, CylindricalGrid, PolarGrid, SphericalGrid};
use curvicast::ray::Ray;
use proptest::prelude::*;
use std::f64::consts::PI;

/// A grid in plain f64 for classification.
#[derive(Debug, Clone)]
enum G {
    S {
        r: Vec<f64>,
        th: Vec<f64>,
        ph: Vec<f64>,
        c: [f64; 3],
    },
    C {
        rho: Vec<f64>,
        ph: Vec<f64>,
        z: Vec<f64>,
        c: [f64; 3],
    },
    P {
        r: Vec<f64>,
        ph: Vec<f64>,
        c: [f64; 2],
    },
}

fn band(v: &[f64], x: f64) -> Option<u32> {
    let n = v.partition_point(|&b| b <= x);
    if n >= 1 && n < v.len() {
        Some((n - 1) as u32)
    } else {
        None
    }
}

fn phi_band(ph: &[f64], x: f64, y: f64) -> Option<u32> {
    let (x, y) = if x == 0.0 && y == 0.0 {
        (1.0, 0.0)
    } else {
        (x, y)
    };
    let a = y.atan2(x);
    let full = ph[ph.len() - 1] - ph[0] >= 2.0 * PI - 1e-12;
    let mut rel = (a - ph[0]).rem_euclid(2.0 * PI);
    if rel >= 2.0 * PI {
        rel = 0.0;
    }
    let shifted: Vec<f64> = ph.iter().map(|p| p - ph[0]).collect();
    let n = shifted.partition_point(|&b| b <= rel);
    if n >= 1 && n < ph.len() {
        Some((n - 1) as u32)
    } else if full {
        Some((ph.len() - 2) as u32)
    } else {
        None
    }
}

fn classify(g: &G, p: [f64; 3]) -> Option<[u32; 3]> {
    match g {
        G::S { r, th, ph, c } => {
            let q = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
            let rr = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
            let theta = if rr == 0.0 {
                0.0
            } else {
                (q[2] / rr).clamp(-1.0, 1.0).acos()
            };
            Some([band(r, rr)?, band(th, theta)?, phi_band(ph, q[0], q[1])?])
        }
        G::C { rho, ph, z, c } => {
            let q = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
            let rr = q[0].hypot(q[1]);
            Some([band(rho, rr)?, phi_band(ph, q[0], q[1])?, band(z, q[2])?])
        }
        G::P { r, ph, c } => {
            let q = [p[0] - c[0], p[1] - c[1]];
            Some([band(r, q[0].hypot(q[1]))?, phi_band(ph, q[0], q[1])?, 0])
        }
    }
}

fn full_phi(ph: &[f64]) -> bool {
    ph[ph.len() - 1] - ph[0] >= 2.0 * PI - 1e-12
}

/// The crossings through the serial march's own `Iterator::fold` (internal iteration), not through `next`.
fn folded(m: impl Iterator<Item = CellCrossing<f64>>) -> Vec<CellCrossing<f64>> {
    m.fold(Vec::new(), |mut v, c| {
        v.push(c);
        v
    })
}

fn march_both(g: &G, ray: &Ray<f64>) -> (Vec<CellCrossing<f64>>, Vec<CellCrossing<f64>>) {
    match g {
        G::S { r, th, ph, c } => {
            let mut ws =
                vec![0.0; SphericalGrid::<f64>::workspace_len(r.len(), th.len(), ph.len())];
            let grid = SphericalGrid::new(r, th, ph, &mut ws)
                .unwrap()
                .with_center(*c)
                .unwrap();
            let mut m = grid.march(ray);
            let a: Vec<_> = m.by_ref().collect();
            assert_eq!(m.error(), None);
            assert_eq!(folded(grid.march(ray)), a, "Iterator::fold against next");
            let b: Vec<_> = grid.march_separable::<512>(ray).unwrap().collect();
            (a, b)
        }
        G::C { rho, ph, z, c } => {
            let mut ws = vec![0.0; CylindricalGrid::<f64>::workspace_len(rho.len(), ph.len())];
            let grid = CylindricalGrid::new(rho, ph, z, &mut ws)
                .unwrap()
                .with_center(*c)
                .unwrap();
            let mut m = grid.march(ray);
            let a: Vec<_> = m.by_ref().collect();
            assert_eq!(m.error(), None);
            assert_eq!(folded(grid.march(ray)), a, "Iterator::fold against next");
            let b: Vec<_> = grid.march_separable::<512>(ray).unwrap().collect();
            (a, b)
        }
        G::P { r, ph, c } => {
            let mut ws = vec![0.0; PolarGrid::<f64>::workspace_len(r.len(), ph.len())];
            let grid = PolarGrid::new(r, ph, &mut ws)
                .unwrap()
                .with_center(*c)
                .unwrap();
            let mut m = grid.march(ray);
            let a: Vec<_> = m.by_ref().collect();
            assert_eq!(m.error(), None);
            assert_eq!(folded(grid.march(ray)), a, "Iterator::fold against next");
            let b: Vec<_> = grid.march_separable::<512>(ray).unwrap().collect();
            (a, b)
        }
    }
}

/// Checks the structure and the midpoints; returns a description of the first problem.
fn check(g: &G, ray: &Ray<f64>, cs: &[CellCrossing<f64>], scale: f64) -> Result<(), String> {
    let o = ray.origin();
    let d = ray.dir();
    let dl = (d.x * d.x + d.y * d.y + d.z * d.z).sqrt();
    let at = |t: f64| [o.x + t * d.x, o.y + t * d.y, o.z + t * d.z];
    // a length in t below which a piece is too short to classify reliably
    let tol = 1e-9 * scale / dl;
    let full = match g {
        G::S { ph, .. } | G::C { ph, .. } | G::P { ph, .. } => full_phi(ph),
    };
    let nphi = match g {
        G::S { ph, .. } | G::C { ph, .. } | G::P { ph, .. } => ph.len() as u32 - 1,
    };
    let phi_slot = match g {
        G::S { .. } => 2,
        _ => 1,
    };
    let mut prev: Option<CellCrossing<f64>> = None;
    for (n, c) in cs.iter().enumerate() {
        if c.t_enter > c.t_exit || c.t_enter.is_nan() {
            return Err(format!("crossing {n} has t_enter > t_exit: {c:?}"));
        }
        if c.t_enter < ray.t_min() || c.t_exit > ray.t_max() {
            return Err(format!("crossing {n} outside the ray interval: {c:?}"));
        }
        if c.t_exit - c.t_enter > tol {
            // two interior points (a midpoint can be the center or an axis point, where φ is a convention)
            for f in [0.3, 0.7] {
                let mid = if c.t_exit.is_finite() {
                    c.t_enter + f * (c.t_exit - c.t_enter)
                } else {
                    c.t_enter + f
                };
                let got = classify(g, at(mid));
                if got != Some(c.cell) {
                    return Err(format!(
                        "crossing {n} {c:?}: point at {f} classifies as {got:?}"
                    ));
                }
            }
        }
        if let Some(p) = prev {
            if c.t_enter < p.t_exit {
                return Err(format!("crossing {n} starts before the previous ends"));
            }
            if c.t_enter == p.t_exit {
                let mut diffs = 0;
                for k in 0..3 {
                    let (a, b) = (p.cell[k], c.cell[k]);
                    if a == b {
                        continue;
                    }
                    diffs += 1;
                    let step =
                        a.abs_diff(b) == 1 || (k == phi_slot && full && a.abs_diff(b) == nphi - 1);
                    if !step {
                        return Err(format!("crossing {n}: index {k} jumps {a} -> {b}"));
                    }
                }
                if diffs != 1 {
                    return Err(format!(
                        "crossing {n}: {diffs} indices change ({:?} -> {:?})",
                        p.cell, c.cell
                    ));
                }
            } else if c.t_enter - p.t_exit > tol {
                let mid = 0.5 * (c.t_enter + p.t_exit);
                if let Some(cell) = classify(g, at(mid)) {
                    return Err(format!(
                        "gap before crossing {n} has its midpoint in cell {cell:?}"
                    ));
                }
            }
        }
        prev = Some(*c);
    }
    Ok(())
}

fn breakpoints(lo: f64, hi: f64, n: usize, seeds: &[f64]) -> Vec<f64> {
    // n + 1 strictly increasing, non-uniform values from lo to hi
    let mut w: Vec<f64> = seeds.iter().take(n).map(|s| 0.2 + s).collect();
    let total: f64 = w.iter().sum();
    let mut out = vec![lo];
    let mut acc = lo;
    for x in w.iter_mut() {
        acc += (hi - lo) * *x / total;
        out.push(acc);
    }
    *out.last_mut().unwrap() = hi;
    out
}

fn arb_grid() -> impl Strategy<Value = G> {
    (
        0usize..3,
        1usize..6,
        1usize..6,
        1usize..7,
        prop::collection::vec(0.0f64..1.0, 8),
        prop::collection::vec(0.0f64..1.0, 8),
        prop::collection::vec(0.0f64..1.0, 8),
        (0u8..4, 0u8..3, -3.0f64..3.0, 0.1f64..2.0 * PI),
        prop::array::uniform3(-0.5f64..0.5),
    )
        .prop_map(|(kind, nr, nt, np, s1, s2, s3, (rk, tk, phi0, span), c)| {
            let r0 = if rk == 0 { 0.3 } else { 0.0 };
            let r = breakpoints(r0, 1.0 + s1[7], nr, &s1);
            let (t0, t1) = match tk {
                0 => (0.0, PI),
                1 => (0.2, PI),
                _ => (0.0, 2.0),
            };
            let th = breakpoints(t0, t1, nt, &s2);
            let span = if rk == 3 || span > 6.0 {
                2.0 * PI
            } else {
                span
            };
            let ph = breakpoints(phi0, phi0 + span, np, &s3);
            let ph = if span == 2.0 * PI {
                let mut p = ph;
                let l = p.len();
                p[l - 1] = p[0] + 2.0 * PI;
                p
            } else {
                ph
            };
            match kind {
                0 => G::S { r, th, ph, c },
                1 => G::C {
                    rho: r,
                    ph,
                    z: breakpoints(-1.0, 1.0, nt, &s2),
                    c,
                },
                _ => G::P {
                    r,
                    ph,
                    c: [c[0], c[1]],
                },
            }
        })
}

fn center_of(g: &G) -> [f64; 3] {
    match g {
        G::S { c, .. } | G::C { c, .. } => *c,
        G::P { c, .. } => [c[0], c[1], 0.0],
    }
}

fn first_radius(g: &G) -> Vec<f64> {
    match g {
        G::S { r, .. } | G::P { r, .. } => r.clone(),
        G::C { rho, .. } => rho.clone(),
    }
}

fn arb_case() -> impl Strategy<Value = (G, Ray<f64>)> {
    arb_grid().prop_flat_map(|g| {
        let c = center_of(&g);
        let radii = first_radius(&g);
        (
            Just(g),
            prop::array::uniform3(-3.0f64..3.0),
            prop::array::uniform3(-1.0f64..1.0),
            0u8..8,
            (-2.0f64..2.0, 0.0f64..6.0, 0usize..8),
        )
            .prop_filter_map(
                "zero direction",
                move |(g, o, d, mode, (tmin, tlen, ri))| {
                    // modes: generic, through the center, crossing the z axis, vertical, in the plane z = c_z,
                    // segment, starting on a sphere, starting at the center
                    let rel = |v: [f64; 3]| [v[0] + c[0], v[1] + c[1], v[2] + c[2]];
                    let (o, d) = match mode {
                        1 => (rel(o), [-o[0], -o[1], -o[2]]),
                        2 => (rel(o), [-o[0], -o[1], d[2]]),
                        3 => (o, [0.0, 0.0, d[2]]),
                        4 => ([o[0], o[1], c[2]], [d[0], d[1], 0.0]),
                        6 => {
                            let n = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
                            let r = radii[ri % radii.len()];
                            (rel([o[0] * r / n, o[1] * r / n, o[2] * r / n]), d)
                        }
                        7 => (c, d),
                        _ => (o, d),
                    };
                    let ray = Ray::new(o, d).ok()?;
                    let ray = if mode == 5 {
                        ray.with_interval(tmin, tmin + tlen).ok()?
                    } else {
                        ray
                    };
                    Some((g, ray))
                },
            )
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: std::env::var("MARCH_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(3000), .. ProptestConfig::default() })]
    #[test]
    fn engines_agree_and_midpoints_classify((g, ray) in arb_case()) {
        let (a, b) = march_both(&g, &ray);
        prop_assert_eq!(&a, &b);
        if let Err(e) = check(&g, &ray, &a, 4.0) {
            prop_assert!(false, "{}\n{:?}\n{:?}\n{:#?}", e, g, ray, a);
        }
    }
}
