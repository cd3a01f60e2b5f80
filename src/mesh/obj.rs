//! OBJ loading of a cloth: `v` world positions, `vt` rest coordinates, `f` faces.
//!
//! Read at scene set-up, before the first step, through the crate's one OBJ reader
//! ([`crate::io::obj`], which states the syntax): `v` world positions (m), `vt` rest coordinates
//! (m, not normalised texture space), `f` polygons fan-triangulated. Every corner needs a `vt`;
//! a vertex used with two different rest coordinates would be a seam, which is not supported.
//! Faces must be consistently oriented in rest space: all clockwise ones are flipped, mixed
//! orientation is an error. Vertices used by no face are dropped (ids are compacted in file
//! order).
use super::{Mesh, MeshError};
use crate::io::obj::{read_obj, ObjCorner, ObjFile};
use crate::math::{signed_area, Real, Vec2, Vec3, MAX_COORDINATE};
use std::path::Path;

/// A cloth read from OBJ: the mesh (rest space from `vt`) and the world positions.
#[derive(Clone, Debug)]
pub struct ObjCloth {
    /// The mesh.
    pub mesh: Mesh,
    /// World position per vertex slot (m).
    pub positions: Vec<Vec3>,
}

/// Why an OBJ file could not be loaded as a cloth. Line numbers are 1-based.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file could not be read or parsed (names the file, the line and the expectation).
    #[error(transparent)]
    File(#[from] crate::io::ObjError),
    /// A face corner has no texture coordinate (`vt`), so the vertex has no rest position.
    #[error(
        "{path}:{line}: face corner has no texture coordinate; every corner needs `v/vt` \
         (vt gives the rest coordinates in m)"
    )]
    NoTexCoords {
        /// The file.
        path: String,
        /// The line.
        line: usize,
    },
    /// A vertex is used with two different texture coordinates (a seam).
    #[error(
        "{path}:{line}: vertex {vertex} is used with texture coordinates {first} and {second}; \
         seams (a vertex with two rest positions) are not supported"
    )]
    Seam {
        /// The file.
        path: String,
        /// The line of the second use.
        line: usize,
        /// The vertex (1-based, as in the file).
        vertex: usize,
        /// The first `vt` index (1-based).
        first: usize,
        /// The conflicting `vt` index (1-based).
        second: usize,
    },
    /// A face is degenerate in rest space, or faces have mixed orientation.
    #[error("{path}:{line}: {message}")]
    Orientation {
        /// The file.
        path: String,
        /// The line of the offending face.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The file has more vertices than a cloth may have ([`super::MAX_VERTICES`]).
    #[error(
        "{path}: {count} vertices; a cloth may have at most {max} (about {} GB of memory at \
         {} bytes each)",
        max * super::BYTES_PER_VERTEX / 1_000_000_000,
        super::BYTES_PER_VERTEX
    )]
    TooLarge {
        /// The file.
        path: String,
        /// Its vertex count.
        count: usize,
        /// [`super::MAX_VERTICES`].
        max: usize,
    },
    /// A vertex position or texture coordinate lies beyond [`crate::math::MAX_COORDINATE`].
    #[error(
        "{path}: {what} {index} is {value:e} m from the origin; expected coordinates within \
         ±{:e} m",
        MAX_COORDINATE
    )]
    OutOfRange {
        /// The file.
        path: String,
        /// `vertex` (`v`) or `texture coordinate` (`vt`).
        what: &'static str,
        /// Its index (1-based, as in the file).
        index: usize,
        /// Its largest coordinate's size.
        value: Real,
    },
    /// The file has no face.
    #[error("{path}: no face (`f`) statement")]
    NoFaces {
        /// The file.
        path: String,
    },
    /// The mesh built from the file breaks a conformity rule.
    #[error("{path}: {source}")]
    Mesh {
        /// The file.
        path: String,
        /// The error.
        source: MeshError,
    },
}

