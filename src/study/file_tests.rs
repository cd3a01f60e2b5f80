//! The study file's parser: sweeps, run settings against the reference's, bad keys and values.

use super::*;
use crate::study::config::configs_for;

fn parse(text: &str) -> Result<Study, StudyError> {
    parse_study(text, "s.toml", "s", Path::new("."))
}

fn args(set: &[Setting]) -> Vec<String> {
    set.iter().map(|s| s.arg.clone()).collect()
}

fn message(text: &str) -> String {
    parse(text).unwrap_err().to_string()
}

const BASIC: &str = r#"
scenes = ["sphere"]
set = { "time.frame_rate" = 30 }

[reference]
resolution = 9
floor = 5

[[runs]]
strategy = "static"
integrator = "implicit_euler"
dt = 0.002
sweep = { "cloth.resolution" = [5, 9] }

[[runs]]
strategy = "bisect48"
set = { "adaptivity.restore_energy" = true }
sweep = { "adaptivity.l_min" = [0.08, 0.04], "adaptivity.max_depth" = [2, 3] }
"#;

#[test]
fn sweeps_expand_to_one_labelled_run_per_combination() {
    let s = parse(BASIC).unwrap();
    assert_eq!(s.name, "s");
    assert_eq!(args(&s.set), ["time.frame_rate=30"]);
    assert_eq!(s.reference.resolution, 9);
    assert_eq!(
        s.reference.integrator.as_deref(),
        Some("rk4"),
        "default reference"
    );
    let scene = crate::scene::load_embedded("sphere", &[]).unwrap().unwrap();
    let labels: Vec<String> = configs_for(&s.runs, &scene)
        .unwrap()
        .iter()
        .map(|c| c.label())
        .collect();
    assert_eq!(
        labels,
        [
            "static-5-implicit_euler",
            "static-9-implicit_euler",
            "bisect48-5-rk4-l_min=0.08-max_depth=2",
            "bisect48-5-rk4-l_min=0.08-max_depth=3",
            "bisect48-5-rk4-l_min=0.04-max_depth=2",
            "bisect48-5-rk4-l_min=0.04-max_depth=3",
        ]
    );
    let fixed = &args(&s.runs[0].set);
    assert!(
        fixed.contains(&"time.mode=\"fixed\"".to_string()),
        "{fixed:?}"
    );
    assert!(fixed.contains(&"time.dt=0.002".to_string()), "{fixed:?}");
    let last = &args(&s.runs[5].set);
    assert!(last.contains(&"adaptivity.l_min=0.04".to_string()));
    assert!(last.contains(&"adaptivity.max_depth=3".to_string()));
    assert!(last.contains(&"adaptivity.restore_energy=true".to_string()));
}

#[test]
fn run_settings_reach_the_run_and_not_the_reference() {
    let s = parse(BASIC).unwrap();
    let plans = crate::study::plan(&s, |n| Path::new("out").join(n), false).unwrap();
    let base = &plans[0].loaded;
    // The study-wide set reaches the base scene (and so the reference)...
    assert_eq!(base.scene.time.frame_rate, 30.0);
    // ...the runs' own keys do not.
    assert_eq!(base.scene.time.mode, crate::scene::TimeMode::Dynamic);
    assert!(!base.scene.adaptivity.restore_energy);
    let static5 = plans[0].configs[0].scene(base).unwrap();
    assert_eq!(static5.scene.time.mode, crate::scene::TimeMode::Fixed);
    assert_eq!(static5.scene.time.dt, 0.002);
    assert_eq!(static5.scene.integrator.name, "implicit_euler");
    assert_eq!(static5.scene.time.frame_rate, 30.0);
    let adaptive = plans[0].configs[5].scene(base).unwrap();
    assert!(adaptive.scene.adaptivity.restore_energy);
    assert_eq!(adaptive.scene.adaptivity.l_min, 0.04);
    assert_eq!(adaptive.scene.adaptivity.max_depth, 3);
    let reference = crate::eval::reference::static_variant(base, 9, &s.reference);
    assert_eq!(reference.scene.integrator.name, "rk4");
    assert_eq!(reference.scene.time.mode, crate::scene::TimeMode::Dynamic);
    assert_eq!(reference.scene.adaptivity.strategy, "static");
    assert!(!reference.scene.adaptivity.restore_energy);
}

