//! The oracle's march in high precision: every surface parameter of the line, the crossings between them, and
//! the path through a tie (the module docs of [`super`], steps 1-3).

use super::*;

impl MarchOracle {
    /// All surface parameters of the line (unfiltered by the ray interval).
    pub(super) fn events(&self, r: &HpRay, apex_tol: &B) -> Vec<B> {
        let mut ev = Vec::new();
        let (q, d) = (&r.q, &r.d);
        let planar_xy = self.kind != GridKind::Spherical;
        // spheres / cylinders / circles
        {
            let (a, b, c0) = if planar_xy {
                (dot2(d, d), dot2(q, d), dot2(q, q))
            } else {
                (dot(d, d), dot(q, d), dot(q, q))
            };
            for (rr, r2) in self.radii.iter().zip(&self.radii_sq) {
                if *rr == 0.0 {
                    continue;
                }
                let c = sub(&c0, r2);
                ev.extend(solve_quadratic(&a, &b, &c));
            }
        }
        // zenith cones
        if self.kind == GridKind::Spherical {
            for (k, g) in self.zenith.iter().enumerate() {
                let raw = self.zenith_raw[k];
                if raw == 0.0 || is_pi(raw) {
                    continue;
                }
                let s2 = mul(&g.s, &g.s);
                let c2 = mul(&g.c, &g.c);
                // z² sin²θ − (x² + y²) cos²θ = 0
                let a = sub(&mul(&mul(&d[2], &d[2]), &s2), &mul(&dot2(d, d), &c2));
                let b = sub(&mul(&mul(&q[2], &d[2]), &s2), &mul(&dot2(q, d), &c2));
                let c = sub(&mul(&mul(&q[2], &q[2]), &s2), &mul(&dot2(q, q), &c2));
                for t in solve_quadratic(&a, &b, &c) {
                    let z = add(&q[2], &mul(&t, &d[2]));
                    let ok = sign(&z) * sign(&g.c) >= 0 || le(&abs(&z), apex_tol);
                    if ok {
                        ev.push(t);
                    }
                }
            }
        }
        // azimuth half-planes / half-lines
        let n_az = if self.full {
            self.azim.len() - 1
        } else {
            self.azim.len()
        };
        for w in self.azim.iter().take(n_az) {
            // plane: −x sin + y cos = 0; side: x cos + y sin ≥ 0
            let num = sub(&mul(&q[1], &w.c), &mul(&q[0], &w.s));
            let den = sub(&mul(&d[1], &w.c), &mul(&d[0], &w.s));
            if den.is_zero() {
                continue;
            }
            let t = div(&num, &den).neg();
            let x = add(&q[0], &mul(&t, &d[0]));
            let y = add(&q[1], &mul(&t, &d[1]));
            let side = add(&mul(&x, &w.c), &mul(&y, &w.s));
            if sign(&side) >= 0 || le(&abs(&side), apex_tol) {
                ev.push(t);
            }
        }
        // planes z
        if self.kind == GridKind::Cylindrical && !d[2].is_zero() {
            for z in &self.zs {
                ev.push(div(&sub(z, &q[2]), &d[2]));
            }
        }
        // where the line meets the z axis (φ jumps) and the center (θ jumps)
        let dd2 = dot2(d, d);
        if !dd2.is_zero() {
            let cr = sub(&mul(&q[0], &d[1]), &mul(&q[1], &d[0]));
            if cr.is_zero() {
                ev.push(div(&dot2(q, d), &dd2).neg());
            }
        }
        ev
    }

