//! The three grids: spherical (r, θ, φ), cylindrical (ρ, φ, z) and 2-D polar (r, φ).

use super::axes::{AzimuthAxis, HeightAxis, RadialAxis, ZenithAxis};
use super::error::{Axis, GridError, MarchError};
use super::kind::{Coordinates, Cylindrical, Dynamic, GridKind, Polar, Spherical};
use super::separable::SeparableMarch;
use super::serial::SerialMarch;
use super::tables::Axes;
use crate::ray::Ray;
use crate::real::Real;
use crate::vec3::V3;
use core::marker::PhantomData;

fn check_center<T: Real>(c: V3<T>) -> Result<V3<T>, GridError> {
    if c.is_finite() {
        Ok(c)
    } else {
        Err(GridError::NonFiniteCenter)
    }
}

fn check_workspace(got: usize, needed: usize) -> Result<(), GridError> {
    if got < needed {
        Err(GridError::WorkspaceTooSmall)
    } else {
        Ok(())
    }
}

/// A grid of kind `K` ([`Spherical`], [`Cylindrical`] or [`Polar`]) over borrowed breakpoints, ready to march
/// rays (Hannasch): built by [`SphericalGrid::new`], [`CylindricalGrid::new`] or [`PolarGrid::new`]. The kind
/// is a type, so a program compiles the marchers of the kinds it uses only; `AnyGrid` holds
/// any of the three when the kind is chosen at run time.
#[derive(Debug, Clone, Copy)]
pub struct Grid<'a, T, K> {
    axes: Axes<'a, T>,
    kind: PhantomData<K>,
}

impl<'a, T: Real, K: GridKind> Grid<'a, T, K> {
    fn of(axes: Axes<'a, T>) -> Self {
        Grid {
            axes,
            kind: PhantomData,
        }
    }

    /// The same grid with its kind left to run time: its marches are [`Dynamic`]'s (the same answers, one
    /// marcher for every kind a program holds this way).
    pub fn into_dynamic(self) -> Grid<'a, T, Dynamic> {
        Grid::of(self.axes)
    }

    /// The kind's coordinates.
    pub fn coordinates(&self) -> Coordinates {
        self.axes.coordinates
    }

    /// The center (a cylinder's: the point of its axis where z = 0).
    pub fn center(&self) -> V3<T> {
        self.axes.center
    }

    /// March `ray` through the grid with the serial engine (Hannasch ch. 5): a lazy iterator of the cells in
    /// increasing `t`, in constant memory.
    ///
    /// ```
    /// # use curvicast::{march::SphericalGrid, ray::Ray};
    /// # use core::f64::consts::PI;
    /// # let (r, theta, phi) = ([0.0, 1.0], [0.0, PI], [0.0, 2.0 * PI]);
    /// # let mut ws = [0.0; SphericalGrid::<f64>::workspace_len(2, 2, 2)];
    /// # let grid = SphericalGrid::new(&r, &theta, &phi, &mut ws)?;
    /// // projection sampler (§6.1): Σ value × length, here a constant density 1 in the unit ball
    /// let ray = Ray::new([-3.0, 0.6, 0.0], [1.0, 0.0, 0.0])?;
    /// let column: f64 = grid.march(&ray).map(|c| 1.0 * (c.t_exit - c.t_enter)).sum();
    /// assert!((column - 1.6).abs() < 1e-12); // the chord 2·sqrt(1 − 0.6²)
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn march(&self, ray: &Ray<T>) -> SerialMarch<'_, T, K> {
        SerialMarch::new(&self.axes, ray)
    }

    /// March `ray` with the separable engine (Hannasch §3): each coordinate's crossings are listed into
    /// buffers of capacity `N` first. Agrees exactly with [`Grid::march`]; a buffer that would overflow
    /// is [`MarchError::BufferFull`].
    pub fn march_separable<const N: usize>(
        &self,
        ray: &Ray<T>,
    ) -> Result<SeparableMarch<T, N>, MarchError> {
        SeparableMarch::new::<K>(&self.axes, ray)
    }

    /// As [`Self::march_separable`], but listing into `march`'s buffers in place (no copy of the `N`-sized
    /// buffers on return), so one [`SeparableMarch`] (e.g. `SeparableMarch::default()`) serves many rays. On an
    /// error `march` is left empty.
    pub fn march_separable_into<const N: usize>(
        &self,
        ray: &Ray<T>,
        march: &mut SeparableMarch<T, N>,
    ) -> Result<(), MarchError> {
        march.fill::<K>(&self.axes, ray)
    }
}

