//! The curvicast kernel on an emulated Cortex-M4F (QEMU `mps2-an386`).
//!
//! Runs every case of [`cases::CASES`] (expected answers computed on the host by the arbitrary-precision oracle)
//! through the kernel's [`Surface::crossings`] in `f64` and in `f32`, plus a march through a spherical grid
//! (serial engine), an edge-beveled sphere and a terrain pick (with the hit refinement, with and without node
//! boxes; the tree and its boxes built on the target by `terrain::build`) with hand-derived
//! expectations (the slanted pick's from the host's terrain oracle), and a quadtree built on the target by
//! `terrain::build` from a crop of the Trinidad DEM ([`dem_crop`]) picked in `f64` and `f32` against the host
//! oracle's answers (the pass line counts these under "march, bevel and pick"), prints one line per failure and a
//! final pass line over semihosting, and exits (semihosting exit) with status 0 only if everything passes.
//!
//! **The panic-path proof.** The `#[panic_handler]` below calls a function that is declared but defined nowhere.
//! With `panic = "abort"`, LTO and one codegen unit, the handler is only linked if some code that can reach a
//! panic survives optimisation; then the link fails with an undefined reference to
//! `curvicast_panic_path_is_reachable`. So `cargo build --release` succeeding *is* the proof that nothing this
//! binary calls (the kernel's ray and surface code in both precisions, libm, this file) can panic.
//!
//! Output is integers and strings only, formatted by the few lines below: `core::fmt`'s float formatting holds
//! panic paths of its own and would make the proof fail for reasons outside the kernel.

#![no_std]
#![no_main]
#![deny(unsafe_code)]

// Generated on the host: its literals are oracle values, not approximations of named constants.
#[allow(
    clippy::approx_constant,
    clippy::excessive_precision,
    clippy::unreadable_literal
)]
mod cases;
// Generated on the host (`host-tests/tests/terrain/smoke_crop.rs`): a real DEM crop and oracle answers.
#[allow(clippy::unreadable_literal)]
mod dem_crop;

use cases::{CASES, Case, Kind};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio};
use curvicast::Real;
use curvicast::geodesy::Ellipsoid;
use curvicast::march::SphericalGrid;
use curvicast::ray::{Ray, RayError};
use curvicast::surface::{
    AxialCone, Crossings, HalfPlane, PlaneZ, Side, Spheroid, Surface, SurfaceError,
};
use curvicast::terrain::boxes::NodeBox;
use curvicast::terrain::build::{
    NodeRecord, SliceStorage, build_boxes_sharing, build_tree, node_slots,
};
use curvicast::terrain::{Grid, Node, NodeId, Picker};
use curvicast::tessellate::bevel::{Face, bevel_sphere, face_count, vertex_count};
use curvicast::vec3::V3;

/// Why one case failed in one precision.
enum Failure {
    /// The kernel rejected the ray.
    Ray(RayError),
    /// The kernel rejected the surface parameters.
    Surface(SurfaceError),
    /// Wrong number of crossings.
    Count { got: usize, want: usize },
    /// Crossing `k` enters the wrong side.
    Side { k: usize },
    /// Crossing `k` is off by more than the tolerance: `|t − t_oracle|` in percent of the tolerance (saturating;
    /// a NaN `t` shows as 0 % and is still a failure).
    T { k: usize, percent_of_tol: u32 },
}

/// The crossings of one case's ray with its surface, in precision `T`.
fn crossings<T: Real>(case: &Case) -> Result<Crossings<T>, Failure> {
    let v = |a: [f64; 3]| [T::from_f64(a[0]), T::from_f64(a[1]), T::from_f64(a[2])];
    let ray = Ray::new(v(case.origin), v(case.dir)).map_err(Failure::Ray)?;
    let [p0, p1] = case.p;
    let (p0, p1) = (T::from_f64(p0), T::from_f64(p1));
    let c = match case.kind {
        Kind::Spheroid => Spheroid::new(p0, p1)
            .map_err(Failure::Surface)?
            .crossings(&ray),
        Kind::Cone => AxialCone::from_zenith_rad(p0, p1)
            .map_err(Failure::Surface)?
            .crossings(&ray),
        Kind::HalfPlane => HalfPlane::from_azimuth_rad(p0)
            .map_err(Failure::Surface)?
            .crossings(&ray),
        Kind::PlaneZ => PlaneZ::new(p0).map_err(Failure::Surface)?.crossings(&ray),
    };
    Ok(c)
}

