//! A study made concrete: each scene loaded with the study's overrides, its configurations built
//! and every run's scene validated, before anything runs.

use super::config::{configs_for, RunConfig};
use super::file::Study;
use super::StudyError;
use crate::scene::{self, LoadedScene, Overrides};
use std::path::PathBuf;

/// One scene of a study, ready to run.
#[derive(Clone, Debug)]
pub struct ScenePlan {
    /// The scene with the study-wide overrides (what the reference runs).
    pub loaded: LoadedScene,
    /// The configurations, in study order.
    pub configs: Vec<RunConfig>,
    /// The comparison's output folder.
    pub out: PathBuf,
}

/// Loads every scene of `study`, builds its configurations and checks every run's scene;
/// `out(scene_name)` is the output folder of a scene.
pub fn plan(study: &Study, out: impl Fn(&str) -> PathBuf) -> Result<Vec<ScenePlan>, StudyError> {
    let overrides = Overrides {
        set: study.set.clone(),
        duration: study.duration,
        ..Overrides::default()
    };
    let mut plans = Vec::new();
    for name in &study.scenes {
        let loaded = scene::resolve(Some(name), &overrides)?;
        let configs = configs_for(&study.runs, &loaded)?;
        let out = out(&loaded.scene.name);
        plans.push(ScenePlan {
            loaded,
            configs,
            out,
        });
    }
    Ok(plans)
}
