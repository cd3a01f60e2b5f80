//! `--threads`: a cloth large enough for chunked force sweeps (49 x 49 = 2,401 vertex slots: five
//! chunks of 512) gives the same frames and metrics, byte for byte, on one thread and on two; a
//! thread count of 0 is refused.
use crate::cli::adaptcloth;
use std::path::Path;

/// Runs the sphere scene at 49 x 49 for 0.05 s (implicit Euler, CG, fixed 2 ms) on `threads`
/// threads into `out`.
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
