//! The reference solution: the static strategy on a fine grid at a small step, its sampled
//! trajectories stored compactly in a cache keyed by a hash of the physics parameters, and its own
//! error floor (the same run at a coarser grid, e.g. 33x33, against it).
//!
//! Cache entry `CACHE/<scene>-<resolution>-<key>/`: `reference.bin` (magic `ACREF001`, a
//! little-endian `u32` header length, a JSON header, then the sampled positions as f32
//! little-endian, frame-major, then the final vertex positions as f32), plus the reference's and
//! the floor run's own outputs (`reference/`, `floor/`: frames, metrics.csv, summary.json).
//! An entry whose sizes disagree with its header or that holds a value not finite is malformed
//! ([`read_bin`]) and recomputed ([`Reference::discarded`]).
//!
//! The key is a 64-bit FNV-1a hash (stable across Rust releases, unlike `DefaultHasher`) of the
//! reference scene serialized to JSON with everything that is not physics normalised away (name,
//! description, the `[adaptivity]` section, `metrics_rate`), of the reference settings (grid,
//! step factor, integrator, sample grid, floor grid) and of the bytes of every mesh file the
//! scene reads. Output folders are not part of it. Frame rate is: the reference is sampled at the
//! scene's frames.

use super::metrics::{self, ErrorReport};
use crate::scene::{
    ClothShape, CollisionSpec, IntegratorSpec, LoadedScene, ObstacleShape, Scene, TimeMode,
};
use crate::sim::{self, RunOptions, RunStatus, RunSummary, SamplePoints, Simulation, Trajectory};
use indicatif::ProgressBar;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Version of the cache format and of the key's contents; bump to invalidate every entry.
pub const CACHE_FORMAT: u32 = 1;

/// How the reference is computed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReferenceSettings {
    /// Vertices per side of the reference grid. Default 65.
    pub resolution: usize,
    /// Vertices per side of the floor run compared against the reference. Default 33.
    pub floor_resolution: usize,
    /// Dynamic step factor `beta` of the reference and floor runs; `None` keeps the scene's.
    /// Default 0.01 (see `docs/results.md`: on the sphere at 17x17 the tracked corner moves by
    /// 1.3e-4 m between beta = 1e-3 and 1e-2, far below the spatial error; 0.05 diverges).
    pub beta: Option<f64>,
    /// Integrator of the reference and floor runs; `None` keeps the scene's.
    pub integrator: Option<String>,
    /// `time.dt_initial` of the reference and floor runs (s; 0 = the dynamic step from the
    /// start); `None` keeps the scene's. Default 0: the scenes' 1e-4 s pre-contact step is
    /// unstable on a 33x33 grid (measured: the sphere diverges at t = 0.099 s), while free fall
    /// before the first contact is the same at any step.
    pub dt_initial: Option<f64>,
    /// Fixed step of the reference and floor runs (s; `time.mode = "fixed"`, so `beta` and
    /// `dt_initial` go unused); `None` keeps the dynamic step. Default `None`. For an implicit
    /// reference finer than the explicit step affords (studies/results-notes.md, "A finer
    /// reference, tried").
    #[serde(default)]
    pub dt: Option<f64>,
    /// Sample grid: `samples x samples` rest points over the pattern. Default 64.
    pub samples: usize,
}

impl Default for ReferenceSettings {
    fn default() -> Self {
        ReferenceSettings {
            resolution: 65,
            floor_resolution: 33,
            beta: Some(0.01),
            integrator: None,
            dt_initial: Some(0.0),
            dt: None,
            samples: 64,
        }
    }
}

/// The floor: the floor run's errors against the reference. An error that is not a number (the
/// tracked-point error of a scene without tracked points) is written `null` in JSON and read
/// back as NaN.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Floor {
    /// Vertices per side of the floor run.
    pub resolution: usize,
    /// Its `e_rms` (m).
    #[serde(deserialize_with = "number_or_nan")]
    pub e_rms: f64,
    /// Its `e_final` (m).
    #[serde(deserialize_with = "number_or_nan")]
    pub e_final: f64,
    /// Its tracked-point error (m).
    #[serde(deserialize_with = "number_or_nan")]
    pub tracked_err: f64,
    /// Its Hausdorff distance (m).
    #[serde(deserialize_with = "number_or_nan")]
    pub hausdorff: f64,
    /// Its wall time (s).
    pub wall_s: f64,
    /// Its steps.
    pub steps: u64,
}

