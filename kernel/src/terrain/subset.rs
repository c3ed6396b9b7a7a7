//! Integer block-subset indexing (Wartell et al. §5, last paragraph).
//!
//! When a leaf's block is not resident, the picker walks up to a resident ancestor and traces only the rectangle
//! of the ancestor's block that covers the original leaf. The paper computes that rectangle incrementally with
//! integers, because its floating-point version "occasionally yielded invalid array indices": start with
//! `x_min = y_min = 0`; at each step up, `x_min ← x_min / 2` if the node just left is in the first half of its
//! parent's columns (the paper's west child), else `x_min ← x_min / 2 + B / 2` (east); the same for `y_min` with
//! rows (south / north); after `levels` steps the rectangle is `extent = max(1, B >> levels)` cells wide.
//!
//! Here `B` (the *block size*) counts **cells** per block side: a block holds `B × B` cells, i.e. `(B + 1)²`
//! height samples, and `B` is a power of two. (The paper calls its block size "vertices per row"; halving works
//! on cells, which is what is used here.) The rectangle is the **half-open** cell range
//! `[x_min, x_max) × [y_min, y_max)` of the ancestor's block, the same convention as [`super::Node`]'s `rows` and
//! `cols`; its cells' corner vertices are the samples `x_min ..= x_max`, `y_min ..= y_max`.
//!
//! # Out-of-range indices are impossible by construction
//!
//! A [`BlockSubset`] is built only by [`BlockSubset::new`], [`BlockSubset::step_up`] and
//! [`BlockSubset::of_descendant`], and always satisfies, per axis,
//! `0 ≤ x_min < x_min + extent = x_max ≤ B`. Proof for `step_up` (induction on `levels = L`; let
//! `e_L = max(1, B >> L)`, a power of two dividing `B`):
//!
//! * `L = 0`: `x_min = 0`, `e_0 = B`.
//! * Invariant: `x_min < B` and `x_min` is a multiple of `e_L`. Since `x_min` and `B` are both multiples of
//!   `e_L`, `x_min < B` gives `x_min ≤ B − e_L`, i.e. `x_max = x_min + e_L ≤ B`.
//! * Step: `x_min < B` gives `x_min / 2 ≤ (B − 1) / 2 < B / 2` for `B ≥ 2` (and `x_min = 0 = B / 2` for `B = 1`),
//!   so `x_min / 2 + B / 2 ≤ B − 1 < B`. Because `x_min / 2 < B / 2` and `B / 2` is a power of two (or zero), the
//!   sum has no carry: it is computed as the bitwise or `x_min / 2 | B / 2`, with no arithmetic that could
//!   overflow. If `B >> (L + 1) ≥ 1` then `e_L = 2 e_{L+1}`, so `x_min / 2` is exact and a multiple of `e_{L+1}`,
//!   as is `B / 2`; otherwise `e_{L+1} = 1` divides everything.
//!
//! The shift `B >> L` is done with [`u32::checked_shr`], which yields `None` (taken as 0, so `extent = 1`) for
//! `L ≥ 32` instead of an overflowing shift. `levels` is capped at [`MAX_LEVELS`]; a further step is
//! [`SubsetError::TooManyLevels`].
//!
//! ```
//! use curvicast::terrain::subset::{BlockSubset, Quadrant};
//!
//! // A leaf two levels below its resident ancestor, whose block has 8 × 8 cells (§5): the leaf is in the second
//! // half of its parent's columns and the first half of its rows; the parent in the first half of the
//! // ancestor's columns and the second half of its rows.
//! let s = BlockSubset::new(8)?
//!     .step_up(Quadrant::new(true, false))?
//!     .step_up(Quadrant::new(false, true))?;
//! assert_eq!(s.levels(), 2);
//! assert_eq!(s.extent(), 2); // 8 >> 2
//! assert_eq!((s.cols(), s.rows()), ([2, 4], [4, 6]));
//! // The same rectangle from the leaf's position among the ancestor's 4 × 4 level-2 descendants.
//! assert_eq!(BlockSubset::of_descendant(8, 2, 1, 2)?, s);
//! # Ok::<(), curvicast::terrain::subset::SubsetError>(())
//! ```

