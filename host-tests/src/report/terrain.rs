//! The report's terrain section (Wartell et al. §3–§5): picking speed of the kernel's spheroidal height-augmented
//! quadtree against parry3d-f64's triangle-mesh BVH and against brute force, on the same ECEF triangles, in the
//! same run, with the memory of each structure.

use super::{Options, Section};
use crate::baselines::terrain::{BruteForceTerrain, ParryTerrain};
use crate::baselines::{TerrainBaseline, embree_baselines};
use crate::oracle::terrain::TerrainOracle;
use crate::scenes::terrain_cases::{TerrainKind, camera_rays, orbit_rays, synthetic};
use curvicast::Ray;
use curvicast::terrain::{PickStats, Picker};
use curvicast_cli::formats::real_dem;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::Dem;
use curvicast_cli::storage::DemStorage;
use std::time::Instant;

struct Row {
    scene: String,
    rays: String,
    block: usize,
    n: usize,
    ours: f64,
    /// `pick_t` (t and cell only), rays/s.
    ours_t: f64,
    parry: f64,
    brute: f64,
    hits: usize,
    disagree: usize,
    max_dist: f64,
    tri_per_ray: f64,
    quads_per_ray: f64,
    /// Rays where `pick_t`'s hit status or cell differs from `pick`'s.
    t_differs: usize,
    /// Largest `|t(pick_t) − t(pick)|·|d|`: what the refinement moves the hit.
    t_refined_by: f64,
    /// The other baselines' (Embree's) rays/s, in the order given.
    extra: Vec<f64>,
}

/// How far a method's hits are from the oracle's, on the first rays of a row.
struct OracleError {
    /// Largest `|t − t_oracle|·|d|` over the rays both hit, metres.
    max: f64,
    /// Its 99th percentile.
    p99: f64,
    /// Rays that one of the method and the oracle hits and the other misses.
    status_differs: usize,
}

impl OracleError {
    fn of(answers: &[Option<f64>], oracle: &[Option<f64>], rays: &[RaySpec]) -> OracleError {
        let mut d: Vec<f64> = Vec::new();
        let mut status_differs = 0;
        for ((a, o), r) in answers.iter().zip(oracle).zip(rays) {
            match (a, o) {
                (Some(t), Some(to)) => {
                    let dl = (r.dir[0].powi(2) + r.dir[1].powi(2) + r.dir[2].powi(2)).sqrt();
                    d.push((t - to).abs() * dl);
                }
                (None, None) => {}
                _ => status_differs += 1,
            }
        }
        d.sort_by(f64::total_cmp);
        let p99 = d
            .get(((d.len() as f64 * 0.99).ceil() as usize).saturating_sub(1))
            .copied()
            .unwrap_or(0.0);
        OracleError {
            max: d.last().copied().unwrap_or(0.0),
            p99,
            status_differs,
        }
    }
}

/// One row of the Embree table: a scene's rays, each method's speed and its error against the oracle.
struct ExtraRow {
    scene: String,
    rays: String,
    /// The method's name, rays/s and error; ours (`pick` and `pick_t` with 8 × 8 blocks) first.
    methods: Vec<(String, f64, OracleError)>,
}

/// A kernel answer: the hit's `t` and cell, or a miss.
type TCell = Option<(f64, [u32; 2])>;

/// Leaf block sizes of our tree in the comparison: 8 × 8 cells (the faster on these scenes) and the command
/// line's default 16 × 16 (the smaller tree).
const BLOCKS: [usize; 2] = [8, 16];

/// Timed passes per method and row.
const PASSES: usize = 5;

fn mb(b: usize) -> String {
    format!("{:.2} MB", b as f64 / 1e6)
}

