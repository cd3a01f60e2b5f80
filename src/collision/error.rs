//! The collision module's error type.

use std::path::PathBuf;

/// Why the obstacles of a scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum CollisionError {
    /// A line of an OBJ mesh file could not be read (bad number, index out of range, ...).
    #[error("{}:{line}: {message}", path.display())]
    MeshFile {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line number (0 when the problem concerns the whole file).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A mesh file could not be opened or read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
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
