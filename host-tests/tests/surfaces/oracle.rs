//! The kernel's ray–surface layer against the arbitrary-precision oracle, on random rays.
//!
//! For each surface kind (spheroid incl. sphere, axial cone, half-plane, plane z = c): 100 000 random rays
//! (seeded ChaCha; scales log-uniform in 1e-8..1e8, directions of length 1, of the scale, or log-uniform in
//! 1e-30..1e30, origins inside and outside, random surface parameters including the special angles; see
//! `curvicast_host::report::surfaces::random_cases`), compared with the oracle in `f64` (default run) and in `f32`
//! and `F32Fast` (a smaller default run; the full sweep in the ignored test `full_sweep_all_modes`).
//!
//! Definitions (module docs of `curvicast_host::report::surfaces` give the reasoning):
//!
//! * error unit `ε S`: `ε` the machine epsilon of the mode's type, `S = max(|p|, |p + t d|)` at the crossing;
//! * forward error `|t_k − t_o| · |d| / (ε S)`; backward error: the distance of the kernel's point from the true
//!   surface `/ (ε S)`;
//! * near-tangent band: `sin(angle between ray and surface) < SIN_BAND` (0.25). The forward error of any algorithm
//!   working in the input precision grows like `(backward error) / sin`, so the band is where the crossing's
//!   condition number `1/sin` exceeds 4; the measured f64 backward error (below 4 ε S) divided by 0.25 keeps the
//!   forward error below 16 ε S outside it. The backward error is asserted everywhere, in the band too.
//! * count and side must agree for every crossing outside the band that is not within the mode's error of an
//!   interval end or of the surface's edge (cone apex, half-plane axis).
//!
//! Asserted: f64 forward ≤ 16 ε S outside the band (the project's accuracy target) and backward ≤ 16 ε S everywhere; the
//! f32 modes against `forward_bound` / `backward_bound`; no count/side mismatch. Every bound and its measured
//! value (largest forward error outside the band / largest backward error, in ε·S, on 100 000 rays per kind and
//! mode) is in one table, `curvicast_host::tolerances::ERROR_BOUNDS`; `full_sweep_all_modes` re-measures
//! it and fails when a measured value is exceeded or has fallen below half (the table is then stale).

use curvicast_host::report::surfaces::{Kind, Precision, Stats, evaluate, random_cases};
use curvicast_host::tolerances::{MEASURED_RAYS, backward_bound, error_bound, forward_bound};

const SEED: u64 = 0x5eed_0002;

fn check(kind: Kind, modes: &[Precision], n: usize, seed: u64) -> Vec<Stats> {
    let cases = random_cases(kind, n, seed);
    let stats = evaluate(&cases, modes);
    let mut failures = Vec::new();
    for (mode, st) in modes.iter().zip(&stats) {
        print_stats(kind, *mode, st);
        if st.rays != n {
            failures.push(format!(
                "{} {}: {} of {n} rays compared",
                kind.name(),
                mode.name(),
                st.rays
            ));
        }
        if st.mismatches > 0 {
            failures.push(format!(
                "{} {}: {} count/side mismatches, e.g. {:#?}",
                kind.name(),
                mode.name(),
                st.mismatches,
                st.mismatch_examples
            ));
        }
        if st.max_forward.0.is_nan() || st.max_forward.0 > forward_bound(kind, *mode) {
            failures.push(format!(
                "{} {}: forward error {} > {} at {:?}",
                kind.name(),
                mode.name(),
                st.max_forward.0,
                forward_bound(kind, *mode),
                st.max_forward.1
            ));
        }
        if st.max_backward.0.is_nan() || st.max_backward.0 > backward_bound(kind, *mode) {
            failures.push(format!(
                "{} {}: backward error {} > {} at {:?}",
                kind.name(),
                mode.name(),
                st.max_backward.0,
                backward_bound(kind, *mode),
                st.max_backward.1
            ));
        }
        // The test must see crossings, outside the band too, or it proves nothing.
        if st.crossings < n / 4 || st.crossings - st.in_band < n / 5 {
            failures.push(format!(
                "{} {}: only {} crossings ({} in band)",
                kind.name(),
                mode.name(),
                st.crossings,
                st.in_band
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    stats
}

fn print_stats(kind: Kind, mode: Precision, st: &Stats) {
    println!(
        "{:<10} {:<9} rays {:>7} crossings {:>7} (in band {:>5})  max forward {:>8.3} ε·S  max backward {:>8.3} ε·S  mismatches {}",
        kind.name(),
        mode.name(),
        st.rays,
        st.crossings,
        st.in_band,
        st.max_forward.0,
        st.max_backward.0,
        st.mismatches
    );
    println!("    worst forward at {:?}", st.max_forward.1);
    println!("    worst backward at {:?}", st.max_backward.1);
}

#[test]
fn spheroid_f64_100k_rays() {
    check(Kind::Spheroid, &[Precision::F64], 100_000, SEED);
}

#[test]
fn cone_f64_100k_rays() {
    check(Kind::Cone, &[Precision::F64], 100_000, SEED);
}

#[test]
fn half_plane_f64_100k_rays() {
    check(Kind::HalfPlane, &[Precision::F64], 100_000, SEED);
}

#[test]
fn plane_z_f64_100k_rays() {
    check(Kind::PlaneZ, &[Precision::F64], 100_000, SEED);
}

#[test]
fn all_kinds_f32_and_f32_fast_10k_rays() {
    for kind in Kind::ALL {
        check(
            kind,
            &[Precision::F32, Precision::F32Fast],
            10_000,
            SEED + 1,
        );
    }
}

/// The full sweep: 100 000 rays per kind in all three modes (a few minutes in a debug build, half a minute in
/// release, where CI runs it: `cargo test --release -p curvicast-host --test surfaces oracle -- --ignored`).
/// Besides the bounds, it re-measures the table `ERROR_BOUNDS`: no measured value may be exceeded, nor be more
/// than twice the error seen now (a stale table).
#[test]
#[ignore = "long: 1.2 million rays against the 256-bit oracle (CI runs it in release)"]
fn full_sweep_all_modes() {
    let mut stale = Vec::new();
    for kind in Kind::ALL {
        let stats = check(kind, &Precision::ALL, MEASURED_RAYS, SEED + 2);
        for (mode, st) in Precision::ALL.into_iter().zip(stats) {
            let b = error_bound(kind, mode);
            for (what, now, table) in [
                ("forward", st.max_forward.0, b.measured_forward),
                ("backward", st.max_backward.0, b.measured_backward),
            ] {
                if !(now <= table * (1.0 + 1e-3) && now >= 0.5 * table) {
                    stale.push(format!(
                        "{} {} {what}: measured {now:.3} ε·S, table says {table}",
                        kind.name(),
                        mode.name()
                    ));
                }
            }
        }
    }
    assert!(
        stale.is_empty(),
        "update ERROR_BOUNDS:\n{}",
        stale.join("\n")
    );
}
