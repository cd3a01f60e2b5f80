//! Material points: locating a rest point in the mesh (barycentric coordinates).
use super::{FaceId, Mesh};
use crate::math::Vec2;

/// A rest point located in a face: the face and its barycentric weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Barycentric {
    /// The face containing the point.
    pub face: FaceId,
    /// Weights of the face's three vertices (sum to 1).
    pub weights: [f64; 3],
}

/// An acceleration structure over the faces' rest triangles, valid for one mesh version.
pub struct RestLocator {}

impl RestLocator {
    /// Builds the locator for the current mesh.
    pub fn new(mesh: &Mesh) -> Self {
        let _ = mesh;
        todo!()
    }

    /// The face containing rest point `p`, or `None` outside the pattern.
    pub fn locate(&self, mesh: &Mesh, p: Vec2) -> Option<Barycentric> {
        let _ = (mesh, p);
        todo!()
    }
}
