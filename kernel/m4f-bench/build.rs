//! Puts the QEMU smoke test's `memory.x` (the mps2-an386 memory map) where cortex-m-rt's `link.x` finds it.

use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::write(
        out.join("memory.x"),
        include_bytes!("../qemu-smoke/memory.x"),
    )
    .expect("write memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=../qemu-smoke/memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}
