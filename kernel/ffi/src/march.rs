//! Marching from C (Hannasch, *Spherical Ray-Tracing*, ch. 5: the serial engine): a grid over the caller's
//! breakpoints and workspace, a march over the grid in the caller's storage, one crossing per
//! `curvicast_march_*_next` (or a batch per `curvicast_march_*_fill`) until `CURVICAST_DONE`. A grid of any kind is
//! held as the kernel's `Grid<_, _, Dynamic>`: one marcher serves the three kinds, so a firmware links one.
//!
//! ```c
//! float r[] = {0.0f, 0.5f, 1.0f}, th[] = {0.0f, 1.5707964f, 3.1415927f}, ph[] = {0.0f, 3.1415927f, 6.2831855f};
//! float ws[CURVICAST_SPHERICAL_WORKSPACE_LEN(3, 3, 3)];
//! curvicast_grid_f32 grid;
//! curvicast_march_f32 march;
//! curvicast_ray_f32 ray = {{-2.0f, 0.1f, 0.25f}, {1.0f, 0.0f, 0.0f}, 0.0f, INFINITY};
//! curvicast_crossing_f32 c;
//! curvicast_spherical_grid_f32_init(&grid, r, 3, th, 3, ph, 3, NULL, ws, sizeof ws / sizeof ws[0]);
//! curvicast_march_f32_begin(&march, &grid, &ray);
//! while (curvicast_march_f32_next(&march, &c) == CURVICAST_OK) { /* c.cell, c.t_enter, c.t_exit */ }
//! ```

use crate::{CRay, Holds, curvicast_ray_f32, curvicast_ray_f64, curvicast_status};
use crate::{get, get_mut, init, out, point_or_origin, read, slice, slice_mut};
use curvicast::Real;
use curvicast::march::{
    CellCrossing, CylindricalGrid, Dynamic, Grid, PolarGrid, SerialMarch, SphericalGrid,
};

/// The storage words of a grid (any kind): a tag, the kind, and the grid's borrowed axes.
pub const CURVICAST_GRID_WORDS: usize = 32;
/// The storage words of a march: a tag and the serial engine's state.
pub const CURVICAST_MARCH_F32_WORDS: usize = 48;
/// The storage words of a march: a tag and the serial engine's state.
pub const CURVICAST_MARCH_F64_WORDS: usize = 80;

/// A spherical, cylindrical or polar grid in single precision (caller storage; fill it with one of the
/// `curvicast_*_grid_f32_init`). It borrows its breakpoints and workspace.
#[repr(C)]
pub struct curvicast_grid_f32 {
    opaque: [u64; CURVICAST_GRID_WORDS],
}

/// A spherical, cylindrical or polar grid in double precision (caller storage; fill it with one of the
/// `curvicast_*_grid_f64_init`). It borrows its breakpoints and workspace.
#[repr(C)]
pub struct curvicast_grid_f64 {
    opaque: [u64; CURVICAST_GRID_WORDS],
}

/// A march in single precision (caller storage; `curvicast_march_f32_begin` fills it). It borrows its grid.
#[repr(C)]
pub struct curvicast_march_f32 {
    opaque: [u64; CURVICAST_MARCH_F32_WORDS],
}

/// A march in double precision (caller storage; `curvicast_march_f64_begin` fills it). It borrows its grid.
#[repr(C)]
pub struct curvicast_march_f64 {
    opaque: [u64; CURVICAST_MARCH_F64_WORDS],
}

/// One cell crossed: `cell` is `[i, j, k]` (r, θ, φ) in a spherical grid, `[i, k, m]` (ρ, φ, z) in a
/// cylindrical one, `[i, k, 0]` (r, φ) in a polar one; the ray is inside from `t_enter` to `t_exit`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct curvicast_crossing_f32 {
    /// The cell index.
    pub cell: [u32; 3],
    /// Where the ray enters the cell.
    pub t_enter: f32,
    /// Where it leaves (`t_exit >= t_enter`; equal for a zero-length crossing at an edge or corner).
    pub t_exit: f32,
}

