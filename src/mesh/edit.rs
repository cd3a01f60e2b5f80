//! The one checked mesh edit: replace a set of faces by new faces, possibly adding vertices.
//!
//! Every strategy's elementary operation (edge split, merge, bisection, region re-mesh) is
//! expressed as an [`Edit`]. [`Mesh::replace`] validates it, applies it, and returns an
//! [`EditRecord`]; on any error the mesh is left exactly as it was (everything is validated
//! before the first mutation).
//!
//! Validation, in order: the removed faces are live and distinct; the new vertices have finite
//! rest coordinates and live origin vertices; the new faces name valid vertices, are
//! counter-clockwise with a clearly positive rest area, and every new vertex is used; the new faces
//! tile the removed region exactly: their directed boundary edges cancel those of the removed
//! region except along the cloth border, where the remaining old and new border edges must cover
//! the same straight rest-space segments (a border edge bisected, or collinear border edges
//! merged); the rest areas agree to a relative 1e-12 (plus rounding); no edge gets three faces or
//! inconsistent orientation, every touched vertex keeps a single fan; no pinned vertex is removed.

use super::check::{has_directed, is_positive_triangle, single_fan, ON_EDGE_REL_TOL};
use super::{ConformityError, FaceId, Mesh, Rule, VertexId};
use crate::math::{signed_area, Real, Vec2};
use std::collections::{BTreeMap, BTreeSet};

/// A vertex of a new face: an existing live vertex, or the k-th vertex of [`Edit::new_vertices`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexRef {
    /// An existing live vertex.
    Old(VertexId),
    /// Index into [`Edit::new_vertices`].
    New(usize),
}

/// Where a new vertex takes its world state from (interpolation in rest space, MODEL.md §6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Origin {
    /// Midpoint of an edge between two vertices that exist before the edit: state averaged.
    Midpoint(VertexId, VertexId),
    /// A point of an old triangle (the corners exist before the edit) with barycentric weights.
    InTriangle {
        /// Corners of the old triangle.
        corners: [VertexId; 3],
        /// Barycentric weights (sum to 1).
        weights: [Real; 3],
    },
}

/// A vertex created by an edit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewVertex {
    /// Rest coordinates (m).
    pub rest: Vec2,
    /// How its world state is interpolated.
    pub origin: Origin,
}

/// A replacement of faces: `remove` (live faces) are taken out, `add` (counter-clockwise in rest
/// space) put in. Vertices left without faces are removed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Edit {
    /// Faces to remove.
    pub remove: Vec<FaceId>,
    /// Vertices to create.
    pub new_vertices: Vec<NewVertex>,
    /// Faces to create.
    pub add: Vec<[VertexRef; 3]>,
}

/// What an applied edit changed; consumed by the state transfer (module `adapt`).
///
/// Face slots freed by the edit are reused by its new faces (so an id may appear in both
/// `removed_faces` and `added_faces`); vertex slots freed by the edit are not reused by the same
/// edit (new vertices are created before the emptied ones are freed).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EditRecord {
    /// Removed faces with the vertices they had.
    pub removed_faces: Vec<(FaceId, [VertexId; 3])>,
    /// Created faces.
    pub added_faces: Vec<FaceId>,
    /// Created vertices (same order as [`Edit::new_vertices`]) with their origin.
    pub added_vertices: Vec<(VertexId, Origin)>,
    /// Vertices removed because no face used them any more.
    pub removed_vertices: Vec<VertexId>,
}

