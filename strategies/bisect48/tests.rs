//! Unit tests of the 4-8 operations (block bisection, cascades, merges, refusals, rollback) and
//! the helpers shared with the property tests (`proptests.rs`): the invariant checker and edit
//! targets that check or refuse edits.
use super::*;
use crate::adapt::{ConservingError, EditTarget, EnergyRefusal};
use crate::math::Real;
use crate::mesh::{union_jack, Edit, EditError, EditRecord, FaceId, Mesh, VertexId};
use proptest::prelude::*;
use std::collections::BTreeSet;

// ----- helpers -----

/// A union-jack grid of `cx` x `cy` cells of `cell` x `cell * aspect` m.
pub(super) fn grid(cx: usize, cy: usize, aspect: Real) -> Mesh {
    let cell = 0.25;
    union_jack(
        cx + 1,
        cy + 1,
        cell * cx as Real,
        cell * aspect * cy as Real,
    )
}

/// Faces as vertex triples rotated to start at their smallest id (orientation kept), sorted.
pub(super) fn face_set(m: &Mesh) -> BTreeSet<[VertexId; 3]> {
    m.faces()
        .map(|f| {
            let vs = m.face(f);
            let k = (0..3).min_by_key(|&k| vs[k]).unwrap();
            [vs[k], vs[(k + 1) % 3], vs[(k + 2) % 3]]
        })
        .collect()
}

/// Live vertices with their rest coordinates.
pub(super) fn vertex_set(m: &Mesh) -> Vec<(VertexId, [Real; 2])> {
    m.vertices()
        .map(|v| (v, [m.rest(v).x, m.rest(v).y]))
        .collect()
}

/// Every invariant of MODEL.md §8.4 that holds after an operation on a union-jack grid:
/// conformity, current labels, refinement edge opposite the newest vertex and (square cells)
/// strictly the longest edge, rest area halved per level, neighbours within one level, and on
/// square cells rest angles of 45/45/90 degrees.
pub(super) fn check_invariants(
    m: &Mesh,
    l: &Labels,
    cell_area: Real,
    square: bool,
) -> Result<(), String> {
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
pub(super) struct Checked<T> {
    pub(super) inner: T,
    pub(super) failures: Vec<String>,
    pub(super) edits: usize,
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
    /// Refuse as the energy law does (an edit asked under it), not as the mesh does.
    energy: bool,
}

impl EditTarget for Refusing<'_> {
    fn mesh(&self) -> &Mesh {
        self.mesh
    }

    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        self.count += 1;
        if !self.energy && self.count - 1 == self.fail_at {
            return Err(EditError::NotATiling("refused on purpose".into()));
        }
        self.mesh.replace(edit)
    }

    fn apply_conserving(&mut self, edit: &Edit) -> Result<EditRecord, ConservingError> {
        if self.energy && self.count == self.fail_at {
            self.count += 1;
            return Err(EnergyRefusal {
                gain: 1.0,
                payable: 0.0,
            }
            .into());
        }
        Ok(self.apply(edit)?)
    }
}

/// Merges every mergeable vertex, repeatedly, until none is left.
pub(super) fn merge_all(target: &mut dyn EditTarget, l: &mut Labels) -> Result<usize, String> {
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
pub(super) fn find_face(m: &Mesh, vs: [u32; 3]) -> FaceId {
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

pub(super) fn config(cases: u32) -> ProptestConfig {
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
fn edit_refused_midway_through_a_cascade_by_the_mesh_or_the_energy_law_is_rolled_back() {
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
    let refusals = (1..plan.len()).flat_map(|k| [(k, false), (k, true)]);
    for (fail_at, energy) in refusals {
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
            energy,
        };
        let err = l.bisect(&mut target, t).unwrap_err();
        if energy {
            assert!(matches!(err, OpError::AddsEnergy(_)), "{err}");
        } else {
            assert!(matches!(err, OpError::Edit(_)), "{err}");
        }
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
