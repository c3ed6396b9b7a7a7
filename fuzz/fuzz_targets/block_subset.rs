//! Fuzz target `block_subset`: integer block-subset indexing (`curvicast::terrain::subset`, Wartell et al. §5) on an
//! arbitrary block size (valid or not) and an arbitrary walk of up to 80 steps up (past `MAX_LEVELS`), plus the
//! direct constructor on arbitrary indices.
//!
//! Checked on every input:
//! * nothing panics;
//! * `BlockSubset::new` accepts exactly the powers of two up to `MAX_BLOCK_CELLS`; `step_up` succeeds exactly
//!   while fewer than `MAX_LEVELS` steps were taken, then returns `TooManyLevels`;
//! * every `Ok` rectangle is non-empty and inside the block: `0 ≤ min < max ≤ B` on both axes, of side
//!   `max(1, B >> levels)`;
//! * it equals the exact rational answer: the leaf's interval `[X/2^L, (X+1)/2^L]` of the ancestor's side,
//!   computed by subdividing downwards in `u128` (exact to 64 levels with `B ≤ 2^15`), scaled by `B`, rounded
//!   outwards to cells;
//! * `BlockSubset::of_descendant` accepts exactly the in-range indices and agrees with the walk and the oracle.

#![no_main]

use arbitrary::Arbitrary;
use curvicast::terrain::subset::{BlockSubset, MAX_BLOCK_CELLS, MAX_LEVELS, Quadrant, SubsetError};
use libfuzzer_sys::fuzz_target;

/// A block size: `2^e` (often valid, sometimes too large or, past 31, zero) or any `u32`.
#[derive(Arbitrary, Debug)]
enum Block {
    Exp(u8),
    Raw(u32),
}

#[derive(Arbitrary, Debug)]
struct Input {
    block: Block,
    /// Steps up, leaf first: bit 0 = second half of the columns, bit 1 = second half of the rows.
    steps: Vec<u8>,
    /// For `of_descendant`: levels, column, row.
    direct: (u8, u64, u64),
}

const MAX_STEPS: usize = 80;

/// Exact cell range `[⌊B·lo⌋, ⌈B·hi⌉)` of the leaf reached from the ancestor by `down` (root to leaf).
fn oracle(b: u32, down: impl Iterator<Item = bool>) -> (u32, u32) {
    let (mut lo, mut hi, mut den) = (0_u128, 1_u128, 1_u128);
    for second in down {
        let mid = lo + hi;
        (lo, hi) = if second { (mid, 2 * hi) } else { (2 * lo, mid) };
        den *= 2;
    }
    let b = u128::from(b);
    let floor = u32::try_from(b * lo / den).unwrap();
    let ceil = u32::try_from((b * hi).div_ceil(den)).unwrap();
    (floor, ceil)
}

/// Checks `s` (reached by `up`, leaf first) against the oracle and the bounds.
fn check(b: u32, up: &[u8], s: BlockSubset) {
    let levels = up.len();
    assert_eq!(s.levels() as usize, levels);
    assert_eq!(s.block_cells(), b);
    let extent = u32::try_from((u128::from(b) >> levels).max(1)).unwrap();
    assert_eq!(s.extent(), extent);
    let ox = oracle(b, up.iter().rev().map(|q| q & 1 == 1));
    let oy = oracle(b, up.iter().rev().map(|q| q & 2 == 2));
    assert_eq!((s.x_min(), s.x_max()), ox, "columns, B = {b}, steps {up:?}");
    assert_eq!((s.y_min(), s.y_max()), oy, "rows, B = {b}, steps {up:?}");
    assert!(s.x_min() < s.x_max() && s.x_max() <= b);
    assert!(s.y_min() < s.y_max() && s.y_max() <= b);
    assert_eq!(s.x_max() - s.x_min(), extent);
    assert_eq!(s.y_max() - s.y_min(), extent);
    assert_eq!((s.cols(), s.rows()), ([ox.0, ox.1], [oy.0, oy.1]));
}

fuzz_target!(|input: Input| {
    let b = match input.block {
        Block::Exp(e) => 1_u32.checked_shl(u32::from(e % 40)).unwrap_or(0),
        Block::Raw(b) => b,
    };
    let valid = b.is_power_of_two() && b <= MAX_BLOCK_CELLS;

    // The direct constructor on arbitrary indices.
    let (levels, x, y) = input.direct;
    let levels = u32::from(levels % 72);
    let in_range = |v: u64| 1_u64.checked_shl(levels).is_none_or(|n| v < n);
    match BlockSubset::of_descendant(b, levels, x, y) {
        Ok(s) => {
            assert!(valid && levels <= MAX_LEVELS && in_range(x) && in_range(y));
            // The walk with the bits of x and y, least significant (the leaf's quadrant) first.
            let up: Vec<u8> = (0..levels)
                .map(|i| u8::from((x >> i) & 1 == 1) | (u8::from((y >> i) & 1 == 1) << 1))
                .collect();
            check(b, &up, s);
        }
        Err(SubsetError::InvalidBlockCells(e)) => assert!(!valid && e == b),
        Err(SubsetError::TooManyLevels) => assert!(valid && levels > MAX_LEVELS),
        Err(SubsetError::DescendantOutOfRange) => {
            assert!(valid && levels <= MAX_LEVELS && !(in_range(x) && in_range(y)))
        }
    }

    // The incremental walk.
    let mut s = match BlockSubset::new(b) {
        Ok(s) => {
            assert!(valid, "B = {b} accepted");
            s
        }
        Err(e) => {
            assert!(!valid && e == SubsetError::InvalidBlockCells(b));
            return;
        }
    };
    check(b, &[], s);
    let steps = &input.steps[..input.steps.len().min(MAX_STEPS)];
    for (i, &q) in steps.iter().enumerate() {
        match s.step_up(Quadrant::new(q & 1 == 1, q & 2 == 2)) {
            Ok(next) => {
                assert!(i < MAX_LEVELS as usize);
                s = next;
                check(b, &steps[..=i], s);
            }
            Err(e) => {
                assert_eq!((i, e), (MAX_LEVELS as usize, SubsetError::TooManyLevels));
                break;
            }
        }
    }
});
