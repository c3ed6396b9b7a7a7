//! Embree 3 (the reference CPU ray tracer, through the `embree3` crate) over the DEM's triangles: what a user who
//! wants speed would pick. Embree takes `f32` vertices and rays, so it is built twice: once in ECEF metres, and
//! once in a local frame centred on the DEM (the vertices and the ray origins shifted by the DEM's centre in
//! `f64`, then rounded to `f32`: what a careful Embree user does). Both faces count, as in the contract (Embree's
//! default build does not cull back faces).

use super::terrain::ecef_mesh;
use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::Dem;
use embree3::{BufferUsage, Device, Format, GeometryKind, IntersectContext, Ray, RayHit, Scene};
use std::sync::Arc;
use std::sync::atomic::{AtomicIsize, Ordering};

/// Where Embree's `f32` coordinates are measured from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    /// ECEF metres as they are.
    Ecef,
    /// ECEF metres minus the DEM's centre vertex (subtracted in `f64`).
    Local,
}

impl Frame {
    /// The name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Frame::Ecef => "ECEF",
            Frame::Local => "local frame",
        }
    }
}

/// An Embree scene over a DEM's triangles.
pub struct EmbreeTerrain {
    scene: Scene<'static>,
    /// Subtracted from every vertex and ray origin before rounding to `f32`.
    offset: [f64; 3],
    /// Embree's own accounting (its memory monitor callback): bytes allocated and not yet freed.
    bytes: Arc<AtomicIsize>,
    _device: Device,
}

impl EmbreeTerrain {
    /// Builds the scene (a triangle geometry with Embree's default build quality) in `frame`. Missing vertices
    /// (NaN) are replaced by the offset and never indexed.
    pub fn new(dem: &Dem, frame: Frame) -> anyhow::Result<EmbreeTerrain> {
        let (verts, tris) = ecef_mesh(dem);
        let offset = match frame {
            Frame::Ecef => [0.0; 3],
            Frame::Local => dem
                .vertex_ecef(dem.rows / 2, dem.cols / 2)
                .or_else(|| verts.iter().copied().find(|v| !v[0].is_nan()))
                .unwrap_or([0.0; 3]),
        };
        let err = |what: &str, e: embree3::Error| anyhow::anyhow!("Embree: {what}: {e:?}");
        let device = Device::new().map_err(|e| err("device", e))?;
        let bytes = Arc::new(AtomicIsize::new(0));
        let counter = Arc::clone(&bytes);
        // Each allocation and release is reported once, before or after it happens (`post`); none is cancelled.
        device.set_memory_monitor_function(move |b, _post| {
            counter.fetch_add(b, Ordering::Relaxed);
            true
        });
        let mut geometry = device
            .create_geometry(GeometryKind::TRIANGLE)
            .map_err(|e| err("geometry", e))?;
        geometry
            .set_new_buffer::<[f32; 3]>(BufferUsage::VERTEX, 0, Format::FLOAT3, 12, verts.len())
            .map_err(|e| err("vertex buffer", e))?
            .copy_from_slice(
                &verts
                    .iter()
                    .map(|v| {
                        if v[0].is_nan() {
                            [0.0; 3]
                        } else {
                            [0, 1, 2].map(|k| (v[k] - offset[k]) as f32)
                        }
                    })
                    .collect::<Vec<_>>(),
            );
        geometry
            .set_new_buffer::<[u32; 3]>(BufferUsage::INDEX, 0, Format::UINT3, 12, tris.len())
            .map_err(|e| err("index buffer", e))?
            .copy_from_slice(&tris);
        let geometry = geometry.commit();
        let mut scene = device.create_scene().map_err(|e| err("scene", e))?;
        scene.attach_geometry(&geometry);
        scene.commit();
        Ok(EmbreeTerrain {
            scene,
            offset,
            bytes,
            _device: device,
        })
    }

    /// The nearest hit parameter over `[t_min, t_max]` (in units of the ray's direction, as the caller gave it),
    /// traced as Embree's `f32` ray: origin shifted by the frame's offset in `f64`, then rounded.
    pub fn pick(&self, r: &RaySpec) -> Option<f64> {
        let origin = [0, 1, 2].map(|k| (r.origin[k] - self.offset[k]) as f32);
        let dir = r.dir.map(|x| x as f32);
        let mut hit = RayHit::from(Ray::new(
            origin,
            dir,
            r.t_min as f32,
            r.t_max_or_inf() as f32,
            0.0,
            u32::MAX,
            0,
        ));
        let mut ctx = IntersectContext::incoherent();
        self.scene.intersect(&mut ctx, &mut hit);
        hit.hit.is_valid().then_some(f64::from(hit.ray.tfar))
    }

    /// The bytes Embree holds for the scene (vertices, indices, BVH), by its own memory monitor.
    pub fn memory_bytes(&self) -> usize {
        usize::try_from(self.bytes.load(Ordering::Relaxed)).unwrap_or(0)
    }
}
