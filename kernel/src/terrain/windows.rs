//! Leaf windows (beyond the paper): a storage with node boxes may also give each full-resolution leaf the boxes of
//! its *windows*, a split of its cells into up to 4 × 4 rectangles of about 4 × 4 cells ([`window_ranges`]), each
//! box in the frame of the leaf's own box and quantized to 255ths of the leaf box's extent per axis, rounded
//! outwards ([`WindowBox`]: 6 bytes, so 0.375 bytes per height for leaves of 8 × 8 or 16 × 16 cells; leaves of
//! at most 4 × 4 cells, one window each, have none).
//!
//! A window's box contains all of its cells' vertices, so the triangles of its cells (the leaf walk, `leaf.rs`,
//! traces only its own block's plain cells here: stride 1, no stitching). The leaf walk then traces, in order of
//! entry, only the windows whose boxes the ray enters before the best hit, each over the part of the ray inside
//! its box and clipped to its own columns and rows: a hit in a window's cell lies in that part, so no hit is
//! lost, and the walk skips the columns and rows of windows the ray passes above. A ray whose part in the leaf
//! moves less than an eighth of a window sideways (a steep one, as from orbit) is traced whole: it crosses few
//! cells anyway (callgrind: an eighth did better than a quarter, a half or a whole window from a camera 2 km up,
//! and as well from orbit; every ray by windows cost 4 to 9 % more from orbit).

use super::boxes::{FrameRay, NodeBox};
use super::error::TerrainError;
use super::picker::Picker;
use super::storage::TerrainCaches;
use super::walk::{Unit, Walk};
use crate::real::Real;
use crate::sort::insertion_sort;

/// The cells along a window's side that the split aims at.
pub const WINDOW_CELLS: u32 = 4;
/// The most windows along one side of a leaf.
pub const WINDOWS_PER_SIDE: u32 = 4;

/// The box of one window of a leaf (module docs), relative to the leaf's [`NodeBox`]: per axis (east, north,
/// up) the low and high faces as `lo + (hi − lo)·q/255` of the leaf box's `lo` and `hi`, rounded outwards. A
/// window without data has `lo > hi` on every axis ([`WindowBox::EMPTY`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WindowBox {
    /// Low faces (east, north, up), in 255ths of the leaf box.
    pub lo: [u8; 3],
    /// High faces.
    pub hi: [u8; 3],
}

impl WindowBox {
    /// A window without data (and an unbuilt slot): no ray enters it.
    pub const EMPTY: WindowBox = WindowBox {
        lo: [u8::MAX; 3],
        hi: [0; 3],
    };

    /// The window box of `window` (a box in the frame of `leaf`, inside it) rounded outwards to 255ths of
    /// `leaf`: every real point of `window` lies inside the exact faces `lo + (hi − lo)·q/255`.
    pub fn quantize(leaf: &NodeBox, window: &NodeBox) -> WindowBox {
        let mut out = WindowBox::EMPTY;
        for k in 0..3 {
            let get = |a: &[f32; 3]| a.get(k).map_or(f64::NAN, |&v| f64::from(v));
            let (l, h) = (get(&leaf.lo), get(&leaf.hi));
            let (wl, wh) = (get(&window.lo), get(&window.hi));
            // The first guesses (truncated) are moved outwards until each face, computed in f64, clears the
            // window by its rounding (a few ulps of the larger end).
            let slack = 8.0 * f64::EPSILON * (l.abs() + h.abs());
            let face = |q: u8| l + (h - l) * (f64::from(q) / 255.0);
            let scale = if h > l { 255.0 / (h - l) } else { 0.0 };
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let mut q_lo = ((wl - l) * scale).clamp(0.0, 255.0) as u8;
            while q_lo > 0 && !(face(q_lo) + slack <= wl) {
                q_lo = q_lo.saturating_sub(1);
            }
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let mut q_hi = ((wh - l) * scale).clamp(0.0, 255.0) as u8;
            while q_hi < u8::MAX && !(face(q_hi) - slack >= wh) {
                q_hi = q_hi.saturating_add(1);
            }
            if let (Some(a), Some(b)) = (out.lo.get_mut(k), out.hi.get_mut(k)) {
                (*a, *b) = (q_lo, q_hi);
            }
        }
        out
    }

