//! `curvicast pick` end to end: the binary, its output lines, and its errors (command-line contract).

use crate::support;

use curvicast_cli::formats::spec::RaySpec;
use curvicast_host::oracle::terrain::TerrainOracle;
use curvicast_host::scenes::terrain_cases::{TerrainKind, random_rays, synthetic};

use crate::support::temp_dir as dir;

/// [`support::run`] with no input for `None`.
fn run(args: &[&str], stdin: Option<&str>) -> (i32, String, String) {
    support::run(args, stdin.unwrap_or(""))
}

#[test]
fn pick_answers_every_ray_in_order_and_matches_the_oracle() {
    let tmp = dir("ok");
    let d = tmp.path();
    let dem = synthetic(
        TerrainKind::Fractal,
        (36.0, -118.0, 0.01, 0.01),
        (40, 50),
        5,
    );
    let json = d.join("terrain.json");
    dem.write_terrain_json(&json).unwrap();
    let rays = random_rays(&dem, 40, 6);
    let mut text: String = rays
        .iter()
        .map(|r| serde_json::to_string(r).unwrap() + "\n")
        .collect();
    text.push_str("{\"origin\": [0, 0, 0], \"dir\": [0, 0, 0]}\n");
    text.push_str("not json\n");
    let rays_path = d.join("rays.jsonl");
    std::fs::write(&rays_path, &text).unwrap();
    let (code, out, err) = run(
        &[
            "pick",
            "--terrain",
            json.to_str().unwrap(),
            "--rays",
            rays_path.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let lines: Vec<serde_json::Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 42);
    let oracle = TerrainOracle::new(&dem);
    let mut hits = 0;
    for (k, (l, r)) in lines.iter().zip(&rays).enumerate() {
        assert_eq!(l["ray"], k);
        let truth = oracle.pick(r);
        match (&l["hit"], truth) {
            (serde_json::Value::Null, None) => {}
            (h, Some(t)) if h.is_object() => {
                hits += 1;
                let e: Vec<f64> = h["ecef"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect();
                let dist = ((e[0] - t.point[0]).powi(2)
                    + (e[1] - t.point[1]).powi(2)
                    + (e[2] - t.point[2]).powi(2))
                .sqrt();
                assert!(dist < 1e-6, "ray {k}: {dist}");
                for key in ["t", "lat", "lon", "h"] {
                    assert!(h[key].is_number(), "{key}");
                }
                assert_eq!(h["cell"].as_array().unwrap().len(), 2);
                let lat = h["lat"].as_f64().unwrap();
                assert!((35.9..=36.5).contains(&lat), "{lat}");
            }
            (h, t) => panic!("ray {k}: cli {h} vs oracle {t:?}"),
        }
    }
    assert!(hits > 10);
    assert_eq!(lines[40]["ray"], 40);
    assert!(lines[40]["error"].as_str().unwrap().contains("invalid ray"));
    assert_eq!(lines[41]["ray"], 41);
    assert!(lines[41]["error"].is_string());
}

#[test]
fn pick_reads_rays_from_stdin_with_inline_heights() {
    let tmp = dir("stdin");
    let d = tmp.path();
    let json = d.join("t.json");
    std::fs::write(
        &json,
        r#"{"ellipsoid": {"a": 6371000.0, "b": 6371000.0}, "grid": {"lat0": 10, "lon0": 20, "dlat": 1,
            "dlon": 1, "rows": 3, "cols": 3, "heights_inline": [0, 0, 0, 0, 100, 0, 0, 0, 0]}}"#,
    )
    .unwrap();
    // Straight down the radial through vertex (1, 1) at 11°N 21°E from 1000 km.
    let (p, l) = (11f64.to_radians(), 21f64.to_radians());
    let u = [p.cos() * l.cos(), p.cos() * l.sin(), p.sin()];
    let r = RaySpec::new(u.map(|c| c * 7_371_000.0), u.map(|c| -c));
    let (code, out, err) = run(
        &["pick", "--terrain", json.to_str().unwrap(), "--block", "1"],
        Some(&(serde_json::to_string(&r).unwrap() + "\n")),
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let t = v["hit"]["t"].as_f64().unwrap();
    assert!((t - (1_000_000.0 - 100.0)).abs() < 1e-6, "{t}");
    assert!((v["hit"]["h"].as_f64().unwrap() - 100.0).abs() < 1e-6);
}

fn assert_usage_error(args: &[&str], needle: &str) {
    let (code, out, err) = run(args, Some(""));
    assert_eq!(code, 2, "{args:?}: {err}");
    assert!(out.is_empty(), "{out}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains(needle), "{err} lacks {needle}");
}

#[test]
fn pick_bad_files_and_arguments_exit_2_with_one_line_naming_the_file() {
    let tmp = dir("bad");
    let d = tmp.path();
    let json = d.join("terrain.json");
    let j = json.to_str().unwrap();
    assert_usage_error(&["pick", "--terrain", j], "terrain.json");
    std::fs::write(
        &json,
        r#"{"ellipsoid": "WGS84", "grid": {"lat0": 0, "lon0": 0, "dlat": 1, "dlon": 1, "rows": 2, "cols": 2,
            "heights": "h.f32"}}"#,
    )
    .unwrap();
    assert_usage_error(&["pick", "--terrain", j], "h.f32");
    std::fs::write(d.join("h.f32"), [0u8; 15]).unwrap();
    assert_usage_error(&["pick", "--terrain", j], "h.f32");
    std::fs::write(d.join("h.f32"), [0u8; 16]).unwrap();
    assert_usage_error(&["pick", "--terrain", j, "--block", "0"], "--block");
    assert_usage_error(
        &["pick", "--terrain", j, "--min-level", "99"],
        "--min-level",
    );
    assert_usage_error(
        &["pick", "--terrain", j, "--rays", "/nonexistent/rays.jsonl"],
        "rays.jsonl",
    );
    std::fs::write(
        &json,
        r#"{"ellipsoid": "WGS84", "grid": {"lat0": 89.5, "lon0": 0, "dlat": 1, "dlon": 1, "rows": 2, "cols": 2,
            "heights": "h.f32"}}"#,
    )
    .unwrap();
    assert_usage_error(&["pick", "--terrain", j], "outside [-90, 90]");
    let (code, out, _) = run(&["pick", "--terrain", j], Some(""));
    assert_eq!((code, out.as_str()), (2, ""));
}

