//! The collision module's error type.

/// Why the obstacles of a scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum CollisionError {
    /// An obstacle's OBJ mesh file could not be read or parsed (the error names the file and the
    /// line).
    #[error("obstacle {index}: {source}")]
    MeshFile {
        /// Index of the obstacle in the scene's `[[obstacles]]` list.
        index: usize,
        /// Why the file could not be read.
        source: crate::io::ObjError,
    },
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
