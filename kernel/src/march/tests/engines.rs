//! The kinds and the engines: cylinders, separable buffers, grid errors, sizes, and `t` that cannot be
//! represented.

use super::*;
use crate::ray::Ray;
use core::f64::consts::PI;
use std::vec::Vec;

#[test]
fn cylinder_cells_and_wedge_across_phi_zero() {
    let (rho, ph, z) = ([0.5, 1.0, 2.0], [-0.5, 0.0, 0.5], [0.0, 1.0]);
    let mut ws = [0.0; 16];
    let g = CylindricalGrid::new(&rho, &ph, &z, &mut ws).unwrap();
    // along −x at y = −0.1, z = 0.5: inside the wedge φ ∈ [−0.5, 0) while x > 0.1 / tan 0.5
    let ray = Ray::new([3.0, -0.1, 0.5], [-1.0, 0.0, 0.0]).unwrap();
    let a: Vec<_> = g.march(&ray).collect();
    let b: Vec<_> = g.march_separable::<16>(&ray).unwrap().collect();
    assert_eq!(a, b);
    let cells: Vec<_> = a.iter().map(|c| c.cell).collect();
    // ρ = 2 at x = sqrt(4 − 0.01), ρ = 1 at sqrt(1 − 0.01), ρ = 0.5 at sqrt(0.25 − 0.01): y < 0 → φ ∈ [−0.5, 0)
    assert_eq!(cells, [[1, 0, 0], [0, 0, 0]]);
    assert!((a[0].t_enter - (3.0 - 3.99f64.sqrt())).abs() < 1e-15);
    assert!((a[1].t_exit - (3.0 - 0.24f64.sqrt())).abs() < 1e-15);
}

#[test]
fn separable_buffer_full_is_an_error_not_a_truncation() {
    let r: Vec<f64> = (0..20).map(|i| i as f64 * 0.05).collect();
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&r, &TH, &PH, &mut ws).unwrap();
    let ray = Ray::new([-2.0, 0.01, 0.01], [1.0, 0.0, 0.0]).unwrap();
    assert_eq!(
        g.march_separable::<4>(&ray).err(),
        Some(MarchError::BufferFull {
            axis: Axis::R,
            capacity: 4
        })
    );
    assert!(g.march_separable::<64>(&ray).is_ok());
}

