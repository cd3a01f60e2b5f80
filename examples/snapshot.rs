//! Renders a snapshot grid (and one picture of each run's last chosen frame) from run folders.
//!
//! ```text
//! cargo run --release --example snapshot -- SCENE.toml OUT.png T1,T2,... RUN_DIR[=LABEL]...
//! ```
//! Picks, for each time, the frame whose time is nearest. Writes `OUT.png` (the grid) and
//! `OUT-<k>.png` (the last chosen frame of run k alone, 480 x 360), `OUT.html` (a report page with
//! the grid and a 3D replay of every frame of every run) and prints the render times.
use adaptcloth::report::html::{write_report_html, HtmlSection, ReplayRun};
use adaptcloth::report::pictures::{frame_times, pick_frames};
use adaptcloth::report::render::{self, FrameMesh, SnapshotRow};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        bail!("usage: snapshot SCENE.toml OUT.png T1,T2,... RUN_DIR[=LABEL]...");
    }
    let loaded = adaptcloth::scene::load(Path::new(&args[0]), &[])?;
    let out = PathBuf::from(&args[1]);
    let times: Vec<f64> = args[2]
        .split(',')
        .map(|t| t.parse().context("times"))
        .collect::<Result<_>>()?;
    let obstacles = render::obstacle_meshes(&loaded.scene.obstacles, &loaded.base_dir)?;
    let mut rows = Vec::new();
    let mut replays = Vec::new();
    for run in &args[3..] {
        let (dir, label) = run.split_once('=').unwrap_or((run, run));
        let frames = frame_times(Path::new(dir));
        if frames.is_empty() {
            bail!("{dir}: no frames");
        }
        let mut row = SnapshotRow {
            label: label.to_string(),
            frames: Vec::new(),
        };
        for (t, path) in pick_frames(&frames, &times) {
            row.frames.push((t, FrameMesh::read(&path)?));
        }
        rows.push(row);
        let mut replay = ReplayRun {
            label: label.to_string(),
            ..Default::default()
        };
        for (t, p) in &frames {
            replay.frame_times.push(*t);
            replay.frames.push(FrameMesh::read(p)?);
        }
        replays.push(replay);
    }
    let start = Instant::now();
    render::snapshot_grid(&rows, &obstacles, &out)?;
    let cells: usize = rows.iter().map(|r| r.frames.len()).sum();
    println!(
        "grid of {cells} cells: {:.3} s",
        start.elapsed().as_secs_f64()
    );
    for (k, row) in rows.iter().enumerate() {
        let Some((_, mesh)) = row.frames.last() else {
            continue;
        };
        let path = out.with_file_name(format!(
            "{}-{k}.png",
            out.file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("snapshot")
        ));
        let start = Instant::now();
        render::render_png(mesh, &obstacles, 480, 360, &path)?;
        let triangles: usize = mesh.faces.len()
            + obstacles
                .iter()
                .map(|o: &FrameMesh| o.faces.len())
                .sum::<usize>();
        println!(
            "{}: {triangles} triangles at 480x360: {:.3} s",
            path.display(),
            start.elapsed().as_secs_f64()
        );
    }
    let section = HtmlSection {
        title: "Snapshots".into(),
        markdown: format!("Scene `{}`.", args[0]),
        images: vec![out.clone()],
    };
    write_report_html(
        &out.with_extension("html"),
        "adaptcloth snapshots",
        &[section],
        &replays,
        &obstacles,
    )?;
    Ok(())
}
