//! `adaptcloth reference`, `compare`, `merge` end to end on tiny configurations (a 9x9 reference,
//! 3x3 and 5x5 runs, 0.15 s so the cloth touches the sphere): the files exist, the table parses,
//! the reference is cached, and sharded runs merge into the same numbers as one run.
use adaptcloth::report::reading::SUMMARY_NOTE;
use adaptcloth::study::table::{column_names, read_csv};
use std::path::Path;
use std::process::Command;

fn adaptcloth(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(args)
        .output()
        .expect("binary runs");
    let text =
        String::from_utf8_lossy(&out.stderr).into_owned() + &String::from_utf8_lossy(&out.stdout);
    (out.status.code().unwrap_or(-1), text)
}

const RUNS: &str = "static@3,static@5,remesh";

const TINY: &[&str] = &[
    "--ref-resolution",
    "9",
    "--floor-resolution",
    "5",
    "--samples",
    "12",
    "--duration",
    "0.15",
    "--quiet",
];

fn compare_into(out: &Path, cache: &Path, runs: &str, extra: &[&str]) -> String {
    let mut args = vec![
        "compare",
        "sphere",
        "--runs",
        runs,
        "--out",
        out.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ];
    args.extend_from_slice(TINY);
    args.extend_from_slice(extra);
    let (code, text) = adaptcloth(&args);
    assert_eq!(code, 0, "{text}");
    text
}

