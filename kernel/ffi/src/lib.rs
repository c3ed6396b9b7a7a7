//! # curvicast-ffi: the kernel's C interface
//!
//! `extern "C"` entry points over the public API of the [`curvicast`] kernel, for firmware written in C. Like
//! the kernel it is `#![no_std]`, allocates nothing and never panics: every failure is a [`curvicast_status`],
//! one code per variant of the kernel's typed errors, plus four for the boundary itself (a NULL pointer, a
//! misaligned one, a short buffer, an object used before its `init`).
//!
//! The static library C links is built by `kernel/ffi/staticlib` (`libcurvicast.a`); its header,
//! `kernel/ffi/include/curvicast.h`, is generated from this crate by cbindgen. `docs/c-interface.md` shows a
//! complete C program, the build flags and the link line.
//!
//! **Memory.** The caller owns every byte. Objects the kernel keeps between calls (a grid, a march, a terrain,
//! a picker) live in caller-provided storage whose size and alignment are fixed in the header
//! (`curvicast_march_f32` and so on: arrays of `uint64_t`, so a C declaration has the right alignment); this
//! crate checks at compile time, for each target it is built for, that the kernel's object fits. They borrow:
//! a grid its breakpoints and workspace, a march its grid, a terrain its heights, node records and residency
//! flags, a picker its terrain. The caller keeps what is borrowed alive, in place and unchanged (residency
//! flags aside) while the borrower is used: C cannot be checked for this, so it is the contract of every
//! function that takes a borrower.
//!
//! **Checks at the boundary.** NULL and misaligned pointers are [`curvicast_status::CURVICAST_NULL_POINTER`]
//! and [`curvicast_status::CURVICAST_MISALIGNED`]; a buffer shorter than the kernel needs is the kernel's own
//! error for it; an object whose storage was not filled by its `init` (zeroed, or failed) is
//! [`curvicast_status::CURVICAST_NOT_INITIALIZED`], found from a tag word each `init` writes. Lengths are
//! counts of elements, never bytes.
//!
//! The unsafe of raw pointers lives in this module's helpers (`Holds`, `get`, `slice`, …), each block with
//! its safety argument; the modules [`march`], [`terrain`] and [`tessellate`] call them and the kernel's safe
//! API.
#![no_std]
#![allow(non_camel_case_types)]
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing,
    clippy::arithmetic_side_effects
)]
#![cfg_attr(
    test,
    allow(
        clippy::indexing_slicing,
        clippy::arithmetic_side_effects,
        clippy::unwrap_used
    )
)]

#[cfg(test)]
extern crate std;

pub mod march;
pub mod picker;
mod status;
pub mod terrain;
pub mod tessellate;
#[cfg(test)]
mod tests;

pub use status::curvicast_status;

use core::mem::{align_of, size_of};
use curvicast::Real;
use curvicast::ray::Ray;

/// A ray `origin + t·dir`, `t_min ≤ t ≤ t_max`, in single precision (`t_min = 0`, `t_max = INFINITY` for a
/// whole ray).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct curvicast_ray_f32 {
    /// Origin.
    pub origin: [f32; 3],
    /// Direction (any nonzero length; `t` is in its units).
    pub dir: [f32; 3],
    /// Start of the interval.
    pub t_min: f32,
    /// End of the interval.
    pub t_max: f32,
}

/// A ray `origin + t·dir`, `t_min ≤ t ≤ t_max`, in double precision (`t_min = 0`, `t_max = INFINITY` for a
/// whole ray).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct curvicast_ray_f64 {
    /// Origin.
    pub origin: [f64; 3],
    /// Direction (any nonzero length; `t` is in its units).
    pub dir: [f64; 3],
    /// Start of the interval.
    pub t_min: f64,
    /// End of the interval.
    pub t_max: f64,
}

/// The C ray of a scalar type, turned into the kernel's [`Ray`] (validated there).
pub(crate) trait CRay<T: Real> {
    fn ray(&self) -> Result<Ray<T>, curvicast_status>;
}

/// [`CRay`] for one precision.
macro_rules! c_ray {
    ($t:ty, $ray:ident) => {
        impl CRay<$t> for $ray {
            fn ray(&self) -> Result<Ray<$t>, curvicast_status> {
                Ok(Ray::new(self.origin, self.dir)?.with_interval(self.t_min, self.t_max)?)
            }
        }
    };
}
c_ray!(f32, curvicast_ray_f32);
c_ray!(f64, curvicast_ray_f64);

