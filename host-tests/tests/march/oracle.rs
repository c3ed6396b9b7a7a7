//! Marching (Hannasch) against the independent oracle: closed-form checks of the oracle itself, one
//! named test per hard case with both engines, and the random suite.
//!
//! Criterion (issue 3, item 7), in f64: the engine's list satisfies the contract's structural invariants; after
//! dropping crossings shorter than 1e-7·L from both lists, the cell sequences are identical; every crossing point
//! lies within 16·eps·L of its boundary surface. f32 and f32-fast are measured and printed; for them only the
//! structural invariants are asserted (the contract holds in every precision).
//!
//! The full random suite (≥ 200 000 rays) is `cargo test -p curvicast-host --test march oracle -- --ignored`, or
//! `curvicast-march-oracle --rays 200000`.

use crate::support;

use curvicast_cli::formats::spec::{GridSpec, RaySpec};
use curvicast_host::march_run::{self as run, Engine, Precision, Rounded};
use curvicast_host::oracle::march::{KernelCrossing, MarchOracle, compare};
use curvicast_host::scenes::march_cases::{self as mc, Case};
use curvicast_host::tolerances::MARCH_F64_BOUNDARY;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

fn sph(r: &[f64], theta: &[f64], phi: &[f64]) -> GridSpec {
    GridSpec::Spherical {
        center: None,
        r: r.to_vec(),
        theta: theta.to_vec(),
        phi: phi.to_vec(),
    }
}

fn oracle_list(g: &GridSpec, ray: &RaySpec) -> Vec<([Option<u32>; 3], f64, f64)> {
    let o = MarchOracle::new(g).unwrap();
    let r = o.march(ray);
    o.check_oracle_structure(&r).unwrap();
    r.crossings
        .iter()
        .map(|c| (c.cell, c.t_enter, c.t_exit))
        .collect()
}

fn s3(c: [u32; 3]) -> [Option<u32>; 3] {
    c.map(Some)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs()).max(1.0)
}

fn assert_list(got: &[([Option<u32>; 3], f64, f64)], want: &[([Option<u32>; 3], f64, f64)]) {
    assert_eq!(got.len(), want.len(), "got {got:?}\nwant {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.0, w.0, "got {got:?}\nwant {want:?}");
        assert!(
            close(g.1, w.1) && close(g.2, w.2),
            "got {got:?}\nwant {want:?}"
        );
    }
}

// ---- the oracle against closed forms -------------------------------------------------------------------------

#[test]
fn oracle_chord_through_single_shell() {
    let g = sph(&[0.0, 1.0], &[0.0, PI], &[0.0, TAU]);
    let got = oracle_list(&g, &RaySpec::new([-2.0, 0.6, 0.0], [1.0, 0.0, 0.0]));
    assert_list(&got, &[(s3([0, 0, 0]), 1.2, 2.8)]);
}

#[test]
fn oracle_diameter_in_plane_z0_with_known_cells() {
    // z = 0 is θ = π/2, which the half-open rule puts in band 1; x < 0, y = 0 is φ = π > f64 π: sector 1
    let g = sph(&[0.0, 0.5, 1.0], &[0.0, FRAC_PI_2, PI], &[0.0, PI, TAU]);
    let got = oracle_list(&g, &RaySpec::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]));
    assert_list(
        &got,
        &[
            (s3([1, 1, 1]), 1.0, 1.5),
            (s3([0, 1, 1]), 1.5, 2.0),
            (s3([0, 1, 0]), 2.0, 2.5),
            (s3([1, 1, 0]), 2.5, 3.0),
        ],
    );
}

#[test]
fn oracle_diagonal_through_origin_emits_tie_cells_in_canonical_order() {
    // before the origin θ = acos(−1/√3) ≈ 2.19, φ = 5π/4; after θ ≈ 0.96, φ = π/4
    let g = sph(
        &[0.0, 1.0, 2.0],
        &[0.0, 1.0, 2.0, PI],
        &[0.0, 1.0, 4.0, TAU],
    );
    let got = oracle_list(&g, &RaySpec::new([-2.0, -2.0, -2.0], [1.0, 1.0, 1.0]));
    let s = 1.0 / 3f64.sqrt();
    assert_list(
        &got,
        &[
            (s3([1, 2, 1]), 2.0 - 2.0 * s, 2.0 - s),
            (s3([0, 2, 1]), 2.0 - s, 2.0),
            (s3([0, 1, 1]), 2.0, 2.0),
            (s3([0, 0, 1]), 2.0, 2.0),
            (s3([0, 0, 0]), 2.0, 2.0 + s),
            (s3([1, 0, 0]), 2.0 + s, 2.0 + 2.0 * s),
        ],
    );
}

