//! Unit tests of moving obstacles: poses and velocities of the motions, the swept test against a
//! moving solid, friction drag, and the queries on a moved mesh.

use super::*;
use std::f64::consts::PI;

fn v(x: Real, y: Real, z: Real) -> Vec3 {
    Vec3::new(x, y, z)
}

fn moving(shape: ObstacleShape, motion: ObstacleMotion, friction: Real) -> Obstacles {
    crate::testing::obstacles(&[Obstacle {
        friction,
        motion,
        ..Obstacle::new(shape)
    }])
}

/// Where the motion takes `p` at `t`.
fn place(m: &ObstacleMotion, t: Real, p: Vec3) -> Vec3 {
    to_na(m.pose(t).transform_point(to_glam(p)))
}

#[test]
fn keyframes_interpolate_linearly_and_hold_outside_their_times() {
    let m = ObstacleMotion::Keyframes {
        times: vec![1.0, 2.0, 4.0],
        positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 2.0, 0.0]],
        rotations: Vec::new(),
        pivot: [0.0; 3],
    };
    let origin = v(0.0, 0.0, 0.0);
    for (t, want) in [
        (0.0, v(0.0, 0.0, 0.0)),
        (1.5, v(0.5, 0.0, 0.0)),
        (3.0, v(1.0, 1.0, 0.0)),
        (9.0, v(1.0, 2.0, 0.0)),
    ] {
        assert!((place(&m, t, origin) - want).norm() < 1e-12, "t = {t}");
    }
    assert_eq!(m.velocity(1.5).linear, Vector::new(1.0, 0.0, 0.0));
    assert_eq!(m.velocity(3.0).linear, Vector::new(0.0, 1.0, 0.0));
    assert_eq!(m.velocity(0.5).linear, Vector::ZERO);
    assert_eq!(m.velocity(4.0).linear, Vector::ZERO);
    // The matrix form says the same.
    let [.., dx, dy, dz] = m.matrix(3.0);
    assert_eq!([dx, dy, dz], [1.0, 1.0, 0.0]);
}

#[test]
fn keyframe_rotations_turn_about_the_moving_pivot_at_a_constant_rate() {
    // A quarter turn about +z through the pivot (1, 0, 0) between t = 0 and 2 s, while the pivot
    // moves by (0, 0, 2).
    let m = ObstacleMotion::Keyframes {
        times: vec![0.0, 2.0],
        positions: vec![[0.0; 3], [0.0, 0.0, 2.0]],
        rotations: vec![[0.0; 3], [0.0, 0.0, PI / 2.0]],
        pivot: [1.0, 0.0, 0.0],
    };
    let p = v(2.0, 0.0, 0.0);
    assert!((place(&m, 2.0, p) - v(1.0, 1.0, 2.0)).norm() < 1e-12);
    // Half way: an eighth of a turn, half the offset.
    let h = (PI / 4.0).cos();
    assert!((place(&m, 1.0, p) - v(1.0 + h, h, 1.0)).norm() < 1e-12);
    // Held after the last keyframe, at rest.
    assert!((place(&m, 5.0, p) - v(1.0, 1.0, 2.0)).norm() < 1e-12);
    assert_eq!(m.velocity(5.0).at(to_glam(p)), Vector::ZERO);
    // The velocity field is the pose's time derivative at every point.
    for (t, q) in [(0.3, p), (1.2, v(-0.5, 2.0, 0.7)), (1.9, v(1.0, 0.0, 0.0))] {
        let dt = 1e-6;
        let numeric = (place(&m, t + dt, q) - place(&m, t - dt, q)) / (2.0 * dt);
        let moved = m.pose(t).transform_point(to_glam(q));
        let field = to_na(m.velocity(t).at(moved));
        assert!(
            (numeric - field).norm() < 1e-6,
            "t = {t}: {numeric} {field}"
        );
    }
}

#[test]
fn keyframe_rotations_take_the_short_way_between_keyframes() {
    // From +170 to -170 degrees about z: 20 degrees through 180, not 340 back through 0.
    let deg = PI / 180.0;
    let m = ObstacleMotion::Keyframes {
        times: vec![0.0, 1.0],
        positions: vec![[0.0; 3]; 2],
        rotations: vec![[0.0, 0.0, 170.0 * deg], [0.0, 0.0, -170.0 * deg]],
        pivot: [0.0; 3],
    };
    let w = m.velocity(0.5).angular;
    assert!((w.length() - 20.0 * deg).abs() < 1e-9, "{w}");
    assert!((place(&m, 0.5, v(1.0, 0.0, 0.0)) - v(-1.0, 0.0, 0.0)).norm() < 1e-12);
}

