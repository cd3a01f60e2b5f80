//! The elementary operations on the hierarchy: [`Hierarchy::split_edge`] and
//! [`Hierarchy::merge_edge`], each changing only the (at most two) hierarchy triangles adjacent to
//! the edge and expressed as ONE [`Edit`] that replaces their current faces by their new ones.
//!
//! Each operation checks its preconditions first (returning an [`OpError`] naming the violated
//! one), builds the edit, hands it to a [`EditTarget`] under the energy law (the bare mesh for
//! topology tests, or the cloth through [`crate::adapt::apply_edit_conserving`] for the physics:
//! an edit that would add energy its region's motion cannot pay is refused), and commits the
//! hierarchy change only when the target applied it: on any error neither the mesh nor the
//! hierarchy changes.
//! [`Hierarchy::split_edge_forced`] is the `force_completion` option: a sequence of elementary
//! splits that first completes the state-1-6 parent triangles blocking the wanted edge.

use super::hierarchy::{bits_of, state_of, EdgeNode, EdgeRole, Hierarchy, TriKey, TriNode};
use crate::adapt::{ConservingError, EditTarget, EnergyRefusal};
use crate::math::Real;
use crate::mesh::{
    EdgeKey, Edit, EditError, EditRecord, FaceId, Mesh, NewVertex, Origin, VertexId, VertexRef,
};

/// Which operation a record describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpKind {
    /// An edge was split.
    Split,
    /// An edge was merged.
    Merge,
}

/// What one elementary operation changed.
#[derive(Clone, Debug, PartialEq)]
pub struct OpRecord {
    /// Split or merge.
    pub kind: OpKind,
    /// The hierarchy edge split or merged.
    pub edge: EdgeKey,
    /// Its midpoint vertex (created by a split, removed by a merge).
    pub mid: VertexId,
    /// The adjacent hierarchy triangles with their states before and after.
    pub triangles: Vec<(TriKey, u8, u8)>,
    /// The mesh's record of the edit.
    pub edit: EditRecord,
}

