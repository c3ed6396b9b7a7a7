//! Named hard cases of the ray–surface layer, each compared with the arbitrary-precision oracle.
//!
//! Every case runs in the three modes (f64, f32, F32Fast; the f32 modes on the case's data rounded to f32, with
//! the oracle answering for the rounded data) through `curvicast_host::report::surfaces::compare`: count and side
//! must agree outside the near-tangent band and the ambiguity zones, the forward error must stay within the mode's
//! bound outside the band and the backward error within its bound everywhere (definitions in the docs of
//! `curvicast_host::report::surfaces`). In f64 the count and the sides must moreover agree with the oracle
//! *exactly* (no band), and where the geometry has a known answer, the oracle must give it.

use curvicast_host::oracle::surfaces::AngleType;
use curvicast_host::report::surfaces::{
    Kind, Precision, SurfaceCase, compare, kernel_crossings_in, oracle_answer,
};
use curvicast_host::tolerances::{backward_bound, forward_bound};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

fn case(kind: Kind, p: [f64; 2], origin: [f64; 3], dir: [f64; 3]) -> SurfaceCase {
    SurfaceCase {
        kind,
        p,
        origin,
        dir,
    }
}

/// Checks a case in every mode. `expect` is the known answer (sides entered, in order) in f64, if any: then the
/// oracle must give it and the f64 kernel must match it exactly, band or not.
fn check(c: SurfaceCase, expect: Option<&[bool]>) {
    for mode in Precision::ALL {
        let data = c.for_mode(mode);
        let o = oracle_answer(&data, AngleType::of(mode));
        let k = kernel_crossings_in(mode, &c);
        let r = compare(c.kind, mode, &o, &k);
        assert!(r.mismatch.is_none(), "{mode:?} {c:?}: {:?}", r.mismatch);
        assert!(
            r.forward <= forward_bound(c.kind, mode),
            "{mode:?} {c:?}: forward error {} ε·S",
            r.forward
        );
        assert!(
            r.backward <= backward_bound(c.kind, mode),
            "{mode:?} {c:?}: backward error {} ε·S",
            r.backward
        );
        if let (Precision::F64, Some(e)) = (mode, expect) {
            let k = k.unwrap();
            let os: Vec<bool> = o.crossings.iter().map(|x| x.into_positive).collect();
            let ks: Vec<bool> = k.iter().map(|x| x.into_positive).collect();
            assert_eq!(os, ks, "f64 sides, oracle vs kernel, {c:?}: {k:?}");
            assert_eq!(os, e, "oracle vs the known answer, {c:?}");
        }
    }
}

fn sphere(r: f64) -> [f64; 2] {
    [r, r]
}

// ---- tangent rays -------------------------------------------------------------------------------------------