#[test]
fn pick_on_the_shipped_etopo20_written_as_terrain_json_matches_the_oracle() {
    use curvicast_cli::formats::real_dem;
    use curvicast_host::scenes::terrain_cases::orbit_rays;
    let tmp = dir("etopo");
    let d = tmp.path();
    let dem = real_dem::etopo20().unwrap();
    let json = d.join("etopo20.json");
    dem.write_terrain_json(&json).unwrap();
    let mut rays = orbit_rays(&dem, 20, 3);
    rays.extend(random_rays(&dem, 20, 4));
    let text: String = rays
        .iter()
        .map(|r| serde_json::to_string(r).unwrap() + "\n")
        .collect();
    let (code, out, err) = run(&["pick", "--terrain", json.to_str().unwrap()], Some(&text));
    assert_eq!(code, 0, "{err}");
    let oracle = TerrainOracle::new(&dem);
    let lines: Vec<serde_json::Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), rays.len());
    let mut hits = 0;
    for (k, (l, r)) in lines.iter().zip(&rays).enumerate() {
        match (oracle.pick(r), &l["hit"]) {
            (None, serde_json::Value::Null) => {}
            (Some(t), h) if h.is_object() => {
                hits += 1;
                let e: Vec<f64> = h["ecef"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect();
                let dist = ((e[0] - t.point[0]).powi(2)
                    + (e[1] - t.point[1]).powi(2)
                    + (e[2] - t.point[2]).powi(2))
                .sqrt();
                assert!(dist < 1e-6, "ray {k}: {dist} m");
                assert_eq!(h["cell"][0].as_u64().unwrap() as usize, t.cell.0, "ray {k}");
            }
            (t, h) => panic!("ray {k}: oracle {t:?} vs cli {h}"),
        }
    }
    assert!(hits >= 20, "{hits}");
}

