//! Writes the pictures of a 4-8 forced cascade for `docs/strategies/bisect48.md`:
//!
//! ```text
//! cargo run --release --example bisect48_cascade [OUT_DIR]   # default docs/strategies/img
//! ```
//!
//! A 5 x 5 union-jack grid (1 m x 1 m) is refined around one point so that levels 0 to 3 meet;
//! then the face whose `bisect(t)` forces the longest cascade is bisected. Outputs, all in rest
//! space (z = 0, in metres):
//! - `cascade_before.obj`, `cascade_after.obj`: the mesh before and after `bisect(t)`;
//! - `cascade_target.obj`: the face `t` asked for (lifted 1 mm, for an overlay);
//! - `cascade_new_faces.obj`: the faces created by the cascade (lifted 1 mm, for an overlay);
//! - `cascade.svg`: both meshes side by side, faces shaded by level, `t` and the new faces
//!   outlined, so the docs have a picture before the PNG renderer is merged.

use adaptcloth::math::Vec3;
use adaptcloth::mesh::{union_jack, FaceId, Mesh, VertexId};
use adaptcloth::sim::write_mesh_frame as write_frame;
use adaptcloth::strategies::bisect48::Labels;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "docs/strategies/img".into()),
    );
    std::fs::create_dir_all(&out)?;
    let mut mesh = union_jack(5, 5, 1.0, 1.0);
    let mut labels = Labels::new(&mesh, 8);
    // Refine three times around the rest point (0.4, 0.6), always bisecting the face holding it.
    for _ in 0..3 {
        let f = face_at(&mesh, 0.4, 0.6);
        labels.bisect(&mut mesh, f)?;
    }
    // The face whose bisection forces the longest cascade (ties: the smallest id).
    let target = mesh
        .faces()
        .max_by_key(|&f| {
            let n = labels.plan_cascade(&mesh, f).map_or(0, |c| c.len());
            (n, std::cmp::Reverse(f))
        })
        .ok_or("empty mesh")?;
    let chain = labels.plan_cascade(&mesh, target)?;
    let before = mesh.clone();
    let before_labels = labels.clone();
    let done = labels.bisect(&mut mesh, target)?;
    let new_faces: Vec<FaceId> = done
        .steps
        .iter()
        .flat_map(|r| r.added_faces.iter().copied())
        .filter(|&f| mesh.is_face(f))
        .collect();
    println!(
        "bisect(t) of face {} (level {}): cascade of {} block bisections, {} -> {} vertices",
        target.0,
        before_labels.label(&before, target).map_or(0, |l| l.level),
        chain.len(),
        before.vertex_count(),
        mesh.vertex_count()
    );

    write_frame(
        &out.join("cascade_before.obj"),
        &before,
        &flat(&before, 0.0),
        0.0,
    )?;
    write_frame(
        &out.join("cascade_after.obj"),
        &mesh,
        &flat(&mesh, 0.0),
        0.0,
    )?;
    write_faces(&out.join("cascade_target.obj"), &before, &[target], 0.001)?;
    write_faces(&out.join("cascade_new_faces.obj"), &mesh, &new_faces, 0.001)?;
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="860" height="430" viewBox="-0.05 -0.05 2.15 1.1">"#
    );
    draw(&mut svg, &before, &before_labels, &[target], 0.0);
    draw(&mut svg, &mesh, &labels, &new_faces, 1.05);
    svg.push_str("</svg>\n");
    std::fs::write(out.join("cascade.svg"), svg)?;
    println!("wrote {}", out.display());
    Ok(())
}

/// The face containing rest point (u, v).
fn face_at(mesh: &Mesh, u: f64, v: f64) -> FaceId {
    let p = adaptcloth::math::Vec2::new(u, v);
    mesh.faces()
        .find(|&f| {
            let [a, b, c] = mesh.face(f).map(|w| mesh.rest(w));
            let s = |x, y| adaptcloth::math::signed_area(x, y, p) >= 0.0;
            s(a, b) && s(b, c) && s(c, a)
        })
        .expect("point on the pattern")
}

/// World positions = rest positions at height z (m), per vertex slot.
fn flat(mesh: &Mesh, z: f64) -> Vec<Vec3> {
    (0..mesh.vertex_slots() as u32)
        .map(|i| {
            let v = VertexId(i);
            if mesh.is_vertex(v) {
                Vec3::new(mesh.rest(v).x, mesh.rest(v).y, z)
            } else {
                Vec3::zeros()
            }
        })
        .collect()
}

/// Writes `faces` of `mesh` as an OBJ at height z (m): a possibly disconnected overlay.
fn write_faces(path: &Path, mesh: &Mesh, faces: &[FaceId], z: f64) -> std::io::Result<()> {
    let mut used: Vec<VertexId> = faces.iter().flat_map(|&f| mesh.face(f)).collect();
    used.sort_unstable();
    used.dedup();
    let mut s = String::from("# adaptcloth bisect48 cascade overlay (rest space, m)\n");
    for &v in &used {
        let r = mesh.rest(v);
        let _ = writeln!(s, "v {:.9} {:.9} {z:.9}", r.x, r.y);
    }
    for &f in faces {
        let [a, b, c] = mesh
            .face(f)
            .map(|v| used.binary_search(&v).unwrap_or(0) + 1);
        let _ = writeln!(s, "f {a} {b} {c}");
    }
    std::fs::write(path, s)
}

/// One panel: faces filled by level (darker = finer), `marked` faces outlined in red.
fn draw(svg: &mut String, mesh: &Mesh, labels: &Labels, marked: &[FaceId], dx: f64) {
    let shades = [
        "#f4f4f4", "#d9e6f2", "#a9c8e6", "#6fa3d6", "#3d7cc0", "#1f5a9c",
    ];
    let pt = |v| {
        let r = mesh.rest(v);
        format!("{:.4},{:.4}", r.x + dx, 1.0 - r.y)
    };
    for f in mesh.faces() {
        let level = labels.label(mesh, f).map_or(0, |l| l.level) as usize;
        let [a, b, c] = mesh.face(f);
        let _ = writeln!(
            svg,
            r##"<polygon points="{} {} {}" fill="{}" stroke="#333" stroke-width="0.003"/>"##,
            pt(a),
            pt(b),
            pt(c),
            shades[level.min(shades.len() - 1)]
        );
    }
    for &f in marked {
        let [a, b, c] = mesh.face(f);
        let _ = writeln!(
            svg,
            r##"<polygon points="{} {} {}" fill="none" stroke="#d62728" stroke-width="0.008"/>"##,
            pt(a),
            pt(b),
            pt(c)
        );
    }
}
