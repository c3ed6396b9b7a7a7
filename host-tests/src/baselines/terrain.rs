//! Terrain baselines: what a user would otherwise do to pick a DEM — a general triangle-mesh ray caster
//! (parry3d-f64's `TriMesh`, a BVH over the same ECEF triangles) and brute force over every triangle.

use crate::oracle::terrain::moller_trumbore;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::Dem;
use parry3d_f64::math::Vector;
use parry3d_f64::query::{Ray as PRay, RayCast};
use parry3d_f64::shape::TriMesh;

/// The ECEF vertices (`f64`, NaN for missing ones) and the present triangles of a DEM, in the contract's order
/// (cell (i, j): triangle 0 then 1).
pub fn ecef_mesh(dem: &Dem) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut verts = Vec::with_capacity(dem.rows * dem.cols);
    for i in 0..dem.rows {
        for j in 0..dem.cols {
            verts.push(dem.vertex_ecef(i, j).unwrap_or([f64::NAN; 3]));
        }
    }
    let mut tris = Vec::with_capacity(2 * dem.cell_count());
    for i in 0..dem.rows - 1 {
        for j in 0..dem.cols - 1 {
            for k in 0..2 {
                if let Some(t) = dem.triangle(i, j, k) {
                    tris.push(t.map(|(a, b)| (a * dem.cols + b) as u32));
                }
            }
        }
    }
    (verts, tris)
}

/// parry3d-f64's triangle mesh over the DEM's ECEF triangles (its BVH is built on construction).
pub struct ParryTerrain {
    /// The mesh.
    pub mesh: TriMesh,
}

impl ParryTerrain {
    /// Builds the mesh (missing vertices are replaced by the origin and never indexed). The vertex array is
    /// converted in place (same size and alignment), so that only parry's own arrays and its BVH build remain
    /// at the peak of the build.
    pub fn new(dem: &Dem) -> anyhow::Result<ParryTerrain> {
        let (verts, tris) = ecef_mesh(dem);
        let v: Vec<Vector> = verts
            .into_iter()
            .map(|p| {
                if p[0].is_nan() {
                    Vector::new(0.0, 0.0, 0.0)
                } else {
                    Vector::new(p[0], p[1], p[2])
                }
            })
            .collect();
        let mesh = TriMesh::new(v, tris).map_err(|e| anyhow::anyhow!("parry TriMesh: {e:?}"))?;
        Ok(ParryTerrain { mesh })
    }

    /// The nearest hit parameter over `[t_min, t_max]` (parry casts from t = 0; hits before `t_min` are not
    /// skipped, so callers use `t_min = 0`).
    pub fn pick(&self, r: &RaySpec) -> Option<f64> {
        let ray = PRay::new(
            Vector::new(r.origin[0], r.origin[1], r.origin[2]),
            Vector::new(r.dir[0], r.dir[1], r.dir[2]),
        );
        self.mesh.cast_local_ray(&ray, r.t_max_or_inf(), false)
    }

    /// parry's own estimate of the mesh's memory (`TriMesh::total_memory_size`: vertices, indices, BVH nodes,
    /// and its other buffers).
    pub fn memory_bytes(&self) -> usize {
        self.mesh.total_memory_size()
    }
}

/// Brute force over every triangle with precomputed `f64` ECEF vertices (Möller–Trumbore, both faces).
pub struct BruteForceTerrain {
    verts: Vec<[f64; 3]>,
    tris: Vec<[u32; 3]>,
}

impl BruteForceTerrain {
    /// Precomputes the vertices and the triangle list.
    pub fn new(dem: &Dem) -> BruteForceTerrain {
        let (verts, tris) = ecef_mesh(dem);
        BruteForceTerrain { verts, tris }
    }

    /// The nearest hit parameter within `[t_min, t_max]`.
    pub fn pick(&self, r: &RaySpec) -> Option<f64> {
        let (t0, t1) = (r.t_min, r.t_max_or_inf());
        let mut best: Option<f64> = None;
        for t in &self.tris {
            let v = t.map(|k| self.verts[k as usize]);
            if let Some(x) = moller_trumbore(&r.origin, &r.dir, &v)
                && x >= t0
                && x <= t1
                && best.is_none_or(|b| x < b)
            {
                best = Some(x);
            }
        }
        best
    }

    /// Bytes of the vertex and triangle arrays.
    pub fn memory_bytes(&self) -> usize {
        self.verts.len() * 24 + self.tris.len() * 12
    }
}
