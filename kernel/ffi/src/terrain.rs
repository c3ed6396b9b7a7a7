//! Terrain picking from C (Wartell, Ribarsky, Hodges, *Efficient Ray Intersection with Global Terrain using
//! Spheroidal Height-Augmented Quadtrees*, §3–§5) on the WGS84 spheroid: the quadtree of the caller's heights
//! built into the caller's node records, a terrain over them, a picker over the terrain.
//!
//! ```c
//! curvicast_dem_grid_f64 g = {45.0, 7.0, 0.01, 0.01, 9, 9};      /* lat0, lon0, dlat, dlon (deg), rows, cols */
//! static float heights[9 * 9];                                   /* row-major, NaN: no data */
//! static curvicast_node_record nodes[64];                        /* >= curvicast_node_slots(9, 9, 8) */
//! static curvicast_terrain_f64 terrain;
//! static curvicast_picker_f64 picker;
//! curvicast_hit_f64 hit;
//! curvicast_terrain_f64_build(&terrain, &g, heights, 81, 8, nodes, 64);
//! curvicast_picker_f64_init(&picker, &terrain, 0);
//! if (curvicast_picker_f64_pick(&picker, &ray, &hit, NULL) == CURVICAST_OK) { /* hit.lat_deg, hit.h, ... */ }
//! ```
//!
//! **Multi-resolution (§5).** `curvicast_terrain_*_build_multires` builds the pyramid, and takes one residency
//! flag per node (its id is its index). A pick that needs a block that is not resident, and that no coarser
//! resident block at or below the picker's `min_level` can stand in for, returns
//! `CURVICAST_TERRAIN_NEEDS_BLOCK` with the node's id in `*needs_node`: set its flag once its block is in
//! memory, and ask again.

use crate::{Holds, curvicast_status};
use crate::{init, read, slice, slice_mut};
use core::sync::atomic::AtomicBool;
use curvicast::Real;
use curvicast::geodesy::Ellipsoid;
use curvicast::terrain::build::{
    MultiRes, NodeRecord, Parts, SliceStorage, Tree, build_multires_tree, build_tree, node_slots,
};
use curvicast::terrain::{Grid, Hit, Picker};

/// The words of a node record (exactly the kernel's record of `float` heights).
pub const CURVICAST_NODE_RECORD_WORDS: usize = 11;
/// The storage words of a terrain: a tag and the storage over the caller's buffers.
pub const CURVICAST_TERRAIN_WORDS: usize = 32;
/// The storage words of a picker in single precision.
pub const CURVICAST_PICKER_F32_WORDS: usize = 1280;
/// The storage words of a picker in double precision.
pub const CURVICAST_PICKER_F64_WORDS: usize = 2304;
/// The traversal stack of a picker: up to 3 entries per tree level plus 4 (so trees up to 20 levels deep).
pub const CURVICAST_PICKER_STACK: usize = 64;
/// The zones a picker holds: every tree `curvicast_terrain_*_build` makes has at most 4 × 8.
pub const CURVICAST_PICKER_ZONES: usize = 32;

/// The regular geodetic grid of a DEM on WGS84: vertex `(i, j)` is at latitude `lat0_deg + i·dlat_deg`,
/// longitude `lon0_deg + j·dlon_deg` (degrees), `0 ≤ i < rows`, `0 ≤ j < cols`; `dlat_deg ≠ 0` of either sign,
/// `0 < dlon_deg < 180`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct curvicast_dem_grid_f32 {
    /// Latitude of row 0, degrees.
    pub lat0_deg: f32,
    /// Longitude of column 0, degrees.
    pub lon0_deg: f32,
    /// Row spacing, degrees.
    pub dlat_deg: f32,
    /// Column spacing, degrees.
    pub dlon_deg: f32,
    /// Vertex rows (at least 2).
    pub rows: u32,
    /// Vertex columns (at least 2).
    pub cols: u32,
}

