//! The measuring harness shared by the firmwares in `src/bin/`: one firmware per kernel feature, so that each
//! binary's code size is that feature's (minus the `empty` firmware, which holds only this harness).
//!
//! Runs on QEMU's `mps2-an386` (Cortex-M4F) with `-icount shift=0`: virtual time then advances one nanosecond per
//! guest instruction, and SysTick, clocked from the 25 MHz core clock, counts one tick per 40 instructions. The
//! Cortex-M4's cycle counter (DWT CYCCNT) is not modelled by QEMU, so instruction counts are what is measured:
//! [`Timer::calibrate`] times two delay loops of known length and prints the instructions per tick it finds,
//! so that a reader can check the conversion instead of trusting it.
//!
//! * [`Timer`]: SysTick as a free-running 24-bit down-counter; [`Timer::instructions`] runs a closure
//!   `repeat` times and returns the instructions per run.
//! * [`Fit`]: the least-squares line `instructions = set-up + marginal × crossings` over many rays, in integer
//!   arithmetic (no soft double precision in the firmware, whose size is measured).
//! * [`stack_high_water`]: paints the stack below the caller with a pattern, runs a closure, and finds the
//!   lowest word it overwrote.
//! * [`measure`]: one point of a series (instructions and stack of one workload), the step that the march and
//!   the loop check share.
//!
//! **A fair subtraction.** Every firmware's code size is quoted minus a baseline's: the `empty` firmware's, and
//! for a march firmware its workload firmware's (`march-workload-f32`, `-f64`: [`march_driver`] making the same
//! grid breakpoints and rays in the primitive type's own arithmetic, [`Scalar`], with no kernel call). So the
//! measuring code must be the same bytes in both: the closures are passed as `&mut dyn FnMut` (one copy of the
//! timing, stack and fit code, not one per closure type), the driver is one function out of line, and the `empty`
//! firmware's loop check goes through the same [`measure`] and [`print_fit`] as the march. What a march firmware
//! adds over its baseline is then the kernel, the libraries it links, and what a user of it writes: making a
//! grid from breakpoints and a ray from two points, folding the crossings.
//! * [`Out`]: one line of text over semihosting, integers and strings only (`core::fmt`'s float formatting has
//!   panic paths of its own and would break the panic-free proof).
//!
//! **The panic-path proof.** As in the QEMU smoke test, the panic handler calls a function that no object
//! defines, so a firmware links only if nothing it calls can panic.
//!
//! Output lines start with `m4f-bench <firmware>:` followed by `key value` pairs that `run.sh` collects.

#![no_std]
#![deny(unsafe_code)]

use core::ops::{Add, Div, Mul, Sub};
use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_semihosting::{debug, hio};
use curvicast::Real;
use curvicast::march::SphericalGrid;
use curvicast::ray::Ray;

/// SysTick as a free-running 24-bit down-counter on the core clock (interrupts off).
pub struct Timer {
    syst: SYST,
    /// Instructions per tick, as measured by [`Timer::calibrate`] (40 on QEMU's mps2-an386 with `-icount shift=0`).
    per_tick: u64,
}

/// The largest SysTick reload value (24 bits).
const RELOAD: u32 = 0x00FF_FFFF;

impl Timer {
    /// Takes the core peripherals and starts SysTick; `None` if they were already taken.
    pub fn new() -> Option<Timer> {
        let p = cortex_m::Peripherals::take()?;
        let mut syst = p.SYST;
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.disable_interrupt();
        syst.enable_counter();
        Some(Timer { syst, per_tick: 0 })
    }

    /// Ticks elapsed while `f` runs `repeat` times (runs must stay below 2²⁴ ticks together), and the last
    /// run's result.
    #[inline(never)]
    fn ticks(&mut self, repeat: u32, f: &mut dyn FnMut() -> u32) -> (u64, u32) {
        let a = SYST::get_current();
        let mut last = 0;
        for _ in 0..repeat {
            last = core::hint::black_box(f());
        }
        let b = SYST::get_current();
        let _ = &mut self.syst;
        (u64::from(a.wrapping_sub(b) & RELOAD), last)
    }

