use super::geometry::{closest_between_segments, closest_on_triangle, coplanar_times};
use super::tree::FaceTree;
use super::*;
use crate::collision::self_intersections;
use crate::testing::pieces_pattern;
use proptest::prelude::*;

/// A flat square sheet of `n x n` vertices, side `size` (m), at height `z` (m), shifted by
/// `(dx, dy)`; vertex slots start at `first`. Returns positions and faces.
fn sheet(n: usize, size: Real, z: Real, (dx, dy): (Real, Real), first: usize) -> Sheet {
    let h = size / (n - 1) as Real;
    let x = (0..n * n)
        .map(|k| Vec3::new(dx + (k % n) as Real * h, dy + (k / n) as Real * h, z))
        .collect();
    let mut faces = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = first + j * n + i;
            faces.push([a, a + 1, a + n + 1]);
            faces.push([a, a + n + 1, a + n]);
        }
    }
    Sheet { x, faces }
}

struct Sheet {
    x: Vec<Vec3>,
    faces: Vec<[usize; 3]>,
}

/// Every edge of `faces` once (vertex slots).
fn edges_of(faces: &[[usize; 3]]) -> Vec<[usize; 2]> {
    let mut edges: Vec<[usize; 2]> = faces
        .iter()
        .flat_map(|f| (0..3).map(move |k| [f[k].min(f[(k + 1) % 3]), f[k].max(f[(k + 1) % 3])]))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Two 6 x 6 sheets of side 0.5 m: the lower at rest at z = 0, the upper `gap` (m) above and
/// shifted by a fraction of a cell so no vertex sits over another, moving down at `speed` (m/s).
fn two_sheets(gap: Real, speed: Real) -> (Vec<Vec3>, Vec<Vec3>, Vec<[usize; 3]>) {
    let lower = sheet(6, 0.5, 0.0, (0.0, 0.0), 0);
    let upper = sheet(6, 0.5, gap, (0.037, 0.021), 36);
    let x: Vec<Vec3> = lower.x.iter().chain(&upper.x).copied().collect();
    let v = (0..72)
        .map(|i| Vec3::new(0.0, 0.0, if i < 36 { 0.0 } else { -speed }))
        .collect();
    let faces = lower.faces.iter().chain(&upper.faces).copied().collect();
    (x, v, faces)
}

/// Takes one step of `dt` (s) of free motion with velocities `v` and runs the self-contact pass
/// (thickness `h`, friction 0.3, unit masses); returns the end positions, velocities and stats.
fn step(
    x: &[Vec3],
    v: &[Vec3],
    faces: &[[usize; 3]],
    h: Real,
    dt: Real,
) -> (Vec<Vec3>, Vec<Vec3>, SelfContactStats) {
    let mut x_end: Vec<Vec3> = x.iter().zip(v).map(|(p, u)| p + u * dt).collect();
    let mut v_end = v.to_vec();
    let inv_mass = vec![1.0; x.len()];
    let mut contact = SelfContact::new(h);
    let stats = contact.respond(
        0,
        faces.iter().copied(),
        &pieces_pattern(x, faces),
        x,
        &mut x_end,
        Some(&mut v_end),
        &inv_mass,
        0.3,
        dt,
    );
    (x_end, v_end, stats)
}

#[test]
fn two_sheets_meeting_at_five_metres_a_second_do_not_pass_through() {
    // The upper sheet starts 1 cm above and moves 5 cm in the step: without the swept test it
    // ends 4 cm below the lower one, passed through it whole (which leaves no crossing to
    // count at the step's end: only the swept test sees it).
    let (x, v, faces) = two_sheets(0.01, 5.0);
    let edges = edges_of(&faces);
    let free: Vec<Vec3> = x.iter().zip(&v).map(|(p, u)| p + u * 0.01).collect();
    // The part of the upper sheet over the lower one, against the lower one: mean heights.
    let upper_above = |y: &[Vec3]| {
        let over: Vec<Real> = y[36..]
            .iter()
            .filter(|p| p.x < 0.5 && p.y < 0.5)
            .map(|p| p.z)
            .collect();
        let lower = y[..36].iter().map(|p| p.z).sum::<Real>() / 36.0;
        over.iter().sum::<Real>() / over.len() as Real > lower
    };
    assert!(!upper_above(&free));
    let (x_end, _, stats) = step(&x, &v, &faces, 2e-3, 0.01);
    assert!(stats.crossings > 0, "{stats:?}");
    assert_eq!(self_intersections(&x_end, &faces, &edges), 0, "{stats:?}");
    assert!(upper_above(&x_end), "{stats:?}");
}

#[test]
fn self_contact_keeps_linear_momentum() {
    // Unit masses, no pinned vertex: every impulse and every rigid zone keeps the sum of
    // velocities (the end velocities; and the step's mean velocities, through the positions).
    let (x, v, faces) = two_sheets(0.01, 5.0);
    let dt = 0.01;
    let (x_end, v_end, _) = step(&x, &v, &faces, 2e-3, dt);
    let before: Vec3 = v.iter().sum();
    let after: Vec3 = v_end.iter().sum();
    assert!(
        (after - before).norm() < 1e-9 * before.norm(),
        "{before} {after}"
    );
    let mean_after: Vec3 = x_end.iter().zip(&x).map(|(e, s)| (e - s) / dt).sum();
    assert!((mean_after - before).norm() < 1e-9 * before.norm());
}

#[test]
fn a_pair_closer_than_the_thickness_stops_approaching() {
    // The upper sheet 1 mm above (thickness 2 mm), moving down slowly: after the pass no
    // vertex-face pair closes in, and the sheets move apart.
    let (x, v, faces) = two_sheets(1e-3, 0.01);
    let dt = 1e-3;
    let (x_end, _, stats) = step(&x, &v, &faces, 2e-3, dt);
    assert!(stats.proximities > 0);
    let mean_z = |r: std::ops::Range<usize>| {
        let n = r.len() as Real;
        x_end[r].iter().map(|p| p.z).sum::<Real>() / n
    };
    assert!(mean_z(36..72) - mean_z(0..36) > 1e-3, "the gap shrank");
}

#[test]
fn a_cloth_thicker_than_its_triangles_is_not_its_own_contact() {
    // A flat 9 x 9 sheet of side 0.5 m: its right triangles are 4.4 cm high over their long
    // side, so at a thickness of 5 cm each vertex is closer than the thickness to faces it is
    // not a corner of. Those pairs are one piece of cloth in the rest pattern: no repulsion, and
    // the sheet ends where its own motion takes it (it was pushed apart before).
    let sheet = sheet(9, 0.5, 0.0, (0.0, 0.0), 0);
    let v: Vec<Vec3> = (0..sheet.x.len())
        .map(|i| Vec3::new(0.0, 0.0, 0.01 * (i % 3) as Real))
        .collect();
    let dt = 1e-3;
    let free: Vec<Vec3> = sheet.x.iter().zip(&v).map(|(p, u)| p + u * dt).collect();
    let (x_end, _, stats) = step(&sheet.x, &v, &sheet.faces, 0.05, dt);
    assert_eq!(stats.proximities, 0, "{stats:?}");
    assert_eq!(x_end, free);
    // The same sheet folded onto a copy of itself 1 cm above (another piece of the pattern):
    // the layers are closer than the thickness, and pushed apart.
    let upper = sheet_above(&sheet, 0.01);
    let (x, faces) = (upper.0, upper.1);
    let v = vec![Vec3::zeros(); x.len()];
    let (_, _, stats) = step(&x, &v, &faces, 0.05, dt);
    assert!(stats.proximities > 0, "{stats:?}");
}

/// `sheet` and a copy of it `gap` (m) above, slots after the sheet's: positions and faces.
fn sheet_above(sheet: &Sheet, gap: Real) -> (Vec<Vec3>, Vec<[usize; 3]>) {
    let n = sheet.x.len();
    let x = sheet
        .x
        .iter()
        .copied()
        .chain(sheet.x.iter().map(|p| p + Vec3::new(0.0, 0.0, gap)))
        .collect();
    let faces = sheet
        .faces
        .iter()
        .copied()
        .chain(sheet.faces.iter().map(|f| f.map(|i| i + n)))
        .collect();
    (x, faces)
}

#[test]
fn pinned_vertices_never_move() {
    let (x, v, faces) = two_sheets(0.01, 5.0);
    let dt = 0.01;
    let mut x_end: Vec<Vec3> = x.iter().zip(&v).map(|(p, u)| p + u * dt).collect();
    let mut v_end = v.clone();
    // The lower sheet pinned: the upper one takes the whole response.
    let inv_mass: Vec<Real> = (0..72).map(|i| if i < 36 { 0.0 } else { 1.0 }).collect();
    let mut contact = SelfContact::new(2e-3);
    contact.respond(
        0,
        faces.iter().copied(),
        &pieces_pattern(&x, &faces),
        &x,
        &mut x_end,
        Some(&mut v_end),
        &inv_mass,
        0.3,
        dt,
    );
    assert_eq!(&x_end[..36], &x[..36]);
    assert_eq!(self_intersections(&x_end, &faces, &edges_of(&faces)), 0);
}

#[test]
fn impact_zones_move_rigidly_and_keep_momentum() {
    // Four vertices in one zone, with different velocities: after the move their distances are
    // those at the start and their momentum is the one they had.
    let x_start = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.2, 0.3, 0.5),
    ];
    let v0 = [
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(0.5, 0.5, 0.5),
    ];
    let dt = 0.1;
    let mut x: Vec<Vec3> = x_start.iter().zip(&v0).map(|(p, u)| p + u * dt).collect();
    let mut v = v0.to_vec();
    let inv_mass = [1.0, 0.5, 2.0, 1.0];
    let mut zones = zones::Zones::default();
    zones.reset(4);
    for k in 1..4 {
        zones.union(0, k);
    }
    let moved = zones.move_rigidly(&[0, 1, 2, 3], &x_start, &mut x, Some(&mut v), &inv_mass, dt);
    assert_eq!(moved, 4);
    for i in 0..4 {
        for j in 0..4 {
            let (d0, d1) = ((x_start[i] - x_start[j]).norm(), (x[i] - x[j]).norm());
            assert!((d0 - d1).abs() < 1e-12, "{i} {j}: {d0} {d1}");
        }
    }
    let momentum = |u: &[Vec3]| -> Vec3 { (0..4).map(|i| u[i] / inv_mass[i]).sum() };
    assert!((momentum(&v) - momentum(&v0)).norm() < 1e-12);
}

