use super::*;
use curvicast_cli::formats::terrain::{WGS84_A, WGS84_B};

const R: f64 = 6_371_000.0;

fn unit(lat: f64, lon: f64) -> [f64; 3] {
    let (p, l) = (lat.to_radians(), lon.to_radians());
    [p.cos() * l.cos(), p.cos() * l.sin(), p.sin()]
}

fn sphere_flat(geo: (f64, f64, f64, f64), shape: (usize, usize), h: f32) -> Dem {
    Dem::new(R, R, geo, shape, vec![h; shape.0 * shape.1], None).unwrap()
}

#[test]
fn to_f64_rounds_big_floats() {
    for x in [1.0, -2.5, 6378137.0, 1e-300, 3.0e12, 0.1, -123456.789] {
        assert_eq!(to_f64(&bf(x)), x);
    }
    let third = bf(1.0).div(&bf(3.0), P, RM);
    assert_eq!(to_f64(&third), 1.0 / 3.0);
}

#[test]
fn radial_ray_through_a_vertex_of_flat_terrain_on_a_sphere() {
    let dem = sphere_flat((10.0, 20.0, 1.0, 1.0), (6, 6), 500.0);
    let o = TerrainOracle::new(&dem);
    let u = unit(12.0, 23.0);
    let k = R + 4.0e7;
    let ray = RaySpec::new(u.map(|c| c * k), u.map(|c| -c));
    let h = o.pick(&ray).unwrap();
    assert!((h.t - (k - R - 500.0)).abs() < 1e-6, "{h:?}");
    // From the centre outwards, the same point.
    let ray = RaySpec::new([0.0; 3], u);
    let h2 = o.pick(&ray).unwrap();
    assert!((h2.t - (R + 500.0)).abs() < 1e-6, "{h2:?}");
    for a in 0..3 {
        assert!((h.point[a] - h2.point[a]).abs() < 1e-6);
    }
}

#[test]
fn radial_ray_through_a_cell_centre_hits_the_chord_plane() {
    let dem = sphere_flat((10.0, 20.0, 1.0, 1.0), (6, 6), 0.0);
    let o = TerrainOracle::new(&dem);
    // Through the middle of cell (2, 3)'s diagonal: the hit is the midpoint of the chord V(2,3)–V(3,4).
    let a = unit(12.0, 23.0).map(|c| c * R);
    let b = unit(13.0, 24.0).map(|c| c * R);
    let m = [0, 1, 2].map(|k| (a[k] + b[k]) / 2.0);
    let ml = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    let u = m.map(|c| c / ml);
    let h = o.pick(&RaySpec::new([0.0; 3], u)).unwrap();
    assert!((h.t - ml).abs() < 1e-6, "{} vs {ml}", h.t);
    assert_eq!(h.cell, (2, 3));
    // The chord is below the sphere by the sagitta.
    assert!(R - ml > 10.0);
}

#[test]
fn rays_outside_the_extent_and_through_missing_vertices_miss() {
    let mut dem = sphere_flat((10.0, 20.0, 1.0, 1.0), (6, 6), 0.0);
    let o = TerrainOracle::new(&dem);
    let u = unit(30.0, 23.0);
    assert!(o.pick(&RaySpec::new([0.0; 3], u)).is_none());
    let u = unit(12.5, 23.5);
    assert!(o.pick(&RaySpec::new([0.0; 3], u)).is_some());
    dem.heights[2 * 6 + 3] = f32::NAN; // vertex (2, 3): cell (2, 3) loses both triangles
    let o = TerrainOracle::new(&dem);
    assert!(o.pick(&RaySpec::new([0.0; 3], u)).is_none());
    let u = unit(12.1, 23.9); // cell (2, 3) upper triangle corner near (2, 4): still uses V(2,3)
    assert!(o.pick(&RaySpec::new([0.0; 3], u)).is_none());
    let u = unit(14.5, 24.5);
    assert!(o.pick(&RaySpec::new([0.0; 3], u)).is_some());
}