#[test]
fn a_spin_turns_about_its_axis_and_comes_back_after_a_full_turn() {
    let omega = 2.0;
    let m = ObstacleMotion::Spin {
        axis_point: [1.0, 0.0, 0.0],
        axis: [0.0, 0.0, 3.0],
        angular_velocity: omega,
    };
    let p = v(2.0, 0.0, 0.5);
    // A quarter turn, right-handed about +z through (1, 0, 0): (2, 0) -> (1, 1).
    assert!((place(&m, PI / 4.0, p) - v(1.0, 1.0, 0.5)).norm() < 1e-12);
    assert!((place(&m, 2.0 * PI / omega, p) - p).norm() < 1e-12);
    // The axis does not move; the material at p moves at omega r, tangentially.
    assert!((place(&m, 0.7, v(1.0, 0.0, 9.0)) - v(1.0, 0.0, 9.0)).norm() < 1e-12);
    let u = m.velocity(0.3).at(to_glam(p));
    assert!((to_na(u) - v(0.0, omega, 0.0)).norm() < 1e-12, "{u}");
    let r = m.matrix(PI / 4.0);
    assert!((r[0] - 0.0).abs() < 1e-12 && (r[1] + 1.0).abs() < 1e-12 && (r[3] - 1.0).abs() < 1e-12);
}

#[test]
fn unusable_motions_are_named_and_the_ground_cannot_move() {
    let bad = [
        ObstacleMotion::Linear {
            velocity: [Real::NAN, 0.0, 0.0],
        },
        ObstacleMotion::Spin {
            axis_point: [0.0; 3],
            axis: [0.0; 3],
            angular_velocity: 1.0,
        },
        ObstacleMotion::Keyframes {
            times: vec![0.0, 0.0],
            positions: vec![[0.0; 3]; 2],
            rotations: Vec::new(),
            pivot: [0.0; 3],
        },
        ObstacleMotion::Keyframes {
            times: vec![0.0, 1.0],
            positions: vec![[0.0; 3]],
            rotations: Vec::new(),
            pivot: [0.0; 3],
        },
        ObstacleMotion::Keyframes {
            times: Vec::new(),
            positions: Vec::new(),
            rotations: Vec::new(),
            pivot: [0.0; 3],
        },
        ObstacleMotion::Keyframes {
            times: vec![0.0, 1.0],
            positions: vec![[0.0; 3]; 2],
            rotations: vec![[0.0; 3]],
            pivot: [0.0; 3],
        },
        ObstacleMotion::Keyframes {
            times: vec![0.0],
            positions: vec![[0.0; 3]],
            rotations: Vec::new(),
            pivot: [Real::INFINITY, 0.0, 0.0],
        },
    ];
    let sphere = ObstacleShape::Sphere {
        center: [0.0; 3],
        radius: 1.0,
    };
    for motion in bad {
        assert!(motion.problem().is_some(), "{motion:?}");
        // Poses of an unusable motion never panic: the identity.
        assert_eq!(
            motion.matrix(1.0)[..9],
            [1., 0., 0., 0., 1., 0., 0., 0., 1.]
        );
        let spec = Obstacle {
            motion,
            ..Obstacle::new(sphere.clone())
        };
        assert!(Obstacles::build(&[spec], &ContactParams::default()).is_err());
    }
    let ground = Obstacle {
        motion: ObstacleMotion::Linear {
            velocity: [0.0, 0.0, 1.0],
        },
        ..Obstacle::new(ObstacleShape::Ground { height: 0.0 })
    };
    let err = Obstacles::build(&[ground], &ContactParams::default()).err();
    assert!(err.is_some_and(|e| e.to_string().contains("the ground cannot move")));
}

