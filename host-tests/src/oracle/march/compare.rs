//! The comparison criterion of the marching tests and the report: the order of cells exact, each `t` within a
//! tolerance.

use super::*;

/// Statistics of a successful comparison.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// Crossings in the engine's list.
    pub n_kernel: usize,
    /// Crossings in the oracle's list.
    pub n_oracle: usize,
    /// Whether the two cell sequences are identical even before dropping short crossings.
    pub identical_raw: bool,
    /// Largest distance of an engine crossing point from its boundary surface, in units of `eps·L`.
    pub max_backward_eps: f64,
    /// Largest `|t_engine − t_oracle|·|d|` over matched crossing ends not next to a dropped crossing, in `eps·L`.
    pub max_forward_eps: f64,
}

/// Why a comparison failed.
#[derive(Debug, Clone, PartialEq)]
pub enum Mismatch {
    /// The engine's list breaks a structural invariant of the contract.
    Structure(String),
    /// The cell sequences differ after dropping short crossings.
    Sequence {
        /// Reduced engine list.
        kernel: Vec<(OracleCell, f64, f64)>,
        /// Reduced oracle list.
        oracle: Vec<(OracleCell, f64, f64)>,
    },
    /// A crossing point is farther than the bound from its boundary surface.
    Backward {
        /// The parameter.
        t: f64,
        /// Its distance in units of `eps·L`.
        err_eps: f64,
    },
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Mismatch::Structure(s) => write!(f, "structure: {s}"),
            Mismatch::Sequence { kernel, oracle } => {
                writeln!(f, "cell sequences differ:")?;
                writeln!(f, "  engine ({}):", kernel.len())?;
                for c in kernel {
                    writeln!(f, "    {:?} [{:e}, {:e}]", c.0, c.1, c.2)?;
                }
                writeln!(f, "  oracle ({}):", oracle.len())?;
                for c in oracle {
                    writeln!(f, "    {:?} [{:e}, {:e}]", c.0, c.1, c.2)?;
                }
                Ok(())
            }
            Mismatch::Backward { t, err_eps } => {
                write!(
                    f,
                    "crossing point at t = {t:e} lies {err_eps:.1} eps·L from its surface"
                )
            }
        }
    }
}

/// Relative length below which crossings are dropped before comparing sequences (issue: `1e-7·L`).
pub const DROP_REL: f64 = 1e-7;

/// A reduced crossing: cell, ends, and whether each end touches a dropped piece.
#[derive(Debug, Clone, Copy)]
struct Reduced {
    cell: OracleCell,
    a: f64,
    b: f64,
    clean_a: bool,
    clean_b: bool,
}

/// Drops crossings shorter than `min_t` (in t units) and merges survivors in the same cell that only dropped
/// crossings or gaps shorter than `min_t` separate.
fn reduce(list: &[(OracleCell, f64, f64)], min_t: f64) -> Vec<Reduced> {
    let short = |c: &(OracleCell, f64, f64)| c.2 - c.1 < min_t;
    let mut out: Vec<Reduced> = Vec::new();
    let mut all_short = true; // every piece and gap since the last survivor is short
    for (n, c) in list.iter().enumerate() {
        let (cell, a, b) = *c;
        if n > 0 && a - list[n - 1].2 >= min_t {
            all_short = false;
        }
        if short(c) {
            continue;
        }
        let prev_drop = n > 0 && short(&list[n - 1]) && list[n - 1].2 == a;
        let next_drop = list.get(n + 1).is_some_and(|q| short(q) && q.1 == b);
        if let Some(last) = out.last_mut() {
            if all_short && last.cell == cell {
                last.b = b;
                last.clean_b = !next_drop;
                continue;
            }
        }
        out.push(Reduced {
            cell,
            a,
            b,
            clean_a: !prev_drop,
            clean_b: !next_drop,
        });
        all_short = true;
    }
    out
}

fn cells_match(a: &OracleCell, b: &OracleCell) -> bool {
    a.iter()
        .zip(b.iter())
        .all(|(x, y)| x.is_none() || y.is_none() || x == y)
}

