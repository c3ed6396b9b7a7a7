//! Where a high-precision point is: its cell, and its distance to a boundary surface (module docs of [`super`]),
//! with the high-precision geometry they share.

use super::*;

impl MarchOracle {
    /// Locates a point (relative to the center) by the half-open rule; `None` outside the domain.
    pub fn classify(&self, p: &[B; 3]) -> Option<OracleCell> {
        let (x, y, z) = (&p[0], &p[1], &p[2]);
        let rho2 = add(&mul(x, x), &mul(y, y));
        let on_axis = rho2.is_zero();
        match self.kind {
            GridKind::Spherical => {
                let r2 = add(&rho2, &mul(z, z));
                let i = locate_sorted(&self.radii_sq, &r2)?;
                if r2.is_zero() {
                    return Some([Some(i), None, None]);
                }
                let rho = sqrt(&rho2);
                // θ ≥ θ_k ⟺ sin(θ − θ_k) > 0, or equal angles, or (θ = π, θ_k = 0)
                let ge = |g: &Dir2| -> bool {
                    let dd = sub(&mul(&rho, &g.c), &mul(z, &g.s));
                    match sign(&dd) {
                        1 => true,
                        -1 => false,
                        _ => {
                            let dt = add(&mul(&rho, &g.s), &mul(z, &g.c));
                            sign(&dt) > 0 || (g.c.cmp(&hp(1.0)) == Some(0))
                        }
                    }
                };
                // θ ≥ θ_k is monotone in k: binary search
                let count = self.zenith.partition_point(ge);
                let n = self.zenith.len();
                if count == 0 || count == n {
                    return None;
                }
                let j = count - 1;
                let k = self.locate_phi_or_axis(x, y, on_axis)?;
                Some([Some(i), Some(j as u32), Some(k)])
            }
            GridKind::Cylindrical => {
                let i = locate_sorted(&self.radii_sq, &rho2)?;
                let m = locate_sorted(&self.zs, z)?;
                let k = Some(self.locate_phi_or_axis(x, y, on_axis)?);
                Some([Some(i), k, Some(m)])
            }
            GridKind::Polar => {
                let i = locate_sorted(&self.radii_sq, &rho2)?;
                let k = Some(self.locate_phi_or_axis(x, y, on_axis)?);
                Some([Some(i), k, Some(0)])
            }
        }
    }

    /// Azimuth index; a point on the z axis has φ = 0 (the kernel's documented convention).
    pub(super) fn locate_phi_or_axis(&self, x: &B, y: &B, on_axis: bool) -> Option<u32> {
        if on_axis {
            self.locate_phi(&hp(1.0), &hp(0.0))
        } else {
            self.locate_phi(x, y)
        }
    }

    /// Azimuth index of `(x, y) ≠ 0` by exact angular order from `φ_0`; `None` outside the wedge.
    pub(super) fn locate_phi(&self, x: &B, y: &B) -> Option<u32> {
        let e0 = &self.azim[0];
        let n = self.azim.len();
        let u = Dir2 {
            c: x.clone(),
            s: y.clone(),
        };
        // number of breakpoints k (k < n − 1 when full) with β_k ≤ α
        let upto = if self.full { n - 1 } else { n };
        // the breakpoints are sorted by angle from φ_0, so β_k ≤ α is monotone in k: binary search
        let count = self.azim[..upto].partition_point(|w| angle_le(e0, w, &u));
        if count == 0 {
            // cannot happen (β_0 = 0 ≤ α), kept for safety
            return None;
        }
        if !self.full && count == n {
            return None;
        }
        Some((count - 1) as u32)
    }

    /// Distance from a point (relative to the center) to boundary surface `idx` of coordinate `coord`.
    pub(super) fn dist_to(&self, p: &[B; 3], coord: usize, idx: usize) -> Option<B> {
        let (x, y, z) = (&p[0], &p[1], &p[2]);
        let rho = sqrt(&add(&mul(x, x), &mul(y, y)));
        let kind_coord = match (self.kind, coord) {
            (GridKind::Spherical, 0) => 0,
            (GridKind::Spherical, 1) => 1,
            (GridKind::Spherical, 2) => 2,
            (GridKind::Cylindrical, 0) => 3,
            (GridKind::Cylindrical, 1) => 2,
            (GridKind::Cylindrical, 2) => 4,
            (GridKind::Polar, 0) => 3,
            (GridKind::Polar, 1) => 2,
            _ => return None,
        };
        match kind_coord {
            0 => {
                let r = sqrt(&dot(p, p));
                Some(abs(&sub(&r, self.radii_hp.get(idx)?)))
            }
            1 => {
                let g = self.zenith.get(idx)?;
                let proj = add(&mul(&rho, &g.s), &mul(z, &g.c));
                if sign(&proj) < 0 {
                    Some(sqrt(&dot(p, p)))
                } else {
                    Some(abs(&sub(&mul(&rho, &g.c), &mul(z, &g.s))))
                }
            }
            2 => {
                let w = self.azim.get(idx)?;
                let proj = add(&mul(x, &w.c), &mul(y, &w.s));
                if sign(&proj) < 0 {
                    Some(rho)
                } else {
                    Some(abs(&sub(&mul(y, &w.c), &mul(x, &w.s))))
                }
            }
            3 => Some(abs(&sub(&rho, self.radii_hp.get(idx)?))),
            4 => Some(abs(&sub(z, self.zs.get(idx)?))),
            _ => None,
        }
    }

    pub(super) fn n_breaks(&self, coord: usize) -> usize {
        match (self.kind, coord) {
            (GridKind::Spherical, 0) | (GridKind::Cylindrical, 0) | (GridKind::Polar, 0) => {
                self.radii.len()
            }
            (GridKind::Spherical, 1) => self.zenith.len(),
            (GridKind::Spherical, 2) | (GridKind::Cylindrical, 1) | (GridKind::Polar, 1) => {
                self.azim.len()
            }
            (GridKind::Cylindrical, 2) => self.zs.len(),
            _ => 0,
        }
    }

    /// Distance (in length units, `f64`) from the point `p + t d` to the boundary surface crossed when index
    /// `coord` steps across breakpoint `idx`, or — with `which = None` — to the nearest boundary surface.
    pub fn boundary_distance(&self, ray: &HpRay, t: f64, which: Option<(usize, usize)>) -> f64 {
        let p = self.point(ray, &hp(t));
        let d = match which {
            // two sectors on a full circle: a step 0 ↔ 1 crosses either breakpoint
            Some((c, _)) if c == self.phi_coord() && self.full && self.dims[c] == 2 => {
                match (self.dist_to(&p, c, 0), self.dist_to(&p, c, 1)) {
                    (Some(a), Some(b)) => Some(min_b(a, b)),
                    (a, b) => a.or(b),
                }
            }
            Some((c, i)) => self.dist_to(&p, c, i),
            None => {
                let mut best: Option<B> = None;
                for c in 0..self.n_coords() {
                    for i in 0..self.n_breaks(c) {
                        if c == 0 && self.radii[i] == 0.0 {
                            continue;
                        }
                        if self.kind == GridKind::Spherical && c == 1 && self.zenith_raw[i] == 0.0 {
                            continue;
                        }
                        if let Some(v) = self.dist_to(&p, c, i) {
                            best = Some(match best {
                                None => v,
                                Some(b) => min_b(b, v),
                            });
                        }
                    }
                }
                best
            }
        };
        d.map(|v| to_f64(&v)).unwrap_or(f64::INFINITY)
    }
}