/// A 2 mm thick wall crossing 10 cm in one step sweeps a still vertex along instead of passing
/// through it: the vertex ends in front of the wall, moving faster than the wall (restitution on
/// the relative velocity). A still wall at the end pose would have seen nothing.
#[test]
fn a_fast_thin_wall_pushes_a_still_vertex_instead_of_tunnelling() {
    let wall = ObstacleShape::Box {
        center: [-0.05, 0.0, 0.0],
        half_extents: [1e-3, 0.5, 0.5],
    };
    let speed = 10.0;
    let mut obs = moving(
        wall.clone(),
        ObstacleMotion::Linear {
            velocity: [speed, 0.0, 0.0],
        },
        0.0,
    );
    let dt = 0.01;
    obs.set_step(0.0, dt);
    let start = [v(0.0, 0.0, 0.0)];
    let (mut x, mut vel) = (start, [v(0.0, 0.0, 0.0)]);
    let stats = obs.respond(&start, &mut x, &mut vel, &[1.0], 0.0, dt);
    assert_eq!(stats.contacts, 1);
    let face = 0.05 + 1e-3 + obs.margin();
    assert!(x[0].x >= face - 1e-12, "{}", x[0]);
    assert!(vel[0].x > speed, "{}", vel[0]);
    assert_eq!((vel[0].y, vel[0].z), (0.0, 0.0));
    // The wall standing still where the moving one ends misses the vertex.
    let still = crate::testing::obstacles(&[Obstacle::new(ObstacleShape::Box {
        center: [0.05, 0.0, 0.0],
        half_extents: [1e-3, 0.5, 0.5],
    })]);
    let (mut x, mut vel) = (start, [v(0.0, 0.0, 0.0)]);
    assert_eq!(
        still
            .respond(&start, &mut x, &mut vel, &[1.0], 0.0, dt)
            .contacts,
        0
    );
}

/// A point mass under gravity from rest at `start` (m) on an obstacle: `steps` steps of `dt` (s),
/// each followed by the contact pass with the cloth friction `cloth_mu`. Returns its position
/// and velocity.
fn ride(obs: &mut Obstacles, start: Vec3, steps: usize, dt: Real, cloth_mu: Real) -> (Vec3, Vec3) {
    let g = v(0.0, 0.0, -9.81);
    let (mut x, mut vel) = ([start], [v(0.0, 0.0, 0.0)]);
    for k in 0..steps {
        let x0 = x;
        vel[0] += g * dt;
        x[0] += vel[0] * dt;
        obs.set_step(k as Real * dt, (k + 1) as Real * dt);
        obs.respond(&x0, &mut x, &mut vel, &[1.0], cloth_mu, dt);
    }
    (x[0], vel[0])
}

/// Friction drags a point resting on a plate moving along +x up to the plate's speed (Coulomb:
/// at `mu g` per second), never against it nor sideways; a frictionless plate slides under it.
#[test]
fn a_moving_plate_drags_a_resting_point_by_friction_only() {
    let plate = ObstacleShape::Box {
        center: [0.0, 0.0, -0.05],
        half_extents: [2.0, 2.0, 0.05],
    };
    let speed = 0.3;
    let motion = ObstacleMotion::Linear {
        velocity: [speed, 0.0, 0.0],
    };
    let dt = 1e-3;
    // Friction (0.5 + 0.5) / 2 = 0.5: 0.3 m/s is reached after 0.3 / (0.5 g) = 61 ms.
    let mut obs = moving(plate.clone(), motion.clone(), 0.5);
    let (x, vel) = ride(&mut obs, v(0.0, 0.0, 2e-3), 200, dt, 0.5);
    assert!((vel.x - speed).abs() < 1e-9, "{vel}");
    assert_eq!(vel.y, 0.0);
    assert!(vel.z.abs() < 0.02, "{vel}");
    assert!(x.z >= 2e-3 - 1e-9, "{x}");
    // Halfway through the acceleration, it is behind the plate, never ahead.
    let mut obs = moving(plate.clone(), motion.clone(), 0.5);
    let (_, half) = ride(&mut obs, v(0.0, 0.0, 2e-3), 30, dt, 0.5);
    assert!(half.x > 0.3 * speed && half.x < 0.7 * speed, "{half}");
    // Frictionless: no drag.
    let mut obs = moving(plate, motion, 0.0);
    let (_, vel) = ride(&mut obs, v(0.0, 0.0, 2e-3), 200, dt, 0.0);
    assert_eq!((vel.x, vel.y), (0.0, 0.0));
}