/// The comparison criterion of the marching tests: the order of cells exact, each t within a tolerance.
///
/// 1. `kernel` must satisfy [`MarchOracle::check_structure`].
/// 2. After dropping crossings shorter than `1e-7·L` from both lists (and merging neighbours that then agree),
///    the cell sequences must be identical (an unknown oracle index matches any index).
/// 3. Every engine crossing end strictly inside `(t_min, t_max)` must lie within `bound_eps·eps·L` of a boundary
///    surface: the surface of the index that changes there when the neighbour touches, else the nearest one
///    (domain entries and exits). `bound_eps = None` measures without failing.
///
/// The forward error `|t − t_oracle|·|d| / (eps·L)` is measured on matched ends that no dropped crossing touches.
pub fn compare(
    oracle: &MarchOracle,
    reference: &Reference,
    kernel: &[KernelCrossing],
    eps: f64,
    bound_eps: Option<f64>,
) -> Result<Stats, Mismatch> {
    let r = &reference.ray;
    oracle
        .check_structure(kernel, r.t_min, r.t_max)
        .map_err(Mismatch::Structure)?;
    let l = reference.l;
    let min_t = DROP_REL * l / r.dir_norm;
    let k_list: Vec<(OracleCell, f64, f64)> = kernel
        .iter()
        .map(|c| (c.cell.map(Some), c.t_enter, c.t_exit))
        .collect();
    let o_list: Vec<(OracleCell, f64, f64)> = reference
        .crossings
        .iter()
        .map(|c| (c.cell, c.t_enter, c.t_exit))
        .collect();
    let identical_raw = k_list.len() == o_list.len()
        && k_list
            .iter()
            .zip(&o_list)
            .all(|(k, o)| cells_match(&k.0, &o.0));
    let kr = reduce(&k_list, min_t);
    let or = reduce(&o_list, min_t);
    let same = kr.len() == or.len()
        && kr
            .iter()
            .zip(&or)
            .all(|(k, o)| cells_match(&k.cell, &o.cell));
    if !same {
        return Err(Mismatch::Sequence {
            kernel: kr.iter().map(|c| (c.cell, c.a, c.b)).collect(),
            oracle: or.iter().map(|c| (c.cell, c.a, c.b)).collect(),
        });
    }
    let unit = eps * l;
    let mut fwd: f64 = 0.0;
    for (k, o) in kr.iter().zip(&or) {
        if k.clean_a && o.clean_a && k.a.is_finite() && o.a.is_finite() {
            fwd = fwd.max((k.a - o.a).abs() * r.dir_norm / unit);
        }
        if k.clean_b && o.clean_b && k.b.is_finite() && o.b.is_finite() {
            fwd = fwd.max((k.b - o.b).abs() * r.dir_norm / unit);
        }
    }
    // backward error
    let mut bwd: f64 = 0.0;
    for (n, c) in kernel.iter().enumerate() {
        for (end, t) in [(0, c.t_enter), (1, c.t_exit)] {
            if !(t > r.t_min && t < r.t_max) {
                continue;
            }
            let neighbour = if end == 0 {
                n.checked_sub(1)
                    .map(|m| &kernel[m])
                    .filter(|p| p.t_exit == t)
            } else {
                kernel.get(n + 1).filter(|p| p.t_enter == t)
            };
            let which = neighbour.and_then(|p| {
                oracle
                    .one_step(&c.cell.map(Some), &p.cell.map(Some))
                    .ok()
                    .flatten()
            });
            let dist = oracle.boundary_distance(r, t, which);
            let e = dist / unit;
            bwd = bwd.max(e);
            if let Some(bound) = bound_eps {
                if e > bound {
                    return Err(Mismatch::Backward { t, err_eps: e });
                }
            }
        }
    }
    Ok(Stats {
        n_kernel: kernel.len(),
        n_oracle: reference.crossings.len(),
        identical_raw,
        max_backward_eps: bwd,
        max_forward_eps: fwd,
    })
}

/// Only the sequence part of [`compare`]: whether the cell sequences agree after dropping crossings shorter
/// than `1e-7·L` from both lists (no structural or backward-error check; for baselines such as a voxel march
/// mapped back to cells, whose lists need not satisfy the contract).
pub fn same_sequence(reference: &Reference, list: &[KernelCrossing]) -> bool {
    let min_t = DROP_REL * reference.l / reference.ray.dir_norm;
    let k_list: Vec<(OracleCell, f64, f64)> = list
        .iter()
        .map(|c| (c.cell.map(Some), c.t_enter, c.t_exit))
        .collect();
    let o_list: Vec<(OracleCell, f64, f64)> = reference
        .crossings
        .iter()
        .map(|c| (c.cell, c.t_enter, c.t_exit))
        .collect();
    let (kr, or) = (reduce(&k_list, min_t), reduce(&o_list, min_t));
    kr.len() == or.len()
        && kr
            .iter()
            .zip(&or)
            .all(|(k, o)| cells_match(&k.cell, &o.cell))
}
