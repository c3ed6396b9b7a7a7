//! `c_cases emit`: the cases, one per line (marches over random and named hard rays, terrain picks and paging,
//! level choices and bevels), every number as the hex bits of its type.

use super::*;
use std::f64::consts::PI;

/// A xorshift generator of uniform numbers in [0, 1).
pub(super) struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` non-uniform breakpoints from `lo` to `hi`.
pub(super) fn breakpoints(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let u = i as f64 / (n - 1) as f64;
            if i + 1 == n {
                hi
            } else {
                lo + (hi - lo) * u * (1.0 + u) / 2.0
            }
        })
        .collect()
}

pub(super) fn list<T: Bits>(v: &[f64]) -> String {
    let mut s = v.len().to_string();
    for &x in v {
        write!(s, " {}", T::from_f64(x).hex()).ok();
    }
    s
}

pub(super) fn values<T: Bits>(v: &[f64]) -> String {
    v.iter()
        .map(|&x| T::from_f64(x).hex())
        .collect::<Vec<_>>()
        .join(" ")
}

/// A march case line: kind, precision, the axes, the center (or none), the ray, the workspace shortfall.
pub(super) fn march_line<T: Bits>(
    kind: char,
    axes: &[&[f64]],
    center: Option<&[f64]>,
    ray: [f64; 8],
    shortfall: usize,
) -> String {
    let axes: Vec<String> = axes.iter().map(|a| list::<T>(a)).collect();
    let center = center.map_or("0".to_string(), |c| format!("1 {}", values::<T>(c)));
    format!(
        "march {kind} {} {} {center} {} {shortfall}\n",
        <T as Bits>::BITS_NAME,
        axes.join(" "),
        values::<T>(&ray)
    )
}

/// A ray from the sphere of radius 2.5 toward a point within 0.9 of the center.
pub(super) fn random_ray(rng: &mut Rng, planar: bool) -> [f64; 8] {
    let mut unit = |s: f64| {
        let (u, v) = (rng.next(), rng.next());
        let (z, a) = (if planar { 0.0 } else { 2.0 * u - 1.0 }, 2.0 * PI * v);
        let q = (1.0 - z * z).sqrt();
        [s * q * a.cos(), s * q * a.sin(), s * z]
    };
    let (from, to) = (unit(2.5), unit(0.63));
    [
        from[0],
        from[1],
        from[2],
        to[0] - from[0],
        to[1] - from[1],
        to[2] - from[2],
        0.0,
        f64::INFINITY,
    ]
}

/// The named hard geometries, as rays (origin, direction, interval).
pub(super) fn hard_rays(planar: bool) -> Vec<[f64; 8]> {
    let inf = f64::INFINITY;
    let mut v = vec![
        [-2.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, inf], // through the origin along x
        [-2.0, 0.25, 0.0, 1.0, 0.0, 0.0, 0.0, inf], // across phi = 0 and pi
        [-2.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, inf], // tangent to the unit circle / sphere
        [0.1, 0.2, 0.0, 0.3, -0.4, 0.0, 0.0, inf], // starting inside
        [-2.0, 0.1, 0.0, 1.0, 0.0, 0.0, 0.5, 2.3], // an interval ending inside
        [-1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, inf], // starting on the outer boundary
        [-2.0, 0.3, 0.0, 1e-30, 0.0, 0.0, 0.0, inf], // a tiny direction
    ];
    if !planar {
        v.push([0.0, 0.0, -2.0, 0.0, 0.0, 1.0, 0.0, inf]); // along the z axis
        v.push([0.3, 0.0, -2.0, 0.0, 0.0, 1.0, 0.0, inf]); // parallel to the z axis
        v.push([-2.0, 0.2, 0.1, 1.0, 0.0, 0.0, 0.0, inf]); // near the equator
    }
    v.extend([
        [-2.0, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, inf], // zero direction
        [f64::NAN, 0.1, 0.0, 1.0, 0.0, 0.0, 0.0, inf], // NaN origin
        [-2.0, 0.1, 0.0, 1.0, 0.0, 0.0, 2.0, 1.0], // t_min > t_max
    ]);
    v
}

pub(super) fn march_cases<T: Bits>(out: &mut String, rng: &mut Rng) {
    let tau = 2.0 * PI;
    // The QEMU smoke test's march.
    let r = [0.0, 0.5, 1.0];
    let (th, ph) = ([0.0, PI / 2.0, PI], [0.0, PI, tau]);
    out.push_str(&march_line::<T>(
        'S',
        &[&r, &th, &ph],
        None,
        [-2.0, 0.25, 0.25, 1.0, 0.0, 0.0, 0.0, f64::INFINITY],
        0,
    ));
    let (bp, none) = (breakpoints, None::<Vec<f64>>);
    // (kind, breakpoints per axis, center)
    let grids = [
        (
            'S',
            vec![bp(0.0, 1.0, 5), bp(0.0, PI, 5), bp(0.0, tau, 7)],
            none.clone(),
        ),
        (
            'S',
            vec![bp(0.3, 1.0, 4), bp(0.2, 2.9, 4), bp(-0.5, 0.5, 3)],
            none.clone(),
        ),
        (
            'S',
            vec![bp(0.0, 1.0, 3), bp(0.0, PI, 3), bp(0.0, tau, 4)],
            Some(vec![0.25, -0.5, 0.125]),
        ),
        (
            'C',
            vec![bp(0.0, 1.0, 4), bp(0.0, tau, 5), bp(-1.0, 1.0, 4)],
            none.clone(),
        ),
        (
            'C',
            vec![bp(0.2, 1.0, 3), bp(-1.0, 2.0, 4), bp(-0.5, 0.5, 3)],
            Some(vec![0.1, 0.1, 0.0]),
        ),
        ('P', vec![bp(0.0, 1.0, 5), bp(0.0, tau, 6)], none.clone()),
        (
            'P',
            vec![bp(0.4, 1.0, 3), bp(-0.5, 1.5, 4)],
            Some(vec![0.125, 0.0]),
        ),
    ];
    for (kind, axes, center) in &grids {
        let planar = *kind == 'P';
        let axes: Vec<&[f64]> = axes.iter().map(Vec::as_slice).collect();
        for ray in hard_rays(planar)
            .into_iter()
            .chain((0..12).map(|_| random_ray(rng, planar)))
        {
            out.push_str(&march_line::<T>(*kind, &axes, center.as_deref(), ray, 0));
        }
    }
    // Invalid grids: each axis's own error, and a workspace one scalar short.
    let ray = [-2.0, 0.1, 0.1, 1.0, 0.0, 0.0, 0.0, f64::INFINITY];
    let (r, th, ph) = (
        breakpoints(0.0, 1.0, 3),
        breakpoints(0.0, PI, 3),
        breakpoints(0.0, tau, 3),
    );
    for (rr, tt, pp) in [
        (vec![0.0, 1.0, 0.5], th.clone(), ph.clone()),
        (r.clone(), vec![0.0, f64::NAN, PI], ph.clone()),
        (vec![1.0], th.clone(), ph.clone()),
        (vec![-1.0, 1.0], th.clone(), ph.clone()),
        (r.clone(), vec![0.0, 4.0], ph.clone()),
        (r.clone(), th.clone(), vec![0.0, 7.0]),
    ] {
        out.push_str(&march_line::<T>('S', &[&rr, &tt, &pp], None, ray, 0));
    }
    out.push_str(&march_line::<T>('S', &[&r, &th, &ph], None, ray, 1));
    out.push_str(&march_line::<T>(
        'S',
        &[&r, &th, &ph],
        Some(&[f64::INFINITY, 0.0, 0.0]),
        ray,
        0,
    ));
    out.push_str(&march_line::<T>('C', &[&r, &ph, &[1.0, 0.0]], None, ray, 0));
    out.push_str(&march_line::<T>('P', &[&r, &ph], None, ray, 1));
}

pub(super) fn terrain_cases<T: Bits>(out: &mut String) {
    use dem_crop::{BLOCK, COLS, GRID, HEIGHTS, RAYS, ROWS};
    let heights: Vec<String> = HEIGHTS.iter().map(|&h| f32::from(h).hex()).collect();
    let grid = values::<T>(&GRID);
    let (s, w) = (GRID[0] + (ROWS - 1) as f64 * GRID[2], GRID[1]);
    let fine = values::<T>(&[s + 0.01, s + 0.02, w + 0.01, w + 0.03]);
    for multires in [None, Some("0 1".to_string()), Some(format!("1 {fine} 1"))] {
        let (flag, shape) = match multires {
            None => ("0".to_string(), String::new()),
            Some(m) => ("1".to_string(), format!(" {m}")),
        };
        writeln!(
            out,
            "terrain {} {flag} {ROWS} {COLS} {grid} {BLOCK}{shape} {} {}",
            <T as Bits>::BITS_NAME,
            heights.len(),
            heights.join(" ")
        )
        .ok();
        for r in &RAYS {
            let ray = [
                r.origin[0],
                r.origin[1],
                r.origin[2],
                r.dir[0],
                r.dir[1],
                r.dir[2],
                0.0,
                f64::INFINITY,
            ];
            writeln!(out, "pick {}", values::<T>(&ray)).ok();
            if let Some(t) = r.t {
                let at = |s: f64| [0, 1, 2].map(|k| r.origin[k] + s * t * r.dir[k]);
                writeln!(
                    out,
                    "los {} {}",
                    values::<T>(&r.origin),
                    values::<T>(&at(0.99))
                )
                .ok();
                writeln!(
                    out,
                    "los {} {}",
                    values::<T>(&r.origin),
                    values::<T>(&at(1.01))
                )
                .ok();
            }
        }
        let o = RAYS[0].origin;
        writeln!(
            out,
            "pick {}",
            values::<T>(&[o[0], o[1], o[2], 0.0, 0.0, 0.0, 0.0, f64::INFINITY])
        )
        .ok();
    }
    // Invalid DEMs: a block of 0, too few heights.
    writeln!(
        out,
        "terrain {} 0 {ROWS} {COLS} {grid} 0 {} {}",
        <T as Bits>::BITS_NAME,
        heights.len(),
        heights.join(" ")
    )
    .ok();
    writeln!(
        out,
        "terrain {} 0 {ROWS} {COLS} {grid} {BLOCK} 3 {}",
        <T as Bits>::BITS_NAME,
        heights[..3].join(" ")
    )
    .ok();
}

pub(super) fn tessellate_cases<T: Bits>(out: &mut String) {
    let wgs84 = [6378137.0, 6378137.0, 6356752.314245];
    for (kind, axes, a, b) in [
        ('D', [1.0; 3], 1e-2, 0.0),
        ('D', [1.0; 3], 1e-4, 0.0),
        ('D', wgs84, 100.0, 0.0),
        ('D', [3.0, 2.0, 1.0], 1e-3, 0.0),
        ('D', [1.0; 3], -1.0, 0.0),
        ('A', [1.0; 3], 3.0, 0.0),
        ('A', [3.0, 2.0, 1.0], 3.1, 0.0),
        ('S', [1.0; 3], 10.0, 1e-3),
        ('S', wgs84, 2e7, 1e-4),
        ('S', [1.0; 3], 0.5, 1e-3),
    ] {
        writeln!(
            out,
            "level {} {kind} {} {} {}",
            <T as Bits>::BITS_NAME,
            values::<T>(&axes),
            T::from_f64(a).hex(),
            T::from_f64(b).hex()
        )
        .ok();
    }
    for level in 0..4u32 {
        for axes in [[1.0; 3], [3.0, 2.0, 1.0]] {
            let (nv, nf) = (8usize << (2 * level), (4usize << (2 * level)) + 2);
            writeln!(
                out,
                "bevel {} {level} {} {nv} {nf}",
                <T as Bits>::BITS_NAME,
                values::<T>(&axes)
            )
            .ok();
        }
    }
    writeln!(
        out,
        "bevel {} 2 {} 127 66",
        <T as Bits>::BITS_NAME,
        values::<T>(&[1.0; 3])
    )
    .ok();
    writeln!(
        out,
        "bevel {} 13 {} 0 0",
        <T as Bits>::BITS_NAME,
        values::<T>(&[1.0; 3])
    )
    .ok();
    writeln!(
        out,
        "bevel {} 1 {} 32 18",
        <T as Bits>::BITS_NAME,
        values::<T>(&[1.0, 0.0, 1.0])
    )
    .ok();
}

pub(super) fn emit() -> String {
    let mut out = String::new();
    let mut rng = Rng(0x5EED_C0DE);
    march_cases::<f32>(&mut out, &mut rng);
    march_cases::<f64>(&mut out, &mut rng);
    terrain_cases::<f32>(&mut out);
    terrain_cases::<f64>(&mut out);
    tessellate_cases::<f32>(&mut out);
    tessellate_cases::<f64>(&mut out);
    out
}

// ---------------------------------------------------------------------------------------------------------
// The answers.
