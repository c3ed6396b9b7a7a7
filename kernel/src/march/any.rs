//! The grid kind chosen at run time (a command line, a grid file, the C interface): a thin enum over the three
//! grid types, and the march of whichever it holds. A program that names one kind's grid only does not link
//! this, nor the other kinds' marchers.

use super::crossing::CellCrossing;
use super::error::MarchError;
use super::grid::{CylindricalGrid, Grid, PolarGrid, SphericalGrid};
use super::kind::{Cylindrical, Dynamic, Polar, Spherical};
use super::serial::SerialMarch;
use crate::ray::Ray;
use crate::real::Real;

/// A grid of any of the three kinds.
///
/// ```
/// use curvicast::march::{AnyGrid, PolarGrid};
/// use curvicast::ray::Ray;
/// let (r, phi) = ([1.0, 2.0], [-0.5, 0.5]);
/// let mut ws = [0.0; PolarGrid::<f64>::workspace_len(2, 2)];
/// let grid = AnyGrid::from(PolarGrid::new(&r, &phi, &mut ws)?);
/// let ray = Ray::new([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])?;
/// assert_eq!(grid.march(&ray).count(), 1);
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub enum AnyGrid<'a, T> {
    /// A spherical grid.
    Spherical(SphericalGrid<'a, T>),
    /// A cylindrical grid.
    Cylindrical(CylindricalGrid<'a, T>),
    /// A 2-D polar grid.
    Polar(PolarGrid<'a, T>),
}

/// The serial march (Hannasch ch. 5) of an [`AnyGrid`]: the march of the kind it holds.
#[derive(Debug, Clone)]
pub enum AnyMarch<'g, T> {
    /// Through a spherical grid.
    Spherical(SerialMarch<'g, T, Spherical>),
    /// Through a cylindrical grid.
    Cylindrical(SerialMarch<'g, T, Cylindrical>),
    /// Through a 2-D polar grid.
    Polar(SerialMarch<'g, T, Polar>),
}

impl<'a, T> From<SphericalGrid<'a, T>> for AnyGrid<'a, T> {
    fn from(g: SphericalGrid<'a, T>) -> Self {
        AnyGrid::Spherical(g)
    }
}

impl<'a, T> From<CylindricalGrid<'a, T>> for AnyGrid<'a, T> {
    fn from(g: CylindricalGrid<'a, T>) -> Self {
        AnyGrid::Cylindrical(g)
    }
}

impl<'a, T> From<PolarGrid<'a, T>> for AnyGrid<'a, T> {
    fn from(g: PolarGrid<'a, T>) -> Self {
        AnyGrid::Polar(g)
    }
}

/// `$body` with `$m` bound to the march of whichever kind `$march` holds.
macro_rules! each {
    ($march:expr, $m:ident => $body:expr) => {
        match $march {
            AnyMarch::Spherical($m) => $body,
            AnyMarch::Cylindrical($m) => $body,
            AnyMarch::Polar($m) => $body,
        }
    };
}

impl<'a, T: Real> AnyGrid<'a, T> {
    /// The serial march of `ray` (see `Grid::march`).
    pub fn march(&self, ray: &Ray<T>) -> AnyMarch<'_, T> {
        match self {
            AnyGrid::Spherical(g) => AnyMarch::Spherical(g.march(ray)),
            AnyGrid::Cylindrical(g) => AnyMarch::Cylindrical(g.march(ray)),
            AnyGrid::Polar(g) => AnyMarch::Polar(g.march(ray)),
        }
    }

    /// The grid's kind, as named in the grid files.
    pub fn kind_name(&self) -> &'static str {
        use super::kind::GridKind;
        match self {
            AnyGrid::Spherical(_) => Spherical::NAME,
            AnyGrid::Cylindrical(_) => Cylindrical::NAME,
            AnyGrid::Polar(_) => Polar::NAME,
        }
    }

    /// The grid with its kind left to run time (see `Dynamic`).
    pub fn into_dynamic(self) -> Grid<'a, T, Dynamic> {
        match self {
            AnyGrid::Spherical(g) => g.into_dynamic(),
            AnyGrid::Cylindrical(g) => g.into_dynamic(),
            AnyGrid::Polar(g) => g.into_dynamic(),
        }
    }
}

impl<T: Real> AnyMarch<'_, T> {
    /// See [`SerialMarch::error`].
    pub fn error(&self) -> Option<MarchError> {
        each!(self, m => m.error())
    }

    /// See [`SerialMarch::fold_in_place`].
    pub fn fold_in_place<B>(&mut self, init: B, f: impl FnMut(B, CellCrossing<T>) -> B) -> B {
        each!(self, m => m.fold_in_place(init, f))
    }

    /// See [`SerialMarch::next_into`].
    pub fn next_into<C: From<CellCrossing<T>>>(&mut self, out: &mut [C]) -> usize {
        each!(self, m => m.next_into(out))
    }

    /// See [`SerialMarch::for_each_while`].
    pub fn for_each_while(&mut self, f: impl FnMut(CellCrossing<T>) -> bool) {
        each!(self, m => m.for_each_while(f))
    }
}

impl<T: Real> Iterator for AnyMarch<'_, T> {
    type Item = CellCrossing<T>;

    fn next(&mut self) -> Option<CellCrossing<T>> {
        each!(self, m => m.next())
    }

    /// The kind's internal iteration (see [`SerialMarch::fold_in_place`]): one dispatch per march.
    fn fold<B, F>(self, init: B, f: F) -> B
    where
        F: FnMut(B, CellCrossing<T>) -> B,
    {
        each!(self, m => m.fold(init, f))
    }
}
