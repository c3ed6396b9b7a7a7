//! The shared cases of the C interface's host test, answered through the kernel's Rust API.
//!
//! * `c_cases emit` writes the cases (one per line; numbers as the hex bits of their `float`/`double`, so both
//!   languages read them exactly): marches through spherical, cylindrical and polar grids in both precisions
//!   (the QEMU smoke test's march, random rays, the named hard geometries, invalid input), picks, `pick_t`s and
//!   lines of sight on the Trinidad crop of the QEMU smoke test (single- and multi-resolution, the latter with
//!   blocks paged in on `NEEDS_BLOCK`), level choices and bevels.
//! * `c_cases run` reads cases on stdin and prints the answers, every number as its bits.
//!
//! `kernel/ffi/c/cases.c` answers the same lines through `libcurvicast.a`; `kernel/ffi/c/check-host.sh` compares
//! the two outputs byte for byte.

use curvicast::Real;
use curvicast::geodesy::Ellipsoid;
use curvicast::ray::Ray;
use curvicast::spherical::{CylindricalGrid, MarchError, PolarGrid, SerialMarch, SphericalGrid};
use curvicast::terrain::build::{
    MultiRes, NodeRecord, Parts, SliceStorage, build_multires_tree, build_tree, node_slots,
};
use curvicast::terrain::{Grid, Picker, TerrainError};
use curvicast::tessellate::bevel::{Face, bevel_ellipsoid};
use curvicast::tessellate::lod::{Bound, Shape, min_level};
use curvicast::vec3::V3;
use curvicast_ffi::curvicast_status as S;
use curvicast_ffi::terrain::{CURVICAST_PICKER_STACK, CURVICAST_PICKER_ZONES};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::io::{BufRead, Write};
use std::sync::atomic::{AtomicBool, Ordering};

#[path = "../../qemu-smoke/src/dem_crop.rs"]
#[allow(dead_code)]
mod dem_crop;

/// A scalar as its hex bits, both ways.
trait Bits: Real {
    const BITS_NAME: &'static str;
    fn hex(self) -> String;
    fn parse(s: &str) -> Option<Self>;
}

impl Bits for f32 {
    const BITS_NAME: &'static str = "32";
    fn hex(self) -> String {
        format!("0x{:08x}", self.to_bits())
    }
    fn parse(s: &str) -> Option<f32> {
        u32::from_str_radix(s.strip_prefix("0x")?, 16)
            .ok()
            .map(f32::from_bits)
    }
}

impl Bits for f64 {
    const BITS_NAME: &'static str = "64";
    fn hex(self) -> String {
        format!("0x{:016x}", self.to_bits())
    }
    fn parse(s: &str) -> Option<f64> {
        u64::from_str_radix(s.strip_prefix("0x")?, 16)
            .ok()
            .map(f64::from_bits)
    }
}

fn main() {
    match std::env::args().nth(1).as_deref() {
        Some("emit") => print!("{}", emit()),
        Some("run") => {
            let lines: Vec<String> = std::io::stdin()
                .lock()
                .lines()
                .map_while(Result::ok)
                .collect();
            let mut lines = lines.iter().map(String::as_str).enumerate().peekable();
            let mut out = String::new();
            while let Some((n, line)) = lines.next() {
                run(line, &mut lines, &mut out)
                    .unwrap_or_else(|| panic!("line {}: malformed case", n + 1));
            }
            std::io::stdout()
                .lock()
                .write_all(out.as_bytes())
                .expect("stdout");
        }
        _ => {
            eprintln!("usage: c_cases emit | c_cases run < cases");
            std::process::exit(2);
        }
    }
}

// ---------------------------------------------------------------------------------------------------------
// The cases.