    /// Times `cortex_m::asm::delay` (a loop of two instructions per iteration, `n + 1` iterations) for two
    /// lengths and sets the instructions per tick from the difference; prints the calibration line and returns
    /// `(instructions in the difference, ticks in the difference)`.
    #[inline(never)]
    pub fn calibrate(&mut self, out: &mut Out) -> (u64, u64) {
        const SHORT: u32 = 100_000;
        const LONG: u32 = 300_000;
        let (t_short, _) = self.ticks(1, &mut || {
            cortex_m::asm::delay(SHORT);
            SHORT
        });
        let (t_long, _) = self.ticks(1, &mut || {
            cortex_m::asm::delay(LONG);
            LONG
        });
        let instructions = 2 * u64::from(LONG - SHORT);
        let ticks = t_long.saturating_sub(t_short);
        self.per_tick = instructions.checked_div(ticks).unwrap_or(0);
        out.str("calibration_instructions ")
            .num(instructions)
            .str(" calibration_ticks ")
            .num(ticks)
            .str(" instructions_per_tick ")
            .num(self.per_tick);
        out.flush();
        (instructions, ticks)
    }

    /// Instructions per run of `f`, over `repeat` runs timed together (for a resolution of
    /// `instructions_per_tick / repeat`; an indirect call per run is included, a constant), and the last run's
    /// result.
    pub fn instructions(&mut self, repeat: u32, f: &mut dyn FnMut() -> u32) -> (u64, u32) {
        let (t, r) = self.ticks(repeat, f);
        let total = t.saturating_mul(self.per_tick);
        (total.checked_div(u64::from(repeat)).unwrap_or(0), r)
    }
}

/// The least-squares line `y = a + b x` over points `(x, y)` (crossings, instructions), in exact integer sums.
#[derive(Default, Clone, Copy)]
pub struct Fit {
    n: i64,
    sx: i64,
    sy: i64,
    sxx: i64,
    sxy: i64,
}

impl Fit {
    /// Adds one point.
    #[inline(never)]
    pub fn add(&mut self, x: u64, y: u64) {
        let (x, y) = (x as i64, y as i64);
        self.n = self.n.saturating_add(1);
        self.sx = self.sx.saturating_add(x);
        self.sy = self.sy.saturating_add(y);
        self.sxx = self.sxx.saturating_add(x.saturating_mul(x));
        self.sxy = self.sxy.saturating_add(x.saturating_mul(y));
    }

    /// The number of points.
    pub fn points(&self) -> u64 {
        self.n as u64
    }

    /// The total of `x` (crossings) over the points.
    pub fn total_x(&self) -> u64 {
        self.sx as u64
    }

    /// `(10 × slope, intercept)`, rounded to nearest; `None` with fewer than two distinct `x`.
    #[inline(never)]
    pub fn slope_tenths_and_intercept(&self) -> Option<(i64, i64)> {
        let den = self
            .n
            .saturating_mul(self.sxx)
            .saturating_sub(self.sx.saturating_mul(self.sx));
        if den <= 0 {
            return None;
        }
        let num = self
            .n
            .saturating_mul(self.sxy)
            .saturating_sub(self.sx.saturating_mul(self.sy));
        let slope10 = div_round(num.saturating_mul(10), den)?;
        // a = (Σy − b Σx) / n with b = num / den: (Σy·den − num·Σx) / (n·den)
        let a_num = self
            .sy
            .saturating_mul(den)
            .saturating_sub(num.saturating_mul(self.sx));
        let intercept = div_round(a_num, self.n.saturating_mul(den))?;
        Some((slope10, intercept))
    }
}

/// The number of breakpoints per axis of the two benchmark grids (16³ and 32³ cells).
pub const GRID_BREAKPOINTS: [usize; 2] = [17, 33];
/// Rays per grid (most of them hit it).
pub const RAYS_PER_GRID: u32 = 48;
/// Runs timed together per ray.
pub const REPEAT: u32 = 8;

/// The primitive floats' own arithmetic, in which the march benchmark's workload is made (not the kernel's
/// [`Real`]): the code that makes it is then the harness's, the same bytes in a march firmware and in its
/// baseline, the workload firmware, which makes the same workload and marches nothing.
pub trait Scalar:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
{
    /// 0.
    const NIL: Self;
    /// 1.
    const UNIT: Self;
    /// 1/2.
    const ONE_HALF: Self;
    /// π, rounded to the type.
    const HALF_TURN: Self;
    /// `n` rounded to the type.
    fn of(n: i32) -> Self;
    /// The correctly rounded square root (the kernel's too, so the rays are the same bits as its own
    /// arithmetic would make them).
    fn root(self) -> Self;
}

