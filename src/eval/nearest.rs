//! Nearest-item search in 3D for the surface distances of [`super::metrics`]: a uniform grid of
//! buckets over the items' bounding boxes (points or triangles), searched shell by shell around
//! a query point until no unvisited cell can hold anything closer. Exact: it returns the same
//! distance as a brute-force search (tested in `metrics`).

use super::metrics::point_triangle_distance;

/// A uniform bucket grid over items with bounding boxes (points or triangles), searched shell by
/// shell around a query point until no unvisited cell can hold anything closer.
struct NearestGrid {
    lo: [f64; 3],
    cell: f64,
    dims: [usize; 3],
    start: Vec<usize>,
    items: Vec<usize>,
}

impl NearestGrid {
    fn new(boxes: &[([f64; 3], [f64; 3])]) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for (a, b) in boxes {
            for c in 0..3 {
                lo[c] = lo[c].min(a[c]);
                hi[c] = hi[c].max(b[c]);
            }
        }
        let ext: Vec<f64> = (0..3).map(|c| (hi[c] - lo[c]).max(0.0)).collect();
        // Cloth surfaces are two-dimensional: size cells for about one item per cell over the
        // two largest extents.
        let mut sorted = ext.clone();
        sorted.sort_by(|a, b| b.total_cmp(a));
        let n = boxes.len().max(1) as f64;
        let diag = (ext[0] * ext[0] + ext[1] * ext[1] + ext[2] * ext[2]).sqrt();
        let cell = (sorted[0] * sorted[1] / n).sqrt().max(diag / n).max(1e-9);
        let dims = [0, 1, 2].map(|c| ((ext[c] / cell) as usize + 1).min(512));
        let idx = |x: f64, c: usize| (((x - lo[c]) / cell).max(0.0) as usize).min(dims[c] - 1);
        let ncells = dims[0] * dims[1] * dims[2];
        let mut lists: Vec<Vec<usize>> = vec![Vec::new(); ncells];
        for (j, (a, b)) in boxes.iter().enumerate() {
            let i0 = [0, 1, 2].map(|c| idx(a[c], c));
            let i1 = [0, 1, 2].map(|c| idx(b[c], c));
            for z in i0[2]..=i1[2] {
                for y in i0[1]..=i1[1] {
                    for x in i0[0]..=i1[0] {
                        lists[(z * dims[1] + y) * dims[0] + x].push(j);
                    }
                }
            }
        }
        let mut start = Vec::with_capacity(ncells + 1);
        let mut items = Vec::new();
        start.push(0);
        for l in lists {
            items.extend(l);
            start.push(items.len());
        }
        NearestGrid {
            lo,
            cell,
            dims,
            start,
            items,
        }
    }

    /// The smallest `dist(item)` over the items, visiting cells in shells around `p`.
    fn nearest(&self, p: &[f64; 3], mut dist: impl FnMut(usize) -> f64) -> f64 {
        let centre = [0, 1, 2].map(|c| {
            let x = ((p[c] - self.lo[c]) / self.cell).floor();
            x.clamp(-1.0, self.dims[c] as f64) as i64
        });
        let mut best = f64::INFINITY;
        let max_r = *self.dims.iter().max().expect("3 dims") as i64 + 2;
        for r in 0..=max_r {
            // Every item first met in shell r is at least (r - 1) cells away.
            if r >= 1 && ((r - 1) as f64 * self.cell) > best {
                break;
            }
            let range = |c: usize| {
                let lo = (centre[c] - r).max(0);
                let hi = (centre[c] + r).min(self.dims[c] as i64 - 1);
                lo..=hi
            };
            for iz in range(2) {
                for iy in range(1) {
                    let on_shell = (iz - centre[2]).abs() == r || (iy - centre[1]).abs() == r;
                    let xs: Vec<i64> = if on_shell {
                        range(0).collect()
                    } else {
                        [centre[0] - r, centre[0] + r]
                            .into_iter()
                            .filter(|&x| x >= 0 && x < self.dims[0] as i64)
                            .collect()
                    };
                    for ix in xs {
                        let k =
                            (iz as usize * self.dims[1] + iy as usize) * self.dims[0] + ix as usize;
                        for &j in &self.items[self.start[k]..self.start[k + 1]] {
                            best = best.min(dist(j));
                        }
                    }
                }
            }
        }
        best
    }
}

pub(crate) struct PointGrid<'a> {
    points: &'a [[f64; 3]],
    grid: NearestGrid,
}

impl<'a> PointGrid<'a> {
    pub(crate) fn new(points: &'a [[f64; 3]]) -> Self {
        let boxes: Vec<([f64; 3], [f64; 3])> = points.iter().map(|p| (*p, *p)).collect();
        PointGrid {
            points,
            grid: NearestGrid::new(&boxes),
        }
    }

    pub(crate) fn nearest_distance(&self, p: &[f64; 3]) -> f64 {
        self.grid.nearest(p, |j| {
            let q = self.points[j];
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
    }
}

pub(crate) struct TriangleGrid<'a> {
    tris: &'a [[[f64; 3]; 3]],
    grid: NearestGrid,
}

impl<'a> TriangleGrid<'a> {
    pub(crate) fn new(tris: &'a [[[f64; 3]; 3]]) -> Self {
        let boxes: Vec<([f64; 3], [f64; 3])> = tris
            .iter()
            .map(|t| {
                let lo = [0, 1, 2].map(|c| t[0][c].min(t[1][c]).min(t[2][c]));
                let hi = [0, 1, 2].map(|c| t[0][c].max(t[1][c]).max(t[2][c]));
                (lo, hi)
            })
            .collect();
        TriangleGrid {
            tris,
            grid: NearestGrid::new(&boxes),
        }
    }

    pub(crate) fn nearest_distance(&self, p: &[f64; 3]) -> f64 {
        self.grid
            .nearest(p, |j| point_triangle_distance(*p, &self.tris[j]))
    }
}
