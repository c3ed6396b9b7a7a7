//! The columns of a unit that a segment can cross ([`Picker::unit_columns`]) and the rows a column's segment can
//! cross ([`Picker::crossed_rows`]): those of its two ends' cells, and a column or row of margin only beyond a
//! meridian or row plane that an end lies within rounding of.

use super::*;
use crate::terrain::walk::Unit;

/// The full-resolution unit of these tests: rows `[2, 10]` and columns `[0, 8]` (45.02° – 45.10° N, 7.00° –
/// 7.08° E, cells 0.01° wide).
const UNIT: Unit = Unit {
    rows: [2, 10],
    cols: [0, 8],
    stride: 1,
    level: 0,
};

/// `f` with a picker over a flat 13 × 13-vertex grid at 45° N, 7° E holding [`UNIT`], its rows running north
/// when `north_up`, and the DEM.
fn with_picker<R>(
    north_up: bool,
    f: impl FnOnce(&Picker<'_, f64, Storage<'_>>, &TestDem) -> R,
) -> R {
    let dlat = if north_up { 0.01 } else { -0.01 };
    let dem = TestDem::new(grid(45.0, 7.0, dlat, 0.01, 13, 13), std::vec![0.0; 169], 4);
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    f(&p, &dem)
}

/// Row plane `i` at `t = i` along the ray, north of it for `t ≥ i` when `north_up` (rows run north), south of it
/// otherwise.
fn plane_at_t(north_up: bool) -> impl Fn(u32, f64) -> f64 {
    let sign = if north_up { 1.0 } else { -1.0 };
    move |i, t| sign * (t - f64::from(i))
}

/// [`UNIT`]'s rows with [`plane_at_t`]'s planes, far from the axis; `near` is 1/8. `crossed_rows` for the column
/// segment `[lo, hi]`, from `hint`: the rows and the new hint.
fn rows_of(north_up: bool, [lo, hi]: [f64; 2], hint: Option<i64>) -> ((u32, u32), i64) {
    with_picker(north_up, |p, _| {
        let mut hint = hint;
        let plane = plane_at_t(north_up);
        let rows = p.crossed_rows(&UNIT, [lo, hi], (1e7, 0.0), &plane, 0.125, &mut hint);
        (rows, hint.unwrap())
    })
}

#[test]
fn column_segment_ends_clear_of_row_planes_cross_only_the_rows_between_their_cells() {
    for north_up in [true, false] {
        for hint in [None, Some(1), Some(5), Some(10)] {
            let (rows, next) = rows_of(north_up, [4.5, 6.5], hint);
            assert_eq!(rows, (4, 7), "{north_up} {hint:?}");
            // the hint becomes the cell of the end at `hi`, where the next column in ray order begins
            assert_eq!(next, 6);
            assert_eq!(rows_of(north_up, [5.2, 5.8], hint).0, (5, 6));
        }
    }
}

#[test]
fn column_segment_ends_within_rounding_of_a_row_plane_add_the_row_beyond_it() {
    for north_up in [true, false] {
        // Either end of either cell, on either side of the plane: the row on the plane's far side is added.
        assert_eq!(rows_of(north_up, [4.05, 6.5], None).0, (3, 7));
        assert_eq!(rows_of(north_up, [3.95, 6.5], None).0, (3, 7));
        assert_eq!(rows_of(north_up, [4.5, 6.95], None).0, (4, 8));
        assert_eq!(rows_of(north_up, [4.5, 7.05], None).0, (4, 8));
        assert_eq!(rows_of(north_up, [5.05, 5.8], None).0, (4, 6));
        assert_eq!(rows_of(north_up, [5.2, 5.95], None).0, (5, 7));
        assert_eq!(rows_of(north_up, [5.05, 5.95], None).0, (4, 7));
        // Exactly `near` from the plane, either side: still near.
        assert_eq!(rows_of(north_up, [4.125, 6.5], None).0, (3, 7));
        assert_eq!(rows_of(north_up, [3.875, 6.5], None).0, (3, 7));
        assert_eq!(rows_of(north_up, [4.5, 6.875], None).0, (4, 8));
        assert_eq!(rows_of(north_up, [5.125, 5.875], None).0, (4, 7));
        // An end near a plane inside the span adds nothing.
        assert_eq!(rows_of(north_up, [4.5, 6.05], None).0, (4, 7));
        // On the unit's first and last planes: no row beyond the unit.
        assert_eq!(rows_of(north_up, [2.0, 2.5], None).0, (2, 3));
        assert_eq!(rows_of(north_up, [9.5, 10.0], None).0, (9, 10));
    }
}

