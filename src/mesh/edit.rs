//! The one checked mesh edit: replace a set of faces by new faces, possibly adding vertices.
//!
//! Every strategy's elementary operation (edge split, merge, bisection, region re-mesh) is
//! expressed as an [`Edit`]. [`Mesh::replace`] validates it, applies it, and returns an
//! [`EditRecord`]; on any error the mesh is left exactly as it was.

use super::{FaceId, Mesh, VertexId};
use crate::math::{Real, Vec2};

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
    /// A pinned vertex would be removed.
    #[error("the edit would remove pinned vertex {0:?}")]
    RemovesPinned(VertexId),
}

impl Mesh {
    /// Applies `edit` if it keeps the mesh conforming, returning what changed; see the module doc.
    pub fn replace(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        let _ = edit;
        todo!("implemented by the mesh work package")
    }
}
