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
//!   (§3.4, eq. 3.4-1), the locus of the normals at geodetic latitude ψ, as an [`AxialCone`] of zenith angle
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

pub use bounds::{
    HeightQuadBounds, QuadTrig, RelaxedVolume, SideWalls, Wedge, chord_sagitta_bound,
    convex_interval, latitude_bulge_bound, relaxed_interval, upper_spheroid,
};

use crate::real::Real;
use crate::surface::{AxialCone, HalfPlane, Spheroid, SurfaceError};
use crate::vec3::V3;

/// Why a geodetic quantity could not be formed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GeodesyError {
    /// A parameter is NaN or infinite.
    NonFinite,
    /// The axes do not satisfy `a ≥ b > 0`.
    BadAxes,
    /// A height at or below `−b²/a`: the parallel surface degenerates there (Wartell et al. Appendix A2), so no bound
    /// of §3.1 exists.
    HeightTooLow,
    /// A latitude outside `[−π/2, π/2]`.
    LatitudeOutOfRange,
    /// A triangle edge `d` too long for the chord-sagitta bound ([`chord_sagitta_bound`]): it needs
    /// `d < √1.5 · (b²/a + h_min)`, about 7 700 km on the Earth, so DEM cells must span less than about 70°.
    TriangleTooLarge,
}

impl core::fmt::Display for GeodesyError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            GeodesyError::NonFinite => "geodetic parameter is not finite",
            GeodesyError::BadAxes => "ellipsoid axes must satisfy a >= b > 0",
            GeodesyError::HeightTooLow => {
                "height at or below -b^2/a (no height-quad bound exists there)"
            }
            GeodesyError::LatitudeOutOfRange => "latitude outside [-90, 90] degrees",
            GeodesyError::TriangleTooLarge => {
                "triangle edge longer than the chord bound allows (sqrt(1.5) (b^2/a + h_min), about 7700 km on \
                 the Earth): DEM cells must span less than about 70 degrees"
            }
        })
    }
}

impl core::error::Error for GeodesyError {}

impl From<SurfaceError> for GeodesyError {
    fn from(e: SurfaceError) -> Self {
        match e {
            SurfaceError::NonFinite => GeodesyError::NonFinite,
            SurfaceError::BadAxes => GeodesyError::BadAxes,
            SurfaceError::AngleOutOfRange => GeodesyError::LatitudeOutOfRange,
        }
    }
}

/// Geodetic coordinates: latitude and longitude in radians, height in the ellipsoid's length unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geodetic<T> {
    /// Geodetic latitude ψ, radians, in `[−π/2, π/2]`.
    pub lat_rad: T,
    /// Longitude λ, radians, in `[−π, π]`.
    pub lon_rad: T,
    /// Height above the ellipsoid along its normal.
    pub h: T,
}

/// An oblate spheroid (`a ≥ b > 0`; a sphere when `a = b`) with its derived constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipsoid<T> {
    a: T,
    b: T,
    /// e² = (a² − b²)/a², formed as (a − b)(a + b)/a² (no cancellation).
    e2: T,
    /// 1 − e² = b²/a².
    e2m: T,
    /// e⁴.
    e4: T,
}

/// WGS84 semi-major axis (m).
pub const WGS84_A: f64 = 6_378_137.0;
/// WGS84 flattening.
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;

impl<T: Real> Ellipsoid<T> {
    /// The ellipsoid with semi-axes `a` (equatorial) and `b` (polar).
    pub fn new(a: T, b: T) -> Result<Self, GeodesyError> {
        if !a.is_finite() || !b.is_finite() {
            return Err(GeodesyError::NonFinite);
        }
        if !(b > T::ZERO && a >= b) {
            return Err(GeodesyError::BadAxes);
        }
        let a2 = a * a;
        if !a2.is_finite() || !(a2 > T::ZERO) {
            return Err(GeodesyError::BadAxes);
        }
        let e2 = (a - b) * (a + b) / a2;
        let e2m = (b / a) * (b / a);
        Ok(Ellipsoid {
            a,
            b,
            e2,
            e2m,
            e4: e2 * e2,
        })
    }

