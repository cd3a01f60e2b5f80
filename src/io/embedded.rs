//! Files built into the binary, read under the virtual folder `<embedded>`: the meshes the
//! embedded scenes read (`<embedded>/meshes/bunny.obj`, a copy of `scenes/meshes/bunny.obj`), so
//! a copied or installed binary runs every embedded scene without the source tree.
//! [`super::read_text`] (and so every OBJ read) serves them.

use std::path::Path;

/// The virtual folder of the built-in files: a path under it is read from the binary.
pub const EMBEDDED_DIR: &str = "<embedded>";

/// The built-in files, by their path under [`EMBEDDED_DIR`].
const FILES: &[(&str, &str)] = &[(
    "meshes/bunny.obj",
    include_str!("../../scenes/meshes/bunny.obj"),
)];

/// Whether `path` lies under [`EMBEDDED_DIR`] (built in or not).
pub fn is_embedded_path(path: &Path) -> bool {
    path.starts_with(EMBEDDED_DIR)
}

/// The text of the built-in file at `path` (`<embedded>/meshes/bunny.obj`); `None` for a path
/// not under [`EMBEDDED_DIR`] or naming no built-in file.
pub fn embedded_text(path: &Path) -> Option<&'static str> {
    let rest = path.strip_prefix(EMBEDDED_DIR).ok()?;
    FILES
        .iter()
        .find(|(name, _)| Path::new(name) == rest)
        .map(|(_, text)| *text)
}

/// The error for a path under [`EMBEDDED_DIR`] that names no built-in file, listing them.
pub(super) fn not_built_in(path: &Path) -> std::io::Error {
    let names: Vec<String> = FILES
        .iter()
        .map(|(name, _)| format!("{EMBEDDED_DIR}/{name}"))
        .collect();
    std::io::Error::new(
        std::io::ErrorKind::NotFound,
        format!(
            "{} is not built into the binary (built in: {})",
            path.display(),
            names.join(", ")
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The embedded bunny scene's mesh reads from the binary (trial report A7): 2002 vertices,
    /// 4000 faces, the same text as the source tree's file.
    #[test]
    fn the_bunny_mesh_is_built_in() {
        let path = Path::new("<embedded>/meshes/bunny.obj");
        let obj = crate::io::read_obj(path).unwrap();
        assert_eq!((obj.positions.len(), obj.faces.len()), (2002, 4000));
        let tree = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes/bunny.obj");
        assert_eq!(
            embedded_text(path),
            Some(std::fs::read_to_string(tree).unwrap().as_str())
        );
        let e = crate::io::read_obj(Path::new("<embedded>/meshes/cow.obj")).unwrap_err();
        assert!(
            e.to_string()
                .contains("not built into the binary (built in: <embedded>/meshes/bunny.obj)"),
            "{e}"
        );
    }
}
