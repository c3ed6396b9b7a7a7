//! Pickers over a built terrain: `init`, and per ray `pick`, `pick_t` and `line_of_sight` (Wartell et al.; the
//! kernel's `Picker`).

use crate::terrain::{
    CPicker, Scalar, curvicast_hit_f32, curvicast_hit_f64, curvicast_picker_f32,
    curvicast_picker_f64, curvicast_terrain_f32, curvicast_terrain_f64,
};
use crate::{CRay, curvicast_ray_f32, curvicast_ray_f64, curvicast_status};
use crate::{get, init, out, point, put_optional, read, write};
use curvicast::terrain::TerrainError;

/// Fills `picker` for `terrain`: the zones' bounding volumes and the global bound, computed once. Blocks of
/// nodes shallower than `min_level` never stand in for missing finer ones (0: any resident block may).
///
/// # Safety
/// Each pointer is NULL or valid; `terrain` stays alive, in place and unchanged while `picker` is used.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_picker_f32_init(
    picker: *mut curvicast_picker_f32,
    terrain: *const curvicast_terrain_f32,
    min_level: u8,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe {
        init(picker, || {
            Ok(CPicker::new(get(terrain)?)?.with_min_level(min_level))
        })
    }
}

/// [`curvicast_picker_f32_init`] in double precision.
///
/// # Safety
/// As [`curvicast_picker_f32_init`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_picker_f64_init(
    picker: *mut curvicast_picker_f64,
    terrain: *const curvicast_terrain_f64,
    min_level: u8,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe {
        init(picker, || {
            Ok(CPicker::new(get(terrain)?)?.with_min_level(min_level))
        })
    }
}

/// A kernel answer as a status: its `Ok` value, or the error's status with `NeedsBlock`'s node written to
/// `needs_node` (if not NULL).
///
/// # Safety
/// `needs_node` is NULL or valid.
unsafe fn answer<V>(
    r: Result<V, TerrainError>,
    needs_node: *mut u32,
) -> Result<V, curvicast_status> {
    r.or_else(|e| {
        if let TerrainError::NeedsBlock(id) = e {
            // SAFETY: the contract.
            unsafe { put_optional(needs_node, id.0) }?;
        }
        Err(e.into())
    })
}

/// # Safety
/// As [`curvicast_picker_f32_pick`].
unsafe fn pick<T: Scalar, R: CRay<T>>(
    picker: *const T::Picker,
    ray: *const R,
    hit: *mut T::Hit,
    needs_node: *mut u32,
) -> Result<(), curvicast_status> {
    // SAFETY: the contract.
    let (p, ray, hit) = unsafe { (get(picker)?, read(ray)?.ray()?, out(hit)?) };
    // SAFETY: the contract.
    match unsafe { answer(p.pick(&ray), needs_node) }? {
        Some(h) => {
            *hit = T::hit(h);
            Ok(())
        }
        None => Err(curvicast_status::CURVICAST_NO_HIT),
    }
}

/// # Safety
/// As [`curvicast_picker_f32_pick_t`].
unsafe fn pick_t<T: Scalar, R: CRay<T>>(
    picker: *const T::Picker,
    ray: *const R,
    t: *mut T,
    cell: *mut [u32; 2],
    needs_node: *mut u32,
) -> Result<(), curvicast_status> {
    // SAFETY: the contract.
    let (p, ray, t, cell) = unsafe { (get(picker)?, read(ray)?.ray()?, out(t)?, out(cell)?) };
    // SAFETY: the contract.
    match unsafe { answer(p.pick_t(&ray), needs_node) }? {
        Some((s, c)) => {
            (*t, *cell) = (s, c);
            Ok(())
        }
        None => Err(curvicast_status::CURVICAST_NO_HIT),
    }
}