use core::fmt;

/// The largest block size `B` (cells per block side) accepted: `2^15`. It is the largest power of two whose
/// block's samples, `(B + 1)² < 2^32`, can all be indexed with a `u32`.
pub const MAX_BLOCK_CELLS: u32 = 1 << 15;

/// The most steps up a [`BlockSubset`] accepts: 64. A quadtree over `u32` grid indices has at most 32 levels,
/// so a longer ancestor walk means a malformed tree; 64 keeps a leaf's index among the ancestor's descendants
/// within a `u64` ([`BlockSubset::of_descendant`]).
pub const MAX_LEVELS: u32 = 64;

/// Which quarter of its parent a node covers, in index terms (Wartell et al. §5's west/east, south/north child).
///
/// `x_high` is true when the node covers the second (higher-index) half of its parent's cell **columns**,
/// `y_high` when it covers the second half of its parent's cell **rows**. In a grid whose columns run eastwards
/// and rows northwards (a [`super::Grid`] with `dlon_deg > 0`, `dlat_deg > 0`) these are the paper's east and north
/// children; in a grid whose rows run southwards, `y_high` is the southern half. The indexing only ever uses
/// "first half / second half", never geography.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Quadrant {
    /// The node covers the second half of its parent's columns (`x`): the paper's east child.
    pub x_high: bool,
    /// The node covers the second half of its parent's rows (`y`): the paper's north child.
    pub y_high: bool,
}

impl Quadrant {
    /// The quadrant from its two halves: `x_high` (second half of the columns), `y_high` (second half of the
    /// rows).
    #[must_use]
    pub const fn new(x_high: bool, y_high: bool) -> Self {
        Quadrant { x_high, y_high }
    }
}

/// Invalid input to [`BlockSubset`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SubsetError {
    /// The block size (cells per side) is not a power of two in `1 ..= MAX_BLOCK_CELLS`.
    InvalidBlockCells(u32),
    /// More than [`MAX_LEVELS`] steps up.
    TooManyLevels,
    /// [`BlockSubset::of_descendant`]: a column or row index not below `2^levels`.
    DescendantOutOfRange,
}

impl fmt::Display for SubsetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SubsetError::InvalidBlockCells(b) => write!(
                f,
                "block size {b} is not a power of two in 1..={MAX_BLOCK_CELLS} cells"
            ),
            SubsetError::TooManyLevels => {
                write!(f, "block subset more than {MAX_LEVELS} levels up")
            }
            SubsetError::DescendantOutOfRange => f.write_str(
                "descendant index outside the ancestor's 2^levels × 2^levels descendants",
            ),
        }
    }
}

impl core::error::Error for SubsetError {}

/// The rectangle of an ancestor's block that covers a leaf `levels` steps below it (Wartell et al. §5): the half-open
/// cell range `[x_min, x_max) × [y_min, y_max)` of a block of `B × B` cells (`x` = columns, `y` = rows).
///
/// Always `0 ≤ x_min < x_max ≤ B` and `0 ≤ y_min < y_max ≤ B`, with `x_max − x_min = y_max − y_min =`
/// [`extent`](Self::extent) `= max(1, B >> levels)` (proof in the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlockSubset {
    block_cells: u32,
    levels: u32,
    x_min: u32,
    y_min: u32,
}

/// `true` when `b` is a power of two in `1 ..= MAX_BLOCK_CELLS`.
const fn valid_block(b: u32) -> bool {
    b.is_power_of_two() && b <= MAX_BLOCK_CELLS
}

impl BlockSubset {
    /// The whole block of `block_cells × block_cells` cells, zero levels up: the start of the ancestor loop.
    ///
    /// # Errors
    /// [`SubsetError::InvalidBlockCells`] unless `block_cells` is a power of two in `1 ..= MAX_BLOCK_CELLS`.
    pub const fn new(block_cells: u32) -> Result<Self, SubsetError> {
        if !valid_block(block_cells) {
            return Err(SubsetError::InvalidBlockCells(block_cells));
        }
        Ok(BlockSubset {
            block_cells,
            levels: 0,
            x_min: 0,
            y_min: 0,
        })
    }

