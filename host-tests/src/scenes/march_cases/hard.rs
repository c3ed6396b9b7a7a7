//! The named hard cases of marching (rays through the origin, along the z axis, tangent to shells, parallel to cone generators, through edges and corners, starting on boundaries, at Earth and micro scales...), each a list of grids and rays.

use super::*;

/// Rays through the center in many directions (θ jumps to π − θ, φ by π), on the full, partial and shifted grids.
pub fn through_origin() -> Vec<Case> {
    let mut rng = deterministic_rng(1);
    let mut out = Vec::new();
    for grid in [full_grid(), partial_grid(), shifted_grid()] {
        let (c, _) = bounds(&grid);
        let mut rays = Vec::new();
        for n in 0..24 {
            let u = unit(&mut rng);
            // dyadic multiples keep the center exactly on the line: origin = c − 2u (rounded), dir = u
            let origin = [0, 1, 2].map(|i| c[i] - 2.0 * u[i]);
            let dir = [0, 1, 2].map(|i| c[i] - origin[i]);
            let mut ray = RaySpec::new(origin, dir);
            if n % 4 == 3 {
                ray.t_min = 0.5;
                ray.t_max = Some(1.5);
            }
            rays.push(ray);
        }
        out.push(Case {
            name: "through_origin",
            grid,
            rays,
        });
    }
    out
}

pub(super) fn axis_rays(sign: f64) -> Vec<RaySpec> {
    let mut v = Vec::new();
    for &start in &[-2.0, -0.6, 0.0, 0.3, 2.0] {
        let mut r = RaySpec::new([0.0, 0.0, start * sign], [0.0, 0.0, sign]);
        if start == 2.0 {
            r.dir = [0.0, 0.0, -sign];
        }
        v.push(r);
    }
    v.push(RaySpec {
        origin: [0.0, 0.0, -1.5 * sign],
        dir: [0.0, 0.0, 0.5 * sign],
        t_min: 1.0,
        t_max: Some(4.0),
    });
    v
}

/// Rays along the +z axis (every point on the axis: φ undefined, θ = 0 or π).
pub fn along_plus_z_axis() -> Vec<Case> {
    [full_grid(), partial_grid(), shifted_grid()]
        .into_iter()
        .map(|grid| {
            let (c, _) = bounds(&grid);
            let rays = axis_rays(1.0)
                .into_iter()
                .map(|mut r| {
                    r.origin = shift(r.origin, c);
                    r
                })
                .collect();
            Case {
                name: "along_plus_z_axis",
                grid,
                rays,
            }
        })
        .collect()
}

/// Rays along the −z axis.
pub fn along_minus_z_axis() -> Vec<Case> {
    [full_grid(), partial_grid(), shifted_grid()]
        .into_iter()
        .map(|grid| {
            let (c, _) = bounds(&grid);
            let rays = axis_rays(-1.0)
                .into_iter()
                .map(|mut r| {
                    r.origin = shift(r.origin, c);
                    r
                })
                .collect();
            Case {
                name: "along_minus_z_axis",
                grid,
                rays,
            }
        })
        .collect()
}