/// A number as serde_json writes it, `null` for a NaN, read back (NaN for `null`).
fn number_or_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// The JSON header of `reference.bin`: everything about the reference but the positions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReferenceHeader {
    /// [`CACHE_FORMAT`].
    pub format: u32,
    /// The cache key (16 hex digits).
    pub key: String,
    /// Scene name.
    pub scene: String,
    /// How it was computed.
    pub settings: ReferenceSettings,
    /// Integrator actually used.
    pub integrator: String,
    /// Step factor actually used.
    pub beta: f64,
    /// The sampled rest points.
    pub samples: SamplePoints,
    /// Frame times (s).
    pub times: Vec<f64>,
    /// Number of final vertices stored.
    pub final_vertices: usize,
    /// Steps of the reference run.
    pub steps: u64,
    /// Wall time of the reference run (s).
    pub wall_s: f64,
    /// Simulated time reached (s).
    pub sim_time: f64,
    /// The floor.
    pub floor: Floor,
    /// The normalised physics parameters that were hashed (for people reading the cache).
    pub physics: serde_json::Value,
    /// FNV-1a (16 hex digits) of the data after the header, set when written: data edited or
    /// corrupted into other finite numbers is found on reading. Empty in entries written before
    /// it was kept (2026-11-29), which are read unchecked rather than computed again.
    #[serde(default)]
    pub data_hash: String,
}

/// A loaded or computed reference.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Its header.
    pub header: ReferenceHeader,
    /// Its sampled trajectory.
    pub trajectory: Trajectory,
    /// The cache entry folder (holds `reference/` and `floor/` run outputs).
    pub dir: PathBuf,
    /// True when it was read from the cache rather than computed now.
    pub cached: bool,
    /// Why the `reference.bin` found in the cache entry was not used (malformed, or written for
    /// another key), when this reference was computed in its place; callers say so on stderr.
    pub discarded: Option<String>,
}

impl Reference {
    /// The stderr line saying a cache entry was unusable and recomputed, if it was.
    pub fn discarded_note(&self) -> Option<String> {
        self.discarded
            .as_ref()
            .map(|why| format!("warning: {why}; the reference was recomputed"))
    }
}

/// Said after a reference or floor run diverged: the keys a study sets for every run reach the
/// reference as well.
const DIVERGED_HINT: &str = "\n(the reference and floor runs take the scene keys given to every \
    run: `set` at the top of a study file, or `--set` and `--duration` of `compare` and \
    `reference`; keys meant for the runs alone, such as a fixed step, go in a study file's \
    [[runs]] entry: its `set`, `dt` or `beta`)";

/// What may have made a reference or floor run end with `status`: [`DIVERGED_HINT`] for a
/// divergence, nothing otherwise.
/// `status: message`, or the message alone for an interrupted run (it says so itself).
fn how_it_ended(status: RunStatus, message: &str) -> String {
    match status {
        RunStatus::Interrupted => message.to_string(),
        _ => format!("{status:?}: {message}"),
    }
}

fn hint_for(status: RunStatus) -> &'static str {
    if status == RunStatus::Diverged {
        DIVERGED_HINT
    } else {
        ""
    }
}

