//! The bisection labels of MODEL.md §8.4: per face its newest vertex (the refinement edge is the
//! edge opposite it) and its level; per vertex created by a bisection the edge it split.
//!
//! Faces are addressed by slot ([`FaceId`]); every entry also keeps the face's vertex triple, so
//! a label that no longer matches the mesh is detected instead of silently read. The tables are
//! updated from each [`EditRecord`] by the operations of `ops.rs`; [`Labels::version`] remembers the
//! mesh version they describe, and an operation on a mesh edited behind their back is refused.
//!
//! Initial labelling: the newest vertex of every face is the one opposite its longest rest edge
//! (ties broken by the smallest edge key), level 0. On the union-jack grid this is exactly the
//! 4-8 labelling (the diagonal of each cell is the hypotenuse of both its triangles); on any other
//! mesh (an OBJ cloth, the disk) it is the longest-edge labelling under which newest-vertex
//! bisection still conforms and its cascades terminate (Mitchell 1991); only the "neighbours
//! differ by at most one level" property is specific to 4-8 compatible meshes
//! ([`Labels::is_four_eight`]).

use crate::math::Real;
use crate::mesh::{EdgeKey, FaceId, Mesh, VertexId, VertexKey};

/// What a face knows about its place in the bisection hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FaceLabel {
    /// The face's newest vertex; the refinement edge is the edge opposite it.
    pub newest: VertexId,
    /// Number of bisections from the initial face (0 for initial faces).
    pub level: u32,
}

/// A labelled face: the vertex triple it was labelled for and its label.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Entry {
    verts: [VertexId; 3],
    label: FaceLabel,
}

/// The edge a vertex was inserted on by a bisection (its parents in the hierarchy).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SplitOrigin {
    /// The vertex itself (slot and generation).
    pub key: VertexKey,
    /// The ends of the bisected refinement edge.
    pub ends: [VertexKey; 2],
}

/// The labels of every live face and the split origin of every vertex created by bisection.
#[derive(Clone, Debug, PartialEq)]
pub struct Labels {
    faces: Vec<Option<Entry>>,
    split: Vec<Option<SplitOrigin>>,
    version: u64,
    max_level: u32,
}

/// Why the labels do not describe the mesh (a bug or an edit made behind their back).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("bisection labels out of step with the mesh: {0}")]
pub struct LabelMismatch(pub String);

impl Labels {
    /// Labels every face of `mesh` by its longest rest edge, level 0; faces may be bisected up to
    /// `max_level` times.
    pub fn new(mesh: &Mesh, max_level: u32) -> Labels {
        let mut faces = vec![None; mesh.face_slots()];
        for f in mesh.faces() {
            let verts = mesh.face(f);
            faces[f.0 as usize] = Some(Entry {
                verts,
                label: FaceLabel {
                    newest: opposite_longest_edge(mesh, verts),
                    level: 0,
                },
            });
        }
        Labels {
            faces,
            split: vec![None; mesh.vertex_slots()],
            version: mesh.version(),
            max_level,
        }
    }

    /// The largest level a face may reach.
    pub fn max_level(&self) -> u32 {
        self.max_level
    }

    /// The mesh version these labels describe.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// Fails unless the labels describe this version of `mesh`.
    pub fn ensure_current(&self, mesh: &Mesh) -> Result<(), LabelMismatch> {
        if mesh.version() == self.version {
            Ok(())
        } else {
            Err(LabelMismatch(format!(
                "labels are for mesh version {}, the mesh is at version {}",
                self.version,
                mesh.version()
            )))
        }
    }

    /// The label of a live face, `None` when the face is not live or its entry is stale.
    pub fn label(&self, mesh: &Mesh, f: FaceId) -> Option<FaceLabel> {
        if !mesh.is_face(f) {
            return None;
        }
        let e = self.faces.get(f.0 as usize).copied().flatten()?;
        (e.verts == mesh.face(f)).then_some(e.label)
    }

    /// The refinement edge of a face as `(a, b, newest)` counter-clockwise: the edge is `a-b`.
    pub fn refinement(&self, mesh: &Mesh, f: FaceId) -> Option<[VertexId; 3]> {
        let label = self.label(mesh, f)?;
        let vs = mesh.face(f);
        let k = vs.iter().position(|&v| v == label.newest)?;
        Some([vs[(k + 1) % 3], vs[(k + 2) % 3], vs[k]])
    }

