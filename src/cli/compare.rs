//! `reference`, `compare`, `merge` and `report`: studies of speed against error.

use super::args::{CompareArgs, MergeArgs, RefOpts, ReferenceArgs, ReportArgs};
use super::{interrupt_flag, read_input, show_progress, CliError};
use crate::eval::reference::{self, ReferenceSettings};
use crate::scene::{self, LoadedScene, Overrides};
use crate::study::{self, CompareOptions, Comparison, RunConfig, Shard};
use std::path::PathBuf;
use std::sync::atomic::Ordering;

fn overrides(set: &[String], duration: Option<f64>) -> Overrides {
    Overrides {
        set: set.to_vec(),
        duration,
        ..Overrides::default()
    }
}

/// `scene` or a positive finite number.
fn optional_number(option: &str, text: &str, min: f64) -> Result<Option<f64>, CliError> {
    if text == "scene" {
        return Ok(None);
    }
    let bad = || {
        CliError::Input(format!(
            "{option} {text}: expected a number >= {min} or `scene`"
        ))
    };
    let x: f64 = text.parse().map_err(|_| bad())?;
    if x.is_finite() && (x > min || (x == min && min == 0.0)) {
        Ok(Some(x))
    } else {
        Err(bad())
    }
}

fn reference_settings(o: &RefOpts) -> Result<ReferenceSettings, CliError> {
    if let Some(i) = &o.ref_integrator {
        crate::physics::integrator_named(i)
            .map_err(|e| CliError::Input(format!("--ref-integrator: {e}")))?;
    }
    for (name, v) in [
        ("--ref-resolution", o.ref_resolution),
        ("--floor-resolution", o.floor_resolution),
        ("--samples", o.samples),
    ] {
        if v < 2 {
            return Err(CliError::Input(format!("{name} {v}: must be at least 2")));
        }
    }
    Ok(ReferenceSettings {
        resolution: o.ref_resolution,
        floor_resolution: o.floor_resolution,
        beta: optional_number("--ref-beta", &o.ref_beta, f64::MIN_POSITIVE)?,
        integrator: o.ref_integrator.clone(),
        dt_initial: optional_number("--ref-dt-initial", &o.ref_dt_initial, 0.0)?,
        samples: o.samples,
    })
}

/// `adaptcloth reference`: compute (or load from the cache) a scene's reference and its floor.
pub fn reference(args: ReferenceArgs) -> Result<(), CliError> {
    let loaded = scene::resolve(args.scene.as_deref(), &overrides(&args.set, args.duration))?;
    let settings = reference_settings(&args.reference)?;
    let progress = study::pool::Progress::new(show_progress(args.quiet));
    let clock = std::time::Instant::now();
    let r = reference::ensure_reference(
        &loaded,
        &settings,
        &args.reference.cache,
        args.jobs,
        args.reference.force_reference,
        Some(progress.multi()),
        Some(interrupt_flag()),
    )?;
    println!("{}", reference::describe(&r));
    eprintln!("done in {:.1} s", clock.elapsed().as_secs_f64());
    Ok(())
}

/// One scene of `compare`: the scene, its configurations, its output folder.
struct Plan {
    loaded: LoadedScene,
    configs: Vec<RunConfig>,
    out: PathBuf,
}

/// Loads and checks every scene and configuration list before anything runs.
fn plan(args: &CompareArgs) -> Result<Vec<Plan>, CliError> {
    let mut names = args.scenes.clone();
    if args.all_source_scenes {
        names.extend(scene::SOURCE_SCENES.map(String::from));
    }
    if names.is_empty() {
        names.push(scene::DEFAULT_SCENE.into());
    }
    let spec = args.runs.clone().unwrap_or_else(study::default_spec);
    let mut plans = Vec::new();
    for name in &names {
        let loaded = scene::resolve(Some(name), &overrides(&args.set, args.duration))?;
        let configs = study::parse_configs(&spec, &loaded.scene, &args.integrators)?;
        let scene_name = &loaded.scene.name;
        let out = match (&args.out, names.len()) {
            (Some(o), 1) => o.clone(),
            (Some(o), _) => o.join(scene_name),
            (None, 1) => PathBuf::from("out").join(format!("compare-{scene_name}")),
            (None, _) => PathBuf::from("out").join("compare").join(scene_name),
        };
        plans.push(Plan {
            loaded,
            configs,
            out,
        });
    }
    Ok(plans)
}

