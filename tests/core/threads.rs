//! `--threads`: a cloth large enough for chunked force sweeps (49 x 49 = 2,401 vertex slots: five
//! chunks of 512) and for triangular solves split over two threads gives the same frames and
//! metrics, byte for byte, on one thread and on two; a thread count of 0 is refused.
use crate::cli::adaptcloth;
use std::path::Path;

/// Runs the sphere scene at 49 x 49 for 0.05 s (implicit Euler, the default solver, fixed 2 ms) on
/// `threads` threads into `out`.
fn run_on(threads: &str, out: &Path) {
    let out = out.to_str().expect("a UTF-8 path");
    let (code, stderr) = adaptcloth(&[
        "--threads",
        threads,
        "run",
        "--quiet",
        "--integrator",
        "implicit_euler",
        "--duration",
        "0.05",
        "--set",
        "cloth.resolution=49",
        "--set",
        "time.mode=\"fixed\"",
        "--set",
        "time.dt=0.002",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
}

#[test]
fn one_thread_and_two_give_the_same_run_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    run_on("1", &one);
    run_on("2", &two);
    let read = |folder: &Path, file: &str| std::fs::read(folder.join(file)).unwrap();
    let metrics = read(&one, "metrics.csv");
    assert!(metrics.len() > 100);
    assert!(metrics == read(&two, "metrics.csv"), "metrics differ");
    let frames = |folder: &Path| {
        let mut names: Vec<_> = std::fs::read_dir(folder.join("frames"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        names
    };
    let names = frames(&one);
    assert!(names.len() >= 3, "{names:?}");
    assert_eq!(names, frames(&two));
    for name in names {
        let file = Path::new("frames").join(&name);
        let file = file.to_str().unwrap();
        assert!(read(&one, file) == read(&two, file), "{file} differs");
    }
}

#[test]
fn zero_threads_is_refused_with_the_option_named() {
    let (code, stderr) = adaptcloth(&["--threads", "0", "scenes"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--threads"), "{stderr}");
}

/// A study of two runs at a time on a pool of one thread (`--threads 1 --jobs 2`, as two cores
/// give): the runs' own threads must not hand work to the pool, whose one thread waits for them
/// (the self-intersection measure, split over 17x17's edges, hung here). Fails after two
/// minutes instead of hanging.
#[test]
fn a_study_on_a_pool_of_one_thread_finishes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args([
            "--threads",
            "1",
            "compare",
            "sphere",
            "--runs",
            "static@17,remesh",
        ])
        .args(["--integrators", "implicit_euler", "--ref-resolution", "17"])
        .args([
            "--floor-resolution",
            "9",
            "--samples",
            "8",
            "--duration",
            "0.1",
        ])
        .args(["--jobs", "2", "--quiet", "--out"])
        .arg(&out)
        .arg("--cache")
        .arg(dir.path().join("cache"))
        .stderr(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .spawn()
        .expect("binary runs");
    let started = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed().as_secs() > 120 {
            child.kill().unwrap();
            panic!("the study did not finish in two minutes");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    assert!(status.success(), "{status}");
}