/// A sweep of 299 x 299 values is refused before any run is planned, with the count.
#[test]
fn a_study_of_too_many_runs_is_refused_before_planning() {
    let values: Vec<String> = (0..299)
        .map(|k| format!("{}", 0.01 + k as f64 * 1e-4))
        .collect();
    let list = values.join(", ");
    let text = format!(
        "scenes = [\"sphere\", \"bunny\"]\n[[runs]]\nstrategy = \"bisect48\"\nsweep = {{ \"adaptivity.h_min\" = [{list}], \"adaptivity.l_max\" = [{list}] }}\n"
    );
    let started = std::time::Instant::now();
    let m = message(&text);
    assert!(m.contains("89401 runs per scene (178802 in all"), "{m}");
    assert!(m.contains(&MAX_RUNS.to_string()), "{m}");
    assert!(started.elapsed().as_secs() < 5);
    // At the limit it is planned.
    let list = values[..100].join(", ");
    let text = format!(
        "scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"bisect48\"\nsweep = {{ \"adaptivity.h_min\" = [{list}], \"adaptivity.l_max\" = [{list}] }}\n"
    );
    assert_eq!(parse(&text).unwrap().runs.len(), MAX_RUNS);
}

#[test]
fn a_fixed_reference_step_reaches_the_reference_settings_only() {
    let text = "scenes = [\"sphere\"]\n[reference]\nintegrator = \"implicit_euler\"\ndt = 0.00025\n[[runs]]\nstrategy = \"static\"\n";
    let s = parse(text).unwrap();
    assert_eq!(s.reference.dt, Some(0.00025));
    assert_eq!(s.reference.integrator.as_deref(), Some("implicit_euler"));
    assert_eq!(
        parse(BASIC).unwrap().reference.dt,
        None,
        "dynamic by default"
    );
    let scene = crate::scene::load_embedded("sphere", &[]).unwrap().unwrap();
    let run = configs_for(&s.runs, &scene).unwrap()[0]
        .scene(&scene)
        .unwrap();
    assert_eq!(
        run.scene.time.mode,
        crate::scene::TimeMode::Dynamic,
        "the run keeps its step"
    );
}

