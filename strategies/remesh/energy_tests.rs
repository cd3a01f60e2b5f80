//! The energy law on the stability suite's long hanging run (issue 15, item 7): no adaptation
//! pass of `remesh` raises the cloth's total energy.

use super::Remesh;
use crate::adapt::{AdaptContext, AdaptParams, Adaptivity};
use crate::math::Real;
use crate::scene::TimeMode;
use crate::sim::Simulation;
use crate::study::stability;

/// Total energy (J).
fn energy(sim: &Simulation) -> Real {
    sim.cloth.model.energies(&sim.cloth.x, &sim.cloth.v).total()
}

#[test]
fn no_remesh_pass_raises_the_energy_of_the_hanging_cloth() {
    // `hanging` 9x9 for 2 s under implicit Euler at 1/240 s (the suite's quick long run); the
    // simulation itself does not adapt, the test runs remesh's passes and measures each.
    let mut loaded = stability::embedded("hanging", "implicit_euler", "static");
    let s = &mut loaded.scene;
    s.cloth.resolution = 9;
    s.time.mode = TimeMode::Fixed;
    s.time.dt = 1.0 / 240.0;
    s.time.dt_initial = 0.0;
    s.time.duration = 2.0;
    let params: AdaptParams = (&s.adaptivity).into();
    let mut sim = Simulation::new(&loaded).expect("hanging builds");
    let scale = sim.cloth.model.total_mass() * 9.81;
    let mass = sim.cloth.model.total_mass();
    let mut remesh = Remesh::new();
    let (mut next, mut worst, mut passes) = (0.0, Real::NEG_INFINITY, 0);
    while !sim.finished() {
        sim.step().expect("steps");
        if sim.t < next - 1e-12 {
            continue;
        }
        next = sim.t + params.interval;
        let before = energy(&sim);
        let ctx = AdaptContext {
            obstacles: &sim.obstacles,
            time: sim.t,
            params: &params,
            interrupt: None,
        };
        let report = remesh.adapt(&mut sim.cloth, &ctx).expect("adapts");
        sim.after_mesh_edit();
        let gain = energy(&sim) - before;
        assert!(
            gain <= 1e-9 * scale,
            "t = {:.4} s: the pass ({} edits) added {gain:.3e} J",
            sim.t,
            report.events
        );
        worst = worst.max(gain);
        passes += 1;
        let m = sim.cloth.model.total_mass();
        assert!((m - mass).abs() <= 1e-12 * mass, "mass {mass} -> {m}");
    }
    let c = &remesh.counters;
    eprintln!("{passes} passes, largest gain {worst:.3e} J, {c:?}");
    assert!(c.refined > 0 && c.simplified > 0, "{c:?}");
    assert!(c.energy_refused > 0, "the law never had to refuse: {c:?}");
}
