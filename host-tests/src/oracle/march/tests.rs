use super::*;

#[test]
fn to_f64_round_trips() {
    for &x in &[
        1.0,
        -2.5,
        1e-300,
        6.4e6,
        0.1,
        1e30,
        -1e-30,
        std::f64::consts::PI,
    ] {
        assert_eq!(to_f64(&hp(x)), x, "{x}");
    }
    let third = div(&hp(1.0), &hp(3.0));
    assert_eq!(to_f64(&third), 1.0 / 3.0);
}
