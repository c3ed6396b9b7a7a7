//! The reference ellipsoid (Wartell et al. §2): [`Ellipsoid`] with geodetic ↔ ECEF conversion, [`Geodetic`]
//! coordinates, [`GeodesyError`], and the trigonometry in degrees the terrain shares ([`sin_cos_deg`]).

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
    /// A triangle edge `d` too long for the chord-sagitta bound ([`chord_sagitta_bound`](crate::geodesy::chord_sagitta_bound)): it needs
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
    ///   `λ = λ₀ + Δλ`, wrapped once by a turn into `(−180°, 180°]`. `None` beyond `|w| = 0.02` (1.1°), on the
    ///   z axis, or where one wrap does not bring `λ` into that range (λ₀ a turn or more outside it).
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
mod tests;
