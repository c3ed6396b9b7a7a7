//! The expectations of the QEMU smoke test (`kernel/qemu-smoke/src/cases.rs`), generated here from the oracle.
//!
//! The cases are fixed and well conditioned, so that the `f64` and the `f32` kernel must both agree with the
//! oracle in count and side, and in `t` to a stated multiple of `ε·S`:
//!
//! * every input is exactly representable in `f32` (coordinates are small dyadic numbers times a power-of-two
//!   scale, angles are dyadic, and θ = π/2 is `FRAC_PI_2`, which both types treat as the exact plane), so the `f32`
//!   kernel on the target solves the very same problem as the oracle;
//! * every crossing has `sin(angle between ray and surface) >= 0.25`, lies at least `S/64` along the ray from its
//!   origin, and at least `S/64` from the surface's edge (cone apex, half-plane axis);
//! * the tolerance of each case is `TOL_MULT · ε · S / |d|` in units of `t`, with `ε` the machine epsilon of the
//!   precision and `S = max(|p|, |p + t d|)` over the crossings: by the oracle test's measurements the kernel stays
//!   below `16 ε S` along the ray at such angles, so 64 leaves a margin of 4 without hiding a real error.
//!
//! Run with `CURVICAST_UPDATE_SMOKE=1` to rewrite the file; without it the test fails if the committed file differs
//! from what the oracle gives now. The same cases and tolerances are also checked against the host's `f64` and
//! `f32` kernel here, so a tolerance mistake shows up on the host too.

use curvicast_host::oracle::surfaces::{AngleType, OracleRay, OracleSurface};
use curvicast_host::report::surfaces::{Kind, Precision, SurfaceCase, kernel_crossings_in};
use std::f64::consts::FRAC_PI_2;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The tolerance multiple of `ε·S`.
const TOL_MULT: f64 = 64.0;
/// The smallest sine of the crossing angle accepted in a smoke case.
const MIN_SIN: f64 = 0.25;

struct Expected {
    case: SurfaceCase,
    n: usize,
    t: [f64; 2],
    into_positive: [bool; 2],
    tol: [f64; 2],
}

/// The hand-made geometry, at a power-of-two `s` and with the direction scaled by a power of two `dl`.
fn geometry(s: f64, dl: f64) -> Vec<SurfaceCase> {
    let c = |kind, p: [f64; 2], o: [f64; 3], d: [f64; 3]| SurfaceCase {
        kind,
        p,
        origin: o.map(|x| x * s),
        dir: d.map(|x| x * dl),
    };
    let ps = |a: f64, b: f64| [a * s, b * s];
    vec![
        // sphere, from outside through it
        c(
            Kind::Spheroid,
            ps(2.0, 2.0),
            [-4.0, 0.5, 0.25],
            [1.0, 0.125, 0.0],
        ),
        // sphere, from inside: only the exit
        c(
            Kind::Spheroid,
            ps(2.0, 2.0),
            [0.5, 0.25, 0.0],
            [0.25, 1.0, 0.5],
        ),
        // oblate spheroid from above
        c(
            Kind::Spheroid,
            ps(2.0, 1.0),
            [0.5, 0.25, 4.0],
            [0.0, 0.125, -1.0],
        ),
        // sphere, clear miss: 0 crossings
        c(
            Kind::Spheroid,
            ps(1.0, 1.0),
            [-4.0, 3.0, 0.0],
            [1.0, 0.25, 0.0],
        ),
        // upper-nappe cone (θ = 0.75) with apex above the origin, horizontal ray
        c(
            Kind::Cone,
            [0.5 * s, 0.75],
            [-3.0, 0.5, 2.0],
            [1.0, 0.0, 0.0],
        ),
        // lower-nappe cone (θ = 2.25), apex below the origin
        c(
            Kind::Cone,
            [-0.25 * s, 2.25],
            [2.0, 1.0, -3.0],
            [-1.0, -0.25, 0.5],
        ),
        // θ = π/2: the exact plane z = k, crossed downward
        c(
            Kind::Cone,
            [0.5 * s, FRAC_PI_2],
            [0.25, 0.75, 2.0],
            [0.5, 0.0, -1.0],
        ),
        // half-plane at φ = 0.75 crossed counter-clockwise
        c(
            Kind::HalfPlane,
            [0.75, 0.0],
            [2.0, -1.0, 0.5],
            [-0.25, 1.0, 0.125],
        ),
        // half-plane at φ = 4.0 (third quadrant) crossed clockwise
        c(
            Kind::HalfPlane,
            [4.0, 0.0],
            [-0.5, -3.0, 1.0],
            [-0.5, 1.0, -0.25],
        ),
        // plane z = 0.75 s, upward, from below
        c(
            Kind::PlaneZ,
            [0.75 * s, 0.0],
            [0.0, 0.0, -1.0],
            [0.25, 0.5, 1.0],
        ),
    ]
}

