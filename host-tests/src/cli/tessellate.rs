//! `curvicast tessellate (--sphere R | --ellipsoid A B C) (--level K | --max-angle-deg X | --max-deviation E)
//! --out FILE.obj`: the edge-beveled polyhedron (seed 004 §4.3–4.4) as Wavefront OBJ, and a one-line JSON summary
//! `{"level": k, "faces": n, "vertices": m, "min_dihedral_deg": x, "max_deviation": e}` on stdout.
//!
//! * `--level K` builds level K; `--max-angle-deg X` asks for the smallest level whose adjacent faces' normals are
//!   at most X degrees apart (the smallest dihedral angle at least `180 − X`); `--max-deviation E` for the smallest
//!   level whose largest distance from the true surface is at most E. Both are chosen a priori by
//!   `curvicast::tessellate::lod::min_level`, which returns the smallest level that meets the bound for spheres
//!   and ellipsoids alike, without building any level.
//! * The summary's `min_dihedral_deg` and `max_deviation` are *measured* on the built polyhedron: dihedral angles
//!   from the face normals of every pair of faces sharing an edge (normals by Newell's method from the written
//!   vertices), the deviation as the largest distance of a vertex from the surface (for a convex polyhedron
//!   around a convex surface the farthest points are vertices), for ellipsoids by a bisection of its own.
//! * Faces are written counter-clockwise seen from outside, 1-based, as polygons (quadrilaterals and hexagons).
//!
//! Also home of the mesh measurements that the report and the host tests share.

use crate::cli::io::UsageError;
use curvicast::V3;
use curvicast::tessellate::bevel::{self, Face};
use curvicast::tessellate::lod::{self, Bound, Shape};
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The deepest level the command builds (level 10: 8.4 million vertices).
pub const CLI_MAX_LEVEL: u32 = 10;

/// A built polyhedron, owned.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Vertices.
    pub vertices: Vec<[f64; 3]>,
    /// Faces: vertex indices, counter-clockwise seen from outside.
    pub faces: Vec<Vec<u32>>,
    /// Each face's center point (where it touches the surface).
    pub centers: Vec<[f64; 3]>,
}

/// Semi-axes of a shape (a sphere has three equal ones).
pub fn axes_of(shape: Shape<f64>) -> [f64; 3] {
    match shape {
        Shape::Sphere(r) => [r, r, r],
        Shape::Ellipsoid(a) => a,
    }
}

/// Builds the level-`level` polyhedron of `shape` with the kernel (f64).
pub fn build(
    shape: Shape<f64>,
    level: u32,
) -> Result<Mesh, curvicast::tessellate::TessellateError> {
    let nv = bevel::vertex_count(level);
    let nf = bevel::face_count(level);
    if nv == usize::MAX {
        return Err(curvicast::tessellate::TessellateError::LevelTooDeep {
            level,
            max: bevel::MAX_LEVEL,
        });
    }
    let mut v = vec![V3::<f64>::ZERO; nv];
    let mut f = vec![Face::<f64>::EMPTY; nf];
    bevel::bevel_ellipsoid(level, axes_of(shape), &mut v, &mut f)?;
    Ok(Mesh {
        vertices: v.iter().map(|p| p.to_array()).collect(),
        faces: f.iter().map(|x| x.vertex_indices().to_vec()).collect(),
        centers: f.iter().map(|x| x.center.to_array()).collect(),
    })
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Newell's normal of a polygon (unit; outward for a counter-clockwise polygon seen from outside).
pub fn newell_normal(mesh: &Mesh, face: &[u32]) -> [f64; 3] {
    let mut n = [0.0; 3];
    // Relative to the first vertex, so that large coordinates do not cost precision.
    let o = mesh.vertices[face[0] as usize];
    for k in 0..face.len() {
        let a = sub(mesh.vertices[face[k] as usize], o);
        let b = sub(mesh.vertices[face[(k + 1) % face.len()] as usize], o);
        let c = cross(a, b);
        n = [n[0] + c[0], n[1] + c[1], n[2] + c[2]];
    }
    let l = norm(n);
    [n[0] / l, n[1] / l, n[2] / l]
}

/// The smallest dihedral angle (radians) over all pairs of faces sharing an edge, from Newell normals.
pub fn min_dihedral(mesh: &Mesh) -> f64 {
    let normals: Vec<[f64; 3]> = mesh.faces.iter().map(|f| newell_normal(mesh, f)).collect();
    let mut owner: HashMap<(u32, u32), usize> = HashMap::with_capacity(mesh.faces.len() * 3);
    let mut worst = std::f64::consts::PI;
    for (fi, f) in mesh.faces.iter().enumerate() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            if let Some(&other) = owner.get(&(b, a)) {
                let (n0, n1) = (normals[fi], normals[other]);
                let theta = norm(cross(n0, n1)).atan2(dot(n0, n1));
                worst = worst.min(std::f64::consts::PI - theta);
            } else {
                owner.insert((a, b), fi);
            }
        }
    }
    worst
}

