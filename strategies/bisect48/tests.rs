//! Tests of the 4-8 operations: unit tests of block bisection, cascades, merges and refusals, and
//! property tests driving random sequences of `bisect(t)` / `merge(v)` on random union-jack grids,
//! checking after every operation conformity, levels, labels, rest geometry, and (through the
//! state-transfer service) mass, momentum and kinetic energy.
use super::*;
use crate::adapt::AdaptReport;
use crate::adapt::TransferOptions;
use crate::cloth::Cloth;
use crate::math::{Real, Vec3};
use crate::mesh::{union_jack, Edit, EditError, EditRecord, FaceId, Mesh, VertexId};
use crate::scene::{ForcesSpec, MaterialSpec};
use proptest::prelude::*;
use std::collections::BTreeSet;

// ----- helpers -----

/// A union-jack grid of `cx` x `cy` cells of `cell` x `cell * aspect` m.
fn grid(cx: usize, cy: usize, aspect: Real) -> Mesh {
    let cell = 0.25;
    union_jack(
        cx + 1,
        cy + 1,
        cell * cx as Real,
        cell * aspect * cy as Real,
    )
}

/// Faces as vertex triples rotated to start at their smallest id (orientation kept), sorted.
fn face_set(m: &Mesh) -> BTreeSet<[VertexId; 3]> {
    m.faces()
        .map(|f| {
            let vs = m.face(f);
            let k = (0..3).min_by_key(|&k| vs[k]).unwrap();
            [vs[k], vs[(k + 1) % 3], vs[(k + 2) % 3]]
        })
        .collect()
}

/// Live vertices with their rest coordinates.
fn vertex_set(m: &Mesh) -> Vec<(VertexId, [Real; 2])> {
    m.vertices()
        .map(|v| (v, [m.rest(v).x, m.rest(v).y]))
        .collect()
}

/// Every invariant of MODEL.md §8.4 that holds after an operation on a union-jack grid:
/// conformity, current labels, refinement edge opposite the newest vertex and (square cells)
/// strictly the longest edge, rest area halved per level, neighbours within one level, and on
/// square cells rest angles of 45/45/90 degrees.
fn check_invariants(m: &Mesh, l: &Labels, cell_area: Real, square: bool) -> Result<(), String> {
    m.check().map_err(|e| format!("conformity: {e}"))?;
    l.check(m).map_err(|e| e.to_string())?;
    for f in m.faces() {
        let label = l.label(m, f).ok_or("unlabelled face")?;
        let [a, b, c] = l.refinement(m, f).ok_or("no refinement edge")?;
        if c != label.newest || [a, b].contains(&label.newest) {
            return Err(format!(
                "face {f:?}: refinement edge not opposite the newest vertex"
            ));
        }
        let want = cell_area / 2.0 / (1u64 << label.level) as Real;
        if (m.face_rest_area(f) - want).abs() > 1e-12 * want {
            return Err(format!(
                "face {f:?} at level {} has rest area {} instead of {want}",
                label.level,
                m.face_rest_area(f)
            ));
        }
        if square {
            let hyp = m.rest_length(a, b);
            if !(hyp > m.rest_length(b, c) && hyp > m.rest_length(c, a)) {
                return Err(format!("face {f:?}: refinement edge is not the longest"));
            }
            let [pa, pb, pc] = [a, b, c].map(|v| m.rest(v));
            let angle = |p: crate::math::Vec2, q: crate::math::Vec2, r: crate::math::Vec2| {
                ((q - p).normalize().dot(&(r - p).normalize()))
                    .clamp(-1.0, 1.0)
                    .acos()
            };
            let mut angles = [angle(pa, pb, pc), angle(pb, pc, pa), angle(pc, pa, pb)];
            angles.sort_by(|x, y| x.total_cmp(y));
            let q = std::f64::consts::FRAC_PI_4;
            let want = [q, q, 2.0 * q];
            if angles.iter().zip(want).any(|(x, w)| (x - w).abs() > 1e-9) {
                return Err(format!("face {f:?} has rest angles {angles:?}"));
            }
        }
    }
    for (e, faces) in m.edges() {
        if let Some(g) = faces.second {
            let (l1, l2) = (l.label(m, faces.first), l.label(m, g));
            let (l1, l2) = (l1.ok_or("unlabelled")?.level, l2.ok_or("unlabelled")?.level);
            if l1.abs_diff(l2) > 1 {
                return Err(format!("edge {e:?}: neighbouring levels {l1} and {l2}"));
            }
        }
    }
    Ok(())
}