/// The alignment of every storage object (`curvicast_grid_f32`, …): they are arrays of `uint64_t`.
pub const CURVICAST_STORAGE_ALIGN: usize = 8;

/// A kernel object as it sits in caller storage: a tag word, then the object.
#[repr(C)]
struct Slot<V> {
    tag: u64,
    value: V,
}

/// A C storage type (an array of `u64`) and the kernel object it holds.
///
/// # Safety
/// `TAG` is nonzero and differs between implementors, and `Self` is a `#[repr(C)]` array of `u64` (so any bit
/// pattern is a valid `Self`, and C's declaration of it has `Self`'s size and alignment).
pub(crate) unsafe trait Holds: Sized {
    /// The kernel object.
    type Value;
    /// The tag `init` writes before the object.
    const TAG: u64;
    /// The object fits, at the storage's alignment: a compile-time error otherwise (evaluated per target).
    const FITS: () = assert!(
        size_of::<Slot<Self::Value>>() <= size_of::<Self>()
            && align_of::<Slot<Self::Value>>() <= align_of::<Self>()
            && align_of::<Self>() == CURVICAST_STORAGE_ALIGN,
        "a kernel object outgrew its C storage: raise the storage's size in the header"
    );
}

/// Checks a pointer for NULL and alignment.
fn check<T>(p: *const T) -> Result<(), curvicast_status> {
    if p.is_null() {
        Err(curvicast_status::CURVICAST_NULL_POINTER)
    } else if !p.is_aligned() {
        Err(curvicast_status::CURVICAST_MISALIGNED)
    } else {
        Ok(())
    }
}

/// Stores `value` in the storage at `p` after its tag. On an error from `value` the tag is cleared, so that a
/// storage whose `init` failed reads as not initialized.
///
/// # Safety
/// `p` is NULL or points to writable memory of `S`'s size that nothing else accesses during the call.
unsafe fn init<S: Holds>(
    p: *mut S,
    value: impl FnOnce() -> Result<S::Value, curvicast_status>,
) -> curvicast_status {
    let () = S::FITS;
    if let Err(e) = check(p) {
        return e;
    }
    let slot = p.cast::<Slot<S::Value>>();
    match value() {
        Ok(v) => {
            // SAFETY: `p` is non-null, aligned for `S` and so for `Slot` (FITS), and writable for `S`'s size,
            // which covers `Slot` (FITS). `write` does not read or drop the old bytes.
            unsafe {
                slot.write(Slot {
                    tag: S::TAG,
                    value: v,
                })
            };
            curvicast_status::CURVICAST_OK
        }
        Err(e) => {
            // SAFETY: as above; the tag is the first `u64` of the storage (`Slot` is `repr(C)`).
            unsafe { p.cast::<u64>().write(0) };
            e
        }
    }
}

/// The object in the storage at `p`, if an `init` put it there.
///
/// # Safety
/// `p` is NULL or points to storage of type `S` that is initialized memory (a C object, zeroed or filled by an
/// `init`) and that nothing writes during `'a`; what the object borrows is alive and unchanged during `'a`.
unsafe fn get<'a, S: Holds>(p: *const S) -> Result<&'a S::Value, curvicast_status> {
    let () = S::FITS;
    check(p)?;
    // SAFETY: `p` is non-null and aligned for `S` (so for `u64`), and the storage's first word is initialized.
    if unsafe { p.cast::<u64>().read() } != S::TAG {
        return Err(curvicast_status::CURVICAST_NOT_INITIALIZED);
    }
    // SAFETY: the tag says an `init` wrote a `Slot<S::Value>` here (tags are unique per storage type and `init`
    // clears it on failure); aligned and in bounds by FITS; no one writes it during `'a` (the contract).
    Ok(unsafe { &(*p.cast::<Slot<S::Value>>()).value })
}

/// As [`get`], mutably.
///
/// # Safety
/// As [`get`], and nothing else reads or writes the storage during `'a`.
unsafe fn get_mut<'a, S: Holds>(p: *mut S) -> Result<&'a mut S::Value, curvicast_status> {
    let () = S::FITS;
    check(p)?;
    // SAFETY: as in `get`.
    if unsafe { p.cast::<u64>().read() } != S::TAG {
        return Err(curvicast_status::CURVICAST_NOT_INITIALIZED);
    }
    // SAFETY: as in `get`, and the access is exclusive during `'a` (the contract).
    Ok(unsafe { &mut (*p.cast::<Slot<S::Value>>()).value })
}

