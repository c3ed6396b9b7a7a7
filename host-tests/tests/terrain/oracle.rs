//! Kernel `pick` against the independent terrain oracle (brute force over every triangle, 256-bit exact stage).
//!
//! Criterion (terrain issue, item 9): no miss, no false hit, the kernel's hit point within 1 µm of the oracle's
//! (f64, Earth scale); when the two report different triangles, the hit points must still agree within 1 µm (a
//! tie on a shared edge or vertex). A ray that passes within 1 µm of an edge or vertex is decided by rounding:
//! such a disagreement is accepted (and counted as `ambiguous`) only if the oracle, asked again with the ray
//! translated by 1 µm along one of the six axis directions or vertically, agrees with the kernel (both miss, or
//! hit points within 2 µm), and at most one ray in a thousand of a suite may be so excused (`ambiguous_allowed`;
//! the count is printed with each suite).
//!
//! Every ray also goes through `pick_t`, the same traversal without the refinement: it must report the same hit
//! status and cell as `pick`; the worst distance of its unrefined point from the oracle's is reported beside.
//! A hit's latitude, longitude (degrees, times 111 320 m) and height, seeded at its cell, must agree with the
//! closed-form conversion of its point within 1e-8 m (`geodesy_oracle` holds both to the exact inversion).
//!
//! The default run checks every suite on a reduced number of rays; the `#[ignore]`d `*_full` tests bring the
//! total above 100 000 rays (`cargo test -p curvicast-host --release --test terrain oracle -- --include-ignored`).

use crate::support;

use curvicast::Ray;
use curvicast::geodesy::Ellipsoid;
use curvicast::terrain::Picker;
use curvicast::vec3::V3;
use curvicast_cli::formats::real_dem;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::{Dem, geodetic_to_ecef_f64};
use curvicast_cli::storage::DemStorage;
use curvicast_host::oracle::terrain::TerrainOracle;
use curvicast_host::scenes::terrain_cases::{
    TerrainKind, camera_rays, orbit_rays, random_rays, synthetic,
};
use rayon::prelude::*;
use std::sync::OnceLock;

/// The table's bound on the hit point's distance from the oracle's, metres.
const TOL: f64 = curvicast_host::tolerances::TERRAIN_HIT_F64.bound;

