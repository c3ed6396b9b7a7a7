//! Fuzz target for terrain picking (Wartell et al. §3–§4): small random DEMs (2–9 × 2–9 vertices, anywhere on the
//! globe, any spacing, nodata vertices, poles) and random rays. The kernel must not panic or hang, must return
//! either a typed error or an answer, and must agree with an `f64` brute force over every triangle. Both checks
//! are geometric (distances in metres, with coordinates taken relative to a triangle vertex), so that sliver
//! triangles at a pole or an origin 10⁹ m away cannot make the brute force's barycentric rounding look like a
//! kernel error:
//!
//! * no false hit: a kernel hit point must lie within 1 mm (plus rounding of the point itself) of some triangle;
//! * no miss: if the brute force finds a hit at a non-grazing angle whose point lies at least 1 mm inside a
//!   triangle (from every edge), the kernel must return a hit no farther than it (within 1 mm).
//!
//! The tree is the kernel's builder's (`terrain::build`): with `split`, one-cell leaves under zones (two levels
//! once a side has more than four cells), else one leaf over the whole grid. Bit 3 of `rows` (unused by the grid
//! size) makes the storage provide node boxes (`TerrainCaches::node_box`, built into the node records by
//! `build_boxes_sharing` from every vertex of each node; otherwise the records' box slots stay empty), so that half of the inputs run the traversal's box tests and half its spheroidal
//! volumes (the shipped seeds keep the volumes); bits 4–7 choose which boxes are in their parent's box frame
//! rather than their parent's own. With boxes, a leaf of 8 × 8 cells also has its windows' boxes
//! (`build_windows`: a leaf of at least 5 cells a side is walked by windows).
#![no_main]

use arbitrary::Arbitrary;
use curvicast::Ray;
use curvicast::geodesy::Ellipsoid;
use curvicast::terrain::boxes::NodeBox;
use curvicast::terrain::build::{
    NodeRecord, Parts, TreeStorage, build_boxes_sharing, build_tree, build_windows, node_slots,
    window_slots,
};
use curvicast::terrain::windows::WindowBox;
use curvicast::terrain::{Grid, Node, NodeId, Picker};
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
struct Input {
    lat0: i16,
    lon0: i16,
    dlat: i16,
    dlon: u16,
    rows: u8,
    cols: u8,
    heights: [i16; 81],
    nodata: u128,
    origin_lat: i16,
    origin_lon: i16,
    origin_h: i32,
    target: [u8; 2],
    target_h: i16,
    jitter: [i16; 3],
    t_max: Option<u16>,
    split: bool,
}

type P3 = [f64; 3];
fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: P3) -> f64 {
    dot(a, a).sqrt()
}

/// The ray's crossing of the triangle's plane: (t, sin of the angle between ray and plane), or `None` when
/// the ray is parallel to it. The origin is taken relative to `v[0]` first.
fn plane_crossing(o: P3, d: P3, v: [P3; 3]) -> Option<(f64, f64)> {
    let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    let nd = dot(n, d);
    if nd == 0.0 || !nd.is_finite() {
        return None;
    }
    let t = -dot(n, sub(o, v[0])) / nd;
    Some((t, nd.abs() / (norm(n) * norm(d))))
}

/// Signed in-plane distances of `p` from the triangle's three edge lines (positive inside).
fn edge_distances(p: P3, v: [P3; 3]) -> [f64; 3] {
    let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    let nn = norm(n);
    let mut out = [0.0; 3];
    for (k, slot) in out.iter_mut().enumerate() {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        let e = sub(b, a);
        *slot = dot(cross(e, sub(p, a)), n) / (nn * norm(e));
    }
    out
}

/// Distance from `p` to the (closed) triangle.
fn distance_to_triangle(p: P3, v: [P3; 3]) -> f64 {
    let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    let nn = norm(n);
    let mut best = f64::INFINITY;
    // The segments.
    for k in 0..3 {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        let e = sub(b, a);
        let ee = dot(e, e);
        let s = if ee > 0.0 {
            (dot(sub(p, a), e) / ee).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + s * e[0], a[1] + s * e[1], a[2] + s * e[2]];
        best = best.min(norm(sub(p, q)));
    }
    // The interior, when the projection falls inside.
    if nn > 0.0 && edge_distances(p, v).iter().all(|&x| x >= 0.0) {
        best = best.min((dot(sub(p, v[0]), n) / nn).abs());
    }
    best
}

