//! What the integration tests share: one way to run the `curvicast` binary, and the shard of a long suite.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

/// Runs `curvicast ARGS` to the end with `stdin` as its input, written from a thread (so that a child whose
/// stdout pipe is full cannot block the write): (exit code, stdout, stderr). A child that exits without reading
/// all of its input (it rejected its files) leaves a broken pipe, which is not an error.
#[allow(dead_code)] // each test binary uses one of the two
pub fn run(args: &[&str], stdin: &str) -> (i32, String, String) {
    run_in(None, args, stdin)
}

/// [`run`] in the working directory `cwd` (`None`: the test's own).
#[allow(dead_code)] // not every test binary runs the command
pub fn run_in(cwd: Option<&Path>, args: &[&str], stdin: &str) -> (i32, String, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_curvicast"));
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
    let input = stdin.to_owned();
    let feeder = std::thread::spawn(move || si.write_all(input.as_bytes()));
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

/// The shard of a long suite this run takes. `CURVICAST_LONG_SHARD=k/n` keeps the items whose index is `k`
/// modulo `n` (CI's long step runs shard `commits mod n` of each full suite, so that every item runs once every
/// `n` commits); unset, every item. A malformed value is an error, not a silent full run.
#[allow(dead_code)] // not every test binary has a long suite
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
