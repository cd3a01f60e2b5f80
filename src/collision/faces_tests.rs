//! Tests of the obstacles against the cloth's triangles (`faces.rs`).

use super::*;
use crate::collision::{Obstacle, ObstacleShape};
use parry3d_f64::shape::Segment;

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
fn the_distance_from_the_origin_to_a_plane_triangle() {
    let d = |tri| distance_to_origin_2d(tri).0;
    assert_eq!(d([[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]]), 0.0);
    assert!((d([[2.0, -1.0], [2.0, 1.0], [3.0, 0.0]]) - 2.0).abs() < 1e-12);
    assert!((d([[1.0, 1.0], [2.0, 1.0], [1.0, 2.0]]) - 2.0_f64.sqrt()).abs() < 1e-12);
    // Degenerate: a segment (the plane image of a vertical face).
    assert!((d([[1.0, -1.0], [1.0, 1.0], [1.0, 1.0]]) - 1.0).abs() < 1e-12);
}

/// The cylinder's culls never hide a contact parry's GJK finds, and its side contacts in
/// closed form are GJK's: over triangles scattered around the table's side, rim and cap (some
/// crossing the axis), every triangle called clear has no contact nearer than the band but at
/// a vertex, and every closed-form contact has GJK's distance and normal.
#[test]
fn the_cylinder_cull_hides_no_contact() {
    let obs = obstacles(ObstacleShape::Cylinder {
        center: [0.0, 0.0, 0.25],
        radius: 0.3,
        height: 0.5,
    });
    let solid = &obs.obstacles[0];
    let Geometry::Cylinder(shape) = solid.geometry() else {
        unreachable!()
    };
    let mut next = crate::testing::uniform(12345);
    let (mut culled, mut kept, mut closed_form) = (0, 0, 0);
    for _ in 0..4000 {
        let centre = Vector::new(0.7 * next() - 0.35, 0.7 * next() - 0.35, 0.7 * next());
        let size = 0.01 + 0.2 * next();
        let tri = [0, 1, 2]
            .map(|_| centre + Vector::new(next() - 0.5, next() - 0.5, next() - 0.5) * size);
        let band = 0.004;
        if let Some(side) = cylinder_side_contact(solid.pose(), 0.3, 0.25, tri) {
            closed_form += 1;
            let gjk = convex_contact(solid.pose(), shape, tri, 1.0).unwrap();
            assert!(
                (side.distance - gjk.distance).abs() < 1e-7,
                "{side:?} {gjk:?}"
            );
            assert!(side.normal.dot(gjk.normal) > 1.0 - 1e-6, "{side:?} {gjk:?}");
            // Its point is on the triangle, as far from the axis as the distance says.
            let axis_offset = side.point.x.hypot(side.point.y);
            assert!((axis_offset - 0.3 - side.distance).abs() < 1e-9, "{side:?}");
            let w = barycentric(side.point, tri);
            let back: Vector = (0..3).map(|k| tri[k] * w[k]).sum();
            assert!((back - side.point).length() < 1e-9, "{side:?}");
        }
        if solid.triangle_clear(tri, band) {
            culled += 1;
            let c = convex_contact(solid.pose(), shape, tri, band);
            // Clear means no contact but at a vertex (the vertex pass's).
            let at_vertex =
                |c: &TriangleContact| tri.iter().any(|&p| (p - c.point).length() < 1e-9);
            assert!(
                c.is_none_or(|c| c.distance >= band - 1e-9 || at_vertex(&c)),
                "{tri:?}: {c:?}"
            );
        } else {
            kept += 1;
        }
    }
    assert!(culled > 500 && kept > 500, "{culled} culled, {kept} kept");
    assert!(
        closed_form > 200,
        "{closed_form} side contacts in closed form"
    );
}

