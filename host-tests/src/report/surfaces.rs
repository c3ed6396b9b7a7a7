//! Report section 1: the ray–surface layer — speed and error of every surface kind in every precision mode.
//!
//! This module also holds the machinery that the oracle tests share with the report (the random case generator,
//! the kernel adapters, and the comparison against [`crate::oracle::surfaces`]), so that the report measures
//! exactly what the tests assert.
//!
//! # Error measurement
//!
//! For a ray `p + t d` and a crossing that the oracle puts at `t_o`, with `ε` the machine epsilon of the mode's
//! type (`2^-52` for `f64`, `2^-23` for `f32` and `F32Fast`) and the scale `S = max(|p|, |p + t_o d|)`:
//!
//! * **forward error** `= |t_k − t_o| · |d| / (ε S)`: the kernel's error along the ray, in units of `ε S`;
//! * **backward error** `= dist(p + t_k d, surface) / (ε S_k)` with `S_k` the scale at the kernel's `t_k`: how far
//!   the kernel's point is from the true surface (computed by the oracle in high precision). Forward error times
//!   the sine of the crossing angle is the same quantity to first order.
//!
//! The inputs of an `f32` mode are the `f64` case rounded to `f32`, and the oracle answers for those rounded inputs:
//! the error measured is the kernel's, not the rounding of the data. A crossing whose `t` lies beyond the type's
//! range (possible in `f32`: a distance of 1e8 along a direction of length 1e-30) is correctly reported as `±∞`
//! and is matched without an error measure.
//!
//! # The near-tangent band
//!
//! A crossing is *in the band* when the sine of the angle between ray and surface at the crossing,
//! `σ = |n·d| / (|n| |d|)`, is below [`SIN_BAND`]. The band is where the problem itself is ill-conditioned: moving
//! the inputs by their own rounding (relative `ε`) moves the surface by about `ε S` along its normal, which moves
//! the crossing along the ray by `ε S / σ`. No algorithm working in the input precision can have a forward error
//! below that, so a forward bound of `16 ε S` can only be asked where `σ` is not small; the band is the set where
//! `1/σ` (the condition number of the crossing) exceeds `1/SIN_BAND`. Inside the band the backward error is still
//! measured and bounded, and the counts may legitimately differ (a near-miss of a tangent may come out as a touch).
//!
//! Besides the band, a crossing is *ambiguous* (may be present in one answer and not the other without error) when
//! a perturbation of the size of the mode's forward bound, `B ε S / σ` along the ray, can move it across a
//! decision: across the start of the interval (`t = 0`; the cases run over `[0, ∞)`), or across the edge of the surface's own
//! decision (for a cone the plane `z = k` through its apex, which separates its nappe from the other; for a
//! half-plane its z axis). Count and side must agree for every other crossing.
//!
//! # Timing
//!
//! The median over repetitions of the time per ray–surface intersection (`crossings` on a prepared ray), on a
//! fixed random batch per kind, warm, each result passed through `black_box`.

use super::{Options, Section};
use crate::oracle::surfaces::{
    AngleType, OracleCrossing, OracleRay, OracleSurface, PreparedSurface,
};
use crate::tolerances::forward_bound;
use curvicast::F32Fast;
use curvicast::Ray;
use curvicast::real::Real;
use curvicast::surface::{AxialCone, HalfPlane, PlaneZ, Side, Spheroid, Surface};
pub use curvicast_cli::precision::Precision;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::hint::black_box;
use std::time::Instant;

/// The near-tangent band: crossings with `sin(angle between ray and surface)` below this are excluded from the
/// forward-error bound and from the count/side agreement (see the module docs for why). Measured justification
/// (100 000 rays per kind, three seeds): the f64 kernel's backward error stays below 4 ε S everywhere, so outside
/// the band its forward error cannot exceed 4 / SIN_BAND = 16 ε S (measured: at most 4.3 ε S).
pub const SIN_BAND: f64 = 0.25;

/// The surface families of the kernel's `surface` layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// `Spheroid::new(a, b)`, a sphere when `a = b`.
    Spheroid,
    /// `AxialCone::from_zenith_rad(apex_z, theta)`.
    Cone,
    /// `HalfPlane::from_azimuth_rad(phi)`.
    HalfPlane,
    /// `PlaneZ::new(c)`.
    PlaneZ,
}