#[test]
fn column_segment_outside_the_unit_or_near_the_axis() {
    for north_up in [true, false] {
        // Wholly before the unit's first plane, or past its last: no row.
        assert_eq!(rows_of(north_up, [0.5, 1.5], None).0, (2, 2));
        assert_eq!(rows_of(north_up, [10.5, 11.5], None).0, (10, 10));
        // From before the unit into it: from its first row.
        assert_eq!(rows_of(north_up, [1.5, 3.5], None).0, (2, 4));
    }
    // Near the axis (the planes may be unordered there) and for an infinite end, every row.
    with_picker(true, |p, _| {
        let mut hint = None;
        for (radial, span) in [((1.0, 0.0), [5.2, 5.8]), ((1e7, 0.0), [5.2, f64::INFINITY])] {
            let rows = p.crossed_rows(&UNIT, span, radial, &plane_at_t(true), 0.125, &mut hint);
            assert_eq!(rows, (2, 10));
        }
        assert_eq!(hint, None);
    });
}

/// `margin_near` against every row wall's tolerance `τ (row_mag + |o_z − k(ψ)|)` (the latitude cone's apex
/// `k(ψ)` for ψ from pole to pole), for origins from far below the centre to far above it: at least twice the
/// largest, and no more (the pole's apex is the farthest).
#[test]
fn margin_near_is_twice_the_largest_row_wall_tolerance_from_pole_to_pole() {
    let pole_apex = with_picker(true, |p, _| p.pole_apex);
    let e = Ellipsoid::<f64>::wgs84();
    let tau = 64.0 * f64::EPSILON;
    for o_z in [-4e7, -6.4e6, -1e5, 0.0, 3e4, 6.4e6, 4e7] {
        for row_mag in [0.0, 1e3, 7e6, 4e7] {
            let near = crate::terrain::leaf::margin_near(tau, row_mag, o_z, pole_apex);
            let widest = (-180..=180)
                .map(|k| {
                    let (sin, _) = sin_cos_deg(f64::from(k) * 0.5);
                    tau * (row_mag + (o_z - e.latitude_cone_apex(sin)).abs())
                })
                .fold(0.0, f64::max);
            assert!(
                near >= 2.0 * widest,
                "{o_z} {row_mag}: {near} < 2 × {widest}"
            );
            assert!(
                near <= 2.000_001 * widest,
                "{o_z} {row_mag}: {near} > 2 × {widest}"
            );
        }
    }
}

/// The rows are located only where the column's row planes are ordered, beyond `rows_ordered_beyond` from the
/// axis along the column's middle meridian at both ends of the segment (`radial_o + t·radial_d`); with one end
/// on that distance or inside it, every row of the unit.
#[test]
fn rows_are_located_only_when_both_ends_lie_beyond_the_ordered_distance() {
    with_picker(true, |p, _| {
        let r = p.rows_ordered_beyond;
        let plane = plane_at_t(true);
        let rows = |radial: (f64, f64), span: [f64; 2]| {
            p.crossed_rows(&UNIT, span, radial, &plane, 0.125, &mut None)
        };
        // Both ends beyond (r + 0.4 and r + 1.6, moving outwards): located.
        assert_eq!(rows((r - 10.0, 2.0), [5.2, 5.8]), (5, 6));
        // The far end inside (r + 0.3, then r − 0.3): every row.
        assert_eq!(rows((r + 5.5, -1.0), [5.2, 5.8]), (2, 10));
        // An end exactly at the distance, the other beyond: every row.
        assert_eq!(rows((r, 1.0), [0.0, 0.5]), (2, 10));
        assert_eq!(rows((r, -1.0), [-0.5, 0.0]), (2, 10));
        // Both beyond, before the unit: no row.
        assert_eq!(rows((r + 1.0, 1.0), [0.0, 0.5]), (2, 2));
    });
}

