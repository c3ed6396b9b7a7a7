//! Cameras of `curvicast render`: one ray per pixel, as the command-line contract defines the pixel geometry.
//!
//! Pixel (row i, column j) looks through the image-plane point
//! `look_at + ((j + 0.5)/W − 0.5) · width · right + (0.5 − (i + 0.5)/H) · (width · H/W) · up'`, with
//! `dir = normalize(look_at − eye)`, `right = normalize(dir × up)` and `up' = right × dir`. Orthographic rays are
//! parallel to `dir` and start on the plane through `eye`; perspective rays start at `eye`, and the plane's width
//! is `2 · |look_at − eye| · tan(fov / 2)` (`fov_deg` is the horizontal field of view). Directions are unit length.

use serde::Deserialize;

/// A camera as written in SCENE.json.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum CameraSpec {
    /// Parallel rays; `width` is the image plane's width in the grid's units.
    Orthographic {
        /// Where the rays start (the plane through it, perpendicular to the view direction).
        eye: [f64; 3],
        /// The image plane's center.
        look_at: [f64; 3],
        /// The up direction (default +z).
        #[serde(default = "default_up")]
        up: [f64; 3],
        /// Width of the image plane.
        width: f64,
    },
    /// Rays from `eye`; `fov_deg` is the horizontal field of view in degrees.
    Perspective {
        /// The eye point.
        eye: [f64; 3],
        /// The point the view is centred on.
        look_at: [f64; 3],
        /// The up direction (default +z).
        #[serde(default = "default_up")]
        up: [f64; 3],
        /// Horizontal field of view, degrees, in (0, 180).
        fov_deg: f64,
    },
}

fn default_up() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

/// A camera set up for an image of `width × height` pixels: the rays of its pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    eye: [f64; 3],
    look_at: [f64; 3],
    dir: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    plane_width: f64,
    distance: f64,
    orthographic: bool,
    pixels: [usize; 2],
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    a.map(|x| x * s)
}

impl Camera {
    /// Sets up `spec` for `pixels = [W, H]`; an error message when the camera is degenerate (eye at `look_at`,
    /// `up` parallel to the view, a width or field of view out of range, values not finite).
    pub fn new(spec: &CameraSpec, pixels: [usize; 2]) -> Result<Camera, String> {
        let (eye, look_at, up, orthographic) = match *spec {
            CameraSpec::Orthographic {
                eye, look_at, up, ..
            } => (eye, look_at, up, true),
            CameraSpec::Perspective {
                eye, look_at, up, ..
            } => (eye, look_at, up, false),
        };
        if !eye.iter().chain(&look_at).chain(&up).all(|x| x.is_finite()) {
            return Err("camera: eye, look_at and up must be finite".into());
        }
        let view = sub(look_at, eye);
        let distance = norm(view);
        if distance <= 0.0 {
            return Err("camera: eye and look_at coincide".into());
        }
        let dir = scale(view, 1.0 / distance);
        let side = cross(dir, up);
        let up_len = norm(up);
        if norm(side) <= 1e-9 * up_len || up_len == 0.0 {
            return Err("camera: up is zero or parallel to the view direction".into());
        }
        let right = scale(side, 1.0 / norm(side));
        let up = cross(right, dir);
        let plane_width = match *spec {
            CameraSpec::Orthographic { width, .. } => {
                if !(width.is_finite() && width > 0.0) {
                    return Err(format!("camera: width must be positive, got {width}"));
                }
                width
            }
            CameraSpec::Perspective { fov_deg, .. } => {
                if !(fov_deg > 0.0 && fov_deg < 180.0) {
                    return Err(format!(
                        "camera: fov_deg must be in (0, 180), got {fov_deg}"
                    ));
                }
                2.0 * distance * (fov_deg.to_radians() / 2.0).tan()
            }
        };
        Ok(Camera {
            eye,
            look_at,
            dir,
            right,
            up,
            plane_width,
            distance,
            orthographic,
            pixels,
        })
    }

    /// The ray of pixel (row `i`, column `j`): origin and unit direction (`t` from 0).
    pub fn ray(&self, i: usize, j: usize) -> ([f64; 3], [f64; 3]) {
        let [w, h] = self.pixels.map(|p| p as f64);
        let a = ((j as f64 + 0.5) / w - 0.5) * self.plane_width;
        let b = (0.5 - (i as f64 + 0.5) / h) * self.plane_width * h / w;
        let p = [0, 1, 2].map(|k| self.look_at[k] + a * self.right[k] + b * self.up[k]);
        if self.orthographic {
            (
                [0, 1, 2].map(|k| p[k] - self.distance * self.dir[k]),
                self.dir,
            )
        } else {
            let d = sub(p, self.eye);
            (self.eye, scale(d, 1.0 / norm(d)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orthographic_pixel_geometry_follows_the_contract() {
        let spec = CameraSpec::Orthographic {
            eye: [-3.0, 0.0, 0.0],
            look_at: [0.0; 3],
            up: [0.0, 0.0, 1.0],
            width: 2.0,
        };
        let cam = Camera::new(&spec, [4, 2]).unwrap();
        // dir = +x, right = x × z = -y, up' = right × dir = z
        let (o, d) = cam.ray(0, 0);
        assert_eq!(d, [1.0, 0.0, 0.0]);
        // a = (0.5/4 - 0.5)·2 = -0.75 along -y; b = (0.5 - 0.25)·2·2/4 = 0.25 along z
        assert!((o[0] + 3.0).abs() < 1e-15 && (o[1] - 0.75).abs() < 1e-15);
        assert!((o[2] - 0.25).abs() < 1e-15);
    }

    #[test]
    fn perspective_center_pixel_looks_at_the_target() {
        let spec = CameraSpec::Perspective {
            eye: [0.0, -5.0, 0.0],
            look_at: [0.0; 3],
            up: [0.0, 0.0, 1.0],
            fov_deg: 30.0,
        };
        let cam = Camera::new(&spec, [3, 3]).unwrap();
        let (o, d) = cam.ray(1, 1);
        assert_eq!(o, [0.0, -5.0, 0.0]);
        assert!((d[1] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn degenerate_cameras_are_rejected() {
        let up_along_view = CameraSpec::Orthographic {
            eye: [0.0, 0.0, 3.0],
            look_at: [0.0; 3],
            up: [0.0, 0.0, 1.0],
            width: 2.0,
        };
        assert!(Camera::new(&up_along_view, [2, 2]).is_err());
        let wide = CameraSpec::Perspective {
            eye: [3.0, 0.0, 0.0],
            look_at: [0.0; 3],
            up: [0.0, 0.0, 1.0],
            fov_deg: 180.0,
        };
        assert!(Camera::new(&wide, [2, 2]).is_err());
    }
}
