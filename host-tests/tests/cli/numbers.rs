//! Every number the commands read is correctly rounded, and every number they write reads back to the same bits.
//!
//! A fast decimal parser (a 19-digit significand converted to `f64`, then multiplied or divided by a power of
//! ten: two roundings) lands on the neighbouring double for about a third of random 17-digit decimals; serde_json
//! parses that way unless its `float_roundtrip` feature is on. The numbers below are generated the way the bug
//! shows: random 17-digit decimals, parsed both by such a two-rounding parser and by `str::parse` (correctly
//! rounded), keeping those where the two differ. The commands must read each one to `str::parse`'s bits.

use crate::support;
use curvicast::terrain::Picker;

use curvicast_cli::cli::pick::answer;
use curvicast_cli::formats::spec::{GridSpec, RaySpec};
use curvicast_cli::formats::terrain::load_terrain;
use curvicast_cli::storage::DemStorage;
use curvicast_host::march_run::{Engine, Precision, run_engine};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use support::run;

/// The two-rounding fast path: the significand as `f64` (exact below 2^53, rounded above), then one
/// multiplication or division by a correctly rounded power of ten.
fn fast_parse(text: &str) -> f64 {
    if let Some(positive) = text.strip_prefix('-') {
        return -fast_parse(positive);
    }
    let (mantissa, exp) = text.split_once('e').unwrap_or((text, "0"));
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let digits = format!("{int}{frac}");
    let sig: u64 = digits.parse().unwrap();
    let exp: i32 = exp.parse::<i32>().unwrap() - i32::try_from(frac.len()).unwrap();
    let pow: f64 = format!("1e{}", exp.abs()).parse().unwrap();
    if exp >= 0 {
        sig as f64 * pow
    } else {
        sig as f64 / pow
    }
}

/// `n` decimals with 17 significant digits in `[lo, hi)` (`lo < hi`, both of `hi`'s decade or below) that the fast
/// path misreads.
fn misread(rng: &mut ChaCha8Rng, lo: f64, hi: f64, n: usize) -> Vec<String> {
    let decade = lo.abs().max(hi.abs()).log10().floor() as i32;
    // 17 significant digits: `places` digits after the point.
    let places = 16 - decade;
    let scale = 10f64.powi(places);
    let (a, b) = ((lo * scale).ceil() as i128, (hi * scale).floor() as i128);
    let mut out = Vec::new();
    for _ in 0..1_000_000 {
        let sig = rng.random_range(a..b);
        let digits = format!(
            "{:0>width$}",
            sig.abs(),
            width = usize::try_from(places.max(0) + 1).unwrap()
        );
        let (int, frac) = digits.split_at(digits.len() - usize::try_from(places.max(0)).unwrap());
        let sign = if sig < 0 { "-" } else { "" };
        let text = if frac.is_empty() {
            format!("{sign}{int}")
        } else {
            format!("{sign}{int}.{frac}")
        };
        let exact: f64 = text.parse().unwrap();
        if exact.to_bits() != fast_parse(&text).to_bits() && (lo..hi).contains(&exact) {
            out.push(text);
            if out.len() == n {
                return out;
            }
        }
    }
    panic!("too few misread decimals in [{lo}, {hi})");
}

fn num(text: &str) -> f64 {
    text.parse().unwrap()
}

#[test]
fn the_fast_path_emulation_misreads_the_reported_t_max() {
    // The decimal of the report: a two-rounding parser gives the double below it.
    let text = "0.9757777680109765";
    assert_eq!(fast_parse(text).to_bits() + 1, num(text).to_bits());
}