/// The DEM grid (see `curvicast_dem_grid_f32`) in double precision.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct curvicast_dem_grid_f64 {
    /// Latitude of row 0, degrees.
    pub lat0_deg: f64,
    /// Longitude of column 0, degrees.
    pub lon0_deg: f64,
    /// Row spacing, degrees.
    pub dlat_deg: f64,
    /// Column spacing, degrees.
    pub dlon_deg: f64,
    /// Vertex rows (at least 2).
    pub rows: u32,
    /// Vertex columns (at least 2).
    pub cols: u32,
}

/// The shape of a multi-resolution tree (§5, Fig. 11): branches end `coarse_level` levels above the leaves
/// outside the fine region `[lat_s, lat_n, lon_w, lon_e]` (degrees), whose nodes go down to full resolution.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct curvicast_multires_f32 {
    /// Whether `fine_region` is used (false: every node goes down to the leaves).
    pub has_fine_region: bool,
    /// `[lat_s, lat_n, lon_w, lon_e]`, degrees.
    pub fine_region: [f32; 4],
    /// The level above the leaves at which branches outside the fine region end.
    pub coarse_level: u32,
}

/// The shape of a multi-resolution tree (see `curvicast_multires_f32`) in double precision.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct curvicast_multires_f64 {
    /// Whether `fine_region` is used (false: every node goes down to the leaves).
    pub has_fine_region: bool,
    /// `[lat_s, lat_n, lon_w, lon_e]`, degrees.
    pub fine_region: [f64; 4],
    /// The level above the leaves at which branches outside the fine region end.
    pub coarse_level: u32,
}

/// One quadtree node as the builder stores it (opaque; `curvicast_node_slots` of them per DEM).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct curvicast_node_record {
    pub(crate) opaque: [u32; CURVICAST_NODE_RECORD_WORDS],
}

/// A terrain: the tree and the caller's heights, node records and residency flags, which it borrows.
#[repr(C)]
pub struct curvicast_terrain_f32 {
    opaque: [u64; CURVICAST_TERRAIN_WORDS],
}

/// A terrain (see `curvicast_terrain_f32`) in double precision.
#[repr(C)]
pub struct curvicast_terrain_f64 {
    opaque: [u64; CURVICAST_TERRAIN_WORDS],
}

/// A picker: the per-terrain constants (global bound, zone volumes). It borrows its terrain.
#[repr(C)]
pub struct curvicast_picker_f32 {
    opaque: [u64; CURVICAST_PICKER_F32_WORDS],
}

/// A picker (see `curvicast_picker_f32`) in double precision.
#[repr(C)]
pub struct curvicast_picker_f64 {
    opaque: [u64; CURVICAST_PICKER_F64_WORDS],
}

/// The nearest hit of a ray with the terrain.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct curvicast_hit_f32 {
    /// The ray parameter (in the units of the ray's direction).
    pub t: f32,
    /// The hit point, ECEF metres.
    pub ecef: [f32; 3],
    /// Geodetic latitude, degrees.
    pub lat_deg: f32,
    /// Longitude, degrees in [−180, 180].
    pub lon_deg: f32,
    /// Height above the ellipsoid, metres.
    pub h: f32,
    /// The grid cell `[row, column]` whose triangle was hit (the first of the traced cell's).
    pub cell: [u32; 2],
    /// The traced cell's size in grid steps (1 at full resolution).
    pub stride: u32,
    /// The quadtree level of the node whose block was traced.
    pub level: u8,
}

/// The nearest hit (see `curvicast_hit_f32`) in double precision.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct curvicast_hit_f64 {
    /// The ray parameter (in the units of the ray's direction).
    pub t: f64,
    /// The hit point, ECEF metres.
    pub ecef: [f64; 3],
    /// Geodetic latitude, degrees.
    pub lat_deg: f64,
    /// Longitude, degrees in [−180, 180].
    pub lon_deg: f64,
    /// Height above the ellipsoid, metres.
    pub h: f64,
    /// The grid cell `[row, column]` whose triangle was hit (the first of the traced cell's).
    pub cell: [u32; 2],
    /// The traced cell's size in grid steps (1 at full resolution).
    pub stride: u32,
    /// The quadtree level of the node whose block was traced.
    pub level: u8,
}

