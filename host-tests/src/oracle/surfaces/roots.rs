//! The oracle's roots of each surface family in high precision: the quadratic, the spheroid, the cone's nappe, the half-plane.

use super::*;

/// Roots of the expanded quadratic `A t² + 2 B t + C` (A ≠ 0 or B ≠ 0), ascending, with a flag for a double root.
pub(super) fn quadratic(a: &H, b: &H, c: &H) -> Vec<(H, bool)> {
    if a.is_zero() {
        if b.is_zero() {
            return vec![];
        }
        return vec![(c.neg().div(&b.mul(&H::f(2.0))), false)];
    }
    let disc = b.sq().sub(&a.mul(c));
    if disc.is_neg() {
        return vec![];
    }
    if disc.is_zero() {
        let t = b.neg().div(a);
        return vec![(t.clone(), true), (t, true)];
    }
    let r = disc.sqrt();
    let t1 = b.neg().sub(&r).div(a);
    let t2 = b.neg().add(&r).div(a);
    if t1.cmp(&t2) == Ordering::Greater {
        vec![(t2, false), (t1, false)]
    } else {
        vec![(t1, false), (t2, false)]
    }
}

pub(super) fn spheroid_roots(a2: &H, b2: &H, p: &V, d: &V) -> Vec<(H, bool, f64)> {
    // F = b²(x² + y²) + a² z² − a² b², positive outside.
    let qa = b2.mul(&d[0].sq().add(&d[1].sq())).add(&a2.mul(&d[2].sq()));
    let qb = b2
        .mul(&p[0].mul(&d[0]).add(&p[1].mul(&d[1])))
        .add(&a2.mul(&p[2].mul(&d[2])));
    let qc = b2
        .mul(&p[0].sq().add(&p[1].sq()))
        .add(&a2.mul(&p[2].sq()))
        .sub(&a2.mul(b2));
    let roots = quadratic(&qa, &qb, &qc);
    let mut out = Vec::new();
    for (i, (t, double)) in roots.into_iter().enumerate() {
        // qa > 0: the first root enters the solid, the second leaves (a touch: in, then out).
        let into_positive = i == 1;
        let sin = if double {
            0.0
        } else {
            let x = point(p, d, &t);
            sin_between(&[b2.mul(&x[0]), b2.mul(&x[1]), a2.mul(&x[2])], d)
        };
        out.push((t, into_positive, sin));
    }
    out
}

/// The side of a direction or point `v` (relative to the apex) of the cone of cosine `c`: `Some(true)` when its
/// zenith angle is larger than θ, i.e. `v_z < c |v|`; `None` on the cone (or for the zero vector).
pub(super) fn cone_side_of(c: &H, v: &V) -> Option<bool> {
    let n = dot(v, v).sqrt();
    if n.is_zero() {
        return None;
    }
    match v[2].cmp(&c.mul(&n)) {
        Ordering::Less => Some(true),
        Ordering::Greater => Some(false),
        Ordering::Equal => None,
    }
}

pub(super) fn cone_roots(k: &H, shape: &ConeShape, p: &V, d: &V) -> Vec<(H, bool, f64)> {
    let q = [p[0].clone(), p[1].clone(), p[2].sub(k)];
    let (c, s, c2, s2) = match shape {
        ConeShape::Axis => return vec![],
        ConeShape::Plane => {
            if d[2].is_zero() {
                return vec![];
            }
            let t = q[2].neg().div(&d[2]);
            let n = [H::zero(), H::zero(), H::f(1.0)];
            // larger θ is below the plane
            return vec![(t, d[2].is_neg(), sin_between(&n, d))];
        }
        ConeShape::Proper { c, s, c2, s2 } => (c, s, c2, s2),
    };
    let _ = s;
    // Does the line pass exactly through the apex? Then q × d = 0 (exact: products of f64 data), and the apex is
    // at t = −λ with q = λ d.
    let through_apex = q[1].mul(&d[2]).sub(&q[2].mul(&d[1])).is_zero()
        && q[2].mul(&d[0]).sub(&q[0].mul(&d[2])).is_zero()
        && q[0].mul(&d[1]).sub(&q[1].mul(&d[0])).is_zero();
    let lambda = dot(&q, d).div(&dot(d, d));
    if through_apex {
        let before = cone_side_of(c, &[d[0].neg(), d[1].neg(), d[2].neg()]);
        let after = cone_side_of(c, d);
        return match (before, after) {
            (Some(b), Some(a)) if a != b => vec![(lambda.neg(), a, 0.0)],
            _ => vec![],
        };
    }
    // Q = c²(x² + y²) − s² z² along the ray, expanded.
    let qa = c2.mul(&d[0].sq().add(&d[1].sq())).sub(&s2.mul(&d[2].sq()));
    let qb = c2
        .mul(&q[0].mul(&d[0]).add(&q[1].mul(&d[1])))
        .sub(&s2.mul(&q[2].mul(&d[2])));
    let qc = c2.mul(&q[0].sq().add(&q[1].sq())).sub(&s2.mul(&q[2].sq()));
    if qa.is_zero() && qb.is_zero() {
        return vec![]; // on the double cone (C = 0) or parallel to a generator and never meeting it
    }
    let upper = c.is_pos();
    let mut out = Vec::new();
    let roots = quadratic(&qa, &qb, &qc);
    let double = roots.first().map(|r| r.1).unwrap_or(false);
    if double {
        // A touch. The line lies on one side everywhere else: evaluate a point off the touch.
        let t0 = roots[0].0.clone();
        let x = point(&q, d, &t0);
        let on_nappe = if upper { x[2].is_pos() } else { x[2].is_neg() };
        if on_nappe {
            let off = point(&q, d, &t0.add(&H::f(1.0)));
            if let Some(line_side) = cone_side_of(c, &off) {
                out.push((t0.clone(), !line_side, 0.0));
                out.push((t0, line_side, 0.0));
            }
        }
        return out;
    }
    for (t, _) in roots {
        let x = point(&q, d, &t);
        let on_nappe = if upper { x[2].is_pos() } else { x[2].is_neg() };
        if !on_nappe {
            continue;
        }
        // d/dt cos θ(t) ∝ d_z |x|² − x_z (x·d): negative means θ grows, i.e. into the positive side.
        let g = d[2].mul(&dot(&x, &x)).sub(&x[2].mul(&dot(&x, d)));
        let n = [c2.mul(&x[0]), c2.mul(&x[1]), s2.mul(&x[2]).neg()];
        out.push((t, g.is_neg(), sin_between(&n, d)));
    }
    out
}

pub(super) fn half_plane_roots(cos: &H, sin: &H, p: &V, d: &V) -> Vec<(H, bool, f64)> {
    // normal n = (−sin φ, cos φ, 0) points toward increasing φ
    let nd = cos.mul(&d[1]).sub(&sin.mul(&d[0]));
    if nd.is_zero() {
        return vec![];
    }
    let np = cos.mul(&p[1]).sub(&sin.mul(&p[0]));
    let t = np.neg().div(&nd);
    // Does the line meet the z axis (then the crossing is on the axis, the edge, which belongs to the half-plane)?
    let meets_axis = p[0].mul(&d[1]).sub(&p[1].mul(&d[0])).is_zero();
    let x = point(p, d, &t);
    let along = cos.mul(&x[0]).add(&sin.mul(&x[1]));
    if !meets_axis && along.is_neg() {
        return vec![];
    }
    let n = [sin.neg(), cos.clone(), H::zero()];
    vec![(t, nd.is_pos(), sin_between(&n, d))]
}
