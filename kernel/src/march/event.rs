//! The per-ray set-up and the one step shared by both engines: where the ray meets the grid, each
//! coordinate's stream started there, and the next event of one stream. Generic over the grid's kind, so that
//! each kind's code holds only its own coordinates' steps.

use super::error::MarchError;
use super::kind::{GridKind, SlotKind, coordinates, may_have_height, may_have_zenith};
use super::stream::{RadialLine, SecondRoots, StepKind, Stream};
use super::tables::Axes;
use crate::ray::{Line, Ray};
use crate::real::Real;
use crate::surface::sphere_scaled_roots;
use crate::vec3::V3;

/// The ray's line in the grid's frame, `rel` (relative to the center: the solvers report every crossing of the
/// whole line, so that the streams can check their topology against the limit at infinity), the ray's `t_max`
/// (which cuts the events), and the line as the radius stream sees it (`rel` itself for the sphere grid, its
/// projection on z = 0 for the cylinder and the polar grid).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rays<T> {
    pub(crate) rel: Line<T>,
    pub(crate) t_max: T,
    pub(crate) radial: RadialLine<T>,
}

impl<T: Real> Rays<T> {
    /// Before the set-up: the caller's ray's line and `t_max` (the set-up replaces them, also when it then fails).
    pub(crate) fn of(ray: &Ray<T>) -> Self {
        Rays {
            rel: *ray.line(),
            t_max: ray.t_max(),
            radial: RadialLine::unset(ray.line()),
        }
    }
    #[inline(always)]
    pub(crate) fn t_max(&self) -> T {
        self.t_max
    }
    /// True when an event's `t` may fail to be finite (see `emitter::CHECK_T`): the line's or the radius line's
    /// `t = s·2^-e` can overflow where `s` does not.
    pub(crate) fn t_may_overflow(&self) -> bool {
        self.rel.scale().enlarges() || self.radial.scale().enlarges()
    }
}

/// As [`next_event`], kept out of line: for the set-up (each stream's first event), so that the streams' code is
/// inlined only into the engines' loops, not a second time into the set-up (on a Cortex-M4F each inlined copy of
/// the radius, zenith and azimuth steps costs about 2 KB of code). In a build for size, where `next_event` itself
/// is out of line, this is only its other name.
#[cfg_attr(not(curvicast_small_code), inline(never))]
#[cfg_attr(curvicast_small_code, inline(always))]
pub(crate) fn next_event_outlined<T: Real, K: GridKind>(
    axes: &Axes<'_, T>,
    rays: &Rays<T>,
    streams: &mut [Stream<T>; 3],
    roots: &mut SecondRoots<T>,
    slot: usize,
) -> bool {
    next_event::<T, K>(axes, rays, streams, roots, slot)
}

/// Advances slot `slot`'s stream to its next event (then its `t` and `band`); false when it has none. Inlined
/// into the engines' loops, with the radius, zenith and azimuth steps (the cone solver stays out of line); in a
/// build for size (`opt-level` "s" or "z", see `build.rs`) kept out of line instead, one copy for the set-up and
/// every loop (on the Cortex-M4F: 1.6 KB less code in the march firmware at opt "s").
#[cfg_attr(not(curvicast_small_code), inline(always))]
#[cfg_attr(curvicast_small_code, inline(never))]
pub(crate) fn next_event<T: Real, K: GridKind>(
    axes: &Axes<'_, T>,
    rays: &Rays<T>,
    streams: &mut [Stream<T>; 3],
    roots: &mut SecondRoots<T>,
    slot: usize,
) -> bool {
    let Some(s) = streams.get_mut(slot) else {
        return false;
    };
    match s.step_kind() {
        StepKind::Radial => s.next_radial(&axes.radial, &rays.radial, rays.t_max()),
        StepKind::Zenith if may_have_zenith::<K>() => axes
            .zenith
            .as_ref()
            .is_some_and(|z| s.next_zenith(z, &rays.rel, rays.t_max(), roots)),
        StepKind::Azimuth => s.next_azimuth(&axes.azimuth, &rays.rel, rays.t_max()),
        StepKind::Height if may_have_height::<K>() => axes
            .height
            .as_ref()
            .is_some_and(|h| s.next_height(h, &rays.rel, rays.t_max())),
        StepKind::Walk => s.next_walk(axes.azimuth.boundaries.max(1), rays.t_max()),
        StepKind::Zenith | StepKind::Height | StepKind::None => false,
    }
}

/// False when the line crosses the outer radius (sphere, or cylinder for the flat ray) and the ray's interval
/// reaches a part of it where `t` is not finite: the scaled roots are finite, but `t = s·2^-e` overflows (a
/// direction too short for its distance). Every crossing of the domain lies within the outer radius, so
/// otherwise each `t` an engine reports is finite.
fn outer_ball_representable<T: Real>(
    axes: &Axes<'_, T>,
    ray: &Line<T>,
    t_min: T,
    t_max: T,
) -> bool {
    let Some(&r2) = axes.radial.r2.last() else {
        return true;
    };
    // Cheap bound first (no square root, no division): a point of the ball has |s| ≤ 2(|p| + R) (the scaled
    // direction is at least 1/2 long), and |p| + R ≤ 2 max|p_i| + max(1, R²); with a factor 2 for rounding.
    let bound = (ray.origin().max_abs() * T::TWO + r2.max(T::ONE)) * (T::TWO + T::TWO);
    if ray.t_from_scaled(bound).is_finite() {
        return true;
    }
    match sphere_scaled_roots(r2, ray) {
        Some((s_in, s_out)) if s_in < s_out => {
            let (t_in, t_out) = (ray.t_from_scaled(s_in), ray.t_from_scaled(s_out));
            !((t_out == T::INFINITY && t_max == T::INFINITY)
                || (t_in == T::NEG_INFINITY && t_min == T::NEG_INFINITY))
        }
        _ => true,
    }
}

