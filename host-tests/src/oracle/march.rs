//! Brute-force reference for ray marching through spherical, cylindrical and polar grids (Hannasch,
//! *Spherical Ray-Tracing*, §3.1 and the half-open cell convention of the command-line contract).
//!
//! # Method
//!
//! Nothing here follows the kernel's algorithm (no ditone hinges, no pseudospherical coordinates, no
//! interleaving). For one ray the oracle
//!
//! 1. intersects the ray with **every** boundary surface of the grid in 384-bit arithmetic (`astro-float`), with
//!    formulas of its own: every sphere `r = r_i` (`r_i > 0`), every zenith cone `θ = θ_j` (one nappe: `θ < π/2` the
//!    upper, `θ > π/2` the lower, `θ = π/2` the plane `z = 0`), every azimuth half-plane `φ = φ_k`; for a
//!    cylindrical grid every cylinder, half-plane and plane `z = z_m`; for a polar grid every circle and half-line;
//!    it also adds the parameters where the line meets the z axis and the center, where φ (and θ) jump;
//! 2. keeps the parameters inside `[t_min, t_max]`, adds the interval ends, sorts them and clusters parameters
//!    closer than `2^-200` of the ray's natural scale `(L + |p - c|) / |d|` (ties: edges, corners, the axis);
//! 3. classifies the midpoint of every interval between consecutive clusters by locating the point in high
//!    precision with the half-open rule (`r_i <= r < r_{i+1}`, `θ_j <= θ < θ_{j+1}`, `φ_k <= φ < φ_{k+1}` with φ
//!    modulo 2π), or as outside the domain;
//! 4. merges neighbouring intervals in the same cell and inserts the zero-length crossings of a tie.
//!
//! # Conventions (documented choices where the contract leaves room)
//!
//! * Breakpoints are exact real numbers (the `f64` values given), except three canonical values: a zenith
//!   breakpoint equal to `π/2` rounded (to `f64` or to `f32`) is the plane `z = 0`, one equal to `π` rounded is
//!   the exact south pole, and an azimuth range whose span `φ_last − φ_0` is within `8·eps·2π` of `2π` (`eps` of
//!   the precision in use; the kernel's tolerance) is a full circle: its last breakpoint is taken as `φ_0 + 2π`
//!   exactly. A zenith breakpoint `0` is the north pole.
//! * The rule is strictly half-open, as the contract states it: a point on the negative z axis has `θ = π`,
//!   which no band `θ_j <= θ < θ_{j+1}` contains (`θ_last <= π`), so it is outside the domain — a ray along the
//!   −z axis has no crossings there. A point on the z axis has `φ = 0` (the kernel's documented convention; the
//!   contract leaves it open), located in the wedge like any other azimuth. The center itself has neither θ nor
//!   φ: the oracle reports those indices as unknown (`None`), which the comparison matches with any index; only
//!   zero-length crossings exactly at the center can carry them.
//! * **Ties.** Where several indices change at one parameter, the oracle emits zero-length crossings so that one
//!   index changes per crossing, in the canonical order: first the radius (ρ) index, then zenith, then azimuth,
//!   then z; each index moves one step at a time toward its value after the tie (an azimuth index on a full
//!   circle moves the shorter way round, increasing on a tie of the two ways). The contract allows any order, so
//!   [`compare`] drops short crossings from both lists before comparing; the order is only for
//!   [`MarchOracle::check_structure`] on the oracle's own output.
//! * A ray that touches the domain at a single point (no interval of positive length inside) produces nothing.

use super::precise::{RM, bf, with_consts};
use crate::scenes::spec::{GridSpec, RaySpec};
use astro_float::BigFloat;
use std::fmt;

/// Working precision of the oracle in bits.
pub const PRECISION: usize = 384;

type B = BigFloat;

fn hp(x: f64) -> B {
    bf(x, PRECISION)
}
fn add(a: &B, b: &B) -> B {
    a.add(b, PRECISION, RM)
}
fn sub(a: &B, b: &B) -> B {
    a.sub(b, PRECISION, RM)
}
fn mul(a: &B, b: &B) -> B {
    a.mul(b, PRECISION, RM)
}
fn div(a: &B, b: &B) -> B {
    a.div(b, PRECISION, RM)
}
fn sqrt(a: &B) -> B {
    a.sqrt(PRECISION, RM)
}
fn sign(a: &B) -> i32 {
    if a.is_zero() {
        0
    } else if a.is_negative() {
        -1
    } else {
        1
    }
}
fn lt(a: &B, b: &B) -> bool {
    a.cmp(b).is_some_and(|c| c < 0)
}
fn le(a: &B, b: &B) -> bool {
    a.cmp(b).is_some_and(|c| c <= 0)
}
fn abs(a: &B) -> B {
    if a.is_negative() { a.neg() } else { a.clone() }
}
fn min_b(a: B, b: B) -> B {
    if lt(&b, &a) { b } else { a }
}

pub use super::precise::to_f64;

/// The kind of grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridKind {
    /// Spherical (r, θ, φ); cell `[i, j, k]`.
    Spherical,
    /// Cylindrical (ρ, φ, z); cell `[i, k, m]`.
    Cylindrical,
    /// Polar (r, φ) in the plane; cell `[i, k, 0]`.
    Polar,
}

/// A cell as the oracle knows it: `None` where the coordinate is undefined (zenith and azimuth at the center). Unused third index of a polar grid is `Some(0)`.
pub type OracleCell = [Option<u32>; 3];

/// One crossing of the reference answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OracleCrossing {
    /// The cell.
    pub cell: OracleCell,
    /// Entry parameter (rounded to `f64` from the high-precision value).
    pub t_enter: f64,
    /// Exit parameter.
    pub t_exit: f64,
}

/// One crossing as produced by an engine under test (any precision, widened to `f64`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KernelCrossing {
    /// The cell `[i, j, k]` (polar: `[i, k, 0]`).
    pub cell: [u32; 3],
    /// Entry parameter.
    pub t_enter: f64,
    /// Exit parameter.
    pub t_exit: f64,
}

