//! Moving obstacles through the whole pipeline: friction drags a cloth resting on a moving plate,
//! and the two moving-obstacle scenes run with every strategy, carrying the cloth along.
use crate::common::{run_into, scene, scene_text};
use adaptcloth::math::Real;
use adaptcloth::sim::{RunStatus, Simulation};

/// A 0.5 m square cloth (5 x 5) resting on a wide plate (top at z = 0) that moves along +x at
/// 0.3 m/s; no air drag, so only the plate's friction moves the cloth along x.
const PLATE: &str = r#"
[cloth]
size = [0.5, 0.5]
resolution = 5
center = [0.0, 0.0, 0.002]
[material]
mu = 0.5
[forces]
drag = false
[time]
duration = 0.15
[[obstacles]]
kind = "box"
center = [0.0, 0.0, -0.05]
half_extents = [2.0, 2.0, 0.05]
friction = 0.5
[obstacles.motion]
kind = "linear"
velocity = [0.3, 0.0, 0.0]
"#;

fn run_to_end(sim: &mut Simulation) {
    while !sim.finished() {
        sim.step().expect("no divergence");
    }
}

/// Friction (mu = 0.5) accelerates the cloth at about `mu g` = 4.9 m/s² to the plate's speed in
/// about 0.06 s: after 0.15 s its momentum is the plate's velocity times its mass, in the plate's
/// direction only. Without friction the plate slides under it and nothing moves it along x.
#[test]
fn a_cloth_resting_on_a_moving_plate_is_dragged_along_by_friction_only() {
    let loaded = scene_text(PLATE, &[]);
    let mut sim = Simulation::new(&loaded).unwrap();
    run_to_end(&mut sim);
    let p = sim.cloth.linear_momentum();
    let carried = 0.3 * sim.cloth.model.total_mass();
    assert!((p.x - carried).abs() < 0.02 * carried, "{p} vs {carried}");
    assert!(p.y.abs() < 1e-6 * carried, "{p}");
    assert!(p.z.abs() < 0.05 * carried, "{p}");
    // Every vertex goes along, none against the plate's motion.
    let cloth = &sim.cloth;
    assert!(cloth.mesh.vertices().all(|v| cloth.v[v.0 as usize].x > 0.0));

    let frictionless = scene_text(PLATE, &["material.mu=0.0", "obstacles.0.friction=0.0"]);
    let mut sim = Simulation::new(&frictionless).unwrap();
    run_to_end(&mut sim);
    let p = sim.cloth.linear_momentum();
    assert!(p.x.abs() < 1e-9 * carried, "{p}");
}

/// Angular momentum about the vertical axis through the origin (kg m²/s).
fn spin_momentum(sim: &Simulation) -> Real {
    let m = sim.cloth.model.mass();
    sim.cloth
        .mesh
        .vertices()
        .map(|v| {
            let i = v.0 as usize;
            m[i] * sim.cloth.x[i].cross(&sim.cloth.v[i]).z
        })
        .sum()
}

/// Both moving-obstacle scenes, started in contact and run briefly, complete with every strategy,
/// keep every vertex outside the obstacles, and leave the cloth moving with the obstacle: pushed
/// along +y by the sphere, turned counter-clockwise by the table.
#[test]
fn the_moving_obstacle_scenes_run_for_every_strategy() {
    let cases: [(&str, &[&str]); 2] = [
        // The sphere's front 1 cm from the cloth.
        (
            "moving_sphere",
            &[
                "obstacles.0.center=[0.0, -0.19, 0.85]",
                "time.duration=0.06",
            ],
        ),
        // The cloth 1 cm above the table.
        (
            "turntable",
            &["cloth.center=[0.0, 0.0, 0.76]", "time.duration=0.1"],
        ),
    ];
    for (name, overrides) in cases {
        for strategy in ["static", "remesh", "simnett", "bisect48"] {
            let set = format!("adaptivity.strategy=\"{strategy}\"");
            let mut all = overrides.to_vec();
            all.push(&set);
            let loaded = scene(name, &all);
            let dir = tempfile::tempdir().unwrap();
            let (sim, summary) = run_into(&loaded, dir.path());
            let label = format!("{name} {strategy}");
            assert_eq!(
                summary.status,
                RunStatus::Completed,
                "{label}: {}",
                summary.message
            );
            assert!(
                summary.max_penetration <= loaded.scene.collision.margin,
                "{label}: {}",
                summary.max_penetration
            );
            // Mean velocity (m/s) along the sphere's motion, and mean angular momentum per mass
            // (m²/s) about the table's axis.
            let mass = sim.cloth.model.total_mass();
            let carried = if name == "moving_sphere" {
                sim.cloth.linear_momentum().y / mass
            } else {
                spin_momentum(&sim) / mass
            };
            // Still obstacles would leave both at rounding level.
            let least = if name == "moving_sphere" { 0.1 } else { 0.01 };
            assert!(carried > least, "{label}: {carried}");
        }
    }
}