/// Why an operation was refused; the mesh and the hierarchy are unchanged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OpError {
    /// The vertex pair is neither a hierarchy edge nor a mesh edge.
    #[error("{0:?} is not an edge of the hierarchy or the mesh")]
    NotAnEdge(EdgeKey),
    /// The edge lies between the temporary (state -1) children of a triangle in states 1-6; it is
    /// not a hierarchy edge and can be neither split nor merged.
    #[error(
        "edge {edge:?} lies between the temporary (state -1) children of triangle {triangle:?} \
         (state {state}): it is not a hierarchy edge"
    )]
    Temporary {
        /// The edge.
        edge: EdgeKey,
        /// The triangle owning the temporary children.
        triangle: TriKey,
        /// That triangle's state (1-6).
        state: u8,
    },
    /// Split: the edge is already split (not a leaf).
    #[error("split refused: edge {0:?} is already split (not a leaf)")]
    AlreadySplit(EdgeKey),
    /// Split: the edge is at the maximum depth.
    #[error("split refused: edge {edge:?} is at depth {depth}, the maximum depth is {max_depth}")]
    MaxDepth {
        /// The edge.
        edge: EdgeKey,
        /// Its depth.
        depth: u32,
        /// The limit.
        max_depth: u32,
    },
    /// Split: a triangle next to the edge is a temporary (state -1) child (the faithful rule).
    #[error(
        "split refused: edge {edge:?} is next to a temporary (state -1) child of triangle \
         {triangle:?} in state {state}"
    )]
    NextToTemporary {
        /// The edge.
        edge: EdgeKey,
        /// The parent-level triangle in states 1-6 whose temporary children border the edge.
        triangle: TriKey,
        /// Its state.
        state: u8,
    },
    /// Merge: the edge is not split.
    #[error("merge refused: edge {0:?} is not split")]
    NotSplit(EdgeKey),
    /// Merge: a child edge is split itself.
    #[error("merge refused: child edge {child:?} of {edge:?} is split")]
    ChildSplit {
        /// The edge.
        edge: EdgeKey,
        /// The split child.
        child: EdgeKey,
    },
    /// Merge: an adjacent triangle is in state 7 and one of its children is refined.
    #[error(
        "merge refused: triangle {triangle:?} next to edge {edge:?} is in state 7 and its child \
         {child:?} is in state {state} (not an unsplit leaf)"
    )]
    RefinedChildren {
        /// The edge.
        edge: EdgeKey,
        /// The state-7 triangle.
        triangle: TriKey,
        /// Its refined child.
        child: TriKey,
        /// The child's state.
        state: u8,
    },
    /// The mesh refused the edit: the new faces would cross the cloth, or (a bug) the hierarchy
    /// and the mesh disagree.
    #[error("the mesh refused the edit: {0}")]
    Edit(#[from] EditError),
    /// The edit would add energy that its region's relative motion cannot pay (the energy law,
    /// docs/model-notes.md, "Energy of a re-meshing").
    #[error(transparent)]
    AddsEnergy(#[from] EnergyRefusal),
}

impl Hierarchy {
    /// The error for an operation on `e` when it is not a hierarchy edge.
    fn not_hierarchy(&self, mesh: &Mesh, e: EdgeKey) -> OpError {
        match self.role(mesh, e) {
            Some(EdgeRole::Temporary(t)) => OpError::Temporary {
                edge: e,
                triangle: t,
                state: self.tris[&t].state,
            },
            _ => OpError::NotAnEdge(e),
        }
    }

    /// Splits the leaf edge `e` at its rest midpoint (`x`, `v` averaged by the target): the
    /// adjacent triangles move to their next state (a triangle reaching state 7 gets its four
    /// regular children in state 0). Preconditions: `e` is a hierarchy leaf, its depth is below
    /// `max_depth`, and no triangle next to it is a temporary (state -1) child. `now` (s) stamps
    /// the new edges for the split/merge time limit.
    pub fn split_edge(
        &mut self,
        target: &mut dyn EditTarget,
        e: EdgeKey,
        max_depth: u32,
        now: Real,
    ) -> Result<OpRecord, OpError> {
        let mesh = target.mesh();
        let Some(node) = self.edges.get(&e) else {
            return Err(self.not_hierarchy(mesh, e));
        };
        if node.mid.is_some() {
            return Err(OpError::AlreadySplit(e));
        }
        if node.depth >= max_depth {
            return Err(OpError::MaxDepth {
                edge: e,
                depth: node.depth,
                max_depth,
            });
        }
        if let Some(p) = node.parent {
            if let Some((&t, tri)) = self.edges[&p]
                .tris
                .iter()
                .map(|t| (t, &self.tris[t]))
                .find(|(_, tri)| tri.state != 7)
            {
                return Err(OpError::NextToTemporary {
                    edge: e,
                    triangle: t,
                    state: tri.state,
                });
            }
        }
        let tris = node.tris.clone();
        let mut edit = Edit {
            remove: Vec::new(),
            new_vertices: vec![NewVertex {
                rest: (mesh.rest(e.0) + mesh.rest(e.1)) * 0.5,
                origin: Origin::Midpoint(e.0, e.1),
            }],
            add: Vec::new(),
        };
        let mut plan = Vec::new();
        for &tk in &tris {
            let t = &self.tris[&tk];
            let k = t.edge_index(e).expect("edge lists its triangles");
            let bits = bits_of(t.state) | (1 << k);
            edit.remove.extend(removed_faces(self, t));
            let faces = self.active_faces(mesh, t, bits, Some(k));
            edit.add.extend(faces.iter().map(|f| to_refs(*f)));
            plan.push((tk, t.state, state_of(bits), faces.len()));
        }
        let record = target
            .apply_conserving(&edit)
            .map_err(ConservingError::into_error::<OpError>)?;
        let mid = record.added_vertices[0].0;
        for f in &edit.remove {
            self.owner.remove(f);
        }
        let depth = node_depth(self, e);
        let split = self.edges.get_mut(&e).expect("checked");
        split.mid = Some(mid);
        split.split_at = now;
        for c in [EdgeKey::new(e.0, mid), EdgeKey::new(mid, e.1)] {
            self.edges.insert(c, new_edge(depth + 1, Some(e), now));
        }
        let mut next = 0;
        let mut triangles = Vec::new();
        for (tk, old, new, n) in plan {
            let faces = &record.added_faces[next..next + n];
            next += n;
            let t = self.tris.get_mut(&tk).expect("checked");
            t.state = new;
            t.changed = now;
            if new == 7 {
                t.faces.clear();
                self.make_children(tk, faces, now);
            } else {
                t.faces = faces.to_vec();
                for &f in faces {
                    self.owner.insert(f, tk);
                }
            }
            triangles.push((tk, old, new));
        }
        Ok(OpRecord {
            kind: OpKind::Split,
            edge: e,
            mid,
            triangles,
            edit: record,
        })
    }

    /// Merges the split edge `e`: its midpoint and child edges go, the adjacent triangles return to
    /// their previous state (a state-7 triangle loses its four children and returns to a two-edge
    /// state). Preconditions: `e` is split, its children are leaves, and every adjacent state-7
    /// triangle has only unsplit leaf children (state 0).
    pub fn merge_edge(
        &mut self,
        target: &mut dyn EditTarget,
        e: EdgeKey,
        now: Real,
    ) -> Result<OpRecord, OpError> {
        let mesh = target.mesh();
        let Some(node) = self.edges.get(&e) else {
            return Err(self.not_hierarchy(mesh, e));
        };
        let (Some(mid), Some(children)) = (node.mid, node.children(e)) else {
            return Err(OpError::NotSplit(e));
        };
        if let Some(&child) = children.iter().find(|c| self.edges[*c].mid.is_some()) {
            return Err(OpError::ChildSplit { edge: e, child });
        }
        for &tk in &node.tris {
            let t = &self.tris[&tk];
            if let Some(ch) = t.children {
                if let Some(&c) = ch.iter().find(|c| self.tris[*c].state != 0) {
                    return Err(OpError::RefinedChildren {
                        edge: e,
                        triangle: tk,
                        child: c,
                        state: self.tris[&c].state,
                    });
                }
            }
        }
        let tris = node.tris.clone();
        let mut edit = Edit::default();
        let mut plan = Vec::new();
        for &tk in &tris {
            let t = &self.tris[&tk];
            let k = t.edge_index(e).expect("edge lists its triangles");
            let bits = bits_of(t.state) & !(1 << k);
            edit.remove.extend(removed_faces(self, t));
            let faces = self.active_faces(mesh, t, bits, None);
            edit.add.extend(faces.iter().map(|f| to_refs(*f)));
            plan.push((tk, t.state, state_of(bits), faces.len()));
        }
        let record = target
            .apply_conserving(&edit)
            .map_err(ConservingError::into_error::<OpError>)?;
        for f in &edit.remove {
            self.owner.remove(f);
        }
        let mut next = 0;
        let mut triangles = Vec::new();
        for (tk, old, new, n) in plan {
            let faces = record.added_faces[next..next + n].to_vec();
            next += n;
            if old == 7 {
                self.remove_children(tk);
            }
            for &f in &faces {
                self.owner.insert(f, tk);
            }
            let t = self.tris.get_mut(&tk).expect("checked");
            t.state = new;
            t.changed = now;
            t.faces = faces;
            triangles.push((tk, old, new));
        }
        for c in children {
            self.edges.remove(&c);
        }
        self.edges.get_mut(&e).expect("checked").mid = None;
        Ok(OpRecord {
            kind: OpKind::Merge,
            edge: e,
            mid,
            triangles,
            edit: record,
        })
    }

    /// The `force_completion` split: when `e` is blocked by a temporary (state -1) neighbour, the
    /// blocking parent-level triangle is completed first (its remaining edges split, recursively
    /// forced), so `e` becomes splittable; then `e` is split. A temporary edge (inside a triangle
    /// in states 1-6) completes its triangle. Returns every elementary operation in order; each
    /// leaves the mesh conforming. Preconditions of `e` itself (leaf, depth) are checked before
    /// anything changes.
    pub fn split_edge_forced(
        &mut self,
        target: &mut dyn EditTarget,
        e: EdgeKey,
        max_depth: u32,
        now: Real,
    ) -> Result<Vec<OpRecord>, OpError> {
        let mut forcing = Forcing {
            target,
            max_depth,
            now,
            out: Vec::new(),
        };
        self.force_into(e, &mut forcing)?;
        Ok(forcing.out)
    }

    fn force_into(&mut self, e: EdgeKey, f: &mut Forcing) -> Result<(), OpError> {
        // At most two blocking neighbours, then the split itself.
        for _ in 0..3 {
            match self.split_edge(f.target, e, f.max_depth, f.now) {
                Ok(r) => {
                    f.out.push(r);
                    return Ok(());
                }
                Err(OpError::NextToTemporary { triangle, .. }) => {
                    self.complete_into(triangle, f)?;
                }
                Err(OpError::Temporary { triangle, .. }) => {
                    return self.complete_into(triangle, f);
                }
                Err(other) => return Err(other),
            }
        }
        Err(OpError::Edit(EditError::NotATiling(format!(
            "forced split of {e:?} did not converge (hierarchy inconsistent)"
        ))))
    }

    /// Splits every unsplit edge of triangle `t` (forced), bringing it to state 7.
    fn complete_into(&mut self, t: TriKey, f: &mut Forcing) -> Result<(), OpError> {
        for k in 0..3 {
            let e = self.tris[&t].edge(k);
            if self.edges[&e].mid.is_none() {
                self.force_into(e, f)?;
            }
        }
        Ok(())
    }

    /// Creates the four regular children of `tk` (now in state 7) owning `faces` (in the order of
    /// [`Hierarchy::active_faces`] for state 7), and the three interior edges.
    fn make_children(&mut self, tk: TriKey, faces: &[FaceId], now: Real) {
        let t = &self.tris[&tk];
        let c = t.corners;
        let m: [VertexId; 3] = [0, 1, 2].map(|k| self.edges[&t.edge(k)].mid.expect("state 7"));
        let depth = t.depth + 1;
        let corners = [
            [c[0], m[0], m[2]],
            [m[0], c[1], m[1]],
            [m[2], m[1], c[2]],
            [m[0], m[1], m[2]],
        ];
        for k in 0..3 {
            let inner = EdgeKey::new(m[k], m[(k + 1) % 3]);
            self.edges.insert(inner, new_edge(depth, None, now));
        }
        let keys = corners.map(TriKey::new);
        for (i, (&key, cs)) in keys.iter().zip(corners).enumerate() {
            let child = TriNode {
                corners: cs,
                depth,
                parent: Some(tk),
                state: 0,
                faces: vec![faces[i]],
                children: None,
                changed: now,
            };
            for k in 0..3 {
                let list = &mut self
                    .edges
                    .get_mut(&child.edge(k))
                    .expect("child edges exist")
                    .tris;
                let pos = list.partition_point(|&g| g < key);
                list.insert(pos, key);
            }
            self.owner.insert(faces[i], key);
            self.tris.insert(key, child);
        }
        self.tris.get_mut(&tk).expect("live").children = Some(keys);
    }

    /// Removes the (state-0) children of `tk` and its interior edges; the children's faces must
    /// already be out of the owner map.
    fn remove_children(&mut self, tk: TriKey) {
        let Some(children) = self.tris.get_mut(&tk).and_then(|t| t.children.take()) else {
            return;
        };
        for ck in children {
            let child = self.tris.remove(&ck).expect("children are live");
            for k in 0..3 {
                if let Some(e) = self.edges.get_mut(&child.edge(k)) {
                    e.tris.retain(|&g| g != ck);
                }
            }
        }
        // The middle child's corners are the three midpoints: its edges are the interior ones.
        let middle = children[3].0;
        for k in 0..3 {
            self.edges
                .remove(&EdgeKey::new(middle[k], middle[(k + 1) % 3]));
        }
    }
}

/// The faces a triangle owns now: its own in states 0-6, its children's in state 7 (children in
/// state 0 each own one face; callers check that first).
fn removed_faces(h: &Hierarchy, t: &TriNode) -> Vec<FaceId> {
    match t.children {
        Some(ch) => ch
            .iter()
            .flat_map(|c| h.tris[c].faces.iter().copied())
            .collect(),
        None => t.faces.clone(),
    }
}

fn node_depth(h: &Hierarchy, e: EdgeKey) -> u32 {
    h.edges[&e].depth
}

fn new_edge(depth: u32, parent: Option<EdgeKey>, now: Real) -> EdgeNode {
    EdgeNode {
        depth,
        parent,
        mid: None,
        tris: Vec::new(),
        born: Some(now),
        split_at: now,
    }
}

fn to_refs(f: [Option<VertexId>; 3]) -> [VertexRef; 3] {
    f.map(|v| v.map_or(VertexRef::New(0), VertexRef::Old))
}

/// What a forced split carries through its recursion: where edits go, the depth limit, the time
/// (s) and the operations applied so far.
struct Forcing<'a> {
    target: &'a mut dyn EditTarget,
    max_depth: u32,
    now: Real,
    out: Vec<OpRecord>,
}