impl Kind {
    /// Every kind, in report order.
    pub const ALL: [Kind; 4] = [Kind::Spheroid, Kind::Cone, Kind::HalfPlane, Kind::PlaneZ];
    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Spheroid => "spheroid",
            Kind::Cone => "cone",
            Kind::HalfPlane => "half-plane",
            Kind::PlaneZ => "plane z",
        }
    }
}

/// One ray–surface case over `t ∈ [0, ∞)`, in `f64` data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceCase {
    /// The surface family.
    pub kind: Kind,
    /// Its parameters: `(a, b)`, `(apex_z, theta)`, `(phi, 0)`, `(c, 0)`.
    pub p: [f64; 2],
    /// Ray origin.
    pub origin: [f64; 3],
    /// Ray direction.
    pub dir: [f64; 3],
}

fn r32(x: f64) -> f64 {
    x as f32 as f64
}

impl SurfaceCase {
    /// The case with every value rounded to `f32` (the inputs of the `f32` modes).
    pub fn to_f32(&self) -> SurfaceCase {
        SurfaceCase {
            kind: self.kind,
            p: self.p.map(r32),
            origin: self.origin.map(r32),
            dir: self.dir.map(r32),
        }
    }
    /// The case's data in the precision of `mode`.
    pub fn for_mode(&self, mode: Precision) -> SurfaceCase {
        match mode {
            Precision::F64 => *self,
            Precision::F32 | Precision::F32Fast => self.to_f32(),
        }
    }
    /// The surface for the oracle.
    pub fn oracle_surface(&self, angles: AngleType) -> OracleSurface {
        match self.kind {
            Kind::Spheroid => OracleSurface::Spheroid {
                a: self.p[0],
                b: self.p[1],
            },
            Kind::Cone => OracleSurface::Cone {
                apex_z: self.p[0],
                theta: self.p[1],
                angles,
            },
            Kind::HalfPlane => OracleSurface::HalfPlane { phi: self.p[0] },
            Kind::PlaneZ => OracleSurface::PlaneZ { c: self.p[0] },
        }
    }
    /// The ray for the oracle.
    pub fn oracle_ray(&self) -> OracleRay {
        OracleRay::new(self.origin, self.dir)
    }
}

/// A crossing as the kernel reported it, widened to `f64` (exactly).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KernelCrossing {
    /// The ray parameter.
    pub t: f64,
    /// Whether the ray enters the positive side.
    pub into_positive: bool,
}

fn v3<T: Real>(a: [f64; 3]) -> [T; 3] {
    a.map(T::from_f64)
}

/// The kernel's ray for a case, in scalar `T`.
pub fn kernel_ray<T: Real>(case: &SurfaceCase) -> Result<Ray<T>, String> {
    Ray::new(v3::<T>(case.origin), v3::<T>(case.dir)).map_err(|e| e.to_string())
}

/// Runs the kernel in scalar `T` on a case (whose data should already be in `T`'s precision).
pub fn kernel_crossings<T: Real>(case: &SurfaceCase) -> Result<Vec<KernelCrossing>, String> {
    let ray = kernel_ray::<T>(case)?;
    let (a, b) = (T::from_f64(case.p[0]), T::from_f64(case.p[1]));
    let e = |e: curvicast::surface::SurfaceError| e.to_string();
    let c = match case.kind {
        Kind::Spheroid => Spheroid::new(a, b).map_err(e)?.crossings(&ray),
        Kind::Cone => AxialCone::from_zenith_rad(a, b).map_err(e)?.crossings(&ray),
        Kind::HalfPlane => HalfPlane::from_azimuth_rad(a).map_err(e)?.crossings(&ray),
        Kind::PlaneZ => PlaneZ::new(a).map_err(e)?.crossings(&ray),
    };
    Ok(c.iter()
        .map(|x| KernelCrossing {
            t: x.t.to_f64(),
            into_positive: x.into == Side::Positive,
        })
        .collect())
}

