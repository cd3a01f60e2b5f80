//! Tests of the energy law of an edit (`energy`) and of the relaxation of new vertices (`relax`).

use super::*;
use crate::cloth::Cloth;
use crate::math::{Real, Vec2, Vec3};
use crate::mesh::{union_jack, Edit, FaceId, Mesh, NewVertex, Origin, VertexId, VertexRef};
use crate::physics::{Forces, Material};
use crate::testing;

fn options() -> TransferOptions<'static> {
    TransferOptions {
        restore_momentum: true,
        ..TransferOptions::default()
    }
}

fn total(cloth: &Cloth) -> Real {
    cloth.model.energies(&cloth.x, &cloth.v).total()
}

/// A 5x5 cloth of the default material and forces, 1 m up, randomly deformed and moving.
fn moving_cloth(seed: u64) -> Cloth {
    let mesh = union_jack(5, 5, 1.0, 1.0);
    let (mut x, v) = testing::random_state(&mesh, seed, 0.02);
    for p in &mut x {
        p.z += 1.0;
    }
    let mut cloth = testing::cloth(mesh, x);
    cloth.v = v;
    cloth
}

/// Face `f` split in three at its rest centroid.
fn centroid_split(mesh: &Mesh, f: FaceId) -> Edit {
    let [a, b, c] = mesh.face(f);
    let rest = (mesh.rest(a) + mesh.rest(b) + mesh.rest(c)) / 3.0;
    let (o, n) = (VertexRef::Old, VertexRef::New(0));
    Edit {
        remove: vec![f],
        new_vertices: vec![NewVertex {
            rest,
            origin: Origin::InTriangle {
                corners: [a, b, c],
                weights: [1.0 / 3.0; 3],
            },
        }],
        add: vec![[o(a), o(b), n], [o(b), o(c), n], [o(c), o(a), n]],
    }
}

#[test]
fn a_trial_measures_what_the_edit_does_to_the_whole_cloth() {
    for seed in 0..4 {
        let cloth = moving_cloth(seed);
        let f = cloth.mesh.faces().nth(5 + seed as usize).expect("a face");
        let edit = centroid_split(&cloth.mesh, f);
        let trial = energy_trial(&cloth, &edit, &options()).expect("valid edit");
        // The same edit on the whole cloth, new vertex where the trial relaxed it.
        let mut whole = moving_cloth(seed);
        let e0 = total(&whole);
        let t = apply_edit_with(&mut whole, &edit, &options()).expect("valid edit");
        whole.x[t.record.added_vertices[0].0 .0 as usize] = trial.positions[0];
        whole.refresh();
        let change = total(&whole) - e0;
        assert!(
            (change - trial.gain).abs() <= 1e-10 * e0.abs(),
            "seed {seed}: whole cloth {change:e} J, trial {:e} J",
            trial.gain
        );
    }
}

/// Two triangles `[A, B, C]`, `[A, C, D]` of the unit square, sheared in plane: the diagonal
/// `AC` at 70 % of its rest length (slack), the sides at rest length, so the other diagonal `BD`,
/// which no spring measures, is stretched by 23 %. Springs only.
fn sheared_quad() -> Cloth {
    let rest = vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 1.0),
    ];
    let mesh = Mesh::from_faces(rest, &[[0, 1, 2], [0, 2, 3]]).expect("valid quad");
    let s = 0.7;
    let mid = Vec3::new(s / 2.0, s / 2.0, 0.0);
    let half = (2.0 as Real).sqrt() * s / 2.0;
    let out = (1.0 - half * half).sqrt() * Vec3::new(1.0, -1.0, 0.0).normalize();
    let x = vec![Vec3::zeros(), mid + out, Vec3::new(s, s, 0.0), mid - out];
    let forces = Forces {
        springs: true,
        ..testing::no_forces()
    };
    Cloth::new(mesh, x, Vec3::zeros(), &Material::default(), &forces)
}

/// The quad's other diagonal: `[A, B, D]`, `[B, C, D]`.
fn flip() -> Edit {
    let o = |i: u32| VertexRef::Old(VertexId(i));
    Edit {
        remove: vec![FaceId(0), FaceId(1)],
        new_vertices: vec![],
        add: vec![[o(0), o(1), o(3)], [o(1), o(2), o(3)]],
    }
}

