//! What the integration tests share: one way to run the `curvicast` binary.

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
