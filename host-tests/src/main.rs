//! The `curvicast` command: `report`, `tessellate`, `pick`, `march` and `march-oracle`.
//! See the command-line contract, docs/formats.md.
//!
//! Exit codes: 0 done (also when standard output is a closed pipe), 2 a malformed argument or input file (one line
//! on stderr), 1 an error writing the output of `report`, `tessellate` or `march-oracle`, or `march-oracle` failing its
//! criterion.

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
    /// Run the scene suite: speed-against-error tables on stdout, report.md and plots in DIR.
    Report {
        /// Small sizes (under a minute on two cores).
        #[arg(long)]
        quick: bool,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
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
    /// Marching against the independent oracle on random rays over random grids (both engines, every precision);
    /// exit code 1 when an f64 ray fails the criterion or any list breaks the contract's invariants.
    MarchOracle {
        /// Number of random rays (20 per random grid).
        #[arg(long, default_value_t = 200_000)]
        rays: usize,
        /// Seed of the generator.
        #[arg(long, default_value_t = 7)]
        seed: u64,
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
        engine: curvicast_host::cli::march::Engine,
        /// The scalar type.
        #[arg(long, value_enum, default_value = "f64")]
        precision: curvicast_host::cli::march::Precision,
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

/// clap's error as the contract's one line (clap's own spans four or five: the message, a tip, the usage and a
/// pointer to `--help`).
fn one_line(e: &clap::Error) -> String {
    use clap::error::ErrorKind;
    let first = match e.kind() {
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let names: Vec<String> = <Cli as clap::CommandFactory>::command()
                .get_subcommands()
                .map(|c| c.get_name().to_string())
                .collect();
            format!("a subcommand is required ({})", names.join(", "))
        }
        _ => {
            // The message is the first paragraph (a list of missing arguments continues it on indented lines).
            let text = e.render().to_string();
            let paragraph: Vec<&str> = text
                .lines()
                .skip_while(|l| l.trim().is_empty())
                .take_while(|l| !l.trim().is_empty())
                .map(str::trim)
                .collect();
            let line = paragraph.join(" ");
            line.strip_prefix("error: ").unwrap_or(&line).to_string()
        }
    };
    format!("curvicast: {first}; see 'curvicast --help'")
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) if e.use_stderr() => {
            eprintln!("{}", one_line(&e));
            return ExitCode::from(2);
        }
        // --help and --version, on stdout; a failed write there (a closed pipe) is no reason to panic.
        Err(e) => {
            let _ = curvicast_host::cli::print_stdout(&e.render().to_string());
            return ExitCode::SUCCESS;
        }
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
            use curvicast_host::cli::pick::TerrainSource;
            let args = curvicast_host::cli::pick::PickArgs {
                terrain: match (terrain, dem) {
                    (Some(t), _) => TerrainSource::Terrain(t),
                    (None, d) => TerrainSource::Dem(d.unwrap_or_default()),
                },
                rays,
                min_level,
                block,
                multires: curvicast_host::cli::pick::MultiResArgs {
                    fine_region,
                    coarse_level,
                    non_resident_levels,
                    non_resident_region,
                    no_paging,
                },
            };
            let mut out = std::io::stdout().lock();
            curvicast_host::cli::pick::run(&args, &mut out).map_err(anyhow::Error::from)
        }
        Command::Report { quick, out } => {
            curvicast_host::report::run(&curvicast_host::report::Options {
                quick,
                out_dir: out,
            })
            .map(|_| ())
        }
        Command::Tessellate { args } => curvicast_host::cli::tessellate::run(&args),
        Command::MarchOracle { rays, seed } => {
            let (text, ok) = curvicast_host::report::march::oracle_suite_text(rays, seed);
            match curvicast_host::cli::print_stdout(&text) {
                Ok(()) if !ok => return ExitCode::from(1),
                Ok(()) => Ok(()),
                // A closed pipe ends quietly, with the suite's own exit code.
                Err(e) if e.is_closed_pipe() => return ExitCode::from(u8::from(!ok)),
                Err(e) => Err(e.into()),
            }
        }
        Command::March {
            grid,
            rays,
            engine,
            precision,
        } => curvicast_host::cli::march::run(
            &curvicast_host::cli::march::MarchArgs {
                grid,
                rays,
                engine,
                precision,
            },
            &mut std::io::stdout().lock(),
        ),
        Command::Render { scene, out } => {
            curvicast_host::cli::render::run(&curvicast_host::cli::render::RenderArgs {
                scene,
                out,
            })
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => match e
            .downcast_ref::<curvicast_host::cli::OutputError>()
            .or_else(|| {
                e.downcast_ref::<curvicast_host::cli::io::StreamError>()
                    .and_then(|s| s.output())
            }) {
            // The reader went away: end quietly, as Unix tools do.
            Some(out) if out.is_closed_pipe() => ExitCode::SUCCESS,
            Some(_) => {
                eprintln!("curvicast: {e:#}");
                ExitCode::from(1)
            }
            None => {
                eprintln!("curvicast: {e:#}");
                ExitCode::from(2)
            }
        },
    }
}
