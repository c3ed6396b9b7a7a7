//! Multi-resolution picking (Wartell et al. §5–§6) against the independent multi-resolution oracle
//! ([`curvicast_host::oracle::multires`]): the surface that a tree, a residency pattern and a `min_level` select,
//! brute force in 256 bits.
//!
//! Criterion: no miss, no false hit, hit points within 1 µm; a disagreement within 1 µm of an edge is accepted
//! when the oracle, asked again with the ray moved by 1 µm, agrees with the kernel (a tie decided by rounding).
//! The crack tests aim rays at resolution borders of terrain without missing data, where every downward ray must
//! hit.

use curvicast::Ray;
use curvicast::terrain::{Hit, NodeId, Picker, TerrainError};
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::{Dem, geodetic_to_ecef_f64};
use curvicast_cli::storage::{DemStorage, MultiRes};
use curvicast_host::oracle::multires::{MultiResOracle, TreeNode};
use curvicast_host::oracle::terrain::TerrainOracle;
use curvicast_host::scenes::terrain_cases::{TerrainKind, camera_rays, random_rays, synthetic};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// The table's bound on the hit point's distance from the oracle's, metres.
const TOL: f64 = curvicast_host::tolerances::TERRAIN_HIT_F64.bound;

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn kernel_ray(r: &RaySpec) -> Ray<f64> {
    Ray::new(r.origin, r.dir)
        .and_then(|x| x.with_interval(r.t_min, r.t_max_or_inf()))
        .expect("valid ray")
}

fn pick(s: &DemStorage<'_>, min_level: u8, r: &RaySpec) -> Result<Option<Hit<f64>>, TerrainError> {
    let p: Picker<'_, f64, DemStorage<'_>> = Picker::new(s).expect("picker");
    p.with_min_level(min_level).pick(&kernel_ray(r))
}

/// A fractal DEM of `n × n` vertices at (lat, lon) with 0.002° spacing.
fn dem_at(lat: f64, lon: f64, n: usize, seed: u64) -> Dem {
    synthetic(TerrainKind::Fractal, (lat, lon, 0.002, 0.002), (n, n), seed)
}

/// Sets residency from `keep` for every node, except that nodes at or above `min_level` (and the first node at or
/// below it on each path) stay resident, so that the surface needs no block.
fn set_residency(s: &DemStorage<'_>, min_level: u8, keep: impl Fn(&TreeNode) -> bool) {
    let tree = s.tree();
    let level_of = |id: u32| tree.iter().find(|n| n.id == id).map_or(0, |n| n.level);
    for n in &tree {
        let top = n.level <= min_level || n.parent.is_none_or(|p| level_of(p) < min_level);
        s.set_resident(NodeId(n.id), top || keep(n));
    }
}

#[derive(Default, Debug)]
struct Tally {
    rays: usize,
    hits: usize,
    coarse_hits: usize,
    ties: usize,
    worst: f64,
    failures: Vec<String>,
}

/// Every ray through the kernel and the oracle of the storage's current residency.
fn compare(dem: &Dem, s: &DemStorage<'_>, min_level: u8, rays: &[RaySpec]) -> Tally {
    let oracle =
        MultiResOracle::new(dem, &s.tree(), min_level).expect("a surface that needs no block");
    let picker: Picker<'_, f64, DemStorage<'_>> = Picker::new(s).expect("picker");
    let picker = picker.with_min_level(min_level);
    type Answer = Result<(Option<Hit<f64>>, bool), String>;
    let out: Vec<Answer> = rays
        .par_iter()
        .enumerate()
        .map(|(k, r)| {
            let ours = picker
                .pick(&kernel_ray(r))
                .map_err(|e| format!("ray {k} {r:?}: {e}"))?;
            let truth = oracle.pick(r);
            let agree = |q: Option<[f64; 3]>, tol: f64| match (ours.map(|h| h.ecef), q) {
                (None, None) => true,
                (Some(a), Some(b)) => dist(a, b) <= tol,
                _ => false,
            };
            if agree(truth.map(|h| h.point), TOL) {
                return Ok((ours, false));
            }
            for a in 0..6 {
                let mut moved = *r;
                moved.origin[a % 3] += if a < 3 { 1e-6 } else { -1e-6 };
                if agree(oracle.pick(&moved).map(|h| h.point), 2.0 * TOL) {
                    return Ok((ours, true));
                }
            }
            Err(format!(
                "ray {k} {r:?}: kernel {ours:?} vs oracle {truth:?}"
            ))
        })
        .collect();
    let mut t = Tally::default();
    for (res, r) in out.into_iter().zip(rays) {
        t.rays += 1;
        match res {
            Err(e) => t.failures.push(e),
            Ok((h, tie)) => {
                t.ties += usize::from(tie);
                if let Some(h) = h {
                    t.hits += 1;
                    t.coarse_hits += usize::from(h.stride > 1);
                    if !tie {
                        if let Some(q) = oracle.pick(r) {
                            t.worst = t.worst.max(dist(h.ecef, q.point));
                        }
                    }
                }
            }
        }
    }
    t
}

