//! Run configurations of a study: a strategy on a starting grid with an integrator, at the scene's
//! other parameters; parsed from `strategy[@resolution],...` and crossed with integrators.

use super::file::RunTemplate;
use super::StudyError;
use crate::physics::integrator_named;
use crate::scene::{LoadedScene, Setting, TimeMode};
use crate::strategies::strategy_names;

/// Static grids of the default comparison (vertices per side).
pub const DEFAULT_STATIC_GRIDS: [usize; 4] = [5, 9, 17, 33];

/// One configuration: a strategy on a starting grid with an integrator and its own scene
/// overrides, at the scene's other parameters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunConfig {
    /// Strategy name.
    pub strategy: String,
    /// Vertices per side of the starting grid.
    pub resolution: usize,
    /// Integrator name.
    pub integrator: String,
    /// The label's first part (the strategy, or the study run's `label`).
    pub base: String,
    /// Scene overrides of this run only; never the reference's.
    pub set: Vec<Setting>,
    /// Label suffix from swept values (`-h_min=0.04`), empty without a sweep.
    pub suffix: String,
    /// Where the run was given (`study.toml:7: runs[0]`, `--runs static@5`): messages about its
    /// grid, strategy and integrator name it.
    pub from: String,
}

/// A run's label from its parts: `base-grid-integrator[suffix]`, made a plain folder name
/// ([`crate::io::folder_label`]).
pub(super) fn run_label(base: &str, grid: &str, integrator: &str, suffix: &str) -> String {
    crate::io::folder_label(&format!("{base}-{grid}-{integrator}{suffix}"))
}

impl RunConfig {
    /// `base-resolution-integrator[suffix]`, e.g. `static-17-rk4` (also the run's folder name,
    /// so made a plain folder name: [`crate::io::folder_label`]).
    pub fn label(&self) -> String {
        run_label(
            &self.base,
            &self.resolution.to_string(),
            &self.integrator,
            &self.suffix,
        )
    }

    /// The scene of this configuration: `base` with its grid, strategy, integrator and own
    /// overrides, validated as a run ([`LoadedScene::check_run`]); errors end with the label.
    pub fn scene(&self, base: &LoadedScene) -> Result<LoadedScene, StudyError> {
        let given = |key: &str, value: String| {
            Setting::at(
                format!("{key}={value}"),
                format!("{}: {key} = {value}", self.from),
            )
        };
        let mut set = vec![
            given("cloth.resolution", self.resolution.to_string()),
            given("cloth.resolution_v", "0".into()),
            given("adaptivity.strategy", format!("{:?}", self.strategy)),
            given("integrator.name", format!("{:?}", self.integrator)),
        ];
        set.extend(self.set.iter().cloned());
        crate::scene::with_overrides(base, &set)
            .and_then(|l| l.check_run().map(|()| l))
            .map_err(|e| StudyError::Config(format!("{e} (run {})", self.label())))
    }

    /// Fails when a key of this run's own `set` or `sweep` is one its scene `run` (this run's,
    /// [`RunConfig::scene`]) does not read, so runs swept over it would be the same run under
    /// different labels: `time.dt` on the dynamic step, `time.beta` and the dynamic step's
    /// clamps on a fixed step, `[adaptivity]` keys on a strategy that never edits the mesh; and
    /// `time.duration`, which is the study's (errors are measured against the reference over
    /// one span of time).
    pub fn check_keys_read(&self, run: &LoadedScene) -> Result<(), StudyError> {
        let time = &run.scene.time;
        let adapts = crate::strategies::edits_mesh(&self.strategy);
        for setting in &self.set {
            let Some(key) = setting.key() else { continue };
            let from = || setting.from.clone().unwrap_or_else(|| self.from.clone());
            if key == "time.duration" {
                return Err(StudyError::Config(format!(
                    "{}: time.duration cannot be set per run: a run's duration is the study's \
                     (its error is measured against the reference over the same span of time); \
                     set `duration` at the top of the study file",
                    from()
                )));
            }
            let why = match key {
                "time.dt" if time.mode == TimeMode::Dynamic => Some(
                    "the run takes the dynamic step (time.mode = \"dynamic\"), which never reads \
                     time.dt: give the entry `dt = ...` for a fixed step, or set time.beta"
                        .to_string(),
                ),
                "time.beta" | "time.dt_initial" | "time.dt_min" | "time.dt_max"
                    if time.mode == TimeMode::Fixed =>
                {
                    Some(format!(
                        "the run takes the fixed step time.dt = {} s, and {key} sets only the \
                         dynamic step: give the entry `beta = ...` for the dynamic step, or set \
                         time.dt",
                        time.dt
                    ))
                }
                k if k.starts_with("adaptivity.") && k != "adaptivity.strategy" && !adapts => {
                    Some(format!(
                        "strategy `{}` never adapts the mesh and reads no [adaptivity] key",
                        self.strategy
                    ))
                }
                _ => None,
            };
            if let Some(why) = why {
                return Err(StudyError::Config(format!(
                    "{}: {key} is not read by run {}: {why}; runs differing only by it would be \
                     the same run under different labels",
                    from(),
                    self.label()
                )));
            }
        }
        Ok(())
    }
}

