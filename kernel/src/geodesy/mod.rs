//! Geodesy on an oblate spheroid (Wartell et al. §2, §3.1–3.4 and Appendix A2): the ellipsoid, geodetic
//! (latitude ψ, longitude λ, height h) ↔ ECEF, the surface normal, the latitude cone of §3.4 and the meridian
//! half-planes of §3.3.
//!
//! * Forward: `X = (N + h) cos ψ cos λ`, `Y = (N + h) cos ψ sin λ`, `Z = (N (1 − e²) + h) sin ψ`, with the prime
//!   vertical radius `N(ψ) = a / sqrt(1 − e² sin² ψ)`.
//! * Reverse ([`Ellipsoid::ecef_to_geodetic`]): the closed-form solution of Vermeille (J. Geodesy 2002, 2011) in
//!   the formulation that GeographicLib's `Geocentric` class made robust: the quartic in the auxiliary
//!   unknown `k` is reduced to a resolvent cubic, solved by Cardano's formula when its discriminant is
//!   non-negative and by the trigonometric form otherwise, and every step is written so that no difference of
//!   nearly equal quantities is formed (the `u < 0` branch of `u + v`, the `w ≥ 0` clamp). Points inside the
//!   evolute on the equatorial plane (`R < a e²`, `z = 0`, where the latitude is not unique) take the explicit
//!   branch `sin ψ ∝ sqrt((e⁴ − p)/(1 − e²))`, `cos ψ ∝ sqrt(p)` (there `R = N e² cos ψ` and `h = −N(1 − e²)`).
//!   With `p = R²/a²`, `q = (1 − e²) z²/a²`, `r = (p + q − e⁴)/6`, `S = e⁴pq/4`, the resolvent cubic's real root
//!   is `u = r + T + r²/T`, `T³ = S + r³ ± sqrt(S(2r³ + S))` (sign chosen as the sign of `S + r³`), or
//!   `u = r + 2r cos(atan2(sqrt(−Δ), −(S + r³))/3)` when `Δ = S(2r³ + S) < 0`; then `v = sqrt(u² + e⁴q)`,
//!   `w = e²(u + v − q)/(2v)`, `k = (u + v)/(sqrt(u + v + w²) + w)`, `tan ψ = (z/k)/(R/(k + e²))`,
//!   `h = (1 − (1 − e²)/k)·hypot(kR/(k + e²), z)`.
//!   Accuracy (f64): the host test `geodesy_oracle` compares against an arbitrary-precision Newton inversion
//!   of the exact equations over 100 000+ points with heights in ±5000 km, including the poles, the z axis and
//!   points near the center, and asserts GeographicLib's documented bound (position error < 7 nm).
//! * [`Ellipsoid::latitude_cone`]: the cone `z = r tan ψ + k`, `k = Z_ψ − X_ψ tan ψ = −N(ψ) e² sin ψ`
//!   (§3.4, eq. 3.4-1), the locus of the normals at geodetic latitude ψ, as an [`AxialCone`](crate::surface::AxialCone) of zenith angle
//!   `θ = π/2 − ψ`. Its negative side is geodetic latitude `> ψ`, its positive side latitude `< ψ` (for points
//!   with `h > −b²/a`, where normals of different latitudes do not cross: Appendix A2).
//! * [`meridian_rad`]: the half-plane of longitude λ (§3.3; eq. 3.3-1 names the plane's normal with sin and cos
//!   swapped — the plane containing the meridian has normal `(−sin λ, cos λ, 0)`).
//!
//! ```
//! use curvicast::geodesy::Ellipsoid;
//! let wgs84 = Ellipsoid::<f64>::wgs84();
//! let p = wgs84.geodetic_rad_to_ecef(0.5, -1.2, 812.3);
//! let g = wgs84.ecef_to_geodetic(p);
//! assert!((g.lat_rad - 0.5).abs() < 1e-15 && (g.lon_rad + 1.2).abs() < 1e-15 && (g.h - 812.3).abs() < 1e-8);
//! ```

mod bounds;
mod ellipsoid;
mod relaxed;

pub use bounds::{
    HeightQuadBounds, QuadTrig, SideWalls, Wedge, chord_sagitta_bound, convex_interval,
    latitude_bulge_bound, upper_spheroid,
};
pub use ellipsoid::{
    Ellipsoid, GeodesyError, Geodetic, WGS84_A, WGS84_F, cbrt, hypot, meridian_deg, meridian_rad,
    sin_cos_deg,
};
pub use relaxed::{RelaxedVolume, relaxed_interval};
