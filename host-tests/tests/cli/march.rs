//! `curvicast march` follows the command-line contract: answers per ray, error lines for bad rays, exit code 2
//! with an empty stdout and one stderr line naming the file for a malformed grid.

use crate::support;

use support::{run, temp_file as tmp};

const SPHERE: &str = r#"{"kind": "spherical", "center": [0, 0, 0], "r": [0.0, 0.5, 1.0], "theta": [0.0, 1.5707963267948966, 3.141592653589793], "phi": [0.0, 3.141592653589793, 6.283185307179586]}"#;

#[test]
fn spherical_rays_answer_in_order_with_error_lines_for_bad_rays() {
    let grid = tmp("sphere.json", SPHERE);
    let rays = tmp(
        "rays.jsonl",
        concat!(
            "{\"origin\": [-2, 0.1, 0.25], \"dir\": [1, 0, 0]}\n",
            "{\"origin\": [-2, 0, 0], \"dir\": [0, 0, 0]}\n",
            "{\"origin\": [5, 5, 5], \"dir\": [1, 0, 0]}\n",
            "not json\n",
            "{\"origin\": [-2, 0.1, 0.25], \"dir\": [1, 0, 0], \"t_min\": 3.0, \"t_max\": 1.0}\n",
        ),
    );
    for engine in ["serial", "separable"] {
        for precision in ["f64", "f32", "f32-fast"] {
            let (code, out, err) = run(
                &[
                    "march",
                    "--grid",
                    grid.to_str().unwrap(),
                    "--rays",
                    rays.to_str().unwrap(),
                    "--engine",
                    engine,
                    "--precision",
                    precision,
                ],
                "",
            );
            assert_eq!(code, 0, "{err}");
            let lines: Vec<serde_json::Value> = out
                .lines()
                .map(|l| serde_json::from_str(l).unwrap())
                .collect();
            assert_eq!(lines.len(), 5);
            for (i, l) in lines.iter().enumerate() {
                assert_eq!(l["ray"], i);
            }
            let c = lines[0]["crossings"].as_array().unwrap();
            let cells: Vec<Vec<u64>> = c
                .iter()
                .map(|x| {
                    x["cell"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|v| v.as_u64().unwrap())
                        .collect()
                })
                .collect();
            assert_eq!(cells, vec![vec![1, 0, 0], vec![0, 0, 0], vec![1, 0, 0]]);
            let t0 = c[0]["t_enter"].as_f64().unwrap();
            let expect = 2.0 - (1.0f64 - 0.01 - 0.0625).sqrt();
            assert!((t0 - expect).abs() < 1e-6, "{t0} vs {expect}");
            assert!(lines[1]["error"].as_str().unwrap().contains("zero"));
            assert_eq!(lines[2]["crossings"].as_array().unwrap().len(), 0);
            assert!(lines[3]["error"].is_string());
            assert!(lines[4]["error"].is_string());
        }
    }
}

#[test]
fn rays_from_stdin_and_polar_cells_have_two_indices() {
    let grid = tmp(
        "polar.json",
        r#"{"kind": "polar", "center": [1, 0], "r": [1.0, 2.0], "phi": [-0.5, 0.5]}"#,
    );
    let (code, out, err) = run(
        &["march", "--grid", grid.to_str().unwrap()],
        "{\"origin\": [1, 0, 9], \"dir\": [1, 0, 0]}\n",
    );
    assert_eq!(code, 0, "{err}");
    let l: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(l["crossings"][0]["cell"], serde_json::json!([0, 0]));
    assert_eq!(l["crossings"][0]["t_enter"], 1.0);
    assert_eq!(l["crossings"][0]["t_exit"], 2.0);
}

#[test]
fn malformed_grids_exit_2_with_one_stderr_line_naming_the_file() {
    let cases = [
        (
            "unsorted.json",
            r#"{"kind": "spherical", "r": [0.0, 2.0, 1.0], "theta": [0.0, 3.14], "phi": [0.0, 1.0]}"#,
        ),
        (
            "theta.json",
            r#"{"kind": "spherical", "r": [0.0, 1.0], "theta": [0.0, 4.0], "phi": [0.0, 1.0]}"#,
        ),
        (
            "short.json",
            r#"{"kind": "cylindrical", "rho": [1.0], "phi": [0.0, 1.0], "z": [0.0, 1.0]}"#,
        ),
        (
            "phispan.json",
            r#"{"kind": "polar", "r": [0.0, 1.0], "phi": [0.0, 7.0]}"#,
        ),
        ("garbage.json", "{not json"),
    ];
    for (name, text) in cases {
        let grid = tmp(name, text);
        let (code, out, err) = run(
            &["march", "--grid", grid.to_str().unwrap()],
            "{\"origin\": [0,0,0], \"dir\": [1,0,0]}\n",
        );
        assert_eq!(code, 2, "{name}: {err}");
        assert!(out.is_empty(), "{name}: {out}");
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(name), "{name}: {err}");
    }
    let (code, out, err) = run(&["march", "--grid", "/nonexistent/grid.json"], "");
    assert_eq!((code, out.is_empty()), (2, true));
    assert!(err.contains("grid.json"));
}
