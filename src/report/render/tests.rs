//! Unit tests of the renderer: OBJ reading, obstacle meshes, rasterisation.

use super::camera::Camera;
use super::picture::draw_scene;
use super::*;
use crate::scene::{ObstacleShape, ObstacleSpec};
use std::path::Path;

fn spec(shape: ObstacleShape) -> ObstacleSpec {
    ObstacleSpec {
        shape,
        friction: 0.0,
        restitution: 0.0,
        motion: None,
    }
}

/// Signed volume (m³) of a closed mesh: positive when the faces point outwards.
fn signed_volume(m: &FrameMesh) -> f64 {
    m.faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| m.positions[i as usize].map(f64::from));
            let cross = [
                b[1] * c[2] - b[2] * c[1],
                b[2] * c[0] - b[0] * c[2],
                b[0] * c[1] - b[1] * c[0],
            ];
            (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
        })
        .sum()
}

/// Every directed edge appears once and its reverse once: the mesh is closed and consistently
/// oriented.
fn is_closed_and_oriented(m: &FrameMesh) -> bool {
    let mut directed: Vec<(u32, u32)> = m
        .faces
        .iter()
        .flat_map(|f| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
        .collect();
    directed.sort_unstable();
    let unique = directed.windows(2).all(|w| w[0] != w[1]);
    unique
        && directed
            .iter()
            .all(|&(a, b)| directed.binary_search(&(b, a)).is_ok())
}

#[test]
fn reads_a_frame_written_by_a_run() {
    let text = "# adaptcloth frame, t = 0.250000 s\n\
                v 0 0 0.3\nv 1 0 0.3\nv 0 1 0.3\nv 1 1 0.25\n\
                vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n\
                f 1/1 2/2 3/3\nf 2/2 4/4 3/3 1/1\n";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frame_00001.obj");
    std::fs::write(&path, text).unwrap();
    let m = FrameMesh::read(&path).unwrap();
    assert_eq!(m.positions.len(), 4);
    assert_eq!(m.positions[3], [1.0, 1.0, 0.25]);
    assert_eq!(m.faces, vec![[0, 1, 2], [1, 3, 2], [1, 2, 0]]);
    m.validate().unwrap();
    assert!(matches!(
        FrameMesh::read(Path::new("/nonexistent/frame.obj")),
        Err(RenderError::Obj(crate::io::ObjError::Io { .. }))
    ));
}

#[test]
fn obstacle_meshes_are_closed_outward_and_near_the_analytic_volume() {
    use std::f64::consts::PI;
    let specs = [
        spec(ObstacleShape::Sphere {
            center: [0.1, 0.2, 0.3],
            radius: 0.25,
        }),
        spec(ObstacleShape::Cylinder {
            center: [0.0, 0.0, 0.375],
            radius: 0.35,
            height: 0.75,
        }),
        spec(ObstacleShape::Box {
            center: [1.0, -1.0, 0.5],
            half_extents: [0.1, 0.2, 0.3],
        }),
    ];
    let meshes = obstacle_meshes(&specs, Path::new(".")).unwrap();
    let analytic = [
        4.0 / 3.0 * PI * 0.25f64.powi(3),
        PI * 0.35f64.powi(2) * 0.75,
        0.2 * 0.4 * 0.6,
    ];
    for (m, v) in meshes.iter().zip(analytic) {
        assert!(is_closed_and_oriented(m));
        let vol = signed_volume(m);
        assert!(vol > 0.0 && (vol / v - 1.0).abs() < 0.02, "{vol} vs {v}");
    }
    let (lo, hi) = meshes[1].bounds().unwrap();
    assert!((lo[2] - 0.0).abs() < 1e-6 && (hi[2] - 0.75).abs() < 1e-6);
}

#[test]
fn bunny_obstacle_is_scaled_translated_and_outward() {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let specs = [
        spec(ObstacleShape::Mesh {
            file: "meshes/bunny.obj".into(),
            scale: 2.0,
            translation: [0.0, 0.0, 1.0],
        }),
        spec(ObstacleShape::Ground { height: 0.0 }),
    ];
    let meshes = obstacle_meshes(&specs, &base).unwrap();
    assert_eq!(meshes[0].positions.len(), 2002);
    assert_eq!(meshes[0].faces.len(), 4000);
    assert!(signed_volume(&meshes[0]) > 0.0);
    let (lo, _) = meshes[0].bounds().unwrap();
    assert!((lo[2] - 1.0).abs() < 1e-3, "base at z = 1: {lo:?}");
    // The ground is an upward square reaching beyond the bunny.
    let (glo, ghi) = meshes[1].bounds().unwrap();
    assert_eq!(glo[2], 0.0);
    assert!(ghi[0] >= 1.5 && glo[1] <= -1.5);
    let [a, b, c] = meshes[1].faces[0].map(|i| meshes[1].positions[i as usize]);
    let nz = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    assert!(nz > 0.0);
    let missing = [spec(ObstacleShape::Mesh {
        file: "meshes/none.obj".into(),
        scale: 1.0,
        translation: [0.0; 3],
    })];
    assert!(matches!(
        obstacle_meshes(&missing, &base),
        Err(RenderError::Obj(crate::io::ObjError::Io { .. }))
    ));
    let bad = [spec(ObstacleShape::Sphere {
        center: [0.0; 3],
        radius: -1.0,
    })];
    assert!(matches!(
        obstacle_meshes(&bad, &base),
        Err(RenderError::Obstacle { index: 0, .. })
    ));
}

fn pixel(rgb: &[u8], width: usize, x: usize, y: usize) -> [u8; 3] {
    let i = (y * width + x) * 3;
    [rgb[i], rgb[i + 1], rgb[i + 2]]
}

/// A large triangle facing the camera (perpendicular to the view direction through `center`).
fn facing_triangle(camera: &Camera, center: [f32; 3], size: f32) -> FrameMesh {
    use super::camera::{cross, normalize, sub};
    let to_eye = normalize(sub(camera.eye(), center));
    let right = normalize(cross([0.0, 0.0, 1.0], to_eye));
    let up = cross(to_eye, right);
    let at = |a: f32, b: f32| [0, 1, 2].map(|k| center[k] + size * (a * right[k] + b * up[k]));
    FrameMesh {
        positions: vec![at(-1.0, -0.8), at(1.0, -0.8), at(0.0, 1.0)],
        faces: vec![[0, 1, 2]],
    }
}

#[test]
fn a_triangle_is_drawn_where_it_is_and_nowhere_else() {
    let (w, h) = (200, 150);
    let cam = Camera::framing([[-1.0; 3], [1.0; 3]], w as f32, h as f32);
    let tri = facing_triangle(&cam, [0.0; 3], 0.8);
    let rgb = draw_scene(&cam, &tri, &[], w, h).unwrap();
    let centre = pixel(&rgb, w, w / 2, h / 2);
    assert!(
        centre[2] > centre[0] + 40,
        "blue-ish cloth front at the centre: {centre:?}"
    );
    assert_eq!(
        pixel(&rgb, w, 2, 2),
        [255; 3],
        "white background in the corner"
    );
    // Seen from behind, the same triangle is shaded with the back tint (orange-ish).
    let mut back = tri.clone();
    back.faces = vec![[0, 2, 1]];
    let rgb = draw_scene(&cam, &back, &[], w, h).unwrap();
    let c = pixel(&rgb, w, w / 2, h / 2);
    assert!(c[0] > c[2] + 40, "back faces are shaded too: {c:?}");
    // Mesh edges are dark lines: a facing parallelogram a, b, -a, -b split along the diagonal
    // through the centre (same orientation as the first triangle) is dark at the centre.
    let (a, b) = (tri.positions[0], tri.positions[1]);
    let quad = FrameMesh {
        positions: vec![a, b, a.map(|x| -x), b.map(|x| -x)],
        faces: vec![[0, 1, 2], [0, 2, 3]],
    };
    let rgb = draw_scene(&cam, &quad, &[], w, h).unwrap();
    let brightness = |p: [u8; 3]| p.iter().map(|&x| x as u32).sum::<u32>();
    let o = cam.screen(cam.view([0.0; 3]));
    let (ox, oy) = (o[0] as usize, o[1] as usize);
    let on_edge = (ox - 1..=ox + 1)
        .flat_map(|x| (oy - 1..=oy + 1).map(move |y| (x, y)))
        .map(|(x, y)| brightness(pixel(&rgb, w, x, y)))
        .min()
        .unwrap();
    assert!(
        on_edge + 100 < brightness(centre),
        "{on_edge} vs {centre:?}"
    );
}

#[test]
fn the_nearer_triangle_hides_the_farther_whatever_the_order() {
    let (w, h) = (160, 120);
    let cam = Camera::framing([[-1.0; 3], [1.0; 3]], w as f32, h as f32);
    let near_cloth = facing_triangle(&cam, [0.0; 3], 0.5);
    let to_eye = super::camera::normalize(super::camera::sub(cam.eye(), [0.0; 3]));
    let far_obstacle = facing_triangle(&cam, to_eye.map(|c| -0.8 * c), 1.5);
    // Cloth drawn after the obstacle, in front: blue at the centre.
    let rgb = draw_scene(&cam, &near_cloth, std::slice::from_ref(&far_obstacle), w, h).unwrap();
    let c = pixel(&rgb, w, w / 2, h / 2);
    assert!(c[2] > c[0] + 40, "{c:?}");
    // Cloth drawn after the obstacle, behind it: the grey obstacle stays at the centre.
    let near_obstacle = facing_triangle(&cam, to_eye.map(|c| 0.5 * c), 1.5);
    let far_cloth = facing_triangle(&cam, to_eye.map(|c| -0.5 * c), 0.5);
    let rgb = draw_scene(&cam, &far_cloth, &[near_obstacle], w, h).unwrap();
    let c = pixel(&rgb, w, w / 2, h / 2);
    assert!(c[0].abs_diff(c[2]) < 8 && c[0] > 100, "grey: {c:?}");
}

#[test]
fn pictures_are_deterministic_pngs_and_bad_sizes_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let specs = [
        spec(ObstacleShape::Sphere {
            center: [0.0; 3],
            radius: 0.25,
        }),
        spec(ObstacleShape::Ground { height: -0.3 }),
    ];
    let obstacles = obstacle_meshes(&specs, dir.path()).unwrap();
    let cloth = FrameMesh {
        positions: vec![
            [-0.5, -0.5, 0.3],
            [0.5, -0.5, 0.3],
            [0.5, 0.5, 0.3],
            [-0.5, 0.5, 0.3],
        ],
        faces: vec![[0, 1, 2], [0, 2, 3]],
    };
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    render_png(&cloth, &obstacles, 120, 90, &a).unwrap();
    render_png(&cloth, &obstacles, 120, 90, &b).unwrap();
    let bytes = std::fs::read(&a).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    assert_eq!(bytes, std::fs::read(&b).unwrap());
    assert!(matches!(
        render_png(&cloth, &obstacles, 0, 90, &a),
        Err(RenderError::Size { .. })
    ));
    // Each side within 16384 but 4096 x 4097 pixels in all: refused before anything is drawn.
    assert!(matches!(
        render_png(&cloth, &obstacles, 4096, 4097, &a),
        Err(RenderError::Size { .. })
    ));
    let broken = FrameMesh {
        positions: vec![[0.0; 3]],
        faces: vec![[0, 0, 3]],
    };
    assert!(matches!(
        render_png(&broken, &[], 10, 10, &a),
        Err(RenderError::BadFace { index: 3, .. })
    ));
    let rows = [
        SnapshotRow {
            label: "static 5x5".into(),
            frames: vec![(0.0, cloth.clone()), (0.1, cloth.clone())],
        },
        SnapshotRow {
            label: "other".into(),
            frames: vec![(0.0, cloth.clone())],
        },
    ];
    let grid = dir.path().join("grid.png");
    snapshot_grid(&rows, &obstacles, &grid).unwrap();
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&grid).unwrap()));
    let reader = decoder.read_info().unwrap();
    assert_eq!(reader.info().height, 30 + 2 * 270);
}