#[test]
fn bad_keys_and_values_name_the_file_the_line_and_the_expectation() {
    let cases = [
        ("scenes = [\"sphere\"]\nrunz = 1\n", "s.toml", "unknown field `runz`"),
        ("scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"magic\"\n", "s.toml:3", "bisect48"),
        ("scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\nintegrator = \"leap\"\n", "s.toml:4", "rk4"),
        ("scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\nresolution = 1\n", "s.toml:4", "at least 2"),
        ("scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\ndt = 0.1\nbeta = 0.1\n", "s.toml:4", "not both"),
        ("scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\nsweep = { \"cloth.resolution\" = [1] }\n", "s.toml:4", "at least 2 vertices"),
        ("scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\nsweep = { \"x.y\" = [] }\n", "s.toml:4", "at least one value"),
        ("scenes = [\"sphere\"]\n[reference]\nfloor = 1\n[[runs]]\nstrategy = \"static\"\n", "s.toml:3", "reference.floor"),
        ("scenes = [\"sphere\"]\n[reference]\nbeta = -1.0\n[[runs]]\nstrategy = \"static\"\n", "s.toml:3", "reference.beta"),
        ("scenes = [\"sphere\"]\n[reference]\ndt = 0.0\n[[runs]]\nstrategy = \"static\"\n", "s.toml:3", "reference.dt = 0: expected a finite step > 0 (s)"),
        ("scenes = [\"sphere\"]\n[reference]\ndt = 0.001\nbeta = 0.01\n[[runs]]\nstrategy = \"static\"\n", "s.toml:4", "reference.beta and reference.dt: expected one"),
        ("scenes = [\"sphere\"]\n[reference]\nsamples = 100000000\n[[runs]]\nstrategy = \"static\"\n", "s.toml:3", "reference.samples = 100000000: expected 2 to 1000 points per side"),
        ("scenes = [\"sphere\"]\n[reference]\nresolution = 2001\n[[runs]]\nstrategy = \"static\"\n", "s.toml:3", "reference.resolution = 2001: expected 2 to 2000 vertices per side"),
    ("scenes = [\"sphere\"]\n[reference]\nresolution = 5\nfloor = 9\n[[runs]]\nstrategy = \"static\"\n", "s.toml:4", "expected below reference.resolution = 5"),
    // The default floor (33) above a coarser reference: the message points at the resolution.
    ("scenes = [\"sphere\"]\n[reference]\nresolution = 17\n[[runs]]\nstrategy = \"static\"\n", "s.toml:3", "reference.floor = 33"),
    ("scenes = [\"sphere\", \"round_tabel\"]\n[[runs]]\nstrategy = \"static\"\n", "s.toml:1", "scenes[1] = \"round_tabel\": no such scene file"),
    ("scenes = [\"/\"]\n[[runs]]\nstrategy = \"static\"\n", "s.toml:1", "scenes[0] = \"/\": / is a folder; expected a scene file"),
        ("scenes = []\n[[runs]]\nstrategy = \"static\"\n", "s.toml", "scenes"),
        ("scenes = [\"sphere\"]\n", "s.toml", "runs"),
        ("scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\n[[runs]]\nstrategy = \"static\"\n", "s.toml", "same label"),
        ("scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\ncolour = 1\n", "s.toml", "unknown field `colour`"),
        // A wrong form of a top-level key gets its expected form, not only Rust's types.
        ("[[scenes]]\nname = \"sphere\"\n[[runs]]\nstrategy = \"static\"\n", "s.toml", "`scenes` is a list of embedded scene names"),
        ("scenes = \"sphere\"\n[[runs]]\nstrategy = \"static\"\n", "s.toml", "expected a list [...]"),
        ("scenes = [\"sphere\"]\nduration = \"long\"\n[[runs]]\nstrategy = \"static\"\n", "s.toml", "expected a number"),
    ];
    for (text, place, expected) in cases {
        let m = message(text);
        assert!(m.starts_with(place), "{text:?}: {m}");
        assert!(m.contains(expected), "{text:?}: {m}");
    }
}

#[test]
fn a_bad_scene_key_in_a_run_is_caught_before_anything_runs() {
    let s = parse(
        "scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\nset = { \"cloth.nokey\" = 1 }\n",
    )
    .unwrap();
    let e = crate::study::plan(&s, |n| Path::new("out").join(n), false).unwrap_err();
    assert!(e.to_string().contains("cloth.nokey"), "{e}");
    let s = parse(
        "scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\nset = { \"time.dt\" = -1.0 }\n",
    )
    .unwrap();
    let e = crate::study::plan(&s, |n| Path::new("out").join(n), false).unwrap_err();
    assert!(e.to_string().contains("time.dt"), "{e}");
}

#[test]
fn a_bad_scene_key_or_value_in_a_study_names_the_study_file_and_its_line() {
    let head = "scenes = [\"sphere\"]\n\n[[runs]]\nstrategy = \"bisect48\"\n";
    let cases = [
        ("set = { \"adaptivity.h_min\" = -1 }\n", "s.toml:5: runs[0].set.\"adaptivity.h_min\" = -1: expected a finite value >= 0 (run bisect48-5-rk4)"),
        ("set = { \"adaptivity.nokey\" = 1 }\n", "s.toml:5: runs[0].set.\"adaptivity.nokey\" = 1: no such scene key"),
        ("set = { \"adaptivity.h_min\" = \"abc\" }\n", "s.toml:5: runs[0].set.\"adaptivity.h_min\" = \"abc\": invalid type"),
        ("set = { \"adaptivity..x\" = 1 }\n", "s.toml:5: runs[0].set.\"adaptivity..x\" = 1: expected section.key=value"),
        ("\nsweep = { \"adaptivity.h_min\" = [0.05, -2] }\n", "s.toml:6: runs[0].sweep.\"adaptivity.h_min\" = -2: expected a finite value >= 0 (run bisect48-5-rk4-h_min=-2)"),
        ("dt = -0.5\n", "s.toml:5: runs[0].dt = -0.5: expected a finite value > 0"),
        ("resolution = 100000\n", "s.toml:4: runs[0]: cloth.resolution = 100000: a 100000 x 100000 grid"),
    ];
    for (run, expected) in cases {
        let s = parse(&format!("{head}{run}")).unwrap();
        let e = crate::study::plan(&s, |n| Path::new("out").join(n), false).unwrap_err();
        assert!(e.to_string().starts_with(expected), "{run}: {e}");
    }
    // The study-wide `set` too.
    let s = parse(
        "scenes = [\"sphere\"]\nset = { \"material.rho\" = 0 }\n[[runs]]\nstrategy = \"static\"\n",
    )
    .unwrap();
    let e = crate::study::plan(&s, |n| Path::new("out").join(n), false).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("s.toml:2: set.\"material.rho\" = 0: expected a finite value > 0"),
        "{e}"
    );
}

