//! The contract's invariants of a crossing list (each step changes one index by one, ...), checked on the
//! oracle's own lists and on the kernel's.

use super::*;

impl MarchOracle {
    /// Checks the contract's structural invariants on any list of crossings: `t_min <= t_enter <= t_exit <=
    /// t_max`, indices in range, and consecutive crossings either touch and differ in exactly one index by one
    /// step (the azimuth wraps only on a full circle) or are separated by a gap.
    pub fn check_structure(
        &self,
        list: &[KernelCrossing],
        t_min: f64,
        t_max: f64,
    ) -> Result<(), String> {
        for (n, c) in list.iter().enumerate() {
            if c.t_enter.partial_cmp(&c.t_exit).is_none_or(|o| o.is_gt()) {
                return Err(format!(
                    "crossing {n}: t_enter {} > t_exit {}",
                    c.t_enter, c.t_exit
                ));
            }
            if c.t_enter < t_min || c.t_exit > t_max {
                return Err(format!(
                    "crossing {n}: [{}, {}] outside [{t_min}, {t_max}]",
                    c.t_enter, c.t_exit
                ));
            }
            for k in 0..3 {
                if c.cell[k] >= self.dims[k] {
                    return Err(format!(
                        "crossing {n}: cell {:?} out of range {:?}",
                        c.cell, self.dims
                    ));
                }
            }
            if n == 0 {
                continue;
            }
            let p = &list[n - 1];
            if c.t_enter < p.t_exit {
                return Err(format!(
                    "crossing {n}: t_enter {} before previous t_exit {}",
                    c.t_enter, p.t_exit
                ));
            }
            if c.t_enter == p.t_exit {
                self.one_step(&p.cell.map(Some), &c.cell.map(Some))
                    .map_err(|e| {
                        format!("crossings {}→{n}: {:?}→{:?}: {e}", n - 1, p.cell, c.cell)
                    })?;
            }
        }
        Ok(())
    }

    /// Checks that two cells differ in exactly one (known) index by one step.
    pub(super) fn one_step(
        &self,
        a: &OracleCell,
        b: &OracleCell,
    ) -> Result<Option<(usize, usize)>, String> {
        let mut changed = None;
        for k in 0..3 {
            let (Some(x), Some(y)) = (a[k], b[k]) else {
                continue;
            };
            if x == y {
                continue;
            }
            if changed.is_some() {
                return Err("more than one index changes".into());
            }
            let n = self.dims[k];
            let boundary = if x + 1 == y {
                y as usize
            } else if y + 1 == x {
                x as usize
            } else if k == self.phi_coord()
                && self.full
                && n > 1
                && ((x == 0 && y == n - 1) || (y == 0 && x == n - 1))
            {
                0
            } else {
                return Err(format!("index {k} jumps {x}→{y}"));
            };
            changed = Some((k, boundary));
        }
        if changed.is_none() && a == b {
            return Err("touching crossings in the same cell".into());
        }
        Ok(changed)
    }

    /// Converts the oracle's list for [`MarchOracle::check_structure`] (unknown indices as 0).
    pub fn as_kernel_list(list: &[OracleCrossing]) -> Vec<KernelCrossing> {
        list.iter()
            .map(|c| KernelCrossing {
                cell: c.cell.map(|v| v.unwrap_or(0)),
                t_enter: c.t_enter,
                t_exit: c.t_exit,
            })
            .collect()
    }

    /// Structural check of the oracle's own list (unknown indices are skipped).
    pub fn check_oracle_structure(&self, r: &Reference) -> Result<(), String> {
        for (n, w) in r.crossings.windows(2).enumerate() {
            if w[1].t_enter < w[0].t_exit || w[0].t_enter > w[0].t_exit {
                return Err(format!("oracle crossings {n}: not ordered"));
            }
            if w[1].t_enter == w[0].t_exit {
                if w[0]
                    .cell
                    .iter()
                    .chain(w[1].cell.iter())
                    .any(|c| c.is_none())
                {
                    continue;
                }
                self.one_step(&w[0].cell, &w[1].cell).map_err(|e| {
                    format!("oracle crossings {n}: {:?}→{:?}: {e}", w[0].cell, w[1].cell)
                })?;
            }
        }
        Ok(())
    }
}
