//! Statistics of the surface layer against the oracle: per kind and mode, the largest forward and backward errors and the mismatches, over a set of cases.

use super::*;

/// Worst cases and totals of one kind in one mode.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    /// Rays compared.
    pub rays: usize,
    /// Oracle crossings seen.
    pub crossings: usize,
    /// Of those, in the near-tangent band.
    pub in_band: usize,
    /// Largest forward error outside the band (units of `ε S`), and the case.
    pub max_forward: (f64, Option<SurfaceCase>),
    /// Largest backward error (units of `ε S_k`), and the case.
    pub max_backward: (f64, Option<SurfaceCase>),
    /// Count/side disagreements outside the band and ambiguity zones.
    pub mismatches: usize,
    /// The first few of them, described.
    pub mismatch_examples: Vec<String>,
}

impl Stats {
    fn add(&mut self, case: &SurfaceCase, r: &CaseOutcome) {
        self.rays += 1;
        self.crossings += r.oracle_crossings;
        self.in_band += r.in_band;
        if r.forward > self.max_forward.0 {
            self.max_forward = (r.forward, Some(*case));
        }
        if r.backward > self.max_backward.0 {
            self.max_backward = (r.backward, Some(*case));
        }
        if let Some(m) = &r.mismatch {
            self.mismatches += 1;
            if self.mismatch_examples.len() < 5 {
                self.mismatch_examples.push(format!("{case:?}: {m}"));
            }
        }
    }
    fn merge(mut self, o: Stats) -> Stats {
        self.rays += o.rays;
        self.crossings += o.crossings;
        self.in_band += o.in_band;
        if o.max_forward.0 > self.max_forward.0 {
            self.max_forward = o.max_forward;
        }
        if o.max_backward.0 > self.max_backward.0 {
            self.max_backward = o.max_backward;
        }
        self.mismatches += o.mismatches;
        for m in o.mismatch_examples {
            if self.mismatch_examples.len() < 5 {
                self.mismatch_examples.push(m);
            }
        }
        self
    }
}

/// Compares the kernel with the oracle on every case in each of `modes`, in parallel. The oracle runs once for the
/// `f64` data and once for the `f32` data (shared by both `f32` modes), and prepares each surface once per run of
/// consecutive cases that share it. Returns one [`Stats`] per mode, in order.
pub fn evaluate(cases: &[SurfaceCase], modes: &[Precision]) -> Vec<Stats> {
    let n = modes.len();
    let need64 = modes.contains(&Precision::F64);
    let need32 = modes.iter().any(|m| *m != Precision::F64);
    cases
        .par_chunk_by(|a, b| a.kind == b.kind && a.p == b.p)
        .fold(
            || vec![Stats::default(); n],
            |mut acc, group| {
                let Some(first) = group.first() else {
                    return acc;
                };
                let s64 = need64.then(|| first.oracle_surface(AngleType::F64).prepare());
                let s32 = need32.then(|| first.to_f32().oracle_surface(AngleType::F32).prepare());
                for case in group {
                    let o64 = s64.as_ref().map(|s| oracle_answer_on(s, case));
                    let o32 = s32.as_ref().map(|s| oracle_answer_on(s, &case.to_f32()));
                    for (slot, &mode) in acc.iter_mut().zip(modes) {
                        let o = match mode {
                            Precision::F64 => o64.as_ref(),
                            _ => o32.as_ref(),
                        };
                        let Some(o) = o else { continue };
                        let k = kernel_crossings_in(mode, case);
                        let r = compare(case.kind, mode, o, &k);
                        slot.add(&case.for_mode(mode), &r);
                    }
                }
                acc
            },
        )
        .reduce(
            || vec![Stats::default(); n],
            |a, b| a.into_iter().zip(b).map(|(x, y)| x.merge(y)).collect(),
        )
}
