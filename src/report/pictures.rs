//! The pictures of a comparison: the snapshot grid (`render::snapshot_grid`) and the
//! self-contained `report.html` (`html::write_report_html`), kept in two small functions; a
//! rendering failure is reported in the report, never fatal to the comparison.

use super::render::FrameMesh;
use crate::study::Comparison;
use std::path::{Path, PathBuf};

/// What a rendering call produced.
#[derive(Clone, Debug, PartialEq)]
pub enum RenderOutcome {
    /// The file written.
    Written(PathBuf),
    /// Rendering failed (the message says why); the rest of the report is still written.
    Failed(String),
}

/// Fractions of the duration at which snapshots are taken (like the source's Figures 5.2, 5.7,
/// 5.12: four times per run).
pub const SNAPSHOT_FRACTIONS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

pub use super::html::HtmlSection as Section;

/// The frames of a run folder with their times (s), read from each OBJ's first line.
pub fn frame_times(run_dir: &Path) -> Vec<(f64, PathBuf)> {
    let Ok(entries) = std::fs::read_dir(run_dir.join("frames")) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "obj"))
        .collect();
    files.sort();
    files
        .into_iter()
        .filter_map(|p| Some((crate::io::read_frame_time(&p).ok()??, p)))
        .collect()
}

/// The frames nearest to each of `targets` (s).
pub fn pick_frames(frames: &[(f64, PathBuf)], targets: &[f64]) -> Vec<(f64, PathBuf)> {
    targets
        .iter()
        .filter_map(|&t| {
            frames
                .iter()
                .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
                .cloned()
        })
        .collect()
}

/// Runs shown in snapshots and replays: `(label, run folder)` for every run that wrote frames,
/// the reference first.
pub fn shown_runs(out: &Path, c: &Comparison) -> Vec<(String, PathBuf)> {
    let mut v = vec![(
        format!("reference {0}x{0}", c.manifest.reference.resolution),
        c.manifest.reference.dir.join("reference"),
    )];
    for r in &c.rows {
        v.push((r.label.clone(), out.join("runs").join(&r.label)));
    }
    v.retain(|(_, d)| d.join("frames").is_dir());
    v
}

/// Writes `out/snapshots.png`: one row per run, one column per snapshot time.
pub fn snapshots(out: &Path, c: &Comparison) -> RenderOutcome {
    use super::render::{obstacle_meshes, snapshot_grid, SnapshotRow};
    let targets: Vec<f64> = SNAPSHOT_FRACTIONS
        .iter()
        .map(|f| f * c.manifest.duration)
        .collect();
    let mut rows = Vec::new();
    for (label, dir) in shown_runs(out, c) {
        let mut frames = Vec::new();
        for (t, path) in pick_frames(&frame_times(&dir), &targets) {
            match FrameMesh::read(&path) {
                Ok(m) => frames.push((t, m)),
                Err(e) => return RenderOutcome::Failed(format!("{}: {e}", path.display())),
            }
        }
        rows.push(SnapshotRow { label, frames });
    }
    let obstacles = match obstacle_meshes(&c.manifest.obstacles, &c.manifest.base_dir) {
        Ok(o) => o,
        Err(e) => return RenderOutcome::Failed(format!("obstacles: {e}")),
    };
    let path = out.join("snapshots.png");
    match snapshot_grid(&rows, &obstacles, &path) {
        Ok(()) => RenderOutcome::Written(path),
        Err(e) => RenderOutcome::Failed(e.to_string()),
    }
}

