//! Integer block-subset indexing (Wartell et al. §5, last paragraph) against exact rational arithmetic.
//!
//! The oracle shares nothing with the kernel's halving: it walks **down** from the ancestor to the leaf,
//! subdividing the ancestor's unit side as exact rationals (`[lo/den, hi/den]`, numerators and denominator in
//! `u128`, the denominator doubling per level), so the leaf's interval is `[X/2^L, (X+1)/2^L]`. Scaled by the
//! block size `B`, the cells it touches are `[⌊B·lo/den⌋, ⌈B·hi/den⌉)`. The kernel gets the same path reversed
//! (leaf first, walking up) and must produce exactly that rectangle, with `0 ≤ min < max ≤ B`.
//!
//! * exhaustive: every `B = 1, 2, 4, …, 1024`, every depth `L = 0..=12`, every path per axis (`2^L`), each axis
//!   with the other held at both extremes; and every joint 2-D path (`4^L`) for `L ≤ 6`;
//! * property test: `B` up to `2^15`, depth up to `MAX_LEVELS` (64; `B·2^64 < 2^80` keeps `u128` exact), and the
//!   step past `MAX_LEVELS` is an error.

use curvicast::terrain::subset::{BlockSubset, MAX_BLOCK_CELLS, MAX_LEVELS, Quadrant, SubsetError};
use proptest::prelude::*;

/// The exact rational cell range `[floor, ceil)` of the leaf reached from the ancestor by `down` (`true` = the
/// second half), in a block of `b` cells per side.
fn oracle(b: u32, down: &[bool]) -> (u32, u32) {
    let (mut lo, mut hi, mut den) = (0_u128, 1_u128, 1_u128);
    for &second in down {
        // [lo, hi]/den halves at (lo + hi)/(2 den); everything over 2 den.
        let mid = lo + hi;
        (lo, hi) = if second { (mid, 2 * hi) } else { (2 * lo, mid) };
        den *= 2;
    }
    let b = u128::from(b);
    let floor = b * lo / den;
    let ceil = (b * hi).div_ceil(den);
    (
        u32::try_from(floor).expect("floor ≤ B"),
        u32::try_from(ceil).expect("ceil ≤ B"),
    )
}

/// The kernel's rectangle for a leaf reached by the two root-to-leaf paths (equal lengths).
fn kernel(b: u32, down_x: &[bool], down_y: &[bool]) -> BlockSubset {
    assert_eq!(down_x.len(), down_y.len());
    let mut s = BlockSubset::new(b).expect("valid block size");
    // Walk up: the leaf's own quadrant (the last step down) first.
    for (&x, &y) in down_x.iter().zip(down_y).rev() {
        s = s.step_up(Quadrant::new(x, y)).expect("within MAX_LEVELS");
    }
    s
}

/// Checks one leaf: both axes against the oracle, bounds, and the level count.
fn check(b: u32, down_x: &[bool], down_y: &[bool]) {
    let s = kernel(b, down_x, down_y);
    let (ox, oy) = (oracle(b, down_x), oracle(b, down_y));
    let ctx = || format!("B = {b}, x path {down_x:?}, y path {down_y:?}");
    assert_eq!((s.x_min(), s.x_max()), ox, "columns, {}", ctx());
    assert_eq!((s.y_min(), s.y_max()), oy, "rows, {}", ctx());
    assert!(s.x_min() < s.x_max() && s.x_max() <= b, "{}", ctx());
    assert!(s.y_min() < s.y_max() && s.y_max() <= b, "{}", ctx());
    assert_eq!(s.cols(), [ox.0, ox.1]);
    assert_eq!(s.rows(), [oy.0, oy.1]);
    assert_eq!(s.levels() as usize, down_x.len());
    assert_eq!(s.extent(), s.x_max() - s.x_min());
    assert_eq!(s.extent(), s.y_max() - s.y_min());
}

