//! Named hard cases with hand-derived expectations (light enough for Miri). The arbitrary-precision oracle
//! comparisons are in the host crate.

use super::*;
use crate::ray::Ray;
use core::f64::consts::PI;
use std::vec::Vec;

mod any;
mod axes;
mod azimuth;
mod engines;
mod hard;
mod streams;

const R: [f64; 3] = [0.0, 0.5, 1.0];
const TH: [f64; 3] = [0.0, PI / 2.0, PI];
const PH: [f64; 3] = [0.0, PI, 2.0 * PI];

/// Marches with both engines (which must agree exactly) and returns the crossings.
fn march_s(r: &[f64], th: &[f64], ph: &[f64], ray: &Ray<f64>) -> Vec<CellCrossing<f64>> {
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(r, th, ph, &mut ws).unwrap();
    let mut m = g.march(ray);
    let a: Vec<_> = m.by_ref().collect();
    assert_eq!(m.error(), None);
    let b: Vec<_> = g.march_separable::<32>(ray).unwrap().collect();
    assert_eq!(a, b, "serial and separable differ");
    a
}

/// Checks cells exactly and t values to `tol` (relative to max(1, |t|)).
fn expect(got: &[CellCrossing<f64>], want: &[([u32; 3], f64, f64)], tol: f64) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, &(cell, a, b)) in got.iter().zip(want) {
        assert_eq!(g.cell, cell, "{got:?}");
        assert!(
            (g.t_enter - a).abs() <= tol * a.abs().max(1.0),
            "{g:?} vs {a}"
        );
        assert!(
            (g.t_exit - b).abs() <= tol * b.abs().max(1.0),
            "{g:?} vs {b}"
        );
    }
}