fn expected(case: SurfaceCase) -> Result<Expected, String> {
    let surface = match case.kind {
        Kind::Spheroid => OracleSurface::Spheroid {
            a: case.p[0],
            b: case.p[1],
        },
        Kind::Cone => OracleSurface::Cone {
            apex_z: case.p[0],
            theta: case.p[1],
            angles: AngleType::F64,
        },
        Kind::HalfPlane => OracleSurface::HalfPlane { phi: case.p[0] },
        Kind::PlaneZ => OracleSurface::PlaneZ { c: case.p[0] },
    }
    .prepare();
    let ray = OracleRay::new(case.origin, case.dir);
    let cs = surface.crossings(&ray);
    if cs.len() > 2 {
        return Err(format!("{} crossings", cs.len()));
    }
    let dl = ray.dir_len();
    let mut s = ray.scale_at(0.0);
    let mut t = [0.0; 2];
    let mut into = [false; 2];
    for (i, c) in cs.iter().enumerate() {
        let si = ray.scale_at(c.t_f64);
        s = s.max(si);
        if c.sin_angle < MIN_SIN {
            return Err(format!("crossing {i} at sin {}", c.sin_angle));
        }
        if c.t_f64 * dl < si / 64.0 {
            return Err(format!("crossing {i} too near the origin"));
        }
        if surface.edge_distance_at(&ray, c.t_f64) < si / 64.0 {
            return Err(format!("crossing {i} too near the edge"));
        }
        t[i] = c.t_f64;
        into[i] = c.into_positive;
    }
    // f32-exactness of every input (θ = π/2 excepted: both types treat their nearest value as the plane).
    let exact32 = |x: f64| x as f32 as f64 == x;
    let angle_ok = case.kind == Kind::Cone && case.p[1] == FRAC_PI_2;
    if !(case.origin.iter().chain(&case.dir).all(|&x| exact32(x))
        && exact32(case.p[0])
        && (exact32(case.p[1]) || angle_ok))
    {
        return Err("an input is not exact in f32".into());
    }
    let tol = [
        TOL_MULT * f64::EPSILON * s / dl,
        TOL_MULT * f32::EPSILON as f64 * s / dl,
    ];
    Ok(Expected {
        case,
        n: cs.len(),
        t,
        into_positive: into,
        tol,
    })
}

fn all_cases() -> Vec<Expected> {
    let mut out = Vec::new();
    let scales = [
        2f64.powi(-20),
        2f64.powi(-10),
        1.0,
        2f64.powi(10),
        2f64.powi(20),
    ];
    for (i, s) in scales.into_iter().enumerate() {
        // direction lengths: unit-ish, tiny, huge
        let dl = [1.0, 2f64.powi(-40), 1.0, 2f64.powi(40), 1.0][i];
        for case in geometry(s, dl) {
            match expected(case) {
                Ok(e) => out.push(e),
                Err(why) => panic!("smoke case {case:?} is not well conditioned: {why}"),
            }
        }
    }
    out
}

fn lit(x: f64) -> String {
    let s = format!("{x:?}");
    assert!(x.is_finite(), "non-finite value in a smoke case");
    s
}

fn lits(v: &[f64]) -> String {
    v.iter().map(|&x| lit(x)).collect::<Vec<_>>().join(", ")
}

/// One `name: [values],` field as rustfmt lays it out: on one line when the array's items are at most 60 columns
/// wide (rustfmt's default `array_width`), else one value per line with a trailing comma.
fn field(name: &str, v: &[f64]) -> String {
    let items = lits(v);
    if items.len() <= 60 {
        return format!("        {name}: [{items}],\n");
    }
    let mut s = format!("        {name}: [\n");
    for &x in v {
        let _ = writeln!(s, "            {},", lit(x));
    }
    s.push_str("        ],\n");
    s
}

