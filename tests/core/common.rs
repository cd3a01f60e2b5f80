//! Helpers shared by the integration tests.
use adaptcloth::math::Vec2;
use adaptcloth::mesh::{Edit, NewVertex, Origin, VertexId, VertexRef};
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

/// The edit splitting edge `(a, b)` (vertex slots) at its rest midpoint: each adjacent face is
/// cut in two through the new vertex, whose state is the average of the ends'.
pub fn split_edit(sim: &Simulation, a: u32, b: u32) -> Edit {
    let mesh = &sim.cloth.mesh;
    let (a, b) = (VertexId(a), VertexId(b));
    let faces: Vec<_> = mesh.edge(a, b).expect("edge exists").iter().collect();
    let mut add = Vec::new();
    for &f in &faces {
        let vs = mesh.face(f);
        let k = (0..3)
            .find(|&k| {
                let (p, q) = (vs[k], vs[(k + 1) % 3]);
                (p == a && q == b) || (p == b && q == a)
            })
            .expect("face has the edge");
        let (p, q, r) = (vs[k], vs[(k + 1) % 3], vs[(k + 2) % 3]);
        add.push([VertexRef::Old(p), VertexRef::New(0), VertexRef::Old(r)]);
        add.push([VertexRef::New(0), VertexRef::Old(q), VertexRef::Old(r)]);
    }
    Edit {
        remove: faces,
        new_vertices: vec![NewVertex {
            rest: Vec2::from((mesh.rest(a) + mesh.rest(b)) * 0.5),
            origin: Origin::Midpoint(a, b),
        }],
        add,
    }
}

/// Says that (part of) a test was skipped, on the process's stderr directly: libtest captures
/// `eprintln!` of passing tests, so a skip said that way would never be seen.
pub fn say_skipped(why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "SKIPPED: {why}");
}

/// Every row's value of column `name` of the metrics table a run wrote into `out` (an empty cell
/// reads NaN).
pub fn metrics_column(out: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = header
        .iter()
        .position(|h| *h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    lines
        .map(|l| match l.split(',').nth(column).unwrap() {
            "" => f64::NAN,
            cell => cell.parse().unwrap(),
        })
        .collect()
}

/// Runs the binary with `args`, sends it SIGINT once `started` exists (within 60 s), and returns
/// its exit code and standard error: for runs that would not end by themselves.
pub fn interrupted_once(args: &[&str], started: &Path) -> (i32, String) {
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(args)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("binary runs");
    let clock = std::time::Instant::now();
    while !started.exists() {
        assert!(
            clock.elapsed().as_secs() < 60,
            "{} never appeared",
            started.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let sent = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
    let output = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&output.stderr).into_owned();
    (output.status.code().unwrap_or(-1), err)
}
