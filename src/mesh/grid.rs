//! A uniform bucket grid over rest space (compressed rows), shared by the conformity checker
//! (vertices, T-junction search) and the rest-point locator (face bounding boxes). Built in
//! O(items + cells); items are stored in insertion order within each cell, so queries are
//! deterministic.
use crate::math::{Real, Vec2};

/// Largest number of cells along one axis.
const MAX_CELLS_PER_AXIS: usize = 1 << 12;

/// Items bucketed by the cells their rest bounding boxes overlap.
#[derive(Clone, Debug, Default)]
pub(crate) struct BucketGrid<T> {
    origin: Vec2,
    inv_cell: Real,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    items: Vec<T>,
}

impl<T: Copy> BucketGrid<T> {
    /// A grid over the box `[lo, hi]` (m) with square cells of about `cell` (m), holding each
    /// entry `(box_lo, box_hi, item)` in every cell its box overlaps. Boxes outside `[lo, hi]` are
    /// clamped to the border cells.
    pub(crate) fn new(lo: Vec2, hi: Vec2, cell: Real, entries: &[(Vec2, Vec2, T)]) -> Self {
        let ext = hi - lo;
        let cell = if cell.is_finite() && cell > 0.0 {
            cell.max(ext.max() / MAX_CELLS_PER_AXIS as Real)
        } else {
            ext.max().max(1.0)
        };
        let cells = |e: Real| ((e / cell).max(0.0) as usize + 1).min(MAX_CELLS_PER_AXIS);
        let (nx, ny) = (cells(ext.x), cells(ext.y));
        let mut grid = BucketGrid {
            origin: lo,
            inv_cell: 1.0 / cell,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
            items: Vec::new(),
        };
        let mut count = vec![0u32; nx * ny + 1];
        for (a, b, _) in entries {
            grid.for_cells(*a, *b, |c| count[c + 1] += 1);
        }
        for i in 0..nx * ny {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut items: Vec<Option<T>> = vec![None; count[nx * ny] as usize];
        for &(a, b, item) in entries {
            grid.for_cells(a, b, |c| {
                items[fill[c] as usize] = Some(item);
                fill[c] += 1;
            });
        }
        grid.start = count;
        grid.items = items.into_iter().flatten().collect();
        grid
    }

    fn coord(&self, x: Real, origin: Real, n: usize) -> usize {
        let i = ((x - origin) * self.inv_cell).floor();
        if i.is_nan() || i < 0.0 {
            0
        } else {
            (i as usize).min(n - 1)
        }
    }

    fn for_cells(&self, lo: Vec2, hi: Vec2, mut f: impl FnMut(usize)) {
        let (i0, i1) = (
            self.coord(lo.x, self.origin.x, self.nx),
            self.coord(hi.x, self.origin.x, self.nx),
        );
        let (j0, j1) = (
            self.coord(lo.y, self.origin.y, self.ny),
            self.coord(hi.y, self.origin.y, self.ny),
        );
        for j in j0..=j1 {
            for i in i0..=i1 {
                f(j * self.nx + i);
            }
        }
    }

    /// Calls `f` on every item of every cell overlapping the box `[lo, hi]` (an item spanning
    /// several of those cells is visited once per cell).
    pub(crate) fn for_each_in(&self, lo: Vec2, hi: Vec2, mut f: impl FnMut(T)) {
        self.for_cells(lo, hi, |c| {
            for &item in &self.items[self.start[c] as usize..self.start[c + 1] as usize] {
                f(item);
            }
        });
    }

    /// The items of the cell containing `p` (clamped to the grid).
    pub(crate) fn at(&self, p: Vec2) -> &[T] {
        let c = self.coord(p.y, self.origin.y, self.ny) * self.nx
            + self.coord(p.x, self.origin.x, self.nx);
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }
}
