//! The command's own rules, as the command-line contract states them: a malformed argument is one line on stderr,
//! exit code 2 and nothing on stdout (clap's errors included; `--help` and `--version` still print normally); an
//! error on output (a full disk) is one line and a non-zero exit, a closed pipe ends the command quietly, never a
//! panic; `tessellate` answers extreme radii right.

use crate::support::{MARCH_ORACLE, REPORT, command as cli, run, run_program};
use std::io::Read;
use std::process::Stdio;
use tempfile::TempPath;

/// A fresh empty file whose name ends in `name`, removed when the returned path drops.
fn scratch(name: &str) -> TempPath {
    crate::support::temp_file(name, "")
}

fn assert_usage_error(args: &[&str]) -> String {
    let (code, out, err) = run(args, "");
    assert_eq!(code, 2, "{args:?}: {err}");
    assert!(out.is_empty(), "{args:?}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

#[test]
fn clap_errors_are_one_line_with_exit_2() {
    for args in [
        &["--frobnicate"][..],
        &[],
        &["march"],
        &["march", "--grid"],
        &["march", "--grid", "g.json", "--engine", "warp"],
        &["pick", "--terrain", "t.json", "--block", "many"],
    ] {
        let err = assert_usage_error(args);
        assert!(err.starts_with("curvicast: "), "{err}");
    }
    // The harness's commands follow the same rule, under their own names.
    for (program, name, args) in [
        (REPORT, "curvicast-report", &["--quick", "--nonsense"][..]),
        (
            MARCH_ORACLE,
            "curvicast-march-oracle",
            &["--rays", "-3"][..],
        ),
    ] {
        let (code, out, err) = run_program(program, None, args, "");
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty() && err.lines().count() == 1, "{err}");
        assert!(err.starts_with(&format!("{name}: ")), "{err}");
    }
}

#[test]
fn help_and_version_still_print_on_stdout() {
    let (code, text, _) = run(&["--help"], "");
    assert_eq!(code, 0);
    assert!(text.contains("Usage") && text.lines().count() > 5, "{text}");
    let (code, text, _) = run(&["--version"], "");
    assert_eq!(code, 0);
    assert!(text.starts_with("curvicast "), "{text}");
}

#[test]
fn report_out_at_an_existing_file_names_the_path() {
    let file = scratch("not-a-directory");
    std::fs::write(&file, "x").unwrap();
    let args = ["--quick", "--out", file.to_str().unwrap()];
    let (code, out, err) = run_program(REPORT, None, &args, "");
    assert_eq!(
        (code, out.as_str(), err.lines().count()),
        (2, "", 1),
        "{err}"
    );
    assert!(err.contains(file.to_str().unwrap()), "{err}");
}

#[cfg(target_os = "linux")]
#[test]
fn tessellate_to_a_full_disk_is_one_line_and_exit_1() {
    let obj = scratch("full.obj");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = cli()
        .args(["tessellate", "--sphere", "1", "--level", "2", "--out"])
        .arg(&obj)
        .stdout(full)
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("standard output"), "{err}");
}

#[test]
fn tessellate_into_a_closed_pipe_ends_quietly() {
    let obj = scratch("pipe.obj");
    // The reader is gone before the command starts, so its summary must meet the closed pipe.
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let mut child = cli()
        .args(["tessellate", "--sphere", "1", "--level", "6", "--out"])
        .arg(&obj)
        .stdout(writer)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}: {err}");
    assert!(err.is_empty(), "{err}");
    assert!(obj.exists());
}

/// The summary line of `tessellate` for `args` (with a scratch `--out`).
fn tessellate(args: &[&str]) -> serde_json::Value {
    let obj = scratch("extreme.obj");
    let args = [&["tessellate"], args, &["--out", obj.to_str().unwrap()]].concat();
    let (code, out, err) = run(&args, "");
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap()
}