/// Rays lying in the plane z = 0, which is the zenith breakpoint π/2 (the half-open rule puts them in the band
/// below it), through the origin and not.
pub fn in_plane_z0() -> Vec<Case> {
    let mut rng = deterministic_rng(2);
    [full_grid(), partial_grid()]
        .into_iter()
        .map(|grid| {
            let mut rays = vec![
                RaySpec::new([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
                RaySpec::new([-2.0, 0.3, 0.0], [1.0, 0.0, 0.0]),
                RaySpec::new([0.1, -2.0, 0.0], [0.0, 1.0, 0.0]),
                RaySpec::new([0.0, 0.0, 0.0], [0.6, 0.8, 0.0]),
            ];
            for _ in 0..12 {
                let a: f64 = rng.random_range(0.0..TAU);
                let b: f64 = rng.random_range(-0.9..0.9);
                rays.push(RaySpec::new(
                    [
                        -2.0 * a.cos() - b * a.sin(),
                        -2.0 * a.sin() + b * a.cos(),
                        0.0,
                    ],
                    [a.cos(), a.sin(), 0.0],
                ));
            }
            Case {
                name: "in_plane_z0",
                grid,
                rays,
            }
        })
        .collect()
}

/// Rays that cross the z axis exactly, off the origin: `(−a, −b, z0) + t (a, b, dz)` meets the axis at `t = 1`.
pub fn crossing_z_axis_off_origin() -> Vec<Case> {
    let mut rng = deterministic_rng(3);
    [full_grid(), partial_grid(), shifted_grid()]
        .into_iter()
        .map(|grid| {
            let (c, _) = bounds(&grid);
            let mut rays = Vec::new();
            for n in 0..16 {
                let a: f64 = rng.random_range(-1.0..1.0);
                let b: f64 = rng.random_range(-1.0..1.0);
                let z0: f64 = rng.random_range(-0.9..0.9);
                let dz: f64 = if n % 3 == 0 {
                    0.0
                } else {
                    rng.random_range(-0.5..0.5)
                };
                rays.push(RaySpec::new([c[0] - a, c[1] - b, c[2] + z0], [a, b, dz]));
            }
            // through the axis point exactly on a zenith band edge region and on a sphere: (0, 0, 3/4)
            rays.push(RaySpec::new(
                [c[0] - 0.5, c[1] - 0.25, c[2] + 0.75],
                [0.5, 0.25, 0.0],
            ));
            Case {
                name: "crossing_z_axis_off_origin",
                grid,
                rays,
            }
        })
        .collect()
}

/// Rays parallel to a generator of a zenith cone (the quadratic degenerates to a linear equation), offset from
/// the apex in several directions (also along the axis, where the line meets the cone once).
pub fn parallel_to_cone_generator() -> Vec<Case> {
    let mut out = Vec::new();
    for grid in [full_grid(), partial_grid()] {
        let GridSpec::Spherical { theta, .. } = &grid else {
            continue;
        };
        let mut rays = Vec::new();
        for &t in theta.iter() {
            if t == 0.0 || t == PI || t == FRAC_PI_2 {
                continue;
            }
            // azimuths that are no breakpoint: the line offset along the axis lies in the vertical plane of g
            for &phi in &[0.45, 2.2, 3.8] {
                let g = [t.sin() * f64::cos(phi), t.sin() * f64::sin(phi), t.cos()];
                // offset from the apex: a line through the apex along g would lie in the cone up to the
                // rounding of g, where either side is a correct answer (an ill-posed case, not tested here)
                for &off in &[
                    [0.1, 0.0, 0.0],
                    [0.0, -0.2, 0.05],
                    [0.0, 0.0, 0.3],
                    [0.0, 0.0, -0.25],
                ] {
                    rays.push(RaySpec::new(
                        [
                            off[0] - 2.0 * g[0],
                            off[1] - 2.0 * g[1],
                            off[2] - 2.0 * g[2],
                        ],
                        g,
                    ));
                }
            }
        }
        out.push(Case {
            name: "parallel_to_cone_generator",
            grid,
            rays,
        });
    }
    out
}

/// Rays tangent to the shell r = 9/16 (exactly: the discriminant is 0), and 1e-12 (relative) inside and outside
/// tangency; also tangent to the inner sphere of the partial grid.
pub fn tangent_to_shell() -> Vec<Case> {
    let mut out = Vec::new();
    for (grid, rr) in [
        (full_grid(), 0.5625),
        (partial_grid(), 0.25),
        (partial_grid(), 0.625),
    ] {
        let mut rays = Vec::new();
        for &f in &[1.0, 1.0 - 1e-12, 1.0 + 1e-12] {
            let y = rr * f;
            rays.push(RaySpec::new([-2.0, y, 0.0], [1.0, 0.0, 0.0]));
            rays.push(RaySpec::new([-2.0, 0.0, y], [1.0, 0.0, 0.0]));
            rays.push(RaySpec::new([0.0, -2.0, -y], [0.0, 1.0, 0.0]));
            rays.push(RaySpec::new([y, 0.0, -2.0], [0.0, 0.0, 1.0]));
            rays.push(RaySpec::new([0.6 * y, 0.8 * y, -2.0], [0.0, 0.0, 1.0]));
        }
        out.push(Case {
            name: "tangent_to_shell",
            grid,
            rays,
        });
    }
    out
}

/// Rays through edges: sphere ∩ plane θ = π/2 exactly (points (0, ±R, 0)), and sphere ∩ cone (the f64 point
/// nearest the edge: a tie up to rounding, which the comparison tolerates).
pub fn through_edge() -> Vec<Case> {
    let grid = full_grid();
    let mut rays = Vec::new();
    for &rr in &[0.25, 0.5625, 0.75] {
        for &p in &[[0.0, rr, 0.0], [0.0, -rr, 0.0]] {
            for d in [[0.5, 0.25, 0.5], [-0.25, 0.5, -0.75], [1.0, 0.0, 0.25]] {
                rays.push(RaySpec::new(
                    [p[0] - 2.0 * d[0], p[1] - 2.0 * d[1], p[2] - 2.0 * d[2]],
                    d,
                ));
            }
        }
        for &t in &[0.4_f64, 1.1, 2.0, 2.7] {
            let phi: f64 = 1.3;
            let p = [
                rr * t.sin() * phi.cos(),
                rr * t.sin() * phi.sin(),
                rr * t.cos(),
            ];
            for d in [[0.5, 0.25, 0.5], [-0.25, 0.5, -0.75]] {
                rays.push(RaySpec::new(
                    [p[0] - 2.0 * d[0], p[1] - 2.0 * d[1], p[2] - 2.0 * d[2]],
                    d,
                ));
            }
        }
    }
    vec![Case {
        name: "through_edge",
        grid,
        rays,
    }]
}

/// Rays through corners sphere ∩ plane θ = π/2 ∩ half-plane φ = 0 (the exact point (R, 0, 0)), and the f64
/// point nearest a corner sphere ∩ cone ∩ half-plane.
pub fn through_corner() -> Vec<Case> {
    let grid = full_grid();
    let mut rays = Vec::new();
    for &rr in &[0.25, 0.5625, 0.75, 1.0] {
        for d in [
            [-0.5, 0.25, 0.5],
            [-0.25, -0.5, -0.75],
            [1.0, 0.5, 0.25],
            [0.0, 0.5, 0.5],
        ] {
            let p = [rr, 0.0, 0.0];
            rays.push(RaySpec::new(
                [p[0] - 2.0 * d[0], p[1] - 2.0 * d[1], p[2] - 2.0 * d[2]],
                d,
            ));
        }
        for (t, phi) in [(0.4f64, 0.7f64), (1.1, 2.0), (2.0, 3.3), (2.7, 5.5)] {
            let p = [
                rr * t.sin() * phi.cos(),
                rr * t.sin() * phi.sin(),
                rr * t.cos(),
            ];
            for d in [[0.5, 0.25, 0.5], [-0.25, 0.5, -0.75]] {
                rays.push(RaySpec::new(
                    [p[0] - 2.0 * d[0], p[1] - 2.0 * d[1], p[2] - 2.0 * d[2]],
                    d,
                ));
            }
        }
    }
    vec![Case {
        name: "through_corner",
        grid,
        rays,
    }]
}

pub(super) fn directions() -> [[f64; 3]; 6] {
    [
        [1.0, 0.0, 0.0],
        [-0.5, 0.25, 0.5],
        [0.25, -0.5, -0.75],
        [0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0],
        [-0.75, -0.5, 0.125],
    ]
}

/// Rays starting exactly on a sphere (`(1/4, 1/2, 1/2)` has r = 3/4), on the plane θ = π/2, on the half-plane
/// φ = 0, near a cone (the nearest f64 point), on the inner sphere of a partial grid, on a cylinder and a plane
/// z of a cylindrical grid and on a circle and half-line of a polar grid; in several directions each.
pub fn starting_on_boundary() -> Vec<Case> {
    let mut out = Vec::new();
    let starts_sph: Vec<[f64; 3]> = vec![
        [0.25, 0.5, 0.5],
        [0.3, 0.2, 0.0],
        [0.4, 0.0, 0.1],
        {
            let (t, p): (f64, f64) = (1.1, 2.5);
            [
                0.6 * t.sin() * p.cos(),
                0.6 * t.sin() * p.sin(),
                0.6 * t.cos(),
            ]
        },
        [0.0, 0.0, 0.0],
        [0.75, 0.0, 0.0],
    ];
    let rays = |starts: &[[f64; 3]]| {
        let mut v = Vec::new();
        for s in starts {
            for d in directions() {
                v.push(RaySpec::new(*s, d));
                v.push(RaySpec::new(*s, d.map(|a| -a)));
            }
        }
        v
    };
    out.push(Case {
        name: "starting_on_boundary",
        grid: full_grid(),
        rays: rays(&starts_sph),
    });
    out.push(Case {
        name: "starting_on_boundary",
        grid: partial_grid(),
        rays: rays(&[
            [0.0, 0.25, 0.0],
            [0.125, 0.0, 0.0],
            [0.3, 0.2, 0.0],
            [0.5, 0.0, 0.0],
        ]),
    });
    out.push(Case {
        name: "starting_on_boundary",
        grid: GridSpec::Cylindrical {
            center: None,
            rho: vec![0.0, 0.25, 0.625, 1.0],
            phi: vec![0.0, 1.5, 3.0, 4.5, TAU],
            z: vec![-1.0, -0.25, 0.5, 1.0],
        },
        rays: rays(&[
            [0.375, 0.5, 0.0],
            [0.5, 0.0, -0.25],
            [0.3, 0.2, 0.5],
            [0.25, 0.0, -1.0],
        ]),
    });
    out.push(Case {
        name: "starting_on_boundary",
        grid: GridSpec::Polar {
            center: None,
            r: vec![0.0, 0.25, 0.625, 1.0],
            phi: vec![0.0, 1.5, 3.0, 4.5, TAU],
        },
        rays: rays(&[[0.375, 0.5, 0.0], [0.5, 0.0, 0.7], [0.0, 0.0, 0.0]])
            .into_iter()
            .filter(|r| r.dir[0] != 0.0 || r.dir[1] != 0.0)
            .collect(),
    });
    out
}

/// Rays whose interval `[t_min, t_max]` starts and ends inside the domain (also inside a single cell).
pub fn starting_and_ending_inside() -> Vec<Case> {
    let mut rng = deterministic_rng(4);
    [full_grid(), partial_grid(), shifted_grid()]
        .into_iter()
        .map(|grid| {
            let (c, rad) = bounds(&grid);
            let mut rays = Vec::new();
            for n in 0..24 {
                let u = unit(&mut rng);
                let v = unit(&mut rng);
                let o = [0, 1, 2].map(|i| c[i] + 0.9 * rad * u[i]);
                let mut r = RaySpec::new(o, v);
                r.t_min = if n % 2 == 0 { 0.0 } else { 0.05 };
                r.t_max = Some(r.t_min + if n % 3 == 0 { 1e-3 } else { 0.3 });
                rays.push(r);
            }
            Case {
                name: "starting_and_ending_inside",
                grid,
                rays,
            }
        })
        .collect()
}

/// Rays that leave a wedge wider than π (φ ∈ [−0.5, 4.0]) through one face and re-enter through the other.
pub fn reentering_wide_wedge() -> Vec<Case> {
    let mut rays = Vec::new();
    for &y in &[-0.3, -0.6, -0.15] {
        for &z in &[0.0, 0.1, -0.2] {
            rays.push(RaySpec::new([-2.0, y, z], [1.0, 0.0, 0.0]));
            rays.push(RaySpec::new([2.0, y, z], [-1.0, 0.0, 0.0]));
            rays.push(RaySpec::new([-2.0, y, z], [1.0, 0.125, 0.0625]));
        }
    }
    let mut out = vec![Case {
        name: "reentering_wide_wedge",
        grid: partial_grid(),
        rays: rays.clone(),
    }];
    out.push(Case {
        name: "reentering_wide_wedge",
        grid: GridSpec::Cylindrical {
            center: None,
            rho: vec![0.0, 0.5, 1.0],
            phi: vec![-0.5, 1.0, 2.5, 4.0],
            z: vec![-1.0, 0.0, 1.0],
        },
        rays: rays.clone(),
    });
    out.push(Case {
        name: "reentering_wide_wedge",
        grid: GridSpec::Polar {
            center: None,
            r: vec![0.0, 0.5, 1.0],
            phi: vec![-0.5, 1.0, 2.5, 4.0],
        },
        rays,
    });
    out
}

/// Rays crossing the θ = π/2 boundary at steep and grazing angles, and skimming just above and below it.
pub fn theta_half_pi_boundary() -> Vec<Case> {
    let mut rays = Vec::new();
    for &dz in &[1.0, 0.1, 1e-3, 1e-8, -1e-8, -0.5] {
        rays.push(RaySpec::new([-2.0, 0.1, -2.0 * dz], [1.0, 0.0, dz]));
        rays.push(RaySpec::new([-2.0, -0.4, -dz], [1.0, 0.25, dz]));
    }
    for &z in &[1e-12, -1e-12, 1e-300, -1e-300] {
        rays.push(RaySpec::new([-2.0, 0.2, z], [1.0, 0.0, 0.0]));
    }
    [full_grid(), partial_grid()]
        .into_iter()
        .map(|grid| Case {
            name: "theta_half_pi_boundary",
            grid,
            rays: rays.clone(),
        })
        .collect()
}

/// A grid at Earth scale: radii 6 371 000 m … +24 m in 1 m shells (non-uniform at the ends), a zenith band of
/// 1e-6 rad bands around θ = 0.8 and an azimuth wedge of 1e-6 rad sectors around φ = 0.3; rays vertical,
/// slanted and grazing through it.
pub fn earth_scale() -> Vec<Case> {
    let r0 = 6_371_000.0;
    let mut r: Vec<f64> = (0..=24).map(|i| r0 + i as f64).collect();
    r.insert(1, r0 + 0.25);
    let theta: Vec<f64> = (0..=12).map(|i| 0.8 + i as f64 * 1e-6).collect();
    let phi: Vec<f64> = (0..=12).map(|i| 0.3 + i as f64 * 1e-6).collect();
    let grid = GridSpec::Spherical {
        center: None,
        r,
        theta,
        phi,
    };
    let (t, p) = (0.8 + 6.3e-6f64, 0.3 + 5.7e-6f64);
    let up = [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()];
    let east = [-p.sin(), p.cos(), 0.0];
    let north = [t.cos() * p.cos(), t.cos() * p.sin(), -t.sin()];
    let at = |h: f64| up.map(|a| a * (r0 + h));
    let mut rays = Vec::new();
    let combo = |a: [f64; 3], b: [f64; 3], s: f64| [0, 1, 2].map(|i| a[i] + s * b[i]);
    // vertical, downward from 100 m above
    rays.push(RaySpec::new(at(100.0), up.map(|a| -a)));
    // slanted
    for &(e, n) in &[(1.0, 0.0), (0.0, 1.0), (0.7, -0.7), (3.0, 1.0)] {
        let d = combo(combo(up.map(|a| -a), east, e), north, n);
        rays.push(RaySpec::new(combo(at(30.0), d, -3.0), d));
    }
    // grazing: nearly horizontal at 12.5 m height
    for &s in &[1e-3, 1e-5] {
        let d = combo(east, up, -s);
        rays.push(RaySpec::new(combo(at(12.5), east, -3.0), d));
    }
    vec![Case {
        name: "earth_scale",
        grid,
        rays,
    }]
}

/// Cones within 1e-12 to 1e-6 of either pole (where `cos² θ` rounds to 1 and only `sin θ` tells them from the
/// axis), crossed by nearly vertical lines at distances from the axis of the cones' own size, and by horizontal
/// lines passing the axis just inside and outside them.
pub fn near_the_poles() -> Vec<Case> {
    let theta = vec![
        0.0,
        1e-12,
        5e-9,
        1e-6,
        FRAC_PI_2,
        PI - 1e-6,
        PI - 5e-9,
        PI - 1e-12,
        PI,
    ];
    let grid = GridSpec::Spherical {
        center: None,
        r: vec![0.0, 0.5, 1.0, 2.0],
        theta,
        phi: vec![0.0, 2.0, 4.0, TAU],
    };
    let mut rays = Vec::new();
    for &rho in &[1e-12, 1.5e-12, 4e-9, 6e-9, 1e-6, 1.7e-6] {
        for &slope in &[0.0, 1e-13, 1e-10, 3e-7] {
            for &dz in &[1.0, -1.0] {
                // from below (above) the ball along ±z, starting inside the ball and from outside it
                rays.push(RaySpec::new(
                    [rho * 0.6, rho * 0.8, -3.0 * dz],
                    [slope, -0.5 * slope, dz],
                ));
                rays.push(RaySpec::new(
                    [-rho * 0.8, rho * 0.6, 0.3 * dz],
                    [0.0, slope, dz],
                ));
            }
        }
    }
    for &b in &[5e-13, 2e-12, 2e-9, 8e-9, 5e-7, 3e-6] {
        for &h in &[1.0, -1.0, 0.7, -1.9] {
            rays.push(RaySpec::new([-3.0, b, h], [1.0, 0.0, 0.0]));
            rays.push(RaySpec::new([b, -3.0, h], [0.0, 1.0, 1e-9]));
        }
    }
    vec![Case {
        name: "near_the_poles",
        grid,
        rays,
    }]
}

/// [`full_grid`] and [`partial_grid`] scaled by 1e-6 (center shifted by 1e-6), with random rays scaled alike.
pub fn micro_scale() -> Vec<Case> {
    let mut rng = deterministic_rng(5);
    let s = 1e-6;
    let scale = |g: GridSpec| match g {
        GridSpec::Spherical { r, theta, phi, .. } => GridSpec::Spherical {
            center: Some([s, -0.5 * s, 0.25 * s]),
            r: r.iter().map(|a| a * s).collect(),
            theta,
            phi,
        },
        g => g,
    };
    [scale(full_grid()), scale(partial_grid())]
        .into_iter()
        .map(|grid| {
            let rays = (0..40).map(|_| random_ray(&mut rng, &grid)).collect();
            Case {
                name: "micro_scale",
                grid,
                rays,
            }
        })
        .collect()
}

/// Random rays on the full and partial grids with the direction scaled to length `len` (1e-30 or 1e30): the
/// parameters t scale by 1/len and nothing may overflow or underflow.
pub fn direction_length(len: f64) -> Vec<Case> {
    let mut rng = deterministic_rng(6);
    [full_grid(), partial_grid()]
        .into_iter()
        .map(|grid| {
            let rays = (0..40)
                .map(|_| {
                    let mut r = random_ray(&mut rng, &grid);
                    let n = r.dir.iter().map(|a| a * a).sum::<f64>().sqrt();
                    let k = len / n;
                    r.dir = r.dir.map(|a| a * k);
                    r.t_min *= n / len;
                    r.t_max = r.t_max.map(|t| t * n / len);
                    r
                })
                .collect();
            Case {
                name: "direction_length",
                grid,
                rays,
            }
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------------------------
// the random suite
