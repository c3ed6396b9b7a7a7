//! Baseline for marching: resample a spherical grid's cell index field onto an `n³` Cartesian voxel grid, march
//! the voxels with the Amanatides–Woo 3-D DDA (J. Amanatides and A. Woo, *A Fast Voxel Traversal Algorithm for
//! Ray Tracing*, Eurographics 1987), and map each voxel back to the spherical cell of its center.
//!
//! This is what Hannasch (ch. 6) compares against: a user who converts the data to a box grid. The
//! resampling is done once per grid and not timed (as in §6.3); its accuracy cost is that a voxel straddling a
//! spherical boundary carries one cell for its whole extent, so the cell sequence and the `t` values differ from
//! the exact ones.

/// A spherical grid resampled onto an `n³` voxel grid covering its bounding cube.
#[derive(Debug, Clone)]
pub struct VoxelGrid {
    cube: VoxelCube,
    /// Per voxel: the spherical cell `[i, j, k]` of its center, or `None` outside the domain.
    cells: Vec<Option<[u32; 3]>>,
}

/// One run of a voxel march mapped back to spherical cells: consecutive voxels in the same cell are merged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoxelCrossing {
    /// The spherical cell.
    pub cell: [u32; 3],
    /// Entry parameter.
    pub t_enter: f64,
    /// Exit parameter.
    pub t_exit: f64,
}

fn locate(v: &[f64], x: f64) -> Option<u32> {
    // half-open: v[i] <= x < v[i+1]
    let i = v.partition_point(|&b| b <= x);
    if i == 0 || i == v.len() {
        None
    } else {
        Some((i - 1) as u32)
    }
}

impl VoxelGrid {
    /// Resamples the full or partial spherical grid (`r`, `theta`, `phi` as in the contract, centred at
    /// `center`) onto `n³` voxels spanning `[center − r_max, center + r_max]³`.
    pub fn resample(
        center: [f64; 3],
        r: &[f64],
        theta: &[f64],
        phi: &[f64],
        n: usize,
    ) -> VoxelGrid {
        let cube = VoxelCube::around(center, r[r.len() - 1], n);
        let cells = (0..n * n * n)
            .map(|v| spherical_cell_of(center, r, theta, phi, cube.voxel_center(v)))
            .collect();
        VoxelGrid { cube, cells }
    }

    /// Voxels per side.
    pub fn n(&self) -> usize {
        self.cube.n()
    }

    /// Marches the ray `origin + t dir`, `t ∈ [t_min, t_max]`, through the voxels (Amanatides–Woo), mapping each
    /// voxel to its spherical cell and merging neighbours in the same cell. Appends to `out` (cleared first).
    pub fn march(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        t_min: f64,
        t_max: f64,
        out: &mut Vec<VoxelCrossing>,
    ) {
        out.clear();
        self.cube
            .traverse(origin, dir, t_min, t_max, |v, t, t_exit| {
                if let Some(cell) = self.cells[v] {
                    match out.last_mut() {
                        Some(last) if last.cell == cell && last.t_exit == t => last.t_exit = t_exit,
                        _ => out.push(VoxelCrossing {
                            cell,
                            t_enter: t,
                            t_exit,
                        }),
                    }
                }
                true
            });
    }
}

/// The spherical cell `[i, j, k]` (half-open, as in the contract; φ modulo 2π) containing the point `p`, or `None`
/// outside the domain of the grid `r`, `theta`, `phi` centred at `center`.
pub fn spherical_cell_of(
    center: [f64; 3],
    r: &[f64],
    theta: &[f64],
    phi: &[f64],
    p: [f64; 3],
) -> Option<[u32; 3]> {
    let (x, y, z) = (p[0] - center[0], p[1] - center[1], p[2] - center[2]);
    let rr = (x * x + y * y + z * z).sqrt();
    let th = if rr > 0.0 {
        (z / rr).clamp(-1.0, 1.0).acos()
    } else {
        0.0
    };
    let k = azimuth_of(phi, x, y);
    match (locate(r, rr), locate(theta, th), k) {
        (Some(i), Some(j), Some(k)) => Some([i, j, k]),
        _ => None,
    }
}

/// The cylindrical cell `[i, k, m]` (ρ, φ, z; half-open as in the contract, φ modulo 2π, z relative to
/// `center[2]`) containing the point `p`, or `None` outside the domain of the grid `rho`, `phi`, `z`.
pub fn cylindrical_cell_of(
    center: [f64; 3],
    rho: &[f64],
    phi: &[f64],
    z: &[f64],
    p: [f64; 3],
) -> Option<[u32; 3]> {
    let (x, y, h) = (p[0] - center[0], p[1] - center[1], p[2] - center[2]);
    match (locate(rho, x.hypot(y)), azimuth_of(phi, x, y), locate(z, h)) {
        (Some(i), Some(k), Some(m)) => Some([i, k, m]),
        _ => None,
    }
}

