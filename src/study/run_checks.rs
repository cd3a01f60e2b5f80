//! The checks of a study's `[[runs]]` entries: each scene key given once per entry, each sweep
//! value once, each label once over the study.

use super::{is_grid_key, Errors, RunTemplate, RunToml};
use crate::study::config::run_label;
use crate::study::StudyError;
use std::collections::BTreeMap;
use toml::Spanned;

/// The scene keys a `[[runs]]` entry's own keys set (`dt` and `beta` set `time.mode` too).
const RUN_KEYS: [(&str, &[&str]); 5] = [
    ("strategy", &["adaptivity.strategy"]),
    ("resolution", &["cloth.resolution"]),
    ("integrator", &["integrator.name"]),
    ("dt", &["time.dt", "time.mode"]),
    ("beta", &["time.beta", "time.mode"]),
];

/// Fails when a `[[runs]]` entry sets one scene key twice (`dt` and `set."time.dt"`, `strategy`
/// and `set."adaptivity.strategy"`, a `set` and a `sweep` of one key, `resolution` and a sweep
/// of the grid, the grid swept as both `resolution` and `cloth.resolution`): one of the two was
/// ignored, unchecked. The grid and the integrator, which the label and the table row name, are
/// not taken from `set` either: only from `resolution` (or a sweep of the grid) and `integrator`.
pub(super) fn check_keys_given_once(
    run: &RunToml,
    index: usize,
    err: &Errors,
) -> Result<(), StudyError> {
    let spans = [
        Some(run.strategy.span()),
        run.resolution.as_ref().map(Spanned::span),
        run.integrator.as_ref().map(Spanned::span),
        run.dt.as_ref().map(Spanned::span),
        run.beta.as_ref().map(Spanned::span),
    ];
    // (scene key, the key as the entry writes it, its span), in the entry's order of keys.
    let mut given: Vec<(&str, String, std::ops::Range<usize>)> = Vec::new();
    for ((own, scene_keys), span) in RUN_KEYS.iter().zip(&spans) {
        if let Some(span) = span {
            given.extend(
                scene_keys
                    .iter()
                    .map(|k| (*k, format!("`{own}`"), span.clone())),
            );
        }
    }
    let set = run.set.iter().map(|(k, v)| ("set", k, v.span()));
    let sweep = run.sweep.iter().map(|(k, v)| ("sweep", k, v.span()));
    for (table, key, span) in set.chain(sweep) {
        let swept_grid = table == "sweep" && is_grid_key(key);
        let scene_key = if swept_grid {
            "cloth.resolution"
        } else {
            key.as_str()
        };
        let own = match scene_key {
            "cloth.resolution" if !swept_grid && run.resolution.is_none() => Some("resolution"),
            "integrator.name" if run.integrator.is_none() => Some("integrator"),
            _ => None,
        };
        if let Some(own) = own {
            return Err(err.at(
                span,
                format!(
                    "runs[{index}].{table}.\"{key}\": a run's {own} is given by its key `{own}` \
                     (it names the run's label and its row of the table): write `{own} = ...` in \
                     this entry instead"
                ),
            ));
        }
        given.push((scene_key, format!("`{table}.\"{key}\"`"), span));
    }
    for (j, (key, b, span)) in given.iter().enumerate() {
        if let Some((_, a, first)) = given[..j].iter().find(|(k, _, _)| k == key) {
            return Err(err.at(
                span.clone(),
                format!(
                    "runs[{index}]: {b} sets {key}, which {a} ({}) sets already: give it once \
                     (one of the two would be ignored)",
                    err.place(first.clone())
                ),
            ));
        }
    }
    Ok(())
}

/// The label `t` will have, naming the scene's grid or integrator when it leaves them to the
/// scene.
fn label_of(t: &RunTemplate) -> String {
    let grid = t
        .resolution
        .map_or("<scene's grid>".to_string(), |r| r.to_string());
    let integrator = t.integrator.as_deref().unwrap_or("<scene's integrator>");
    run_label(&t.base, &grid, integrator, &t.suffix)
}

/// Fails when a sweep of `run` (the `[[runs]]` entry `index`, expanded to `runs`) lists a value
/// twice (as its label writes it): two runs of one label, the second overwriting the first.
pub(super) fn check_sweep_values(
    run: &RunToml,
    index: usize,
    runs: &[RunTemplate],
    err: &Errors,
) -> Result<(), StudyError> {
    for (key, values) in &run.sweep {
        let written: Vec<String> = values.get_ref().iter().map(|v| v.to_string()).collect();
        let Some(v) = (1..written.len())
            .find(|&j| written[..j].contains(&written[j]))
            .map(|j| &written[j])
        else {
            continue;
        };
        let mut seen = std::collections::BTreeSet::new();
        let twice = runs
            .iter()
            .find(|t| !seen.insert((t.resolution, &t.suffix)))
            .map(label_of)
            .unwrap_or_default();
        return Err(err.spanned(
            values,
            format!(
                "runs[{index}].sweep.\"{key}\" lists {v} twice, so two runs would have the same \
                 label {twice}: each value makes one run; remove the repeated value"
            ),
        ));
    }
    Ok(())
}

/// Two runs of different `[[runs]]` entries with the same label would write the same folder:
/// an error naming the label and both entries (the runs of one entry differ by
/// [`check_keys_given_once`] and [`check_sweep_values`]).
pub(super) fn check_unique_labels(runs: &[RunTemplate]) -> Result<(), StudyError> {
    let mut seen: BTreeMap<_, &RunTemplate> = BTreeMap::new();
    for t in runs {
        let key = (&t.base, t.resolution, &t.integrator, &t.suffix);
        if let Some(first) = seen.insert(key, t) {
            return Err(StudyError::Config(format!(
                "{}: two runs would have the same label {} ({} makes it too): give one of the \
                 two entries a `label` (the label's first part)",
                t.from,
                label_of(t),
                first.from
            )));
        }
    }
    Ok(())
}
