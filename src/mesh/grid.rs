//! A bucket grid over rest space (compressed rows) for the rest-point locator (face bounding
//! boxes). Cells may be longer along one axis than the other, so long thin faces (an N x 100000
//! grid) stay in a few cells each. Built in O(items + cells); items are stored in insertion order
//! within each cell, so queries are deterministic.
use crate::math::{Real, Vec2};

/// Most cells per item (and at least this many cells are allowed in all).
const MAX_CELLS_PER_ITEM: usize = 4;

/// Items bucketed by the cells their rest bounding boxes overlap.
#[derive(Clone, Debug, Default)]
pub(crate) struct BucketGrid<T> {
    origin: Vec2,
    inv_cell: Vec2,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    items: Vec<T>,
}

impl<T: Copy> BucketGrid<T> {
    /// A grid over the box `[lo, hi]` (m) with cells of about `cell.x` by `cell.y` (m), holding
    /// each entry `(box_lo, box_hi, item)` in every cell its box overlaps. Cells grow (keeping
    /// their aspect) until there are at most `MAX_CELLS_PER_ITEM` per entry. Boxes outside
    /// `[lo, hi]` are clamped to the border cells.
    pub(crate) fn new(lo: Vec2, hi: Vec2, cell: Vec2, entries: &[(Vec2, Vec2, T)]) -> Self {
        let ext = hi - lo;
        let size = |c: Real, e: Real| {
            if c.is_finite() && c > 0.0 {
                c
            } else {
                e.max(1.0)
            }
        };
        let mut cell = Vec2::new(size(cell.x, ext.x), size(cell.y, ext.y));
        let cells = |e: Real, c: Real| (e / c).clamp(0.0, 1e9) as usize + 1;
        let max_cells = MAX_CELLS_PER_ITEM * entries.len().max(1);
        let total = |c: Vec2| cells(ext.x, c.x).saturating_mul(cells(ext.y, c.y));
        while total(cell) > max_cells {
            cell *= 2.0;
        }
        let (nx, ny) = (cells(ext.x, cell.x), cells(ext.y, cell.y));
        let mut grid = BucketGrid {
            origin: lo,
            inv_cell: Vec2::new(1.0 / cell.x, 1.0 / cell.y),
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

    fn coord(&self, x: Real, origin: Real, inv_cell: Real, n: usize) -> usize {
        let i = ((x - origin) * inv_cell).floor();
        if i.is_nan() || i < 0.0 {
            0
        } else {
            (i as usize).min(n - 1)
        }
    }

    fn column(&self, x: Real) -> usize {
        self.coord(x, self.origin.x, self.inv_cell.x, self.nx)
    }

    fn row(&self, y: Real) -> usize {
        self.coord(y, self.origin.y, self.inv_cell.y, self.ny)
    }

    fn for_cells(&self, lo: Vec2, hi: Vec2, mut f: impl FnMut(usize)) {
        let (i0, i1) = (self.column(lo.x), self.column(hi.x));
        let (j0, j1) = (self.row(lo.y), self.row(hi.y));
        for j in j0..=j1 {
            for i in i0..=i1 {
                f(j * self.nx + i);
            }
        }
    }

    /// The items of the cell containing `p` (clamped to the grid).
    pub(crate) fn at(&self, p: Vec2) -> &[T] {
        let c = self.row(p.y) * self.nx + self.column(p.x);
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }
}
