//! The terrain picking oracle: the nearest intersection of a ray with the contract's triangle surface of a DEM,
//! by brute force over every triangle, decided in arbitrary precision.
//!
//! Independence: this module shares no code path with the kernel's terrain traversal (Wartell et al. §3–§4). It does not
//! use zones, quads, bounding spheroids, cones or meridian planes. It works in three stages:
//!
//! 1. **Filter (f64, conservative).** Every triangle lies inside the convex hull of its three vertices, hence
//!    inside the axis-aligned box of any set of vertices containing them, and inside the ball around its centroid
//!    through its farthest vertex. The oracle computes every vertex in `f64`, groups cells into chunks of
//!    8 × 8 and 64 × 64, and keeps a triangle only if the ray (over `[t_min, t_max]`) meets its chunk boxes and
//!    its ball, every box and ball grown by a margin far above the `f64` error of the vertices and of the test
//!    (1 mm + 1e-9 relative; the `f64` vertices are within a few nanometres of the exact ones). No triangle the
//!    ray can touch is dropped.
//! 2. **Exact (astro-float, 256 bits).** The vertices of the candidates are recomputed from the DEM's numbers in
//!    256-bit arithmetic (degrees to radians with a 256-bit π, sine, cosine, the prime-vertical radius
//!    N = a²/√(a²cos²φ + b²sin²φ)), and the ray is intersected with each closed triangle by the signs of
//!    scalar triple products (Möller–Trumbore without division for the inside test). At 256 bits the rounding is
//!    ~1e-70 relative: the inside/outside decisions are exact for every ray that is not exactly on an edge, and an
//!    exact edge hit belongs to both neighbours with the same t.
//! 3. **Order.** Candidates are processed by the entry parameter of their ball; the search stops when the next
//!    ball starts beyond the best exact hit, so the answer is the nearest hit with `t_min ≤ t ≤ t_max`, ties
//!    broken by (row, column, triangle).
//!
//! Per the contract: both faces count (a ray starting below the surface hits it from below); a vertex that is
//! missing (NaN) removes its adjacent triangles; a row at ±90° is a pole where all vertices coincide (the
//! triangles touching it degenerate to segments or keep one edge on the axis); longitudes past ±180° are just
//! angles.

pub(crate) use super::precise::RM;
pub use super::precise::to_f64;
use super::precise::with_consts;
use astro_float::{BigFloat, Consts};
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::{Dem, geodetic_to_ecef_f64};

pub(crate) const P: usize = 256;
const CHUNK: usize = 8;
const SUPER: usize = 64;

/// The oracle's answer for one ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OracleHit {
    /// The ray parameter of the hit (in units of the ray's direction), rounded from 256 bits.
    pub t: f64,
    /// The hit point `origin + t·dir` computed in 256 bits, rounded to `f64`.
    pub point: [f64; 3],
    /// The grid cell (row i, column j).
    pub cell: (usize, usize),
    /// Which of the cell's triangles: 0 = (V(i,j), V(i,j+1), V(i+1,j+1)), 1 = (V(i,j), V(i+1,j+1), V(i+1,j)).
    pub triangle: usize,
}

/// Counters of one oracle query.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OracleStats {
    /// Triangles that passed the f64 filter.
    pub candidates: usize,
    /// Triangles tested in 256-bit arithmetic.
    pub exact_tests: usize,
}

#[derive(Clone, Copy)]
struct Aabb {
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
    };
    fn add(&mut self, p: &[f64; 3]) {
        for (k, &x) in p.iter().enumerate() {
            self.lo[k] = self.lo[k].min(x);
            self.hi[k] = self.hi[k].max(x);
        }
    }
    fn merge(&mut self, o: &Aabb) {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(o.lo[k]);
            self.hi[k] = self.hi[k].max(o.hi[k]);
        }
    }
    fn is_empty(&self) -> bool {
        self.lo[0] > self.hi[0]
    }
    /// Conservative slab test over [t0, t1]: false only if the ray surely misses the box grown by the margin.
    fn meets(&self, o: &[f64; 3], d: &[f64; 3], t0: f64, t1: f64) -> bool {
        if self.is_empty() {
            return false;
        }
        let (mut a, mut b) = (t0, t1);
        for k in 0..3 {
            let m = margin(self.lo[k].abs().max(self.hi[k].abs()));
            let (lo, hi) = (self.lo[k] - m, self.hi[k] + m);
            if d[k] == 0.0 {
                if o[k] < lo || o[k] > hi {
                    return false;
                }
                continue;
            }
            let (mut u, mut v) = ((lo - o[k]) / d[k], (hi - o[k]) / d[k]);
            if u > v {
                std::mem::swap(&mut u, &mut v);
            }
            // Division and subtraction round: widen by a relative slack.
            let s = 1e-9 * (u.abs().max(v.abs())) + 1e-12;
            a = a.max(u - s);
            b = b.min(v + s);
            if a > b {
                return false;
            }
        }
        true
    }
}