#[test]
fn separable_filled_in_place_is_reused_across_hits_misses_and_a_full_buffer() {
    // One march reused: a ray through the center (a jump through every radius band), one that misses the
    // ball, one that overflows the 8-entry buffers, then a hit again. After each fill it must yield exactly what
    // the serial engine does (nothing after a miss or an error), never leftovers of the previous ray.
    let r: Vec<f64> = (0..8).map(|i| i as f64 / 7.0).collect();
    let many: Vec<f64> = (0..20).map(|i| i as f64 * 0.05).collect();
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&r, &TH, &PH, &mut ws).unwrap();
    let mut ws2 = [0.0; 64];
    let g_many = SphericalGrid::new(&many, &TH, &PH, &mut ws2).unwrap();
    let through = Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
    let miss = Ray::new([-2.0, 3.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
    let off = Ray::new([-2.0, 0.3, 0.4], [1.0, 0.1, -0.2]).unwrap();
    let overflow = Ray::new([-2.0, 0.01, 0.01], [1.0, 0.0, 0.0]).unwrap();
    let mut m = SeparableMarch::<f64, 16>::default();
    assert_eq!(m.by_ref().count(), 0);
    for ray in [&through, &miss, &off, &through] {
        g.march_separable_into(ray, &mut m).unwrap();
        let got: Vec<_> = m.by_ref().collect();
        let want: Vec<_> = g.march(ray).collect();
        assert_eq!(got, want);
        assert_eq!(m.error(), None);
    }
    assert_eq!(
        g_many.march_separable_into(&overflow, &mut m),
        Err(MarchError::BufferFull {
            axis: Axis::R,
            capacity: 16
        })
    );
    assert_eq!(m.listed(), [0, 0, 0]);
    assert_eq!(m.by_ref().count(), 0);
    g.march_separable_into(&off, &mut m).unwrap();
    // every crossing after the first begins at a listed event (more are listed: those outside the domain)
    let listed = m.listed();
    let again: Vec<_> = m.by_ref().collect();
    assert!(!again.is_empty());
    assert!(
        listed.iter().sum::<usize>() >= again.len() - 1 && listed.iter().all(|&n| n <= 16),
        "{listed:?} for {again:?}"
    );
    assert_eq!(again, g.march(&off).collect::<Vec<_>>());
}

#[test]
fn grid_errors_name_axis_and_index() {
    let mut ws = [0.0; 64];
    let e =
        |r: &[f64], th: &[f64], ph: &[f64], ws: &mut [f64]| SphericalGrid::new(r, th, ph, ws).err();
    assert_eq!(
        e(&[0.0], &TH, &PH, &mut ws),
        Some(GridError::TooFewBreakpoints {
            axis: Axis::R,
            len: 1
        })
    );
    assert_eq!(
        e(&[0.0, 1.0, 1.0], &TH, &PH, &mut ws),
        Some(GridError::NotIncreasing {
            axis: Axis::R,
            index: 2
        })
    );
    assert_eq!(
        e(&[-1.0, 1.0], &TH, &PH, &mut ws),
        Some(GridError::OutOfRange {
            axis: Axis::R,
            index: 0
        })
    );
    assert_eq!(
        e(&R, &[0.0, 4.0], &PH, &mut ws),
        Some(GridError::OutOfRange {
            axis: Axis::Theta,
            index: 1
        })
    );
    assert_eq!(
        e(&R, &TH, &[0.0, f64::NAN], &mut ws),
        Some(GridError::NonFinite {
            axis: Axis::Phi,
            index: 1
        })
    );
    assert_eq!(
        e(&R, &TH, &[-1.0, 6.0], &mut ws),
        Some(GridError::OutOfRange {
            axis: Axis::Phi,
            index: 1
        })
    );
    assert_eq!(
        e(&R, &TH, &PH, &mut ws[..5]),
        Some(GridError::WorkspaceTooSmall)
    );
    let mut ws2 = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws2).unwrap();
    assert_eq!(
        g.with_center([f64::NAN, 0.0, 0.0]).err(),
        Some(GridError::NonFiniteCenter)
    );
    let msg = std::format!(
        "{}",
        GridError::NotIncreasing {
            axis: Axis::Theta,
            index: 3
        }
    );
    assert!(msg.contains("theta[3]"));
}

#[test]
fn size_of_the_serial_iterator() {
    let s64 = core::mem::size_of::<SerialMarch<'static, f64, Spherical>>();
    let s32 = core::mem::size_of::<SerialMarch<'static, f32, Spherical>>();
    std::println!("size_of SerialMarch: f64 {s64} bytes, f32 {s32} bytes");
    // measured: 480 and 288 (the ray's line in the grid's frame is 112 bytes of it in f64, the radius stream's
    // line 64, each stream 40, the zenith stream's kept second roots 88); the design goal of 192 and 128 is not
    // reached: what a march must carry is about 170 and 110 bytes, the rest saves work per crossing (docs/performance.md's
    // "How far the targets are")
    assert!(s64 <= 480 && s32 <= 288, "{s64} {s32}");
}

#[test]
fn tiny_direction_whose_t_overflows_is_an_error_not_a_miss() {
    // The line along +x from (-3, 0.1, 0.2) crosses the unit ball, but at t ≈ 2.2e308 and beyond: not finite.
    let ray = Ray::new([-3.0, 0.1, 0.2], [1e-308, 0.0, 0.0]).unwrap();
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws).unwrap();
    let mut m = g.march(&ray);
    let got: Vec<_> = m.by_ref().collect();
    assert_eq!(
        (got.as_slice(), m.error()),
        (&[][..], Some(MarchError::Unrepresentable))
    );
    assert_eq!(
        g.march_separable::<32>(&ray).err(),
        Some(MarchError::Unrepresentable)
    );
}

