//! The cloth's crossings with itself: the self-intersection measure (`self_intersections` in
//! metrics.csv).
//!
//! A crossing is a pair (edge, face) of the cloth's mesh that share no vertex, where the edge
//! passes through the face's interior: its ends lie strictly on opposite sides of the face's plane
//! and the line through it passes strictly inside the triangle (three signed volumes of one
//! sign). Touching, grazing and coplanar configurations are not counted; a sheet passing through
//! another shows as at least one crossing along every line where they cut. Candidate faces come
//! from a uniform grid of the faces' bounding boxes built for each measure ([`FaceGrid`]), so a measure costs about linear time in the faces for a cloth of even elements.

use super::face_grid::{bounds, FaceGrid};
use crate::math::{Real, Vec3};
use rayon::prelude::*;

/// Six times the signed volume of the tetrahedron `(a, b, c, d)` (m³): positive when `d` is on the
/// side of `(b - a) x (c - a)`.
fn orient(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Real {
    (b - a).cross(&(c - a)).dot(&(d - a))
}

/// Whether the segment `p -> q` passes through the interior of the triangle `tri` (strict
/// inequalities: touching, grazing or coplanar is no crossing). A segment whose box misses the
/// triangle's is apart from it: for a segment nearly parallel to the triangle's plane the signed
/// volumes below are decided by rounding, and without that test they could call a segment 6 cm
/// away crossing (found in an adaptation's crossing check).
pub fn segment_crosses_triangle(p: Vec3, q: Vec3, [a, b, c]: [Vec3; 3]) -> bool {
    let (lo, hi) = (a.inf(&b).inf(&c), a.sup(&b).sup(&c));
    if (0..3).any(|k| p[k].max(q[k]) < lo[k] || p[k].min(q[k]) > hi[k]) {
        return false;
    }
    let (sp, sq) = (orient(a, b, c, p), orient(a, b, c, q));
    if !(sp > 0.0 && sq < 0.0 || sp < 0.0 && sq > 0.0) {
        return false;
    }
    let sides = [orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)];
    sides.iter().all(|&s| s > 0.0) || sides.iter().all(|&s| s < 0.0)
}

/// Counts the crossings of the mesh with faces `faces` and edges `edges` (vertex slots) at
/// positions `x` (m): pairs of an edge and a face sharing no vertex where the edge passes through
/// the face. Faces and edges with a non-finite position count nothing.
pub fn self_intersections(x: &[Vec3], faces: &[[usize; 3]], edges: &[[usize; 2]]) -> usize {
    let finite = |i: usize| x[i].iter().all(|c| c.is_finite());
    let live: Vec<usize> = (0..faces.len())
        .filter(|&f| faces[f].iter().all(|&i| finite(i)))
        .collect();
    if live.is_empty() {
        return 0;
    }
    let grid = FaceGrid::new(x, faces, &live);
    if !crate::parallel::pool_can_help() {
        return crossings_of(x, faces, &live, &grid, edges);
    }
    // The edges in chunks, four per thread of the pool (at least MIN_EDGES_PER_TASK edges each);
    // the count does not depend on the chunks.
    let chunk = MIN_EDGES_PER_TASK.max(edges.len().div_ceil(4 * rayon::current_num_threads()));
    edges
        .par_chunks(chunk)
        .map(|chunk| crossings_of(x, faces, &live, &grid, chunk))
        .sum()
}

/// Fewest edges per parallel task of [`self_intersections`].
const MIN_EDGES_PER_TASK: usize = 256;