/// Writes `runs/<label>/error_map.png` for every run that wrote `error_map.csv`: its error over
/// the rest-space pattern at each map time, with its mesh at that time (the frame nearest in
/// time) drawn over it, on one colour scale shared by all runs of the comparison. Returns each
/// run's label and outcome.
pub fn error_maps(out: &Path, c: &Comparison) -> Vec<(String, RenderOutcome)> {
    use crate::eval::error_map::read_error_maps;
    let maps: Vec<(String, PathBuf, Vec<_>)> = c
        .rows
        .iter()
        .filter_map(|r| {
            let dir = out.join("runs").join(&r.label);
            let maps = read_error_maps(&dir.join("error_map.csv")).ok()?;
            (!maps.is_empty()).then(|| (r.label.clone(), dir, maps))
        })
        .collect();
    let e_max = maps
        .iter()
        .flat_map(|(_, _, m)| m.iter().flat_map(|m| m.samples.iter().map(|s| s.1)))
        .filter(|e| e.is_finite())
        .fold(0.0, f64::max);
    maps.iter()
        .map(|(label, dir, maps)| (label.clone(), error_map(dir, label, maps, e_max)))
        .collect()
}

/// One run's error-map picture (see [`error_maps`]).
fn error_map(
    dir: &Path,
    label: &str,
    maps: &[crate::eval::error_map::ErrorMap],
    e_max: f64,
) -> RenderOutcome {
    use super::render::error_map::{error_map_png, MapPanel};
    let frames = frame_times(dir);
    let mut panels = Vec::new();
    for map in maps {
        let Some((_, frame)) = pick_frames(&frames, &[map.t]).pop() else {
            return RenderOutcome::Failed(format!("{}: no frames", dir.display()));
        };
        let obj = match crate::io::read_obj(&frame) {
            Ok(o) => o,
            Err(e) => return RenderOutcome::Failed(e.to_string()),
        };
        let rest = |c: crate::io::obj::ObjCorner| c.vt.map(|t| obj.texcoords[t]);
        let triangles = obj
            .triangle_corners()
            .filter_map(|(_, c)| Some([rest(c[0])?, rest(c[1])?, rest(c[2])?]))
            .collect();
        panels.push(MapPanel { map, triangles });
    }
    let path = dir.join("error_map.png");
    let title = format!("{label}: e(u, v) over the pattern, with the mesh");
    match error_map_png(&path, &title, &panels, e_max) {
        Ok(()) => RenderOutcome::Written(path),
        Err(e) => RenderOutcome::Failed(e.to_string()),
    }
}

/// Writes `out/report.html` with the sections and a 3D replay of every run.
pub fn html(out: &Path, c: &Comparison, title: &str, sections: &[Section]) -> RenderOutcome {
    use super::html::{write_report_html, ReplayRun};
    use super::render::obstacle_meshes;
    let mut replays = Vec::new();
    for (label, dir) in shown_runs(out, c).into_iter().skip(1) {
        let mut run = ReplayRun {
            label,
            frame_times: Vec::new(),
            frames: Vec::new(),
        };
        for (t, path) in frame_times(&dir) {
            match FrameMesh::read(&path) {
                Ok(m) => {
                    run.frame_times.push(t);
                    run.frames.push(m);
                }
                Err(e) => return RenderOutcome::Failed(format!("{}: {e}", path.display())),
            }
        }
        replays.push(run);
    }
    let obstacles = match obstacle_meshes(&c.manifest.obstacles, &c.manifest.base_dir) {
        Ok(o) => o,
        Err(e) => return RenderOutcome::Failed(format!("obstacles: {e}")),
    };
    let path = out.join("report.html");
    match write_report_html(&path, title, sections, &replays, &obstacles) {
        Ok(()) => RenderOutcome::Written(path),
        Err(e) => RenderOutcome::Failed(e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn picks_nearest_frames() {
        let frames: Vec<(f64, PathBuf)> = (0..=6)
            .map(|k| (k as f64 * 0.1, PathBuf::from(format!("f{k}"))))
            .collect();
        let picked = pick_frames(&frames, &[0.15, 0.3, 0.44, 0.6]);
        let names: Vec<String> = picked.iter().map(|p| p.1.display().to_string()).collect();
        assert_eq!(names, ["f1", "f3", "f4", "f6"]);
    }
}
