//! `adaptcloth compare`: runs a list of configurations (strategy x grid x integrator) of one scene,
//! in parallel, measures each against the reference, and writes the comparison table, plots and
//! reports ([`super::report`]). `--shard i/n` runs a deterministic slice and [`merge`] combines the
//! shards' folders into one report.
//!
//! Output folder: `comparison.csv` (one row per run), `comparison.json` (the manifest: scene,
//! configurations, skipped strategies, reference and floor), `runs/<label>/` (each run's own
//! frames, metrics.csv, summary.json, and `error.csv` with `e(t)`), plots and reports.

use super::metrics;
use super::reference::{self, Floor, Reference, ReferenceError, ReferenceSettings};
use crate::physics::integrator_named;
use crate::scene::{LoadedScene, ObstacleSpec, Scene};
use crate::sim::{RunStatus, SamplePoints};
use crate::strategies::{make_strategy, strategy_names};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Static grids of the default comparison (vertices per side).
pub const DEFAULT_STATIC_GRIDS: [usize; 4] = [5, 9, 17, 33];

/// Why a comparison could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// A configuration, shard or option is invalid (bad input).
    #[error("{0}")]
    Config(String),
    /// The reference could not be made.
    #[error("reference: {0}")]
    Reference(#[from] ReferenceError),
    /// Reading or writing outputs failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: String,
        /// The error.
        source: std::io::Error,
    },
    /// Shards cannot be merged.
    #[error("merge: {0}")]
    Merge(String),
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> CompareError + '_ {
    move |source| CompareError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// One configuration: a strategy on a starting grid with an integrator, at the scene's other
/// parameters.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunConfig {
    /// Strategy name.
    pub strategy: String,
    /// Vertices per side of the starting grid.
    pub resolution: usize,
    /// Integrator name.
    pub integrator: String,
}

impl RunConfig {
    /// `strategy-resolution-integrator`, e.g. `static-17-rk4` (also the run's folder name).
    pub fn label(&self) -> String {
        format!("{}-{}-{}", self.strategy, self.resolution, self.integrator)
    }
}

/// The default configurations: static on [`DEFAULT_STATIC_GRIDS`] and every adaptive strategy
/// on the scene's grid, each with every integrator in `integrators` (configuration-major).
pub fn default_configs(scene: &Scene, integrators: &[String]) -> Vec<RunConfig> {
    let mut spec: Vec<String> = DEFAULT_STATIC_GRIDS
        .iter()
        .map(|n| format!("static@{n}"))
        .collect();
    spec.extend(
        strategy_names()
            .iter()
            .filter(|s| **s != "static")
            .map(|s| s.to_string()),
    );
    parse_configs(&spec.join(","), scene, integrators).expect("default configurations parse")
}

/// Parses `strategy[@resolution],...` (resolution defaults to the scene's) crossed with the
/// integrators (default: the scene's). Unknown strategies and integrators are errors; strategies
/// that are not built are kept (see [`split_built`]).
pub fn parse_configs(
    spec: &str,
    scene: &Scene,
    integrators: &[String],
) -> Result<Vec<RunConfig>, CompareError> {
    let integrators: Vec<String> = if integrators.is_empty() {
        vec![scene.integrator.name.clone()]
    } else {
        integrators.to_vec()
    };
    for i in &integrators {
        integrator_named(i).map_err(|e| CompareError::Config(e.to_string()))?;
    }
    let mut out = Vec::new();
    for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (strategy, resolution) = match item.split_once('@') {
            Some((s, r)) => {
                let r: usize = r.trim().parse().map_err(|_| {
                    CompareError::Config(format!(
                        "configuration `{item}`: expected strategy@resolution with an integer resolution"
                    ))
                })?;
                (s.trim(), r)
            }
            None => (item, scene.cloth.resolution),
        };
        if !strategy_names().contains(&strategy) {
            return Err(CompareError::Config(format!(
                "configuration `{item}`: unknown strategy `{strategy}`; valid strategies: {}",
                strategy_names().join(", ")
            )));
        }
        if resolution < 2 {
            return Err(CompareError::Config(format!(
                "configuration `{item}`: resolution must be at least 2"
            )));
        }
        for i in &integrators {
            let c = RunConfig {
                strategy: strategy.to_string(),
                resolution,
                integrator: i.clone(),
            };
            if out.contains(&c) {
                return Err(CompareError::Config(format!(
                    "configuration {} listed twice",
                    c.label()
                )));
            }
            out.push(c);
        }
    }
    if out.is_empty() {
        return Err(CompareError::Config("no configuration to run".into()));
    }
    Ok(out)
}

