//! Report section: the edge-beveled sphere and ellipsoid per level (the edge-beveling thesis §4.3–4.4, chapter 5), next to a
//! UV-sphere of about the same face count.
//!
//! Columns per level: faces, the largest deviation from the true surface and the smallest dihedral angle, both
//! measured on the built polyhedron (see `cli::tessellate`), the a-priori worst case of `lod::worst_case` for the
//! sphere, and the kernel's build time. The UV-sphere (`n` stacks × `2n` slices, vertices on the surface, as most
//! tools make it) has its `n` chosen for the nearest face count; its deviation is the largest depth of the surface
//! beyond a face plane (`h(n̂) − n̂·v`, `h` the support function). `deviation × faces` compares deviation per face:
//! for a uniform tessellation it is about constant, and smaller is better.

use super::{Options, Section};
use curvicast::V3;
use curvicast::tessellate::bevel::{self, Face};
use curvicast::tessellate::lod::{self, Shape};
use curvicast_cli::cli::tessellate::{build, max_deviation, min_dihedral};
use std::fmt::Write as _;
use std::time::Instant;

const WGS84: [f64; 3] = [6378137.0, 6378137.0, 6356752.314245179];

/// Mean wall time of one kernel build at `level`, repeated until about 20 ms have passed.
fn build_time(axes: [f64; 3], level: u32) -> anyhow::Result<f64> {
    let mut v = vec![V3::<f64>::ZERO; bevel::vertex_count(level)];
    let mut f = vec![Face::<f64>::EMPTY; bevel::face_count(level)];
    let start = Instant::now();
    let mut reps = 0u32;
    while reps == 0 || (start.elapsed().as_secs_f64() < 0.02 && reps < 1000) {
        bevel::bevel_ellipsoid(level, axes, &mut v, &mut f)?;
        std::hint::black_box(&v);
        reps += 1;
    }
    Ok(start.elapsed().as_secs_f64() / f64::from(reps))
}

/// A UV-sphere/ellipsoid with `n` stacks and `2n` slices, vertices on the surface; returns (faces, deviation).
fn uv_sphere(axes: [f64; 3], n: usize) -> (usize, f64) {
    let slices = 2 * n;
    let point = |i: usize, j: usize| {
        let u = std::f64::consts::PI * (i as f64 / n as f64) - std::f64::consts::FRAC_PI_2;
        let l = 2.0 * std::f64::consts::PI * (j as f64 / slices as f64);
        [
            axes[0] * u.cos() * l.cos(),
            axes[1] * u.cos() * l.sin(),
            axes[2] * u.sin(),
        ]
    };
    let support = |n: [f64; 3]| {
        ((axes[0] * n[0]).powi(2) + (axes[1] * n[1]).powi(2) + (axes[2] * n[2]).powi(2)).sqrt()
    };
    let mut worst = 0.0_f64;
    let mut faces = 0;
    for i in 0..n {
        for j in 0..slices {
            let (a, b, c, d) = (
                point(i, j),
                point(i, j + 1),
                point(i + 1, j + 1),
                point(i + 1, j),
            );
            // A pole row is a triangle; its plane comes from the three distinct corners.
            let tri = if i == 0 { [a, c, d] } else { [a, b, c] };
            let e1 = [
                tri[1][0] - tri[0][0],
                tri[1][1] - tri[0][1],
                tri[1][2] - tri[0][2],
            ];
            let e2 = [
                tri[2][0] - tri[0][0],
                tri[2][1] - tri[0][1],
                tri[2][2] - tri[0][2],
            ];
            let mut nrm = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            let l = (nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]).sqrt();
            nrm = [nrm[0] / l, nrm[1] / l, nrm[2] / l];
            let off = nrm[0] * tri[0][0] + nrm[1] * tri[0][1] + nrm[2] * tri[0][2];
            let (nrm, off) = if off < 0.0 {
                ([-nrm[0], -nrm[1], -nrm[2]], -off)
            } else {
                (nrm, off)
            };
            worst = worst.max(support(nrm) - off);
            faces += 1;
        }
    }
    (faces, worst)
}

