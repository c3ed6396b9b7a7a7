//! The two choices every marching command, scene and table makes, as one type each: the scalar the kernel runs in
//! ([`Precision`]) and the marching engine ([`Engine`]). The command line (clap), the scene files (serde) and the
//! harness's tables all use these.

use serde::Deserialize;

/// Which scalar the kernel runs in: `"f64"`, `"f32"` or `"f32-fast"` on the command line and in scene files.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, clap::ValueEnum, Deserialize)]
pub enum Precision {
    /// IEEE binary64 with the exact math backend.
    #[default]
    #[serde(rename = "f64")]
    F64,
    /// IEEE binary32 with the exact math backend (correctly rounded square root).
    #[serde(rename = "f32")]
    F32,
    /// binary32 with the fast math backend (`curvicast::F32Fast`: micromath's inverse-square-root estimate refined
    /// by Newton steps).
    #[value(name = "f32-fast")]
    #[serde(rename = "f32-fast")]
    F32Fast,
}

impl Precision {
    /// Every precision, in the tables' order.
    pub const ALL: [Precision; 3] = [Precision::F64, Precision::F32, Precision::F32Fast];

    /// The name on the command line and in tables.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F64 => "f64",
            Precision::F32 => "f32",
            Precision::F32Fast => "f32-fast",
        }
    }

    /// The machine epsilon of the scalar: the unit of its errors.
    pub fn eps(self) -> f64 {
        match self {
            Precision::F64 => f64::EPSILON,
            Precision::F32 | Precision::F32Fast => f64::from(f32::EPSILON),
        }
    }

    /// The largest finite value of the scalar (a `t` beyond it rounds to ±∞).
    pub fn max_finite(self) -> f64 {
        match self {
            Precision::F64 => f64::MAX,
            Precision::F32 | Precision::F32Fast => f64::from(f32::MAX),
        }
    }
}

/// Which engine marches (Hannasch).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Engine {
    /// The serial, constant-memory engine (Hannasch ch. 5): `grid.march(&ray)`.
    Serial,
    /// The separable engine (Hannasch §3), buffers sized from the grid: `grid.march_separable::<N>(&ray)`.
    Separable,
}