#[test]
fn march_reads_every_number_to_its_correctly_rounded_bits_and_writes_them_back_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let n = 40;
    // Breakpoints, centre, origins and directions that the fast path misreads; t_min and t_max inside the grid.
    let r_mid = misread(&mut rng, 0.4, 0.6, 1).remove(0);
    let th_mid = misread(&mut rng, 1.2, 1.9, 1).remove(0);
    let ph_mid = misread(&mut rng, 2.0, 4.0, 1).remove(0);
    let cz = misread(&mut rng, 0.01, 0.02, 1).remove(0);
    let grid_text = format!(
        r#"{{"kind": "spherical", "center": [0, 0, {cz}], "r": [0.0, {r_mid}, 1.0], "theta": [0.0, {th_mid}, 3.141592653589793], "phi": [0.0, {ph_mid}, 6.283185307179586]}}"#
    );
    let ys = misread(&mut rng, 0.1, 0.3, n);
    let dys = misread(&mut rng, 0.01, 0.09, n);
    let t_mins = misread(&mut rng, 1.3, 1.6, n);
    let t_maxs = misread(&mut rng, 2.4, 2.6, n);
    let dir = tempfile::tempdir().unwrap();
    let grid_path = dir.path().join("grid.json");
    std::fs::write(&grid_path, &grid_text).unwrap();
    let mut rays_text = String::new();
    let mut rays = Vec::new();
    for k in 0..n {
        let (y, dy, t0, t1) = (&ys[k], &dys[k], &t_mins[k], &t_maxs[k]);
        rays_text.push_str(&format!(
            "{{\"origin\": [-2, {y}, 0.05], \"dir\": [1, {dy}, 0], \"t_min\": {t0}, \"t_max\": {t1}}}\n"
        ));
        rays.push(RaySpec {
            origin: [-2.0, num(y), 0.05],
            dir: [1.0, num(dy), 0.0],
            t_min: num(t0),
            t_max: Some(num(t1)),
        });
    }
    let grid = GridSpec::Spherical {
        center: Some([0.0, 0.0, num(&cz)]),
        r: vec![0.0, num(&r_mid), 1.0],
        theta: vec![0.0, num(&th_mid), std::f64::consts::PI],
        phi: vec![0.0, num(&ph_mid), std::f64::consts::TAU],
    };
    for (engine, name) in [(Engine::Serial, "serial"), (Engine::Separable, "separable")] {
        let (code, out, err) = run(
            &[
                "march",
                "--grid",
                grid_path.to_str().unwrap(),
                "--engine",
                name,
            ],
            &rays_text,
        );
        assert_eq!(code, 0, "{err}");
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), n);
        for (k, (line, ray)) in lines.iter().zip(&rays).enumerate() {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            let crossings = v["crossings"].as_array().unwrap();
            // Every number as the command wrote it, read back with the correctly rounded `str::parse`, is
            // `want` to the bit.
            let same = |c: &serde_json::Value, key: &str, want: f64| {
                let written: f64 = c[key].to_string().parse().unwrap();
                assert_eq!(written.to_bits(), want.to_bits(), "ray {k} {key}: {line}");
            };
            same(crossings.first().unwrap(), "t_enter", ray.t_min);
            same(crossings.last().unwrap(), "t_exit", ray.t_max_or_inf());
            // The whole answer is the kernel's, in this process, on the correctly rounded inputs.
            let expect = run_engine(&grid, ray, engine, Precision::F64).unwrap();
            assert_eq!(crossings.len(), expect.len(), "ray {k}: {line}");
            for (c, e) in crossings.iter().zip(&expect) {
                let cell: Vec<u64> = c["cell"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_u64().unwrap())
                    .collect();
                let want: Vec<u64> = e.cell.iter().map(|&x| u64::from(x)).collect();
                assert_eq!(cell, want, "ray {k}: {line}");
                same(c, "t_enter", e.t_enter);
                same(c, "t_exit", e.t_exit);
            }
        }
    }
}

