//! Renders a snapshot grid (and one picture of each run's last chosen frame) from run folders.
//!
//! ```text
//! cargo run --release --example snapshot -- SCENE.toml OUT.png T1,T2,... RUN_DIR[=LABEL]...
//! ```
//! Picks, for each time, the frame whose time is nearest. Writes `OUT.png` (the grid) and
//! `OUT-<k>.png` (the last chosen frame of run k alone, 480 x 360), `OUT.html` (a report page with
//! the grid and a 3D replay of every frame of every run) and prints the render times.
//! Bad input (a time that is not a finite number >= 0 or lies past a run's last frame, a missing
//! argument, a bad scene or run folder) exits with status 2 and says which; a failure to write
//! exits with 1.
use adaptcloth::report::html::{write_report_html, HtmlSection, ReplayRun};
use adaptcloth::report::pictures::{frame_times, pick_frames};
use adaptcloth::report::render::{self, FrameMesh, SnapshotRow};
use anyhow::Result;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Input the example cannot use: exit status 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct BadInput(String);

fn main() -> ExitCode {
    match snapshot() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            let bad = e.downcast_ref::<BadInput>().is_some()
                || e.downcast_ref::<adaptcloth::scene::SceneError>().is_some();
            ExitCode::from(if bad { 2 } else { 1 })
        }
    }
}

/// The times of the `T1,T2,...` argument: finite numbers >= 0 (s).
fn parse_times(arg: &str) -> Result<Vec<f64>, BadInput> {
    arg.split(',')
        .map(|t| match t.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
            _ => Err(BadInput(format!(
                "times `{arg}`: `{t}` is not a time; expected finite numbers of seconds >= 0 \
                 separated by commas (0,0.2,0.4)"
            ))),
        })
        .collect()
}

fn snapshot() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        return Err(BadInput(
            "usage: snapshot SCENE.toml OUT.png T1,T2,... RUN_DIR[=LABEL]...".into(),
        )
        .into());
    }
    let loaded = adaptcloth::scene::load(Path::new(&args[0]), &[])?;
    let out = PathBuf::from(&args[1]);
    let times = parse_times(&args[2])?;
    let obstacles = render::obstacle_meshes(&loaded.scene.obstacles, &loaded.base_dir)?;
    let mut rows = Vec::new();
    let mut replays = Vec::new();
    for run in &args[3..] {
        let (dir, label) = run.split_once('=').unwrap_or((run, run));
        let frames = frame_times(Path::new(dir));
        let Some(last) = frames.iter().map(|(t, _)| *t).reduce(f64::max) else {
            return Err(BadInput(format!("{dir}: no frames (expected a run folder)")).into());
        };
        // Half a millisecond of slack: frame times are written rounded.
        if let Some(t) = times.iter().find(|&&t| t > last + 5e-4) {
            return Err(BadInput(format!(
                "time {t:?} s is past the last frame of {dir} (t = {last:?} s); expected times \
                 within the run"
            ))
            .into());
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
