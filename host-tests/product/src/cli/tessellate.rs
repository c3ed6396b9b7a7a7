//! `curvicast tessellate (--sphere R | --ellipsoid A B C) (--level K | --max-angle-deg X | --max-deviation E)
//! --out FILE.obj`: the edge-beveled polyhedron (the edge-beveling thesis §4.3–4.4) as Wavefront OBJ, and a one-line JSON summary
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
use crate::cli::print_stdout;
use curvicast::V3;
use curvicast::tessellate::TessellateError;
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
fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn max_abs(a: [f64; 3]) -> f64 {
    a[0].abs().max(a[1].abs()).max(a[2].abs())
}
/// `|a|` at any scale: the squares are taken of `a / max|a_i|`, so they neither overflow (|a| near 1e200) nor
/// underflow (near 1e-200).
fn norm(a: [f64; 3]) -> f64 {
    let m = max_abs(a);
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    let u = scale(a, 1.0 / m);
    m * dot(u, u).sqrt()
}

/// `2^e` for the largest `|x_i|` in `[2^e, 2^(e+1))`, with `e` kept in `[-1021, 1021]` so that both `2^e` and
/// `2^-e` are normal: dividing by it is exact, and brings the largest `|x_i|` near 1.
fn power_of_two_scale(x: &[f64]) -> f64 {
    let m = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if m == 0.0 || !m.is_finite() {
        return 1.0;
    }
    let e = m.log2().floor().clamp(-1021.0, 1021.0) as i32;
    2.0_f64.powi(e)
}

