//! The one resolution knob of every adaptive strategy, `adaptivity.h_min`: no strategy creates a
//! rest edge shorter than it, and a smaller `h_min` lets every strategy refine further.
use crate::common::{run_into, scene};
use adaptcloth::strategies::STRATEGIES;
use std::path::Path;

/// The shortest rest edge (m, from the frames' `vt`) over every frame of a run, and the largest
/// vertex count.
fn shortest_rest_edge(run: &Path) -> (f64, usize) {
    let mut frames: Vec<_> = std::fs::read_dir(run.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    frames.sort();
    let (mut shortest, mut vertices) = (f64::INFINITY, 0);
    for f in frames {
        let obj = adaptcloth::io::read_obj(&f).unwrap();
        vertices = vertices.max(obj.texcoords.len());
        for (_, c) in obj.triangle_corners() {
            for k in 0..3 {
                let (a, b) = (c[k].vt.unwrap(), c[(k + 1) % 3].vt.unwrap());
                let (p, q) = (obj.texcoords[a], obj.texcoords[b]);
                shortest = shortest.min(((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt());
            }
        }
    }
    (shortest, vertices)
}

#[test]
fn no_strategy_creates_an_edge_shorter_than_h_min_and_a_smaller_h_min_refines_more() {
    let dir = tempfile::tempdir().unwrap();
    for info in STRATEGIES.iter().filter(|s| s.edits_mesh) {
        let mut vertices = Vec::new();
        for h_min in [0.06, 0.03] {
            let strategy = format!("adaptivity.strategy=\"{}\"", info.name);
            let h = format!("adaptivity.h_min={h_min}");
            let loaded = scene(
                "sphere",
                &[
                    &strategy,
                    &h,
                    "integrator.name=\"implicit_euler\"",
                    "time.mode=\"fixed\"",
                    "time.dt=0.004",
                    "time.duration=0.45",
                    "time.frame_rate=20",
                ],
            );
            let out = dir.path().join(format!("{}-{h_min}", info.name));
            run_into(&loaded, &out);
            let (shortest, n) = shortest_rest_edge(&out);
            assert!(
                shortest >= h_min * (1.0 - 1e-6),
                "{}: a rest edge of {shortest} m with h_min = {h_min} m",
                info.name
            );
            vertices.push(n);
        }
        assert!(
            vertices[1] > vertices[0],
            "{}: h_min 0.03 should refine beyond h_min 0.06: {vertices:?}",
            info.name
        );
    }
}

#[test]
fn h_min_overrides_the_scenes_own_length_and_depth_limits() {
    // round_table.toml sets its own refinement limits (the source's table); h_min overrides them.
    let dir = tempfile::tempdir().unwrap();
    let loaded = scene(
        "round_table",
        &[
            "adaptivity.strategy=\"bisect48\"",
            "adaptivity.h_min=0.02",
            "integrator.name=\"implicit_euler\"",
            "time.mode=\"fixed\"",
            "time.dt=0.004",
            "time.duration=0.6",
            "time.frame_rate=20",
        ],
    );
    assert!(loaded.scene.adaptivity.l_min > 2.0 * 0.02);
    let out = dir.path().join("rt");
    run_into(&loaded, &out);
    let (shortest, _) = shortest_rest_edge(&out);
    assert!(shortest >= 0.02 * (1.0 - 1e-6), "{shortest}");
    assert!(
        shortest < 0.5 * loaded.scene.adaptivity.l_min,
        "refined below the scene's l_min ({}): shortest edge {shortest}",
        loaded.scene.adaptivity.l_min
    );
}

#[test]
fn more_rounds_per_pass_refine_further_in_one_pass() {
    // The sizing field with a 0.1 m ceiling asks every edge of the 5x5 start (0.25 m) to be
    // refined several levels; one round refines one level per pass, four rounds go further.
    for info in STRATEGIES.iter().filter(|s| s.edits_mesh) {
        let vertices_after_one_step = |rounds: u32| {
            let strategy = format!("adaptivity.strategy=\"{}\"", info.name);
            let rounds = format!("adaptivity.rounds={rounds}");
            let loaded = scene(
                "sphere",
                &[
                    &strategy,
                    &rounds,
                    "cloth.resolution=5",
                    "adaptivity.criteria=\"sizing\"",
                    "adaptivity.l_max=0.1",
                    "adaptivity.h_min=0.02",
                ],
            );
            let mut sim = adaptcloth::sim::Simulation::new(&loaded).unwrap();
            sim.step().unwrap();
            sim.cloth.mesh.vertex_count()
        };
        let (one, four) = (vertices_after_one_step(1), vertices_after_one_step(4));
        assert!(
            one > 25 && four > one,
            "{}: {one} vertices after one round, {four} after four",
            info.name
        );
    }
}