/// A unit direction in high precision: `(cos a, sin a)`.
#[derive(Debug, Clone)]
struct Dir2 {
    c: B,
    s: B,
}

/// The grid, in high precision, built from its spec independently of the kernel.
#[derive(Debug, Clone)]
pub struct MarchOracle {
    kind: GridKind,
    center: [B; 3],
    radii: Vec<f64>,
    radii_hp: Vec<B>,
    radii_sq: Vec<B>,
    /// Zenith breakpoints as generators `(sin θ, cos θ)` in the (ρ, z) half-plane, stored as `Dir2 { c: cos, s: sin }`.
    zenith: Vec<Dir2>,
    zenith_raw: Vec<f64>,
    azim: Vec<Dir2>,
    full: bool,
    zs: Vec<B>,
    extent: f64,
    dims: [u32; 3],
}

/// Where the oracle's grid rejects a spec.
#[derive(Debug, Clone, PartialEq)]
pub struct SpecError(pub String);

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for SpecError {}

fn check_list(name: &str, v: &[f64]) -> Result<(), SpecError> {
    if v.len() < 2 {
        return Err(SpecError(format!("{name}: fewer than 2 breakpoints")));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(SpecError(format!("{name}: non-finite breakpoint")));
    }
    if v.windows(2).any(|w| w[0] >= w[1]) {
        return Err(SpecError(format!("{name}: not strictly increasing")));
    }
    Ok(())
}

const PI_F32: f64 = std::f32::consts::PI as f64;

/// The canonical zenith value π: `f64` π or `f32` π (the south pole).
fn is_pi(a: f64) -> bool {
    a == std::f64::consts::PI || a == PI_F32
}
/// The canonical zenith value π/2 (the plane `z = 0`), in `f64` or `f32`.
fn is_half_pi(a: f64) -> bool {
    a == std::f64::consts::FRAC_PI_2 || a == std::f32::consts::FRAC_PI_2 as f64
}

/// Whether an azimuth range `[p0, p1]` is a full turn: its span is within `8·eps·2π` of `2π`, `eps` the machine
/// epsilon of the precision the grid is used in (the tolerance the kernel applies; the contract says only "a full
/// 2π", and `2π` itself is not representable).
fn is_full_turn(p0: f64, p1: f64, eps: f64) -> bool {
    p1 - p0 >= std::f64::consts::TAU * (1.0 - 8.0 * eps)
}

fn hp_cos_sin(a: f64) -> Dir2 {
    if a == 0.0 {
        return Dir2 {
            c: hp(1.0),
            s: hp(0.0),
        };
    }
    let x = hp(a);
    with_consts(|cc| Dir2 {
        c: x.cos(PRECISION, RM, cc),
        s: x.sin(PRECISION, RM, cc),
    })
}

/// The ray in high precision, relative to the grid's center.
#[derive(Debug, Clone)]
pub struct HpRay {
    q: [B; 3],
    d: [B; 3],
    /// `t_min`, `t_max` as given.
    pub t_min: f64,
    /// Upper end (may be +∞).
    pub t_max: f64,
    /// `|d|` (of the components used: xy for a polar grid).
    pub dir_norm: f64,
    /// `|p − c|`.
    pub origin_dist: f64,
}

/// The reference answer for one ray, with what [`compare`] needs.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The crossings, canonical order at ties.
    pub crossings: Vec<OracleCrossing>,
    /// `L`: the larger of the grid's extent and the origin's distance from the center.
    pub l: f64,
    /// The ray.
    pub ray: HpRay,
}

impl MarchOracle {
    /// Builds the oracle's grid from a spec, validating it by the contract's rules, for use against `f64`.
    pub fn new(spec: &GridSpec) -> Result<Self, SpecError> {
        Self::new_for(spec, f64::EPSILON)
    }

    /// As [`MarchOracle::new`] for a grid used in a precision of machine epsilon `eps` (this only sets the
    /// full-turn tolerance of the azimuth range, see the module docs).
    pub fn new_for(spec: &GridSpec, eps: f64) -> Result<Self, SpecError> {
        let (kind, center, radii, theta, phi, zs) = match spec {
            GridSpec::Spherical {
                center,
                r,
                theta,
                phi,
            } => (
                GridKind::Spherical,
                center.unwrap_or([0.0; 3]),
                r.clone(),
                theta.clone(),
                phi.clone(),
                Vec::new(),
            ),
            GridSpec::Cylindrical {
                center,
                rho,
                phi,
                z,
            } => (
                GridKind::Cylindrical,
                center.unwrap_or([0.0; 3]),
                rho.clone(),
                Vec::new(),
                phi.clone(),
                z.clone(),
            ),
            GridSpec::Polar { center, r, phi } => {
                let c = center.unwrap_or([0.0; 2]);
                (
                    GridKind::Polar,
                    [c[0], c[1], 0.0],
                    r.clone(),
                    Vec::new(),
                    phi.clone(),
                    Vec::new(),
                )
            }
        };
        if center.iter().any(|x| !x.is_finite()) {
            return Err(SpecError("center: non-finite".into()));
        }
        check_list("r", &radii)?;
        if radii[0] < 0.0 {
            return Err(SpecError("r: negative radius".into()));
        }
        check_list("phi", &phi)?;
        // f32 grids carry f32-rounded constants (2π and π round up in f32): accept those as well
        if phi[phi.len() - 1] - phi[0]
            > std::f64::consts::TAU * (1.0 + 8.0 * eps.max(f32::EPSILON as f64))
        {
            return Err(SpecError("phi: span larger than 2π".into()));
        }
        if kind == GridKind::Spherical {
            check_list("theta", &theta)?;
            if theta[0] < 0.0 || theta[theta.len() - 1] > PI_F32 {
                return Err(SpecError("theta: outside [0, π]".into()));
            }
        }
        if kind == GridKind::Cylindrical {
            check_list("z", &zs)?;
        }
        let full = is_full_turn(phi[0], phi[phi.len() - 1], eps);
        let mut azim: Vec<Dir2> = phi.iter().map(|&a| hp_cos_sin(a)).collect();
        if full {
            let first = azim[0].clone();
            if let Some(last) = azim.last_mut() {
                *last = first;
            }
        }
        let zenith: Vec<Dir2> = theta
            .iter()
            .map(|&a| {
                if is_half_pi(a) {
                    Dir2 {
                        c: hp(0.0),
                        s: hp(1.0),
                    }
                } else if is_pi(a) {
                    Dir2 {
                        c: hp(-1.0),
                        s: hp(0.0),
                    }
                } else {
                    hp_cos_sin(a)
                }
            })
            .collect();
        let radii_hp: Vec<B> = radii.iter().map(|&r| hp(r)).collect();
        let radii_sq = radii_hp.iter().map(|r| mul(r, r)).collect();
        let mut extent = radii[radii.len() - 1];
        if kind == GridKind::Cylindrical {
            extent = extent.max(zs[0].abs()).max(zs[zs.len() - 1].abs());
        }
        let dims = match kind {
            GridKind::Spherical => [
                (radii.len() - 1) as u32,
                (theta.len() - 1) as u32,
                (phi.len() - 1) as u32,
            ],
            GridKind::Cylindrical => [
                (radii.len() - 1) as u32,
                (phi.len() - 1) as u32,
                (zs.len() - 1) as u32,
            ],
            GridKind::Polar => [(radii.len() - 1) as u32, (phi.len() - 1) as u32, 1],
        };
        Ok(MarchOracle {
            kind,
            center: [hp(center[0]), hp(center[1]), hp(center[2])],
            radii,
            radii_hp,
            radii_sq,
            zenith,
            zenith_raw: theta,
            azim,
            full,
            zs: zs.iter().map(|&z| hp(z)).collect(),
            extent,
            dims,
        })
    }

