//! `curvicast march` and `pick` stream (command-line contract): answers come out while rays are still arriving,
//! bad lines are reported with their own line number, long answers stream, and errors on output end the command
//! with one line (or silently for a closed pipe), never a panic.

use crate::support::{command, json_lines, run, temp_dir as dir};
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, Stdio};
use std::sync::mpsc;
use std::time::Duration;

fn write(d: &std::path::Path, name: &str, bytes: &[u8]) -> String {
    let p = d.join(name);
    std::fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_string()
}

const SPHERE: &str = r#"{"kind": "spherical", "r": [0.0, 0.5, 1.0], "theta": [0.0, 1.5707963267948966, 3.141592653589793], "phi": [0.0, 3.141592653589793, 6.283185307179586]}"#;
const RAY: &str = r#"{"origin": [-2, 0.1, 0.25], "dir": [1, 0, 0]}"#;

/// A 3 × 3 terrain of inline heights near 36°N 118°W and a ray straight down onto its middle vertex.
const TERRAIN: &str = r#"{"ellipsoid": "WGS84", "grid": {"lat0": 36.0, "lon0": -118.0, "dlat": 0.001, "dlon": 0.001,
 "rows": 3, "cols": 3, "heights_inline": [100, 110, 120, 105, 115, 125, 110, 120, 130]}}"#;

fn down_ray() -> String {
    // ECEF of (36.001°N, −117.999°W, 1000 m) and the direction to (…, 0 m): computed here in f64.
    let (a, b) = (6_378_137.0_f64, 6_356_752.314_245_179_f64);
    let ecef = |lat: f64, lon: f64, h: f64| {
        let (sp, cp) = lat.to_radians().sin_cos();
        let (sl, cl) = lon.to_radians().sin_cos();
        let n = a * a / ((a * cp).hypot(b * sp));
        [
            (n + h) * cp * cl,
            (n + h) * cp * sl,
            (n * b * b / (a * a) + h) * sp,
        ]
    };
    let p = ecef(36.001, -117.999, 1000.0);
    let q = ecef(36.001, -117.999, 0.0);
    format!(
        r#"{{"origin": [{}, {}, {}], "dir": [{}, {}, {}]}}"#,
        p[0],
        p[1],
        p[2],
        q[0] - p[0],
        q[1] - p[1],
        q[2] - p[2]
    )
}

fn spawn(args: &[&str], stdout: Stdio) -> Child {
    command()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Feeds one ray, waits for its answer, then feeds the next: the command must answer each ray while standard
/// input is still open. (The wait is a guard against a hang, not a timing criterion.)
fn answers_arrive_while_input_is_open(args: &[&str], ray: &str) {
    let mut child = spawn(args, Stdio::piped());
    let mut stdin = child.stdin.take().unwrap();
    let stdout = child.stdout.take().unwrap();
    let (tx, rx) = mpsc::channel();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            if tx.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    for k in 0..3 {
        writeln!(stdin, "{ray}").unwrap();
        stdin.flush().unwrap();
        let line = rx
            .recv_timeout(Duration::from_secs(120))
            .unwrap_or_else(|_| {
                let _ = child.kill();
                panic!("no answer to ray {k} while standard input is still open")
            });
        let v: serde_json::Value = serde_json::from_str(&line).unwrap();
        assert_eq!(v["ray"], k, "{line}");
        assert!(v.get("error").is_none(), "{line}");
    }
    drop(stdin);
    let status = child.wait().unwrap();
    reader.join().unwrap();
    assert!(status.success());
    assert!(
        rx.try_recv().is_err(),
        "one answer per ray, no more after input ends"
    );
}

#[test]
fn march_answers_each_ray_piped_in_before_the_next_arrives() {
    let tmp = dir("march-pipe");
    let d = tmp.path();
    let g = write(d, "grid.json", SPHERE.as_bytes());
    answers_arrive_while_input_is_open(&["march", "--grid", &g], RAY);
    answers_arrive_while_input_is_open(&["march", "--grid", &g, "--engine", "separable"], RAY);
}

#[test]
fn pick_answers_each_ray_piped_in_before_the_next_arrives() {
    let tmp = dir("pick-pipe");
    let d = tmp.path();
    let t = write(d, "terrain.json", TERRAIN.as_bytes());
    answers_arrive_while_input_is_open(&["pick", "--terrain", &t], &down_ray());
}

#[test]
fn nan_in_line_2_is_reported_as_line_2_and_blank_lines_keep_their_numbers() {
    let tmp = dir("nan");
    let d = tmp.path();
    let g = write(d, "grid.json", SPHERE.as_bytes());
    let t = write(d, "terrain.json", TERRAIN.as_bytes());
    let nan = r#"{"origin": [NaN, 0, 0], "dir": [1, 0, 0]}"#;
    let input = format!("{RAY}\n{nan}\n\n{nan}\n");
    for (args, good) in [
        (vec!["march", "--grid", &g], RAY.to_string()),
        (vec!["pick", "--terrain", &t], down_ray()),
    ] {
        let input = input.replace(RAY, &good);
        let (code, out, err) = run(&args, input.as_bytes());
        assert_eq!(code, 0, "{err}");
        let lines = json_lines(&out);
        assert_eq!(lines.len(), 3, "{out}");
        let e1 = lines[1]["error"].as_str().unwrap();
        assert!(e1.starts_with("line 2 column 13: invalid ray"), "{e1}");
        assert_eq!(lines[1]["ray"], 1);
        let e2 = lines[2]["error"].as_str().unwrap();
        assert!(
            e2.starts_with("line 4 column 13:"),
            "a blank line counts as a line, not a ray: {e2}"
        );
        assert_eq!(lines[2]["ray"], 2);
    }
}

#[test]
fn rays_file_starting_with_a_utf8_byte_order_mark_is_accepted() {
    let tmp = dir("bom");
    let d = tmp.path();
    let g = write(d, "grid.json", SPHERE.as_bytes());
    let rays = write(
        d,
        "rays.jsonl",
        format!("\u{FEFF}{RAY}\r\n{RAY}\r\n").as_bytes(),
    );
    let (code, out, err) = run(&["march", "--grid", &g, "--rays", &rays], b"");
    assert_eq!(code, 0, "{err}");
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 2);
    assert_eq!((&lines[0]["ray"], &lines[1]["ray"]), (&0.into(), &1.into()));
    assert_eq!(lines[0]["crossings"], lines[1]["crossings"], "{out}");
    assert_eq!(lines[0]["crossings"].as_array().unwrap().len(), 3);
}

