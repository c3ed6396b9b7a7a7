//! `libcurvicast.a`: the curvicast kernel's C interface ([`curvicast_ffi`]) as a static library, for the host
//! and for `thumbv7em-none-eabihf`. The header is `kernel/ffi/include/curvicast.h`.
//!
//! **The panic-path proof.** The panic handler calls `curvicast_panic_path_is_reachable`, which no object
//! defines: a C program that links this library with `--gc-sections` links only if nothing it calls can reach
//! a panic (the same proof as the QEMU smoke test's, for every function the program references; the C tests
//! of `kernel/ffi/c` reference every function of the header).
#![no_std]
#![deny(unsafe_code)]

pub use curvicast_ffi::*;

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    #[allow(unsafe_code)] // declares a function that exists nowhere; no unsafe code runs
    unsafe extern "C" {
        /// Defined nowhere: a reference to it that survives the linker's garbage collection is a reachable
        /// panic path.
        safe fn curvicast_panic_path_is_reachable() -> !;
    }
    curvicast_panic_path_is_reachable()
}
