//! What a march yields: one cell crossed and the parameters where the ray enters and leaves it.

/// One cell crossed by a ray: its index and the parameters where the ray enters and leaves it.
///
/// The index is `[i, j, k]` for a spherical grid (r, θ, φ), `[i, k, m]` for a cylindrical one (ρ, φ, z) and
/// `[i, k, 0]` for a polar one (r, φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellCrossing<T> {
    /// The cell index.
    pub cell: [u32; 3],
    /// Where the ray enters the cell (in the caller's units of `t`).
    pub t_enter: T,
    /// Where it leaves (`t_exit >= t_enter`; equal for a zero-length crossing at a tie).
    pub t_exit: T,
}
