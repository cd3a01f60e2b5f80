//! Renders a snapshot grid (and one picture of each run's last chosen frame) from run folders.
//!
//! ```text
//! cargo run --release --example snapshot -- SCENE.toml OUT.png T1,T2,... RUN_DIR[=LABEL]...
//! ```
//! Picks, for each time, the frame whose time is nearest. Writes `OUT.png` (the grid) and
//! `OUT-<k>.png` (the last chosen frame of run k alone, 480 x 360), `OUT.html` (a report page with
//! the grid and a 3D replay of every frame of every run) and prints the render times.
use adaptcloth::render::{self, FrameMesh, SnapshotRow};
use adaptcloth::report_html::{write_report_html, HtmlSection, ReplayRun};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn frames_of(dir: &Path) -> Result<Vec<(f64, PathBuf)>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir.join("frames"))
        .with_context(|| format!("{}: no frames folder", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|p| Ok((render::read_obj_frame_time(&p)?.unwrap_or(0.0), p)))
        .collect()
}

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
        let frames = frames_of(Path::new(dir))?;
        let mut row = SnapshotRow {
            label: label.to_string(),
            frames: Vec::new(),
        };
        for &t in &times {
            let nearest = frames
                .iter()
                .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
                .context("a run without frames")?;
            row.frames
                .push((nearest.0, render::read_obj_frame(&nearest.1)?));
        }
        rows.push(row);
        let mut replay = ReplayRun {
            label: label.to_string(),
            ..Default::default()
        };
        for (t, p) in &frames {
            replay.frame_times.push(*t);
            replay.frames.push(render::read_obj_frame(p)?);
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
