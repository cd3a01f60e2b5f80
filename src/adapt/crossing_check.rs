//! Whether a mesh edit would make the cloth cross itself: the check behind
//! [`super::TransferOptions::refuse_crossings`], so that with self-collision on no adaptation
//! creates a crossing the step's swept test could never undo (it assumes a start free of them).

use crate::cloth::Cloth;
use crate::collision::{bounds, segment_crosses_triangle, FaceGrid};
use crate::math::{Real, Vec3};
use crate::mesh::{Edit, EditRecord, FaceId, VertexId, VertexRef};
use std::collections::HashMap;

/// A vertex of the edited mesh: an old vertex slot, or a new vertex (`usize::MAX - k` for new
/// vertex `k`), so the two never collide.
type Key = usize;

/// Whether applying `edit` to `cloth`, with new vertex `k` at `new_positions[k]` (m), would give
/// an edge crossing a face it shares no vertex with ([`segment_crosses_triangle`]): the new
/// edges against the faces that stay and the new faces, and the edges of the faces that stay
/// against the new faces. Faces that stay are tested only when their box meets the new faces'
/// box, so the check costs one pass over the faces' boxes plus the few pairs near the edit; over
/// a sequence of edits a [`CrossingGuard`] answers the same without the pass.
pub fn edit_crosses(cloth: &Cloth, edit: &Edit, new_positions: &[Vec3]) -> bool {
    let Some(shape) = EditShape::new(cloth, edit, new_positions) else {
        return false;
    };
    let mesh = &cloth.mesh;
    // The box first: most faces are far from the edit.
    shape.new_pairs_cross()
        || mesh.faces().any(|id| {
            let f = mesh.face(id).map(|v| v.0 as usize);
            shape.kept_face_crosses(id, f, &bounds(&f.map(|k| cloth.x[k])))
        })
}

/// [`edit_crosses`], through `guard` when there is one.
pub(super) fn edit_crosses_with(
    guard: Option<&CrossingGuard>,
    cloth: &Cloth,
    edit: &Edit,
    new_positions: &[Vec3],
) -> bool {
    match guard {
        Some(g) => g.edit_crosses(cloth, edit, new_positions),
        None => edit_crosses(cloth, edit, new_positions),
    }
}

/// The faces of a cloth when an adaptation pass starts, in a grid of their boxes
/// ([`FaceGrid`]), and the faces the pass has added since, hashed by their boxes
/// ([`AddedFaces`]): [`CrossingGuard::edit_crosses`] answers as [`edit_crosses`] does, looking
/// only at the faces near the edit.
///
/// Contract: the vertices the cloth had when the guard was built do not move while it is used;
/// every edit applied to the cloth is passed to [`CrossingGuard::applied`], and a vertex an edit
/// added that moves afterwards is passed to [`CrossingGuard::moved`] (as
/// [`super::ClothTarget::place`] does).
pub struct CrossingGuard {
    grid: FaceGrid,
    /// The faces listed in the grid (numbered as there) and their vertex slots at the start.
    start_faces: Vec<(FaceId, [usize; 3])>,
    /// Faces added by the edits applied since.
    added: AddedFaces,
}

impl CrossingGuard {
    /// The guard over `cloth` as it is now (faces with a non-finite position cross nothing and
    /// are left out).
    pub fn new(cloth: &Cloth) -> CrossingGuard {
        let mesh = &cloth.mesh;
        let finite = |k: usize| cloth.x[k].iter().all(|c| c.is_finite());
        let start_faces: Vec<(FaceId, [usize; 3])> = mesh
            .faces()
            .map(|id| (id, mesh.face(id).map(|v| v.0 as usize)))
            .filter(|(_, f)| f.iter().all(|&k| finite(k)))
            .collect();
        let slots: Vec<[usize; 3]> = start_faces.iter().map(|&(_, f)| f).collect();
        let listed: Vec<usize> = (0..slots.len()).collect();
        let grid = FaceGrid::new(&cloth.x, &slots, &listed);
        CrossingGuard {
            added: AddedFaces::new(grid.cell_size()),
            grid,
            start_faces,
        }
    }

