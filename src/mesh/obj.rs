//! OBJ loading of a cloth: `v` world positions, `vt` rest coordinates, `f` faces.
use super::Mesh;
use crate::math::Vec3;
use std::path::Path;

/// A cloth read from OBJ: the mesh (rest space from `vt`) and the world positions.
pub struct ObjCloth {
    /// The mesh.
    pub mesh: Mesh,
    /// World position per vertex slot (m).
    pub positions: Vec<Vec3>,
}

/// Why an OBJ file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// I/O error.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The error.
        source: std::io::Error,
    },
}

/// Loads a cloth from an OBJ file.
pub fn load_obj(path: &Path) -> Result<ObjCloth, ObjError> {
    let _ = path;
    todo!()
}