    /// One step of the ancestor loop (§5): `child` is the quadrant, within its parent, of the node being left;
    /// the result is the subset of the parent's block (same block size) covering the original leaf.
    ///
    /// # Errors
    /// [`SubsetError::TooManyLevels`] if `self` is already [`MAX_LEVELS`] levels up.
    pub const fn step_up(self, child: Quadrant) -> Result<Self, SubsetError> {
        if self.levels >= MAX_LEVELS {
            return Err(SubsetError::TooManyLevels);
        }
        let half = self.block_cells / 2;
        Ok(BlockSubset {
            block_cells: self.block_cells,
            // Cannot saturate: levels < MAX_LEVELS.
            levels: self.levels.saturating_add(1),
            x_min: halve(self.x_min, child.x_high, half),
            y_min: halve(self.y_min, child.y_high, half),
        })
    }

    /// The subset covering the level-`levels` descendant in column `x` and row `y` of the ancestor's
    /// `2^levels × 2^levels` descendants (0 = the first, lowest-index one): directly, without the loop. Equal
    /// to `levels` calls of [`step_up`](Self::step_up) with the bits of `x` and `y`, least significant (the
    /// leaf's own quadrant) first. Here `x_min = ⌊B·x / 2^levels⌋`.
    ///
    /// # Errors
    /// [`SubsetError::InvalidBlockCells`] as for [`new`](Self::new); [`SubsetError::TooManyLevels`] if
    /// `levels > MAX_LEVELS`; [`SubsetError::DescendantOutOfRange`] if `x` or `y` is not below `2^levels`.
    pub fn of_descendant(
        block_cells: u32,
        levels: u32,
        x: u64,
        y: u64,
    ) -> Result<Self, SubsetError> {
        let whole = Self::new(block_cells)?;
        if levels > MAX_LEVELS {
            return Err(SubsetError::TooManyLevels);
        }
        // `None` for levels = 64: every u64 is below 2^64.
        if let Some(count) = 1_u64.checked_shl(levels) {
            if x >= count || y >= count {
                return Err(SubsetError::DescendantOutOfRange);
            }
        }
        let k = block_cells.trailing_zeros(); // B = 2^k, k ≤ 15
        // ⌊2^k·v / 2^L⌋ = v << (k − L) (exact, < 2^k) for L ≤ k, else v >> (L − k) (< 2^k as v < 2^L).
        let scale = |v: u64| -> Result<u32, SubsetError> {
            let scaled = match k.checked_sub(levels) {
                Some(up) => v.checked_shl(up),
                // A shift by 64 (B = 1, levels = 64) is `None` from `checked_shr`: the quotient is 0.
                None => Some(v.checked_shr(levels.saturating_sub(k)).unwrap_or(0)),
            };
            // Below `B` by the range check above (so no filter against `B` here).
            scaled
                .and_then(|s| u32::try_from(s).ok())
                .ok_or(SubsetError::DescendantOutOfRange)
        };
        Ok(BlockSubset {
            levels,
            x_min: scale(x)?,
            y_min: scale(y)?,
            ..whole
        })
    }

    /// The block size `B`: cells per block side.
    #[must_use]
    pub const fn block_cells(&self) -> u32 {
        self.block_cells
    }

    /// The number of steps up from the leaf (the paper's `levels`).
    #[must_use]
    pub const fn levels(&self) -> u32 {
        self.levels
    }

    /// Cells per side of the rectangle: `max(1, B >> levels)` (no shift overflow for `levels ≥ 32`).
    #[must_use]
    pub const fn extent(&self) -> u32 {
        match self.block_cells.checked_shr(self.levels) {
            Some(e) if e > 0 => e,
            _ => 1,
        }
    }

    /// First column (inclusive).
    #[must_use]
    pub const fn x_min(&self) -> u32 {
        self.x_min
    }