fn render(cases: &[Expected]) -> String {
    let mut s = String::new();
    s.push_str(
        "//! Generated by `cargo test -p curvicast-host --test march smoke_cases` (set CURVICAST_UPDATE_SMOKE=1 to rewrite).
//! Expected values computed by the host's arbitrary-precision oracle. Do not edit by hand.

/// Which surface a case intersects.
#[derive(Clone, Copy)]
pub enum Kind {
    /// `Spheroid::new(p[0], p[1])` (a sphere when equal).
    Spheroid,
    /// `AxialCone::from_zenith_rad(p[0] /* apex_z */, p[1] /* theta */)`.
    Cone,
    /// `HalfPlane::from_azimuth_rad(p[0])`.
    HalfPlane,
    /// `PlaneZ::new(p[0])`.
    PlaneZ,
}

/// One fixed ray–surface case with the oracle's answer.
pub struct Case {
    /// The surface family.
    pub kind: Kind,
    /// Its parameters (unused entries are 0).
    pub p: [f64; 2],
    /// Ray origin.
    pub origin: [f64; 3],
    /// Ray direction.
    pub dir: [f64; 3],
    /// Number of crossings for t >= 0 (0, 1 or 2).
    pub n: usize,
    /// The oracle's t of each crossing (unused entries are 0), rounded to f64.
    pub t: [f64; 2],
    /// Whether each crossing enters the positive side.
    pub into_positive: [bool; 2],
    /// Allowed |t_kernel − t| for the f64 kernel and for the f32 kernel (absolute, in t units).
    pub tol: [f64; 2],
}

/// The cases.
pub const CASES: &[Case] = &[
",
    );
    for e in cases {
        let kind = match e.case.kind {
            Kind::Spheroid => "Spheroid",
            Kind::Cone => "Cone",
            Kind::HalfPlane => "HalfPlane",
            Kind::PlaneZ => "PlaneZ",
        };
        let _ = write!(s, "    Case {{\n        kind: Kind::{kind},\n");
        s.push_str(&field("p", &e.case.p));
        s.push_str(&field("origin", &e.case.origin));
        s.push_str(&field("dir", &e.case.dir));
        let _ = writeln!(s, "        n: {},", e.n);
        s.push_str(&field("t", &e.t));
        let _ = writeln!(
            s,
            "        into_positive: [{}, {}],",
            e.into_positive[0], e.into_positive[1]
        );
        s.push_str(&field("tol", &e.tol));
        s.push_str("    },\n");
    }
    s.push_str("];\n");
    s
}

fn path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../kernel/qemu-smoke/src/cases.rs")
}

#[test]
fn smoke_cases_cover_what_they_claim() {
    let cases = all_cases();
    assert!(cases.len() >= 40, "{} cases", cases.len());
    for kind in Kind::ALL {
        assert!(
            cases.iter().any(|e| e.case.kind == kind && e.n > 0),
            "{kind:?}"
        );
    }
    assert!(cases.iter().any(|e| e.n == 0), "a case with no crossing");
    assert!(cases.iter().any(|e| e.n == 1), "a case with one crossing");
    assert!(cases.iter().any(|e| e.n == 2), "a case with two crossings");
    let sides = |b: bool| {
        cases
            .iter()
            .any(|e| e.into_positive.iter().take(e.n).any(|&x| x == b))
    };
    assert!(sides(true) && sides(false), "crossings into both sides");
}

#[test]
fn host_kernel_meets_the_smoke_tolerances() {
    let mut failures = Vec::new();
    for e in all_cases() {
        for (mode, tol) in [(Precision::F64, e.tol[0]), (Precision::F32, e.tol[1])] {
            match kernel_crossings_in(mode, &e.case) {
                Err(err) => failures.push(format!("{:?} {mode:?}: {err}", e.case)),
                Ok(k) => {
                    let ok = k.len() == e.n
                        && k.iter().enumerate().all(|(i, c)| {
                            c.into_positive == e.into_positive[i] && (c.t - e.t[i]).abs() <= tol
                        });
                    if !ok {
                        failures.push(format!(
                            "{:?} {mode:?}: kernel {k:?}, expected n {} t {:?} into {:?} tol {tol:e}",
                            e.case, e.n, e.t, e.into_positive
                        ));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn committed_smoke_cases_match_the_oracle() {
    let text = render(&all_cases());
    let p = path();
    if std::env::var_os("CURVICAST_UPDATE_SMOKE").is_some_and(|v| v == "1") {
        if let Some(dir) = p.parent() {
            std::fs::create_dir_all(dir).unwrap();
        }
        std::fs::write(&p, &text).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&p).unwrap_or_default();
    assert!(
        committed == text,
        "{} differs from the oracle's expectations: rerun with CURVICAST_UPDATE_SMOKE=1 and commit it",
        p.display()
    );
}
