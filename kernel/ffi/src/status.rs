//! The status codes: one per variant of the kernel's typed errors, plus the boundary's own.

use curvicast::RayError;
use curvicast::geodesy::GeodesyError;
use curvicast::march::{GridError, MarchError};
use curvicast::terrain::TerrainError;
use curvicast::terrain::build::BuildError;
use curvicast::tessellate::TessellateError;

/// What a call did. `CURVICAST_OK` (0) and the two answers `CURVICAST_DONE` and `CURVICAST_NO_HIT` are
/// successes; every other code is a failure, named after the kernel error it stands for (`RAY_*`: `RayError`,
/// `GRID_*`: `GridError`, `MARCH_*`: `MarchError`, `GEODESY_*`: `GeodesyError`, `BUILD_*`: `BuildError`,
/// `TERRAIN_*`: `TerrainError`, `TESSELLATE_*`: `TessellateError`) or after the boundary's own check.
/// `curvicast_status_message` gives each a sentence.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum curvicast_status {
    /// Success.
    CURVICAST_OK = 0,
    /// A march has no more crossings (success).
    CURVICAST_DONE = 1,
    /// A pick found no hit (success).
    CURVICAST_NO_HIT = 2,
    /// A required pointer is NULL.
    CURVICAST_NULL_POINTER = 10,
    /// A pointer is not aligned for its type.
    CURVICAST_MISALIGNED = 11,
    /// A length times its element size exceeds the address space.
    CURVICAST_BUFFER_TOO_LARGE = 12,
    /// An object's storage was not filled by its `init` (or its `init` failed).
    CURVICAST_NOT_INITIALIZED = 13,
    /// A batch of capacity 0 (it could never make progress).
    CURVICAST_ZERO_CAPACITY = 14,
    /// The ray's origin has a NaN or infinite component.
    CURVICAST_RAY_NON_FINITE_ORIGIN = 20,
    /// The ray's direction has a NaN or infinite component.
    CURVICAST_RAY_NON_FINITE_DIRECTION = 21,
    /// The ray's direction is the zero vector.
    CURVICAST_RAY_ZERO_DIRECTION = 22,
    /// `t_min` or `t_max` is NaN, `t_min > t_max`, `t_min = +∞` or `t_max = −∞`.
    CURVICAST_RAY_INVALID_INTERVAL = 23,
    /// Fewer than two breakpoints on an axis.
    CURVICAST_GRID_TOO_FEW_BREAKPOINTS = 30,
    /// More breakpoints than a `uint32_t` cell index can address.
    CURVICAST_GRID_TOO_MANY_BREAKPOINTS = 31,
    /// A breakpoint is not larger than the one before it.
    CURVICAST_GRID_NOT_INCREASING = 32,
    /// A breakpoint is NaN or infinite.
    CURVICAST_GRID_NON_FINITE = 33,
    /// A breakpoint is out of its range (`r < 0`, θ outside [0, π], φ spanning more than 2π).
    CURVICAST_GRID_OUT_OF_RANGE = 34,
    /// The grid's center is not finite.
    CURVICAST_GRID_NON_FINITE_CENTER = 35,
    /// The workspace is shorter than the grid's `*_workspace_len`.
    CURVICAST_GRID_WORKSPACE_TOO_SMALL = 36,
    /// A separable march's buffer is full (not returned by the serial march of this interface).
    CURVICAST_MARCH_BUFFER_FULL = 40,
    /// The march exceeded its iteration bound (a safety net; crossings before it were returned).
    CURVICAST_MARCH_ITERATION_BOUND = 41,
    /// The ray's `t` in the grid is beyond the largest finite value (a direction too short).
    CURVICAST_MARCH_UNREPRESENTABLE = 42,
    /// A geodetic parameter is NaN or infinite.
    CURVICAST_GEODESY_NON_FINITE = 50,
    /// The ellipsoid's axes do not satisfy `a ≥ b > 0`.
    CURVICAST_GEODESY_BAD_AXES = 51,
    /// A height at or below `−b²/a`.
    CURVICAST_GEODESY_HEIGHT_TOO_LOW = 52,
    /// A latitude outside [−90°, 90°].
    CURVICAST_GEODESY_LATITUDE_OUT_OF_RANGE = 53,
    /// A DEM cell too large for the chord bound (cells must span less than about 70°).
    CURVICAST_GEODESY_TRIANGLE_TOO_LARGE = 54,
    /// The DEM grid is invalid.
    CURVICAST_BUILD_INVALID_GRID = 60,
    /// The heights array does not hold `rows × cols` heights.
    CURVICAST_BUILD_HEIGHTS_LENGTH = 61,
    /// A height is infinite (a missing height is NaN).
    CURVICAST_BUILD_INFINITE_HEIGHT = 62,
    /// The block size is 0, or a block would span 180° of longitude or more.
    CURVICAST_BUILD_INVALID_BLOCK = 63,
    /// The node array is shorter than `curvicast_node_slots`.
    CURVICAST_BUILD_BUFFER_TOO_SMALL = 64,
    /// The node records are not the ones built for this grid.
    CURVICAST_BUILD_RECORDS_MISMATCH = 65,
    /// A residency array is neither empty nor `curvicast_node_slots` long.
    CURVICAST_BUILD_BUFFER_LENGTH = 66,
    /// The multi-resolution shape is invalid (a non-finite or reversed fine region).
    CURVICAST_BUILD_INVALID_SHAPE = 67,
    /// A multi-resolution tree in a single-resolution storage.
    CURVICAST_BUILD_SINGLE_RESOLUTION = 68,
    /// The DEM grid is invalid (at pick time).
    CURVICAST_TERRAIN_INVALID_GRID = 70,
    /// A node is missing, outside the grid, or not strictly inside its parent.
    CURVICAST_TERRAIN_MALFORMED_TREE = 71,
    /// More zones than the picker holds.
    CURVICAST_TERRAIN_TOO_MANY_ZONES = 72,
    /// The traversal stack is full (a tree deeper than the picker was sized for).
    CURVICAST_TERRAIN_STACK_FULL = 73,
    /// The traversal visited more nodes than the grid can hold (a malformed tree).
    CURVICAST_TERRAIN_TRAVERSAL_BOUND = 74,
    /// The answer needs a block that is not resident: page in the node written to `needs_node`, ask again.
    CURVICAST_TERRAIN_NEEDS_BLOCK = 75,
    /// The ray meets the terrain where its `t` is beyond the largest finite value.
    CURVICAST_TERRAIN_UNREPRESENTABLE = 76,
    /// The level exceeds the largest supported one.
    CURVICAST_TESSELLATE_LEVEL_TOO_DEEP = 80,
    /// A buffer is shorter than the level needs.
    CURVICAST_TESSELLATE_BUFFER_TOO_SMALL = 81,
    /// A radius or semi-axis is not positive and finite.
    CURVICAST_TESSELLATE_INVALID_SHAPE = 82,
    /// The ratio of the largest to the smallest semi-axis is beyond the verified range.
    CURVICAST_TESSELLATE_AXIS_RATIO_TOO_LARGE = 83,
    /// A control polygon is invalid.
    CURVICAST_TESSELLATE_INVALID_CONTROL_POLYGON = 84,
    /// A level-of-detail bound is NaN or out of range, or the viewer is not outside the object.
    CURVICAST_TESSELLATE_INVALID_BOUND = 85,
    /// No supported level meets the bound.
    CURVICAST_TESSELLATE_UNREACHABLE = 86,
    /// An internal consistency check failed (a bug, reported instead of a panic).
    CURVICAST_TESSELLATE_INTERNAL = 87,
}