/// The fingerprint of a run's settings: FNV-1a (hex) of its scene `run` ([`RunConfig::scene`])
/// as TOML (mesh paths as written, so shards run in other folders agree).
pub fn fingerprint(run: &LoadedScene) -> String {
    let text = toml::to_string(&run.scene).unwrap_or_else(|e| format!("not serializable: {e}"));
    let hash = crate::eval::fnv1a(crate::eval::FNV_OFFSET, text.as_bytes());
    format!("{hash:016x}")
}

/// The default list: static on [`DEFAULT_STATIC_GRIDS`] and every adaptive strategy on the
/// scene's grid.
pub fn default_spec() -> String {
    let statics = DEFAULT_STATIC_GRIDS.iter().map(|n| format!("static@{n}"));
    let adaptive = strategy_names()
        .iter()
        .filter(|s| **s != "static")
        .map(|s| s.to_string());
    statics.chain(adaptive).collect::<Vec<_>>().join(",")
}

/// Parses `strategy[@resolution],...` (resolution default: the scene's) crossed with the
/// integrators (none: the scene's), configuration-major. Unknown strategies and integrators,
/// resolutions below 2 and an empty list are errors.
pub fn parse_runs(spec: &str, integrators: &[String]) -> Result<Vec<RunTemplate>, StudyError> {
    let option = || format!("--integrators {}", integrators.join(","));
    for (k, i) in integrators.iter().enumerate() {
        integrator_named(i).map_err(|e| StudyError::Config(format!("{}: {e}", option())))?;
        if integrators[..k].contains(i) {
            return Err(StudyError::Config(format!(
                "{}: integrator {i} listed twice: list it once",
                option()
            )));
        }
    }
    let integrators: Vec<Option<String>> = if integrators.is_empty() {
        vec![None]
    } else {
        integrators.iter().cloned().map(Some).collect()
    };
    let mut out = Vec::new();
    for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (strategy, resolution) = match item.split_once('@') {
            Some((s, r)) => {
                let r: usize = r.trim().parse().map_err(|_| {
                    StudyError::Config(format!(
                        "configuration `{item}`: expected strategy@resolution with an integer resolution"
                    ))
                })?;
                (s.trim(), Some(r))
            }
            None => (item, None),
        };
        if !strategy_names().contains(&strategy) {
            return Err(StudyError::Config(format!(
                "configuration `{item}`: unknown strategy `{strategy}`; valid strategies: {}",
                strategy_names().join(", ")
            )));
        }
        if resolution.is_some_and(|r| r < 2) {
            return Err(StudyError::Config(format!(
                "configuration `{item}`: resolution must be at least 2"
            )));
        }
        for integrator in &integrators {
            out.push(RunTemplate {
                strategy: strategy.to_string(),
                resolution,
                integrator: integrator.clone(),
                base: strategy.to_string(),
                set: Vec::new(),
                suffix: String::new(),
                from: format!("--runs {item}"),
            });
        }
    }
    if out.is_empty() {
        return Err(StudyError::Config("no configuration to run".into()));
    }
    Ok(out)
}

/// The configurations of `runs` on `scene`; two with the same label are an error.
pub fn configs_for(
    runs: &[RunTemplate],
    scene: &LoadedScene,
) -> Result<Vec<RunConfig>, StudyError> {
    let mut out: Vec<RunConfig> = Vec::new();
    for t in runs {
        let c = t.config(scene);
        if let Some(first) = out.iter().find(|o| o.label() == c.label()) {
            return Err(StudyError::Config(format!(
                "{}: configuration {} listed twice (also by {}){}",
                c.from,
                c.label(),
                first.from,
                if c.from.starts_with("--runs") {
                    ": list it once"
                } else if c.base != first.base && c.base != c.strategy {
                    // Two labels that become one folder name (`a/b` and `a\\b` are both `a_b`).
                    ": their labels become the same folder name; give one of the two entries \
                     another `label`"
                } else {
                    ": give one of the two entries a `label` (the label's first part)"
                }
            )));
        }
        c.scene(scene)?;
        out.push(c);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_embedded;

    fn scene() -> LoadedScene {
        load_embedded("sphere", &[]).unwrap().unwrap()
    }

    fn parse_configs(
        spec: &str,
        scene: &LoadedScene,
        integrators: &[String],
    ) -> Result<Vec<RunConfig>, StudyError> {
        configs_for(&parse_runs(spec, integrators)?, scene)
    }

    #[test]
    fn default_configurations() {
        let c = parse_configs(&default_spec(), &scene(), &[]).unwrap();
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
        // The integrator list's own mistakes name it.
        let e = parse_configs("static", &scene(), &["rk4".into(), "rk4".into()]).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("--integrators rk4,rk4: integrator rk4 listed twice"),
            "{e}"
        );
        let e = parse_configs("static", &scene(), &["".into(), "".into()]).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("--integrators ,: unknown integrator"),
            "{e}"
        );
    }
}
