//! The study and compare commands on the command line: `--force`, the hints given for
//! implicit runs, references announced, pages rewritten from a folder, study-wide keys.
use super::cli::adaptcloth;
use std::process::Command;

/// `study --force` and `compare --force` run what the step estimate refuses, run by run (here a
/// run of 1e-300 s steps, stopped by Ctrl-C once it has started); the reference is checked
/// whatever `--force` says.
#[test]
fn study_and_compare_force_reaches_every_run_but_not_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("f.toml");
    std::fs::write(
        &file,
        "scenes = [\"sphere\"]\nduration = 0.02\n[reference]\nresolution = 5\nfloor = 3\n\
         samples = 4\n[[runs]]\nstrategy = \"static\"\nresolution = 3\nset = { \
         \"time.dt_initial\" = 1e-300 }\n",
    )
    .unwrap();
    let (out, cache) = (dir.path().join("o"), dir.path().join("cache"));
    let mut args = vec![
        "study",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
        "--quiet",
    ];
    let (code, err) = adaptcloth(&args);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("run static-3-rk4: this run would take"),
        "{err}"
    );
    assert!(err.contains("--force runs it anyway"), "{err}");
    assert!(!cache.exists(), "nothing runs before the check");
    args.push("--force");
    let run = out.join("sphere/runs/static-3-rk4");
    let (code, err) = super::common::interrupted_once(&args, &run.join("metrics.csv.partial"));
    assert_eq!(code, 130, "{err}");
    let summary = std::fs::read_to_string(run.join("summary.json"));
    assert!(summary.unwrap().contains("\"status\": \"interrupted\""));
    for command in ["study", "compare"] {
        let help = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
            .args([command, "--help"])
            .output()
            .unwrap();
        let help = String::from_utf8_lossy(&help.stdout).into_owned();
        assert!(
            help.lines()
                .any(|l| l.trim() == "--force" || l.trim().starts_with("--force ")),
            "{command}: {help}"
        );
    }
    let (code, err) = adaptcloth(&[
        "compare",
        "--runs",
        "static@3",
        "--set",
        "material.E=1e308",
        "--ref-resolution",
        "5",
        "--floor-resolution",
        "3",
        "--cache",
        cache.to_str().unwrap(),
        "--out",
        dir.path().join("c").to_str().unwrap(),
        "--force",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("the reference run of <embedded sphere> (not covered by --force)"),
        "{err}"
    );
}

/// An integrator stable at any step on its scene's dynamic step (set by the explicit
/// integrators' stability) is told so, with how to fix the step, by `run` and by a study (naming
/// the run); nothing is said on a fixed step or for an explicit integrator.
#[test]
fn implicit_runs_on_the_dynamic_step_are_told_how_to_take_large_steps() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let out = out.to_str().unwrap();
    let note = "takes the scene's dynamic step";
    let run = |extra: &[&str]| {
        let mut args = vec!["run", "--quiet", "--duration", "0.01", "--out", out];
        args.extend_from_slice(extra);
        let (code, err) = adaptcloth(&args);
        assert_eq!(code, 0, "{err}");
        err
    };
    let err = run(&["--integrator", "implicit_euler"]);
    assert!(
        err.contains(note) && err.contains("--set time.mode=fixed"),
        "{err}"
    );
    assert!(run(&["--integrator", "bdf2"]).contains(note));
    let fixed = ["--set", "time.mode=fixed", "--set", "time.dt=0.002"];
    let err = run(&[&["--integrator", "implicit_euler"][..], &fixed[..]].concat());
    assert!(!err.contains(note), "{err}");
    let err = run(&["--integrator", "rk4"]);
    assert!(!err.contains(note), "{err}");

    let args = small_study(
        dir.path(),
        "duration = 0.01",
        "[[runs]]\nstrategy = \"static\"\nintegrator = \"implicit_euler\"\nresolution = 5\n\
         [[runs]]\nlabel = \"fixed\"\nstrategy = \"static\"\nintegrator = \"implicit_euler\"\n\
         resolution = 5\ndt = 0.002\n",
    );
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    let line = err
        .lines()
        .find(|l| l.contains("take the scene's dynamic step"))
        .expect("a note");
    assert!(line.contains("static-5-implicit_euler"), "{line}");
    assert!(!line.contains("fixed-5"), "{line}");
}

/// A reference to compute is announced, with its grids and step counts, before it is computed;
/// once cached, it is not.
#[test]
fn a_reference_to_compute_is_announced_before_it_runs() {
    let dir = tempfile::tempdir().unwrap();
    let args = small_study(
        dir.path(),
        "duration = 0.01",
        "[[runs]]\nstrategy = \"static\"\nresolution = 5\n",
    );
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    let announced = err
        .lines()
        .position(|l| l.contains("computing static 9x9") && l.contains("floor 5x5"))
        .expect("the reference announced");
    let done = err
        .lines()
        .position(|l| l.starts_with("reference sphere: static 9x9"))
        .expect("the reference reported");
    assert!(announced < done, "{err}");
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("computing static"), "{err}");
}