/// A spherical grid (Hannasch): radius `r`, zenith angle θ from +z in [0, π], azimuth φ from +x toward +y.
///
/// Cell `[i, j, k]` is `r[i] <= r < r[i+1]`, `theta[j] <= θ < theta[j+1]`, `phi[k] <= φ < phi[k+1]` (φ taken
/// modulo 2π). Breakpoints are borrowed, strictly increasing and non-uniform as the caller likes; the domain may
/// be a shell (`r[0] > 0`), a zenith band excluding either pole, and an azimuth wedge of any width up to 2π,
/// also across φ = 0 (e.g. `phi = [-0.5, 0.5]`). Points on the z axis have φ = 0 (the `atan2(0, 0)`
/// convention); a point on the −z axis has θ = π, so it lies outside a grid whose last θ is π.
///
/// **Storage.** The pseudospherical breakpoints of §2 (r², (cos θ, sin θ) and (cos φ, sin φ)) are computed once
/// into a caller-provided workspace of [`SphericalGrid::workspace_len`]`(r.len(), theta.len(), phi.len())`
/// scalars (no allocation):
///
/// ```
/// use curvicast::ray::Ray;
/// use curvicast::march::SphericalGrid;
/// use core::f64::consts::PI;
/// let (r, theta, phi) = ([0.0, 0.5, 1.0], [0.0, PI / 2.0, PI], [0.0, PI, 2.0 * PI]);
/// let mut ws = [0.0; SphericalGrid::<f64>::workspace_len(3, 3, 3)];
/// let grid = SphericalGrid::new(&r, &theta, &phi, &mut ws)?;
/// // a ray along +x at height z = 0.25, in front of the xz plane (y = 0.1)
/// let ray = Ray::new([-2.0, 0.1, 0.25], [1.0, 0.0, 0.0])?;
/// let cells: Vec<[u32; 3]> = grid.march(&ray).map(|c| c.cell).collect();
/// assert_eq!(cells.first(), Some(&[1, 0, 0])); // outer shell, upper half, φ in [0, π)
/// assert_eq!(cells.len(), 3); // outer shell, inner ball, outer shell
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub type SphericalGrid<'a, T> = Grid<'a, T, Spherical>;

impl<T> Grid<'_, T, Spherical> {
    /// The workspace length (in scalars) that [`SphericalGrid::new`] needs: `nr + 2 nθ + 2 nφ`.
    pub const fn workspace_len(nr: usize, ntheta: usize, nphi: usize) -> usize {
        nr.saturating_add(ntheta.saturating_mul(2))
            .saturating_add(nphi.saturating_mul(2))
    }
}

impl<'a, T: Real> Grid<'a, T, Spherical> {
    /// A grid centred at the origin. Validates the breakpoints (at least 2 each, finite, strictly increasing,
    /// `r[0] >= 0`, θ in [0, π], φ span at most 2π) and fills `workspace` with their pseudospherical form.
    pub fn new(
        r: &'a [T],
        theta: &'a [T],
        phi: &'a [T],
        workspace: &'a mut [T],
    ) -> Result<Self, GridError> {
        check_workspace(
            workspace.len(),
            Self::workspace_len(r.len(), theta.len(), phi.len()),
        )?;
        let mut ws = workspace;
        let radial = RadialAxis::build(Axis::R, r, &mut ws)?;
        let mut zenith = ZenithAxis::build(theta, &mut ws)?;
        let mut azimuth = AzimuthAxis::build(phi, &mut ws)?;
        let scale = r.last().copied().unwrap_or(T::ZERO);
        zenith.scale = scale;
        azimuth.scale = scale;
        Ok(Grid::of(Axes::new(
            Coordinates::SPHERICAL,
            radial,
            Some(zenith),
            azimuth,
            None,
        )))
    }

    /// The same grid centred at `center` (an error if it is not finite).
    pub fn with_center(mut self, center: impl Into<V3<T>>) -> Result<Self, GridError> {
        self.axes.center = check_center(center.into())?;
        Ok(self)
    }

    /// The number of cells along each axis `[r, θ, φ]`.
    pub fn shape(&self) -> [u32; 3] {
        [
            self.axes.radial.len.saturating_sub(1),
            self.axes.zenith.map_or(0, |z| z.len.saturating_sub(1)),
            self.axes.azimuth.sectors,
        ]
    }

    /// True when the φ breakpoints span a full turn (the φ index wraps around).
    pub fn azimuth_is_full_turn(&self) -> bool {
        self.axes.azimuth.full
    }
}

/// A cylindrical grid: radius ρ from the z axis, azimuth φ, height z; cell `[i, k, m]` is
/// `rho[i] <= ρ < rho[i+1]`, `phi[k] <= φ < phi[k+1]` (modulo 2π), `z[m] <= z < z[m+1]` (Hannasch §3.3).
///
/// Workspace: [`CylindricalGrid::workspace_len`]`(rho.len(), phi.len())` scalars (ρ² and (cos φ, sin φ)).
///
/// ```
/// use curvicast::ray::Ray;
/// use curvicast::march::CylindricalGrid;
/// use core::f64::consts::PI;
/// let (rho, phi, z) = ([0.0, 1.0, 2.0], [0.0, PI, 2.0 * PI], [-1.0, 0.0, 1.0]);
/// let mut ws = [0.0; CylindricalGrid::<f64>::workspace_len(3, 3)];
/// let grid = CylindricalGrid::new(&rho, &phi, &z, &mut ws)?;
/// let ray = Ray::new([0.5, 0.5, -5.0], [0.0, 0.0, 1.0])?; // vertical, inside ρ < 1, φ = π/4
/// let cells: Vec<[u32; 3]> = grid.march(&ray).map(|c| c.cell).collect();
/// assert_eq!(cells, [[0, 0, 0], [0, 0, 1]]);
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub type CylindricalGrid<'a, T> = Grid<'a, T, Cylindrical>;

