//! Unit tests of the collision module: response laws (4.16)-(4.18), swept detection, push-out,
//! queries, and the bunny mesh.

use super::*;
use std::path::PathBuf;

const MARGIN: Real = 2e-3;
const GAMMA: Real = 0.5;

fn collision() -> ContactParams {
    ContactParams {
        margin: MARGIN,
        restitution: GAMMA,
        faces: false,
    }
}

fn spec(shape: ObstacleShape, friction: Real) -> Obstacle {
    Obstacle {
        friction,
        ..Obstacle::new(shape)
    }
}

fn build(specs: &[Obstacle]) -> Obstacles {
    Obstacles::build(specs, &collision()).expect("valid obstacles")
}

fn ground(friction: Real) -> Obstacles {
    build(&[spec(ObstacleShape::Ground { height: 0.0 }, friction)])
}

fn sphere() -> Obstacles {
    build(&[spec(
        ObstacleShape::Sphere {
            center: [0.0, 0.0, 0.0],
            radius: 1.0,
        },
        0.0,
    )])
}

fn unit_box() -> Obstacles {
    build(&[spec(
        ObstacleShape::Box {
            center: [0.0, 0.0, 0.0],
            half_extents: [0.5, 0.3, 0.2],
        },
        0.0,
    )])
}

fn cylinder() -> Obstacles {
    build(&[spec(
        ObstacleShape::Cylinder {
            center: [1.0, 2.0, 0.5],
            radius: 0.3,
            height: 1.0,
        },
        0.0,
    )])
}

fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bunny() -> Obstacles {
    Obstacles::build(
        &[spec(
            ObstacleShape::Mesh {
                file: manifest_dir().join("scenes/meshes/bunny.obj"),
                scale: 1.0,
                translation: [0.0; 3],
            },
            0.0,
        )],
        &collision(),
    )
    .expect("bunny loads")
}

/// One free vertex: returns (x, v, stats) after `respond`.
fn respond_one(
    obs: &Obstacles,
    start: Vec3,
    end: Vec3,
    vel: Vec3,
    cloth_mu: Real,
    dt: Real,
) -> (Vec3, Vec3, ContactStats) {
    let mut x = [end];
    let mut v = [vel];
    let stats = obs.respond(&[start], &mut x, &mut v, &[1.0], cloth_mu, dt);
    (x[0], v[0], stats)
}

fn close(a: Real, b: Real, tol: Real) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn ground_bounce_reflects_normal_velocity_with_restitution() {
    let obs = ground(0.0);
    let dt = 0.01;
    let v = Vec3::new(0.0, 0.0, -10.0);
    let start = Vec3::new(0.0, 0.0, 0.01);
    let (x, v2, stats) = respond_one(&obs, start, start + v * dt, v, 0.0, dt);
    assert!(close(v2.z, GAMMA * 10.0, 1e-12), "v_n' = {}", v2.z);
    assert!(close(v2.x, 0.0, 1e-15) && close(v2.y, 0.0, 1e-15));
    assert!(close(x.z, start.z + v2.z * dt, 1e-12));
    assert!(x.z >= MARGIN);
    assert_eq!(stats.contacts, 1);
    assert_eq!(stats.max_penetration, 0.0);
}

#[test]
fn ground_bounce_ends_at_margin_when_rebound_is_short() {
    let obs = ground(0.0);
    let dt = 1e-3;
    let v = Vec3::new(0.0, 0.0, -2.0);
    let start = Vec3::new(0.0, 0.0, 0.0005);
    let (x, v2, _) = respond_one(&obs, start, start + v * dt, v, 0.0, dt);
    // x_start + v' dt = 0.0005 + 0.001 is inside the margin band: pushed to the margin.
    assert!(close(x.z, MARGIN, 1e-12), "z = {}", x.z);
    assert!(close(v2.z, GAMMA * 2.0, 1e-12));
}

#[test]
fn obstacle_restitution_overrides_default() {
    let mut s = spec(ObstacleShape::Ground { height: 0.0 }, 0.0);
    s.restitution = 0.8;
    let obs = build(&[s]);
    let v = Vec3::new(0.0, 0.0, -10.0);
    let start = Vec3::new(0.0, 0.0, 0.05);
    let (_, v2, _) = respond_one(&obs, start, start + v * 0.01, v, 0.0, 0.01);
    assert!(close(v2.z, 8.0, 1e-12));
}