#[test]
fn vertical_tiny_direction_in_a_cylinder_stops_with_an_error_at_the_first_unrepresentable_t() {
    // A vertical line inside the cylinder (its radius never changes): z = 0 at t = 5e307, z = 4 at t = 4.5e308,
    // beyond the largest f64. The first crossing is correct and finite; the second cannot be expressed, whether
    // z = 4 is where the line leaves the domain or a boundary between two cells inside it.
    for z in [&[-1.0, 0.0, 4.0][..], &[-1.0, 0.0, 4.0, 5.0]] {
        let (rho, phi) = ([0.0, 1.0, 2.0], [0.0, PI, 2.0 * PI]);
        let mut ws = [0.0; 64];
        let g = CylindricalGrid::new(&rho, &phi, z, &mut ws).unwrap();
        let ray = Ray::new([0.5, 0.5, -0.5], [0.0, 0.0, 1e-308]).unwrap();
        let mut m = g.march(&ray);
        let serial: Vec<_> = m.by_ref().collect();
        assert_eq!(m.error(), Some(MarchError::Unrepresentable), "{z:?}");
        let mut s = g.march_separable::<32>(&ray).unwrap();
        let separable: Vec<_> = s.by_ref().collect();
        assert_eq!(s.error(), Some(MarchError::Unrepresentable));
        assert_eq!(serial, separable);
        assert_eq!(
            serial,
            [CellCrossing {
                cell: [0, 0, 0],
                t_enter: 0.0,
                t_exit: 0.5 / 1e-308
            }],
            "{z:?}"
        );
    }
}

/// A unit-sized direction (`s = t`, so the emitter does not test `t`) nearly parallel to the azimuth boundary
/// φ = 0, whose crossing of it lies at t ≈ 1e309 (not finite): that event comes after the ray leaves the outer
/// radius, which ends the march, so every crossing is finite and none is lost (both engines).
#[test]
fn unit_direction_whose_far_azimuth_crossing_overflows_gives_finite_crossings() {
    let ph = [0.0, PI / 2.0, PI, 1.5 * PI, 2.0 * PI];
    let ray = Ray::new([-2.0, 0.1, 0.3], [1.0, -1e-310, 0.0]).unwrap();
    let got = march_s(&R, &TH, &ph, &ray);
    let cells: Vec<_> = got.iter().map(|c| c.cell).collect();
    // outer shell, inner ball, outer shell in the upper half; φ from just below π to π/2 and on toward 0
    assert_eq!(
        cells,
        [[1, 0, 1], [0, 0, 1], [0, 0, 0], [1, 0, 0]],
        "{got:?}"
    );
    assert!(
        got.iter()
            .all(|c| c.t_enter.is_finite() && c.t_exit.is_finite())
    );
    let exit = 2.0 + (1.0f64 - 0.01 - 0.09).sqrt();
    assert!((got[3].t_exit - exit).abs() < 1e-15, "{got:?}");
}

#[test]
fn tiny_direction_from_inside_the_ball_is_an_error() {
    // Starts inside the inner ball; it leaves that at t ≈ 1e308 (finite) and the outer ball at t ≈ 2.2e308
    // (not): the march is refused as a whole (the outer ball's exit is checked when the march starts).
    let ray = Ray::new([0.1, 0.1, 0.1], [4e-309, 0.0, 0.0]).unwrap();
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws).unwrap();
    let mut m = g.march(&ray);
    assert_eq!(m.by_ref().count(), 0);
    assert_eq!(m.error(), Some(MarchError::Unrepresentable));
    assert_eq!(
        g.march_separable::<32>(&ray).err(),
        Some(MarchError::Unrepresentable)
    );
}

#[test]
fn subnormal_direction_with_representable_t_marches_exactly_like_a_unit_one() {
    // A grid 2^-53 the size of the unit one and a direction 2^-1030 (components subnormal, all exact): every t is
    // the unit march's t times 2^977, bit for bit, and the cells are the same.
    // (powers of two from their bits: `powi` need not be exact, and under Miri it is not)
    let small =
        |v: &[f64]| -> Vec<f64> { v.iter().map(|x| x * f64::from_bits(970 << 52)).collect() };
    let (o, d) = ([-1.5, -0.25, -0.125], [1.0, 0.125, 0.09375]);
    let base = march_s(&R, &TH, &PH, &Ray::new(o, d).unwrap());
    assert!(base.len() >= 5, "{base:?}");
    let tiny = Ray::new(
        o.map(|x| x * f64::from_bits(970 << 52)), // 2^-53
        d.map(|x| x * f64::from_bits(1 << 44)),   // 2^-1030
    )
    .unwrap();
    assert!(tiny.dir().x < f64::MIN_POSITIVE);
    let c = march_s(&small(&R), &TH, &PH, &tiny);
    let k = f64::from_bits(2000 << 52); // 2^977
    let scaled: Vec<_> = base
        .iter()
        .map(|b| CellCrossing {
            cell: b.cell,
            t_enter: b.t_enter * k,
            t_exit: b.t_exit * k,
        })
        .collect();
    assert_eq!(c, scaled);
}