    /// The refinement edge of a face as an undirected key.
    pub fn refinement_edge(&self, mesh: &Mesh, f: FaceId) -> Option<EdgeKey> {
        self.refinement(mesh, f).map(|[a, b, _]| EdgeKey::new(a, b))
    }

    /// The split origin of a live vertex created by bisection (`None` for initial vertices).
    pub fn split_origin(&self, mesh: &Mesh, v: VertexId) -> Option<SplitOrigin> {
        let s = self.split.get(v.0 as usize).copied().flatten()?;
        (mesh.resolve(s.key) == Some(v)).then_some(s)
    }

    /// True when every face's refinement edge is shared with a neighbour whose refinement edge it
    /// also is, or lies on the cloth border: the mesh is a 4-8 mesh of blocks (diamonds), on which
    /// newest-vertex bisection keeps neighbouring faces within one level.
    pub fn is_four_eight(&self, mesh: &Mesh) -> bool {
        mesh.faces().all(|f| {
            let Some([a, b, _]) = self.refinement(mesh, f) else {
                return false;
            };
            let Some(ef) = mesh.edge(a, b) else {
                return false;
            };
            ef.iter()
                .filter(|&g| g != f)
                .all(|g| self.refinement_edge(mesh, g) == Some(EdgeKey::new(a, b)))
        })
    }

    /// Checks that every live face has a current label whose newest vertex is one of its corners,
    /// that every level is within `max_level`, and that the labels describe this mesh version.
    pub fn check(&self, mesh: &Mesh) -> Result<(), LabelMismatch> {
        self.ensure_current(mesh)?;
        for f in mesh.faces() {
            let Some(label) = self.label(mesh, f) else {
                return Err(LabelMismatch(format!("face {} has no current label", f.0)));
            };
            if !mesh.face(f).contains(&label.newest) {
                return Err(LabelMismatch(format!(
                    "face {}'s newest vertex {} is not one of its corners",
                    f.0, label.newest.0
                )));
            }
            if label.level > self.max_level {
                return Err(LabelMismatch(format!(
                    "face {} is at level {} above the maximum {}",
                    f.0, label.level, self.max_level
                )));
            }
        }
        Ok(())
    }

    // ----- updates, called by the operations after each applied edit -----

    /// Forgets removed faces and labels added ones; `labels` pairs each added face (in record
    /// order) with its label. Records the mesh version.
    pub(super) fn update(
        &mut self,
        mesh: &Mesh,
        removed: &[(FaceId, [VertexId; 3])],
        added: &[FaceId],
        labels: &[FaceLabel],
    ) {
        for (f, _) in removed {
            self.faces[f.0 as usize] = None;
        }
        if self.faces.len() < mesh.face_slots() {
            self.faces.resize(mesh.face_slots(), None);
        }
        for (&f, &label) in added.iter().zip(labels) {
            self.faces[f.0 as usize] = Some(Entry {
                verts: mesh.face(f),
                label,
            });
        }
        if self.split.len() < mesh.vertex_slots() {
            self.split.resize(mesh.vertex_slots(), None);
        }
        self.version = mesh.version();
    }

    /// Records (`Some`) or forgets (`None`) the split origin of vertex slot `v`.
    pub(super) fn set_split(&mut self, v: VertexId, origin: Option<SplitOrigin>) {
        let i = v.0 as usize;
        if self.split.len() <= i {
            self.split.resize(i + 1, None);
        }
        self.split[i] = origin;
    }
}

/// The corner opposite the longest rest edge of a face (ties: the smallest edge key), so the
/// choice is a strict total order on edges and level-0 cascades cannot cycle.
pub fn opposite_longest_edge(mesh: &Mesh, verts: [VertexId; 3]) -> VertexId {
    let mut best: Option<(Real, EdgeKey, VertexId)> = None;
    for k in 0..3 {
        let (a, b, c) = (verts[(k + 1) % 3], verts[(k + 2) % 3], verts[k]);
        let len2 = (mesh.rest(b) - mesh.rest(a)).norm_squared();
        let key = EdgeKey::new(a, b);
        let better = match best {
            None => true,
            Some((l, kb, _)) => len2 > l || (len2 == l && key < kb),
        };
        if better {
            best = Some((len2, key, c));
        }
    }
    best.map(|(_, _, c)| c).unwrap_or(verts[0])
}
