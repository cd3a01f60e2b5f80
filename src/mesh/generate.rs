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

/// A disk of the given radius (m) centred on `(radius, radius)` with `rings` rings.
pub fn disk(radius: Real, rings: usize) -> Mesh {
    let _ = (radius, rings);
    todo!()
}