/// Multi-resolution options end to end: a tree with full resolution only in a box, the blocks below the zones not
/// resident, answered from the zones' blocks (checked against the multi-resolution oracle); the same with
/// `--min-level` at the full depth, where the tool pages in what each ray needs and the answers are the
/// full-resolution ones; and `--no-paging`, where a needed block is an error line naming the node.
#[test]
fn pick_multi_resolution_options_page_in_what_each_ray_needs() {
    use curvicast_cli::storage::{DemStorage, MultiRes};
    use curvicast_host::oracle::multires::MultiResOracle;
    let tmp = dir("multires");
    let d = tmp.path();
    let dem = synthetic(
        TerrainKind::Fractal,
        (36.0, -118.0, 0.002, 0.002),
        (97, 97),
        8,
    );
    let json = d.join("terrain.json");
    dem.write_terrain_json(&json).unwrap();
    let rays = random_rays(&dem, 60, 9);
    let text: String = rays
        .iter()
        .map(|r| serde_json::to_string(r).unwrap() + "\n")
        .collect();
    let rays_path = d.join("rays.jsonl");
    std::fs::write(&rays_path, &text).unwrap();
    let base = [
        "pick",
        "--terrain",
        json.to_str().unwrap(),
        "--rays",
        rays_path.to_str().unwrap(),
        "--block",
        "8",
    ];
    let lines = |extra: &[&str]| -> Vec<serde_json::Value> {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        let (code, out, err) = run(&args, None);
        assert_eq!(code, 0, "{err}");
        out.lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect()
    };
    let point = |l: &serde_json::Value| -> Option<[f64; 3]> {
        let e = l["hit"].get("ecef")?;
        Some([0, 1, 2].map(|k| e[k].as_f64().unwrap()))
    };
    let near = |a: Option<[f64; 3]>, b: Option<[f64; 3]>| match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt() < 1e-6,
        _ => false,
    };
    // 1. Zones only: the tree of the tool, rebuilt here for the oracle with the same residency.
    let region = "36.05,36.12,-117.95,-117.88";
    let out = lines(&[
        "--fine-region",
        region,
        "--coarse-level",
        "1",
        "--non-resident-levels",
        "1,2",
    ]);
    let s = DemStorage::multi_resolution(
        &dem,
        8,
        MultiRes {
            fine_region: Some([36.05, 36.12, -117.95, -117.88]),
            coarse_level: 1,
        },
    );
    for n in s.tree() {
        s.set_resident(curvicast::terrain::NodeId(n.id), n.level == 0);
    }
    let oracle = MultiResOracle::new(&dem, &s.tree(), 0).expect("zones resident");
    let mut coarse = 0;
    for (k, (l, r)) in out.iter().zip(&rays).enumerate() {
        assert_eq!(l["ray"], k);
        let o = oracle.pick(r);
        assert!(near(point(l), o.map(|h| h.point)), "ray {k}: {l} vs {o:?}");
        coarse += usize::from(
            l["hit"]
                .get("stride")
                .and_then(|s| s.as_u64())
                .is_some_and(|s| s > 1),
        );
    }
    assert!(coarse > 10, "answers come from coarse blocks ({coarse})");
    // 2. min_level at full depth: every needed block is paged in; the full-resolution surface answers.
    let depth = s.depth().to_string();
    let out = lines(&["--non-resident-levels", "1,2", "--min-level", &depth]);
    let fine = TerrainOracle::new(&dem);
    for (k, (l, r)) in out.iter().zip(&rays).enumerate() {
        assert!(
            near(point(l), fine.pick(r).map(|h| h.point)),
            "ray {k}: {l}"
        );
        if l["hit"].is_object() {
            assert_eq!(l["hit"]["stride"], 1);
        }
    }
    // 3. Without paging: error lines naming the needed node.
    let out = lines(&[
        "--non-resident-levels",
        "1,2",
        "--min-level",
        &depth,
        "--no-paging",
    ]);
    let needs = out
        .iter()
        .filter(|l| {
            l["error"]
                .as_str()
                .is_some_and(|e| e.contains("needs the block of node"))
        })
        .count();
    assert!(needs > 30, "{needs} rays needed a block");
    // Bad option values are one-line usage errors.
    for bad in [
        &["--fine-region", "1,2,3"][..],
        &["--non-resident-levels", "x"],
        &["--non-resident-levels", "99"],
    ] {
        let args: Vec<&str> = base.iter().chain(bad).copied().collect();
        let (code, out, err) = run(&args, None);
        assert_eq!(code, 2, "{bad:?}: {out}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}
