//! Comparing two frames (`frame_*.obj`) of runs on the same pattern: the RMS distance between
//! their vertices, which are the same material points when both runs kept the same mesh.

use crate::io::{read_obj, ObjError};
use std::path::Path;

/// Why two frames cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum FrameDiffError {
    /// A frame could not be read.
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// The frames have different vertex counts (different meshes).
    #[error("the frames have {0} and {1} vertices: not the same mesh")]
    Mismatch(usize, usize),
}

/// RMS and largest distance (m) between corresponding vertices of two frames.
pub fn frame_distance(a: &Path, b: &Path) -> Result<(f64, f64), FrameDiffError> {
    let (pa, pb) = (read_obj(a)?.positions, read_obj(b)?.positions);
    if pa.len() != pb.len() || pa.is_empty() {
        return Err(FrameDiffError::Mismatch(pa.len(), pb.len()));
    }
    let (mut sum, mut max) = (0.0, 0.0f64);
    for (p, q) in pa.iter().zip(&pb) {
        let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
        sum += d * d;
        max = max.max(d);
    }
    Ok(((sum / pa.len() as f64).sqrt(), max))
}