use curvicast_status as S;

impl From<RayError> for curvicast_status {
    fn from(e: RayError) -> Self {
        match e {
            RayError::NonFiniteOrigin => S::CURVICAST_RAY_NON_FINITE_ORIGIN,
            RayError::NonFiniteDirection => S::CURVICAST_RAY_NON_FINITE_DIRECTION,
            RayError::ZeroDirection => S::CURVICAST_RAY_ZERO_DIRECTION,
            RayError::InvalidInterval => S::CURVICAST_RAY_INVALID_INTERVAL,
        }
    }
}

impl From<GridError> for curvicast_status {
    fn from(e: GridError) -> Self {
        match e {
            GridError::TooFewBreakpoints { .. } => S::CURVICAST_GRID_TOO_FEW_BREAKPOINTS,
            GridError::TooManyBreakpoints { .. } => S::CURVICAST_GRID_TOO_MANY_BREAKPOINTS,
            GridError::NotIncreasing { .. } => S::CURVICAST_GRID_NOT_INCREASING,
            GridError::NonFinite { .. } => S::CURVICAST_GRID_NON_FINITE,
            GridError::OutOfRange { .. } => S::CURVICAST_GRID_OUT_OF_RANGE,
            GridError::NonFiniteCenter => S::CURVICAST_GRID_NON_FINITE_CENTER,
            GridError::WorkspaceTooSmall => S::CURVICAST_GRID_WORKSPACE_TOO_SMALL,
        }
    }
}

