//! The obstacles against the cloth's triangles: an obstacle poking through a face between
//! vertices that are all outside it, which no vertex test sees. [`Obstacles::surface_penetration`]
//! measures it (what a user sees: `max_surface_penetration`).
//!
//! The deepest point of an obstacle inside a triangle, per shape:
//! - ground: a plane, so the lowest vertex (exact);
//! - sphere: the triangle's closest point to the centre (exact);
//! - cylinder and box: parry's convex contact (GJK/EPA): the smallest translation that separates
//!   the triangle from the solid, so a rim or a box edge or corner through a face is found;
//! - mesh: each obstacle vertex near the triangle is followed along its outward pseudo-normal to
//!   the triangle's plane; where that meets the triangle, the vertex's signed distance across
//!   the plane is how far the cloth lies above (positive) or below (negative) the obstacle there. Mesh edges
//!   crossing a face between mesh vertices are not seen (the bunny's vertices are 1 to 2 cm
//!   apart, its surface smooth at that scale).

use super::shape::{Geometry, Solid};
use super::Obstacles;
use crate::math::{Real, Vec3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{Shape, TriMesh, Triangle};

/// Below this length (m) an offset gives no direction.
const DEGENERATE_LENGTH: Real = 1e-12;

/// Where an obstacle comes closest to (or deepest into) a cloth triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TriangleContact {
    /// The point of the cloth triangle (m).
    pub point: Vector,
    /// Outward unit normal of the obstacle there: the direction to move the triangle out along.
    pub normal: Vector,
    /// Signed distance from the obstacle's surface to the triangle along `normal` (m); negative
    /// when the obstacle pokes through the triangle by that much.
    pub distance: Real,
}

impl Solid {
    /// The deepest (or closest) contact of this obstacle with the triangle `tri` (world, m), when
    /// its signed distance is below `band` (m); `None` otherwise.
    pub(crate) fn triangle_contact(&self, tri: [Vector; 3], band: Real) -> Option<TriangleContact> {
        let contact = match self.geometry() {
            Geometry::Ground(_) => {
                let h = self.pose().translation.z;
                let low = tri
                    .into_iter()
                    .min_by(|p, q| p.z.total_cmp(&q.z))
                    .expect("three vertices");
                TriangleContact {
                    point: low,
                    normal: Vector::Z,
                    distance: low.z - h,
                }
            }
            Geometry::Ball(ball) => {
                let centre = self.pose().translation;
                let t = Triangle::new(tri[0], tri[1], tri[2]);
                let q = t.project_local_point(centre, false).point;
                let offset = q - centre;
                let length = offset.length();
                let normal = if length > DEGENERATE_LENGTH {
                    offset / length
                } else {
                    t.normal().unwrap_or(Vector::Z)
                };
                TriangleContact {
                    point: q,
                    normal,
                    distance: length - ball.radius,
                }
            }
            Geometry::Cylinder(s) => convex_contact(self.pose(), s, tri, band)?,
            Geometry::Cuboid(s) => convex_contact(self.pose(), s, tri, band)?,
            Geometry::Mesh(m) => mesh_contact(self, m, tri, band)?,
        };
        (contact.distance < band).then_some(contact)
    }
}

/// parry's contact between the triangle and a convex solid at `pose`.
fn convex_contact(
    pose: &Pose,
    solid: &dyn Shape,
    tri: [Vector; 3],
    band: Real,
) -> Option<TriangleContact> {
    let t = Triangle::new(tri[0], tri[1], tri[2]);
    let c = parry3d_f64::query::contact(&Pose::identity(), &t, pose, solid, band).ok()??;
    Some(TriangleContact {
        point: c.point1,
        normal: -c.normal1,
        distance: c.dist,
    })
}