#[test]
fn friction_reduces_tangential_velocity_by_mu_dvn() {
    // mu = (0.02 + 0.04) / 2 = 0.03; dv_N = (1 + 0.5) 10 = 15; |v_T| = 1 -> 1 - 0.45.
    let obs = ground(0.04);
    let dt = 0.01;
    let v = Vec3::new(0.6, 0.8, -10.0);
    let start = Vec3::new(0.0, 0.0, 0.05);
    let (_, v2, _) = respond_one(&obs, start, start + v * dt, v, 0.02, dt);
    let scale = 1.0 - 0.03 * 15.0;
    assert!(close(v2.x, 0.6 * scale, 1e-12), "{v2:?}");
    assert!(close(v2.y, 0.8 * scale, 1e-12), "{v2:?}");
    assert!(close(v2.z, 5.0, 1e-12));
}

#[test]
fn large_friction_stops_but_does_not_reverse_sliding() {
    let obs = ground(1.0);
    let dt = 0.01;
    let v = Vec3::new(1.0, -0.5, -10.0);
    let start = Vec3::new(0.0, 0.0, 0.05);
    let (_, v2, _) = respond_one(&obs, start, start + v * dt, v, 1.0, dt);
    assert_eq!(v2.x, 0.0);
    assert_eq!(v2.y, 0.0);
    assert!(close(v2.z, 5.0, 1e-12));
}

#[test]
fn resting_vertex_within_margin_loses_inward_velocity_and_feels_friction() {
    let obs = ground(0.2);
    let dt = 1e-3;
    // Starts at the margin, ends inside the band without crossing the surface.
    let start = Vec3::new(0.0, 0.0, MARGIN);
    let v = Vec3::new(0.5, 0.0, -0.1);
    let (x, v2, stats) = respond_one(&obs, start, start + v * dt, v, 0.2, dt);
    assert_eq!(stats.contacts, 1);
    assert!(close(x.z, MARGIN, 1e-12));
    assert!(v2.z.abs() < 1e-12, "{v2:?}");
    // mu = 0.2, dv_N = 0.1: tangential speed 0.5 - 0.02.
    assert!(close(v2.x, 0.48, 1e-12), "{v2:?}");
}

#[test]
fn clear_vertex_is_untouched() {
    let obs = ground(0.0);
    let start = Vec3::new(0.0, 0.0, 1.0);
    let v = Vec3::new(0.1, 0.2, -1.0);
    let end = start + v * 0.01;
    let (x, v2, stats) = respond_one(&obs, start, end, v, 0.1, 0.01);
    assert_eq!((x, v2), (end, v));
    assert_eq!(stats, ContactStats::default());
}

#[test]
fn swept_test_catches_tunnelling_through_thin_box() {
    let obs = build(&[spec(
        ObstacleShape::Box {
            center: [0.0, 0.0, 0.0],
            half_extents: [1.0, 1.0, 0.005],
        },
        0.0,
    )]);
    let dt = 0.01;
    let v = Vec3::new(0.0, 0.0, -20.0);
    let start = Vec3::new(0.1, 0.2, 0.1);
    let end = start + v * dt; // z = -0.1: both ends outside the slab
    assert_eq!(obs.penetration(end), 0.0);
    let (x, v2, stats) = respond_one(&obs, start, end, v, 0.0, dt);
    assert_eq!(stats.contacts, 1);
    assert!(close(v2.z, GAMMA * 20.0, 1e-9), "{v2:?}");
    assert!(x.z >= 0.005 + MARGIN - 1e-12, "{x:?}");
}

#[test]
fn pinned_vertices_are_never_moved() {
    let obs = sphere();
    let inside = Vec3::new(0.1, 0.0, 0.0);
    let start = Vec3::new(2.0, 0.0, 0.0);
    let mut x = [inside, inside];
    let mut v = [Vec3::new(-1.0, 0.0, 0.0); 2];
    let stats = obs.respond(&[start, start], &mut x, &mut v, &[0.0, 1.0], 0.1, 0.01);
    assert_eq!(x[0], inside);
    assert_eq!(v[0], Vec3::new(-1.0, 0.0, 0.0));
    assert_ne!(x[1], inside);
    assert_eq!(stats.contacts, 1);
    assert!(obs.penetration(x[1]) == 0.0);
}