/// One cell crossed (see `curvicast_crossing_f32`), in double precision.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct curvicast_crossing_f64 {
    /// The cell index.
    pub cell: [u32; 3],
    /// Where the ray enters the cell.
    pub t_enter: f64,
    /// Where it leaves (`t_exit >= t_enter`; equal for a zero-length crossing at an edge or corner).
    pub t_exit: f64,
}

// SAFETY: arrays of u64; the tags are distinct across `Holds` implementors (module `terrain` uses 0x…7xx).
unsafe impl Holds for curvicast_grid_f32 {
    type Value = Grid<'static, f32, Dynamic>;
    const TAG: u64 = 0x6375_7276_6963_0601;
}
// SAFETY: as above.
unsafe impl Holds for curvicast_grid_f64 {
    type Value = Grid<'static, f64, Dynamic>;
    const TAG: u64 = 0x6375_7276_6963_0602;
}
// SAFETY: as above.
unsafe impl Holds for curvicast_march_f32 {
    type Value = SerialMarch<'static, f32, Dynamic>;
    const TAG: u64 = 0x6375_7276_6963_0603;
}
// SAFETY: as above.
unsafe impl Holds for curvicast_march_f64 {
    type Value = SerialMarch<'static, f64, Dynamic>;
    const TAG: u64 = 0x6375_7276_6963_0604;
}

/// The workspace length, in scalars, of a spherical grid with these breakpoint counts: `nr + 2 nθ + 2 nφ`.
#[unsafe(no_mangle)]
pub extern "C" fn curvicast_spherical_workspace_len(
    nr: usize,
    ntheta: usize,
    nphi: usize,
) -> usize {
    SphericalGrid::<f32>::workspace_len(nr, ntheta, nphi)
}

/// The workspace length, in scalars, of a cylindrical grid: `nρ + 2 nφ`.
#[unsafe(no_mangle)]
pub extern "C" fn curvicast_cylindrical_workspace_len(nrho: usize, nphi: usize) -> usize {
    CylindricalGrid::<f32>::workspace_len(nrho, nphi)
}

/// The workspace length, in scalars, of a polar grid: `nr + 2 nφ`.
#[unsafe(no_mangle)]
pub extern "C" fn curvicast_polar_workspace_len(nr: usize, nphi: usize) -> usize {
    PolarGrid::<f32>::workspace_len(nr, nphi)
}

/// # Safety
/// See [`curvicast_spherical_grid_f32_init`].
#[allow(clippy::too_many_arguments)]
unsafe fn spherical<T: Real>(
    r: (*const T, usize),
    theta: (*const T, usize),
    phi: (*const T, usize),
    center: *const T,
    workspace: (*mut T, usize),
) -> Result<Grid<'static, T, Dynamic>, curvicast_status> {
    // SAFETY: the caller's contract: valid arrays (or NULL), kept alive and unchanged while the grid is used.
    let (r, theta, phi, center, ws) = unsafe {
        (
            slice(r.0, r.1)?,
            slice(theta.0, theta.1)?,
            slice(phi.0, phi.1)?,
            point_or_origin::<T, 3>(center)?,
            slice_mut(workspace.0, workspace.1)?,
        )
    };
    Ok(SphericalGrid::new(r, theta, phi, ws)?
        .with_center(center)?
        .into_dynamic())
}

/// # Safety
/// See [`curvicast_cylindrical_grid_f32_init`].
unsafe fn cylindrical<T: Real>(
    rho: (*const T, usize),
    phi: (*const T, usize),
    z: (*const T, usize),
    center: *const T,
    workspace: (*mut T, usize),
) -> Result<Grid<'static, T, Dynamic>, curvicast_status> {
    // SAFETY: as in `spherical`.
    let (rho, phi, z, center, ws) = unsafe {
        (
            slice(rho.0, rho.1)?,
            slice(phi.0, phi.1)?,
            slice(z.0, z.1)?,
            point_or_origin::<T, 3>(center)?,
            slice_mut(workspace.0, workspace.1)?,
        )
    };
    Ok(CylindricalGrid::new(rho, phi, z, ws)?
        .with_center(center)?
        .into_dynamic())
}