/// A configuration left out, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Skipped {
    /// Its label.
    pub label: String,
    /// Why (e.g. the strategy is unknown).
    pub reason: String,
}

/// Splits configurations into those whose strategy [`make_strategy`] builds and the skipped ones.
pub fn split_built(configs: &[RunConfig]) -> (Vec<RunConfig>, Vec<Skipped>) {
    let mut built = Vec::new();
    let mut skipped = Vec::new();
    for c in configs {
        match make_strategy(&c.strategy) {
            Ok(_) => built.push(c.clone()),
            Err(e) => skipped.push(Skipped {
                label: c.label(),
                reason: e.to_string(),
            }),
        }
    }
    (built, skipped)
}

/// A slice `index/count` of a list (1-based index): item `j` belongs to shard `j % count + 1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 1-based shard number.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = CompareError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || CompareError::Config(format!("--shard {s}: expected i/n with 1 <= i <= n"));
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if index == 0 || count == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// Whether item `j` (0-based position in the full list) belongs to this shard.
    pub fn contains(&self, j: usize) -> bool {
        j % self.count + 1 == self.index
    }

    /// The items of this shard, in list order.
    pub fn slice<T: Clone>(&self, items: &[T]) -> Vec<T> {
        items
            .iter()
            .enumerate()
            .filter(|(j, _)| self.contains(*j))
            .map(|(_, x)| x.clone())
            .collect()
    }
}

/// One row of `comparison.csv`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// Strategy.
    pub strategy: String,
    /// Integrator.
    pub integrator: String,
    /// Configuration label.
    pub label: String,
    /// Wall time of the run (s), recording included.
    pub wall_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// Time-weighted mean live vertex count.
    pub mean_vertices: f64,
    /// Largest live vertex count.
    pub max_vertices: usize,
    /// RMS over frames of `e(t)` (m).
    pub e_rms: f64,
    /// `e` at the last frame (m).
    pub e_final: f64,
    /// Tracked-point trajectory error (m).
    pub tracked_err: f64,
    /// Hausdorff distance between the final surfaces (m).
    pub hausdorff: f64,
    /// Largest depth inside an obstacle (m).
    pub max_penetration: f64,
    /// `completed`, `diverged`, `interrupted`, `failed`, or `error` (could not start).
    pub status: String,
    /// Starting grid (vertices per side).
    pub resolution: usize,
    /// Simulated time reached (s).
    pub sim_time: f64,
    /// Adaptation operations.
    pub adapt_events: u64,
    /// Largest momentum change of one adaptation event (kg m/s).
    pub max_momentum_jump: f64,
    /// Largest absolute kinetic-energy change of one step's adaptation (J).
    pub max_energy_jump: f64,
    /// Sum of adaptation kinetic-energy changes (J).
    pub total_energy_jump: f64,
    /// Wall time integrating (s).
    pub integrate_s: f64,
    /// Wall time in collisions (s).
    pub collide_s: f64,
    /// Wall time adapting (s).
    pub adapt_s: f64,
    /// Wall time rebuilding elements (s).
    pub rebuild_s: f64,
    /// Wall time recording outputs (s).
    pub record_s: f64,
}

