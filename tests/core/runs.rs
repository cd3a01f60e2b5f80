//! Whole runs: every shipped scene completes (short), outputs are complete and consistent, runs
//! are deterministic, and failures stop cleanly with everything on disk.
use crate::common::{run_into, scene, scene_text};
use adaptcloth::sim::{self, RunOptions, RunStatus, Simulation};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Reads `metrics.csv` into its header and rows; an empty cell (a measure not taken on that row)
/// reads NaN, anything else must be a number.
fn metrics(dir: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("metrics.csv")).expect("metrics.csv");
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|x| match x {
                    "" => f64::NAN,
                    x => x.parse::<f64>().unwrap(),
                })
                .collect()
        })
        .collect();
    (header, rows)
}

/// Short smoke run of every source scene at 5x5 and 17x17: completes, no divergence, no
/// penetration beyond the margin, all outputs present, every frame conforming (checked by the run).
#[test]
fn every_scene_runs_short_without_divergence_or_penetration() {
    for name in ["sphere", "round_table", "bunny", "hanging", "sphere_peer"] {
        for res in [5, 17] {
            let loaded = scene(
                name,
                &["time.duration=0.02", &format!("cloth.resolution={res}")],
            );
            let dir = tempfile::tempdir().unwrap();
            let (_, summary) = run_into(&loaded, dir.path());
            assert_eq!(
                summary.status,
                RunStatus::Completed,
                "{name} {res}: {}",
                summary.message
            );
            assert!(
                summary.max_penetration <= loaded.scene.collision.margin,
                "{name} {res}: penetration {}",
                summary.max_penetration
            );
            assert!(dir.path().join("summary.json").is_file());
            assert!(!dir.path().join("metrics.csv.partial").exists());
            assert!(dir.path().join("frames/frame_00000.obj").is_file());
            assert_eq!(summary.final_vertices, res * res);
        }
    }
}

/// The metrics table has the required columns and its mass and vertex columns are consistent.
#[test]
fn metrics_have_the_required_columns() {
    let loaded = scene("sphere", &["time.duration=0.01"]);
    let dir = tempfile::tempdir().unwrap();
    let (sim, summary) = run_into(&loaded, dir.path());
    let (header, rows) = metrics(dir.path());
    for col in [
        "step",
        "t",
        "dt",
        "vertices",
        "edges",
        "faces",
        "min_mass",
        "max_stiffness",
        "total_mass",
        "linear_momentum",
        "kinetic_energy",
        "max_penetration",
        // The tracked point by its name in the scene (`name = "P"`).
        "P_x",
        "P_y",
        "P_z",
    ] {
        assert!(header.iter().any(|h| h == col), "missing column {col}");
    }
    assert!(rows.len() >= 10, "only {} rows", rows.len());
    let total_mass = header.iter().position(|h| h == "total_mass").unwrap();
    for r in &rows {
        assert!((r[total_mass] - sim.cloth.model.total_mass()).abs() < 1e-12);
    }
    let last = rows.last().unwrap();
    assert_eq!(last[0] as u64, summary.steps);
    // The crossing count is taken on the frames' rows and the last one only.
    let crossings = header
        .iter()
        .position(|h| h == "self_intersections")
        .unwrap();
    let taken = rows.iter().filter(|r| !r[crossings].is_nan()).count();
    assert!(!last[crossings].is_nan());
    assert!(
        taken >= summary.frames && taken <= summary.frames + 1,
        "{taken} rows"
    );
    // The tracked corner P = (1, 1) starts at the world corner (0.5, 0.5, 0.3).
    let px = header.iter().position(|h| h == "P_x").unwrap();
    assert!((rows[0][px] - 0.5).abs() < 1e-12);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    for key in [
        "scene",
        "strategy",
        "integrator",
        "steps",
        "sim_time",
        "wall_time_s",
        "max_vertices",
        "final_vertices",
        "status",
    ] {
        assert!(json.get(key).is_some(), "summary lacks {key}");
    }
    assert_eq!(json["status"], "completed");
    // 60 frames per second over 0.01 s: frame 0 at t = 0 only.
    assert_eq!(summary.frames, 1);
}

