//! The harness alone (calibration, the loop check, output, the panic-free proof): the code size the other
//! firmwares are measured against.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use curvicast_m4f_bench::{Out, Timer, finish, loop_check};

#[entry]
fn main() -> ! {
    let mut out = Out::new("empty");
    let Some(mut timer) = Timer::new() else {
        finish(&mut out, false)
    };
    timer.calibrate(&mut out);
    let ok = loop_check(&mut timer, &mut out);
    finish(&mut out, ok)
}
