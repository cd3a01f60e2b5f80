//! `reference`, `compare`, `merge` and `report`: studies of speed against error.

use super::args::{
    CompareArgs, DocsArgs, ExecutionArgs, MergeArgs, RefOpts, ReferenceArgs, ReportArgs, StudyArgs,
};
use super::{
    cache_folder, interrupt_flag, not_in_the_way, output_folder, show_progress, writable_folder,
    CliError,
};
use crate::console::clip;
use crate::eval::reference::{self, ReferenceSettings};
use crate::scene::{self, Overrides, Setting};
use crate::study::{self, CompareOptions, Comparison, ScenePlan, Shard, Study, StudyError};
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

fn overrides(set: &[String], duration: Option<f64>) -> Overrides {
    Overrides {
        set: Setting::options(set),
        duration,
        ..Overrides::default()
    }
}

/// `text` as a finite number that is positive, or non-negative when `zero_ok`; `None` otherwise.
fn finite_number(text: &str, zero_ok: bool) -> Option<f64> {
    let x: f64 = text.parse().ok()?;
    (x.is_finite() && (x > 0.0 || (zero_ok && x == 0.0))).then_some(x)
}

/// `scene` (`None`), or a finite number that is positive, or non-negative when `zero_ok`.
fn optional_number(option: &str, text: &str, zero_ok: bool) -> Result<Option<f64>, CliError> {
    if text == "scene" {
        return Ok(None);
    }
    let expected = if zero_ok { ">= 0" } else { "> 0" };
    finite_number(text, zero_ok).map(Some).ok_or_else(|| {
        CliError::Input(format!(
            "{option} {text}: expected a number {expected} or `scene`"
        ))
    })
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
    if o.floor_resolution >= o.ref_resolution {
        return Err(CliError::Input(format!(
            "--floor-resolution {} must be below --ref-resolution {} (the floor is a coarser grid, \
             measured against the reference)",
            o.floor_resolution, o.ref_resolution
        )));
    }
    Ok(ReferenceSettings {
        resolution: o.ref_resolution,
        floor_resolution: o.floor_resolution,
        beta: optional_number("--ref-beta", &o.ref_beta, false)?,
        integrator: o.ref_integrator.clone(),
        dt_initial: optional_number("--ref-dt-initial", &o.ref_dt_initial, true)?,
        dt: o
            .ref_dt
            .as_deref()
            .map(|text| {
                finite_number(text, false).ok_or_else(|| {
                    CliError::Input(format!("--ref-dt {text}: expected a step > 0 (s)"))
                })
            })
            .transpose()?,
        samples: o.samples,
    })
}

/// `adaptcloth reference`: compute (or load from the cache) a scene's reference and its floor.
pub fn reference(args: ReferenceArgs) -> Result<(), CliError> {
    let loaded = scene::resolve(args.scene.as_deref(), &overrides(&args.set, args.duration))?;
    let settings = reference_settings(&args.reference)?;
    cache_folder(&args.reference.cache)?;
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
    if let Some(note) = r.discarded_note() {
        crate::note!("{note}");
    }
    crate::say!("{}", reference::describe(&r));
    crate::note!("done in {:.1} s", clock.elapsed().as_secs_f64());
    Ok(())
}

/// The scene names of `compare`: the listed ones, the source scenes, or the default scene.
fn scene_names(args: &CompareArgs) -> Vec<String> {
    let mut names = args.scenes.clone();
    if args.all_source_scenes {
        names.extend(scene::SOURCE_SCENES.map(String::from));
    }
    if names.is_empty() {
        names.push(scene::DEFAULT_SCENE.into());
    }
    names
}

/// `adaptcloth compare`: the study the options describe, run like a study file.
pub fn compare(args: CompareArgs) -> Result<(), CliError> {
    let spec = args.runs.clone().unwrap_or_else(study::default_spec);
    let scenes = scene_names(&args);
    let definition = Study {
        name: "compare".into(),
        description: String::new(),
        source: "command line".into(),
        scenes_from: scenes
            .iter()
            .enumerate()
            .map(|(i, s)| format!("scene {} = {s:?}", i + 1))
            .collect(),
        scenes,
        set: Setting::options(&args.set),
        duration: args.duration,
        reference: reference_settings(&args.reference)?,
        runs: study::parse_runs(&spec, &args.integrators)?,
    };
    let notes = read_notes(&args.docs)?;
    let n = definition.scenes.len();
    let out = |name: &str| match (&args.out, n) {
        (Some(o), 1) => o.clone(),
        (Some(o), _) => o.join(name),
        (None, 1) => PathBuf::from("out").join(format!("compare-{name}")),
        (None, _) => PathBuf::from("out").join("compare").join(name),
    };
    let plans = study::plan(&definition, out, args.execution.force)?;
    let execution = Execution::new(
        &args.execution,
        &args.reference.cache,
        args.reference.force_reference,
    )?;
    let done = run_plans(&definition, plans, &execution)?;
    let command = format!(
        "adaptcloth {}",
        std::env::args().skip(1).collect::<Vec<_>>().join(" ")
    );
    write_docs(args.docs.write_docs, &done, &command, notes)
}