#[test]
fn an_edit_that_reveals_a_hidden_stretch_is_refused_at_rest_and_paid_in_motion() {
    let mut cloth = sheared_quad();
    let trial = energy_trial(&cloth, &flip(), &options()).expect("valid flip");
    assert!(trial.gain > 1.0, "the new diagonal is stretched: {trial:?}");
    let version = cloth.mesh.version();
    let err = apply_edit_conserving(&mut cloth, &flip(), &options()).unwrap_err();
    assert!(matches!(err, ConservingError::AddsEnergy(_)), "{err}");
    assert_eq!(
        cloth.mesh.version(),
        version,
        "a refused edit changes nothing"
    );
    // Give B and D opposite velocities holding twice the gain.
    let (m1, m3) = (cloth.model.mass()[1], cloth.model.mass()[3]);
    let w = (2.0 * trial.gain / (0.5 * (m1 + m3))).sqrt();
    cloth.v[1] = Vec3::new(0.0, 0.0, w);
    cloth.v[3] = Vec3::new(0.0, 0.0, -w * m1 / m3);
    let (e0, p0) = (total(&cloth), cloth.linear_momentum());
    let t = apply_edit_conserving(&mut cloth, &flip(), &options()).expect("payable");
    cloth.refresh();
    assert!(
        total(&cloth) <= e0 + 1e-12 * e0,
        "{e0} -> {}",
        total(&cloth)
    );
    assert!((cloth.linear_momentum() - p0).norm() <= 1e-12 * w * m1);
    assert!(t.kinetic_energy_change < -0.9 * trial.gain, "{t:?}");
}

#[test]
fn an_edit_that_adds_no_energy_is_applied_with_its_new_vertices_relaxed() {
    let mut cloth = moving_cloth(7);
    let (m0, p0, e0) = (
        cloth.model.total_mass(),
        cloth.linear_momentum(),
        total(&cloth),
    );
    let f = cloth.mesh.faces().nth(3).expect("a face");
    let edit = centroid_split(&cloth.mesh, f);
    let trial = energy_trial(&cloth, &edit, &options()).expect("valid edit");
    let t = apply_edit_conserving(&mut cloth, &edit, &options()).expect("allowed");
    cloth.refresh();
    let new = t.record.added_vertices[0].0 .0 as usize;
    assert_eq!(cloth.x[new], trial.positions[0]);
    assert!((cloth.model.total_mass() - m0).abs() <= 1e-12 * m0);
    assert!((cloth.linear_momentum() - p0).norm() <= 1e-12 * p0.norm().max(1.0));
    assert!(
        total(&cloth) <= e0 + 1e-12 * e0.abs(),
        "{e0} -> {}",
        total(&cloth)
    );
}

/// A flat 5x5 cloth at rest with springs and bending only.
fn elastic_sheet() -> Cloth {
    let forces = Forces {
        springs: true,
        bending: true,
        ..testing::no_forces()
    };
    let mesh = union_jack(5, 5, 1.0, 1.0);
    let x = testing::lifted(&mesh);
    Cloth::new(mesh, x, Vec3::zeros(), &Material::default(), &forces)
}

#[test]
fn relaxation_lowers_the_potential_and_brings_a_displaced_vertex_back() {
    let mut cloth = elastic_sheet();
    let v = VertexId(12);
    let home = cloth.x[12];
    cloth.x[12] += Vec3::new(0.05, 0.03, 0.02);
    let still = vec![Vec3::zeros(); cloth.x.len()];
    let before = cloth.model.energies(&cloth.x, &still).total();
    let decrease = relax(&mut cloth, &[v], 0.0, |_, _| false);
    let after = cloth.model.energies(&cloth.x, &still).total();
    assert!(decrease > 0.0 && (before - after - decrease).abs() <= 1e-12 * before);
    assert!(after <= 1e-6 * before, "{before} -> {after}");
    assert!((cloth.x[12] - home).norm() < 0.01, "{}", cloth.x[12] - home);
    // Held vertices do not move, and relaxing again gains little.
    assert_eq!(cloth.x[11], testing::lifted(&cloth.mesh)[11]);
    assert!(relax(&mut cloth, &[v], 0.0, |_, _| false) <= 1e-6 * before);
}

#[test]
fn relaxation_stops_once_enough_holds() {
    // Stopped once it has taken half the displaced vertex's elastic energy: at least that, yet
    // less than relaxing to the end takes.
    let displaced = || {
        let mut cloth = elastic_sheet();
        cloth.x[12] += Vec3::new(0.05, 0.03, 0.02);
        cloth
    };
    let (mut cloth, mut full) = (displaced(), displaced());
    let still = vec![Vec3::zeros(); cloth.x.len()];
    let e = cloth.model.energies(&cloth.x, &still);
    let elastic = e.stretch + e.bending;
    let stopped = relax(&mut cloth, &[VertexId(12)], 0.0, |_, decrease| {
        decrease >= 0.5 * elastic
    });
    let relaxed = relax(&mut full, &[VertexId(12)], 0.0, |_, _| false);
    assert!(stopped >= 0.5 * elastic, "{elastic}: {stopped}");
    assert!(stopped < relaxed, "{stopped} >= {relaxed}");
    // The decrease is the elastic energy's.
    let after = cloth.model.energies(&cloth.x, &still);
    let change = elastic - (after.stretch + after.bending);
    assert!(
        (change - stopped).abs() <= 1e-12 * elastic,
        "{change} vs {stopped}"
    );
}