    /// The window's faces `(lo, hi)` in `T` ([`Faces::of`]).
    pub fn faces<T: Real>(&self, leaf: &NodeBox) -> ([T; 3], [T; 3]) {
        Faces::new(leaf).of(self)
    }
}

/// A leaf box's constants for decoding its windows' faces in `T`: per axis its low face, a 255th of its extent,
/// and the rounding of a face so computed (`8 ε` of the box's coordinates).
#[derive(Debug, Clone, Copy)]
pub struct Faces<T> {
    base: [T; 3],
    step: [T; 3],
    slack: [T; 3],
}

impl<T: Real> Faces<T> {
    /// The constants of `leaf`.
    #[inline]
    pub fn new(leaf: &NodeBox) -> Self {
        let at = |v: f32| T::from_f64(f64::from(v));
        let (inv255, eps8) = (T::from_f64(1.0 / 255.0), T::from_f64(8.0) * T::EPSILON);
        let (lo, hi) = (leaf.lo.map(at), leaf.hi.map(at));
        let mut f = Faces {
            base: lo,
            step: [T::ZERO; 3],
            slack: [T::ZERO; 3],
        };
        for (k, (&l, &h)) in lo.iter().zip(&hi).enumerate() {
            if let (Some(step), Some(slack)) = (f.step.get_mut(k), f.slack.get_mut(k)) {
                *step = (h - l) * inv255;
                *slack = eps8 * (l.abs() + h.abs());
            }
        }
        f
    }

    /// Window `w`'s faces `(lo, hi)`, widened by their rounding so that they contain the exact faces
    /// `lo + (hi − lo)·q/255`.
    #[inline]
    pub fn of(&self, w: &WindowBox) -> ([T; 3], [T; 3]) {
        let face = |k: usize, q: u8, sign: T| match (
            self.base.get(k),
            self.step.get(k),
            self.slack.get(k),
        ) {
            (Some(&b), Some(&s), Some(&e)) => b + s * T::from_f64(f64::from(q)) + sign * e,
            _ => T::NAN,
        };
        let (mut lo, mut hi) = ([T::ZERO; 3], [T::ZERO; 3]);
        for (k, ((l, h), (&ql, &qh))) in lo
            .iter_mut()
            .zip(hi.iter_mut())
            .zip(w.lo.iter().zip(&w.hi))
            .enumerate()
        {
            *l = face(k, ql, -T::ONE);
            *h = face(k, qh, T::ONE);
        }
        (lo, hi)
    }
}

/// How many windows split `cells` cells along one side of a leaf: about one per [`WINDOW_CELLS`], at least 1
/// and at most [`WINDOWS_PER_SIDE`].
pub const fn windows_per_side(cells: u32) -> u32 {
    let n = cells.div_ceil(WINDOW_CELLS);
    if n < 1 {
        1
    } else if n > WINDOWS_PER_SIDE {
        WINDOWS_PER_SIDE
    } else {
        n
    }
}

/// The window records per leaf of a tree with leaf blocks of `block × block` cells (a leaf at the grid's edge,
/// with fewer cells, uses the first of its records): none for blocks of at most [`WINDOW_CELLS`] cells, whose
/// leaves would be one window.
pub const fn windows_per_leaf(block: u32) -> usize {
    let n = windows_per_side(block) as usize;
    if n < 2 { 0 } else { n.saturating_mul(n) }
}

/// The cell ranges `(rows, cols)` of window `k` (row-major) of a leaf with cell ranges `rows` and `cols`, or
/// `None` past its last window: each side cut into [`windows_per_side`] nearly equal parts ([`WindowGrid`]).
pub fn window_ranges(rows: [u32; 2], cols: [u32; 2], k: usize) -> Option<([u32; 2], [u32; 2])> {
    WindowGrid::new(rows, cols).ranges(k)
}

/// How a leaf's cells split into windows: the cuts along each side, `lo + (hi − lo)·i/n` for `i` in `0..=n`.
#[derive(Debug, Clone, Copy)]
pub struct WindowGrid {
    rows: [u32; WINDOWS_PER_SIDE as usize + 1],
    cols: [u32; WINDOWS_PER_SIDE as usize + 1],
    /// Windows along the rows and along the columns.
    n: [u32; 2],
}

