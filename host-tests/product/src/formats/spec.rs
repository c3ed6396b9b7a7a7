//! The input formats of the `curvicast` command-line contract (rays, grids), shared by the CLI, the oracle and
//! the tests. Plain data in `f64`; validation against the kernel's rules happens where they are used.

use serde::{Deserialize, Serialize};

/// One ray of a rays file: `{"origin": [x, y, z], "dir": [dx, dy, dz], "t_min": 0.0, "t_max": 25.0}`.
///
/// `t_min` defaults to 0 and `t_max` to +∞ (omitted, or `null`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RaySpec {
    /// The origin.
    pub origin: [f64; 3],
    /// The direction (not necessarily unit; t is in its units).
    pub dir: [f64; 3],
    /// Lower end of the interval.
    #[serde(default)]
    pub t_min: f64,
    /// Upper end of the interval; `None` is +∞.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_max: Option<f64>,
}

impl RaySpec {
    /// A ray over `[0, +∞)`.
    pub fn new(origin: [f64; 3], dir: [f64; 3]) -> Self {
        RaySpec {
            origin,
            dir,
            t_min: 0.0,
            t_max: None,
        }
    }
    /// The upper end as a number (+∞ when absent).
    pub fn t_max_or_inf(&self) -> f64 {
        self.t_max.unwrap_or(f64::INFINITY)
    }
}

/// A grid file of `curvicast march` (angles in radians).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum GridSpec {
    /// Spherical (r, θ zenith, φ azimuth); cell `[i, j, k]`.
    Spherical {
        /// Center (default origin).
        #[serde(default)]
        center: Option<[f64; 3]>,
        /// Radius breakpoints.
        r: Vec<f64>,
        /// Zenith breakpoints in [0, π].
        theta: Vec<f64>,
        /// Azimuth breakpoints, span ≤ 2π.
        phi: Vec<f64>,
    },
    /// Cylindrical (ρ, φ, z); cell `[i, k, m]`.
    Cylindrical {
        /// Center (default origin).
        #[serde(default)]
        center: Option<[f64; 3]>,
        /// Radius breakpoints.
        rho: Vec<f64>,
        /// Azimuth breakpoints.
        phi: Vec<f64>,
        /// Height breakpoints.
        z: Vec<f64>,
    },
    /// 2-D polar (r, φ); cell `[i, k]`; the rays' z components are ignored.
    Polar {
        /// Center (default origin).
        #[serde(default)]
        center: Option<[f64; 2]>,
        /// Radius breakpoints.
        r: Vec<f64>,
        /// Azimuth breakpoints.
        phi: Vec<f64>,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_defaults() {
        let r: RaySpec =
            serde_json::from_str(r#"{"origin": [0, 0, 0], "dir": [1, 0, 0]}"#).unwrap();
        assert_eq!(r.t_min, 0.0);
        assert_eq!(r.t_max_or_inf(), f64::INFINITY);
        assert!(
            serde_json::from_str::<RaySpec>(r#"{"origin": [0, 0], "dir": [1, 0, 0]}"#).is_err()
        );
    }

    #[test]
    fn grid_kinds() {
        let g: GridSpec = serde_json::from_str(
            r#"{"kind": "spherical", "r": [0.0, 1.0], "theta": [0.0, 3.14], "phi": [0.0, 6.28]}"#,
        )
        .unwrap();
        assert!(matches!(g, GridSpec::Spherical { center: None, .. }));
        let g: GridSpec = serde_json::from_str(
            r#"{"kind": "polar", "center": [1, 2], "r": [0.0, 1.0], "phi": [0.0, 1.0]}"#,
        )
        .unwrap();
        assert!(matches!(
            g,
            GridSpec::Polar {
                center: Some([1.0, 2.0]),
                ..
            }
        ));
    }
}
