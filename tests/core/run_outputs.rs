//! A run's outputs under stress: unconverged solves counted and reported, a reused output
//! folder, a failed write, a full disk, and SIGTERM / SIGHUP, all through the command line.
use crate::cli::adaptcloth;
use std::process::Command;

/// `implicit_euler` on the hanging cloth at a fixed 4 ms, for 10 steps, into `out`, with more
/// `--set` options.
fn implicit_run(out: &std::path::Path, set: &[&str]) -> (i32, String) {
    let mut args = vec![
        "run",
        "hanging",
        "--integrator",
        "implicit_euler",
        "--set",
        "time.mode=\"fixed\"",
        "--set",
        "time.dt=0.004",
        "--duration",
        "0.04",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    for s in set {
        args.extend(["--set", s]);
    }
    adaptcloth(&args)
}

/// The `cg_unconverged` column of `metrics.csv` in `out`, one value per row.
fn unconverged_column(out: &std::path::Path) -> Vec<u64> {
    let text = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|c| *c == "cg_unconverged").unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

/// Issue 13: under `solver = "cg"` a solve that stops at its cap above tolerance is counted
/// (cumulative in metrics.csv, total in summary.json) and warned about once;
/// `on_unconverged = "fail"` ends the run as failed with what was written so far; converged
/// solves count nothing. Under `auto` the same capped solves are solved again by Cholesky: none
/// unconverged, no warning, the rescues counted in summary.json.
#[test]
fn unconverged_solves_are_counted_warned_about_once_or_fail_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let summary = |out: &std::path::Path| -> serde_json::Value {
        serde_json::from_str(&summary_of(out)).unwrap()
    };
    let fine = dir.path().join("fine");
    let (code, err) = implicit_run(&fine, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning"), "{err}");
    assert_eq!(summary(&fine)["cg_unconverged"], 0);
    assert_eq!(summary(&fine)["cholesky_rescues"], 0);
    assert_eq!(summary(&fine)["cholesky_switches"], 0);
    assert!(unconverged_column(&fine).iter().all(|&c| c == 0));

    let capped = dir.path().join("capped");
    let cg_capped = ["integrator.solver=\"cg\"", "integrator.cg_max_iterations=1"];
    let (code, err) = implicit_run(&capped, &cg_capped);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err.matches("warning").count(), 1, "{err}");
    assert!(
        err.contains("did not converge at step 1, t = 0.004000 s")
            && err.contains("integrator.cg_max_iterations = 1"),
        "{err}"
    );
    let column = unconverged_column(&capped);
    assert!(column.windows(2).all(|w| w[0] <= w[1]), "{column:?}");
    let s = summary(&capped);
    assert_eq!(s["status"], "completed");
    assert_eq!(s["cg_unconverged"], s["steps"], "every step capped");
    assert_eq!(Some(column[column.len() - 1]), s["cg_unconverged"].as_u64());

    let failed = dir.path().join("failed");
    let (code, err) = implicit_run(
        &failed,
        &[
            "integrator.solver=\"cg\"",
            "integrator.cg_max_iterations=1",
            "integrator.on_unconverged=\"fail\"",
        ],
    );
    assert_eq!(code, 1, "{err}");
    let s = summary(&failed);
    assert_eq!(s["status"], "failed");
    assert_eq!(s["steps"], 1);
    assert_eq!(s["cg_unconverged"], 1);
    let message = s["message"].as_str().unwrap();
    assert!(
        message.contains("did not converge at step 1")
            && message.contains("on_unconverged = \"fail\""),
        "{message}"
    );
    assert!(err.contains(message), "{err}");
    assert_eq!(unconverged_column(&failed).last(), Some(&1));
    assert!(failed.join("frames/frame_00000.obj").is_file());

    let rescued = dir.path().join("rescued");
    let (code, err) = implicit_run(
        &rescued,
        &[
            "integrator.solver=\"auto\"",
            "integrator.cg_max_iterations=1",
            "integrator.on_unconverged=\"fail\"",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning"), "{err}");
    let s = summary(&rescued);
    assert_eq!(
        (&s["status"], &s["cg_unconverged"]),
        (&"completed".into(), &0.into())
    );
    // Steps 1 and 10 (after a window of 8 straight to Cholesky) stop at the cap.
    assert_eq!(s["cholesky_rescues"], 2, "{s}");
    assert!(unconverged_column(&rescued).iter().all(|&c| c == 0));
}

fn summary_of(out: &std::path::Path) -> String {
    std::fs::read_to_string(out.join("summary.json")).unwrap()
}

/// A reused output folder: the run removes its own earlier frames and leftover temporary files,
/// never a file it did not write (issue 15: `frame_*.obj` of any name was deleted).
#[test]
fn a_run_removes_only_its_own_files_from_a_reused_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let frames = out.join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    let foreign = [
        "notes.txt",
        "other.tmp",
        "frames/frame_final.obj",
        "frames/frame_12.obj",
        "frames/notes.obj",
        "frames/frame_00009.obj.bak",
    ];
    let own = [
        "frames/frame_00009.obj",
        "frames/frame_00007.obj.tmp",
        "summary.json.tmp",
        "scene.resolved.toml.tmp",
    ];
    for f in foreign.iter().chain(&own) {
        std::fs::write(out.join(f), "x").unwrap();
    }
    let (code, err) = adaptcloth(&[
        "run",
        "--duration",
        "0.02",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    for f in foreign {
        assert!(out.join(f).is_file(), "{f} was removed");
    }
    for f in own {
        assert!(!out.join(f).exists(), "{f} was left");
    }
    assert!(frames.join("frame_00001.obj").is_file());
}

/// A write that fails during the run (here a folder stands where frame 1 goes) ends the run with
/// status `failed` naming the file, exit 1, the summary and the complete metrics on disk, and no
/// temporary file left behind; alike when the frames are written on the loop's thread (one
/// thread) and on another (two).
#[test]
fn a_failed_write_fails_the_run_with_a_clear_message() {
    for threads in ["1", "2"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("o");
        std::fs::create_dir_all(out.join("frames/frame_00001.obj")).unwrap();
        let (code, err) = adaptcloth(&[
            "--threads",
            threads,
            "run",
            "--duration",
            "0.05",
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        assert_eq!(code, 1, "{threads} threads: {err}");
        assert!(err.contains("frame_00001.obj failed at step"), "{err}");
        let summary = summary_of(&out);
        assert!(summary.contains("\"status\": \"failed\""), "{summary}");
        assert!(summary.contains("\"frames\": 1,"), "{summary}");
        assert!(out.join("metrics.csv").is_file());
        assert!(!out.join("frames/frame_00001.obj.tmp").exists());
    }
}

/// A full disk under the metrics table (its file is `/dev/full`): the run fails with the table's
/// name, and the torn table keeps its `.partial` name, so it never looks complete.
#[test]
fn a_full_disk_fails_the_run_and_leaves_no_torn_file_looking_complete() {
    if !std::path::Path::new("/dev/full").exists() {
        crate::common::say_skipped("no /dev/full on this system");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink("/dev/full", out.join("metrics.csv.partial")).unwrap();
    let (code, err) = adaptcloth(&[
        "run",
        "--duration",
        "0.05",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("metrics.csv.partial failed at step"), "{err}");
    assert!(summary_of(&out).contains("\"status\": \"failed\""));
    assert!(!out.join("metrics.csv").exists());
}

/// Starts a run of minutes (the hanging scene over 10 s of simulated time) into `out` and returns
/// once it is stepping (its metrics table exists, and 0.2 s more).
fn start_long_run(out: &std::path::Path) -> std::process::Child {
    let child = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(["run", "hanging", "--duration", "10", "--quiet", "--out"])
        .arg(out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("binary runs");
    let started = std::time::Instant::now();
    while !out.join("metrics.csv.partial").exists() {
        assert!(started.elapsed().as_secs() < 60, "the run did not start");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(200));
    child
}

/// Sends `signal` (`-INT`, `-TERM`, ...) to `child`.
fn send(signal: &str, child: &std::process::Child) {
    let sent = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
}

/// SIGTERM and SIGHUP stop a run like Ctrl-C: status `interrupted` in the summary, exit 130.
#[test]
fn sigterm_and_sighup_stop_a_run_cleanly() {
    for signal in ["-TERM", "-HUP"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("o");
        let mut child = start_long_run(&out);
        send(signal, &child);
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(130), "{signal}");
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        assert!(
            summary.contains("\"status\": \"interrupted\""),
            "{signal}: {summary}"
        );
        assert!(out.join("metrics.csv").is_file(), "{signal}");
    }
}

/// A study stopped while its reference runs exits as interrupted (130), not as failed, and
/// starts nothing after it.
#[test]
fn a_study_interrupted_during_its_reference_exits_130() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    // The quick study's reference, a 33x33 RK4 run of about 30 s.
    let child = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(["study", "--references-only", "--quiet", "--cache"])
        .arg(&cache)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("binary runs");
    let started = std::time::Instant::now();
    let metrics = |d: &std::path::Path| d.join("reference").join("metrics.csv.partial").exists();
    while !std::fs::read_dir(&cache)
        .ok()
        .and_then(|mut entries| entries.next())
        .and_then(|e| e.ok())
        .is_some_and(|e| metrics(&e.path()))
    {
        assert!(
            started.elapsed().as_secs() < 60,
            "the reference did not start"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
    let output = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    assert!(!err.contains("Interrupted: interrupted"), "{err}");
    // One job: the floor run comes after the reference, and an interrupted reference starts
    // no floor run.
    let entry = std::fs::read_dir(&cache).unwrap().next().unwrap().unwrap();
    assert!(!entry.path().join("floor").exists(), "{err}");
}

/// Two interrupts in quick succession are one: `timeout -s INT` signals the command and then its
/// process group, and the run must still stop cleanly (summary written, metrics renamed).
#[test]
fn two_signals_at_once_stop_a_run_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let mut child = start_long_run(&out);
    send("-INT", &child);
    send("-INT", &child);
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"interrupted\""), "{summary}");
    assert!(out.join("metrics.csv").is_file());
}

/// `summary.json` says where the run's command ran and how to run it alone again: the `rerun`
/// line (absolute paths, quoted where needed) gives the same metrics from another folder.
#[test]
fn a_runs_rerun_line_reproduces_it_from_anywhere() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("first run");
    let status = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(["run", "hanging", "--duration", "0.05", "--quiet", "--out"])
        .arg(&out)
        .current_dir(dir.path())
        .status()
        .expect("binary runs");
    assert!(status.success());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let cwd = summary["working_dir"].as_str().unwrap();
    assert_eq!(
        std::path::Path::new(cwd).canonicalize().unwrap(),
        dir.path().canonicalize().unwrap()
    );
    let rerun = summary["rerun"].as_str().unwrap();
    let program = std::path::Path::new(env!("CARGO_BIN_EXE_adaptcloth"));
    let (plain, quoted) = (
        format!("{} run ", program.display()),
        format!("'{}' run ", program.display()),
    );
    assert!(
        rerun.starts_with(&plain) || rerun.starts_with(&quoted),
        "the line names the program that ran: {rerun}"
    );
    // Run it as it is from another folder, through a shell (the line is a shell command).
    let elsewhere = tempfile::tempdir().unwrap();
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!("{rerun} --quiet"))
        .current_dir(elsewhere.path())
        .status()
        .expect("sh runs");
    assert!(status.success(), "{rerun}");
    let again = dir.path().join("first run-rerun");
    assert_eq!(
        std::fs::read(out.join("metrics.csv")).unwrap(),
        std::fs::read(again.join("metrics.csv")).unwrap(),
        "{rerun}"
    );
}