#[test]
fn t_interval_is_respected_and_the_nearest_of_two_crossings_wins() {
    let dem = sphere_flat((-10.0, -10.0, 1.0, 1.0), (21, 21), 0.0);
    let o = TerrainOracle::new(&dem);
    // A chord 50 km below the top of the sphere: enters the cap near lon -7.2° and leaves near +7.2°.
    let p = [R - 5.0e4, -1.2e6, 0.0];
    let d = [0.0, 1.0, 0.0];
    let h = o.pick(&RaySpec::new(p, d)).unwrap();
    let mut r2 = RaySpec::new(p, d);
    r2.t_min = h.t + 1.0;
    let h2 = o.pick(&r2).unwrap();
    assert!(h2.t > h.t + 1.0);
    r2.t_max = Some(h.t - 1.0);
    r2.t_min = 0.0;
    assert!(o.pick(&r2).is_none());
    // Both points are on the sphere-ish surface.
    for q in [h.point, h2.point] {
        let r = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
        assert!(r <= R + 1e-6 && r > R - 2000.0, "{r}");
    }
}

#[test]
fn ray_down_the_axis_hits_the_pole_vertex() {
    let dem = Dem::new(
        WGS84_A,
        WGS84_B,
        (90.0, -180.0, -1.0, 10.0),
        (4, 37),
        vec![100.0; 4 * 37],
        None,
    )
    .unwrap();
    let o = TerrainOracle::new(&dem);
    let h = o
        .pick(&RaySpec::new([0.0, 0.0, 1.0e7], [0.0, 0.0, -1.0]))
        .unwrap();
    assert!((h.t - (1.0e7 - WGS84_B - 100.0)).abs() < 1e-6, "{h:?}");
    assert_eq!(h.cell.0, 0);
}

#[test]
fn antimeridian_grid_is_hit_on_both_sides() {
    let dem = sphere_flat((-5.0, 170.0, 1.0, 1.0), (11, 21), 0.0);
    let o = TerrainOracle::new(&dem);
    for lon in [175.3, -175.3, 179.99, -179.99, 179.5] {
        let h = o.pick(&RaySpec::new([0.0; 3], unit(0.5, lon))).unwrap();
        assert!(h.t > R - 1000.0 && h.t <= R, "{lon}: {h:?}");
        let j = (lon.rem_euclid(360.0_f64) - 170.0).floor() as usize;
        assert_eq!(h.cell, (5, j), "{lon}");
    }
    assert!(o.pick(&RaySpec::new([0.0; 3], unit(0.5, -169.0))).is_none());
}

#[test]
fn grazing_ray_above_the_maximum_misses_and_below_hits() {
    let dem = sphere_flat((-1.0, -1.0, 0.1, 0.1), (21, 21), 1000.0);
    let o = TerrainOracle::new(&dem);
    let p = [R + 1001.0, -2.0e5, 0.0];
    assert!(o.pick(&RaySpec::new(p, [0.0, 1.0, 0.0])).is_none());
    let p = [R + 990.0, -2.0e5, 0.0];
    let h = o.pick(&RaySpec::new(p, [0.0, 1.0, 0.0])).unwrap();
    assert!(h.point[1] < 0.0 && h.point[1] > -1.2e5, "{h:?}");
}

#[test]
fn agrees_with_f64_brute_force_on_a_rough_terrain() {
    let (rows, cols) = (12, 15);
    let h: Vec<f32> = (0..rows * cols)
        .map(|k| ((k * 7919 % 997) as f32) * 3.0 - 500.0)
        .collect();
    let dem = Dem::wgs84((45.0, 7.0, -0.01, 0.01), (rows, cols), h).unwrap();
    let o = TerrainOracle::new(&dem);
    let c = dem.vertex_ecef(6, 7).unwrap();
    let mut hits = 0;
    for n in 0..200 {
        let a = n as f64 * 0.7;
        let origin = [
            c[0] * 1.0001,
            c[1] * 1.0001 + 500.0 * a.sin(),
            c[2] * 1.0001,
        ];
        let target = dem.vertex_ecef(1 + n % 10, 1 + (n * 7) % 13).unwrap();
        let dir = [0, 1, 2].map(|k| target[k] - origin[k] + 300.0 * (a * (k as f64 + 1.0)).cos());
        let ray = RaySpec::new(origin, dir);
        let ours = o.pick(&ray);
        let bf = brute_force_f64(&dem, &ray);
        match (ours, bf) {
            (Some(x), Some((t, _))) => {
                hits += 1;
                assert!(
                    (x.t - t).abs() <= 1e-9 * t.abs().max(1.0),
                    "{n}: {} vs {t}",
                    x.t
                )
            }
            (None, None) => {}
            _ => panic!("ray {n}: oracle {ours:?} vs f64 {bf:?}"),
        }
    }
    assert!(hits > 100, "{hits}");
}