type Record = NodeRecord<f32>;
/// The kernel's storage over the caller's buffers (heights in `float`, residency flags for paging).
pub(crate) type Storage<T> = SliceStorage<'static, T, f32, (), AtomicBool>;
/// The kernel's picker over it.
pub(crate) type CPicker<T> =
    Picker<'static, T, Storage<T>, CURVICAST_PICKER_STACK, CURVICAST_PICKER_ZONES>;

const _: () = assert!(
    core::mem::size_of::<Record>() == core::mem::size_of::<curvicast_node_record>()
        && core::mem::align_of::<Record>() == core::mem::align_of::<curvicast_node_record>(),
    "the C node record must have the kernel record's size and alignment"
);

// SAFETY: arrays of u64 with tags distinct from every other `Holds` implementor's (0x…06xx in `march`).
unsafe impl Holds for curvicast_terrain_f32 {
    type Value = Storage<f32>;
    const TAG: u64 = 0x6375_7276_6963_0701;
}
// SAFETY: as above.
unsafe impl Holds for curvicast_terrain_f64 {
    type Value = Storage<f64>;
    const TAG: u64 = 0x6375_7276_6963_0702;
}
// SAFETY: as above.
unsafe impl Holds for curvicast_picker_f32 {
    type Value = CPicker<f32>;
    const TAG: u64 = 0x6375_7276_6963_0703;
}
// SAFETY: as above.
unsafe impl Holds for curvicast_picker_f64 {
    type Value = CPicker<f64>;
    const TAG: u64 = 0x6375_7276_6963_0704;
}

/// The C types of a scalar type: its DEM grid, multi-resolution shape, hit and picker storage.
pub(crate) trait Scalar: Real {
    type DemGrid: Copy;
    type MultiRes: Copy;
    type Hit;
    type Picker: Holds<Value = CPicker<Self>>;
    fn grid(g: &Self::DemGrid) -> Grid<Self>;
    fn shape(s: &Self::MultiRes) -> MultiRes<Self>;
    fn hit(h: Hit<Self>) -> Self::Hit;
}

/// [`Scalar`] for one precision: the C structs mirror the kernel's field by field.
macro_rules! scalar {
    ($t:ty, $grid:ident, $multires:ident, $hit:ident, $picker:ident) => {
        impl Scalar for $t {
            type DemGrid = $grid;
            type MultiRes = $multires;
            type Hit = $hit;
            type Picker = $picker;
            fn grid(g: &$grid) -> Grid<$t> {
                let &$grid {
                    lat0_deg,
                    lon0_deg,
                    dlat_deg,
                    dlon_deg,
                    rows,
                    cols,
                } = g;
                Grid {
                    lat0_deg,
                    lon0_deg,
                    dlat_deg,
                    dlon_deg,
                    rows,
                    cols,
                }
            }
            fn shape(s: &$multires) -> MultiRes<$t> {
                MultiRes {
                    fine_region: s.has_fine_region.then_some(s.fine_region),
                    coarse_level: s.coarse_level,
                }
            }
            fn hit(h: Hit<$t>) -> $hit {
                let Hit {
                    t,
                    ecef,
                    lat_deg,
                    lon_deg,
                    h,
                    cell,
                    level,
                    stride,
                } = h;
                $hit {
                    t,
                    ecef,
                    lat_deg,
                    lon_deg,
                    h,
                    cell,
                    stride,
                    level,
                }
            }
        }
    };
}
scalar!(
    f32,
    curvicast_dem_grid_f32,
    curvicast_multires_f32,
    curvicast_hit_f32,
    curvicast_picker_f32
);
scalar!(
    f64,
    curvicast_dem_grid_f64,
    curvicast_multires_f64,
    curvicast_hit_f64,
    curvicast_picker_f64
);

/// # Safety
/// `ecef` is NULL or points to 3 writable scalars.
unsafe fn to_ecef<T: Real>(lat_deg: T, lon_deg: T, h: T, ecef: *mut T) -> curvicast_status {
    // SAFETY: the contract.
    match unsafe { slice_mut(ecef, 3) } {
        Ok(out) => {
            let p = Ellipsoid::<T>::wgs84().geodetic_deg_to_ecef(lat_deg, lon_deg, h);
            out.copy_from_slice(&[p.x, p.y, p.z]);
            curvicast_status::CURVICAST_OK
        }
        Err(e) => e,
    }
}