/// Checks one case in precision `T` against the oracle's answer with the tolerance `tol`.
fn check<T: Real>(case: &Case, tol: f64) -> Result<(), Failure> {
    let c = crossings::<T>(case)?;
    if c.len() != case.n {
        return Err(Failure::Count {
            got: c.len(),
            want: case.n,
        });
    }
    for (k, ((x, &t), &pos)) in c
        .iter()
        .zip(case.t.iter())
        .zip(case.into_positive.iter())
        .enumerate()
    {
        let err = (x.t.to_f64() - t).abs();
        if err.is_nan() || err > tol {
            // `as` saturates (and maps NaN to 0): no panic path.
            let percent_of_tol = (err / tol * 100.0) as u32;
            return Err(Failure::T { k, percent_of_tol });
        }
        if (x.into == Side::Positive) != pos {
            return Err(Failure::Side { k });
        }
    }
    Ok(())
}

/// Marches the ray `(−2, ¼, ¼) + t (1, 0, 0)` through the grid r = [0, ½, 1], θ = [0, π/2, π], φ = [0, π, 2π]
/// with the serial engine. The line stays at y = z = ¼ (θ < π/2, 0 < φ < π), so it crosses the outer shell, the
/// inner ball and the outer shell again: cells [1,0,0], [0,0,0], [1,0,0], entering at t = 2 − √(7/8), passing
/// r = ½ at t = 2 ∓ √(1/8) and leaving at t = 2 + √(7/8) (derived by hand). `tol` is relative to 1.
fn march_case<T: Real>(tol: f64) -> bool {
    let h = |x: f64| T::from_f64(x);
    let r = [h(0.0), h(0.5), h(1.0)];
    let th = [h(0.0), T::FRAC_PI_2, T::PI];
    let ph = [h(0.0), T::PI, T::PI + T::PI];
    let mut ws = [T::ZERO; SphericalGrid::<f64>::workspace_len(3, 3, 3)];
    let Ok(grid) = SphericalGrid::new(&r, &th, &ph, &mut ws) else {
        return false;
    };
    let Ok(ray) = Ray::new([h(-2.0), h(0.25), h(0.25)], [h(1.0), h(0.0), h(0.0)]) else {
        return false;
    };
    let (a, b) = (libm::sqrt(7.0 / 8.0), libm::sqrt(1.0 / 8.0));
    let want = [
        ([1, 0, 0], 2.0 - a, 2.0 - b),
        ([0, 0, 0], 2.0 - b, 2.0 + b),
        ([1, 0, 0], 2.0 + b, 2.0 + a),
    ];
    let mut n = 0usize;
    let mut march = grid.march(&ray);
    for c in &mut march {
        let Some((cell, t0, t1)) = want.get(n) else {
            return false;
        };
        let close = |x: T, y: f64| (x.to_f64() - y).abs() <= tol;
        if c.cell != *cell || !close(c.t_enter, *t0) || !close(c.t_exit, *t1) {
            return false;
        }
        n = n.wrapping_add(1);
    }
    n == want.len() && march.error().is_none()
}

/// Edge-bevels the unit sphere at level 2 into fixed buffers and checks the counts against the `const fn`s, that
/// every face plane touches the sphere at its center point, and that no vertex lies inside the sphere.
fn bevel_case<T: Real>(tol: f64) -> bool {
    const LEVEL: u32 = 2;
    const NV: usize = vertex_count(LEVEL);
    const NF: usize = face_count(LEVEL);
    let mut vertices = [V3::<T>::ZERO; NV];
    let face = Face {
        center: V3::ZERO,
        normal: V3::ZERO,
        vertices: [0; 6],
        len: 0,
    };
    let mut faces = [face; NF];
    let Ok(counts) = bevel_sphere(LEVEL, T::ONE, &mut vertices, &mut faces) else {
        return false;
    };
    let centers_touch = faces.iter().all(|f| {
        let r = f.center.length().to_f64();
        (r - 1.0).abs() <= tol && (f.normal.dot(f.center).to_f64() - 1.0).abs() <= tol
    });
    let outside = vertices.iter().all(|v| v.length().to_f64() >= 1.0 - tol);
    counts.vertices == NV && counts.faces == NF && centers_touch && outside
}