/// Why an edit was refused; the mesh is unchanged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EditError {
    /// A face to remove is not live, or is listed twice.
    #[error("face {0:?} is not a live face (or is listed twice)")]
    StaleFace(FaceId),
    /// A new face names a vertex that is not live, or a new-vertex index out of range.
    #[error("new face {face} names a vertex that does not exist: {vertex:?}")]
    BadVertex {
        /// Index of the new face in the edit.
        face: usize,
        /// The reference.
        vertex: VertexRef,
    },
    /// A new face has a repeated vertex or a non-positive rest area.
    #[error("new face {face} is degenerate or clockwise (rest area {area:e} m²)")]
    BadFace {
        /// Index of the new face in the edit.
        face: usize,
        /// Its signed rest area (m²).
        area: Real,
    },
    /// The new faces do not cover exactly the region of the removed faces.
    #[error("the new faces do not tile the removed region: {0}")]
    NotATiling(String),
    /// The result would break a conformity rule.
    #[error("the edit would break conformity: {0}")]
    Conformity(#[from] super::ConformityError),
    /// A new vertex has non-finite rest coordinates or an origin naming a vertex that is not live.
    #[error("new vertex {index} is invalid: {reason}")]
    BadNewVertex {
        /// Index into [`Edit::new_vertices`].
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// A pinned vertex would be removed.
    #[error("the edit would remove pinned vertex {0:?}")]
    RemovesPinned(VertexId),
    /// The new faces or edges would cross the cloth (refused by the state transfer when
    /// self-collision is on, `crate::adapt::TransferOptions::refuse_crossings`; never by the
    /// mesh). A refusal, not a defect: the strategy skips the operation.
    #[error("the edit would make the cloth cross itself")]
    CrossesCloth,
}

impl Mesh {
    /// Applies `edit` if it keeps the mesh conforming, returning what changed; see the module doc
    /// for the rules. On error the mesh is unchanged (including its version).
    pub fn replace(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        let removed_vertices = self.validate_edit(edit)?;
        Ok(self.commit(edit, removed_vertices))
    }

    /// Applies `edit` as [`Mesh::replace`] does, without validating it again: only for an edit
    /// [`Mesh::check_edit`] accepted on this mesh as it is now (or the same edit in a patch's local
    /// ids, [`Mesh::patch`], whose faces around the region are the mesh's). Anything else may break
    /// the mesh.
    pub(crate) fn replace_checked(&mut self, edit: &Edit) -> EditRecord {
        let removed = sorted_unique(edit.remove.clone());
        let region = self.region_vertices(&removed);
        let gone = self.vanishing(edit, &removed, &region);
        self.commit(edit, gone)
    }

    /// Applies a validated `edit` whose vertices left without faces are `removed_vertices`.
    fn commit(&mut self, edit: &Edit, removed_vertices: Vec<VertexId>) -> EditRecord {
        let removed_faces: Vec<(FaceId, [VertexId; 3])> =
            edit.remove.iter().map(|&f| (f, self.face(f))).collect();
        for &f in &edit.remove {
            self.free_face(f);
        }
        let new_ids: Vec<VertexId> = edit
            .new_vertices
            .iter()
            .map(|nv| self.push_vertex(nv.rest))
            .collect();
        let added_faces = edit
            .add
            .iter()
            .map(|f| self.push_face(f.map(|r| resolve(r, &new_ids))))
            .collect();
        for &v in &removed_vertices {
            self.free_vertex(v);
        }
        debug_assert!(
            self.face_count() >= 2000 || self.check().is_ok(),
            "edit broke conformity: {:?}",
            self.check()
        );
        EditRecord {
            removed_faces,
            added_faces,
            added_vertices: new_ids
                .into_iter()
                .zip(edit.new_vertices.iter().map(|nv| nv.origin))
                .collect(),
            removed_vertices,
        }
    }

    /// Checks `edit` as [`Mesh::replace`] would, without applying it.
    pub fn check_edit(&self, edit: &Edit) -> Result<(), EditError> {
        self.validate_edit(edit).map(|_| ())
    }

    /// Validates `edit` without changing anything; returns the vertices it would remove (in id
    /// order).
    fn validate_edit(&self, edit: &Edit) -> Result<Vec<VertexId>, EditError> {
        // Removed faces: live, distinct.
        if edit.remove.is_empty() {
            return Err(EditError::NotATiling("the edit removes no face".into()));
        }
        let mut removed = edit.remove.clone();
        removed.sort_unstable();
        if let Some(f) = self.first_stale(&edit.remove, &removed) {
            return Err(EditError::StaleFace(f));
        }
        removed.dedup();
        let region = self.region_vertices(&removed);
        // New vertices.
        for (index, nv) in edit.new_vertices.iter().enumerate() {
            let bad = |reason: String| Err(EditError::BadNewVertex { index, reason });
            if !(nv.rest.x.is_finite() && nv.rest.y.is_finite()) {
                return bad(format!("rest coordinates {:?}", nv.rest.as_slice()));
            }
            let corners: &[VertexId] = match &nv.origin {
                Origin::Midpoint(a, b) => &[*a, *b][..],
                Origin::InTriangle { corners, .. } => &corners[..],
            };
            if let Some(v) = corners.iter().find(|&&v| !self.is_vertex(v)) {
                return bad(format!("origin names vertex {} which is not live", v.0));
            }
        }
        // New faces: valid references inside the region, positive area.
        let pos = |r: Key| match r {
            Key::Old(v) => self.rest(v),
            Key::New(k) => edit.new_vertices[k].rest,
        };
        let mut used = vec![false; edit.new_vertices.len()];
        let mut added = Vec::with_capacity(edit.add.len());
        for (face, refs) in edit.add.iter().enumerate() {
            let mut keys = [Key::New(0); 3];
            for (k, &r) in refs.iter().enumerate() {
                keys[k] = match r {
                    VertexRef::Old(v) if self.is_vertex(v) => Key::Old(v),
                    VertexRef::New(i) if i < edit.new_vertices.len() => {
                        used[i] = true;
                        Key::New(i)
                    }
                    _ => return Err(EditError::BadVertex { face, vertex: r }),
                };
            }
            let [a, b, c] = keys.map(pos);
            if keys[0] == keys[1]
                || keys[1] == keys[2]
                || keys[2] == keys[0]
                || !is_positive_triangle(a, b, c)
            {
                let area = signed_area(a, b, c);
                return Err(EditError::BadFace { face, area });
            }
            if let Some(Key::Old(v)) = keys
                .iter()
                .find(|k| matches!(k, Key::Old(v) if region.binary_search(v).is_err()))
            {
                return Err(EditError::NotATiling(format!(
                    "new face {face} uses vertex {} which is not a vertex of the removed faces",
                    v.0
                )));
            }
            added.push(keys);
        }
        if let Some(k) = used.iter().position(|&u| !u) {
            return Err(EditError::NotATiling(format!(
                "new vertex {k} is used by no new face"
            )));
        }
        let new_dir = self.check_tiling(edit, &removed, &added, &pos)?;
        self.check_local_conformity(&removed, &added, &new_dir)?;
        let gone = self.vanishing(edit, &removed, &region);
        match gone.iter().find(|&&v| self.is_pinned(v)) {
            Some(&v) => Err(EditError::RemovesPinned(v)),
            None => Ok(gone),
        }
    }

    /// The first face of `remove` (in its order) that is not live or repeats an earlier one;
    /// `sorted` is `remove` sorted.
    fn first_stale(&self, remove: &[FaceId], sorted: &[FaceId]) -> Option<FaceId> {
        let mut seen = vec![false; sorted.len()];
        remove.iter().copied().find(|&f| {
            if !self.is_face(f) {
                return true;
            }
            // Equal ids sit together in `sorted`: the first of them marks the id as seen.
            let k = sorted.partition_point(|&g| g < f);
            std::mem::replace(&mut seen[k], true)
        })
    }

    /// The vertices of the (sorted) `removed` faces, sorted, each once.
    fn region_vertices(&self, removed: &[FaceId]) -> Vec<VertexId> {
        sorted_unique(removed.iter().flat_map(|&f| self.face(f)).collect())
    }

    /// The vertices of `region` (the sorted `removed` faces' vertices) that `edit` leaves without
    /// faces, in id order.
    fn vanishing(&self, edit: &Edit, removed: &[FaceId], region: &[VertexId]) -> Vec<VertexId> {
        let in_new = sorted_unique(
            edit.add
                .iter()
                .flatten()
                .filter_map(|r| match *r {
                    VertexRef::Old(v) => Some(v),
                    VertexRef::New(_) => None,
                })
                .collect(),
        );
        region
            .iter()
            .copied()
            .filter(|v| {
                in_new.binary_search(v).is_err()
                    && self
                        .vertex_faces(*v)
                        .iter()
                        .all(|f| removed.binary_search(f).is_ok())
            })
            .collect()
    }

    /// The new faces cover exactly the removed region (sorted): directed boundaries cancel except
    /// along the cloth border, where old and new border chains cover the same straight segments;
    /// areas agree. Returns the new faces' directed edges, sorted (each once: no two new faces
    /// traverse the same edge the same way).
    fn check_tiling(
        &self,
        edit: &Edit,
        removed: &[FaceId],
        added: &[[Key; 3]],
        pos: &dyn Fn(Key) -> Vec2,
    ) -> Result<Vec<(Key, Key)>, EditError> {
        let not = EditError::NotATiling;
        // A conforming mesh traverses each directed edge once: no duplicates to remove.
        let mut old_dir: Vec<(Key, Key)> = removed
            .iter()
            .flat_map(|&f| {
                let vs = self.face(f).map(Key::Old);
                (0..3).map(move |k| (vs[k], vs[(k + 1) % 3]))
            })
            .collect();
        old_dir.sort_unstable();
        // Each directed edge with its corner slot `3 i + k` (face i, corner k), the slots in order.
        let mut slots: Vec<((Key, Key), usize)> = added
            .iter()
            .enumerate()
            .flat_map(|(i, keys)| (0..3).map(move |k| ((keys[k], keys[(k + 1) % 3]), 3 * i + k)))
            .collect();
        slots.sort_unstable();
        // Two faces traversing one edge the same way: report the first repeat in face order.
        if let Some(w) = slots
            .windows(2)
            .filter(|w| w[0].0 == w[1].0)
            .min_by_key(|w| w[1].1)
        {
            let (e, j, i) = (w[1].0, w[0].1 / 3, w[1].1 / 3);
            return Err(not(format!(
                "new faces {j} and {i} overlap (both traverse {e:?})"
            )));
        }
        let new_dir: Vec<(Key, Key)> = slots.into_iter().map(|(e, _)| e).collect();
        let border = |dir: &[(Key, Key)]| -> Vec<(Key, Key)> {
            dir.iter()
                .filter(|&&(a, b)| dir.binary_search(&(b, a)).is_err())
                .copied()
                .collect()
        };
        let (old_border, new_border) = (border(&old_dir), border(&new_dir));
        let minus = |a: &[(Key, Key)], b: &[(Key, Key)]| -> Vec<(Key, Key)> {
            a.iter()
                .filter(|e| b.binary_search(e).is_err())
                .copied()
                .collect()
        };
        let old_rest = minus(&old_border, &new_border);
        let new_rest = minus(&new_border, &old_border);
        // Remaining old edges must be cloth-border edges.
        for &(a, b) in &old_rest {
            if let (Key::Old(va), Key::Old(vb)) = (a, b) {
                if let Some(g) = self
                    .edge(va, vb)
                    .and_then(|e| e.iter().find(|g| removed.binary_search(g).is_err()))
                {
                    return Err(not(format!(
                        "edge {}-{} between the region and kept face {} is not reproduced by the \
                         new faces",
                        va.0, vb.0, g.0
                    )));
                }
            }
        }
        match_border_chains(&old_rest, &new_rest, pos).map_err(not)?;
        // Areas.
        let area_old: Real = removed.iter().map(|&f| self.face_rest_area(f)).sum();
        let mut area_new = 0.0;
        let mut allowance = 0.0;
        for keys in added {
            let [a, b, c] = keys.map(pos);
            area_new += signed_area(a, b, c);
            let scale = a.abs().max().max(b.abs().max()).max(c.abs().max());
            allowance += 16.0 * Real::EPSILON * scale * ((b - a).norm() + (c - b).norm());
        }
        for &f in removed {
            let [a, b, c] = self.face(f).map(|v| self.rest(v));
            let scale = a.abs().max().max(b.abs().max()).max(c.abs().max());
            allowance += 16.0 * Real::EPSILON * scale * ((b - a).norm() + (c - b).norm());
        }
        let error = (area_new - area_old).abs();
        if error.is_nan() || error > AREA_EDIT_REL_TOL * area_old + allowance {
            return Err(not(format!(
                "removed faces cover {area_old:e} m², new faces {area_new:e} m² ({} new vertices)",
                edit.new_vertices.len()
            )));
        }
        Ok(new_dir)
    }

    /// No edge with three faces or inconsistent orientation against the kept mesh, and a single fan
    /// around every vertex of a new face.
    fn check_local_conformity(
        &self,
        removed: &[FaceId],
        added: &[[Key; 3]],
        new_dir: &[(Key, Key)],
    ) -> Result<(), EditError> {
        let conf =
            |rule: Rule, at: String| Err(EditError::Conformity(ConformityError { rule, at }));
        for (i, keys) in added.iter().enumerate() {
            for k in 0..3 {
                let (Key::Old(a), Key::Old(b)) = (keys[k], keys[(k + 1) % 3]) else {
                    continue;
                };
                let Some(ef) = self.edge(a, b) else { continue };
                for g in ef.iter().filter(|g| removed.binary_search(g).is_err()) {
                    if has_directed(self.face(g), a, b) {
                        return conf(
                            Rule::Orientation,
                            format!(
                                "new face {i} and kept face {} both traverse {}->{}",
                                g.0, a.0, b.0
                            ),
                        );
                    }
                    // A kept face b->a is fine only when no other new face also uses a-b (another
                    // new face traversing a->b was refused by the tiling check, so it would
                    // traverse b->a).
                    let twice = new_dir.binary_search(&(keys[(k + 1) % 3], keys[k])).is_ok();
                    if twice || ef.extra > 0 {
                        return conf(
                            Rule::EdgeFaceCount,
                            format!("edge {}-{} would have more than two faces", a.0, b.0),
                        );
                    }
                }
            }
        }
        // Every new face's wedge at each of its corners, grouped by corner in face order.
        let mut corners: Vec<(Key, (Key, Key))> = added
            .iter()
            .flat_map(|&keys| keys.map(|v| (v, wedge(keys, v))))
            .collect();
        corners.sort_by_key(|&(v, _)| v);
        let mut wedges = Vec::new();
        for group in corners.chunk_by(|a, b| a.0 == b.0) {
            let v = group[0].0;
            wedges.clear();
            if let Key::Old(ov) = v {
                for &f in self
                    .vertex_faces(ov)
                    .iter()
                    .filter(|f| removed.binary_search(f).is_err())
                {
                    let vs = self.face(f).map(Key::Old);
                    wedges.push(wedge(vs, v));
                }
            }
            wedges.extend(group.iter().map(|&(_, w)| w));
            if let Err(why) = single_fan(&wedges) {
                return conf(Rule::NonManifoldVertex, format!("vertex {v:?}: {why}"));
            }
        }
        Ok(())
    }
}

/// Relative tolerance on the equality of removed and added rest areas (dimensionless).
const AREA_EDIT_REL_TOL: Real = 1e-12;

/// A vertex of the edit: an existing one or a new one (ordered old first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Key {
    Old(VertexId),
    New(usize),
}