/// The crossings of the edges `edges` with the faces listed in `grid` (`live`: their indices in
/// `faces`).
fn crossings_of(
    x: &[Vec3],
    faces: &[[usize; 3]],
    live: &[usize],
    grid: &FaceGrid,
    edges: &[[usize; 2]],
) -> usize {
    let finite = |i: usize| x[i].iter().all(|c| c.is_finite());
    let mut count = 0;
    for &[p, q] in edges {
        if !(finite(p) && finite(q)) {
            continue;
        }
        let (lo, hi) = bounds(&[x[p], x[q]]);
        grid.visit_overlapping(lo, hi, |k| {
            let face = faces[live[k]];
            if !face.contains(&p)
                && !face.contains(&q)
                && segment_crosses_triangle(x[p], x[q], face.map(|i| x[i]))
            {
                count += 1;
            }
        });
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A segment nearly parallel to a triangle's plane, 6 cm from it (its box misses the
    /// triangle's): rounding made the signed volumes call it crossing.
    #[test]
    fn a_nearly_parallel_segment_far_from_the_triangle_does_not_cross() {
        let p = Vec3::new(
            -0.1250025850866014,
            0.12500257026227746,
            0.24652801364514076,
        );
        let q = Vec3::new(
            -2.4830271963963958e-8,
            0.12493920697402597,
            0.24658411321933899,
        );
        let tri = [
            Vec3::new(
                -6.385113797538168e-8,
                5.514986992696908e-8,
                0.25225991868543374,
            ),
            Vec3::new(
                -4.434070496967282e-8,
                0.062469631061947944,
                0.24942201595238636,
            ),
            Vec3::new(
                -0.06250132446886969,
                0.06250131270607369,
                0.24939396616528725,
            ),
        ];
        assert!(!segment_crosses_triangle(p, q, tri));
    }

    /// Two squares of two triangles each: the unit square in the plane z = 0, and a vertical one
    /// (y in [0.25, 0.75], z in [-0.5, 0.5]) through it along x = 0.5 when `cut`, or beside it
    /// at x = 2 otherwise. Every coordinate is exact in binary, so the touching cases are exact.
    fn two_sheets(cut: bool) -> (Vec<Vec3>, Vec<[usize; 3]>, Vec<[usize; 2]>) {
        let x0 = if cut { 0.5 } else { 2.0 };
        let x = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(x0, 0.25, -0.5),
            Vec3::new(x0, 0.75, -0.5),
            Vec3::new(x0, 0.75, 0.5),
            Vec3::new(x0, 0.25, 0.5),
        ];
        let faces = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
        let edges = vec![
            [0, 1],
            [1, 2],
            [2, 3],
            [3, 0],
            [0, 2],
            [4, 5],
            [5, 6],
            [6, 7],
            [7, 4],
            [4, 6],
        ];
        (x, faces, edges)
    }

    #[test]
    fn a_sheet_through_another_crosses_and_one_beside_it_does_not() {
        let (x, faces, edges) = two_sheets(false);
        assert_eq!(self_intersections(&x, &faces, &edges), 0);
        let (x, faces, edges) = two_sheets(true);
        // The vertical sheet's edges 5-6 and 7-4 pass through the horizontal sheet at y = 0.75
        // and 0.25, inside one triangle each; its diagonal 4-6 meets it at (0.5, 0.5, 0), on the
        // horizontal diagonal 0-2 (both triangles' shared edge: strictly inside neither). The
        // horizontal diagonal meets the vertical sheet at that same point, on its diagonal (not
        // counted); the horizontal edges 0-1 and 2-3 pass beside it.
        assert_eq!(self_intersections(&x, &faces, &edges), 2);
    }

    #[test]
    fn edges_sharing_a_vertex_with_the_face_never_count() {
        // A fan folded through itself at a shared vertex: the only candidates share vertex 0.
        let x = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.3, 0.3, -1.0),
            Vec3::new(0.3, 0.3, 1.0),
        ];
        let faces = vec![[0, 1, 2], [0, 3, 4]];
        let edges = vec![[0, 1], [1, 2], [2, 0], [0, 3], [3, 4], [4, 0]];
        // Edge 3-4 shares no vertex with face 0-1-2 and passes through it at (0.3, 0.3, 0).
        assert_eq!(self_intersections(&x, &faces, &edges), 1);
        let edges_without = vec![[0, 1], [1, 2], [2, 0], [0, 3], [4, 0]];
        assert_eq!(self_intersections(&x, &faces, &edges_without), 0);
    }

    #[test]
    fn non_finite_positions_count_nothing() {
        let (mut x, faces, edges) = two_sheets(true);
        x[5] = Vec3::new(Real::NAN, 0.0, 0.0);
        // Face 4-5-6 and the edges at vertex 5 drop out; edge 7-4 still crosses triangle 0-1-2,
        // and the horizontal diagonal still meets face 4-6-7 only on its edge 4-6.
        assert_eq!(self_intersections(&x, &faces, &edges), 1);
    }

    proptest! {
        /// The grid finds exactly the crossings a check of every pair finds.
        #[test]
        fn the_grid_finds_what_every_pair_finds(
            coords in prop::collection::vec(-1.0f64..1.0, 3 * 12),
            tris in prop::collection::vec((0usize..12, 0usize..12, 0usize..12), 1..10),
        ) {
            let x: Vec<Vec3> = coords.chunks(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
            let faces: Vec<[usize; 3]> = tris
                .iter()
                .filter(|(a, b, c)| a != b && b != c && a != c)
                .map(|&(a, b, c)| [a, b, c])
                .collect();
            let edges: Vec<[usize; 2]> = (0..12)
                .flat_map(|a| (a + 1..12).map(move |b| [a, b]))
                .collect();
            let mut brute = 0;
            for &[p, q] in &edges {
                for f in &faces {
                    if !f.contains(&p)
                        && !f.contains(&q)
                        && segment_crosses_triangle(x[p], x[q], f.map(|i| x[i]))
                    {
                        brute += 1;
                    }
                }
            }
            prop_assert_eq!(self_intersections(&x, &faces, &edges), brute);
        }
    }
}
