//! Node boxes (beyond the paper): a storage may give every node a box that contains all of the node's vertices,
//! in a local frame ([`LocalFrame`]). Triangles are the convex hulls of their vertices, so the box contains every
//! triangle the traversal can trace under the node — at any block stride and with the stitching fans of §6, whose
//! vertices are the node's grid vertices and midpoints of its cells' diagonals — with no sagitta or bulge bound
//! needed. The traversal moves the ray into a frame once and tests boxes with three slabs each (a small fraction
//! of the cost of the spheroidal volume's relaxed test, [`crate::geodesy::relaxed_interval`]); for a node a few
//! kilometres across the box is also the tighter of the two (its faces follow the local horizon; the volume's
//! lower wall is a sphere). The no-miss argument (`traverse.rs`, "No misses: what is proven") holds unchanged
//! with the box as the node's volume.
//!
//! **Which frame.** A zone's box is in the frame of the whole grid. A child's box is in its parent's own frame
//! ([`super::node_frame`]), or, when the box says so ([`NodeBox::shared_frame`]), in the frame its parent's box is
//! in. A frame is *anchored* at the node whose own frame it is (or at the grid); while the anchor is small, its
//! frame fits every box below it nearly as well as their parents' own frames would, so a storage may pass it
//! down, and the traversal of a regional DEM then moves the ray into one frame per ray or per zone instead of one
//! per visited node ([`shares_frame_with_children`] is the rule the host's storage follows; the kernel only reads
//! the flag). [`super::box_frame`] gives a box's frame from its anchor.
//!
//! A frame is east, north, up at a node's middle vertex ([`super::node_frame`]); the box is stored in `f32`,
//! rounded outwards, and the kernel inflates it by the rounding of the ray's transformation and of the frame and
//! vertices in the picker's scalar type (`f32` pickers included).

use super::grid::{Grid, Node};

use crate::ray::Ray;
use crate::real::Real;
use crate::vec3::V3;

/// A node's local frame: unit vectors east `e = (−sin λ, cos λ, 0)`, north `n = (−sin φ cos λ, −sin φ sin λ,
/// cos φ)` and up `u = (cos φ cos λ, cos φ sin λ, sin φ)` (the geodetic normal) at the node's middle vertex
/// `(φ, λ)`, with origin `a·u`. Coordinates of a point `P` are `(e·P, n·P, u·P − a)`, formed through the
/// horizontal radial component `r = x cos λ + y sin λ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFrame<T> {
    sin_lat: T,
    cos_lat: T,
    sin_lon: T,
    cos_lon: T,
    a: T,
}

impl<T: Real> LocalFrame<T> {
    /// The frame at the vertex whose latitude has `(sin, cos)` `row` and longitude `col`, on an ellipsoid of
    /// equatorial radius `a` (a storage's frames: [`super::node_frame`], [`super::box_frame`]).
    pub fn at(a: T, (sin_lat, cos_lat): (T, T), (sin_lon, cos_lon): (T, T)) -> Self {
        LocalFrame {
            sin_lat,
            cos_lat,
            sin_lon,
            cos_lon,
            a,
        }
    }

    /// `(e·v, n·v, u·v)` of a vector.
    #[inline]
    fn rotate(&self, v: V3<T>) -> V3<T> {
        let r = self.cos_lon * v.x + self.sin_lon * v.y;
        V3::new(
            self.cos_lon * v.y - self.sin_lon * v.x,
            self.cos_lat * v.z - self.sin_lat * r,
            self.cos_lat * r + self.sin_lat * v.z,
        )
    }

    /// The up coordinate `u·P − a` of a point.
    #[inline]
    pub fn up(&self, p: V3<T>) -> T {
        self.up_dir(p) - self.a
    }

    /// The frame's `a`: the origin lies at `a·u`.
    #[inline]
    pub fn a(&self) -> T {
        self.a
    }

    /// The largest up coordinate of a point of the spheroid with semi-axes `a` (the frame's) and `b`: its
    /// support function in the direction `u`, `√(a²(u_x² + u_y²) + b² u_z²) − a`, a bound that holds for the `u`
    /// formed from the rounded sines and cosines too (no tangency is assumed). Rounded to within a few ulps of `a`.
    #[inline]
    pub fn spheroid_top(&self, b: T) -> T {
        let (ux, uy, uz) = (
            self.cos_lat * self.cos_lon,
            self.cos_lat * self.sin_lon,
            self.sin_lat,
        );
        (self.a * self.a * (ux * ux + uy * uy) + b * b * (uz * uz)).sqrt() - self.a
    }