fn assert_pushed_to_margin(obs: &Obstacles, p: Vec3) {
    assert!(obs.penetration(p) > 0.0, "{p:?} should start inside");
    let q = obs.push_out(p);
    let s = obs.closest_surface(q).expect("an obstacle");
    assert!(
        close(s.distance, MARGIN, 1e-9),
        "distance {} at {q:?}",
        s.distance
    );
    assert_eq!(obs.penetration(q), 0.0);
    // Already clear: unchanged.
    assert_eq!(obs.push_out(q), q);
}

#[test]
fn push_out_sphere_box_cylinder_to_margin() {
    assert_pushed_to_margin(&sphere(), Vec3::new(0.3, -0.2, 0.5));
    assert_pushed_to_margin(&unit_box(), Vec3::new(0.45, 0.1, -0.05));
    assert_pushed_to_margin(&unit_box(), Vec3::new(0.49, 0.29, 0.19)); // near a corner
    assert_pushed_to_margin(&cylinder(), Vec3::new(1.2, 2.0, 0.5)); // near the side
    assert_pushed_to_margin(&cylinder(), Vec3::new(1.0, 2.05, 0.98)); // near the top
                                                                      // Within the margin but outside: pushed to the margin too.
    let q = sphere().push_out(Vec3::new(0.0, 0.0, 1.0005));
    assert!(close(q.z, 1.0 + MARGIN, 1e-12));
}

#[test]
fn cylinder_axis_is_vertical() {
    let obs = cylinder(); // centre (1, 2, 0.5), radius 0.3, height 1
    assert!(obs.penetration(Vec3::new(1.0, 2.0, 0.95)) > 0.0);
    assert!(obs.penetration(Vec3::new(1.0, 2.0, 0.05)) > 0.0);
    assert_eq!(obs.penetration(Vec3::new(1.0, 2.45, 0.5)), 0.0);
    assert_eq!(obs.penetration(Vec3::new(1.0, 2.0, 1.05)), 0.0);
    let top = obs
        .closest_surface(Vec3::new(1.05, 2.0, 1.2))
        .expect("some");
    assert!(close(top.point.z, 1.0, 1e-12) && close(top.normal.z, 1.0, 1e-12));
}

#[test]
fn penetration_is_zero_outside_and_depth_inside_sphere() {
    let obs = sphere();
    assert_eq!(obs.penetration(Vec3::new(0.0, 1.5, 0.0)), 0.0);
    assert_eq!(obs.penetration(Vec3::new(0.0, 1.0005, 0.0)), 0.0);
    assert!(close(obs.penetration(Vec3::new(0.0, 0.7, 0.0)), 0.3, 1e-12));
    assert!(close(obs.penetration(Vec3::new(0.3, 0.0, 0.4)), 0.5, 1e-12));
}

#[test]
fn edge_hit_sphere_crossing_box_inside_and_clear_segment() {
    let s = sphere();
    let hit = s
        .edge_hit(Vec3::new(-2.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0))
        .expect("crosses the sphere");
    assert_eq!(hit.obstacle, 0);
    assert!(
        (hit.point - Vec3::new(-1.0, 0.0, 0.0)).norm() < 1e-9,
        "{hit:?}"
    );
    assert!(
        (hit.normal - Vec3::new(-1.0, 0.0, 0.0)).norm() < 1e-9,
        "{hit:?}"
    );

    let b = unit_box();
    let a = Vec3::new(-0.2, 0.0, 0.0);
    let hit = b
        .edge_hit(a, Vec3::new(0.2, 0.1, 0.0))
        .expect("inside the box");
    assert_eq!(hit.point, a);
    assert!(close(hit.normal.norm(), 1.0, 1e-12));

    assert!(s
        .edge_hit(Vec3::new(-2.0, 1.5, 0.0), Vec3::new(2.0, 1.5, 0.0))
        .is_none());
    assert!(b
        .edge_hit(Vec3::new(3.0, 3.0, 3.0), Vec3::new(4.0, 3.0, 3.0))
        .is_none());
}