#[test]
fn oracle_inner_hole_leaves_a_gap() {
    let g = sph(&[0.5, 1.0], &[0.0, PI], &[0.0, TAU]);
    let got = oracle_list(&g, &RaySpec::new([-2.0, 0.3, 0.0], [1.0, 0.0, 0.0]));
    let (a, b) = ((1.0f64 - 0.09).sqrt(), (0.25f64 - 0.09).sqrt());
    assert_list(
        &got,
        &[
            (s3([0, 0, 0]), 2.0 - a, 2.0 - b),
            (s3([0, 0, 0]), 2.0 + b, 2.0 + a),
        ],
    );
}

#[test]
fn oracle_wedge_across_phi_zero() {
    let g = sph(&[0.0, 3.0], &[0.0, PI], &[-0.5, 0.5]);
    let got = oracle_list(&g, &RaySpec::new([2.0, -2.0, 0.1], [0.0, 1.0, 0.0]));
    let h = 2.0 * 0.5f64.tan();
    assert_list(&got, &[(s3([0, 0, 0]), 2.0 - h, 2.0 + h)]);
}

#[test]
fn oracle_ray_along_z_axis_has_azimuth_zero_and_excludes_minus_z_axis() {
    // the half-open rule: θ = π (the −z axis) is in no band; φ on the axis is 0 (sector 0 here, outside [1, 2))
    let g = sph(&[0.0, 1.0], &[0.0, FRAC_PI_2, PI], &[0.0, 1.0, TAU]);
    let got = oracle_list(&g, &RaySpec::new([0.0, 0.0, 2.0], [0.0, 0.0, -1.0]));
    assert_list(&got, &[(s3([0, 0, 0]), 1.0, 2.0)]);
    let g = sph(&[0.0, 1.0], &[0.0, FRAC_PI_2, PI], &[1.0, 2.0]);
    assert!(oracle_list(&g, &RaySpec::new([0.0, 0.0, 2.0], [0.0, 0.0, -1.0])).is_empty());
}

#[test]
fn oracle_cylinder_vertical_ray_and_polar_ignores_z() {
    let g = GridSpec::Cylindrical {
        center: None,
        rho: vec![0.0, 1.0],
        phi: vec![0.0, TAU],
        z: vec![0.0, 0.5, 1.0],
    };
    let got = oracle_list(&g, &RaySpec::new([0.5, 0.0, -1.0], [0.0, 0.0, 1.0]));
    assert_list(
        &got,
        &[(s3([0, 0, 0]), 1.0, 1.5), (s3([0, 0, 1]), 1.5, 2.0)],
    );
    let g = GridSpec::Polar {
        center: None,
        r: vec![0.0, 1.0, 2.0],
        phi: vec![0.0, TAU],
    };
    let got = oracle_list(&g, &RaySpec::new([-3.0, 0.5, 7.0], [1.0, 0.0, 123.0]));
    let (a, b) = ((4.0f64 - 0.25).sqrt(), (1.0f64 - 0.25).sqrt());
    assert_list(
        &got,
        &[
            (s3([1, 0, 0]), 3.0 - a, 3.0 - b),
            (s3([0, 0, 0]), 3.0 - b, 3.0 + b),
            (s3([1, 0, 0]), 3.0 + b, 3.0 + a),
        ],
    );
}

#[test]
fn oracle_corner_tie_steps_radius_then_zenith_then_azimuth() {
    // (2, 0, −1) + t (−1, 0, 1) reaches (1, 0, 0) at t = 1: sphere r = 1 ∩ plane z = 0 ∩ half-plane φ = 0
    let g = sph(&[0.0, 1.0, 3.0], &[0.0, FRAC_PI_2, PI], &[0.0, 1.0, TAU]);
    let got = oracle_list(&g, &RaySpec::new([2.0, 0.0, -1.0], [-1.0, 0.0, 1.0]));
    // y = 0 on the whole line: φ = 0 while x > 0 (sector 0). Before t = 1: r > 1, z < 0 (band 1); after: r < 1,
    // z > 0 (band 0): two indices change at once, the radius first.
    let cells: Vec<_> = got.iter().map(|c| c.0).collect();
    assert_eq!(cells[0], s3([1, 1, 0]));
    assert_eq!(cells[1], s3([0, 1, 0]), "{got:?}");
    assert_eq!(cells[2], s3([0, 0, 0]), "{got:?}");
    assert_eq!((got[1].1, got[1].2), (1.0, 1.0));
}

