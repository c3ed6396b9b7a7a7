//! Many rays at once: an image's rays marched across cores with rayon (Hannasch ch. 5's serial engine, one
//! iterator per ray).
//!
//! The kernel's part is a marcher that is cheap to construct and owns nothing but a few scalars; this module
//! only spreads the rays over rayon's thread pool in contiguous runs of at least 64 rays (so a thread walks
//! neighbouring rays through the same breakpoint tables), hands every ray's iterator to the caller's sampler and
//! writes each answer straight into its place in the result. The answers do not depend on the number of
//! threads: each ray is marched exactly as `grid.march(&ray)` would march it alone.
//!
//! ```
//! use curvicast::{ray::Ray, march::SphericalGrid};
//! use curvicast_cli::batch::march_batch;
//! use std::f64::consts::PI;
//! let (r, th, ph) = ([0.0, 0.5, 1.0], [0.0, PI / 2.0, PI], [0.0, PI, 2.0 * PI]);
//! let mut ws = vec![0.0; SphericalGrid::<f64>::workspace_len(3, 3, 3)];
//! let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
//! let rays: Vec<Ray<f64>> = (0..16)
//!     .map(|i| Ray::new([-3.0, -0.9 + 0.12 * i as f64, 0.1], [1.0, 0.0, 0.0]).unwrap())
//!     .collect();
//! // a projection image (§6.1): Σ length over the cells crossed, one value per ray
//! let image = march_batch(&grid, &rays, |_, m| m.map(|c| c.t_exit - c.t_enter).sum::<f64>());
//! assert_eq!(image.len(), 16);
//! assert!(image.iter().all(|&v| v > 0.0 && v <= 2.0));
//! ```

use curvicast::march::{Grid, GridKind, SerialMarch};
use curvicast::ray::Ray;
use curvicast::real::Real;
use rayon::prelude::*;

/// The fewest rays per rayon task: far more marching work than scheduling cost (a ray through a 64³ grid crosses
/// tens to hundreds of cells), and still enough tasks that two cores share an image evenly.
const MIN_RAYS_PER_TASK: usize = 64;

/// Marches every ray of `rays` through `grid` on rayon's thread pool and returns `sampler(index, march)` for
/// each, in the order of `rays`. The sampler consumes the iterator as it likes (a sum, a compositing loop that
/// stops early, a collect) and can ask `march.error()` afterwards.
pub fn march_batch<T, K, S, F>(grid: &Grid<'_, T, K>, rays: &[Ray<T>], sampler: F) -> Vec<S>
where
    T: Real,
    K: GridKind,
    S: Send,
    F: Fn(usize, &mut SerialMarch<'_, T, K>) -> S + Sync,
{
    // an indexed iterator: each task writes its answers straight into their places in the result (no per-task
    // lists to concatenate), and a task marches neighbouring rays through the same breakpoint tables
    rays.par_iter()
        .with_min_len(MIN_RAYS_PER_TASK)
        .enumerate()
        .map(|(i, ray)| {
            let mut m = grid.march(ray);
            sampler(i, &mut m)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use curvicast::march::SphericalGrid;
    use std::f64::consts::PI;

    fn grid_and_rays() -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<Ray<f64>>) {
        let r: Vec<f64> = (0..=16).map(|i| i as f64 / 16.0).collect();
        let th: Vec<f64> = (0..=16).map(|i| PI * i as f64 / 16.0).collect();
        let ph: Vec<f64> = (0..=16).map(|i| 2.0 * PI * i as f64 / 16.0).collect();
        let rays = (0..40 * 40)
            .map(|k| {
                let (a, b) = ((k / 40) as f64 / 20.0 - 1.0, (k % 40) as f64 / 20.0 - 1.0);
                Ray::new([-3.0, a, b], [1.0, 0.15, 0.1]).unwrap()
            })
            .collect();
        (r, th, ph, rays)
    }

    #[test]
    fn batch_equals_one_ray_at_a_time_on_one_and_two_threads() {
        let (r, th, ph, rays) = grid_and_rays();
        let mut ws = vec![0.0; SphericalGrid::<f64>::workspace_len(r.len(), th.len(), ph.len())];
        let grid = SphericalGrid::new(&r, &th, &ph, &mut ws).unwrap();
        let alone: Vec<Vec<_>> = rays.iter().map(|ray| grid.march(ray).collect()).collect();
        assert!(alone.iter().filter(|v| v.len() > 20).count() > 100);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let batch = pool.install(|| {
                march_batch(&grid, &rays, |i, m| {
                    let v: Vec<_> = m.by_ref().collect();
                    assert_eq!(m.error(), None);
                    (i, v)
                })
            });
            assert_eq!(batch.len(), rays.len());
            for (k, (i, v)) in batch.into_iter().enumerate() {
                assert_eq!(i, k);
                assert_eq!(v, alone[k], "ray {k}, {threads} threads");
            }
        }
    }
}