fn margin(scale: f64) -> f64 {
    1e-3 + 1e-9 * scale
}

/// Rows and columns of 256-bit trigonometry for a DEM, computed once.
pub(crate) struct Exact {
    /// Per row: (N cosφ, N (b²/a²) sinφ, cosφ, sinφ).
    rows: Vec<[BigFloat; 4]>,
    /// Per column: (cosλ, sinλ).
    cols: Vec<[BigFloat; 2]>,
}

pub(crate) fn bf(x: f64) -> BigFloat {
    super::precise::bf(x, P)
}

/// Sine and cosine of an angle in degrees at 256 bits, exact at multiples of 90° (so that a pole row lies exactly
/// on the axis and the meridians at ±180° coincide).
fn sincos_deg_exact(deg: &BigFloat, cc: &mut Consts) -> (BigFloat, BigFloat) {
    let q = deg.div(&bf(90.0), P, RM);
    if q.is_int() {
        let k = to_f64(&q).rem_euclid(4.0) as i64;
        let (s, c) = [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0)][k as usize];
        return (bf(s), bf(c));
    }
    let r = deg_to_rad(deg, cc);
    (r.sin(P, RM, cc), r.cos(P, RM, cc))
}

fn deg_to_rad(deg: &BigFloat, cc: &mut Consts) -> BigFloat {
    let pi = cc.pi(P, RM);
    deg.mul(&pi, P, RM).div(&bf(180.0), P, RM)
}

impl Exact {
    pub(crate) fn new(dem: &Dem) -> Exact {
        let a = bf(dem.a);
        let b = bf(dem.b);
        let a2 = a.mul(&a, P, RM);
        let b2 = b.mul(&b, P, RM);
        let b2_over_a2 = b2.div(&a2, P, RM);
        let rows = (0..dem.rows)
            .map(|i| {
                let lat = bf(dem.lat0).add(&bf(i as f64).mul(&bf(dem.dlat), P, RM), P, RM);
                // A row exactly at ±90° is a pole: all its vertices lie exactly on the axis (contract).
                let (s, c) = with_consts(|cc| sincos_deg_exact(&lat, cc));
                let den = a2
                    .mul(&c.mul(&c, P, RM), P, RM)
                    .add(&b2.mul(&s.mul(&s, P, RM), P, RM), P, RM)
                    .sqrt(P, RM);
                let n = a2.div(&den, P, RM);
                [
                    n.mul(&c, P, RM),
                    n.mul(&b2_over_a2, P, RM).mul(&s, P, RM),
                    c,
                    s,
                ]
            })
            .collect();
        // A grid spanning 360° (to 1e-9°) closes: its last column is the first one plus exactly 360°.
        let closes = ((dem.cols - 1) as f64 * dem.dlon - 360.0).abs() < 1e-9;
        let cols = (0..dem.cols)
            .map(|j| {
                let lon = if closes && j == dem.cols - 1 {
                    bf(dem.lon0).add(&bf(360.0), P, RM)
                } else {
                    bf(dem.lon0).add(&bf(j as f64).mul(&bf(dem.dlon), P, RM), P, RM)
                };
                let (s, c) = with_consts(|cc| sincos_deg_exact(&lon, cc));
                [c, s]
            })
            .collect();
        Exact { rows, cols }
    }