/// Runs the kernel in the given mode on a case (rounding its data to the mode's precision first).
pub fn kernel_crossings_in(
    mode: Precision,
    case: &SurfaceCase,
) -> Result<Vec<KernelCrossing>, String> {
    let c = case.for_mode(mode);
    match mode {
        Precision::F64 => kernel_crossings::<f64>(&c),
        Precision::F32 => kernel_crossings::<f32>(&c),
        Precision::F32Fast => kernel_crossings::<F32Fast>(&c),
    }
}

/// Random cases of one kind, deterministic in `seed`: scales log-uniform in `1e-8 ..= 1e8` (30 % at scale 1),
/// random surface parameters (spheres and spheroids; cones with apex at 0 or anywhere, narrow, wide, near π/2,
/// exactly π/2 and near π; half-planes at any azimuth including the exact multiples of π/2; planes at any height),
/// origins inside and outside, directions aimed at the surface's region or random, of length 1, of the scale, or
/// log-uniform in `1e-30 ..= 1e30`. Consecutive groups of [`RAYS_PER_SURFACE`] rays share one surface (and its
/// scale), so that the oracle computes its high-precision cosines once per group.
pub fn random_cases(kind: Kind, n: usize, seed: u64) -> Vec<SurfaceCase> {
    let salt: u64 = match kind {
        Kind::Spheroid => 0x5be1,
        Kind::Cone => 0xc0e,
        Kind::HalfPlane => 0x4a1f,
        Kind::PlaneZ => 0x91a2,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (salt << 32));
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let (p, center, scale) = random_surface(kind, &mut rng);
        for _ in 0..RAYS_PER_SURFACE.min(n - out.len()) {
            let (origin, dir) = random_ray(center, scale, &mut rng);
            out.push(SurfaceCase {
                kind,
                p,
                origin,
                dir,
            });
        }
    }
    out
}

/// How many consecutive cases of [`random_cases`] share a surface.
pub const RAYS_PER_SURFACE: usize = 16;

fn unit(rng: &mut ChaCha8Rng) -> [f64; 3] {
    loop {
        let v = [
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0f64),
        ];
        let n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        if n2 > 1e-6 && n2 <= 1.0 {
            let n = n2.sqrt();
            return v.map(|x| x / n);
        }
    }
}

/// A random surface of a kind: its parameters, a centre of interest (the apex, the plane's foot), its scale.
fn random_surface(kind: Kind, rng: &mut ChaCha8Rng) -> ([f64; 2], [f64; 3], f64) {
    use std::f64::consts::{FRAC_PI_2, PI};
    let scale = if rng.random_bool(0.3) {
        1.0
    } else {
        10f64.powf(rng.random_range(-8.0..=8.0))
    };
    let (p, center) = match kind {
        Kind::Spheroid => {
            let a = scale * rng.random_range(0.5..2.0);
            let b = if rng.random_bool(0.35) {
                a
            } else {
                a * rng.random_range(0.2..1.0)
            };
            ([a, b], [0.0, 0.0, 0.0])
        }
        Kind::Cone => {
            let apex = if rng.random_bool(0.4) {
                0.0
            } else {
                scale * rng.random_range(-1.0..1.0)
            };
            let u: f64 = rng.random();
            let theta = if u < 0.1 {
                FRAC_PI_2
            } else if u < 0.15 {
                rng.random_range(1e-6..1e-2)
            } else if u < 0.2 {
                PI - rng.random_range(1e-6..1e-2)
            } else if u < 0.25 {
                FRAC_PI_2 + rng.random_range(-1e-3..1e-3)
            } else {
                rng.random_range(0.01..PI - 0.01)
            };
            ([apex, theta], [0.0, 0.0, apex])
        }
        Kind::HalfPlane => {
            let phi = if rng.random_bool(0.1) {
                [0.0, FRAC_PI_2, PI, -FRAC_PI_2, 1.5 * PI][rng.random_range(0..5)]
            } else {
                rng.random_range(-2.0 * PI..4.0 * PI)
            };
            ([phi, 0.0], [0.0, 0.0, 0.0])
        }
        Kind::PlaneZ => {
            let c = if rng.random_bool(0.1) {
                0.0
            } else {
                scale * rng.random_range(-1.0..1.0)
            };
            ([c, 0.0], [0.0, 0.0, c])
        }
    };
    (p, center, scale)
}

