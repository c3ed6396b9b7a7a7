//! Tessellation from C (rational corner-cutting and edge-beveling, ch. 4–5): the level a scene needs, chosen
//! a priori, and the edge-beveled sphere or ellipsoid of that level written into the caller's arrays.
//!
//! ```c
//! uint32_t level;
//! double axes[3] = {6378137.0, 6378137.0, 6356752.314245};
//! curvicast_level_for_deviation_f64(axes, 100.0, &level);        /* at most 100 m from the surface */
//! size_t nv = curvicast_bevel_vertex_count(level), nf = curvicast_bevel_face_count(level);
//! /* vertices: nv curvicast_vec3_f64, faces: nf curvicast_face_f64 */
//! curvicast_bevel_ellipsoid_f64(level, axes, vertices, nv, faces, nf);
//! ```

use crate::{curvicast_status, point, slice_mut};
use core::mem::{align_of, offset_of, size_of};
use curvicast::Real;
use curvicast::tessellate::bevel::{
    Face, MAX_FACE_VERTICES, bevel_ellipsoid, face_count, vertex_count,
};
use curvicast::tessellate::lod::{Bound, Shape, min_level};
use curvicast::vec3::V3;

/// A point or vector.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct curvicast_vec3_f32 {
    /// x.
    pub x: f32,
    /// y.
    pub y: f32,
    /// z.
    pub z: f32,
}

/// A point or vector in double precision.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct curvicast_vec3_f64 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// The most vertices a face has.
pub const CURVICAST_FACE_MAX_VERTICES: usize = 6;

/// One face of a beveled polyhedron: a planar convex polygon tangent to the surface at `center`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct curvicast_face_f32 {
    /// Where the face's plane touches the surface.
    pub center: curvicast_vec3_f32,
    /// The unit outward normal of the face's plane.
    pub normal: curvicast_vec3_f32,
    /// Indices into the vertex array, counter-clockwise seen from outside; the first `len` are used.
    pub vertices: [u32; CURVICAST_FACE_MAX_VERTICES],
    /// Number of vertices: 4 or 6.
    pub len: u8,
}

/// One face (see `curvicast_face_f32`) in double precision.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct curvicast_face_f64 {
    /// Where the face's plane touches the surface.
    pub center: curvicast_vec3_f64,
    /// The unit outward normal of the face's plane.
    pub normal: curvicast_vec3_f64,
    /// Indices into the vertex array, counter-clockwise seen from outside; the first `len` are used.
    pub vertices: [u32; CURVICAST_FACE_MAX_VERTICES],
    /// Number of vertices: 4 or 6.
    pub len: u8,
}

/// The C types and the kernel's have one layout (both `repr(C)`), so the kernel writes the caller's arrays.
macro_rules! same_layout {
    ($c:ty, $k:ty) => {
        const _: () = assert!(size_of::<$c>() == size_of::<$k>() && align_of::<$c>() == align_of::<$k>());
    };
    ($c:ty, $k:ty, $($f:ident),+) => {
        same_layout!($c, $k);
        $(const _: () = assert!(offset_of!($c, $f) == offset_of!($k, $f));)+
    };
}
same_layout!(curvicast_vec3_f32, V3<f32>, x, y, z);
same_layout!(curvicast_vec3_f64, V3<f64>, x, y, z);
same_layout!(curvicast_face_f32, Face<f32>, center, normal, vertices, len);
same_layout!(curvicast_face_f64, Face<f64>, center, normal, vertices, len);
const _: () = assert!(CURVICAST_FACE_MAX_VERTICES == MAX_FACE_VERTICES);

/// The vertices of the level-`level` beveled polyhedron, `8·4^level` (0 above the largest level, 12).
#[unsafe(no_mangle)]
pub extern "C" fn curvicast_bevel_vertex_count(level: u32) -> usize {
    if level > curvicast::tessellate::bevel::MAX_LEVEL {
        0
    } else {
        vertex_count(level)
    }
}