/// # Safety
/// See [`curvicast_polar_grid_f32_init`].
unsafe fn polar<T: Real>(
    r: (*const T, usize),
    phi: (*const T, usize),
    center: *const T,
    workspace: (*mut T, usize),
) -> Result<Grid<'static, T, Dynamic>, curvicast_status> {
    // SAFETY: as in `spherical`.
    let (r, phi, center, ws) = unsafe {
        (
            slice(r.0, r.1)?,
            slice(phi.0, phi.1)?,
            point_or_origin::<T, 2>(center)?,
            slice_mut(workspace.0, workspace.1)?,
        )
    };
    Ok(PolarGrid::new(r, phi, ws)?
        .with_center(center)?
        .into_dynamic())
}

/// Fills `grid` with a spherical grid (Hannasch ch. 2): cell `[i, j, k]` is `r[i] ≤ r < r[i+1]`,
/// `theta[j] ≤ θ < theta[j+1]` (zenith from +z, radians), `phi[k] ≤ φ < phi[k+1]` (azimuth from +x toward +y,
/// modulo 2π), centred at `center` (3 scalars; NULL: the origin). Breakpoints strictly increasing, at least 2
/// per axis; `workspace` holds at least `curvicast_spherical_workspace_len(r_len, theta_len, phi_len)` scalars.
///
/// # Safety
/// Each pointer is NULL or valid for its length; the breakpoints and the workspace stay alive, in place and
/// unchanged while the grid (or a march over it) is used; nothing else writes `grid` during the call.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn curvicast_spherical_grid_f32_init(
    grid: *mut curvicast_grid_f32,
    r: *const f32,
    r_len: usize,
    theta: *const f32,
    theta_len: usize,
    phi: *const f32,
    phi_len: usize,
    center: *const f32,
    workspace: *mut f32,
    workspace_len: usize,
) -> curvicast_status {
    // SAFETY: the contract above is `spherical`'s and `init`'s.
    unsafe {
        init(grid, || {
            spherical(
                (r, r_len),
                (theta, theta_len),
                (phi, phi_len),
                center,
                (workspace, workspace_len),
            )
        })
    }
}

/// [`curvicast_spherical_grid_f32_init`] in double precision.
///
/// # Safety
/// As [`curvicast_spherical_grid_f32_init`].
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn curvicast_spherical_grid_f64_init(
    grid: *mut curvicast_grid_f64,
    r: *const f64,
    r_len: usize,
    theta: *const f64,
    theta_len: usize,
    phi: *const f64,
    phi_len: usize,
    center: *const f64,
    workspace: *mut f64,
    workspace_len: usize,
) -> curvicast_status {
    // SAFETY: as in the f32 version.
    unsafe {
        init(grid, || {
            spherical(
                (r, r_len),
                (theta, theta_len),
                (phi, phi_len),
                center,
                (workspace, workspace_len),
            )
        })
    }
}

/// Fills `grid` with a cylindrical grid (Hannasch §3.3): cell `[i, k, m]` is `rho[i] ≤ ρ < rho[i+1]`,
/// `phi[k] ≤ φ < phi[k+1]`, `z[m] ≤ z < z[m+1]`, centred at `center` (3 scalars; NULL: the origin);
/// `workspace` holds at least `curvicast_cylindrical_workspace_len(rho_len, phi_len)` scalars.
///
/// # Safety
/// As [`curvicast_spherical_grid_f32_init`].
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn curvicast_cylindrical_grid_f32_init(
    grid: *mut curvicast_grid_f32,
    rho: *const f32,
    rho_len: usize,
    phi: *const f32,
    phi_len: usize,
    z: *const f32,
    z_len: usize,
    center: *const f32,
    workspace: *mut f32,
    workspace_len: usize,
) -> curvicast_status {
    // SAFETY: as in the spherical version.
    unsafe {
        init(grid, || {
            cylindrical(
                (rho, rho_len),
                (phi, phi_len),
                (z, z_len),
                center,
                (workspace, workspace_len),
            )
        })
    }
}

