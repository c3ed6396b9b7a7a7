//! Regression tests for two defects of the marchers: the last crossing of a ray that ends inside the domain exits
//! at the ray's `t_max` bit for bit, and a ray whose crossings lie where `t` overflows (a tiny direction) is a
//! typed error — in the kernel and as an error line of `curvicast march` — never a miss or a `null` t.

use crate::support;

use curvicast_host::march_run::{Engine, Precision, Rounded, run_engine};
use curvicast_host::scenes::march_cases::{partial_grid, random_grid, random_ray};
use rand::{Rng, SeedableRng};

/// The neighbours of `t` by `k` units in the last place of the precision's type.
fn ulps(p: Precision, t: f64, k: i64) -> f64 {
    match p {
        Precision::F64 => f64::from_bits((t.to_bits() as i64 + k) as u64),
        _ => f32::from_bits(((t as f32).to_bits() as i64 + k) as u32) as f64,
    }
}

/// A ray that ends inside the domain: its last crossing's `t_exit` is the ray's `t_max`, bit for bit, in every
/// precision and both engines. Random grids (partial ones included) and the partial hard-case grid; `t_max` is
/// placed strictly inside a crossing of the unclipped ray, at random or one ulp inside either end, or exactly
/// on an event between two cells of the domain.
#[test]
fn last_crossing_of_a_ray_ending_inside_exits_at_t_max_exactly() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x0016_7a4a);
    let mut checked = 0;
    let mut bad = Vec::new();
    for n in 0..3000 {
        let g = if n % 2 == 0 {
            partial_grid()
        } else {
            random_grid(&mut rng)
        };
        let mut ray = random_ray(&mut rng, &g);
        ray.t_max = None;
        for p in [Precision::F64, Precision::F32, Precision::F32Fast] {
            let rp = p.round_ray(&ray);
            let gp = p.round_grid(&g);
            let Ok(full) = run_engine(&gp, &rp, Engine::Serial, p) else {
                continue;
            };
            if full.is_empty() {
                continue;
            }
            let i = rng.random_range(0..full.len());
            let c = full[i];
            if c.t_exit <= c.t_enter || !c.t_exit.is_finite() {
                continue;
            }
            let t_max = match rng.random_range(0..4) {
                0 => ulps(p, c.t_exit, -1),
                1 => ulps(p, c.t_enter, 1),
                2 if full.get(i + 1).is_some_and(|d| d.t_enter == c.t_exit) => c.t_exit,
                _ => c.t_enter + rng.random_range(0.0..1.0) * (c.t_exit - c.t_enter),
            };
            let mut clipped = rp;
            clipped.t_max = Some(t_max);
            let clipped = p.round_ray(&clipped);
            let want = clipped.t_max.unwrap();
            let inside = full.iter().any(|d| d.t_enter < want && want < d.t_exit)
                || full
                    .windows(2)
                    .any(|w| w[0].t_exit == want && w[1].t_enter == want);
            if !inside || want < clipped.t_min {
                continue;
            }
            for e in [Engine::Serial, Engine::Separable] {
                let got = run_engine(&gp, &clipped, e, p).unwrap();
                checked += 1;
                match got.last() {
                    Some(l) if l.t_exit.to_bits() == want.to_bits() => {}
                    other => bad.push(format!("{} {e:?} {gp:?} {clipped:?}: {other:?}", p.name())),
                }
            }
        }
    }
    assert!(checked > 5000, "{checked}");
    assert!(
        bad.is_empty(),
        "{} of {checked}: {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
}

/// The standard output of a successful run.
fn run_cli(args: &[&str], stdin: &str) -> String {
    let (code, out, err) = support::run(args, stdin);
    assert_eq!(code, 0, "{err}");
    out
}