/// The study `adaptcloth study` runs without a file.
const QUICK_STUDY: &str = include_str!("../../studies/quick.toml");

/// `adaptcloth study FILE.toml`: a study file's runs on each of its scenes, one report per scene;
/// each scene's ranked table on stdout.
pub fn study(args: StudyArgs) -> Result<(), CliError> {
    let definition = match &args.file {
        Some(file) => study::load_study(file)?,
        None => study::parse_study(
            QUICK_STUDY,
            "<embedded studies/quick.toml>",
            "quick",
            Path::new("."),
        )?,
    };
    let notes = read_notes(&args.docs)?;
    let root = args
        .out
        .clone()
        .unwrap_or_else(|| default_study_out(&definition.name));
    let plans = study::plan(&definition, |name| root.join(name), args.execution.force)?;
    let execution = Execution::new(&args.execution, &args.cache, args.force_reference)?;
    if args.references_only {
        return references(&definition, &plans, &execution);
    }
    let done = run_plans(&definition, plans, &execution)?;
    write_docs(
        args.docs.write_docs.clone(),
        &done,
        &study_command(&args),
        notes,
    )
}

/// The study command that writes the same docs: the file, `--jobs` (the wall times depend on
/// it), `--write-docs` and `--docs-notes`.
fn study_command(args: &StudyArgs) -> String {
    let mut command = String::from("adaptcloth study");
    if let Some(file) = &args.file {
        command += &format!(" {}", file.display());
    }
    if args.execution.jobs > 1 {
        command += &format!(" --jobs {}", args.execution.jobs);
    }
    if let Some(dir) = &args.docs.write_docs {
        command += &format!(" --write-docs {}", dir.display());
    }
    if let Some(notes) = &args.docs.docs_notes {
        command += &format!(" --docs-notes {}", notes.display());
    }
    command
}

/// `study --references-only`: each scene's reference in the cache, nothing else.
fn references(definition: &Study, plans: &[ScenePlan], e: &Execution) -> Result<(), CliError> {
    cache_folder(&e.cache)?;
    for r in ensure_references(definition, plans, e)? {
        crate::say!("{}", reference::describe(&r));
    }
    Ok(())
}

/// Every scene's reference and floor in the cache (computed when missing, or always with
/// `--force-reference`), `e.jobs` scenes at a time, each scene's two runs side by side as well
/// when `e.jobs >= 2`: a study's references before its runs, so that no core waits while one
/// scene's reference runs alone. Scenes sharing a cache entry are computed once and returned
/// once, in the plans' order.
fn ensure_references(
    definition: &Study,
    plans: &[ScenePlan],
    e: &Execution,
) -> Result<Vec<reference::Reference>, CliError> {
    let settings = &definition.reference;
    let entries: Vec<PathBuf> = plans
        .iter()
        .map(|p| reference::entry_dir(&e.cache, &p.loaded, settings))
        .collect();
    let first: Vec<usize> = (0..plans.len())
        .filter(|&i| !entries[..i].contains(&entries[i]))
        .collect();
    let progress = study::pool::Progress::new(e.progress);
    let interrupt = interrupt_flag();
    Ok(study::pool::run_all(
        &first,
        e.jobs,
        // Each reference stops on the interrupt itself, and fails: the command exits 130.
        None,
        &progress,
        |_| 0,
        |&i| plans[i].loaded.scene.name.clone(),
        |&i, bar| {
            bar.finish_and_clear(); // the runs show their own bars
            let r = reference::ensure_reference(
                &plans[i].loaded,
                settings,
                &e.cache,
                e.jobs,
                e.force_reference,
                Some(progress.multi()),
                Some(interrupt.clone()),
            )?;
            // Said when computed; each scene's comparison names it again, read from the cache.
            if !r.cached {
                if let Some(note) = r.discarded_note() {
                    progress.println(&note);
                }
                progress.println(&reference::describe(&r));
            }
            Ok::<_, reference::ReferenceError>(r)
        },
    )?)
}

/// How the runs of a study are executed (shared by `compare` and `study`).
struct Execution {
    jobs: usize,
    shard: Option<Shard>,
    cache: PathBuf,
    force_reference: bool,
    progress: bool,
}