    /// Vertex (i, j) at height h in 256 bits: ((N + h) cosφ cosλ, (N + h) cosφ sinλ, (N b²/a² + h) sinφ).
    pub(crate) fn vertex(&self, i: usize, j: usize, h: f32) -> [BigFloat; 3] {
        let [ncos, nz, c, s] = &self.rows[i];
        let [cl, sl] = &self.cols[j];
        let h = bf(f64::from(h));
        let rho = ncos.add(&h.mul(c, P, RM), P, RM);
        [
            rho.mul(cl, P, RM),
            rho.mul(sl, P, RM),
            nz.add(&h.mul(s, P, RM), P, RM),
        ]
    }
}

fn sub3(a: &[BigFloat; 3], b: &[BigFloat; 3]) -> [BigFloat; 3] {
    [
        a[0].sub(&b[0], P, RM),
        a[1].sub(&b[1], P, RM),
        a[2].sub(&b[2], P, RM),
    ]
}

fn cross3(a: &[BigFloat; 3], b: &[BigFloat; 3]) -> [BigFloat; 3] {
    let m = |x: &BigFloat, y: &BigFloat| x.mul(y, P, RM);
    [
        m(&a[1], &b[2]).sub(&m(&a[2], &b[1]), P, RM),
        m(&a[2], &b[0]).sub(&m(&a[0], &b[2]), P, RM),
        m(&a[0], &b[1]).sub(&m(&a[1], &b[0]), P, RM),
    ]
}

fn dot3(a: &[BigFloat; 3], b: &[BigFloat; 3]) -> BigFloat {
    a[0].mul(&b[0], P, RM)
        .add(&a[1].mul(&b[1], P, RM), P, RM)
        .add(&a[2].mul(&b[2], P, RM), P, RM)
}

/// The brute-force oracle over one DEM. Construction computes every vertex in `f64` (for the filter) and the
/// per-row and per-column trigonometry in 256 bits (for the exact stage).
pub struct TerrainOracle<'a> {
    dem: &'a Dem,
    verts: Vec<[f64; 3]>,
    chunks: Vec<Aabb>,
    chunk_dims: (usize, usize),
    supers: Vec<Aabb>,
    super_dims: (usize, usize),
    exact: Exact,
}