impl Scalar for f32 {
    const NIL: f32 = 0.0;
    const UNIT: f32 = 1.0;
    const ONE_HALF: f32 = 0.5;
    const HALF_TURN: f32 = core::f32::consts::PI;
    #[inline]
    fn of(n: i32) -> f32 {
        n as f32
    }
    #[inline]
    fn root(self) -> f32 {
        curvicast_arm_sqrt::sqrtf(self)
    }
}

impl Scalar for f64 {
    const NIL: f64 = 0.0;
    const UNIT: f64 = 1.0;
    const ONE_HALF: f64 = 0.5;
    const HALF_TURN: f64 = core::f64::consts::PI;
    #[inline]
    fn of(n: i32) -> f64 {
        f64::from(n)
    }
    #[inline]
    fn root(self) -> f64 {
        libm::sqrt(self)
    }
}

/// The largest number of breakpoints per axis of the benchmark grids.
const MAX_BREAKPOINTS: usize = 33;

/// One benchmark grid's breakpoints `[r, θ, φ]` (a full sphere of unit radius), `n` per axis (at most
/// [`MAX_BREAKPOINTS`]), non-uniform: `hi u (1 + u) / 2` at `u = i / (n − 1)` from 0 to `hi` (1, π, 2π), both ends exact.
#[inline(never)]
pub fn grid_breakpoints<S: Scalar>(n: usize) -> [[S; MAX_BREAKPOINTS]; 3] {
    let mut axes = [[S::NIL; MAX_BREAKPOINTS]; 3];
    let last = n.saturating_sub(1);
    let d = S::of(i32::try_from(last).unwrap_or(1));
    let two_pi = S::HALF_TURN + S::HALF_TURN;
    for (out, hi) in axes.iter_mut().zip([S::UNIT, S::HALF_TURN, two_pi]) {
        for (i, b) in out.iter_mut().enumerate().take(n) {
            let u = S::of(i32::try_from(i).unwrap_or(0)) / d;
            *b = if i == last {
                hi
            } else {
                hi * u * (S::UNIT + u) * S::ONE_HALF
            };
        }
    }
    axes
}

/// The next benchmark ray, `[origin, direction]`: from a point on the sphere of radius 2.5 toward a point
/// within radius 0.9 of the center (so that it crosses the unit-radius grid), both drawn from `rng`.
#[inline(never)]
pub fn ray_ends<S: Scalar>(rng: &mut Rng) -> [[S; 3]; 2] {
    let mut point = |s: S| {
        let scale = S::of(1 << 23);
        let mut c = || S::of(rng.next24()) / scale - S::UNIT;
        let v = [c(), c(), c()];
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).root();
        if l > S::NIL {
            let k = s / l;
            v.map(|x| x * k)
        } else {
            [s, S::NIL, S::NIL]
        }
    };
    let from = point(S::of(5) * S::ONE_HALF);
    let to = point(S::of(9) / S::of(10));
    [from, [to[0] - from[0], to[1] - from[1], to[2] - from[2]]]
}

/// The seed of the benchmark rays' sequence.
const RAY_SEED: u32 = 0x5EED_0017;

/// One march: the sum of the crossings' lengths and the cell indices, folded so that nothing is optimised away,
/// and the number of crossings (`u32::MAX` if the march failed).
#[inline(never)]
fn march_once<T: Real>(grid: &SphericalGrid<'_, T>, ray: &Ray<T>) -> (T, u32, u32) {
    // internal iteration (`fold_in_place`): the serial engine's fastest use, with its error readable after
    let mut march = grid.march(ray);
    let (length, cells, mut count) =
        march.fold_in_place((T::ZERO, 0u32, 0u32), |(length, cells, count), c| {
            (
                length + (c.t_exit - c.t_enter),
                cells
                    .wrapping_add(c.cell[0] ^ c.cell[1].rotate_left(8) ^ c.cell[2].rotate_left(16)),
                count.wrapping_add(1),
            )
        });
    if march.error().is_some() {
        count = u32::MAX;
    }
    (length, cells, count)
}

