//! The streams near their limits: cones nanoradians from the poles, sector lookup, kept second roots, the
//! zenith event bound, and directions of any size.

use super::*;
use crate::ray::Ray;
use core::f64::consts::PI;
use std::vec::Vec;

#[test]
fn ray_near_the_minus_z_axis_inside_a_cone_five_nanoradians_from_the_pole() {
    // cos²(π − 5e-9) rounds to 1: only sin² tells this cone from the −z axis. The ray starts at θ = π − 1e-8,
    // outside the narrow cone, and enters it where ρ / |z| = tan 5e-9, at z = −1.
    let th = [0.0, PI / 2.0, PI - 5e-9, PI];
    let ray = Ray::new([0.5e-8, 0.0, -0.5], [0.0, 0.0, -1.0]).unwrap();
    let c = march_s(&[0.0, 2.0], &th, &PH, &ray);
    // the f64 breakpoint is not π − 5e-9 to all digits (π itself rounds): the crossing where ρ / |z| = tan θ_2
    let z = 0.5e-8 * -th[2].cos() / th[2].sin();
    let out = (4.0f64 - 0.25e-16).sqrt() - 0.5;
    expect(
        &c,
        &[([0, 1, 0], 0.0, z - 0.5), ([0, 2, 0], z - 0.5, out)],
        1e-12,
    );
}

#[test]
fn ray_starting_inside_a_cone_five_nanoradians_from_the_plus_z_pole() {
    // the mirror image at the +z pole: θ = 2e-9 at the start, inside the cone θ = 5e-9 down to z = 0.4, then
    // across the plane z = 0 and out through the sphere r = 2 below it
    let th = [0.0, 5e-9, PI / 2.0, PI];
    let ray = Ray::new([0.2e-8, 0.0, 1.0], [0.0, 0.0, -1.0]).unwrap();
    let c = march_s(&[0.0, 2.0], &th, &PH, &ray);
    let z = 0.2e-8 * th[1].cos() / th[1].sin();
    expect(
        &c,
        &[
            ([0, 0, 0], 0.0, 1.0 - z),
            ([0, 1, 0], 1.0 - z, 1.0),
            ([0, 2, 0], 1.0, 3.0),
        ],
        1e-12,
    );
}

#[test]
fn ray_entering_the_ball_just_outside_a_cone_five_nanoradians_from_the_minus_z_pole() {
    // from far below along +z at ρ = 1.02e-8 (direction a hair off the axis): the cone θ = π − 5e-9 meets this
    // line at |z| ≈ 2.04, outside the ball of radius 2, so the whole chord inside is outside the cone
    let th = [0.0, PI / 2.0, PI - 5e-9, PI];
    let ray = Ray::new([1.02e-8, 0.0, -10.0], [1e-19, 0.0, 1.0]).unwrap();
    let c = march_s(&[0.0, 2.0], &th, &PH, &ray);
    expect(
        &c,
        &[([0, 1, 0], 8.0, 10.0), ([0, 0, 0], 10.0, 12.0)],
        1e-12,
    );
}

#[test]
fn sector_lookup_with_the_half_turn_split_matches_testing_each_boundary() {
    use crate::march::axes::AzimuthAxis;
    // a full turn, a wedge across φ = 0, and breakpoints within rounding of φ_0 + π (where the split is decided
    // by the same sign test as each boundary's own)
    let full: Vec<f64> = (0..=64).map(|i| f64::from(i) * (2.0 * PI / 64.0)).collect();
    let wedge: Vec<f64> = (0..=64)
        .map(|i| -1.0 + f64::from(i) * (5.0 / 64.0))
        .collect();
    let ulps = |k: i64| f64::from_bits((0.25 + PI).to_bits().wrapping_add_signed(k));
    let near_pi = [0.25, ulps(-2), ulps(-1), ulps(0), ulps(1), ulps(2), 5.5];
    for phi in [&full[..], &wedge[..], &near_pi[..]] {
        let mut buf = [0.0; 2 * 65];
        let mut ws = &mut buf[..];
        let axis = AzimuthAxis::build(phi, &mut ws).unwrap();
        let plain = axis.without_half_split();
        // directions all round, each boundary's own direction and its neighbours, and the zero vector
        // (fewer under Miri, whose interpreter is slow)
        let (n, near) = if cfg!(miri) { (64, 1) } else { (4096, 3) };
        let mut dirs: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let a = f64::from(i) * (2.0 * PI / f64::from(n));
                (a.cos(), a.sin())
            })
            .collect();
        for &p in phi.iter().chain([phi[0] + PI].iter()) {
            for k in -near..=near {
                let a = f64::from_bits(p.to_bits().wrapping_add_signed(k));
                dirs.push((a.cos(), a.sin()));
                dirs.push((a.cos() * 1e-300, a.sin() * 1e-300));
            }
        }
        dirs.push((0.0, 0.0));
        for (x, y) in dirs {
            assert_eq!(
                axis.sector_of(x, y),
                plain.sector_of(x, y),
                "{phi:?} at ({x}, {y})"
            );
        }
    }
}