#[derive(Default, Debug)]
struct Tally {
    rays: usize,
    hits: usize,
    misses: usize,
    false_hits: usize,
    far: usize,
    ambiguous: usize,
    worst: f64,
    /// The worst distance of `pick_t`'s unrefined point `o + t·d` from the oracle's hit.
    worst_t: f64,
    failures: Vec<String>,
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Runs every ray through the kernel and the oracle and tallies disagreements.
fn compare(dem: &Dem, block: usize, rays: &[RaySpec]) -> Tally {
    let storage = DemStorage::new(dem, block);
    let picker: Picker<'_, f64, DemStorage<'_>> = Picker::new(&storage).expect("picker");
    let oracle = TerrainOracle::new(dem);
    #[allow(clippy::type_complexity)]
    let results: Vec<(
        usize,
        Result<(Option<[f64; 3]>, Option<[f64; 3]>, bool, f64), String>,
    )> = rays
        .par_iter()
        .enumerate()
        .map(|(k, r)| {
            let ray = Ray::new(r.origin, r.dir)
                .and_then(|x| x.with_interval(r.t_min, r.t_max_or_inf()))
                .map_err(|e| format!("ray {k}: {e}"));
            let out = ray.and_then(|ray| {
                let hit = picker
                    .pick(&ray)
                    .map_err(|e| format!("ray {k}: kernel error {e}"))?;
                let ours = hit.map(|h| h.ecef);
                // The hit's geodetic coordinates (seeded at its cell) against the closed form's of its point.
                if let Some(h) = hit {
                    let g = Ellipsoid::<f64>::wgs84().ecef_to_geodetic(V3::from(h.ecef));
                    let dlon =
                        (h.lon_deg - g.lon_rad.to_degrees() + 540.0).rem_euclid(360.0) - 180.0;
                    let off =
                        [h.lat_deg - g.lat_rad.to_degrees(), dlon].map(|d| d.abs() * 111_320.0);
                    if off.iter().any(|&d| d > 1e-8) || (h.h - g.h).abs() > 1e-8 {
                        return Err(format!(
                            "ray {k}: hit ({}, {}, {}) vs closed form ({}, {}, {})",
                            h.lat_deg,
                            h.lon_deg,
                            h.h,
                            g.lat_rad.to_degrees(),
                            g.lon_rad.to_degrees(),
                            g.h
                        ));
                    }
                }
                let truth = oracle.pick(r).map(|h| h.point);
                // `pick_t` is the same traversal without the refinement: the same status and cell as `pick`.
                let fast = picker
                    .pick_t(&ray)
                    .map_err(|e| format!("ray {k}: kernel error in pick_t {e}"))?;
                if fast.map(|f| f.1) != hit.map(|h| h.cell) {
                    return Err(format!("ray {k} {r:?}: pick_t {fast:?} vs pick {hit:?}"));
                }
                let err_t = match (fast, truth) {
                    (Some((t, _)), Some(q)) => dist(ray.at(t), q),
                    _ => 0.0,
                };
                let agree = |q: Option<[f64; 3]>, tol: f64| match (ours, q) {
                    (None, None) => true,
                    (Some(a), Some(b)) => dist(a, b) <= tol,
                    _ => false,
                };
                if agree(truth, TOL) {
                    return Ok((ours, truth, false, err_t));
                }
                // Shifts: ±1 µm along each axis and along the radial (≈ vertical) direction at either hit.
                let mut shifts: Vec<[f64; 3]> = (0..6)
                    .map(|a| {
                        let mut v = [0.0; 3];
                        v[a % 3] = if a < 3 { 1e-6 } else { -1e-6 };
                        v
                    })
                    .collect();
                for p in [ours, truth].into_iter().flatten() {
                    let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                    shifts.push(p.map(|c| c / l * 1e-6));
                    shifts.push(p.map(|c| -c / l * 1e-6));
                }
                for sh in shifts {
                    let mut moved = *r;
                    for (c, d) in moved.origin.iter_mut().zip(sh) {
                        *c += d;
                    }
                    if agree(oracle.pick(&moved).map(|h| h.point), 2.0 * TOL) {
                        return Ok((ours, ours, true, 0.0));
                    }
                }
                Ok((ours, truth, false, err_t))
            });
            (k, out)
        })
        .collect();
    let mut t = Tally::default();
    for (k, res) in results {
        t.rays += 1;
        match res {
            Err(e) => t.failures.push(e),
            Ok((_, _, true, _)) => t.ambiguous += 1,
            Ok((None, None, _, _)) => {}
            Ok((Some(p), Some(q), _, err_t)) => {
                t.hits += 1;
                t.worst_t = t.worst_t.max(err_t);
                let e = dist(p, q);
                t.worst = t.worst.max(e);
                if e > TOL {
                    t.far += 1;
                    let d = rays[k].dir;
                    let ql = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
                    let dl = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    let sin_elev = ((d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / (ql * dl)).abs();
                    t.failures.push(format!(
                        "ray {k} {:?}: kernel {p:?} vs oracle {q:?} ({e} m; ray elevation {:.3}°, \
                         hit {:.0} m from the origin)",
                        rays[k],
                        sin_elev.asin().to_degrees(),
                        dist(rays[k].origin, q)
                    ));
                }
            }
            Ok((None, Some(q), _, _)) => {
                t.misses += 1;
                t.failures
                    .push(format!("ray {k} {:?}: MISS, oracle {q:?}", rays[k]));
            }
            Ok((Some(p), None, _, _)) => {
                t.false_hits += 1;
                t.failures
                    .push(format!("ray {k} {:?}: FALSE HIT {p:?}", rays[k]));
            }
        }
    }
    t
}

/// How many rays of a suite may be excused as ambiguous: one in a thousand (measured in the default run: none,
/// except in `grazing_rays_skimming_peaks`, which aims a third of its rays exactly at vertices and has its own
/// allowance). Each excuse is a disagreement the kernel and the oracle settle only by moving the origin 1 µm,
/// so their number is bounded, and reported.
fn ambiguous_allowed(rays: usize) -> usize {
    rays / 1000
}

fn report(name: &str, t: &Tally) -> usize {
    report_allowing(name, t, ambiguous_allowed(t.rays))
}

fn report_allowing(name: &str, t: &Tally, allowed: usize) -> usize {
    eprintln!(
        "{name}: {} rays, {} hits, {} misses, {} false hits, {} beyond 1 µm, {} ambiguous within 1 µm, worst {:.3e} m \
         (pick_t unrefined: worst {:.3e} m)",
        t.rays, t.hits, t.misses, t.false_hits, t.far, t.ambiguous, t.worst, t.worst_t
    );
    for f in t.failures.iter().take(5) {
        eprintln!("  {f}");
    }
    let excess = t.ambiguous > allowed;
    if excess {
        eprintln!(
            "  {} rays excused as ambiguous, more than the {allowed} allowed",
            t.ambiguous
        );
    }
    t.failures.len() + usize::from(excess)
}

fn assert_clean(name: &str, t: &Tally) {
    assert_clean_allowing(name, t, ambiguous_allowed(t.rays));
}

fn assert_clean_allowing(name: &str, t: &Tally, allowed_ambiguous: usize) {
    let n = report_allowing(name, t, allowed_ambiguous);
    assert_eq!(
        n, 0,
        "{name}: {n} failures or too many ambiguous rays ({} of at most {allowed_ambiguous}; listed above)",
        t.ambiguous
    );
}

fn scale(default: usize, full: usize, is_full: bool) -> usize {
    if is_full { full } else { default }
}

fn synthetic_suite(kind: TerrainKind, n: usize, seed: u64) -> usize {
    let mut failed = 0;
    let geos = [
        (36.0, -118.0, 0.01, 0.01, 40, 40),
        (-20.0, 140.0, -0.05, 0.07, 33, 47),
        (61.0, 10.0, 0.2, 0.3, 30, 30),
        (80.0, -30.0, 0.25, 1.0, 30, 40),
        (-5.0, 175.0, 0.1, 0.1, 64, 64),
    ];
    for (g, &(lat0, lon0, dlat, dlon, r, c)) in geos.iter().enumerate() {
        let dem = synthetic(kind, (lat0, lon0, dlat, dlon), (r, c), seed + g as u64);
        for block in [4, 16] {
            let rays = random_rays(&dem, n, seed * 31 + g as u64);
            let t = compare(&dem, block, &rays);
            failed += report(&format!("{kind:?} geo {g} block {block}"), &t);
            assert!(t.hits > 0);
        }
    }
    failed
}

#[test]
fn synthetic_flat() {
    assert_eq!(synthetic_suite(TerrainKind::Flat, 150, 1), 0);
}
#[test]
fn synthetic_fractal() {
    assert_eq!(synthetic_suite(TerrainKind::Fractal, 150, 2), 0);
}
#[test]
fn synthetic_spiky() {
    assert_eq!(synthetic_suite(TerrainKind::Spiky, 150, 3), 0);
}
#[test]
fn synthetic_negative_heights() {
    assert_eq!(synthetic_suite(TerrainKind::Negative, 150, 4), 0);
}

#[test]
#[ignore = "long: part of the 100 000-ray suite"]
fn synthetic_all_kinds_full() {
    let mut failed = 0;
    let kinds = [
        TerrainKind::Flat,
        TerrainKind::Fractal,
        TerrainKind::Spiky,
        TerrainKind::Negative,
    ];
    // CI's long step runs one shard of each full suite per commit (support::long_shard).
    for (k, kind) in support::long_shard(kinds.into_iter().enumerate().collect()) {
        failed += synthetic_suite(kind, 1500, 100 + k as u64);
    }
    assert_eq!(failed, 0);
}

fn trinidad() -> &'static Dem {
    static D: OnceLock<Dem> = OnceLock::new();
    D.get_or_init(|| real_dem::trinidad().expect("shipped Trinidad DEM"))
}

fn etopo() -> &'static Dem {
    static D: OnceLock<Dem> = OnceLock::new();
    D.get_or_init(|| real_dem::etopo20().expect("shipped ETOPO20 DEM"))
}