/// `adaptcloth compare`: every configuration of every scene against its reference, reports.
pub fn compare(args: CompareArgs) -> Result<(), CliError> {
    let settings = reference_settings(&args.reference)?;
    let shard = args.shard.as_deref().map(str::parse::<Shard>).transpose()?;
    let notes = args.docs_notes.as_deref().map(read_input).transpose()?;
    let interrupt = interrupt_flag();
    let mut done = Vec::new();
    for Plan {
        loaded,
        configs,
        out,
    } in plan(&args)?
    {
        let clock = std::time::Instant::now();
        let shard_text = shard.map(|s| format!(", shard {s}")).unwrap_or_default();
        eprintln!(
            "adaptcloth compare: {} ({}), {} configuration(s){shard_text} -> {}",
            loaded.scene.name,
            loaded.source,
            configs.len(),
            out.display()
        );
        let opts = CompareOptions {
            configs,
            jobs: args.jobs.max(1),
            shard,
            out_dir: out.clone(),
            reference: settings.clone(),
            cache_dir: args.reference.cache.clone(),
            force_reference: args.reference.force_reference,
            progress: show_progress(args.quiet),
            interrupt: Some(interrupt.clone()),
        };
        let comparison = study::compare(&loaded, &opts)?;
        crate::report::write_report(&out, &comparison)?;
        let (runs, secs) = (comparison.rows.len(), clock.elapsed().as_secs_f64());
        let report = out.join("report.md");
        eprintln!(
            "{}: {runs} run(s) in {secs:.1} s; report: {}",
            loaded.scene.name,
            report.display()
        );
        if interrupt.load(Ordering::SeqCst) {
            return Err(CliError::Interrupted(String::new()));
        }
        done.push((out, comparison));
    }
    let command = format!(
        "adaptcloth {}",
        std::env::args().skip(1).collect::<Vec<_>>().join(" ")
    );
    write_docs(args.write_docs, &done, &command, notes)
}

/// `--write-docs DIR`: `DIR/results.md` over the comparisons.
fn write_docs(
    dir: Option<PathBuf>,
    done: &[(PathBuf, Comparison)],
    command: &str,
    notes: Option<String>,
) -> Result<(), CliError> {
    if let Some(dir) = dir {
        let notes = notes.unwrap_or_default();
        let path = crate::report::write_docs(&dir, done, command, &notes)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// `adaptcloth merge`: shard folders into one comparison and its report.
pub fn merge(args: MergeArgs) -> Result<(), CliError> {
    let comparison = study::merge(&args.dirs, &args.out)?;
    crate::report::write_report(&args.out, &comparison)?;
    eprintln!(
        "merged {} run(s) from {} folder(s); report: {}",
        comparison.rows.len(),
        args.dirs.len(),
        args.out.join("report.md").display()
    );
    Ok(())
}

/// `adaptcloth report`: rewrite the plots and reports of comparison folders, and results.md.
pub fn report(args: ReportArgs) -> Result<(), CliError> {
    let notes = args.docs_notes.as_deref().map(read_input).transpose()?;
    let mut done = Vec::new();
    for dir in &args.dirs {
        let comparison = study::read_comparison(dir)?;
        crate::report::write_report(dir, &comparison)?;
        eprintln!("{}", dir.join("report.md").display());
        done.push((dir.clone(), comparison));
    }
    write_docs(args.write_docs, &done, &args.docs_command, notes)
}
