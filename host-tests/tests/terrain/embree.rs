//! Embree as a baseline (`--features embree`): its hits over the DEM's triangles agree with the oracle's up to
//! the `f32` rounding of its vertices and rays, and that rounding is what its ECEF frame pays for at Earth scale.

use curvicast_host::baselines::embree::{EmbreeTerrain, Frame};
use curvicast_host::oracle::terrain::TerrainOracle;
use curvicast_host::scenes::terrain_cases::{TerrainKind, camera_rays, orbit_rays, synthetic};

/// The largest distance `|t − t_oracle|·|d|` over rays both hit, and the rays whose hit or miss differs.
fn against_oracle(
    e: &EmbreeTerrain,
    oracle: &TerrainOracle<'_>,
    rays: &[curvicast_cli::formats::spec::RaySpec],
) -> (f64, usize) {
    let (mut max, mut differs) = (0.0_f64, 0);
    for r in rays {
        match (e.pick(r), oracle.pick(r)) {
            (Some(t), Some(h)) => {
                let dl = r.dir.iter().map(|x| x * x).sum::<f64>().sqrt();
                max = max.max((t - h.t).abs() * dl);
            }
            (None, None) => {}
            _ => differs += 1,
        }
    }
    (max, differs)
}

#[test]
fn embree_in_a_local_frame_hits_the_oracles_triangles_within_f32_rounding_and_ecef_does_not() {
    let dem = synthetic(
        TerrainKind::Fractal,
        (36.0, -118.0, -1.0 / 1200.0, 1.0 / 1200.0),
        (129, 129),
        7,
    );
    let oracle = TerrainOracle::new(&dem);
    let local = EmbreeTerrain::new(&dem, Frame::Local).unwrap();
    let ecef = EmbreeTerrain::new(&dem, Frame::Ecef).unwrap();
    assert!(
        local.memory_bytes() > 0,
        "Embree's memory monitor reported nothing"
    );
    let camera = camera_rays(&dem, 200, 2000.0, 3);
    let (local_max, local_differs) = against_oracle(&local, &oracle, &camera);
    let (ecef_max, _) = against_oracle(&ecef, &oracle, &camera);
    // In the local frame the coordinates are within about 10 km: f32 rounds them to about a millimetre, and a
    // hit moves by that over the slope of the terrain.
    assert!(local_max < 0.05, "local frame: {local_max} m");
    assert!(
        local_differs <= 2,
        "local frame: {local_differs} of 200 differ"
    );
    // In ECEF the coordinates are about 6.4e6 m: f32 rounds them to about half a metre.
    assert!(
        ecef_max > 10.0 * local_max,
        "ECEF {ecef_max} m, local {local_max} m"
    );
    // From orbit (4e7 m) the ray origin itself rounds to metres in either frame.
    let orbit = orbit_rays(&dem, 100, 4);
    let (orbit_max, orbit_differs) = against_oracle(&local, &oracle, &orbit);
    assert!(
        orbit_max < 50.0 && orbit_differs <= 2,
        "orbit: {orbit_max} m, {orbit_differs} differ"
    );
}