/// `[1e-308, 0, 0]` from three units away crosses the unit ball at t ≈ 2e308..4e308, beyond the largest f64:
/// the CLI answers with an error line (both engines), and the same line with a direction a thousand times
/// longer has ordinary, finite crossings.
#[test]
fn tiny_direction_whose_t_overflows_is_an_error_line_not_a_miss() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let grid = dir.join("sphere.json");
    std::fs::write(
        &grid,
        r#"{"kind": "spherical", "r": [0.0, 0.5, 1.0], "theta": [0.0, 1.5707963267948966, 3.141592653589793], "phi": [0.0, 3.141592653589793, 6.283185307179586]}"#,
    )
    .unwrap();
    let rays = concat!(
        "{\"origin\": [-3, 0.1, 0.2], \"dir\": [1e-308, 0, 0]}\n",
        "{\"origin\": [-3, 0.1, 0.2], \"dir\": [1e-305, 0, 0]}\n",
    );
    for engine in ["serial", "separable"] {
        let out = run_cli(
            &[
                "march",
                "--grid",
                grid.to_str().unwrap(),
                "--engine",
                engine,
            ],
            rays,
        );
        let lines: Vec<serde_json::Value> = out
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 2, "{out}");
        let msg = lines[0]["error"].as_str().unwrap_or_default();
        assert!(msg.contains("largest finite"), "{engine}: {out}");
        let cs = lines[1]["crossings"].as_array().unwrap();
        assert!(cs.len() >= 3, "{out}");
        assert!(
            cs.iter()
                .all(|c| c["t_enter"].is_f64() && c["t_exit"].is_f64()),
            "{out}"
        );
    }
}

/// Through the command, in every precision and both engines: rays that end inside a partial grid (a shell, a cone
/// band and a wedge across φ = 0) at a `t_max` that `f32` cannot represent (1.7, 2.3) and at one it can (1.5) end
/// with `t_exit` equal to the given `t_max` as written in the rays file, and one that starts inside at such a
/// `t_min` begins there. Before the fix an `f32` march printed the bound rounded to `f32` (1.7000000476837158).
#[test]
fn cli_last_crossing_of_a_ray_ending_inside_a_partial_grid_is_the_given_t_max() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let grid = dir.join("partial.json");
    std::fs::write(
        &grid,
        r#"{"kind": "spherical", "r": [0.5, 0.8, 1.3, 2.0], "theta": [0.6, 1.2, 1.9, 2.5], "phi": [-0.7, 0.0, 0.45, 0.9]}"#,
    )
    .unwrap();
    // From (-0.2, 0, 0) along +x the ray enters the shell at t = 0.7 and stays in the wedge and band to t = 2.2.
    let rays = concat!(
        "{\"origin\": [-0.2, 0.01, 0.02], \"dir\": [1, 0.05, 0.03], \"t_max\": 1.7}\n",
        "{\"origin\": [-0.2, 0.01, 0.02], \"dir\": [1, 0.05, 0.03], \"t_max\": 1.5}\n",
        "{\"origin\": [-0.2, 0.01, 0.02], \"dir\": [1, 0.05, 0.03], \"t_min\": 0.9, \"t_max\": 2.1}\n",
    );
    let want = [(None, 1.7), (None, 1.5), (Some(0.9), 2.1)];
    for engine in ["serial", "separable"] {
        for precision in ["f64", "f32", "f32-fast"] {
            let out = run_cli(
                &[
                    "march",
                    "--grid",
                    grid.to_str().unwrap(),
                    "--engine",
                    engine,
                    "--precision",
                    precision,
                ],
                rays,
            );
            let lines: Vec<serde_json::Value> = out
                .lines()
                .map(|l| serde_json::from_str(l).unwrap())
                .collect();
            assert_eq!(lines.len(), 3, "{out}");
            for (line, (t_min, t_max)) in lines.iter().zip(want) {
                let cs = line["crossings"].as_array().unwrap();
                assert!(cs.len() >= 2, "{engine} {precision}: {out}");
                let last = cs.last().unwrap()["t_exit"].as_f64().unwrap();
                assert_eq!(
                    last.to_bits(),
                    f64::to_bits(t_max),
                    "{engine} {precision}: {line}"
                );
                if let Some(t_min) = t_min {
                    let first = cs[0]["t_enter"].as_f64().unwrap();
                    assert_eq!(
                        first.to_bits(),
                        f64::to_bits(t_min),
                        "{engine} {precision}: {line}"
                    );
                }
            }
        }
    }
}
