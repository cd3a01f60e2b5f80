//! Comparing two frames (`frame_*.obj`) of runs on the same pattern: the RMS distance between
//! their vertices, which are the same material points when both runs kept the same mesh.

use crate::io::{read_obj, ObjError, ObjFile};
use std::path::Path;

/// Why two frames cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum FrameDiffError {
    /// A frame could not be read.
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// The frames are not of the same mesh: different vertex counts, faces or rest coordinates
    /// (`vt`); the message says which.
    #[error("not the same mesh: {0}")]
    Mismatch(String),
}

/// RMS and largest distance (m) between corresponding vertices of two frames of the same mesh:
/// the same vertex count, the same faces (corner by corner, `vt` indices included) and the same
/// rest coordinates (`vt`); [`FrameDiffError::Mismatch`] otherwise.
pub fn frame_distance(a: &Path, b: &Path) -> Result<(f64, f64), FrameDiffError> {
    let (fa, fb) = (read_obj(a)?, read_obj(b)?);
    same_mesh(&fa, &fb).map_err(FrameDiffError::Mismatch)?;
    let (pa, pb) = (fa.positions, fb.positions);
    let (mut sum, mut max) = (0.0, 0.0f64);
    for (p, q) in pa.iter().zip(&pb) {
        let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
        sum += d * d;
        max = max.max(d);
    }
    Ok(((sum / pa.len() as f64).sqrt(), max))
}

/// Why `a` and `b` are not frames of the same mesh (first difference found), `Ok` when they are.
fn same_mesh(a: &ObjFile, b: &ObjFile) -> Result<(), String> {
    let (na, nb) = (a.positions.len(), b.positions.len());
    if na != nb || na == 0 {
        return Err(format!("the frames have {na} and {nb} vertices"));
    }
    if a.faces.len() != b.faces.len() {
        return Err(format!(
            "the frames have {} and {} faces",
            a.faces.len(),
            b.faces.len()
        ));
    }
    if let Some((fa, fb)) = a
        .faces
        .iter()
        .zip(&b.faces)
        .find(|(fa, fb)| fa.corners != fb.corners)
    {
        return Err(format!(
            "the faces differ (the first frame's line {}, the second's line {})",
            fa.line, fb.line
        ));
    }
    if a.texcoords.len() != b.texcoords.len() {
        return Err(format!(
            "the frames have {} and {} rest coordinates (`vt`)",
            a.texcoords.len(),
            b.texcoords.len()
        ));
    }
    if let Some(i) = (0..a.texcoords.len()).find(|&i| a.texcoords[i] != b.texcoords[i]) {
        return Err(format!(
            "the rest coordinates differ (`vt` {} is {:?} and {:?})",
            i + 1,
            a.texcoords[i],
            b.texcoords[i]
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n\
                       f 1/1 2/2 3/3\nf 2/2 4/4 3/3\n";

    fn diff(a: &str, b: &str) -> Result<(f64, f64), FrameDiffError> {
        let dir = tempfile::tempdir().unwrap();
        let (pa, pb) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
        std::fs::write(&pa, a).unwrap();
        std::fs::write(&pb, b).unwrap();
        frame_distance(&pa, &pb)
    }

    #[test]
    fn same_mesh_moved_gives_the_distance() {
        let moved = TWO.replace("v 1 1 0", "v 1 1 2");
        let (rms, max) = diff(TWO, &moved).unwrap();
        assert_eq!(max, 2.0);
        assert_eq!(rms, 1.0);
    }

    /// Regression (trial report A8): equal vertex counts with other faces compared as 0.
    #[test]
    fn frame_diff_refuses_other_faces() {
        let other = TWO.replace("f 2/2 4/4 3/3", "f 1/1 2/2 3/3");
        let e = diff(TWO, &other).unwrap_err().to_string();
        assert!(e.contains("not the same mesh: the faces differ"), "{e}");
        let fewer = TWO.replace("f 2/2 4/4 3/3\n", "");
        let e = diff(TWO, &fewer).unwrap_err().to_string();
        assert!(e.contains("2 and 1 faces"), "{e}");
    }

    /// Regression (trial report A8): other rest coordinates compared as 0.
    #[test]
    fn frame_diff_refuses_other_rest_coordinates() {
        let other = TWO.replace("vt 1 1", "vt 9 9");
        let e = diff(TWO, &other).unwrap_err().to_string();
        assert!(e.contains("the rest coordinates differ (`vt` 4"), "{e}");
    }
}