/// Runs the section: Trinidad (1201 × 2401) and a fractal synthetic terrain of 4096 × 4096 vertices (1024 × 1024
/// with `--quick`), rays from a camera 2 km above ground and from orbit (4·10⁷ m).
pub fn section(opts: &Options) -> anyhow::Result<Section> {
    let n_syn = if opts.quick { 1024 } else { 4096 };
    let n_rays = if opts.quick { 1000 } else { 10_000 };
    let n_brute = if opts.quick { 2 } else { 5 };
    let n_oracle = if opts.quick { 200 } else { 1000 };
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
    let mut extra_rows = Vec::new();
    let mut extra_mem = String::new();
    let mut mem = String::from(
        "| scene | ours: block | triangles | heights (f32) | ours: quadtree overhead | ours: build | parry TriMesh (BVH + vertices + indices) | parry: build | brute force: f64 vertices + indices |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for (name, dem) in &scenes {
        let t0 = Instant::now();
        let parry = ParryTerrain::new(dem)?;
        let parry_build = t0.elapsed().as_secs_f64();
        let brute = BruteForceTerrain::new(dem);
        let extra = embree_baselines(dem)?;
        let triangles = parry.mesh.indices().len();
        let mut storages = Vec::new();
        for block in BLOCKS {
            let t0 = Instant::now();
            let storage = DemStorage::new(dem, block);
            let build = t0.elapsed().as_secs_f64();
            mem.push_str(&format!(
                "| {name} | {block} × {block} | {triangles} | {} | {} ({:.2} % of the heights; {} node records) | {:.3} s | {} ({:.1}× ours + heights) | {:.2} s | {} |\n",
                mb(storage.heights_bytes()),
                mb(storage.overhead_bytes()),
                100.0 * storage.overhead_bytes() as f64 / storage.heights_bytes() as f64,
                storage.node_count(),
                build,
                mb(parry.memory_bytes()),
                parry.memory_bytes() as f64 / (storage.overhead_bytes() + storage.heights_bytes()) as f64,
                parry_build,
                mb(brute.memory_bytes()),
            ));
            storages.push((block, storage));
        }
        for b in &extra {
            let (_, ours) = &storages[0];
            extra_mem.push_str(&format!(
                "| {name} | {} | {} | {:.2} s | {:.1}× ours (8 × 8 blocks) + heights |\n",
                b.name,
                mb(b.memory_bytes),
                b.build_seconds,
                b.memory_bytes as f64 / (ours.overhead_bytes() + ours.heights_bytes()) as f64,
            ));
        }
        let oracle = (!extra.is_empty()).then(|| TerrainOracle::new(dem));
        let pickers = storages
            .iter()
            .map(|(block, s)| {
                Picker::new(s)
                    .map(|p| (*block, p))
                    .map_err(|e| anyhow::anyhow!("{name}: {e}"))
            })
            .collect::<anyhow::Result<Vec<(usize, Picker<'_, f64, DemStorage<'_>>)>>>()?;
        for (kind, rays) in [
            (
                "camera 2 km above ground",
                camera_rays(dem, n_rays, 2000.0, 1),
            ),
            ("orbit (4e7 m)", orbit_rays(dem, n_rays, 2)),
        ] {
            let (scene_rows, answers) =
                measure(name, kind, &rays, &pickers, &parry, &brute, n_brute, &extra)?;
            if let Some(oracle) = &oracle {
                let sample = &rays[..n_oracle.min(rays.len())];
                let truth: Vec<Option<f64>> =
                    sample.iter().map(|r| oracle.pick(r).map(|h| h.t)).collect();
                let mut methods = Vec::new();
                for (k, (label, rate)) in [
                    ("ours: pick, 8 × 8 blocks", scene_rows[0].ours),
                    ("ours: pick_t, 8 × 8 blocks", scene_rows[0].ours_t),
                ]
                .into_iter()
                .enumerate()
                {
                    let a: Vec<Option<f64>> =
                        answers.ours[k].iter().take(sample.len()).copied().collect();
                    methods.push((label.to_string(), rate, OracleError::of(&a, &truth, sample)));
                }
                for (b, (rate, a)) in extra
                    .iter()
                    .zip(scene_rows[0].extra.iter().zip(&answers.extra))
                {
                    let a = &a[..sample.len()];
                    methods.push((b.name.clone(), *rate, OracleError::of(a, &truth, sample)));
                }
                extra_rows.push(ExtraRow {
                    scene: name.clone(),
                    rays: kind.into(),
                    methods,
                });
            }
            rows.extend(scene_rows);
        }
        drop(oracle);
        drop(extra);
        drop(pickers);
        drop(storages);
        drop(brute);
        drop(parry);
    }
    let mut md = String::new();
    md.push_str(&format!(
        "Nearest-hit picking of f64 rays against the contract's triangle surface (single thread, release build). \
         Ours: `curvicast::terrain::Picker` over the host's `DemStorage` with node boxes, leaf blocks of 8 × 8 \
         and of 16 × 16 cells (the command line's default); \
         `pick` returns the refined hit with its geodetic coordinates, `pick_t` the same traversal's `t` and cell \
         only (what parry's cast returns; the last distance column is how far the refinement moves the hit). \
         parry: parry3d-f64 `TriMesh::cast_local_ray` (its BVH over the same ECEF triangles, built from the same f64 \
         vertices). Brute force: Möller–Trumbore over every triangle with precomputed vertices, timed on the first \
         {n_brute} rays of each row (sampled). Synthetic terrain: {n_syn} × {n_syn}{}. Rays per second are wall-clock \
         figures under one policy for every method: each builds its own rays from the same f64 records inside \
         the timed region, each timed run follows an untimed run of the same method (so that each starts with its \
         own data in the caches, not the previous method's), and all run interleaved, {PASSES} passes each, best \
         pass kept, so the ratios are the figures to read on a loaded machine. \"status differs\" counts rays that one of ours/parry \
         hits and the other misses.\n\n",
        if opts.quick {
            " (quick mode; the full report uses 4096 × 4096)"
        } else {
            ""
        }
    ));
    md.push_str("| scene | rays | ours: block | n | ours: pick (rays/s) | ours: pick_t (rays/s) | parry (rays/s) | pick / parry | pick_t / parry | brute (rays/s) | ours / brute | hits | ours vs parry: status differs | max hit distance ours–parry | pick_t vs pick: status or cell differs | max pick_t–pick distance | triangles tested / ray | quads / ray |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in &rows {
        md.push_str(&format!(
            "| {} | {} | {} × {} | {} | {:.0} | {:.0} | {:.0} | {:.2}× | {:.2}× | {:.2} | {:.0}× | {} | {} | {:.2e} m | {} | {:.2e} m | {:.1} | {:.1} |\n",
            r.scene,
            r.rays,
            r.block,
            r.block,
            r.n,
            r.ours,
            r.ours_t,
            r.parry,
            r.ours / r.parry,
            r.ours_t / r.parry,
            r.brute,
            r.ours / r.brute,
            r.hits,
            r.disagree,
            r.max_dist,
            r.t_differs,
            r.t_refined_by,
            r.tri_per_ray,
            r.quads_per_ray,
        ));
    }
    md.push_str("\nMemory. Ours: one 72-byte record per quadtree node (cell ranges, height range, child ids, level, \
                 the node's box in a local frame as six f32 and a flag; siblings' records adjacent), the boxes of \
                 the leaves' windows (6 bytes for about 4 × 4 cells, none with 4 × 4 blocks) plus the zone list, the sine/cosine of every grid \
                 row and column (two f64 each) and their double-double forms for the refinement (64 bytes per \
                 row, 32 per column) — the heights themselves are the DEM's and are needed by every method. parry: \
                 its own `TriMesh::total_memory_size()` estimate (vertex array of f64 triples, index triples, BVH \
                 nodes and auxiliary buffers); it holds ECEF vertices instead of heights.\n\n");
    md.push_str(&mem);
    if extra_rows.is_empty() {
        md.push_str(
            "\nEmbree: not in this build. `--features embree` (with Embree 3 installed, Debian's `libembree-dev`) \
             adds its rows: speed, memory, build time and the error of its hits against the oracle, in ECEF and in \
             a local frame.\n",
        );
    } else {
        md.push_str(&format!(
            "\nAgainst Embree 3 (`embree3` crate, default build quality, `rtcIntersect1` one ray at a time, single \
             thread), over the same triangles: its vertices and rays are `f32`, once in ECEF metres and once in a \
             frame centred on the DEM (vertices and ray origins shifted by its centre vertex in `f64`, then \
             rounded). Rays/s as above (same passes, interleaved). The error columns: the distance \
             `|t − t_oracle|·|d|` to the oracle's hit (256-bit, `oracle::terrain`) over the first {n_oracle} rays of \
             each row where both hit, largest and 99th percentile, and the rays where one hits and the other \
             misses. Ours: `pick` and `pick_t` with 8 × 8 blocks.\n\n\
             | scene | rays | method | rays/s | ours pick_t / it | max distance to oracle | 99th percentile | hit/miss differs from oracle |\n\
             |---|---|---|---|---|---|---|---|\n"
        ));
        for r in &extra_rows {
            let ours_t = r.methods.get(1).map_or(f64::NAN, |m| m.1);
            for (name, rate, e) in &r.methods {
                md.push_str(&format!(
                    "| {} | {} | {name} | {rate:.0} | {:.2}× | {:.2e} m | {:.2e} m | {} |\n",
                    r.scene,
                    r.rays,
                    ours_t / rate,
                    e.max,
                    e.p99,
                    e.status_differs,
                ));
            }
        }
        md.push_str(
            "\nEmbree's memory (its memory monitor callback: vertices, indices and BVH) and build time:\n\n\
             | scene | method | memory | build | against ours |\n|---|---|---|---|---|\n",
        );
        md.push_str(&extra_mem);
    }
    Ok(Section {
        title: "Terrain picking: height-augmented quadtree vs parry3d BVH vs brute force".into(),
        markdown: md,
    })
}