/// A picture replaces its file by a rename: a hard link to the old file keeps the old bytes, and
/// a failed write leaves no temporary file.
#[test]
fn pictures_are_written_atomically() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.png");
    std::fs::write(&path, "old").unwrap();
    std::fs::hard_link(&path, dir.path().join("link")).unwrap();
    let rgb = vec![200u8; 4 * 3 * 3];
    picture::write_png(&path, 4, 3, &rgb).unwrap();
    assert_eq!(std::fs::read(dir.path().join("link")).unwrap(), b"old");
    assert!(std::fs::read(&path).unwrap().starts_with(b"\x89PNG"));
    let folder = dir.path().join("folder.png");
    std::fs::create_dir(&folder).unwrap();
    assert!(picture::write_png(&folder, 4, 3, &rgb).is_err());
    assert!(!dir.path().join("folder.png.tmp").exists());
}

/// A moving obstacle is drawn where its motion takes it at the asked time; still obstacles are
/// drawn as the scene places them (borrowed, no copy, when nothing moves).
#[test]
fn moving_obstacles_are_drawn_where_they_stand_at_a_time() {
    use crate::scene::MotionSpec;
    use std::borrow::Cow;
    let sphere = ObstacleShape::Sphere {
        center: [0.0, 0.0, 0.5],
        radius: 0.25,
    };
    let table = ObstacleShape::Cylinder {
        center: [0.0, 0.0, 0.375],
        radius: 0.35,
        height: 0.75,
    };
    let mut specs = [spec(sphere), spec(table)];
    let still = obstacle_meshes(&specs, Path::new(".")).unwrap();
    assert!(still.poses(1.0).is_none());
    assert!(matches!(still.at(1.0), Cow::Borrowed(_)));
    specs[0].motion = Some(MotionSpec::Linear {
        velocity: [1.0, 0.0, -0.5],
    });
    specs[1].motion = Some(MotionSpec::Spin {
        axis_point: [0.0; 3],
        axis: [0.0, 0.0, 1.0],
        angular_velocity: std::f64::consts::PI,
    });
    let moving = obstacle_meshes(&specs, Path::new(".")).unwrap();
    let at = moving.at(0.5);
    for (p, q) in moving[0].positions.iter().zip(&at[0].positions) {
        let want = [p[0] + 0.5, p[1], p[2] - 0.25];
        assert!(
            (0..3).all(|k| (q[k] - want[k]).abs() < 1e-6),
            "{q:?} vs {want:?}"
        );
    }
    // A quarter turn: (x, y) -> (-y, x).
    for (p, q) in moving[1].positions.iter().zip(&at[1].positions) {
        let want = [-p[1], p[0], p[2]];
        assert!(
            (0..3).all(|k| (q[k] - want[k]).abs() < 1e-6),
            "{q:?} vs {want:?}"
        );
    }
    let poses = moving.poses(0.5).unwrap();
    assert_eq!(poses.len(), 2);
    assert_eq!(poses[0][9..], [0.5, 0.0, -0.25]);
    // An unusable motion is an error, not a panic.
    specs[0].motion = Some(MotionSpec::Spin {
        axis_point: [0.0; 3],
        axis: [0.0; 3],
        angular_velocity: 1.0,
    });
    assert!(matches!(
        obstacle_meshes(&specs, Path::new(".")),
        Err(RenderError::Obstacle { index: 0, .. })
    ));
}