#[test]
fn edge_hit_returns_nearest_obstacle_along_segment() {
    let obs = build(&[
        spec(
            ObstacleShape::Sphere {
                center: [3.0, 0.0, 0.0],
                radius: 0.5,
            },
            0.0,
        ),
        spec(
            ObstacleShape::Sphere {
                center: [1.0, 0.0, 0.0],
                radius: 0.5,
            },
            0.0,
        ),
    ]);
    let hit = obs
        .edge_hit(Vec3::zeros(), Vec3::new(4.0, 0.0, 0.0))
        .expect("hit");
    assert_eq!(hit.obstacle, 1);
    assert!(close(hit.point.x, 0.5, 1e-9));
}

/// Volume centroid of the bunny's mesh (divergence theorem over its triangles).
fn mesh_centroid(obs: &Obstacles) -> Vec3 {
    let mesh = obs.obstacles[0].mesh().expect("a mesh");
    let vs = mesh.vertices();
    let mut volume = 0.0;
    let mut moment = Vec3::zeros();
    for t in mesh.indices() {
        let [a, b, c] = t.map(|i| shape::to_na(vs[i as usize]));
        let v6 = a.dot(&b.cross(&c));
        volume += v6;
        moment += (a + b + c) * v6 * 0.25;
    }
    moment / volume
}

#[test]
fn bunny_loads_with_expected_size() {
    let obs = bunny();
    assert_eq!(obs.len(), 1);
    let mesh = obs.obstacles[0].mesh().expect("a mesh");
    assert_eq!(mesh.vertices().len(), 2002);
    assert_eq!(mesh.indices().len(), 4000);
}

#[test]
fn bunny_closest_surface_consistent_with_penetration() {
    let obs = bunny();
    let centroid = mesh_centroid(&obs);
    let inside = obs.closest_surface(centroid).expect("some");
    assert!(
        inside.distance < -0.02,
        "centroid distance {}",
        inside.distance
    );
    assert!(close(obs.penetration(centroid), -inside.distance, 1e-12));

    let above = Vec3::new(centroid.x, centroid.y, 0.7);
    let outside = obs.closest_surface(above).expect("some");
    assert!(outside.distance > 0.05, "{outside:?}");
    assert_eq!(obs.penetration(above), 0.0);
    assert!(outside.normal.z > 0.0);
    assert!(close(
        (above - outside.point).norm(),
        outside.distance,
        1e-12
    ));

    for p in [
        Vec3::new(0.0, 0.0, 0.1),
        Vec3::new(0.1, 0.05, 0.3),
        Vec3::new(-0.2, 0.1, 0.2),
        Vec3::new(0.3, -0.3, 0.05),
    ] {
        let s = obs.closest_surface(p).expect("some");
        assert!(close(obs.penetration(p), (-s.distance).max(0.0), 1e-12));
    }
    assert_pushed_to_margin(&obs, centroid);
}

#[test]
fn bunny_drop_keeps_every_vertex_outside_the_margin() {
    let obs = bunny();
    let c = mesh_centroid(&obs);
    // A grid of vertices above the bunny falling fast through it in one step.
    let mut x_start = Vec::new();
    for i in 0..21 {
        for j in 0..21 {
            let u = -0.3 + 0.03 * i as Real;
            let w = -0.3 + 0.03 * j as Real;
            x_start.push(Vec3::new(c.x + u, c.y + w, 0.6));
        }
    }
    let dt = 0.01;
    let vel = Vec3::new(0.0, 0.0, -30.0);
    let mut x: Vec<Vec3> = x_start.iter().map(|p| p + vel * dt).collect();
    let mut v = vec![vel; x.len()];
    let inv_mass = vec![1.0; x.len()];
    let stats = obs.respond(&x_start, &mut x, &mut v, &inv_mass, 0.3, dt);
    assert!(stats.contacts > 50, "{stats:?}");
    assert!(stats.max_penetration <= MARGIN);
    for p in &x {
        assert_eq!(obs.penetration(*p), 0.0, "{p:?}");
    }
}

#[test]
fn build_rejects_bad_shapes_and_files() {
    let bad_radius = spec(
        ObstacleShape::Sphere {
            center: [0.0; 3],
            radius: 0.0,
        },
        0.0,
    );
    let err = Obstacles::build(
        &[spec(ObstacleShape::Ground { height: 0.0 }, 0.0), bad_radius],
        &collision(),
    )
    .err()
    .expect("error");
    assert!(
        matches!(err, CollisionError::BadShape { index: 1, .. }),
        "{err}"
    );

    let bad_box = spec(
        ObstacleShape::Box {
            center: [0.0; 3],
            half_extents: [1.0, -1.0, 1.0],
        },
        0.0,
    );
    assert!(Obstacles::build(&[bad_box], &collision()).is_err());

    let missing = spec(
        ObstacleShape::Mesh {
            file: "no/such/file.obj".into(),
            scale: 1.0,
            translation: [0.0; 3],
        },
        0.0,
    );
    let err = Obstacles::build(&[missing], &collision())
        .err()
        .expect("error");
    assert!(
        matches!(
            err,
            CollisionError::MeshFile {
                index: 0,
                source: crate::io::ObjError::Io { .. }
            }
        ),
        "{err}"
    );
}