/// A point resting off the axis of a spinning round table gains the table's tangential velocity,
/// in the direction of the spin.
#[test]
fn a_spinning_table_carries_a_resting_point_round() {
    let table = ObstacleShape::Cylinder {
        center: [0.0, 0.0, -0.05],
        radius: 1.0,
        height: 0.1,
    };
    let omega = 1.5;
    let mut obs = moving(
        table,
        ObstacleMotion::Spin {
            axis_point: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            angular_velocity: omega,
        },
        0.5,
    );
    let (x, vel) = ride(&mut obs, v(0.5, 0.0, 2e-3), 300, 1e-3, 0.5);
    // Tangential direction at x (counter-clockwise seen from above).
    let r = v(x.x, x.y, 0.0);
    let tangent = v(-x.y, x.x, 0.0).normalize();
    let along = vel.dot(&tangent);
    assert!(
        (along - omega * r.norm()).abs() < 0.02 * omega * r.norm(),
        "{vel} at {x}"
    );
    assert!(x.y > 0.0, "{x}");
}

/// A moved mesh answers as a still mesh built where the moved one stands: penetration,
/// projection and the depth through a face (its grid and vertices are in its own frame).
#[test]
fn a_moved_mesh_answers_like_a_mesh_built_where_it_stands() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("tetra.obj");
    // A closed, outward tetrahedron around the origin.
    std::fs::write(
        &file,
        "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n",
    )
    .unwrap();
    let shape = |translation| ObstacleShape::Mesh {
        file: file.clone(),
        scale: 1.0,
        translation,
    };
    let shift = [0.4, -0.2, 0.3];
    let mut moved = moving(
        shape([0.0; 3]),
        ObstacleMotion::Keyframes {
            times: vec![0.0, 1.0],
            positions: vec![[0.0; 3], shift],
            rotations: Vec::new(),
            pivot: [0.0; 3],
        },
        0.0,
    );
    moved.set_step(0.5, 1.0);
    let still = crate::testing::obstacles(&[Obstacle::new(shape(shift))]);
    let d = v(shift[0], shift[1], shift[2]);
    for p in [v(0.1, 0.1, 0.1), v(0.9, 0.8, 0.7), v(2.0, 0.0, 0.0)] {
        let p = p + d;
        assert!(
            (moved.penetration(p) - still.penetration(p)).abs() < 1e-12,
            "{p}"
        );
        let (a, b) = (
            moved.closest_surface(p).unwrap(),
            still.closest_surface(p).unwrap(),
        );
        assert!((a.point - b.point).norm() < 1e-12 && (a.distance - b.distance).abs() < 1e-12);
    }
    // A wide triangle under the top vertices (1, 1, 1) and (-1, -1, 1), its corners outside.
    let tri = [v(-3.0, -3.0, 0.9), v(3.0, -3.0, 0.9), v(0.0, 6.0, 0.9)].map(|p| p + d);
    let depth = |o: &Obstacles| o.surface_penetration(&tri, [[0, 1, 2]]);
    assert!(depth(&still) > 0.05, "{}", depth(&still));
    assert!((depth(&moved) - depth(&still)).abs() < 1e-12);
}

/// Face contact with a moving obstacle: a face resting on a rising sphere is pushed up to the
/// margin and leaves with the sphere's velocity along the normal.
#[test]
fn face_contact_takes_the_velocity_of_a_moving_obstacle() {
    let params = ContactParams {
        faces: true,
        ..Default::default()
    };
    let spec = Obstacle {
        motion: ObstacleMotion::Linear {
            velocity: [0.0, 0.0, 0.5],
        },
        ..Obstacle::new(ObstacleShape::Sphere {
            center: [0.0; 3],
            radius: 1.0,
        })
    };
    let mut obs = Obstacles::build(&[spec], &params).unwrap();
    obs.set_step(0.0, 0.2); // the sphere's top at z = 1.1
    let mut x = vec![v(-3.0, -3.0, 1.0), v(3.0, -3.0, 1.0), v(0.0, 6.0, 1.0)];
    let mut vel = vec![v(0.0, 0.0, 0.0); 3];
    let stats = crate::testing::respond_one_face(&obs, None, &mut x, &mut vel, [1.0; 3]);
    assert!(stats.contacts >= 1);
    for k in 0..3 {
        assert!((x[k].z - (1.1 + obs.margin())).abs() < 1e-9, "{}", x[k]);
        assert!((vel[k] - v(0.0, 0.0, 0.5)).norm() < 1e-12, "{}", vel[k]);
    }
}
