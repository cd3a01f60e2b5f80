//! Running a comparison: the reference (cached), then every configuration of the shard on the
//! pool, each measured against the reference. Output folder: `comparison.csv`,
//! `comparison.json` ([`super::table`]), `runs/<label>/` (each run's frames, metrics.csv,
//! summary.json, `error.csv` with `e(t)` and `error_map.csv` with `e(u, v)`); the plots and
//! reports come from `crate::report`.

use super::config::RunConfig;
use super::pool::{self, Progress};
use super::shard::Shard;
use super::table::{Comparison, Manifest, ReferenceInfo, Row, Skipped};
use super::{io_err, StudyError};
use crate::eval::error_map::{error_maps, write_error_maps};
use crate::eval::metrics;
use crate::eval::reference::{self, Reference, ReferenceError, ReferenceSettings};
use crate::scene::LoadedScene;
use crate::sim::{RunStatus, SamplePoints};
use indicatif::ProgressBar;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// How to run a comparison.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// The configurations (all shards).
    pub configs: Vec<RunConfig>,
    /// Each configuration's settings fingerprint, in `configs`' order (recorded in the manifest
    /// for `merge`).
    pub settings: Vec<String>,
    /// Parallel runs.
    pub jobs: usize,
    /// Run only this slice.
    pub shard: Option<Shard>,
    /// Output folder.
    pub out_dir: PathBuf,
    /// Reference settings.
    pub reference: ReferenceSettings,
    /// Reference cache folder.
    pub cache_dir: PathBuf,
    /// Recompute the reference even when cached.
    pub force_reference: bool,
    /// Show progress bars (on a terminal).
    pub progress: bool,
    /// Set to stop every run cleanly.
    pub interrupt: Option<Arc<AtomicBool>>,
}

