//! The terrain pick in `f32` (seeds 000/003) on a small DEM without node boxes: 9 × 9 vertices at 0.01° near
//! (45° N, 7° E) on WGS84, one zone that is a single leaf of 8 × 8 cells, heights 0–300 m from a fixed pattern.
//! 32 rays from 5 km above the DEM down to points inside it: the mean instructions per pick (with the hit
//! refinement), the number of hits, and one pick's stack high-water mark.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use curvicast::geodesy::Ellipsoid;
use curvicast::ray::Ray;
use curvicast::terrain::{Grid, Node, NodeId, Picker, TerrainStorage};
use curvicast_m4f_bench::{Out, Rng, Timer, finish, loop_check, stack_high_water};

/// The DEM: heights `50 · ((3i + 5j) mod 7)` m.
struct Hills;

const N: u32 = 9;

impl TerrainStorage<f32> for Hills {
    fn ellipsoid(&self) -> Ellipsoid<f32> {
        Ellipsoid::wgs84()
    }
    fn grid(&self) -> Grid<f32> {
        Grid {
            lat0_deg: 45.0,
            lon0_deg: 7.0,
            dlat_deg: 0.01,
            dlon_deg: 0.01,
            rows: N,
            cols: N,
        }
    }
    fn zone_count(&self) -> usize {
        1
    }
    fn zone(&self, k: usize) -> Option<NodeId> {
        (k == 0).then_some(NodeId(0))
    }
    fn node(&self, id: NodeId) -> Option<Node<f32>> {
        (id.0 == 0).then_some(Node {
            rows: [0, N - 1],
            cols: [0, N - 1],
            heights: Some([0.0, 300.0]),
            children: [None; 4],
            level: 0,
        })
    }
    fn height(&self, i: u32, j: u32) -> Option<f32> {
        (i < N && j < N).then(|| 50.0 * ((3 * i + 5 * j) % 7) as f32)
    }
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
    let dem = Hills;
    let Ok(picker) = Picker::<'_, f32, Hills, 16, 4>::new(&dem) else {
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