/// Vertex rows of the peak DEM ([`peak_heights`]).
const PEAK_ROWS: u32 = 3;
/// Vertex columns of the peak DEM: ten, so that the builder's one-cell leaves (2 × 9) sit under five zones of
/// 2 × 2 leaves, the first of them the peak's.
const PEAK_COLS: u32 = 10;
/// Node slots of the peak DEM's tree with one-cell leaves.
const PEAK_SLOTS: usize = node_slots(PEAK_ROWS, PEAK_COLS, 1);

/// A 3 × 10-vertex DEM from (10°N, 20°E) at 0.01°, flat at 0 m with vertex (1, 1) raised to 500 m, row-major.
fn peak_heights<T: Real>() -> [T; (PEAK_ROWS * PEAK_COLS) as usize] {
    let mut h = [T::ZERO; (PEAK_ROWS * PEAK_COLS) as usize];
    if let Some(v) = h.get_mut(PEAK_COLS as usize + 1) {
        *v = T::from_f64(500.0);
    }
    h
}

/// The peak DEM's grid.
fn peak_grid<T: Real>() -> Grid<T> {
    let h = |x: f64| T::from_f64(x);
    Grid {
        lat0_deg: h(10.0),
        lon0_deg: h(20.0),
        dlat_deg: h(0.01),
        dlon_deg: h(0.01),
        rows: PEAK_ROWS,
        cols: PEAK_COLS,
    }
}

/// The oracle's answer for the slanted ray of [`pick_case`] in `f64`: its `t` and the hit's height (checked by
/// `host-tests/tests/terrain/smoke_pick.rs` against the independent terrain oracle).
const PEAK_SLOPE_T: f64 = 0.800_016_529_664_916_8;
/// See [`PEAK_SLOPE_T`].
const PEAK_SLOPE_H: f64 = 399.966_730_307_997_1;

/// Picks the peak straight down and a slope from the side (with node boxes when `boxed`), against the oracle's
/// answers: within `tol_m` metres along the ray and in height.
fn pick_case<T: Real>(tol_m: f64, boxed: bool) -> bool {
    let e = Ellipsoid::<T>::wgs84();
    let h = |x: f64| T::from_f64(x);
    // The tree built on the target by the kernel's builder, and with `boxed` its node boxes in its records
    // (odd-numbered nodes' boxes in their parent's box frame, the others in their parent's own frame; without
    // `boxed` the records' box slots stay empty).
    let heights = peak_heights::<T>();
    let grid = peak_grid::<T>();
    let mut nodes = [NodeRecord::<T, Option<NodeBox>>::EMPTY; PEAK_SLOTS];
    let Ok(tree) = build_tree(&heights, &grid, 1, &mut nodes) else {
        return false;
    };
    if boxed {
        let odd = |id: NodeId, _: Option<&Node<f64>>| id.0 % 2 == 1;
        let e = Ellipsoid::wgs84();
        if build_boxes_sharing(&e, &grid, &heights, tree, None, &mut nodes, odd).is_err()
            || !nodes.iter().any(|r| r.bbox.is_some_and(|b| b.shared_frame))
        {
            return false;
        }
    }
    let Ok(dem) = SliceStorage::new(Ellipsoid::wgs84(), grid, &heights, &nodes, tree) else {
        return false;
    };
    let Ok(picker) = Picker::<'_, T, _, 16, 8>::new(&dem) else {
        return false;
    };
    let top = e.geodetic_deg_to_ecef(h(10.01), h(20.01), h(10_000.0));
    let down = e
        .normal_rad(h(10.01_f64.to_radians()), h(20.01_f64.to_radians()))
        .negated();
    let Ok(ray) = Ray::new(top, down) else {
        return false;
    };
    let straight = match picker.pick(&ray) {
        Ok(Some(hit)) => {
            (hit.t.to_f64() - 9500.0).abs() <= tol_m && (hit.h.to_f64() - 500.0).abs() <= tol_m
        }
        _ => false,
    };
    let from = e.geodetic_deg_to_ecef(h(10.0), h(20.004), h(1000.0));
    let below_peak = e.geodetic_deg_to_ecef(h(10.01), h(20.01), h(250.0));
    let Ok(slanted) = Ray::new(from, below_peak.minus(from)) else {
        return false;
    };
    let length = below_peak.minus(from).length().to_f64();
    let slope = match picker.pick(&slanted) {
        Ok(Some(hit)) => {
            let (t, h) = (hit.t.to_f64(), hit.h.to_f64());
            (t - PEAK_SLOPE_T).abs() * length <= tol_m && (h - PEAK_SLOPE_H).abs() <= tol_m
        }
        _ => false,
    };
    straight && slope
}

