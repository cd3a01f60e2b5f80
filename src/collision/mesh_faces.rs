//! A cloth triangle against a mesh obstacle: the tip test and the sunk-face samples of
//! [`super::faces`]'s mesh case, and the obstacle's per-vertex data they read.
//!
//! The tip test follows each obstacle vertex near the triangle along its unit pseudo-normal to
//! the triangle's plane. Those normals are taken once, when the obstacle is built
//! ([`MeshObstacle::new`]), and each query looks at a mesh vertex once, however many of the
//! triangles the tree returns share it (a vertex of a closed mesh belongs to about six): a vertex
//! seen again could not change the answer, since its distance is the same and only a strictly
//! smaller one replaces the best.

use super::faces::{bounds, TriangleContact, DEGENERATE_LENGTH};
use super::shape::Solid;
use crate::math::Real;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector;
use parry3d_f64::shape::TriMesh;
use std::cell::RefCell;

/// A mesh obstacle: parry's triangle mesh and its vertices' unit pseudo-normals.
#[derive(Clone)]
pub(crate) struct MeshObstacle {
    /// The mesh, vertices in the obstacle's own frame (m).
    pub shape: TriMesh,
    /// Per vertex, its pseudo-normal normalised (`None` where it has no direction); `None` when
    /// the mesh has no pseudo-normals (the tip test then finds nothing).
    unit_normals: Option<Vec<Option<Vector>>>,
}

impl MeshObstacle {
    /// The obstacle of `shape`, its unit pseudo-normals taken once.
    pub fn new(shape: TriMesh) -> Self {
        let unit_normals = shape.pseudo_normals().map(|normals| {
            normals
                .vertices_pseudo_normal
                .iter()
                .map(|n| n.try_normalize())
                .collect()
        });
        MeshObstacle {
            shape,
            unit_normals,
        }
    }
}

/// Marks of the mesh vertices one query has looked at: vertex `i` was seen when `mark[i]` is
/// the current `stamp` (a new stamp per query, so nothing is cleared between queries).
#[derive(Default)]
struct Seen {
    mark: Vec<u32>,
    stamp: u32,
}

impl Seen {
    /// Starts a query over `vertices` mesh vertices: none seen yet.
    fn start(&mut self, vertices: usize) {
        if self.mark.len() < vertices {
            self.mark.resize(vertices, 0);
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.mark.fill(0);
            self.stamp = 1;
        }
    }

    /// True the first time `i` is asked about in this query.
    fn first(&mut self, i: usize) -> bool {
        let fresh = self.mark[i] != self.stamp;
        self.mark[i] = self.stamp;
        fresh
    }
}

thread_local! {
    /// Each thread's marks (queries run on any thread of the pool, one at a time per thread).
    static SEEN: RefCell<Seen> = RefCell::default();
}