#[test]
fn each_grid_kind_states_its_shape_workspace_and_coordinates() {
    let (r, th, ph, z) = (
        [0.0, 0.5, 1.0, 2.0],
        [0.0, 1.0, PI],
        [0.0, 2.0, 4.0, 2.0 * PI],
        [-1.0, 1.0],
    );
    // exactly the workspace each kind asks for is enough, one scalar less is not
    assert_eq!(SphericalGrid::<f64>::workspace_len(4, 3, 4), 4 + 6 + 8);
    assert_eq!(CylindricalGrid::<f64>::workspace_len(4, 4), 4 + 8);
    assert_eq!(PolarGrid::<f64>::workspace_len(4, 4), 4 + 8);
    let mut ws = [0.0; 18];
    let s = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    assert_eq!(s.shape(), [3, 2, 3]);
    assert!(s.azimuth_is_full_turn());
    assert_eq!(s.coordinates(), Coordinates::SPHERICAL);
    let mut ws = [0.0; 12];
    let c = CylindricalGrid::new(&r, &ph, &z, &mut ws).unwrap();
    assert_eq!(c.shape(), [3, 3, 1]);
    let mut ws = [0.0; 12];
    let p = PolarGrid::new(&r, &ph[..3], &mut ws).unwrap();
    assert_eq!(p.shape(), [3, 2]);
    let mut ws = [0.0; 17];
    assert_eq!(
        SphericalGrid::new(&r, &th, &ph, &mut ws).err(),
        Some(GridError::WorkspaceTooSmall)
    );
    let mut ws = [0.0; 11];
    assert_eq!(
        CylindricalGrid::new(&r, &ph, &z, &mut ws).err(),
        Some(GridError::WorkspaceTooSmall)
    );
    assert_eq!(
        PolarGrid::new(&r, &ph, &mut ws).err(),
        Some(GridError::WorkspaceTooSmall)
    );
    // too small a workspace is reported before the breakpoints are read
    assert_eq!(
        SphericalGrid::new(&[1.0, 0.0], &th, &ph, &mut [0.0; 4]).err(),
        Some(GridError::WorkspaceTooSmall)
    );
    // a wedge is not a full turn
    let mut ws = [0.0; 18];
    let wedge = SphericalGrid::new(&r, &th, &ph[..3], &mut ws).unwrap();
    assert!(!wedge.azimuth_is_full_turn());
    assert_eq!(wedge.shape(), [3, 2, 2]);
    // which streams each kind has, and so which steps its march compiles
    let (sph, cyl, pol) = (
        Coordinates::SPHERICAL,
        Coordinates::CYLINDRICAL,
        Coordinates::POLAR,
    );
    assert_eq!(
        (sph.zenith(), sph.height(), sph.flat_radius()),
        (true, false, false)
    );
    assert_eq!(
        (cyl.zenith(), cyl.height(), cyl.flat_radius()),
        (false, true, true)
    );
    assert_eq!(
        (pol.zenith(), pol.height(), pol.flat_radius()),
        (false, false, true)
    );
    use crate::march::kind::{may_have_height, may_have_zenith};
    assert!(may_have_zenith::<Spherical>() && !may_have_height::<Spherical>());
    assert!(!may_have_zenith::<Cylindrical>() && may_have_height::<Cylindrical>());
    assert!(!may_have_zenith::<Polar>() && !may_have_height::<Polar>());
    assert!(may_have_zenith::<Dynamic>() && may_have_height::<Dynamic>());
}

#[test]
fn whole_lines_through_a_sphere_and_a_cylinder_grid() {
    // t from −∞: each stream starts where the line comes from (below every z plane going up, above them going
    // down; before the radius's hinge), and the crossings are those of the line.
    let all = |r: Ray<f64>| r.with_interval(f64::NEG_INFINITY, f64::INFINITY).unwrap();
    let line = all(Ray::new([0.0, 0.3, 0.2], [1.0, 0.0, 0.0]).unwrap());
    let (a, b) = ((1.0f64 - 0.13).sqrt(), (0.25f64 - 0.13).sqrt());
    let c = march_s(&R, &TH, &PH, &line);
    expect(
        &c,
        &[([1, 0, 0], -a, -b), ([0, 0, 0], -b, b), ([1, 0, 0], b, a)],
        1e-15,
    );
    let (rho, z) = ([0.0, 1.0, 2.0], [-1.0, 0.0, 1.0]);
    let mut ws = [0.0; 16];
    let g = CylindricalGrid::new(&rho, &PH, &z, &mut ws).unwrap();
    for (dz, want) in [
        (1.0, [([0, 0, 0], -1.0, 0.0), ([0, 0, 1], 0.0, 1.0)]),
        (-1.0, [([0, 0, 1], -1.0, 0.0), ([0, 0, 0], 0.0, 1.0)]),
    ] {
        let line = all(Ray::new([0.5, 0.5, 0.0], [0.0, 0.0, dz]).unwrap());
        let a: Vec<_> = g.march(&line).collect();
        let b: Vec<_> = g.march_separable::<8>(&line).unwrap().collect();
        assert_eq!(a, b);
        expect(&a, &want, 1e-15);
    }
}

