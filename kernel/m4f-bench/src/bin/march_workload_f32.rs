//! The baseline of the `march-f32` firmware's code size: the harness and the march benchmark's workload in
//! `f32` (the two grids' breakpoints and the rays, made as `march-f32` makes them), with no kernel call.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use curvicast_m4f_bench::{Out, Timer, finish, loop_check, march_workload};

#[entry]
fn main() -> ! {
    let mut out = Out::new("march-workload-f32");
    let Some(mut timer) = Timer::new() else {
        finish(&mut out, false)
    };
    timer.calibrate(&mut out);
    let ok = loop_check(&mut timer, &mut out);
    let ok = march_workload::<f32>(&mut timer, &mut out) && ok;
    finish(&mut out, ok)
}
