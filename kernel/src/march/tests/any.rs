//! The grid kind chosen at run time: `AnyGrid` marches each kind exactly as its typed grid does, through every
//! way of reading a march (the iterator, internal iteration, a buffer, a callback that stops), and reports its
//! kind and its errors.

use super::*;
use crate::ray::Ray;
use core::f64::consts::PI;
use std::vec::Vec;

/// Rays that cross several cells of the grids below, one through the center (the walks) and one that misses.
fn rays() -> [Ray<f64>; 4] {
    [
        Ray::new([-3.0, 0.3, 0.2], [1.0, 0.05, 0.1]).unwrap(),
        Ray::new([0.2, -3.0, -0.6], [0.1, 1.0, 0.3]).unwrap(),
        Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap(),
        Ray::new([-3.0, 5.0, 0.0], [1.0, 0.0, 0.0]).unwrap(),
    ]
}

/// Checks every way of reading `any`'s march of each ray against the crossings `typed` gives; `name` its kind.
fn check(any: &AnyGrid<'_, f64>, name: &str, typed: impl Fn(&Ray<f64>) -> Vec<CellCrossing<f64>>) {
    assert_eq!(any.kind_name(), name);
    let mut crossed = 0;
    for ray in &rays() {
        let want = typed(ray);
        crossed += want.len();
        // the iterator, one crossing at a time
        let mut m = any.march(ray);
        let got: Vec<_> = m.by_ref().collect();
        assert_eq!(
            (got.as_slice(), m.error()),
            (want.as_slice(), None),
            "{name}"
        );
        // internal iteration, by value and in place
        let folded = any.march(ray).fold(Vec::new(), |mut v, c| {
            v.push(c);
            v
        });
        assert_eq!(folded, want, "{name} fold");
        let mut m = any.march(ray);
        let in_place = m.fold_in_place(Vec::new(), |mut v, c| {
            v.push(c);
            v
        });
        assert_eq!(in_place, want, "{name} fold_in_place");
        // into buffers of 1, 2 and 64 crossings (and empty ones between)
        for size in [1, 2, 64] {
            let mut m = any.march(ray);
            let blank = CellCrossing {
                cell: [0; 3],
                t_enter: 0.0,
                t_exit: 0.0,
            };
            let mut buf = [blank; 64];
            let mut got = Vec::new();
            loop {
                // an empty buffer takes nothing
                assert_eq!(m.next_into(&mut buf[..0]), 0, "{name}");
                let n = m.next_into(&mut buf[..size]);
                assert!(n <= size, "{name}");
                got.extend_from_slice(&buf[..n]);
                if n < size {
                    break;
                }
            }
            assert_eq!(got, want, "{name} next_into {size}");
        }
        // a callback that stops after the first two crossings, then the rest from the iterator
        let mut m = any.march(ray);
        let mut first = Vec::new();
        m.for_each_while(|c| {
            first.push(c);
            first.len() < 2
        });
        assert_eq!(first.as_slice(), &want[..want.len().min(2)], "{name}");
        first.extend(m);
        assert_eq!(first, want, "{name} for_each_while");
        // the kind left to run time marches alike
        let dynamic: Vec<_> = any.into_dynamic().march(ray).collect();
        assert_eq!(dynamic, want, "{name} dynamic");
    }
    assert!(crossed > 8, "{name}: the rays must cross cells ({crossed})");
}

#[test]
fn any_grid_of_each_kind_marches_as_its_typed_grid() {
    let (r, th, ph) = (
        [0.0, 0.5, 1.0, 2.0],
        [0.0, 1.0, PI / 2.0, PI],
        [0.0, 2.0, 4.0, 2.0 * PI],
    );
    let mut ws = [0.0; 64];
    let s = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    check(&AnyGrid::from(s), "spherical", |ray| s.march(ray).collect());

    let z = [-1.0, -0.25, 0.5, 1.0];
    let mut ws = [0.0; 64];
    let c = CylindricalGrid::new(&r, &ph, &z, &mut ws).unwrap();
    check(&AnyGrid::from(c), "cylindrical", |ray| {
        c.march(ray).collect()
    });

    let mut ws = [0.0; 64];
    let p = PolarGrid::new(&r, &ph, &mut ws).unwrap();
    check(&AnyGrid::from(p), "polar", |ray| p.march(ray).collect());
}

#[test]
fn any_grid_reports_the_error_of_a_march_whose_t_overflows() {
    // The line crosses the ball only where t ≈ 2e308 and beyond (a direction 1e-308 long): each kind's error.
    let ray = Ray::new([-3.0, 0.1, 0.2], [1e-308, 0.0, 0.0]).unwrap();
    let (r, ph, z) = ([0.0, 1.0], [0.0, 2.0 * PI], [-1.0, 1.0]);
    let mut ws = [0.0; 16];
    let s = AnyGrid::from(SphericalGrid::new(&r, &TH, &ph, &mut ws).unwrap());
    let mut ws = [0.0; 16];
    let c = AnyGrid::from(CylindricalGrid::new(&r, &ph, &z, &mut ws).unwrap());
    let mut ws = [0.0; 16];
    let p = AnyGrid::from(PolarGrid::new(&r, &ph, &mut ws).unwrap());
    for g in [s, c, p] {
        let mut m = g.march(&ray);
        assert_eq!(m.next(), None, "{}", g.kind_name());
        assert_eq!(
            m.error(),
            Some(MarchError::Unrepresentable),
            "{}",
            g.kind_name()
        );
    }
}