#[test]
fn cylinder_segment_ending_before_a_z_plane() {
    // Up the vertical line (0.5, 0.5) from z = −2 to z = 0.5 (t_max = 2.5): z = −1 at t = 1, z = 0 at t = 2; the
    // plane z = 1 (t = 3) lies beyond the segment.
    let (rho, z) = ([0.0, 1.0, 2.0], [-1.0, 0.0, 1.0]);
    let mut ws = [0.0; 16];
    let g = CylindricalGrid::new(&rho, &PH, &z, &mut ws).unwrap();
    let ray = Ray::new([0.5, 0.5, -2.0], [0.0, 0.0, 1.0])
        .unwrap()
        .with_interval(0.0, 2.5)
        .unwrap();
    let a: Vec<_> = g.march(&ray).collect();
    let b: Vec<_> = g.march_separable::<8>(&ray).unwrap().collect();
    assert_eq!(a, b);
    expect(&a, &[([0, 0, 0], 1.0, 2.0), ([0, 0, 1], 2.0, 2.5)], 1e-15);
}

#[test]
fn subnormal_vertical_direction_crosses_a_z_plane_at_the_correctly_rounded_t() {
    // Up the line (0.5, 0.5) from z = −1e-300 with a direction 1e-310 long (subnormal: scaled by about 2^1030, so
    // the plane's denominator cannot take the scale and the quotient is rescaled instead): z = 0 at t = 1e10
    // (to the rounding of the two literals), z = 1 at t ≈ 1e310, which is not representable.
    let (rho, z) = ([0.0, 1.0, 2.0], [-1.0, 0.0, 1.0]);
    let mut ws = [0.0; 16];
    let g = CylindricalGrid::new(&rho, &PH, &z, &mut ws).unwrap();
    let ray = Ray::new([0.5, 0.5, -1e-300], [0.0, 0.0, 1e-310]).unwrap();
    let mut m = g.march(&ray);
    let got: Vec<_> = m.by_ref().collect();
    assert_eq!(m.error(), Some(MarchError::Unrepresentable));
    assert_eq!(got.len(), 1, "{got:?}");
    assert_eq!((got[0].cell, got[0].t_enter), ([0, 0, 0], 0.0));
    assert!((got[0].t_exit / 1e10 - 1.0).abs() < 1e-12, "{got:?}");
}

#[test]
fn segments_ending_at_and_before_the_center_of_a_line_through_it() {
    // Along +x at y = z = 0 from x = −2 (the center at t = 2): ending at t = 2 the walk through the center is
    // taken there (zero-length crossings into the far cells); ending at t = 1.5 it is not.
    let seg = |t_max: f64| {
        Ray::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0])
            .unwrap()
            .with_interval(0.0, t_max)
            .unwrap()
    };
    let c = march_s(&R, &TH, &PH, &seg(1.5));
    let cells: Vec<_> = c.iter().map(|x| x.cell).collect();
    assert_eq!(cells, [[1, 1, 1], [0, 1, 1]], "{c:?}");
    assert_eq!(c[1].t_exit, 1.5);
    let c = march_s(&R, &TH, &PH, &seg(2.0));
    let at_end = c
        .iter()
        .filter(|x| x.t_enter == 2.0 && x.t_exit == 2.0)
        .count();
    assert!(at_end >= 1, "{c:?}");
    assert_eq!(c.last().map(|x| x.cell), Some([0, 1, 0]), "{c:?}");
}

