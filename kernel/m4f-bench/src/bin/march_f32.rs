//! The serial march in `f32` on two full-sphere grids (16³ and 32³ cells, non-uniform breakpoints): marginal
//! instructions per crossing, set-up per ray, and one march's stack high-water mark.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use curvicast_m4f_bench::{Out, Timer, finish, loop_check, march_bench};

#[entry]
fn main() -> ! {
    let mut out = Out::new("march-f32");
    let Some(mut timer) = Timer::new() else {
        finish(&mut out, false)
    };
    timer.calibrate(&mut out);
    let ok = loop_check(&mut timer, &mut out);
    let ok = march_bench::<f32>(&mut timer, &mut out) && ok;
    finish(&mut out, ok)
}
