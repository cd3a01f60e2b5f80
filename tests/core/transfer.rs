//! The shared transfer service keeps mass and momentum when a strategy edits the mesh.
use crate::common::{scene_text, split_edit};
use adaptcloth::adapt::apply_edit;
use adaptcloth::math::{Vec2, Vec3};
use adaptcloth::mesh::{Edit, NewVertex, Origin, VertexRef};
use adaptcloth::sim::Simulation;

#[test]
fn midpoint_split_conserves_mass_and_momentum_and_records_energy_loss() {
    let loaded = scene_text("[cloth]\nresolution = 5\n", &[]);
    let mut sim = Simulation::new(&loaded).unwrap();
    // Give the cloth a non-uniform velocity field.
    for v in sim.cloth.mesh.vertices().collect::<Vec<_>>() {
        let p = sim.cloth.mesh.rest(v);
        sim.cloth.v[v.0 as usize] = Vec3::new(p.x * 2.0 - 1.0, p.y * p.y, 0.3 * p.x * p.y);
    }
    let m0 = sim.cloth.model.total_mass();
    let p0 = sim.cloth.linear_momentum();
    let e0 = sim.cloth.kinetic_energy();
    // Vertex (1,1) = 6 and (2,2) = 12 are joined by a diagonal in the union-jack grid.
    let edit = split_edit(&sim, 6, 12);
    let t = apply_edit(&mut sim.cloth, &edit, None, false).expect("valid split");
    sim.cloth.refresh();
    sim.cloth.mesh.check().expect("conforming");
    assert_eq!(t.record.added_vertices.len(), 1);
    let m1 = sim.cloth.model.total_mass();
    assert!((m1 - m0).abs() <= 1e-12 * m0, "{m0} -> {m1}");
    let p1 = sim.cloth.linear_momentum();
    assert!((p1 - p0).norm() <= 1e-12 * p0.norm(), "{p0} -> {p1}");
    let e1 = sim.cloth.kinetic_energy();
    assert!(e1 <= e0 + 1e-15);
    assert!((t.kinetic_energy_change - (e1 - e0)).abs() <= 1e-12 * e0);
    // The energy lost by averaging is m_new / 8 |v_a - v_b|² (MODEL.md §6).
    let new = t.record.added_vertices[0].0;
    let m_new = sim.cloth.model.mass()[new.0 as usize];
    // The velocities of the edge's ends are unchanged by the split.
    let loss = e0 - e1;
    let expected = m_new / 8.0 * (vel(&sim, 6) - vel(&sim, 12)).norm_squared();
    assert!(
        (loss - expected).abs() <= 1e-9 * expected.max(1e-30),
        "{loss} vs {expected}"
    );
}

fn vel(sim: &Simulation, i: usize) -> Vec3 {
    sim.cloth.v[i]
}

#[test]
fn refused_edit_leaves_the_cloth_untouched() {
    let loaded = scene_text("[cloth]\nresolution = 4\n", &[]);
    let mut sim = Simulation::new(&loaded).unwrap();
    let before_x = sim.cloth.x.clone();
    let version = sim.cloth.mesh.version();
    let mut edit = split_edit(&sim, 5, 10);
    edit.add.pop(); // leaves a hole
    assert!(apply_edit(&mut sim.cloth, &edit, None, true).is_err());
    assert_eq!(sim.cloth.mesh.version(), version);
    assert_eq!(sim.cloth.x, before_x);
    sim.cloth.mesh.check().unwrap();
}

#[test]
fn region_remesh_with_momentum_restoration_conserves_momentum() {
    // Replace the two triangles of cell (1,1) of a 4x4 grid by four around an interior point
    // off-centre: barycentric transfer changes momentum; the service restores it.
    let loaded = scene_text("[cloth]\nresolution = 4\n", &[]);
    let mut sim = Simulation::new(&loaded).unwrap();
    for v in sim.cloth.mesh.vertices().collect::<Vec<_>>() {
        let p = sim.cloth.mesh.rest(v);
        sim.cloth.v[v.0 as usize] = Vec3::new(p.x, -p.y * 3.0, p.x * p.y);
    }
    let mesh = &sim.cloth.mesh;
    let (a, b, c, d) = (5u32, 6u32, 10u32, 9u32); // cell (1,1): (1,1),(2,1),(2,2),(1,2)
    let ids = [a, b, c, d].map(adaptcloth::mesh::VertexId);
    let faces: Vec<_> = mesh
        .faces()
        .filter(|&f| mesh.face(f).iter().all(|v| ids.contains(v)))
        .collect();
    assert_eq!(faces.len(), 2);
    let p = Vec2::new(0.40, 0.45); // inside the cell [1/3, 2/3]²
    let tri = faces
        .iter()
        .find_map(|&f| {
            let vs = mesh.face(f);
            let [r0, r1, r2] = vs.map(|v| mesh.rest(v));
            let area = adaptcloth::math::signed_area(r0, r1, r2);
            let w = [
                adaptcloth::math::signed_area(p, r1, r2) / area,
                adaptcloth::math::signed_area(r0, p, r2) / area,
                adaptcloth::math::signed_area(r0, r1, p) / area,
            ];
            w.iter().all(|&x| x >= 0.0).then_some((vs, w))
        })
        .expect("point in the cell");
    let [va, vb, vc, vd] = ids.map(VertexRef::Old);
    let n = VertexRef::New(0);
    let edit = Edit {
        remove: faces,
        new_vertices: vec![NewVertex {
            rest: p,
            origin: Origin::InTriangle {
                corners: tri.0,
                weights: tri.1,
            },
        }],
        add: vec![[va, vb, n], [vb, vc, n], [vc, vd, n], [vd, va, n]],
    };
    let m0 = sim.cloth.model.total_mass();
    let p0 = sim.cloth.linear_momentum();
    let t = apply_edit(&mut sim.cloth, &edit, None, true).expect("valid re-mesh");
    sim.cloth.refresh();
    sim.cloth.mesh.check().unwrap();
    assert!((sim.cloth.model.total_mass() - m0).abs() <= 1e-12 * m0);
    let p1 = sim.cloth.linear_momentum();
    assert!((p1 - p0).norm() <= 1e-12 * p0.norm(), "{p0} -> {p1}");
    assert!(t.momentum_change <= 1e-12 * p0.norm());
}
