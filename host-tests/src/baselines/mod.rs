//! Baselines: what a user would otherwise do, measured in the same run as the kernel. The Cartesian resampling
//! with Amanatides–Woo is part of the product (`curvicast render`'s `{"cartesian": N}` method,
//! `curvicast_cli::render::dda`); the general mesh ray casters and the brute force are here.

use curvicast_cli::formats::spec::RaySpec;
use curvicast_cli::formats::terrain::Dem;

#[cfg(feature = "embree")]
pub mod embree;
pub mod terrain;

/// A nearest-hit query: the ray parameter of the hit over the ray's `[t_min, t_max]`, or a miss.
pub type PickFn<'a> = Box<dyn Fn(&RaySpec) -> Option<f64> + 'a>;

/// A terrain baseline built over one DEM: its nearest-hit query (the ray parameter, or a miss), its memory, and
/// how long it took to build.
pub struct TerrainBaseline<'a> {
    /// Its name in the report.
    pub name: String,
    /// Its nearest-hit query.
    pub pick: PickFn<'a>,
    /// Bytes it holds (its own accounting).
    pub memory_bytes: usize,
    /// Seconds its build took.
    pub build_seconds: f64,
}

/// The Embree baselines of `dem` (ECEF and local frame) when the harness is built with `--features embree`;
/// none otherwise.
pub fn embree_baselines(dem: &Dem) -> anyhow::Result<Vec<TerrainBaseline<'static>>> {
    #[cfg(feature = "embree")]
    {
        [embree::Frame::Ecef, embree::Frame::Local]
            .into_iter()
            .map(|frame| {
                let t0 = std::time::Instant::now();
                let scene = embree::EmbreeTerrain::new(dem, frame)?;
                let build_seconds = t0.elapsed().as_secs_f64();
                Ok(TerrainBaseline {
                    name: format!("Embree {}", frame.name()),
                    memory_bytes: scene.memory_bytes(),
                    build_seconds,
                    pick: Box::new(move |r| scene.pick(r)),
                })
            })
            .collect()
    }
    #[cfg(not(feature = "embree"))]
    {
        let _ = dem;
        Ok(Vec::new())
    }
}