/// The ECEF point (metres, 3 scalars into `ecef`) of geodetic latitude and longitude (degrees) and height
/// above the WGS84 ellipsoid (metres): where to start a ray above the terrain.
///
/// # Safety
/// `ecef` is NULL or points to 3 writable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_wgs84_to_ecef_f32(
    lat_deg: f32,
    lon_deg: f32,
    h: f32,
    ecef: *mut f32,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { to_ecef(lat_deg, lon_deg, h, ecef) }
}

/// [`curvicast_wgs84_to_ecef_f32`] in double precision.
///
/// # Safety
/// `ecef` is NULL or points to 3 writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_wgs84_to_ecef_f64(
    lat_deg: f64,
    lon_deg: f64,
    h: f64,
    ecef: *mut f64,
) -> curvicast_status {
    // SAFETY: the contract above.
    unsafe { to_ecef(lat_deg, lon_deg, h, ecef) }
}

/// The length of the node array for a DEM of `rows × cols` vertices and leaf blocks of `block × block` cells
/// (0 for fewer than 2 rows or columns or a block of 0).
#[unsafe(no_mangle)]
pub extern "C" fn curvicast_node_slots(rows: u32, cols: u32, block: u32) -> usize {
    node_slots(rows, cols, block)
}

/// Builds the tree (single- or multi-resolution) and the storage over the caller's buffers.
///
/// # Safety
/// As [`curvicast_terrain_f64_build_multires`].
#[allow(clippy::too_many_arguments)]
unsafe fn build<T: Scalar>(
    grid: *const T::DemGrid,
    heights: (*const f32, usize),
    block: u32,
    shape: Option<*const T::MultiRes>,
    nodes: (*mut curvicast_node_record, usize),
    resident: (*const bool, usize),
) -> Result<Storage<T>, curvicast_status> {
    // SAFETY: the caller's contract: valid arrays, alive and unchanged (residency flags aside) while used.
    let (grid, heights, records) = unsafe {
        let grid = T::grid(read(grid)?);
        let records = slice_mut(nodes.0, nodes.1)?.as_mut_ptr().cast::<Record>();
        (grid, slice(heights.0, heights.1)?, (records, nodes.1))
    };
    // The C records may hold any bytes: each is set to the empty record before the kernel sees them.
    let mut p = records.0;
    for _ in 0..records.1 {
        // SAFETY: `records` is the caller's array of `nodes.1` C records, checked non-null and aligned above,
        // which has the kernel record's size and alignment (the assertion above), so `p` stays inside it.
        unsafe {
            p.write(Record::EMPTY);
            p = p.add(1);
        }
    }
    // SAFETY: every element was just written with a valid record; the array is the caller's, exclusively ours
    // for the call and then only read (the contract).
    let nodes: &'static mut [Record] =
        unsafe { core::slice::from_raw_parts_mut(records.0, records.1) };
    let tree: Tree = match shape {
        Some(s) => {
            // SAFETY: the contract: `s` is NULL or a valid shape.
            let shape = T::shape(unsafe { read(s) }?);
            build_multires_tree(heights, &grid, block, shape, nodes)?
        }
        None => build_tree(heights, &grid, block, nodes)?,
    };
    let nodes: &'static [Record] = nodes;
    let resident: &'static [AtomicBool] = if resident.1 == 0 {
        &[]
    } else {
        // SAFETY: the contract: `resident.1` C `bool`s (0 or 1, as `AtomicBool` holds them; same size and
        // alignment), which the caller writes only between calls.
        let flags = unsafe { slice(resident.0.cast::<AtomicBool>(), resident.1) }?;
        flags
            .get(..tree.slots())
            .ok_or(curvicast_status::CURVICAST_BUILD_BUFFER_LENGTH)?
    };
    let parts = Parts::new(heights, nodes).with_resident(resident);
    Ok(SliceStorage::with_buffers(
        Ellipsoid::wgs84(),
        grid,
        tree,
        parts,
    )?)
}

