//! A uniform grid of the bounding boxes of a set of triangles: which faces are near a box, in
//! about constant time for a cloth of even elements. Used by the self-intersection measure
//! ([`super::self_intersections`]) and by adaptation's crossing check of an edit.

use crate::math::{Real, Vec3};

/// Most grid cells per face on average: the cell grows until the grid has at most this many
/// cells per face.
const CELLS_PER_FACE: usize = 4;

/// A uniform grid of cubic cells over the faces' bounding box, each cell listing the faces whose
/// bounding boxes overlap it (compressed rows, faces in ascending order within a cell).
pub(crate) struct FaceGrid {
    origin: Vec3,
    inv_cell: Real,
    dims: [usize; 3],
    start: Vec<usize>,
    items: Vec<usize>,
    /// Per listed face: its bounding box (m) and its lowest cell.
    boxes: Vec<(Vec3, Vec3)>,
    low_cells: Vec<Cell>,
}

type Cell = nalgebra::Vector3<usize>;

impl FaceGrid {
    /// The grid of the faces `live` (indices into `faces`, every position finite) at `x`; the
    /// listed faces are numbered as in `live`.
    pub(crate) fn new(x: &[Vec3], faces: &[[usize; 3]], live: &[usize]) -> FaceGrid {
        let boxes: Vec<(Vec3, Vec3)> = live
            .iter()
            .map(|&f| bounds(&faces[f].map(|i| x[i])))
            .collect();
        let mut lo = Vec3::repeat(Real::INFINITY);
        let mut hi = Vec3::repeat(Real::NEG_INFINITY);
        let mut extent_sum = 0.0;
        for &(a, b) in &boxes {
            lo = lo.inf(&a);
            hi = hi.sup(&b);
            extent_sum += (b - a).max();
        }
        let span = (hi - lo).max();
        let mut cell = (extent_sum / live.len() as Real).max(span * 1e-9);
        if cell.is_nan() || cell <= 0.0 {
            cell = 1.0; // every face is a point
        }
        let dims_for = |c: Real| (hi - lo).map(|e| (e / c).min(1e6) as usize + 1);
        while dims_for(cell).iter().product::<usize>() > CELLS_PER_FACE * live.len() {
            cell *= 2.0;
        }
        let d = dims_for(cell);
        let mut grid = FaceGrid {
            origin: lo,
            inv_cell: 1.0 / cell,
            dims: [d.x, d.y, d.z],
            start: vec![0; d.x * d.y * d.z + 1],
            items: Vec::new(),
            boxes: Vec::new(),
            low_cells: Vec::new(),
        };
        let face_cells: Vec<(Cell, Cell)> = boxes.iter().map(|&(a, b)| grid.cells(a, b)).collect();
        for &(a, b) in &face_cells {
            let start = &mut grid.start;
            for_each_cell(grid.dims, a, b, |c, _| start[c + 1] += 1);
        }
        for c in 0..grid.start.len() - 1 {
            grid.start[c + 1] += grid.start[c];
        }
        let mut fill = grid.start.clone();
        grid.items = vec![0; grid.start[grid.start.len() - 1]];
        for (k, &(a, b)) in face_cells.iter().enumerate() {
            let (dims, items) = (grid.dims, &mut grid.items);
            for_each_cell(dims, a, b, |c, _| {
                items[fill[c]] = k;
                fill[c] += 1;
            });
        }
        grid.low_cells = face_cells.iter().map(|&(a, _)| a).collect();
        grid.boxes = boxes;
        grid
    }

    /// The edge of a cell (m).
    pub(crate) fn cell_size(&self) -> Real {
        1.0 / self.inv_cell
    }

    /// The lowest and highest cells (per axis) of the box `[lo, hi]` (m; clamped to the grid).
    fn cells(&self, lo: Vec3, hi: Vec3) -> (Cell, Cell) {
        let at = |p: Vec3| {
            Cell::from_fn(|k, _| {
                let c = ((p[k] - self.origin[k]) * self.inv_cell).max(0.0);
                (c as usize).min(self.dims[k] - 1)
            })
        };
        (at(lo), at(hi))
    }

    /// Calls `f(k)` once for every listed face whose box meets the box `[lo, hi]` (m; touching
    /// included), `k` its index in the listed faces. The pair is taken in the first cell both
    /// boxes share, so a face in several cells comes once.
    pub(crate) fn visit_overlapping(&self, lo: Vec3, hi: Vec3, mut f: impl FnMut(usize)) {
        let (lo_cell, hi_cell) = self.cells(lo, hi);
        for_each_cell(self.dims, lo_cell, hi_cell, |c, cell| {
            for &k in &self.items[self.start[c]..self.start[c + 1]] {
                let (face_lo, face_hi) = self.boxes[k];
                if self.low_cells[k].sup(&lo_cell) == cell
                    && (0..3).all(|a| face_lo[a] <= hi[a] && face_hi[a] >= lo[a])
                {
                    f(k);
                }
            }
        });
    }
}

/// Calls `f(index, cell)` for every cell from `lo` to `hi` of a grid of `dims` cells.
fn for_each_cell(dims: [usize; 3], lo: Cell, hi: Cell, mut f: impl FnMut(usize, Cell)) {
    for k in lo.z..=hi.z {
        for j in lo.y..=hi.y {
            for i in lo.x..=hi.x {
                f(i + dims[0] * (j + dims[1] * k), Cell::new(i, j, k));
            }
        }
    }
}

/// The componentwise minimum and maximum of `points` (m).
pub(crate) fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    let mut lo = Vec3::repeat(Real::INFINITY);
    let mut hi = Vec3::repeat(Real::NEG_INFINITY);
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (lo, hi)
}