    /// WGS84: `a = 6378137 m`, `f = 1/298.257223563`, `b = a(1 − f)`.
    pub fn wgs84() -> Self {
        let a = WGS84_A;
        let b = a * (1.0 - WGS84_F);
        let e2 = WGS84_F * (2.0 - WGS84_F);
        Ellipsoid {
            a: T::from_f64(a),
            b: T::from_f64(b),
            e2: T::from_f64(e2),
            e2m: T::from_f64((1.0 - WGS84_F) * (1.0 - WGS84_F)),
            e4: T::from_f64(e2 * e2),
        }
    }

    /// The equatorial semi-axis a.
    #[inline]
    pub fn a(&self) -> T {
        self.a
    }
    /// The polar semi-axis b.
    #[inline]
    pub fn b(&self) -> T {
        self.b
    }
    /// The first eccentricity squared e².
    #[inline]
    pub fn e2(&self) -> T {
        self.e2
    }
    /// `−b²/a`: heights must stay strictly above it (Appendix A2).
    #[inline]
    pub fn min_height(&self) -> T {
        -(self.b * (self.b / self.a))
    }
    /// The ellipsoid as a [`Spheroid`] surface (height 0).
    pub fn spheroid(&self) -> Result<Spheroid<T>, GeodesyError> {
        Ok(Spheroid::new(self.a, self.b)?)
    }

    /// The prime vertical radius of curvature `N(ψ) = a / sqrt(1 − e² sin²ψ)` from `sin ψ`.
    #[inline]
    pub fn prime_vertical_radius(&self, sin_lat: T) -> T {
        self.a / (T::ONE - self.e2 * sin_lat * sin_lat).sqrt()
    }

    /// ECEF of the geodetic point given by the sines and cosines of its latitude and longitude.
    #[inline]
    pub fn ecef_from_sin_cos(&self, sin_lat: T, cos_lat: T, sin_lon: T, cos_lon: T, h: T) -> V3<T> {
        let n = self.prime_vertical_radius(sin_lat);
        self.ecef_from_parts(sin_lat, cos_lat, n, sin_lon, cos_lon, h)
    }

    /// [`Ellipsoid::ecef_from_sin_cos`] with the prime vertical radius `n` of the latitude given (a picker
    /// computes it once per grid row); the same value bit for bit.
    #[inline]
    pub fn ecef_from_parts(
        &self,
        sin_lat: T,
        cos_lat: T,
        n: T,
        sin_lon: T,
        cos_lon: T,
        h: T,
    ) -> V3<T> {
        let rho = (n + h) * cos_lat;
        V3::new(rho * cos_lon, rho * sin_lon, (n * self.e2m + h) * sin_lat)
    }

    /// ECEF of the geodetic point (latitude, longitude in radians).
    pub fn geodetic_rad_to_ecef(&self, lat_rad: T, lon_rad: T, h: T) -> V3<T> {
        let (lat, lon) = (lat_rad, lon_rad);
        self.ecef_from_sin_cos(lat.sin(), lat.cos(), lon.sin(), lon.cos(), h)
    }

    /// ECEF of the geodetic point (latitude, longitude in degrees). Multiples of 90° are exact (a pole row maps to
    /// one point on the z axis; see [`sin_cos_deg`]).
    pub fn geodetic_deg_to_ecef(&self, lat_deg: T, lon_deg: T, h: T) -> V3<T> {
        let (sl, cl) = sin_cos_deg(lat_deg);
        let (so, co) = sin_cos_deg(lon_deg);
        self.ecef_from_sin_cos(sl, cl, so, co, h)
    }

    /// The outward unit normal of the ellipsoid at geodetic latitude / longitude in radians.
    pub fn normal_rad(&self, lat_rad: T, lon_rad: T) -> V3<T> {
        let (cl, sl) = (lat_rad.cos(), lat_rad.sin());
        V3::new(cl * lon_rad.cos(), cl * lon_rad.sin(), sl)
    }

    /// The outward unit normal of the ellipsoid at geodetic latitude / longitude in degrees (the unit of
    /// [`crate::terrain::Grid`]); exact at multiples of 90° (see [`sin_cos_deg`]).
    ///
    /// ```
    /// use curvicast::geodesy::Ellipsoid;
    /// let n = Ellipsoid::<f64>::wgs84().normal_deg(90.0, 0.0);
    /// assert_eq!((n.x, n.y, n.z), (0.0, 0.0, 1.0));
    /// ```
    pub fn normal_deg(&self, lat_deg: T, lon_deg: T) -> V3<T> {
        let (sl, cl) = sin_cos_deg(lat_deg);
        let (so, co) = sin_cos_deg(lon_deg);
        V3::new(cl * co, cl * so, sl)
    }