#[test]
fn oracle_is_consistent_with_its_own_classification_on_random_rays() {
    use curvicast_host::oracle::march::PRECISION;
    const { assert!(PRECISION >= 256) };
    for (g, rays) in mc::random_suite_inputs(400, 77) {
        let o = MarchOracle::new(&g).unwrap();
        for ray in &rays {
            let r = o.march(ray);
            o.check_oracle_structure(&r)
                .unwrap_or_else(|e| panic!("{e}\n{g:?}\n{ray:?}"));
            let kl = MarchOracle::as_kernel_list(&r.crossings);
            for w in kl.windows(2) {
                assert!(w[0].t_exit <= w[1].t_enter);
            }
        }
    }
}

// ---- engines against the oracle ----------------------------------------------------------------------------------

fn engine_list(g: &GridSpec, r: &RaySpec, e: Engine, p: Precision) -> Vec<KernelCrossing> {
    run::run_engine(g, r, e, p).unwrap_or_else(|err| panic!("{err}\n  grid {g:?}\n  ray {r:?}"))
}

/// Runs every ray of the cases through both engines in every precision; asserts the criterion in f64 and the
/// structural invariants everywhere, prints the f32 figures.
fn check_cases(cases: Vec<Case>) {
    let mut failures = Vec::new();
    let name = cases.first().map(|c| c.name).unwrap_or("?");
    let mut summary: Vec<(String, usize, usize, f64)> = Vec::new();
    for case in &cases {
        for p in [Precision::F64, Precision::F32, Precision::F32Fast] {
            let g = p.round_grid(&case.grid);
            let o = match MarchOracle::new_for(&g, p.eps()) {
                Ok(o) => o,
                Err(e) => {
                    // e.g. 1 m shells at 6.4e6 m collapse in f32 (ulp 0.5 m)
                    println!("{name} {}: grid not representable ({e}); skipped", p.name());
                    continue;
                }
            };
            for e in [Engine::Serial, Engine::Separable] {
                let key = format!("{:?}/{}", e, p.name());
                let mut row = (key.clone(), 0usize, 0usize, 0f64);
                for ray0 in &case.rays {
                    let ray = p.round_ray(ray0);
                    let reference = o.march(&ray);
                    if let Err(msg) = o.check_oracle_structure(&reference) {
                        failures.push(format!("oracle: {msg}\n  ray {ray:?}"));
                    }
                    let k = match run::run_engine(&g, &ray, e, p) {
                        Ok(k) => k,
                        Err(msg) => {
                            failures.push(format!("{key}: {msg}\n  grid {g:?}\n  ray {ray:?}"));
                            continue;
                        }
                    };
                    row.1 += 1;
                    let bound = (p == Precision::F64).then_some(MARCH_F64_BOUNDARY.bound);
                    match compare(&o, &reference, &k, p.eps(), bound) {
                        Ok(s) => {
                            row.2 += 1;
                            row.3 = row.3.max(s.max_backward_eps);
                        }
                        Err(m) => {
                            let structural =
                                matches!(m, curvicast_host::oracle::march::Mismatch::Structure(_));
                            if p == Precision::F64 || structural {
                                failures.push(format!("{key}: {m}\n  grid {g:?}\n  ray {ray:?}"));
                            }
                        }
                    }
                    if p == Precision::F64 && e == Engine::Separable {
                        let serial = engine_list(&g, &ray, Engine::Serial, p);
                        if serial != k {
                            failures.push(format!(
                                "separable differs from serial\n  serial {serial:?}\n  separable {k:?}\n  ray {ray:?}"
                            ));
                        }
                    }
                }
                match summary.iter_mut().find(|s| s.0 == key) {
                    Some(s) => {
                        s.1 += row.1;
                        s.2 += row.2;
                        s.3 = s.3.max(row.3);
                    }
                    None => summary.push(row),
                }
            }
        }
    }
    for (k, n, ok, b) in &summary {
        println!("{name} {k}: {ok}/{n} rays match the oracle, max backward error {b:.2} eps·L");
    }
    if !failures.is_empty() {
        let n = failures.len();
        failures.truncate(6);
        panic!("{name}: {n} failures; first:\n{}", failures.join("\n"));
    }
}

