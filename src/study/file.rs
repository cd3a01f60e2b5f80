//! Study files: a study described in TOML (`adaptcloth study FILE.toml`), parsed into a [`Study`].
//! The format is documented in `docs/studies.md`; in short:
//!
//! ```toml
//! name = "round_table"                  # default: the file's stem
//! scenes = ["round_table"]              # embedded scene names, or files relative to this file
//! duration = 0.6                        # optional: simulated time of every run (s)
//! set = { "time.frame_rate" = 30 }      # scene keys for every run AND the reference
//!
//! [reference]                           # independent of the runs; these are the defaults
//! resolution = 65                       # static grid, vertices per side
//! floor = 33                            # the floor run's grid
//! integrator = "rk4"
//! beta = 0.01                           # dynamic step factor
//! dt_initial = 0.0                      # step until the first contact (s); 0: dynamic at once
//! # dt = 0.00025                        # a fixed step (s) instead of the dynamic one (no beta)
//! samples = 64                          # material-point grid per side
//!
//! [[runs]]
//! strategy = "bisect48"
//! resolution = 5                        # start grid (default: the scene's)
//! integrator = "implicit_euler"         # default: the scene's
//! dt = 0.002                            # fixed step (s); or `beta` for the dynamic step
//! set = { "adaptivity.interval" = 0.01 }          # scene keys for this run only
//! sweep = { "adaptivity.h_min" = [0.08, 0.04] }   # one run per value (per combination)
//! ```
//!
//! Labels: `BASE-RESOLUTION-INTEGRATOR` then `-KEY=VALUE` per swept key other than the grid
//! (`KEY` is the last part of the scene key), `BASE` being the run's `label` or its strategy.
//! Sweeping `cloth.resolution` (or `resolution`) sets the start grid. Every error names the file,
//! the line and what was expected.

use super::config::RunConfig;
use super::StudyError;
use crate::eval::reference::{ReferenceSettings, MAX_GRID_SIDE, MAX_SAMPLES};
use crate::physics::integrator_named;
use crate::scene::{plain_types, LoadedScene, Setting};
use crate::strategies::strategy_names;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;
use toml::Spanned;

/// Most runs a study may hold over all its scenes (a study of hundreds of runs is the intended
/// scale; a sweep typed with thousands of values per key is refused before it is planned).
pub const MAX_RUNS: usize = 10_000;

/// A parsed study: what to run and what to measure against.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    /// Name (outputs go to a folder of this name).
    pub name: String,
    /// One-line description.
    pub description: String,
    /// Where it came from (a file, or `command line`).
    pub source: String,
    /// Scenes: embedded names or paths.
    pub scenes: Vec<String>,
    /// Where each scene was given, for messages (`study.toml:3: scenes[1] = "sphere"`, `scene
    /// argument 2 = "sphere"`); as long as `scenes`.
    pub scenes_from: Vec<String>,
    /// Scene overrides for every run and the reference.
    pub set: Vec<Setting>,
    /// Simulated duration of every run and the reference (s), if not the scene's.
    pub duration: Option<f64>,
    /// The reference and its floor.
    pub reference: ReferenceSettings,
    /// The runs, before their scene is known (the start grid and integrator may be the scene's).
    pub runs: Vec<RunTemplate>,
}

/// One run of a study, resolved against a scene by [`RunTemplate::config`].
#[derive(Clone, Debug, PartialEq)]
pub struct RunTemplate {
    /// Strategy name.
    pub strategy: String,
    /// Start grid (vertices per side); `None`: the scene's.
    pub resolution: Option<usize>,
    /// Integrator; `None`: the scene's.
    pub integrator: Option<String>,
    /// The label's first part (default: the strategy).
    pub base: String,
    /// Scene overrides of this run only.
    pub set: Vec<Setting>,
    /// Label suffix from the swept values (`-h_min=0.04`), empty without a sweep.
    pub suffix: String,
    /// Where the run was given, for messages about its grid and strategy (`study.toml:7:
    /// runs[0]`, `--runs static@5`).
    pub from: String,
}