/// The deepest mesh vertex under the triangle, followed along its outward pseudo-normal; vertices
/// more than the triangle's longest edge below it are not looked at, and a vertex counts as
/// through the triangle only when the triangle's point on its normal line is inside the solid (a
/// vertex on the far side of the mesh meets the triangle from behind, through the solid, with
/// the triangle's point outside). Worked in the mesh's own frame (a moving mesh's triangle is
/// brought there, the contact taken back).
pub(super) fn mesh_contact(
    solid: &Solid,
    mesh: &MeshObstacle,
    tri: [Vector; 3],
    band: Real,
) -> Option<TriangleContact> {
    let normals = mesh.unit_normals.as_ref()?;
    let tri = tri.map(|p| solid.mesh_point(p));
    let [a, b, c] = tri;
    let n = (b - a).cross(c - a);
    let area2 = n.length();
    if area2 <= DEGENERATE_LENGTH * DEGENERATE_LENGTH {
        return None;
    }
    let reach = (b - a).length().max((c - b).length()).max((a - c).length());
    let pad = Vector::splat(reach.max(band));
    let (lo, hi) = bounds(tri);
    let aabb = Aabb::new(lo - pad, hi + pad);
    let unit = n / area2;
    let vertices = mesh.shape.vertices();
    let mut best: Option<TriangleContact> = None;
    SEEN.with_borrow_mut(|seen| {
        seen.start(vertices.len());
        for part in mesh.shape.bvh().intersect_aabb(&aabb) {
            for &vi in &mesh.shape.indices()[part as usize] {
                let vi = vi as usize;
                if !seen.first(vi) {
                    continue;
                }
                let Some(np) = normals[vi] else {
                    continue;
                };
                let p = vertices[vi];
                let facing = np.dot(unit);
                if facing.abs() <= 1e-9 {
                    continue;
                }
                // Along the normal line to the plane, then measured across the plane: how far
                // the triangle lies above (positive) or below the vertex.
                let s = (a - p).dot(unit) / facing;
                let distance = s * facing.abs();
                if distance >= band
                    || s < -reach
                    || best.is_some_and(|best| distance >= best.distance)
                {
                    continue;
                }
                let r = p + np * s;
                if inside_triangle(r, tri, n)
                    && (s >= 0.0 || solid.depth(solid.world_point(r)) > 0.0)
                {
                    best = Some(TriangleContact {
                        point: r,
                        normal: unit * facing.signum(),
                        distance,
                    });
                }
            }
        }
    });
    best.map(|c| TriangleContact {
        point: solid.world_point(c.point),
        normal: solid.world_vector(c.normal),
        ..c
    })
}

/// The deepest of the triangle's ten points at barycentric thirds (world, m) whose signed
/// distance to the mesh is below `band` (m), with its projection's outward normal; `None` when
/// none is.
pub(super) fn mesh_sample_contact(
    solid: &Solid,
    tri: [Vector; 3],
    band: Real,
) -> Option<TriangleContact> {
    const THIRDS: usize = 3;
    let mut best: Option<TriangleContact> = None;
    for i in 0..=THIRDS {
        for j in 0..=THIRDS - i {
            let k = THIRDS - i - j;
            let p = (tri[0] * i as Real + tri[1] * j as Real + tri[2] * k as Real) / THIRDS as Real;
            let Some(proj) = solid.project_near(p, band) else {
                continue;
            };
            if best.is_none_or(|best| proj.distance < best.distance) {
                best = Some(TriangleContact {
                    point: p,
                    normal: proj.normal,
                    distance: proj.distance,
                });
            }
        }
    }
    best
}

