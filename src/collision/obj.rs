//! A minimal OBJ reader for obstacle meshes: `v` and `f` lines only, every other line ignored.
//!
//! Faces may be written `a`, `a/b`, `a/b/c` or `a//c` (only the position index is used; negative
//! indices count back from the last vertex read); polygons are fan-triangulated.

use super::error::CollisionError;
use crate::math::{Real, Vec3};
use std::path::Path;

/// Vertices (m, as written in the file) and triangles (0-based vertex indices) of an OBJ file.
#[derive(Clone, Debug, Default)]
pub(crate) struct ObjMesh {
    /// Vertex positions.
    pub vertices: Vec<Vec3>,
    /// Triangles, counter-clockwise seen from outside for an outward-oriented mesh.
    pub triangles: Vec<[u32; 3]>,
}

/// Reads the OBJ file at `path`.
pub(crate) fn read_obj(path: &Path) -> Result<ObjMesh, CollisionError> {
    let text = std::fs::read_to_string(path).map_err(|source| CollisionError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_obj(&text, path)
}

/// Parses OBJ text; `path` is only used in error messages.
pub(crate) fn parse_obj(text: &str, path: &Path) -> Result<ObjMesh, CollisionError> {
    let mut mesh = ObjMesh::default();
    let mut face: Vec<u32> = Vec::new();
    for (line_index, raw) in text.lines().enumerate() {
        let line_no = line_index + 1;
        let err = |message: String| CollisionError::MeshFile {
            path: path.to_path_buf(),
            line: line_no,
            message,
        };
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let mut c = [0.0; 3];
                for (k, slot) in c.iter_mut().enumerate() {
                    let token = tokens
                        .next()
                        .ok_or_else(|| err(format!("vertex has {k} coordinates, expected 3")))?;
                    let value: Real = token
                        .parse()
                        .map_err(|_| err(format!("bad vertex coordinate `{token}`")))?;
                    if !value.is_finite() {
                        return Err(err(format!("non-finite vertex coordinate `{token}`")));
                    }
                    *slot = value;
                }
                mesh.vertices.push(Vec3::new(c[0], c[1], c[2]));
            }
            Some("f") => {
                face.clear();
                for token in tokens {
                    let index_text = token.split('/').next().unwrap_or("");
                    let index: i64 = index_text
                        .parse()
                        .map_err(|_| err(format!("bad face index `{token}`")))?;
                    let n = mesh.vertices.len() as i64;
                    let resolved = if index > 0 { index - 1 } else { n + index };
                    if index == 0 || resolved < 0 || resolved >= n {
                        return Err(err(format!(
                            "face index {index} out of range (1..={n} vertices read so far)"
                        )));
                    }
                    face.push(resolved as u32);
                }
                if face.len() < 3 {
                    return Err(err(format!(
                        "face has {} vertices, expected at least 3",
                        face.len()
                    )));
                }
                for k in 1..face.len() - 1 {
                    mesh.triangles.push([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if mesh.triangles.is_empty() {
        return Err(CollisionError::MeshFile {
            path: path.to_path_buf(),
            line: 0,
            message: "no faces: an obstacle mesh needs at least one `f` line".into(),
        });
    }
    Ok(mesh)
}