/// The section.
pub fn section(opts: &Options) -> anyhow::Result<Section> {
    let top = if opts.quick { 5 } else { 8 };
    let mut md = String::new();
    md.push_str(
        "Edge-beveled polyhedra (the edge-beveling thesis §4.3.4, §4.4): every face tangent to the surface at its center point. \
         Deviation and dihedral angle are measured on the built mesh; \"a priori\" is `lod::worst_case` \
         (chapter 5), which `lod::min_level` follows without building anything. The UV-sphere has vertices on \
         the surface and the nearest face count.\n\n",
    );
    for (name, axes) in [("unit sphere", [1.0; 3]), ("WGS84 ellipsoid (m)", WGS84)] {
        let shape = if axes[0] == axes[2] {
            Shape::Sphere(axes[0])
        } else {
            Shape::Ellipsoid(axes)
        };
        writeln!(md, "### {name}\n")?;
        md.push_str(
            "| level | faces | max deviation | a priori bound | min dihedral ° | build ms | UV faces | UV deviation | deviation × faces (bevel / UV) |\n\
             | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
        );
        let (mut bevel_pts, mut uv_pts) = (Vec::new(), Vec::new());
        for level in 0..=top {
            let mesh = build(shape, level)?;
            let dev = max_deviation(&mesh, shape);
            let dih = min_dihedral(&mesh).to_degrees();
            let a_priori = match shape {
                Shape::Sphere(r) => lod::worst_case::<f64>(level)?.max_deviation * r,
                Shape::Ellipsoid(a) => lod::ellipsoid_worst_case(a, level)?.max_deviation,
            };
            let t = build_time(axes, level)?;
            let faces = mesh.faces.len();
            let n = ((faces as f64 / 2.0).sqrt().round() as usize).max(2);
            let (uv_faces, uv_dev) = uv_sphere(axes, n);
            bevel_pts.push((faces as f64, dev));
            uv_pts.push((uv_faces as f64, uv_dev));
            writeln!(
                md,
                "| {level} | {faces} | {dev:.4e} | {a_priori:.4e} | {dih:.4} | {:.3} | {uv_faces} | {uv_dev:.4e} | {:.3e} / {:.3e} |",
                t * 1e3,
                dev * faces as f64,
                uv_dev * uv_faces as f64
            )?;
        }
        let svg = format!(
            "tessellation_{}.svg",
            if axes[0] == axes[2] {
                "sphere"
            } else {
                "wgs84"
            }
        );
        let series = |name: &str, points: Vec<(f64, f64)>| super::plot::Series {
            name: name.into(),
            labels: vec![String::new(); points.len()],
            points,
        };
        super::plot::loglog_svg(
            &opts.out_dir.join(&svg),
            super::plot::Labels {
                title: &format!("{name}: largest deviation against faces"),
                x: "faces",
                y: "largest deviation from the surface",
            },
            &[
                series("edge-beveled", bevel_pts),
                series("UV sphere", uv_pts),
            ],
        )?;
        writeln!(md, "\n![deviation against faces, {name}]({svg})")?;
        md.push('\n');
    }
    md.push_str(
        "For the ellipsoid the \"a priori\" column is `lod::ellipsoid_worst_case`: the exact largest deviation \
         from a walk over one octant's vertices, without building the level; `lod::min_level` decides each level \
         from witnesses, axis-ratio guarantees and, only when they leave it open, a pruned walk (see `lod`). \
         Build times are single-threaded wall times of `bevel_ellipsoid` in this binary's \
         profile.\n",
    );
    Ok(Section {
        title: "Tessellation: edge-beveled sphere and ellipsoid".into(),
        markdown: md,
    })
}
