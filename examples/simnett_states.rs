//! Writes the pictures' geometry for `docs/strategies/simnett.md`: one triangle in each state 0-7
//! of the 1-to-4 hierarchy (`simnett_state_<s>.obj`), and a 2x2-cell grid showing the faithful
//! rule (`simnett_blocked.obj`: one diagonal split, its children blocked by temporary children) and
//! `force_completion` (`simnett_forced.obj`: a child split after completing both parents).
//!
//! Run: `cargo run --example simnett_states [out_dir]` (default `docs/strategies/img`). The OBJ
//! files hold rest coordinates as `v u v 0` and the faces; render them to PNG with the project's
//! renderer.

use adaptcloth::math::Vec2;
use adaptcloth::mesh::{union_jack, EdgeKey, Mesh, VertexId};
use adaptcloth::strategies::simnett::{state_of, Hierarchy, TriKey};
use std::fmt::Write as _;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("docs/strategies/img"));
    std::fs::create_dir_all(&out)?;
    for bits in [0b000u8, 0b001, 0b010, 0b100, 0b011, 0b110, 0b101, 0b111] {
        let mut mesh = Mesh::from_faces(
            vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(0.35, 0.8),
            ],
            &[[0, 1, 2]],
        )?;
        let mut h = Hierarchy::new(&mesh);
        let t = TriKey::new([VertexId(0), VertexId(1), VertexId(2)]);
        for k in 0..3 {
            if bits & (1 << k) != 0 {
                let e = h.triangle(t).ok_or("triangle")?.edge(k);
                h.split_edge(&mut mesh, e, 3, 0.0)?;
            }
        }
        let s = state_of(bits);
        let path = out.join(format!("simnett_state_{s}.obj"));
        std::fs::write(&path, obj(&mesh, &format!("triangle in state {s}")))?;
        println!("{}", path.display());
    }
    // The faithful rule on a 2x2-cell grid.
    let mut mesh = union_jack(3, 3, 1.0, 1.0);
    let mut h = Hierarchy::new(&mesh);
    let diagonal = EdgeKey::new(VertexId(0), VertexId(4));
    let mid = h.split_edge(&mut mesh, diagonal, 3, 0.0)?.mid;
    let blocked = out.join("simnett_blocked.obj");
    std::fs::write(
        &blocked,
        obj(&mesh, "diagonal 0-4 split: its children are blocked"),
    )?;
    println!("{}", blocked.display());
    h.split_edge_forced(&mut mesh, EdgeKey::new(VertexId(0), mid), 3, 0.0)?;
    let forced = out.join("simnett_forced.obj");
    std::fs::write(
        &forced,
        obj(&mesh, "force_completion: parents completed, child split"),
    )?;
    println!("{}", forced.display());
    Ok(())
}

/// The mesh's rest geometry as OBJ text (vertices renumbered densely in slot order).
fn obj(mesh: &Mesh, title: &str) -> String {
    let mut s = format!("# adaptcloth simnett: {title}\n");
    let mut index = vec![0usize; mesh.vertex_slots()];
    for (i, v) in mesh.vertices().enumerate() {
        index[v.0 as usize] = i + 1;
        let p = mesh.rest(v);
        let _ = writeln!(s, "v {} {} 0", p.x, p.y);
    }
    for f in mesh.faces() {
        let [a, b, c] = mesh.face(f).map(|v| index[v.0 as usize]);
        let _ = writeln!(s, "f {a} {b} {c}");
    }
    s
}