/// The columns of `comparison.csv`, in order.
pub const CSV_COLUMNS: &[&str] = &[
    "scene",
    "strategy",
    "integrator",
    "label",
    "wall_s",
    "steps",
    "mean_vertices",
    "max_vertices",
    "e_rms",
    "e_final",
    "tracked_err",
    "hausdorff",
    "max_penetration",
    "status",
    "resolution",
    "sim_time",
    "adapt_events",
    "max_momentum_jump",
    "max_energy_jump",
    "total_energy_jump",
    "integrate_s",
    "collide_s",
    "adapt_s",
    "rebuild_s",
    "record_s",
];

impl Row {
    fn csv_line(&self) -> String {
        format!(
            "{},{},{},{},{:.4},{},{:.2},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{},{},{:.6},{},{:.6e},{:.6e},{:.6e},{:.4},{:.4},{:.4},{:.4},{:.4}",
            self.scene,
            self.strategy,
            self.integrator,
            self.label,
            self.wall_s,
            self.steps,
            self.mean_vertices,
            self.max_vertices,
            self.e_rms,
            self.e_final,
            self.tracked_err,
            self.hausdorff,
            self.max_penetration,
            self.status,
            self.resolution,
            self.sim_time,
            self.adapt_events,
            self.max_momentum_jump,
            self.max_energy_jump,
            self.total_energy_jump,
            self.integrate_s,
            self.collide_s,
            self.adapt_s,
            self.rebuild_s,
            self.record_s,
        )
    }

    /// True when the run completed (only those enter the Pareto front and the speed-ups).
    pub fn completed(&self) -> bool {
        self.status == "completed"
    }
}

/// Writes `comparison.csv`.
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<(), CompareError> {
    let mut s = CSV_COLUMNS.join(",");
    s.push('\n');
    for r in rows {
        s.push_str(&r.csv_line());
        s.push('\n');
    }
    crate::output::write_atomic(path, s.as_bytes()).map_err(io_err(path))
}

/// Reads `comparison.csv` (columns by name).
pub fn read_csv(path: &Path) -> Result<Vec<Row>, CompareError> {
    let text = std::fs::read_to_string(path).map_err(io_err(path))?;
    let bad = |why: String| CompareError::Merge(format!("{}: {why}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| bad("empty".into()))?
        .split(',')
        .collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| bad(format!("no column {name}")))
    };
    let idx: Vec<usize> = CSV_COLUMNS
        .iter()
        .map(|c| col(c))
        .collect::<Result<_, _>>()?;
    let mut rows = Vec::new();
    for (n, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let cells: Vec<&str> = line.split(',').collect();
        let get = |k: usize| -> Result<&str, CompareError> {
            cells
                .get(idx[k])
                .copied()
                .ok_or_else(|| bad(format!("line {}: short row", n + 2)))
        };
        let num = |k: usize| -> Result<f64, CompareError> {
            let s = get(k)?;
            s.parse::<f64>().map_err(|_| {
                bad(format!(
                    "line {}: {} = `{s}` is not a number",
                    n + 2,
                    CSV_COLUMNS[k]
                ))
            })
        };
        rows.push(Row {
            scene: get(0)?.to_string(),
            strategy: get(1)?.to_string(),
            integrator: get(2)?.to_string(),
            label: get(3)?.to_string(),
            wall_s: num(4)?,
            steps: num(5)? as u64,
            mean_vertices: num(6)?,
            max_vertices: num(7)? as usize,
            e_rms: num(8)?,
            e_final: num(9)?,
            tracked_err: num(10)?,
            hausdorff: num(11)?,
            max_penetration: num(12)?,
            status: get(13)?.to_string(),
            resolution: num(14)? as usize,
            sim_time: num(15)?,
            adapt_events: num(16)? as u64,
            max_momentum_jump: num(17)?,
            max_energy_jump: num(18)?,
            total_energy_jump: num(19)?,
            integrate_s: num(20)?,
            collide_s: num(21)?,
            adapt_s: num(22)?,
            rebuild_s: num(23)?,
            record_s: num(24)?,
        });
    }
    Ok(rows)
}