/// The radius stream at the start `t_min` of `radial_ray` (the ray in the grid's frame, or its projection on
/// z = 0 for a cylinder or polar grid), with the line's invariants written to `line`. Out of line: its
/// temporaries stay out of the set-up's frame.
#[inline(never)]
fn radial_start<T: Real>(
    axes: &Axes<'_, T>,
    radial_ray: &Line<T>,
    line: &mut RadialLine<T>,
    t_min: T,
    t_max: T,
) -> Result<(Stream<T>, u32), MarchError> {
    *line = RadialLine::of(radial_ray);
    if !outer_ball_representable(axes, radial_ray, t_min, t_max) {
        return Err(MarchError::Unrepresentable);
    }
    Ok(Stream::radial(&axes.radial, radial_ray, line, t_min))
}

/// [`radial_start`] on the projection of `ray` on z = 0 (cylinder and polar grids), from `rel`, its line in the
/// grid's frame; `Ok(None)` for a vertical line, whose distance from the axis does not change. Out of line: the
/// projected ray lives in its own frame.
#[inline(never)]
fn flat_radial_start<T: Real>(
    axes: &Axes<'_, T>,
    ray: &Ray<T>,
    rel: &Line<T>,
    line: &mut RadialLine<T>,
) -> Result<Option<(Stream<T>, u32)>, MarchError> {
    let (p, d) = (rel.origin(), ray.dir());
    let Ok(flat) = Ray::new(V3::new(p.x, p.y, T::ZERO), V3::new(d.x, d.y, T::ZERO))
        .and_then(|r| r.with_interval(ray.t_min(), T::INFINITY))
    else {
        return Ok(None);
    };
    radial_start(axes, flat.line(), line, ray.t_min(), ray.t_max()).map(Some)
}

/// Locates the ray, finds where it enters the outer radius, and starts the other coordinates there: fills in
/// `rays` and `streams` (in place: a march's state is not moved around) and returns the start `t`. The
/// streams' bands are the bands at the start. `Ok(None)` when the ray cannot meet the domain.
///
/// Not inlined: its temporaries (each coordinate's start) then live in its own frame, which is gone before the
/// march's first crossing, instead of in the caller's for the whole march. The ray in the grid's frame is formed
/// in place in `rays`, and the radius stream's start (with the projected ray of a cylinder or polar grid) out of
/// line, so that no copy of a ray sits in this frame (on a Cortex-M4F this halved its frame).
#[inline(never)]
pub(crate) fn setup<T: Real, K: GridKind>(
    axes: &Axes<'_, T>,
    ray: &Ray<T>,
    rays: &mut Rays<T>,
    streams: &mut [Stream<T>; 3],
    roots: &mut SecondRoots<T>,
) -> Result<Option<T>, MarchError> {
    // the ray's line in the grid's frame, formed in place (no copies of it in this frame)
    rays.rel = *ray.line();
    rays.rel.recenter(axes.center).map_err(MarchError::Ray)?;
    rays.t_max = ray.t_max();
    let t_min = ray.t_min();
    let radial = if coordinates::<K>(axes.coordinates).flat_radius() {
        flat_radial_start(axes, ray, &rays.rel, &mut rays.radial)?
    } else {
        Some(radial_start(
            axes,
            &rays.rel,
            &mut rays.radial,
            t_min,
            rays.t_max,
        )?)
    };
    let radial_moves = radial.is_some();
    let (mut rs, mut rband) = radial.unwrap_or_else(|| {
        // a vertical line in a cylinder or polar grid: its distance from the axis is constant
        let p = rays.rel.origin();
        let band = axes.radial.band_of_r2(p.x * p.x + p.y * p.y);
        (Stream::fixed(band), band)
    });
    let mut t0 = t_min;
    if rband >= axes.radial.len {
        let [s0, ..] = streams;
        *s0 = rs;
        if !next_event_outlined::<T, K>(axes, rays, streams, roots, 0) {
            return Ok(None);
        }
        let [s0, ..] = streams;
        rs = *s0;
        t0 = rs.t;
        rband = rs.band;
        if !t0.is_finite() {
            // the line enters the outer radius where t overflows: a crossing that t cannot express
            return Err(MarchError::Unrepresentable);
        }
    }
    if !radial_moves && rband == 0 {
        return Ok(None); // a vertical line inside the hole of a cylinder grid
    }
    if let Some(s) = streams.get_mut(0) {
        *s = rs;
    }
    for slot in 1..3 {
        let (s, _) = match coordinates::<K>(axes.coordinates).slots.get(slot) {
            Some(SlotKind::Zenith) if may_have_zenith::<K>() => match axes.zenith.as_ref() {
                Some(z) if t0.is_finite() => Stream::zenith(z, &rays.rel, t0),
                _ => (Stream::fixed(0), 0),
            },
            Some(SlotKind::Azimuth) => Stream::azimuth(&axes.azimuth, &rays.rel, t0),
            Some(SlotKind::Height) if may_have_height::<K>() => match axes.height.as_ref() {
                Some(h) => Stream::height(h, &rays.rel, t0),
                None => (Stream::fixed(0), 0),
            },
            _ => (Stream::fixed(0), 0),
        };
        if let Some(sl) = streams.get_mut(slot) {
            *sl = s;
        }
    }
    Ok(Some(t0))
}