/// The deepest mesh vertex under the triangle, followed along its outward pseudo-normal; vertices
/// more than the triangle's longest edge below it are not looked at, and a vertex counts as
/// through the triangle only when the triangle's point on its normal line is inside the solid (a
/// vertex on the far side of the mesh meets the triangle from behind, through the solid, with
/// the triangle's point outside).
fn mesh_contact(
    solid: &Solid,
    mesh: &TriMesh,
    tri: [Vector; 3],
    band: Real,
) -> Option<TriangleContact> {
    let normals = mesh.pseudo_normals()?;
    let [a, b, c] = tri;
    let n = (b - a).cross(c - a);
    let area2 = n.length();
    if area2 <= DEGENERATE_LENGTH * DEGENERATE_LENGTH {
        return None;
    }
    let reach = (b - a).length().max((c - b).length()).max((a - c).length());
    let pad = Vector::splat(reach.max(band));
    let aabb = Aabb::new(a.min(b).min(c) - pad, a.max(b).max(c) + pad);
    let unit = n / area2;
    let vertices = mesh.vertices();
    let mut best: Option<TriangleContact> = None;
    for part in mesh.bvh().intersect_aabb(&aabb) {
        for &vi in &mesh.indices()[part as usize] {
            let p = vertices[vi as usize];
            let Some(np) = normals.vertices_pseudo_normal[vi as usize].try_normalize() else {
                continue;
            };
            let facing = np.dot(unit);
            if facing.abs() <= 1e-9 {
                continue;
            }
            // Along the normal line to the plane, then measured across the plane: how far the
            // triangle lies above (positive) or below the vertex.
            let s = (a - p).dot(unit) / facing;
            let distance = s * facing.abs();
            if distance >= band || s < -reach || best.is_some_and(|best| distance >= best.distance)
            {
                continue;
            }
            let r = p + np * s;
            if inside_triangle(r, tri, n) && (s >= 0.0 || solid.depth(r) > 0.0) {
                best = Some(TriangleContact {
                    point: r,
                    normal: unit * facing.signum(),
                    distance,
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

impl Obstacles {
    /// The deepest point of any obstacle inside the cloth surface (m): over the triangles `faces`
    /// (vertex indices into `x`, world positions in m) and the obstacles whose bounding box meets
    /// a triangle's, the largest depth by which an obstacle pokes through a triangle; 0 when none
    /// does. Unlike the vertex figure, it sees obstacles through faces between outside vertices.
    pub fn surface_penetration(
        &self,
        x: &[Vec3],
        faces: impl IntoIterator<Item = [usize; 3]>,
    ) -> Real {
        let mut deepest: Real = 0.0;
        for f in faces {
            let tri = f.map(|i| super::shape::to_glam(x[i]));
            let lo = tri[0].min(tri[1]).min(tri[2]);
            let hi = tri[0].max(tri[1]).max(tri[2]);
            for ob in &self.obstacles {
                if !ob.overlaps(lo, hi, 0.0) {
                    continue;
                }
                if let Some(c) = ob.triangle_contact(tri, 0.0) {
                    deepest = deepest.max(-c.distance);
                }
            }
        }
        deepest
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::{Obstacle, ObstacleShape};

    fn obstacles(shape: ObstacleShape) -> Obstacles {
        crate::testing::obstacles(&[Obstacle::new(shape)])
    }

    fn v(x: Real, y: Real, z: Real) -> Vec3 {
        Vec3::new(x, y, z)
    }

    /// The depth through one triangle.
    fn depth(obs: &Obstacles, tri: [Vec3; 3]) -> Real {
        obs.surface_penetration(&tri, [[0, 1, 2]])
    }

    /// The unit cube's surface as an outward-oriented OBJ mesh, centred at the origin.
    fn cube_mesh(dir: &std::path::Path) -> ObstacleShape {
        let file = dir.join("cube.obj");
        let mut text = String::new();
        for k in 0..8 {
            let c = |bit: usize| if k & bit != 0 { 1.0 } else { -1.0 };
            text += &format!("v {} {} {}\n", c(1), c(2), c(4));
        }
        for f in [
            [1, 3, 4],
            [1, 4, 2],
            [5, 6, 8],
            [5, 8, 7],
            [1, 2, 6],
            [1, 6, 5],
            [3, 7, 8],
            [3, 8, 4],
            [1, 5, 7],
            [1, 7, 3],
            [2, 4, 8],
            [2, 8, 6],
        ] {
            text += &format!("f {} {} {}\n", f[0], f[1], f[2]);
        }
        std::fs::write(&file, text).unwrap();
        ObstacleShape::Mesh {
            file,
            scale: 1.0,
            translation: [0.0; 3],
        }
    }

    /// A triangle at height `z` whose vertices are all outside the cube [-1, 1]^3 but whose
    /// middle crosses the vertical edge x = y = 1 (the corner region x + y >= 1.7 is inside).
    fn over_the_corner(z: Real) -> [Vec3; 3] {
        [v(0.2, 1.5, z), v(1.5, 0.2, z), v(1.5, 1.5, z)]
    }

    #[test]
    fn a_sphere_through_a_face_between_outside_vertices_is_measured_exactly() {
        let obs = obstacles(ObstacleShape::Sphere {
            center: [0.0, 0.0, 0.0],
            radius: 1.0,
        });
        // A wide triangle in the plane z = 0.9: its vertices are far outside the sphere.
        let tri = [v(-3.0, -3.0, 0.9), v(3.0, -3.0, 0.9), v(0.0, 3.0, 0.9)];
        assert!(tri.iter().all(|&p| obs.penetration(p) == 0.0));
        assert!((depth(&obs, tri) - 0.1).abs() < 1e-12);
        let above = tri.map(|p| p + v(0.0, 0.0, 0.2));
        assert_eq!(depth(&obs, above), 0.0);
    }

    #[test]
    fn a_box_corner_and_a_cylinder_rim_through_a_face_are_measured() {
        let cube = obstacles(ObstacleShape::Box {
            center: [0.0; 3],
            half_extents: [1.0; 3],
        });
        let tri = over_the_corner(0.9);
        assert!(tri.iter().all(|&p| cube.penetration(p) == 0.0));
        assert!(
            (depth(&cube, tri) - 0.1).abs() < 1e-6,
            "{}",
            depth(&cube, tri)
        );
        assert_eq!(depth(&cube, over_the_corner(1.1)), 0.0);
        // A table top of radius 1 and height 2 (top at z = 1); a triangle at z = 0.95 across
        // its rim, vertices outside.
        let table = obstacles(ObstacleShape::Cylinder {
            center: [0.0; 3],
            radius: 1.0,
            height: 2.0,
        });
        let tri = [v(0.8, -1.0, 0.95), v(1.5, 0.0, 0.95), v(0.8, 1.0, 0.95)];
        assert!(tri.iter().all(|&p| table.penetration(p) == 0.0));
        assert!(
            (depth(&table, tri) - 0.05).abs() < 1e-6,
            "{}",
            depth(&table, tri)
        );
    }

    #[test]
    fn a_mesh_vertex_through_a_face_is_measured_and_the_far_side_is_not() {
        let dir = tempfile::tempdir().unwrap();
        let cube = obstacles(cube_mesh(dir.path()));
        let tri = over_the_corner(0.9);
        assert!(tri.iter().all(|&p| cube.penetration(p) == 0.0));
        assert!(
            (depth(&cube, tri) - 0.1).abs() < 1e-9,
            "{}",
            depth(&cube, tri)
        );
        // Above the cube: the bottom corners' normals meet the triangle through the solid, from
        // behind; they must not count.
        let big = [v(-3.0, -3.0, 1.5), v(3.0, -3.0, 1.5), v(0.0, 3.0, 1.5)];
        assert_eq!(depth(&cube, big), 0.0);
        // The ground: the lowest vertex.
        let ground = obstacles(ObstacleShape::Ground { height: 0.0 });
        assert!(
            (depth(
                &ground,
                [v(0.0, 0.0, -0.2), v(1.0, 0.0, 0.3), v(0.0, 1.0, 1.0)]
            ) - 0.2)
                .abs()
                < 1e-12
        );
    }
}