/// What the comparison measured against.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReferenceInfo {
    /// Reference grid.
    pub resolution: usize,
    /// Its step factor.
    pub beta: f64,
    /// Its integrator.
    pub integrator: String,
    /// Its step until the first contact (s; 0 = dynamic from the start; `None`: the scene's).
    #[serde(default)]
    pub dt_initial: Option<f64>,
    /// Cache key.
    pub key: String,
    /// Its steps.
    pub steps: u64,
    /// Its wall time (s).
    pub wall_s: f64,
    /// Sample grid (per side).
    pub samples: usize,
    /// The floor.
    pub floor: Floor,
    /// The cache entry folder.
    pub dir: PathBuf,
    /// The reference's first tracked point: `[t, x, y, z]` per frame (s, m).
    pub tracked: Vec<[f64; 4]>,
}

/// `comparison.json`: everything about a comparison but the rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Scene name.
    pub scene: String,
    /// Scene file or `<embedded NAME>`.
    pub source: String,
    /// Folder of the scene's relative files.
    pub base_dir: PathBuf,
    /// Simulated duration (s).
    pub duration: f64,
    /// The scene's step factor (runs use it).
    pub beta: f64,
    /// Every built configuration of the sweep (all shards), by label, in order.
    pub configs: Vec<String>,
    /// Configurations left out (strategy not built).
    pub skipped: Vec<Skipped>,
    /// The shard this folder holds (`None`: all, or merged).
    pub shard: Option<Shard>,
    /// Parallel jobs used.
    pub jobs: usize,
    /// The reference.
    pub reference: ReferenceInfo,
    /// The scene's obstacles (for rendering).
    pub obstacles: Vec<ObstacleSpec>,
}

/// A comparison: its manifest and its rows (in configuration order).
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The manifest.
    pub manifest: Manifest,
    /// One row per run.
    pub rows: Vec<Row>,
}

/// How to run a comparison.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// The configurations (built and not built; the latter are skipped and listed).
    pub configs: Vec<RunConfig>,
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

/// A progress bar style with the run's label as prefix.
pub fn style_bar(bar: &ProgressBar, label: &str) {
    if let Ok(style) =
        ProgressStyle::with_template("{prefix:>22} [{bar:25}] {pos}/{len} ms, {msg}, ETA {eta}")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(label.to_string());
}

