//! A patch: a copy of some faces of a mesh as a mesh of its own, for trying an edit on a small
//! copy before applying it (the energy law of `crate::adapt::energy`).

use super::check::single_fan;
use super::{FaceId, Mesh, VertexId};
use std::collections::{BTreeMap, BTreeSet};

/// A copy of some faces of a mesh. Local ids keep the order of the original ids, so sums over a
/// vertex's faces or over the edges run in the same order in the patch as in the mesh.
#[derive(Clone, Debug)]
pub struct Patch {
    /// The copied faces as a mesh (rest coordinates and pinned flags copied).
    pub mesh: Mesh,
    /// The original vertex of every local vertex slot.
    pub vertices: Vec<VertexId>,
    /// Local vertex of every copied original vertex.
    pub vertex_map: BTreeMap<VertexId, VertexId>,
    /// Local face of every copied original face.
    pub face_map: BTreeMap<FaceId, FaceId>,
}

impl Mesh {
    /// The patch of every face having a vertex in `core` (live vertices), grown by the whole star
    /// of any other vertex whose copied faces would not form a single fan, so the patch is
    /// conforming. Every vertex of `core` has all its faces in the patch (its mass, springs and
    /// bending elements are those of the mesh).
    pub fn patch(&self, core: &BTreeSet<VertexId>) -> Patch {
        // Sorted vectors: a patch is a few dozen faces, built for every trial of an edit.
        let mut faces: Vec<FaceId> = core
            .iter()
            .flat_map(|&v| self.vertex_faces(v).iter().copied())
            .collect();
        faces.sort_unstable();
        faces.dedup();
        let mut complete: Vec<VertexId> = core.iter().copied().collect();
        let mut wedges: Vec<(VertexId, VertexId)> = Vec::new();
        loop {
            let mut split = Vec::new();
            for v in sorted_vertices(self, &faces) {
                if complete.binary_search(&v).is_ok() {
                    continue;
                }
                wedges.clear();
                wedges.extend(
                    self.vertex_faces(v)
                        .iter()
                        .filter(|f| faces.binary_search(f).is_ok())
                        .map(|&f| wedge(self.face(f), v)),
                );
                if single_fan(&wedges).is_err() {
                    split.push(v);
                }
            }
            if split.is_empty() {
                break;
            }
            for &v in &split {
                faces.extend(self.vertex_faces(v).iter().copied());
            }
            faces.sort_unstable();
            faces.dedup();
            complete.extend(split);
            complete.sort_unstable();
        }
        let used = sorted_vertices(self, &faces);
        let mut out = Patch {
            mesh: Mesh::with_capacity(used.len(), faces.len()),
            vertices: Vec::with_capacity(used.len()),
            vertex_map: BTreeMap::new(),
            face_map: BTreeMap::new(),
        };
        let mut vertex_map = Vec::with_capacity(used.len());
        for v in used {
            let local = out.mesh.push_vertex(self.rest(v));
            out.mesh.pinned[local.0 as usize] = self.is_pinned(v);
            out.vertices.push(v);
            vertex_map.push((v, local));
        }
        let local = |v: VertexId| {
            let k = vertex_map
                .binary_search_by_key(&v, |&(original, _)| original)
                .expect("a face's vertices are in the patch");
            vertex_map[k].1
        };
        let mut face_map = Vec::with_capacity(faces.len());
        for f in faces {
            let vs = self.face(f).map(local);
            face_map.push((f, out.mesh.push_face(vs)));
        }
        out.vertex_map = vertex_map.into_iter().collect();
        out.face_map = face_map.into_iter().collect();
        out.mesh.pattern_area = out.mesh.faces().map(|f| out.mesh.face_rest_area(f)).sum();
        out
    }
}

/// The vertices of `faces`, sorted, each once.
fn sorted_vertices(mesh: &Mesh, faces: &[FaceId]) -> Vec<VertexId> {
    let mut vertices: Vec<VertexId> = faces.iter().flat_map(|&f| mesh.face(f)).collect();
    vertices.sort_unstable();
    vertices.dedup();
    vertices
}

/// The wedge `x -> y` of face `vs` around its vertex `v`.
fn wedge(vs: [VertexId; 3], v: VertexId) -> (VertexId, VertexId) {
    let k = (0..3).find(|&k| vs[k] == v).unwrap_or(0);
    (vs[(k + 1) % 3], vs[(k + 2) % 3])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::union_jack;

    #[test]
    fn a_patch_holds_the_stars_of_its_core_in_the_same_order() {
        let mesh = union_jack(5, 5, 1.0, 1.0);
        let core: BTreeSet<VertexId> = [VertexId(6), VertexId(12)].into();
        let p = mesh.patch(&core);
        p.mesh.check().unwrap();
        for v in &core {
            let local = p.vertex_map[v];
            assert_eq!(
                p.mesh.vertex_faces(local).len(),
                mesh.vertex_faces(*v).len()
            );
            assert!(
                (p.mesh.vertex_rest_area(local) - mesh.vertex_rest_area(*v)).abs() == 0.0,
                "same faces, same order, same sum"
            );
        }
        // Local ids follow the original order.
        assert!(p.vertices.windows(2).all(|w| w[0] < w[1]));
        let faces: Vec<FaceId> = p.face_map.keys().copied().collect();
        assert!(faces
            .windows(2)
            .all(|w| p.face_map[&w[0]] < p.face_map[&w[1]]));
    }

    #[test]
    fn a_patch_is_grown_where_its_faces_would_pinch_a_vertex() {
        // Two vertices two cells apart on a 5x5 grid: their stars touch at vertices shared by
        // faces that are not adjacent, which the closure completes.
        let mesh = union_jack(5, 5, 1.0, 1.0);
        for pair in [[6, 8], [6, 18], [0, 12], [7, 17]] {
            let core: BTreeSet<VertexId> = pair.map(VertexId).into();
            let p = mesh.patch(&core);
            p.mesh.check().unwrap_or_else(|e| panic!("{pair:?}: {e}"));
        }
    }
}