/// An edit target that checks conformity after every elementary edit.
struct Checked<T> {
    inner: T,
    failures: Vec<String>,
    edits: usize,
}

impl<T: EditTarget> EditTarget for Checked<T> {
    fn mesh(&self) -> &Mesh {
        self.inner.mesh()
    }

    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        let r = self.inner.apply(edit);
        if r.is_ok() {
            self.edits += 1;
            if let Err(e) = self.inner.mesh().check() {
                self.failures
                    .push(format!("after elementary edit {}: {e}", self.edits));
            }
        }
        r
    }
}

/// An edit target that refuses its `fail_at`-th edit (counting from 0).
struct Refusing<'a> {
    mesh: &'a mut Mesh,
    fail_at: usize,
    count: usize,
}

impl EditTarget for Refusing<'_> {
    fn mesh(&self) -> &Mesh {
        self.mesh
    }

    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        self.count += 1;
        if self.count - 1 == self.fail_at {
            return Err(EditError::NotATiling("refused on purpose".into()));
        }
        self.mesh.replace(edit)
    }
}

/// Merges every mergeable vertex, repeatedly, until none is left.
fn merge_all(target: &mut dyn EditTarget, l: &mut Labels) -> Result<usize, String> {
    let mut merged = 0;
    loop {
        let ready = l.mergeable_vertices(target.mesh());
        if ready.is_empty() {
            return Ok(merged);
        }
        for v in ready {
            if target.mesh().is_vertex(v) && l.is_mergeable(target.mesh(), v) {
                l.merge(target, v).map_err(|e| e.to_string())?;
                merged += 1;
            }
        }
    }
}

/// The face of `m` with the given corner ids (in any rotation).
fn find_face(m: &Mesh, vs: [u32; 3]) -> FaceId {
    m.faces()
        .find(|&f| {
            let mut a = m.face(f).map(|v| v.0);
            let mut b = vs;
            a.sort_unstable();
            b.sort_unstable();
            a == b
        })
        .expect("face exists")
}

fn config(cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(cases);
    ProptestConfig {
        cases,
        ..ProptestConfig::default()
    }
}

// ----- unit tests -----

#[test]
fn initial_union_jack_labels_are_the_diagonals() {
    for (cx, cy, aspect) in [(2, 2, 1.0), (3, 5, 1.0), (4, 3, 0.6)] {
        let m = grid(cx, cy, aspect);
        let l = Labels::new(&m, 4);
        assert!(l.is_four_eight(&m));
        let cell_area = 0.25 * 0.25 * aspect;
        check_invariants(&m, &l, cell_area, aspect == 1.0).unwrap();
        for f in m.faces() {
            let [a, b, c] = l.refinement(&m, f).unwrap();
            // The refinement edge is the cell diagonal: its ends differ in both grid coordinates.
            let (pa, pb) = (m.rest(a), m.rest(b));
            assert!(
                (pa.x - pb.x).abs() > 0.1 && (pa.y - pb.y).abs() > 0.1,
                "{f:?}"
            );
            assert_eq!(l.label(&m, f).unwrap().level, 0);
            assert_eq!(c, l.label(&m, f).unwrap().newest);
        }
    }
}

