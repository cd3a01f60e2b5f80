//! The elementary operations of 4-8 bisection (MODEL.md §8.4), each applied as checked
//! [`Edit`]s: block bisection, `bisect(t)` with its forced cascade, and `merge(v)`.
//!
//! - **Block bisection**: the block of a face `t` is `t` with the neighbour across its refinement
//!   edge `a-b` when that neighbour has the same refinement edge (a diamond), or `t` alone when
//!   `a-b` is on the cloth border. One edit removes the block and inserts the rest midpoint `m`
//!   of `a-b` (`Origin::Midpoint(a, b)`) joined to the opposite vertices: 2 faces become 4 (1
//!   becomes 2). Every child has newest vertex `m` and the parent's level plus one.
//! - **`bisect(t)`**: the refinement chain `t = t_0, t_1, ...` (each `t_{i+1}` across the
//!   refinement edge of `t_i`, which is not its own refinement edge) is followed to a face whose
//!   block exists; the blocks are then bisected from the end of the chain back to `t`: bisecting
//!   the block of `t_{i+1}` leaves a child across `t_i`'s refinement edge whose refinement edge it
//!   is, so `t_i` then has a block. The whole chain is planned first (levels against the maximum,
//!   cycles), so a cascade refused by its plan leaves the mesh untouched; an edit refused midway
//!   (its faces would cross the cloth, it would add energy its region's motion cannot pay, or a
//!   bug) is rolled back by merging the vertices already inserted, newest first.
//! - **`merge(p)`**: `p` was inserted by a bisection, is not pinned, and is the newest vertex of
//!   all its faces, 4 inside or 2 on the border (its star is exactly the children of one block).
//!   One edit removes `p` and restores the parents `a-b-o` for each opposite vertex `o`, with
//!   newest vertex `o` and the children's level minus one.
//!
//! Edits go through an [`EditTarget`]: the bare mesh ([`Mesh::replace`]) for topology tests, or a
//! cloth through the state-transfer service in the simulation, bisections under the energy law
//! (`adapt::apply_edit_conserving`) and merges as they come (`adapt::apply_edit_with`): a merge
//! only restores springs the cloth had, so a rollback is never refused for its energy; a
//! simplification pass asks [`Labels::merge_conserving`] instead.

use super::labels::{FaceLabel, LabelMismatch, Labels, SplitOrigin};
use crate::adapt::{ConservingError, EditTarget, EnergyRefusal};
use crate::math::signed_area;
use crate::mesh::{
    EdgeKey, Edit, EditError, EditRecord, FaceId, Mesh, NewVertex, Origin, VertexId, VertexRef,
};

/// Why a bisection or merge was refused; the mesh and the labels are unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OpError {
    /// The face is not live (or not labelled).
    #[error("face {0:?} is not a live labelled face")]
    UnknownFace(FaceId),
    /// The cascade would take a face beyond the maximum level.
    #[error(
        "bisecting face {face:?} needs a face at level {level} bisected, the maximum is {max}"
    )]
    MaxLevel {
        /// The face asked for.
        face: FaceId,
        /// The level of the face that would be bisected.
        level: u32,
        /// The maximum level.
        max: u32,
    },
    /// The refinement chain comes back to a face (a labelling that does not terminate).
    #[error("the refinement chain of face {0:?} cycles")]
    Cycle(FaceId),
    /// The vertex cannot be merged.
    #[error("vertex {vertex:?} cannot be merged: {reason}")]
    NotMergeable {
        /// The vertex.
        vertex: VertexId,
        /// Which condition fails.
        reason: &'static str,
    },
    /// The labels do not describe the mesh.
    #[error(transparent)]
    Labels(#[from] LabelMismatch),
    /// An edit was refused by the mesh (earlier edits of the cascade were rolled back).
    #[error("edit refused: {0}")]
    Edit(#[from] EditError),
    /// An edit would add energy that its region's relative motion cannot pay (the energy law,
    /// docs/model-notes.md, "Energy of a re-meshing"; earlier edits of the cascade were rolled
    /// back).
    #[error(transparent)]
    AddsEnergy(#[from] EnergyRefusal),
    /// An edit was refused and rolling back the earlier ones failed too (the mesh is conforming
    /// but partly refined).
    #[error("edit refused ({refusal}); rollback failed: {rollback}")]
    RollbackFailed {
        /// The first refusal.
        refusal: Box<OpError>,
        /// Why the rollback failed.
        rollback: Box<OpError>,
    },
}

/// What `bisect(t)` changed: the block bisections in the order applied (the cascade first, the
/// block of `t` last).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bisection {
    /// One record per block bisection.
    pub steps: Vec<EditRecord>,
}

impl Bisection {
    /// The inserted vertices, in order.
    pub fn new_vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        self.steps
            .iter()
            .flat_map(|r| r.added_vertices.iter().map(|(v, _)| *v))
    }
}

