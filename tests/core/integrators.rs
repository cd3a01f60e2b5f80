//! Integrators through the whole pipeline: multi-step history across adaptation.
use crate::common::{scene_text, split_edit};
use adaptcloth::adapt::apply_edit;
use adaptcloth::math::Vec3;
use adaptcloth::mesh::VertexId;
use adaptcloth::sim::Simulation;

/// Splits the edge (a, b) at its midpoint (both faces), as in `transfer.rs`.
/// Every live vertex moves with vertex 0: same velocity, same displacement from its rest layout.
fn assert_uniform(sim: &Simulation, what: &str) {
    let c = &sim.cloth;
    let (x0, v0, r0) = (c.x[0], c.v[0], c.mesh.rest(VertexId(0)));
    for v in c.mesh.vertices() {
        let i = v.0 as usize;
        let r = c.mesh.rest(v) - r0;
        let offset = c.x[i] - x0 - Vec3::new(r.x, r.y, 0.0);
        assert!(offset.norm() <= 1e-12, "{what}: vertex {i} off by {offset}");
        assert!(
            (c.v[i] - v0).norm() <= 1e-12,
            "{what}: vertex {i} v {} vs {v0}",
            c.v[i]
        );
    }
}

#[test]
fn verlet_history_of_a_split_vertex_comes_from_the_transfer() {
    for integrator in ["verlet", "time_corrected_verlet", "verlet_relaxation"] {
        // A free cloth in uniform motion: gravity and drag (uniform per unit mass), springs at
        // rest, flat: every vertex follows the same trajectory.
        let text = format!(
            "[cloth]\nresolution = 5\nvelocity = [0.3, -0.2, 0.5]\n[time]\nmode = \"fixed\"\n\
             dt = 1e-3\nduration = 1.0\n[integrator]\nname = \"{integrator}\"\n"
        );
        let loaded = scene_text(&text, &[]);
        let mut sim = Simulation::new(&loaded).expect("scene builds");
        let mut control = Simulation::new(&loaded).expect("scene builds");
        for _ in 0..5 {
            sim.step().expect("step");
            control.step().expect("step");
        }
        assert_uniform(&sim, integrator);
        let edit = split_edit(&sim, 6, 12);
        let t = apply_edit(&mut sim.cloth, &edit, None, true).expect("valid split");
        sim.cloth.refresh();
        let new = t.record.added_vertices[0].0 .0 as usize;
        for _ in 0..5 {
            sim.step().expect("step");
            control.step().expect("step");
        }
        assert_uniform(&sim, integrator);
        // The new vertex moved exactly like the rest, and the cloth like the unsplit control.
        assert!(
            (sim.cloth.x[0] - control.cloth.x[0]).norm() <= 1e-12,
            "{integrator}"
        );
        assert!(
            (sim.cloth.v[new] - control.cloth.v[0]).norm() <= 1e-12,
            "{integrator}"
        );
    }
}

/// `bdf2` keeps its history across steps but drops it at every adaptation event (a changed mesh
/// makes the previous state meaningless slot by slot): every adaptive strategy on the sphere at
/// 2 ms completes, refines, and keeps the obstacle out.
#[test]
fn bdf2_runs_every_adaptive_strategy_through_its_mesh_changes() {
    for strategy in ["remesh", "simnett", "bisect48"] {
        let loaded = crate::common::scene(
            "sphere",
            &[
                "integrator.name=\"bdf2\"",
                "time.mode=\"fixed\"",
                "time.dt=0.002",
                "time.duration=0.4",
                &format!("adaptivity.strategy=\"{strategy}\""),
            ],
        );
        let dir = tempfile::tempdir().unwrap();
        let (sim, summary) = crate::common::run_into(&loaded, dir.path());
        assert_eq!(
            summary.status,
            adaptcloth::sim::RunStatus::Completed,
            "{strategy}: {}",
            summary.message
        );
        assert!(
            sim.cloth.mesh.vertex_count() > 25,
            "{strategy} never refined"
        );
        assert!(summary.max_penetration <= loaded.scene.collision.margin);
    }
}