/// Same scene twice gives identical outputs.
#[test]
fn runs_are_deterministic() {
    let loaded = scene("sphere", &["time.duration=0.05", "cloth.resolution=9"]);
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    run_into(&loaded, a.path());
    run_into(&loaded, b.path());
    for f in [
        "metrics.csv",
        "frames/frame_00000.obj",
        "frames/frame_00003.obj",
    ] {
        let (x, y) = (
            std::fs::read(a.path().join(f)).unwrap(),
            std::fs::read(b.path().join(f)).unwrap(),
        );
        assert!(x == y, "{f} differs between identical runs");
    }
}

/// A step far beyond the explicit stability limit ends as `diverged` with a message naming the
/// step and time, and every output written so far is complete.
#[test]
fn divergence_stops_cleanly_with_outputs_on_disk() {
    let loaded = scene_text(
        "[cloth]\nresolution = 9\n[material]\nE = 1e9\n[time]\nduration = 1.0\nmode = \"fixed\"\ndt = 0.01\n[integrator]\nname = \"symplectic_euler\"\n[collision]\nmargin = 0.0\n[[obstacles]]\nkind = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0.25\n",
        &["cloth.center=[0.0, 0.0, 0.26]", "forces.springs=true"],
    );
    let dir = tempfile::tempdir().unwrap();
    let (_, summary) = run_into(&loaded, dir.path());
    assert_eq!(summary.status, RunStatus::Diverged);
    assert!(summary.message.contains("step"), "{}", summary.message);
    assert!(summary.message.contains("t = "), "{}", summary.message);
    assert!(dir.path().join("metrics.csv").is_file());
    assert!(!dir.path().join("metrics.csv.partial").exists());
    let json = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    assert!(json.contains("\"diverged\""));
}

/// An interrupt stops the run at once with status `interrupted` and complete outputs.
#[test]
fn interrupt_stops_cleanly() {
    let loaded = scene("sphere", &[]);
    let mut s = Simulation::new(&loaded).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions {
        out_dir: dir.path().to_path_buf(),
        progress: false,
        interrupt: Some(Arc::new(AtomicBool::new(true))),
        source: "test".into(),
        ..RunOptions::default()
    };
    let summary = sim::run(&mut s, &opts).unwrap();
    assert_eq!(summary.status, RunStatus::Interrupted);
    assert!(summary.message.contains("step 0"), "{}", summary.message);
    assert!(dir.path().join("metrics.csv").is_file());
    assert!(dir.path().join("frames/frame_00000.obj").is_file());
}

/// The adaptation pass honours the interrupt flag: with the flag set, a step edits nothing
/// (without it, the same step refines), so Ctrl-C is answered within the pass.
#[test]
fn an_interrupt_stops_the_adaptation_pass() {
    let loaded = scene(
        "sphere",
        &[
            "adaptivity.strategy=\"bisect48\"",
            "cloth.resolution=9",
            "adaptivity.criteria=\"sizing\"",
            "adaptivity.h_min=0.02",
            "adaptivity.l_min=0.01",
            "adaptivity.l_max=0.05",
        ],
    );
    let vertices_after_one_step = |flag: bool| {
        let mut s = Simulation::new(&loaded).unwrap();
        s.set_interrupt(Arc::new(AtomicBool::new(flag)));
        s.step().unwrap();
        s.cloth.mesh.vertex_count()
    };
    assert!(vertices_after_one_step(false) > 81);
    assert_eq!(vertices_after_one_step(true), 81);
}

