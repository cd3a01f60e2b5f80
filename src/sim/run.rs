//! The run driver: steps the simulation to its duration, records metrics and frames, shows
//! progress, and stops cleanly on divergence, adaptation failure, a non-conforming frame or an
//! interrupt, with everything recorded so far on disk and a summary saying why it stopped.

use super::frames::{Frame, FrameWrites};
use super::sample::{SamplePoints, Sampler, Trajectory};
use super::{Simulation, StageTimes, StepError};
use crate::io::{frame_path, is_frame_name, temp_path, write_atomic, MetricsRow, MetricsWriter};
use crate::math::Real;
use crate::math::Vec3;
use crate::mesh::Mesh;
use crate::parallel::pool_can_help;
use crate::scene::LinearSolver;
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How a run is driven.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder (created if missing).
    pub out_dir: PathBuf,
    /// Show a progress bar on stderr (it stays hidden when stderr is not a terminal).
    pub progress: bool,
    /// Set to true (e.g. by Ctrl-C) to stop the run cleanly.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Where the scene came from, for the summary.
    pub source: String,
    /// Material points to sample at every output frame (error metrics); the trajectory is
    /// returned in [`RunSummary::trajectory`].
    pub samples: Option<Arc<SamplePoints>>,
    /// A progress bar to drive instead of creating one (e.g. one line of a multi-run display).
    pub bar: Option<ProgressBar>,
    /// The scene after every override (`crate::scene::resolved_toml`), written as
    /// `scene.resolved.toml` when the run starts; `None` writes none.
    pub resolved_scene: Option<String>,
    /// The command line that started the run (recorded in `summary.json`).
    pub command: String,
}

/// The command line of this process (`adaptcloth run ...`), for the records a run keeps.
pub fn this_command() -> String {
    std::env::args().collect::<Vec<_>>().join(" ")
}

/// `BINARY run SCENE --out OUT` on the `scene.resolved.toml` the run writes, `BINARY` the
/// running program (absolute paths, so the line works as it is from any folder; `adaptcloth`
/// when the program's path is unknown; the copy goes beside the original, `-rerun` added); empty
/// when the run writes none.
fn rerun_command(opts: &RunOptions) -> String {
    if opts.resolved_scene.is_none() {
        return String::new();
    }
    rerun_line(&opts.out_dir)
}

/// The line that runs the `scene.resolved.toml` of the run folder `out_dir` again with the
/// running program, into `out_dir` with `-rerun` added (absolute paths).
pub fn rerun_line(out_dir: &Path) -> String {
    let program = std::env::current_exe()
        .map(|p| shell_word(&p))
        .unwrap_or_else(|_| "adaptcloth".to_string());
    let out = std::path::absolute(out_dir).unwrap_or_else(|_| out_dir.to_path_buf());
    let mut again = out.clone().into_os_string();
    again.push("-rerun");
    format!(
        "{program} run {} --out {}",
        shell_word(&out.join("scene.resolved.toml")),
        shell_word(Path::new(&again))
    )
}

