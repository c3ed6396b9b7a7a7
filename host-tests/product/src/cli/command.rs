//! The `curvicast` command: its arguments (clap) and the dispatch to the subcommands, with the exit codes of
//! [`super::exit`].

use super::exit;
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "curvicast",
    version,
    about = "Ray casting through curved coordinate systems"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Edge-beveled sphere or ellipsoid as OBJ: (--sphere R | --ellipsoid A B C)
    /// (--level K | --max-angle-deg X | --max-deviation E) --out FILE.obj
    Tessellate {
        /// The options above (parsed by the subcommand itself, so that every error is one line).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// Nearest hit of each ray with a DEM's triangle surface (ECEF meters; see the command-line contract).
    Pick {
        /// The TERRAIN.json file.
        #[arg(long, required_unless_present = "dem", conflicts_with = "dem")]
        terrain: Option<PathBuf>,
        /// A DEM file instead of --terrain: SRTM .hgt, single-band geographic GeoTIFF, or .dem.cc.
        #[arg(long)]
        dem: Option<PathBuf>,
        /// Rays (JSON Lines); standard input without it.
        #[arg(long)]
        rays: Option<PathBuf>,
        /// Coarsest quadtree level whose blocks may stand in for missing finer ones (multi-resolution terrain;
        /// between 0 and the tree's depth).
        #[arg(long, default_value_t = 0)]
        min_level: u32,
        /// Cells per block side (1 to 1024).
        #[arg(long, default_value_t = 16)]
        block: usize,
        /// Multi-resolution tree: full resolution only in this box (LAT_S,LAT_N,LON_W,LON_E, degrees); elsewhere
        /// branches end at --coarse-level.
        #[arg(
            long,
            value_name = "LAT_S,LAT_N,LON_W,LON_E",
            allow_hyphen_values = true
        )]
        fine_region: Option<String>,
        /// Pyramid level (0 = full resolution, each level doubles the block spacing) where branches outside
        /// --fine-region end (default 2).
        #[arg(long)]
        coarse_level: Option<u32>,
        /// Multi-resolution tree with the blocks of these quadtree levels not resident (comma-separated; zones
        /// are level 0).
        #[arg(long, value_name = "L,L,..")]
        non_resident_levels: Option<String>,
        /// Multi-resolution tree with the blocks of the nodes inside this box not resident.
        #[arg(
            long,
            value_name = "LAT_S,LAT_N,LON_W,LON_E",
            allow_hyphen_values = true
        )]
        non_resident_region: Option<String>,
        /// Report a needed block as an error line instead of paging it in and asking again.
        #[arg(long)]
        no_paging: bool,
    },
    /// March rays through a spherical, cylindrical or polar grid: one JSON line of cell crossings per ray.
    March {
        /// The grid file (JSON).
        #[arg(long)]
        grid: PathBuf,
        /// The rays file (JSON Lines); standard input when absent.
        #[arg(long)]
        rays: Option<PathBuf>,
        /// The engine.
        #[arg(long, value_enum, default_value = "serial")]
        engine: crate::precision::Engine,
        /// The scalar type.
        #[arg(long, value_enum, default_value = "f64")]
        precision: crate::precision::Precision,
    },
    /// Render a field on a spherical, cylindrical or polar grid: DIR/image.png, values.f32 and render.json.
    Render {
        /// The SCENE.json file.
        #[arg(long)]
        scene: PathBuf,
        /// The output directory.
        #[arg(long)]
        out: PathBuf,
    },
}

/// Runs the `curvicast` command on this process's arguments: the product's `main`, and the harness's
/// `curvicast-product` (the same command, built in the harness's package so that its tests can run it).
pub fn main() -> ExitCode {
    let cli: Cli = match exit::parse("curvicast") {
        Ok(c) => c,
        Err(code) => return code,
    };
    let result = match cli.command {
        Command::Pick {
            terrain,
            dem,
            rays,
            min_level,
            block,
            fine_region,
            coarse_level,
            non_resident_levels,
            non_resident_region,
            no_paging,
        } => {
            use super::pick::TerrainSource;
            let args = super::pick::PickArgs {
                terrain: match (terrain, dem) {
                    (Some(t), _) => TerrainSource::Terrain(t),
                    (None, d) => TerrainSource::Dem(d.unwrap_or_default()),
                },
                rays,
                min_level,
                block,
                multires: super::pick::MultiResArgs {
                    fine_region,
                    coarse_level,
                    non_resident_levels,
                    non_resident_region,
                    no_paging,
                },
            };
            let mut out = std::io::stdout().lock();
            super::pick::run(&args, &mut out).map_err(anyhow::Error::from)
        }
        Command::Tessellate { args } => super::tessellate::run(&args),
        Command::March {
            grid,
            rays,
            engine,
            precision,
        } => super::march::run(
            &super::march::MarchArgs {
                grid,
                rays,
                engine,
                precision,
            },
            &mut std::io::stdout().lock(),
        ),
        Command::Render { scene, out } => {
            super::render::run(&super::render::RenderArgs { scene, out })
        }
    };
    exit::exit_code(result, "curvicast")
}