/// A ray's part of the benchmark, as a firmware supplies it: given the ray's `[origin, direction]` and `timed`
/// (which times the run it is given, adds it to the fits and returns its count, as [`measure`] does), returns
/// what `timed` returned, or `u32::MAX` if the ray could not be made.
pub type EachRay<'a, S> =
    dyn FnMut(&[[S; 3]; 2], &mut dyn FnMut(&mut dyn FnMut() -> u32) -> u32) -> u32 + 'a;

/// A grid's part of the benchmark, as a firmware supplies it: given the grid's breakpoints `[r, θ, φ]` and a
/// function that runs an [`EachRay`] on the grid's rays, makes the grid and runs its [`EachRay`] (false if it
/// could not make the grid).
pub type PerGrid<'a, S> = dyn FnMut(&[&[S]; 3], &mut dyn FnMut(&mut EachRay<'_, S>)) -> bool + 'a;

/// The march benchmark's driver, the same code in a march firmware and in its baseline: for each grid of
/// [`GRID_BREAKPOINTS`] (a full sphere of unit radius, non-uniform breakpoints in r, θ and φ), `per_grid`
/// ([`PerGrid`]) makes the grid and has its [`EachRay`] run on [`RAYS_PER_GRID`] rays. Prints per grid and for both the
/// marginal instructions per crossing and the set-up per ray (least squares over the hitting rays), and the
/// stack high-water mark of one run. Returns false if a grid or a ray failed.
#[inline(never)]
pub fn march_driver<S: Scalar>(
    timer: &mut Timer,
    out: &mut Out,
    per_grid: &mut PerGrid<'_, S>,
) -> bool {
    let mut ok = true;
    let mut all = Fit::default();
    let mut stack = 0usize;
    let mut rng = Rng::new(RAY_SEED);
    for n in GRID_BREAKPOINTS {
        let [r, th, ph] = grid_breakpoints::<S>(n);
        let (Some(r), Some(th), Some(ph)) = (r.get(..n), th.get(..n), ph.get(..n)) else {
            return false;
        };
        let mut fit = Fit::default();
        let made = per_grid(&[r, th, ph], &mut |each_ray| {
            for _ in 0..RAYS_PER_GRID {
                let ends = ray_ends::<S>(&mut rng);
                let x = each_ray(&ends, &mut |run| {
                    measure(timer, &mut [&mut fit, &mut all], &mut stack, run)
                });
                if x == u32::MAX {
                    ok = false;
                }
            }
        });
        if !made {
            return false;
        }
        out.str("grid ").num(n as u64 - 1).str("^3");
        print_fit(out, &fit, MARCH_LABELS);
    }
    out.str("grid both");
    print_fit(out, &all, MARCH_LABELS);
    out.str("march_stack_bytes ").num(stack as u64);
    out.flush();
    ok
}

/// The march benchmark in precision `T` ([`march_driver`]): each grid made by the kernel, each ray made and
/// marched by it (the ray made outside the timed run).
pub fn march_bench<T: Real + Scalar>(timer: &mut Timer, out: &mut Out) -> bool {
    const MAX: usize = MAX_BREAKPOINTS;
    march_driver::<T>(timer, out, &mut |[r, th, ph], rays| {
        let mut ws = [<T as Real>::ZERO; SphericalGrid::<f32>::workspace_len(MAX, MAX, MAX)];
        let Ok(grid) = SphericalGrid::new(r, th, ph, &mut ws) else {
            return false;
        };
        rays(&mut |[origin, dir], timed| {
            let Ok(ray) = Ray::new(*origin, *dir) else {
                return u32::MAX;
            };
            timed(&mut || {
                let (length, cells, count) = march_once(&grid, &ray);
                core::hint::black_box((length, cells));
                count
            })
        });
        true
    })
}

/// The march benchmark's workload alone, its baseline ([`march_driver`] with no kernel call): each grid's
/// breakpoints and each ray's ends are made and kept (`black_box`), and a run counts nothing, so no fit has a
/// point. A march firmware's code size is quoted minus this firmware's.
pub fn march_workload<S: Scalar>(timer: &mut Timer, out: &mut Out) -> bool {
    march_driver::<S>(timer, out, &mut |axes, rays| {
        core::hint::black_box(axes);
        rays(&mut |ends, timed| {
            timed(&mut || {
                core::hint::black_box(ends);
                0
            })
        });
        true
    })
}