#[test]
fn a_trial_within_the_allowance_keeps_the_interpolated_positions() {
    // A flat cloth at rest, split at a face's rest centroid: the new springs are at their rest
    // length, so the edit adds nothing and needs no relaxation.
    let mesh = union_jack(5, 5, 1.0, 1.0);
    let x = testing::lifted(&mesh);
    let mut cloth = testing::cloth(mesh, x);
    let f = cloth.mesh.faces().nth(6).expect("a face");
    let edit = centroid_split(&cloth.mesh, f);
    let corners = cloth.mesh.face(f).map(|v| cloth.x[v.0 as usize]);
    let interpolated = corners
        .iter()
        .fold(Vec3::zeros(), |s, &c| s + c * (1.0 / 3.0));
    let trial = energy_trial(&cloth, &edit, &options()).expect("valid edit");
    assert!(
        trial.gain <= trial.tolerance && trial.payment() == 0.0,
        "{trial:?}"
    );
    assert_eq!(trial.positions, vec![interpolated]);
    let e0 = total(&cloth);
    let t = apply_edit_conserving(&mut cloth, &edit, &options()).expect("allowed");
    cloth.refresh();
    assert_eq!(
        cloth.x[t.record.added_vertices[0].0 .0 as usize],
        interpolated
    );
    assert!(
        total(&cloth) <= e0 + trial.tolerance,
        "{e0} -> {}",
        total(&cloth)
    );
}

#[test]
fn relaxation_brings_two_neighbouring_displaced_vertices_back_together() {
    let mut cloth = elastic_sheet();
    let x = cloth.x.clone();
    cloth.x[12] += Vec3::new(0.05, 0.03, 0.02);
    cloth.x[13] += Vec3::new(0.04, -0.02, 0.03);
    let still = vec![Vec3::zeros(); cloth.x.len()];
    let before = cloth.model.energies(&cloth.x, &still).total();
    relax(&mut cloth, &[VertexId(13), VertexId(12)], 0.0, |_, _| false);
    let after = cloth.model.energies(&cloth.x, &still).total();
    assert!(after <= 1e-6 * before, "{before} -> {after}");
    for i in [12, 13] {
        assert!(
            (cloth.x[i] - x[i]).norm() < 0.01,
            "{i}: {}",
            cloth.x[i] - x[i]
        );
    }
}

#[test]
fn a_relaxation_that_cannot_reach_the_allowance_stops_within_a_percent_of_the_relaxed_gain() {
    // The sheared quad split at its rest centre: the new vertex's springs to B and D must
    // stretch (B and D are farther apart than their two rest halves), so the gain stays far
    // above the allowance. B lifted off the plane so the interpolated position is not the
    // minimum.
    let quad = || {
        let mut cloth = sheared_quad();
        cloth.x[1].z += 0.6;
        cloth
    };
    let cloth = quad();
    let (o, n) = (|i: u32| VertexRef::Old(VertexId(i)), VertexRef::New(0));
    let edit = Edit {
        remove: vec![FaceId(0), FaceId(1)],
        new_vertices: vec![NewVertex {
            rest: Vec2::new(0.5, 0.5),
            origin: Origin::Midpoint(VertexId(0), VertexId(2)),
        }],
        add: vec![
            [o(0), o(1), n],
            [o(1), o(2), n],
            [o(2), o(3), n],
            [o(3), o(0), n],
        ],
    };
    let trial = energy_trial(&cloth, &edit, &options()).expect("valid split");
    assert!(trial.gain > 1e6 * trial.tolerance, "{trial:?}");
    // The same edit relaxed to the end on the whole cloth.
    let mut whole = quad();
    let e0 = total(&whole);
    let t = apply_edit_with(&mut whole, &edit, &options()).expect("valid split");
    whole.refresh();
    let new = t.record.added_vertices[0].0;
    let interpolated = total(&whole) - e0;
    whole.x[new.0 as usize] = trial.positions[0];
    relax(&mut whole, &[new], 0.0, |_, _| false);
    let relaxed = total(&whole) - e0;
    assert!(relaxed < 0.99 * interpolated, "{interpolated} -> {relaxed}");
    assert!(
        trial.gain >= relaxed - 1e-12 * e0.abs() && trial.gain <= 1.01 * relaxed,
        "trial {:e} J, relaxed to the end {relaxed:e} J",
        trial.gain
    );
}