/// A random ray near `center` at `scale`: origin within `3 · scale`, direction aimed at a point within
/// `1.2 · scale` of the centre or random, of length 1, `scale`, or log-uniform in `1e-30 ..= 1e30`.
fn random_ray(center: [f64; 3], scale: f64, rng: &mut ChaCha8Rng) -> ([f64; 3], [f64; 3]) {
    let u = unit(rng);
    let r = scale * rng.random_range(0.0..3.0);
    let origin = [
        center[0] + r * u[0],
        center[1] + r * u[1],
        center[2] + r * u[2],
    ];
    let mut d = if rng.random_bool(0.5) {
        let v = unit(rng);
        let rt = scale * rng.random_range(0.0..1.2);
        [
            center[0] + rt * v[0] - origin[0],
            center[1] + rt * v[1] - origin[1],
            center[2] + rt * v[2] - origin[2],
        ]
    } else {
        unit(rng)
    };
    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if n.is_nan() || n <= 0.0 || !n.is_finite() {
        d = unit(rng);
    } else {
        d = d.map(|x| x / n);
    }
    let u: f64 = rng.random();
    let len = if u < 0.4 {
        1.0
    } else if u < 0.7 {
        scale
    } else {
        10f64.powf(rng.random_range(-30.0..=30.0))
    };
    (origin, d.map(|x| x * len))
}

/// The comparison of one case in one mode against the oracle.
#[derive(Debug, Clone, Default)]
pub struct CaseOutcome {
    /// Largest forward error (units of `ε S`) over matched crossings outside the band; 0 if none.
    pub forward: f64,
    /// Largest backward error (units of `ε S_k`) over all the kernel's crossings; 0 if none.
    pub backward: f64,
    /// Crossings the oracle reported.
    pub oracle_crossings: usize,
    /// Of those, in the near-tangent band.
    pub in_band: usize,
    /// A count/side disagreement outside the band and the ambiguity zones, described.
    pub mismatch: Option<String>,
}

/// The oracle's answer for a case in a mode (the case's data rounded to the mode's precision).
pub struct OracleAnswer {
    /// The prepared surface.
    pub surface: PreparedSurface,
    /// The ray.
    pub ray: OracleRay,
    /// Its crossings.
    pub crossings: Vec<OracleCrossing>,
}

/// Runs the oracle on a case (data taken as given: pass `case.for_mode(mode)`), with the special angles of `angles`.
pub fn oracle_answer(case: &SurfaceCase, angles: AngleType) -> OracleAnswer {
    oracle_answer_on(&case.oracle_surface(angles).prepare(), case)
}

/// [`oracle_answer`] on an already prepared surface (which must be the case's).
pub fn oracle_answer_on(surface: &PreparedSurface, case: &SurfaceCase) -> OracleAnswer {
    let surface = surface.clone();
    let ray = case.oracle_ray();
    let crossings = surface.crossings(&ray);
    OracleAnswer {
        surface,
        ray,
        crossings,
    }
}

/// Whether a crossing at `t` (with angle sine `sin`) may legitimately be present in one answer and absent in the
/// other: in the band, or within the mode's error of the interval end `t = 0` or of the surface's edge.
fn ambiguous(o: &OracleAnswer, kind: Kind, t: f64, sin: f64, mode: Precision, bound: f64) -> bool {
    if sin < SIN_BAND {
        return true;
    }
    let eps = mode.eps();
    let s = o.ray.scale_at(t);
    let reach = bound * eps * s / sin;
    let along = t.abs() * o.ray.dir_len();
    if along <= reach {
        return true;
    }
    match kind {
        Kind::Cone | Kind::HalfPlane => o.surface.edge_distance_at(&o.ray, t) <= reach,
        Kind::Spheroid | Kind::PlaneZ => false,
    }
}

