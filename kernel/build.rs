//! Tells the kernel whether the build optimises for size (Cargo's `opt-level` "s" or "z"): then
//! `cfg(curvicast_small_code)` is set, and the march keeps its per-event step out of line (one copy instead of one
//! per engine loop), as it does the small helpers that the march inlines at many places (the scale conversions of
//! `t`, `max`, `max_abs`, the cone's Newton step, the stable quadratic), which makes the code smaller and each
//! crossing a few instructions slower. The answers are the same either way.
fn main() {
    println!("cargo::rustc-check-cfg=cfg(curvicast_small_code)");
    println!("cargo::rerun-if-env-changed=OPT_LEVEL");
    if matches!(std::env::var("OPT_LEVEL").as_deref(), Ok("s" | "z")) {
        println!("cargo::rustc-cfg=curvicast_small_code");
    }
}