/// # Safety
/// As [`curvicast_picker_f32_line_of_sight`].
unsafe fn line_of_sight<T: Scalar>(
    picker: *const T::Picker,
    a: *const T,
    b: *const T,
    clear: *mut bool,
    needs_node: *mut u32,
) -> Result<(), curvicast_status> {
    crate::check(clear)?;
    // SAFETY: the contract.
    let (p, a, b) = unsafe { (get(picker)?, point::<T, 3>(a)?, point::<T, 3>(b)?) };
    // SAFETY: the contract.
    let answer = unsafe { answer(p.line_of_sight(a, b), needs_node) }?;
    // SAFETY: the contract (a C `bool` is written whole, not read).
    unsafe { write(clear, answer) }
}

/// The nearest hit of `ray` with the terrain (Wartell et al. §4: the traversal; the hit refined in double-double
/// and converted to geodetic coordinates): `CURVICAST_OK` with `*hit` written, `CURVICAST_NO_HIT`, or an error
/// (`CURVICAST_TERRAIN_NEEDS_BLOCK`: the node whose block to page in, written to `*needs_node` unless NULL).
///
/// # Safety
/// Each pointer is NULL or valid; what the picker borrows is alive and unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_picker_f32_pick(
    picker: *const curvicast_picker_f32,
    ray: *const curvicast_ray_f32,
    hit: *mut curvicast_hit_f32,
    needs_node: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above.
    crate::status::status(unsafe { pick::<f32, _>(picker, ray, hit, needs_node) })
}

/// [`curvicast_picker_f32_pick`] in double precision.
///
/// # Safety
/// As [`curvicast_picker_f32_pick`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_picker_f64_pick(
    picker: *const curvicast_picker_f64,
    ray: *const curvicast_ray_f64,
    hit: *mut curvicast_hit_f64,
    needs_node: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above.
    crate::status::status(unsafe { pick::<f64, _>(picker, ray, hit, needs_node) })
}

/// The parameter `*t` and the grid cell `cell[2]` of the nearest hit, without `pick`'s refinement and
/// geodetic output (what a general ray caster returns; `t` within a few ulps of the vertices' coordinates
/// over the sine of the ray's elevation above the triangle): `CURVICAST_OK`, `CURVICAST_NO_HIT`, or an error as
/// for [`curvicast_picker_f32_pick`].
///
/// # Safety
/// Each pointer is NULL or valid (`cell` for 2 elements); what the picker borrows is alive and unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_picker_f32_pick_t(
    picker: *const curvicast_picker_f32,
    ray: *const curvicast_ray_f32,
    t: *mut f32,
    cell: *mut u32,
    needs_node: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above (`[u32; 2]` has `u32`'s alignment).
    crate::status::status(unsafe { pick_t::<f32, _>(picker, ray, t, cell.cast(), needs_node) })
}

/// [`curvicast_picker_f32_pick_t`] in double precision.
///
/// # Safety
/// As [`curvicast_picker_f32_pick_t`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_picker_f64_pick_t(
    picker: *const curvicast_picker_f64,
    ray: *const curvicast_ray_f64,
    t: *mut f64,
    cell: *mut u32,
    needs_node: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above (`[u32; 2]` has `u32`'s alignment).
    crate::status::status(unsafe { pick_t::<f64, _>(picker, ray, t, cell.cast(), needs_node) })
}

/// Whether the closed segment from `a` to `b` (ECEF metres, 3 scalars each) meets no terrain triangle:
/// `*clear` written and `CURVICAST_OK`, or an error as for [`curvicast_picker_f32_pick`].
///
/// # Safety
/// Each pointer is NULL or valid; what the picker borrows is alive and unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_picker_f32_line_of_sight(
    picker: *const curvicast_picker_f32,
    a: *const f32,
    b: *const f32,
    clear: *mut bool,
    needs_node: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above.
    crate::status::status(unsafe { line_of_sight::<f32>(picker, a, b, clear, needs_node) })
}

/// [`curvicast_picker_f32_line_of_sight`] in double precision.
///
/// # Safety
/// As [`curvicast_picker_f32_line_of_sight`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_picker_f64_line_of_sight(
    picker: *const curvicast_picker_f64,
    a: *const f64,
    b: *const f64,
    clear: *mut bool,
    needs_node: *mut u32,
) -> curvicast_status {
    // SAFETY: the contract above.
    crate::status::status(unsafe { line_of_sight::<f64>(picker, a, b, clear, needs_node) })
}