fuzz_target!(|inp: Input| {
    let rows = 2 + u32::from(inp.rows % 8);
    let cols = 2 + u32::from(inp.cols % 8);
    let dlat = f64::from(inp.dlat) / 2000.0; // up to ±16°
    let dlon = 1e-4 + f64::from(inp.dlon) / 2000.0; // up to 33°
    let lat0 = (f64::from(inp.lat0) / 360.0).clamp(-90.0, 90.0);
    let last = lat0 + f64::from(rows - 1) * dlat;
    if dlat == 0.0 || !(-90.0..=90.0).contains(&last) {
        return;
    }
    let lon0 = f64::from(inp.lon0) / 90.0;
    let grid = Grid {
        lat0_deg: lat0,
        lon0_deg: lon0,
        dlat_deg: dlat,
        dlon_deg: dlon,
        rows,
        cols,
    };
    let n = (rows * cols) as usize;
    let h: Vec<f64> = (0..n)
        .map(|k| {
            if (inp.nodata >> k) & 1 == 0 || k >= 128 {
                f64::from(inp.heights[k % 81]) / 4.0
            } else {
                f64::NAN
            }
        })
        .collect();
    let (cr, cc) = (rows - 1, cols - 1);
    // The kernel's builder: one-cell leaves under zones of up to 2 × 2 of them (two levels once a side has more
    // than four cells), or with `split` unset one block over the whole grid (a single zone that is a leaf).
    let block = if inp.split { 1 } else { 8 };
    let mut nodes = vec![NodeRecord::<f64, Option<NodeBox>>::EMPTY; node_slots(rows, cols, block)];
    let Ok(tree) = build_tree(&h, &grid, block, &mut nodes) else {
        return;
    };
    let e = Ellipsoid::<f64>::wgs84();
    let mut windows = Vec::new();
    if inp.rows & 0x08 != 0 {
        let share = inp.rows >> 4;
        let shared = |id: NodeId, _: Option<&Node<f64>>| (share >> (id.0 % 4)) & 1 == 1;
        if build_boxes_sharing(&e, &grid, &h, tree, None, &mut nodes, shared).is_err() {
            return;
        }
        windows = vec![WindowBox::EMPTY; window_slots(rows, cols, block)];
        if build_windows(&e, &grid, &h, tree, None, &nodes, &mut windows).is_err() {
            return;
        }
    }
    let parts = Parts::new(&h[..], &nodes[..]).with_windows(&windows);
    let Ok(t) = TreeStorage::with_buffers(e, grid, tree, parts) else {
        return;
    };
    let Ok(picker) = Picker::<'_, f64, _>::new(&t) else {
        return;
    };
    let olat = (f64::from(inp.origin_lat) / 360.0).clamp(-90.0, 90.0);
    let o = e.geodetic_deg_to_ecef(
        olat,
        f64::from(inp.origin_lon) / 90.0,
        f64::from(inp.origin_h) * 4.0,
    );
    let ti = f64::from(inp.target[0] % 64) / 64.0 * f64::from(cr);
    let tj = f64::from(inp.target[1] % 64) / 64.0 * f64::from(cc);
    let tp = e.geodetic_deg_to_ecef(lat0 + ti * dlat, lon0 + tj * dlon, f64::from(inp.target_h));
    let o = [o.x, o.y, o.z];
    let mut d = [tp.x - o[0], tp.y - o[1], tp.z - o[2]];
    for (c, j) in d.iter_mut().zip(inp.jitter) {
        *c += f64::from(j);
    }
    let t_max = inp.t_max.map_or(f64::INFINITY, |m| f64::from(m) / 1000.0);
    let Ok(ray) = Ray::new(o, d).and_then(|r| r.with_interval(0.0, t_max)) else {
        return;
    };
    let Ok(hit) = picker.pick(&ray) else {
        return;
    };
    // Brute force over every triangle. Lengths are in metres; `slack` covers the rounding of a point of the
    // ray, which grows with the distance of the origin.
    let dl = norm(d);
    let slack = 1e-3 + 1e-12 * norm(o);
    let at = |tt: f64| [o[0] + tt * d[0], o[1] + tt * d[1], o[2] + tt * d[2]];
    let vert = |i: u32, j: u32| {
        let hh = Some(h[(i * cols + j) as usize]).filter(|v| !v.is_nan())?;
        let p = e.geodetic_deg_to_ecef(grid.lat_deg(i), grid.lon_deg(j), hh);
        Some([p.x, p.y, p.z])
    };
    let mut nearest_to_hit = f64::INFINITY;
    let mut strict: Option<f64> = None;
    for i in 0..cr {
        for j in 0..cc {
            for tri in [
                [(i, j), (i, j + 1), (i + 1, j + 1)],
                [(i, j), (i + 1, j + 1), (i + 1, j)],
            ] {
                let (Some(a), Some(b), Some(c)) = (
                    vert(tri[0].0, tri[0].1),
                    vert(tri[1].0, tri[1].1),
                    vert(tri[2].0, tri[2].1),
                ) else {
                    continue;
                };
                let v = [a, b, c];
                if let Some(h) = &hit {
                    nearest_to_hit = nearest_to_hit.min(distance_to_triangle(at(h.t), v));
                }
                let Some((tt, sin)) = plane_crossing(o, d, v) else {
                    continue;
                };
                let tol_t = (slack + 1e-12 * tt.abs() * dl) / dl;
                if sin > 1e-3
                    && tt > tol_t
                    && tt < t_max - tol_t
                    && edge_distances(at(tt), v).iter().all(|&x| x >= 1e-3 + slack)
                {
                    strict = Some(strict.map_or(tt, |s: f64| s.min(tt)));
                }
            }
        }
    }
    if let Some(h) = &hit {
        let tol = slack + 1e-12 * h.t.abs() * dl;
        assert!(
            nearest_to_hit <= tol,
            "false hit at t = {}: the nearest triangle is {nearest_to_hit} m away",
            h.t
        );
    }
    if let Some(tb) = strict {
        let tk = hit.map(|h| h.t);
        let tol_t = (slack + 1e-12 * tb.abs() * dl) / dl;
        assert!(
            tk.is_some_and(|tk| tk <= tb + tol_t),
            "miss: brute force hits at t = {tb}, kernel {tk:?}"
        );
    }
});