#[test]
fn mesh_obstacle_files_report_the_line_and_need_faces() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = |name: &str, text: &str| {
        std::fs::write(dir.path().join(name), text).unwrap();
        spec(
            ObstacleShape::Mesh {
                file: dir.path().join(name),
                scale: 1.0,
                translation: [0.0; 3],
            },
            0.0,
        )
    };
    let bad_line = mesh("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
    let err = Obstacles::build(&[bad_line], &collision())
        .err()
        .expect("error");
    assert!(
        matches!(
            err,
            CollisionError::MeshFile {
                index: 0,
                source: crate::io::ObjError::Parse { line: 3, .. }
            }
        ),
        "{err}"
    );
    let no_faces = mesh("empty.obj", "v 0 0 0\n");
    let err = Obstacles::build(&[no_faces], &collision())
        .err()
        .expect("error");
    assert!(err.to_string().contains("no faces"), "{err}");
    // A mesh scaled to a subnormal size (parry's tree over it recursed until the stack
    // overflowed) is refused by its size; at 1e-6 m across it is built.
    let tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    let scaled = |scale: Real| {
        let mut s = mesh("tet.obj", tet);
        if let ObstacleShape::Mesh { scale: sc, .. } = &mut s.shape {
            *sc = scale;
        }
        Obstacles::build(&[s], &collision())
    };
    let err = scaled(1e-308).err().expect("error");
    assert!(
        err.to_string().contains("m across") && err.to_string().contains("scale"),
        "{err}"
    );
    assert!(scaled(1e-6).is_ok());
    // Scaled beyond a million metres: refused (it was accepted and drew a blank picture).
    let err = scaled(1e300).err().expect("error");
    assert!(err.to_string().contains("within ±1e6 m"), "{err}");
    assert!(scaled(1e5).is_ok());
    // Only flat faces: nothing to collide with.
    let flat = mesh("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    let err = Obstacles::build(&[flat], &collision())
        .err()
        .expect("error");
    assert!(
        err.to_string().contains("no face has a positive area"),
        "{err}"
    );
}

#[test]
fn empty_obstacle_list_changes_nothing() {
    let obs = build(&[]);
    assert!(obs.is_empty());
    assert!(obs.closest_surface(Vec3::zeros()).is_none());
    assert!(obs.edge_hit(Vec3::zeros(), Vec3::x()).is_none());
    assert_eq!(obs.penetration(Vec3::zeros()), 0.0);
}

/// Timing sanity check, not a test: run with
/// `cargo test --release --lib collision::tests::respond_timing_against_bunny -- --ignored --nocapture`.
#[test]
#[ignore]
fn respond_timing_against_bunny() {
    use rand::{Rng, SeedableRng};
    let obs = bunny();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let n = 10_000;
    let dt = 1e-3;
    let c = mesh_centroid(&obs);
    let mesh = obs.obstacles[0].mesh().expect("a mesh");
    let aabb = mesh.local_aabb();
    let (lo, hi) = (shape::to_na(aabb.mins), shape::to_na(aabb.maxs));
    let mut uniform = |lo: Vec3, hi: Vec3| {
        Vec3::new(
            rng.random_range(lo.x..hi.x),
            rng.random_range(lo.y..hi.y),
            rng.random_range(lo.z..hi.z),
        )
    };
    let half = Vec3::new(0.5, 0.5, 0.3);
    let wide: Vec<Vec3> = (0..n).map(|_| uniform(c - half, c + half)).collect();
    let mut wide_outside = Vec::with_capacity(n);
    while wide_outside.len() < n {
        let p = uniform(c - half, c + half);
        if obs.penetration(p) == 0.0 {
            wide_outside.push(p);
        }
    }
    let tight: Vec<Vec3> = (0..n).map(|_| uniform(lo, hi)).collect();
    let near: Vec<Vec3> = tight
        .iter()
        .map(|&p| {
            let s = obs.closest_surface(p).expect("some");
            s.point + s.normal * (0.5 * MARGIN)
        })
        .collect();
    let vel: Vec<Vec3> = (0..n)
        .map(|_| uniform(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 1.0, 1.0)))
        .collect();
    let inv_mass = vec![1.0; n];
    for (name, ends) in [
        ("1.0 x 1.0 x 0.6 m box around the bunny", &wide),
        ("same box, points outside the bunny only", &wide_outside),
        ("inside the bunny's AABB", &tight),
        ("all within the margin of the surface", &near),
    ] {
        let starts: Vec<Vec3> = ends.iter().zip(&vel).map(|(p, v)| p - v * dt).collect();
        let mut x = ends.clone();
        let mut v = vel.clone();
        let reps = 20;
        let mut contacts = 0;
        let mut per_call = Real::INFINITY;
        for _ in 0..reps {
            x.copy_from_slice(ends);
            v.copy_from_slice(&vel);
            let t0 = std::time::Instant::now();
            contacts = obs
                .respond(&starts, &mut x, &mut v, &inv_mass, 0.3, dt)
                .contacts;
            per_call = per_call.min(t0.elapsed().as_secs_f64());
        }
        println!(
            "{n} points, {name}: {:.3} ms per respond call (best of {reps}), {contacts} contacts",
            per_call * 1e3
        );
    }
}