fn assert_clean(name: &str, t: &Tally) {
    eprintln!(
        "{name}: {} rays, {} hits ({} on coarse cells), {} ties, worst {:.2e} m",
        t.rays, t.hits, t.coarse_hits, t.ties, t.worst
    );
    assert!(
        t.failures.is_empty(),
        "{name}: {} failures, first: {:#?}",
        t.failures.len(),
        &t.failures[..t.failures.len().min(5)]
    );
    assert!(t.ties * 50 <= t.rays, "{name}: too many ties ({})", t.ties);
}

/// Rays aimed at the interior borders between nodes (not the DEM's own edges): from 50 m to 5 km above a random
/// point of a random node's border (exactly on a lattice vertex for a third of them), down towards a point at or
/// near it.
fn border_rays(dem: &Dem, tree: &[TreeNode], n: usize, seed: u64) -> Vec<RaySpec> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (hmin, hmax) = dem.height_range().expect("data");
    let (cr, cc) = ((dem.rows - 1) as u32, (dem.cols - 1) as u32);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let k = out.len();
        let node = &tree[rng.random_range(0..tree.len())];
        let along_row = rng.random_bool(0.5);
        let (ends, last) = if along_row {
            (node.rows, cr)
        } else {
            (node.cols, cc)
        };
        let inner: Vec<u32> = ends.into_iter().filter(|&x| x > 0 && x < last).collect();
        if inner.is_empty() {
            continue;
        }
        let at = f64::from(inner[rng.random_range(0..inner.len())]);
        let span = if along_row { node.cols } else { node.rows };
        let pos = if k % 3 == 0 {
            f64::from(rng.random_range(span[0]..=span[1]))
        } else {
            rng.random_range(f64::from(span[0])..=f64::from(span[1]))
        };
        let (fi, fj) = if along_row { (at, pos) } else { (pos, at) };
        let (lat, lon) = (dem.lat0 + fi * dem.dlat, dem.lon0 + fj * dem.dlon);
        let top = geodetic_to_ecef_f64(
            dem.a,
            dem.b,
            lat,
            lon,
            f64::from(hmax) + rng.random_range(50.0..5000.0),
        );
        let jitter = if k % 2 == 0 { 0.0 } else { 0.3 };
        let fi2 = (fi + rng.random_range(-jitter..=jitter)).clamp(0.5, f64::from(cr) - 0.5);
        let fj2 = (fj + rng.random_range(-jitter..=jitter)).clamp(0.5, f64::from(cc) - 0.5);
        let bottom = geodetic_to_ecef_f64(
            dem.a,
            dem.b,
            dem.lat0 + fi2 * dem.dlat,
            dem.lon0 + fj2 * dem.dlon,
            f64::from(hmin) - 100.0,
        );
        out.push(RaySpec::new(top, [0, 1, 2].map(|a| bottom[a] - top[a])));
    }
    out
}

