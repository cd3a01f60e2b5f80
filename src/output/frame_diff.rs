//! Comparing two frames (`frame_*.obj`) of runs on the same pattern: the RMS distance between
//! their vertices, which are the same material points when both runs kept the same mesh.

use crate::math::{Real, Vec3};
use std::path::Path;

/// Why two frames cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum FrameDiffError {
    /// A frame could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The frame.
        path: String,
        /// The error.
        source: std::io::Error,
    },
    /// A `v` line is not three numbers.
    #[error("{path}:{line}: expected `v x y z`")]
    Parse {
        /// The frame.
        path: String,
        /// 1-based line.
        line: usize,
    },
    /// The frames have different vertex counts (different meshes).
    #[error("the frames have {0} and {1} vertices: not the same mesh")]
    Mismatch(usize, usize),
}

/// The world positions (m) of a frame's `v` lines, in order.
pub fn read_frame_positions(path: &Path) -> Result<Vec<Vec3>, FrameDiffError> {
    let text = std::fs::read_to_string(path).map_err(|source| FrameDiffError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let Some(rest) = line.strip_prefix("v ") else {
            continue;
        };
        let c: Vec<Real> = rest
            .split_whitespace()
            .filter_map(|s| s.parse().ok())
            .collect();
        if c.len() != 3 {
            return Err(FrameDiffError::Parse {
                path: path.display().to_string(),
                line: k + 1,
            });
        }
        out.push(Vec3::new(c[0], c[1], c[2]));
    }
    Ok(out)
}

/// RMS and largest distance (m) between corresponding vertices of two frames.
pub fn frame_distance(a: &Path, b: &Path) -> Result<(Real, Real), FrameDiffError> {
    let (pa, pb) = (read_frame_positions(a)?, read_frame_positions(b)?);
    if pa.len() != pb.len() || pa.is_empty() {
        return Err(FrameDiffError::Mismatch(pa.len(), pb.len()));
    }
    let (mut sum, mut max) = (0.0, 0.0 as Real);
    for (p, q) in pa.iter().zip(&pb) {
        let d = (p - q).norm();
        sum += d * d;
        max = max.max(d);
    }
    Ok(((sum / pa.len() as Real).sqrt(), max))
}