/// The faces of the level-`level` beveled polyhedron, `4·4^level + 2` (0 above the largest level, 12).
#[unsafe(no_mangle)]
pub extern "C" fn curvicast_bevel_face_count(level: u32) -> usize {
    if level > curvicast::tessellate::bevel::MAX_LEVEL {
        0
    } else {
        face_count(level)
    }
}

/// The shape of three semi-axes: a sphere when they are equal.
fn shape<T: Real>([a, b, c]: [T; 3]) -> Shape<T> {
    if a == b && b == c {
        Shape::Sphere(a)
    } else {
        Shape::Ellipsoid([a, b, c])
    }
}

/// # Safety
/// `axes` is NULL or points to 3 scalars; `level` is NULL or valid.
unsafe fn level<T: Real>(axes: *const T, bound: Bound<T>, level: *mut u32) -> curvicast_status {
    // SAFETY: the contract.
    let r = unsafe { (point::<T, 3>(axes), crate::out(level)) };
    match r {
        (Ok(axes), Ok(level)) => match min_level(shape(axes), bound) {
            Ok(l) => {
                *level = l;
                curvicast_status::CURVICAST_OK
            }
            Err(e) => e.into(),
        },
        (Err(e), _) | (_, Err(e)) => e,
    }
}

/// The smallest level whose polyhedron of the ellipsoid with semi-axes `axes` (3 scalars; a sphere when equal)
/// stays within `max_deviation` of the surface (same unit as the axes), into `*level` (ch. 5: chosen without
/// building any level).
///
/// # Safety
/// `axes` is NULL or points to 3 floats; `level` is NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_level_for_deviation_f32(
    axes: *const f32,
    max_deviation: f32,
    level: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { self::level(axes, Bound::MaxDeviation(max_deviation), level) }
}

/// [`curvicast_level_for_deviation_f32`] in double precision.
///
/// # Safety
/// `axes` is NULL or points to 3 doubles; `level` is NULL or valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_level_for_deviation_f64(
    axes: *const f64,
    max_deviation: f64,
    level: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { self::level(axes, Bound::MaxDeviation(max_deviation), level) }
}

/// The smallest level whose dihedral angles between adjacent faces are all at least `min_dihedral_rad`
/// (radians, in [0, π)), into `*level`.
///
/// # Safety
/// As [`curvicast_level_for_deviation_f32`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_level_for_dihedral_f32(
    axes: *const f32,
    min_dihedral_rad: f32,
    level: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { self::level(axes, Bound::MinDihedral(min_dihedral_rad), level) }
}

/// [`curvicast_level_for_dihedral_f32`] in double precision.
///
/// # Safety
/// As [`curvicast_level_for_deviation_f64`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_level_for_dihedral_f64(
    axes: *const f64,
    min_dihedral_rad: f64,
    level: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { self::level(axes, Bound::MinDihedral(min_dihedral_rad), level) }
}

/// The smallest level whose deviation, seen from `distance` (eye to the object's center, outside its
/// bounding sphere), subtends at most `pixel_angle_rad` (radians, in (0, π]), into `*level`.
///
/// # Safety
/// As [`curvicast_level_for_deviation_f32`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_level_for_screen_f32(
    axes: *const f32,
    distance: f32,
    pixel_angle_rad: f32,
    level: *mut u32,
) -> curvicast_status {
    let bound = Bound::ScreenSpace {
        distance,
        pixel_angle: pixel_angle_rad,
    };
    // SAFETY: the contract above.
    unsafe { self::level(axes, bound, level) }
}

/// [`curvicast_level_for_screen_f32`] in double precision.
///
/// # Safety
/// As [`curvicast_level_for_deviation_f64`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_level_for_screen_f64(
    axes: *const f64,
    distance: f64,
    pixel_angle_rad: f64,
    level: *mut u32,
) -> curvicast_status {
    let bound = Bound::ScreenSpace {
        distance,
        pixel_angle: pixel_angle_rad,
    };
    // SAFETY: the contract above.
    unsafe { self::level(axes, bound, level) }
}