/// Grazing rays along node borders: starting 1–30 m above the terrain's maximum... over a border vertex, heading
/// along the border line (a parallel or a meridian) at 0.2°–3° below the horizontal.
fn grazing_border_rays(dem: &Dem, tree: &[TreeNode], n: usize, seed: u64) -> Vec<RaySpec> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (_, hmax) = dem.height_range().expect("data");
    (0..n)
        .map(|_| {
            let node = &tree[rng.random_range(0..tree.len())];
            let i = if rng.random_bool(0.5) {
                node.rows[0]
            } else {
                node.rows[1]
            } as usize;
            let j = if rng.random_bool(0.5) {
                node.cols[0]
            } else {
                node.cols[1]
            } as usize;
            let h = f64::from(hmax) + rng.random_range(1.0..30.0);
            let o = geodetic_to_ecef_f64(dem.a, dem.b, dem.lat(i), dem.lon(j), h);
            // A target along the row (parallel) or the column (meridian), far enough to cross many cells.
            let (ti, tj) = if rng.random_bool(0.5) {
                (
                    i as f64,
                    if j > dem.cols / 2 {
                        0.0
                    } else {
                        (dem.cols - 1) as f64
                    },
                )
            } else {
                (
                    if i > dem.rows / 2 {
                        0.0
                    } else {
                        (dem.rows - 1) as f64
                    },
                    j as f64,
                )
            };
            let far = geodetic_to_ecef_f64(
                dem.a,
                dem.b,
                dem.lat0 + ti * dem.dlat,
                dem.lon0 + tj * dem.dlon,
                h,
            );
            let horiz = [0, 1, 2].map(|a| far[a] - o[a]);
            let len = (horiz.iter().map(|x| x * x).sum::<f64>()).sqrt();
            let up = {
                let l = (o.iter().map(|x| x * x).sum::<f64>()).sqrt();
                o.map(|x| x / l)
            };
            let dip = rng.random_range(0.2f64..3.0).to_radians().tan() * len;
            RaySpec::new(o, [0, 1, 2].map(|a| horiz[a] - dip * up[a]))
        })
        .collect()
}

/// A multi-resolution storage: 8-cell blocks, full resolution only in the box around the DEM's center, leaves
/// at pyramid level `coarse` elsewhere.
fn shaped(dem: &Dem, coarse: usize, block: usize) -> DemStorage<'_> {
    let (ci, cj) = ((dem.rows / 2) as f64, (dem.cols / 2) as f64);
    let q = |x: f64| x * 0.3;
    let region = [
        dem.lat0 + (ci - q(dem.rows as f64)) * dem.dlat,
        dem.lat0 + (ci + q(dem.rows as f64)) * dem.dlat,
        dem.lon0 + (cj - q(dem.cols as f64)) * dem.dlon,
        dem.lon0 + (cj + q(dem.cols as f64)) * dem.dlon,
    ];
    let region = [
        region[0].min(region[1]),
        region[0].max(region[1]),
        region[2],
        region[3],
    ];
    DemStorage::multi_resolution(
        dem,
        block,
        MultiRes {
            fine_region: Some(region),
            coarse_level: coarse,
        },
    )
}

fn run_suite(name: &str, dem: &Dem, coarse: usize, block: usize, seeds: u64, rays_per: usize) {
    let s = shaped(dem, coarse, block);
    let depth = s.tree().iter().map(|n| n.level).max().unwrap_or(0);
    let mut total = Tally::default();
    for seed in 0..seeds {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        // Every min_level in turn.
        let min_level = (seed % (u64::from(depth) + 1)) as u8;
        let p: f64 = rng.random_range(0.2..0.9);
        let salt: u64 = rng.random();
        // Random residency, independent per node (the kernel then uses a block only below resident ancestors).
        set_residency(&s, min_level, |n| {
            let mut r = ChaCha8Rng::seed_from_u64(
                salt ^ u64::from(n.id).wrapping_mul(0x9E37_79B9_7F4A_7C15),
            );
            r.random_bool(p)
        });
        let tree = s.tree();
        let mut rays = border_rays(dem, &tree, rays_per, seed + 100);
        rays.extend(grazing_border_rays(dem, &tree, rays_per / 4, seed + 200));
        rays.extend(camera_rays(dem, rays_per / 4, 1500.0, seed + 300));
        rays.extend(random_rays(dem, rays_per / 4, seed + 400));
        let t = compare(dem, &s, min_level, &rays);
        assert!(
            t.failures.is_empty(),
            "{name} seed {seed} (min_level {min_level}, p {p:.2}): {} failures, first: {:#?}",
            t.failures.len(),
            &t.failures[..t.failures.len().min(4)]
        );
        total.rays += t.rays;
        total.hits += t.hits;
        total.coarse_hits += t.coarse_hits;
        total.ties += t.ties;
        total.worst = total.worst.max(t.worst);
    }
    assert_clean(name, &total);
    assert!(total.coarse_hits > 0, "{name}: no ray hit a coarse cell");
}

#[test]
fn random_residency_and_every_min_level_mid_latitude() {
    let dem = dem_at(36.0, -118.0, 97, 1);
    run_suite("mid-latitude", &dem, 2, 8, 12, 160);
}