#[test]
fn diamond_bisection_makes_four_children_and_border_block_two() {
    let mut m = grid(2, 2, 1.0);
    let mut l = Labels::new(&m, 4);
    // Cell (0,0) of a 3x3-vertex grid: faces [0,1,4], [0,4,3], diagonal 0-4: a diamond.
    let t = find_face(&m, [0, 1, 4]);
    let done = l.bisect(&mut m, t).unwrap();
    assert_eq!(done.steps.len(), 1);
    let rec = &done.steps[0];
    assert_eq!(rec.removed_faces.len(), 2);
    assert_eq!(rec.added_faces.len(), 4);
    let mid = rec.added_vertices[0].0;
    assert_eq!(m.rest(mid), crate::math::Vec2::new(0.125, 0.125));
    for &f in &rec.added_faces {
        assert_eq!(
            l.label(&m, f).unwrap(),
            FaceLabel {
                newest: mid,
                level: 1
            }
        );
    }
    check_invariants(&m, &l, 0.0625, true).unwrap();
    // A child's refinement edge is a cell border edge, e.g. 0-1 on the cloth border: its block is
    // the child alone, 1 face -> 2.
    let child = rec
        .added_faces
        .iter()
        .copied()
        .find(|&f| {
            let e = l.refinement_edge(&m, f).unwrap();
            m.edge(e.0, e.1).unwrap().is_border()
        })
        .expect("a child on the border");
    let e = l.refinement_edge(&m, child).unwrap();
    assert!(m.edge(e.0, e.1).unwrap().is_border(), "{e:?}");
    let done = l.bisect(&mut m, child).unwrap();
    assert_eq!(done.steps.len(), 1);
    assert_eq!(done.steps[0].removed_faces.len(), 1);
    assert_eq!(done.steps[0].added_faces.len(), 2);
    check_invariants(&m, &l, 0.0625, true).unwrap();
}

#[test]
fn bisecting_a_fine_face_cascades_into_coarser_neighbours() {
    let mut m = grid(4, 4, 1.0);
    let mut l = Labels::new(&m, 8);
    let initial = face_set(&m);
    // Refine the face at the grid's centre three times in a row; the later bisections must first
    // bisect coarser neighbours.
    let mut longest = 0;
    let mut t = find_face(&m, [6, 7, 12]);
    for _ in 0..5 {
        let done = l.bisect(&mut m, t).unwrap();
        longest = longest.max(done.steps.len());
        check_invariants(&m, &l, 0.0625, true).unwrap();
        let last = done.steps.last().unwrap();
        t = last.added_faces[0];
    }
    assert!(longest >= 2, "no cascade seen");
    merge_all(&mut m, &mut l).unwrap();
    assert_eq!(face_set(&m), initial);
}

#[test]
fn max_level_refusal_leaves_mesh_and_labels_identical() {
    let mut m = grid(2, 2, 1.0);
    let mut l = Labels::new(&m, 2);
    let mut t = find_face(&m, [0, 1, 4]);
    for _ in 0..2 {
        let done = l.bisect(&mut m, t).unwrap();
        t = done.steps.last().unwrap().added_faces[0];
    }
    assert_eq!(l.label(&m, t).unwrap().level, 2);
    let (m0, l0) = (m.clone(), l.clone());
    let err = l.bisect(&mut m, t).unwrap_err();
    assert!(
        matches!(
            err,
            OpError::MaxLevel {
                level: 2,
                max: 2,
                ..
            }
        ),
        "{err}"
    );
    assert_eq!(m, m0);
    assert_eq!(l, l0);
}

#[test]
fn refused_edit_midway_through_a_cascade_is_rolled_back() {
    let mut m = grid(4, 4, 1.0);
    let mut l = Labels::new(&m, 8);
    // Make a face whose bisection cascades through at least two blocks.
    let mut t = find_face(&m, [6, 7, 12]);
    for _ in 0..3 {
        t = l
            .bisect(&mut m, t)
            .unwrap()
            .steps
            .last()
            .unwrap()
            .added_faces[0];
    }
    let plan = l.plan_cascade(&m, t).unwrap();
    assert!(plan.len() >= 2, "{plan:?}");
    for fail_at in 1..plan.len() {
        let (faces0, verts0) = (face_set(&m), vertex_set(&m));
        let labels_of = |m: &Mesh, l: &Labels| -> BTreeSet<([VertexId; 3], VertexId, u32)> {
            m.faces()
                .map(|f| {
                    let lab = l.label(m, f).unwrap();
                    (m.face(f), lab.newest, lab.level)
                })
                .collect()
        };
        let lab0 = labels_of(&m, &l);
        let mut target = Refusing {
            mesh: &mut m,
            fail_at,
            count: 0,
        };
        let err = l.bisect(&mut target, t).unwrap_err();
        assert!(matches!(err, OpError::Edit(_)), "{err}");
        // Same vertices and faces (slots may differ), labels current and equal per face.
        assert_eq!(face_set(&m), faces0);
        assert_eq!(vertex_set(&m), verts0);
        l.check(&m).unwrap();
        let mut a: Vec<_> = labels_of(&m, &l).into_iter().collect();
        let mut b: Vec<_> = lab0.into_iter().collect();
        let canon = |x: &mut Vec<([VertexId; 3], VertexId, u32)>| {
            for (vs, _, _) in x.iter_mut() {
                let k = (0..3).min_by_key(|&k| vs[k]).unwrap();
                *vs = [vs[k], vs[(k + 1) % 3], vs[(k + 2) % 3]];
            }
            x.sort();
        };
        canon(&mut a);
        canon(&mut b);
        assert_eq!(a, b);
        t = find_face(&m, m.face(t).map(|v| v.0));
    }
}