/// A xorshift generator of uniform numbers in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` non-uniform breakpoints from `lo` to `hi`.
fn breakpoints(lo: f64, hi: f64, n: usize) -> Vec<f64> {
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

fn list<T: Bits>(v: &[f64]) -> String {
    let mut s = v.len().to_string();
    for &x in v {
        write!(s, " {}", T::from_f64(x).hex()).ok();
    }
    s
}

fn values<T: Bits>(v: &[f64]) -> String {
    v.iter()
        .map(|&x| T::from_f64(x).hex())
        .collect::<Vec<_>>()
        .join(" ")
}

/// A march case line: kind, precision, the axes, the center (or none), the ray, the workspace shortfall.
fn march_line<T: Bits>(
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
fn random_ray(rng: &mut Rng, planar: bool) -> [f64; 8] {
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
fn hard_rays(planar: bool) -> Vec<[f64; 8]> {
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

fn march_cases<T: Bits>(out: &mut String, rng: &mut Rng) {
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

fn terrain_cases<T: Bits>(out: &mut String) {
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

fn tessellate_cases<T: Bits>(out: &mut String) {
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

fn emit() -> String {
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

/// The tokens of a line.
struct Tokens<'a>(std::str::SplitWhitespace<'a>);
impl Tokens<'_> {
    fn word(&mut self) -> Option<&str> {
        self.0.next()
    }
    fn int<I: std::str::FromStr>(&mut self) -> Option<I> {
        self.0.next()?.parse().ok()
    }
    fn real<T: Bits>(&mut self) -> Option<T> {
        T::parse(self.0.next()?)
    }
    fn reals<T: Bits>(&mut self, n: usize) -> Option<Vec<T>> {
        (0..n).map(|_| self.real()).collect()
    }
    fn list<T: Bits>(&mut self) -> Option<Vec<T>> {
        let n = self.int()?;
        self.reals(n)
    }
}

fn code(s: S) -> u32 {
    s as u32
}

/// The lines after a `terrain` line: its picks and lines of sight.
type Lines<'a, I> = std::iter::Peekable<I>;

fn run<'a, I: Iterator<Item = (usize, &'a str)>>(
    line: &str,
    rest: &mut Lines<'a, I>,
    out: &mut String,
) -> Option<()> {
    let mut t = Tokens(line.split_whitespace());
    let answer = match t.word()? {
        "march" => {
            let kind = t.word()?.chars().next()?;
            match t.word()? {
                "32" => march::<f32>(kind, &mut t),
                _ => march::<f64>(kind, &mut t),
            }
        }
        "terrain" => {
            return match t.word()? {
                "32" => terrain::<f32, I>(&mut t, rest, out),
                _ => terrain::<f64, I>(&mut t, rest, out),
            };
        }
        "level" => match t.word()? {
            "32" => level::<f32>(&mut t),
            _ => level::<f64>(&mut t),
        },
        "bevel" => match t.word()? {
            "32" => bevel::<f32>(&mut t),
            _ => bevel::<f64>(&mut t),
        },
        _ => None,
    };
    out.push_str(&answer?);
    Some(())
}

fn ray_of<T: Bits>(v: &[T]) -> Result<Ray<T>, S> {
    Ok(Ray::new([v[0], v[1], v[2]], [v[3], v[4], v[5]])?.with_interval(v[6], v[7])?)
}

/// One grid kind's march, behind one type.
enum AnyGrid<'a, T> {
    S(SphericalGrid<'a, T>),
    C(CylindricalGrid<'a, T>),
    P(PolarGrid<'a, T>),
}

impl<T: Real> AnyGrid<'_, T> {
    fn march(&self, ray: &Ray<T>) -> SerialMarch<'_, T> {
        match self {
            AnyGrid::S(g) => g.march(ray),
            AnyGrid::C(g) => g.march(ray),
            AnyGrid::P(g) => g.march(ray),
        }
    }
}

fn march<T: Bits>(kind: char, t: &mut Tokens) -> Option<String> {
    let n_axes = if kind == 'P' { 2 } else { 3 };
    let axes: Vec<Vec<T>> = (0..n_axes).map(|_| t.list()).collect::<Option<_>>()?;
    let center: Option<Vec<T>> = match t.int::<u32>()? {
        0 => None,
        _ => Some(t.reals(if kind == 'P' { 2 } else { 3 })?),
    };
    let ray = t.reals::<T>(8)?;
    let shortfall: usize = t.int()?;
    let need = match kind {
        'S' => SphericalGrid::<T>::workspace_len(axes[0].len(), axes[1].len(), axes[2].len()),
        'C' => CylindricalGrid::<T>::workspace_len(axes[0].len(), axes[1].len()),
        _ => PolarGrid::<T>::workspace_len(axes[0].len(), axes[1].len()),
    };
    let mut ws = vec![T::ZERO; need.saturating_sub(shortfall)];
    let c3 = center.as_ref().map_or([T::ZERO; 3], |c| {
        [c[0], c[1], c.get(2).copied().unwrap_or(T::ZERO)]
    });
    let grid: Result<AnyGrid<T>, S> = match kind {
        'S' => SphericalGrid::new(&axes[0], &axes[1], &axes[2], &mut ws)
            .and_then(|g| g.with_center(c3))
            .map(AnyGrid::S)
            .map_err(S::from),
        'C' => CylindricalGrid::new(&axes[0], &axes[1], &axes[2], &mut ws)
            .and_then(|g| g.with_center(c3))
            .map(AnyGrid::C)
            .map_err(S::from),
        _ => PolarGrid::new(&axes[0], &axes[1], &mut ws)
            .and_then(|g| g.with_center([c3[0], c3[1]]))
            .map(AnyGrid::P)
            .map_err(S::from),
    };
    let grid = match grid {
        Ok(g) => g,
        Err(e) => return Some(format!("M {} -\n", code(e))),
    };
    let ray = match ray_of(&ray) {
        Ok(r) => r,
        Err(e) => return Some(format!("M 0 {}\n", code(e))),
    };
    let mut out = String::from("M 0 0\n");
    let mut march = grid.march(&ray);
    for c in &mut march {
        let [i, j, k] = c.cell;
        writeln!(out, "  {i} {j} {k} {} {}", c.t_enter.hex(), c.t_exit.hex()).ok();
    }
    let end = march
        .error()
        .map_or(S::CURVICAST_DONE, |e: MarchError| S::from(e));
    // The C side marches again in batches (`curvicast_march_*_fill`) and says whether they agree.
    writeln!(out, "  end {}\n  fill agrees", code(end)).ok();
    Some(out)
}

/// A `terrain` line and the picks and lines of sight after it, with one storage and one picker.
fn terrain<'a, T: Bits, I: Iterator<Item = (usize, &'a str)>>(
    t: &mut Tokens,
    rest: &mut Lines<'a, I>,
    out: &mut String,
) -> Option<()> {
    let multires = t.int::<u32>()? == 1;
    let (rows, cols): (u32, u32) = (t.int()?, t.int()?);
    let g: Vec<T> = t.reals(4)?;
    let block = t.int()?;
    let shape = if multires {
        let fine: Option<Vec<T>> = if t.int::<u32>()? == 1 {
            Some(t.reals(4)?)
        } else {
            None
        };
        let fine_region = fine.map(|f| [f[0], f[1], f[2], f[3]]);
        Some(MultiRes {
            fine_region,
            coarse_level: t.int()?,
        })
    } else {
        None
    };
    let heights: Vec<f32> = t.list()?;
    let grid = Grid {
        lat0_deg: g[0],
        lon0_deg: g[1],
        dlat_deg: g[2],
        dlon_deg: g[3],
        rows,
        cols,
    };
    let mut nodes = vec![NodeRecord::<f32>::EMPTY; node_slots(rows, cols, block)];
    // Multi-resolution: every block paged out; the picks page them in one by one.
    let resident: Vec<AtomicBool> = (0..if multires { nodes.len() } else { 0 })
        .map(|_| AtomicBool::new(false))
        .collect();
    let built = match shape {
        None => build_tree(&heights, &grid, block, &mut nodes),
        Some(shape) => build_multires_tree(&heights, &grid, block, shape, &mut nodes),
    };
    let storage = built.map_err(S::from).and_then(|tree| {
        let flags = if resident.is_empty() {
            &[][..]
        } else {
            resident
                .get(..tree.slots())
                .ok_or(S::CURVICAST_BUILD_BUFFER_LENGTH)?
        };
        let parts = Parts::new(&heights[..], &nodes[..]).with_resident(flags);
        Ok(Storage::<T>::with_buffers(
            Ellipsoid::wgs84(),
            grid,
            tree,
            parts,
        )?)
    });
    let storage = match storage {
        Ok(s) => s,
        Err(e) => {
            writeln!(out, "T {} -", code(e)).ok();
            return Some(());
        }
    };
    let picker = match CPicker::<T>::new(&storage) {
        Ok(p) => p,
        Err(e) => {
            writeln!(out, "T 0 {}", code(e.into())).ok();
            return Some(());
        }
    };
    out.push_str("T 0 0\n");
    while let Some(&(_, line)) = rest.peek() {
        let mut t = Tokens(line.split_whitespace());
        match t.word()? {
            "pick" => pick::<T>(&picker, &resident, &mut t, out)?,
            "los" => los::<T>(&picker, &resident, &mut t, out)?,
            _ => break,
        }
        rest.next();
    }
    Some(())
}

type Storage<'a, T> = SliceStorage<'a, T, f32, (), AtomicBool>;
type CPicker<'s, T> = Picker<'s, T, Storage<'s, T>, CURVICAST_PICKER_STACK, CURVICAST_PICKER_ZONES>;

/// Asks `f` until it answers something other than `NeedsBlock`, paging in (and printing) each node it needs.
fn paging<V>(
    resident: &[AtomicBool],
    out: &mut String,
    mut f: impl FnMut() -> Result<V, TerrainError>,
) -> Result<V, TerrainError> {
    loop {
        match f() {
            Err(TerrainError::NeedsBlock(id)) if resident.get(id.0 as usize).is_some() => {
                writeln!(out, "  needs {}", id.0).ok();
                resident[id.0 as usize].store(true, Ordering::Relaxed);
            }
            r => return r,
        }
    }
}

fn pick<T: Bits>(
    p: &CPicker<T>,
    resident: &[AtomicBool],
    t: &mut Tokens,
    out: &mut String,
) -> Option<()> {
    let v = t.reals::<T>(8)?;
    out.push_str("P\n");
    let ray = ray_of(&v);
    match ray.and_then(|r| paging(resident, out, || p.pick(&r)).map_err(S::from)) {
        Ok(Some(h)) => {
            let e = h.ecef.map(Bits::hex).join(" ");
            let (lat, lon, hh) = (h.lat_deg.hex(), h.lon_deg.hex(), h.h.hex());
            let [i, j] = h.cell;
            writeln!(
                out,
                "  hit {} {e} {lat} {lon} {hh} {i} {j} {} {}",
                h.t.hex(),
                h.stride,
                h.level
            )
            .ok()
        }
        Ok(None) => writeln!(out, "  no hit").ok(),
        Err(e) => writeln!(out, "  error {}", code(e)).ok(),
    };
    match ray.and_then(|r| paging(resident, out, || p.pick_t(&r)).map_err(S::from)) {
        Ok(Some((t, [i, j]))) => writeln!(out, "  t {} {i} {j}", t.hex()).ok(),
        Ok(None) => writeln!(out, "  t none").ok(),
        Err(e) => writeln!(out, "  t error {}", code(e)).ok(),
    };
    Some(())
}

fn los<T: Bits>(
    p: &CPicker<T>,
    resident: &[AtomicBool],
    t: &mut Tokens,
    out: &mut String,
) -> Option<()> {
    let (a, b) = (t.reals::<T>(3)?, t.reals::<T>(3)?);
    out.push_str("L\n");
    match paging(resident, out, || {
        p.line_of_sight([a[0], a[1], a[2]], [b[0], b[1], b[2]])
    }) {
        Ok(clear) => writeln!(out, "  clear {}", u8::from(clear)).ok(),
        Err(e) => writeln!(out, "  error {}", code(e.into())).ok(),
    };
    Some(())
}

fn level<T: Bits>(t: &mut Tokens) -> Option<String> {
    let kind = t.word()?.to_string();
    let axes = t.reals::<T>(3)?;
    let (a, b) = (t.real::<T>()?, t.real::<T>()?);
    let shape = if axes[0] == axes[1] && axes[1] == axes[2] {
        Shape::Sphere(axes[0])
    } else {
        Shape::Ellipsoid([axes[0], axes[1], axes[2]])
    };
    let bound = match kind.as_str() {
        "D" => Bound::MaxDeviation(a),
        "A" => Bound::MinDihedral(a),
        _ => Bound::ScreenSpace {
            distance: a,
            pixel_angle: b,
        },
    };
    Some(match min_level(shape, bound) {
        Ok(l) => format!("V 0 {l}\n"),
        Err(e) => format!("V {} -\n", code(e.into())),
    })
}

fn bevel<T: Bits>(t: &mut Tokens) -> Option<String> {
    let level: u32 = t.int()?;
    let axes = t.reals::<T>(3)?;
    let (nv, nf): (usize, usize) = (t.int()?, t.int()?);
    let mut v = vec![V3::<T>::ZERO; nv];
    let mut f = vec![Face::<T>::EMPTY; nf];
    Some(
        match bevel_ellipsoid(level, [axes[0], axes[1], axes[2]], &mut v, &mut f) {
            Ok(_) => {
                // FNV-1a over every number written, as its bits in decimal text.
                let mut h: u64 = 0xcbf2_9ce4_8422_2325;
                let mut eat = |s: String| {
                    for b in s.bytes().chain([b' ']) {
                        h = (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
                    }
                };
                for p in &v {
                    [p.x, p.y, p.z].into_iter().for_each(|x| eat(x.hex()));
                }
                for face in &f {
                    let c = [face.center, face.normal];
                    c.iter()
                        .flat_map(|p| [p.x, p.y, p.z])
                        .for_each(|x| eat(x.hex()));
                    face.vertices.iter().for_each(|i| eat(i.to_string()));
                    eat(face.len.to_string());
                }
                format!("B 0 {h:016x}\n")
            }
            Err(e) => format!("B {} -\n", code(e.into())),
        },
    )
}
