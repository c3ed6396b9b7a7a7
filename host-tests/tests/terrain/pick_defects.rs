//! `curvicast pick` on directions at the ends of the floating-point range (issue: a ray whose hit lies beyond
//! the largest finite `t` must be a typed error, never a silent miss; directions whose `t` is representable
//! must work down to subnormal components).

use curvicast_cli::formats::spec::RaySpec;

/// A 3 × 3 DEM on a sphere of radius 6 371 km with a 100 m peak at vertex (1, 1), 11°N 21°E.
const TERRAIN: &str = r#"{"ellipsoid": {"a": 6371000.0, "b": 6371000.0}, "grid": {"lat0": 10, "lon0": 20,
    "dlat": 1, "dlon": 1, "rows": 3, "cols": 3, "heights_inline": [0, 0, 0, 0, 100, 0, 0, 0, 0]}}"#;

/// The unit vector from the center to the peak.
fn up() -> [f64; 3] {
    let (p, l) = (11f64.to_radians(), 21f64.to_radians());
    [p.cos() * l.cos(), p.cos() * l.sin(), p.sin()]
}

/// Picks each ray through the command; returns one JSON value per output line.
fn pick(name: &str, rays: &[RaySpec]) -> Vec<serde_json::Value> {
    let tmp = crate::support::temp_dir(&format!("pick-{name}"));
    let json = tmp.path().join("terrain.json");
    std::fs::write(&json, TERRAIN).unwrap();
    let text: String = rays
        .iter()
        .map(|r| serde_json::to_string(r).unwrap() + "\n")
        .collect();
    let args = ["pick", "--terrain", json.to_str().unwrap(), "--block", "1"];
    let (code, out, err) = crate::support::run(&args, text);
    assert_eq!(code, 0, "{err}");
    crate::support::json_lines(&out)
}

/// Straight down onto the peak from 1 000 km: with a direction of length 1e-308 the hit is at t ≈ 1e314, beyond
/// the largest f64, and the answer is an error line naming that (before the fix: a miss); with length 1e-300 it
/// is an ordinary hit at t = 999 900 km / 1e-300 (before the fix: a hit whose t and point were null).
#[test]
fn tiny_direction_whose_hit_t_overflows_is_an_error_line_not_a_miss() {
    let u = up();
    let from = u.map(|c| c * 7_371_000.0);
    let lines = pick(
        "tiny",
        &[
            RaySpec::new(from, u.map(|c| -c * 1e-308)),
            RaySpec::new(from, u.map(|c| -c * 1e-300)),
        ],
    );
    assert_eq!(lines.len(), 2, "{lines:?}");
    let msg = lines[0]["error"].as_str().unwrap_or_default();
    assert!(msg.contains("largest finite"), "{lines:?}");
    let t = lines[1]["hit"]["t"].as_f64().unwrap();
    assert!((t * 1e-300 - 999_900.0).abs() < 1e-6, "{t}");
    assert!((lines[1]["hit"]["h"].as_f64().unwrap() - 100.0).abs() < 1e-6);
}

/// Straight down onto the peak from 1 cm above it with a subnormal direction (length 1e-308, every component
/// below the smallest normal f64): the hit is at t ≈ 1e306, representable, while the far side of the terrain's
/// bounding shell is not (about 1.3e315). The hit is found, 1 cm along the ray, at the peak's height.
#[test]
fn subnormal_direction_with_a_representable_hit_finds_it() {
    let u = up();
    let from = u.map(|c| c * (6_371_000.0 + 100.01));
    let d = u.map(|c| -c * 1e-308);
    assert!(d.iter().all(|c| c.abs() < f64::MIN_POSITIVE));
    let lines = pick("subnormal", &[RaySpec::new(from, d)]);
    let hit = &lines[0]["hit"];
    let t = hit["t"].as_f64().unwrap_or_else(|| panic!("{lines:?}"));
    assert!((t * 1e-308 - 0.01).abs() < 1e-6, "{t}");
    assert!((hit["h"].as_f64().unwrap() - 100.0).abs() < 1e-6, "{hit}");
}

/// The peak from 1 cm above it with directions deep in the subnormal range: length 1e-309 (t ≈ 1e307, still
/// representable) is an ordinary hit 1 cm along the ray; length 1e-315 (t ≈ 1e313) and a direction of the
/// smallest subnormal components (t ≈ 1e321) are error lines; the same 1e-309 direction with `t_max` short of
/// the hit is a miss, not an error (before the fix, every direction of length 1e-309 or less was the error).
#[test]
fn deep_subnormal_directions_hit_where_t_is_representable_and_error_where_not() {
    let u = up();
    let from = u.map(|c| c * (6_371_000.0 + 100.01));
    let down = |len: f64| u.map(|c| -c * len);
    let smallest = u.map(|c| -c.signum() * f64::from_bits(1));
    let mut short = RaySpec::new(from, down(1e-309));
    short.t_max = Some(0.005 / 1e-309);
    let lines = pick(
        "deep-subnormal",
        &[
            RaySpec::new(from, down(1e-309)),
            RaySpec::new(from, down(1e-315)),
            RaySpec::new(from, smallest),
            short,
        ],
    );
    let t = lines[0]["hit"]["t"]
        .as_f64()
        .unwrap_or_else(|| panic!("{lines:?}"));
    assert!((t * 1e-309 - 0.01).abs() < 1e-6, "{t}");
    assert!((lines[0]["hit"]["h"].as_f64().unwrap() - 100.0).abs() < 1e-6);
    for line in &lines[1..3] {
        let e = line["error"].as_str().unwrap_or_else(|| panic!("{line}"));
        assert!(e.contains("largest finite"), "{e}");
    }
    assert!(
        lines[3]["hit"].is_null() && lines[3].get("error").is_none(),
        "{}",
        lines[3]
    );
}

/// A direction of length 1e300 from 1 000 km above the peak: t ≈ 1e-294 (the line is the same, its parameter
/// tiny); the hit is the peak's, as with a unit direction.
#[test]
fn huge_direction_hits_like_a_unit_one() {
    let u = up();
    let from = u.map(|c| c * (6_371_000.0 + 1_000_000.0));
    let lines = pick(
        "huge",
        &[
            RaySpec::new(from, u.map(|c| -c * 1e300)),
            RaySpec::new(from, u.map(|c| -c)),
        ],
    );
    let t = lines[0]["hit"]["t"]
        .as_f64()
        .unwrap_or_else(|| panic!("{lines:?}"));
    let t1 = lines[1]["hit"]["t"].as_f64().unwrap();
    assert!(((t * 1e300) / t1 - 1.0).abs() < 1e-12, "{t} vs {t1}");
    assert_eq!(lines[0]["hit"]["cell"], lines[1]["hit"]["cell"]);
    assert!((lines[0]["hit"]["h"].as_f64().unwrap() - 100.0).abs() < 1e-6);
}