#[test]
fn tiny_compare_end_to_end_with_cache_shards_and_merge() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let full = dir.path().join("full");
    let text = compare_into(&full, &cache, RUNS, &["--jobs", "2"]);
    assert!(!text.contains("(cached)"), "first run computes: {text}");

    for f in [
        "comparison.csv",
        "comparison.json",
        "report.md",
        "speed_error.svg",
        "speed_error.png",
        "elements.svg",
        "step.svg",
        "tracked.svg",
        "error.svg",
        "runs/static-3-rk4/metrics.csv",
        "runs/static-3-rk4/error.csv",
        "runs/static-5-rk4/summary.json",
    ] {
        assert!(full.join(f).is_file(), "missing {f}");
    }
    let header = std::fs::read_to_string(full.join("comparison.csv")).unwrap();
    assert_eq!(
        header.lines().next().unwrap(),
        column_names().collect::<Vec<_>>().join(",")
    );
    let rows = read_csv(&full.join("comparison.csv")).unwrap();
    let labels: Vec<&str> = rows.iter().map(|r| r.label.as_str()).collect();
    assert!(
        labels.starts_with(&["static-3-rk4", "static-5-rk4"]),
        "{labels:?}"
    );
    for r in &rows {
        assert_eq!(r.status, "completed", "{}", r.label);
        assert!(r.steps > 0 && r.wall_s > 0.0);
        // The cloth has touched the sphere: the coarse runs differ from the 9x9 reference.
        assert!(
            r.e_rms.is_finite() && r.e_rms > 1e-5,
            "{}: {}",
            r.label,
            r.e_rms
        );
        assert!(r.e_final.is_finite() && r.e_final >= 0.0);
        assert!(r.tracked_err.is_finite() && r.hausdorff.is_finite());
        assert!(r.e_rms <= r.e_final * 10.0 + 1.0, "sane magnitudes");
        assert!((r.sim_time - 0.15).abs() < 1e-9);
    }
    let report = std::fs::read_to_string(full.join("report.md")).unwrap();
    assert!(report.contains("Error floor"), "{report}");
    // What the summary's speed-ups, static-curve times and flags mean, under its table.
    let note = report
        .find(SUMMARY_NOTE)
        .expect("the summary's definitions");
    assert!(report.find("| **wins** |").unwrap() < note, "{report}");
    assert!(labels.contains(&"remesh-5-rk4"), "{labels:?}");

    // The reference is read from the cache the second time (one entry).
    let again = dir.path().join("again");
    let text = compare_into(&again, &cache, "static@3", &[]);
    assert!(text.contains("(cached)"), "{text}");
    assert_eq!(std::fs::read_dir(&cache).unwrap().count(), 1);

    // Two shards, merged, give the same runs with the same errors (runs are deterministic).
    let s1 = dir.path().join("s1");
    let s2 = dir.path().join("s2");
    compare_into(&s1, &cache, RUNS, &["--shard", "1/2"]);
    compare_into(&s2, &cache, RUNS, &["--shard", "2/2"]);
    let n1 = read_csv(&s1.join("comparison.csv")).unwrap().len();
    let n2 = read_csv(&s2.join("comparison.csv")).unwrap().len();
    assert_eq!(n1 + n2, rows.len());
    assert!(n1 >= 1 && n2 >= 1);
    let merged = dir.path().join("merged");
    let (code, text) = adaptcloth(&[
        "merge",
        s1.to_str().unwrap(),
        s2.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{text}");
    let m = read_csv(&merged.join("comparison.csv")).unwrap();
    assert_eq!(m.len(), rows.len());
    for (a, b) in m.iter().zip(&rows) {
        assert_eq!(a.label, b.label);
        assert_eq!(a.steps, b.steps);
        assert!(
            (a.e_rms - b.e_rms).abs() <= 1e-9 * b.e_rms.abs(),
            "{}",
            a.label
        );
        assert!(merged
            .join("runs")
            .join(&a.label)
            .join("metrics.csv")
            .is_file());
    }
    assert!(merged.join("speed_error.svg").is_file());

    // The docs page over the merged comparison opens with the summary: per scene and
    // integrator, one row per adaptive strategy, one column per (measure, static target), each
    // cell a speed-up or the reason there is none, and the winner of each column.
    let docs = dir.path().join("docs");
    let (code, text) = adaptcloth(&[
        "report",
        merged.to_str().unwrap(),
        "--write-docs",
        docs.to_str().unwrap(),
        "--docs-command",
        "test",
    ]);
    assert_eq!(code, 0, "{text}");
    let page = std::fs::read_to_string(docs.join("results.md")).unwrap();
    let summary = page
        .split("## Summary")
        .nth(1)
        .expect("a summary section")
        .split("\n## ")
        .next()
        .unwrap();
    assert!(
        summary.contains("| strategy (sphere, `rk4`) |"),
        "{summary}"
    );
    assert!(summary.contains("e_rms of static 3x3"), "{summary}");
    assert!(summary.contains("Hausdorff of static 5x5"), "{summary}");
    let row = summary
        .lines()
        .find(|l| l.starts_with("| `remesh` |"))
        .expect("a remesh row");
    let cells: Vec<&str> = row.trim_matches('|').split(" | ").map(str::trim).collect();
    assert_eq!(cells.len(), 5, "{row}");
    for cell in &cells[1..] {
        assert!(
            cell.starts_with('x') || cell.starts_with(">= x") || cell.starts_with("does not reach"),
            "{row}"
        );
    }
    assert_eq!(summary.matches(SUMMARY_NOTE).count(), 1, "{summary}");
    // A target the reference does not resolve is flagged in its column's header and winner.
    let header = summary
        .lines()
        .find(|l| l.starts_with("| strategy"))
        .unwrap();
    let wins = summary
        .lines()
        .find(|l| l.starts_with("| **wins** |"))
        .expect("a verdict row");
    let heads: Vec<&str> = header.trim_matches('|').split(" | ").collect();
    let verdicts: Vec<&str> = wins.trim_matches('|').split(" | ").map(str::trim).collect();
    for (h, v) in heads.iter().zip(&verdicts).skip(1) {
        assert_eq!(
            h.contains("**not resolved**"),
            v.ends_with("(not resolved)"),
            "{summary}"
        );
    }

    // Merging a shard twice is refused.
    let (code, text) = adaptcloth(&[
        "merge",
        s1.to_str().unwrap(),
        s1.to_str().unwrap(),
        "--out",
        dir.path().join("bad").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{text}");
}

#[test]
fn reference_command_reports_the_floor_and_bad_options_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let args = [
        "reference",
        "sphere",
        "--ref-resolution",
        "5",
        "--floor-resolution",
        "3",
        "--samples",
        "8",
        "--duration",
        "0.02",
        "--cache",
        cache.to_str().unwrap(),
        "--quiet",
    ];
    let (code, text) = adaptcloth(&args);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("error floor (3x3 against 5x5)"), "{text}");
    let entry = std::fs::read_dir(&cache).unwrap().next().unwrap().unwrap();
    let bin = entry.path().join("reference.bin");
    assert!(bin.is_file());
    // A NaN written over the data (trial report A6) is not used as "(cached)": the entry is
    // recomputed, saying why on stderr.
    let mut bytes = std::fs::read(&bin).unwrap();
    let at = bytes.len() - 4;
    bytes[at..].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(&bin, &bytes).unwrap();
    let again = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
            .args(args)
            .output()
            .unwrap();
        let (stdout, stderr) = (
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        );
        (out.status.code(), stdout, stderr)
    };
    let (code, stdout, stderr) = again(&args);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    assert!(
        stderr.contains("malformed reference cache file")
            && stderr.contains("the reference was recomputed"),
        "{stderr}"
    );
    assert!(!stdout.contains("(cached)"), "{stdout}");
    // The rewritten entry is valid again.
    let (_, stdout, stderr) = again(&args);
    assert!(
        stdout.contains("(cached)") && !stderr.contains("warning"),
        "{stdout}{stderr}"
    );
    for (args, needle) in [
        (vec!["compare", "--runs", "magic"], "unknown strategy"),
        (vec!["compare", "--shard", "3/2"], "--shard"),
        (vec!["compare", "--integrators", "leapfrog"], "leapfrog"),
        (vec!["reference", "--ref-beta=-1"], "--ref-beta"),
        (vec!["compare", "--runs", "static@1"], "at least 2"),
        (
            vec![
                "reference",
                "--ref-resolution",
                "9",
                "--floor-resolution",
                "17",
            ],
            "--floor-resolution 17 must be below --ref-resolution 9",
        ),
    ] {
        let (code, text) = adaptcloth(&args);
        assert_eq!(code, 2, "{args:?}: {text}");
        assert!(text.contains(needle), "{args:?}: {text}");
    }
}