impl WindowGrid {
    /// The split of a leaf with cell ranges `rows` and `cols`.
    pub fn new(rows: [u32; 2], cols: [u32; 2]) -> Self {
        let cuts = |[lo, hi]: [u32; 2]| {
            let n = windows_per_side(hi.saturating_sub(lo));
            // in u64, so that it cannot overflow; `i ≤ n` keeps the result in `[lo, hi]`
            let cut = |i: u32| {
                let step = u64::from(hi.saturating_sub(lo))
                    .saturating_mul(u64::from(i.min(n)))
                    .checked_div(u64::from(n))
                    .unwrap_or(0);
                lo.saturating_add(u32::try_from(step).unwrap_or(u32::MAX))
            };
            (
                core::array::from_fn(|i| cut(u32::try_from(i).unwrap_or(u32::MAX))),
                n,
            )
        };
        let ((rows, nr), (cols, nc)) = (cuts(rows), cuts(cols));
        WindowGrid {
            rows,
            cols,
            n: [nr, nc],
        }
    }

    /// The number of windows.
    pub fn count(&self) -> usize {
        usize::try_from(self.n[0].saturating_mul(self.n[1])).unwrap_or(0)
    }

    /// Window `k`'s cell ranges `(rows, cols)`, or `None` past the last.
    pub fn ranges(&self, k: usize) -> Option<([u32; 2], [u32; 2])> {
        let nc = usize::try_from(self.n[1]).ok()?;
        let (a, b) = (k.checked_div(nc)?, k.checked_rem(nc)?);
        if a >= usize::try_from(self.n[0]).ok()? {
            return None;
        }
        let pair = |cuts: &[u32], i: usize| Some([*cuts.get(i)?, *cuts.get(i.checked_add(1)?)?]);
        Some((pair(&self.rows, a)?, pair(&self.cols, b)?))
    }
}

impl<T: Real, S: TerrainCaches<T>, const STACK: usize, const ZONES: usize>
    Picker<'_, T, S, STACK, ZONES>
{
    /// Traces a full-resolution leaf by its windows (module docs): `windows` its window boxes, `leaf` its box,
    /// `frame` the ray in the frame of that box (formed for an interval containing `[t_in, t_out]`).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn trace_windows(
        &self,
        u: &Unit,
        leaf: &NodeBox,
        frame: &FrameRay<T>,
        windows: &[WindowBox],
        t_in: T,
        t_out: T,
        w: &mut Walk<'_, '_, T>,
    ) -> Result<(), TerrainError> {
        let ray = w.ray;
        let span = [t_in.max(ray.t_min()), t_out.max(t_in).min(ray.t_max())];
        let sideways = |k: usize, [a, b]: [u32; 2]| {
            let n = windows_per_side(b.saturating_sub(a));
            let at = |a: &[f32; 3]| a.get(k).map_or(T::NAN, |&v| T::from_f64(f64::from(v)));
            let width = (at(&leaf.hi) - at(&leaf.lo)) / T::from_f64(f64::from(n));
            n > 1 && frame.travel(k, span) >= T::from_f64(0.125) * width
        };
        if !(sideways(0, u.cols) || sideways(1, u.rows)) {
            return self.trace_unit(u, t_in, t_out, w);
        }
        let grid = WindowGrid::new(u.rows, u.cols);
        // A storage that gives fewer boxes than the leaf has windows has its leaf walked whole.
        if windows.len() < grid.count() {
            return self.trace_unit(u, t_in, t_out, w);
        }
        let faces = Faces::new(leaf);
        let mut hits: heapless::Vec<(T, T, u8), 16> = heapless::Vec::new();
        for (k, wb) in windows.iter().enumerate().take(grid.count()) {
            let (lo, hi) = faces.of(wb);
            if let (Some((a, c)), Ok(k)) = (frame.interval_of(lo, hi, span), u8::try_from(k)) {
                // At most 16 windows, so the push cannot fail.
                let _ = hits.push((a, c, k));
            }
        }
        insertion_sort(&mut hits, |x, y| x.0 < y.0);
        let trace = self.unit_trace(u, ray, t_in, t_out);
        let mut row_hint = None;
        for &(a, c, k) in hits.iter() {
            let best_t = w.best_t();
            if a > best_t {
                break;
            }
            let Some(win) = grid.ranges(usize::from(k)) else {
                continue;
            };
            self.trace_window(&trace, win, a, c.min(best_t), w, &mut row_hint)?;
        }
        Ok(())
    }
}