/// Newell's normal of a polygon (unit; outward for a counter-clockwise polygon seen from outside). Computed on
/// the polygon moved to its first vertex and scaled to unit size, so that any scale of the mesh gives the same
/// normals (the products of coordinates overflow beyond 1e154 and underflow below 1e-154 otherwise).
pub fn newell_normal(mesh: &Mesh, face: &[u32]) -> [f64; 3] {
    // Vertices divided by a power of two near the largest coordinate (exact), so that differences of vertices
    // near ±1e308 do not overflow; then relative to the first vertex and scaled to the face's extent.
    let vertex = |k: usize| mesh.vertices[face[k % face.len()] as usize];
    let coords: Vec<f64> = (0..face.len()).flat_map(vertex).collect();
    let inv_s = 1.0 / power_of_two_scale(&coords);
    let o = scale(vertex(0), inv_s);
    let rel = |k: usize| sub(scale(vertex(k), inv_s), o);
    let extent = (1..face.len()).fold(0.0_f64, |m, k| m.max(max_abs(rel(k))));
    let inv = if extent > 0.0 { 1.0 / extent } else { 1.0 };
    let mut n = [0.0; 3];
    for k in 0..face.len() {
        let c = cross(scale(rel(k), inv), scale(rel(k + 1), inv));
        n = [n[0] + c[0], n[1] + c[1], n[2] + c[2]];
    }
    scale(n, 1.0 / norm(n))
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
/// `y_i t / (t + a_i²)` per axis (no cancellation). Returns a negative number for points inside. Solved with the
/// axes and the point divided by a power of two near the largest semi-axis (exact), so at any scale.
pub fn ellipsoid_distance(a: [f64; 3], y: [f64; 3]) -> f64 {
    let s = power_of_two_scale(&a);
    s * unit_ellipsoid_distance(scale(a, 1.0 / s), scale(y, 1.0 / s))
}

/// [`ellipsoid_distance`] for semi-axes of order 1.
fn unit_ellipsoid_distance(a: [f64; 3], y: [f64; 3]) -> f64 {
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
    norm([0, 1, 2].map(|i| y[i] * t / (t + a[i] * a[i])))
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
                if r < f64::MIN_POSITIVE {
                    return Err(UsageError(format!(
                        "--sphere: radius {r} must be positive and at least {:e} (the smallest normal f64)",
                        f64::MIN_POSITIVE
                    )));
                }
                set_shape(&mut shape, Shape::Sphere(r))?;
            }
            "--ellipsoid" => {
                let a = [
                    num(flag, it.next())?,
                    num(flag, it.next())?,
                    num(flag, it.next())?,
                ];
                if a.iter().any(|&x| x < f64::MIN_POSITIVE) {
                    return Err(UsageError(format!(
                        "--ellipsoid: semi-axes {a:?} must be positive and at least {:e} (the smallest normal f64)",
                        f64::MIN_POSITIVE
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
    let hint = |e: TessellateError| match e {
        TessellateError::AxisRatioTooLarge => format!("{e}; --level K builds any ratio"),
        _ => e.to_string(),
    };
    let level = match req.detail {
        Detail::Level(k) => k,
        Detail::MaxAngleDeg(x) => {
            if x >= 90.0 {
                0 // the cube's faces are 90° apart
            } else {
                lod::min_level(req.shape, Bound::MinDihedral((180.0 - x).to_radians()))
                    .map_err(|e| UsageError(format!("--max-angle-deg {x}: {}", hint(e))))?
            }
        }
        Detail::MaxDeviation(e) => lod::min_level(req.shape, Bound::MaxDeviation(e))
            .map_err(|err| UsageError(format!("--max-deviation {e}: {}", hint(err))))?,
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

/// The whole subcommand: parse, run, print the JSON line on stdout (or the usage on `--help`). Errors: a
/// [`UsageError`] for the arguments and the OBJ file, a [`crate::cli::OutputError`] for standard output.
pub fn run(args: &[String]) -> anyhow::Result<()> {
    let line = match parse(args)? {
        None => USAGE.to_string(),
        Some(req) => {
            let s = execute(&req)?;
            serde_json::to_string(&s)
                .map_err(|e| UsageError(format!("cannot format the summary: {e}")))?
        }
    };
    print_stdout(&format!("{line}\n"))?;
    Ok(())
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

    /// (min dihedral in degrees, max deviation) as the command measures them.
    fn measured(shape: Shape<f64>, level: u32) -> (f64, f64) {
        let mesh = build(shape, level).unwrap();
        (
            min_dihedral(&mesh).to_degrees(),
            max_deviation(&mesh, shape),
        )
    }

    /// The measurements at radius `r` are the unit sphere's, the deviation scaled by `r`.
    fn like_the_unit_sphere(r: f64, level: u32) {
        let (dih1, dev1) = measured(Shape::Sphere(1.0), level);
        let (dih, dev) = measured(Shape::Sphere(r), level);
        assert!((dih - dih1).abs() < 1e-9, "radius {r}: {dih}° vs {dih1}°");
        assert!(dev > 0.0 && dev.is_finite(), "radius {r}: deviation {dev}");
        assert!(
            (dev / r - dev1).abs() < 1e-12 * dev1,
            "radius {r}: {dev} vs {dev1} r"
        );
    }

    #[test]
    fn sphere_of_radius_1e200_and_1e308_measures_like_the_unit_sphere() {
        for level in [0, 1, 3] {
            like_the_unit_sphere(1e200, level);
            like_the_unit_sphere(1e308, level);
        }
    }

    #[test]
    fn sphere_of_radius_1e_minus_200_has_a_positive_deviation() {
        for level in [0, 1, 3] {
            like_the_unit_sphere(1e-200, level);
        }
        like_the_unit_sphere(f64::MIN_POSITIVE, 2);
    }

    #[test]
    fn level_1_dihedral_is_120_degrees_at_radius_1e77_and_1e_minus_100() {
        for r in [1.0, 1e77, 1e-100, 1e-80, 1e60] {
            let (dih, _) = measured(Shape::Sphere(r), 1);
            assert!((dih - 120.0).abs() < 1e-9, "radius {r}: {dih}°");
            like_the_unit_sphere(r, 2);
        }
    }

    #[test]
    fn sphere_radius_below_the_normal_range_is_a_usage_error() {
        let e = parse(&args("--sphere 1e-310 --level 1 --out a.obj")).unwrap_err();
        assert!(e.0.contains("smallest normal"), "{e}");
    }

    #[test]
    fn ellipsoid_1e10_1_1e_minus_10_builds_and_names_the_axis_ratio_limit() {
        let r = parse(&args(
            "--ellipsoid 1e10 1 1e-10 --max-deviation 1 --out a.obj",
        ))
        .unwrap()
        .unwrap();
        let e = choose_level(&r).unwrap_err();
        assert!(e.0.contains("ratio") && e.0.contains("1e6"), "{e}");
        assert!(!e.0.contains("positive and finite"), "{e}");
        // A given level builds, and measures as the same shape scaled by 1e-10 does.
        let shape = Shape::Ellipsoid([1e10, 1.0, 1e-10]);
        let small = Shape::Ellipsoid([1.0, 1e-10, 1e-20]);
        for level in [1, 3] {
            let ((dih, dev), (dih_s, dev_s)) = (measured(shape, level), measured(small, level));
            assert!(dev > 0.0 && dev.is_finite() && dih > 0.0 && dih < 180.0);
            assert!((dih - dih_s).abs() < 1e-6, "{dih}° vs {dih_s}°");
            // The deviation is 1e-11 of the largest semi-axis: the vertices' rounding (1e-16 of it) moves it by
            // about 1e-5 of itself, so the two scales agree to that, not to the last digit.
            assert!(
                (dev * 1e-10 - dev_s).abs() < 1e-5 * dev_s,
                "{dev} vs {dev_s}"
            );
        }
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