    /// Records an edit applied to `cloth`: its new faces are tested from now on.
    pub fn applied(&mut self, cloth: &Cloth, record: &EditRecord) {
        for &id in &record.added_faces {
            self.added.all.push(id);
            self.added.insert(id, face_box(cloth, id));
        }
    }

    /// Records that vertex `v`, added by an edit since the guard was built, moved: the faces
    /// around it are hashed again at their boxes now.
    pub fn moved(&mut self, cloth: &Cloth, v: VertexId) {
        for &id in cloth.mesh.vertex_faces(v) {
            self.added.insert(id, face_box(cloth, id));
        }
    }

    /// [`edit_crosses`] for the cloth the guard follows.
    pub fn edit_crosses(&self, cloth: &Cloth, edit: &Edit, new_positions: &[Vec3]) -> bool {
        let Some(shape) = EditShape::new(cloth, edit, new_positions) else {
            return false;
        };
        if shape.new_pairs_cross() {
            return true;
        }
        let mesh = &cloth.mesh;
        let mut found = false;
        // A listed face still in the mesh as it was (a face id may be reused: the new face is
        // among the added ones).
        self.grid
            .visit_overlapping(shape.region.0, shape.region.1, |k| {
                let (id, f) = self.start_faces[k];
                found = found
                    || (mesh.is_face(id)
                        && mesh.face(id).map(|v| v.0 as usize) == f
                        && shape.kept_face_crosses(id, f, &face_box(cloth, id)));
            });
        found
            || self.added.any_near(&shape.region, |id| {
                mesh.is_face(id) && {
                    let f = mesh.face(id).map(|v| v.0 as usize);
                    shape.kept_face_crosses(id, f, &face_box(cloth, id))
                }
            })
    }
}

/// Most cells a face is hashed into: a face whose box spans more is tested at every check.
const MAX_FACE_CELLS: Real = 64.0;

/// Most cells a check looks up: an edit whose box spans more tests every added face.
const MAX_REGION_CELLS: Real = 4096.0;

/// The faces a pass added, hashed by the cubic cells (edge `cell`, m) their boxes met when they
/// were hashed. An entry may be stale (its face since removed, its id reused, its vertex
/// moved and hashed again elsewhere): a check tests each candidate at its current box, so a stale
/// entry costs a test and hides nothing.
struct AddedFaces {
    cell: Real,
    /// Every face added, in order.
    all: Vec<FaceId>,
    cells: HashMap<[i64; 3], Vec<FaceId>>,
    /// Faces whose box spans more than [`MAX_FACE_CELLS`] cells.
    wide: Vec<FaceId>,
}

impl AddedFaces {
    fn new(cell: Real) -> AddedFaces {
        AddedFaces {
            cell,
            all: Vec::new(),
            cells: HashMap::new(),
            wide: Vec::new(),
        }
    }

    /// The lowest and highest cells of box `b`, and how many cells that range holds (a float:
    /// huge or non-finite boxes give huge counts, never an overflow).
    fn cells_of(&self, b: &Bounds) -> ([i64; 3], [i64; 3], Real) {
        let cell = |p: Vec3| [0, 1, 2].map(|k| (p[k] / self.cell).floor() as i64);
        let (lo, hi) = (cell(b.0), cell(b.1));
        let count = (0..3)
            .map(|k| hi[k].saturating_sub(lo[k]) as Real + 1.0)
            .product::<Real>();
        (lo, hi, if count.is_finite() { count } else { Real::MAX })
    }

    /// Hashes face `id` at its box `b` (m).
    fn insert(&mut self, id: FaceId, b: Bounds) {
        let (lo, hi, count) = self.cells_of(&b);
        if !(1.0..=MAX_FACE_CELLS).contains(&count) {
            self.wide.push(id);
            return;
        }
        for_each_cell(lo, hi, |c| self.cells.entry(c).or_default().push(id));
    }

