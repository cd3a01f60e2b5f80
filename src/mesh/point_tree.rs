//! A static 2D k-d tree over rest points, for the segment query of the conformity checker's
//! T-junction rule: every point within a distance of a segment.
//!
//! Built in O(n log n) (median splits along the wider side of each node's box). A query prunes
//! every node whose box is farther than the distance from the segment along x, y or the
//! segment's normal, so it costs about O(log n + k) for the edges of a tiling, whatever the
//! aspect ratio of its triangles (a uniform grid sized for the mean edge visits a whole column of
//! an N x 100000 grid per edge).
use crate::math::{Real, Vec2};

/// Most points in a leaf.
const LEAF: usize = 16;

/// One node: the bounding box of its points and their range in the permuted point list; an inner
/// node's children are the two halves of its range.
#[derive(Clone, Debug)]
struct Node {
    lo: Vec2,
    hi: Vec2,
    start: usize,
    end: usize,
    /// Index of the first child (the second follows it); 0 for a leaf.
    children: usize,
}

/// Points with payloads `T`, organised for segment-distance queries.
#[derive(Clone, Debug)]
pub(crate) struct PointTree<T> {
    nodes: Vec<Node>,
    points: Vec<(Vec2, T)>,
}

impl<T: Copy> PointTree<T> {
    /// The tree over `points` (m); non-finite points are never reported.
    pub(crate) fn new(mut points: Vec<(Vec2, T)>) -> Self {
        points.retain(|(p, _)| p.x.is_finite() && p.y.is_finite());
        let mut tree = PointTree {
            nodes: Vec::with_capacity(2 * points.len() / LEAF + 1),
            points,
        };
        tree.nodes.push(tree.node(0, tree.points.len()));
        let mut k = 0;
        while k < tree.nodes.len() {
            let (start, end) = (tree.nodes[k].start, tree.nodes[k].end);
            if end - start > LEAF {
                let ext = tree.nodes[k].hi - tree.nodes[k].lo;
                let axis = usize::from(ext.y > ext.x);
                let mid = start + (end - start) / 2;
                tree.points[start..end]
                    .select_nth_unstable_by(mid - start, |a, b| a.0[axis].total_cmp(&b.0[axis]));
                tree.nodes[k].children = tree.nodes.len();
                let (left, right) = (tree.node(start, mid), tree.node(mid, end));
                tree.nodes.push(left);
                tree.nodes.push(right);
            }
            k += 1;
        }
        tree
    }

    /// A leaf node over `points[start..end]` with its bounding box.
    fn node(&self, start: usize, end: usize) -> Node {
        let mut lo = Vec2::repeat(Real::INFINITY);
        let mut hi = Vec2::repeat(Real::NEG_INFINITY);
        for (p, _) in &self.points[start..end] {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        Node {
            lo,
            hi,
            start,
            end,
            children: 0,
        }
    }

    /// Calls `f` on every point whose distance to the segment `a b` may be at most `tol` (m): all
    /// of those, and only points whose leaf box is within `tol` of the segment (callers test the
    /// exact condition). `stack` is scratch space, reused across queries.
    pub(crate) fn for_each_near_segment(
        &self,
        (a, b): (Vec2, Vec2),
        tol: Real,
        stack: &mut Vec<usize>,
        mut f: impl FnMut(Vec2, T),
    ) {
        if self.points.is_empty() {
            return;
        }
        let (seg_lo, seg_hi) = (a.inf(&b), a.sup(&b));
        let d = b - a;
        let len = d.norm();
        let normal = if len > 0.0 {
            Vec2::new(-d.y, d.x) / len
        } else {
            Vec2::zeros()
        };
        stack.clear();
        stack.push(0);
        while let Some(k) = stack.pop() {
            let n = &self.nodes[k];
            let apart = n.lo.x > seg_hi.x + tol
                || n.lo.y > seg_hi.y + tol
                || n.hi.x < seg_lo.x - tol
                || n.hi.y < seg_lo.y - tol;
            if apart || Self::beside_line(n, a, normal, tol) {
                continue;
            }
            if n.children == 0 {
                for &(p, item) in &self.points[n.start..n.end] {
                    f(p, item);
                }
            } else {
                stack.push(n.children + 1);
                stack.push(n.children);
            }
        }
    }

    /// True when the node's box lies entirely more than `tol` to one side of the line through
    /// `a` with unit `normal`.
    fn beside_line(n: &Node, a: Vec2, normal: Vec2, tol: Real) -> bool {
        let side = |x: Real, y: Real| normal.dot(&(Vec2::new(x, y) - a));
        let s = [
            side(n.lo.x, n.lo.y),
            side(n.hi.x, n.lo.y),
            side(n.lo.x, n.hi.y),
            side(n.hi.x, n.hi.y),
        ];
        s.iter().all(|&v| v > tol) || s.iter().all(|&v| v < -tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tree reports every point within the distance that a brute-force scan finds.
    #[test]
    fn finds_every_point_near_a_segment() {
        let mut points = Vec::new();
        let mut next = crate::testing::uniform(12345);
        for i in 0..2000 {
            points.push((Vec2::new(next(), next() * 0.01), i));
        }
        let tree = PointTree::new(points.clone());
        for _ in 0..200 {
            let a = Vec2::new(next(), next() * 0.01);
            let b = Vec2::new(next(), next() * 0.01);
            let tol = 1e-3 * next();
            let d = b - a;
            let near = |p: Vec2| {
                let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
                (p - a - d * t).norm() <= tol
            };
            let mut found = Vec::new();
            tree.for_each_near_segment((a, b), tol, &mut Vec::new(), |p, i| {
                if near(p) {
                    found.push(i)
                }
            });
            found.sort_unstable();
            let expected: Vec<i32> = points
                .iter()
                .filter(|(p, _)| near(*p))
                .map(|&(_, i)| i)
                .collect();
            assert_eq!(found, expected);
        }
    }
}