/// Distance from a point outside (or on) the ellipsoid with semi-axes `a` to its surface: the Lagrange parameter
/// `t ≥ 0` of the closest point solves `Σ (a_i y_i / (t + a_i²))² = 1`, found by bisection; the gap is
/// `y_i t / (t + a_i²)` per axis (no cancellation). Returns a negative number for points inside.
pub fn ellipsoid_distance(a: [f64; 3], y: [f64; 3]) -> f64 {
    let inside = (0..3).map(|i| (y[i] / a[i]).powi(2)).sum::<f64>();
    if inside < 1.0 {
        return -1.0;
    }
    let f = |t: f64| {
        (0..3)
            .map(|i| (a[i] * y[i] / (t + a[i] * a[i])).powi(2))
            .sum::<f64>()
            - 1.0
    };
    let (mut lo, mut hi) = (
        0.0_f64,
        (0..3).map(|i| (a[i] * y[i]).powi(2)).sum::<f64>().sqrt(),
    );
    for _ in 0..2000 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let t = 0.5 * (lo + hi);
    (0..3)
        .map(|i| (y[i] * t / (t + a[i] * a[i])).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The largest distance between the polyhedron and the surface of `shape`: the largest vertex distance.
pub fn max_deviation(mesh: &Mesh, shape: Shape<f64>) -> f64 {
    match shape {
        Shape::Sphere(r) => mesh
            .vertices
            .iter()
            .map(|&v| norm(v) - r)
            .fold(f64::NEG_INFINITY, f64::max),
        Shape::Ellipsoid(a) => mesh
            .vertices
            .iter()
            .map(|&v| ellipsoid_distance(a, v))
            .fold(f64::NEG_INFINITY, f64::max),
    }
}

/// Writes the mesh as Wavefront OBJ.
pub fn write_obj(path: &Path, mesh: &Mesh, comment: &str) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(w, "# {comment}")?;
    for v in &mesh.vertices {
        writeln!(w, "v {:?} {:?} {:?}", v[0], v[1], v[2])?;
    }
    for f in &mesh.faces {
        write!(w, "f")?;
        for &i in f {
            write!(w, " {}", i + 1)?;
        }
        writeln!(w)?;
    }
    w.flush()
}

/// What to build, parsed from the command line.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// The surface.
    pub shape: Shape<f64>,
    /// How the level is chosen.
    pub detail: Detail,
    /// The OBJ file.
    pub out: PathBuf,
}

/// How the level is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Detail {
    /// `--level K`.
    Level(u32),
    /// `--max-angle-deg X`: adjacent normals at most X degrees apart.
    MaxAngleDeg(f64),
    /// `--max-deviation E`.
    MaxDeviation(f64),
}

const USAGE: &str = "usage: curvicast tessellate (--sphere R | --ellipsoid A B C) (--level K | --max-angle-deg X | --max-deviation E) --out FILE.obj";

fn num(flag: &str, s: Option<&String>) -> Result<f64, UsageError> {
    let s = s.ok_or_else(|| UsageError(format!("{flag}: missing value; {USAGE}")))?;
    let x: f64 = s
        .parse()
        .map_err(|_| UsageError(format!("{flag}: '{s}' is not a number")))?;
    if !x.is_finite() {
        return Err(UsageError(format!("{flag}: '{s}' is not finite")));
    }
    Ok(x)
}