/// Whether `r`, in the plane of `tri` (normal `n`, unnormalised), lies in the closed triangle.
fn inside_triangle(r: Vector, tri: [Vector; 3], n: Vector) -> bool {
    (0..3).all(|k| {
        let (p, q) = (tri[k], tri[(k + 1) % 3]);
        (q - p).cross(r - p).dot(n) >= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::shape::Geometry;
    use crate::collision::{Obstacle, ObstacleShape, Obstacles};
    use proptest::prelude::*;
    use std::sync::OnceLock;

    /// The bunny as the scenes load it.
    fn bunny() -> &'static Obstacles {
        static BUNNY: OnceLock<Obstacles> = OnceLock::new();
        BUNNY.get_or_init(|| {
            crate::testing::obstacles(&[Obstacle::new(ObstacleShape::Mesh {
                file: std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                    .join("scenes/meshes/bunny.obj"),
                scale: 1.0,
                translation: [0.0; 3],
            })])
        })
    }

    /// The corners of the mesh's bounding box (m).
    fn extent(mesh: &MeshObstacle) -> (Vector, Vector) {
        let v = mesh.shape.vertices();
        let lo = v
            .iter()
            .fold(Vector::splat(Real::INFINITY), |m, &p| m.min(p));
        let hi = v
            .iter()
            .fold(Vector::splat(Real::NEG_INFINITY), |m, &p| m.max(p));
        (lo, hi)
    }

    /// The tip test as it was written first: every vertex of every triangle the tree returns,
    /// its pseudo-normal normalised at each visit.
    fn every_visit(solid: &Solid, tri: [Vector; 3], band: Real) -> Option<TriangleContact> {
        let Geometry::Mesh(mesh) = solid.geometry() else {
            panic!("a mesh obstacle")
        };
        let mesh = &mesh.shape;
        let normals = mesh.pseudo_normals()?;
        let tri = tri.map(|p| solid.mesh_point(p));
        let [a, b, c] = tri;
        let n = (b - a).cross(c - a);
        let area2 = n.length();
        if area2 <= DEGENERATE_LENGTH * DEGENERATE_LENGTH {
            return None;
        }
        let reach = (b - a).length().max((c - b).length()).max((a - c).length());
        let pad = Vector::splat(reach.max(band));
        let (lo, hi) = bounds(tri);
        let unit = n / area2;
        let mut best: Option<TriangleContact> = None;
        for part in mesh.bvh().intersect_aabb(&Aabb::new(lo - pad, hi + pad)) {
            for &vi in &mesh.indices()[part as usize] {
                let p = mesh.vertices()[vi as usize];
                let Some(np) = normals.vertices_pseudo_normal[vi as usize].try_normalize() else {
                    continue;
                };
                let facing = np.dot(unit);
                if facing.abs() <= 1e-9 {
                    continue;
                }
                let s = (a - p).dot(unit) / facing;
                let distance = s * facing.abs();
                if distance >= band
                    || s < -reach
                    || best.is_some_and(|best| distance >= best.distance)
                {
                    continue;
                }
                let r = p + np * s;
                if inside_triangle(r, tri, n)
                    && (s >= 0.0 || solid.depth(solid.world_point(r)) > 0.0)
                {
                    best = Some(TriangleContact {
                        point: r,
                        normal: unit * facing.signum(),
                        distance,
                    });
                }
            }
        }
        best.map(|c| TriangleContact {
            point: solid.world_point(c.point),
            normal: solid.world_vector(c.normal),
            ..c
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// Each vertex looked at once, its normal taken once: the same contact, bit for bit, as
        /// every visit with the normal normalised each time, over triangles of 1 mm to 30 cm in
        /// and around the bunny, queried one after the other (the marks of one query must not
        /// hide a vertex from the next).
        #[test]
        fn looking_at_each_vertex_once_finds_the_same_contact(
            queries in prop::collection::vec(
                (prop::array::uniform3(prop::array::uniform3(-0.15..0.15f64)),
                 prop::array::uniform3(-1.0..1.0f64), 0.001..0.3f64, 0.0..0.05f64),
                1..6,
            )
        ) {
            let solid = &bunny().obstacles[0];
            let Geometry::Mesh(mesh) = solid.geometry() else { panic!("a mesh obstacle") };
            let (lo, hi) = extent(mesh);
            for (corners, centre, size, band) in queries {
                let middle = (lo + hi) * 0.5 + (hi - lo) * 0.6 * Vector::from(centre);
                let tri = corners.map(|c| middle + Vector::from(c) * (size / 0.15));
                let once = mesh_contact(solid, mesh, tri, band);
                prop_assert_eq!(once, every_visit(solid, tri, band));
            }
        }
    }

    #[test]
    fn a_triangle_through_the_bunny_finds_a_contact() {
        let solid = &bunny().obstacles[0];
        let Geometry::Mesh(mesh) = solid.geometry() else {
            panic!("a mesh obstacle")
        };
        let (lo, hi) = extent(mesh);
        let middle = (lo + hi) * 0.5;
        let tri = [
            middle + Vector::new(-0.3, -0.3, 0.0),
            middle + Vector::new(0.3, -0.3, 0.0),
            middle + Vector::new(0.0, 0.3, 0.0),
        ];
        let contact = mesh_contact(solid, mesh, tri, 0.01).expect("the bunny pokes through");
        assert!(contact.distance < 0.0, "{contact:?}");
        assert_eq!(Some(contact), every_visit(solid, tri, 0.01));
    }
}