/// Why a reference could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// Reading or writing the cache or run outputs failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: String,
        /// The error.
        source: std::io::Error,
    },
    /// The scene could not be set up.
    #[error("{0}")]
    Setup(#[from] crate::sim::SetupError),
    /// A run ended without completing.
    #[error(
        "the {what} run ({resolution}x{resolution}) did not complete: {}{}",
        how_it_ended(*.status, .message),
        hint_for(*.status)
    )]
    RunFailed {
        /// `reference` or `floor`.
        what: &'static str,
        /// Its grid.
        resolution: usize,
        /// How it ended.
        status: RunStatus,
        /// Why.
        message: String,
    },
    /// A cache file is malformed.
    #[error("{path}: malformed reference cache file: {why}")]
    Malformed {
        /// The file.
        path: String,
        /// What is wrong.
        why: String,
    },
    /// The settings are unusable.
    #[error("reference settings: {0}")]
    Settings(String),
    /// The metrics could not be computed.
    #[error("{0}")]
    Eval(#[from] metrics::EvalError),
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> ReferenceError + '_ {
    move |source| ReferenceError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// 64-bit FNV-1a of `bytes`, continuing from `hash` (start with [`FNV_OFFSET`]).
pub fn fnv1a(mut hash: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        hash ^= b as u64;
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

/// FNV-1a 64 offset basis.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// The scene of a reference-like static run derived from `base`: grid `resolution`, strategy
/// static, and the settings' step factor, initial step and integrator when set.
pub fn static_variant(
    base: &LoadedScene,
    resolution: usize,
    settings: &ReferenceSettings,
) -> LoadedScene {
    let (beta, integrator) = (settings.beta, settings.integrator.as_deref());
    let mut l = base.clone();
    if let Some(d) = settings.dt_initial {
        l.scene.time.dt_initial = d;
    }
    l.scene.cloth.resolution = resolution;
    l.scene.cloth.resolution_v = 0;
    l.scene.adaptivity.strategy = "static".into();
    if let Some(b) = beta {
        l.scene.time.beta = b;
    }
    if let Some(i) = integrator {
        l.scene.integrator.name = i.to_string();
    }
    if let Some(dt) = settings.dt {
        l.scene.time.mode = TimeMode::Fixed;
        l.scene.time.dt = dt;
    }
    l
}

/// The physics parameters of a scene as they enter the key: name, description and the metrics
/// rate normalised away, and the adaptivity section left out (a reference is static, and new
/// adaptivity keys must not invalidate cached references). Keys added after the cache format
/// ([`LATER_KEYS`]) are left out at their default values, so the references cached before they
/// existed keep their keys; a non-default value still changes the key.
pub fn physics_json(scene: &Scene) -> serde_json::Value {
    let mut s = scene.clone();
    s.name.clear();
    s.description.clear();
    s.time.metrics_rate = 0.0;
    let mut value = serde_json::to_value(&s).expect("a scene serializes");
    let defaults = serde_json::json!({
        "integrator": IntegratorSpec::default(),
        "collision": CollisionSpec::default(),
    });
    if let Some(fields) = value.as_object_mut() {
        fields.remove("adaptivity");
        for (section, key) in LATER_KEYS {
            let default = defaults.get(section).and_then(|d| d.get(key));
            if let Some(table) = fields.get_mut(section).and_then(|t| t.as_object_mut()) {
                if table.get(key) == default {
                    table.remove(key);
                }
            }
        }
        // The face penalty came on by default on 2026-11-30: off, a scene runs the model of the
        // references cached before it, under their keys.
        if let Some(collision) = fields.get_mut("collision").and_then(|t| t.as_object_mut()) {
            if collision.get("penalty").and_then(|p| p.as_f64()) == Some(0.0) {
                collision.remove("penalty");
            }
        }
    }
    value
}

/// `(section, key)` of the keys that came after cached references existed (issues 13 and 16):
/// they enter [`physics_json`] only when set to a non-default value. (`solver`'s default became
/// `auto` on 2026-11-27, then `pcg_springs` the same day: a scene that names `cg` or `auto`, an
/// earlier default, now keys apart; the references run RK4, so such a reference is recomputed
/// to the same result.)
const LATER_KEYS: [(&str, &str); 4] = [
    ("integrator", "solver"),
    ("integrator", "on_unconverged"),
    ("collision", "self"),
    ("collision", "thickness"),
];

/// The cache key of the reference of `base` under `settings` (16 hex digits).
pub fn cache_key(base: &LoadedScene, settings: &ReferenceSettings) -> String {
    let reference = static_variant(base, settings.resolution, settings);
    let physics = physics_json(&reference.scene);
    let keyed = serde_json::json!({
        "format": CACHE_FORMAT,
        "physics": physics,
        "samples": settings.samples,
        "floor_resolution": settings.floor_resolution,
    });
    let mut h = fnv1a(FNV_OFFSET, keyed.to_string().as_bytes());
    for file in mesh_files(&reference) {
        h = fnv1a(h, file.display().to_string().as_bytes());
        match crate::io::read_text(&file) {
            Ok(text) => h = fnv1a(h, text.as_bytes()),
            Err(_) => h = fnv1a(h, b"<unreadable>"),
        }
    }
    format!("{h:016x}")
}

/// Files a scene reads: the cloth OBJ and obstacle meshes.
fn mesh_files(l: &LoadedScene) -> Vec<PathBuf> {
    let mut files = Vec::new();
    if l.scene.cloth.shape == ClothShape::Obj {
        files.push(PathBuf::from(&l.scene.cloth.mesh));
    }
    for o in &l.scene.obstacles {
        if let ObstacleShape::Mesh { file, .. } = &o.shape {
            files.push(PathBuf::from(file));
        }
    }
    // Hash contents read from base_dir but name them relative, so moving the tree keeps the key.
    files
        .into_iter()
        .map(|f| {
            let full = crate::scene::mesh_path(&l.base_dir, &f.to_string_lossy());
            if full.exists() || crate::io::is_embedded_path(&full) {
                full
            } else {
                f
            }
        })
        .collect()
}

/// The cache entry folder of a reference.
pub fn entry_dir(cache: &Path, base: &LoadedScene, settings: &ReferenceSettings) -> PathBuf {
    cache.join(format!(
        "{}-{}-{}",
        base.scene.name,
        settings.resolution,
        cache_key(base, settings)
    ))
}

/// Runs one static run of `loaded` into `out`, sampling `samples`.
pub fn run_sampled(
    loaded: &LoadedScene,
    out: &Path,
    samples: Arc<SamplePoints>,
    bar: Option<ProgressBar>,
    interrupt: Option<Arc<AtomicBool>>,
) -> Result<RunSummary, ReferenceError> {
    let mut simulation = Simulation::new(loaded)?;
    let command = sim::this_command();
    let opts = RunOptions {
        out_dir: out.to_path_buf(),
        progress: false,
        interrupt,
        source: loaded.source.clone(),
        samples: Some(samples),
        bar,
        resolved_scene: Some(crate::scene::resolved_toml(loaded, &command)),
        command,
    };
    sim::run(&mut simulation, &opts).map_err(io_err(out))
}

/// The sample points of a scene: `n x n` over its pattern plus its tracked points.
pub fn sample_points(loaded: &LoadedScene, n: usize) -> Result<SamplePoints, ReferenceError> {
    let cloth = crate::sim::build_cloth(loaded)?;
    let tracked: Vec<[f64; 2]> = loaded.scene.tracked.iter().map(|t| t.rest).collect();
    Ok(SamplePoints::grid_over(&cloth.mesh, n, &tracked))
}

/// Most material-point samples per side of a reference (a million points in all).
pub const MAX_SAMPLES: usize = 1000;

/// Largest reference or floor grid side (vertices per side): a grid of it holds at most
/// [`crate::mesh::MAX_VERTICES`] vertices.
pub const MAX_GRID_SIDE: usize = 2000;
const _: () = assert!(MAX_GRID_SIDE * MAX_GRID_SIDE <= crate::mesh::MAX_VERTICES);

/// Loads the reference of `base` from the cache, or computes it (reference and floor runs, in
/// parallel when `jobs >= 2`) and stores it. `force` recomputes even when cached. `progress`
/// receives one bar per run when given.
pub fn ensure_reference(
    base: &LoadedScene,
    settings: &ReferenceSettings,
    cache: &Path,
    jobs: usize,
    force: bool,
    progress: Option<&indicatif::MultiProgress>,
    interrupt: Option<Arc<AtomicBool>>,
) -> Result<Reference, ReferenceError> {
    if settings.resolution < 2 || settings.floor_resolution < 2 || settings.samples < 2 {
        return Err(ReferenceError::Settings(format!(
            "resolution {}, floor resolution {} and samples {} must be at least 2",
            settings.resolution, settings.floor_resolution, settings.samples
        )));
    }
    if settings.floor_resolution >= settings.resolution {
        return Err(ReferenceError::Settings(format!(
            "floor resolution {} must be below the reference's resolution {}",
            settings.floor_resolution, settings.resolution
        )));
    }
    let largest_grid = settings.resolution.max(settings.floor_resolution);
    if largest_grid
        .checked_mul(largest_grid)
        .is_none_or(|n| n > crate::mesh::MAX_VERTICES)
        || settings.samples > MAX_SAMPLES
    {
        return Err(ReferenceError::Settings(format!(
            "resolution {}, floor resolution {} and samples {}: a grid may have at most {} \
             vertices ({MAX_GRID_SIDE} per side) and the sample grid at most {MAX_SAMPLES} points \
             per side",
            settings.resolution,
            settings.floor_resolution,
            settings.samples,
            crate::mesh::MAX_VERTICES,
        )));
    }
    if settings.beta.is_some_and(|b| !(b > 0.0 && b.is_finite())) {
        return Err(ReferenceError::Settings(
            "beta must be positive".to_string(),
        ));
    }
    if settings.dt.is_some_and(|dt| !(dt > 0.0 && dt.is_finite())) {
        return Err(ReferenceError::Settings(
            "the fixed step dt must be positive".to_string(),
        ));
    }
    let key = cache_key(base, settings);
    let dir = entry_dir(cache, base, settings);
    let bin = dir.join("reference.bin");
    let mut discarded = None;
    if !force && bin.is_file() {
        match read_bin(&bin) {
            Ok((header, trajectory)) if header.key == key && header.format == CACHE_FORMAT => {
                return Ok(Reference {
                    header,
                    trajectory,
                    dir,
                    cached: true,
                    discarded: None,
                });
            }
            Ok((header, _)) => {
                discarded = Some(format!(
                    "{}: written for key {} (format {}), not {key} (format {CACHE_FORMAT})",
                    bin.display(),
                    header.key,
                    header.format
                ));
            }
            Err(e) => discarded = Some(e.to_string()),
        }
    }
    let reference_scene = static_variant(base, settings.resolution, settings);
    let floor_scene = static_variant(base, settings.floor_resolution, settings);
    // A reference that could never finish is refused whatever the runs' `--force` says.
    let mut steps = [0.0; 2];
    for (k, (what, scene)) in [("reference", &reference_scene), ("floor", &floor_scene)]
        .into_iter()
        .enumerate()
    {
        let simulation = Simulation::new(scene)?;
        simulation.check_step_estimate().map_err(|e| {
            ReferenceError::Settings(format!(
                "the {what} run of {} (not covered by --force): {e} (the reference and floor \
                 runs take the integrator and time.beta, time.dt_initial or a fixed time.dt from \
                 --ref-integrator, --ref-beta, --ref-dt-initial and --ref-dt, or a study's \
                 [reference] integrator, beta, dt_initial and dt)",
                base.source
            ))
        })?;
        steps[k] = simulation.step_estimate().0;
    }
    crate::note!(
        "reference {}: computing static {n}x{n} (about {:.0} steps) and its floor {m}x{m} \
         (about {:.0}), then cached in {}",
        crate::console::clip(&base.scene.name),
        steps[0],
        steps[1],
        crate::console::clip(&dir.display().to_string()),
        n = settings.resolution,
        m = settings.floor_resolution,
    );
    let samples = Arc::new(sample_points(&reference_scene, settings.samples)?);
    std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
    let bar = |label: &str| progress.map(|m| crate::sim::labelled_bar(m, label));
    let jobs_ref = (
        &reference_scene,
        dir.join("reference"),
        bar(&format!("reference {0}x{0}", settings.resolution)),
    );
    let jobs_floor = (
        &floor_scene,
        dir.join("floor"),
        bar(&format!("floor {0}x{0}", settings.floor_resolution)),
    );
    let run = |(scene, out, bar): (&LoadedScene, PathBuf, Option<ProgressBar>)| {
        let r = run_sampled(scene, &out, samples.clone(), bar.clone(), interrupt.clone());
        if let Some(b) = bar {
            b.finish_and_clear();
        }
        r
    };
    let completed = |what, resolution, s: RunSummary| match s.status {
        RunStatus::Completed => Ok(s),
        status => Err(ReferenceError::RunFailed {
            what,
            resolution,
            status,
            message: s.message,
        }),
    };
    let (reference, floor) = if jobs >= 2 {
        std::thread::scope(|s| {
            let f = s.spawn(|| run(jobs_floor));
            let r = run(jobs_ref);
            (r, f.join().expect("floor run thread"))
        })
    } else {
        // One after the other: a reference that did not complete (interrupted, diverged)
        // starts no floor run.
        let r = match run(jobs_ref).and_then(|r| completed("reference", settings.resolution, r)) {
            Ok(r) => r,
            Err(e) => {
                if let Some(b) = &jobs_floor.2 {
                    b.finish_and_clear();
                }
                return Err(e);
            }
        };
        (Ok(r), run(jobs_floor))
    };
    let reference = completed("reference", settings.resolution, reference?)?;
    let floor = completed("floor", settings.floor_resolution, floor?)?;
    let trajectory = reference.trajectory.clone().expect("sampled run");
    let floor_traj = floor.trajectory.clone().expect("sampled run");
    let e: ErrorReport = metrics::compare(&floor_traj, &trajectory)?;
    let header = ReferenceHeader {
        format: CACHE_FORMAT,
        key,
        scene: base.scene.name.clone(),
        settings: settings.clone(),
        integrator: reference.integrator.clone(),
        beta: reference_scene.scene.time.beta,
        samples: (*samples).clone(),
        times: trajectory.times.clone(),
        final_vertices: trajectory.final_vertices.len(),
        steps: reference.steps,
        wall_s: reference.wall_time_s,
        sim_time: reference.sim_time,
        floor: Floor {
            resolution: settings.floor_resolution,
            e_rms: e.e_rms,
            e_final: e.e_final,
            tracked_err: e.tracked_err,
            hausdorff: e.hausdorff,
            wall_s: floor.wall_time_s,
            steps: floor.steps,
        },
        physics: physics_json(&reference_scene.scene),
        data_hash: String::new(), // set by `write_bin`
    };
    let header = write_bin(&bin, &header, &trajectory)?;
    Ok(Reference {
        header,
        trajectory,
        dir,
        cached: false,
        discarded,
    })
}

/// How a reference steps, for people: `fixed step 0.00025 s` when `dt` is set, else `beta = B`
/// and when the dynamic step starts (`dt_initial`: 0 = from the start; `None`: the scene's).
pub fn step_description(beta: f64, dt_initial: Option<f64>, dt: Option<f64>) -> String {
    match (dt, dt_initial) {
        (Some(dt), _) => format!("fixed step {dt} s"),
        (None, Some(0.0)) => format!("beta = {beta}, dynamic step from the start"),
        (None, Some(d)) => format!("beta = {beta}, {d} s until the first contact"),
        (None, None) => format!("beta = {beta}"),
    }
}

/// A human-readable summary of a reference and its floor.
pub fn describe(r: &Reference) -> String {
    let h = &r.header;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "reference {scene}: static {n}x{n}, {integ}, {step}, {steps} steps, {wall:.1} s wall{cached}",
        scene = h.scene,
        n = h.settings.resolution,
        integ = h.integrator,
        step = step_description(h.beta, h.settings.dt_initial, h.settings.dt),
        steps = h.steps,
        wall = h.wall_s,
        cached = if r.cached { " (cached)" } else { "" }
    );
    let f = &h.floor;
    let _ = writeln!(
        s,
        "error floor ({m}x{m} against {n}x{n}): e_rms {:.3e} m, e_final {:.3e} m, tracked {:.3e} m, Hausdorff {:.3e} m ({:.1} s wall)",
        f.e_rms,
        f.e_final,
        f.tracked_err,
        f.hausdorff,
        f.wall_s,
        m = f.resolution,
        n = h.settings.resolution,
    );
    let _ = write!(s, "cache: {}", r.dir.display());
    s
}

#[path = "reference_bin.rs"]
mod bin;
pub use bin::{read_bin, write_bin};

#[cfg(test)]
#[path = "reference_tests.rs"]
mod tests;
