//! OBJ frames: `v` world positions (m), `vt` rest coordinates (m), `f v/vt` faces.

use crate::math::Vec3;
use crate::mesh::Mesh;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// `DIR/frames/frame_NNNNN.obj`.
pub fn frame_path(out_dir: &Path, index: usize) -> PathBuf {
    out_dir.join("frames").join(format!("frame_{index:05}.obj"))
}

/// Writes one frame atomically: live vertices renumbered in slot order.
pub fn write_frame(path: &Path, mesh: &Mesh, x: &[Vec3], time: f64) -> std::io::Result<()> {
    let mut s = String::with_capacity(64 * mesh.vertex_count() + 32 * mesh.face_count());
    let _ = writeln!(s, "# adaptcloth frame, t = {time:.6} s");
    let mut number = vec![0usize; mesh.vertex_slots()];
    for (k, v) in mesh.vertices().enumerate() {
        number[v.0 as usize] = k + 1;
        let p = x[v.0 as usize];
        let _ = writeln!(s, "v {:.9} {:.9} {:.9}", p.x, p.y, p.z);
    }
    for v in mesh.vertices() {
        let r = mesh.rest(v);
        let _ = writeln!(s, "vt {:.9} {:.9}", r.x, r.y);
    }
    for f in mesh.faces() {
        let [a, b, c] = mesh.face(f).map(|v| number[v.0 as usize]);
        let _ = writeln!(s, "f {a}/{a} {b}/{b} {c}/{c}");
    }
    super::write_atomic(path, s.as_bytes())
}