/// Loads a cloth from an OBJ file (format in the module doc). Never panics on malformed input;
/// every error names the file and, where it applies, the line.
pub fn load_obj(path: &Path) -> Result<ObjCloth, ObjError> {
    cloth_from_obj(&read_obj(path)?, &path.display().to_string())
}

/// A face corner: 0-based (vertex, texture coordinate) indices.
type Corner = (usize, usize);

/// Parses OBJ text as a cloth; `path` only names the source in errors.
#[cfg(test)]
pub(crate) fn parse_obj(text: &str, path: &str) -> Result<ObjCloth, ObjError> {
    cloth_from_obj(&crate::io::obj::parse_obj(text, Path::new(path))?, path)
}

/// The cloth of a parsed OBJ file; `path` names the source in errors.
/// The first of `rows` (`what`s of the file `path`, in file order) with a coordinate beyond
/// [`MAX_COORDINATE`], as an error.
fn far_coordinate<'a>(
    path: &str,
    what: &'static str,
    rows: impl Iterator<Item = &'a [Real]>,
) -> Option<ObjError> {
    rows.enumerate().find_map(|(k, row)| {
        let value = crate::math::largest_abs(row);
        (value > MAX_COORDINATE).then(|| ObjError::OutOfRange {
            path: path.to_string(),
            what,
            index: k + 1,
            value,
        })
    })
}

fn cloth_from_obj(obj: &ObjFile, path: &str) -> Result<ObjCloth, ObjError> {
    let no_tex = |line| ObjError::NoTexCoords {
        path: path.to_string(),
        line,
    };
    let tris: Vec<(usize, [Corner; 3])> = obj
        .triangle_corners()
        .map(|(line, c)| {
            let pair = |c: ObjCorner| c.vt.map(|t| (c.v, t)).ok_or_else(|| no_tex(line));
            Ok((line, [pair(c[0])?, pair(c[1])?, pair(c[2])?]))
        })
        .collect::<Result<_, ObjError>>()?;
    if obj.positions.len() > super::MAX_VERTICES {
        return Err(ObjError::TooLarge {
            path: path.to_string(),
            count: obj.positions.len(),
            max: super::MAX_VERTICES,
        });
    }
    if tris.is_empty() {
        return Err(ObjError::NoFaces {
            path: path.to_string(),
        });
    }
    let positions_far = far_coordinate(path, "vertex", obj.positions.iter().map(|p| &p[..]));
    let texcoords_far = || {
        far_coordinate(
            path,
            "texture coordinate",
            obj.texcoords.iter().map(|t| &t[..]),
        )
    };
    if let Some(e) = positions_far.or_else(texcoords_far) {
        return Err(e);
    }
    let positions: Vec<Vec3> = obj
        .positions
        .iter()
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect();
    let tex: Vec<Vec2> = obj
        .texcoords
        .iter()
        .map(|t| Vec2::new(t[0], t[1]))
        .collect();
    // One rest position per vertex.
    let mut tex_of: Vec<Option<usize>> = vec![None; positions.len()];
    for &(line, corners) in &tris {
        for (v, t) in corners {
            match tex_of[v] {
                None => tex_of[v] = Some(t),
                Some(t0) if t0 == t || tex[t0] == tex[t] => {}
                Some(t0) => {
                    return Err(ObjError::Seam {
                        path: path.to_string(),
                        line,
                        vertex: v + 1,
                        first: t0 + 1,
                        second: t + 1,
                    })
                }
            }
        }
    }
    // Compact the used vertices in file order.
    let mut id = vec![usize::MAX; positions.len()];
    let mut rest = Vec::new();
    let mut world = Vec::new();
    for (v, t) in tex_of.iter().enumerate() {
        if let Some(t) = *t {
            id[v] = rest.len();
            rest.push(tex[t]);
            world.push(positions[v]);
        }
    }
    let mut faces: Vec<[usize; 3]> = tris
        .iter()
        .map(|(_, c)| [id[c[0].0], id[c[1].0], id[c[2].0]])
        .collect();
    orient(&rest, &mut faces, &tris, path)?;
    let mesh = Mesh::from_faces(rest, &faces).map_err(|source| ObjError::Mesh {
        path: path.to_string(),
        source,
    })?;
    Ok(ObjCloth {
        mesh,
        positions: world,
    })
}

