//! The report: speed-against-error tables for every mode of the kernel, written to stdout and `DIR/report.md`,
//! with the SVG charts ([`plot`]) and PNG images it links written beside it.
//!
//! Each section lives in its own module and returns a [`Section`]; [`run`] runs them in order.

pub mod embedded;
pub mod march;
pub mod plot;
pub mod render;
pub mod surfaces;
pub mod terrain;
pub mod terrain_multires;
pub mod tessellate;

use std::path::Path;

/// One section of the report.
#[derive(Debug, Clone, Default)]
pub struct Section {
    /// The heading.
    pub title: String,
    /// Markdown body (tables, notes, links to files written into the output directory).
    pub markdown: String,
}

/// Options shared by all sections.
#[derive(Debug, Clone)]
pub struct Options {
    /// Small sizes: the whole report in under a minute on two cores.
    pub quick: bool,
    /// Where files (plots, images) go.
    pub out_dir: std::path::PathBuf,
}

/// Runs every section, prints each to stdout as it completes, and writes `report.md` into `opts.out_dir`.
///
/// An error on standard output (a closed pipe, a full disk) stops the printing but not the report: `report.md` is
/// written, then the error is returned as a [`curvicast_cli::cli::OutputError`].
pub fn run(opts: &Options) -> anyhow::Result<Vec<Section>> {
    let started = std::time::Instant::now();
    std::fs::create_dir_all(&opts.out_dir).map_err(|e| {
        anyhow::anyhow!(
            "{}: cannot create the output directory: {e}",
            opts.out_dir.display()
        )
    })?;
    let mut stdout = curvicast_cli::cli::Stdout::default();
    type SectionFn = fn(&Options) -> anyhow::Result<Section>;
    let sections: &[SectionFn] = &[
        surfaces::section,
        march::section,
        terrain::section,
        terrain_multires::section,
        tessellate::section,
        render::section,
        embedded::section,
        crate::tolerances::section,
    ];
    let mut done = Vec::new();
    let mut md = String::from("# curvicast report\n\n");
    md.push_str(&format!(
        "Mode: {}.\n\n",
        if opts.quick { "quick" } else { "full" }
    ));
    for f in sections {
        let s = f(opts)?;
        stdout.print(&format!("## {}\n\n{}\n", s.title, s.markdown));
        md.push_str(&format!("## {}\n\n{}\n", s.title, s.markdown));
        done.push(s);
    }
    let total = format!(
        "The whole report took {:.1} s of wall-clock time ({} mode).\n",
        started.elapsed().as_secs_f64(),
        if opts.quick { "quick" } else { "full" }
    );
    stdout.print(&format!("{total}\n"));
    md.push_str(&total);
    write(&opts.out_dir.join("report.md"), &md)?;
    stdout.finish()?;
    Ok(done)
}

fn write(path: &Path, text: &str) -> anyhow::Result<()> {
    std::fs::write(path, text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}
