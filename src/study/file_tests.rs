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
    ("scenes = [\"sphere\"]\n[reference]\nresolution = 5\nfloor = 9\n[[runs]]\nstrategy = \"static\"\n", "s.toml:4", "expected below reference.resolution = 5"),
    // The default floor (33) above a coarser reference: the message points at the resolution.
    ("scenes = [\"sphere\"]\n[reference]\nresolution = 17\n[[runs]]\nstrategy = \"static\"\n", "s.toml:3", "reference.floor = 33"),
    ("scenes = [\"sphere\", \"round_tabel\"]\n[[runs]]\nstrategy = \"static\"\n", "s.toml:1", "scenes[1] = \"round_tabel\": no such scene file"),
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