fn real_suite(dem: &Dem, name: &str, full: bool) {
    let n = scale(100, 10_000, full);
    let mut rays = random_rays(dem, n, 7);
    rays.extend(camera_rays(dem, n, 2000.0, 8));
    rays.extend(orbit_rays(dem, n / 2, 9));
    if full {
        rays = support::long_shard(rays);
    }
    let t = compare(dem, 16, &rays);
    assert_clean(name, &t);
    assert!(
        t.hits > rays.len() / 5,
        "{} hits of {} rays",
        t.hits,
        rays.len()
    );
}

#[test]
fn real_trinidad() {
    real_suite(trinidad(), "trinidad", false);
}
#[test]
fn real_etopo20() {
    real_suite(etopo(), "etopo20", false);
}
#[test]
#[ignore = "long: part of the 100 000-ray suite"]
fn real_trinidad_full() {
    real_suite(trinidad(), "trinidad full", true);
}
#[test]
#[ignore = "long: part of the 100 000-ray suite"]
fn real_etopo20_full() {
    real_suite(etopo(), "etopo20 full", true);
}

// ---- adversarial, named by geometry -------------------------------------------------------------------------

fn ecef(dem: &Dem, lat: f64, lon: f64, h: f64) -> [f64; 3] {
    geodetic_to_ecef_f64(dem.a, dem.b, lat, lon, h)
}