    /// The kind of grid.
    pub fn kind(&self) -> GridKind {
        self.kind
    }
    /// Number of cells along each index (`[n_r, n_θ, n_φ]`, `[n_ρ, n_φ, n_z]`, `[n_r, n_φ, 1]`).
    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }
    /// Whether the azimuth range is a full circle (the φ index wraps).
    pub fn full_circle(&self) -> bool {
        self.full
    }
    /// The grid's extent: outer radius (cylindrical: also the largest |z|).
    pub fn extent(&self) -> f64 {
        self.extent
    }
    /// Which index of a cell is the azimuth.
    pub fn phi_coord(&self) -> usize {
        match self.kind {
            GridKind::Spherical => 2,
            _ => 1,
        }
    }
    fn n_coords(&self) -> usize {
        if self.kind == GridKind::Polar { 2 } else { 3 }
    }

    /// Converts a ray to high precision relative to the center (polar: z dropped).
    pub fn hp_ray(&self, ray: &RaySpec) -> HpRay {
        let planar = self.kind == GridKind::Polar;
        let mut q: [B; 3] = std::array::from_fn(|i| sub(&hp(ray.origin[i]), &self.center[i]));
        let mut d: [B; 3] = std::array::from_fn(|i| hp(ray.dir[i]));
        if planar {
            q[2] = hp(0.0);
            d[2] = hp(0.0);
        }
        let dn = to_f64(&sqrt(&dot(&d, &d)));
        let od = to_f64(&sqrt(&dot(&q, &q)));
        HpRay {
            q,
            d,
            t_min: ray.t_min,
            t_max: ray.t_max_or_inf(),
            dir_norm: dn,
            origin_dist: od,
        }
    }

    /// The reference crossings of one ray (see the module docs for the conventions).
    pub fn march(&self, ray: &RaySpec) -> Reference {
        let r = self.hp_ray(ray);
        let l = self.extent.max(r.origin_dist);
        let crossings = self.march_hp(&r, l);
        Reference {
            crossings,
            l,
            ray: r,
        }
    }

    fn point(&self, r: &HpRay, t: &B) -> [B; 3] {
        std::array::from_fn(|i| add(&r.q[i], &mul(t, &r.d[i])))
    }

    /// All surface parameters of the line (unfiltered by the ray interval).
    fn events(&self, r: &HpRay, apex_tol: &B) -> Vec<B> {
        let mut ev = Vec::new();
        let (q, d) = (&r.q, &r.d);
        let planar_xy = self.kind != GridKind::Spherical;
        // spheres / cylinders / circles
        {
            let (a, b, c0) = if planar_xy {
                (dot2(d, d), dot2(q, d), dot2(q, q))
            } else {
                (dot(d, d), dot(q, d), dot(q, q))
            };
            for (rr, r2) in self.radii.iter().zip(&self.radii_sq) {
                if *rr == 0.0 {
                    continue;
                }
                let c = sub(&c0, r2);
                ev.extend(solve_quadratic(&a, &b, &c));
            }
        }
        // zenith cones
        if self.kind == GridKind::Spherical {
            for (k, g) in self.zenith.iter().enumerate() {
                let raw = self.zenith_raw[k];
                if raw == 0.0 || is_pi(raw) {
                    continue;
                }
                let s2 = mul(&g.s, &g.s);
                let c2 = mul(&g.c, &g.c);
                // z² sin²θ − (x² + y²) cos²θ = 0
                let a = sub(&mul(&mul(&d[2], &d[2]), &s2), &mul(&dot2(d, d), &c2));
                let b = sub(&mul(&mul(&q[2], &d[2]), &s2), &mul(&dot2(q, d), &c2));
                let c = sub(&mul(&mul(&q[2], &q[2]), &s2), &mul(&dot2(q, q), &c2));
                for t in solve_quadratic(&a, &b, &c) {
                    let z = add(&q[2], &mul(&t, &d[2]));
                    let ok = sign(&z) * sign(&g.c) >= 0 || le(&abs(&z), apex_tol);
                    if ok {
                        ev.push(t);
                    }
                }
            }
        }
        // azimuth half-planes / half-lines
        let n_az = if self.full {
            self.azim.len() - 1
        } else {
            self.azim.len()
        };
        for w in self.azim.iter().take(n_az) {
            // plane: −x sin + y cos = 0; side: x cos + y sin ≥ 0
            let num = sub(&mul(&q[1], &w.c), &mul(&q[0], &w.s));
            let den = sub(&mul(&d[1], &w.c), &mul(&d[0], &w.s));
            if den.is_zero() {
                continue;
            }
            let t = div(&num, &den).neg();
            let x = add(&q[0], &mul(&t, &d[0]));
            let y = add(&q[1], &mul(&t, &d[1]));
            let side = add(&mul(&x, &w.c), &mul(&y, &w.s));
            if sign(&side) >= 0 || le(&abs(&side), apex_tol) {
                ev.push(t);
            }
        }
        // planes z
        if self.kind == GridKind::Cylindrical && !d[2].is_zero() {
            for z in &self.zs {
                ev.push(div(&sub(z, &q[2]), &d[2]));
            }
        }
        // where the line meets the z axis (φ jumps) and the center (θ jumps)
        let dd2 = dot2(d, d);
        if !dd2.is_zero() {
            let cr = sub(&mul(&q[0], &d[1]), &mul(&q[1], &d[0]));
            if cr.is_zero() {
                ev.push(div(&dot2(q, d), &dd2).neg());
            }
        }
        ev
    }

    fn march_hp(&self, r: &HpRay, l: f64) -> Vec<OracleCrossing> {
        // t scale of the ray: (L + |q|) / |d|
        let tscale = hp((l + r.origin_dist) / r.dir_norm);
        let apex_tol = hp(l * 2f64.powi(-280));
        let tol = mul(&tscale, &hp(2f64.powi(-200)));
        let tmin = hp(r.t_min);
        let tmax = hp(r.t_max);
        let mut ev: Vec<B> = self
            .events(r, &apex_tol)
            .into_iter()
            .filter(|t| {
                (r.t_min == f64::NEG_INFINITY || lt(&tmin, t))
                    && (r.t_max == f64::INFINITY || lt(t, &tmax))
            })
            .collect();
        ev.sort_by(|a, b| a.cmp(b).unwrap_or(0).cmp(&0));
        // representatives of clusters; the interval ends are exact representatives
        let mut reps: Vec<B> = Vec::new();
        if r.t_min.is_finite() {
            reps.push(tmin.clone());
        }
        for t in ev {
            match reps.last() {
                Some(last) if le(&sub(&t, last), &tol) => {}
                _ => reps.push(t),
            }
        }
        if r.t_max.is_finite() {
            match reps.last() {
                Some(last) if le(&sub(&tmax, last), &tol) => {
                    let n = reps.len();
                    if n >= 2 || !r.t_min.is_finite() {
                        reps[n - 1] = tmax.clone();
                    } else {
                        // t_min == t_max (or within tol): a single point, nothing of positive length
                        if r.t_min < r.t_max {
                            reps.push(tmax.clone());
                        }
                    }
                }
                _ => reps.push(tmax.clone()),
            }
        }
        // intervals: (−∞, reps[0]) if t_min = −∞, between reps, (reps[last], +∞) if t_max = +∞
        let mut pieces: Vec<(Option<OracleCell>, B, B)> = Vec::new();
        let neg_inf = BigFloat::from_f64(f64::NEG_INFINITY, PRECISION);
        let pos_inf = BigFloat::from_f64(f64::INFINITY, PRECISION);
        if reps.is_empty() {
            let mid = hp(0.0);
            pieces.push((self.classify(&self.point(r, &mid)), neg_inf, pos_inf));
        } else {
            if !r.t_min.is_finite() {
                let mid = sub(&reps[0], &tscale);
                pieces.push((
                    self.classify(&self.point(r, &mid)),
                    neg_inf,
                    reps[0].clone(),
                ));
            }
            for w in reps.windows(2) {
                let mid = div(&add(&w[0], &w[1]), &hp(2.0));
                pieces.push((
                    self.classify(&self.point(r, &mid)),
                    w[0].clone(),
                    w[1].clone(),
                ));
            }
            if !r.t_max.is_finite() {
                let last = &reps[reps.len() - 1];
                let mid = add(last, &tscale);
                pieces.push((self.classify(&self.point(r, &mid)), last.clone(), pos_inf));
            }
        }
        // merge equal neighbours, drop outside
        let mut merged: Vec<(OracleCell, B, B)> = Vec::new();
        let mut prev_inside = false;
        for (cell, a, b) in pieces {
            match cell {
                None => prev_inside = false,
                Some(c) => {
                    if prev_inside {
                        if let Some(last) = merged.last_mut() {
                            if last.0 == c {
                                last.2 = b;
                                continue;
                            }
                        }
                    }
                    merged.push((c, a, b));
                    prev_inside = true;
                }
            }
        }
        // emit with zero-length tie cells between touching pieces
        let mut out = Vec::new();
        for (n, (cell, a, b)) in merged.iter().enumerate() {
            if n > 0 {
                let (pc, _, pb) = &merged[n - 1];
                if pb.cmp(a) == Some(0) {
                    let t = to_f64(a);
                    for mid in self.tie_path(*pc, *cell) {
                        out.push(OracleCrossing {
                            cell: mid,
                            t_enter: t,
                            t_exit: t,
                        });
                    }
                }
            }
            out.push(OracleCrossing {
                cell: *cell,
                t_enter: to_f64(a),
                t_exit: to_f64(b),
            });
        }
        out
    }

    /// The intermediate cells (exclusive of both ends) from `a` to `b`, one index step each, canonical order.
    fn tie_path(&self, a: OracleCell, b: OracleCell) -> Vec<OracleCell> {
        let mut cur = a;
        let mut path = Vec::new();
        // index order is the canonical order: spherical r, θ, φ; cylindrical ρ, φ, z; polar r, φ
        for c in 0..3 {
            let (Some(x), Some(y)) = (cur[c], b[c]) else {
                cur[c] = b[c];
                continue;
            };
            if x == y {
                continue;
            }
            let n = self.dims[c];
            let wrap = c == self.phi_coord() && self.full;
            let mut i = x;
            let up = if wrap {
                let fwd = (y + n - x) % n;
                fwd <= n - fwd
            } else {
                y > x
            };
            while i != y {
                i = if up {
                    if wrap { (i + 1) % n } else { i + 1 }
                } else if wrap {
                    (i + n - 1) % n
                } else {
                    i - 1
                };
                cur[c] = Some(i);
                path.push(cur);
            }
        }
        // the last pushed equals b (when anything changed); it is not an intermediate
        if path.last() == Some(&b) {
            path.pop();
        }
        // any remaining difference (unknown indices) is absorbed into b
        path
    }

    /// Locates a point (relative to the center) by the half-open rule; `None` outside the domain.
    pub fn classify(&self, p: &[B; 3]) -> Option<OracleCell> {
        let (x, y, z) = (&p[0], &p[1], &p[2]);
        let rho2 = add(&mul(x, x), &mul(y, y));
        let on_axis = rho2.is_zero();
        match self.kind {
            GridKind::Spherical => {
                let r2 = add(&rho2, &mul(z, z));
                let i = locate_sorted(&self.radii_sq, &r2)?;
                if r2.is_zero() {
                    return Some([Some(i), None, None]);
                }
                let rho = sqrt(&rho2);
                // θ ≥ θ_k ⟺ sin(θ − θ_k) > 0, or equal angles, or (θ = π, θ_k = 0)
                let ge = |g: &Dir2| -> bool {
                    let dd = sub(&mul(&rho, &g.c), &mul(z, &g.s));
                    match sign(&dd) {
                        1 => true,
                        -1 => false,
                        _ => {
                            let dt = add(&mul(&rho, &g.s), &mul(z, &g.c));
                            sign(&dt) > 0 || (g.c.cmp(&hp(1.0)) == Some(0))
                        }
                    }
                };
                // θ ≥ θ_k is monotone in k: binary search
                let count = self.zenith.partition_point(ge);
                let n = self.zenith.len();
                if count == 0 || count == n {
                    return None;
                }
                let j = count - 1;
                let k = self.locate_phi_or_axis(x, y, on_axis)?;
                Some([Some(i), Some(j as u32), Some(k)])
            }
            GridKind::Cylindrical => {
                let i = locate_sorted(&self.radii_sq, &rho2)?;
                let m = locate_sorted(&self.zs, z)?;
                let k = Some(self.locate_phi_or_axis(x, y, on_axis)?);
                Some([Some(i), k, Some(m)])
            }
            GridKind::Polar => {
                let i = locate_sorted(&self.radii_sq, &rho2)?;
                let k = Some(self.locate_phi_or_axis(x, y, on_axis)?);
                Some([Some(i), k, Some(0)])
            }
        }
    }

    /// Azimuth index; a point on the z axis has φ = 0 (the kernel's documented convention).
    fn locate_phi_or_axis(&self, x: &B, y: &B, on_axis: bool) -> Option<u32> {
        if on_axis {
            self.locate_phi(&hp(1.0), &hp(0.0))
        } else {
            self.locate_phi(x, y)
        }
    }

    /// Azimuth index of `(x, y) ≠ 0` by exact angular order from `φ_0`; `None` outside the wedge.
    fn locate_phi(&self, x: &B, y: &B) -> Option<u32> {
        let e0 = &self.azim[0];
        let n = self.azim.len();
        let u = Dir2 {
            c: x.clone(),
            s: y.clone(),
        };
        // number of breakpoints k (k < n − 1 when full) with β_k ≤ α
        let upto = if self.full { n - 1 } else { n };
        // the breakpoints are sorted by angle from φ_0, so β_k ≤ α is monotone in k: binary search
        let count = self.azim[..upto].partition_point(|w| angle_le(e0, w, &u));
        if count == 0 {
            // cannot happen (β_0 = 0 ≤ α), kept for safety
            return None;
        }
        if !self.full && count == n {
            return None;
        }
        Some((count - 1) as u32)
    }

    /// Distance from a point (relative to the center) to boundary surface `idx` of coordinate `coord`.
    fn dist_to(&self, p: &[B; 3], coord: usize, idx: usize) -> Option<B> {
        let (x, y, z) = (&p[0], &p[1], &p[2]);
        let rho = sqrt(&add(&mul(x, x), &mul(y, y)));
        let kind_coord = match (self.kind, coord) {
            (GridKind::Spherical, 0) => 0,
            (GridKind::Spherical, 1) => 1,
            (GridKind::Spherical, 2) => 2,
            (GridKind::Cylindrical, 0) => 3,
            (GridKind::Cylindrical, 1) => 2,
            (GridKind::Cylindrical, 2) => 4,
            (GridKind::Polar, 0) => 3,
            (GridKind::Polar, 1) => 2,
            _ => return None,
        };
        match kind_coord {
            0 => {
                let r = sqrt(&dot(p, p));
                Some(abs(&sub(&r, self.radii_hp.get(idx)?)))
            }
            1 => {
                let g = self.zenith.get(idx)?;
                let proj = add(&mul(&rho, &g.s), &mul(z, &g.c));
                if sign(&proj) < 0 {
                    Some(sqrt(&dot(p, p)))
                } else {
                    Some(abs(&sub(&mul(&rho, &g.c), &mul(z, &g.s))))
                }
            }
            2 => {
                let w = self.azim.get(idx)?;
                let proj = add(&mul(x, &w.c), &mul(y, &w.s));
                if sign(&proj) < 0 {
                    Some(rho)
                } else {
                    Some(abs(&sub(&mul(y, &w.c), &mul(x, &w.s))))
                }
            }
            3 => Some(abs(&sub(&rho, self.radii_hp.get(idx)?))),
            4 => Some(abs(&sub(z, self.zs.get(idx)?))),
            _ => None,
        }
    }

    fn n_breaks(&self, coord: usize) -> usize {
        match (self.kind, coord) {
            (GridKind::Spherical, 0) | (GridKind::Cylindrical, 0) | (GridKind::Polar, 0) => {
                self.radii.len()
            }
            (GridKind::Spherical, 1) => self.zenith.len(),
            (GridKind::Spherical, 2) | (GridKind::Cylindrical, 1) | (GridKind::Polar, 1) => {
                self.azim.len()
            }
            (GridKind::Cylindrical, 2) => self.zs.len(),
            _ => 0,
        }
    }

    /// Distance (in length units, `f64`) from the point `p + t d` to the boundary surface crossed when index
    /// `coord` steps across breakpoint `idx`, or — with `which = None` — to the nearest boundary surface.
    pub fn boundary_distance(&self, ray: &HpRay, t: f64, which: Option<(usize, usize)>) -> f64 {
        let p = self.point(ray, &hp(t));
        let d = match which {
            // two sectors on a full circle: a step 0 ↔ 1 crosses either breakpoint
            Some((c, _)) if c == self.phi_coord() && self.full && self.dims[c] == 2 => {
                match (self.dist_to(&p, c, 0), self.dist_to(&p, c, 1)) {
                    (Some(a), Some(b)) => Some(min_b(a, b)),
                    (a, b) => a.or(b),
                }
            }
            Some((c, i)) => self.dist_to(&p, c, i),
            None => {
                let mut best: Option<B> = None;
                for c in 0..self.n_coords() {
                    for i in 0..self.n_breaks(c) {
                        if c == 0 && self.radii[i] == 0.0 {
                            continue;
                        }
                        if self.kind == GridKind::Spherical && c == 1 && self.zenith_raw[i] == 0.0 {
                            continue;
                        }
                        if let Some(v) = self.dist_to(&p, c, i) {
                            best = Some(match best {
                                None => v,
                                Some(b) => min_b(b, v),
                            });
                        }
                    }
                }
                best
            }
        };
        d.map(|v| to_f64(&v)).unwrap_or(f64::INFINITY)
    }

    /// Checks the contract's structural invariants on any list of crossings: `t_min <= t_enter <= t_exit <=
    /// t_max`, indices in range, and consecutive crossings either touch and differ in exactly one index by one
    /// step (the azimuth wraps only on a full circle) or are separated by a gap.
    pub fn check_structure(
        &self,
        list: &[KernelCrossing],
        t_min: f64,
        t_max: f64,
    ) -> Result<(), String> {
        for (n, c) in list.iter().enumerate() {
            if c.t_enter.partial_cmp(&c.t_exit).is_none_or(|o| o.is_gt()) {
                return Err(format!(
                    "crossing {n}: t_enter {} > t_exit {}",
                    c.t_enter, c.t_exit
                ));
            }
            if c.t_enter < t_min || c.t_exit > t_max {
                return Err(format!(
                    "crossing {n}: [{}, {}] outside [{t_min}, {t_max}]",
                    c.t_enter, c.t_exit
                ));
            }
            for k in 0..3 {
                if c.cell[k] >= self.dims[k] {
                    return Err(format!(
                        "crossing {n}: cell {:?} out of range {:?}",
                        c.cell, self.dims
                    ));
                }
            }
            if n == 0 {
                continue;
            }
            let p = &list[n - 1];
            if c.t_enter < p.t_exit {
                return Err(format!(
                    "crossing {n}: t_enter {} before previous t_exit {}",
                    c.t_enter, p.t_exit
                ));
            }
            if c.t_enter == p.t_exit {
                self.one_step(&p.cell.map(Some), &c.cell.map(Some))
                    .map_err(|e| {
                        format!("crossings {}→{n}: {:?}→{:?}: {e}", n - 1, p.cell, c.cell)
                    })?;
            }
        }
        Ok(())
    }

    /// Checks that two cells differ in exactly one (known) index by one step.
    fn one_step(&self, a: &OracleCell, b: &OracleCell) -> Result<Option<(usize, usize)>, String> {
        let mut changed = None;
        for k in 0..3 {
            let (Some(x), Some(y)) = (a[k], b[k]) else {
                continue;
            };
            if x == y {
                continue;
            }
            if changed.is_some() {
                return Err("more than one index changes".into());
            }
            let n = self.dims[k];
            let boundary = if x + 1 == y {
                y as usize
            } else if y + 1 == x {
                x as usize
            } else if k == self.phi_coord()
                && self.full
                && n > 1
                && ((x == 0 && y == n - 1) || (y == 0 && x == n - 1))
            {
                0
            } else {
                return Err(format!("index {k} jumps {x}→{y}"));
            };
            changed = Some((k, boundary));
        }
        if changed.is_none() && a == b {
            return Err("touching crossings in the same cell".into());
        }
        Ok(changed)
    }

    /// Converts the oracle's list for [`MarchOracle::check_structure`] (unknown indices as 0).
    pub fn as_kernel_list(list: &[OracleCrossing]) -> Vec<KernelCrossing> {
        list.iter()
            .map(|c| KernelCrossing {
                cell: c.cell.map(|v| v.unwrap_or(0)),
                t_enter: c.t_enter,
                t_exit: c.t_exit,
            })
            .collect()
    }

    /// Structural check of the oracle's own list (unknown indices are skipped).
    pub fn check_oracle_structure(&self, r: &Reference) -> Result<(), String> {
        for (n, w) in r.crossings.windows(2).enumerate() {
            if w[1].t_enter < w[0].t_exit || w[0].t_enter > w[0].t_exit {
                return Err(format!("oracle crossings {n}: not ordered"));
            }
            if w[1].t_enter == w[0].t_exit {
                if w[0]
                    .cell
                    .iter()
                    .chain(w[1].cell.iter())
                    .any(|c| c.is_none())
                {
                    continue;
                }
                self.one_step(&w[0].cell, &w[1].cell).map_err(|e| {
                    format!("oracle crossings {n}: {:?}→{:?}: {e}", w[0].cell, w[1].cell)
                })?;
            }
        }
        Ok(())
    }
}