#[test]
fn polar_ray_whose_flat_direction_alone_is_tiny_is_an_error_not_a_crossing_at_infinity() {
    // Along (1e-309, 0, 1) from (0.5, 0): the line's own direction is unit-sized, but its projection on the plane,
    // which a polar grid's radius follows, is subnormal: r = 0.75 is crossed at t = 2.5e308 and r = 1 at 5e308,
    // beyond the largest f64. The march reports the error, not a crossing at t = ∞.
    let (r, ph) = ([0.0, 0.75, 1.0], [0.0, 2.0 * PI]);
    let mut ws = [0.0; 16];
    let g = PolarGrid::new(&r, &ph, &mut ws).unwrap();
    let ray = Ray::new([0.5, 0.0, 0.0], [1e-309, 0.0, 1.0]).unwrap();
    let mut m = g.march(&ray);
    let got: Vec<_> = m.by_ref().collect();
    assert_eq!(m.error(), Some(MarchError::Unrepresentable), "{got:?}");
    assert!(got.iter().all(|c| c.t_exit.is_finite()), "{got:?}");
}

/// A tiny direction whose `t` overflows only where the line leaves the outer ball, beyond a finite `t_max` (the
/// line from (−1.5, 0.1, 0.2) along +x at 1e-308 enters the unit ball at t ≈ 5.3e307 and would leave it at
/// t ≈ 2.5e308): restricted to `t ≤ 1e308` it marches its one crossing, finite, to `t_max`; with `t_max = ∞` it
/// is refused. Behind the origin the same: from (0.9, 0.1, 0.2) the line left the ball at t ≈ −4.7e308 (not
/// finite) and leaves it ahead at t ≈ 1.9e307; from `t_min = 0` that crossing is marched, from `t_min = −∞` the
/// march is refused (both engines).
#[test]
fn tiny_direction_whose_t_overflows_only_outside_the_interval_marches() {
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws).unwrap();
    let x_ball = 0.95_f64.sqrt();
    let cases = [
        (
            [-1.5, 0.1, 0.2],
            1e-308,
            [0.0, 1e308],
            (1.5 - x_ball) / 1e-308,
            1e308,
        ),
        (
            [0.9, 0.1, 0.2],
            4e-309,
            [0.0, f64::INFINITY],
            0.0,
            (x_ball - 0.9) / 4e-309,
        ),
    ];
    for (o, dx, [t_min, t_max], t_enter, t_exit) in cases {
        let ray = Ray::new(o, [dx, 0.0, 0.0]).unwrap();
        let limited = ray.with_interval(t_min, t_max).unwrap();
        let mut m = g.march(&limited);
        let got: Vec<_> = m.by_ref().collect();
        assert_eq!(m.error(), None, "{o:?}");
        assert_eq!(got.len(), 1, "{o:?}: {got:?}");
        let c = got[0];
        assert_eq!(c.cell, [1, 0, 0], "{o:?}");
        assert!(
            (c.t_enter - t_enter).abs() <= 1e-14 * t_exit,
            "{o:?}: {c:?} vs {t_enter}"
        );
        assert!(
            (c.t_exit - t_exit).abs() <= 1e-14 * t_exit,
            "{o:?}: {c:?} vs {t_exit}"
        );
        let separable: Vec<_> = g.march_separable::<32>(&limited).unwrap().collect();
        assert_eq!(separable, got, "{o:?}");
        // The whole line on the side where t overflows: refused.
        let whole = if t_min == 0.0 && t_max.is_finite() {
            ray.with_interval(0.0, f64::INFINITY)
        } else {
            ray.with_interval(f64::NEG_INFINITY, t_max)
        }
        .unwrap();
        let mut m = g.march(&whole);
        assert_eq!(m.by_ref().count(), 0, "{o:?}");
        assert_eq!(m.error(), Some(MarchError::Unrepresentable), "{o:?}");
        assert_eq!(
            g.march_separable::<32>(&whole).err(),
            Some(MarchError::Unrepresentable),
            "{o:?}"
        );
    }
}