    pub(super) fn march_hp(&self, r: &HpRay, l: f64) -> Vec<OracleCrossing> {
        // t scale of the ray: (L + |q|) / |d|
        let tscale = hp((l + r.origin_dist) / r.dir_norm);
        let apex_tol = hp(l * 2f64.powi(-280));
        let tol = mul(&tscale, &hp(2f64.powi(-200)));
        let tmin = hp(r.t_min);
        let tmax = hp(r.t_max);
        let mut ev: Vec<B> = self
            .events(r, &apex_tol)
            .into_iter()
            .filter(|t| {
                (r.t_min == f64::NEG_INFINITY || lt(&tmin, t))
                    && (r.t_max == f64::INFINITY || lt(t, &tmax))
            })
            .collect();
        ev.sort_by(|a, b| a.cmp(b).unwrap_or(0).cmp(&0));
        // representatives of clusters; the interval ends are exact representatives
        let mut reps: Vec<B> = Vec::new();
        if r.t_min.is_finite() {
            reps.push(tmin.clone());
        }
        for t in ev {
            match reps.last() {
                Some(last) if le(&sub(&t, last), &tol) => {}
                _ => reps.push(t),
            }
        }
        if r.t_max.is_finite() {
            match reps.last() {
                Some(last) if le(&sub(&tmax, last), &tol) => {
                    let n = reps.len();
                    if n >= 2 || !r.t_min.is_finite() {
                        reps[n - 1] = tmax.clone();
                    } else {
                        // t_min == t_max (or within tol): a single point, nothing of positive length
                        if r.t_min < r.t_max {
                            reps.push(tmax.clone());
                        }
                    }
                }
                _ => reps.push(tmax.clone()),
            }
        }
        // intervals: (−∞, reps[0]) if t_min = −∞, between reps, (reps[last], +∞) if t_max = +∞
        let mut pieces: Vec<(Option<OracleCell>, B, B)> = Vec::new();
        let neg_inf = BigFloat::from_f64(f64::NEG_INFINITY, PRECISION);
        let pos_inf = BigFloat::from_f64(f64::INFINITY, PRECISION);
        if reps.is_empty() {
            let mid = hp(0.0);
            pieces.push((self.classify(&self.point(r, &mid)), neg_inf, pos_inf));
        } else {
            if !r.t_min.is_finite() {
                let mid = sub(&reps[0], &tscale);
                pieces.push((
                    self.classify(&self.point(r, &mid)),
                    neg_inf,
                    reps[0].clone(),
                ));
            }
            for w in reps.windows(2) {
                let mid = div(&add(&w[0], &w[1]), &hp(2.0));
                pieces.push((
                    self.classify(&self.point(r, &mid)),
                    w[0].clone(),
                    w[1].clone(),
                ));
            }
            if !r.t_max.is_finite() {
                let last = &reps[reps.len() - 1];
                let mid = add(last, &tscale);
                pieces.push((self.classify(&self.point(r, &mid)), last.clone(), pos_inf));
            }
        }
        // merge equal neighbours, drop outside
        let mut merged: Vec<(OracleCell, B, B)> = Vec::new();
        let mut prev_inside = false;
        for (cell, a, b) in pieces {
            match cell {
                None => prev_inside = false,
                Some(c) => {
                    if prev_inside {
                        if let Some(last) = merged.last_mut() {
                            if last.0 == c {
                                last.2 = b;
                                continue;
                            }
                        }
                    }
                    merged.push((c, a, b));
                    prev_inside = true;
                }
            }
        }
        // emit with zero-length tie cells between touching pieces
        let mut out = Vec::new();
        for (n, (cell, a, b)) in merged.iter().enumerate() {
            if n > 0 {
                let (pc, _, pb) = &merged[n - 1];
                if pb.cmp(a) == Some(0) {
                    let t = to_f64(a);
                    for mid in self.tie_path(*pc, *cell) {
                        out.push(OracleCrossing {
                            cell: mid,
                            t_enter: t,
                            t_exit: t,
                        });
                    }
                }
            }
            out.push(OracleCrossing {
                cell: *cell,
                t_enter: to_f64(a),
                t_exit: to_f64(b),
            });
        }
        out
    }

    /// The intermediate cells (exclusive of both ends) from `a` to `b`, one index step each, canonical order.
    pub(super) fn tie_path(&self, a: OracleCell, b: OracleCell) -> Vec<OracleCell> {
        let mut cur = a;
        let mut path = Vec::new();
        // index order is the canonical order: spherical r, θ, φ; cylindrical ρ, φ, z; polar r, φ
        for c in 0..3 {
            let (Some(x), Some(y)) = (cur[c], b[c]) else {
                cur[c] = b[c];
                continue;
            };
            if x == y {
                continue;
            }
            let n = self.dims[c];
            let wrap = c == self.phi_coord() && self.full;
            let mut i = x;
            let up = if wrap {
                let fwd = (y + n - x) % n;
                fwd <= n - fwd
            } else {
                y > x
            };
            while i != y {
                i = if up {
                    if wrap { (i + 1) % n } else { i + 1 }
                } else if wrap {
                    (i + n - 1) % n
                } else {
                    i - 1
                };
                cur[c] = Some(i);
                path.push(cur);
            }
        }
        // the last pushed equals b (when anything changed); it is not an intermediate
        if path.last() == Some(&b) {
            path.pop();
        }
        // any remaining difference (unknown indices) is absorbed into b
        path
    }
}