fn toward(o: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    [p[0] - o[0], p[1] - o[1], p[2] - o[2]]
}

fn polar_dem(seed: u64) -> Dem {
    // 60°N to the pole in 0.5° rows, 2° columns all around (the last column repeats the first). The pole row
    // (row 60) is one point, so it gets one height (the contract: all its vertices coincide).
    let mut d = synthetic(
        TerrainKind::Fractal,
        (60.0, -180.0, 0.5, 2.0),
        (61, 181),
        seed,
    );
    let h = d.heights[60 * 181];
    d.heights[60 * 181..].fill(h);
    for i in 0..61 {
        d.heights[i * 181 + 180] = d.heights[i * 181];
    }
    d
}

#[test]
fn steep_rays_at_latitude_borders_of_quads_60_to_89_degrees() {
    let dem = polar_dem(11);
    let mut rays = Vec::new();
    // Quad borders of blocks of 4 cells fall on every 4th row (2° of latitude); aim exactly at them, and a hair
    // either side, from steep directions tilted north and south.
    for i in (0..61).step_by(2) {
        let lat = dem.lat(i);
        for (k, dl) in [-1e-9, 0.0, 1e-9, 1e-4].into_iter().enumerate() {
            for lon in [-170.3, -33.0, 0.7, 91.1, 179.0] {
                let target = ecef(&dem, (lat + dl).min(90.0), lon, 500.0);
                for tilt in [-0.02, 0.0, 0.02] {
                    let top = ecef(
                        &dem,
                        (lat + tilt * 10.0).clamp(-90.0, 90.0),
                        lon + 0.01 * k as f64,
                        30_000.0,
                    );
                    rays.push(RaySpec::new(top, toward(top, target)));
                }
            }
        }
    }
    for block in [2, 4, 16] {
        assert_clean(
            &format!("lat borders block {block}"),
            &compare(&dem, block, &rays),
        );
    }
}

#[test]
fn grazing_rays_skimming_peaks() {
    let dem = synthetic(TerrainKind::Spiky, (45.0, 7.0, -0.01, 0.01), (60, 60), 12);
    let mut rays = Vec::new();
    for i in 1..59 {
        for j in 1..59 {
            let Some(h) = dem.height(i, j) else { continue };
            if h < 1000.0 {
                continue;
            }
            // Horizontal-ish rays passing 1 mm above, at, and 1 mm below the peak vertex, from 30 km away.
            for dh in [1e-3, 0.0, -1e-3] {
                let peak = ecef(&dem, dem.lat(i), dem.lon(j), f64::from(h) + dh);
                for az in [0.0f64, 1.3, 2.9] {
                    let far = ecef(
                        &dem,
                        dem.lat(i) + 0.27 * az.cos(),
                        dem.lon(j) + 0.27 * az.sin(),
                        f64::from(h) + dh + 60.0,
                    );
                    rays.push(RaySpec::new(far, toward(far, peak)));
                }
            }
        }
    }
    assert!(rays.len() > 50);
    // A third of the rays pass exactly through a peak vertex (dh = 0), where rounding decides which of the
    // triangles around it is hit: only those may be ambiguous (measured: 132 of 1467 rays).
    assert_clean_allowing("grazing peaks", &compare(&dem, 8, &rays), rays.len() / 3);
}