/// A run interrupted during a long adaptation pass stops within the pass with status
/// `interrupted` and its summary written. The first pass is long: the sizing field asks a
/// 150 x 150 grid for several rounds of refinement (about 180k vertices, seconds in one step).
#[test]
fn a_run_interrupted_during_adaptation_stops_cleanly() {
    let loaded = scene(
        "sphere",
        &[
            "adaptivity.strategy=\"bisect48\"",
            "cloth.resolution=150",
            "adaptivity.rounds=16",
            "adaptivity.criteria=\"sizing\"",
            "adaptivity.h_min=0.002",
            "adaptivity.l_min=0.001",
            "adaptivity.l_max=0.003",
            "adaptivity.max_vertices=4000000",
            "time.mode=\"fixed\"",
            "time.dt=1e-6",
            "time.duration=1e-5",
        ],
    );
    let mut s = Simulation::new(&loaded).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    let opts = RunOptions {
        out_dir: dir.path().to_path_buf(),
        progress: false,
        interrupt: Some(flag.clone()),
        source: "test".into(),
        ..RunOptions::default()
    };
    let clock = std::time::Instant::now();
    let setter = std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_millis(300));
        flag.store(true, std::sync::atomic::Ordering::SeqCst);
    });
    let summary = sim::run(&mut s, &opts).unwrap();
    setter.join().unwrap();
    let wall = clock.elapsed().as_secs_f64();
    assert_eq!(
        summary.status,
        RunStatus::Interrupted,
        "{}",
        summary.message
    );
    assert!(wall < 1.3, "answered the interrupt after {wall:.2} s");
    let json = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    assert!(json.contains("\"interrupted\""), "{json}");
}

/// A mesh that adaptation grows past `adaptivity.max_vertices` stops the run with status
/// `failed`, a message naming the cap and the key, and complete outputs (issue 15: `l_min = 1e-9`
/// with a deep `max_depth` grew without bound).
#[test]
fn adaptation_past_max_vertices_fails_the_run() {
    for strategy in ["remesh", "simnett", "bisect48"] {
        let loaded = scene(
            "sphere",
            &[
                "time.duration=0.2",
                "cloth.center=[0.0, 0.0, 0.26]",
                &format!("adaptivity.strategy=\"{strategy}\""),
                "adaptivity.l_min=1e-9",
                "adaptivity.max_vertices=30",
            ],
        );
        let dir = tempfile::tempdir().unwrap();
        let (sim, summary) = run_into(&loaded, dir.path());
        assert_eq!(summary.status, RunStatus::Failed, "{strategy}");
        assert!(
            summary
                .message
                .contains("above adaptivity.max_vertices = 30"),
            "{strategy}: {}",
            summary.message
        );
        assert!(sim.cloth.mesh.vertex_count() > 30);
        // The summary's largest count includes the failing pass's mesh (trial report B7).
        assert_eq!(summary.max_vertices, summary.final_vertices, "{strategy}");
        assert!(summary.max_vertices > 30, "{strategy}");
        assert!(dir.path().join("metrics.csv").is_file());
    }
}

/// Every adaptive strategy on each source scene (one test per scene, so the test threads share
/// the nine runs), started just above the obstacle so contact (and adaptation) begins at once:
/// the run completes, every frame conforms (checked by the run driver), no vertex penetrates
/// beyond the margin, total mass is kept, and the mesh refines. The sphere here.
#[test]
fn every_adaptive_strategy_runs_the_sphere_and_refines_at_contact() {
    runs_and_refines_at_contact("sphere", "[0.0, 0.0, 0.26]");
}

/// As above, on the round table.
#[test]
fn every_adaptive_strategy_runs_the_round_table_and_refines_at_contact() {
    runs_and_refines_at_contact("round_table", "[0.0, 0.0, 0.76]");
}

/// As above, on the bunny.
#[test]
fn every_adaptive_strategy_runs_the_bunny_and_refines_at_contact() {
    runs_and_refines_at_contact("bunny", "[0.0, 0.0, 0.50]");
}

