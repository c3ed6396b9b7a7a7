//! Terrain picking benchmarks (Wartell et al. §3–§5): the kernel's `Picker` over the host's `DemStorage` against
//! parry3d-f64's `TriMesh` BVH and brute force, on Trinidad (1201 × 2401) and a synthetic fractal terrain of
//! 4096 × 4096 vertices (set `CURVICAST_TERRAIN_BENCH_N` for another size: parry's mesh needs about 170 bytes per
//! triangle, 5.6 GB at 4096²), rays from a camera 2 km above ground and from orbit. Each iteration picks a batch
//! of distinct rays; throughput is in rays. Two batch sizes: 256 rays (`_x256`), whose nodes stay in the caches
//! between iterations, and 4096 (`_x4096`), closer to a stream of picks over the whole terrain, where the size
//! of each structure shows. `quadtree_block*` is `Picker::pick` (the refined hit with its geodetic
//! coordinates); `quadtree_t_block*` is `Picker::pick_t`, the same traversal returning `t` and the cell, which is
//! what parry's `cast_local_ray` returns.
//!
//! With `--features embree` (Embree 3 installed: Debian's `libembree-dev`), Embree's single-ray
//! `rtcIntersect1` over the same triangles in `f32`, in ECEF (`Embree_ECEF`) and in a frame centred on the DEM
//! (`Embree_local_frame`).
//!
//! Quick run: `cargo bench -p curvicast-host --bench terrain -- --warm-up-time 1 --measurement-time 2`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use curvicast::Ray;
use curvicast::terrain::Picker;
use curvicast_cli::formats::real_dem;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::Dem;
use curvicast_cli::storage::DemStorage;
use curvicast_host::baselines::embree_baselines;
use curvicast_host::baselines::terrain::{BruteForceTerrain, ParryTerrain};
use curvicast_host::scenes::terrain_cases::{TerrainKind, camera_rays, orbit_rays, synthetic};
use std::hint::black_box;

/// The batch sizes (distinct rays per iteration).
const BATCHES: [usize; 2] = [256, 4096];

fn bench_scene(c: &mut Criterion, name: &str, dem: &Dem) {
    // Leaf blocks of 8 × 8 cells (the faster) and 16 × 16 (the command line's default), with node boxes.
    let storages = [8, 16].map(|block| (block, DemStorage::new(dem, block)));
    let pickers: Vec<(usize, Picker<'_, f64, DemStorage<'_>>)> = storages
        .iter()
        .map(|(block, s)| (*block, Picker::new(s).expect("picker")))
        .collect();
    let parry = ParryTerrain::new(dem).expect("parry mesh");
    let brute = BruteForceTerrain::new(dem);
    // Embree in ECEF and in a local frame, with `--features embree` (none otherwise).
    let embree = embree_baselines(dem).expect("Embree scenes");
    let mut g = c.benchmark_group(format!("terrain/{name}"));
    g.sample_size(10);
    for (kind, rays) in BATCHES.into_iter().flat_map(|n| {
        [
            (format!("camera_2km_x{n}"), camera_rays(dem, n, 2000.0, 1)),
            (format!("orbit_x{n}"), orbit_rays(dem, n, 2)),
        ]
    }) {
        let kind = kind.as_str();
        // One policy for every method: each builds its own ray from the same f64 records inside the timed
        // loop (the kernel's `Ray::new` here, parry's inside `ParryTerrain::pick`, brute force's none).
        let kernel_ray = |r: &RaySpec| Ray::new(r.origin, r.dir).expect("ray");
        g.throughput(Throughput::Elements(rays.len() as u64));
        for (block, picker) in &pickers {
            let id = BenchmarkId::new(format!("quadtree_block{block}"), kind);
            g.bench_with_input(id, &rays, |b, rays| {
                b.iter(|| {
                    rays.iter()
                        .filter(|r| {
                            picker
                                .pick(&kernel_ray(black_box(r)))
                                .ok()
                                .flatten()
                                .is_some()
                        })
                        .count()
                })
            });
            // `pick_t`: the same traversal, `t` and the cell only, as parry's cast returns `t` only.
            let id = BenchmarkId::new(format!("quadtree_t_block{block}"), kind);
            g.bench_with_input(id, &rays, |b, rays| {
                b.iter(|| {
                    rays.iter()
                        .filter(|r| {
                            picker
                                .pick_t(&kernel_ray(black_box(r)))
                                .ok()
                                .flatten()
                                .is_some()
                        })
                        .count()
                })
            });
        }
        g.bench_with_input(
            BenchmarkId::new("parry_bvh", kind),
            &rays,
            |b, rays: &Vec<RaySpec>| {
                b.iter(|| {
                    rays.iter()
                        .filter(|r| parry.pick(black_box(r)).is_some())
                        .count()
                })
            },
        );
        for e in &embree {
            let id = BenchmarkId::new(e.name.replace(' ', "_"), kind);
            g.bench_with_input(id, &rays, |b, rays: &Vec<RaySpec>| {
                b.iter(|| {
                    rays.iter()
                        .filter(|r| (e.pick)(black_box(r)).is_some())
                        .count()
                })
            });
        }
        // Brute force is sampled: one ray per iteration (once per kind of ray).
        if rays.len() == BATCHES[0] {
            g.throughput(Throughput::Elements(1));
            g.bench_with_input(BenchmarkId::new("brute_force", kind), &rays[0], |b, r| {
                b.iter(|| brute.pick(black_box(r)))
            });
        }
    }
    g.finish();
}

fn terrain(c: &mut Criterion) {
    let trinidad = real_dem::trinidad().expect("shipped Trinidad DEM");
    bench_scene(c, "trinidad", &trinidad);
    drop(trinidad);
    let n: usize = std::env::var("CURVICAST_TERRAIN_BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4096);
    let syn = synthetic(
        TerrainKind::Fractal,
        (36.0, -118.0, -1.0 / 1200.0, 1.0 / 1200.0),
        (n, n),
        42,
    );
    bench_scene(c, &format!("synthetic_{n}"), &syn);
}

criterion_group!(benches, terrain);
criterion_main!(benches);