/// A random segment about a random point of the box of half-width `half` (m) about `middle`,
/// its ends within `reach` times `half` of that point along each axis.
fn random_segment(
    next: &mut impl FnMut() -> Real,
    middle: Vector,
    half: Real,
    reach: Real,
) -> (Vector, Vector) {
    let centre = middle + Vector::new(next() - 0.5, next() - 0.5, next() - 0.5) * 2.0 * half;
    let size = (0.01 + reach * next()) * half;
    let p = centre + Vector::new(next() - 0.5, next() - 0.5, next() - 0.5) * size;
    let q = centre + Vector::new(next() - 0.5, next() - 0.5, next() - 0.5) * size;
    (p, q)
}

/// The criteria's edge query skips a cylinder only where the segment is surely clear of it: a
/// skipped segment has no contact closer than the band, at its ends included. (A mesh's branch
/// is the faces' cull, by the distance grid's lower bound.)
#[test]
fn the_segment_cull_hides_no_contact() {
    // The shape with the half-width of the box its segments are drawn in, about its centre.
    let shapes = [(
        ObstacleShape::Cylinder {
            center: [0.0, 0.0, 0.25],
            radius: 0.3,
            height: 0.5,
        },
        Vector::new(0.0, 0.0, 0.25),
        0.5,
    )];
    let mut next = crate::testing::uniform(4242);
    for (shape, middle, half) in shapes {
        let obs = obstacles(shape);
        let solid = &obs.obstacles[0];
        let (mut culled, mut kept) = (0, 0);
        for _ in 0..4000 {
            let (p, q) = random_segment(&mut next, middle, half, 0.3);
            let band = 0.004 + 0.05 * next();
            if solid.hull_clear([p, q, q], band) {
                culled += 1;
                let c = parry3d_f64::query::contact(
                    &Pose::identity(),
                    &Segment::new(p, q),
                    solid.pose(),
                    solid.shape(),
                    band,
                )
                .unwrap();
                assert!(c.is_none_or(|c| c.dist >= band - 1e-9), "{p} {q}: {c:?}");
            } else {
                kept += 1;
            }
        }
        assert!(culled > 300 && kept > 300, "{culled} culled, {kept} kept");
    }
}

/// The criteria's edge query in closed form ([`Solid::segment_closest`]: a cylinder's side, a
/// cap's or a box face's flat region, a sphere) agrees with parry's contact, distance and
/// obstacle normal at the point, and answers most segments near a round table, a box and a
/// sphere.
#[test]
fn the_closed_form_segment_contact_agrees_with_gjk() {
    let shapes = [
        (
            ObstacleShape::Cylinder {
                center: [0.0, 0.0, 0.375],
                radius: 0.35,
                height: 0.75,
            },
            Vector::new(0.0, 0.0, 0.375),
            0.6,
        ),
        (
            ObstacleShape::Box {
                center: [0.1, -0.2, 0.3],
                half_extents: [0.3, 0.2, 0.25],
            },
            Vector::new(0.1, -0.2, 0.3),
            0.5,
        ),
        (
            ObstacleShape::Sphere {
                center: [0.0, 0.1, 0.0],
                radius: 0.25,
            },
            Vector::new(0.0, 0.1, 0.0),
            0.4,
        ),
    ];
    let mut next = crate::testing::uniform(777);
    for (shape, middle, half) in shapes {
        let obs = obstacles(shape);
        let solid = &obs.obstacles[0];
        let (mut closed, mut regions) = (0, 0);
        for _ in 0..4000 {
            let (p, q) = random_segment(&mut next, middle, half, 0.2);
            let Some((distance, point)) = solid.segment_closest(p, q) else {
                continue;
            };
            closed += 1;
            regions += usize::from(
                solid.flat_region(p).is_some() || matches!(solid.geometry(), Geometry::Ball(_)),
            );
            let gjk = parry3d_f64::query::contact(
                &Pose::identity(),
                &Segment::new(p, q),
                solid.pose(),
                solid.shape(),
                10.0,
            )
            .unwrap()
            .expect("within 10 m");
            // GJK stops within about 1e-8 m; the closed form is exact.
            assert!(
                (distance - gjk.dist).abs() < 1e-7,
                "{p} {q}: {distance} {gjk:?}"
            );
            let (ours, theirs) = (solid.project(point), solid.project(gjk.point1));
            assert!(
                ours.normal.dot(theirs.normal) > 1.0 - 1e-6,
                "{p} {q}: {ours:?} {theirs:?}"
            );
            // The point is on the segment.
            let t = (point - p).dot(q - p) / (q - p).length_squared().max(1e-300);
            assert!((p + (q - p) * t.clamp(0.0, 1.0) - point).length() < 1e-9);
        }
        assert!(
            closed > 1000 && regions > 300,
            "{closed} closed, {regions} in flat regions"
        );
    }
}