    /// `X_ψ` and `Z_ψ` of §3.4: the point of the meridian ellipse (y = 0, x ≥ 0) at geodetic latitude ψ, from
    /// `sin ψ`, `cos ψ`: `X_ψ = a cos ψ / W`, `Z_ψ = a (1 − e²) sin ψ / W`, `W = sqrt(1 − e² sin²ψ)`.
    pub fn x_z_psi(&self, sin_lat: T, cos_lat: T) -> (T, T) {
        let n = self.prime_vertical_radius(sin_lat);
        (n * cos_lat, n * self.e2m * sin_lat)
    }

    /// The apex `k = Z_ψ − X_ψ tan ψ = −N(ψ) e² sin ψ` of the latitude cone (eq. 3.4-1), in the cancellation-free
    /// closed form.
    pub fn latitude_cone_apex(&self, sin_lat: T) -> T {
        -(self.prime_vertical_radius(sin_lat) * self.e2 * sin_lat)
    }

    /// The latitude cone of §3.4 (eq. 3.4-1) for geodetic latitude ψ given by `sin ψ`, `cos ψ ≥ 0`: the
    /// [`AxialCone`] with apex `(0, 0, −N(ψ)e² sin ψ)` and zenith angle `θ = π/2 − ψ`. Negative side: latitude
    /// above ψ. At ψ = ±90° the cone degenerates to the z axis (no wall is needed there).
    pub fn latitude_cone(&self, sin_lat: T, cos_lat: T) -> Result<AxialCone<T>, GeodesyError> {
        if !(cos_lat >= T::ZERO) {
            return Err(GeodesyError::LatitudeOutOfRange);
        }
        Ok(AxialCone::from_cos_sin(
            self.latitude_cone_apex(sin_lat),
            sin_lat,
            cos_lat,
        )?)
    }

    /// ECEF → geodetic (Vermeille's closed form; see the module docs). Robust at the poles, on the z axis, at
    /// the center and inside the evolute. Non-finite input gives NaN output.
    pub fn ecef_to_geodetic(&self, p: V3<T>) -> Geodetic<T> {
        let (x, y, z) = (p.x, p.y, p.z);
        let r_xy = hypot(x, y);
        let lon = if r_xy == T::ZERO { T::ZERO } else { y.atan2(x) };
        let (sin_lat, cos_lat, h) = self.reverse_meridian(r_xy, z);
        Geodetic {
            lat_rad: sin_lat.atan2(cos_lat),
            lon_rad: lon,
            h,
        }
    }

