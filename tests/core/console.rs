//! Status lines on a closed pipe (`adaptcloth scenes | true`, `run ... 2>&1 | head -1`): the
//! command does its work and exits with its usual code, never a panic (exit 101).
use std::io::Read;
use std::process::{Command, Stdio};

/// Runs the binary with `args`, its stdout a pipe whose read end is closed at once, and its
/// stderr too when `close_stderr` (else read to the end): its exit code and what it wrote on
/// stderr.
fn with_closed_stdout(args: &[&str], close_stderr: bool) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("binary runs");
    drop(child.stdout.take());
    let mut stderr = String::new();
    let pipe = child.stderr.take();
    if close_stderr {
        drop(pipe);
    } else if let Some(mut pipe) = pipe {
        pipe.read_to_string(&mut stderr).expect("stderr reads");
    }
    let status = child.wait().expect("binary ends");
    // A panic ends the process with 101; a signal (SIGPIPE not ignored) with no code.
    (status.code().unwrap_or(-1), stderr)
}

#[test]
fn a_closed_stdout_and_stderr_do_not_stop_a_command() {
    for close_stderr in [false, true] {
        let (code, err) = with_closed_stdout(&["scenes"], close_stderr);
        assert_eq!(code, 0, "{err}");
        assert!(!err.contains("panicked"), "{err}");
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("o");
        let run = ["run", "--duration", "0.02", "--out", out.to_str().unwrap()];
        let (code, err) = with_closed_stdout(&run, close_stderr);
        assert_eq!(code, 0, "{err}");
        assert!(!err.contains("panicked"), "{err}");
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        assert!(summary.contains("\"status\": \"completed\""), "{summary}");
        // An error is still an error: its line may be lost, its exit code is not.
        let (code, err) = with_closed_stdout(&["run", "--strategy", "magic"], close_stderr);
        assert_eq!(code, 2, "{err}");
    }
}