#[test]
fn malformed_line_1000_after_999_answers_is_that_rays_error_line() {
    let tmp = dir("line1000");
    let d = tmp.path();
    let g = write(d, "grid.json", SPHERE.as_bytes());
    let mut text = String::new();
    for _ in 0..999 {
        text.push_str(RAY);
        text.push('\n');
    }
    text.push_str("{\"origin\": [1, 2\n");
    text.push_str(RAY);
    text.push('\n');
    let rays = write(d, "rays.jsonl", text.as_bytes());
    let (code, out, err) = run(&["march", "--grid", &g, "--rays", &rays], b"");
    assert_eq!(code, 0, "{err}");
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 1001);
    for (k, l) in lines.iter().enumerate() {
        assert_eq!(l["ray"], k);
        assert_eq!(l.get("error").is_some(), k == 999, "{l}");
    }
    let e = lines[999]["error"].as_str().unwrap();
    assert!(
        e.starts_with("line 1000 column 16: invalid ray: EOF while parsing"),
        "{e}"
    );
}

#[test]
fn line_longer_than_the_limit_is_an_error_for_that_ray_only() {
    let tmp = dir("long");
    let d = tmp.path();
    let g = write(d, "grid.json", SPHERE.as_bytes());
    let long = format!("{{\"origin\": [{}0, 0, 0]}}", "0".repeat(200_000));
    let input = format!("{RAY}\n{long}\n{RAY}\n");
    let (code, out, err) = run(&["march", "--grid", &g], input.as_bytes());
    assert_eq!(code, 0, "{err}");
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 3);
    assert!(
        lines[1]["error"]
            .as_str()
            .unwrap()
            .starts_with("line 2: invalid ray: longer than")
    );
    assert_eq!(lines[2]["crossings"], lines[0]["crossings"]);
}