    /// ECEF → geodetic `(latitude°, longitude°, h)` for a point near a known latitude ψ₀ and longitude λ₀, each
    /// given in degrees with its sine and cosine (a grid vertex near a terrain hit, whose trigonometry a storage
    /// caches), without the closed form's `cbrt` and arctangents; `None` where it does not apply, and the caller
    /// uses [`Ellipsoid::ecef_to_geodetic`] instead.
    ///
    /// * Longitude: the point turned by −λ₀ about the z axis is `(R cos Δλ, R sin Δλ)`; `Δλ` is the arctangent
    ///   of their ratio `w` by its series to `w⁹` (the next term is below `2e-20` for `|w| ≤ 0.02`), so
    ///   `λ = λ₀ + Δλ`, wrapped into `(−180°, 180°]`. `None` beyond `|w| = 0.02` (1.1°), on the z axis, or
    ///   for λ₀ more than a turn outside ±180°.
    /// * Latitude: Newton steps from ψ₀ on the condition that the point lies on the normal at φ,
    ///   `f(φ) = R sin φ − z cos φ − e² N sin φ cos φ = 0`, with
    ///   `f′ = R cos φ + z sin φ − e² N (cos²φ − sin²φ) − e⁴ N sin²φ cos²φ / W²` (`W² = 1 − e² sin²φ`). Near the
    ///   root `f″/2f′ ≈ e²/2`, so a step of size `s` leaves an error of about `e² s²/2`: from a seed one grid
    ///   cell of 3″ away the second step is below 1e-12 rad, from 1/3° the third. The sine and cosine of
    ///   `ψ₀ + δ` come from ψ₀'s by the addition theorem and the series of `sin δ`, `cos δ` (`|δ| ≤ 0.02`).
    ///   The iteration stops once a step is below `√ε` (what it leaves is then below `e² ε / 2`); `None` if
    ///   that takes more than three steps, a step exceeds 0.02 or the latitude would pass a pole.
    /// * Height: `h = R cos φ + z sin φ − a W`.
    ///
    /// Each term is formed to a few ulps of the coordinates, like the closed form; the host test
    /// `geodesy_oracle` holds both to GeographicLib's bound (7 nm).
    ///
    /// ```
    /// use curvicast::geodesy::{Ellipsoid, sin_cos_deg};
    /// let e = Ellipsoid::<f64>::wgs84();
    /// let p = e.geodetic_deg_to_ecef(45.0004, -117.9993, 812.3);
    /// let (sl, cl) = sin_cos_deg(45.0);
    /// let (so, co) = sin_cos_deg(-118.0);
    /// let (lat, lon, h) = e.ecef_to_geodetic_near(p, (45.0, sl, cl), (-118.0, so, co)).unwrap();
    /// assert!((lat - 45.0004).abs() < 1e-12 && (lon + 117.9993).abs() < 1e-12 && (h - 812.3).abs() < 1e-8);
    /// ```
    pub fn ecef_to_geodetic_near(
        &self,
        p: V3<T>,
        (lat0_deg, s0, c0): (T, T, T),
        (lon0_deg, sl, cl): (T, T, T),
    ) -> Option<(T, T, T)> {
        let limit = T::from_f64(0.02);
        let deg = T::from_f64(180.0) / T::PI;
        // Longitude.
        let (v, u) = (cl * p.x + sl * p.y, cl * p.y - sl * p.x);
        if !(v > T::ZERO && u.abs() <= limit * v) {
            return None;
        }
        let w = u / v;
        let w2 = w * w;
        let third = T::ONE / T::from_f64(3.0);
        let (fifth, seventh, ninth) = (
            T::from_f64(0.2),
            T::ONE / T::from_f64(7.0),
            T::ONE / T::from_f64(9.0),
        );
        let d_lon = w * (T::ONE - w2 * (third - w2 * (fifth - w2 * (seventh - w2 * ninth))));
        let mut lon = lon0_deg + d_lon * deg;
        let (half, full) = (T::from_f64(180.0), T::from_f64(360.0));
        if lon > half {
            lon -= full;
        } else if lon <= -half {
            lon += full;
        }
        if !(lon > -half && lon <= half) {
            return None; // a seed more than a turn off
        }
        // Latitude.
        let (r, z) = ((p.x * p.x + p.y * p.y).sqrt(), p.z);
        let (a, e2, e4) = (self.a, self.e2, self.e4);
        let tol = T::EPSILON.sqrt();
        let (mut delta, mut s, mut c) = (T::ZERO, s0, c0);
        for _ in 0..3 {
            let inv_w = T::ONE / (T::ONE - e2 * s * s).sqrt();
            let n = a * inv_w;
            let f = r * s - z * c - e2 * n * s * c;
            let fp = r * c + z * s
                - e2 * n * (c * c - s * s)
                - e4 * n * (s * s) * (c * c) * (inv_w * inv_w);
            let step = -f / fp;
            if !(step.abs() <= limit) {
                return None;
            }
            delta += step;
            if !(delta.abs() <= limit) {
                return None;
            }
            let d2 = delta * delta;
            let sin_d = delta
                * (T::ONE
                    - d2 / T::from_f64(6.0)
                        * (T::ONE - d2 / T::from_f64(20.0) * (T::ONE - d2 / T::from_f64(42.0))));
            let cos_d = T::ONE
                - d2 / T::TWO
                    * (T::ONE
                        - d2 / T::from_f64(12.0)
                            * (T::ONE
                                - d2 / T::from_f64(30.0) * (T::ONE - d2 / T::from_f64(56.0))));
            s = s0 * cos_d + c0 * sin_d;
            c = c0 * cos_d - s0 * sin_d;
            if !(c >= T::ZERO) {
                return None;
            }
            if step.abs() <= tol {
                let h = r * c + z * s - a * (T::ONE - e2 * s * s).sqrt();
                let lat = lat0_deg + delta * deg;
                return (lat.is_finite() && lon.is_finite() && h.is_finite())
                    .then_some((lat, lon, h));
            }
        }
        None
    }

