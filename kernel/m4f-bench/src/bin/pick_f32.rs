//! The terrain pick in `f32` (Wartell et al.) on a small DEM without node boxes: 9 × 9 vertices at 0.01° near
//! (45° N, 7° E) on WGS84, one zone that is a single leaf of 8 × 8 cells (built by the kernel's builder), heights
//! 0–300 m from a fixed pattern.
//! 32 rays from 5 km above the DEM down to points inside it: the mean instructions per pick (with the hit
//! refinement), the number of hits, and one pick's stack high-water mark.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use curvicast::geodesy::Ellipsoid;
use curvicast::ray::Ray;
use curvicast::terrain::build::{NodeRecord, SliceStorage, build_tree, node_slots};
use curvicast::terrain::{Grid, Picker};
use curvicast_m4f_bench::{Out, Rng, Timer, finish, loop_check, stack_high_water};

/// Vertex rows and columns of the DEM.
const N: u32 = 9;
/// Cells per leaf block: the whole DEM is one leaf (and its one zone).
const BLOCK: u32 = 8;

/// The DEM's heights, row-major: `50 · ((3i + 5j) mod 7)` m.
fn hills() -> [f32; (N * N) as usize] {
    let mut h = [0.0; (N * N) as usize];
    for (k, v) in (0u32..).zip(h.iter_mut()) {
        let (i, j) = (k / N, k % N);
        *v = 50.0 * ((3 * i + 5 * j) % 7) as f32;
    }
    h
}

const PICKS: u32 = 32;

#[entry]
fn main() -> ! {
    let mut out = Out::new("pick-f32");
    let Some(mut timer) = Timer::new() else {
        finish(&mut out, false)
    };
    timer.calibrate(&mut out);
    let mut ok = loop_check(&mut timer, &mut out);
    // The tree built by the kernel's builder (what a user on the target does).
    let grid = Grid {
        lat0_deg: 45.0,
        lon0_deg: 7.0,
        dlat_deg: 0.01,
        dlon_deg: 0.01,
        rows: N,
        cols: N,
    };
    let heights = hills();
    let mut nodes = [NodeRecord::<f32>::EMPTY; node_slots(N, N, BLOCK)];
    let Ok(tree) = build_tree(&heights, &grid, BLOCK, &mut nodes) else {
        finish(&mut out, false)
    };
    let Ok(dem) = SliceStorage::new(Ellipsoid::wgs84(), grid, &heights, &nodes, tree) else {
        finish(&mut out, false)
    };
    let Ok(picker) = Picker::<'_, f32, SliceStorage<'_, f32>, 16, 4>::new(&dem) else {
        finish(&mut out, false)
    };
    let e = Ellipsoid::<f32>::wgs84();
    let mut rng = Rng::new(0x0000_91CC);
    let mut coord = |lo: f32| lo + 0.005 + 0.07 * (rng.next24() as f32 / 16_777_216.0);
    let (mut total, mut hits, mut stack) = (0u64, 0u64, 0usize);
    for _ in 0..PICKS {
        let from = e.geodetic_deg_to_ecef(coord(45.0), coord(7.0), 5000.0);
        let to = e.geodetic_deg_to_ecef(coord(45.0), coord(7.0), 0.0);
        let Ok(ray) = Ray::new(from, to.minus(from)) else {
            ok = false;
            continue;
        };
        // 1: a hit within the DEM's heights; 0: no such hit; 2: an error.
        let mut run = || match picker.pick(&ray) {
            Ok(Some(h)) if (0.0..=300.5).contains(&h.h) => 1,
            Ok(_) => 0,
            Err(_) => 2,
        };
        let (instructions, hit) = timer.instructions(1, &mut run);
        total += instructions;
        match hit {
            1 => hits += 1,
            0 => {}
            _ => ok = false,
        }
        let (bytes, _) = stack_high_water(&mut run);
        stack = stack.max(bytes);
    }
    out.str("picks ")
        .num(u64::from(PICKS))
        .str(" hits ")
        .num(hits)
        .str(" per_pick ")
        .num(total / u64::from(PICKS))
        .str(" stack_bytes ")
        .num(stack as u64);
    out.flush();
    finish(&mut out, ok && hits > 0)
}