    /// The up component `u·d` of a direction.
    #[inline]
    pub fn up_dir(&self, d: V3<T>) -> T {
        self.cos_lat * (self.cos_lon * d.x + self.sin_lon * d.y) + self.sin_lat * d.z
    }

    /// The coordinates `(e·P, n·P, u·P − a)` of an ECEF point.
    #[inline]
    pub fn coords(&self, p: V3<T>) -> V3<T> {
        let q = self.rotate(p);
        V3::new(q.x, q.y, q.z - self.a)
    }

    /// The ECEF point of frame coordinates `q` (the inverse of [`LocalFrame::coords`], up to rounding).
    #[inline]
    pub fn point(&self, q: V3<T>) -> V3<T> {
        let (up, north) = (q.z + self.a, q.y);
        let r = self.cos_lat * up - self.sin_lat * north;
        V3::new(
            self.cos_lon * r - self.sin_lon * q.x,
            self.sin_lon * r + self.cos_lon * q.x,
            self.sin_lat * up + self.cos_lat * north,
        )
    }
}

/// The widest anchor, in degrees of latitude and of longitude, whose frame [`shares_frame_with_children`] keeps.
pub const SHARED_FRAME_SPAN_DEG: f64 = 1.0;

/// The rule the host's storage follows for [`NodeBox::shared_frame`] (the kernel only reads the flag): a node's
/// children's boxes stay in the frame of the node's own box when that frame's anchor (`None`: the grid) spans at
/// most [`SHARED_FRAME_SPAN_DEG`] of latitude and of longitude; otherwise they are in the node's own frame. The
/// children lie inside the anchor, so their boxes' faces tilt against their local horizon by at most about that
/// angle: a box 1.5 km wide is at most about 26 m thicker than in its parent's own frame, while a regional DEM's
/// traversal moves the ray into one frame per zone (or per ray) instead of one per visited node.
pub fn shares_frame_with_children<T: Real>(grid: &Grid<T>, anchor: Option<&Node<T>>) -> bool {
    let (rows, cols) = match anchor {
        Some(n) => (n.rows, n.cols),
        None => ([0, grid.cell_rows()], [0, grid.cell_cols()]),
    };
    let span = |[a, b]: [u32; 2], step: T| T::from_f64(f64::from(b.saturating_sub(a))) * step.abs();
    let lim = T::from_f64(SHARED_FRAME_SPAN_DEG);
    span(rows, grid.dlat_deg) <= lim && span(cols, grid.dlon_deg) <= lim
}

/// The anchor of node `k`'s box frame ([`super::box_frame`]) for a storage's build step, from its tree's parent
/// links and the flags it gives the boxes ([`NodeBox::shared_frame`]): up from `k` while the box shares its
/// parent's box frame, then that node's parent; `None` for the grid's frame (a zone's, or a chain of shared frames
/// up to a zone). At most `nodes` steps: only a cycle of parent links takes more, and gives `None`.
pub fn anchor_of(
    k: usize,
    nodes: usize,
    parent: impl Fn(usize) -> Option<usize>,
    shared: impl Fn(usize) -> bool,
) -> Option<usize> {
    let mut c = k;
    for _ in 0..=nodes {
        let p = parent(c)?;
        if !shared(c) {
            return Some(p);
        }
        c = p;
    }
    None
}

/// A node's box in a [`LocalFrame`] (module docs, "Which frame"): `lo ≤ coords(V) ≤ hi` for every vertex `V` of
/// the node with data (rows `rows[0] ..= rows[1]`, columns `cols[0] ..= cols[1]`), the vertices as
/// [`super::vertex_ecef`] forms them in `f64`. Build it with [`super::node_box_of_vertices`] or [`BoxBuilder`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeBox {
    /// Lower corner (east, north, up), metres.
    pub lo: [f32; 3],
    /// Upper corner.
    pub hi: [f32; 3],
    /// The box is in the frame of its parent's box, not in its parent's own frame (ignored for a zone, whose
    /// box is in the grid's frame).
    pub shared_frame: bool,
}

impl NodeBox {
    /// The smallest box containing both (the same frame assumed), keeping this box's flag.
    pub fn union(&self, other: &NodeBox) -> NodeBox {
        let mut b = *self;
        for k in 0..3 {
            if let (Some(l), Some(&o)) = (b.lo.get_mut(k), other.lo.get(k)) {
                *l = l.min(o);
            }
            if let (Some(h), Some(&o)) = (b.hi.get_mut(k), other.hi.get(k)) {
                *h = h.max(o);
            }
        }
        b
    }