#[test]
fn random_residency_high_latitude_across_the_antimeridian() {
    let dem = dem_at(71.9, 179.9, 97, 2);
    run_suite("high latitude, antimeridian", &dem, 2, 8, 12, 160);
}

/// 4-cell blocks: sources whose cells are larger than the leaves below them.
#[test]
fn random_residency_small_blocks_coarse_cells_larger_than_leaves() {
    let dem = dem_at(-33.0, 151.0, 97, 4);
    run_suite("4-cell blocks", &dem, 2, 4, 12, 160);
}

#[test]
fn random_residency_southern_hemisphere_negative_latitudes() {
    let dem = synthetic(TerrainKind::Spiky, (-48.0, 10.0, 0.003, 0.003), (81, 81), 3);
    run_suite("southern, spiky", &dem, 3, 8, 10, 160);
}

/// Every downward ray aimed at a resolution border of gap-free terrain hits, and where the oracle's surface
/// stitches coarse cells to finer ones, the hit agrees with it: no crack lets a ray through.
#[test]
fn rays_along_resolution_borders_find_no_crack() {
    for (lat, seed) in [(36.0, 5), (-63.0, 6), (84.0, 7)] {
        let dem = dem_at(lat, 20.0, 97, seed);
        let s = shaped(&dem, 2, 8);
        let tree = s.tree();
        let oracle = MultiResOracle::new(&dem, &tree, 0).expect("all resident");
        assert!(
            oracle.stitched_cells() > 0,
            "the tree has resolution borders"
        );
        let rays = border_rays(&dem, &tree, 3000, seed);
        let misses: Vec<usize> = rays
            .par_iter()
            .enumerate()
            .filter(|(_, r)| pick(&s, 0, r).expect("answer").is_none())
            .map(|(k, _)| k)
            .collect();
        assert!(
            misses.is_empty(),
            "lat {lat}: {} rays passed through the surface, first {:?}",
            misses.len(),
            rays[misses[0]]
        );
        let t = compare(&dem, &s, 0, &rays[..600]);
        assert_clean(&format!("borders at {lat}°"), &t);
    }
}

/// The four cases of the ancestor loop, on one tree: 97 × 97 vertices, 8-cell blocks, full depth everywhere
/// (zones at level 0, leaves at level 3 with stride 1).
mod ancestor_loop;

/// With every block resident and `min_level` at the tree's depth, a full-depth tree answers exactly as the
/// single-resolution surface (the contract's triangles): checked against the single-resolution oracle.
#[test]
fn min_level_at_full_depth_is_the_single_resolution_surface() {
    let dem = dem_at(-12.0, 131.0, 97, 21);
    let s = DemStorage::multi_resolution(
        &dem,
        8,
        MultiRes {
            fine_region: None,
            coarse_level: 0,
        },
    );
    let depth = s.tree().iter().map(|n| n.level).max().expect("nodes");
    let oracle = TerrainOracle::new(&dem);
    let rays = random_rays(&dem, 400, 9);
    for (k, r) in rays.iter().enumerate() {
        let ours = pick(&s, depth, r).expect("answer");
        let truth = oracle.pick(r);
        match (ours, truth) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                assert!(dist(a.ecef, b.point) < TOL, "ray {k}: {a:?} vs {b:?}");
                assert_eq!(a.stride, 1);
            }
            (a, b) => panic!("ray {k}: {a:?} vs {b:?}"),
        }
    }
}

