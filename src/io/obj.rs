//! The one OBJ reader and writer of the crate: cloth patterns ([`crate::mesh::load_obj`]), obstacle
//! meshes (collision), run frames (pictures, replays, `frame-diff`) all read through [`read_obj`].
//!
//! Read: `v x y z` (extra numbers such as `w` or colours ignored), `vt u v` (an optional `w`
//! ignored), `f` polygons whose corners are `a`, `a/ta`, `a/ta/na` or `a//na` with 1-based or
//! negative (relative to the counts read so far) indices; `vn`, `vp`, `l`, `o`, `g`, `s`,
//! `usemtl`, `mtllib` and comments are skipped; any other statement is an error. Indices may point
//! forward: they are checked against the final counts. Every error names the file and the 1-based
//! line, and says what was expected. Numbers must be finite.
//!
//! Written: the frames a run records ([`write_frame`]): a `# adaptcloth frame, t = T s` first line,
//! `v` world positions and `vt` rest coordinates with 9 decimals, `f v/vt` triangles.

use super::decimal::push_fixed9;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One face corner: 0-based indices into [`ObjFile::positions`] and [`ObjFile::texcoords`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjCorner {
    /// Vertex index.
    pub v: usize,
    /// Texture-coordinate index, if the corner has one.
    pub vt: Option<usize>,
}

/// One `f` statement: its corners (at least three) and its line in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjFace {
    /// 1-based line of the statement.
    pub line: usize,
    /// Corners in file order.
    pub corners: Vec<ObjCorner>,
}

/// The geometry of an OBJ file, every index checked in range.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjFile {
    /// `v` statements (as written; m for the crate's files).
    pub positions: Vec<[f64; 3]>,
    /// `vt` statements (the crate's cloth files: rest coordinates in m).
    pub texcoords: Vec<[f64; 2]>,
    /// `f` statements.
    pub faces: Vec<ObjFace>,
}

impl ObjFile {
    /// Every face fan-triangulated, as 0-based vertex indices, with the face's line.
    pub fn triangles(&self) -> impl Iterator<Item = (usize, [usize; 3])> + '_ {
        self.faces.iter().flat_map(|f| {
            let c = &f.corners;
            (1..c.len() - 1).map(move |k| (f.line, [c[0].v, c[k].v, c[k + 1].v]))
        })
    }

    /// Fan triangles as corners (vertex and texture indices), with the face's line.
    pub fn triangle_corners(&self) -> impl Iterator<Item = (usize, [ObjCorner; 3])> + '_ {
        self.faces.iter().flat_map(|f| {
            let c = &f.corners;
            (1..c.len() - 1).map(move |k| (f.line, [c[0], c[k], c[k + 1]]))
        })
    }
}

/// Why an OBJ file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A statement is malformed or an index is out of range.
    #[error("{}:{line}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What was expected and what was found.
        message: String,
    },
}