/// Builds the quadtree of the Trinidad crop ([`dem_crop`]) on the target with the kernel's builder and picks
/// every ray of [`dem_crop::RAYS`], each within `tol` metres of the oracle's `t` (or a miss where it misses).
fn crop_case<T: Real>(tol: f64) -> bool {
    use dem_crop::{BLOCK, COLS, GRID, HEIGHTS, RAYS, ROWS};
    let [lat0_deg, lon0_deg, dlat_deg, dlon_deg] = GRID.map(T::from_f64);
    let grid = Grid {
        lat0_deg,
        lon0_deg,
        dlat_deg,
        dlon_deg,
        rows: ROWS,
        cols: COLS,
    };
    let mut heights = [T::ZERO; HEIGHTS.len()];
    for (h, &m) in heights.iter_mut().zip(HEIGHTS.iter()) {
        *h = T::from_f64(f64::from(m));
    }
    let mut nodes = [NodeRecord::<T>::EMPTY; node_slots(ROWS, COLS, BLOCK)];
    let Ok(tree) = build_tree(&heights, &grid, BLOCK, &mut nodes) else {
        return false;
    };
    let Ok(storage) = SliceStorage::new(Ellipsoid::wgs84(), grid, &heights, &nodes, tree) else {
        return false;
    };
    let Ok(picker) = Picker::<'_, T, SliceStorage<'_, T>, 16, 32>::new(&storage) else {
        return false;
    };
    RAYS.iter().all(|r| {
        let Ok(ray) = Ray::new(r.origin.map(T::from_f64), r.dir.map(T::from_f64)) else {
            return false;
        };
        match (picker.pick(&ray), r.t) {
            (Ok(Some(hit)), Some(t)) => (hit.t.to_f64() - t).abs() <= tol,
            (Ok(None), None) => true,
            _ => false,
        }
    })
}

/// A fixed line buffer written to the host's stdout over semihosting. Overlong lines are cut (with `...`); the
/// pass line is short.
struct Line {
    buf: [u8; 160],
    len: usize,
}

impl Line {
    fn new() -> Self {
        Line {
            buf: [0; 160],
            len: 0,
        }
    }
    fn str(&mut self, s: &str) -> &mut Self {
        for &b in s.as_bytes() {
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = b;
                self.len = self.len.wrapping_add(1);
            }
        }
        self
    }
    /// Decimal digits of `n`, most significant first.
    fn num(&mut self, n: usize) -> &mut Self {
        let mut digits = [0u8; 20];
        let mut i = digits.len();
        let mut n = n;
        loop {
            i = i.wrapping_sub(1);
            if let Some(d) = digits.get_mut(i) {
                *d = b'0'.wrapping_add((n % 10) as u8);
            }
            n /= 10;
            if n == 0 || i == 0 {
                break;
            }
        }
        for &d in digits.get(i..).unwrap_or(&[]) {
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = d;
                self.len = self.len.wrapping_add(1);
            }
        }
        self
    }
    fn flush(&mut self, out: &mut hio::HostStream) {
        if self.len >= self.buf.len() {
            for (slot, &b) in self.buf.iter_mut().rev().zip(b"...") {
                *slot = b;
            }
        }
        let line = self.buf.get(..self.len).unwrap_or(&[]);
        // Nothing useful can be done if the host stops listening; the exit status still tells.
        let _ = out.write_all(line);
        let _ = out.write_all(b"\n");
        self.len = 0;
    }
}