/// `report` and `merge` on a path that is not a comparison folder: bad input (exit 2), saying
/// what the path is and what was expected.
#[test]
fn report_and_merge_refuse_a_path_that_is_not_a_comparison_folder() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("afile");
    std::fs::write(&file, "x").unwrap();
    let missing = dir.path().join("missing");
    for (path, what) in [
        (dir.path(), "a folder without comparison.json"),
        (file.as_path(), "not a folder"),
        (missing.as_path(), "no such folder"),
    ] {
        let p = path.to_str().unwrap();
        let out = dir.path().join("merged");
        for args in [
            vec!["report", p],
            vec!["merge", p, "--out", out.to_str().unwrap()],
        ] {
            let (code, text) = adaptcloth(&args);
            assert_eq!(code, 2, "{args:?}: {text}");
            assert!(text.contains(what), "{args:?}: {text}");
            assert!(
                text.contains("expected a comparison folder"),
                "{args:?}: {text}"
            );
        }
    }
}

/// A `--set` that makes the reference diverge (it reaches the reference too) fails with a hint
/// that says so and where run-only keys go.
#[test]
fn a_reference_diverging_under_a_shared_key_says_where_run_only_keys_go() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cache) = (dir.path().join("o"), dir.path().join("cache"));
    let (code, text) = adaptcloth(&[
        "compare",
        "hanging",
        "--quiet",
        "--duration",
        "0.2",
        "--ref-resolution",
        "9",
        "--floor-resolution",
        "5",
        "--samples",
        "8",
        "--runs",
        "static@5",
        "--set",
        "time.mode=\"fixed\"",
        "--set",
        "time.dt=0.02",
        "--out",
        out.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("did not complete: Diverged"), "{text}");
    assert!(text.contains("[[runs]] entry"), "{text}");
}
