//! Why a pick failed: [`TerrainError`].

use super::grid::NodeId;
use crate::geodesy::GeodesyError;
use crate::ray::RayError;

/// Why a pick failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TerrainError {
    /// The ray (or segment) is invalid.
    Ray(RayError),
    /// A bound could not be formed (heights at or below `−b²/a`, non-finite values, bad axes).
    Geodesy(GeodesyError),
    /// The grid is invalid (see [`Grid::validate`](crate::terrain::Grid::validate)).
    InvalidGrid,
    /// A node is missing, outside the grid, or not strictly inside its parent.
    MalformedTree,
    /// More zones than the picker's `ZONES` capacity.
    TooManyZones,
    /// The traversal stack (capacity `STACK`) is full: the tree is deeper than the picker was sized for.
    StackFull,
    /// The traversal visited more nodes than the grid can hold (a malformed tree).
    TraversalBound,
    /// The answer needs the block of this node, which is not resident, and no coarser resident block at or
    /// below the picker's `min_level` can stand in for it (§5): page it in and ask again. Reported only when
    /// the node could hold a hit nearer than any found.
    NeedsBlock(NodeId),
    /// The ray meets the terrain's bounding volume, but where its parameter `t` is beyond the largest finite
    /// value of the scalar type (a direction so short, like `[1e-308, 0, 0]` from a thousand kilometres away,
    /// that `t = distance / |d|` overflows), and no hit was found at a representable `t`. Answered as an error
    /// rather than as a miss.
    Unrepresentable,
}

impl core::fmt::Display for TerrainError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TerrainError::Ray(e) => write!(f, "invalid ray: {e}"),
            TerrainError::Geodesy(e) => write!(f, "invalid terrain bound: {e}"),
            TerrainError::InvalidGrid => f.write_str(
                "invalid DEM grid: it needs finite lat0, lon0, dlat and dlon, at least 2 rows and 2 columns, \
                 dlat != 0, 0 < dlon < 180 degrees and every row's latitude within [-90, 90]",
            ),
            TerrainError::MalformedTree => f.write_str("malformed terrain quadtree"),
            TerrainError::TooManyZones => f.write_str("more zones than the picker's capacity"),
            TerrainError::StackFull => {
                f.write_str("traversal stack full (tree deeper than capacity)")
            }
            TerrainError::TraversalBound => f.write_str("traversal exceeded its node bound"),
            TerrainError::NeedsBlock(id) => write!(f, "needs the block of node {}", id.0),
            TerrainError::Unrepresentable => f.write_str(
                "the ray meets the terrain where its t exceeds the largest finite value (direction too short)",
            ),
        }
    }
}

impl core::error::Error for TerrainError {}

impl From<RayError> for TerrainError {
    fn from(e: RayError) -> Self {
        TerrainError::Ray(e)
    }
}
impl From<GeodesyError> for TerrainError {
    fn from(e: GeodesyError) -> Self {
        TerrainError::Geodesy(e)
    }
}
