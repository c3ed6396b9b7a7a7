//! The "Embedded" section: the kernel on an emulated Cortex-M4F (code size, instructions per crossing or per pick,
//! stack), from the M4F firmwares of `kernel/m4f-bench`.
//!
//! The report does not run QEMU. It includes, at build time, the table that `kernel/m4f-bench/run.sh` last wrote
//! to `kernel/m4f-bench/embedded.md` (CI runs that script and prints the same table), and says so.

use super::{Options, Section};

/// The table as `run.sh` wrote it (its own heading first).
const EMBEDDED_MD: &str = include_str!("../../../kernel/m4f-bench/embedded.md");

/// The section: where the numbers come from, how to regenerate them, then the committed table and its notes.
pub fn section(_opts: &Options) -> anyhow::Result<Section> {
    // `run.sh` starts the file with a heading of its own; the section's title replaces it.
    let body = match EMBEDDED_MD.split_once('\n') {
        Some((first, rest)) if first.starts_with('#') => rest.trim_start(),
        _ => EMBEDDED_MD,
    };
    let mut md = String::from(
        "Not measured by this report: the table below is `kernel/m4f-bench/embedded.md`, written by \
         `kernel/m4f-bench/run.sh` when it last ran (CI runs it in its step \"M4F firmwares\" and prints the same \
         numbers) and included here as committed. It comes from minimal firmwares, one per kernel feature, built for \
         a Cortex-M4F (`thumbv7em-none-eabihf`) and run on QEMU's `mps2-an386` with instruction counting. To \
         regenerate it: `rustup target add thumbv7em-none-eabihf`, `rustup component add llvm-tools`, install \
         `qemu-system-arm`, then `kernel/m4f-bench/run.sh`.\n\n",
    );
    md.push_str(body);
    if !md.ends_with('\n') {
        md.push('\n');
    }
    Ok(Section {
        title: "Embedded: the kernel on an emulated Cortex-M4F".into(),
        markdown: md,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_section_holds_the_committed_table_without_its_heading() {
        let opts = Options {
            quick: true,
            out_dir: std::env::temp_dir(),
        };
        let s = section(&opts).unwrap();
        assert!(s.markdown.contains("| firmware (minus its baseline) |"));
        assert!(s.markdown.contains("| march-f32, "));
        assert!(s.markdown.contains("kernel/m4f-bench/run.sh"));
        assert!(!s.markdown.contains("### Embedded"));
    }
}