    /// First row (inclusive).
    #[must_use]
    pub const fn y_min(&self) -> u32 {
        self.y_min
    }

    /// End column (exclusive), `≤ B`.
    #[must_use]
    pub const fn x_max(&self) -> u32 {
        // Never saturates: x_min + extent ≤ B ≤ 2^15 (module docs).
        self.x_min.saturating_add(self.extent())
    }

    /// End row (exclusive), `≤ B`.
    #[must_use]
    pub const fn y_max(&self) -> u32 {
        // Never saturates: y_min + extent ≤ B ≤ 2^15 (module docs).
        self.y_min.saturating_add(self.extent())
    }

    /// The cell columns `[x_min, x_max)`, in [`super::Node`]'s convention.
    #[must_use]
    pub const fn cols(&self) -> [u32; 2] {
        [self.x_min, self.x_max()]
    }

    /// The cell rows `[y_min, y_max)`, in [`super::Node`]'s convention.
    #[must_use]
    pub const fn rows(&self) -> [u32; 2] {
        [self.y_min, self.y_max()]
    }
}

/// One step of the paper's update: `v / 2`, plus `half = B / 2` when the node left is in the second half.
/// `v < B` gives `v / 2 < B / 2`, a power of two (or 0 for `B = 1`, when `v = 0`), so the sum has no carry and is
/// the bitwise or.
const fn halve(v: u32, high: bool, half: u32) -> u32 {
    let v = v / 2;
    if high { v | half } else { v }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LL: Quadrant = Quadrant::new(false, false);
    const HL: Quadrant = Quadrant::new(true, false);
    const LH: Quadrant = Quadrant::new(false, true);
    const HH: Quadrant = Quadrant::new(true, true);

    fn rect(s: BlockSubset) -> ([u32; 2], [u32; 2]) {
        (s.cols(), s.rows())
    }

    #[test]
    fn single_cell_block_is_always_the_whole_cell() {
        let mut s = BlockSubset::new(1).unwrap();
        for (i, q) in [HH, LL, HL, LH, HH, HH].iter().cycle().take(70).enumerate() {
            match s.step_up(*q) {
                Ok(n) => s = n,
                Err(e) => {
                    assert_eq!((i, e), (64, SubsetError::TooManyLevels));
                    break;
                }
            }
            assert_eq!(rect(s), ([0, 1], [0, 1]));
        }
        assert_eq!(s.levels(), MAX_LEVELS);
    }

    #[test]
    fn accessors_report_block_size_levels_and_first_column_and_row() {
        // Block of 8 cells, two levels up from the leaf in column 3, row 1 of the 4 × 4 descendants.
        let s = BlockSubset::of_descendant(8, 2, 3, 1).unwrap();
        assert_eq!(
            (
                s.block_cells(),
                s.levels(),
                s.extent(),
                s.x_min(),
                s.y_min()
            ),
            (8, 2, 2, 6, 2)
        );
        assert_eq!((s.x_max(), s.y_max()), (8, 4));
    }

    #[test]
    fn errors_say_what_is_wrong() {
        use std::string::ToString;
        let text = |e: SubsetError| e.to_string();
        assert!(
            text(SubsetError::InvalidBlockCells(6)).contains("block size 6 is not a power of two")
        );
        assert!(text(SubsetError::TooManyLevels).contains("more than 64 levels up"));
        assert!(text(SubsetError::DescendantOutOfRange).contains("descendant index outside"));
    }

    #[test]
    fn four_children_one_level_up() {
        let b = BlockSubset::new(8).unwrap();
        assert_eq!(rect(b), ([0, 8], [0, 8]));
        assert_eq!(rect(b.step_up(LL).unwrap()), ([0, 4], [0, 4]));
        assert_eq!(rect(b.step_up(HL).unwrap()), ([4, 8], [0, 4]));
        assert_eq!(rect(b.step_up(LH).unwrap()), ([0, 4], [4, 8]));
        assert_eq!(rect(b.step_up(HH).unwrap()), ([4, 8], [4, 8]));
    }

    #[test]
    fn deep_path_past_the_cell_size_and_past_32_levels() {
        // B = 16; the leaf's own quadrant first. x bits (leaf first) 1,0,1,1 → x = 0b1101 = 13 of 16 columns at
        // level 4, i.e. cell 13 of the block; y bits 0,1,1,0 → y = 0b0110 = 6.
        let mut s = BlockSubset::new(16).unwrap();
        for q in [HL, LH, HH, HL] {
            s = s.step_up(q).unwrap();
        }
        assert_eq!((s.levels(), s.extent()), (4, 1));
        assert_eq!(rect(s), ([13, 14], [6, 7]));
        // One more level: level-5 index x = 13 + 16 = 29 → cell ⌊16·29/32⌋ = 14; y = 6 → cell 3.
        s = s.step_up(HL).unwrap();
        assert_eq!(rect(s), ([14, 15], [3, 4]));
        // Then the all-high path: x_min → 15 and stays there, at and past 32 levels (no shift overflow).
        for _ in 5..40 {
            s = s.step_up(HH).unwrap();
            assert_eq!(s.extent(), 1);
        }
        assert_eq!((s.levels(), rect(s)), (40, ([15, 16], [15, 16])));
    }

    #[test]
    fn largest_block_stays_in_range() {
        let mut s = BlockSubset::new(MAX_BLOCK_CELLS).unwrap();
        for _ in 0..MAX_LEVELS {
            s = s.step_up(HH).unwrap();
            assert!(s.x_min() < s.x_max() && s.x_max() <= MAX_BLOCK_CELLS);
        }
        assert_eq!(
            rect(s),
            (
                [MAX_BLOCK_CELLS - 1, MAX_BLOCK_CELLS],
                [MAX_BLOCK_CELLS - 1, MAX_BLOCK_CELLS]
            )
        );
        assert_eq!(s.step_up(LL), Err(SubsetError::TooManyLevels));
    }

    #[test]
    fn invalid_block_sizes_are_errors() {
        for b in [0, 3, 6, 12, 1 << 16, 1 << 31, u32::MAX] {
            assert_eq!(BlockSubset::new(b), Err(SubsetError::InvalidBlockCells(b)));
            assert_eq!(
                BlockSubset::of_descendant(b, 0, 0, 0),
                Err(SubsetError::InvalidBlockCells(b))
            );
        }
        for k in 0..=15 {
            assert!(BlockSubset::new(1 << k).is_ok());
        }
    }

    #[test]
    fn of_descendant_matches_the_loop() {
        for b in [1, 2, 8] {
            for levels in 0..=5_u32 {
                for x in 0..1_u64 << levels {
                    let y = (x * 5 + 3) % (1 << levels);
                    let mut s = BlockSubset::new(b).unwrap();
                    for i in 0..levels {
                        s = s
                            .step_up(Quadrant::new((x >> i) & 1 == 1, (y >> i) & 1 == 1))
                            .unwrap();
                    }
                    assert_eq!(BlockSubset::of_descendant(b, levels, x, y), Ok(s));
                }
            }
        }
        let top = BlockSubset::of_descendant(4, 64, u64::MAX, 0).unwrap();
        assert_eq!(rect(top), ([3, 4], [0, 1]));
        // B = 1 at MAX_LEVELS: a shift by 64 (found by the host property test).
        let one = BlockSubset::of_descendant(1, 64, u64::MAX, 0).unwrap();
        assert_eq!(rect(one), ([0, 1], [0, 1]));
    }

    #[test]
    fn of_descendant_errors() {
        assert_eq!(
            BlockSubset::of_descendant(4, 2, 4, 0),
            Err(SubsetError::DescendantOutOfRange)
        );
        assert_eq!(
            BlockSubset::of_descendant(4, 2, 0, 4),
            Err(SubsetError::DescendantOutOfRange)
        );
        assert_eq!(
            BlockSubset::of_descendant(4, 0, 1, 0),
            Err(SubsetError::DescendantOutOfRange)
        );
        assert_eq!(
            BlockSubset::of_descendant(4, 65, 0, 0),
            Err(SubsetError::TooManyLevels)
        );
    }
}