/// # Safety
/// As [`curvicast_bevel_ellipsoid_f32`], with `V` and `F` the kernel types of the C arrays (same layout).
unsafe fn bevel<T: Real, CV, CF>(
    level: u32,
    axes: *const T,
    vertices: (*mut CV, usize),
    faces: (*mut CF, usize),
) -> curvicast_status {
    // SAFETY: the contract; `CV`/`CF` have `V3<T>`/`Face<T>`'s layout (asserted above), and both are plain
    // numbers, so any bytes the caller's arrays hold are valid values.
    let r = unsafe {
        (
            point::<T, 3>(axes),
            slice_mut(vertices.0.cast::<V3<T>>(), vertices.1),
            slice_mut(faces.0.cast::<Face<T>>(), faces.1),
        )
    };
    match r {
        (Ok(axes), Ok(v), Ok(f)) => match bevel_ellipsoid(level, axes, v, f) {
            Ok(_) => curvicast_status::CURVICAST_OK,
            Err(e) => e.into(),
        },
        (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => e,
    }
}

/// Writes the level-`level` edge-beveled polyhedron of the ellipsoid `x²/A² + y²/B² + z²/C² = 1`,
/// `axes = {A, B, C}` (a sphere when equal; ch. 4, §4.3–4.4): `curvicast_bevel_vertex_count(level)` vertices and
/// `curvicast_bevel_face_count(level)` faces into the front of the arrays. Every face's plane touches the
/// surface at its center; every vertex lies outside.
///
/// # Safety
/// `axes` is NULL or points to 3 floats; `vertices` and `faces` are NULL or valid for their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_bevel_ellipsoid_f32(
    level: u32,
    axes: *const f32,
    vertices: *mut curvicast_vec3_f32,
    vertices_len: usize,
    faces: *mut curvicast_face_f32,
    faces_len: usize,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { bevel(level, axes, (vertices, vertices_len), (faces, faces_len)) }
}

/// Writes the level-`level` edge-beveled polyhedron of the sphere of radius `radius` about the origin (§4.3):
/// [`curvicast_bevel_ellipsoid_f32`] with three equal semi-axes.
///
/// # Safety
/// `vertices` and `faces` are NULL or valid for their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_bevel_sphere_f32(
    level: u32,
    radius: f32,
    vertices: *mut curvicast_vec3_f32,
    vertices_len: usize,
    faces: *mut curvicast_face_f32,
    faces_len: usize,
) -> curvicast_status {
    let axes = [radius; 3];
    // SAFETY: the contract above; `axes` is 3 floats.
    unsafe {
        bevel(
            level,
            axes.as_ptr(),
            (vertices, vertices_len),
            (faces, faces_len),
        )
    }
}

/// [`curvicast_bevel_sphere_f32`] in double precision.
///
/// # Safety
/// `vertices` and `faces` are NULL or valid for their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_bevel_sphere_f64(
    level: u32,
    radius: f64,
    vertices: *mut curvicast_vec3_f64,
    vertices_len: usize,
    faces: *mut curvicast_face_f64,
    faces_len: usize,
) -> curvicast_status {
    let axes = [radius; 3];
    // SAFETY: the contract above; `axes` is 3 doubles.
    unsafe {
        bevel(
            level,
            axes.as_ptr(),
            (vertices, vertices_len),
            (faces, faces_len),
        )
    }
}

/// [`curvicast_bevel_ellipsoid_f32`] in double precision.
///
/// # Safety
/// `axes` is NULL or points to 3 doubles; `vertices` and `faces` are NULL or valid for their lengths.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_bevel_ellipsoid_f64(
    level: u32,
    axes: *const f64,
    vertices: *mut curvicast_vec3_f64,
    vertices_len: usize,
    faces: *mut curvicast_face_f64,
    faces_len: usize,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { bevel(level, axes, (vertices, vertices_len), (faces, faces_len)) }
}