impl Execution {
    fn new(o: &ExecutionArgs, cache: &Path, force_reference: bool) -> Result<Execution, CliError> {
        Ok(Execution {
            jobs: o.jobs,
            shard: o.shard.as_deref().map(str::parse::<Shard>).transpose()?,
            cache: cache.to_path_buf(),
            force_reference,
            progress: show_progress(o.quiet),
        })
    }
}

/// Runs every scene's comparison and writes its report; stops after the scene during which
/// Ctrl-C was pressed.
fn run_plans(
    definition: &Study,
    plans: Vec<ScenePlan>,
    e: &Execution,
) -> Result<Vec<(PathBuf, Comparison)>, CliError> {
    for plan in &plans {
        output_folder(&plan.out)?;
    }
    cache_folder(&e.cache)?;
    if plans.len() > 1 {
        ensure_references(definition, &plans, e)?;
    }
    let interrupt = interrupt_flag();
    let count_scenes = plans.len();
    let mut done = Vec::new();
    for ScenePlan {
        loaded,
        configs,
        settings,
        out,
        notes,
    } in plans
    {
        let clock = std::time::Instant::now();
        let shard_text = e.shard.map(|s| format!(", shard {s}")).unwrap_or_default();
        let (scene, count) = (&loaded.scene.name, configs.len());
        crate::note!(
            "adaptcloth {}: {} ({}), {count} configuration(s){shard_text} -> {}",
            clip(&definition.name),
            clip(scene),
            clip(&loaded.source),
            clip(&out.to_string_lossy())
        );
        for note in &notes {
            crate::note!("{note}");
        }
        let opts = CompareOptions {
            configs,
            settings,
            jobs: e.jobs,
            shard: e.shard,
            out_dir: out.clone(),
            reference: definition.reference.clone(),
            cache_dir: e.cache.clone(),
            // With several scenes every reference was just made (forced or not).
            force_reference: e.force_reference && count_scenes == 1,
            progress: e.progress,
            interrupt: Some(interrupt.clone()),
        };
        // The pages are made from the tables as written (their numbers rounded), as
        // `adaptcloth report` makes them, so the two give the same pages; a table that cannot be
        // read back leaves the pages made from the runs as they are (the runs are not lost).
        let measured = study::compare(&loaded, &opts)?;
        let comparison = match study::table::as_written(&out, &measured) {
            Ok(read_back) => read_back,
            Err(e) => {
                crate::note!("warning: the comparison's tables could not be read back ({e}); its pages are made from the runs as measured");
                measured
            }
        };
        crate::report::write_report(&out, &comparison)?;
        let (runs, secs) = (comparison.rows.len(), clock.elapsed().as_secs_f64());
        let stopped = interrupt.load(Ordering::SeqCst);
        if stopped {
            let completed = comparison.rows.iter().filter(|r| r.completed()).count();
            // The shard's runs: those started (rows) and those not (listed as skipped).
            let planned = runs + comparison.manifest.skipped.len();
            crate::note!(
                "{}: interrupted after {secs:.1} s: {completed} of {planned} run(s) completed, \
                 the others are listed as not run in report.md",
                clip(scene)
            );
        } else {
            crate::note!("{}: {runs} run(s) in {secs:.1} s", clip(scene));
        }
        crate::say!(
            "{}report: {}\n",
            crate::report::ranking::ranking(&comparison),
            out.join("report.html").display()
        );
        if stopped {
            return Err(CliError::Interrupted(String::new()));
        }
        done.push((out, comparison));
    }
    Ok(done)
}

/// The `--docs-notes` file's text, read before anything runs (exit 2 naming the option when it
/// cannot be read), after checking that `--write-docs`'s folder can be created and written in
/// (exit 2 before any run, not after an hour of them).
fn read_notes(docs: &DocsArgs) -> Result<String, CliError> {
    if let Some(dir) = &docs.write_docs {
        writable_folder("--write-docs", "docs folder", dir)?;
    }
    let Some(path) = &docs.docs_notes else {
        return Ok(String::new());
    };
    crate::io::read_text(path).map_err(|e| {
        CliError::Input(format!(
            "--docs-notes {}: cannot be read: {e}; expected a markdown file",
            path.display()
        ))
    })
}

/// `--write-docs DIR`: `DIR/results.md` over the comparisons, with the notes.
fn write_docs(
    dir: Option<PathBuf>,
    done: &[(PathBuf, Comparison)],
    command: &str,
    notes: String,
) -> Result<(), CliError> {
    if let Some(dir) = dir {
        let path = crate::report::write_docs(&dir, done, command, &notes)?;
        crate::note!("wrote {}", path.display());
    }
    Ok(())
}