/// Regression (trial report B1): a `[[runs]]` entry setting one scene key twice kept one and
/// ignored the other unchecked (`dt = 0.002` with `set = { "time.dt" = -1 }` ran). Refused,
/// naming both keys and their lines; the grid and integrator come only from the entry's keys.
#[test]
fn a_run_entry_that_sets_one_scene_key_twice_is_refused() {
    let head = "scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\n";
    let cases = [
        ("dt = 0.002\nset = { \"time.dt\" = -1 }\n", "s.toml:5: runs[0]: `set.\"time.dt\"` sets time.dt, which `dt` (s.toml:4) sets already"),
        ("beta = 0.01\nset = { \"time.mode\" = \"fixed\" }\n", "s.toml:5: runs[0]: `set.\"time.mode\"` sets time.mode, which `beta` (s.toml:4) sets already"),
        ("set = { \"adaptivity.strategy\" = \"remesh\" }\n", "s.toml:4: runs[0]: `set.\"adaptivity.strategy\"` sets adaptivity.strategy, which `strategy` (s.toml:3) sets already"),
        ("integrator = \"rk4\"\nset = { \"integrator.name\" = \"implicit_euler\" }\n", "s.toml:5: runs[0]: `set.\"integrator.name\"` sets integrator.name, which `integrator` (s.toml:4) sets already"),
        ("resolution = 5\nsweep = { \"cloth.resolution\" = [5, 9] }\n", "s.toml:5: runs[0]: `sweep.\"cloth.resolution\"` sets cloth.resolution, which `resolution` (s.toml:4) sets already"),
        ("sweep = { \"cloth.resolution\" = [5, 9], \"resolution\" = [5] }\n", "s.toml:4: runs[0]: `sweep.\"resolution\"` sets cloth.resolution, which `sweep.\"cloth.resolution\"` (s.toml:4) sets already"),
        ("set = { \"adaptivity.h_min\" = 0.1 }\nsweep = { \"adaptivity.h_min\" = [0.2] }\n", "s.toml:5: runs[0]: `sweep.\"adaptivity.h_min\"` sets adaptivity.h_min, which `set.\"adaptivity.h_min\"` (s.toml:4) sets already"),
        ("set = { \"integrator.name\" = \"implicit_euler\" }\n", "s.toml:4: runs[0].set.\"integrator.name\": a run's integrator is given by its key `integrator`"),
        ("set = { \"cloth.resolution\" = 9 }\n", "s.toml:4: runs[0].set.\"cloth.resolution\": a run's resolution is given by its key `resolution`"),
    ];
    for (run, expected) in cases {
        let m = message(&format!("{head}{run}"));
        assert!(m.starts_with(expected), "{run}: {m}");
    }
    // Each key once is fine; a grid sweep without `resolution` sets the grid.
    parse(&format!(
        "{head}dt = 0.002\nset = {{ \"time.frame_rate\" = 30 }}\nsweep = {{ \"resolution\" = [5, 9] }}\n"
    ))
    .unwrap();
}