/// A study's pages are the ones `adaptcloth report` makes from its folder afterwards: made from
/// the tables as written, not from the unrounded numbers in memory.
#[test]
fn report_on_a_study_folder_rewrites_the_same_pages() {
    let dir = tempfile::tempdir().unwrap();
    let args = small_study(
        dir.path(),
        "duration = 0.02",
        "[[runs]]\nstrategy = \"static\"\nsweep = { \"cloth.resolution\" = [3, 5] }\n\
         [[runs]]\nstrategy = \"bisect48\"\nresolution = 3\n",
    );
    let out = dir.path().join("out");
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    let folder = out.join("sphere");
    let read = |f: &str| std::fs::read(folder.join(f)).unwrap();
    let (report, table) = (read("report.md"), read("comparison.csv"));
    // Regression (study review 2026-11-29, finding 11): nothing said how the comparison was made.
    let made = String::from_utf8(report.clone()).unwrap();
    assert!(
        made.contains(&format!(
            "Made by `{} study ",
            env!("CARGO_BIN_EXE_adaptcloth")
        )) && made.contains(&format!("(adaptcloth {})", env!("CARGO_PKG_VERSION"))),
        "{made}"
    );
    let (code, err) = adaptcloth(&["report", folder.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(read("report.md") == report, "report.md differs");
    assert!(read("comparison.csv") == table, "comparison.csv differs");

    // Two comparisons of one scene would share results/sphere/: refused with --write-docs
    // before anything is written, accepted without.
    let copy = dir.path().join("copy");
    std::fs::create_dir_all(&copy).unwrap();
    for f in ["comparison.json", "comparison.csv"] {
        std::fs::copy(folder.join(f), copy.join(f)).unwrap();
    }
    let docs = dir.path().join("docs");
    let (folder_s, copy_s, docs_s) = (
        folder.to_str().unwrap(),
        copy.to_str().unwrap(),
        docs.to_str().unwrap(),
    );
    let (code, err) = adaptcloth(&["report", folder_s, copy_s, "--write-docs", docs_s]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("both comparisons of scene sphere"), "{err}");
    assert!(!docs.join("results.md").exists(), "{err}");
    assert!(!copy.join("report.md").exists(), "{err}");
    let (code, err) = adaptcloth(&["report", folder_s, copy_s]);
    assert_eq!(code, 0, "{err}");
    // The copy has no runs/ folder: its runs are in its tables, not in its plots, and it says so.
    assert!(err.contains("in the tables, not in the plots"), "{err}");
    let copied = std::fs::read_to_string(copy.join("report.md")).unwrap();
    assert!(copied.contains("left out of the plots"), "{copied}");
    assert!(
        read("report.md") == report,
        "the original's report.md changed"
    );

    // The scene names the plots' folder: one that leaves the docs folder is refused (it wrote
    // DIR/results/../../../x).
    let json = copy.join("comparison.json");
    let text = std::fs::read_to_string(&json).unwrap();
    let escaped = dir.path().join("escaped");
    let scene = "../../escaped";
    std::fs::write(
        &json,
        text.replacen(
            "\"scene\": \"sphere\"",
            &format!("\"scene\": \"{scene}\""),
            1,
        ),
    )
    .unwrap();
    let (code, err) = adaptcloth(&["report", copy_s, "--write-docs", docs_s]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("is not a plain folder name"), "{err}");
    assert!(!escaped.exists() && !docs.join("results.md").exists());

    // A run folder no row names (an earlier study's in the same --out) is said, not listed.
    std::fs::create_dir_all(folder.join("runs/old-run")).unwrap();
    let (code, err) = adaptcloth(&["report", folder_s]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("runs/ also holds old-run"), "{err}");
    let again = String::from_utf8(read("report.md")).unwrap();
    assert!(again.contains("not runs of this comparison (left as they are): old-run"));

    // Regression (study review 2026-11-29, finding 8): a garbled error.csv or metrics.csv left
    // its run out of the plots with no word.
    for name in ["error.csv", "metrics.csv"] {
        let file = folder.join("runs/static-5-rk4").join(name);
        let kept = std::fs::read(&file).unwrap();
        std::fs::write(&file, "garbage\n").unwrap();
        let (code, err) = adaptcloth(&["report", folder_s]);
        assert_eq!(code, 0, "{err}");
        assert!(
            err.contains(&format!("{}: line 1: no column `t`", file.display()))
                && err.contains("run static-5-rk4 left out of the plots"),
            "{name}: {err}"
        );
        std::fs::write(&file, kept).unwrap();
    }
}

/// A study-wide `h_min` reaches every run, its static baseline included, which ignores it; a
/// run on its own with `h_min` and the static strategy runs, told that `h_min` is ignored, and
/// so does its rerun line (its resolved scene keeps `h_min`).
#[test]
fn a_study_wide_h_min_leaves_its_static_baseline_alone() {
    let dir = tempfile::tempdir().unwrap();
    let alone = dir.path().join("alone");
    let (code, err) = adaptcloth(&[
        "run",
        "--quiet",
        "--duration",
        "0.01",
        "--set",
        "adaptivity.h_min=0.03",
        "--out",
        alone.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("adaptivity.h_min = 0.03 is ignored") && err.contains("--strategy bisect48"),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(alone.join("summary.json")).unwrap())
            .unwrap();
    let rerun = summary["rerun"].as_str().unwrap();
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!("{rerun} --quiet"))
        .stderr(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "{rerun}");

    let args = small_study(
        dir.path(),
        "duration = 0.01\nset = { \"adaptivity.h_min\" = 0.03 }",
        "[[runs]]\nstrategy = \"static\"\nresolution = 5\n\
         [[runs]]\nstrategy = \"bisect48\"\nresolution = 5\n",
    );
    let out = dir.path().join("out");
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    let table = std::fs::read_to_string(out.join("sphere/comparison.csv")).unwrap();
    assert_eq!(table.matches(",completed,").count(), 2, "{table}");
}

/// Regression (study review 2026-11-29, findings 3-5): a run's own `set` or `sweep` of a key
/// the run does not read made identical runs under different labels (`time.dt` on the dynamic
/// step, `time.beta` on a fixed one, `h_min` on the static strategy), a run's own duration was
/// measured against the reference over a shorter span, and a swept value that makes a scene
/// that cannot be set up failed at its turn with exit 0. All refused, naming the study line and
/// the run, before anything runs (no reference computed).
#[test]
fn a_run_entry_must_set_only_what_its_run_reads() {
    let dir = tempfile::tempdir().unwrap();
    for (runs, expected) in [
        (
            "strategy = \"static\"\nsweep = { \"time.dt\" = [0.002, 0.001] }",
            "s.toml:11: runs[0].sweep.\"time.dt\" = 0.002: time.dt is not read by run \
             static-5-rk4-dt=0.002: the run takes the dynamic step",
        ),
        (
            "strategy = \"static\"\ndt = 0.002\nsweep = { \"time.beta\" = [0.001, 0.01] }",
            "time.beta is not read by run static-5-rk4-beta=0.001: the run takes the fixed step",
        ),
        (
            "strategy = \"static\"\nset = { \"adaptivity.h_min\" = 0.03 }",
            "adaptivity.h_min is not read by run static-5-rk4: strategy `static` never adapts",
        ),
        (
            "strategy = \"bisect48\"\nsweep = { \"time.duration\" = [0.005, 0.01] }",
            "time.duration cannot be set per run",
        ),
        (
            "strategy = \"static\"\nsweep = { \"cloth.size\" = [[1.0, 1.0], [0.2, 0.2]] }",
            "run static-5-rk4-size=[0.2_ 0.2]: its settings make a scene that cannot be set up: \
             <embedded sphere>",
        ),
    ] {
        let args = small_study(
            dir.path(),
            "duration = 0.01",
            &format!("[[runs]]\nresolution = 5\n{runs}\n"),
        );
        let (code, err) = adaptcloth(&strs(&args));
        assert_eq!(code, 2, "{runs}: {err}");
        assert!(err.contains(expected), "{runs}: {err}");
        assert!(!dir.path().join("cache").exists(), "{runs}: nothing runs");
    }
}

/// Writes `DIR/s.toml`, a study of the sphere with a 9x9 reference and a 5x5 floor, its
/// top-level keys `top` (`duration = ...` first) and its `[[runs]]` entries `runs`; the
/// arguments that run it quietly into `DIR/out`, its references cached in `DIR/cache`.
fn small_study(dir: &std::path::Path, top: &str, runs: &str) -> Vec<String> {
    let study = dir.join("s.toml");
    let text = format!(
        "name = \"s\"\ndescription = \"d\"\nscenes = [\"sphere\"]\n{top}\n\
         [reference]\nresolution = 9\nfloor = 5\n{runs}"
    );
    std::fs::write(&study, text).unwrap();
    let path = |p: std::path::PathBuf| p.to_str().unwrap().to_string();
    vec![
        "study".into(),
        path(study),
        "--quiet".into(),
        "--out".into(),
        path(dir.join("out")),
        "--cache".into(),
        path(dir.join("cache")),
    ]
}

/// `args` as the string slices [`adaptcloth`] takes.
fn strs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}