/// The line y = 0.5 along +x through a ball of radius 1 cut into 36 sectors (boundaries at 5° + 10°k): its
/// azimuth falls from 150° where it enters the ball to 30° where it leaves, crossing the twelve boundaries from
/// 145° to 35° inside, and goes on falling towards 0° outside, across 25°, 15° and 5°. The separable engine
/// lists only the twelve (it stops a coordinate's list at the last event of the radius, once the ray has left
/// the outer sphere for good), and gives the serial engine's crossings.
#[test]
fn separable_march_lists_no_azimuth_crossing_after_the_ray_leaves_the_outer_sphere() {
    let r = [0.0, 1.0];
    let th = [0.0, PI];
    let ph: Vec<f64> = (0..=36)
        .map(|k| (5.0 + 10.0 * f64::from(k)).to_radians())
        .collect();
    let mut ws = [0.0; 128];
    let g = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
    let ray = Ray::new([-3.0, 0.5, 0.0], [1.0, 0.0, 0.0]).unwrap();
    let mut m = SeparableMarch::<f64, 16>::default();
    g.march_separable_into(&ray, &mut m).unwrap();
    assert_eq!(m.listed()[2], 12);
    let got: Vec<_> = m.by_ref().collect();
    let want: Vec<_> = g.march(&ray).collect();
    assert_eq!(got, want);
    assert_eq!(got.len(), 13);
}

/// A tiny direction from inside the ball (radius 1) whose crossings of the inner sphere (radius 0.5) have finite
/// `t` but whose exit from the ball does not: refused before any crossing, by both engines (the set-up's test of
/// the outer ball, whose first, cheap bound must hold however the origin and the radius compare). From
/// (−0.5, 0.1, 0.2) along x at 5e-309 (the inner sphere at t ≈ 1.1e307 and 1.9e308, the ball's exit beyond
/// 2.9e308) and from (−0.05, 0.01, 0.02) at 4e-309 (the inner sphere at t ≈ 1.4e308, the exit beyond 2.6e308).
#[test]
fn tiny_direction_from_inside_the_ball_whose_exit_overflows_is_refused_before_any_crossing() {
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws).unwrap();
    for (o, dx) in [([-0.5, 0.1, 0.2], 5e-309), ([-0.05, 0.01, 0.02], 4e-309)] {
        let ray = Ray::new(o, [dx, 0.0, 0.0]).unwrap();
        let mut m = g.march(&ray);
        let got: Vec<_> = m.by_ref().collect();
        assert_eq!(
            (got.as_slice(), m.error()),
            (&[][..], Some(MarchError::Unrepresentable)),
            "{o:?}"
        );
        assert_eq!(
            g.march_separable::<32>(&ray).err(),
            Some(MarchError::Unrepresentable)
        );
    }
}

/// Tiny directions whose `t` overflows only where the line does not cross the ball: marched without an error.
/// The lines y = 1 and z = 1 along x from x = −3 at 2^−1023 touch the unit ball at t = 3·2^1023, beyond the
/// largest `f64` (a touch is not a crossing): no crossing. The line from (−3, 0.1, 0.2) along x at 2^−1020 crosses
/// it at t below 4·2^1020, all finite, though the set-up's cheap bound (28·2^1020) is not: the crossings of the
/// same line along x at unit speed, each `t` times 2^1020 exactly, from `t = 0` or over the whole line.
#[test]
fn tiny_direction_touching_the_ball_or_crossing_it_at_finite_t_marches_without_an_error() {
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws).unwrap();
    let tiny = |k: i32| libm::scalbn(1.0, k);
    for o in [[-3.0, 1.0, 0.0], [-3.0, 0.0, 1.0]] {
        let ray = Ray::new(o, [tiny(-1023), 0.0, 0.0]).unwrap();
        let mut m = g.march(&ray);
        assert_eq!(m.by_ref().count(), 0, "{o:?}");
        assert_eq!(m.error(), None, "{o:?}");
        assert_eq!(g.march_separable::<32>(&ray).map(|s| s.count()), Ok(0));
    }
    let o = [-3.0, 0.1, 0.2];
    let unit: Vec<_> = g.march(&Ray::new(o, [1.0, 0.0, 0.0]).unwrap()).collect();
    let ray = Ray::new(o, [tiny(-1020), 0.0, 0.0]).unwrap();
    let mut m = g.march(&ray);
    let got: Vec<_> = m.by_ref().collect();
    assert_eq!(m.error(), None);
    assert!(!unit.is_empty());
    let scaled: Vec<_> = unit
        .iter()
        .map(|c| CellCrossing {
            cell: c.cell,
            t_enter: c.t_enter * tiny(1020),
            t_exit: c.t_exit * tiny(1020),
        })
        .collect();
    assert_eq!(got, scaled);
    let separable: Vec<_> = g.march_separable::<32>(&ray).unwrap().collect();
    assert_eq!(separable, scaled);
    // and over the whole line (t from −∞): the same crossings
    let line = ray.with_interval(f64::NEG_INFINITY, f64::INFINITY).unwrap();
    let mut m = g.march(&line);
    assert_eq!(m.by_ref().collect::<Vec<_>>(), scaled);
    assert_eq!(m.error(), None);
}

