use super::*;
use crate::geodesy::{Ellipsoid, sin_cos_deg};

/// A small xorshift generator: the test's cases are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The heights-only bound holds for vertices formed as the leaf walk forms them (`ecef_from_parts` from the
/// sines and cosines of the grid's latitudes and longitudes), in `T`: every vertex's up coordinate, as the
/// exact cull computes it, is at most `top_of` its height, over units from a few cells of 3″ to 20° wide,
/// anywhere from pole to pole, heights from −11 km to 9 km. Returns the largest slack `top_of(h) − up` seen
/// for the smallest units (8 × 8 cells of 3″), to show the bound is also tight enough to cull.
fn bound_holds<T: Real>(cases: usize) -> f64 {
    let e = Ellipsoid::<T>::wgs84();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut slack_small = 0.0f64;
    for k in 0..cases {
        // half spans of the unit, degrees
        let half = [3.0 / 3600.0 * 4.0, 0.05, 10.0][k % 3];
        let lat_mid = rng.range(-89.0 + half, 89.0 - half);
        let lon_mid = rng.range(-180.0, 180.0);
        let frame = LocalFrame::at(
            e.a(),
            sin_cos_deg(T::from_f64(lat_mid)),
            sin_cos_deg(T::from_f64(lon_mid)),
        );
        let cull = HeightCull::new(
            frame,
            (
                V3::new(T::ZERO, T::ZERO, T::ZERO),
                V3::new(T::ONE, T::ZERO, T::ZERO),
            ),
            T::ZERO,
            e.b(),
        );
        for _ in 0..8 {
            let lat = lat_mid + rng.range(-half, half);
            let lon = lon_mid + rng.range(-half, half);
            let h = T::from_f64(rng.range(-11_000.0, 9_000.0));
            let (s_lat, c_lat) = sin_cos_deg(T::from_f64(lat));
            let (s_lon, c_lon) = sin_cos_deg(T::from_f64(lon));
            let n = e.prime_vertical_radius(s_lat);
            let up = frame.up(e.ecef_from_parts(s_lat, c_lat, n, s_lon, c_lon, h));
            let top = cull.top_of(h);
            assert!(
                top >= up,
                "unit at ({lat_mid}, {lon_mid}) ± {half}°, vertex ({lat}, {lon}, {}): up {} above its bound {}",
                h.to_f64(),
                up.to_f64(),
                top.to_f64()
            );
            if half < 0.01 {
                slack_small = slack_small.max((top - up).to_f64());
            }
        }
    }
    slack_small
}

#[test]
fn heights_only_bound_is_above_every_vertex_in_f64_and_within_centimetres_on_leaf_sized_units() {
    let slack = bound_holds::<f64>(if cfg!(miri) { 30 } else { 30_000 });
    // Within ±12″ of the frame's vertex the spheroid falls about 2 cm below its tangent plane (2.1 cm measured):
    // the slack is that fall, not the rounding margin (1e-7 m), so the heights-only test culls nearly as well.
    assert!(slack < 0.05, "{slack}");
}

#[test]
fn heights_only_bound_is_above_every_vertex_in_f32() {
    bound_holds::<f32>(if cfg!(miri) { 30 } else { 30_000 });
}

/// Both culls from both sides of their tolerance: a cell is kept while the ray's part in it comes within `tol`
/// of the bound (0.5 and 0.9 of it) and skipped beyond (1.1 and 2 of it), for a ray climbing and one falling
/// across the cell, so that each end of its part in the cell is the one that counts once; and `top_of` is the
/// spheroid's top plus `h` plus `128 ε |h|`.
#[test]
fn each_cull_keeps_a_cell_within_its_tolerance_of_the_ray_and_skips_it_beyond() {
    let e = Ellipsoid::<f64>::wgs84();
    let ((sp, cp), (sl, cl)) = (sin_cos_deg(40.0), sin_cos_deg(10.0));
    let frame = LocalFrame::at(e.a(), (sp, cp), (sl, cl));
    let n = V3::new(cp * cl, cp * sl, sp); // the frame's up axis
    let east = V3::new(-sl, cl, 0.0);
    let base = e.geodetic_deg_to_ecef(40.0, 10.0, 0.0);
    // A point whose up coordinate is `z`, along the up axis from the base point.
    let at_up = |z: f64| {
        let p = base.add_scaled(z - frame.up(base), n);
        p.add_scaled(z - frame.up(p), n)
    };
    let tol = 1.0e-3;
    let (clo, chi) = (10.0, 30.0);
    let sides = [(0.5, false), (0.9, false), (1.1, true), (2.0, true)];
    for slope in [0.25, -0.25] {
        let cull = HeightCull::new(frame, (at_up(100.0), east.add_scaled(slope, n)), tol, e.b());
        let up = |t: f64| cull.up_origin + t * cull.up_rate;
        let (low, high) = (up(clo).min(up(chi)), up(clo).max(up(chi)));
        assert!(
            high - low > 4.0,
            "the ray's part in the cell spans {} m of height",
            high - low
        );
        for h in [-11.0e3, 0.0, 9.0e3] {
            let want = cull.spheroid_top + h + 128.0 * f64::EPSILON * h.abs();
            assert!(
                (cull.top_of(h) - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
                "{h}"
            );
        }
        for (k, skipped) in sides {
            // Heights whose bound lies k tolerances below the ray's lowest point in the cell.
            let h = low - k * tol - cull.spheroid_top;
            assert_eq!(
                cull.surely_above(h, clo, chi),
                skipped,
                "slope {slope}: heights {k} tol below"
            );
            // Corners whose highest is k tolerances below the ray's part, and whose lowest is k above it.
            let below = [
                Some(at_up(low - k * tol)),
                Some(at_up(low - 5.0)),
                None,
                Some(at_up(low - 9.0)),
            ];
            assert_eq!(
                cull.passes_clear_of(&below, clo, chi),
                skipped,
                "slope {slope}: {k} tol below"
            );
            let above = [
                Some(at_up(high + k * tol)),
                None,
                Some(at_up(high + 5.0)),
                Some(at_up(high + 9.0)),
            ];
            assert_eq!(
                cull.passes_clear_of(&above, clo, chi),
                skipped,
                "slope {slope}: {k} tol above"
            );
        }
    }
}