/// Rays descending at 0.1° elevation onto flat terrain (500 m, 3° × 3° at 0.02°), hitting 150 km from their
/// origin: a vertex error δ moves such a hit by δ / sin 0.1° ≈ 570 δ along the ray, so `f64` vertices alone
/// (δ ≈ 1e-9 m) give about 1 µm; the kernel's double-double refinement of the hit must agree with the oracle
/// within 0.2 µm.
#[test]
fn grazing_ray_at_0_1_degrees_over_flat_terrain_150_km_away_within_0_2_micrometres() {
    let (rows, cols) = (151, 151);
    let dem = Dem::wgs84(
        (44.0, 6.0, 0.02, 0.02),
        (rows, cols),
        vec![500.0; rows * cols],
    )
    .expect("flat DEM");
    let (elev, range) = (0.1_f64.to_radians(), 150_000.0);
    let mut rays = Vec::new();
    for (lat, lon) in [(45.5, 7.5), (45.513, 7.4871), (45.4917, 7.5233)] {
        let target = ecef(&dem, lat, lon, 500.0);
        let (sp, cp) = lat.to_radians().sin_cos();
        let (sl, cl) = lon.to_radians().sin_cos();
        let up = [cp * cl, cp * sl, sp];
        let east = [-sl, cl, 0.0];
        let north = [-sp * cl, -sp * sl, cp];
        for k in 0..12 {
            let az = (30.0 * k as f64 + 7.0).to_radians();
            let d: [f64; 3] = std::array::from_fn(|c| {
                elev.cos() * (az.cos() * north[c] + az.sin() * east[c]) - elev.sin() * up[c]
            });
            let origin: [f64; 3] = std::array::from_fn(|c| target[c] - range * d[c]);
            rays.push(RaySpec::new(origin, d));
        }
    }
    let t = compare(&dem, 16, &rays);
    assert_clean("grazing 0.1° at 150 km", &t);
    assert_eq!((t.hits, t.ambiguous), (rays.len(), 0));
    assert!(t.worst <= 2e-7, "worst {:.3e} m", t.worst);
}

#[test]
fn rays_crossing_the_antimeridian() {
    let dem = synthetic(
        TerrainKind::Fractal,
        (-10.0, 170.0, 0.25, 0.25),
        (81, 81),
        13,
    );
    let mut rays = Vec::new();
    for k in 0..300 {
        let lat = -9.0 + (k % 30) as f64 * 0.6;
        let from = ecef(
            &dem,
            lat,
            177.0 + (k % 7) as f64 * 0.1,
            5000.0 + 100.0 * (k % 11) as f64,
        );
        let to = ecef(&dem, lat + 0.3, -176.0 - (k % 5) as f64 * 0.2, -200.0);
        rays.push(RaySpec::new(from, toward(from, to)));
        rays.push(RaySpec::new(to, toward(to, from))); // from below, back across
    }
    let t = compare(&dem, 16, &rays);
    assert_clean("antimeridian", &t);
    assert!(t.hits > 300);
}

#[test]
fn rays_over_and_through_the_poles() {
    let dem = polar_dem(14);
    let mut rays = Vec::new();
    for k in 0..200 {
        let lon = -180.0 + 1.8 * k as f64;
        let from = ecef(&dem, 80.0, lon, 3000.0 + 10.0 * k as f64);
        // Straight over the pole to the other side, skimming.
        let to = ecef(&dem, 80.0, lon + 180.0, 0.0);
        rays.push(RaySpec::new(from, toward(from, to)));
        // Down through the pole region (the pole row is a vertex shared by all columns).
        let to = ecef(&dem, 89.9, lon + 90.0, -1000.0);
        rays.push(RaySpec::new(from, toward(from, to)));
    }
    // Straight down the axis, and up the axis from the centre.
    rays.push(RaySpec::new([0.0, 0.0, 1.0e7], [0.0, 0.0, -1.0]));
    rays.push(RaySpec::new([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]));
    rays.push(RaySpec::new([1e-3, -1e-3, 7.0e6], [0.0, 0.0, -1.0]));
    let t = compare(&dem, 4, &rays);
    assert_clean("poles", &t);
    assert!(t.hits > 200);
}