/// Cylinder grid rho ∈ {0.5, 1, 2} (a hole of radius 0.5 round the axis), φ ∈ {−0.5, 0, 0.5}, z ∈ {0, 1}. A
/// vertical line at (0.5, −0.2) (ρ² = 0.29, between the radii 0.5 and 1; x² − y² and x²y² would put it in the
/// hole) stays in the cell of its ρ; a horizontal ray starting in the hole, at (0, 0.1, 0.5) along x, marches from
/// where it leaves the hole (ρ = 0.5 at x = √0.24) out through ρ = 1 and 2.
#[test]
fn vertical_line_in_the_cell_of_its_radius_and_a_ray_starting_in_the_hole_of_a_cylinder_grid() {
    let (rho, ph, z) = ([0.5, 1.0, 2.0], [-0.5, 0.0, 0.5], [0.0, 1.0]);
    let mut ws = [0.0; 16];
    let g = CylindricalGrid::new(&rho, &ph, &z, &mut ws).unwrap();
    // at φ = −0.38, in the sector [−0.5, 0)
    let vertical = Ray::new([0.5, -0.2, -1.0], [0.0, 0.0, 1.0]).unwrap();
    let c: Vec<_> = g.march(&vertical).collect();
    assert_eq!(c.len(), 1);
    assert_eq!(
        (c[0].cell, c[0].t_enter, c[0].t_exit),
        ([0, 0, 0], 1.0, 2.0)
    );
    let from_hole = Ray::new([0.0, 0.1, 0.5], [1.0, 0.0, 0.0]).unwrap();
    let c: Vec<_> = g.march(&from_hole).collect();
    let cells: Vec<_> = c.iter().map(|c| c.cell).collect();
    assert_eq!(cells, [[0, 1, 0], [1, 1, 0]]);
    for (got, want) in [
        (c[0].t_enter, 0.24f64.sqrt()),
        (c[0].t_exit, 0.99f64.sqrt()),
        (c[1].t_exit, 3.99f64.sqrt()),
    ] {
        assert!((got - want).abs() < 1e-15, "{got} against {want}");
    }
    let s: Vec<_> = g.march_separable::<16>(&from_hole).unwrap().collect();
    assert_eq!(s, c);
}

/// The line from (−0.5, 1e-10, 0.1) along (1, −(1 + 2^−20)·2^−30, 0) crosses the half-plane φ = π (y = 0,
/// x < 0) inside the ball, nearly parallel to it, at t ≈ 0.1. Along the same direction times 2^−996 (exactly),
/// every crossing's `t` is the first one's times 2^996, bit for bit: the plane's `t` is formed in the scaled
/// parameter and rescaled exactly, where folding the rescaling into its small denominator (about 2^−1026, a
/// subnormal, which keeps fewer bits than the denominator has) would round.
#[test]
fn tiny_direction_nearly_parallel_to_an_azimuth_plane_crosses_it_at_exactly_the_rescaled_t() {
    let mut ws = [0.0; 64];
    let g = SphericalGrid::new(&R, &TH, &PH, &mut ws).unwrap();
    let o = [-0.5, 1e-10, 0.1];
    // (1 + 2^−20)·2^−30: few enough bits that the direction times 2^−996 (subnormal) is exact
    let d = [
        1.0,
        -(1.0 + libm::scalbn(1.0, -20)) * libm::scalbn(1.0, -30),
        0.0,
    ];
    let unit: Vec<_> = g.march(&Ray::new(o, d).unwrap()).collect();
    let k = libm::scalbn(1.0, -996);
    let tiny: Vec<_> = g
        .march(&Ray::new(o, [d[0] * k, d[1] * k, d[2] * k]).unwrap())
        .collect();
    assert!(unit.iter().any(|c| c.cell[2] == 1) && unit.iter().any(|c| c.cell[2] == 0));
    let scaled: Vec<_> = unit
        .iter()
        .map(|c| CellCrossing {
            cell: c.cell,
            t_enter: c.t_enter / k,
            t_exit: c.t_exit / k,
        })
        .collect();
    assert_eq!(tiny, scaled);
}
