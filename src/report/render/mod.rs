//! Pictures of runs: a small software rasteriser to PNG, outside the step loop.
//!
//! Reads the OBJ frames a run writes ([`FrameMesh::read`]), builds drawable triangle meshes of the
//! scene's obstacles ([`obstacle_meshes`]) and draws them with a perspective camera looking down
//! at 30 degrees from a 3/4 view: one picture ([`render_png`]) or a grid of snapshots, one row per
//! run and one column per time ([`snapshot_grid`]). The reports and `adaptcloth render` use it; the
//! simulation never does.
//!
//! Files: `error_map.rs` (the error map of a run over its rest-space mesh), `obstacles.rs` (obstacle tessellation), `camera.rs` (framing
//! and projection), `raster.rs` (z-buffered triangle fill with barycentric edge lines), `text.rs`
//! (labels with the DejaVu font), `picture.rs` (the public pictures and PNG encoding).
//!
//! Everything is deterministic: same meshes, same bytes.

mod camera;
pub mod error_map;
mod obstacles;
mod picture;
mod raster;
mod text;

pub use obstacles::{obstacle_meshes, ObstacleMeshes};
pub(crate) use picture::encode_png;
pub use picture::{render_png, snapshot_grid, SnapshotRow, MAX_PIXELS, MAX_SIDE};

use std::path::PathBuf;

/// A triangle mesh to draw: world positions (m) and counter-clockwise faces (0-based indices
/// into `positions`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameMesh {
    /// Vertex positions (m), z up.
    pub positions: Vec<[f32; 3]>,
    /// Triangles as 0-based vertex indices; every index is below `positions.len()`.
    pub faces: Vec<[u32; 3]>,
}

impl FrameMesh {
    /// Axis-aligned bounds `(min, max)` (m), or `None` for a mesh without vertices.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.positions.first()?;
        let mut lo = first;
        let mut hi = first;
        for p in &self.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }
}

/// Why a frame could not be read or a picture not drawn.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// An OBJ file could not be read or parsed.
    #[error(transparent)]
    Obj(#[from] crate::io::ObjError),
    /// A mesh to draw refers to a vertex it does not have.
    #[error("face {face} refers to vertex {index} but the mesh has {vertex_count} vertices")]
    BadFace {
        /// Index of the face in `faces`.
        face: usize,
        /// The offending 0-based vertex index.
        index: u32,
        /// Number of vertices of the mesh.
        vertex_count: usize,
    },
    /// A picture size that cannot be drawn (zero, or above 16384 pixels a side).
    #[error(
        "cannot draw a {width}x{height} picture: expected sides of 1 to {MAX_SIDE} pixels and at \
         most {MAX_PIXELS} pixels in all (4096x4096; drawing takes about 55 bytes a pixel)"
    )]
    Size {
        /// Width (pixels).
        width: u32,
        /// Height (pixels).
        height: u32,
    },
    /// An obstacle cannot be turned into a drawable mesh.
    #[error("obstacle {index}: {reason}")]
    Obstacle {
        /// Index of the obstacle in the scene's list.
        index: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// PNG encoding failed.
    #[error("{}: PNG encoding: {source}", path.display())]
    Png {
        /// The file being written.
        path: PathBuf,
        /// The encoder's error.
        #[source]
        source: png::EncodingError,
    },
}

impl FrameMesh {
    /// Reads an OBJ file (a run's frame, or an obstacle mesh): its positions and fan triangles.
    pub fn read(path: &std::path::Path) -> Result<FrameMesh, RenderError> {
        Ok(FrameMesh::from_obj(&crate::io::read_obj(path)?))
    }

    /// The drawable mesh of a parsed OBJ file (positions rounded to `f32`).
    pub fn from_obj(obj: &crate::io::ObjFile) -> FrameMesh {
        FrameMesh {
            positions: obj.positions.iter().map(|p| p.map(|x| x as f32)).collect(),
            faces: obj.triangles().map(|(_, t)| t.map(|i| i as u32)).collect(),
        }
    }

    /// Checks that every face index is in range.
    pub fn validate(&self) -> Result<(), RenderError> {
        let n = self.positions.len();
        for (face, f) in self.faces.iter().enumerate() {
            if let Some(&index) = f.iter().find(|&&i| i as usize >= n) {
                return Err(RenderError::BadFace {
                    face,
                    index,
                    vertex_count: n,
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