/// A wide face through a frictionless sphere, its centroid over the centre: the pass lifts
/// the contact point to the margin in one move, removes its inward velocity and changes the
/// momentum only along the normal. With a vertex pinned, that vertex never moves and the
/// sphere still ends outside the face.
#[test]
fn a_face_through_a_sphere_is_pushed_to_the_margin_by_barycentric_impulses() {
    let shape = ObstacleShape::Sphere {
        center: [0.0, 0.0, 0.0],
        radius: 1.0,
    };
    let params = crate::collision::ContactParams {
        faces: true,
        ..Default::default()
    };
    let obs = Obstacles::build(&[Obstacle::new(shape)], &params).unwrap();
    let margin = obs.margin();
    let start = vec![v(-3.0, -3.0, 0.9), v(3.0, -3.0, 0.9), v(0.0, 6.0, 0.9)];
    let (mut x, mut vel) = (start.clone(), vec![v(0.3, 0.0, -1.0); 3]);
    let stats = crate::testing::respond_one_face(&obs, None, &mut x, &mut vel, [1.0; 3]);
    assert_eq!(stats.contacts, 1, "{stats:?}");
    for k in 0..3 {
        assert!((x[k] - start[k] - v(0.0, 0.0, 0.1 + margin)).norm() < 1e-12);
        // Momentum (unit masses) changed along the normal only, by the removed speed.
        assert!((vel[k] - v(0.3, 0.0, 0.0)).norm() < 1e-12, "{}", vel[k]);
    }
    assert_eq!(depth(&obs, [x[0], x[1], x[2]]), 0.0);

    let (mut x, mut vel) = (start.clone(), vec![v(0.3, 0.0, -1.0); 3]);
    crate::testing::respond_one_face(&obs, None, &mut x, &mut vel, [1.0, 2.0, 0.0]);
    assert_eq!((x[2], vel[2]), (start[2], v(0.3, 0.0, -1.0)));
    assert_eq!(depth(&obs, [x[0], x[1], x[2]]), 0.0);
}