/// Reads and parses the OBJ file at `path`.
pub fn read_obj(path: &Path) -> Result<ObjFile, ObjError> {
    let text = super::read_text(path).map_err(|source| ObjError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_obj(&text, path)
}

/// Parses OBJ text; `path` only names the source in errors.
pub fn parse_obj(text: &str, path: &Path) -> Result<ObjFile, ObjError> {
    let err = |line: usize, message: String| ObjError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut obj = ObjFile::default();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut words = content.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword {
            "v" => {
                let [x, y, z] =
                    numbers::<3>(&mut words).map_err(|m| err(line, format!("`v`: {m}")))?;
                obj.positions.push([x, y, z]);
            }
            "vt" => {
                let [u, v] =
                    numbers::<2>(&mut words).map_err(|m| err(line, format!("`vt`: {m}")))?;
                obj.texcoords.push([u, v]);
            }
            "f" => {
                let counts = (obj.positions.len(), obj.texcoords.len());
                let corners = words
                    .map(|w| {
                        corner(w, counts).map_err(|m| err(line, format!("`f` corner `{w}`: {m}")))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                if corners.len() < 3 {
                    let found = corners.len();
                    return Err(err(
                        line,
                        format!("`f`: expected at least 3 corners, found {found}"),
                    ));
                }
                obj.faces.push(ObjFace { line, corners });
            }
            "vn" | "vp" | "l" | "o" | "g" | "s" | "usemtl" | "mtllib" => {}
            other => {
                return Err(err(
                    line,
                    format!("unsupported statement `{other}` (expected v, vt, f)"),
                ))
            }
        }
    }
    let (nv, nt) = (obj.positions.len(), obj.texcoords.len());
    for f in &obj.faces {
        for c in &f.corners {
            if c.v >= nv || c.vt.is_some_and(|t| t >= nt) {
                return Err(err(
                    f.line,
                    format!(
                        "`f`: index out of range: vertex {} of {nv}{}",
                        c.v + 1,
                        c.vt.map(|t| format!(", texture coordinate {} of {nt}", t + 1))
                            .unwrap_or_default()
                    ),
                ));
            }
        }
    }
    Ok(obj)
}

/// The first `N` words as finite numbers (further words ignored).
fn numbers<'a, const N: usize>(
    words: &mut impl Iterator<Item = &'a str>,
) -> Result<[f64; N], String> {
    let mut xs = [0.0; N];
    for (k, x) in xs.iter_mut().enumerate() {
        let w = words
            .next()
            .ok_or_else(|| format!("expected {N} numbers, found {k}"))?;
        *x = w
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("expected a finite number, found `{w}`"))?;
    }
    Ok(xs)
}

/// Parses `a`, `a/ta`, `a/ta/na` or `a//na`; `counts` are the vertex and texture-coordinate
/// counts read so far (negative indices count back from them).
fn corner(w: &str, counts: (usize, usize)) -> Result<ObjCorner, String> {
    let parts: Vec<&str> = w.split('/').collect();
    if parts.len() > 3 {
        return Err("expected v, v/vt, v/vt/vn or v//vn".into());
    }
    let index = |s: &str, count: usize, what: &str| -> Result<usize, String> {
        let i: i64 = s
            .parse()
            .map_err(|_| format!("expected an integer {what} index, found `{s}`"))?;
        let resolved = if i > 0 {
            Some(i as usize - 1)
        } else if i < 0 {
            count.checked_sub(i.unsigned_abs() as usize)
        } else {
            None
        };
        resolved.ok_or_else(|| format!("{what} index {i} is out of range"))
    };
    let v = index(parts[0], counts.0, "vertex")?;
    if let Some(n) = parts.get(2).filter(|n| !n.is_empty()) {
        index(n, usize::MAX, "normal")?;
    }
    let vt = match parts.get(1) {
        None | Some(&"") => None,
        Some(t) => Some(index(t, counts.1, "texture coordinate")?),
    };
    Ok(ObjCorner { v, vt })
}

/// The simulated time (s) of a frame, from the `# adaptcloth frame, t = T s` comment a run writes
/// on its first line; `None` when the first line is no such comment.
pub fn read_frame_time(path: &Path) -> Result<Option<f64>, ObjError> {
    use std::io::BufRead;
    let io = |source| ObjError::Io {
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

/// `DIR/frames/frame_NNNNN.obj`.
pub fn frame_path(out_dir: &Path, index: usize) -> PathBuf {
    out_dir.join("frames").join(format!("frame_{index:05}.obj"))
}

/// True when `name` is a frame file name [`frame_path`] makes: `frame_`, five or more digits,
/// `.obj`. Runs clear only these from a reused frames folder.
pub fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|r| r.strip_suffix(".obj"))
        .is_some_and(|d| d.len() >= 5 && d.bytes().all(|b| b.is_ascii_digit()))
}