fn dot(a: &[B; 3], b: &[B; 3]) -> B {
    add(
        &add(&mul(&a[0], &b[0]), &mul(&a[1], &b[1])),
        &mul(&a[2], &b[2]),
    )
}
fn dot2(a: &[B; 3], b: &[B; 3]) -> B {
    add(&mul(&a[0], &b[0]), &mul(&a[1], &b[1]))
}

/// Roots of `a t² + 2 b t + c = 0` (a double root once; none when the line lies in the surface).
fn solve_quadratic(a: &B, b: &B, c: &B) -> Vec<B> {
    if a.is_zero() {
        if b.is_zero() {
            return Vec::new();
        }
        return vec![div(c, &mul(b, &hp(2.0))).neg()];
    }
    let disc = sub(&mul(b, b), &mul(a, c));
    if sign(&disc) < 0 {
        return Vec::new();
    }
    let s = sqrt(&disc);
    let q = if sign(b) < 0 {
        sub(&s, b)
    } else {
        add(b, &s).neg()
    };
    if q.is_zero() {
        return vec![hp(0.0)];
    }
    if disc.is_zero() {
        return vec![div(&q, a)];
    }
    vec![div(&q, a), div(c, &q)]
}

/// Index `i` with `v[i] <= x < v[i+1]`, or `None`.
fn locate_sorted(v: &[B], x: &B) -> Option<u32> {
    let count = v.partition_point(|b| le(b, x));
    if count == 0 || count == v.len() {
        None
    } else {
        Some((count - 1) as u32)
    }
}