#[test]
fn coplanar_times_find_a_point_crossing_a_plane() {
    // A point from z = 1 to z = -1 through the plane z = 0 of a still triangle: t = 0.5.
    let x0 = [
        Vec3::new(0.2, 0.2, 1.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let dx = [
        Vec3::new(0.0, 0.0, -2.0),
        Vec3::zeros(),
        Vec3::zeros(),
        Vec3::zeros(),
    ];
    let (t, n) = coplanar_times(x0, dx);
    assert_eq!(n, 1);
    assert!((t[0] - 0.5).abs() < 1e-12);
    // Moving away: no root.
    let away = [
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::zeros(),
        Vec3::zeros(),
        Vec3::zeros(),
    ];
    assert_eq!(coplanar_times(x0, away).1, 0);
}

/// Points in the cube [-1, 1]^3.
fn point() -> impl Strategy<Value = Vec3> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0).prop_map(|(a, b, c)| Vec3::new(a, b, c))
}

proptest! {
    /// The closest point on a triangle is no farther than any sampled point of it.
    #[test]
    fn closest_on_triangle_beats_every_sample(p in point(), a in point(), b in point(), c in point()) {
        let w = closest_on_triangle(p, a, b, c);
        prop_assert!((w.iter().sum::<Real>() - 1.0).abs() < 1e-9);
        prop_assert!(w.iter().all(|&wi| wi >= -1e-12));
        let d = (p - (a * w[0] + b * w[1] + c * w[2])).norm();
        for i in 0..=20 {
            for j in 0..=20 - i {
                let (u, v) = (i as Real / 20.0, j as Real / 20.0);
                let q = a * (1.0 - u - v) + b * u + c * v;
                prop_assert!(d <= (p - q).norm() + 1e-9);
            }
        }
    }

    /// The closest points of two segments are no farther apart than any sampled pair.
    #[test]
    fn closest_between_segments_beats_every_sample(p1 in point(), q1 in point(), p2 in point(), q2 in point()) {
        let (s, t) = closest_between_segments(p1, q1, p2, q2);
        let at = |p: Vec3, q: Vec3, s: Real| p + (q - p) * s;
        let d = (at(p1, q1, s) - at(p2, q2, t)).norm();
        for i in 0..=40 {
            for j in 0..=40 {
                let e = (at(p1, q1, i as Real / 40.0) - at(p2, q2, j as Real / 40.0)).norm();
                prop_assert!(d <= e + 1e-9);
            }
        }
    }

    /// The tree's face pairs are exactly the pairs whose boxes meet.
    #[test]
    fn the_tree_finds_every_meeting_pair(coords in prop::collection::vec(-1.0f64..1.0, 3 * 20), pad in 0.0f64..0.2) {
        let x: Vec<Vec3> = coords.chunks(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
        let faces: Vec<[usize; 3]> = (0..18).map(|k| [k, k + 1, (k + 2) % 20]).collect();
        let mut tree = FaceTree::default();
        tree.set_faces(faces.iter().copied());
        tree.update(&x, &x, pad);
        // A refit with the same boxes finds the same pairs as the build.
        tree.update(&x, &x, pad);
        tree.find_pairs();
        let mut found: Vec<(usize, usize)> =
            tree.pairs.iter().map(|&(a, b)| (a.min(b), a.max(b))).collect();
        found.sort_unstable();
        let mut all = Vec::new();
        for a in 0..faces.len() {
            for b in a + 1..faces.len() {
                if tree::overlap(&tree.boxes[a], &tree.boxes[b]) {
                    all.push((a, b));
                }
            }
        }
        prop_assert_eq!(found, all);
    }

    /// A sheet thrown through another at any speed up to 10 m/s, from any offset, ends with no
    /// crossing.
    #[test]
    fn thrown_sheets_never_end_crossed(
        speed in 0.0f64..10.0,
        gap in 3e-3f64..0.05,
        dx in -0.2f64..0.2,
        tilt in -2.0f64..2.0,
    ) {
        let (mut x, mut v, faces) = two_sheets(gap, speed);
        for i in 36..72 {
            x[i].x += dx;
            v[i].z -= tilt * (x[i].x - 0.25);
        }
        let (x_end, _, stats) = step(&x, &v, &faces, 2e-3, 0.01);
        prop_assert_eq!(self_intersections(&x_end, &faces, &edges_of(&faces)), 0, "{:?}", stats);
    }
}

#[test]
fn a_point_ending_in_a_face_is_sent_back_to_its_side() {
    // A triangle's corner falling onto a still face and ending exactly in its plane (as an
    // obstacle's push to the margin can leave two layers): it ends back on its side,
    // CCD_SEPARATION h off the face, however the plane's height rounds.
    let h = 2e-3;
    for k in 0..200 {
        let z_face = 1e-3 + 0.00731 * k as Real;
        let tilt = 1e-3 * (k % 7) as Real;
        let x = vec![
            Vec3::new(0.25 + 0.001 * (k % 13) as Real, 0.25, z_face + 2.1e-3),
            Vec3::new(0.0, 0.0, z_face),
            Vec3::new(1.0, 0.0, z_face + tilt),
            Vec3::new(0.0, 1.0, z_face),
            Vec3::new(0.6, 0.25, z_face + 0.05),
            Vec3::new(0.6, 0.35, z_face + 0.05),
        ];
        // Everything slides by `shift`; the corner ends on the face's plane, up to rounding.
        let shift = Vec3::new(1e-3 / 3.0, 1e-3 / 7.0, 0.0);
        let mut x_end: Vec<Vec3> = x.iter().map(|p| p + shift).collect();
        x_end[0].z = z_face + tilt * x_end[0].x;
        let mut v = vec![Vec3::zeros(); 6];
        let mut contact = SelfContact::new(h);
        let faces = [[1, 2, 3], [0, 4, 5]];
        let inv_mass = [1.0, 1.0, 1.0, 1.0, 0.0, 0.0];
        let stats = contact.respond(
            0,
            faces.iter().copied(),
            &pieces_pattern(&x, &faces),
            &x,
            &mut x_end,
            Some(&mut v),
            &inv_mass,
            0.0,
            1e-3,
        );
        let gap = x_end[0].z - x_end[1].z;
        assert!(
            gap >= 0.99 * CCD_SEPARATION * h,
            "{z_face}: gap {gap} {stats:?}"
        );
    }
}
