//! `adaptcloth study` end to end: a tiny study file run whole, and the same study split into two
//! shards run by GNU parallel with two local slots (the path to a cluster: `--shard i/n`, then
//! `merge`), merged into the same table.
//!
//! Skipped (with a message) when GNU `parallel` is not installed, except under CI (`CI=true`),
//! where `.ci/run` installs Debian's `parallel` and a missing one fails the test.
use std::path::Path;
use std::process::Command;

const STUDY: &str = r#"
name = "tiny"
scenes = ["sphere"]
duration = 0.15

[reference]
resolution = 7
floor = 5
samples = 10

[[runs]]
strategy = "static"
sweep = { "cloth.resolution" = [3, 5] }

[[runs]]
strategy = "bisect48"
resolution = 3
integrator = "implicit_euler"
dt = 0.004
sweep = { "adaptivity.l_min" = [0.2, 0.1] }
"#;

fn adaptcloth(dir: &Path, args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("binary runs");
    let text = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {text}");
    text
}

/// `comparison.csv` without its wall-time columns (`*_s` but `sim_time`).
fn table(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("comparison.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !header[i].ends_with("_s"))
        .collect();
    std::iter::once(header.join(","))
        .chain(lines.map(String::from))
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&i| cells[i]).collect::<Vec<_>>().join(",")
        })
        .collect()
}

fn has_parallel() -> bool {
    Command::new("parallel")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// A study of several scenes makes every reference before its runs, scenes side by side: each
/// scene's comparison then reads its reference from the cache, even under `--force-reference`
/// (so a forced reference is computed once, not twice).
#[test]
fn a_study_of_two_scenes_makes_each_reference_once_before_its_runs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = STUDY.replace(
        r#"scenes = ["sphere"]"#,
        r#"scenes = ["sphere", "hanging"]"#,
    );
    std::fs::write(d.join("two.toml"), two).unwrap();
    let args = [
        "study",
        "two.toml",
        "--cache",
        "cache",
        "--out",
        "o",
        "--quiet",
        "--jobs",
        "2",
        "--force-reference",
    ];
    let text = adaptcloth(d, &args);
    let read_back = text.lines().filter(|l| l.starts_with("reference "));
    assert_eq!(
        read_back.filter(|l| l.ends_with("(cached)")).count(),
        2,
        "{text}"
    );
    for scene in ["sphere", "hanging"] {
        assert!(
            d.join("o").join(scene).join("comparison.csv").is_file(),
            "{scene}"
        );
    }
}

#[test]
fn a_study_sharded_under_gnu_parallel_merges_into_the_single_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("tiny.toml"), STUDY).unwrap();
    let common = ["--cache", "cache", "--quiet"];
    let mut args = vec!["study", "tiny.toml", "--references-only"];
    args.extend(common);
    let text = adaptcloth(d, &args);
    assert!(!text.contains("panicked"), "{text}");
    let mut args = vec!["study", "tiny.toml", "--out", "single", "--jobs", "2"];
    args.extend(common);
    adaptcloth(d, &args);
    let single = table(&d.join("single/sphere/comparison.csv"));
    assert_eq!(single.len(), 5, "{single:?}");
    assert!(
        single[3].contains("bisect48-3-implicit_euler-l_min=0.2"),
        "{single:?}"
    );
    assert!(d.join("single/sphere/report.md").is_file());

    if !has_parallel() {
        assert!(
            std::env::var("CI").is_err(),
            "GNU parallel is missing under CI: .ci/run installs Debian's `parallel`"
        );
        crate::common::say_skipped("the GNU parallel part (no `parallel` on PATH)");
        return;
    }
    let bin = env!("CARGO_BIN_EXE_adaptcloth");
    let status = Command::new("parallel")
        .current_dir(d)
        .args(["--will-cite", "-j", "2", "--halt", "now,fail=1"])
        .arg(format!(
            "{bin} study tiny.toml --shard {{}}/2 --out shard{{}} --cache cache --quiet"
        ))
        .args([":::", "1", "2"])
        .status()
        .expect("parallel runs");
    assert!(status.success());
    adaptcloth(
        d,
        &[
            "merge",
            "shard1/sphere",
            "shard2/sphere",
            "--out",
            "merged/sphere",
        ],
    );
    assert_eq!(table(&d.join("merged/sphere/comparison.csv")), single);
}

#[test]
fn the_first_command_prints_the_ranked_table_of_the_four_strategies() {
    // The README's main job: `adaptcloth study` with no file runs the embedded quick study.
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(["study", "--quiet", "--jobs", "2", "--out"])
        .arg(dir.path().join("quick"))
        .arg("--cache")
        .arg(dir.path().join("cache"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("ranked by speed-up"), "{stdout}");
    for strategy in ["bisect48", "simnett", "remesh"] {
        assert!(
            stdout.contains(&format!("  {strategy} ")),
            "{strategy}: {stdout}"
        );
    }
    // The six adaptive runs ranked, the three static grids as the baseline.
    assert!(stdout.contains("\n   6  "), "{stdout}");
    assert!(!stdout.contains("\n   7  "), "{stdout}");
    assert!(stdout.contains("static baseline: 5x5"), "{stdout}");
    assert!(dir.path().join("quick/sphere/report.html").is_file());
    assert!(stdout.contains("report.html"), "{stdout}");
}