/// Runs the comparison of `base`: the reference (cached), then every built configuration of the
/// shard, `jobs` at a time. Per-run failures become rows with their status; only the reference
/// failing, bad options or I/O stop it.
pub fn compare(base: &LoadedScene, opts: &CompareOptions) -> Result<Comparison, CompareError> {
    let (built, skipped) = split_built(&opts.configs);
    let labels: Vec<String> = built.iter().map(RunConfig::label).collect();
    let mine = match opts.shard {
        Some(s) => s.slice(&built),
        None => built.clone(),
    };
    std::fs::create_dir_all(&opts.out_dir).map_err(io_err(&opts.out_dir))?;
    let multi = MultiProgress::with_draw_target(if opts.progress {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let jobs = opts.jobs.max(1);
    let reference = reference::ensure_reference(
        base,
        &opts.reference,
        &opts.cache_dir,
        jobs,
        opts.force_reference,
        Some(&multi),
        opts.interrupt.clone(),
    )?;
    let _ = multi.println(reference::describe(&reference));
    if !opts.progress {
        eprintln!("{}", reference::describe(&reference));
    }
    let samples = Arc::new(reference.header.samples.clone());

    // Largest grids first (shortest makespan); rows keep configuration order.
    let mut order: Vec<usize> = (0..mine.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(mine[i].resolution));
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Row>>> = Mutex::new(vec![None; mine.len()]);
    let first_error: Mutex<Option<CompareError>> = Mutex::new(None);
    std::thread::scope(|s| {
        for _ in 0..jobs.min(mine.len()) {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some(&i) = order.get(k) else { break };
                let config = &mine[i];
                let bar = multi.add(ProgressBar::new(1));
                style_bar(&bar, &config.label());
                match run_config(
                    base,
                    config,
                    &opts.out_dir,
                    &samples,
                    &reference,
                    bar.clone(),
                    opts.interrupt.clone(),
                ) {
                    Ok(row) => {
                        bar.finish_and_clear();
                        let line = format!(
                            "{:>22}: {} in {:.1} s, {} steps, e_rms {:.3e} m, e_final {:.3e} m",
                            row.label, row.status, row.wall_s, row.steps, row.e_rms, row.e_final
                        );
                        if opts.progress {
                            let _ = multi.println(line);
                        } else {
                            eprintln!("{line}");
                        }
                        results.lock().expect("results lock")[i] = Some(row);
                    }
                    Err(e) => {
                        bar.finish_and_clear();
                        first_error.lock().expect("error lock").get_or_insert(e);
                    }
                }
            });
        }
    });
    if let Some(e) = first_error.into_inner().expect("error lock") {
        return Err(e);
    }
    let rows: Vec<Row> = results
        .into_inner()
        .expect("results lock")
        .into_iter()
        .flatten()
        .collect();
    let manifest = Manifest {
        scene: base.scene.name.clone(),
        source: base.source.clone(),
        base_dir: base.base_dir.clone(),
        duration: base.scene.time.duration,
        beta: base.scene.time.beta,
        configs: labels,
        skipped,
        shard: opts.shard,
        jobs,
        reference: reference_info(&reference),
        obstacles: base.scene.obstacles.clone(),
    };
    Ok(Comparison { manifest, rows })
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
        key: h.key.clone(),
        steps: h.steps,
        wall_s: h.wall_s,
        samples: h.settings.samples,
        floor: h.floor.clone(),
        dir: r.dir.clone(),
        tracked,
    }
}

/// The scene of one configuration.
pub fn config_scene(base: &LoadedScene, c: &RunConfig) -> LoadedScene {
    let mut l = base.clone();
    l.scene.cloth.resolution = c.resolution;
    l.scene.cloth.resolution_v = 0;
    l.scene.adaptivity.strategy = c.strategy.clone();
    l.scene.integrator.name = c.integrator.clone();
    l
}

/// Runs one configuration into `out/runs/<label>/` and measures it against the reference.
fn run_config(
    base: &LoadedScene,
    c: &RunConfig,
    out: &Path,
    samples: &Arc<SamplePoints>,
    reference: &Reference,
    bar: ProgressBar,
    interrupt: Option<Arc<AtomicBool>>,
) -> Result<Row, CompareError> {
    let loaded = config_scene(base, c);
    let dir = out.join("runs").join(c.label());
    let mut row = Row {
        scene: base.scene.name.clone(),
        strategy: c.strategy.clone(),
        integrator: c.integrator.clone(),
        label: c.label(),
        wall_s: f64::NAN,
        steps: 0,
        mean_vertices: f64::NAN,
        max_vertices: 0,
        e_rms: f64::NAN,
        e_final: f64::NAN,
        tracked_err: f64::NAN,
        hausdorff: f64::NAN,
        max_penetration: f64::NAN,
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
    };
    let summary = match reference::run_sampled(&loaded, &dir, samples.clone(), Some(bar), interrupt)
    {
        Ok(s) => s,
        Err(ReferenceError::Setup(e)) => {
            std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
            let _ = std::fs::write(dir.join("error.txt"), e.to_string());
            return Ok(row);
        }
        Err(ReferenceError::Io { path, source }) => return Err(CompareError::Io { path, source }),
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
            crate::output::write_atomic(&path, s.as_bytes()).map_err(io_err(&path))?;
        }
    }
    Ok(row)
}