/// `path` as one shell word: as it is when it holds only safe characters, else single-quoted.
fn shell_word(path: &Path) -> String {
    let text = path.display().to_string();
    let safe = |c: char| c.is_ascii_alphanumeric() || "/._-=+,:@".contains(c);
    if !text.is_empty() && text.chars().all(safe) {
        text
    } else {
        format!("'{}'", text.replace('\'', "'\\''"))
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// Reached the scene's duration.
    Completed,
    /// Non-finite state or a velocity above `time.max_speed`.
    Diverged,
    /// Stopped by the user.
    Interrupted,
    /// Adaptation failed or a frame broke a conformity rule.
    Failed,
}

/// `summary.json`: what ran, how long it took, how it ended.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// Scene file or `<embedded NAME>`.
    pub source: String,
    /// The command line that started the run (for a study's run, the whole study's).
    pub command: String,
    /// The folder `command` ran in (absolute; empty when unknown).
    pub working_dir: String,
    /// This run alone again (absolute paths): `adaptcloth run` on the `scene.resolved.toml` it
    /// wrote; empty when it wrote none.
    pub rerun: String,
    /// The version of adaptcloth that ran it.
    pub version: String,
    /// Strategy.
    pub strategy: String,
    /// Integrator.
    pub integrator: String,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time reached (s).
    pub sim_time: Real,
    /// Wall time of the run (s).
    pub wall_time_s: f64,
    /// Largest live vertex count.
    pub max_vertices: usize,
    /// Final live vertex count.
    pub final_vertices: usize,
    /// Frames written.
    pub frames: usize,
    /// Largest depth of a vertex inside an obstacle over the recorded rows (m).
    pub max_penetration: Real,
    /// Largest depth of an obstacle through the cloth surface (faces included) over the recorded
    /// rows (m).
    pub max_surface_penetration: Real,
    /// Largest count of the cloth's crossings with itself over the frames and the last state
    /// ([`Simulation::self_intersections`]; not taken on the rows in between).
    pub max_self_intersections: usize,
    /// Steps whose linear solve ended above its tolerance (`implicit_euler`; 0 otherwise).
    pub cg_unconverged: u64,
    /// Steps with a failed factorisation ([`crate::physics::StepStats::solver_fallback`]:
    /// `integrator.solver = "cholesky"`, `"auto"` or `"pcg_springs"`).
    pub solver_fallbacks: u64,
    /// Steps whose CG ended above its tolerance and that Cholesky solved again
    /// (`integrator.solver = "auto"` or `"pcg_springs"`).
    pub cholesky_rescues: u64,
    /// Windows of steps that `integrator.solver = "auto"` solved by Cholesky because CG had
    /// converged slowly (more than 3.5 `sqrt(slots)` iterations on 24 consecutive steps of one
    /// mesh).
    pub cholesky_switches: u64,
    /// What self-collision did, when `collision.self = true`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub self_contact: Option<crate::collision::SelfContactTotals>,
    /// How the run ended.
    pub status: RunStatus,
    /// Why it stopped, when not completed.
    pub message: String,
    /// Wall time per stage of the step.
    pub stage_times: StageTimes,
    /// The sampled material points, when [`RunOptions::samples`] asked for them (not serialized).
    #[serde(skip)]
    pub trajectory: Option<Trajectory>,
}