/// A study error of `command` (`merge`, `report`): a comparison folder it refused names the
/// command (exit 2); the other errors are as they are.
fn refused_by(command: &'static str) -> impl Fn(StudyError) -> CliError {
    move |e| match e {
        StudyError::Config(why) => CliError::Input(format!("{command}: {why}")),
        e => e.into(),
    }
}

/// `adaptcloth merge`: shard folders into one comparison and its report.
pub fn merge(args: MergeArgs) -> Result<(), CliError> {
    not_in_the_way("--out", &args.out)?;
    let interrupt = super::interrupt_flag();
    let existed = args.out.exists();
    super::output_folder(&args.out)?;
    let comparison = study::merge(&args.dirs, &args.out, Some(&interrupt)).map_err(|e| {
        // A refused merge writes nothing: not even the folder the check above made.
        if !existed && !matches!(e, StudyError::Interrupted(_)) {
            let _ = std::fs::remove_dir(args.out.join("runs"));
            let _ = std::fs::remove_dir(&args.out);
        }
        refused_by("merge")(e)
    })?;
    crate::report::write_report(&args.out, &comparison)?;
    if interrupt.load(std::sync::atomic::Ordering::SeqCst) {
        return Err(CliError::Interrupted(format!(
            "merge interrupted while writing the report: the comparison in {} is complete; \
             `adaptcloth report {}` writes its pages again",
            args.out.display(),
            args.out.display()
        )));
    }
    crate::note!(
        "merged {} run(s) from {} folder(s); report: {}",
        comparison.rows.len(),
        args.dirs.len(),
        args.out.join("report.md").display()
    );
    for missing in &comparison.manifest.skipped {
        crate::note!("missing run {}: {}", missing.label, missing.reason);
    }
    Ok(())
}

/// `adaptcloth report`: rewrite the plots and reports of comparison folders, and results.md.
pub fn report(args: ReportArgs) -> Result<(), CliError> {
    let notes = read_notes(&args.docs)?;
    let mut done: Vec<(PathBuf, Comparison)> = Vec::new();
    for dir in &args.dirs {
        let comparison = study::read_comparison(dir).map_err(refused_by("report"))?;
        // results.md has one section and one plot folder per scene.
        let scene = &comparison.manifest.scene;
        if let Some((first, _)) = done.iter().find(|(_, c)| &c.manifest.scene == scene) {
            if args.docs.write_docs.is_some() {
                return Err(CliError::Input(format!(
                    "report: {} and {} are both comparisons of scene {scene}: --write-docs \
                     writes one section and one plot folder (results/{scene}/) per scene, so \
                     the second would overwrite the first's plots; give one folder per scene",
                    first.display(),
                    dir.display()
                )));
            }
        }
        done.push((dir.clone(), comparison));
    }
    let interrupt = super::interrupt_flag();
    for (dir, comparison) in &done {
        crate::report::write_report(dir, comparison)?;
        if interrupt.load(std::sync::atomic::Ordering::SeqCst) {
            return Err(CliError::Interrupted(format!(
                "report interrupted: the pages of {} may be part rewritten; run the report again",
                dir.display()
            )));
        }
        crate::note!("{}", dir.join("report.md").display());
    }
    write_docs(args.docs.write_docs, &done, &args.docs_command, notes)
}

/// `out/study-NAME`, NAME made one plain folder name: a study `name = "../../../../x"` gave
/// `out/study-../../../../x`, which leaves the working folder.
fn default_study_out(name: &str) -> PathBuf {
    PathBuf::from("out").join(format!("study-{}", crate::io::file_safe(name)))
}

#[cfg(test)]
mod tests {
    use super::study_command;
    use crate::cli::args::{Cli, Command};
    use clap::Parser;

    /// The command a study names in results.md is one that writes the same page: its file, its
    /// `--jobs`, `--write-docs` and `--docs-notes`, nothing that does not change the page.
    #[test]
    fn a_study_names_the_command_that_writes_its_docs() {
        let named = |argv: &[&str]| match Cli::parse_from(argv).command {
            Command::Study(args) => study_command(&args),
            _ => unreachable!("a study command"),
        };
        assert_eq!(
            named(&[
                "adaptcloth",
                "study",
                "studies/results.toml",
                "--jobs",
                "2",
                "--quiet",
                "--write-docs",
                "docs",
                "--docs-notes",
                "studies/results-notes.md",
            ]),
            "adaptcloth study studies/results.toml --jobs 2 --write-docs docs --docs-notes \
             studies/results-notes.md"
        );
        assert_eq!(named(&["adaptcloth", "study"]), "adaptcloth study");
    }
}