#[test]
fn sphere_tangent_ray_exact_touches_twice() {
    check(
        case(
            Kind::Spheroid,
            sphere(1.0),
            [-5.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
        ),
        Some(&[false, true]),
    );
}

#[test]
fn sphere_tangent_ray_1e_12_inside_crosses_twice() {
    check(
        case(
            Kind::Spheroid,
            sphere(1.0),
            [-5.0, 1.0 - 1e-12, 0.0],
            [1.0, 0.0, 0.0],
        ),
        Some(&[false, true]),
    );
}

#[test]
fn sphere_tangent_ray_1e_12_outside_misses() {
    check(
        case(
            Kind::Spheroid,
            sphere(1.0),
            [-5.0, 1.0 + 1e-12, 0.0],
            [1.0, 0.0, 0.0],
        ),
        Some(&[]),
    );
}

#[test]
fn spheroid_tangent_at_the_pole_touches_twice() {
    check(
        case(
            Kind::Spheroid,
            [2.0, 1.0],
            [-5.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
        ),
        Some(&[false, true]),
    );
    check(
        case(
            Kind::Spheroid,
            [2.0, 1.0],
            [-5.0, 0.0, 1.0 - 1e-12],
            [1.0, 0.0, 0.0],
        ),
        Some(&[false, true]),
    );
    check(
        case(
            Kind::Spheroid,
            [2.0, 1.0],
            [-5.0, 0.0, 1.0 + 1e-12],
            [1.0, 0.0, 0.0],
        ),
        Some(&[]),
    );
}

#[test]
fn cone_tangent_ray_and_1e_12_inside_outside() {
    // The 60° cone (apex 0) contains the generator through (sin 60°, 0, cos 60°); the line through that point
    // along y is tangent to the cone there. θ = 1.0471975511965976 is the f64 nearest π/3, so the tangency is
    // exact only to the oracle's precision: the f64 answer is whatever the oracle says, and the offsets by
    // ±1e-12 decide it.
    let theta = std::f64::consts::FRAC_PI_3;
    let (s, c) = theta.sin_cos();
    // (in the band: the oracle and the kernel may differ between a touch and a near miss)
    check(
        case(Kind::Cone, [0.0, theta], [s, -2.0, c], [0.0, 1.0, 0.0]),
        None,
    );
    // outward (larger ρ): the line stays outside the cone (θ > 60°)
    check(
        case(
            Kind::Cone,
            [0.0, theta],
            [s + 1e-12, -2.0, c],
            [0.0, 1.0, 0.0],
        ),
        Some(&[]),
    );
    // inward: crosses in and out
    check(
        case(
            Kind::Cone,
            [0.0, theta],
            [s - 1e-12, -2.0, c],
            [0.0, 1.0, 0.0],
        ),
        Some(&[false, true]),
    );
}

// ---- the cone's apex and generators -------------------------------------------------------------------------

#[test]
fn cone_ray_along_the_axis_through_the_apex() {
    let c45 = [0.0, FRAC_PI_4];
    // downward: from inside the upper nappe (θ = 0 < 45°) through the apex to below it (θ = 180°)
    check(
        case(Kind::Cone, c45, [0.0, 0.0, 2.0], [0.0, 0.0, -1.0]),
        Some(&[true]),
    );
    check(
        case(Kind::Cone, c45, [0.0, 0.0, -2.0], [0.0, 0.0, 1.0]),
        Some(&[false]),
    );
}

#[test]
fn cone_oblique_ray_through_an_offset_apex() {
    // apex (0, 0, 0.5); q = origin − apex = −d exactly: the line passes through the apex at t = 1, from below
    // (θ > 45°) into the cone (its direction is 29° from +z).
    check(
        case(
            Kind::Cone,
            [0.5, FRAC_PI_4],
            [-1.0, -0.5, -1.5],
            [1.0, 0.5, 2.0],
        ),
        Some(&[false]),
    );
    // a horizontal line through the apex stays at θ = 90° on both sides: nothing
    check(
        case(
            Kind::Cone,
            [0.5, FRAC_PI_4],
            [-1.0, 0.0, 0.5],
            [1.0, 0.0, 0.0],
        ),
        Some(&[]),
    );
}

#[test]
fn cone_ray_starting_at_the_apex() {
    check(
        case(
            Kind::Cone,
            [0.5, FRAC_PI_4],
            [0.0, 0.0, 0.5],
            [0.25, 0.0, 1.0],
        ),
        None,
    );
    check(
        case(
            Kind::Cone,
            [0.5, FRAC_PI_4],
            [0.0, 0.0, 0.5],
            [1.0, 0.0, 0.25],
        ),
        None,
    );
}

#[test]
fn cone_ray_parallel_to_a_generator_is_nearly_linear() {
    // Direction (1, 0, 1) is a generator of the 45° cone (to the rounding of FRAC_PI_4): A ≈ 0, one root at
    // t = 5/3 on the upper nappe, the other (if any) far away.
    check(
        case(
            Kind::Cone,
            [0.0, FRAC_PI_4],
            [-3.0, 1.0, 0.0],
            [1.0, 0.0, 1.0],
        ),
        None,
    );
    check(
        case(
            Kind::Cone,
            [0.0, FRAC_PI_4],
            [-3.0, 1.0, 0.0],
            [-1.0, 0.0, -1.0],
        ),
        None,
    );
    // the lower nappe, direction (1, 0, −1)
    check(
        case(
            Kind::Cone,
            [0.0, 3.0 * FRAC_PI_4],
            [-3.0, 1.0, 0.0],
            [1.0, 0.0, -1.0],
        ),
        None,
    );
}

#[test]
fn cone_theta_half_pi_is_the_plane() {
    // θ = FRAC_PI_2 is exactly the plane z = k (f64 and f32 alike); larger θ is below it.
    check(
        case(
            Kind::Cone,
            [0.5, FRAC_PI_2],
            [0.3, 0.2, 2.0],
            [0.1, 0.0, -1.0],
        ),
        Some(&[true]),
    );
    check(
        case(
            Kind::Cone,
            [0.5, FRAC_PI_2],
            [0.3, 0.2, -2.0],
            [0.1, 0.0, 1.0],
        ),
        Some(&[false]),
    );
    // horizontal in the plane: nothing
    check(
        case(
            Kind::Cone,
            [0.5, FRAC_PI_2],
            [0.3, 0.2, 0.5],
            [1.0, 0.0, 0.0],
        ),
        Some(&[]),
    );
}

#[test]
fn cone_theta_zero_and_pi_are_never_crossed() {
    check(
        case(Kind::Cone, [0.0, 0.0], [-1.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
        Some(&[]),
    );
    check(
        case(Kind::Cone, [0.0, PI], [-1.0, 0.0, -1.0], [1.0, 0.0, 0.0]),
        Some(&[]),
    );
}

// ---- half-planes ---------------------------------------------------------------------------------------------

#[test]
fn half_plane_ray_in_its_plane_reports_nothing() {
    // φ = 0: sin φ = 0 exactly, the plane y = 0; a ray in it
    check(
        case(
            Kind::HalfPlane,
            [0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
        ),
        Some(&[]),
    );
    check(
        case(
            Kind::HalfPlane,
            [0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
        ),
        Some(&[]),
    );
    // φ = FRAC_PI_2: its cosine is 6e-17, so the plane is not exactly x = 0; the ray (0, 1, 0) + t (0, 1, 1) crosses
    // the full plane at t = −1 only: nothing for t ≥ 0
    check(
        case(
            Kind::HalfPlane,
            [FRAC_PI_2, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 1.0, 1.0],
        ),
        Some(&[]),
    );
}

#[test]
fn half_plane_ray_along_the_z_axis_reports_nothing() {
    for phi in [0.0, 0.3, FRAC_PI_2, 2.5, -1.0] {
        check(
            case(
                Kind::HalfPlane,
                [phi, 0.0],
                [0.0, 0.0, -1.0],
                [0.0, 0.0, 1.0],
            ),
            Some(&[]),
        );
    }
}

#[test]
fn half_plane_ray_crossing_the_z_axis_off_the_origin() {
    // The line meets the axis at (0, 0, 5): every half-plane includes its edge, so each is crossed there.
    for phi in [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0] {
        check(
            case(
                Kind::HalfPlane,
                [phi, 0.0],
                [-1.0, -1.0, 5.0],
                [1.0, 1.0, 0.0],
            ),
            None,
        );
    }
    // the other half is never crossed away from the axis
    check(
        case(
            Kind::HalfPlane,
            [0.0, 0.0],
            [-2.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
        ),
        Some(&[]),
    );
    check(
        case(
            Kind::HalfPlane,
            [0.0, 0.0],
            [2.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
        ),
        Some(&[true]),
    );
    check(
        case(
            Kind::HalfPlane,
            [0.0, 0.0],
            [2.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
        ),
        Some(&[false]),
    );
}

// ---- rays starting on the surface ----------------------------------------------------------------------------

#[test]
fn sphere_ray_starting_on_the_surface_includes_t0() {
    check(
        case(
            Kind::Spheroid,
            sphere(5.0),
            [3.0, 4.0, 0.0],
            [-3.0, -4.0, 0.0],
        ),
        Some(&[false, true]),
    );
    // leaving outward from the surface: a single crossing at t = 0
    check(
        case(
            Kind::Spheroid,
            sphere(5.0),
            [3.0, 4.0, 0.0],
            [3.0, 4.0, 0.0],
        ),
        Some(&[true]),
    );
}

#[test]
fn spheroid_ray_starting_on_the_pole_and_the_equator() {
    // (0, 0, b) and (a, 0, 0) lie exactly on the spheroid a = 2, b = 1
    check(
        case(
            Kind::Spheroid,
            [2.0, 1.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.0, -1.0],
        ),
        Some(&[false, true]),
    );
    check(
        case(
            Kind::Spheroid,
            [2.0, 1.0],
            [2.0, 0.0, 0.0],
            [-1.0, 0.25, 0.5],
        ),
        Some(&[false, true]),
    );
    check(
        case(
            Kind::Spheroid,
            [2.0, 1.0],
            [2.0, 0.0, 0.0],
            [1.0, 0.25, 0.5],
        ),
        Some(&[true]),
    );
}

#[test]
fn half_plane_and_plane_ray_starting_on_the_surface() {
    check(
        case(
            Kind::HalfPlane,
            [0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ),
        Some(&[true]),
    );
    check(
        case(Kind::PlaneZ, [2.0, 0.0], [1.0, 1.0, 2.0], [0.0, 0.0, -1.0]),
        Some(&[false]),
    );
    check(
        case(
            Kind::Cone,
            [2.0, FRAC_PI_2],
            [1.0, 1.0, 2.0],
            [0.0, 0.5, 1.0],
        ),
        Some(&[false]),
    );
}

// ---- scales and direction lengths ----------------------------------------------------------------------------

fn typical(kind: Kind, s: f64, dl: f64) -> Vec<SurfaceCase> {
    let o = |v: [f64; 3]| v.map(|x| x * s);
    let d = |v: [f64; 3]| v.map(|x| x * dl);
    match kind {
        Kind::Spheroid => vec![
            case(kind, [s, s], o([-3.0, 0.6, 0.0]), d([1.0, 0.0, 0.0])),
            case(kind, [2.0 * s, s], o([0.3, 0.2, 4.0]), d([0.1, 0.2, -1.0])),
        ],
        Kind::Cone => vec![
            case(
                kind,
                [0.5 * s, 0.7],
                o([-3.0, 0.4, 2.0]),
                d([1.0, 0.1, 0.0]),
            ),
            case(
                kind,
                [-0.5 * s, 2.3],
                o([2.0, 1.0, -3.0]),
                d([-1.0, -0.2, 0.5]),
            ),
        ],
        Kind::HalfPlane => vec![
            case(kind, [0.7, 0.0], o([2.0, -1.0, 0.5]), d([-0.2, 1.0, 0.1])),
            case(kind, [4.0, 0.0], o([-0.5, -3.0, 1.0]), d([-0.5, 1.0, -0.2])),
        ],
        Kind::PlaneZ => vec![
            case(
                kind,
                [0.7 * s, 0.0],
                o([0.1, 0.2, -1.0]),
                d([0.2, 0.5, 1.0]),
            ),
            case(
                kind,
                [-0.3 * s, 0.0],
                o([0.1, 0.2, 1.0]),
                d([0.2, 0.5, -1.0]),
            ),
        ],
    }
}

#[test]
fn huge_scale_1e8_every_kind() {
    for kind in Kind::ALL {
        for c in typical(kind, 1e8, 1.0) {
            check(c, None);
        }
    }
}

#[test]
fn tiny_scale_1e_8_every_kind() {
    for kind in Kind::ALL {
        for c in typical(kind, 1e-8, 1.0) {
            check(c, None);
        }
    }
}

#[test]
fn direction_length_1e_30_every_kind() {
    // At scale 1e8 a crossing at t = 3.8e8 / 1e-30 lies beyond the f32 range (3.4e38): the f32 kernel reports
    // its correctly rounded value, +∞, which `compare` accepts only when the oracle's t is indeed out of range.
    for kind in Kind::ALL {
        for s in [1e-8, 1.0, 1e4, 1e8] {
            for c in typical(kind, s, 1e-30) {
                check(c, None);
            }
        }
    }
}

#[test]
fn direction_length_1e30_every_kind() {
    for kind in Kind::ALL {
        for s in [1e-8, 1.0, 1e8] {
            for c in typical(kind, s, 1e30) {
                check(c, None);
            }
        }
    }
}

#[test]
fn f32_crossing_beyond_the_f32_range_is_infinite() {
    let c = case(
        Kind::Spheroid,
        sphere(1e8),
        [-3e8, 6e7, 0.0],
        [1e-30, 0.0, 0.0],
    );
    let k = kernel_crossings_in(Precision::F32, &c).unwrap();
    assert_eq!(k.len(), 2);
    assert!(k[0].t.is_finite() && k[1].t == f64::INFINITY, "{k:?}");
    let o = oracle_answer(&c.to_f32(), AngleType::F32);
    assert!(o.crossings[1].t_f64 > f32::MAX as f64);
    check(c, Some(&[false, true]));
}

#[test]
fn f32_angles_of_the_special_cone_values_are_exact() {
    // In f32, θ = f32::consts::FRAC_PI_2 (wider than the f64 value) is the plane too; the oracle follows.
    let theta = std::f32::consts::FRAC_PI_2 as f64;
    let c = case(Kind::Cone, [0.5, theta], [0.3, 0.2, 2.0], [0.1, 0.0, -1.0]);
    let o = oracle_answer(&c, AngleType::F32);
    let k = kernel_crossings_in(Precision::F32, &c).unwrap();
    assert_eq!(o.crossings.len(), 1);
    assert_eq!(k.len(), 1);
    assert_eq!(o.crossings[0].t_f64, 1.5);
    assert!((k[0].t - 1.5).abs() <= 4.0 * f32::EPSILON as f64 * 2.0);
}