impl Labels {
    /// Bisects face `t`, first bisecting the blocks its cascade forces (MODEL.md §8.4 rules 3-4).
    /// On error the mesh and the labels are unchanged.
    pub fn bisect(&mut self, target: &mut dyn EditTarget, t: FaceId) -> Result<Bisection, OpError> {
        let chain = self.plan_cascade(target.mesh(), t)?;
        let mut done = Bisection::default();
        for &f in chain.iter().rev() {
            match self.bisect_block(target, f) {
                Ok(record) => done.steps.push(record),
                Err(refusal) => return Err(self.roll_back(target, &done, refusal)),
            }
        }
        Ok(done)
    }

    /// The faces whose blocks `bisect(t)` bisects, `t` first; checks levels and cycles.
    pub fn plan_cascade(&self, mesh: &Mesh, t: FaceId) -> Result<Vec<FaceId>, OpError> {
        self.ensure_current(mesh)?;
        let level_of = |f: FaceId| self.label(mesh, f).map(|l| l.level);
        if level_of(t).is_none() {
            return Err(OpError::UnknownFace(t));
        }
        let mut chain = vec![t];
        let mut cur = t;
        loop {
            let level = level_of(cur).ok_or(OpError::UnknownFace(cur))?;
            if level >= self.max_level() {
                return Err(OpError::MaxLevel {
                    face: t,
                    level,
                    max: self.max_level(),
                });
            }
            let [a, b, _] = self
                .refinement(mesh, cur)
                .ok_or(OpError::UnknownFace(cur))?;
            let Some(n) = across(mesh, cur, a, b) else {
                break; // a border block
            };
            let nl = level_of(n).ok_or(OpError::UnknownFace(n))?;
            if self.refinement_edge(mesh, n) == Some(EdgeKey::new(a, b)) {
                if nl >= self.max_level() {
                    return Err(OpError::MaxLevel {
                        face: t,
                        level: nl,
                        max: self.max_level(),
                    });
                }
                break; // a diamond
            }
            if chain.contains(&n) || chain.len() > mesh.face_count() {
                return Err(OpError::Cycle(t));
            }
            chain.push(n);
            cur = n;
        }
        Ok(chain)
    }

    /// Bisects the block of `f`, whose refinement edge must be shared by the face across it (or
    /// lie on the border).
    fn bisect_block(
        &mut self,
        target: &mut dyn EditTarget,
        f: FaceId,
    ) -> Result<EditRecord, OpError> {
        let mesh = target.mesh();
        self.ensure_current(mesh)?;
        let label = self.label(mesh, f).ok_or(OpError::UnknownFace(f))?;
        let [a, b, c] = self.refinement(mesh, f).ok_or(OpError::UnknownFace(f))?;
        let mate = across(mesh, f, a, b);
        let mut edit = Edit {
            remove: vec![f],
            new_vertices: vec![NewVertex {
                rest: (mesh.rest(a) + mesh.rest(b)) * 0.5,
                origin: Origin::Midpoint(a, b),
            }],
            add: Vec::new(),
        };
        let (old, m) = (VertexRef::Old, VertexRef::New(0));
        edit.add.push([old(a), m, old(c)]);
        edit.add.push([m, old(b), old(c)]);
        let mut levels = vec![label.level + 1; 2];
        if let Some(g) = mate {
            let [b2, a2, d] = self.refinement(mesh, g).ok_or(OpError::UnknownFace(g))?;
            if (a2, b2) != (a, b) {
                return Err(OpError::Edit(EditError::NotATiling(format!(
                    "face {} has no block: its neighbour {} has another refinement edge",
                    f.0, g.0
                ))));
            }
            let gl = self.label(mesh, g).ok_or(OpError::UnknownFace(g))?.level;
            edit.remove.push(g);
            edit.add.push([old(b), m, old(d)]);
            edit.add.push([m, old(a), old(d)]);
            levels.extend([gl + 1; 2]);
        }
        let ends = [mesh.key(a), mesh.key(b)];
        let record = target
            .apply_conserving(&edit)
            .map_err(ConservingError::into_error::<OpError>)?;
        let mesh = target.mesh();
        let mid = record.added_vertices[0].0;
        let labels: Vec<FaceLabel> = levels
            .into_iter()
            .map(|level| FaceLabel { newest: mid, level })
            .collect();
        self.update(mesh, &record.removed_faces, &record.added_faces, &labels);
        self.set_split(
            mid,
            Some(SplitOrigin {
                key: mesh.key(mid),
                ends,
            }),
        );
        Ok(record)
    }

    /// Undoes the applied steps of a cascade, newest first, and returns the error to report:
    /// `refusal`, or [`OpError::RollbackFailed`].
    fn roll_back(
        &mut self,
        target: &mut dyn EditTarget,
        done: &Bisection,
        refusal: OpError,
    ) -> OpError {
        for step in done.steps.iter().rev() {
            let v = step.added_vertices[0].0;
            if let Err(e) = self.merge(target, v) {
                return OpError::RollbackFailed {
                    refusal: Box::new(refusal),
                    rollback: Box::new(e),
                };
            }
        }
        refusal
    }