/// A C struct passed by pointer.
///
/// # Safety
/// `p` is NULL or points to an initialized `T` that nothing writes during `'a`.
unsafe fn read<'a, T>(p: *const T) -> Result<&'a T, curvicast_status> {
    check(p)?;
    // SAFETY: non-null and aligned (checked); initialized and not written during `'a` (the contract).
    Ok(unsafe { &*p })
}

/// An out-parameter.
///
/// # Safety
/// `p` is NULL or points to a writable `T` that nothing else accesses during `'a`.
unsafe fn out<'a, T>(p: *mut T) -> Result<&'a mut T, curvicast_status> {
    check(p)?;
    // SAFETY: non-null and aligned (checked), exclusive during `'a` (the contract). The C types this is used
    // with are plain numbers, for which every bit pattern is valid, so the old contents are a valid `T`.
    Ok(unsafe { &mut *p })
}

/// Whether `len` elements of `T` fit in `isize::MAX` bytes (what a slice may span).
fn fits_address_space<T>(len: usize) -> bool {
    len.checked_mul(size_of::<T>())
        .is_some_and(|b| b <= isize::MAX as usize)
}

/// A C array of `len` elements. NULL with `len = 0` is the empty slice.
///
/// # Safety
/// Unless `len` is 0, `p` is NULL or points to `len` initialized `T` that nothing writes during `'a`.
unsafe fn slice<'a, T>(p: *const T, len: usize) -> Result<&'a [T], curvicast_status> {
    if len == 0 && p.is_null() {
        return Ok(&[]);
    }
    check(p)?;
    if !fits_address_space::<T>(len) {
        return Err(curvicast_status::CURVICAST_BUFFER_TOO_LARGE);
    }
    // SAFETY: non-null and aligned (checked); `len` initialized elements (the contract) whose total size fits
    // in `isize` (checked); not written during `'a` (the contract).
    Ok(unsafe { core::slice::from_raw_parts(p, len) })
}

/// A writable C array of `len` elements. NULL with `len = 0` is the empty slice.
///
/// # Safety
/// Unless `len` is 0, `p` is NULL or points to `len` writable `T` that nothing else accesses during `'a`; `T` is
/// a plain-number type (every bit pattern valid) or the memory is initialized.
unsafe fn slice_mut<'a, T>(p: *mut T, len: usize) -> Result<&'a mut [T], curvicast_status> {
    if len == 0 && p.is_null() {
        return Ok(&mut []);
    }
    check(p)?;
    if !fits_address_space::<T>(len) {
        return Err(curvicast_status::CURVICAST_BUFFER_TOO_LARGE);
    }
    // SAFETY: non-null and aligned (checked); `len` elements exclusively ours during `'a` whose total size
    // fits in `isize` (checked); valid values (the contract).
    Ok(unsafe { core::slice::from_raw_parts_mut(p, len) })
}

/// A point of `N` coordinates.
///
/// # Safety
/// `p` is NULL or points to `N` initialized scalars.
unsafe fn point<T: Real, const N: usize>(p: *const T) -> Result<[T; N], curvicast_status> {
    // SAFETY: the contract.
    let s = unsafe { slice(p, N) }?;
    s.try_into()
        .map_err(|_| curvicast_status::CURVICAST_NULL_POINTER)
}

/// An optional point: NULL is the origin.
///
/// # Safety
/// `p` is NULL or points to `N` initialized scalars.
unsafe fn point_or_origin<T: Real, const N: usize>(
    p: *const T,
) -> Result<[T; N], curvicast_status> {
    if p.is_null() {
        return Ok([T::ZERO; N]);
    }
    // SAFETY: the contract.
    unsafe { point(p) }
}

/// Writes `value` through `p` without reading what is there (for types such as `bool` whose old bytes,
/// written by C, need not be a valid value).
///
/// # Safety
/// `p` is NULL or points to a writable `T` that nothing else accesses during the call.
unsafe fn write<T>(p: *mut T, value: T) -> Result<(), curvicast_status> {
    check(p)?;
    // SAFETY: non-null and aligned (checked), writable (the contract); `write` neither reads nor drops.
    unsafe { p.write(value) };
    Ok(())
}

/// Writes `value` through `p` if it is not NULL (an optional out-parameter).
///
/// # Safety
/// As [`out`].
unsafe fn put_optional<T>(p: *mut T, value: T) -> Result<(), curvicast_status> {
    if !p.is_null() {
        // SAFETY: the contract.
        *unsafe { out(p) }? = value;
    }
    Ok(())
}