/// The azimuth sector of the direction `(x, y)` among the breakpoints `phi` (φ taken modulo 2π; a full turn has
/// no gap).
fn azimuth_of(phi: &[f64], x: f64, y: f64) -> Option<u32> {
    let mut ph = y.atan2(x);
    // into [phi0, phi0 + 2π)
    ph -= std::f64::consts::TAU * ((ph - phi[0]) / std::f64::consts::TAU).floor();
    let full = phi[phi.len() - 1] - phi[0] >= std::f64::consts::TAU;
    if full {
        locate(phi, ph).or(Some((phi.len() - 2) as u32))
    } else {
        locate(phi, ph)
    }
}

/// An axis-aligned cube of `n³` equal voxels, numbered `x + n (y + n z)`, and the Amanatides–Woo walk through it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoxelCube {
    n: usize,
    lo: [f64; 3],
    h: f64,
}

impl VoxelCube {
    /// The cube `[center − half, center + half]³` cut into `n³` voxels.
    pub fn around(center: [f64; 3], half: f64, n: usize) -> VoxelCube {
        VoxelCube {
            n,
            lo: center.map(|c| c - half),
            h: 2.0 * half / n as f64,
        }
    }

    /// Voxels per side.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The center of voxel `v` (numbered `x + n (y + n z)`).
    pub fn voxel_center(&self, v: usize) -> [f64; 3] {
        let n = self.n;
        let idx = [v % n, (v / n) % n, v / (n * n)];
        [0, 1, 2].map(|a| self.lo[a] + (idx[a] as f64 + 0.5) * self.h)
    }

    /// Walks the ray `origin + t dir`, `t ∈ [t_min, t_max]`, through the voxels in order (Amanatides–Woo), calling
    /// `visit(voxel, t_enter, t_exit)` for each voxel crossed over a positive length; `visit` returns `false` to
    /// stop early. At most `3 n + 3` steps.
    pub fn traverse(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        t_min: f64,
        t_max: f64,
        mut visit: impl FnMut(usize, f64, f64) -> bool,
    ) {
        let n = self.n as i64;
        let size = self.h * self.n as f64;
        // clip to the cube (slabs)
        let (mut t0, mut t1) = (t_min, t_max);
        for a in 0..3 {
            let lo = self.lo[a];
            let hi = lo + size;
            if dir[a] == 0.0 {
                if origin[a] < lo || origin[a] >= hi {
                    return;
                }
            } else {
                let inv = 1.0 / dir[a];
                let (mut ta, mut tb) = ((lo - origin[a]) * inv, (hi - origin[a]) * inv);
                if ta > tb {
                    std::mem::swap(&mut ta, &mut tb);
                }
                t0 = t0.max(ta);
                t1 = t1.min(tb);
            }
        }
        if t0 >= t1 {
            return;
        }
        // starting voxel and the DDA state
        let mut idx = [0i64; 3];
        let mut step = [0i64; 3];
        let mut t_next = [f64::INFINITY; 3];
        let mut t_delta = [f64::INFINITY; 3];
        for a in 0..3 {
            let p = origin[a] + t0 * dir[a];
            let v = ((p - self.lo[a]) / self.h).floor() as i64;
            idx[a] = v.clamp(0, n - 1);
            if dir[a] > 0.0 {
                step[a] = 1;
                let b = self.lo[a] + (idx[a] + 1) as f64 * self.h;
                t_next[a] = (b - origin[a]) / dir[a];
                t_delta[a] = self.h / dir[a];
            } else if dir[a] < 0.0 {
                step[a] = -1;
                let b = self.lo[a] + idx[a] as f64 * self.h;
                t_next[a] = (b - origin[a]) / dir[a];
                t_delta[a] = -self.h / dir[a];
            }
        }
        let mut t = t0;
        let max_steps = 3 * self.n + 3;
        for _ in 0..max_steps {
            let a = if t_next[0] <= t_next[1] && t_next[0] <= t_next[2] {
                0
            } else if t_next[1] <= t_next[2] {
                1
            } else {
                2
            };
            let t_exit = t_next[a].min(t1);
            let vi = (idx[2] * n * n + idx[1] * n + idx[0]) as usize;
            if t_exit > t && !visit(vi, t, t_exit) {
                return;
            }
            if t_next[a] >= t1 {
                break;
            }
            t = t_exit;
            idx[a] += step[a];
            if idx[a] < 0 || idx[a] >= n {
                break;
            }
            t_next[a] += t_delta[a];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    #[test]
    fn dda_chord_through_a_ball_is_close_to_exact_and_converges() {
        let mut errs = Vec::new();
        for n in [16, 64] {
            let g = VoxelGrid::resample([0.0; 3], &[0.0, 1.0], &[0.0, PI], &[0.0, TAU], n);
            let mut out = Vec::new();
            g.march(
                [-2.0, 0.1, 0.2],
                [1.0, 0.0, 0.0],
                0.0,
                f64::INFINITY,
                &mut out,
            );
            assert_eq!(out.len(), 1);
            let len = out[0].t_exit - out[0].t_enter;
            let exact = 2.0 * (1.0f64 - 0.05).sqrt();
            errs.push((len - exact).abs());
        }
        assert!(errs[0] < 4.0 * 2.0 / 16.0 && errs[1] < errs[0], "{errs:?}");
    }
}
