//! The collision module's error type.

/// Why the obstacles of a scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum CollisionError {
    /// An OBJ mesh file could not be read or parsed (names the file and the line).
    #[error(transparent)]
    MeshFile(#[from] crate::io::ObjError),
    /// An obstacle's geometry is invalid (non-positive or non-finite size, bad mesh, ...).
    #[error("obstacle {index}: {message}")]
    BadShape {
        /// Index of the obstacle in the scene's `[[obstacles]]` list.
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// A `[collision]` parameter is invalid (negative margin, ...).
    #[error("collision: {message}")]
    BadParameter {
        /// What is wrong.
        message: String,
    },
}
