//! Edge-bevels the unit sphere at level 2 in `f32` (the edge-beveling thesis, ch. 4): instructions per bevel and its stack
//! high-water mark; checks that every face's center lies on the sphere.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use curvicast::tessellate::bevel::{Face, bevel_sphere, face_count, vertex_count};
use curvicast::vec3::V3;
use curvicast_m4f_bench::{Out, REPEAT, Timer, finish, loop_check, stack_high_water};

const LEVEL: u32 = 2;
const NV: usize = vertex_count(LEVEL);
const NF: usize = face_count(LEVEL);

/// One bevel into fixed buffers; `Some(worst |‖center‖ − 1|)` on success.
#[inline(never)]
fn bevel() -> Option<f32> {
    let mut vertices = [V3::<f32>::ZERO; NV];
    let face = Face {
        center: V3::ZERO,
        normal: V3::ZERO,
        vertices: [0; 6],
        len: 0,
    };
    let mut faces = [face; NF];
    let counts = bevel_sphere(LEVEL, 1.0_f32, &mut vertices, &mut faces).ok()?;
    (counts.faces == NF).then(|| {
        faces
            .iter()
            .map(|f| (f.center.length() - 1.0).abs())
            .fold(0.0, f32::max)
    })
}

#[entry]
fn main() -> ! {
    let mut out = Out::new("bevel-f32");
    let Some(mut timer) = Timer::new() else {
        finish(&mut out, false)
    };
    timer.calibrate(&mut out);
    let ok = loop_check(&mut timer, &mut out);
    // The worst distance's bits, or those of NaN if the bevel failed.
    let mut run = || bevel().unwrap_or(f32::NAN).to_bits();
    let (instructions, worst) = timer.instructions(REPEAT, &mut run);
    let (stack, _) = stack_high_water(&mut run);
    let on_sphere = f32::from_bits(worst) <= 1e-5;
    out.str("level ")
        .num(u64::from(LEVEL))
        .str(" faces ")
        .num(NF as u64)
        .str(" per_bevel ")
        .num(instructions)
        .str(" stack_bytes ")
        .num(stack as u64);
    out.flush();
    finish(&mut out, ok && on_sphere)
}