impl<T> Grid<'_, T, Cylindrical> {
    /// The workspace length (in scalars) that [`CylindricalGrid::new`] needs: `nρ + 2 nφ`.
    pub const fn workspace_len(nrho: usize, nphi: usize) -> usize {
        nrho.saturating_add(nphi.saturating_mul(2))
    }
}

impl<'a, T: Real> Grid<'a, T, Cylindrical> {
    /// A grid around the z axis through the origin; validates like [`SphericalGrid::new`] (z: finite, strictly
    /// increasing, at least 2).
    pub fn new(
        rho: &'a [T],
        phi: &'a [T],
        z: &'a [T],
        workspace: &'a mut [T],
    ) -> Result<Self, GridError> {
        check_workspace(workspace.len(), Self::workspace_len(rho.len(), phi.len()))?;
        let mut ws = workspace;
        let radial = RadialAxis::build(Axis::Rho, rho, &mut ws)?;
        let mut azimuth = AzimuthAxis::build(phi, &mut ws)?;
        azimuth.scale = rho.last().copied().unwrap_or(T::ZERO);
        let height = HeightAxis::build(z)?;
        Ok(Grid::of(Axes::new(
            Coordinates::CYLINDRICAL,
            radial,
            None,
            azimuth,
            Some(height),
        )))
    }

    /// The same grid with its axis through `center` (z breakpoints are relative to `center.z`).
    pub fn with_center(mut self, center: impl Into<V3<T>>) -> Result<Self, GridError> {
        self.axes.center = check_center(center.into())?;
        Ok(self)
    }

    /// The number of cells along each axis `[ρ, φ, z]`.
    pub fn shape(&self) -> [u32; 3] {
        [
            self.axes.radial.len.saturating_sub(1),
            self.axes.azimuth.sectors,
            self.axes.height.map_or(0, |h| h.len.saturating_sub(1)),
        ]
    }
}

/// A 2-D polar grid (Hannasch §3.4): radius r and azimuth φ in the plane; the rays' z components are ignored.
/// Cell `[i, k, 0]` is `r[i] <= r < r[i+1]`, `phi[k] <= φ < phi[k+1]` (the CLI prints `[i, k]`).
///
/// Workspace: [`PolarGrid::workspace_len`]`(r.len(), phi.len())` scalars.
///
/// ```
/// use curvicast::ray::Ray;
/// use curvicast::march::PolarGrid;
/// let (r, phi) = ([1.0, 2.0], [-0.5, 0.5]); // an annular wedge across φ = 0
/// let mut ws = [0.0; PolarGrid::<f64>::workspace_len(2, 2)];
/// let grid = PolarGrid::new(&r, &phi, &mut ws)?;
/// let ray = Ray::new([0.0, 0.0, 7.0], [1.0, 0.0, 3.0])?; // z is ignored
/// let c: Vec<_> = grid.march(&ray).collect();
/// assert_eq!(c.len(), 1);
/// assert_eq!((c[0].cell, c[0].t_enter, c[0].t_exit), ([0, 0, 0], 1.0, 2.0));
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub type PolarGrid<'a, T> = Grid<'a, T, Polar>;

impl<T> Grid<'_, T, Polar> {
    /// The workspace length (in scalars) that [`PolarGrid::new`] needs: `nr + 2 nφ`.
    pub const fn workspace_len(nr: usize, nphi: usize) -> usize {
        nr.saturating_add(nphi.saturating_mul(2))
    }
}

impl<'a, T: Real> Grid<'a, T, Polar> {
    /// A polar grid centred at the origin; validates like [`SphericalGrid::new`].
    pub fn new(r: &'a [T], phi: &'a [T], workspace: &'a mut [T]) -> Result<Self, GridError> {
        check_workspace(workspace.len(), Self::workspace_len(r.len(), phi.len()))?;
        let mut ws = workspace;
        let radial = RadialAxis::build(Axis::R, r, &mut ws)?;
        let mut azimuth = AzimuthAxis::build(phi, &mut ws)?;
        azimuth.scale = r.last().copied().unwrap_or(T::ZERO);
        Ok(Grid::of(Axes::new(
            Coordinates::POLAR,
            radial,
            None,
            azimuth,
            None,
        )))
    }

    /// The same grid centred at `(cx, cy)`.
    pub fn with_center(mut self, center: [T; 2]) -> Result<Self, GridError> {
        let [x, y] = center;
        self.axes.center = check_center(V3::new(x, y, T::ZERO))?;
        Ok(self)
    }

    /// The number of cells along each axis `[r, φ]`.
    pub fn shape(&self) -> [u32; 2] {
        [
            self.axes.radial.len.saturating_sub(1),
            self.axes.azimuth.sectors,
        ]
    }
}
