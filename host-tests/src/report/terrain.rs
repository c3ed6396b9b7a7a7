//! The report's terrain section (seed 000 §3–§5): picking speed of the kernel's spheroidal height-augmented
//! quadtree against parry3d-f64's triangle-mesh BVH and against brute force, on the same ECEF triangles, in the
//! same run, with the memory of each structure.

use super::{Options, Section};
use crate::baselines::terrain::{BruteForceTerrain, ParryTerrain};
use crate::scenes::real_dem;
use crate::scenes::spec::RaySpec;
use crate::scenes::terrain::{Dem, DemStorage};
use crate::scenes::terrain_cases::{TerrainKind, camera_rays, orbit_rays, synthetic};
use curvicast::Ray;
use curvicast::terrain::{PickStats, Picker};
use std::time::Instant;

struct Row {
    scene: String,
    rays: String,
    n: usize,
    ours: f64,
    parry: f64,
    brute: f64,
    brute_n: usize,
    hits: usize,
    disagree: usize,
    max_dist: f64,
    tri_per_ray: f64,
    quads_per_ray: f64,
}

fn mb(b: usize) -> String {
    format!("{:.2} MB", b as f64 / 1e6)
}

/// Runs the section: Trinidad (1201 × 2401) and a fractal synthetic terrain of 4096 × 4096 vertices (1024 × 1024
/// with `--quick`), rays from a camera 2 km above ground and from orbit (4·10⁷ m).
pub fn section(opts: &Options) -> anyhow::Result<Section> {
    let n_syn = if opts.quick { 1024 } else { 4096 };
    let n_rays = if opts.quick { 1000 } else { 10_000 };
    let n_brute = if opts.quick { 2 } else { 5 };
    let scenes: Vec<(String, Dem)> = vec![
        (
            "Trinidad 1201 × 2401 (USGS 3″)".into(),
            real_dem::trinidad()?,
        ),
        (
            format!("synthetic fractal {n_syn} × {n_syn} (3″)"),
            synthetic(
                TerrainKind::Fractal,
                (36.0, -118.0, -1.0 / 1200.0, 1.0 / 1200.0),
                (n_syn, n_syn),
                42,
            ),
        ),
    ];
    let mut rows = Vec::new();
    let mut mem = String::from(
        "| scene | triangles | heights (f32) | ours: quadtree overhead | ours: build | parry TriMesh (BVH + vertices + indices) | parry: build | brute force: f64 vertices + indices |\n|---|---|---|---|---|---|---|---|\n",
    );
    for (name, dem) in &scenes {
        let t0 = Instant::now();
        let storage = DemStorage::new(dem, 16);
        let picker: Picker<'_, f64, DemStorage<'_>> =
            Picker::new(&storage).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        let ours_build = t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let parry = ParryTerrain::new(dem)?;
        let parry_build = t0.elapsed().as_secs_f64();
        let brute = BruteForceTerrain::new(dem);
        let triangles = parry.mesh.indices().len();
        mem.push_str(&format!(
            "| {name} | {triangles} | {} | {} ({:.2} % of the heights; {} nodes) | {:.3} s | {} ({:.1}× ours + heights) | {:.2} s | {} |\n",
            mb(storage.heights_bytes()),
            mb(storage.overhead_bytes()),
            100.0 * storage.overhead_bytes() as f64 / storage.heights_bytes() as f64,
            storage.node_count(),
            ours_build,
            mb(parry.memory_bytes()),
            parry.memory_bytes() as f64 / (storage.overhead_bytes() + storage.heights_bytes()) as f64,
            parry_build,
            mb(brute.memory_bytes()),
        ));
        for (kind, rays) in [
            (
                "camera 2 km above ground",
                camera_rays(dem, n_rays, 2000.0, 1),
            ),
            ("orbit (4e7 m)", orbit_rays(dem, n_rays, 2)),
        ] {
            rows.push(measure(
                name, kind, &rays, &picker, &parry, &brute, n_brute,
            )?);
        }
        drop(brute);
        drop(parry);
    }
    let mut md = String::new();
    md.push_str(&format!(
        "Nearest-hit picking of f64 rays against the contract's triangle surface (single thread, release build). \
         Ours: `curvicast::terrain::Picker` over the host's `DemStorage` (blocks of 16 × 16 cells). parry: \
         parry3d-f64 `TriMesh::cast_local_ray` (its BVH over the same ECEF triangles, built from the same f64 \
         vertices). Brute force: Möller–Trumbore over every triangle with precomputed vertices, timed on {n_brute} \
         rays per row (sampled). Synthetic terrain: {n_syn} × {n_syn}{}. Rays per second are wall-clock \
         figures; the three methods of a row run back to back on the same rays, so their ratio is the figure to \
         read on a loaded machine. \"status differs\" counts rays that one of ours/parry hits and the other \
         misses.\n\n",
        if opts.quick {
            " (quick mode; the full report uses 4096 × 4096)"
        } else {
            ""
        }
    ));
    md.push_str("| scene | rays | n | ours (rays/s) | parry (rays/s) | ours / parry | brute (rays/s) | ours / brute | hits | ours vs parry: status differs | max hit distance ours–parry | triangles tested / ray | quads / ray |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in &rows {
        md.push_str(&format!(
            "| {} | {} | {} | {:.0} | {:.0} | {:.2}× | {:.2} | {:.0}× | {} | {} | {:.2e} m | {:.1} | {:.1} |\n",
            r.scene,
            r.rays,
            r.n,
            r.ours,
            r.parry,
            r.ours / r.parry,
            r.brute,
            r.ours / r.brute,
            r.hits,
            r.disagree,
            r.max_dist,
            r.tri_per_ray,
            r.quads_per_ray,
        ));
        let _ = r.brute_n;
    }
    md.push_str("\nMemory. Ours: one 44-byte record per quadtree node (cell ranges, height range, child ids, level) \
                 plus the zone list and the sine/cosine of every grid row and column (two f64 each) — the heights \
                 themselves are the DEM's and are needed by every method. parry: \
                 its own `TriMesh::total_memory_size()` estimate (vertex array of f64 triples, index triples, BVH \
                 nodes and auxiliary buffers); it holds ECEF vertices instead of heights.\n\n");
    md.push_str(&mem);
    Ok(Section {
        title: "Terrain picking: height-augmented quadtree vs parry3d BVH vs brute force".into(),
        markdown: md,
    })
}