/// Runs `sim` to its duration, writing `frames/`, `metrics.csv` and `summary.json` to
/// `opts.out_dir`. Simulation failures and write failures during the run (a full disk) end the
/// run with a status (`failed` for a write, naming the file); a metrics table whose write failed
/// keeps its `.partial` name. Errors preparing the folder or writing the summary are returned.
pub fn run(sim: &mut Simulation, opts: &RunOptions) -> std::io::Result<RunSummary> {
    let started = Instant::now();
    if let Some(flag) = &opts.interrupt {
        sim.set_interrupt(flag.clone());
    }
    clear_previous_run(&opts.out_dir)?;
    if let Some(text) = &opts.resolved_scene {
        write_atomic(&opts.out_dir.join("scene.resolved.toml"), text.as_bytes())?;
    }
    let names: Vec<String> = sim.tracked.iter().map(|p| p.name.clone()).collect();
    let mut metrics = Some(MetricsWriter::create(&opts.out_dir, &names)?);
    let metrics_path = opts.out_dir.join("metrics.csv.partial");
    let bar = match &opts.bar {
        Some(bar) => {
            bar.set_length((sim.scene.time.duration * 1e3).ceil() as u64);
            bar.clone()
        }
        None => progress_bar(sim, opts.progress),
    };
    let mut sampler = opts.samples.as_deref().map(Sampler::new);

    let frame_period = 1.0 / sim.scene.time.frame_rate;
    let metrics_period = 1.0 / sim.scene.time.metrics_rate;
    let mut frames = 0usize;
    // The mesh version last found conforming: the check depends only on the topology and the
    // rest geometry, which the version tracks, so an unchanged mesh is not checked again.
    let mut conforming_version = None;
    let mut max_vertices = sim.cloth.mesh.vertex_count();
    let (mut max_penetration, mut max_surface_penetration): (Real, Real) = (0.0, 0.0);
    let mut max_self_intersections = 0;
    let mut last = super::StepReport::default();
    let mut next_metrics = 0.0;
    let (mut status, mut message) = (RunStatus::Completed, String::new());
    let mut last_flush = Instant::now();
    // A failed write ends the run as `failed`; a failed metrics write also drops the table
    // (left as `.partial`: it may be torn). Frames are written on another thread of the pool
    // when it has one (`frames`); the scope ends when the last of them is written.
    let writes = FrameWrites::default();
    rayon::in_place_scope(|scope| {
        let sink = writes.sink(pool_can_help().then_some(scope));
        loop {
            let clock = Instant::now();
            let due_frame = sim.t >= frames as Real * frame_period - 1e-9 * frame_period;
            let done = sim.finished();
            if due_frame || done || sim.t >= next_metrics || last.adapt.events > 0 {
                // The crossing measure costs as much as a step on small meshes: it is taken on the
                // states written as frames (and the last one), where anyone can take it again.
                let row = metrics_row(sim, &last, due_frame || done);
                max_penetration = max_penetration.max(row.max_penetration);
                max_surface_penetration = max_surface_penetration.max(row.max_surface_penetration);
                if let Some(crossings) = row.self_intersections {
                    max_self_intersections = max_self_intersections.max(crossings);
                }
                if let Some(Err(e)) = metrics.as_mut().map(|m| m.row(&row)) {
                    (status, message) = write_failure(sim, &metrics_path, e);
                    metrics = None;
                }
                while next_metrics <= sim.t {
                    let next = next_metrics + metrics_period;
                    if next == next_metrics {
                        // The period is below the time's resolution: never loop on it.
                        next_metrics = sim.t + metrics_period.max(Real::EPSILON * sim.t.abs());
                        break;
                    }
                    next_metrics = next;
                }
            }
            if due_frame && status == RunStatus::Completed {
                let version = sim.cloth.mesh.version();
                if conforming_version != Some(version) {
                    match sim.cloth.mesh.check() {
                        Ok(()) => conforming_version = Some(version),
                        Err(e) => {
                            status = RunStatus::Failed;
                            message = format!(
                            "frame {frames} at step {}, t = {:.6} s breaks a conformity rule: {e}",
                            sim.steps, sim.t
                        );
                        }
                    }
                }
                let path = frame_path(&opts.out_dir, frames);
                sink.submit(Frame::capture(path, &sim.cloth.mesh, &sim.cloth.x, sim.t));
                if let Some(s) = sampler.as_mut() {
                    s.record(&sim.cloth, sim.t);
                }
                frames += 1;
            }
            if let Some((path, e)) = writes.failure() {
                (status, message) = then_failed(
                    status,
                    std::mem::take(&mut message),
                    write_failure(sim, &path, e),
                );
            }
            if last_flush.elapsed() > Duration::from_secs(2) {
                if let Some(Err(e)) = metrics.as_mut().map(MetricsWriter::flush) {
                    (status, message) = write_failure(sim, &metrics_path, e);
                    metrics = None;
                }
                last_flush = Instant::now();
            }
            sim.stage_times.record_s += clock.elapsed().as_secs_f64();
            if done || status != RunStatus::Completed {
                break;
            }
            if opts
                .interrupt
                .as_ref()
                .is_some_and(|f| f.load(Ordering::Relaxed))
            {
                status = RunStatus::Interrupted;
                message = format!("interrupted at step {}, t = {:.6} s", sim.steps, sim.t);
                break;
            }
            let stepped = sim.step();
            // A failed adaptation pass leaves its mesh (past `max_vertices`): counted too.
            max_vertices = max_vertices.max(sim.cloth.mesh.vertex_count());
            match stepped {
                Ok(report) => {
                    if let Some(s) = sampler.as_mut() {
                        s.observe_adaptation(&report.adapt);
                    }
                    if report.integrator.unconverged && sim.solves.unconverged == 1 {
                        bar.suspend(|| warn_unconverged(sim, &report.integrator, &opts.out_dir));
                    }
                    last = report
                }
                Err(e) => {
                    status = match e {
                        StepError::Diverged { .. } => RunStatus::Diverged,
                        StepError::Adapt { .. } | StepError::Unconverged { .. } => {
                            RunStatus::Failed
                        }
                    };
                    message = e.to_string();
                    let row = metrics_row(sim, &last, true);
                    if let Some(Err(e)) = metrics.as_mut().map(|m| m.row(&row)) {
                        let (failed, why) = write_failure(sim, &metrics_path, e);
                        (status, message) = (failed, format!("{message}; then {why}"));
                        metrics = None;
                    }
                    break;
                }
            }
            if sim.steps % 64 == 0 {
                bar.set_position((sim.t * 1e3) as u64);
                bar.set_message(format!(
                    "{} steps, {} vertices, dt {:.2e} s",
                    sim.steps,
                    sim.cloth.mesh.vertex_count(),
                    last.dt
                ));
            }
        }
    });
    // A frame written after the loop's last look may still have failed.
    if let Some((path, e)) = writes.failure() {
        (status, message) = then_failed(status, message, write_failure(sim, &path, e));
    }
    let frames = writes.written();
    bar.finish_and_clear();
    if let Some(Err(e)) = metrics.map(MetricsWriter::finish) {
        (status, message) = write_failure(sim, &metrics_path, e);
    }
    let summary = RunSummary {
        scene: sim.scene.name.clone(),
        source: opts.source.clone(),
        command: opts.command.clone(),
        working_dir: std::env::current_dir()
            .map(|d| d.display().to_string())
            .unwrap_or_default(),
        rerun: rerun_command(opts),
        version: env!("CARGO_PKG_VERSION").to_string(),
        strategy: sim.strategy_name().to_string(),
        integrator: sim.integrator_name().to_string(),
        steps: sim.steps,
        sim_time: sim.t,
        wall_time_s: started.elapsed().as_secs_f64(),
        max_vertices,
        final_vertices: sim.cloth.mesh.vertex_count(),
        frames,
        max_penetration,
        max_surface_penetration,
        max_self_intersections,
        cg_unconverged: sim.solves.unconverged,
        solver_fallbacks: sim.solves.fallbacks,
        cholesky_rescues: sim.solves.rescues,
        cholesky_switches: sim.solves.switches,
        self_contact: sim
            .scene
            .collision
            .self_collision
            .then_some(sim.self_contact_totals),
        status,
        message,
        stage_times: sim.stage_times,
        trajectory: sampler.map(Sampler::finish),
    };
    let json = serde_json::to_string_pretty(&summary).map_err(std::io::Error::other)?;
    write_atomic(&opts.out_dir.join("summary.json"), json.as_bytes())?;
    Ok(summary)
}

