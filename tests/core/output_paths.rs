//! Output paths: what a scene, a study run or a study names cannot write outside the output
//! folder, and a file in the way of an output folder is named.
use super::cli::adaptcloth;
use std::process::Command;

/// Runs the binary with `args` in the folder `work` and asserts it succeeded.
fn adaptcloth_ok_in(work: &std::path::Path, args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .current_dir(work)
        .args(args)
        .output()
        .expect("binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_scene_name_cannot_write_outside_the_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path().join("work");
    std::fs::create_dir_all(&work).unwrap();
    for name in ["../../escaped", "/tmp/adaptcloth-escaped-name"] {
        let scene = work.join("s.toml");
        std::fs::write(
            &scene,
            format!("name = \"{name}\"\n[time]\nduration = 0.01\n"),
        )
        .unwrap();
        adaptcloth_ok_in(&work, &["run", "s.toml", "--quiet"]);
        // Everything the run wrote is under work/out/.
        let entries: Vec<String> = std::fs::read_dir(&work)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        let mut entries = entries;
        entries.sort();
        assert_eq!(entries, ["out", "s.toml"], "{name}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "{name}");
        assert!(!std::path::Path::new("/tmp/adaptcloth-escaped-name-static").exists());
        let runs: Vec<_> = std::fs::read_dir(work.join("out")).unwrap().collect();
        assert!(runs
            .iter()
            .all(|e| e.as_ref().unwrap().path().join("summary.json").is_file()));
    }
}

/// A study run's `label` names its folder under `runs/`: `/tmp/...` or `../../...` wrote outside
/// the study's output folder (the hostile sweep: `label = "/tmp/x"` wrote `/tmp/x-5-rk4`).
#[test]
fn a_study_label_cannot_write_outside_the_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path().join("work");
    std::fs::create_dir_all(&work).unwrap();
    let abs = "/tmp/adaptcloth-escaped-label";
    for (i, label) in ["../../escaped", abs].into_iter().enumerate() {
        std::fs::write(
            work.join("s.toml"),
            format!(
                "scenes = [\"sphere\"]\nduration = 0.01\n[reference]\nresolution = 5\nfloor = 3\n\
                 samples = 8\n[[runs]]\nstrategy = \"static\"\nresolution = 3\nlabel = \"{label}\"\n"
            ),
        )
        .unwrap();
        adaptcloth_ok_in(
            &work,
            &["study", "s.toml", "--quiet", "--out", &format!("out/s{i}")],
        );
        let mut entries: Vec<String> = std::fs::read_dir(&work)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        entries.sort();
        assert_eq!(entries, ["out", "s.toml"], "{label}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "{label}");
        assert!(!std::path::Path::new(&format!("{abs}-3-rk4")).exists());
        let runs = work.join(format!("out/s{i}/sphere/runs"));
        assert_eq!(std::fs::read_dir(&runs).unwrap().count(), 1, "{label}");
    }
}

/// A study's `name` names its default output folder `out/study-NAME`: `../../../../escaped` left
/// the working folder (the hostile sweep).
#[test]
fn a_study_name_cannot_write_outside_the_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path().join("a/b/work");
    std::fs::create_dir_all(&work).unwrap();
    std::fs::write(
        work.join("s.toml"),
        "name = \"../../../../escaped\"\nscenes = [\"sphere\"]\nduration = 0.01\n\
         [reference]\nresolution = 5\nfloor = 3\nsamples = 8\n\
         [[runs]]\nstrategy = \"static\"\nresolution = 3\n",
    )
    .unwrap();
    adaptcloth_ok_in(&work, &["study", "s.toml", "--quiet"]);
    let names = |p: &std::path::Path| -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(p)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(names(&dir.path().join("a/b")), ["work"]);
    assert_eq!(names(&dir.path().join("a")), ["b"]);
    assert_eq!(names(&work), ["out", "s.toml"]);
    assert!(work
        .join("out/study-_.._.._.._escaped/sphere/report.html")
        .is_file());
}

/// A file where the run's `frames/` folder goes is named in the error, not only the folder.
#[test]
fn a_file_in_place_of_the_frames_folder_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("frames"), "x").unwrap();
    let (code, err) = adaptcloth(&[
        "run",
        "--duration",
        "0.01",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains(&format!(
            "cannot create the folder {}",
            out.join("frames").display()
        )),
        "{err}"
    );
}