    /// Whether `test` holds for a face hashed in a cell that the box `region` meets (or for any
    /// added face, when the region spans too many cells); a face may be tested more than once.
    fn any_near(&self, region: &Bounds, mut test: impl FnMut(FaceId) -> bool) -> bool {
        let (lo, hi, count) = self.cells_of(region);
        if !(1.0..=MAX_REGION_CELLS).contains(&count) {
            return self.all.iter().any(|&id| test(id));
        }
        let mut found = self.wide.iter().any(|&id| test(id));
        for_each_cell(lo, hi, |c| {
            found = found
                || self
                    .cells
                    .get(&c)
                    .is_some_and(|ids| ids.iter().any(|&id| test(id)));
        });
        found
    }
}

/// Calls `f` for every cell from `lo` to `hi` (a range of at most a few thousand cells).
fn for_each_cell(lo: [i64; 3], hi: [i64; 3], mut f: impl FnMut([i64; 3])) {
    for k in lo[2]..=hi[2] {
        for j in lo[1]..=hi[1] {
            for i in lo[0]..=hi[0] {
                f([i, j, k]);
            }
        }
    }
}

/// The box of the cloth's face `id` (m).
fn face_box(cloth: &Cloth, id: FaceId) -> Bounds {
    bounds(&cloth.mesh.face(id).map(|v| cloth.x[v.0 as usize]))
}

/// An edit's new faces and edges, at the positions they would take, with their boxes.
struct EditShape<'a> {
    cloth: &'a Cloth,
    new_positions: &'a [Vec3],
    new_faces: Vec<[Key; 3]>,
    face_boxes: Vec<Bounds>,
    new_edges: Vec<[Key; 2]>,
    edge_boxes: Vec<Bounds>,
    /// The box of the new faces.
    region: Bounds,
    /// The faces the edit removes, sorted.
    removed: Vec<FaceId>,
}

impl<'a> EditShape<'a> {
    /// `None` when the edit adds no face.
    fn new(cloth: &'a Cloth, edit: &Edit, new_positions: &'a [Vec3]) -> Option<EditShape<'a>> {
        let new_faces: Vec<[Key; 3]> = edit.add.iter().map(|f| f.map(key)).collect();
        let first = *new_faces.first()?;
        let at = |k: Key| position(cloth, new_positions, k);
        let mut new_edges: Vec<[Key; 2]> = new_faces
            .iter()
            .flat_map(|f| (0..3).map(move |i| sorted(f[i], f[(i + 1) % 3])))
            .collect();
        new_edges.sort_unstable();
        new_edges.dedup();
        let mut region = (at(first[0]), at(first[0]));
        for &k in new_faces.iter().flatten() {
            region = (region.0.inf(&at(k)), region.1.sup(&at(k)));
        }
        let mut removed = edit.remove.clone();
        removed.sort_unstable();
        Some(EditShape {
            cloth,
            new_positions,
            face_boxes: new_faces.iter().map(|f| bounds(&f.map(at))).collect(),
            edge_boxes: new_edges.iter().map(|e| bounds(&e.map(at))).collect(),
            new_faces,
            new_edges,
            region,
            removed,
        })
    }

    fn at(&self, k: Key) -> Vec3 {
        position(self.cloth, self.new_positions, k)
    }

    /// Whether `edge` crosses `face`: their boxes meet (the test is strict), they share no
    /// vertex, and the segment passes through the triangle.
    fn crosses(
        &self,
        edge: [Key; 2],
        edge_box: &Bounds,
        face: [Key; 3],
        face_box: &Bounds,
    ) -> bool {
        overlap(edge_box, face_box)
            && !face.contains(&edge[0])
            && !face.contains(&edge[1])
            && segment_crosses_triangle(
                self.at(edge[0]),
                self.at(edge[1]),
                face.map(|k| self.at(k)),
            )
    }

    /// Whether a new edge crosses `face` (box `face_box`).
    fn new_edges_cross(&self, face: [Key; 3], face_box: &Bounds) -> bool {
        self.new_edges
            .iter()
            .zip(&self.edge_boxes)
            .any(|(&e, e_box)| self.crosses(e, e_box, face, face_box))
    }

    /// Whether a new edge crosses a new face.
    fn new_pairs_cross(&self) -> bool {
        self.new_faces
            .iter()
            .zip(&self.face_boxes)
            .any(|(&f, f_box)| self.new_edges_cross(f, f_box))
    }

    /// Whether the mesh's face `id` (vertex slots `f`, box `face_box`), if the edit keeps it, is
    /// crossed by a new edge or has an edge crossing a new face.
    fn kept_face_crosses(&self, id: FaceId, f: [usize; 3], face_box: &Bounds) -> bool {
        overlap(face_box, &self.region)
            && self.removed.binary_search(&id).is_err()
            && (self.new_edges_cross(f, face_box)
                || (0..3).any(|i| {
                    let edge = sorted(f[i], f[(i + 1) % 3]);
                    let edge_box = bounds(&edge.map(|k| self.at(k)));
                    self.new_faces
                        .iter()
                        .zip(&self.face_boxes)
                        .any(|(&g, g_box)| self.crosses(edge, &edge_box, g, g_box))
                }))
    }
}