/// Writes one frame atomically, unsynced ([`super::write_atomic_unsynced`]): the time comment, `v` world positions (m), `vt` rest coordinates
/// (m), `f v/vt` triangles of 0-based indices (written 1-based; the same index for `v` and `vt`).
pub fn write_frame(
    path: &Path,
    time: f64,
    positions: &[[f64; 3]],
    rest: &[[f64; 2]],
    triangles: &[[usize; 3]],
) -> std::io::Result<()> {
    let mut s = String::with_capacity(64 * positions.len() + 32 * triangles.len());
    let _ = writeln!(s, "# adaptcloth frame, t = {time:.6} s");
    let mut line = |tag: &str, coordinates: &[f64]| {
        s.push_str(tag);
        for &c in coordinates {
            s.push(' ');
            push_fixed9(&mut s, c);
        }
        s.push('\n');
    };
    for p in positions {
        line("v", p);
    }
    for r in rest {
        line("vt", r);
    }
    for t in triangles {
        let [a, b, c] = t.map(|i| i + 1);
        let _ = writeln!(s, "f {a}/{a} {b}/{b} {c}/{c}");
    }
    super::write_atomic_unsynced(path, s.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<ObjFile, ObjError> {
        parse_obj(text, Path::new("t.obj"))
    }

    fn line_of(e: ObjError) -> (usize, String) {
        match e {
            ObjError::Parse { line, message, .. } => (line, message),
            other => panic!("not a parse error: {other}"),
        }
    }

    #[test]
    fn polygons_fan_and_indices_resolve_negative_and_forward() {
        let obj = parse(
            "o x\nv 0 0 0\nv 1 0 0\nv 1 1 0 1\nvt 0 0\nf 1 2 3 -1\nf 1/1 2//5 -2/-1\nv 0 1 0\n",
        )
        .unwrap();
        assert_eq!(obj.positions.len(), 4);
        let tris: Vec<[usize; 3]> = obj.triangles().map(|t| t.1).collect();
        assert_eq!(tris, [[0, 1, 2], [0, 2, 2], [0, 1, 1]]);
        assert_eq!(obj.faces[1].corners[0].vt, Some(0));
        assert_eq!(obj.faces[1].corners[1].vt, None);
        // Forward references are checked against the final counts.
        assert!(parse("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").is_ok());
    }

    #[test]
    fn errors_name_the_line_and_the_expectation() {
        let cases = [
            ("v 0 0\n", 1, "expected 3 numbers"),
            ("v 0 0 0\nv 0 nan 0\n", 2, "finite number"),
            ("vt 0 x\n", 1, "finite number"),
            ("v 0 0 0\nf 1 1\n", 2, "at least 3 corners"),
            ("v 0 0 0\nf 1 a 1\n", 2, "integer vertex index"),
            ("v 0 0 0\nf 1 1 0\n", 2, "out of range"),
            ("v 0 0 0\n\nf 1 1 4\n", 3, "vertex 4 of 1"),
            (
                "v 0 0 0\nf 1/3 1/1 1/1\nvt 0 0\n",
                2,
                "texture coordinate 3 of 1",
            ),
            ("v 0 0 0\ncurv 1 2\n", 2, "unsupported statement `curv`"),
            ("v 0 0 0\nf 1/1/1/1 1 1\n", 2, "v/vt/vn"),
        ];
        for (text, line, expected) in cases {
            let (l, m) = line_of(parse(text).unwrap_err());
            assert_eq!(l, line, "{text:?}: {m}");
            assert!(m.contains(expected), "{text:?}: {m}");
        }
        let e = read_obj(Path::new("/nonexistent/x.obj")).unwrap_err();
        assert!(matches!(e, ObjError::Io { .. }));
    }

    #[test]
    fn a_written_frame_reads_back_with_its_time() {
        let dir = tempfile::tempdir().unwrap();
        let path = frame_path(dir.path(), 3);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        let p = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.5]];
        let r = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        write_frame(&path, 0.25, &p, &r, &[[0, 1, 2]]).unwrap();
        assert!(path.ends_with("frames/frame_00003.obj"));
        let obj = read_obj(&path).unwrap();
        assert_eq!(obj.positions, p);
        assert_eq!(obj.texcoords, r);
        assert_eq!(
            obj.triangles().map(|t| t.1).collect::<Vec<_>>(),
            [[0, 1, 2]]
        );
        assert_eq!(read_frame_time(&path).unwrap(), Some(0.25));
    }
}
