//! Terrain picking against the brute-force oracle: single and multi-resolution, the bounding boxes, the block subsets,
//! named defects and the smoke crops.
//!
//! One test binary per subject (one link instead of one per file); each module is one suite.

#[path = "../support/mod.rs"]
mod support;

mod block_subset;
mod boxes;
#[cfg(feature = "embree")]
mod embree;
mod multires;
mod oracle;
mod pick_defects;
mod smoke_crop;
mod smoke_pick;