#[test]
fn edge_hit_on_bunny_enters_from_above() {
    let obs = bunny();
    let c = mesh_centroid(&obs);
    let top = Vec3::new(c.x, c.y, 0.8);
    let hit = obs.edge_hit(top, c).expect("enters the bunny");
    assert!(hit.point.z < top.z && hit.point.z > c.z, "{hit:?}");
    assert!(hit.normal.z > 0.0, "{hit:?}");
    assert!(obs.penetration(hit.point) < 1e-9);
    // Starting inside: the hit is the start itself.
    let inside = obs.edge_hit(c, top).expect("starts inside");
    assert_eq!(inside.point, c);
}

/// The edge query never misses a segment that reaches into the bunny:
/// random segments of 1-20 cm around it, sampled every 1 mm, are hit whenever a sample is inside.
#[test]
fn edge_hit_on_bunny_finds_every_segment_that_reaches_inside() {
    let obs = bunny();
    let c = mesh_centroid(&obs);
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as Real / (1u64 << 53) as Real
    };
    let (mut inside, mut clear) = (0, 0);
    for _ in 0..3000 {
        let a = c + Vec3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * 0.5;
        let dir = Vec3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5).normalize();
        let b = a + dir * (0.01 + 0.19 * uniform());
        let samples = ((b - a).norm() / 1e-3).ceil() as usize;
        let reaches = (0..=samples)
            .any(|k| obs.penetration(a + (b - a) * (k as Real / samples as Real)) > 0.0);
        if reaches {
            inside += 1;
            assert!(obs.edge_hit(a, b).is_some(), "missed {a:?} -> {b:?}");
        } else {
            clear += 1;
        }
    }
    assert!(
        inside > 100 && clear > 100,
        "{inside} reaching, {clear} clear"
    );
}

#[test]
fn surface_near_answers_within_its_band_as_closest_surface_does() {
    let obs = bunny();
    let centroid = mesh_centroid(&obs);
    for p in [
        centroid,
        Vec3::new(centroid.x, centroid.y, 0.7),
        Vec3::new(0.0, 0.0, 0.1),
        Vec3::new(0.1, 0.05, 0.3),
        Vec3::new(-0.2, 0.1, 0.2),
        Vec3::new(3.0, 3.0, 3.0),
    ] {
        let exact = obs.closest_surface(p).expect("some");
        for band in [0.01, 0.05, 0.2, 1.0] {
            match obs.surface_near(p, band) {
                Some(s) => {
                    assert!(exact.distance < band, "{p:?} band {band}: {exact:?}");
                    assert!(
                        close(s.distance, exact.distance, 1e-9),
                        "{s:?} vs {exact:?}"
                    );
                    assert!(close((s.point - exact.point).norm(), 0.0, 1e-9));
                }
                None => assert!(exact.distance >= band, "{p:?} band {band}: {exact:?}"),
            }
        }
    }
}
