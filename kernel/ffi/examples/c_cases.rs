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
use curvicast::march::{AnyGrid, CylindricalGrid, MarchError, PolarGrid, SphericalGrid};
use curvicast::ray::Ray;
use curvicast::terrain::build::{
    MultiRes, NodeRecord, Parts, SliceStorage, build_multires_tree, build_tree, node_slots,
};
use curvicast::terrain::{Grid, Picker, TerrainError};
use curvicast::tessellate::bevel::{Face, bevel_ellipsoid};
use curvicast::tessellate::lod::{Bound, Shape, min_level};
use curvicast::vec3::V3;
use curvicast_ffi::curvicast_status as S;
use curvicast_ffi::terrain::{CURVICAST_PICKER_STACK, CURVICAST_PICKER_ZONES};
use std::fmt::Write as _;
use std::io::{BufRead, Write};
use std::sync::atomic::{AtomicBool, Ordering};

#[path = "../../qemu-smoke/src/dem_crop.rs"]
#[allow(dead_code)]
mod dem_crop;
#[path = "c_cases/emit.rs"]
mod emit;

use emit::emit;

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
            .map(AnyGrid::from)
            .map_err(S::from),
        'C' => CylindricalGrid::new(&axes[0], &axes[1], &axes[2], &mut ws)
            .and_then(|g| g.with_center(c3))
            .map(AnyGrid::from)
            .map_err(S::from),
        _ => PolarGrid::new(&axes[0], &axes[1], &mut ws)
            .and_then(|g| g.with_center([c3[0], c3[1]]))
            .map(AnyGrid::from)
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