impl From<MarchError> for curvicast_status {
    fn from(e: MarchError) -> Self {
        match e {
            MarchError::BufferFull { .. } => S::CURVICAST_MARCH_BUFFER_FULL,
            MarchError::IterationBound => S::CURVICAST_MARCH_ITERATION_BOUND,
            MarchError::Ray(e) => e.into(),
            MarchError::Unrepresentable => S::CURVICAST_MARCH_UNREPRESENTABLE,
        }
    }
}

impl From<GeodesyError> for curvicast_status {
    fn from(e: GeodesyError) -> Self {
        match e {
            GeodesyError::NonFinite => S::CURVICAST_GEODESY_NON_FINITE,
            GeodesyError::BadAxes => S::CURVICAST_GEODESY_BAD_AXES,
            GeodesyError::HeightTooLow => S::CURVICAST_GEODESY_HEIGHT_TOO_LOW,
            GeodesyError::LatitudeOutOfRange => S::CURVICAST_GEODESY_LATITUDE_OUT_OF_RANGE,
            GeodesyError::TriangleTooLarge => S::CURVICAST_GEODESY_TRIANGLE_TOO_LARGE,
        }
    }
}

impl From<BuildError> for curvicast_status {
    fn from(e: BuildError) -> Self {
        match e {
            BuildError::InvalidGrid => S::CURVICAST_BUILD_INVALID_GRID,
            BuildError::HeightsLength => S::CURVICAST_BUILD_HEIGHTS_LENGTH,
            BuildError::InfiniteHeight(_) => S::CURVICAST_BUILD_INFINITE_HEIGHT,
            BuildError::InvalidBlock => S::CURVICAST_BUILD_INVALID_BLOCK,
            BuildError::BufferTooSmall => S::CURVICAST_BUILD_BUFFER_TOO_SMALL,
            BuildError::RecordsMismatch => S::CURVICAST_BUILD_RECORDS_MISMATCH,
            BuildError::BufferLength => S::CURVICAST_BUILD_BUFFER_LENGTH,
            BuildError::InvalidShape => S::CURVICAST_BUILD_INVALID_SHAPE,
            BuildError::SingleResolution => S::CURVICAST_BUILD_SINGLE_RESOLUTION,
        }
    }
}

impl From<TerrainError> for curvicast_status {
    fn from(e: TerrainError) -> Self {
        match e {
            TerrainError::Ray(e) => e.into(),
            TerrainError::Geodesy(e) => e.into(),
            TerrainError::InvalidGrid => S::CURVICAST_TERRAIN_INVALID_GRID,
            TerrainError::MalformedTree => S::CURVICAST_TERRAIN_MALFORMED_TREE,
            TerrainError::TooManyZones => S::CURVICAST_TERRAIN_TOO_MANY_ZONES,
            TerrainError::StackFull => S::CURVICAST_TERRAIN_STACK_FULL,
            TerrainError::TraversalBound => S::CURVICAST_TERRAIN_TRAVERSAL_BOUND,
            TerrainError::NeedsBlock(_) => S::CURVICAST_TERRAIN_NEEDS_BLOCK,
            TerrainError::Unrepresentable => S::CURVICAST_TERRAIN_UNREPRESENTABLE,
        }
    }
}

impl From<TessellateError> for curvicast_status {
    fn from(e: TessellateError) -> Self {
        match e {
            TessellateError::LevelTooDeep { .. } => S::CURVICAST_TESSELLATE_LEVEL_TOO_DEEP,
            TessellateError::BufferTooSmall { .. } => S::CURVICAST_TESSELLATE_BUFFER_TOO_SMALL,
            TessellateError::InvalidShape => S::CURVICAST_TESSELLATE_INVALID_SHAPE,
            TessellateError::AxisRatioTooLarge => S::CURVICAST_TESSELLATE_AXIS_RATIO_TOO_LARGE,
            TessellateError::InvalidControlPolygon => {
                S::CURVICAST_TESSELLATE_INVALID_CONTROL_POLYGON
            }
            TessellateError::InvalidBound => S::CURVICAST_TESSELLATE_INVALID_BOUND,
            TessellateError::Unreachable => S::CURVICAST_TESSELLATE_UNREACHABLE,
            TessellateError::Internal => S::CURVICAST_TESSELLATE_INTERNAL,
        }
    }
}