/// With face contact an edge resting within the margin band on a sphere meets it (the
/// criteria's collision test); with vertex contact only a crossing counts.
#[test]
fn an_edge_resting_on_a_sphere_meets_it_only_with_face_contact() {
    let sphere = [Obstacle::new(ObstacleShape::Sphere {
        center: [0.0, 0.0, 0.0],
        radius: 1.0,
    })];
    let build = |faces: bool| {
        let params = crate::collision::ContactParams {
            faces,
            ..Default::default()
        };
        Obstacles::build(&sphere, &params).unwrap()
    };
    let (a, b) = (v(-0.5, 0.0, 1.001), v(0.5, 0.0, 1.001));
    assert_eq!(build(false).edge_hit(a, b), None);
    let hit = build(true)
        .edge_hit(a, b)
        .expect("the edge rests on the sphere");
    assert!(
        (hit.point - v(0.0, 0.0, 1.0)).norm() < 1e-9,
        "{}",
        hit.point
    );
    assert!((hit.normal - v(0.0, 0.0, 1.0)).norm() < 1e-9);
    // 1 cm above: clear in both modes.
    let lift = v(0.0, 0.0, 0.01);
    assert_eq!(build(true).edge_hit(a + lift, b + lift), None);
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

/// The swept face test: a wide face dropped 20 cm in one step over a 2 mm wall 20 cm tall, its
/// vertices passing on both sides of the wall, ends with the wall 15 cm through it. Pushed by
/// the shortest way out (no start positions), it goes on down the wall: it tunnelled.
/// Swept, it is moved back to just above the wall's top and loses its downward velocity.
#[test]
fn a_face_dropped_over_a_thin_wall_in_one_step_stays_above_it() {
    let obs = obstacles(ObstacleShape::Box {
        center: [0.0, 0.0, 0.1],
        half_extents: [0.001, 0.5, 0.1],
    });
    let margin = obs.margin();
    let start = vec![v(-0.3, 0.0, 0.25), v(0.3, -0.1, 0.25), v(0.3, 0.1, 0.25)];
    let end: Vec<Vec3> = start.iter().map(|p| p - v(0.0, 0.0, 0.2)).collect();
    let fall = vec![v(0.0, 0.0, -50.0); 3];

    let (mut x, mut vel) = (end.clone(), fall.clone());
    crate::testing::respond_one_face(&obs, None, &mut x, &mut vel, [1.0; 3]);
    assert!(
        x.iter().all(|p| p.z < 0.1),
        "without the swept test the face is pushed down the wall, past the way it came: {x:?}"
    );

    let (mut x, mut vel) = (end.clone(), fall);
    crate::testing::respond_one_face(&obs, Some(&start), &mut x, &mut vel, [1.0; 3]);
    assert!(depth(&obs, [x[0], x[1], x[2]]) <= margin, "{x:?}");
    for k in 0..3 {
        assert!(x[k].z > 0.2 && x[k].z < 0.21, "{}", x[k]);
        assert!(vel[k].z.abs() < 1e-12, "{}", vel[k]);
    }
}

/// A face across the cube's edge y = z = 1, its vertices outside and the cube's corners 0.7 m
/// away along the edge: no mesh vertex goes through it, so only the samples see it, never
/// deeper than the exact 0.2 m (at y = z = 0.8). The response pushes the face until no sample
/// is inside beyond the margin and takes its inward velocity; a sharp edge between the samples
/// stays partly through (the known limit: the exact depth only falls).
#[test]
fn a_mesh_edge_through_a_face_is_seen_by_the_samples_and_pushed_out() {
    let dir = tempfile::tempdir().unwrap();
    let cube = obstacles(cube_mesh(dir.path()));
    let tri = [v(-0.3, 1.3, 0.3), v(0.3, 1.3, 0.3), v(0.0, 0.3, 1.3)];
    assert!(tri.iter().all(|&p| cube.penetration(p) == 0.0));
    let solid = &cube.obstacles[0];
    let Geometry::Mesh(mesh) = solid.geometry() else {
        panic!("a mesh")
    };
    assert!(mesh_contact(solid, mesh, tri.map(to_glam), 0.0).is_none());
    let seen = depth(&cube, tri);
    assert!(seen > 0.0 && seen <= 0.2 + 1e-12, "{seen}");

    // The deepest point of the face inside the cube, on a fine barycentric grid.
    let exact_depth = |t: &[Vec3]| {
        let n = 200;
        let mut deepest: Real = 0.0;
        for i in 0..=n {
            for j in 0..=n - i {
                let (a, b) = (i as Real / n as Real, j as Real / n as Real);
                let p = t[0] * a + t[1] * b + t[2] * (1.0 - a - b);
                let inside = (1.0 - p.x.abs()).min(1.0 - p.y.abs()).min(1.0 - p.z.abs());
                deepest = deepest.max(inside);
            }
        }
        deepest
    };
    assert!((exact_depth(&tri) - 0.2).abs() < 1e-3);
    let (mut x, mut vel) = (tri.to_vec(), vec![v(0.0, -1.0, -1.0); 3]);
    crate::testing::respond_one_face(&cube, None, &mut x, &mut vel, [1.0; 3]);
    let left = depth(&cube, [x[0], x[1], x[2]]);
    assert!(left <= cube.margin(), "{left} m left at a sample: {x:?}");
    assert!(exact_depth(&x) < 0.2 - 0.02, "{}", exact_depth(&x));
    assert!(vel.iter().all(|w| w.y + w.z > -2.0 + 0.1), "{vel:?}");
}