/// Makes every face counter-clockwise in rest space: all clockwise faces are flipped; zero area
/// or mixed orientation is an error naming the face's line.
fn orient(
    rest: &[Vec2],
    faces: &mut [[usize; 3]],
    tris: &[(usize, [Corner; 3])],
    path: &str,
) -> Result<(), ObjError> {
    let err = |line: usize, message: String| ObjError::Orientation {
        path: path.to_string(),
        line,
        message,
    };
    let mut first_sign = 0.0;
    for (f, &(line, _)) in faces.iter().zip(tris) {
        let area = signed_area(rest[f[0]], rest[f[1]], rest[f[2]]);
        if area == 0.0 || !area.is_finite() {
            return Err(err(
                line,
                format!("face has zero rest (vt) area ({area:e} m²)"),
            ));
        }
        if first_sign == 0.0 {
            first_sign = area.signum();
        } else if area.signum() != first_sign {
            return Err(err(
                line,
                format!(
                    "face is {} in rest (vt) space but the first face is not; faces must be \
                     consistently oriented",
                    if area > 0.0 {
                        "counter-clockwise"
                    } else {
                        "clockwise"
                    }
                ),
            ));
        }
    }
    if first_sign < 0.0 {
        for f in faces.iter_mut() {
            f.swap(1, 2);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Rule;

    const SQUARE: &str = "# a unit square, two triangles and a quad\n\
        v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nv 2 0 1\nv 2 1 1\n\
        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 2 0\nvt 2 1\n\
        vn 0 0 1\ng cloth\ns off\n\
        f 1/1/1 2/2/1 3/3/1\nf 1/1 3/3 4/4\nf 2/2 5/5 6/6 3/3\n";

    fn write(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cloth.obj");
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn loads_a_small_cloth_from_file() {
        let (_dir, path) = write(SQUARE);
        let cloth = load_obj(&path).unwrap();
        assert_eq!(cloth.mesh.vertex_count(), 6);
        assert_eq!(cloth.mesh.face_count(), 4);
        assert_eq!(cloth.positions.len(), 6);
        assert_eq!(cloth.positions[4], Vec3::new(2.0, 0.0, 1.0));
        assert!((cloth.mesh.pattern_area() - 2.0).abs() < 1e-12);
        cloth.mesh.check().unwrap();
    }

    #[test]
    fn clockwise_file_is_flipped_and_unused_vertices_dropped() {
        let text = "v 0 0 0\nv 9 9 9\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 4/3 3/2\n";
        let cloth = parse_obj(text, "cw.obj").unwrap();
        assert_eq!(cloth.mesh.vertex_count(), 3);
        assert_eq!(cloth.positions[1], Vec3::new(1.0, 0.0, 0.0));
        assert!(cloth.mesh.pattern_area() > 0.0);
        cloth.mesh.check().unwrap();
    }

    #[test]
    fn a_file_with_more_vertices_than_a_cloth_may_have_is_refused() {
        let mut text = "v 0 0 0\n".repeat(crate::mesh::MAX_VERTICES + 1);
        text.push_str("vt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
        let e = parse_obj(&text, "big.obj").unwrap_err().to_string();
        assert!(e.contains("at most 4000000"), "{e}");
    }

    /// A vertex or rest coordinate beyond a million metres is refused by its index (a cloth
    /// vertex at 1e300 m was accepted and the run diverged at its first step).
    #[test]
    fn coordinates_beyond_a_million_metres_are_refused() {
        let cloth = |v: &str, vt: &str| {
            let text = format!("v 0 0 0\n{v}\nv 0 1 0\nvt 0 0\n{vt}\nvt 0 1\nf 1/1 2/2 3/3\n");
            parse_obj(&text, "far.obj")
                .map(|_| ())
                .map_err(|e| e.to_string())
        };
        let e = cloth("v 1e300 0 0", "vt 1 0").unwrap_err();
        assert!(e.contains("far.obj: vertex 2 is 1e300 m"), "{e}");
        let e = cloth("v 1 0 0", "vt -2e6 0").unwrap_err();
        assert!(e.contains("texture coordinate 2 is 2e6 m"), "{e}");
        assert!(cloth("v 1e6 0 0", "vt 1 0").is_ok());
    }

    #[test]
    fn negative_indices() {
        let text = "v 0 0 0\nvt 0 0\nv 1 0 0\nvt 1 0\nv 0 1 0\nvt 0 1\nf -3/-3 -2/-2 -1/-1\n";
        assert_eq!(parse_obj(text, "x").unwrap().mesh.face_count(), 1);
    }

    fn line_of(e: &ObjError) -> usize {
        match e {
            ObjError::File(crate::io::ObjError::Parse { line, .. })
            | ObjError::NoTexCoords { line, .. }
            | ObjError::Seam { line, .. }
            | ObjError::Orientation { line, .. } => *line,
            other => panic!("unexpected error {other}"),
        }
    }

    #[test]
    fn malformed_input_reports_line_numbers() {
        let base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
        let cases = [
            ("v 1 2\n", 7, "expected 3 numbers"),
            ("vt 0 x\n", 7, "finite number"),
            ("f 1/1 2/2\n", 7, "at least 3 corners"),
            ("f 1/1 2/2 7/3\n", 7, "out of range"),
            ("f 1/1 2/a 3/3\n", 7, "integer texture coordinate"),
            ("f 1//1 2//1 3//1\n", 7, "no texture coordinate"),
            ("\n\nf 1/1 2/2 3/3\nf 1/2 3/3 2/1\n", 10, "seams"),
            ("curv 1 2\n", 7, "unsupported statement"),
            ("f 1/1 2/2 3/2\n", 7, "zero rest"),
        ];
        for (extra, line, needle) in cases {
            let e = parse_obj(&format!("{base}{extra}"), "bad.obj").unwrap_err();
            assert_eq!(line_of(&e), line, "{extra:?}: {e}");
            assert!(e.to_string().contains(needle), "{extra:?}: {e}");
            assert!(e.to_string().starts_with("bad.obj:"), "{e}");
        }
    }

    #[test]
    fn mixed_orientation_is_an_error() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n\
                    f 1/1 2/2 3/3\nf 2/2 3/3 4/4\n";
        let e = parse_obj(text, "m.obj").unwrap_err();
        assert!(matches!(e, ObjError::Orientation { line: 10, .. }), "{e}");
    }

    #[test]
    fn missing_file_and_non_conforming_mesh() {
        let e = load_obj(Path::new("/nonexistent/cloth.obj")).unwrap_err();
        assert!(matches!(e, ObjError::File(crate::io::ObjError::Io { .. })));
        assert!(matches!(
            parse_obj("v 0 0 0\n", "e"),
            Err(ObjError::NoFaces { .. })
        ));
        // Two triangles touching at one vertex (a bowtie).
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\n\
                    vt 0 0\nvt 1 0\nvt 1 1\nvt -1 0\nvt -1 -1\n\
                    f 1/1 2/2 3/3\nf 1/1 4/4 5/5\n";
        match parse_obj(text, "b.obj") {
            Err(ObjError::Mesh {
                source: MeshError::NotConforming(c),
                ..
            }) => assert_eq!(c.rule, Rule::NonManifoldVertex),
            other => panic!("unexpected {other:?}"),
        }
    }
}