#[test]
fn through_origin() {
    check_cases(mc::through_origin());
}
#[test]
fn along_plus_z_axis() {
    check_cases(mc::along_plus_z_axis());
}
#[test]
fn along_minus_z_axis() {
    check_cases(mc::along_minus_z_axis());
}
#[test]
fn in_plane_z0() {
    check_cases(mc::in_plane_z0());
}
#[test]
fn crossing_z_axis_off_origin() {
    check_cases(mc::crossing_z_axis_off_origin());
}
#[test]
fn parallel_to_cone_generator() {
    check_cases(mc::parallel_to_cone_generator());
}
#[test]
fn tangent_to_shell_and_1e12_inside_outside() {
    check_cases(mc::tangent_to_shell());
}
#[test]
fn through_edge_sphere_cone() {
    check_cases(mc::through_edge());
}
#[test]
fn through_corner_sphere_cone_half_plane() {
    check_cases(mc::through_corner());
}
#[test]
fn starting_exactly_on_each_kind_of_boundary() {
    check_cases(mc::starting_on_boundary());
}
#[test]
fn starting_and_ending_inside() {
    check_cases(mc::starting_and_ending_inside());
}
#[test]
fn leaving_and_reentering_wedge_wider_than_pi() {
    check_cases(mc::reentering_wide_wedge());
}
#[test]
fn theta_half_pi_boundary() {
    check_cases(mc::theta_half_pi_boundary());
}
#[test]
fn earth_scale_1m_shells_1e6_rad_bands() {
    check_cases(mc::earth_scale());
}
#[test]
fn cones_within_nanoradians_of_the_poles() {
    check_cases(mc::near_the_poles());
}
#[test]
fn micro_scale_1e6() {
    check_cases(mc::micro_scale());
}
#[test]
fn direction_length_1e_minus_30() {
    check_cases(mc::direction_length(1e-30));
}
#[test]
fn direction_length_1e30() {
    check_cases(mc::direction_length(1e30));
}

fn random_suite(n: usize, seed: u64) {
    random_suite_of(mc::random_suite_inputs(n, seed));
}