/// The path with `bits`' `len` low bits, most significant first (the first step down from the ancestor).
fn path(bits: u64, len: usize) -> Vec<bool> {
    (0..len).rev().map(|i| (bits >> i) & 1 == 1).collect()
}

const BLOCKS: [u32; 11] = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024];

#[test]
fn every_path_per_axis_to_depth_12_every_block_size_to_1024() {
    let mut leaves = 0_u64;
    for b in BLOCKS {
        for depth in 0..=12_usize {
            let low = vec![false; depth];
            let high = vec![true; depth];
            for bits in 0..1_u64 << depth {
                let p = path(bits, depth);
                for other in [&low, &high] {
                    check(b, &p, other);
                    check(b, other, &p);
                }
                leaves += 1;
            }
        }
    }
    assert_eq!(leaves, 11 * ((1 << 13) - 1));
}

#[test]
fn every_joint_path_to_depth_6_every_block_size_to_1024() {
    let mut leaves = 0_u64;
    for b in BLOCKS {
        for depth in 0..=6_usize {
            for bx in 0..1_u64 << depth {
                for by in 0..1_u64 << depth {
                    check(b, &path(bx, depth), &path(by, depth));
                    leaves += 1;
                }
            }
        }
    }
    assert_eq!(leaves, 11 * (1 + 4 + 16 + 64 + 256 + 1024 + 4096));
}

/// The direct constructor agrees with the oracle too (it is not the oracle: the loop is tested above).
#[test]
fn of_descendant_every_leaf_to_depth_10() {
    for b in BLOCKS {
        for depth in 0..=10_usize {
            for bits in 0..1_u64 << depth {
                let y = (bits * 7 + 1) % (1 << depth);
                let s = BlockSubset::of_descendant(b, depth as u32, bits, y).unwrap();
                assert_eq!((s.x_min(), s.x_max()), oracle(b, &path(bits, depth)));
                assert_eq!((s.y_min(), s.y_max()), oracle(b, &path(y, depth)));
                assert_eq!(s, kernel(b, &path(bits, depth), &path(y, depth)));
            }
        }
    }
}

#[test]
fn block_sizes_that_are_not_powers_of_two_up_to_2_pow_15_are_rejected() {
    for b in 0..=2 * MAX_BLOCK_CELLS {
        let valid = b.is_power_of_two() && b <= MAX_BLOCK_CELLS;
        match BlockSubset::new(b) {
            Ok(s) => {
                assert!(valid, "B = {b} accepted");
                assert_eq!((s.cols(), s.rows(), s.extent()), ([0, b], [0, b], b));
            }
            Err(e) => {
                assert!(!valid, "B = {b} rejected");
                assert_eq!(e, SubsetError::InvalidBlockCells(b));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    #[test]
    fn random_paths_to_max_levels_match_the_rational_oracle(
        k in 0_u32..=15,
        steps in prop::collection::vec(any::<(bool, bool)>(), 0..=MAX_LEVELS as usize),
    ) {
        let b = 1_u32 << k;
        let (xs, ys): (Vec<bool>, Vec<bool>) = steps.iter().copied().unzip();
        check(b, &xs, &ys);
        let s = kernel(b, &xs, &ys);
        if s.levels() == MAX_LEVELS {
            prop_assert_eq!(s.step_up(Quadrant::new(true, true)), Err(SubsetError::TooManyLevels));
        }
        // Leaf index among the ancestor's 2^L descendants, for the direct constructor.
        let index = |p: &[bool]| p.iter().fold(0_u64, |a, &h| (a << 1) | u64::from(h));
        prop_assert_eq!(BlockSubset::of_descendant(b, s.levels(), index(&xs), index(&ys)), Ok(s));
    }

    #[test]
    fn random_paths_to_depth_30(
        k in 0_u32..=15,
        steps in prop::collection::vec(any::<(bool, bool)>(), 0..=30),
    ) {
        let (xs, ys): (Vec<bool>, Vec<bool>) = steps.iter().copied().unzip();
        check(1 << k, &xs, &ys);
    }
}