    /// Why `p` cannot be merged, or the parents its merge restores: each `[a, b, o]`
    /// counter-clockwise with newest vertex `o`, and its level (its children's minus one; on a
    /// 4-8 mesh both parents have the same level, on a longest-edge labelled mesh a block may join
    /// faces of different levels).
    pub fn merge_plan(
        &self,
        mesh: &Mesh,
        p: VertexId,
    ) -> Result<Vec<([VertexId; 3], u32)>, OpError> {
        self.ensure_current(mesh)?;
        let no = |reason| Err(OpError::NotMergeable { vertex: p, reason });
        if !mesh.is_vertex(p) {
            return no("not a live vertex");
        }
        if mesh.is_pinned(p) {
            return no("pinned");
        }
        let Some(origin) = self.split_origin(mesh, p) else {
            return no("an initial vertex");
        };
        let (Some(a), Some(b)) = (mesh.resolve(origin.ends[0]), mesh.resolve(origin.ends[1]))
        else {
            return no("the ends of its split edge are gone");
        };
        let star = mesh.vertex_faces(p);
        if star.len() != 2 && star.len() != 4 {
            return no("valence is not 4 (2 on the border)");
        }
        // Opposite vertex -> (children seen, their level).
        let mut opposite: Vec<(VertexId, usize, u32)> = Vec::with_capacity(2);
        for &f in star {
            let Some(label) = self.label(mesh, f) else {
                return no("a face around it has no label");
            };
            if label.newest != p {
                return no("not the newest vertex of every face around it");
            }
            let vs = mesh.face(f);
            if !(vs.contains(&a) ^ vs.contains(&b)) {
                return no("a face around it does not hold exactly one end of its split edge");
            }
            let o = vs.into_iter().find(|&w| w != p && w != a && w != b);
            let Some(o) = o else {
                return no("a face around it has no opposite vertex");
            };
            match opposite.iter_mut().find(|(w, _, _)| *w == o) {
                Some((_, n, level)) if *level == label.level => *n += 1,
                Some(_) => return no("two children of one parent differ in level"),
                None => opposite.push((o, 1, label.level)),
            }
        }
        if opposite.iter().any(|&(_, n, level)| n != 2 || level == 0) {
            return no("its faces do not pair into parents");
        }
        opposite.sort_unstable();
        let parents = opposite
            .into_iter()
            .map(|(o, _, level)| {
                let face = if signed_area(mesh.rest(a), mesh.rest(b), mesh.rest(o)) > 0.0 {
                    [a, b, o]
                } else {
                    [b, a, o]
                };
                (face, level - 1)
            })
            .collect();
        Ok(parents)
    }

    /// True when `p` can be merged now.
    pub fn is_mergeable(&self, mesh: &Mesh, p: VertexId) -> bool {
        self.merge_plan(mesh, p).is_ok()
    }

    /// Merges vertex `p`: fuses the children of the bisection that inserted it back into their
    /// parents (MODEL.md §8.4 rule 5). On error the mesh and the labels are unchanged. Not under
    /// the energy law: a cascade's rollback must not be refused.
    pub fn merge(
        &mut self,
        target: &mut dyn EditTarget,
        p: VertexId,
    ) -> Result<EditRecord, OpError> {
        self.merge_with(target, p, false)
    }

    /// [`Labels::merge`] under the energy law: refused with [`OpError::AddsEnergy`] when the
    /// merged faces would hold more energy than their region's relative motion can pay.
    pub fn merge_conserving(
        &mut self,
        target: &mut dyn EditTarget,
        p: VertexId,
    ) -> Result<EditRecord, OpError> {
        self.merge_with(target, p, true)
    }

    fn merge_with(
        &mut self,
        target: &mut dyn EditTarget,
        p: VertexId,
        conserving: bool,
    ) -> Result<EditRecord, OpError> {
        let mesh = target.mesh();
        let parents = self.merge_plan(mesh, p)?;
        let edit = Edit {
            remove: mesh.vertex_faces(p).to_vec(),
            new_vertices: Vec::new(),
            add: parents.iter().map(|(f, _)| f.map(VertexRef::Old)).collect(),
        };
        let record = if conserving {
            target
                .apply_conserving(&edit)
                .map_err(ConservingError::into_error::<OpError>)?
        } else {
            target.apply(&edit)?
        };
        let labels: Vec<FaceLabel> = parents
            .iter()
            .map(|&([_, _, o], level)| FaceLabel { newest: o, level })
            .collect();
        self.update(
            target.mesh(),
            &record.removed_faces,
            &record.added_faces,
            &labels,
        );
        self.set_split(p, None);
        Ok(record)
    }

    /// The vertices that can be merged now, in slot order.
    pub fn mergeable_vertices(&self, mesh: &Mesh) -> Vec<VertexId> {
        mesh.vertices()
            .filter(|&v| self.split_origin(mesh, v).is_some() && self.is_mergeable(mesh, v))
            .collect()
    }
}

/// The face across edge `a-b` from face `f`, if any.
fn across(mesh: &Mesh, f: FaceId, a: VertexId, b: VertexId) -> Option<FaceId> {
    mesh.edge(a, b)?.iter().find(|&g| g != f)
}