#[test]
fn tessellate_sphere_of_radius_1e200_and_1e308_has_a_finite_deviation_and_true_dihedral() {
    let unit = tessellate(&["--sphere", "1", "--level", "3"]);
    let (dev1, dih1) = (
        unit["max_deviation"].as_f64().unwrap(),
        unit["min_dihedral_deg"].as_f64().unwrap(),
    );
    for r in ["1e200", "1e308", "1e-200"] {
        let j = tessellate(&["--sphere", r, "--level", "3"]);
        let radius: f64 = r.parse().unwrap();
        let dev = j["max_deviation"].as_f64().unwrap_or(f64::NAN);
        let dih = j["min_dihedral_deg"].as_f64().unwrap();
        assert!(
            dev > 0.0 && (dev / radius / dev1 - 1.0).abs() < 1e-12,
            "{r}: {j}"
        );
        assert!((dih - dih1).abs() < 1e-9, "{r}: {j}");
    }
}

#[test]
fn tessellate_level_1_dihedral_is_120_degrees_at_radius_1e77_and_1e_minus_100() {
    for r in ["1e77", "1e-100"] {
        let j = tessellate(&["--sphere", r, "--level", "1"]);
        let dih = j["min_dihedral_deg"].as_f64().unwrap();
        assert!((dih - 120.0).abs() < 1e-9, "{r}: {j}");
    }
}

#[test]
fn tessellate_ellipsoid_1e10_1_1e_minus_10_names_the_axis_ratio_limit() {
    let err = assert_usage_error(&[
        "tessellate",
        "--ellipsoid",
        "1e10",
        "1",
        "1e-10",
        "--max-deviation",
        "1",
        "--out",
        scratch("ratio.obj").to_str().unwrap(),
    ]);
    assert!(err.contains("ratio") && err.contains("1e6"), "{err}");
    let j = tessellate(&["--ellipsoid", "1e10", "1", "1e-10", "--level", "2"]);
    let dev = j["max_deviation"].as_f64().unwrap();
    assert!(dev > 0.0 && dev.is_finite(), "{j}");
}

/// Runs `pick` on a 3 × 3 flat grid at the equator with columns `dlon` degrees apart, one ray straight down at
/// (0°, `lon`); returns (exit code, stdout, stderr).
fn pick_on_wide_cells(dlon: f64, lon: f64) -> (i32, String, String) {
    let json = scratch(&format!("wide-{dlon}.json"));
    std::fs::write(
        &json,
        format!(
            r#"{{"ellipsoid": "WGS84", "grid": {{"lat0": -10, "lon0": 0, "dlat": 10, "dlon": {dlon},
                "rows": 3, "cols": 3, "heights_inline": [0, 0, 0, 0, 0, 0, 0, 0, 0]}}}}"#
        ),
    )
    .unwrap();
    let l = lon.to_radians();
    let ray = format!(
        "{{\"origin\": [{}, {}, 0], \"dir\": [{}, {}, 0]}}\n",
        7.4e6 * l.cos(),
        7.4e6 * l.sin(),
        -l.cos(),
        -l.sin()
    );
    let rays = scratch(&format!("wide-{dlon}.jsonl"));
    std::fs::write(&rays, ray).unwrap();
    run(
        &[
            "pick",
            "--terrain",
            json.to_str().unwrap(),
            "--rays",
            rays.to_str().unwrap(),
            "--block",
            "1",
        ],
        "",
    )
}

#[test]
fn pick_on_80_degree_cells_names_the_cell_size_limit_not_the_height() {
    let (code, out, err) = pick_on_wide_cells(80.0, 40.0);
    let all = format!("{out}{err}");
    assert!(code == 0 || code == 2, "{code}: {all}");
    assert!(all.contains("70 degrees"), "{all}");
    assert!(!all.contains("at or below"), "{all}");
    // 60° cells are within the limit and answered.
    let (code, out, err) = pick_on_wide_cells(60.0, 40.0);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("\"hit\":{"), "{out}");
}

#[test]
fn pick_on_a_grid_with_dlon_180_says_why_it_is_invalid() {
    let (code, out, err) = pick_on_wide_cells(180.0, 40.0);
    assert_eq!(code, 2, "{out}{err}");
    assert!(out.is_empty(), "{out}");
    assert!(err.contains("0 < dlon < 180"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}