/// Runs the comparison of `base`: the reference (cached), then every configuration of the
/// shard, `jobs` at a time. Per-run failures become rows with their status; only the reference
/// failing, bad options or I/O stop it. After an interrupt no run starts: the runs begun end as
/// `interrupted` rows, the others are listed in the manifest's `skipped`.
pub fn compare(base: &LoadedScene, opts: &CompareOptions) -> Result<Comparison, StudyError> {
    let labels: Vec<String> = opts.configs.iter().map(RunConfig::label).collect();
    let mine = match opts.shard {
        Some(s) => s.slice(&opts.configs),
        None => opts.configs.clone(),
    };
    std::fs::create_dir_all(&opts.out_dir).map_err(io_err(&opts.out_dir))?;
    let progress = Progress::new(opts.progress);
    let jobs = opts.jobs.max(1);
    let reference = reference::ensure_reference(
        base,
        &opts.reference,
        &opts.cache_dir,
        jobs,
        opts.force_reference,
        Some(progress.multi()),
        opts.interrupt.clone(),
    )?;
    if let Some(note) = reference.discarded_note() {
        progress.println(&note);
    }
    progress.println(&reference::describe(&reference));
    let samples = Arc::new(reference.header.samples.clone());
    let rows = pool::run_all(
        &mine,
        jobs,
        opts.interrupt.as_deref(),
        &progress,
        |c| c.resolution,
        RunConfig::label,
        |config, bar| {
            let row = run_config(base, config, opts, &samples, &reference, bar)?;
            let error = |e: f64| {
                if e.is_finite() {
                    format!("{e:.3e} m")
                } else {
                    "- (not measured)".to_string()
                }
            };
            progress.println(&format!(
                "{:>22}: {} in {:.1} s, {} steps, e_rms {}, e_final {}",
                row.label,
                row.status,
                row.wall_s,
                row.steps,
                error(row.e_rms),
                error(row.e_final)
            ));
            Ok::<Row, StudyError>(row)
        },
    )?;
    let manifest = Manifest {
        scene: base.scene.name.clone(),
        source: base.source.clone(),
        base_dir: base.base_dir.clone(),
        duration: base.scene.time.duration,
        beta: base.scene.time.beta,
        configs: labels,
        settings: opts.settings.clone(),
        command: crate::sim::this_command(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        skipped: not_started(&mine, &rows),
        shard: opts.shard,
        jobs,
        reference: reference_info(&reference),
        obstacles: base.scene.obstacles.clone(),
        collision: Some(base.scene.collision.clone()),
    };
    Ok(Comparison { manifest, rows })
}

/// The configurations of `mine` without a row: not started because of an interrupt.
fn not_started(mine: &[RunConfig], rows: &[Row]) -> Vec<Skipped> {
    mine.iter()
        .map(RunConfig::label)
        .filter(|label| rows.iter().all(|r| r.label != *label))
        .map(|label| Skipped {
            label,
            reason: "not started: the study was interrupted".into(),
        })
        .collect()
}

fn reference_info(r: &Reference) -> ReferenceInfo {
    let h = &r.header;
    let t = &r.trajectory;
    let tracked = if t.points > t.grid {
        (0..t.frames())
            .map(|k| {
                let p = t.frame(k)[t.grid];
                [t.times[k], p[0] as f64, p[1] as f64, p[2] as f64]
            })
            .collect()
    } else {
        Vec::new()
    };
    ReferenceInfo {
        resolution: h.settings.resolution,
        beta: h.beta,
        integrator: h.integrator.clone(),
        dt_initial: h.settings.dt_initial,
        dt: h.settings.dt,
        key: h.key.clone(),
        steps: h.steps,
        wall_s: h.wall_s,
        samples: h.settings.samples,
        floor: h.floor.clone(),
        dir: r.dir.clone(),
        tracked,
    }
}

/// A row for a run that has not produced anything yet: NaN measures, status `error`.
fn empty_row(base: &LoadedScene, c: &RunConfig) -> Row {
    Row {
        scene: base.scene.name.clone(),
        strategy: c.strategy.clone(),
        integrator: c.integrator.clone(),
        label: c.label(),
        series: c.base.clone(),
        wall_s: f64::NAN,
        steps: 0,
        mean_vertices: f64::NAN,
        max_vertices: 0,
        e_rms: f64::NAN,
        e_final: f64::NAN,
        tracked_err: f64::NAN,
        hausdorff: f64::NAN,
        max_penetration: f64::NAN,
        max_surface_penetration: f64::NAN,
        max_self_intersections: f64::NAN,
        status: "error".into(),
        resolution: c.resolution,
        sim_time: 0.0,
        adapt_events: 0,
        max_momentum_jump: f64::NAN,
        max_energy_jump: f64::NAN,
        total_energy_jump: f64::NAN,
        integrate_s: f64::NAN,
        collide_s: f64::NAN,
        adapt_s: f64::NAN,
        rebuild_s: f64::NAN,
        record_s: f64::NAN,
    }
}

/// Runs one configuration into `out/runs/<label>/` and measures it against the reference.
fn run_config(
    base: &LoadedScene,
    c: &RunConfig,
    opts: &CompareOptions,
    samples: &Arc<SamplePoints>,
    reference: &Reference,
    bar: ProgressBar,
) -> Result<Row, StudyError> {
    let loaded = c.scene(base)?;
    let dir = opts.out_dir.join("runs").join(c.label());
    let mut row = empty_row(base, c);
    let summary = match reference::run_sampled(
        &loaded,
        &dir,
        samples.clone(),
        Some(bar),
        opts.interrupt.clone(),
    ) {
        Ok(s) => s,
        Err(ReferenceError::Setup(e)) => {
            std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
            let _ = std::fs::write(dir.join("error.txt"), e.to_string());
            return Ok(row);
        }
        Err(ReferenceError::Io { path, source }) => return Err(StudyError::Io { path, source }),
        Err(e) => return Err(e.into()),
    };
    row.status = match summary.status {
        RunStatus::Completed => "completed",
        RunStatus::Diverged => "diverged",
        RunStatus::Interrupted => "interrupted",
        RunStatus::Failed => "failed",
    }
    .into();
    row.wall_s = summary.wall_time_s;
    row.steps = summary.steps;
    row.max_vertices = summary.max_vertices;
    row.max_penetration = summary.max_penetration;
    row.max_surface_penetration = summary.max_surface_penetration;
    row.max_self_intersections = summary.max_self_intersections as f64;
    row.sim_time = summary.sim_time;
    let st = summary.stage_times;
    row.integrate_s = st.integrate_s;
    row.collide_s = st.collide_s;
    row.adapt_s = st.adapt_s;
    row.rebuild_s = st.rebuild_s;
    row.record_s = st.record_s;
    row.mean_vertices = mean_vertices(&dir.join("metrics.csv")).unwrap_or(f64::NAN);
    if let Some(t) = &summary.trajectory {
        row.adapt_events = t.adapt.events;
        row.max_momentum_jump = t.adapt.max_momentum_change;
        row.max_energy_jump = t.adapt.max_energy_change;
        row.total_energy_jump = t.adapt.total_energy_change;
        if let Ok(e) = metrics::compare(t, &reference.trajectory) {
            row.e_rms = e.e_rms;
            row.e_final = e.e_final;
            row.tracked_err = e.tracked_err;
            row.hausdorff = e.hausdorff;
            let mut s = String::from("t,e\n");
            for (t, e) in &e.e_t {
                s.push_str(&format!("{t:.9e},{e:.6e}\n"));
            }
            let path = dir.join("error.csv");
            crate::io::write_atomic(&path, s.as_bytes()).map_err(io_err(&path))?;
            let maps = error_maps(
                t,
                &reference.trajectory,
                samples,
                loaded.scene.time.duration,
            );
            let path = dir.join("error_map.csv");
            write_error_maps(&path, &maps).map_err(io_err(&path))?;
        }
    }
    Ok(row)
}

/// Time-weighted mean of the `vertices` column of a run's `metrics.csv`.
pub fn mean_vertices(metrics_csv: &Path) -> Option<f64> {
    let (header, rows) = crate::io::read_numeric_csv(metrics_csv).ok()?;
    let t = header.iter().position(|h| h == "t")?;
    let v = header.iter().position(|h| h == "vertices")?;
    if rows.is_empty() {
        return None;
    }
    let (mut area, mut span) = (0.0, 0.0);
    for w in rows.windows(2) {
        let dt = w[1][t] - w[0][t];
        if dt > 0.0 {
            area += w[0][v] * dt;
            span += dt;
        }
    }
    Some(if span > 0.0 { area / span } else { rows[0][v] })
}