/// Whether the angle of `w` measured counterclockwise from `e0` (in `[0, 2π)`) is at most that of `u`.
fn angle_le(e0: &Dir2, w: &Dir2, u: &Dir2) -> bool {
    let half = |v: &Dir2| -> u8 {
        let cr = sub(&mul(&e0.c, &v.s), &mul(&e0.s, &v.c));
        match sign(&cr) {
            1 => 0,
            -1 => 1,
            _ => {
                let dt = add(&mul(&e0.c, &v.c), &mul(&e0.s, &v.s));
                if sign(&dt) > 0 { 0 } else { 1 }
            }
        }
    };
    let (hw, hu) = (half(w), half(u));
    if hw != hu {
        return hw < hu;
    }
    // same half: w ≤ u ⟺ cross(w, u) ≥ 0
    let cr = sub(&mul(&w.c, &u.s), &mul(&w.s, &u.c));
    sign(&cr) >= 0
}

/// Statistics of a successful comparison.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// Crossings in the engine's list.
    pub n_kernel: usize,
    /// Crossings in the oracle's list.
    pub n_oracle: usize,
    /// Whether the two cell sequences are identical even before dropping short crossings.
    pub identical_raw: bool,
    /// Largest distance of an engine crossing point from its boundary surface, in units of `eps·L`.
    pub max_backward_eps: f64,
    /// Largest `|t_engine − t_oracle|·|d|` over matched crossing ends not next to a dropped crossing, in `eps·L`.
    pub max_forward_eps: f64,
}

