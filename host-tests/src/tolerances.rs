//! Every tolerance the oracle suites assert, in one table that the tests and the report both read: the bound, what
//! it bounds, the largest value measured, and on what sample. A suite that asserts a bound imports it from here;
//! the report prints the table ("Tolerances"). The measured values are those of the command in each row's
//! `sample`; a change that moves one far should update it here.

use crate::report::surfaces::Kind;
use curvicast_cli::precision::Precision;

/// One bound of an oracle suite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// The bound the suite asserts.
    pub bound: f64,
    /// Its unit.
    pub unit: &'static str,
    /// What it bounds, and which suites assert it.
    pub bounds: &'static str,
    /// The largest value measured on `sample`.
    pub measured: f64,
    /// The sample behind `measured`, and the command that measures it.
    pub sample: &'static str,
}

/// Marching (f64): the distance of every crossing point strictly inside the ray's interval from the boundary
/// surface it crosses, in units of `ε·L` (`L` the grid's extent); the cell order is compared exactly.
pub const MARCH_F64_BOUNDARY: Tolerance = Tolerance {
    bound: 16.0,
    unit: "ε·L",
    bounds: "distance of each f64 crossing point from its boundary surface (tests/march/oracle.rs)",
    measured: MEASURED_MARCH_F64,
    sample: MEASURED_MARCH_SAMPLE,
};

/// Marching (f64): column integrals of piecewise constant and `r²` fields against their closed forms.
pub const MARCH_ANALYTIC_REL: Tolerance = Tolerance {
    bound: 1e-12,
    unit: "relative",
    bounds: "column integrals of constant, step and r² fields against closed forms (tests/march/analytic.rs)",
    measured: MEASURED_ANALYTIC,
    sample: MEASURED_ANALYTIC_SAMPLE,
};

/// Terrain (f64): the distance between the kernel's refined hit point and the oracle's exact one.
pub const TERRAIN_HIT_F64: Tolerance = Tolerance {
    bound: 1e-6,
    unit: "m",
    bounds: "distance of the f64 hit point from the oracle's (tests/terrain: oracle, multires, smoke_crop)",
    measured: MEASURED_TERRAIN,
    sample: MEASURED_TERRAIN_SAMPLE,
};

/// Terrain (f32 picker, the QEMU smoke crop): its hit parameter against the oracle's (unit directions).
pub const TERRAIN_HIT_F32_SMOKE: Tolerance = Tolerance {
    bound: 4.0,
    unit: "m",
    bounds: "the f32 picker's hit parameter against the oracle's on the Cortex-M4F smoke crop (unit \
             directions: metres along the ray; tests/terrain/smoke_crop.rs, checked again on QEMU)",
    measured: MEASURED_SMOKE_F32,
    sample: MEASURED_SMOKE_SAMPLE,
};

/// Geodesy (f64): the round trip ECEF → geodetic → ECEF and the height against the exact inversion.
pub const GEODESY_ROUND_TRIP: Tolerance = Tolerance {
    bound: 7.0e-9,
    unit: "m",
    bounds: "ECEF → geodetic → ECEF round trip and height error, GeographicLib's bound \
             (tests/surfaces/geodesy_oracle.rs)",
    measured: MEASURED_GEODESY,
    sample: MEASURED_GEODESY_SAMPLE,
};

/// The rows above, in the report's order.
pub const TOLERANCES: [Tolerance; 5] = [
    MARCH_F64_BOUNDARY,
    MARCH_ANALYTIC_REL,
    TERRAIN_HIT_F64,
    TERRAIN_HIT_F32_SMOKE,
    GEODESY_ROUND_TRIP,
];

/// One row of the table of error bounds: what the oracle test asserts for a kind and mode, next to what was
/// measured (in units of `ε S`; forward outside the near-tangent band, backward over every kernel crossing).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorBound {
    /// The surface family.
    pub kind: Kind,
    /// The scalar mode.
    pub mode: Precision,
    /// The largest forward error measured on [`MEASURED_RAYS`] rays (`tests/surfaces/oracle.rs: full_sweep_all_modes`).
    pub measured_forward: f64,
    /// The largest backward error measured on the same rays.
    pub measured_backward: f64,
    /// The asserted forward bound: the project's accuracy target, 16, in `f64`; 1.5 × the measured value (rounded up to
    /// a half) in `f32` and `F32Fast`.
    pub forward: f64,
    /// The asserted backward bound, likewise.
    pub backward: f64,
}

/// The sample behind [`ERROR_BOUNDS`]' measured values: 100 000 random rays per kind and mode
/// ([`crate::report::surfaces::random_cases`] with the seed of `tests/surfaces/oracle.rs: full_sweep_all_modes`, which re-checks the table).
pub const MEASURED_RAYS: usize = 100_000;

const fn row(kind: Kind, mode: Precision, mf: f64, mb: f64, f: f64, b: f64) -> ErrorBound {
    ErrorBound {
        kind,
        mode,
        measured_forward: mf,
        measured_backward: mb,
        forward: f,
        backward: b,
    }
}