#[test]
fn rays_from_orbit_4e7_meters() {
    for (g, dem) in [
        synthetic(
            TerrainKind::Fractal,
            (36.0, -118.0, 0.01, 0.01),
            (64, 64),
            15,
        ),
        polar_dem(16),
    ]
    .iter()
    .enumerate()
    {
        let rays = orbit_rays(dem, 400, 17 + g as u64);
        let t = compare(dem, 8, &rays);
        assert_clean(&format!("orbit {g}"), &t);
        assert!(t.hits > 300);
    }
}

#[test]
fn rays_starting_one_meter_above_ground() {
    let dem = synthetic(
        TerrainKind::Fractal,
        (36.0, -118.0, 0.002, 0.002),
        (64, 64),
        18,
    );
    let mut rays = Vec::new();
    for i in (1..63).step_by(3) {
        for j in (1..63).step_by(3) {
            let h = f64::from(dem.height(i, j).unwrap_or(0.0));
            let o = ecef(&dem, dem.lat(i), dem.lon(j), h + 1.0);
            for (a, b) in [(0.01, 0.0), (0.0, -0.01), (-0.004, 0.003), (0.0, 0.0)] {
                let to = ecef(&dem, dem.lat(i) + a, dem.lon(j) + b, h - 50.0);
                rays.push(RaySpec::new(o, toward(o, to)));
            }
        }
    }
    let t = compare(&dem, 8, &rays);
    assert_clean("one meter above", &t);
    assert!(t.hits > rays.len() / 2);
}

#[test]
fn rays_starting_below_the_surface() {
    let dem = synthetic(
        TerrainKind::Fractal,
        (36.0, -118.0, 0.005, 0.005),
        (64, 64),
        19,
    );
    let mut rays = Vec::new();
    for k in 0..400 {
        let i = 1 + (k * 7) % 61;
        let j = 1 + (k * 13) % 61;
        let h = f64::from(dem.height(i, j).unwrap_or(0.0));
        let o = ecef(
            &dem,
            dem.lat(i) + 1e-4,
            dem.lon(j) + 2e-4,
            h - 20.0 - k as f64,
        );
        let up = ecef(
            &dem,
            dem.lat(i) + 0.02 * ((k % 5) as f64 - 2.0),
            dem.lon(j),
            h + 3000.0,
        );
        rays.push(RaySpec::new(o, toward(o, up)));
    }
    let t = compare(&dem, 8, &rays);
    assert_clean("below the surface", &t);
    assert!(t.hits > 300);
}

#[test]
fn rays_aimed_at_the_earths_center() {
    let mut rays = Vec::new();
    let dem = synthetic(TerrainKind::Spiky, (-45.0, 100.0, 0.1, 0.1), (50, 50), 20);
    for k in 0..300 {
        let o = ecef(
            &dem,
            -45.0 + 0.016 * k as f64,
            100.0 + 0.0163 * k as f64,
            8000.0 + 100.0 * k as f64,
        );
        rays.push(RaySpec::new(o, o.map(|c| -c)));
    }
    let t = compare(&dem, 4, &rays);
    assert_clean("to the centre", &t);
    assert!(t.hits > 250);
}

#[test]
#[ignore = "long: part of the 100 000-ray suite"]
fn random_synthetic_terrains_full() {
    let mut failed = 0;
    for s in support::long_shard((0..40u64).collect()) {
        let kind = [
            TerrainKind::Flat,
            TerrainKind::Fractal,
            TerrainKind::Spiky,
            TerrainKind::Negative,
        ][s as usize % 4];
        let lat0 = -85.0 + (s as f64 * 37.0) % 160.0;
        let lon0 = -180.0 + (s as f64 * 71.0) % 350.0;
        let dem = synthetic(
            kind,
            (lat0, lon0, 0.05 + 0.01 * (s % 5) as f64, 0.07),
            (48, 48),
            200 + s,
        );
        let mut rays = random_rays(&dem, 1000, 300 + s);
        rays.extend(orbit_rays(&dem, 250, 400 + s));
        rays.extend(camera_rays(&dem, 250, 2000.0, 500 + s));
        failed += report(
            &format!("random terrain {s} {kind:?}"),
            &compare(&dem, [4, 8, 16][s as usize % 3], &rays),
        );
    }
    assert_eq!(failed, 0, "{failed} failures (listed above)");
}
