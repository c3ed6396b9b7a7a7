//! One coordinate's sequence of boundary crossings along a ray (Hannasch §3.1.1–3.1.2 for the separable form,
//! ch. 5 for the serial one): each stream yields `(t, new band)` events in nondecreasing `t`, one band step each.
//!
//! A stream's state is a few scalars; its next crossing is computed only when the previous one has been consumed
//! (the caller caches it), so each radius or zenith crossing costs one square root and each azimuth or z crossing
//! one division. The streams are independent of each other, which is what lets the serial and the separable engines interleave
//! the very same events and agree exactly.
//!
//! **Topology first.** Which boundary comes next is decided by logic that cannot step by more than one band:
//! * radius (ditone, Lemma 8): a descending phase (before the hinge, entering ever smaller spheres while the line
//!   meets them) and then an ascending phase (leaving ever larger spheres);
//! * zenith (ditone, Lemma 4): a first phase in the direction θ moves at the start (the sign of
//!   `⟨p + t d | d_z p − p_z d⟩`, Lemma 2), crossing the next cone's matching side, and at most one switch to the
//!   other direction when that cone is not reached (the hinge);
//! * azimuth (monotone, Lemma 6): the turning sense is the sign of `(p × d)_z`; the next boundary half-plane in
//!   that sense;
//! * height: the sign of `d_z`.
//!
//! The `t` of each event comes from the shared `surface` solvers and is clamped to be no smaller than the previous
//! event's, so a slightly inaccurate `t` can shorten a crossing to zero length but never reorder the cells.
//!
//! **Degenerate lines.** A line through the center (`p × d = 0`) keeps θ constant except for a jump from θ to
//! π − θ at the center; a line meeting the z axis keeps φ constant except for a jump by π there. Both jumps are
//! emitted as one band step per crossed boundary, all at the same `t` (zero-length crossings, Hannasch §3.1.4).
//! For the azimuth jump the walk goes the way round that stays inside a wedge when one does (a full turn: the
//! shorter way, counter-clockwise on a tie). A line parallel to the z axis keeps φ constant.

mod azimuth;
mod height;
mod radial;
mod state;
mod zenith;

pub(crate) use radial::RadialLine;
pub(crate) use state::{Event, StepKind, Stream};
pub(crate) use zenith::SecondRoots;
#[cfg(test)]
pub(crate) use zenith::zenith_event_bound;