/// Why a comparison failed.
#[derive(Debug, Clone, PartialEq)]
pub enum Mismatch {
    /// The engine's list breaks a structural invariant of the contract.
    Structure(String),
    /// The cell sequences differ after dropping short crossings.
    Sequence {
        /// Reduced engine list.
        kernel: Vec<(OracleCell, f64, f64)>,
        /// Reduced oracle list.
        oracle: Vec<(OracleCell, f64, f64)>,
    },
    /// A crossing point is farther than the bound from its boundary surface.
    Backward {
        /// The parameter.
        t: f64,
        /// Its distance in units of `eps·L`.
        err_eps: f64,
    },
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Mismatch::Structure(s) => write!(f, "structure: {s}"),
            Mismatch::Sequence { kernel, oracle } => {
                writeln!(f, "cell sequences differ:")?;
                writeln!(f, "  engine ({}):", kernel.len())?;
                for c in kernel {
                    writeln!(f, "    {:?} [{:e}, {:e}]", c.0, c.1, c.2)?;
                }
                writeln!(f, "  oracle ({}):", oracle.len())?;
                for c in oracle {
                    writeln!(f, "    {:?} [{:e}, {:e}]", c.0, c.1, c.2)?;
                }
                Ok(())
            }
            Mismatch::Backward { t, err_eps } => {
                write!(
                    f,
                    "crossing point at t = {t:e} lies {err_eps:.1} eps·L from its surface"
                )
            }
        }
    }
}

