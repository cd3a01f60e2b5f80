//! Mesh generators: the union-jack grid (the initial mesh of every strategy) and the disk.
use super::Mesh;
use crate::math::{Real, Vec2};

/// An `nx` x `ny` vertex union-jack grid over the rest rectangle `[0, width] x [0, height]` (m).
///
/// Cell `(i, j)` is cut by the diagonal through its corner `(i, j)` when `i + j` is even and by the
/// other diagonal when odd, so vertex valences alternate 4 and 8 (the 4-8 mesh of MODEL.md §8.4).
/// Vertex `(i, j)` (column i along u, row j along v) has id `j * nx + i`. Panics when `nx` or `ny`
/// is below 2 or a size is not positive: callers validate user input first.
pub fn union_jack(nx: usize, ny: usize, width: Real, height: Real) -> Mesh {
    assert!(nx >= 2 && ny >= 2, "a grid needs at least 2 x 2 vertices");
    assert!(width > 0.0 && height > 0.0, "a grid needs a positive size");
    let mut rest = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            rest.push(Vec2::new(
                width * i as Real / (nx - 1) as Real,
                height * j as Real / (ny - 1) as Real,
            ));
        }
    }
    let id = |i: usize, j: usize| j * nx + i;
    let mut faces = Vec::with_capacity(2 * (nx - 1) * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                faces.push([a, b, c]);
                faces.push([a, c, d]);
            } else {
                faces.push([a, b, d]);
                faces.push([b, c, d]);
            }
        }
    }
    Mesh::from_faces(rest, &faces).expect("a union-jack grid is conforming")
}

/// A disk of the given radius (m) centred on `(radius, radius)` in rest space, so the pattern lies
/// in `[0, 2 radius]²`, made of `rings` concentric rings of roughly equilateral triangles.
///
/// Vertex 0 is the centre; ring `k` (1-based) has `6k` vertices at radius `radius k / rings`, the
/// first on the `+u` axis from the centre, numbered counter-clockwise after those of ring `k - 1`.
/// Consecutive rings are zipped by angle (shorter angular diagonal first), so the mesh is conforming and counter-clockwise. The
/// border is a polygon with `6 rings` sides inscribed in the circle. Panics when `rings` is 0 or
/// the radius is not positive: callers validate user input first.
pub fn disk(radius: Real, rings: usize) -> Mesh {
    assert!(rings >= 1, "a disk needs at least one ring");
    assert!(radius > 0.0, "a disk needs a positive radius");
    let centre = Vec2::new(radius, radius);
    let mut rest = vec![centre];
    // First vertex id of ring k (ring 0 is the centre).
    let first = |k: usize| if k == 0 { 0 } else { 1 + 3 * k * (k - 1) };
    for k in 1..=rings {
        let r = radius * k as Real / rings as Real;
        let n = 6 * k;
        for i in 0..n {
            let a = std::f64::consts::TAU * i as Real / n as Real;
            rest.push(centre + Vec2::new(r * a.cos(), r * a.sin()));
        }
    }
    let mut faces = Vec::with_capacity(6 * rings * rings);
    for i in 0..6 {
        faces.push([0, 1 + i, 1 + (i + 1) % 6]);
    }
    for k in 2..=rings {
        let (n, m) = (6 * k, 6 * (k - 1));
        let outer = |i: usize| first(k) + i % n;
        let inner = |j: usize| first(k - 1) + j % m;
        let (mut i, mut j) = (0, 0);
        while i < n || j < m {
            // Advance the ring whose new diagonal spans the smaller angle (in units of 1/(n m)
            // turn): outer makes inner(j)-outer(i+1), inner makes inner(j+1)-outer(i).
            let outer_span = ((i + 1) * m).abs_diff(j * n);
            let inner_span = ((j + 1) * n).abs_diff(i * m);
            let advance_outer = j == m || (i < n && outer_span <= inner_span);
            if advance_outer {
                faces.push([inner(j), outer(i), outer(i + 1)]);
                i += 1;
            } else {
                faces.push([inner(j), outer(i), inner(j + 1)]);
                j += 1;
            }
        }
    }
    Mesh::from_faces(rest, &faces).expect("a disk is conforming")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disk_counts_and_area() {
        for rings in 1..6 {
            let m = disk(0.5, rings);
            assert_eq!(m.vertex_count(), 1 + 3 * rings * (rings + 1));
            assert_eq!(m.face_count(), 6 * rings * rings);
            // Regular polygon with 6 rings sides inscribed in the circle.
            let n = (6 * rings) as Real;
            let polygon = 0.5 * n * 0.25 * (std::f64::consts::TAU / n).sin();
            assert!((m.pattern_area() - polygon).abs() < 1e-12);
            m.check().unwrap();
        }
    }

    #[test]
    fn disk_triangles_are_roughly_equilateral() {
        let m = disk(1.0, 8);
        for f in m.faces() {
            let [a, b, c] = m.face(f);
            let l = [
                m.rest_length(a, b),
                m.rest_length(b, c),
                m.rest_length(c, a),
            ];
            let (lo, hi) = (
                l.iter().cloned().fold(9.0, Real::min),
                l.iter().cloned().fold(0.0, Real::max),
            );
            assert!(hi / lo < 1.6, "face {f:?} edge lengths {l:?}");
        }
    }

    #[test]
    fn union_jack_is_conforming() {
        let m = union_jack(5, 4, 2.0, 1.0);
        assert_eq!(m.face_count(), 24);
        assert!((m.pattern_area() - 2.0).abs() < 1e-12);
        m.check().unwrap();
    }
}