/// One point of a series: `run` (which returns its `x`, e.g. its crossings; 0 for a run that does not count,
/// `u32::MAX` for a failure) is timed over [`REPEAT`] runs and, if `0 < x < u32::MAX`, `(x, instructions per
/// run)` is added to every fit of `fits` and `stack` raised to its stack high-water mark. Returns `x`.
#[inline(never)]
pub fn measure(
    timer: &mut Timer,
    fits: &mut [&mut Fit],
    stack: &mut usize,
    run: &mut dyn FnMut() -> u32,
) -> u32 {
    let (instructions, x) = timer.instructions(REPEAT, run);
    if x > 0 && x < u32::MAX {
        for fit in fits.iter_mut() {
            fit.add(u64::from(x), instructions);
        }
        let (bytes, _) = stack_high_water(run);
        *stack = (*stack).max(bytes);
    }
    x
}

/// `<points> N<x> N<slope> X.Y setup N` (the fit's number of points, total `x`, slope and intercept; the labels
/// name them, e.g. `" rays "`, `" crossings "`, `" per_crossing "`) and the end of the line.
#[inline(never)]
pub fn print_fit(out: &mut Out, fit: &Fit, [points, x, slope]: [&str; 3]) {
    out.str(points).num(fit.points()).str(x).num(fit.total_x());
    match fit.slope_tenths_and_intercept() {
        Some((b, a)) => out.str(slope).tenths(b).str(" setup ").int(a),
        None => out.str(slope).str("none"),
    };
    out.flush();
}

/// [`print_fit`]'s labels for a march.
const MARCH_LABELS: [&str; 3] = [" rays ", " crossings ", " per_crossing "];

/// The measuring pipeline checked on a loop of known length: `cortex_m::asm::delay(n)` runs `n + 1` iterations
/// of two instructions, so the least-squares slope over n = 50, 100, …, 800 must be 2.0 instructions per
/// iteration. Prints it; returns whether it is 2.0.
#[inline(never)]
pub fn loop_check(timer: &mut Timer, out: &mut Out) -> bool {
    let mut fit = Fit::default();
    let mut stack = 0;
    for k in 1..=16u32 {
        let n = k.wrapping_mul(50);
        measure(timer, &mut [&mut fit], &mut stack, &mut || {
            cortex_m::asm::delay(n);
            n
        });
    }
    out.str("delay_loop");
    print_fit(
        out,
        &fit,
        [" runs ", " iterations ", " loop_per_iteration "],
    );
    fit.slope_tenths_and_intercept()
        .is_some_and(|(b, _)| b == 20)
}

/// `a / b` rounded to nearest (ties away from zero), `b > 0`.
fn div_round(a: i64, b: i64) -> Option<i64> {
    let half = b / 2;
    if a >= 0 {
        a.saturating_add(half).checked_div(b)
    } else {
        a.saturating_sub(half).checked_div(b)
    }
}

/// The pattern painted on the stack.
const PAINT: u32 = 0xC5AC_CE55;

/// The deepest stack use, in bytes below the caller's stack pointer, of running `f` (which must need less than
/// `DEPTH` bytes): the words below the current stack pointer are painted with a pattern, `f` runs, and the
/// lowest word no longer holding the pattern marks the high-water mark. Returns `(bytes, f's result)`.
#[inline(never)]
pub fn stack_high_water(f: &mut dyn FnMut() -> u32) -> (usize, u32) {
    /// How deep below the current stack pointer the pattern goes.
    const DEPTH: usize = 16 * 1024;
    let sp = cortex_m::register::msp::read() as usize;
    // The words in [sp − DEPTH, sp − 64): below this function's frame and that of `paint` itself.
    let top = sp.wrapping_sub(64) & !3;
    let bottom = sp.wrapping_sub(DEPTH);
    paint(bottom, top);
    let r = core::hint::black_box(f());
    let lowest = lowest_touched(bottom, top);
    (sp.saturating_sub(lowest), r)
}

/// Writes [`PAINT`] into every word in `[bottom, top)`.
#[inline(never)]
#[allow(unsafe_code)]
fn paint(bottom: usize, top: usize) {
    let mut a = bottom;
    while a < top {
        // SAFETY: `[bottom, top)` lies in the stack region below every live frame (the caller keeps it at least
        // 64 bytes below its own stack pointer, and this function needs no stack of its own beyond that), so no
        // live value is overwritten; the address is word-aligned RAM of the mps2-an386 memory map.
        unsafe { core::ptr::write_volatile(a as *mut u32, PAINT) };
        a = a.wrapping_add(4);
    }
}