/// Relative length below which crossings are dropped before comparing sequences (issue: `1e-7·L`).
pub const DROP_REL: f64 = 1e-7;

/// A reduced crossing: cell, ends, and whether each end touches a dropped piece.
#[derive(Debug, Clone, Copy)]
struct Reduced {
    cell: OracleCell,
    a: f64,
    b: f64,
    clean_a: bool,
    clean_b: bool,
}

/// Drops crossings shorter than `min_t` (in t units) and merges survivors in the same cell that only dropped
/// crossings or gaps shorter than `min_t` separate.
fn reduce(list: &[(OracleCell, f64, f64)], min_t: f64) -> Vec<Reduced> {
    let short = |c: &(OracleCell, f64, f64)| c.2 - c.1 < min_t;
    let mut out: Vec<Reduced> = Vec::new();
    let mut all_short = true; // every piece and gap since the last survivor is short
    for (n, c) in list.iter().enumerate() {
        let (cell, a, b) = *c;
        if n > 0 && a - list[n - 1].2 >= min_t {
            all_short = false;
        }
        if short(c) {
            continue;
        }
        let prev_drop = n > 0 && short(&list[n - 1]) && list[n - 1].2 == a;
        let next_drop = list.get(n + 1).is_some_and(|q| short(q) && q.1 == b);
        if let Some(last) = out.last_mut() {
            if all_short && last.cell == cell {
                last.b = b;
                last.clean_b = !next_drop;
                continue;
            }
        }
        out.push(Reduced {
            cell,
            a,
            b,
            clean_a: !prev_drop,
            clean_b: !next_drop,
        });
        all_short = true;
    }
    out
}