/// The warning, on stderr, about the first step of a run whose solve ended above tolerance
/// (`stats`: its report); the run's folder `out_dir` names the run.
fn warn_unconverged(sim: &Simulation, stats: &crate::physics::StepStats, out_dir: &Path) {
    let remedy = if sim.scene.integrator.solver == LinearSolver::Cg {
        ", integrator.solver = \"auto\" or \"cholesky\" solves such steps to tolerance"
    } else {
        ""
    };
    crate::note!(
        "warning: {}: the implicit solve did not converge at step {}, t = {:.6} s: {}. The run \
         goes on with the last iterate; every such step is counted in cg_unconverged \
         (metrics.csv, summary.json) and not reported again; integrator.on_unconverged = \
         \"fail\" ends the run instead{remedy}",
        out_dir.display(),
        sim.steps,
        sim.t,
        sim.unconverged_reason(stats)
    );
}

/// The status and message of a run that was at `status` with `message` when `failure` (a status
/// and its message) happened: the failure's own when the run was going on, else the first
/// status with both messages.
fn then_failed(
    status: RunStatus,
    message: String,
    failure: (RunStatus, String),
) -> (RunStatus, String) {
    match status {
        RunStatus::Completed => failure,
        _ => (status, format!("{message}; then {}", failure.1)),
    }
}

/// The status and message of a run whose write of `path` failed (a full disk, no permission).
fn write_failure(sim: &Simulation, path: &Path, e: std::io::Error) -> (RunStatus, String) {
    let message = format!(
        "writing {} failed at step {}, t = {:.6} s: {e}",
        path.display(),
        sim.steps,
        sim.t
    );
    (RunStatus::Failed, message)
}