/// [`curvicast_cylindrical_grid_f32_init`] in double precision.
///
/// # Safety
/// As [`curvicast_spherical_grid_f32_init`].
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn curvicast_cylindrical_grid_f64_init(
    grid: *mut curvicast_grid_f64,
    rho: *const f64,
    rho_len: usize,
    phi: *const f64,
    phi_len: usize,
    z: *const f64,
    z_len: usize,
    center: *const f64,
    workspace: *mut f64,
    workspace_len: usize,
) -> curvicast_status {
    // SAFETY: as in the spherical version.
    unsafe {
        init(grid, || {
            cylindrical(
                (rho, rho_len),
                (phi, phi_len),
                (z, z_len),
                center,
                (workspace, workspace_len),
            )
        })
    }
}

/// Fills `grid` with a 2-D polar grid in the plane z = 0 (Hannasch §3.3): cell `[i, k, 0]` is
/// `r[i] ≤ r < r[i+1]`, `phi[k] ≤ φ < phi[k+1]`, centred at `center` (2 scalars; NULL: the origin);
/// `workspace` holds at least `curvicast_polar_workspace_len(r_len, phi_len)` scalars.
///
/// # Safety
/// As [`curvicast_spherical_grid_f32_init`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_polar_grid_f32_init(
    grid: *mut curvicast_grid_f32,
    r: *const f32,
    r_len: usize,
    phi: *const f32,
    phi_len: usize,
    center: *const f32,
    workspace: *mut f32,
    workspace_len: usize,
) -> curvicast_status {
    // SAFETY: as in the spherical version.
    unsafe {
        init(grid, || {
            polar(
                (r, r_len),
                (phi, phi_len),
                center,
                (workspace, workspace_len),
            )
        })
    }
}

/// [`curvicast_polar_grid_f32_init`] in double precision.
///
/// # Safety
/// As [`curvicast_spherical_grid_f32_init`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_polar_grid_f64_init(
    grid: *mut curvicast_grid_f64,
    r: *const f64,
    r_len: usize,
    phi: *const f64,
    phi_len: usize,
    center: *const f64,
    workspace: *mut f64,
    workspace_len: usize,
) -> curvicast_status {
    // SAFETY: as in the spherical version.
    unsafe {
        init(grid, || {
            polar(
                (r, r_len),
                (phi, phi_len),
                center,
                (workspace, workspace_len),
            )
        })
    }
}

/// Starts marching `ray` through `grid` into `march` (a ray that misses the grid gives `CURVICAST_DONE` at
/// its first `next`).
///
/// # Safety
/// Each pointer is NULL or valid; `grid` stays alive, in place and unchanged while `march` is used.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_march_f32_begin(
    march: *mut curvicast_march_f32,
    grid: *const curvicast_grid_f32,
    ray: *const curvicast_ray_f32,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { init(march, || Ok(get(grid)?.march(&read(ray)?.ray()?))) }
}

/// [`curvicast_march_f32_begin`] in double precision.
///
/// # Safety
/// As [`curvicast_march_f32_begin`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_march_f64_begin(
    march: *mut curvicast_march_f64,
    grid: *const curvicast_grid_f64,
    ray: *const curvicast_ray_f64,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { init(march, || Ok(get(grid)?.march(&read(ray)?.ray()?))) }
}

/// Up to `crossings.len()` crossings into `crossings` (the kernel's batch loop), their number into
/// `*written`: `CURVICAST_OK` when the array is full (more may follow), `CURVICAST_DONE` when the march is over,
/// or the error that stopped it.
fn fill<T: Real, C: From<CellCrossing<T>>>(
    march: &mut SerialMarch<'static, T, Dynamic>,
    crossings: &mut [C],
    written: &mut usize,
) -> curvicast_status {
    if crossings.is_empty() {
        *written = 0;
        return curvicast_status::CURVICAST_ZERO_CAPACITY;
    }
    *written = march.next_into(crossings);
    if *written == crossings.len() {
        curvicast_status::CURVICAST_OK
    } else {
        march
            .error()
            .map_or(curvicast_status::CURVICAST_DONE, Into::into)
    }
}

