//! Face contact (`[collision] mode = "face"`): a coarse 3x3 cloth dropped onto a box corner, onto
//! the round table's rim and onto the bunny keeps every obstacle out of its surface at every
//! metrics row (`max_surface_penetration <= margin`), where vertex contact alone lets the
//! obstacle through a face.
use crate::common::{metrics_column, run_into, scene, scene_text};
use adaptcloth::scene::LoadedScene;
use adaptcloth::sim::RunStatus;
use std::path::Path;

const MARGIN: f64 = 2e-3;

/// Implicit Euler at a fixed 2 ms over 0.6 s, in `mode`.
fn settings(mode: &str) -> Vec<String> {
    vec![
        format!("collision.mode=\"{mode}\""),
        "integrator.name=\"implicit_euler\"".into(),
        "time.mode=\"fixed\"".into(),
        "time.dt=0.002".into(),
        "time.duration=0.6".into(),
        "time.metrics_rate=100".into(),
        "cloth.resolution=3".into(),
    ]
}

/// The largest `max_surface_penetration` over the metrics rows of a run into `out`.
fn deepest_over_rows(loaded: &LoadedScene, out: &Path) -> f64 {
    let (_, summary) = run_into(loaded, out);
    assert_eq!(summary.status, RunStatus::Completed, "{}", summary.message);
    assert!(
        summary.max_penetration <= MARGIN,
        "{}",
        summary.max_penetration
    );
    let rows = metrics_column(out, "max_surface_penetration");
    assert!(rows.len() > 10);
    let deepest = rows.iter().copied().fold(0.0, f64::max);
    let summary_figure = summary.max_surface_penetration;
    assert!(
        (deepest - summary_figure).abs() <= 1e-6 * summary_figure,
        "{deepest} {summary_figure}"
    );
    deepest
}

/// Runs `text` (a scene) in both modes: vertex contact lets the obstacle through a face by more
/// than `through` (m), face contact keeps it within the margin at every row.
fn faces_keep_the_obstacle_out(text: &str, through: f64) {
    let dir = tempfile::tempdir().unwrap();
    let load = |mode: &str| {
        let set = settings(mode);
        let set: Vec<&str> = set.iter().map(String::as_str).collect();
        scene_text(text, &set)
    };
    let vertex = deepest_over_rows(&load("vertex"), &dir.path().join("v"));
    assert!(vertex > through, "vertex contact: {vertex}");
    let face = deepest_over_rows(&load("face"), &dir.path().join("f"));
    assert!(face <= MARGIN, "face contact: {face} m through the surface");
}

#[test]
fn a_coarse_cloth_on_a_box_corner_keeps_the_corner_out() {
    faces_keep_the_obstacle_out(
        "[cloth]\nsize = [1.0, 1.0]\ncenter = [0.55, 0.55, 0.65]\n\
         [[obstacles]]\nkind = \"box\"\ncenter = [0.0, 0.0, 0.3]\nhalf_extents = [0.3, 0.3, 0.3]\n",
        0.01,
    );
}

#[test]
fn a_coarse_cloth_on_the_table_rim_keeps_the_rim_out() {
    faces_keep_the_obstacle_out(
        "[cloth]\nsize = [1.0, 1.0]\ncenter = [0.35, 0.1, 0.6]\n\
         [[obstacles]]\nkind = \"cylinder\"\ncenter = [0.0, 0.0, 0.25]\nradius = 0.3\nheight = 0.5\n",
        0.01,
    );
}

#[test]
fn a_coarse_cloth_on_the_bunny_keeps_the_bunny_out() {
    let dir = tempfile::tempdir().unwrap();
    let run = |mode: &str, out: &str| {
        let set = settings(mode);
        let set: Vec<&str> = set.iter().map(String::as_str).collect();
        deepest_over_rows(&scene("bunny", &set), &dir.path().join(out))
    };
    let vertex = run("vertex", "v");
    assert!(vertex > 0.01, "vertex contact: {vertex}");
    let face = run("face", "f");
    assert!(face <= MARGIN, "face contact: {face} m through the surface");
}

/// The bar: on every source scene, every strategy from the 5x5 start (their adaptive
/// meshes refine where a face touches a curved obstacle, and simnett's collision splits are not
/// snapped onto the surface) keeps every obstacle within the margin of the cloth's surface at
/// every metrics row under face contact.
#[test]
fn every_strategy_on_every_source_scene_keeps_the_obstacles_out_of_its_faces() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["sphere", "round_table", "bunny"] {
        for strategy in ["static", "remesh", "simnett", "bisect48"] {
            let mut set = settings("face");
            set.retain(|s| !s.starts_with("cloth.resolution") && !s.starts_with("time.duration"));
            set.push(format!("adaptivity.strategy=\"{strategy}\""));
            set.push("time.duration=0.5".into());
            let set: Vec<&str> = set.iter().map(String::as_str).collect();
            let out = dir.path().join(format!("{name}-{strategy}"));
            let deepest = deepest_over_rows(&scene(name, &set), &out);
            assert!(deepest <= MARGIN, "{name} {strategy}: {deepest} m through");
        }
    }
}

/// The bunny scene runs face contact (the default), and a fine cloth draped on it keeps the
/// bunny's ears out of its faces at every row: the case that diverged when the mesh's face
/// test followed only its vertices (docs/model-notes.md, "Collision").
#[test]
fn a_fine_cloth_on_the_bunny_keeps_its_ears_out_of_the_faces() {
    let mut set = settings("face");
    set.retain(|s| {
        !["collision.mode", "cloth.resolution", "time.duration"]
            .iter()
            .any(|key| s.starts_with(key))
    });
    set.push("cloth.resolution=49".into());
    set.push("time.duration=0.5".into());
    let set: Vec<&str> = set.iter().map(String::as_str).collect();
    let loaded = scene("bunny", &set);
    assert_eq!(
        loaded.scene.collision.mode,
        adaptcloth::scene::CollisionMode::Face
    );
    let dir = tempfile::tempdir().unwrap();
    let deepest = deepest_over_rows(&loaded, dir.path());
    assert!(deepest <= MARGIN, "{deepest} m through");
}