/// Parses the arguments after `tessellate`. `Ok(None)` means `--help` was asked for.
pub fn parse(args: &[String]) -> Result<Option<Request>, UsageError> {
    let mut shape: Option<Shape<f64>> = None;
    let mut detail: Option<Detail> = None;
    let mut out: Option<PathBuf> = None;
    let mut it = args.iter();
    let set_shape = |s: &mut Option<Shape<f64>>, v: Shape<f64>| -> Result<(), UsageError> {
        if s.replace(v).is_some() {
            return Err(UsageError(
                "give exactly one of --sphere R or --ellipsoid A B C".into(),
            ));
        }
        Ok(())
    };
    let set_detail = |d: &mut Option<Detail>, v: Detail| -> Result<(), UsageError> {
        if d.replace(v).is_some() {
            return Err(UsageError(
                "give exactly one of --level K, --max-angle-deg X, --max-deviation E".into(),
            ));
        }
        Ok(())
    };
    while let Some(flag) = it.next() {
        match flag.as_str() {
            "-h" | "--help" => return Ok(None),
            "--sphere" => {
                let r = num(flag, it.next())?;
                if r <= 0.0 {
                    return Err(UsageError(format!("--sphere: radius {r} must be positive")));
                }
                set_shape(&mut shape, Shape::Sphere(r))?;
            }
            "--ellipsoid" => {
                let a = [
                    num(flag, it.next())?,
                    num(flag, it.next())?,
                    num(flag, it.next())?,
                ];
                if a.iter().any(|&x| x <= 0.0) {
                    return Err(UsageError(format!(
                        "--ellipsoid: semi-axes {a:?} must be positive"
                    )));
                }
                set_shape(&mut shape, Shape::Ellipsoid(a))?;
            }
            "--level" => {
                let s = it
                    .next()
                    .ok_or_else(|| UsageError(format!("--level: missing value; {USAGE}")))?;
                let k: u32 = s.parse().map_err(|_| {
                    UsageError(format!("--level: '{s}' is not a non-negative integer"))
                })?;
                set_detail(&mut detail, Detail::Level(k))?;
            }
            "--max-angle-deg" => {
                let x = num(flag, it.next())?;
                if x <= 0.0 {
                    return Err(UsageError(format!("--max-angle-deg: {x} must be positive")));
                }
                set_detail(&mut detail, Detail::MaxAngleDeg(x))?;
            }
            "--max-deviation" => {
                let e = num(flag, it.next())?;
                if e <= 0.0 {
                    return Err(UsageError(format!("--max-deviation: {e} must be positive")));
                }
                set_detail(&mut detail, Detail::MaxDeviation(e))?;
            }
            "--out" => {
                let p = it
                    .next()
                    .ok_or_else(|| UsageError(format!("--out: missing file name; {USAGE}")))?;
                if out.replace(PathBuf::from(p)).is_some() {
                    return Err(UsageError("--out given twice".into()));
                }
            }
            other => return Err(UsageError(format!("unknown argument '{other}'; {USAGE}"))),
        }
    }
    let shape =
        shape.ok_or_else(|| UsageError(format!("missing --sphere or --ellipsoid; {USAGE}")))?;
    let detail = detail.ok_or_else(|| {
        UsageError(format!(
            "missing --level, --max-angle-deg or --max-deviation; {USAGE}"
        ))
    })?;
    let out = out.ok_or_else(|| UsageError(format!("missing --out FILE.obj; {USAGE}")))?;
    Ok(Some(Request { shape, detail, out }))
}

/// The level a request asks for (a priori, without building anything).
pub fn choose_level(req: &Request) -> Result<u32, UsageError> {
    let level = match req.detail {
        Detail::Level(k) => k,
        Detail::MaxAngleDeg(x) => {
            if x >= 90.0 {
                0 // the cube's faces are 90° apart
            } else {
                lod::min_level(req.shape, Bound::MinDihedral((180.0 - x).to_radians()))
                    .map_err(|e| UsageError(format!("--max-angle-deg {x}: {e}")))?
            }
        }
        Detail::MaxDeviation(e) => lod::min_level(req.shape, Bound::MaxDeviation(e))
            .map_err(|err| UsageError(format!("--max-deviation {e}: {err}")))?,
    };
    if level > CLI_MAX_LEVEL {
        return Err(UsageError(format!(
            "level {level} is deeper than the command builds (at most {CLI_MAX_LEVEL})"
        )));
    }
    Ok(level)
}

/// The summary line's fields.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Summary {
    /// Refinement level.
    pub level: u32,
    /// Number of faces.
    pub faces: usize,
    /// Number of vertices.
    pub vertices: usize,
    /// Smallest dihedral angle, degrees (measured).
    pub min_dihedral_deg: f64,
    /// Largest distance from the surface (measured).
    pub max_deviation: f64,
}