#[test]
fn unreadable_rays_file_exits_2_with_one_line_naming_it() {
    let tmp = dir("unreadable");
    let d = tmp.path();
    let g = write(d, "grid.json", SPHERE.as_bytes());
    for rays in [
        d.to_str().unwrap().to_string(),
        d.join("missing.jsonl").to_str().unwrap().to_string(),
    ] {
        let (code, out, err) = run(&["march", "--grid", &g, "--rays", &rays], b"");
        assert_eq!(code, 2, "{err}");
        assert!(out.is_empty(), "{out}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(&rays), "{err}");
    }
}

fn many_rays(d: &std::path::Path, ray: &str, n: usize) -> String {
    let mut text = String::with_capacity(n * (ray.len() + 1));
    for _ in 0..n {
        text.push_str(ray);
        text.push('\n');
    }
    write(d, "many.jsonl", text.as_bytes())
}

#[test]
fn closed_output_pipe_ends_march_and_pick_silently() {
    let tmp = dir("head");
    let d = tmp.path();
    let g = write(d, "grid.json", SPHERE.as_bytes());
    let t = write(d, "terrain.json", TERRAIN.as_bytes());
    let march_rays = many_rays(d, RAY, 200_000);
    let pick_rays = write(
        d,
        "pick.jsonl",
        format!("{}\n", down_ray()).repeat(50_000).as_bytes(),
    );
    for args in [
        vec!["march", "--grid", &g, "--rays", &march_rays],
        vec!["pick", "--terrain", &t, "--rays", &pick_rays],
    ] {
        // `curvicast … | head -1`: read one line, then close the pipe.
        let mut child = spawn(&args, Stdio::piped());
        drop(child.stdin.take());
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut first = String::new();
        stdout.read_line(&mut first).unwrap();
        let v: serde_json::Value = serde_json::from_str(&first).unwrap();
        assert_eq!(v["ray"], 0, "{first}");
        drop(stdout);
        let status = child.wait().unwrap();
        let mut err = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        assert!(err.is_empty(), "{args:?}: {err}");
        assert_eq!(status.code(), Some(0), "{args:?}");
    }
}

#[test]
fn full_disk_on_output_is_one_line_on_stderr_not_a_panic() {
    let tmp = dir("full");
    let d = tmp.path();
    let g = write(d, "grid.json", SPHERE.as_bytes());
    let t = write(d, "terrain.json", TERRAIN.as_bytes());
    let ray = down_ray();
    for (args, input) in [
        (vec!["march", "--grid", &g], RAY),
        (vec!["pick", "--terrain", &t], ray.as_str()),
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let mut child = spawn(&args, Stdio::from(full));
        let mut si = child.stdin.take().unwrap();
        let input = format!("{input}\n").repeat(1000);
        let feeder = std::thread::spawn(move || si.write_all(input.as_bytes()));
        let out = child.wait_with_output().unwrap();
        let _ = feeder.join().unwrap();
        let err = String::from_utf8(out.stderr).unwrap();
        // An output error exits 1 in every subcommand (the contract), a bad input 2.
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains("No space left on device"), "{err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

/// A grid of 50 000 radii: one ray's answer (up to 100 000 crossings, 8 MB of JSON) is longer than the window
/// of answers held in memory, so it is streamed as the march produces it. It must still be one well-formed line
/// per ray, in order, with touching crossings that change one index at a time.
#[test]
fn ray_through_50_000_radii_streams_one_complete_line_per_ray() {
    let tmp = dir("radii");
    let d = tmp.path();
    let n = 50_000;
    let r: Vec<String> = (0..=n)
        .map(|k| format!("{}", k as f64 / n as f64))
        .collect();
    let grid = format!(
        r#"{{"kind": "spherical", "r": [{}], "theta": [0.0, 3.141592653589793], "phi": [0.0, 6.283185307179586]}}"#,
        r.join(",")
    );
    let g = write(d, "grid.json", grid.as_bytes());
    // At distance 0.25 + 0.5/n from the center: between two breakpoints, so no tangent shell.
    let dist = 0.25 + 0.5 / n as f64;
    let ray_b = format!(r#"{{"origin": [-2, {dist}, 0.0], "dir": [1, 0, 0]}}"#);
    let input = format!("{RAY}\n{ray_b}\n{RAY}\n");
    let (code, out, err) = run(&["march", "--grid", &g], input.as_bytes());
    assert_eq!(code, 0, "{err}");
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 3);
    for (k, l) in lines.iter().enumerate() {
        assert_eq!(l["ray"], k);
        let cs = l["crossings"].as_array().unwrap();
        for w in cs.windows(2) {
            assert_eq!(w[0]["t_exit"], w[1]["t_enter"], "ray {k}: crossings touch");
            let (a, b) = (
                w[0]["cell"][0].as_i64().unwrap(),
                w[1]["cell"][0].as_i64().unwrap(),
            );
            assert!((a - b).abs() <= 1, "ray {k}: one radius step at a time");
        }
    }
    // The second ray crosses every shell above r = 0.25 twice, except the innermost one it passes through
    // once: 2·(n − n/4) − 1 cells.
    let b = lines[1]["crossings"].as_array().unwrap();
    assert_eq!(b.len(), 2 * (n - n / 4) - 1);
    let t0 = b[0]["t_enter"].as_f64().unwrap();
    assert!(
        (t0 - (2.0 - (1.0 - dist * dist).sqrt())).abs() < 1e-9,
        "{t0}"
    );
}
