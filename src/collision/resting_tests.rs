//! Unit tests of the resting contacts handed to the implicit solve: which vertices a face
//! contact holds (`FACE_HOLD_EXCESS`).

use super::*;
use crate::math::Vec3;
use std::collections::BTreeSet;

/// Obstacles with the 2 mm margin (band 3 mm) and face contact.
fn build(shape: ObstacleShape) -> Obstacles {
    let params = ContactParams {
        margin: 2e-3,
        restitution: 0.0,
        faces: true,
    };
    Obstacles::build(&[Obstacle::new(shape)], &params).expect("valid obstacle")
}

/// The slots `resting` finds for the triangle `x` at rest (every vertex free).
fn resting_slots(obstacles: &Obstacles, x: [Vec3; 3]) -> BTreeSet<usize> {
    let mut found = BTreeSet::new();
    let v = [Vec3::zeros(); 3];
    obstacles.resting(&x, &v, &[1.0; 3], Some(&[[0, 1, 2]]), |slot, _, _| {
        found.insert(slot);
    });
    found
}

/// A point `height` (m) above the unit sphere at the origin, in the direction `(a, b, 1)`.
fn above_sphere(a: Real, b: Real, height: Real) -> Vec3 {
    Vec3::new(a, b, 1.0).normalize() * (1.0 + height)
}

#[test]
fn a_face_on_a_smooth_sphere_holds_no_vertex_its_own_distance_leaves_free() {
    let sphere = build(ObstacleShape::Sphere {
        center: [0.0, 0.0, 0.0],
        radius: 1.0,
    });
    // Vertices 3.5 mm above the sphere (outside the 3 mm band), the face's middle about 1.7 mm
    // closer (its sagitta): a face contact, but the vertices' own distances explain it.
    let small = [
        above_sphere(0.06, 0.0, 3.5e-3),
        above_sphere(-0.03, 0.05, 3.5e-3),
        above_sphere(-0.03, -0.05, 3.5e-3),
    ];
    let tri = small.map(|p| parry3d_f64::math::Vector::new(p.x, p.y, p.z));
    let contact = sphere.obstacles[0]
        .triangle_contact(tri, 3e-3)
        .expect("the face is within the band");
    assert!(contact.distance < 2.5e-3, "{}", contact.distance);
    assert!(resting_slots(&sphere, small).is_empty());
    // A coarse face, its sagitta (about 12 mm) far above the margin, rests on the sphere
    // between its vertices: it holds them.
    let coarse = [
        above_sphere(0.2, 0.0, 12e-3),
        above_sphere(-0.1, 0.17, 12e-3),
        above_sphere(-0.1, -0.17, 12e-3),
    ];
    assert_eq!(resting_slots(&sphere, coarse), BTreeSet::from([0, 1, 2]));
}

#[test]
fn a_face_across_a_box_edge_holds_its_vertices() {
    // The plate of the stability suite; the face passes 2.2 mm over its edge at x = 0.2 m, its
    // vertices 19 mm and 105 mm away.
    let plate = build(ObstacleShape::Box {
        center: [0.0, 0.0, 0.0],
        half_extents: [0.2, 0.2, 0.001],
    });
    let x = [
        Vec3::new(0.15, -0.05, 0.02),
        Vec3::new(0.15, 0.05, 0.02),
        Vec3::new(0.3, 0.0, -0.03),
    ];
    assert_eq!(resting_slots(&plate, x), BTreeSet::from([0, 1, 2]));
}
