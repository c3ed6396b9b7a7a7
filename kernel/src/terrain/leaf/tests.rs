//! The leaf walk's per-unit and per-column constants against the formulas their docs give: the height cull's
//! rounding tolerance, the azimuth's rate, a column's middle meridian, its walls' tolerance and the row walls'
//! magnitude. Each tolerance is a bound on rounding with a margin; these pin its terms, on a ray whose every
//! component differs in size so that a wrong term shows.

use super::*;
use crate::geodesy::Ellipsoid;
use crate::terrain::tests::{Storage, TestDem, grid};

/// 9 × 9 vertices of 0.01° at 45° N, 7° E, in one leaf of 8 × 8 cells, flat at 100 m; `f` with its picker and
/// storage.
fn with_leaf<R>(f: impl FnOnce(&Picker<'_, f64, Storage<'_>>, &Storage<'_>) -> R) -> R {
    let dem = TestDem::new(grid(45.0, 7.0, 0.01, 0.01, 9, 9), std::vec![100.0; 81], 8);
    let s = dem.storage();
    let p = Picker::new(&s).unwrap();
    f(&p, &s)
}

const UNIT: Unit = Unit {
    rows: [0, 8],
    cols: [0, 8],
    stride: 1,
    level: 0,
};

/// A slanted ray from 3 000 km above the unit, reaching it at `t = 1`, whose components all differ in size.
fn ray() -> Ray<f64> {
    let e = Ellipsoid::<f64>::wgs84();
    let target = e.geodetic_deg_to_ecef(45.04, 7.035, 100.0);
    let o = target.add_scaled(3.0e6, e.normal_deg(45.5, 6.0));
    Ray::new(o, target.minus(o)).unwrap()
}

fn norm1(v: V3<f64>) -> f64 {
    v.x.abs() + v.y.abs() + v.z.abs()
}

#[test]
fn the_units_cull_tolerance_is_32_eps_of_the_origin_the_farthest_step_and_the_equatorial_radius() {
    with_leaf(|p, _| {
        let ray = ray();
        let (o, d) = (ray.origin(), ray.dir());
        for (t_in, t_out) in [(0.0, 1.2), (-3.0, 1.5), (0.5, 7.0)] {
            let tr = p.unit_trace(&UNIT, &ray, t_in, t_out);
            let far = f64::max(f64::abs(t_in), f64::abs(t_out));
            let want = 32.0 * f64::EPSILON * (norm1(o) + far * norm1(d) + p.ellipsoid.a());
            assert!(
                (tr.cull.tol() - want).abs() <= 4.0 * f64::EPSILON * want,
                "{t_in}..{t_out}"
            );
            assert_eq!(tr.az_rate, o.x * d.y - o.y * d.x);
            assert_eq!(tr.tau, 64.0 * f64::EPSILON);
        }
    });
}

#[test]
fn a_columns_middle_meridian_wall_tolerance_and_row_magnitude_follow_their_formulas() {
    with_leaf(|p, s| {
        let ray = ray();
        let (o, d) = (ray.origin(), ray.dir());
        let tr = p.unit_trace(&UNIT, &ray, 0.0, 2.0);
        for k in [0u32, 3, 7] {
            // the whole ray's part inside the unit's column k, from far outside it on both sides
            let col = p.clip_column(&tr, k, -1.0, 2.0).unwrap();
            assert_eq!(col.cols, [k, k + 1]);
            // the middle meridian, λ_k + 0.005°
            let (sm, cm) = sin_cos_deg(7.0 + 0.01 * f64::from(k) + 0.005);
            let radial = (cm * o.x + sm * o.y, cm * d.x + sm * d.y);
            assert!(
                (col.radial.0 - radial.0).abs() <= 1e-15 * o.x.abs().max(o.y.abs()),
                "{k}"
            );
            assert!(
                (col.radial.1 - radial.1).abs() <= 1e-15 * d.x.abs().max(d.y.abs()),
                "{k}"
            );
            assert_eq!(col.cos_half, sin_cos_deg(0.005).1);
            // the row walls' magnitude over the column's part of the ray
            let far = f64::max(col.lo.abs(), col.hi.abs());
            let want = o.x.abs() + o.y.abs() + norm1(d) * far;
            assert!(
                (col.row_mag - want).abs() <= 4.0 * f64::EPSILON * want,
                "{k}"
            );
            // the part lies between the column's meridian planes, each widened by 64 ε of the coordinates'
            // magnitude over the interval asked for ([-1, 2]): the clip's ends are where a plane is at −tol
            let tol =
                64.0 * f64::EPSILON * ((o.x.abs() + o.y.abs()) + (d.x.abs() + d.y.abs()) * 2.0);
            let (sw, cw) = s.col_sin_cos(k);
            let (se, ce) = s.col_sin_cos(k + 1);
            let west = |t: f64| (cw * o.y - sw * o.x) + t * (cw * d.y - sw * d.x);
            let east = |t: f64| -(ce * o.y - se * o.x) - t * (ce * d.y - se * d.x);
            for (end, name) in [(col.lo, "lo"), (col.hi, "hi")] {
                let at_wall = (west(end) + tol).abs().min((east(end) + tol).abs());
                assert!(
                    at_wall <= 0.01 * tol,
                    "column {k}, {name}: {at_wall} from a widened wall (tol {tol})"
                );
            }
        }
    });
}