fn kind_name(k: Kind) -> &'static str {
    match k {
        Kind::Spheroid => "spheroid",
        Kind::Cone => "cone",
        Kind::HalfPlane => "half-plane",
        Kind::PlaneZ => "plane-z",
    }
}

fn report(
    line: &mut Line,
    out: &mut hio::HostStream,
    i: usize,
    case: &Case,
    prec: &str,
    f: &Failure,
) {
    line.str("FAIL case ")
        .num(i)
        .str(" (")
        .str(kind_name(case.kind))
        .str(") ")
        .str(prec)
        .str(": ");
    match f {
        Failure::Ray(e) => line.str("the kernel rejected the ray: ").str(match e {
            RayError::NonFiniteOrigin => "non-finite origin",
            RayError::NonFiniteDirection => "non-finite direction",
            RayError::ZeroDirection => "zero direction",
            _ => "invalid interval",
        }),
        Failure::Surface(e) => line.str("the kernel rejected the surface: ").str(match e {
            SurfaceError::NonFinite => "non-finite parameter",
            SurfaceError::BadAxes => "bad axes",
            _ => "angle out of range",
        }),
        Failure::Count { got, want } => line
            .str("expected ")
            .num(*want)
            .str(" crossings, got ")
            .num(*got),
        Failure::Side { k } => line.str("crossing ").num(*k).str(" enters the wrong side"),
        Failure::T { k, percent_of_tol } => line
            .str("crossing ")
            .num(*k)
            .str(": |t - t_oracle| is ")
            .num(*percent_of_tol as usize)
            .str("% of the tolerance"),
    };
    line.flush(out);
}

#[entry]
fn main() -> ! {
    let Ok(mut out) = hio::hstdout() else {
        debug::exit(debug::EXIT_FAILURE);
        halt()
    };
    let mut line = Line::new();
    let mut passed = 0usize;
    for (i, case) in CASES.iter().enumerate() {
        let [tol64, tol32] = case.tol;
        let r64 = check::<f64>(case, tol64);
        let r32 = check::<f32>(case, tol32);
        if let Err(f) = &r64 {
            report(&mut line, &mut out, i, case, "f64", f);
        }
        if let Err(f) = &r32 {
            report(&mut line, &mut out, i, case, "f32", f);
        }
        if r64.is_ok() && r32.is_ok() {
            passed = passed.wrapping_add(1);
        }
    }
    let extra = [
        ("march f64", march_case::<f64>(1e-12)),
        ("march f32", march_case::<f32>(1e-5)),
        ("bevel f64", bevel_case::<f64>(1e-12)),
        ("bevel f32", bevel_case::<f32>(1e-5)),
        ("pick f64", pick_case::<f64>(1e-6, false)),
        ("pick f32", pick_case::<f32>(2.0, false)),
        ("pick f64 with boxes", pick_case::<f64>(1e-6, true)),
        ("pick f32 with boxes", pick_case::<f32>(2.0, true)),
        ("pick Trinidad crop f64", crop_case::<f64>(dem_crop::TOL[0])),
        ("pick Trinidad crop f32", crop_case::<f32>(dem_crop::TOL[1])),
    ];
    let mut extra_passed = 0usize;
    for (name, ok) in extra {
        if ok {
            extra_passed = extra_passed.wrapping_add(1);
        } else {
            line.str("FAIL ").str(name);
            line.flush(&mut out);
        }
    }
    let all = passed == CASES.len() && !CASES.is_empty() && extra_passed == extra.len();
    line.str("curvicast qemu-smoke: ");
    if !all {
        line.str("FAILED: ");
    }
    line.num(passed)
        .str("/")
        .num(CASES.len())
        .str(" cases passed (f64 and f32), march, bevel and pick ")
        .num(extra_passed)
        .str("/")
        .num(extra.len());
    line.flush(&mut out);
    debug::exit(if all {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    halt()
}

/// Waits forever (only reached if the host ignored the semihosting exit).
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

/// Reached only through a panic path. It calls a function that no object defines, so the final link fails
/// ("undefined symbol: curvicast_panic_path_is_reachable") whenever any panic path survives optimisation.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    #[allow(unsafe_code)]
    unsafe extern "Rust" {
        safe fn curvicast_panic_path_is_reachable() -> !;
    }
    curvicast_panic_path_is_reachable()
}
