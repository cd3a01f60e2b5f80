//! Paths the commands are given or derive: `--out`, `--cache`, `--docs-notes`, comparison folders
//! and the scene `name` that names default output folders. A path that cannot serve is refused
//! before anything runs (exit 2), naming the option (or key) and what was expected.
use crate::cli::adaptcloth;
use std::path::Path;

/// A one-run comparison of the sphere (a 5x5 reference, 0.02 s) into `out`, shard `shard` of
/// `static@3,static@4`: a second or so.
fn tiny_shard(out: &Path, cache: &Path, shard: &str) {
    let (code, err) = adaptcloth(&[
        "compare",
        "--runs",
        "static@3,static@4",
        "--shard",
        shard,
        "--ref-resolution",
        "5",
        "--floor-resolution",
        "3",
        "--samples",
        "4",
        "--duration",
        "0.02",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
}

/// `merge` says each missing run on stderr; `report` refuses a comparison folder whose table is
/// missing or broken with exit 2, naming itself (not `merge`).
#[test]
fn merge_lists_missing_runs_and_report_names_itself_on_a_broken_folder() {
    let dir = tempfile::tempdir().unwrap();
    let (shard, cache) = (dir.path().join("s1"), dir.path().join("cache"));
    tiny_shard(&shard, &cache, "1/2");
    // An `--out` that a file keeps from being a folder is refused, naming the option.
    let blocker = dir.path().join("afile");
    std::fs::write(&blocker, "x").unwrap();
    for out in [blocker.clone(), blocker.join("sub")] {
        let (code, err) = adaptcloth(&[
            "merge",
            shard.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains(&format!("--out {}: ", out.display()))
                && err.contains("is a file, not a folder"),
            "{err}"
        );
    }
    let merged = dir.path().join("merged");
    let (code, err) = adaptcloth(&[
        "merge",
        shard.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("missing run static-4-") && err.contains("no shard ran it"),
        "{err}"
    );
    let csv = merged.join("comparison.csv");
    std::fs::remove_file(&csv).unwrap();
    let (code, err) = adaptcloth(&["report", merged.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!("error: report: {}: cannot be read", csv.display())),
        "{err}"
    );
    std::fs::write(&csv, "").unwrap();
    let (code, err) = adaptcloth(&["report", merged.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!("error: report: {}: empty", csv.display())),
        "{err}"
    );
    let (code, err) = adaptcloth(&[
        "merge",
        merged.to_str().unwrap(),
        "--out",
        dir.path().join("m2").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!("error: merge: {}: empty", csv.display())),
        "{err}"
    );
}

/// `--out`, `--cache`, `--write-docs` and `--docs-notes` that cannot serve: exit 2 naming the
/// option, before the run's banner.
#[test]
fn unusable_folders_and_files_are_refused_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("afile");
    std::fs::write(&file, "x").unwrap();
    let file = file.to_str().unwrap();
    let notes = dir.path().join("nonexistent.md");
    let notes = notes.to_str().unwrap();
    let docs = dir.path().join("docs").to_str().unwrap().to_string();
    let cases: Vec<(Vec<&str>, String)> =
        vec![
        (
            vec!["run", "--out", "/dev/null"],
            "--out /dev/null: cannot create the output folder: it is a device, pipe or socket, \
             not a folder"
                .into(),
        ),
        (
            vec!["study", "--out", "/dev/null"],
            "--out /dev/null/sphere: cannot create the output folder: /dev/null is a device".into(),
        ),
        (
            vec!["run", "--out", "/proc"],
            "--out /proc: cannot write in the output folder".into(),
        ),
        // Regression (study review 2026-11-29, finding 9): exit 1 without naming the option.
        (
            vec!["merge", file, "--out", "/proc/x"],
            "--out /proc/x: cannot create the output folder".into(),
        ),
        (
            vec!["reference", "--cache", file],
            format!("--cache {file}: cannot create the cache folder: it is a file, not a folder"),
        ),
        (
            vec!["study", "--cache", file, "--out", dir.path().to_str().unwrap()],
            format!("--cache {file}: cannot create the cache folder: it is a file"),
        ),
        (
            vec!["compare", "--docs-notes", notes, "--write-docs", &docs],
            format!("--docs-notes {notes}: cannot be read: "),
        ),
        // Checked before any run, not after them.
        (
            vec!["study", "--write-docs", file],
            format!("--write-docs {file}: cannot create the docs folder: it is a file"),
        ),
        (
            vec!["report", "no-such-folder", "--write-docs", "/dev/null"],
            "--write-docs /dev/null: cannot create the docs folder: it is a device".into(),
        ),
    ];
    for (args, needle) in cases {
        let (code, err) = adaptcloth(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(&needle), "{args:?}: {err}");
        assert!(!err.contains("adaptcloth:"), "the banner came first: {err}");
    }
    // A folder that exists but cannot be written in (not for root, who may write anywhere).
    let read_only = dir.path().join("ro");
    std::fs::create_dir(&read_only).unwrap();
    let mut perms = std::fs::metadata(&read_only).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o555);
    std::fs::set_permissions(&read_only, perms).unwrap();
    if std::fs::write(read_only.join("probe"), "").is_err() {
        let (code, err) = adaptcloth(&["run", "--out", read_only.to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("cannot write in the output folder"), "{err}");
    }
}

/// A scene `name` too long for the folder named after it is blamed on the key, with its line,
/// echoed clipped; with `--out` the run goes on, its banner clipped too.
#[test]
fn a_scene_name_too_long_for_a_folder_names_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("long.toml");
    let name = "x".repeat(100_000);
    std::fs::write(
        &scene,
        format!("name = \"{name}\"\n[time]\nduration = 0.01\n"),
    )
    .unwrap();
    let scene = scene.to_str().unwrap();
    let (code, err) = adaptcloth(&["run", scene, "--quiet"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("{scene}:1: name = xxx")), "{err}");
    assert!(err.contains("give --out"), "{err}");
    assert!(!err.contains("error: --out"), "{err}");
    assert!(err.len() < 2000, "{} bytes", err.len());
    let study = dir.path().join("study.toml");
    std::fs::write(
        &study,
        format!("scenes = [\"{scene}\"]\n[[runs]]\nstrategy = \"static\"\n"),
    )
    .unwrap();
    let out = dir.path().join("st");
    let (code, err) = adaptcloth(&[
        "study",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("{scene}:1: name = xxx")), "{err}");
    assert!(err.len() < 2000, "{} bytes", err.len());
    let out = dir.path().join("o");
    let (code, err) = adaptcloth(&["run", scene, "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(err.len() < 2000, "{} bytes", err.len());
}