/// The snapshot grid frames a moving obstacle where it stands in every cell: a sphere that has
/// moved 20 m away by the second cell is still in view there.
#[test]
fn the_snapshot_grid_keeps_a_far_moving_obstacle_in_view() {
    use crate::scene::MotionSpec;
    let mut sphere = spec(ObstacleShape::Sphere {
        center: [0.0, 0.0, 0.5],
        radius: 0.25,
    });
    sphere.motion = Some(MotionSpec::Linear {
        velocity: [20.0, 0.0, 0.0],
    });
    let obstacles = obstacle_meshes(&[sphere], Path::new(".")).unwrap();
    let cloth = FrameMesh {
        positions: vec![[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.0, 0.5, 0.0]],
        faces: vec![[0, 1, 2]],
    };
    let rows = [SnapshotRow {
        label: "r".into(),
        frames: vec![(0.0, cloth.clone()), (1.0, cloth)],
    }];
    let dir = tempfile::tempdir().unwrap();
    let grid = dir.path().join("grid.png");
    snapshot_grid(&rows, &obstacles, &grid).unwrap();
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&grid).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let (w, h) = (info.width as usize, info.height as usize);
    // Grey (the obstacle's shading: equal channels, neither white nor the rules' 215) in the
    // last cell, away from its borders.
    let grey_in_last_cell = (40..h - 5)
        .flat_map(|y| (w - 360 + 5..w - 5).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = &buf[3 * (y * w + x)..3 * (y * w + x) + 3];
            p[0] == p[1] && p[1] == p[2] && p[0] > 40 && p[0] < 210
        })
        .count();
    assert!(grey_in_last_cell > 20, "{grey_in_last_cell} grey pixels");
}
