//! Helpers shared by the integration tests.
use adaptcloth::scene::{self, LoadedScene};
use adaptcloth::sim::{self, RunOptions, RunSummary, Simulation};
use std::path::Path;

/// An embedded scene with overrides.
pub fn scene(name: &str, overrides: &[&str]) -> LoadedScene {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    scene::load_embedded(name, &overrides)
        .expect("embedded scene")
        .expect("valid scene")
}

/// A scene from TOML text (relative files resolve against `scenes/`).
pub fn scene_text(text: &str, overrides: &[&str]) -> LoadedScene {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    scene::from_text(text, "test.toml", "test", base, &overrides).expect("valid scene")
}

/// Runs a scene to completion into `out`.
pub fn run_into(loaded: &LoadedScene, out: &Path) -> (Simulation, RunSummary) {
    let mut s = Simulation::new(loaded).expect("scene builds");
    let opts = RunOptions {
        out_dir: out.to_path_buf(),
        progress: false,
        interrupt: None,
        source: loaded.source.clone(),
        ..RunOptions::default()
    };
    let summary = sim::run(&mut s, &opts).expect("outputs written");
    (s, summary)
}