#[test]
fn initial_and_non_newest_vertices_are_not_mergeable() {
    let mut m = grid(3, 3, 1.0);
    let mut l = Labels::new(&m, 6);
    let m0 = m.clone();
    let err = l.merge(&mut m, VertexId(5)).unwrap_err();
    assert!(
        matches!(
            err,
            OpError::NotMergeable {
                reason: "an initial vertex",
                ..
            }
        ),
        "{err}"
    );
    assert_eq!(m, m0);
    // Insert p, then refine one of its children: p is no longer the newest vertex of its star.
    let t = find_face(&m, [5, 6, 10]);
    let p = l.bisect(&mut m, t).unwrap().steps[0].added_vertices[0].0;
    assert!(l.is_mergeable(&m, p));
    let child = m.vertex_faces(p)[0];
    l.bisect(&mut m, child).unwrap();
    let (m1, l1) = (m.clone(), l.clone());
    let err = l.merge(&mut m, p).unwrap_err();
    assert!(matches!(err, OpError::NotMergeable { .. }), "{err}");
    assert_eq!((m, l), (m1, l1));
}

#[test]
fn labels_detect_an_edit_made_behind_their_back() {
    let mut m = grid(2, 2, 1.0);
    let mut l = Labels::new(&m, 4);
    let mut other = Labels::new(&m, 4);
    let t = find_face(&m, [0, 1, 4]);
    other.bisect(&mut m, t).unwrap();
    let f = m.faces().next().unwrap();
    assert!(matches!(l.bisect(&mut m, f), Err(OpError::Labels(_))));
}

#[test]
fn longest_edge_labelling_refines_a_disk_conformingly() {
    // The disk is not a 4-8 mesh: bisection by longest-edge labels must still conform.
    let mut m = crate::mesh::disk(0.5, 4);
    let mut l = Labels::new(&m, 6);
    assert!(!l.is_four_eight(&m));
    let initial = face_set(&m);
    let mut rng = 12345u64;
    for _ in 0..300 {
        rng = rng
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let k = (rng >> 33) as usize;
        let f = m.faces().nth(k % m.face_count()).unwrap();
        match l.bisect(&mut m, f) {
            Ok(_) | Err(OpError::MaxLevel { .. }) => {}
            Err(e) => panic!("{e}"),
        }
        m.check().unwrap();
        l.check(&m).unwrap();
    }
    merge_all(&mut m, &mut l).unwrap();
    assert_eq!(face_set(&m), initial);
}

// ----- property tests -----

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
        let mut cloth = Cloth::new(mesh, x, Vec3::zeros(), &MaterialSpec::default(), &ForcesSpec::default());
        for v in cloth.mesh.vertices().collect::<Vec<_>>() {
            cloth.v[v.0 as usize] = Vec3::new(0.3 + next(), -0.2 + next(), 1.0 + next());
        }
        let mut l = Labels::new(&cloth.mesh, 5);
        let (m0, p0, e0) = (cloth.model.total_mass(), cloth.linear_momentum(), cloth.kinetic_energy());
        let area0 = cloth.mesh.pattern_area();
        let mut recorded = 0.0;
        let options = TransferOptions { obstacles: None, restore_momentum: true, restore_energy };
        for (i, (kind, pick)) in ops.into_iter().enumerate() {
            let mut target = Checked {
                inner: ClothTarget { cloth: &mut cloth, options, report: AdaptReport::default() },
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