/// Prepares `out_dir` for a run and removes what an earlier run there left that this run
/// rewrites, and nothing else: frame files of the exact pattern `frames/frame_NNNNN.obj`, the
/// summary, and the temporary files of interrupted atomic writes of those names (`NAME.tmp`).
/// Any other file in the folder (a user's notes, `frame_final.obj`) is kept.
fn clear_previous_run(out_dir: &Path) -> std::io::Result<()> {
    let frames_dir = out_dir.join("frames");
    std::fs::create_dir_all(&frames_dir).map_err(|e| {
        std::io::Error::new(
            e.kind(),
            format!("cannot create the folder {}: {e}", frames_dir.display()),
        )
    })?;
    for entry in std::fs::read_dir(&frames_dir)? {
        let entry = entry?;
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let own = is_frame_name(name.strip_suffix(".tmp").unwrap_or(&name));
        if own && entry.file_type()?.is_file() {
            std::fs::remove_file(entry.path())?;
        }
    }
    for name in ["summary.json", "scene.resolved.toml", "metrics.csv"] {
        let path = out_dir.join(name);
        if name == "summary.json" {
            remove_file_if_any(&path)?;
        }
        remove_file_if_any(&temp_path(&path))?;
    }
    Ok(())
}

/// Removes the regular file `path`; nothing when there is none (or a folder is there).
fn remove_file_if_any(path: &Path) -> std::io::Result<()> {
    if std::fs::symlink_metadata(path).is_ok_and(|m| m.is_file()) {
        std::fs::remove_file(path)?;
    }
    Ok(())
}

/// The metrics of the current state; `last` is the step just taken. The self-intersection count
/// is taken only when `count_crossings`.
fn metrics_row(sim: &Simulation, last: &super::StepReport, count_crossings: bool) -> MetricsRow {
    let cloth = &sim.cloth;
    let energy = sim.energies();
    MetricsRow {
        step: sim.steps,
        t: sim.t,
        dt: last.dt,
        vertices: cloth.mesh.vertex_count(),
        edges: cloth.mesh.edge_count(),
        faces: cloth.mesh.face_count(),
        min_mass: cloth.model.min_mass(),
        max_stiffness: cloth.model.max_stiffness(),
        total_mass: cloth.model.total_mass(),
        linear_momentum: cloth.linear_momentum().norm(),
        kinetic_energy: cloth.kinetic_energy(),
        max_penetration: sim.max_penetration(),
        max_surface_penetration: sim.max_surface_penetration(),
        self_intersections: count_crossings.then(|| sim.self_intersections()),
        contacts: last.contacts.contacts,
        held_contacts: last.held_contacts,
        adapt_events: last.adapt.events,
        adapt_energy_change: last.adapt.kinetic_energy_change,
        adapt_total_energy_change: last.adapt_total_energy_change,
        gravity_energy: energy.gravity,
        stretch_energy: energy.stretch,
        bending_energy: energy.bending,
        total_energy: energy.total(),
        cg_iterations: last.integrator.cg_iterations,
        cg_unconverged: sim.solves.unconverged,
        tracked: sim.tracked_positions().collect(),
    }
}

/// A progress bar over simulated milliseconds, hidden unless asked for and on a terminal.
fn progress_bar(sim: &Simulation, show: bool) -> ProgressBar {
    let total_ms = (sim.scene.time.duration * 1e3).ceil() as u64;
    let bar = ProgressBar::with_draw_target(
        Some(total_ms),
        if show {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    if let Ok(style) = ProgressStyle::with_template(
        "{spinner} [{bar:30}] {pos}/{len} ms simulated, {msg}, ETA {eta}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// A new bar in `multi` over simulated milliseconds, its prefix the run's `label` (one line of a
/// multi-run display: a study's pool, the reference and its floor).
pub fn labelled_bar(multi: &MultiProgress, label: &str) -> ProgressBar {
    let bar = multi.add(ProgressBar::new(1));
    if let Ok(style) =
        ProgressStyle::with_template("{prefix:>22} [{bar:25}] {pos}/{len} ms, {msg}, ETA {eta}")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(label.to_string());
    bar.set_message("starting");
    bar
}

/// Writes one frame of `mesh` at world positions `x` (indexed by slot) through
/// [`crate::io::write_frame`]: live vertices renumbered in slot order.
pub fn write_mesh_frame(path: &Path, mesh: &Mesh, x: &[Vec3], time: f64) -> std::io::Result<()> {
    Frame::capture(path.to_path_buf(), mesh, x, time).write()
}