/// `items` sorted, each once.
fn sorted_unique<T: Ord>(mut items: Vec<T>) -> Vec<T> {
    items.sort_unstable();
    items.dedup();
    items
}

fn resolve(r: VertexRef, new_ids: &[VertexId]) -> VertexId {
    match r {
        VertexRef::Old(v) => v,
        VertexRef::New(k) => new_ids[k],
    }
}

/// The wedge `x -> y` of face `vs` seen from its vertex `v`.
fn wedge(vs: [Key; 3], v: Key) -> (Key, Key) {
    let k = (0..3).find(|&k| vs[k] == v).unwrap_or(0);
    (vs[(k + 1) % 3], vs[(k + 2) % 3])
}

/// The remaining old and new border edges must cover the same straight rest segments: from every
/// vertex where both an old and a new chain start, walk both chains along the first old edge's
/// direction, always advancing the one behind, until they meet at a common vertex; every vertex
/// passed must lie on that line, strictly ahead. Every edge must be consumed by some walk.
fn match_border_chains(
    old: &[(Key, Key)],
    new: &[(Key, Key)],
    pos: &dyn Fn(Key) -> Vec2,
) -> Result<(), String> {
    let outgoing = |edges: &[(Key, Key)]| -> Result<BTreeMap<Key, Key>, String> {
        let mut m = BTreeMap::new();
        for &(a, b) in edges {
            if m.insert(a, b).is_some() {
                return Err(format!("two region border edges leave {a:?}"));
            }
        }
        Ok(m)
    };
    let (out_old, out_new) = (outgoing(old)?, outgoing(new)?);
    let mut used_old = BTreeSet::new();
    let mut used_new = BTreeSet::new();
    for (&s, &first_old) in &out_old {
        let Some(&first_new) = out_new.get(&s) else {
            continue;
        };
        if used_old.contains(&s) || used_new.contains(&s) {
            continue;
        }
        used_old.insert(s);
        used_new.insert(s);
        let origin = pos(s);
        let dir = pos(first_old) - origin;
        let len = dir.norm();
        let dir = dir / len;
        let tol = ON_EDGE_REL_TOL * len.max((pos(first_new) - origin).norm());
        let param = |k: Key| -> Result<Real, String> {
            let d = pos(k) - origin;
            if dir.perp(&d).abs() > tol.max(ON_EDGE_REL_TOL * d.norm()) {
                return Err(format!(
                    "border vertex {k:?} is off the border line from {s:?}"
                ));
            }
            Ok(d.dot(&dir))
        };
        let (mut eo, mut en) = (first_old, first_new);
        let (mut to, mut tn) = (len, param(en)?);
        for _ in 0..old.len() + new.len() {
            if eo == en {
                break;
            }
            let (ends, outs, used, t) = if to < tn {
                (&mut eo, &out_old, &mut used_old, &mut to)
            } else {
                (&mut en, &out_new, &mut used_new, &mut tn)
            };
            let from = *ends;
            let next = *outs
                .get(&from)
                .ok_or_else(|| format!("border chains from {s:?} end apart at {from:?}"))?;
            if !used.insert(from) {
                return Err(format!("border edge from {from:?} matched twice"));
            }
            let tnext = param(next)?;
            if tnext <= *t {
                return Err(format!("border chain from {s:?} turns back at {next:?}"));
            }
            *ends = next;
            *t = tnext;
        }
        if eo != en {
            return Err(format!(
                "border chains from {s:?} do not meet ({eo:?} vs {en:?})"
            ));
        }
    }
    if let Some(&(a, b)) = old.iter().find(|e| !used_old.contains(&e.0)) {
        return Err(format!(
            "old border edge {a:?}->{b:?} is not covered by new faces"
        ));
    }
    if let Some(&(a, b)) = new.iter().find(|e| !used_new.contains(&e.0)) {
        return Err(format!(
            "new face edge {a:?}->{b:?} lies outside the removed region"
        ));
    }
    Ok(())
}

#[cfg(test)]
#[path = "edit_tests.rs"]
mod tests;