fn random_suite_of(inputs: Vec<(GridSpec, Vec<RaySpec>)>) {
    let rows = run::run_suite(&inputs, &run::ALL_MODES);
    let mut failures = Vec::new();
    for r in &rows {
        let (e, p) = (r.engine.unwrap(), r.precision.unwrap());
        println!(
            "{:?}/{}: {} rays, same sequence {}, identical raw {}, within 16 eps·L {}, structure violations {}, \
             errors {}, max backward {:.2} eps·L, max forward {:.2} eps·L",
            e,
            p.name(),
            r.rays,
            r.same_sequence,
            r.identical_raw,
            r.within_backward_bound,
            r.structure_violations,
            r.engine_errors,
            r.max_backward_eps,
            r.max_forward_eps
        );
        let must_pass = p == Precision::F64;
        if (must_pass && r.pass != r.rays) || r.structure_violations > 0 || r.engine_errors > 0 {
            failures.push(format!(
                "{:?}/{}: {} of {} pass; {} structure violations; {} errors; first:\n{}",
                e,
                p.name(),
                r.pass,
                r.rays,
                r.structure_violations,
                r.engine_errors,
                r.failures.join("\n")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn random_rays_over_random_grids_subset() {
    random_suite(3_000, 2024);
}

#[test]
#[ignore = "the full random suite: 200 000 rays over 10 000 random grids (minutes)"]
fn random_rays_over_random_grids_full_200k() {
    // CI's long step runs one shard of it per commit (support::long_shard).
    random_suite_of(support::long_shard(mc::random_suite_inputs(200_000, 7)));
}

/// Both engines, f64: the backward error on this ray is at most `limit` eps·L (and the full criterion holds in
/// every precision, through `check_cases`).
fn far_ray_regression(name: &'static str, grid: GridSpec, ray: RaySpec, limit: f64) {
    let o = MarchOracle::new_for(&grid, Precision::F64.eps()).unwrap();
    let reference = o.march(&ray);
    for e in [Engine::Serial, Engine::Separable] {
        let k = run::run_engine(&grid, &ray, e, Precision::F64).unwrap();
        let s = compare(
            &o,
            &reference,
            &k,
            Precision::F64.eps(),
            Some(MARCH_F64_BOUNDARY.bound),
        )
        .unwrap();
        println!("{name} {e:?}: max backward {:.2} eps·L", s.max_backward_eps);
        assert!(
            s.max_backward_eps <= limit,
            "{e:?}: {} eps·L",
            s.max_backward_eps
        );
    }
    check_cases(vec![Case {
        name,
        grid,
        rays: vec![ray],
    }]);
}

/// Regression (the full random suite, seed 7, grid #2998, one of the two f64 rays over the limit before the
/// cone solver's Newton step at the root): a ray from 27.6 units away (L = 27.6), 0.015 rad off the generators
/// of the zenith cone θ = 2.3167 (between cones at 2.2611 and 2.3379), crossing it at r = 0.77, next to its
/// closest approach to the apex (0.77). The grid also has two shells 7e-5 apart (3.017146, 3.017216), which
/// the ray crosses too, but the bad crossing was the cone's (band 1 → 2, t = 1.45571): the quadratic's leading
/// coefficient nearly cancels there and |∇Q| is small, and without the refinement (`surface/cone.rs`) the
/// point lay 21.0 eps·L off the cone (limit 16); the shells' roots were within 1 eps·L.
#[test]
fn far_ray_nearly_parallel_to_a_cone_generator_crossing_it_near_the_apex() {
    let grid = sph(
        &[
            0.0,
            0.7582860789984203,
            1.548104923317521,
            3.0171463778032748,
            3.017216263010648,
            4.023472695391163,
            6.152487036776193,
            7.41240620134458,
        ],
        &[
            1.0737747484770148,
            2.2610509815483955,
            2.3166969491025764,
            2.3378866719772446,
            2.4570471870014927,
            2.5444516379243725,
            3.057002356955503,
            PI,
        ],
        &[
            4.674116701926735,
            8.18758137499676,
            9.685228550266725,
            10.957302009106321,
        ],
    );
    let ray = RaySpec::new(
        [19.84351522468882, -4.797491810022317, 18.512759639816547],
        [-13.295309132242258, 3.4932679682625025, -13.0776891100085],
    );
    far_ray_regression(
        "far ray nearly parallel to a cone generator, crossing near the apex",
        grid,
        ray,
        4.0,
    );
}

/// Regression (the full random suite, seed 7, the other f64 ray over the limit, 19.6 eps·L, before the cone
/// solver's Newton step): a grid centred off the origin, a ray from 30.0 units away (relative to the center)
/// whose direction is 0.0006 rad off the generators of the domain's upper boundary cone θ_0 = 0.9609 (on the
/// other side of the apex), entering the domain through that cone at r = 0.287 from the apex, next to its
/// closest approach (0.283).
#[test]
fn far_ray_entering_through_the_boundary_cone_near_its_apex_off_center_grid() {
    let grid = GridSpec::Spherical {
        center: Some([1.8128500700811805, 0.19420998336820103, -5.171897638415506]),
        r: vec![
            0.0,
            0.07833264590120576,
            0.25964648676192753,
            0.670723728465695,
            2.5809963852430324,
            3.0610818248898375,
            4.393863922279705,
            6.76896076256853,
            6.911128837304841,
            8.190861870030671,
        ],
        theta: vec![
            0.9608866752430628,
            1.276187398830059,
            1.8257363794329324,
            2.054584842162123,
            2.4474883789226944,
            2.8133194046447745,
            PI,
        ],
        phi: vec![
            0.0,
            0.09824238597922977,
            1.1562591619689901,
            3.3689564235204283,
            3.450860825208342,
            TAU,
        ],
    };
    let ray = RaySpec::new(
        [-17.902657284989967, -14.217340532858868, 12.195902829607085],
        [
            0.16373860127071904,
            0.12138843573360003,
            -0.14261112697780526,
        ],
    );
    far_ray_regression(
        "far ray entering through the boundary cone near its apex, off-center grid",
        grid,
        ray,
        4.0,
    );
}