    /// The reverse problem in the meridian plane: `(sin ψ, cos ψ, h)` from the distance to the axis `R ≥ 0` and
    /// `z`.
    pub fn reverse_meridian(&self, r_xy: T, z: T) -> (T, T, T) {
        let a = self.a;
        let (e2, e4, e2m) = (self.e2, self.e4, self.e2m);
        let p = (r_xy / a).sq();
        let q = e2m * (z / a).sq();
        let r = (p + q - e4) / T::from_f64(6.0);
        if e4 == T::ZERO {
            // a sphere: geocentric = geodetic.
            let hh = hypot(r_xy, z);
            if hh == T::ZERO {
                return (T::ZERO, T::ONE, -a);
            }
            return (z / hh, r_xy / hh, hh - a);
        }
        if !(e4 * q == T::ZERO && r <= T::ZERO) {
            // Not on the equatorial disc inside the evolute.
            let s = e4 * p * q / T::from_f64(4.0);
            let r2 = r * r;
            let r3 = r * r2;
            let disc = s * (T::TWO * r3 + s);
            let mut u = r;
            if disc >= T::ZERO {
                let mut t3 = s + r3;
                // Pick the sign of the square root that avoids cancellation (t3 is then far from 0).
                t3 += disc.sqrt().with_sign_of(t3);
                let t = cbrt(t3);
                u += t + if t != T::ZERO { r2 / t } else { T::ZERO };
            } else {
                // Three real roots; the trigonometric form picks the largest.
                let ang = (-disc).sqrt().atan2(-(s + r3));
                u += T::TWO * r * (ang / T::from_f64(3.0)).cos();
            }
            let v = (u * u + e4 * q).sqrt();
            // u + v without cancellation when u < 0.
            let uv = if u < T::ZERO { e4 * q / (v - u) } else { u + v };
            let w = (e2 * (uv - q) / (T::TWO * v)).max(T::ZERO);
            let k = uv / ((uv + w * w).sqrt() + w);
            let k2 = k + e2;
            let d = k * r_xy / k2;
            let zz = z / k;
            let xx = r_xy / k2;
            let hh = hypot(zz, xx);
            let h = (T::ONE - e2m / k) * hypot(d, z);
            if hh == T::ZERO || !hh.is_finite() {
                return (T::NAN, T::NAN, T::NAN);
            }
            (zz / hh, xx / hh, h)
        } else {
            // The equatorial disc inside the evolute (z = 0, R ≤ a e²): the nearest foot points are at
            // ±ψ with R = N e² cos ψ; h = −N(1 − e²).
            let zz = ((e4 - p) / e2m).max(T::ZERO).sqrt();
            let xx = p.sqrt();
            let hh = hypot(zz, xx);
            let mut s = zz / hh;
            let c = xx / hh;
            if z < T::ZERO {
                s = -s;
            }
            (s, c, -(a * e2m * hh / e2))
        }
    }
}

/// `sqrt(x² + y²)` without overflow or underflow of the squares (scaled by the larger magnitude).
#[inline]
pub fn hypot<T: Real>(x: T, y: T) -> T {
    let (x, y) = (x.abs(), y.abs());
    let m = x.max(y);
    if m == T::ZERO || !m.is_finite() {
        return m;
    }
    let (xs, ys) = (x / m, y / m);
    m * (xs * xs + ys * ys).sqrt()
}

/// The real cube root ([`Real::cbrt`]: libm's in `f64`, a routine in `f32` arithmetic within 1 ulp in `f32`, so
/// that an `f32` geodetic conversion needs no software double precision on a single-precision FPU).
#[inline]
pub fn cbrt<T: Real>(x: T) -> T {
    x.cbrt()
}