/// The result of a call as its status: `CURVICAST_OK` or the error.
pub(crate) fn status(r: Result<(), curvicast_status>) -> curvicast_status {
    match r {
        Ok(()) => S::CURVICAST_OK,
        Err(e) => e,
    }
}

/// Every status with its message (NUL-terminated, for C).
const MESSAGES: &[(curvicast_status, &str)] = &[
    (S::CURVICAST_OK, "ok\0"),
    (S::CURVICAST_DONE, "the march has no more crossings\0"),
    (S::CURVICAST_NO_HIT, "no hit\0"),
    (S::CURVICAST_NULL_POINTER, "a required pointer is NULL\0"),
    (
        S::CURVICAST_MISALIGNED,
        "a pointer is not aligned for its type\0",
    ),
    (
        S::CURVICAST_BUFFER_TOO_LARGE,
        "a length exceeds the address space\0",
    ),
    (
        S::CURVICAST_NOT_INITIALIZED,
        "object used before a successful init\0",
    ),
    (
        S::CURVICAST_RAY_NON_FINITE_ORIGIN,
        "ray origin is not finite\0",
    ),
    (
        S::CURVICAST_RAY_NON_FINITE_DIRECTION,
        "ray direction is not finite\0",
    ),
    (S::CURVICAST_RAY_ZERO_DIRECTION, "ray direction is zero\0"),
    (
        S::CURVICAST_RAY_INVALID_INTERVAL,
        "ray interval is invalid (NaN, or t_min > t_max)\0",
    ),
    (
        S::CURVICAST_GRID_TOO_FEW_BREAKPOINTS,
        "an axis needs at least 2 breakpoints\0",
    ),
    (
        S::CURVICAST_GRID_TOO_MANY_BREAKPOINTS,
        "too many breakpoints for a 32-bit cell index\0",
    ),
    (
        S::CURVICAST_GRID_NOT_INCREASING,
        "breakpoints must be strictly increasing\0",
    ),
    (S::CURVICAST_GRID_NON_FINITE, "a breakpoint is not finite\0"),
    (
        S::CURVICAST_GRID_OUT_OF_RANGE,
        "a breakpoint is out of range (r >= 0, theta in [0, pi], phi span <= 2 pi)\0",
    ),
    (
        S::CURVICAST_GRID_NON_FINITE_CENTER,
        "grid center is not finite\0",
    ),
    (
        S::CURVICAST_GRID_WORKSPACE_TOO_SMALL,
        "workspace shorter than the grid's workspace length\0",
    ),
    (
        S::CURVICAST_MARCH_BUFFER_FULL,
        "separable march buffer full\0",
    ),
    (
        S::CURVICAST_MARCH_ITERATION_BOUND,
        "march exceeded its iteration bound\0",
    ),
    (
        S::CURVICAST_MARCH_UNREPRESENTABLE,
        "the ray's t in the grid exceeds the largest finite value\0",
    ),
    (
        S::CURVICAST_GEODESY_NON_FINITE,
        "geodetic parameter is not finite\0",
    ),
    (
        S::CURVICAST_GEODESY_BAD_AXES,
        "ellipsoid axes must satisfy a >= b > 0\0",
    ),
    (
        S::CURVICAST_GEODESY_HEIGHT_TOO_LOW,
        "height at or below -b^2/a\0",
    ),
    (
        S::CURVICAST_GEODESY_LATITUDE_OUT_OF_RANGE,
        "latitude outside [-90, 90] degrees\0",
    ),
    (
        S::CURVICAST_GEODESY_TRIANGLE_TOO_LARGE,
        "DEM cell too large for the chord bound\0",
    ),
    (S::CURVICAST_BUILD_INVALID_GRID, "invalid DEM grid\0"),
    (
        S::CURVICAST_BUILD_HEIGHTS_LENGTH,
        "heights array does not hold rows x cols heights\0",
    ),
    (S::CURVICAST_BUILD_INFINITE_HEIGHT, "a height is infinite\0"),
    (
        S::CURVICAST_BUILD_INVALID_BLOCK,
        "block size 0, or a block spanning 180 degrees of longitude or more\0",
    ),
    (
        S::CURVICAST_BUILD_BUFFER_TOO_SMALL,
        "node array shorter than curvicast_node_slots()\0",
    ),
    (
        S::CURVICAST_BUILD_RECORDS_MISMATCH,
        "node records not built for this grid\0",
    ),
    (
        S::CURVICAST_BUILD_BUFFER_LENGTH,
        "residency array of the wrong length\0",
    ),
    (
        S::CURVICAST_BUILD_INVALID_SHAPE,
        "invalid multi-resolution shape\0",
    ),
    (
        S::CURVICAST_BUILD_SINGLE_RESOLUTION,
        "multi-resolution tree in a single-resolution storage\0",
    ),
    (S::CURVICAST_TERRAIN_INVALID_GRID, "invalid DEM grid\0"),
    (
        S::CURVICAST_TERRAIN_MALFORMED_TREE,
        "malformed terrain quadtree\0",
    ),
    (
        S::CURVICAST_TERRAIN_TOO_MANY_ZONES,
        "more zones than the picker's capacity\0",
    ),
    (S::CURVICAST_TERRAIN_STACK_FULL, "traversal stack full\0"),
    (
        S::CURVICAST_TERRAIN_TRAVERSAL_BOUND,
        "traversal exceeded its node bound\0",
    ),
    (
        S::CURVICAST_TERRAIN_NEEDS_BLOCK,
        "the answer needs a block that is not resident\0",
    ),
    (
        S::CURVICAST_TERRAIN_UNREPRESENTABLE,
        "the ray meets the terrain where t exceeds the largest finite value\0",
    ),
    (
        S::CURVICAST_TESSELLATE_LEVEL_TOO_DEEP,
        "level exceeds the largest supported level\0",
    ),
    (
        S::CURVICAST_TESSELLATE_BUFFER_TOO_SMALL,
        "buffer shorter than the level needs\0",
    ),
    (
        S::CURVICAST_TESSELLATE_INVALID_SHAPE,
        "radius and semi-axes must be positive and finite\0",
    ),
    (
        S::CURVICAST_TESSELLATE_AXIS_RATIO_TOO_LARGE,
        "semi-axis ratio beyond the verified range\0",
    ),
    (
        S::CURVICAST_TESSELLATE_INVALID_CONTROL_POLYGON,
        "invalid control polygon\0",
    ),
    (
        S::CURVICAST_TESSELLATE_INVALID_BOUND,
        "level-of-detail bound NaN or out of range\0",
    ),
    (
        S::CURVICAST_TESSELLATE_UNREACHABLE,
        "no supported level meets the bound\0",
    ),
    (
        S::CURVICAST_TESSELLATE_INTERNAL,
        "internal consistency check failed\0",
    ),
];

/// A sentence for a status code (static, NUL-terminated); "unknown status" for a number that is none.
#[unsafe(no_mangle)]
pub extern "C" fn curvicast_status_message(status: u32) -> *const core::ffi::c_char {
    MESSAGES
        .iter()
        .find(|(s, _)| *s as u32 == status)
        .map_or("unknown status\0", |(_, m)| m)
        .as_ptr()
        .cast()
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::ffi::CStr;

    #[test]
    fn every_status_has_one_message_ending_in_nul() {
        for (i, (s, m)) in MESSAGES.iter().enumerate() {
            assert!(m.ends_with('\0') && !m[..m.len() - 1].contains('\0'), "{m}");
            assert!(MESSAGES[..i].iter().all(|(t, _)| t != s), "{s:?} twice");
            // SAFETY: a static NUL-terminated string.
            let c = unsafe { CStr::from_ptr(curvicast_status_message(*s as u32)) };
            assert_eq!(c.to_bytes(), &m.as_bytes()[..m.len() - 1]);
        }
        // SAFETY: as above.
        let unknown = unsafe { CStr::from_ptr(curvicast_status_message(9999)) };
        assert_eq!(unknown.to_str(), Ok("unknown status"));
    }
}