/// Reads a CSV file of numbers: its header and rows (cells that do not parse become NaN).
pub fn read_numeric_csv(path: &Path) -> std::io::Result<(Vec<String>, Vec<Vec<f64>>)> {
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .map(|x| x.parse::<f64>().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    Ok((header, rows))
}

/// Time-weighted mean of the `vertices` column of a run's `metrics.csv`.
pub fn mean_vertices(metrics_csv: &Path) -> Option<f64> {
    let (header, rows) = read_numeric_csv(metrics_csv).ok()?;
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

/// Writes `comparison.csv` and `comparison.json` into `out`.
pub fn write_tables(out: &Path, c: &Comparison) -> Result<(), CompareError> {
    write_csv(&out.join("comparison.csv"), &c.rows)?;
    let json = serde_json::to_string_pretty(&c.manifest).map_err(|e| CompareError::Io {
        path: out.join("comparison.json").display().to_string(),
        source: std::io::Error::other(e),
    })?;
    let path = out.join("comparison.json");
    crate::output::write_atomic(&path, json.as_bytes()).map_err(io_err(&path))
}

/// Reads a comparison folder (`comparison.json` and `comparison.csv`).
pub fn read_comparison(dir: &Path) -> Result<Comparison, CompareError> {
    let path = dir.join("comparison.json");
    let text = std::fs::read_to_string(&path).map_err(io_err(&path))?;
    let manifest: Manifest = serde_json::from_str(&text)
        .map_err(|e| CompareError::Merge(format!("{}: {e}", path.display())))?;
    let rows = read_csv(&dir.join("comparison.csv"))?;
    Ok(Comparison { manifest, rows })
}

/// Combines shard folders into one comparison written to `out`: same scene, same reference and
/// same configuration list required; each configuration must come from exactly one shard (a
/// missing one is reported as `missing` in the report, a duplicate is an error). Run folders are
/// copied into `out/runs/`.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Comparison, CompareError> {
    let parts: Vec<(PathBuf, Comparison)> = dirs
        .iter()
        .map(|d| read_comparison(d).map(|c| (d.clone(), c)))
        .collect::<Result<_, _>>()?;
    let Some((_, first)) = parts.first() else {
        return Err(CompareError::Merge("no folder given".into()));
    };
    let mut manifest = first.manifest.clone();
    for (d, c) in &parts[1..] {
        let m = &c.manifest;
        if m.scene != manifest.scene
            || m.reference.key != manifest.reference.key
            || m.configs != manifest.configs
        {
            return Err(CompareError::Merge(format!(
                "{} is not a shard of the same sweep as {} (scene, reference or configurations differ)",
                d.display(),
                dirs[0].display()
            )));
        }
    }
    let mut rows: Vec<Option<Row>> = vec![None; manifest.configs.len()];
    std::fs::create_dir_all(out.join("runs")).map_err(io_err(out))?;
    for (d, c) in &parts {
        for r in &c.rows {
            let k = manifest
                .configs
                .iter()
                .position(|l| *l == r.label)
                .ok_or_else(|| {
                    CompareError::Merge(format!("{}: unknown run {}", d.display(), r.label))
                })?;
            if rows[k].is_some() {
                return Err(CompareError::Merge(format!(
                    "run {} appears in more than one shard",
                    r.label
                )));
            }
            rows[k] = Some(r.clone());
            let from = d.join("runs").join(&r.label);
            let to = out.join("runs").join(&r.label);
            if from.is_dir() && !same_dir(&from, &to) {
                copy_dir(&from, &to)?;
            }
        }
    }
    manifest.shard = None;
    let missing: Vec<String> = manifest
        .configs
        .iter()
        .zip(&rows)
        .filter(|(_, r)| r.is_none())
        .map(|(l, _)| l.clone())
        .collect();
    for l in missing {
        manifest.skipped.push(Skipped {
            label: l,
            reason: "missing: no shard ran it".into(),
        });
    }
    let c = Comparison {
        manifest,
        rows: rows.into_iter().flatten().collect(),
    };
    Ok(c)
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

fn copy_dir(from: &Path, to: &Path) -> Result<(), CompareError> {
    std::fs::create_dir_all(to).map_err(io_err(to))?;
    for entry in std::fs::read_dir(from).map_err(io_err(from))? {
        let entry = entry.map_err(io_err(from))?;
        let p = entry.path();
        let q = to.join(entry.file_name());
        if p.is_dir() {
            copy_dir(&p, &q)?;
        } else {
            std::fs::copy(&p, &q).map_err(io_err(&p))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_embedded;

    fn scene() -> Scene {
        load_embedded("sphere", &[]).unwrap().unwrap().scene
    }

    #[test]
    fn shard_slicing_covers_every_configuration_once() {
        let items: Vec<usize> = (0..11).collect();
        for n in 1..=5 {
            let mut seen = vec![0; items.len()];
            for i in 1..=n {
                let shard: Shard = format!("{i}/{n}").parse().unwrap();
                let slice = shard.slice(&items);
                // Deterministic: the same slice twice.
                assert_eq!(slice, shard.slice(&items));
                for x in slice {
                    seen[x] += 1;
                }
            }
            assert!(seen.iter().all(|&k| k == 1), "n = {n}: {seen:?}");
        }
        for bad in ["0/3", "4/3", "1/0", "x/2", "3", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }

    #[test]
    fn default_configurations() {
        let c = default_configs(&scene(), &[]);
        let labels: Vec<String> = c.iter().map(RunConfig::label).collect();
        assert_eq!(
            labels,
            [
                "static-5-rk4",
                "static-9-rk4",
                "static-17-rk4",
                "static-33-rk4",
                "remesh-5-rk4",
                "simnett-5-rk4",
                "bisect48-5-rk4"
            ]
        );
        let (built, skipped) = split_built(&c);
        // Every configuration is either built or skipped with a reason, never both.
        assert_eq!(built.len() + skipped.len(), c.len());
        assert!(built.iter().any(|b| b.strategy == "static"));
        for s in &skipped {
            assert!(!built.iter().any(|b| b.label() == s.label));
            assert!(s.reason.contains("not built"), "{}", s.reason);
        }
    }

    #[test]
    fn configuration_parsing() {
        let ints = ["rk4".to_string(), "symplectic_euler".to_string()];
        let c = parse_configs("static@3, remesh", &scene(), &ints).unwrap();
        let labels: Vec<String> = c.iter().map(RunConfig::label).collect();
        assert_eq!(
            labels,
            [
                "static-3-rk4",
                "static-3-symplectic_euler",
                "remesh-5-rk4",
                "remesh-5-symplectic_euler"
            ]
        );
        for bad in ["magic", "static@x", "static@1", "static@5,static@5", ""] {
            assert!(parse_configs(bad, &scene(), &[]).is_err(), "{bad}");
        }
        assert!(parse_configs("static", &scene(), &["leapfrog".into()]).is_err());
    }

    #[test]
    fn csv_round_trip() {
        let row = Row {
            scene: "sphere".into(),
            strategy: "static".into(),
            integrator: "rk4".into(),
            label: "static-5-rk4".into(),
            wall_s: 1.25,
            steps: 100,
            mean_vertices: 25.0,
            max_vertices: 25,
            e_rms: 0.0125,
            e_final: 0.02,
            tracked_err: f64::NAN,
            hausdorff: 0.03,
            max_penetration: 0.0,
            status: "completed".into(),
            resolution: 5,
            sim_time: 0.6,
            adapt_events: 0,
            max_momentum_jump: 0.0,
            max_energy_jump: 0.0,
            total_energy_jump: 0.0,
            integrate_s: 1.0,
            collide_s: 0.1,
            adapt_s: 0.0,
            rebuild_s: 0.0,
            record_s: 0.15,
        };
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.csv");
        write_csv(&p, &[row.clone(), row.clone()]).unwrap();
        let back = read_csv(&p).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!(back[0].label, row.label);
        assert_eq!(back[0].e_rms, row.e_rms);
        assert!(back[0].tracked_err.is_nan());
        assert_eq!(back[0].steps, 100);
    }
}