/// 65 zenith breakpoints, uniform in [0, π]: 64 cones.
fn sixty_four_cones() -> Vec<f64> {
    (0..=64).map(|i| f64::from(i) * (PI / 64.0)).collect()
}

/// The zenith axis of `theta` in `buf` (two values per breakpoint), with a unit length scale.
fn zenith_axis<'a>(
    theta: &'a [f64],
    buf: &'a mut [f64],
) -> crate::march::axes::ZenithAxis<'a, f64> {
    let mut ws = buf;
    let mut axis = crate::march::axes::ZenithAxis::build(theta, &mut ws).unwrap();
    axis.scale = 1.0;
    axis
}

#[test]
fn kept_second_roots_of_cones_give_the_same_zenith_events_as_solving_each_cone_again() {
    use crate::march::stream::{SecondRoots, Stream};
    // 64 cones; lines passing the z axis at small distances, so that θ turns and many cones are crossed twice
    let theta = sixty_four_cones();
    let mut buf = [0.0; 2 * 65];
    let axis = zenith_axis(&theta, &mut buf);
    let mut unit = crate::test_util::xorshift_uniform(0x2545_f491_4f6c_dd1d);
    let mut uniform = move || unit() * 2.0 - 1.0;
    let rays = if cfg!(miri) { 8 } else { 400 };
    let mut most_kept = 0;
    for _ in 0..rays {
        let near = 10f64.powf(-6.0 * uniform().abs());
        let origin = [-2.0, near * uniform(), 2.0 * uniform()];
        let dir = [1.0, 0.3 * uniform(), 0.5 * uniform()];
        let ray = Ray::new(origin, dir).unwrap();
        let (mut kept, _) = Stream::zenith(&axis, ray.line(), 0.0);
        let mut solved = kept;
        let mut roots = SecondRoots::EMPTY;
        for _ in 0..300 {
            let a = kept.next_zenith(&axis, ray.line(), f64::INFINITY, &mut roots);
            // a new, empty stack for each step of this one: every cone is solved
            let mut none_kept = SecondRoots::EMPTY;
            let b = solved.next_zenith(&axis, ray.line(), f64::INFINITY, &mut none_kept);
            assert_eq!(a, b, "{ray:?}");
            assert_eq!(
                (kept.t.to_bits(), kept.band),
                (solved.t.to_bits(), solved.band),
                "{ray:?}"
            );
            most_kept = most_kept.max(roots.kept());
            if !a {
                break;
            }
        }
    }
    // the stack was used, up to its capacity
    assert_eq!(most_kept, 8);
}