/// One crossing into `crossing`: `CURVICAST_OK`, `CURVICAST_DONE` when the march is over, or the error that
/// stopped it.
fn next<T: Real, C: From<CellCrossing<T>>>(
    march: &mut SerialMarch<'static, T, Dynamic>,
    crossing: &mut C,
) -> curvicast_status {
    match march.next() {
        Some(c) => {
            *crossing = c.into();
            curvicast_status::CURVICAST_OK
        }
        None => march
            .error()
            .map_or(curvicast_status::CURVICAST_DONE, Into::into),
    }
}

impl From<CellCrossing<f32>> for curvicast_crossing_f32 {
    fn from(c: CellCrossing<f32>) -> Self {
        curvicast_crossing_f32 {
            cell: c.cell,
            t_enter: c.t_enter,
            t_exit: c.t_exit,
        }
    }
}

impl From<CellCrossing<f64>> for curvicast_crossing_f64 {
    fn from(c: CellCrossing<f64>) -> Self {
        curvicast_crossing_f64 {
            cell: c.cell,
            t_enter: c.t_enter,
            t_exit: c.t_exit,
        }
    }
}

/// The next crossing: `CURVICAST_OK` with `*crossing` written, `CURVICAST_DONE` when the ray has left the grid,
/// or the error that stopped the march (after the crossings before it; then `CURVICAST_DONE`).
///
/// # Safety
/// Each pointer is NULL or valid; what the march borrows is alive and unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_march_f32_next(
    march: *mut curvicast_march_f32,
    crossing: *mut curvicast_crossing_f32,
) -> curvicast_status {
    // SAFETY: the contract above.
    let r = unsafe { (get_mut(march), out(crossing)) };
    match r {
        (Ok(m), Ok(c)) => next(m, c),
        (Err(e), _) | (_, Err(e)) => e,
    }
}

/// [`curvicast_march_f32_next`] in double precision.
///
/// # Safety
/// As [`curvicast_march_f32_next`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_march_f64_next(
    march: *mut curvicast_march_f64,
    crossing: *mut curvicast_crossing_f64,
) -> curvicast_status {
    // SAFETY: the contract above.
    let r = unsafe { (get_mut(march), out(crossing)) };
    match r {
        (Ok(m), Ok(c)) => next(m, c),
        (Err(e), _) | (_, Err(e)) => e,
    }
}

/// Up to `capacity` (at least 1) next crossings into `crossings` and their number into `*written` (one call
/// instead of one per crossing): `CURVICAST_OK` when the array is full (more may follow), `CURVICAST_DONE`
/// when the march is over, or the error that stopped it (`*written` counts the crossings before it).
///
/// # Safety
/// Each pointer is NULL or valid (`crossings` for `capacity` elements); what the march borrows is alive and
/// unchanged.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_march_f32_fill(
    march: *mut curvicast_march_f32,
    crossings: *mut curvicast_crossing_f32,
    capacity: usize,
    written: *mut usize,
) -> curvicast_status {
    // SAFETY: the contract above; a crossing is plain numbers (any bits valid).
    let r = unsafe { (get_mut(march), slice_mut(crossings, capacity), out(written)) };
    match r {
        (Ok(m), Ok(c), Ok(w)) => fill(m, c, w),
        (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => e,
    }
}

/// [`curvicast_march_f32_fill`] in double precision.
///
/// # Safety
/// As [`curvicast_march_f32_fill`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_march_f64_fill(
    march: *mut curvicast_march_f64,
    crossings: *mut curvicast_crossing_f64,
    capacity: usize,
    written: *mut usize,
) -> curvicast_status {
    // SAFETY: the contract above; a crossing is plain numbers (any bits valid).
    let r = unsafe { (get_mut(march), slice_mut(crossings, capacity), out(written)) };
    match r {
        (Ok(m), Ok(c), Ok(w)) => fill(m, c, w),
        (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => e,
    }
}