/// The long run (`cargo test -p curvicast-host --release --test terrain multires -- --include-ignored`): more
/// residency patterns and rays on four terrains, every `min_level`. CI's long step runs one shard of the four
/// per commit (`CURVICAST_LONG_SHARD`, tests/support: long_shard).
#[test]
#[ignore = "long: about a minute"]
fn random_residency_full() {
    /// A suite: its name, its terrain, the coarse level and the leaf blocks' cells.
    type Suite = (&'static str, fn() -> Dem, usize, usize);
    let suites: [Suite; 4] = [
        ("full: mid-latitude", || dem_at(47.0, 8.0, 129, 31), 2, 8),
        ("full: 4-cell blocks", || dem_at(12.0, -70.0, 129, 34), 3, 4),
        ("full: polar", || dem_at(-87.5, -179.0, 97, 32), 2, 8),
        (
            "full: spiky",
            || {
                synthetic(
                    TerrainKind::Spiky,
                    (60.0, -150.0, 0.003, 0.004),
                    (97, 97),
                    33,
                )
            },
            3,
            8,
        ),
    ];
    for (name, dem, coarse, block) in crate::support::long_shard(suites.to_vec()) {
        run_suite(name, &dem(), coarse, block, 30, 400);
    }
}

/// Near a pole, coarse cells far wider than tall (0.0001° × 2.7° at 89.4°): a latitude cone's arc between two
/// meridians sags across even the opposite row's chord plane, so the stitched vertices of one row lie beyond
/// the other row's wall (a fuzz finding). Border and grazing rays against the oracle, every block resident.
#[test]
fn wide_coarse_cells_near_the_pole_stitched_to_finer_ones() {
    let dem = synthetic(
        TerrainKind::Fractal,
        (89.40, -0.01, -1.0e-4, 2.7),
        (49, 17),
        41,
    );
    let s = DemStorage::multi_resolution(
        &dem,
        4,
        MultiRes {
            fine_region: Some([89.399, 89.40, 10.0, 16.0]),
            coarse_level: 2,
        },
    );
    let tree = s.tree();
    let oracle = MultiResOracle::new(&dem, &tree, 0).expect("all resident");
    assert!(oracle.stitched_cells() > 0);
    let mut rays = border_rays(&dem, &tree, 1500, 42);
    rays.extend(grazing_border_rays(&dem, &tree, 300, 43));
    let t = compare(&dem, &s, 0, &rays);
    assert_clean("wide cells near the pole", &t);
}

/// The rectangle the kernel traces for a node that falls back to an ancestor `A` — the node's own ranges, when
/// they lie on `A`'s sample lattice — is the §5 block subset computed the paper's incremental integer way
/// ([`BlockSubset`]), for every node and every ancestor of two trees; and where the subset is a single cell
/// larger than the node (`B >> k = 0`), the node is off `A`'s lattice, so the kernel traces that whole cell
/// from a shallower node instead of splitting it.
#[test]
fn traced_rectangles_are_the_papers_block_subsets() {
    use curvicast::terrain::subset::BlockSubset;
    let dem = dem_at(10.0, 10.0, 129, 51);
    let mut checked = (0, 0);
    for block in [4usize, 8] {
        let s = DemStorage::multi_resolution(
            &dem,
            block,
            MultiRes {
                fine_region: None,
                coarse_level: 0,
            },
        );
        let tree = s.tree();
        let get = |id: u32| *tree.iter().find(|n| n.id == id).expect("node");
        for n in &tree {
            let mut a = *n;
            let mut k = 0u32;
            while let Some(p) = a.parent {
                a = get(p);
                k += 1;
                let span = a.rows[1] - a.rows[0];
                assert_eq!(span, a.cols[1] - a.cols[0], "square nodes in this tree");
                let b = span / a.stride;
                let unit = span >> k;
                let (y, x) = (
                    (n.rows[0] - a.rows[0]) / unit,
                    (n.cols[0] - a.cols[0]) / unit,
                );
                let sub =
                    BlockSubset::of_descendant(b, k, u64::from(x), u64::from(y)).expect("subset");
                let grid = |r: [u32; 2], o: u32| [o + r[0] * a.stride, o + r[1] * a.stride];
                let (rows, cols) = (grid(sub.rows(), a.rows[0]), grid(sub.cols(), a.cols[0]));
                let on = n.rows[0] % a.stride == 0
                    && n.rows[1] % a.stride == 0
                    && n.cols[0] % a.stride == 0
                    && n.cols[1] % a.stride == 0;
                if b >> k >= 1 {
                    assert_eq!((rows, cols), (n.rows, n.cols), "node {n:?}, ancestor {a:?}");
                    assert!(on);
                    checked.0 += 1;
                } else {
                    assert!(
                        rows[0] <= n.rows[0]
                            && n.rows[1] <= rows[1]
                            && cols[0] <= n.cols[0]
                            && n.cols[1] <= cols[1]
                    );
                    assert!(
                        !on,
                        "a node smaller than the ancestor's cell is off its lattice"
                    );
                    checked.1 += 1;
                }
            }
        }
    }
    eprintln!(
        "node–ancestor pairs: {} with B >> k ≥ 1, {} with B >> k = 0",
        checked.0, checked.1
    );
    assert!(checked.0 > 100 && checked.1 > 100, "{checked:?}");
}