    /// The eight corners, in frame coordinates.
    pub fn corners(&self) -> [V3<f64>; 8] {
        let mut out = [V3::new(0.0, 0.0, 0.0); 8];
        for (k, c) in out.iter_mut().enumerate() {
            let pick = |axis: usize| {
                let (lo, hi) = (self.lo.get(axis), self.hi.get(axis));
                f64::from(*if (k >> axis) & 1 == 0 { lo } else { hi }.unwrap_or(&0.0))
            };
            *c = V3::new(pick(0), pick(1), pick(2));
        }
        out
    }
}

/// Accumulates ECEF points, in a frame's coordinates (computed in `f64`), into a [`NodeBox`], rounded outwards
/// with a margin for the rounding of the coordinates themselves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxBuilder {
    lo: [f64; 3],
    hi: [f64; 3],
    /// Largest `|P|₁ + a` seen, for the margin.
    mag: f64,
}

impl Default for BoxBuilder {
    fn default() -> Self {
        BoxBuilder {
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
            mag: 0.0,
        }
    }
}

impl BoxBuilder {
    /// Adds the ECEF point `p` in `frame`'s coordinates; non-finite points are ignored.
    pub fn add_point(&mut self, frame: &LocalFrame<f64>, p: V3<f64>) {
        self.add(frame.coords(p), p.x.abs() + p.y.abs() + p.z.abs() + frame.a);
    }

    /// Adds frame coordinates `q` of a point of magnitude `|P|₁ + a` (for the margin).
    fn add(&mut self, q: V3<f64>, magnitude: f64) {
        if !(q.is_finite() && magnitude.is_finite()) {
            return;
        }
        for (k, v) in [q.x, q.y, q.z].into_iter().enumerate() {
            if let (Some(lo), Some(hi)) = (self.lo.get_mut(k), self.hi.get_mut(k)) {
                *lo = lo.min(v);
                *hi = hi.max(v);
            }
        }
        self.mag = self.mag.max(magnitude);
    }

    /// The box of the points added (not [`NodeBox::shared_frame`]), or `None` if there were none.
    pub fn finish(&self) -> Option<NodeBox> {
        if !self.lo.iter().zip(&self.hi).all(|(l, h)| l <= h) {
            return None;
        }
        let margin = 64.0 * f64::EPSILON * self.mag;
        let round = |v: f64, up: bool| {
            // The nearest f32, moved outwards by at least one ulp if it fell on the wrong side.
            #[allow(clippy::cast_possible_truncation)]
            let f = v as f32;
            let step = (f.abs() * f32::EPSILON).max(f32::MIN_POSITIVE);
            match (up, f64::from(f) < v, f64::from(f) > v) {
                (true, true, _) => f + step,
                (false, _, true) => f - step,
                _ => f,
            }
        };
        let mut b = NodeBox {
            lo: [0.0; 3],
            hi: [0.0; 3],
            shared_frame: false,
        };
        for k in 0..3 {
            if let (Some(o), Some(&l)) = (b.lo.get_mut(k), self.lo.get(k)) {
                *o = round(l - margin, false);
            }
            if let (Some(o), Some(&h)) = (b.hi.get_mut(k), self.hi.get(k)) {
                *o = round(h + margin, true);
            }
        }
        b.lo.iter().chain(&b.hi).all(|v| v.is_finite()).then_some(b)
    }
}

impl<T: Real> LocalFrame<T> {
    /// The ray in this frame, for testing boxes of the frame ([`FrameRay::interval`]) within `[lo, hi]` or any
    /// part of it (the tolerance is sized for parameters up to `max(|lo|, |hi|)`).
    pub fn ray(&self, ray: &Ray<T>, [lo, hi]: [T; 2]) -> FrameRay<T> {
        let (o, d) = (ray.origin(), ray.dir());
        let t_abs = lo.abs().max(hi.abs());
        let mag = (o.x.abs() + o.y.abs() + o.z.abs())
            + t_abs * (d.x.abs() + d.y.abs() + d.z.abs())
            + self.a;
        let (q, qd) = (self.coords(o), self.rotate(d));
        let tol = T::from_f64(32.0) * T::EPSILON * mag;
        FrameRay {
            q_lo: V3::new(q.x + tol, q.y + tol, q.z + tol),
            q_hi: V3::new(q.x - tol, q.y - tol, q.z - tol),
            inv: V3::new(T::ONE / qd.x, T::ONE / qd.y, T::ONE / qd.z),
            bounded: tol.is_finite(),
        }
    }
}

