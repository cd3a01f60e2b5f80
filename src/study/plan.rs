//! A study made concrete: each scene loaded with the study's overrides, its configurations built
//! and every run's scene validated, before anything runs.

use super::config::{configs_for, fingerprint, RunConfig};
use super::file::Study;
use super::StudyError;
use crate::scene::{self, LoadedScene, Overrides};
use crate::sim::Simulation;
use std::path::PathBuf;

/// One scene of a study, ready to run.
#[derive(Clone, Debug)]
pub struct ScenePlan {
    /// The scene with the study-wide overrides (what the reference runs).
    pub loaded: LoadedScene,
    /// The configurations, in study order.
    pub configs: Vec<RunConfig>,
    /// Each configuration's settings fingerprint ([`fingerprint`]), in `configs`' order.
    pub settings: Vec<String>,
    /// The comparison's output folder.
    pub out: PathBuf,
    /// What to tell the user before the runs (runs of an integrator stable at any step on the
    /// scene's dynamic step: [`Simulation::dynamic_step_note`]).
    pub notes: Vec<String>,
}

/// Loads every scene of `study`, builds its configurations and checks every run's scene, that
/// no two scenes share an output folder (the second would overwrite the first), and, unless
/// `force`, that no run is estimated at more steps than a run may take
/// ([`Simulation::check_step_estimate`]); `out(scene_name)` is the output folder of a scene (a
/// folder name made from the scene's `name` must fit a file system:
/// [`LoadedScene::check_folder_name`]).
pub fn plan(
    study: &Study,
    out: impl Fn(&str) -> PathBuf,
    force: bool,
) -> Result<Vec<ScenePlan>, StudyError> {
    let overrides = Overrides {
        set: study.set.clone(),
        duration: study.duration,
        ..Overrides::default()
    };
    let mut plans: Vec<ScenePlan> = Vec::new();
    for (i, name) in study.scenes.iter().enumerate() {
        let loaded = scene::resolve(Some(name), &overrides)?;
        let dir = out(&loaded.scene.name);
        if let Some(j) = plans.iter().position(|p| p.out == dir) {
            let given = |k: usize, l: &LoadedScene| {
                let from = study.scenes_from.get(k).unwrap_or(&study.scenes[k]);
                format!("{from} ({}, named `{}`)", l.source, l.scene.name)
            };
            return Err(StudyError::Config(format!(
                "{} and {} would write to the same folder {}: the second would overwrite the \
                 first's results; list each scene once, or give one scene file another `name`",
                given(j, &plans[j].loaded),
                given(i, &loaded),
                dir.display()
            )));
        }
        let configs = configs_for(&study.runs, &loaded)?;
        let mut small_steps = Vec::new();
        let mut settings = Vec::with_capacity(configs.len());
        for c in &configs {
            // A run whose settings make a scene that cannot be set up (a swept cloth size that
            // leaves a tracked point off the cloth) is refused here, before any run starts.
            let run = c.scene(&loaded)?;
            c.check_keys_read(&run)?;
            settings.push(fingerprint(&run));
            let simulation = Simulation::new(&run).map_err(|e| {
                StudyError::Config(format!(
                    "run {}: its settings make a scene that cannot be set up: {e}",
                    c.label()
                ))
            })?;
            if !force {
                check_steps(&simulation, c)?;
            }
            if simulation.dynamic_step_note().is_some() {
                small_steps.push(c.label());
            }
        }
        let notes = dynamic_step_notes(&small_steps);
        // A folder named after the scene (not the one `--out` names whatever the scene).
        let unnamed = out("");
        if let Some(folder) = dir.file_name().filter(|f| Some(*f) != unnamed.file_name()) {
            loaded.check_folder_name(&folder.to_string_lossy(), "")?;
        }
        plans.push(ScenePlan {
            loaded,
            configs,
            settings,
            out: dir,
            notes,
        });
    }
    Ok(plans)
}

/// Fails when the run of `config` (set up as `simulation`) is estimated at more steps than a
/// run may take.
fn check_steps(simulation: &Simulation, config: &RunConfig) -> Result<(), StudyError> {
    simulation.check_step_estimate().map_err(|e| {
        StudyError::Config(format!(
            "run {}: {e}; {}",
            config.label(),
            crate::sim::FORCE_HINT
        ))
    })
}

/// One note naming the runs (by label) of an integrator stable at any step that take their
/// scene's dynamic step; none when there are none.
fn dynamic_step_notes(labels: &[String]) -> Vec<String> {
    if labels.is_empty() {
        return Vec::new();
    }
    vec![format!(
        "note: {} run(s) of an integrator stable at any step take the scene's dynamic step \
         (time.mode = \"dynamic\", set by the explicit integrators' stability): {}; give such a \
         run its own step for large steps (dt = 0.002)",
        labels.len(),
        crate::console::clip(&labels.join(", "))
    )]
}