/// Builds the quadtree of a DEM on WGS84 into `nodes` and fills `terrain` with it (Wartell et al. §3–§4).
/// `heights` holds `grid->rows × grid->cols` heights in metres, row-major (vertex `(i, j)` at
/// `i·cols + j`), NaN for no data; leaves are blocks of `block × block` cells (8 or 16 are typical); `nodes`
/// holds at least `curvicast_node_slots(rows, cols, block)` records.
///
/// # Safety
/// Each pointer is NULL or valid for its length; `heights` and `nodes` stay alive, in place and unchanged
/// while `terrain` (or a picker over it) is used; nothing else accesses `terrain` or `nodes` during the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_terrain_f32_build(
    terrain: *mut curvicast_terrain_f32,
    grid: *const curvicast_dem_grid_f32,
    heights: *const f32,
    heights_len: usize,
    block: u32,
    nodes: *mut curvicast_node_record,
    nodes_len: usize,
) -> curvicast_status {
    let none = (core::ptr::null(), 0);
    // SAFETY: the contract above.
    unsafe {
        init(terrain, || {
            build::<f32>(
                grid,
                (heights, heights_len),
                block,
                None,
                (nodes, nodes_len),
                none,
            )
        })
    }
}

/// [`curvicast_terrain_f32_build`] in double precision (heights stay `float`).
///
/// # Safety
/// As [`curvicast_terrain_f32_build`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn curvicast_terrain_f64_build(
    terrain: *mut curvicast_terrain_f64,
    grid: *const curvicast_dem_grid_f64,
    heights: *const f32,
    heights_len: usize,
    block: u32,
    nodes: *mut curvicast_node_record,
    nodes_len: usize,
) -> curvicast_status {
    let none = (core::ptr::null(), 0);
    // SAFETY: the contract above.
    unsafe {
        init(terrain, || {
            build::<f64>(
                grid,
                (heights, heights_len),
                block,
                None,
                (nodes, nodes_len),
                none,
            )
        })
    }
}

/// Builds the multi-resolution quadtree of a DEM (Wartell et al. §5): as [`curvicast_terrain_f32_build`],
/// every node with its own block at `2^k` grid steps (`k` its level above the leaves), branches ending at
/// `shape->coarse_level` outside `shape->fine_region`. `resident` holds one flag per node (index: the node's
/// id), at least `curvicast_node_slots` of them, true when the node's block is in memory; `resident_len = 0`:
/// every block resident.
///
/// # Safety
/// As [`curvicast_terrain_f32_build`]; `resident` stays alive and in place while the terrain is used, and the
/// caller changes its flags only between calls.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn curvicast_terrain_f32_build_multires(
    terrain: *mut curvicast_terrain_f32,
    grid: *const curvicast_dem_grid_f32,
    heights: *const f32,
    heights_len: usize,
    block: u32,
    shape: *const curvicast_multires_f32,
    nodes: *mut curvicast_node_record,
    nodes_len: usize,
    resident: *const bool,
    resident_len: usize,
) -> curvicast_status {
    let (h, n, r) = (
        (heights, heights_len),
        (nodes, nodes_len),
        (resident, resident_len),
    );
    // SAFETY: the contract above.
    unsafe { init(terrain, || build::<f32>(grid, h, block, Some(shape), n, r)) }
}

/// [`curvicast_terrain_f32_build_multires`] in double precision (heights stay `float`).
///
/// # Safety
/// As [`curvicast_terrain_f32_build_multires`].
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn curvicast_terrain_f64_build_multires(
    terrain: *mut curvicast_terrain_f64,
    grid: *const curvicast_dem_grid_f64,
    heights: *const f32,
    heights_len: usize,
    block: u32,
    shape: *const curvicast_multires_f64,
    nodes: *mut curvicast_node_record,
    nodes_len: usize,
    resident: *const bool,
    resident_len: usize,
) -> curvicast_status {
    let (h, n, r) = (
        (heights, heights_len),
        (nodes, nodes_len),
        (resident, resident_len),
    );
    // SAFETY: the contract above.
    unsafe { init(terrain, || build::<f64>(grid, h, block, Some(shape), n, r)) }
}