impl RunTemplate {
    /// The configuration of this run on `scene`.
    pub fn config(&self, scene: &LoadedScene) -> RunConfig {
        RunConfig {
            strategy: self.strategy.clone(),
            resolution: self.resolution.unwrap_or(scene.scene.cloth.resolution),
            integrator: self
                .integrator
                .clone()
                .unwrap_or_else(|| scene.scene.integrator.name.clone()),
            base: self.base.clone(),
            set: self.set.clone(),
            suffix: self.suffix.clone(),
            from: self.from.clone(),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyToml {
    #[serde(default)]
    name: String,
    #[serde(default)]
    description: String,
    scenes: Vec<Spanned<String>>,
    duration: Option<Spanned<f64>>,
    #[serde(default)]
    set: BTreeMap<String, Spanned<toml::Value>>,
    #[serde(default)]
    reference: ReferenceToml,
    runs: Vec<RunToml>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, default)]
struct ReferenceToml {
    resolution: Spanned<usize>,
    floor: Spanned<usize>,
    integrator: Spanned<String>,
    beta: Spanned<f64>,
    dt_initial: Spanned<f64>,
    dt: Option<Spanned<f64>>,
    samples: Spanned<usize>,
}

impl Default for ReferenceToml {
    fn default() -> Self {
        let d = ReferenceSettings::default();
        ReferenceToml {
            resolution: Spanned::new(0..0, d.resolution),
            floor: Spanned::new(0..0, d.floor_resolution),
            integrator: Spanned::new(0..0, "rk4".into()),
            beta: Spanned::new(0..0, d.beta.unwrap_or(0.01)),
            dt_initial: Spanned::new(0..0, d.dt_initial.unwrap_or(0.0)),
            dt: None,
            samples: Spanned::new(0..0, d.samples),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RunToml {
    strategy: Spanned<String>,
    resolution: Option<Spanned<usize>>,
    integrator: Option<Spanned<String>>,
    label: Option<Spanned<String>>,
    dt: Option<Spanned<f64>>,
    beta: Option<Spanned<f64>>,
    #[serde(default)]
    set: BTreeMap<String, Spanned<toml::Value>>,
    #[serde(default)]
    sweep: BTreeMap<String, Spanned<Vec<toml::Value>>>,
}

/// Errors of one study file: the file, the line of a span, and what was expected.
struct Errors<'a> {
    text: &'a str,
    source: &'a str,
}

impl Errors<'_> {
    /// `FILE:LINE` of the start of `span`.
    fn place(&self, span: std::ops::Range<usize>) -> String {
        let line = self.text[..span.start.min(self.text.len())]
            .matches('\n')
            .count()
            + 1;
        format!("{}:{line}", self.source)
    }

    fn at(&self, span: std::ops::Range<usize>, message: String) -> StudyError {
        StudyError::Config(format!("{}: {message}", self.place(span)))
    }

    /// The setting `key=value` given at `span` under `table` (`set`, `runs[0].sweep`), placed
    /// there for messages.
    fn setting(
        &self,
        span: std::ops::Range<usize>,
        table: &str,
        key: &str,
        value: &toml::Value,
    ) -> Setting {
        Setting::at(
            format!("{key}={value}"),
            format!("{}: {table}.\"{key}\" = {value}", self.place(span)),
        )
    }

    /// Every key of `set` (written under `table`) as a placed setting.
    fn settings(&self, table: &str, set: &BTreeMap<String, Spanned<toml::Value>>) -> Vec<Setting> {
        set.iter()
            .map(|(k, v)| self.setting(v.span(), table, k, v.get_ref()))
            .collect()
    }

    fn spanned<T>(&self, v: &Spanned<T>, message: String) -> StudyError {
        self.at(v.span(), message)
    }
}

/// Reads and checks a study file; scene paths are made relative to its folder.
pub fn load_study(path: &Path) -> Result<Study, StudyError> {
    let text = crate::io::read_text(path).map_err(|e| {
        StudyError::Config(format!("{}: cannot read study file: {e}", path.display()))
    })?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    parse_study(&text, &path.display().to_string(), &stem, &dir)
}

/// The expected form of the top-level key written at byte `at` of `text` (as `key = ...`,
/// `[key]` or `[[key]]`), for a parser error there that names only types.
fn form_of_key_at(text: &str, at: usize) -> Option<&'static str> {
    let line = text.get(at..)?.lines().next()?;
    let key = line
        .trim_start_matches('[')
        .split(['=', ']', '.', ' '])
        .next()?
        .trim();
    Some(match key {
        "scenes" => "`scenes` is a list of embedded scene names or scene files: scenes = [\"sphere\", \"my_scene.toml\"]",
        "runs" => "`runs` are tables, one per run: [[runs]] then strategy = \"bisect48\", ...",
        "reference" => "`reference` is one table: [reference] then resolution = 65, ...",
        "set" => "`set` is a table of scene keys: set = { \"time.frame_rate\" = 30 }",
        "duration" => "`duration` is the simulated time of every run in seconds: duration = 0.6",
        _ => return None,
    })
}

/// Whether a parsed TOML document looks like a study file (`scenes` or `runs` and no scene
/// section), to point a user who gave one to `run` at `study`.
pub fn looks_like_study(doc: &toml::Table) -> bool {
    has_study_key(doc) && !crate::scene::has_scene_section(doc)
}

/// Whether a parsed TOML document has `scenes` or `runs`, keys only a study file has.
pub fn has_study_key(doc: &toml::Table) -> bool {
    doc.contains_key("scenes") || doc.contains_key("runs")
}

/// Parses study text; `source` names it in errors, `default_name` is used when it has no name,
/// `dir` is the folder scene paths are relative to.
pub fn parse_study(
    text: &str,
    source: &str,
    default_name: &str,
    dir: &Path,
) -> Result<Study, StudyError> {
    let err = Errors { text, source };
    let file: StudyToml = toml::from_str(text).map_err(|e| {
        let hint = e.span().and_then(|span| form_of_key_at(text, span.start));
        let message = plain_types(e.to_string().trim_end());
        let scene =
            toml::from_str::<toml::Table>(text).is_ok_and(|t| crate::scene::looks_like_scene(&t));
        StudyError::Config(match hint {
            Some(form) => format!("{source}: {message}\n{form}"),
            None if scene => format!(
                "{source}: {message}\nthis looks like a scene file (it has a scene's sections and \
                 no `scenes` or [[runs]]): run it with `adaptcloth run FILE`"
            ),
            None => format!("{source}: {message}"),
        })
    })?;
    if file.scenes.is_empty() {
        return Err(StudyError::Config(format!(
            "{source}: `scenes` is empty: name at least one scene"
        )));
    }
    if file.runs.is_empty() {
        return Err(StudyError::Config(format!(
            "{source}: no [[runs]]: a study needs at least one run"
        )));
    }
    let scenes = file
        .scenes
        .iter()
        .enumerate()
        .map(|(i, s)| scene_named(s, i, dir, &err))
        .collect::<Result<_, _>>()?;
    if let Some(d) = &file.duration {
        if !(d.get_ref().is_finite() && *d.get_ref() > 0.0) {
            return Err(err.spanned(
                d,
                format!(
                    "duration = {}: expected a finite value > 0 (s)",
                    d.get_ref()
                ),
            ));
        }
    }
    let reference = reference_settings(&file.reference, &err)?;
    let planned = file.runs.iter().fold(0usize, |total, run| {
        let product = run
            .sweep
            .values()
            .fold(1usize, |p, v| p.saturating_mul(v.get_ref().len().max(1)));
        total.saturating_add(product)
    });
    let per_scene_limit = MAX_RUNS / file.scenes.len();
    if planned > per_scene_limit {
        return Err(StudyError::Config(format!(
            "{source}: the runs and sweeps expand to {planned} runs per scene ({} in all over {} \
             scene(s)), more than a study may hold ({MAX_RUNS}); split it into several study \
             files (each can be sharded over a cluster: docs/studies.md)",
            planned.saturating_mul(file.scenes.len()),
            file.scenes.len()
        )));
    }
    let mut runs = Vec::new();
    for (i, run) in file.runs.iter().enumerate() {
        runs.extend(expand_run(run, i, &err)?);
    }
    check_unique_labels(&runs)?;
    Ok(Study {
        name: if file.name.is_empty() {
            default_name.to_string()
        } else {
            file.name
        },
        description: file.description,
        source: source.to_string(),
        scenes,
        scenes_from: file
            .scenes
            .iter()
            .enumerate()
            .map(|(i, s)| format!("{}: scenes[{i}] = {:?}", err.place(s.span()), s.get_ref()))
            .collect(),
        set: err.settings("set", &file.set),
        duration: file.duration.map(|d| d.into_inner()),
        reference,
        runs,
    })
}

/// The scene `scenes[index]` names: a file relative to the study's folder `dir`, else the name
/// as given (an absolute or working-folder path, or an embedded scene); an error at its line
/// when it is none of these.
fn scene_named(
    name: &Spanned<String>,
    index: usize,
    dir: &Path,
    err: &Errors,
) -> Result<String, StudyError> {
    let given = name.get_ref();
    let p = dir.join(given);
    if !Path::new(given).is_absolute() && p.is_file() {
        return Ok(p.display().to_string());
    }
    let embedded = crate::scene::embedded_names();
    if embedded.contains(&given.as_str()) && !Path::new(given).is_file() {
        return Ok(given.clone());
    }
    if Path::new(given).exists() {
        return match crate::scene::not_a_file(Path::new(given)) {
            None => Ok(given.clone()),
            Some(why) => Err(err.spanned(
                name,
                format!("scenes[{index}] = \"{given}\": {why}; expected a scene file"),
            )),
        };
    }
    Err(err.spanned(
        name,
        format!(
            "scenes[{index}] = \"{given}\": no such scene file (relative to the study file's \
             folder) and no embedded scene of that name (embedded: {})",
            embedded.join(", ")
        ),
    ))
}

fn reference_settings(r: &ReferenceToml, err: &Errors) -> Result<ReferenceSettings, StudyError> {
    for (key, v, max, what) in [
        (
            "resolution",
            &r.resolution,
            MAX_GRID_SIDE,
            "vertices per side",
        ),
        ("floor", &r.floor, MAX_GRID_SIDE, "vertices per side"),
        ("samples", &r.samples, MAX_SAMPLES, "points per side"),
    ] {
        if !(2..=max).contains(v.get_ref()) {
            return Err(err.spanned(
                v,
                format!(
                    "reference.{key} = {}: expected 2 to {max} {what}",
                    v.get_ref()
                ),
            ));
        }
    }
    let (resolution, floor) = (*r.resolution.get_ref(), *r.floor.get_ref());
    if floor >= resolution {
        // Point at the key the file wrote (a default has an empty span).
        let at = if r.floor.span().is_empty() {
            &r.resolution
        } else {
            &r.floor
        };
        return Err(err.spanned(
            at,
            format!(
                "reference.floor = {floor}: expected below reference.resolution = {resolution} \
                 (the floor is a coarser grid, measured against the reference)"
            ),
        ));
    }
    integrator_named(r.integrator.get_ref())
        .map_err(|e| err.spanned(&r.integrator, format!("reference.integrator: {e}")))?;
    let beta = *r.beta.get_ref();
    if !(beta.is_finite() && beta > 0.0) {
        return Err(err.spanned(
            &r.beta,
            format!("reference.beta = {beta}: expected a finite value > 0"),
        ));
    }
    let dt0 = *r.dt_initial.get_ref();
    if !(dt0.is_finite() && dt0 >= 0.0) {
        return Err(err.spanned(
            &r.dt_initial,
            format!("reference.dt_initial = {dt0}: expected a finite value >= 0 (s)"),
        ));
    }
    if let Some(dt) = &r.dt {
        let value = *dt.get_ref();
        if !(value.is_finite() && value > 0.0) {
            return Err(err.spanned(
                dt,
                format!("reference.dt = {value}: expected a finite step > 0 (s)"),
            ));
        }
        // A default has an empty span: only a `beta` the file wrote conflicts.
        if !r.beta.span().is_empty() {
            return Err(err.spanned(
                &r.beta,
                "reference.beta and reference.dt: expected one of them (beta sets the dynamic \
                 step, dt a fixed one)"
                    .to_string(),
            ));
        }
    }
    Ok(ReferenceSettings {
        resolution: *r.resolution.get_ref(),
        floor_resolution: *r.floor.get_ref(),
        beta: Some(beta),
        integrator: Some(r.integrator.get_ref().clone()),
        dt_initial: Some(dt0),
        dt: r.dt.as_ref().map(|d| *d.get_ref()),
        samples: *r.samples.get_ref(),
    })
}

/// Is `key` the start grid (`resolution` or `cloth.resolution`)?
fn is_grid_key(key: &str) -> bool {
    key == "resolution" || key == "cloth.resolution"
}

/// One `[[runs]]` entry expanded over its sweep (every combination, keys in name order).
fn expand_run(run: &RunToml, index: usize, err: &Errors) -> Result<Vec<RunTemplate>, StudyError> {
    let strategy = run.strategy.get_ref();
    if !strategy_names().contains(&strategy.as_str()) {
        return Err(err.spanned(
            &run.strategy,
            format!(
                "runs[{index}].strategy = \"{strategy}\": expected one of: {}",
                strategy_names().join(", ")
            ),
        ));
    }
    if let Some(r) = &run.resolution {
        if *r.get_ref() < 2 {
            return Err(err.spanned(
                r,
                format!(
                    "runs[{index}].resolution = {}: expected at least 2",
                    r.get_ref()
                ),
            ));
        }
    }
    if let Some(i) = &run.integrator {
        integrator_named(i.get_ref())
            .map_err(|e| err.spanned(i, format!("runs[{index}].integrator: {e}")))?;
    }
    let mut set = err.settings(&format!("runs[{index}].set"), &run.set);
    // `dt` and `beta` choose the time stepping; a message about either names the study key.
    let stepping = |mode: &str, key: &str, v: &Spanned<f64>| {
        let from = format!(
            "{}: runs[{index}].{key} = {:?}",
            err.place(v.span()),
            v.get_ref()
        );
        [
            Setting::at(format!("time.mode=\"{mode}\""), from.clone()),
            Setting::at(format!("time.{key}={:?}", v.get_ref()), from),
        ]
    };
    match (&run.dt, &run.beta) {
        (Some(dt), Some(_)) => {
            return Err(err.spanned(
                dt,
                format!("runs[{index}]: give `dt` (fixed step) or `beta` (dynamic step), not both"),
            ));
        }
        (Some(dt), None) => set.extend(stepping("fixed", "dt", dt)),
        (None, Some(beta)) => set.extend(stepping("dynamic", "beta", beta)),
        (None, None) => {}
    }
    check_keys_given_once(run, index, err)?;
    if let Some(label) = &run.label {
        let bad = |c: char| c == ',' || c == '"' || c.is_control();
        if label.get_ref().is_empty() || label.get_ref().chars().any(bad) {
            return Err(err.spanned(
                label,
                format!(
                    "runs[{index}].label = {:?}: expected a non-empty name without commas, \
                     quotes or control characters (it is a column of comparison.csv and part of \
                     a folder name)",
                    crate::console::clip(label.get_ref())
                ),
            ));
        }
    }
    let base = run
        .label
        .as_ref()
        .map(|l| l.get_ref().clone())
        .unwrap_or_else(|| strategy.clone());
    let mut out = vec![RunTemplate {
        strategy: strategy.clone(),
        resolution: run.resolution.as_ref().map(|r| *r.get_ref()),
        integrator: run.integrator.as_ref().map(|i| i.get_ref().clone()),
        base,
        set,
        suffix: String::new(),
        from: format!("{}: runs[{index}]", err.place(run.strategy.span())),
    }];
    for (key, values) in &run.sweep {
        if values.get_ref().is_empty() {
            return Err(err.spanned(
                values,
                format!("runs[{index}].sweep.{key}: expected at least one value"),
            ));
        }
        let mut next = Vec::new();
        for t in &out {
            for v in values.get_ref() {
                let mut t = t.clone();
                if is_grid_key(key) {
                    let n = v.as_integer().filter(|n| *n >= 2).ok_or_else(|| {
                        err.spanned(values, format!("runs[{index}].sweep.{key}: {v} is not a grid of at least 2 vertices per side"))
                    })?;
                    t.resolution = Some(n as usize);
                } else {
                    let short = key.rsplit('.').next().unwrap_or(key);
                    t.suffix.push_str(&format!("-{short}={v}"));
                    let table = format!("runs[{index}].sweep");
                    t.set.push(err.setting(values.span(), &table, key, v));
                }
                next.push(t);
            }
        }
        out = next;
    }
    check_sweep_values(run, index, &out, err)?;
    Ok(out)
}

#[path = "run_checks.rs"]
mod run_checks;
use run_checks::{check_keys_given_once, check_sweep_values, check_unique_labels};

#[cfg(test)]
#[path = "file_tests.rs"]
mod tests;
