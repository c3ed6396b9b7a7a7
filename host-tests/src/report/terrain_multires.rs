//! The report's multi-resolution section (Wartell et al. §5): what `min_level` trades. On a Trinidad tree whose every
//! node has its own block (the DEM subsampled at 2^k grid steps), with the blocks of a camera's cache resident
//! (the zones and level 1 everywhere, deeper levels only near the camera), the same rays are picked at every
//! `min_level`: time per ray, how many rays need blocks paged in, and how far the answers are from the
//! full-resolution surface.

use super::{Options, Section};
use crate::scenes::terrain_cases::{camera_rays, orbit_rays};
use curvicast::Ray;
use curvicast::terrain::{NodeId, Picker, TerrainError};
use curvicast_cli::formats::real_dem;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::storage::{DemStorage, MultiRes, pick_paging_in};
use std::time::Instant;

/// One `min_level` row.
struct Row {
    rays: &'static str,
    min_level: u8,
    us_per_ray: f64,
    needs: usize,
    paged_per_ray: f64,
    coarse: usize,
    status_differs: usize,
    median: f64,
    p95: f64,
    max: f64,
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Runs the section.
pub fn section(opts: &Options) -> anyhow::Result<Section> {
    let n_rays = if opts.quick { 300 } else { 5000 };
    let dem = real_dem::trinidad()?;
    let storage = DemStorage::multi_resolution(&dem, 16, MultiRes::default());
    let finest = DemStorage::new(&dem, 16);
    let fine_picker: Picker<'_, f64, DemStorage<'_>> =
        Picker::new(&finest).map_err(|e| anyhow::anyhow!("{e}"))?;
    // The cache: zones and level 1 everywhere; deeper blocks within a sixth of the DEM's extent of the centre.
    let (ci, cj) = ((dem.rows / 2) as f64, (dem.cols / 2) as f64);
    let reach = (dem.rows.min(dem.cols) as f64) / 6.0;
    let tree = storage.tree();
    let depth = tree.iter().map(|n| n.level).max().unwrap_or(0);
    let mut resident = 0;
    for n in &tree {
        let mi = f64::from(n.rows[0] + n.rows[1]) / 2.0;
        let mj = f64::from(n.cols[0] + n.cols[1]) / 2.0;
        let near = (mi - ci).abs() < reach && (mj - cj).abs() < reach;
        let r = n.level <= 1 || near;
        resident += usize::from(r);
        storage.set_resident(NodeId(n.id), r);
    }
    let mut rows = Vec::new();
    for (kind, rays) in [
        (
            "camera 2 km above ground",
            camera_rays(&dem, n_rays, 2000.0, 11),
        ),
        ("orbit (4e7 m)", orbit_rays(&dem, n_rays, 12)),
    ] {
        let kr: Vec<Ray<f64>> = rays
            .iter()
            .map(|r: &RaySpec| Ray::new(r.origin, r.dir))
            .collect::<Result<_, _>>()
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let truth: Vec<Option<[f64; 3]>> = kr
            .iter()
            .map(|r| fine_picker.pick(r).map(|h| h.map(|h| h.ecef)))
            .collect::<Result<_, _>>()
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        for m in 0..=depth {
            let picker: Picker<'_, f64, DemStorage<'_>> =
                Picker::new(&storage).map_err(|e| anyhow::anyhow!("{e}"))?;
            let picker = picker.with_min_level(m);
            // Time: the kernel's answer with the cache as it is (a NeedsBlock is an answer too).
            let t0 = Instant::now();
            let mut needs = 0;
            for r in &kr {
                match picker.pick(r) {
                    Err(TerrainError::NeedsBlock(_)) => needs += 1,
                    Err(e) => anyhow::bail!("min_level {m}: {e}"),
                    Ok(_) => {}
                }
            }
            let us = t0.elapsed().as_secs_f64() * 1e6 / kr.len() as f64;
            // Answers: after paging in what each ray needs.
            let (mut paged, mut coarse, mut differs) = (0usize, 0usize, 0usize);
            let mut d = Vec::new();
            for (r, t) in kr.iter().zip(&truth) {
                let (h, p) =
                    pick_paging_in(&picker, &storage, r).map_err(|e| anyhow::anyhow!("{e}"))?;
                paged += p;
                coarse += usize::from(h.is_some_and(|h| h.stride > 1));
                match (h, t) {
                    (Some(h), Some(t)) => d.push(dist(h.ecef, *t)),
                    (None, None) => {}
                    _ => differs += 1,
                }
            }
            d.sort_by(f64::total_cmp);
            let q = |f: f64| {
                d.get(((d.len() as f64 - 1.0) * f).round() as usize)
                    .copied()
                    .unwrap_or(0.0)
            };
            rows.push(Row {
                rays: kind,
                min_level: m,
                us_per_ray: us,
                needs,
                paged_per_ray: paged as f64 / kr.len() as f64,
                coarse,
                status_differs: differs,
                median: q(0.5),
                p95: q(0.95),
                max: d.last().copied().unwrap_or(0.0),
            });
        }
    }
    let mut md = format!(
        "Trinidad (1201 × 2401), a multi-resolution tree of 16 × 16-cell blocks: a node at height k above the \
         full-resolution leaves holds the DEM subsampled at 2^k grid steps; depth {depth} (zones are level 0). \
         Resident: the blocks of a camera's cache, {resident} of {} nodes (zones and level 1 everywhere, deeper \
         levels within a sixth of the DEM's extent of its centre). For each `min_level`, the same {n_rays} rays \
         per row. \"µs / ray\": the kernel's answer with the cache as it is (single thread, wall clock), where \
         \"needs a block\" counts the rays answered `NeedsBlock`; those rays then get their blocks paged in \
         (per ray) and are asked again, and the answers are compared with the full-resolution surface's: \
         distance between the hit points, and rays that hit on one surface and miss on the other. \
         `min_level` {depth} answers from full-resolution blocks only; 0 from whatever is resident.\n\n",
        tree.len()
    );
    md.push_str("| rays | min_level | µs / ray | needs a block | blocks paged / ray | hits on coarse cells | hit/miss differs | median distance | 95th percentile | max distance |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for r in &rows {
        md.push_str(&format!(
            "| {} | {} | {:.1} | {} | {:.2} | {} | {} | {:.2} m | {:.2} m | {:.2} m |\n",
            r.rays,
            r.min_level,
            r.us_per_ray,
            r.needs,
            r.paged_per_ray,
            r.coarse,
            r.status_differs,
            r.median,
            r.p95,
            r.max
        ));
    }
    let mut series = Vec::new();
    let mut kinds: Vec<&str> = rows.iter().map(|r| r.rays).collect();
    kinds.dedup();
    for kind in kinds {
        let of = |stat: fn(&Row) -> f64, what: &str| super::plot::Series {
            name: format!("{kind}: {what}"),
            points: rows
                .iter()
                .filter(|r| r.rays == kind)
                .map(|r| (r.us_per_ray, stat(r)))
                .collect(),
            labels: rows
                .iter()
                .filter(|r| r.rays == kind)
                .map(|r| format!("min_level {}", r.min_level))
                .collect(),
        };
        series.push(of(|r| r.median, "median"));
        series.push(of(|r| r.p95, "95th percentile"));
    }
    super::plot::loglog_svg(
        &opts.out_dir.join("terrain_min_level.svg"),
        super::plot::Labels {
            title: "min_level: distance to the full-resolution hit against time per ray",
            x: "µs per ray",
            y: "distance to the full-resolution hit (m)",
        },
        &series,
    )?;
    md.push_str(
        "\n![min_level trade-off: median and 95th-percentile distance against µs per ray](terrain_min_level.svg)\n\n\
         Points at zero distance (answers from full-resolution blocks) are not drawn on the log axis.\n",
    );
    Ok(Section {
        title: "Multi-resolution terrain: min_level against accuracy".into(),
        markdown: md,
    })
}
