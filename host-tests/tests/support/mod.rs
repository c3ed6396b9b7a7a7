//! What the integration tests share, written once: the one way to run the `curvicast` binary, scratch files and
//! directories, uniform breakpoints, the readers of the command's outputs, and the shard of a long suite. Each test
//! binary (`tests/<subject>/main.rs`) includes this module; not every binary uses every item.
#![allow(dead_code)]

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

/// The product's `curvicast` command (built in this package as `curvicast-product`, the same code: Cargo gives a
/// test the paths of its own package's binaries only).
pub const CURVICAST: &str = env!("CARGO_BIN_EXE_curvicast-product");
/// The harness's report command.
pub const REPORT: &str = env!("CARGO_BIN_EXE_curvicast-report");
/// The harness's marching-oracle command.
pub const MARCH_ORACLE: &str = env!("CARGO_BIN_EXE_curvicast-march-oracle");

/// The `curvicast` binary as a [`Command`] to configure, for a test that drives a live child (streaming, a closed
/// pipe, a full disk). A test that runs the command to the end uses [`run`] or [`run_in`].
pub fn command() -> Command {
    Command::new(CURVICAST)
}

/// Runs `curvicast ARGS` to the end with `stdin` as its input: (exit code, stdout, stderr).
pub fn run(args: &[&str], stdin: impl AsRef<[u8]>) -> (i32, String, String) {
    run_in(None, args, stdin)
}

/// [`run`] in the working directory `cwd` (`None`: the test's own). The input is written from a thread, so that
/// a child whose stdout pipe is full cannot block the write; a child that exits without reading all of its input
/// (it rejected its files) leaves a broken pipe, which is not an error.
pub fn run_in(cwd: Option<&Path>, args: &[&str], stdin: impl AsRef<[u8]>) -> (i32, String, String) {
    run_program(CURVICAST, cwd, args, stdin)
}

/// [`run_in`] for any of this project's commands ([`CURVICAST`], [`REPORT`], [`MARCH_ORACLE`]).
pub fn run_program(
    program: &str,
    cwd: Option<&Path>,
    args: &[&str],
    stdin: impl AsRef<[u8]>,
) -> (i32, String, String) {
    let mut command = Command::new(program);
    if let Some(dir) = cwd {
        command.current_dir(dir);
    }
    let mut child = command
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut si = child.stdin.take().unwrap();
    let input = stdin.as_ref().to_vec();
    let feeder = std::thread::spawn(move || si.write_all(&input));
    let out = child.wait_with_output().unwrap();
    if let Err(e) = feeder.join().unwrap() {
        assert_eq!(
            e.kind(),
            std::io::ErrorKind::BrokenPipe,
            "writing stdin: {e}"
        );
    }
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// A fresh temporary directory named after `name`, removed with everything in it when the guard drops.
pub fn temp_dir(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("curvicast-{name}-"))
        .tempdir()
        .unwrap()
}

/// A fresh file holding `text` whose name ends in `name` (so that its extension counts), removed when the returned
/// path drops.
pub fn temp_file(name: &str, text: impl AsRef<[u8]>) -> tempfile::TempPath {
    let p = tempfile::Builder::new()
        .prefix("curvicast-")
        .suffix(&format!("-{name}"))
        .tempfile()
        .unwrap()
        .into_temp_path();
    std::fs::write(&p, text).unwrap();
    p
}

/// `n + 1` breakpoints from `lo` to `hi`, evenly spaced.
pub fn uniform(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect()
}

/// A file of little-endian f64 values (`render`'s raw image, a per-cell data file).
pub fn read_f64(p: &Path) -> Vec<f64> {
    std::fs::read(p)
        .unwrap()
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// Each line of the command's output as JSON.
pub fn json_lines(out: &str) -> Vec<serde_json::Value> {
    out.lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect()
}

/// The shard of a long suite this run takes. `CURVICAST_LONG_SHARD=k/n` keeps the items whose index is `k`
/// modulo `n` (CI's long step runs shard `commits mod n` of each full suite, so that every item runs once every
/// `n` commits); unset, every item. A malformed value is an error, not a silent full run.
pub fn long_shard<T>(items: Vec<T>) -> Vec<T> {
    let Ok(spec) = std::env::var("CURVICAST_LONG_SHARD") else {
        return items;
    };
    let (k, n) = spec
        .split_once('/')
        .and_then(|(k, n)| Some((k.parse::<usize>().ok()?, n.parse::<usize>().ok()?)))
        .filter(|&(k, n)| k < n)
        .unwrap_or_else(|| panic!("CURVICAST_LONG_SHARD={spec}: expected k/n with k < n"));
    println!("long suite: shard {k}/{n}");
    items
        .into_iter()
        .enumerate()
        .filter(|(i, _)| i % n == k)
        .map(|(_, x)| x)
        .collect()
}
