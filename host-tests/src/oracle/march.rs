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
use astro_float::BigFloat;
use curvicast_cli::formats::spec::{GridSpec, RaySpec};
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
    pub(super) fn n_coords(&self) -> usize {
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

    pub(super) fn point(&self, r: &HpRay, t: &B) -> [B; 3] {
        std::array::from_fn(|i| add(&r.q[i], &mul(t, &r.d[i])))
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

mod compare;
mod locate;
mod structure;
mod walk;

pub use compare::{DROP_REL, Mismatch, Stats, compare, same_sequence};

#[cfg(test)]
mod tests;