/// A ray in a [`LocalFrame`], set up for its box tests: per axis its origin coordinate shifted by the
/// tolerance `32 ε (|o|₁ + |t|·|d|₁ + a)` (ε of `T`, `t` over the ray's interval) towards each face, which
/// inflates every box by that much, and its reciprocal direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRay<T> {
    /// `q + tol` and `q − tol`: the origin against the boxes' low and high faces.
    q_lo: V3<T>,
    q_hi: V3<T>,
    /// `1 / q_d` per axis: `±∞` for a zero component (signed like the zero).
    inv: V3<T>,
    /// The tolerance is finite; otherwise no box can clip the interval.
    bounded: bool,
}

impl<T: Real> FrameRay<T> {
    /// The hull of the ray's parameters in `[lo, hi]` (within the interval the ray was formed for) inside box `b`
    /// (of the frame, inflated by the tolerance), or `None`. The tolerance covers the rounding of the ray's frame coordinates, of the frame itself and of the vertices
    /// in `T`, and of the slab parameters.
    ///
    /// Per axis the slab is entered at the face the direction points away from. A zero direction component
    /// gives infinite parameters of the right signs (the origin inside the slab: no clip; outside: empty), or a
    /// NaN on a face itself, which compares false and so clips nothing.
    #[inline]
    pub fn interval(&self, b: &NodeBox, span: [T; 2]) -> Option<(T, T)> {
        self.clip_box(b.lo, b.hi, |v: f32| T::from_f64(f64::from(v)), span)
    }

    /// [`FrameRay::interval`] for a box with faces `lo` and `hi` in `T` (a leaf window's,
    /// [`super::windows::WindowBox::faces`]).
    #[inline]
    pub fn interval_of(&self, lo: [T; 3], hi: [T; 3], span: [T; 2]) -> Option<(T, T)> {
        self.clip_box(lo, hi, |v: T| v, span)
    }

    /// The slab test of both: the box's faces as `face` gives them in `T`.
    #[inline(always)]
    fn clip_box<F: Copy>(
        &self,
        b_lo: [F; 3],
        b_hi: [F; 3],
        face: impl Fn(F) -> T,
        [mut lo, mut hi]: [T; 2],
    ) -> Option<(T, T)> {
        if !self.bounded {
            return Some((lo, hi));
        }
        // One axis: the parameters where the ray enters and leaves the slab.
        let slab = |q_lo: T, q_hi: T, inv: T, bl: F, bh: F| {
            let t_lo = (face(bl) - q_lo) * inv;
            let t_hi = (face(bh) - q_hi) * inv;
            if inv < T::ZERO {
                (t_hi, t_lo)
            } else {
                (t_lo, t_hi)
            }
        };
        let clip = |lo: &mut T, hi: &mut T, (enter, leave): (T, T)| {
            if enter > *lo {
                *lo = enter;
            }
            if leave < *hi {
                *hi = leave;
            }
            *lo <= *hi
        };
        let (q_lo, q_hi, inv) = (self.q_lo, self.q_hi, self.inv);
        let [bx, by, bz] = b_lo;
        let [cx, cy, cz] = b_hi;
        let inside = clip(&mut lo, &mut hi, slab(q_lo.x, q_hi.x, inv.x, bx, cx))
            && clip(&mut lo, &mut hi, slab(q_lo.y, q_hi.y, inv.y, by, cy))
            && clip(&mut lo, &mut hi, slab(q_lo.z, q_hi.z, inv.z, bz, cz));
        if !inside {
            return None;
        }
        Some((lo, hi))
    }