impl<'a> TerrainOracle<'a> {
    /// Prepares the oracle for `dem`.
    pub fn new(dem: &'a Dem) -> TerrainOracle<'a> {
        let mut verts = Vec::with_capacity(dem.rows * dem.cols);
        for i in 0..dem.rows {
            for j in 0..dem.cols {
                verts.push(dem.vertex_ecef(i, j).unwrap_or([f64::NAN; 3]));
            }
        }
        let (cr, cc) = (dem.rows - 1, dem.cols - 1);
        let chunk_dims = (cr.div_ceil(CHUNK), cc.div_ceil(CHUNK));
        let mut chunks = vec![Aabb::EMPTY; chunk_dims.0 * chunk_dims.1];
        for i in 0..dem.rows {
            for j in 0..dem.cols {
                let v = &verts[i * dem.cols + j];
                if v[0].is_nan() {
                    continue;
                }
                // A vertex belongs to the chunks of every cell it is a corner of.
                for ci in (i.saturating_sub(1) / CHUNK)..=(i.min(cr - 1) / CHUNK) {
                    for cj in (j.saturating_sub(1) / CHUNK)..=(j.min(cc - 1) / CHUNK) {
                        chunks[ci * chunk_dims.1 + cj].add(v);
                    }
                }
            }
        }
        let r = SUPER / CHUNK;
        let super_dims = (chunk_dims.0.div_ceil(r), chunk_dims.1.div_ceil(r));
        let mut supers = vec![Aabb::EMPTY; super_dims.0 * super_dims.1];
        for ci in 0..chunk_dims.0 {
            for cj in 0..chunk_dims.1 {
                supers[(ci / r) * super_dims.1 + cj / r].merge(&chunks[ci * chunk_dims.1 + cj]);
            }
        }
        TerrainOracle {
            dem,
            verts,
            chunks,
            chunk_dims,
            supers,
            super_dims,
            exact: Exact::new(dem),
        }
    }

    /// The DEM this oracle answers for.
    pub fn dem(&self) -> &Dem {
        self.dem
    }

    /// The nearest hit of `ray` with the surface for `t_min ≤ t ≤ t_max`, or `None`.
    pub fn pick(&self, ray: &RaySpec) -> Option<OracleHit> {
        self.pick_with_stats(ray).0
    }

    /// [`TerrainOracle::pick`] with counters.
    pub fn pick_with_stats(&self, ray: &RaySpec) -> (Option<OracleHit>, OracleStats) {
        let mut stats = OracleStats::default();
        let (o, d) = (ray.origin, ray.dir);
        let (t0, t1) = (ray.t_min, ray.t_max_or_inf());
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if dd.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
            || t0
                .partial_cmp(&t1)
                .is_none_or(|c| c == std::cmp::Ordering::Greater)
        {
            return (None, stats);
        }
        // Stage 1: candidates with the entry parameter of their ball.
        let mut cands: Vec<(f64, usize, usize, usize)> = Vec::new();
        let r = SUPER / CHUNK;
        let cols = self.dem.cols;
        for si in 0..self.super_dims.0 {
            for sj in 0..self.super_dims.1 {
                if !self.supers[si * self.super_dims.1 + sj].meets(&o, &d, t0, t1) {
                    continue;
                }
                for ci in si * r..((si + 1) * r).min(self.chunk_dims.0) {
                    for cj in sj * r..((sj + 1) * r).min(self.chunk_dims.1) {
                        if !self.chunks[ci * self.chunk_dims.1 + cj].meets(&o, &d, t0, t1) {
                            continue;
                        }
                        for i in ci * CHUNK..((ci + 1) * CHUNK).min(self.dem.rows - 1) {
                            for j in cj * CHUNK..((cj + 1) * CHUNK).min(cols - 1) {
                                for k in 0..2 {
                                    let Some(tri) = self.dem.triangle(i, j, k) else {
                                        continue;
                                    };
                                    let v = tri.map(|(a, b)| self.verts[a * cols + b]);
                                    if let Some(te) = ball_entry(&v, &o, &d, dd, t0, t1) {
                                        cands.push((te, i, j, k));
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        stats.candidates = cands.len();
        cands.sort_by(|x, y| {
            x.0.total_cmp(&y.0)
                .then((x.1, x.2, x.3).cmp(&(y.1, y.2, y.3)))
        });
        // Stage 2 and 3: exact tests in order of ball entry.
        let ob = o.map(bf);
        let db = d.map(bf);
        let (t0b, t1b) = (bf(t0), if t1.is_finite() { Some(bf(t1)) } else { None });
        let mut best: Option<(BigFloat, f64, usize, usize, usize)> = None;
        for &(te, i, j, k) in &cands {
            if let Some((_, bt, ..)) = &best
                && te > *bt + 1e-9 * bt.abs() + 1e-9
            {
                break;
            }
            stats.exact_tests += 1;
            let Some(tri) = self.dem.triangle(i, j, k) else {
                continue;
            };
            let v = tri.map(|(a, b)| {
                let h = self.dem.heights[a * cols + b];
                self.exact.vertex(a, b, h)
            });
            let Some(t) = intersect_exact(&ob, &db, &v, &t0b, t1b.as_ref()) else {
                continue;
            };
            let better = match &best {
                None => true,
                Some((bt, ..)) => t.cmp(bt).is_some_and(|c| c < 0),
            };
            if better {
                let tf = to_f64(&t);
                best = Some((t, tf, i, j, k));
            }
        }
        let hit = best.map(|(t, tf, i, j, k)| {
            let p = [0, 1, 2].map(|a| to_f64(&ob[a].add(&t.mul(&db[a], P, RM), P, RM)));
            OracleHit {
                t: tf,
                point: p,
                cell: (i, j),
                triangle: k,
            }
        });
        (hit, stats)
    }

    /// Memory of the oracle's own structures in bytes (f64 vertices and chunk boxes; the 256-bit row/column
    /// trigonometry is not counted).
    pub fn memory_bytes(&self) -> usize {
        self.verts.len() * 24 + (self.chunks.len() + self.supers.len()) * 48
    }
}

/// Entry parameter of the ray into the ball around the triangle's centroid through its farthest vertex (grown by
/// the margin), if the ray meets it within [t0, t1] (conservatively widened).
pub(crate) fn ball_entry(
    v: &[[f64; 3]; 3],
    o: &[f64; 3],
    d: &[f64; 3],
    dd: f64,
    t0: f64,
    t1: f64,
) -> Option<f64> {
    let c = [0, 1, 2].map(|k| (v[0][k] + v[1][k] + v[2][k]) / 3.0);
    let mut r2: f64 = 0.0;
    for p in v {
        let e = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        r2 = r2.max(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    }
    let r = r2.sqrt() * (1.0 + 1e-9) + margin(c[0].abs().max(c[1].abs()).max(c[2].abs()));
    let w = [c[0] - o[0], c[1] - o[1], c[2] - o[2]];
    let tc = (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / dd;
    let x = [
        w[1] * d[2] - w[2] * d[1],
        w[2] * d[0] - w[0] * d[2],
        w[0] * d[1] - w[1] * d[0],
    ];
    let dist2 = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) / dd;
    let wl = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    // Rounding of the cross product: relative 1e-15 of |w|²; grow r² accordingly.
    let r2g = r * r + 1e-12 * wl * wl;
    if dist2 > r2g {
        return None;
    }
    let half = ((r2g - dist2).max(0.0) / dd).sqrt();
    let slack = 1e-9 * (tc.abs() + half) + 1e-9;
    let (a, b) = (tc - half - slack, tc + half + slack);
    if b < t0 || a > t1 {
        return None;
    }
    Some(a.max(t0))
}

fn lt(a: &BigFloat, b: &BigFloat) -> bool {
    a.cmp(b).is_some_and(|c| c < 0)
}

fn mag(v: &[BigFloat; 3]) -> f64 {
    v.iter().map(|x| to_f64(x).abs()).fold(0.0, f64::max)
}

/// The exact ray–triangle intersection (closed triangle, both faces): the least `t` in `[t0, t1]` (`t1 = None`
/// is +∞) at which the ray is on the triangle.
///
/// A ray in the triangle's plane (|det| below 2⁻²⁰⁰ of its scale: at 256 bits only an exactly coplanar ray, such
/// as a ray down the axis in the plane of a pole triangle, gets there) is clipped against the triangle's edges
/// in the plane's 2-D projection.
pub(crate) fn intersect_exact(
    o: &[BigFloat; 3],
    d: &[BigFloat; 3],
    v: &[[BigFloat; 3]; 3],
    t0: &BigFloat,
    t1: Option<&BigFloat>,
) -> Option<BigFloat> {
    let e1 = sub3(&v[1], &v[0]);
    let e2 = sub3(&v[2], &v[0]);
    let p = cross3(d, &e2);
    let det = dot3(&e1, &p);
    let scale = mag(&e1) * mag(&e2) * mag(d);
    if scale == 0.0 {
        return None;
    }
    let in_range = |t: &BigFloat| !lt(t, t0) && t1.is_none_or(|t1| !lt(t1, t));
    if to_f64(&det).abs() <= scale * 2f64.powi(-200) {
        return coplanar(o, d, v, &cross3(&e1, &e2), t0, t1);
    }
    let s = sub3(o, &v[0]);
    let q = cross3(&s, &e1);
    // u·det = s·p, v·det = d·q; inside iff u, v ≥ 0 and u + v ≤ 1, i.e. by signs relative to det.
    let neg = det.is_negative();
    let same = |x: &BigFloat| x.is_zero() || x.is_negative() == neg;
    let ud = dot3(&s, &p);
    let vd = dot3(d, &q);
    if !same(&ud) || !same(&vd) {
        return None;
    }
    let rest = det.sub(&ud, P, RM).sub(&vd, P, RM);
    if !same(&rest) {
        return None;
    }
    let t = dot3(&e2, &q).div(&det, P, RM);
    in_range(&t).then_some(t)
}

/// A ray in the plane of a triangle: the interval of t over which it is inside (2-D projection along the
/// normal's largest component), clipped to [t0, t1]; its start.
fn coplanar(
    o: &[BigFloat; 3],
    d: &[BigFloat; 3],
    v: &[[BigFloat; 3]; 3],
    n: &[BigFloat; 3],
    t0: &BigFloat,
    t1: Option<&BigFloat>,
) -> Option<BigFloat> {
    let nf = n.clone().map(|x| to_f64(&x).abs());
    let drop = if nf[0] >= nf[1] && nf[0] >= nf[2] {
        0
    } else if nf[1] >= nf[2] {
        1
    } else {
        2
    };
    if nf[drop] == 0.0 {
        return None; // degenerate triangle (a segment or a point)
    }
    let (x, y) = ((drop + 1) % 3, (drop + 2) % 3);
    let cr = |ax: &BigFloat, ay: &BigFloat, bx: &BigFloat, by: &BigFloat| {
        ax.mul(by, P, RM).sub(&ay.mul(bx, P, RM), P, RM)
    };
    // Orientation of the triangle in 2-D.
    let area = cr(
        &v[1][x].sub(&v[0][x], P, RM),
        &v[1][y].sub(&v[0][y], P, RM),
        &v[2][x].sub(&v[0][x], P, RM),
        &v[2][y].sub(&v[0][y], P, RM),
    );
    let pos = !area.is_negative();
    // Each edge (A, B) gives a half-plane: cross(B − A, X − A) has the orientation's sign. Along the ray this is
    // affine in t: c0 + c1·t ≥ 0 (sign-adjusted); intersect the t-intervals.
    let mut lo = t0.clone();
    let mut hi = t1.cloned();
    for k in 0..3 {
        let (a, b) = (&v[k], &v[(k + 1) % 3]);
        let ex = b[x].sub(&a[x], P, RM);
        let ey = b[y].sub(&a[y], P, RM);
        let mut c0 = cr(&ex, &ey, &o[x].sub(&a[x], P, RM), &o[y].sub(&a[y], P, RM));
        let mut c1 = cr(&ex, &ey, &d[x], &d[y]);
        if !pos {
            c0 = c0.neg();
            c1 = c1.neg();
        }
        if c1.is_zero() {
            if c0.is_negative() {
                return None;
            }
            continue;
        }
        let t = c0.neg().div(&c1, P, RM);
        if c1.is_negative() {
            // c0 + c1 t ≥ 0 ⇔ t ≤ −c0/c1
            if hi.as_ref().is_none_or(|h| lt(&t, h)) {
                hi = Some(t);
            }
        } else if lt(&lo, &t) {
            lo = t;
        }
    }
    match hi {
        Some(h) if lt(&h, &lo) => None,
        _ => Some(lo),
    }
}

/// An `f64` brute force over every triangle (Möller–Trumbore, no filtering, no arbitrary precision) — the
/// baseline the report and benchmarks time against; not an oracle.
pub fn brute_force_f64(dem: &Dem, ray: &RaySpec) -> Option<(f64, (usize, usize))> {
    let (o, d) = (ray.origin, ray.dir);
    let (t0, t1) = (ray.t_min, ray.t_max_or_inf());
    let mut best: Option<(f64, (usize, usize))> = None;
    for i in 0..dem.rows - 1 {
        for j in 0..dem.cols - 1 {
            for k in 0..2 {
                let Some(tri) = dem.triangle(i, j, k) else {
                    continue;
                };
                let v = tri.map(|(a, b)| {
                    geodetic_to_ecef_f64(
                        dem.a,
                        dem.b,
                        dem.lat(a),
                        dem.lon(b),
                        f64::from(dem.heights[a * dem.cols + b]),
                    )
                });
                if let Some(t) = moller_trumbore(&o, &d, &v)
                    && t >= t0
                    && t <= t1
                    && best.is_none_or(|(bt, _)| t < bt)
                {
                    best = Some((t, (i, j)));
                }
            }
        }
    }
    best
}

/// Möller–Trumbore in `f64` (both faces, closed triangle).
pub fn moller_trumbore(o: &[f64; 3], d: &[f64; 3], v: &[[f64; 3]; 3]) -> Option<f64> {
    let sub = |a: &[f64; 3], b: &[f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: &[f64; 3], b: &[f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let e1 = sub(&v[1], &v[0]);
    let e2 = sub(&v[2], &v[0]);
    let p = cross(d, &e2);
    let det = dot(&e1, &p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = sub(o, &v[0]);
    let u = dot(&s, &p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = cross(&s, &e1);
    let w = dot(d, &q) * inv;
    if w < 0.0 || u + w > 1.0 {
        return None;
    }
    Some(dot(&e2, &q) * inv)
}

#[cfg(test)]
mod tests;
