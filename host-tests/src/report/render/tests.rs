use super::*;

#[test]
fn image_error_skips_pixels_outside_the_field_and_scales_by_the_truth() {
    let truth = [0.0, 2.0, 4.0, 0.0];
    let values = [0.0, 2.5, 4.0, 0.1];
    let e = image_error(&values, &truth);
    // three pixels count: errors 0.5, 0, 0.1
    let rms = ((0.25 + 0.01) / 3.0f64).sqrt();
    assert!((e.rms_abs - rms).abs() < 1e-15);
    assert_eq!(e.max_abs, 0.5);
    assert!((e.rms_rel - rms / (20.0f64 / 3.0).sqrt()).abs() < 1e-15);
    assert_eq!(e.max_rel, 0.125);
}

fn run(native: bool, seconds: f64, rms_rel: f64) -> Run {
    Run {
        native,
        label: format!("{seconds}"),
        seconds,
        resample: None,
        crossings_per_ray: 0.0,
        err: ImageError {
            rms_abs: 0.0,
            max_abs: 0.0,
            rms_rel,
            max_rel: 0.0,
        },
        values: Vec::new(),
    }
}

#[test]
fn conclusions_pick_the_cheapest_run_meeting_each_target() {
    let runs = [
        run(true, 1.0, 5e-3),
        run(true, 2.0, 5e-4),
        run(false, 0.5, 2e-2),
        run(false, 4.0, 5e-3),
    ];
    let text = conclusions(&runs);
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].contains("native 1 cells in 1.00 s") && lines[0].contains("4.0× faster"),
        "{text}"
    );
    assert!(
        lines[1].contains("native 2 cells") && lines[1].contains("no Cartesian"),
        "{text}"
    );
    assert!(lines[2].contains("neither"), "{text}");
}