/// Compares the kernel's crossings with the oracle's (see the module docs for the measures and the band).
pub fn compare(
    kind: Kind,
    mode: Precision,
    o: &OracleAnswer,
    kernel: &Result<Vec<KernelCrossing>, String>,
) -> CaseOutcome {
    let mut out = CaseOutcome {
        oracle_crossings: o.crossings.len(),
        in_band: o
            .crossings
            .iter()
            .filter(|c| c.sin_angle < SIN_BAND)
            .count(),
        ..CaseOutcome::default()
    };
    let k = match kernel {
        Ok(k) => k,
        Err(e) => {
            out.mismatch = Some(format!("kernel rejected the case: {e}"));
            return out;
        }
    };
    let eps = mode.eps();
    let bound = forward_bound(kind, mode);
    // A crossing beyond the range of the mode's type (|t| > its largest finite value) is correctly reported as
    // ±∞: its rounded value. Such a kernel crossing is matched like any other but has no finite error to measure.
    let max_t = mode.max_finite();
    let overflow_ok = |c: &KernelCrossing| {
        c.t.is_infinite()
            && o.crossings.iter().any(|x| {
                x.t_f64.abs() > max_t
                    && (x.t_f64 > 0.0) == (c.t > 0.0)
                    && x.into_positive == c.into_positive
            })
    };
    for c in k {
        if overflow_ok(c) {
            continue;
        }
        let s = o.ray.scale_at(c.t);
        let b = o.surface.distance_at(&o.ray, c.t) / (eps * s);
        // a NaN error must fail the bound, not vanish in `max`
        out.backward = out.backward.max(if b.is_nan() { f64::INFINITY } else { b });
    }
    let o_amb: Vec<bool> = o
        .crossings
        .iter()
        .map(|c| ambiguous(o, kind, c.t_f64, c.sin_angle, mode, bound))
        .collect();
    let k_amb: Vec<bool> = k
        .iter()
        .map(|c| {
            let sin = o.surface.sin_angle_at(&o.ray, c.t);
            ambiguous(o, kind, c.t, sin, mode, bound)
        })
        .collect();
    // All order-preserving partial matchings of (≤ 2) × (≤ 2) crossings.
    let no = o.crossings.len();
    let nk = k.len();
    let mut candidates: Vec<Vec<(usize, usize)>> = vec![vec![]];
    for i in 0..no {
        for j in 0..nk {
            candidates.push(vec![(i, j)]);
            for i2 in i + 1..no {
                for j2 in j + 1..nk {
                    candidates.push(vec![(i, j), (i2, j2)]);
                }
            }
        }
    }
    type Matching = Vec<(usize, usize)>;
    let mut best: Option<(usize, f64, Matching)> = None;
    for m in candidates {
        let sides_ok = m
            .iter()
            .all(|&(i, j)| o.crossings[i].into_positive == k[j].into_positive);
        let o_ok = (0..no).all(|i| m.iter().any(|&(a, _)| a == i) || o_amb[i]);
        let k_ok = (0..nk).all(|j| m.iter().any(|&(_, b)| b == j) || k_amb[j]);
        if !(sides_ok && o_ok && k_ok) {
            continue;
        }
        let cost: f64 = m
            .iter()
            .map(|&(i, j)| (o.crossings[i].t_f64 - k[j].t).abs())
            .sum();
        let better = match &best {
            None => true,
            Some((n, c, _)) => m.len() > *n || (m.len() == *n && cost < *c),
        };
        if better {
            best = Some((m.len(), cost, m));
        }
    }
    match best {
        None => {
            let os: Vec<String> = o
                .crossings
                .iter()
                .map(|c| {
                    format!(
                        "t={:e} +{} sin={:.3e}",
                        c.t_f64, c.into_positive, c.sin_angle
                    )
                })
                .collect();
            let ks: Vec<String> = k
                .iter()
                .map(|c| format!("t={:e} +{}", c.t, c.into_positive))
                .collect();
            out.mismatch = Some(format!(
                "oracle [{}] vs kernel [{}]",
                os.join(", "),
                ks.join(", ")
            ));
        }
        Some((_, _, m)) => {
            for (i, j) in m {
                let oc = &o.crossings[i];
                if oc.sin_angle < SIN_BAND {
                    continue;
                }
                if overflow_ok(&k[j]) {
                    continue;
                }
                let s = o.ray.scale_at(oc.t_f64);
                let fe = o.ray.forward_error(&oc.t, k[j].t) / (eps * s);
                out.forward = out
                    .forward
                    .max(if fe.is_nan() { f64::INFINITY } else { fe });
            }
        }
    }
    out
}

