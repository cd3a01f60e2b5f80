//! A small OBJ reader for drawing: `v` positions and `f` faces (`a`, `a/b`, `a/b/c`, `a//c`,
//! negative indices relative to the end), polygons fanned into triangles; `vt`, `vn`, groups,
//! materials and comments are skipped.

use super::{FrameMesh, RenderError};
use std::path::Path;

/// Reads an OBJ file, e.g. a frame a run wrote (`frames/frame_NNNNN.obj`): world positions and
/// 0-based triangles.
///
/// Errors: the file cannot be read ([`RenderError::Io`]), or a `v`/`f` line is malformed or refers
/// to a vertex not defined before it ([`RenderError::Obj`], with the 1-based line number).
pub fn read_obj_frame(path: &Path) -> Result<FrameMesh, RenderError> {
    let text = std::fs::read_to_string(path).map_err(|source| RenderError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_obj(&text, path)
}

/// The simulated time (s) of a frame, from the `# adaptcloth frame, t = T s` comment a run writes
/// on its first line; `None` when the file has no such comment.
pub fn read_obj_frame_time(path: &Path) -> Result<Option<f64>, RenderError> {
    use std::io::BufRead;
    let io = |source| RenderError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut first = String::new();
    std::io::BufReader::new(std::fs::File::open(path).map_err(io)?)
        .read_line(&mut first)
        .map_err(io)?;
    Ok(first
        .trim()
        .strip_prefix("# adaptcloth frame, t =")
        .and_then(|rest| rest.trim().trim_end_matches('s').trim().parse().ok()))
}

/// Parses OBJ text; `path` only names the source in errors.
pub(crate) fn parse_obj(text: &str, path: &Path) -> Result<FrameMesh, RenderError> {
    let mut mesh = FrameMesh::default();
    let err = |line: usize, expected: &str, found: &str| RenderError::Obj {
        path: path.to_path_buf(),
        line,
        expected: expected.to_string(),
        found: found.to_string(),
    };
    let mut corners: Vec<u32> = Vec::with_capacity(8);
    for (k, raw) in text.lines().enumerate() {
        let line_no = k + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut p = [0f32; 3];
                for c in &mut p {
                    *c = words
                        .next()
                        .and_then(|w| w.parse::<f32>().ok())
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| err(line_no, "`v x y z` with three finite numbers", raw))?;
                }
                mesh.positions.push(p);
            }
            Some("f") => {
                corners.clear();
                for w in words {
                    let index = w
                        .split('/')
                        .next()
                        .and_then(|s| s.parse::<i64>().ok())
                        .ok_or_else(|| {
                            err(line_no, "`f a b c` with integer vertex indices", raw)
                        })?;
                    let n = mesh.positions.len() as i64;
                    let zero_based = if index > 0 { index - 1 } else { n + index };
                    if index == 0 || zero_based < 0 || zero_based >= n {
                        let expected = format!("vertex indices in 1..={n} (or -{n}..=-1)");
                        return Err(err(line_no, &expected, raw));
                    }
                    corners.push(zero_based as u32);
                }
                if corners.len() < 3 {
                    return Err(err(line_no, "a face with at least three vertices", raw));
                }
                for i in 1..corners.len() - 1 {
                    mesh.faces.push([corners[0], corners[i], corners[i + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(mesh)
}