/// `f` run once untimed, then timed: its seconds and its second result. The untimed run brings the method's
/// own data into the caches, whichever method ran before it (one that walks a large structure, such as brute
/// force's vertex arrays, would otherwise leave the next method to start cold).
fn warm_then_time<R>(mut f: impl FnMut() -> R) -> (f64, R) {
    std::hint::black_box(f());
    let t0 = Instant::now();
    let r = f();
    (t0.elapsed().as_secs_f64(), r)
}

/// Times ours at every block size, parry and the sampled brute force on the same rays, interleaved, under one
/// policy for every method: each starts from the same `f64` ray records and builds its own ray inside the timed
/// region (`curvicast::Ray::new`, parry's `Ray::new`), and each pass times every method once (brute force on
/// the first `n_brute` rays) and the best of `PASSES` passes is kept per method (a background load slows a pass,
/// never speeds one up). Each timed run follows an untimed run of the same method over the same rays
/// ([`warm_then_time`]), so that every method is timed with its own data in the caches, not the previous
/// method's.
#[allow(clippy::too_many_arguments)]
fn measure(
    scene: &str,
    kind: &str,
    rays: &[RaySpec],
    pickers: &[(usize, Picker<'_, f64, DemStorage<'_>>)],
    parry: &ParryTerrain,
    brute: &BruteForceTerrain,
    n_brute: usize,
    extra: &[TerrainBaseline<'_>],
) -> anyhow::Result<(Vec<Row>, Answers)> {
    let ray = |r: &RaySpec| Ray::new(r.origin, r.dir).map_err(|e| anyhow::anyhow!("{scene}: {e}"));
    let n = rays.len();
    let mut best_brute = f64::INFINITY;
    let mut best_ours = vec![f64::INFINITY; pickers.len()];
    let mut best_t = vec![f64::INFINITY; pickers.len()];
    let mut answers_t: Vec<Vec<TCell>> = vec![Vec::new(); pickers.len()];
    let mut best_parry = f64::INFINITY;
    let mut answers: Vec<Vec<TCell>> = vec![Vec::new(); pickers.len()];
    let mut theirs: Vec<Option<f64>> = Vec::new();
    let (mut tris, mut quads) = (vec![0u64; pickers.len()], vec![0u64; pickers.len()]);
    let mut best_extra = vec![f64::INFINITY; extra.len()];
    let mut extra_answers: Vec<Vec<Option<f64>>> = vec![Vec::new(); extra.len()];
    for pass in 0..PASSES {
        for (k, (_, picker)) in pickers.iter().enumerate() {
            let (secs, (got, stats)) = warm_then_time(|| {
                let mut stats = PickStats::default();
                let got = rays
                    .iter()
                    .map(|r| {
                        picker
                            .pick_with_stats(&ray(r)?, &mut stats)
                            .map(|h| h.map(|h| (h.t, h.cell)))
                            .map_err(|e| anyhow::anyhow!("{scene}: {e}"))
                    })
                    .collect::<anyhow::Result<Vec<TCell>>>();
                (got, stats)
            });
            let got = got?;
            best_ours[k] = best_ours[k].min(secs);
            let (secs, got_t) = warm_then_time(|| {
                rays.iter()
                    .map(|r| {
                        picker
                            .pick_t(&ray(r)?)
                            .map_err(|e| anyhow::anyhow!("{scene}: {e}"))
                    })
                    .collect::<anyhow::Result<Vec<TCell>>>()
            });
            let got_t = got_t?;
            best_t[k] = best_t[k].min(secs);
            if pass == 0 {
                tris[k] = u64::from(stats.triangles_tested);
                quads[k] = u64::from(stats.quads_visited);
                answers[k] = got;
                answers_t[k] = got_t;
            }
        }
        let (secs, got) = warm_then_time(|| {
            rays.iter()
                .map(|r| parry.pick(r))
                .collect::<Vec<Option<f64>>>()
        });
        best_parry = best_parry.min(secs);
        if pass == 0 {
            theirs = got;
        }
        for (k, b) in extra.iter().enumerate() {
            let (secs, got) = warm_then_time(|| {
                rays.iter()
                    .map(|r| (b.pick)(r))
                    .collect::<Vec<Option<f64>>>()
            });
            best_extra[k] = best_extra[k].min(secs);
            if pass == 0 {
                extra_answers[k] = got;
            }
        }
        let (secs, ()) = warm_then_time(|| {
            for r in rays.iter().take(n_brute) {
                std::hint::black_box(brute.pick(r));
            }
        });
        best_brute = best_brute.min(secs);
    }
    let mut out = Vec::new();
    for (k, (block, _)) in pickers.iter().enumerate() {
        let mut disagree = 0;
        let mut max_dist: f64 = 0.0;
        let mut hits = 0;
        for ((a, b), r) in answers[k].iter().zip(&theirs).zip(rays) {
            match (a, b) {
                (Some((x, _)), Some(y)) => {
                    hits += 1;
                    let dl = (r.dir[0].powi(2) + r.dir[1].powi(2) + r.dir[2].powi(2)).sqrt();
                    max_dist = max_dist.max((x - y).abs() * dl);
                }
                (None, None) => {}
                _ => disagree += 1,
            }
        }
        let (mut t_differs, mut t_refined_by) = (0, 0.0_f64);
        for ((a, f), r) in answers[k].iter().zip(&answers_t[k]).zip(rays) {
            match (a, f) {
                (Some((t, c)), Some((tf, cf))) if c == cf => {
                    let dl = (r.dir[0].powi(2) + r.dir[1].powi(2) + r.dir[2].powi(2)).sqrt();
                    t_refined_by = t_refined_by.max((t - tf).abs() * dl);
                }
                (None, None) => {}
                _ => t_differs += 1,
            }
        }
        out.push(Row {
            scene: scene.into(),
            rays: kind.into(),
            block: *block,
            n,
            ours: n as f64 / best_ours[k],
            ours_t: n as f64 / best_t[k],
            parry: n as f64 / best_parry,
            brute: n_brute.min(n) as f64 / best_brute,
            hits,
            disagree,
            max_dist,
            tri_per_ray: tris[k] as f64 / n as f64,
            quads_per_ray: quads[k] as f64 / n as f64,
            t_differs,
            t_refined_by,
            extra: best_extra.iter().map(|&b| n as f64 / b).collect(),
        });
    }
    let t_of = |v: &[TCell]| v.iter().map(|a| a.map(|(t, _)| t)).collect::<Vec<_>>();
    let first = |v: &[Vec<TCell>]| v.first().map_or_else(Vec::new, |a| t_of(a));
    let answers = Answers {
        ours: [first(&answers), first(&answers_t)],
        extra: extra_answers,
    };
    Ok((out, answers))
}

/// The first pass's answers of a row, for the oracle comparison: ours (`pick`, `pick_t`) with the first block
/// size, and each other baseline's.
struct Answers {
    ours: [Vec<Option<f64>>; 2],
    extra: Vec<Vec<Option<f64>>>,
}