/// The lowest address in `[bottom, top)` whose word no longer holds [`PAINT`] (`top` if none).
#[inline(never)]
#[allow(unsafe_code)]
fn lowest_touched(bottom: usize, top: usize) -> usize {
    let mut a = bottom;
    while a < top {
        // SAFETY: reads word-aligned RAM below the stack pointer (see `paint`); values there are dead.
        if unsafe { core::ptr::read_volatile(a as *const u32) } != PAINT {
            return a;
        }
        a = a.wrapping_add(4);
    }
    top
}

/// A deterministic pseudo-random sequence (xorshift32) for the benchmark rays.
pub struct Rng(u32);

impl Rng {
    /// A sequence from a non-zero seed.
    pub fn new(seed: u32) -> Rng {
        Rng(seed | 1)
    }
    /// An integer in `[0, 2²⁴)`.
    pub fn next24(&mut self) -> i32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        (x >> 8) as i32
    }
}

/// One line of output over semihosting, prefixed with `m4f-bench <firmware>:`.
pub struct Out {
    stream: Option<hio::HostStream>,
    name: &'static str,
    buf: [u8; 200],
    len: usize,
}

impl Out {
    /// Opens the host's stdout for the firmware `name`.
    #[inline(never)]
    pub fn new(name: &'static str) -> Out {
        let mut o = Out {
            stream: hio::hstdout().ok(),
            name,
            buf: [0; 200],
            len: 0,
        };
        o.prefix();
        o
    }

    #[inline(never)]
    fn prefix(&mut self) {
        self.len = 0;
        let name = self.name;
        self.str("m4f-bench ").str(name).str(": ");
    }

    /// Appends a string (cut at the buffer's end).
    #[inline(never)]
    pub fn str(&mut self, s: &str) -> &mut Self {
        for &b in s.as_bytes() {
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = b;
                self.len = self.len.wrapping_add(1);
            }
        }
        self
    }

    /// Appends the decimal digits of `n`.
    #[inline(never)]
    pub fn num(&mut self, n: u64) -> &mut Self {
        let mut digits = [0u8; 20];
        let mut i = digits.len();
        let mut n = n;
        loop {
            i = i.wrapping_sub(1);
            if let Some(d) = digits.get_mut(i) {
                *d = b'0'.wrapping_add((n % 10) as u8);
            }
            n /= 10;
            if n == 0 || i == 0 {
                break;
            }
        }
        for &d in digits.get(i..).unwrap_or(&[]) {
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = d;
                self.len = self.len.wrapping_add(1);
            }
        }
        self
    }

    /// Appends a signed number.
    #[inline(never)]
    pub fn int(&mut self, n: i64) -> &mut Self {
        if n < 0 {
            self.str("-");
        }
        self.num(n.unsigned_abs())
    }

    /// Appends `n / 10` with one decimal (`n` in tenths).
    #[inline(never)]
    pub fn tenths(&mut self, n: i64) -> &mut Self {
        if n < 0 {
            self.str("-");
        }
        let m = n.unsigned_abs();
        self.num(m / 10).str(".").num(m % 10)
    }

    /// Writes the line (and starts the next one).
    #[inline(never)]
    pub fn flush(&mut self) {
        let line = self.buf.get(..self.len).unwrap_or(&[]);
        if let Some(s) = self.stream.as_mut() {
            // Nothing useful can be done if the host stops listening; the exit status still tells.
            let _ = s.write_all(line);
            let _ = s.write_all(b"\n");
        }
        self.prefix();
    }
}

/// Prints `status ok` or `status FAILED` and ends the emulation with the matching exit status.
pub fn finish(out: &mut Out, ok: bool) -> ! {
    out.str("status ").str(if ok { "ok" } else { "FAILED" });
    out.flush();
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::wfi();
    }
}

/// Reached only through a panic path. It calls a function that no object defines, so the final link fails
/// ("undefined symbol: curvicast_panic_path_is_reachable") whenever any panic path survives optimisation.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    #[allow(unsafe_code)]
    unsafe extern "Rust" {
        safe fn curvicast_panic_path_is_reachable() -> !;
    }
    curvicast_panic_path_is_reachable()
}