/// `unit_columns` over [`UNIT`] of the segment from `(45.05°, lon_a, 1000 m)` to `(45.05°, lon_b, 0 m)` (`t` from
/// 0 to 1).
fn columns_of(lon_a: f64, lon_b: f64) -> (u32, u32) {
    with_picker(true, |p, dem| {
        let e = dem.surface.e;
        let a = e.geodetic_deg_to_ecef(45.05, lon_a, 1000.0);
        let b = e.geodetic_deg_to_ecef(45.05, lon_b, 0.0);
        let ray = Ray::new(a, b.minus(a)).unwrap();
        p.unit_columns(&UNIT, &ray, 0.0, 1.0)
    })
}

#[test]
fn segment_ends_clear_of_meridians_cross_only_the_columns_between_their_cells() {
    assert_eq!(columns_of(7.025, 7.055), (2, 6));
    assert_eq!(columns_of(7.055, 7.025), (2, 6));
    // both ends in one column
    assert_eq!(columns_of(7.031, 7.039), (3, 4));
    assert_eq!(columns_of(7.005, 7.009), (0, 1));
    assert_eq!(columns_of(7.075, 7.079), (7, 8));
    // an end east of the unit: from its last column
    assert_eq!(columns_of(7.095, 7.075), (7, 8));
    // an end west of the unit: from its first column
    assert_eq!(columns_of(6.995, 7.015), (0, 2));
}

#[test]
fn segment_ends_on_a_meridian_add_the_column_beyond_it() {
    // On meridian 3 (7.03°), the other end in column 3: column 2 too, whichever side rounding puts the end on.
    assert_eq!(columns_of(7.03, 7.035), (2, 4));
    assert_eq!(columns_of(7.035, 7.03), (2, 4));
    // On meridian 5, the other end in column 4: column 5 too.
    assert_eq!(columns_of(7.045, 7.05), (4, 6));
    // On the unit's first and last meridians: no column beyond the unit.
    assert_eq!(columns_of(7.0, 7.005), (0, 1));
    assert_eq!(columns_of(7.075, 7.08), (7, 8));
}

#[test]
fn segment_behind_the_units_middle_meridian_gets_every_column() {
    // Through the Earth's centre: the far end lies in the opposite hemisphere, where the meridian planes' sides
    // do not order the columns.
    with_picker(true, |p, dem| {
        let a = dem.surface.e.geodetic_deg_to_ecef(45.05, 7.035, 1000.0);
        for (from, to) in [(a, a.negated()), (a.negated(), a)] {
            let ray = Ray::new(from, to.minus(from)).unwrap();
            assert_eq!(p.unit_columns(&UNIT, &ray, 0.0, 1.0), (0, 8));
        }
    });
}