/// `(sin x, cos x)` for `x` in degrees, exact at multiples of 90° (the angle is reduced to `[−45°, 45°]` first, so
/// `sin_cos_deg(90) = (1, 0)` and a pole row maps exactly onto the z axis).
///
/// Computed in the scalar's own arithmetic (no `f64` in `f32`): the reduction `r = x − 90 q` is exact while
/// `90 q` is (|x| below 2²⁴·90/2⁷, about 1.2e7 degrees, in `f32`; 2⁵³·90/2⁷ in `f64`), and `r` is converted to
/// radians with `π/180` split into a leading part and the rest (`f64`: the rest is 0). In `f32` the results are
/// within 1.44 ulp of the `f64` ones of the same angles (measured over [−720°, 720°] by the test
/// `sin_cos_deg_f32_within_2_ulp_of_f64`).
pub fn sin_cos_deg<T: Real>(x: T) -> (T, T) {
    if !x.is_finite() {
        return (T::NAN, T::NAN);
    }
    let ninety = T::from_i32(90);
    // q = nearest multiple of 90.
    let q = (x / ninety).round();
    let r = x - q * ninety;
    // π/180 = hi + lo in the scalar (constants: both fold at compile time).
    let rad_hi = T::from_f64(core::f64::consts::PI / 180.0);
    let rad_lo = T::from_f64(core::f64::consts::PI / 180.0 - rad_hi.to_f64());
    let rad = r * rad_hi + r * rad_lo;
    let (s, c) = (rad.sin(), rad.cos());
    // q mod 4 in [0, 4): q − 4 round(q/4) is exact (an integer in [−2, 2]).
    let four = T::from_i32(4);
    let quadrant = q - four * (q / four).round();
    let quadrant = if quadrant < T::ZERO {
        quadrant + four
    } else {
        quadrant
    };
    let half = T::HALF;
    let (one_half, two_half) = (T::ONE + half, T::TWO + half);
    // 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s). `+ 0` turns −0 into +0.
    let (s, c) = if quadrant < half {
        (s, c)
    } else if quadrant < one_half {
        (c, -s)
    } else if quadrant < two_half {
        (-s, -c)
    } else {
        (-c, s)
    };
    (s + T::ZERO, c + T::ZERO)
}

/// The meridian half-plane of longitude `lon_rad` (radians) (§3.3): its positive side is east (increasing λ).
pub fn meridian_rad<T: Real>(lon_rad: T) -> Result<HalfPlane<T>, GeodesyError> {
    Ok(HalfPlane::from_azimuth_rad(lon_rad)?)
}