fn measure(
    scene: &str,
    kind: &str,
    rays: &[RaySpec],
    picker: &Picker<'_, f64, DemStorage<'_>>,
    parry: &ParryTerrain,
    brute: &BruteForceTerrain,
    n_brute: usize,
) -> anyhow::Result<Row> {
    let kr: Vec<Ray<f64>> = rays
        .iter()
        .map(|r| Ray::new(r.origin, r.dir))
        .collect::<Result<_, _>>()
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let (mut tris, mut quads) = (0u64, 0u64);
    let t0 = Instant::now();
    let ours: Vec<Option<f64>> = kr
        .iter()
        .map(|r| {
            let mut stats = PickStats::default();
            let h = picker.pick_with_stats(r, &mut stats);
            tris += u64::from(stats.triangles_tested);
            quads += u64::from(stats.quads_visited);
            h.map(|h| h.map(|h| h.t))
        })
        .collect::<Result<_, _>>()
        .map_err(|e| anyhow::anyhow!("{scene}: {e}"))?;
    let ours_t = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let theirs: Vec<Option<f64>> = rays.iter().map(|r| parry.pick(r)).collect();
    let parry_t = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let mut brute_hits = 0;
    for r in rays.iter().take(n_brute) {
        brute_hits += usize::from(brute.pick(r).is_some());
    }
    let brute_t = t0.elapsed().as_secs_f64();
    let _ = brute_hits;
    let mut disagree = 0;
    let mut max_dist: f64 = 0.0;
    let mut hits = 0;
    for ((a, b), r) in ours.iter().zip(&theirs).zip(rays) {
        match (a, b) {
            (Some(x), Some(y)) => {
                hits += 1;
                let dl = (r.dir[0].powi(2) + r.dir[1].powi(2) + r.dir[2].powi(2)).sqrt();
                max_dist = max_dist.max((x - y).abs() * dl);
            }
            (None, None) => {}
            _ => disagree += 1,
        }
    }
    let n = rays.len();
    Ok(Row {
        scene: scene.into(),
        rays: kind.into(),
        n,
        ours: n as f64 / ours_t,
        parry: n as f64 / parry_t,
        brute: n_brute.min(n) as f64 / brute_t,
        brute_n: n_brute,
        hits,
        disagree,
        max_dist,
        tri_per_ray: tris as f64 / n as f64,
        quads_per_ray: quads as f64 / n as f64,
    })
}