/// The report section: per kind × mode, median ns per intersection and the largest errors against the oracle.
pub fn section(opts: &Options) -> anyhow::Result<Section> {
    let (n_time, reps, n_err) = if opts.quick {
        (4096, 31, 4000)
    } else {
        (65536, 101, 100_000)
    };
    let mut md = String::new();
    md.push_str(&format!(
        "Each kind: a fixed random batch (seed 2026; scales 1e-8..1e8, direction lengths up to 1e±30, origins \
         inside and outside). Time: median over {reps} warm passes over {n_time} ray–surface pairs. Error: \
         {n_err} rays per kind against the {}-bit oracle; forward error `|t_k − t_o|·|d| / (ε S)` over crossings \
         outside the near-tangent band (sin of the crossing angle < {SIN_BAND}), backward error (distance of the \
         kernel's point from the true surface) `/ (ε S)` over all crossings, with `S = max(|p|, |p + t d|)` and \
         `ε` the machine epsilon of the mode (2^-52 or 2^-23). Count/side mismatches are counted outside the band \
         and the ambiguity zones (see `report::surfaces` docs).\n\n",
        crate::oracle::surfaces::PRECISION
    ));
    md.push_str("| surface | mode | ns / intersection | max forward error (ε·S) | max backward error (ε·S) | crossings (in band) | mismatches |\n");
    md.push_str("| --- | --- | ---: | ---: | ---: | ---: | ---: |\n");
    // per mode: (ns, relative forward error, kind) for the chart
    let mut chart: Vec<Vec<(f64, f64, String)>> = vec![Vec::new(); Precision::ALL.len()];
    for kind in Kind::ALL {
        let time_cases = random_cases(kind, n_time, 2026);
        let err_cases = random_cases(kind, n_err, 2027);
        let stats = evaluate(&err_cases, &Precision::ALL);
        for (m, (mode, st)) in Precision::ALL.iter().zip(stats).enumerate() {
            let ns = median_ns(kind, *mode, &time_cases, reps);
            let eps = if *mode == Precision::F64 {
                f64::EPSILON
            } else {
                f64::from(f32::EPSILON)
            };
            chart[m].push((ns, st.max_forward.0 * eps, kind.name().to_string()));
            md.push_str(&format!(
                "| {} | {} | {:.1} | {:.2} | {:.2} | {} ({}) | {} |\n",
                kind.name(),
                mode.name(),
                ns,
                st.max_forward.0,
                st.max_backward.0,
                st.crossings,
                st.in_band,
                st.mismatches
            ));
        }
    }
    let series: Vec<super::plot::Series> = Precision::ALL
        .iter()
        .zip(chart)
        .map(|(mode, pts)| super::plot::Series {
            name: mode.name().to_string(),
            points: pts.iter().map(|p| (p.0, p.1)).collect(),
            labels: pts.into_iter().map(|p| p.2).collect(),
        })
        .collect();
    super::plot::loglog_svg(
        &opts.out_dir.join("surfaces_speed_error.svg"),
        super::plot::Labels {
            title: "Ray–surface solvers: speed against error, per precision",
            x: "ns per intersection (median)",
            y: "largest forward error / S (relative)",
        },
        &series,
    )?;
    md.push_str(
        "\n![surface solvers: ns per intersection against the largest relative forward error, per precision]\
         (surfaces_speed_error.svg)\n\nOne point per surface kind and precision: the median time against the \
         largest forward error outside the near-tangent band, relative to the scale S (the table's column times \
         the mode's ε); a zero error is not drawn on the log axis.\n",
    );
    Ok(Section {
        title: "Ray–surface intersections".into(),
        markdown: md,
    })
}

mod timing;
pub use timing::*;

mod evaluate;
pub use evaluate::*;