/// Every bound of the surface layer's oracle test and report, with its measured value: the one place they live.
pub const ERROR_BOUNDS: [ErrorBound; 12] = [
    row(Kind::Spheroid, Precision::F64, 3.244, 3.008, 16.0, 16.0),
    row(Kind::Spheroid, Precision::F32, 3.359, 3.067, 5.5, 5.0),
    row(Kind::Spheroid, Precision::F32Fast, 3.435, 3.398, 5.5, 5.5),
    row(Kind::Cone, Precision::F64, 3.229, 1.156, 16.0, 16.0),
    // f32 cones with an opening near π/2 (nearly a plane): the rounding of cos θ in f32 dominates.
    row(Kind::Cone, Precision::F32, 11.425, 5.449, 17.5, 8.5),
    row(Kind::Cone, Precision::F32Fast, 11.425, 5.449, 17.5, 8.5),
    row(Kind::HalfPlane, Precision::F64, 3.085, 1.311, 16.0, 16.0),
    row(Kind::HalfPlane, Precision::F32, 2.806, 1.522, 4.5, 2.5),
    row(Kind::HalfPlane, Precision::F32Fast, 2.806, 1.522, 4.5, 2.5),
    row(Kind::PlaneZ, Precision::F64, 1.339, 1.081, 16.0, 16.0),
    row(Kind::PlaneZ, Precision::F32, 1.719, 1.380, 3.0, 2.5),
    row(Kind::PlaneZ, Precision::F32Fast, 1.719, 1.380, 3.0, 2.5),
];

/// The row of [`ERROR_BOUNDS`] for a kind and mode.
pub fn error_bound(kind: Kind, mode: Precision) -> ErrorBound {
    ERROR_BOUNDS
        .iter()
        .copied()
        .find(|b| b.kind == kind && b.mode == mode)
        .unwrap_or(row(kind, mode, f64::NAN, f64::NAN, 16.0, 16.0))
}

/// The forward-error bound `B` (in units of `ε S`, outside the near-tangent band) asserted by the oracle test for a
/// kind and mode, and used to size the ambiguity zones (see the module docs): [`ERROR_BOUNDS`].
pub fn forward_bound(kind: Kind, mode: Precision) -> f64 {
    error_bound(kind, mode).forward
}

/// The backward-error bound (in units of `ε S_k`, over every kernel crossing, in the band too) asserted by the oracle
/// test: [`ERROR_BOUNDS`].
pub fn backward_bound(kind: Kind, mode: Precision) -> f64 {
    error_bound(kind, mode).backward
}

// The measured values (release builds, 2026-12; each `sample` says how to measure again).
const MEASURED_MARCH_F64: f64 = 2.12;
const MEASURED_MARCH_SAMPLE: &str = "the default run's 4 186 rays (named hard cases and 3 000 random rays), each \
     by both engines: `cargo test --release -p curvicast-host --test march oracle -- --nocapture`";
const MEASURED_ANALYTIC: f64 = 1.11e-14;
const MEASURED_ANALYTIC_SAMPLE: &str = "four fields over three grids each: \
     `cargo test --release -p curvicast-host --test march analytic -- --nocapture`";
const MEASURED_TERRAIN: f64 = 3.485e-9;
const MEASURED_TERRAIN_SAMPLE: &str = "187 850 rays of the full suites (grazing, poles, antimeridian, random \
     terrains, real DEMs): `cargo test --release -p curvicast-host --test terrain oracle -- --include-ignored \
     --nocapture`";
const MEASURED_SMOKE_F32: f64 = 0.342;
const MEASURED_SMOKE_SAMPLE: &str = "the 11 rays of the smoke crop (asserted at a quarter of the bound): \
     `cargo test --release -p curvicast-host --test terrain smoke_crop -- --nocapture`";
const MEASURED_GEODESY: f64 = 5.526e-9;
const MEASURED_GEODESY_SAMPLE: &str = "the suite's uniform, near-pole, z-axis, near-centre and seeded points: \
     `cargo test --release -p curvicast-host --test surfaces geodesy_oracle -- --nocapture`";

/// `x` as a person reads it: plain between 0.01 and 10 000, otherwise with an exponent (4 significant digits).
fn number(x: f64) -> String {
    if (0.01..1e4).contains(&x.abs()) {
        format!("{}", (x * 1e4).round() / 1e4)
    } else {
        format!("{x:.3e}")
    }
}

/// The report's section: every row of [`TOLERANCES`] and of [`ERROR_BOUNDS`], bound next to measured value.
pub fn section(_opts: &crate::report::Options) -> anyhow::Result<crate::report::Section> {
    let mut md = String::from(
        "Every bound the oracle suites assert (`curvicast_host::tolerances`, which the tests import), with the \
         largest value measured and on what sample.\n\n\
         | bound | unit | what it bounds | measured | sample |\n| ---: | --- | --- | ---: | --- |\n",
    );
    for t in TOLERANCES {
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} |\n",
            number(t.bound),
            t.unit,
            t.bounds,
            number(t.measured),
            t.sample
        ));
    }
    md.push_str(&format!(
        "\nThe surface layer's bounds, in units of ε·S (forward outside the near-tangent band, backward over every \
         crossing; measured on {MEASURED_RAYS} random rays per kind and mode, `tests/surfaces/oracle.rs`, \
         `full_sweep_all_modes`):\n\n\
         | surface | mode | forward bound | measured | backward bound | measured |\n\
         | --- | --- | ---: | ---: | ---: | ---: |\n"
    ));
    for b in ERROR_BOUNDS {
        md.push_str(&format!(
            "| {:?} | {:?} | {} | {} | {} | {} |\n",
            b.kind, b.mode, b.forward, b.measured_forward, b.backward, b.measured_backward
        ));
    }
    Ok(crate::report::Section {
        title: "Tolerances".into(),
        markdown: md,
    })
}