/// The meridian half-plane of longitude `lon_deg` (degrees), exact at multiples of 90°.
pub fn meridian_deg<T: Real>(lon_deg: T) -> Result<HalfPlane<T>, GeodesyError> {
    let (s, c) = sin_cos_deg(lon_deg);
    Ok(HalfPlane::from_cos_sin(c, s)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Side, Surface};

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn wgs84_constants() {
        let e = Ellipsoid::<f64>::wgs84();
        assert_eq!(e.a(), 6378137.0);
        assert!(close(e.b(), 6356752.314245179, 1e-8));
        assert!(close(e.min_height(), -6335439.3272928195, 1e-6));
    }

    #[test]
    fn forward_closed_forms_at_equator_and_pole() {
        let e = Ellipsoid::<f64>::wgs84();
        let p = e.geodetic_deg_to_ecef(0.0, 90.0, 10.0);
        assert_eq!(p.to_array(), [0.0, 6378147.0, 0.0]);
        let pole = e.geodetic_deg_to_ecef(90.0, 37.0, 0.0);
        assert_eq!(pole.x, 0.0);
        assert_eq!(pole.y, 0.0);
        assert!(close(pole.z, e.b(), 1e-8));
        let south = e.geodetic_deg_to_ecef(-90.0, -123.0, -5.0);
        assert_eq!((south.x, south.y), (0.0, 0.0));
        assert!(close(south.z, -(e.b() - 5.0), 1e-8));
    }

    #[test]
    fn sin_cos_deg_exact_quadrants() {
        assert_eq!(sin_cos_deg(90.0_f64), (1.0, 0.0));
        assert_eq!(sin_cos_deg(-90.0_f64), (-1.0, 0.0));
        assert_eq!(sin_cos_deg(180.0_f64), (0.0, -1.0));
        assert_eq!(sin_cos_deg(270.0_f64), (-1.0, 0.0));
        assert_eq!(sin_cos_deg(-180.0_f64), (0.0, -1.0));
        let (s, c) = sin_cos_deg(30.0_f64);
        assert!(close(s, 0.5, 2e-16) && close(c, 0.75_f64.sqrt(), 2e-16));
    }

    /// The `f32` sine and cosine of degrees (reduction, conversion to radians and `sin_cos_f32` all in `f32`)
    /// against the `f64` ones of the same angles, in ulps of the `f32` result, on a sweep of [−720°, 720°]
    /// (2¹⁶ + 1 angles; 2¹⁰ + 1 under Miri) and the multiples of 90°, which stay exact.
    #[test]
    fn sin_cos_deg_f32_within_2_ulp_of_f64() {
        let ulps = |got: f32, want: f64| {
            let w = want as f32;
            let ulp = f64::from(f32::from_bits(w.abs().to_bits() + 1) - w.abs());
            (f64::from(got) - want).abs() / ulp
        };
        let n: u32 = if cfg!(miri) { 1 << 10 } else { 1 << 16 };
        let mut worst = 0.0_f64;
        for i in 0..=n {
            let x = -720.0 + 1440.0 * (i as f32) / (n as f32);
            let (s, c) = sin_cos_deg(x);
            let (s64, c64) = sin_cos_deg(f64::from(x));
            worst = worst.max(ulps(s, s64)).max(ulps(c, c64));
        }
        std::println!("sin_cos_deg::<f32>: worst {worst:.3} ulp");
        assert!(worst <= 2.0, "{worst} ulp");
        for k in -8..=8 {
            let (s, c) = sin_cos_deg(90.0_f32 * k as f32);
            let (s64, c64) = sin_cos_deg(90.0 * f64::from(k));
            assert_eq!((f64::from(s), f64::from(c)), (s64, c64), "{k} × 90°");
        }
    }

    /// The `f32` geodetic conversion (its cube root in `f32`, `cbrt_f32`) against the `f64` one of the same
    /// ECEF points, near the WGS84 surface: latitude error in radians and height error in meters.
    #[test]
    fn reverse_f32_against_f64() {
        let (e32, e64) = (Ellipsoid::<f32>::wgs84(), Ellipsoid::<f64>::wgs84());
        let (mut dlat, mut dh) = (0.0_f64, 0.0_f64);
        for i in 0..200 {
            let lat = -1.5 + 3.0 * f64::from(i) / 200.0;
            let lon = 0.1 * f64::from(i);
            let h = 9000.0 * f64::from(i % 7) - 3000.0;
            let p = e64.geodetic_rad_to_ecef(lat, lon, h);
            let p32 = V3::new(p.x as f32, p.y as f32, p.z as f32);
            let g32 = e32.ecef_to_geodetic(p32);
            let g64 = e64.ecef_to_geodetic(V3::new(
                f64::from(p32.x),
                f64::from(p32.y),
                f64::from(p32.z),
            ));
            dlat = dlat.max((f64::from(g32.lat_rad) - g64.lat_rad).abs());
            dh = dh.max((f64::from(g32.h) - g64.h).abs());
        }
        std::println!("ecef_to_geodetic::<f32>: worst latitude {dlat:.3e} rad, height {dh:.3} m");
        assert!(dlat <= 1e-6 && dh <= 2.0, "{dlat} rad, {dh} m");
    }

    #[test]
    fn reverse_round_trip_assorted() {
        let e = Ellipsoid::<f64>::wgs84();
        for &(lat, lon, h) in &[
            (0.3, 0.1, 0.0),
            (-1.2, 2.9, 1234.5),
            (1.5, -3.0, -4000.0),
            (0.0, 0.0, 0.0),
            (-0.7, 1.0, 4.0e6),
            (0.9, -0.4, -4.5e6),
            (1e-9, 0.2, 300.0),
        ] {
            let g = e.ecef_to_geodetic(e.geodetic_rad_to_ecef(lat, lon, h));
            assert!(close(g.lat_rad, lat, 2e-15), "{lat} {}", g.lat_rad);
            assert!(close(g.lon_rad, lon, 2e-15));
            assert!(close(g.h, h, 2e-8), "{h} {}", g.h);
        }
    }

    #[test]
    fn reverse_on_the_z_axis_and_at_the_center() {
        let e = Ellipsoid::<f64>::wgs84();
        let g = e.ecef_to_geodetic(V3::new(0.0, 0.0, 7.0e6));
        assert_eq!((g.lat_rad, g.lon_rad), (core::f64::consts::FRAC_PI_2, 0.0));
        assert!(close(g.h, 7.0e6 - e.b(), 1e-8));
        let g = e.ecef_to_geodetic(V3::new(0.0, 0.0, -100.0));
        assert_eq!(g.lat_rad, -core::f64::consts::FRAC_PI_2);
        assert!(close(g.h, 100.0 - e.b(), 1e-8));
        // The center: nearest surface points are the poles, h = −b.
        let g = e.ecef_to_geodetic(V3::new(0.0, 0.0, 0.0));
        assert!(close(g.h, -e.b(), 1e-8), "{}", g.h);
        assert!(close(g.lat_rad.abs(), core::f64::consts::FRAC_PI_2, 1e-12));
    }

    #[test]
    fn reverse_inside_the_evolute_on_the_equatorial_plane() {
        // R = N e² cos ψ, h = −N(1 − e²): take ψ = 30°.
        let e = Ellipsoid::<f64>::wgs84();
        let (s, c) = (0.5_f64, 0.75_f64.sqrt());
        let n = e.prime_vertical_radius(s);
        let g = e.ecef_to_geodetic(V3::new(n * e.e2() * c, 0.0, 0.0));
        assert!(
            close(g.lat_rad.abs(), core::f64::consts::FRAC_PI_6, 1e-9),
            "{}",
            g.lat_rad
        );
        assert!(close(g.h, -n * (1.0 - e.e2()), 1e-6));
    }

    #[test]
    fn reverse_sphere_is_geocentric() {
        let e = Ellipsoid::new(10.0_f64, 10.0).unwrap();
        let g = e.ecef_to_geodetic(V3::new(3.0, 4.0, 12.0));
        assert!(close(g.h, 3.0, 1e-14));
        // libm, not std: Miri perturbs std's transcendental results by a few ulps.
        assert!(close(g.lat_rad, libm::atan2(12.0, 5.0), 1e-15));
    }

    #[test]
    fn reverse_f32_is_close() {
        let e = Ellipsoid::<f32>::wgs84();
        let p = e.geodetic_rad_to_ecef(0.7, 0.2, 100.0);
        let g = e.ecef_to_geodetic(p);
        assert!(
            (g.lat_rad - 0.7).abs() < 1e-6 && (g.h - 100.0).abs() < 2.0,
            "{g:?}"
        );
    }

    #[test]
    fn latitude_cone_contains_the_normal_line() {
        let e = Ellipsoid::<f64>::wgs84();
        let (s, c) = sin_cos_deg(52.0);
        let cone = e.latitude_cone(s, c).unwrap();
        let (xp, zp) = e.x_z_psi(s, c);
        // X_ψ, Z_ψ and the apex are collinear along the normal (eq. 3.4-1: k = Z − X tan ψ).
        assert!(close(cone.apex_z(), zp - xp * s / c, 1e-6));
        // A point on the normal line at height 3000 m lies on the cone; 1 m further north is on the negative side.
        let on = e.geodetic_deg_to_ecef(52.0, 10.0, 3000.0);
        let n = e.normal_rad(52.0_f64.to_radians(), 10.0_f64.to_radians());
        let north = V3::new(-s * n.x / c, -s * n.y / c, c);
        let inside = on.add_scaled(1.0, north);
        assert_eq!(cone.side_of(inside), Some(Side::Negative));
        assert_eq!(
            cone.side_of(on.add_scaled(-1.0, north)),
            Some(Side::Positive)
        );
    }

    #[test]
    fn typed_errors() {
        assert_eq!(Ellipsoid::new(1.0, 2.0), Err(GeodesyError::BadAxes));
        assert_eq!(Ellipsoid::new(f64::NAN, 2.0), Err(GeodesyError::NonFinite));
        let e = Ellipsoid::<f64>::wgs84();
        assert_eq!(
            e.latitude_cone(0.0, -1.0),
            Err(GeodesyError::LatitudeOutOfRange)
        );
        assert_eq!(meridian_rad(f64::INFINITY), Err(GeodesyError::NonFinite));
    }

    #[test]
    fn meridian_side_is_east() {
        let m = meridian_deg(10.0_f64).unwrap();
        let e = Ellipsoid::<f64>::wgs84();
        assert_eq!(
            m.side_of(e.geodetic_deg_to_ecef(0.0, 11.0, 0.0)),
            Some(Side::Positive)
        );
        assert_eq!(
            m.side_of(e.geodetic_deg_to_ecef(0.0, 9.0, 0.0)),
            Some(Side::Negative)
        );
    }
}