    /// How far the ray moves along frame axis `k` (0 east, 1 north, 2 up) over `[lo, hi]`: `|hi − lo| · |q_d|`
    /// (up to rounding; 0 for a zero component, infinite for an infinite interval).
    #[inline]
    pub fn travel(&self, k: usize, [lo, hi]: [T; 2]) -> T {
        let inv = match k {
            0 => self.inv.x,
            1 => self.inv.y,
            _ => self.inv.z,
        };
        (hi - lo).abs() / inv.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::Ellipsoid;

    #[test]
    fn builder_rounds_outwards_to_f32_with_a_margin() {
        let mut b = BoxBuilder::default();
        assert_eq!(b.finish(), None);
        let pts = [
            V3::new(0.1, -1_234.567_890_123, 1e-9),
            V3::new(-0.3, 98_765.432_1, -7.000_000_1),
            V3::new(f64::NAN, 0.0, 0.0), // ignored
        ];
        for p in pts {
            b.add(p, 1.3e7);
        }
        let bx = b.finish().unwrap();
        let margin = 64.0 * f64::EPSILON * 1.3e7;
        for p in &pts[..2] {
            for (k, v) in [p.x, p.y, p.z].into_iter().enumerate() {
                assert!(f64::from(bx.lo[k]) <= v - margin, "{k}");
                assert!(f64::from(bx.hi[k]) >= v + margin, "{k}");
            }
        }
        // Not loose by more than an f32 ulp or two beyond the margin.
        assert!(f64::from(bx.hi[1]) - (98_765.432_1 + margin) < 0.02);
    }

    #[test]
    fn anchor_follows_shared_frames_up_to_the_grid_and_stops_on_a_cycle() {
        // 0 is a zone; 1 its child; 2 and 3 children of 1; 4 a child of 3.
        let parent = |k: usize| {
            [None, Some(0), Some(1), Some(1), Some(3)]
                .get(k)
                .copied()
                .flatten()
        };
        let shared = |k: usize| k == 3 || k == 4;
        assert_eq!(anchor_of(0, 5, parent, shared), None);
        assert_eq!(anchor_of(1, 5, parent, shared), Some(0));
        assert_eq!(anchor_of(2, 5, parent, shared), Some(1));
        assert_eq!(anchor_of(3, 5, parent, shared), Some(0));
        assert_eq!(anchor_of(4, 5, parent, shared), Some(0));
        // Everything shared: the grid's frame.
        assert_eq!(anchor_of(4, 5, parent, |_| true), None);
        // A cycle of shared parent links ends after `nodes` steps.
        assert_eq!(anchor_of(0, 2, |k| Some(1 - k), |_| true), None);
    }

    /// A ray's travel along each axis of a frame over an interval: `|hi − lo|` times its direction's component
    /// in the frame, 0 along an axis it is perpendicular to.
    #[test]
    fn travel_is_the_interval_times_the_directions_component_along_each_axis() {
        let f = LocalFrame::<f64>::at(6_378_137.0, (0.6, 0.8), (0.0, 1.0));
        // a direction of frame components (3, −4, 0.5) from a point of the frame
        let (o, d) = (f.point(V3::new(10.0, 20.0, 30.0)), V3::new(3.0, -4.0, 0.5));
        let dir = f.point(d).minus(f.point(V3::new(0.0, 0.0, 0.0)));
        let ray = Ray::new(o, dir).unwrap();
        let fr = f.ray(&ray, [-10.0, 10.0]);
        for (k, want) in [(0, 3.0), (1, 4.0), (2, 0.5)] {
            let got = fr.travel(k, [2.0, -0.5]);
            assert!((got - 2.5 * want).abs() < 1e-6, "axis {k}: {got}");
        }
        // along the frame's north axis only: no travel east or up
        let north = f
            .point(V3::new(0.0, 1.0, 0.0))
            .minus(f.point(V3::new(0.0, 0.0, 0.0)));
        let fr = f.ray(&Ray::new(o, north).unwrap(), [0.0, 5.0]);
        // (the direction is a difference of points 6 400 km from the centre: a few 1e-10 off in each component)
        assert!(fr.travel(0, [0.0, 5.0]) < 1e-6 && fr.travel(2, [0.0, 5.0]) < 1e-6);
        assert!((fr.travel(1, [0.0, 5.0]) - 5.0).abs() < 1e-6);
    }

    #[test]
    fn frame_point_inverts_coords_and_up_is_the_normal() {
        let e = Ellipsoid::<f64>::wgs84();
        for (lat, lon) in [
            (0.0, 0.0),
            (36.5, -118.25),
            (-89.9, 179.95),
            (89.999, -45.0),
        ] {
            let (sp, cp) = crate::geodesy::sin_cos_deg(lat);
            let (sl, cl) = crate::geodesy::sin_cos_deg(lon);
            let f = LocalFrame {
                sin_lat: sp,
                cos_lat: cp,
                sin_lon: sl,
                cos_lon: cl,
                a: e.a(),
            };
            let p = e.geodetic_deg_to_ecef(lat + 0.01, lon - 0.02, 1234.0);
            let q = f.coords(p);
            assert!(f.point(q).minus(p).max_abs() < 1e-8, "{lat} {lon}");
            // Up along the normal: a point 100 m above another moves 100 m in `up` only.
            let n = e.normal_rad(lat.to_radians(), lon.to_radians());
            let d = f.coords(p.add_scaled(100.0, n)).minus(q);
            assert!((d.z - 100.0).abs() < 1e-8 && d.x.abs() < 1e-8 && d.y.abs() < 1e-8);
        }
    }
}