/// Regression (trial report B2): two runs of one label were reported as `(static implicit_euler)`
/// without a line, with advice (`give one a label`) that cannot separate the runs of one entry.
/// The message names the real label, the entry's line and the cause.
#[test]
fn a_repeated_label_names_the_label_the_entry_and_the_cause() {
    let head = "scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\n";
    let cases = [
        ("integrator = \"implicit_euler\"\nsweep = { \"cloth.resolution\" = [5, 5] }\n", "s.toml:5: runs[0].sweep.\"cloth.resolution\" lists 5 twice, so two runs would have the same label static-5-implicit_euler: each value makes one run; remove the repeated value"),
        ("sweep = { \"adaptivity.h_min\" = [0.1, 0.3, 0.10] }\n", "s.toml:4: runs[0].sweep.\"adaptivity.h_min\" lists 0.1 twice, so two runs would have the same label static-<scene's grid>-<scene's integrator>-h_min=0.1"),
        ("resolution = 5\n[[runs]]\nstrategy = \"static\"\nsweep = { \"cloth.resolution\" = [9, 5] }\n", "s.toml:6: runs[1]: two runs would have the same label static-5-<scene's integrator> (s.toml:3: runs[0] makes it too): give one of the two entries a `label`"),
    ];
    for (run, expected) in cases {
        let m = message(&format!("{head}{run}"));
        assert!(m.starts_with(expected), "{run}: {m}");
    }
    // One entry on the scene's grid, another naming that grid: found once the scene is known.
    let s = parse(&format!(
        "{head}[[runs]]\nstrategy = \"static\"\nresolution = 5\n"
    ))
    .unwrap();
    let e = crate::study::plan(&s, |n| Path::new("out").join(n), false)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("s.toml:5: runs[1]: configuration static-5-rk4 listed twice (also by s.toml:3: runs[0]): give one of the two entries a `label`"),
        "{e}"
    );
}

/// Regression (trial report A2): two scenes of one study named alike wrote the same folder, the
/// second overwriting the first's results, exit 0. Refused before anything runs, naming both
/// scenes, where they were given and the folder.
#[test]
fn two_scenes_sharing_an_output_folder_are_refused() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("small.toml"),
        "name = \"sphere\"\n[cloth]\nresolution = 5\n",
    )
    .unwrap();
    let runs = "[[runs]]\nstrategy = \"static\"\n";
    for (scenes, second) in [
        (
            "[\"sphere\", \"sphere\"]",
            "scenes[1] = \"sphere\" (<embedded sphere>, named `sphere`)",
        ),
        (
            "[\"sphere\",\n  \"small.toml\"]",
            "s.toml:2: scenes[1] = \"small.toml\"",
        ),
    ] {
        let text = format!("scenes = {scenes}\n{runs}");
        let s = parse_study(&text, "s.toml", "s", d.path()).unwrap();
        let e = crate::study::plan(&s, |n| d.path().join("o").join(n), false)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "s.toml:1: scenes[0] = \"sphere\" (<embedded sphere>, named `sphere`) and "
            ),
            "{e}"
        );
        assert!(e.contains(second), "{e}");
        assert!(
            e.contains(&format!(
                "the same folder {}",
                d.path().join("o/sphere").display()
            )),
            "{e}"
        );
        assert!(!d.path().join("o").exists());
    }
}

/// A run's label is a column of comparison.csv and part of a folder name: a comma, a quote, a
/// control character or nothing at all is refused with its line.
#[test]
fn a_label_that_would_break_the_table_is_refused() {
    for label in ["fine, dense", "a\"b", "tab\there", ""] {
        let text = format!(
            "scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\nlabel = {}\n",
            toml::Value::String(label.to_string())
        );
        let m = message(&text);
        assert!(
            m.contains("s.toml:4") && m.contains("without commas"),
            "{label:?}: {m}"
        );
    }
    let ok = "scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\nlabel = \"fine_dense\"\n";
    assert!(parse(ok).is_ok());
}

#[test]
fn a_scene_file_given_as_a_study_is_named_as_such() {
    let m = message("[cloth]\nresolution = 9\n[time]\nduration = 0.2\n");
    assert!(m.contains("this looks like a scene file"), "{m}");
    assert!(m.contains("adaptcloth run FILE"), "{m}");
    // A study with a mistake is not sent to `run`.
    let m = message("scenes = [\"sphere\"]\ncloth = 1\n[[runs]]\nstrategy = \"static\"\n");
    assert!(!m.contains("scene file"), "{m}");
}