fn cells_match(a: &OracleCell, b: &OracleCell) -> bool {
    a.iter()
        .zip(b.iter())
        .all(|(x, y)| x.is_none() || y.is_none() || x == y)
}

/// The comparison criterion of the marching tests: the order of cells exact, each t within a tolerance.
///
/// 1. `kernel` must satisfy [`MarchOracle::check_structure`].
/// 2. After dropping crossings shorter than `1e-7·L` from both lists (and merging neighbours that then agree),
///    the cell sequences must be identical (an unknown oracle index matches any index).
/// 3. Every engine crossing end strictly inside `(t_min, t_max)` must lie within `bound_eps·eps·L` of a boundary
///    surface: the surface of the index that changes there when the neighbour touches, else the nearest one
///    (domain entries and exits). `bound_eps = None` measures without failing.
///
/// The forward error `|t − t_oracle|·|d| / (eps·L)` is measured on matched ends that no dropped crossing touches.
pub fn compare(
    oracle: &MarchOracle,
    reference: &Reference,
    kernel: &[KernelCrossing],
    eps: f64,
    bound_eps: Option<f64>,
) -> Result<Stats, Mismatch> {
    let r = &reference.ray;
    oracle
        .check_structure(kernel, r.t_min, r.t_max)
        .map_err(Mismatch::Structure)?;
    let l = reference.l;
    let min_t = DROP_REL * l / r.dir_norm;
    let k_list: Vec<(OracleCell, f64, f64)> = kernel
        .iter()
        .map(|c| (c.cell.map(Some), c.t_enter, c.t_exit))
        .collect();
    let o_list: Vec<(OracleCell, f64, f64)> = reference
        .crossings
        .iter()
        .map(|c| (c.cell, c.t_enter, c.t_exit))
        .collect();
    let identical_raw = k_list.len() == o_list.len()
        && k_list
            .iter()
            .zip(&o_list)
            .all(|(k, o)| cells_match(&k.0, &o.0));
    let kr = reduce(&k_list, min_t);
    let or = reduce(&o_list, min_t);
    let same = kr.len() == or.len()
        && kr
            .iter()
            .zip(&or)
            .all(|(k, o)| cells_match(&k.cell, &o.cell));
    if !same {
        return Err(Mismatch::Sequence {
            kernel: kr.iter().map(|c| (c.cell, c.a, c.b)).collect(),
            oracle: or.iter().map(|c| (c.cell, c.a, c.b)).collect(),
        });
    }
    let unit = eps * l;
    let mut fwd: f64 = 0.0;
    for (k, o) in kr.iter().zip(&or) {
        if k.clean_a && o.clean_a && k.a.is_finite() && o.a.is_finite() {
            fwd = fwd.max((k.a - o.a).abs() * r.dir_norm / unit);
        }
        if k.clean_b && o.clean_b && k.b.is_finite() && o.b.is_finite() {
            fwd = fwd.max((k.b - o.b).abs() * r.dir_norm / unit);
        }
    }
    // backward error
    let mut bwd: f64 = 0.0;
    for (n, c) in kernel.iter().enumerate() {
        for (end, t) in [(0, c.t_enter), (1, c.t_exit)] {
            if !(t > r.t_min && t < r.t_max) {
                continue;
            }
            let neighbour = if end == 0 {
                n.checked_sub(1)
                    .map(|m| &kernel[m])
                    .filter(|p| p.t_exit == t)
            } else {
                kernel.get(n + 1).filter(|p| p.t_enter == t)
            };
            let which = neighbour.and_then(|p| {
                oracle
                    .one_step(&c.cell.map(Some), &p.cell.map(Some))
                    .ok()
                    .flatten()
            });
            let dist = oracle.boundary_distance(r, t, which);
            let e = dist / unit;
            bwd = bwd.max(e);
            if let Some(bound) = bound_eps {
                if e > bound {
                    return Err(Mismatch::Backward { t, err_eps: e });
                }
            }
        }
    }
    Ok(Stats {
        n_kernel: kernel.len(),
        n_oracle: reference.crossings.len(),
        identical_raw,
        max_backward_eps: bwd,
        max_forward_eps: fwd,
    })
}

/// Only the sequence part of [`compare`]: whether the cell sequences agree after dropping crossings shorter
/// than `1e-7·L` from both lists (no structural or backward-error check; for baselines such as a voxel march
/// mapped back to cells, whose lists need not satisfy the contract).
pub fn same_sequence(reference: &Reference, list: &[KernelCrossing]) -> bool {
    let min_t = DROP_REL * reference.l / reference.ray.dir_norm;
    let k_list: Vec<(OracleCell, f64, f64)> = list
        .iter()
        .map(|c| (c.cell.map(Some), c.t_enter, c.t_exit))
        .collect();
    let o_list: Vec<(OracleCell, f64, f64)> = reference
        .crossings
        .iter()
        .map(|c| (c.cell, c.t_enter, c.t_exit))
        .collect();
    let (kr, or) = (reduce(&k_list, min_t), reduce(&o_list, min_t));
    kr.len() == or.len()
        && kr
            .iter()
            .zip(&or)
            .all(|(k, o)| cells_match(&k.cell, &o.cell))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn to_f64_round_trips() {
        for &x in &[
            1.0,
            -2.5,
            1e-300,
            6.4e6,
            0.1,
            1e30,
            -1e-30,
            std::f64::consts::PI,
        ] {
            assert_eq!(to_f64(&hp(x)), x, "{x}");
        }
        let third = div(&hp(1.0), &hp(3.0));
        assert_eq!(to_f64(&third), 1.0 / 3.0);
    }
}