/// Runs the subcommand: builds the a-priori level (the smallest that meets the bound), writes the OBJ, and returns
/// the summary (the caller prints it).
pub fn execute(req: &Request) -> Result<Summary, UsageError> {
    let level = choose_level(req)?;
    let mesh = build(req.shape, level).map_err(|e| UsageError(format!("tessellate: {e}")))?;
    let dihedral = min_dihedral(&mesh);
    let deviation = max_deviation(&mesh, req.shape);

    let comment = format!(
        "curvicast tessellate: edge-beveled polyhedron, level {level}, semi-axes {:?}",
        axes_of(req.shape)
    );
    write_obj(&req.out, &mesh, &comment)
        .map_err(|e| UsageError(format!("{}: cannot write: {e}", req.out.display())))?;
    Ok(Summary {
        level,
        faces: mesh.faces.len(),
        vertices: mesh.vertices.len(),
        min_dihedral_deg: dihedral.to_degrees(),
        max_deviation: deviation,
    })
}

/// The whole subcommand: parse, run, print the JSON line on stdout (or the usage on `--help`).
pub fn run(args: &[String]) -> Result<(), UsageError> {
    match parse(args)? {
        None => {
            println!("{USAGE}");
            Ok(())
        }
        Some(req) => {
            let s = execute(&req)?;
            let line = serde_json::to_string(&s)
                .map_err(|e| UsageError(format!("cannot format the summary: {e}")))?;
            println!("{line}");
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn parses_the_contract_forms() {
        let r = parse(&args("--sphere 2 --level 3 --out a.obj"))
            .unwrap()
            .unwrap();
        assert_eq!(r.shape, Shape::Sphere(2.0));
        assert_eq!(r.detail, Detail::Level(3));
        let r = parse(&args("--ellipsoid 3 2 1 --max-deviation 0.01 --out a.obj"))
            .unwrap()
            .unwrap();
        assert_eq!(r.shape, Shape::Ellipsoid([3.0, 2.0, 1.0]));
        // The smallest level: the axis-ratio guarantee alone would give 5.
        assert_eq!(choose_level(&r).unwrap(), 4);
        let dev = |k| max_deviation(&build(r.shape, k).unwrap(), r.shape);
        assert!(dev(4) <= 0.01 && dev(3) > 0.01);
        let r = parse(&args("--sphere 1 --max-angle-deg 10 --out a.obj"))
            .unwrap()
            .unwrap();
        assert_eq!(choose_level(&r).unwrap(), 4); // 171.25° ≥ 170° > 162.66°
    }

    #[test]
    fn rejects_bad_arguments() {
        for bad in [
            "--sphere 1 --level 3",
            "--sphere 1 --ellipsoid 1 2 3 --level 1 --out a.obj",
            "--sphere -1 --level 1 --out a.obj",
            "--sphere x --level 1 --out a.obj",
            "--sphere 1 --level 1 --max-deviation 1 --out a.obj",
            "--sphere 1 --level -1 --out a.obj",
            "--ellipsoid 1 2 --level 1 --out a.obj",
            "--sphere 1 --max-angle-deg nan --out a.obj",
            "--sphere 1 --frobnicate --out a.obj",
        ] {
            assert!(parse(&args(bad)).is_err(), "{bad}");
        }
        let deep = parse(&args("--sphere 1 --level 11 --out a.obj"))
            .unwrap()
            .unwrap();
        assert!(choose_level(&deep).is_err());
        let tiny = parse(&args("--sphere 1 --max-deviation 1e-300 --out a.obj"))
            .unwrap()
            .unwrap();
        assert!(choose_level(&tiny).is_err());
    }

    #[test]
    fn ellipsoid_distance_is_exact_on_the_axes_and_for_spheres() {
        let a = [3.0, 2.0, 1.0];
        assert!((ellipsoid_distance(a, [5.0, 0.0, 0.0]) - 2.0).abs() < 1e-12);
        assert!((ellipsoid_distance(a, [0.0, 0.0, 1.5]) - 0.5).abs() < 1e-12);
        let y = [1.0, 2.0, 2.0]; // |y| = 3
        assert!((ellipsoid_distance([2.0; 3], y) - 1.0).abs() < 1e-12);
        assert!(ellipsoid_distance(a, [0.1, 0.1, 0.1]) < 0.0);
    }
}
