//! Property tests of the 4-8 operations: random sequences of `bisect(t)` / `merge(v)` on random
//! union-jack grids, every invariant checked after every operation, on the bare mesh and on a
//! cloth through the state-transfer service (mass, momentum, kinetic energy).
use super::tests::{
    check_invariants, config, face_set, find_face, grid, merge_all, vertex_set, Checked,
};
use super::*;
use crate::adapt::{ClothTarget, EditTarget, TransferOptions};
use crate::math::{Real, Vec3};
use crate::mesh::{Mesh, VertexId};
use proptest::prelude::*;

/// One random operation: `kind` < 6 bisects face `pick`; otherwise merges a mergeable vertex
/// (kind 6-8) or tries an arbitrary vertex (kind 9), which must fail cleanly when not mergeable.
fn random_op(
    target: &mut dyn EditTarget,
    l: &mut Labels,
    kind: u8,
    pick: u32,
) -> Result<(), TestCaseError> {
    let m = target.mesh();
    if kind < 6 {
        let f = m.faces().nth(pick as usize % m.face_count()).unwrap();
        let (m0, l0) = (m.clone(), l.clone());
        match l.bisect(target, f) {
            Ok(done) => prop_assert!(!done.steps.is_empty()),
            Err(OpError::MaxLevel { .. }) => {
                prop_assert!(*target.mesh() == m0, "refused bisection changed the mesh");
                prop_assert!(*l == l0, "refused bisection changed the labels");
            }
            Err(e) => return Err(TestCaseError::fail(format!("bisect {f:?}: {e}"))),
        }
        return Ok(());
    }
    let ready = l.mergeable_vertices(m);
    let v = if kind < 9 && !ready.is_empty() {
        ready[pick as usize % ready.len()]
    } else {
        m.vertices().nth(pick as usize % m.vertex_count()).unwrap()
    };
    let (m0, l0) = (m.clone(), l.clone());
    let mergeable = ready.contains(&v);
    match l.merge(target, v) {
        Ok(rec) => {
            prop_assert!(mergeable, "merged {v:?} not listed as mergeable");
            prop_assert_eq!(rec.removed_vertices, vec![v]);
        }
        Err(OpError::NotMergeable { .. }) => {
            prop_assert!(!mergeable, "mergeable {v:?} refused");
            prop_assert!(*target.mesh() == m0, "refused merge changed the mesh");
            prop_assert!(*l == l0, "refused merge changed the labels");
        }
        Err(e) => return Err(TestCaseError::fail(format!("merge {v:?}: {e}"))),
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(24))]

    /// Random grids (2x2 to 8x8 cells, square or not), 200+ random bisect/merge operations:
    /// every invariant after every operation (conformity also after every elementary edit of a
    /// cascade); merging everything mergeable then returns the initial mesh and labels.
    #[test]
    fn bisect48_random_operations_keep_every_invariant(
        cx in 2usize..=8,
        cy in 2usize..=8,
        square in any::<bool>(),
        max_level in 3u32..=6,
        ops in proptest::collection::vec((0u8..10, any::<u32>()), 200..=240),
    ) {
        let aspect = if square { 1.0 } else { 0.6 };
        let mesh = grid(cx, cy, aspect);
        let cell_area = 0.0625 * aspect;
        let (faces0, verts0) = (face_set(&mesh), vertex_set(&mesh));
        let area0 = mesh.pattern_area();
        let mut l = Labels::new(&mesh, max_level);
        let labels0 = l.clone();
        let mut target = Checked { inner: mesh, failures: Vec::new(), edits: 0 };
        for (i, (kind, pick)) in ops.into_iter().enumerate() {
            random_op(&mut target, &mut l, kind, pick)?;
            prop_assert!(target.failures.is_empty(), "op {i}: {:?}", target.failures);
            let m = &target.inner;
            if let Err(e) = check_invariants(m, &l, cell_area, square) {
                return Err(TestCaseError::fail(format!("op {i}: {e}")));
            }
            let area: Real = m.faces().map(|f| m.face_rest_area(f)).sum();
            prop_assert!((area - area0).abs() <= 1e-12 * area0, "op {i}: area {area} vs {area0}");
        }
        merge_all(&mut target, &mut l).map_err(TestCaseError::fail)?;
        prop_assert!(target.failures.is_empty(), "{:?}", target.failures);
        let m = &target.inner;
        prop_assert_eq!(face_set(m), faces0);
        prop_assert_eq!(vertex_set(m), verts0);
        // The labels are the initial ones again (face slots may differ: compare per triple).
        for f in m.faces() {
            let g = labels0_face(&labels0, &grid(cx, cy, aspect), m.face(f));
            prop_assert_eq!(l.label(m, f), Some(g));
        }
    }

    /// The same random operations on a cloth through the state-transfer service: total mass and
    /// rest area unchanged (1e-12), linear momentum unchanged (1e-12), the recorded kinetic-energy
    /// changes add up to the actual change, and with `restore_energy` the kinetic energy is
    /// unchanged (1e-9).
    #[test]
    fn bisect48_transfer_conserves_mass_momentum_and_energy(
        cx in 2usize..=8,
        cy in 2usize..=8,
        restore_energy in any::<bool>(),
        seed in any::<u64>(),
        ops in proptest::collection::vec((0u8..10, any::<u32>()), 200..=220),
    ) {
        let mesh = grid(cx, cy, 1.0);
        let mut rng = seed | 1;
        let mut next = move || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as Real / (1u64 << 53) as Real - 0.5
        };
        let x: Vec<Vec3> = mesh
            .vertices()
            .map(|v| {
                let p = mesh.rest(v);
                Vec3::new(p.x, p.y, 0.05 * next())
            })
            .collect();
        let mut cloth = crate::testing::cloth(mesh, x);
        for v in cloth.mesh.vertices().collect::<Vec<_>>() {
            cloth.v[v.0 as usize] = Vec3::new(0.3 + next(), -0.2 + next(), 1.0 + next());
        }
        let mut l = Labels::new(&cloth.mesh, 5);
        let (m0, p0, e0) = (cloth.model.total_mass(), cloth.linear_momentum(), cloth.kinetic_energy());
        let area0 = cloth.mesh.pattern_area();
        let mut recorded = 0.0;
        let options = TransferOptions { obstacles: None, restore_momentum: true, restore_energy, refuse_crossings: false, crossing_guard: None };
        for (i, (kind, pick)) in ops.into_iter().enumerate() {
            let mut target = Checked {
                inner: ClothTarget::new(&mut cloth, options),
                failures: Vec::new(),
                edits: 0,
            };
            random_op(&mut target, &mut l, kind, pick)?;
            prop_assert!(target.failures.is_empty(), "op {i}: {:?}", target.failures);
            recorded += target.inner.report.kinetic_energy_change;
            cloth.refresh();
            let m = &cloth.mesh;
            if let Err(e) = check_invariants(m, &l, 0.0625, true) {
                return Err(TestCaseError::fail(format!("op {i}: {e}")));
            }
            let area: Real = m.faces().map(|f| m.face_rest_area(f)).sum();
            prop_assert!((area - area0).abs() <= 1e-12 * area0, "op {i}: area");
            let mass = cloth.model.total_mass();
            prop_assert!((mass - m0).abs() <= 1e-12 * m0, "op {i}: mass {m0} -> {mass}");
            let p = cloth.linear_momentum();
            prop_assert!((p - p0).norm() <= 1e-12 * p0.norm(), "op {i}: momentum {p0} -> {p}");
            let e = cloth.kinetic_energy();
            prop_assert!(
                (e - e0 - recorded).abs() <= 1e-12 * e0,
                "op {i}: energy change {} but recorded {recorded}", e - e0
            );
            if restore_energy {
                prop_assert!((e - e0).abs() <= 1e-9 * e0, "op {i}: energy {e0} -> {e}");
            }
        }
    }
}

/// The initial label of the face with corners `vs` on a fresh grid.
fn labels0_face(l0: &Labels, m0: &Mesh, vs: [VertexId; 3]) -> FaceLabel {
    let f = find_face(m0, vs.map(|v| v.0));
    l0.label(m0, f).expect("initial face labelled")
}
