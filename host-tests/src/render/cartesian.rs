//! The Cartesian-resampling baseline of `curvicast render` (seed 001 §6.1–6.3): the cells resampled once onto
//! `N³` voxels covering the grid's bounding cube — each voxel takes the value of the native cell containing its
//! center, 0 outside the domain — then marched with the Amanatides–Woo DDA
//! ([`crate::baselines::dda::VoxelCube::traverse`]).

use super::field::SphericalCells;
use super::sampler::Accumulator;
use crate::baselines::dda::{VoxelCube, spherical_cell_of};
use rayon::prelude::*;

/// A field resampled onto voxels: one `f32` per voxel (NaN where the containing cell is empty).
#[derive(Debug, Clone)]
pub struct VoxelValues {
    cube: VoxelCube,
    values: Vec<f32>,
}

impl VoxelValues {
    /// Resamples `values` (one per cell of `grid`, flat order) onto `n³` voxels spanning
    /// `[center − r_max, center + r_max]³`, across the cores.
    pub fn resample(grid: &SphericalCells, values: &[f64], n: usize) -> VoxelValues {
        let cube = VoxelCube::around(grid.center, grid.outer_radius(), n);
        let mut out = vec![0.0f32; n * n * n];
        out.par_chunks_mut(n * n).enumerate().for_each(|(z, slab)| {
            for (i, v) in slab.iter_mut().enumerate() {
                let p = cube.voxel_center(z * n * n + i);
                *v = spherical_cell_of(grid.center, &grid.r, &grid.theta, &grid.phi, p)
                    .and_then(|c| grid.flat(c))
                    .map_or(0.0, |f| values[f] as f32);
            }
        });
        VoxelValues { cube, values: out }
    }

    /// Voxels per side.
    pub fn n(&self) -> usize {
        self.cube.n()
    }

    /// Marches one pixel's ray (`t ≥ 0`) into `acc`; returns the number of voxels visited.
    pub fn sample(&self, origin: [f64; 3], dir: [f64; 3], acc: &mut Accumulator) -> u64 {
        let mut visited = 0u64;
        self.cube
            .traverse(origin, dir, 0.0, f64::INFINITY, |v, t0, t1| {
                visited += 1;
                acc.add(f64::from(self.values[v]), t1 - t0)
            });
        visited
    }
}