/// A box: its lowest and highest corners (m).
type Bounds = (Vec3, Vec3);

/// Whether two boxes meet (touching included).
fn overlap(a: &Bounds, b: &Bounds) -> bool {
    (0..3).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k])
}

/// The key of a vertex of the edited mesh.
fn key(r: VertexRef) -> Key {
    match r {
        VertexRef::Old(v) => v.0 as usize,
        VertexRef::New(k) => usize::MAX - k,
    }
}

/// The world position (m) of the vertex `k` of the edited mesh, new vertex `j` being at
/// `new_positions[j]`.
fn position(cloth: &Cloth, new_positions: &[Vec3], k: Key) -> Vec3 {
    if k > usize::MAX / 2 {
        new_positions[usize::MAX - k]
    } else {
        cloth.x[k]
    }
}

fn sorted(a: Key, b: Key) -> [Key; 2] {
    [a.min(b), a.max(b)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::adapt::apply_edit;
    use crate::math::Vec2;
    use crate::mesh::{FaceId, NewVertex, Origin};
    use crate::testing::folded_cloth;
    use proptest::prelude::*;

    /// [`edit_crosses`] without any box: every new edge against every new face and every face
    /// that stays, every edge of a face that stays against every new face.
    fn crosses_by_every_pair(cloth: &Cloth, edit: &Edit, new_positions: &[Vec3]) -> bool {
        let at = |k: Key| position(cloth, new_positions, k);
        let new_faces: Vec<[Key; 3]> = edit.add.iter().map(|f| f.map(key)).collect();
        let edges_of = |f: [Key; 3]| (0..3).map(move |i| sorted(f[i], f[(i + 1) % 3]));
        let new_edges: Vec<[Key; 2]> = new_faces.iter().flat_map(|&f| edges_of(f)).collect();
        let crosses = |e: [Key; 2], f: [Key; 3]| {
            !f.contains(&e[0])
                && !f.contains(&e[1])
                && segment_crosses_triangle(at(e[0]), at(e[1]), f.map(at))
        };
        let kept: Vec<[Key; 3]> = cloth
            .mesh
            .faces()
            .filter(|f| !edit.remove.contains(f))
            .map(|f| cloth.mesh.face(f).map(|v| v.0 as usize))
            .collect();
        let faces = || new_faces.iter().chain(&kept);
        new_edges.iter().any(|&e| faces().any(|&f| crosses(e, f)))
            || kept
                .iter()
                .any(|&f| edges_of(f).any(|e| new_faces.iter().any(|&g| crosses(e, g))))
    }

    /// Face `f` of `cloth` replaced by three faces around one new vertex at its rest centre
    /// (the check takes the new vertex's position as its argument).
    fn split_at_new_vertex(cloth: &Cloth, f: FaceId) -> Edit {
        let corners = cloth.mesh.face(f);
        let rest = corners.iter().map(|&v| cloth.mesh.rest(v)).sum::<Vec2>() / 3.0;
        let [a, b, c] = corners.map(VertexRef::Old);
        Edit {
            remove: vec![f],
            new_vertices: vec![NewVertex {
                rest,
                origin: Origin::InTriangle {
                    corners,
                    weights: [1.0 / 3.0; 3],
                },
            }],
            add: vec![
                [a, b, VertexRef::New(0)],
                [b, c, VertexRef::New(0)],
                [c, a, VertexRef::New(0)],
            ],
        }
    }

    proptest! {
        /// A face of the folded cloth split at a new vertex placed anywhere around the fold: the
        /// boxes only skip pairs that cannot cross.
        #[test]
        fn the_boxes_skip_no_crossing(
            face in 0usize..32,
            p in (0.2..0.8f64, 0.0..1.0f64, -0.2..0.4f64),
        ) {
            let cloth = folded_cloth(5);
            let faces: Vec<FaceId> = cloth.mesh.faces().collect();
            let f = faces[face % faces.len()];
            let edit = split_at_new_vertex(&cloth, f);
            let at = [Vec3::new(p.0, p.1, p.2)];
            prop_assert_eq!(edit_crosses(&cloth, &edit, &at), crosses_by_every_pair(&cloth, &edit, &at));
        }

        /// Faces split one after another, each new vertex then moved anywhere around the fold
        /// (the guard's contract allows moving the vertices edits add): the guard built before
        /// the first edit answers every edit as testing every pair does, face ids reused by the
        /// edits included.
        #[test]
        fn a_guard_answers_a_sequence_of_edits_as_every_pair(
            steps in prop::collection::vec(
                (0usize..1000, (0.2..0.8f64, 0.0..1.0f64, -0.2..0.4f64)),
                1..16,
            ),
        ) {
            let mut cloth = folded_cloth(5);
            let mut guard = CrossingGuard::new(&cloth);
            for (pick, p) in steps {
                let faces: Vec<FaceId> = cloth.mesh.faces().collect();
                let edit = split_at_new_vertex(&cloth, faces[pick % faces.len()]);
                let at = [Vec3::new(p.0, p.1, p.2)];
                prop_assert_eq!(
                    guard.edit_crosses(&cloth, &edit, &at),
                    crosses_by_every_pair(&cloth, &edit, &at)
                );
                let t = apply_edit(&mut cloth, &edit, None, false).expect("a valid split");
                guard.applied(&cloth, &t.record);
                let v = t.record.added_vertices[0].0;
                cloth.x[v.0 as usize] = at[0];
                guard.moved(&cloth, v);
            }
        }
    }

    /// A new vertex pulled through the standing half of the folded cloth crosses it; one kept
    /// in the face's plane does not.
    #[test]
    fn a_vertex_pulled_through_the_other_half_crosses() {
        let cloth = folded_cloth(5);
        // A face of the flat half touching the fold (x = 0.5), and its centre.
        let f = cloth
            .mesh
            .faces()
            .find(|&f| {
                let xs = cloth.mesh.face(f).map(|v| cloth.x[v.0 as usize]);
                xs.iter().all(|p| p.z == 0.0) && xs.iter().filter(|p| p.x == 0.5).count() == 1
            })
            .unwrap();
        let centre = cloth
            .mesh
            .face(f)
            .map(|v| cloth.x[v.0 as usize])
            .iter()
            .sum::<Vec3>()
            / 3.0;
        let edit = split_at_new_vertex(&cloth, f);
        assert!(!edit_crosses(&cloth, &edit, &[centre]));
        let through = Vec3::new(0.8, centre.y, 0.05);
        assert!(edit_crosses(&cloth, &edit, &[through]));
        assert!(crosses_by_every_pair(&cloth, &edit, &[through]));
    }
}