/// Every adaptive strategy on `scene_name`, the cloth centred at `center` (a TOML vector, m).
fn runs_and_refines_at_contact(scene_name: &str, center: &str) {
    for strategy in ["remesh", "simnett", "bisect48"] {
        let loaded = scene(
            scene_name,
            &[
                "time.duration=0.2",
                &format!("cloth.center={center}"),
                &format!("adaptivity.strategy=\"{strategy}\""),
            ],
        );
        let dir = tempfile::tempdir().unwrap();
        let (sim, summary) = run_into(&loaded, dir.path());
        let what = format!("{scene_name} / {strategy}");
        assert_eq!(
            summary.status,
            RunStatus::Completed,
            "{what}: {}",
            summary.message
        );
        assert!(
            summary.max_penetration <= loaded.scene.collision.margin,
            "{what}: penetration {}",
            summary.max_penetration
        );
        assert!(
            summary.max_vertices > 25,
            "{what}: no refinement ({} vertices)",
            summary.max_vertices
        );
        let expected = loaded.scene.material.rho * loaded.scene.material.thickness;
        let mass = sim.cloth.model.total_mass();
        assert!(
            (mass - expected).abs() <= 1e-9 * expected,
            "{what}: mass {mass}"
        );
        sim.cloth.mesh.check().unwrap();
    }
}

/// A short sphere run with `remesh`: the cloth lands on the sphere, the mesh refines there,
/// every adaptation keeps the mesh conforming and the mass exact.
#[test]
fn remesh_refines_where_the_cloth_meets_the_sphere() {
    use adaptcloth::math::Vec2;
    let loaded = scene(
        "sphere",
        &["adaptivity.strategy=remesh", "time.duration=0.2"],
    );
    let mut sim = Simulation::new(&loaded).unwrap();
    let mass0 = sim.cloth.model.total_mass();
    let mut events = 0;
    while !sim.finished() {
        let report = sim.step().unwrap();
        if report.adapt.events > 0 {
            events += report.adapt.events;
            sim.cloth.mesh.check().unwrap();
            let mass = sim.cloth.model.total_mass();
            assert!((mass - mass0).abs() <= 1e-12 * mass0);
        }
    }
    assert!(events > 0 && sim.cloth.mesh.vertex_count() > 25);
    // New vertices concentrate where the cloth touches the sphere (radius 0.25 m, centre at the
    // origin below the pattern's centre): more new vertices per rest area within 0.3 m of the
    // pattern centre (0.5, 0.5) than outside (the free skirt folds and refines too).
    let mesh = &sim.cloth.mesh;
    let near_area = std::f64::consts::PI * 0.3 * 0.3;
    let (mut near, mut far) = (0.0, 0.0);
    for v in mesh.vertices().filter(|v| v.0 >= 25) {
        if (mesh.rest(v) - Vec2::new(0.5, 0.5)).norm() < 0.3 {
            near += 1.0;
        } else {
            far += 1.0;
        }
    }
    assert!(
        near / near_area > 2.0 * far / (1.0 - near_area),
        "{near} new vertices near the contact, {far} elsewhere"
    );
}

/// `adaptivity.interval` means the same for every strategy: the adapt stage runs on the first
/// step and then not before the interval has passed.
#[test]
fn adaptation_interval_applies_to_every_strategy() {
    for strategy in ["remesh", "simnett", "bisect48"] {
        let set = format!("adaptivity.strategy={strategy}");
        let loaded = scene(
            "sphere",
            &[
                &set,
                "time.duration=0.2",
                "adaptivity.interval=1.0",
                "cloth.center=[0.0, 0.0, 0.26]",
            ],
        );
        let mut sim = Simulation::new(&loaded).unwrap();
        sim.step().unwrap();
        let vertices = sim.cloth.mesh.vertex_count();
        while !sim.finished() {
            let report = sim.step().unwrap();
            assert_eq!(
                report.adapt.events, 0,
                "{strategy} adapted at t = {}",
                sim.t
            );
        }
        assert_eq!(sim.cloth.mesh.vertex_count(), vertices, "{strategy}");
        let every_step = scene(
            "sphere",
            &[&set, "time.duration=0.2", "cloth.center=[0.0, 0.0, 0.26]"],
        );
        let mut sim = Simulation::new(&every_step).unwrap();
        let mut events = 0;
        while !sim.finished() {
            events += sim.step().unwrap().adapt.events;
        }
        assert!(events > 0, "{strategy} never adapted");
    }
}