/// An end of the segment `k` tolerances west of meridian 3 (its column 2), the other end high above column 1
/// (10 000 km up, so that the tolerance's direction part counts as much as its origin part), and the same
/// mirrored east of meridian 5 with the other end above column 7: the column beyond the meridian is added
/// exactly while `k < 1`, the tolerance being `64 ε (|o_x| + |o_y| + (|d_x| + |d_y|) max(|t_in|, |t_out|))`.
#[test]
fn segment_ends_within_the_meridian_tolerance_add_the_column_beyond_and_no_further() {
    with_picker(true, |p, dem| {
        let e = dem.surface.e;
        let s = dem.storage();
        for (m, other_lon, outward) in [(3u32, 7.015, 1.0), (5, 7.075, -1.0)] {
            let (sm, cm) = s.col_sin_cos(m);
            // The meridian plane's side `c·y − s·x` (east positive) and its unit gradient.
            let side = |q: V3<f64>| cm * q.y - sm * q.x;
            let grad = V3::new(-sm, cm, 0.0);
            let o = e
                .geodetic_deg_to_ecef(45.05, other_lon, 0.0)
                .add_scaled(1.0e7, e.normal_deg(45.05, other_lon));
            let on = e.geodetic_deg_to_ecef(45.05, 7.0 + 0.01 * f64::from(m), 0.0);
            let t_out = 2.0;
            for (k, beyond) in [(0.5, true), (0.95, true), (1.05, false), (2.0, false)] {
                // The end at t_out, k tolerances on the far side of the meridian from the other end (the
                // tolerance formed from the segment through `on`, which the end moves by far less than it).
                let d0 = on.minus(o).scaled(1.0 / t_out);
                let tol = 64.0
                    * f64::EPSILON
                    * ((o.x.abs() + o.y.abs()) + (d0.x.abs() + d0.y.abs()) * t_out);
                let end = on.add_scaled(-outward * k * tol - side(on), grad);
                let end = end.add_scaled(-outward * k * tol - side(end), grad);
                let ray = Ray::new(o, end.minus(o).scaled(1.0 / t_out)).unwrap();
                let cols = p.unit_columns(&UNIT, &ray, 0.0, t_out);
                let want = match (outward > 0.0, beyond) {
                    (true, true) => (1, 4),
                    (true, false) => (1, 3),
                    (false, true) => (4, 8),
                    (false, false) => (5, 8),
                };
                assert_eq!(cols, want, "meridian {m}, {k} tolerances on its far side");
            }
        }
    });
}

/// `unit_columns` over a grid of 10° columns (13 rows of 0.01° from 45° N, 36 columns from 0° E) for the
/// segment from `(a, 1000 m)` to `(b, 0 m)` (latitude, longitude), for a unit over columns `cols`.
fn wide_columns(cols: [u32; 2], a: [f64; 2], b: [f64; 2]) -> (u32, u32) {
    let dem = TestDem::new(
        grid(45.0, 0.0, 0.01, 10.0, 13, 37),
        std::vec![0.0; 13 * 37],
        4,
    );
    let s = dem.storage();
    let p: Picker<'_, f64, Storage<'_>> = Picker::new(&s).unwrap();
    let e = dem.surface.e;
    let a = e.geodetic_deg_to_ecef(a[0], a[1], 1000.0);
    let b = e.geodetic_deg_to_ecef(b[0], b[1], 0.0);
    let ray = Ray::new(a, b.minus(a)).unwrap();
    let unit = Unit {
        rows: [2, 10],
        cols,
        stride: 1,
        level: 0,
    };
    p.unit_columns(&unit, &ray, 0.0, 1.0)
}

/// A unit whose columns and one more span 180° or more gets every column: its meridians are not all within 90° of
/// the middle one, where the meridian planes' sides order the columns. Up to 170° they are searched: the segment
/// from 75° to 95° crosses columns 7 to 9. So is one from 113° to 127° in a unit 160° wide whose middle meridian
/// is 120° (columns 4 to 20; its columns 7 and 8), where that meridian's cosine is negative; a segment from 125°
/// through the Earth to the antipode of its start ends behind that meridian and gets every column.
#[test]
fn units_spanning_half_a_turn_get_every_column_and_narrower_ones_are_searched() {
    let lat = 45.05;
    let cols = |c: [u32; 2], a: f64, b: f64| wide_columns(c, [lat, a], [lat, b]);
    assert_eq!(cols([0, 18], 75.0, 95.0), (0, 18));
    assert_eq!(cols([0, 17], 75.0, 95.0), (0, 17));
    assert_eq!(cols([0, 16], 75.0, 95.0), (7, 10));
    assert_eq!(cols([0, 16], 95.0, 75.0), (7, 10));
    assert_eq!(cols([4, 20], 113.0, 127.0), (7, 9));
    assert_eq!(cols([4, 20], 127.0, 113.0), (7, 9));
    assert_eq!(wide_columns([4, 20], [lat, 125.0], [-lat, -55.0]), (0, 16));
    assert_eq!(wide_columns([4, 20], [-lat, -55.0], [lat, 125.0]), (0, 16));
}
