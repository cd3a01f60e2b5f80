//! A coarse signed-distance grid around a mesh obstacle: the mid phase that lets most points near
//! a mesh skip parry's queries.
//!
//! The signed distance `d` to a surface is 1-Lipschitz, so a point `p` in a cell whose centre
//! `c` has exact signed distance `d(c)` satisfies `d(c) - |p - c| <= d(p) <= d(c) + |p - c|`.
//! A point whose lower bound is already beyond the query band is clear without a query, and a
//! point whose upper bound is negative is certainly inside.

use crate::math::Real;
use parry3d_f64::math::Vector;

/// Cells along the longest side of the grid.
pub(crate) const GRID_CELLS: usize = 32;

/// Allowance (m) for the rounding in the stored distances and in `|p - c|`.
const SAFETY: Real = 1e-9;

/// Signed distances (m) at the centres of a regular grid of cubic cells.
pub(crate) struct DistanceGrid {
    origin: Vector,
    cell: Real,
    inv_cell: Real,
    dims: [usize; 3],
    values: Vec<Real>,
}

impl DistanceGrid {
    /// Samples `signed_distance` at the cell centres of a grid covering `[lo, hi]` (m).
    pub fn build(lo: Vector, hi: Vector, signed_distance: impl Fn(Vector) -> Real) -> Self {
        let extent = hi - lo;
        let cell = extent.max_element() / GRID_CELLS as Real;
        let dims = [extent.x, extent.y, extent.z].map(|e| ((e / cell).ceil() as usize).max(1));
        let mut values = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let c =
                        lo + Vector::new(i as Real + 0.5, j as Real + 0.5, k as Real + 0.5) * cell;
                    values.push(signed_distance(c));
                }
            }
        }
        DistanceGrid {
            origin: lo,
            cell,
            inv_cell: 1.0 / cell,
            dims,
            values,
        }
    }

    /// Bounds `(low, high)` (m) on the signed distance at `p`, or `None` outside the grid.
    #[inline]
    pub fn bounds(&self, p: Vector) -> Option<(Real, Real)> {
        let f = (p - self.origin) * self.inv_cell;
        if !(f.x >= 0.0 && f.y >= 0.0 && f.z >= 0.0) {
            return None;
        }
        let (i, j, k) = (f.x as usize, f.y as usize, f.z as usize);
        if i >= self.dims[0] || j >= self.dims[1] || k >= self.dims[2] {
            return None;
        }
        let d = self.values[i + self.dims[0] * (j + self.dims[1] * k)];
        let c = self.origin
            + Vector::new(i as Real + 0.5, j as Real + 0.5, k as Real + 0.5) * self.cell;
        let r = (p - c).length() + SAFETY;
        Some((d - r, d + r))
    }
}
