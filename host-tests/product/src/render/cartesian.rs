//! The Cartesian-resampling baseline of `curvicast render` (Hannasch §6.1–6.3): the cells resampled once onto
//! `N³` voxels covering the grid's bounding cube — each voxel takes the value of the native cell containing its
//! center, 0 outside the domain — then marched with the Amanatides–Woo DDA
//! ([`crate::render::dda::VoxelCube::traverse`]). The bounding cube of a spherical grid is centred on the
//! center with half-side `r_max`; that of a cylindrical grid is centred on the axis halfway up its height range,
//! with half-side the larger of `ρ_max` and half the height range. A polar grid is unbounded in z and has no
//! bounding cube, so it has no Cartesian baseline.

use super::field::Cells;
use super::sampler::Accumulator;
use crate::render::dda::{VoxelCube, cylindrical_cell_of, spherical_cell_of};
use rayon::prelude::*;

/// A field resampled onto voxels: one `f32` per voxel (NaN where the containing cell is empty).
#[derive(Debug, Clone)]
pub struct VoxelValues {
    cube: VoxelCube,
    values: Vec<f32>,
}

impl VoxelValues {
    /// Resamples `values` (one per cell of `grid`, flat order) onto `n³` voxels spanning the grid's bounding cube,
    /// across the cores; an error for a polar grid, which has no bounding cube.
    pub fn resample(grid: &Cells, values: &[f64], n: usize) -> Result<VoxelValues, String> {
        let cube = match grid {
            Cells::Spherical(g) => VoxelCube::around(g.center, g.outer_radius(), n),
            Cells::Cylindrical(g) => {
                let (z0, z1) = (g.z[0], g.z[g.z.len() - 1]);
                let [cx, cy, cz] = g.center;
                let half = grid.outer_radius().max((z1 - z0) / 2.0);
                VoxelCube::around([cx, cy, cz + (z0 + z1) / 2.0], half, n)
            }
            Cells::Polar(_) => {
                return Err(
                    "cartesian: a polar grid is unbounded in z and has no bounding cube to resample onto"
                        .into(),
                );
            }
        };
        let cell_of = |p: [f64; 3]| match grid {
            Cells::Spherical(g) => spherical_cell_of(g.center, &g.r, &g.theta, &g.phi, p),
            Cells::Cylindrical(g) => cylindrical_cell_of(g.center, &g.rho, &g.phi, &g.z, p),
            Cells::Polar(_) => None,
        };
        let mut out = vec![0.0f32; n * n * n];
        out.par_chunks_mut(n * n).enumerate().for_each(|(z, slab)| {
            for (i, v) in slab.iter_mut().enumerate() {
                let p = cube.voxel_center(z * n * n + i);
                *v = cell_of(p)
                    .and_then(|c| grid.flat(c))
                    .map_or(0.0, |f| values[f] as f32);
            }
        });
        Ok(VoxelValues { cube, values: out })
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