#[test]
fn zenith_stream_past_its_event_bound_stops_the_march_with_an_iteration_bound_error() {
    use crate::march::stream::{SecondRoots, Stream, zenith_event_bound};
    // a line that crosses 20 cones of 64: the stream's own bound is far from reached
    let theta = sixty_four_cones();
    let mut buf = [0.0; 2 * 65];
    let axis = zenith_axis(&theta, &mut buf);
    let ray = Ray::new([-2.0, 0.1, 0.3], [1.0, 0.0, 0.0]).unwrap();
    let run = |s: &mut Stream<f64>| {
        let mut roots = SecondRoots::EMPTY;
        let mut n = 0u32;
        while s.next_zenith(&axis, ray.line(), f64::INFINITY, &mut roots) {
            n += 1;
            assert!(n <= 1000);
        }
        n
    };
    let (start, _) = Stream::zenith(&axis, ray.line(), 0.0);
    let mut whole = start;
    let events = run(&mut whole);
    assert!(events >= 10 && events < zenith_event_bound(65), "{events}");
    assert!(!whole.overran());
    // with 3 events left: 3 events, then an overrun
    let mut cut = start.with_events_left(3);
    assert_eq!(run(&mut cut), 3);
    assert!(cut.overran());

    // in the serial engine: the crossings before the overrun are the whole march's first ones, then the error
    let (r, th, ph) = (
        [0.0, 0.5, 1.0],
        theta.clone(),
        [0.0, PI / 2.0, PI, 1.5 * PI, 2.0 * PI],
    );
    let mut ws = std::vec![0.0; SphericalGrid::<f64>::workspace_len(3, 65, 5)];
    let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let whole: Vec<_> = grid.march(&ray).collect();
    let mut march = grid.march(&ray).with_zenith_events_left(2);
    let cut: Vec<_> = march.by_ref().collect();
    assert_eq!(march.error(), Some(MarchError::IterationBound));
    assert!(
        cut.len() >= 2 && cut.len() < whole.len(),
        "{} {}",
        cut.len(),
        whole.len()
    );
    assert_eq!(cut[..], whole[..cut.len()]);
    let mut full = grid.march(&ray);
    assert_eq!(full.by_ref().count(), whole.len());
    assert_eq!(full.error(), None);
}

/// A direction of unit size (largest component in [1/2, 2)) is kept as given (`s = t`), any other is scaled by
/// a power of two: the solvers' expressions are homogeneous in the direction, so a march along `d · 2^k` must
/// give the cells of the march along `d` and its `t` divided by `2^k`, bit for bit, whichever way each ray was
/// scaled (both engines, on a grid with a shell, both poles, cones near the pole and a wedge across φ = 0).
#[test]
fn unit_sized_direction_kept_as_given_marches_like_its_power_of_two_multiples() {
    let r = [0.2, 0.35, 0.5, 0.8, 1.0];
    let th = [0.0, 1e-3, 0.9, PI / 2.0, 2.0, PI];
    let ph = [-0.5, 0.7, 2.0, 3.5];
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let march = |ray: &Ray<f64>| -> Vec<CellCrossing<f64>> {
        let mut m = g.march(ray);
        let a: Vec<_> = m.by_ref().collect();
        assert_eq!(m.error(), None);
        let b: Vec<_> = g.march_separable::<64>(ray).unwrap().collect();
        assert_eq!(a, b, "serial and separable differ");
        a
    };
    let mut unit = crate::test_util::xorshift_uniform(0x5ca1_ab1e);
    let mut v = move || unit() * 4.0 - 2.0;
    // 2^k exactly (`powi` need not be exact, and under Miri it is not)
    let pow2 = |k: i32| f64::from_bits(u64::try_from(1023 + k).unwrap() << 52);
    let rays = if cfg!(miri) { 10 } else { 2_000 };
    let mut compared = 0;
    for i in 0..rays {
        let o = [v(), v(), v()];
        // toward a point near the center (most rays cross the grid), at unit size
        let to = [v() * 0.3, v() * 0.3, v() * 0.3];
        let d = [to[0] - o[0], to[1] - o[1], to[2] - o[2]];
        let n = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        let d = d.map(|x| x / n * [1.0, 0.9, 1.9][i % 3]);
        let base_ray = Ray::new(o, d).unwrap();
        assert_eq!(base_ray.scale_exponent(), 0);
        let base = march(&base_ray);
        for k in [-40, -2, 2, 40] {
            let ray = Ray::new(o, d.map(|x| x * pow2(k))).unwrap();
            assert_ne!(ray.scale_exponent(), 0);
            let scaled: Vec<_> = march(&ray)
                .into_iter()
                .map(|c| CellCrossing {
                    cell: c.cell,
                    t_enter: c.t_enter * pow2(k),
                    t_exit: c.t_exit * pow2(k),
                })
                .collect();
            assert_eq!(scaled, base, "ray {i}, k = {k}");
            compared += base.len();
        }
    }
    assert!(compared > rays * 10, "{compared}");
}
