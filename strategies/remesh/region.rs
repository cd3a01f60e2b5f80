//! Regions (MODEL.md §8.2 steps 2-3): selected edges grouped into connected components (edges are
//! adjacent when they share a face; petgraph's union-find), the region of a component (the faces
//! adjacent to its edges) and the directed border of the hole its removal leaves.

use super::RemeshError;
use crate::mesh::{EdgeKey, FaceId, Mesh, VertexId};
use petgraph::unionfind::UnionFind;
use std::collections::{BTreeMap, BTreeSet};

/// Groups `edges` (existing edges of `mesh`) into connected components: two edges are adjacent
/// when they share a face. Components come in the order of their smallest edge key, each sorted.
pub fn components(mesh: &Mesh, edges: &[EdgeKey]) -> Vec<Vec<EdgeKey>> {
    let mut sorted: Vec<EdgeKey> = edges
        .iter()
        .copied()
        .filter(|e| mesh.edge(e.0, e.1).is_some())
        .collect();
    sorted.sort_unstable();
    sorted.dedup();
    let mut uf = UnionFind::<usize>::new(sorted.len());
    for (i, e) in sorted.iter().enumerate() {
        let Some(faces) = mesh.edge(e.0, e.1) else {
            continue;
        };
        for f in faces.iter() {
            let vs = mesh.face(f);
            for k in 0..3 {
                if let Ok(j) = sorted.binary_search(&EdgeKey::new(vs[k], vs[(k + 1) % 3])) {
                    uf.union(i, j);
                }
            }
        }
    }
    let labels = uf.into_labeling();
    let mut groups: BTreeMap<usize, Vec<EdgeKey>> = BTreeMap::new();
    let mut order: Vec<usize> = Vec::new();
    for (i, e) in sorted.iter().enumerate() {
        let g = groups.entry(labels[i]).or_default();
        if g.is_empty() {
            order.push(labels[i]);
        }
        g.push(*e);
    }
    order
        .into_iter()
        .filter_map(|l| groups.remove(&l))
        .collect()
}

/// The region of an edge set: every face adjacent to one of its edges. Errors when an edge does
/// not exist or the set is empty.
pub fn region_faces(mesh: &Mesh, edges: &[EdgeKey]) -> Result<BTreeSet<FaceId>, RemeshError> {
    let mut faces = BTreeSet::new();
    for e in edges {
        let ef = mesh.edge(e.0, e.1).ok_or(RemeshError::NoSuchEdge(*e))?;
        faces.extend(ef.iter());
    }
    if faces.is_empty() {
        return Err(RemeshError::EmptyRegion);
    }
    Ok(faces)
}

/// One directed edge of a hole's border, with the hole on its left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct BorderEdge {
    /// Start vertex.
    pub from: VertexId,
    /// End vertex.
    pub to: VertexId,
    /// The removed face the edge belongs to.
    pub face: FaceId,
    /// True when the edge is on the cloth border (no kept face across it).
    pub cloth_border: bool,
}

/// The directed border of the hole left by removing `faces`, in (from, to) order.
pub(super) fn hole_border(mesh: &Mesh, faces: &BTreeSet<FaceId>) -> Vec<BorderEdge> {
    let mut directed: BTreeMap<(VertexId, VertexId), FaceId> = BTreeMap::new();
    for &f in faces {
        let vs = mesh.face(f);
        for k in 0..3 {
            directed.insert((vs[k], vs[(k + 1) % 3]), f);
        }
    }
    directed
        .iter()
        .filter(|((a, b), _)| !directed.contains_key(&(*b, *a)))
        .map(|(&(from, to), &face)| BorderEdge {
            from,
            to,
            face,
            cloth_border: mesh.edge(from, to).is_some_and(|e| e.is_border()),
        })
        .collect()
}

/// Vertices of the region that no kept face uses and that are not on the hole border: the old
/// vertices inside the hole.
pub(super) fn interior_vertices(
    mesh: &Mesh,
    faces: &BTreeSet<FaceId>,
    border: &[BorderEdge],
) -> Vec<VertexId> {
    let on_border: BTreeSet<VertexId> = border.iter().flat_map(|e| [e.from, e.to]).collect();
    let mut out: Vec<VertexId> = faces
        .iter()
        .flat_map(|&f| mesh.face(f))
        .filter(|v| !on_border.contains(v))
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}