#[test]
fn pick_reads_every_number_to_its_correctly_rounded_bits_and_writes_them_back_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(32);
    let (rows, cols) = (9, 11);
    let lat0 = misread(&mut rng, 36.1, 36.9, 1).remove(0);
    let lon0 = misread(&mut rng, -117.9, -117.1, 1).remove(0);
    let dlat = misread(&mut rng, -0.0019, -0.0011, 1).remove(0);
    let dlon = misread(&mut rng, 0.0011, 0.0019, 1).remove(0);
    let heights = misread(&mut rng, 1000.0, 1999.0, rows * cols);
    let terrain_text = format!(
        r#"{{"ellipsoid": "WGS84", "grid": {{"lat0": {lat0}, "lon0": {lon0}, "dlat": {dlat}, "dlon": {dlon}, "rows": {rows}, "cols": {cols}, "heights_inline": [{}]}}}}"#,
        heights.join(", ")
    );
    let dir = tempfile::tempdir().unwrap();
    let terrain_path = dir.path().join("terrain.json");
    std::fs::write(&terrain_path, &terrain_text).unwrap();
    // The command's reading of the file, checked number by number against `str::parse`.
    let dem = load_terrain(&terrain_path).unwrap();
    assert_eq!(dem.lat0.to_bits(), num(&lat0).to_bits());
    assert_eq!(dem.lon0.to_bits(), num(&lon0).to_bits());
    assert_eq!(dem.dlat.to_bits(), num(&dlat).to_bits());
    assert_eq!(dem.dlon.to_bits(), num(&dlon).to_bits());
    for (h, text) in dem.heights.iter().zip(&heights) {
        // Heights are kept as `f32` (the contract's heights file): the correctly rounded double, rounded.
        assert_eq!(h.to_bits(), (num(text) as f32).to_bits());
    }
    // Rays from a few km above the crop, aimed down into its middle; every number a misread decimal.
    let n = 40;
    let centre = dem.vertex_ecef(4, 5).unwrap();
    let up = centre.map(|c| c / (centre[0].hypot(centre[1]).hypot(centre[2])));
    let mut near = |c: f64| misread(&mut rng, c, c + 1.0, 1).remove(0);
    let (mut xs, mut ys, mut zs, mut t_maxs) = (vec![], vec![], vec![], vec![]);
    for k in 0..n {
        let side = 300.0 * (k as f64 - 20.0);
        xs.push(near(centre[0] + 5000.0 * up[0] + side));
        ys.push(near(centre[1] + 5000.0 * up[1] - side));
        zs.push(near(centre[2] + 5000.0 * up[2]));
        t_maxs.push(near(100.0));
    }
    let mut rays_text = String::new();
    let mut rays = Vec::new();
    for k in 0..n {
        let o = [num(&xs[k]), num(&ys[k]), num(&zs[k])];
        let d = [centre[0] - o[0], centre[1] - o[1], centre[2] - o[2]];
        // Directions written with 17 digits that the fast path misreads, too.
        let dtext: Vec<String> = d
            .iter()
            .map(|&c| {
                let lo = c * 0.999_999;
                misread(&mut rng, lo.min(c), lo.max(c), 1).remove(0)
            })
            .collect();
        rays_text.push_str(&format!(
            "{{\"origin\": [{}, {}, {}], \"dir\": [{}, {}, {}], \"t_max\": {}}}\n",
            xs[k], ys[k], zs[k], dtext[0], dtext[1], dtext[2], t_maxs[k]
        ));
        rays.push(RaySpec {
            origin: o,
            dir: [num(&dtext[0]), num(&dtext[1]), num(&dtext[2])],
            t_min: 0.0,
            t_max: Some(num(&t_maxs[k])),
        });
    }
    let (code, out, err) = run(
        &["pick", "--terrain", terrain_path.to_str().unwrap()],
        &rays_text,
    );
    assert_eq!(code, 0, "{err}");
    let storage = DemStorage::new(&dem, 16);
    let picker: Picker<'_, f64, DemStorage<'_>> = Picker::new(&storage).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), n);
    let mut hits = 0;
    for (k, (line, ray)) in lines.iter().zip(&rays).enumerate() {
        // The same line as the kernel's answer in this process on the correctly rounded inputs, and each number
        // in it reads back (correctly rounded) to the bits the kernel computed.
        let expect = answer(&picker, &storage, true, k, ray);
        let got: serde_json::Value = serde_json::from_str(line).unwrap();
        let want: serde_json::Value = serde_json::from_str(&expect).unwrap();
        assert_eq!(got, want, "ray {k}");
        if let Some(hit) = got["hit"].as_object() {
            hits += 1;
            for key in ["t", "lat", "lon", "h"] {
                let text = hit[key].to_string();
                assert_eq!(
                    text.parse::<f64>().unwrap().to_bits(),
                    want["hit"][key].as_f64().unwrap().to_bits(),
                    "ray {k} {key}"
                );
            }
        }
    }
    assert!(hits > n / 2, "only {hits} of {n} rays hit");
}
