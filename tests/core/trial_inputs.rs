//! Bad input found by the trial report (a new user's hostile pass): each exits with status 2 and
//! a message naming the file, line and key (or the option), never a panic or a silent change.
use std::path::Path;
use std::process::Command;

/// Runs the binary in the folder `work` with `args`: its exit code and its standard error.
fn adaptcloth_in(work: &Path, args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .current_dir(work)
        .args(args)
        .output()
        .expect("binary runs");
    let text = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code().unwrap_or(-1), text)
}

const MESH_OBSTACLE: &str = "[time]\nduration = 0.01\n\n[[obstacles]]\nkind = \"mesh\"\nfile = ";

#[test]
fn trial_report_inputs_exit_2_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path();
    let write = |name: &str, bytes: &[u8]| std::fs::write(work.join(name), bytes).unwrap();
    // B6: an obstacle mesh that does not read is named by its key and line.
    write("bad.obj", b"v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    write("garbage.obj", &[0xff, 0xfe, 0x80, 0x00]);
    write(
        "bad.toml",
        format!("{MESH_OBSTACLE}\"bad.obj\"\n").as_bytes(),
    );
    write(
        "garbage.toml",
        format!("{MESH_OBSTACLE}\"garbage.obj\"\n").as_bytes(),
    );
    // A3: a section given as a list.
    write("seq.toml", b"time = [0.05]\n");
    // B7: an OBJ cloth of 4 vertices with room for 3.
    write(
        "square.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nf 1/1 2/2 3/3\nf 2/2 4/4 3/3\n",
    );
    write(
        "square.toml",
        b"[cloth]\nshape = \"obj\"\nmesh = \"square.obj\"\n[adaptivity]\nmax_vertices = 3\n",
    );
    // B8: a garbage file named like an embedded scene.
    write("sphere", &[0xff, 0xfe, 0x00]);
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["run", "bad.toml"],
            "bad.toml:6: obstacles.0.file = bad.obj: line 3: `f`",
        ),
        (
            vec!["run", "garbage.toml"],
            "garbage.toml:6: obstacles.0.file = garbage.obj: cannot read the OBJ file: stream did \
             not contain valid UTF-8",
        ),
        (
            vec!["run", "--set", "material=[1,2]"],
            "--set material=[1,2]: expected a section (a table of keys), not a list",
        ),
        (
            vec!["run", "--set", "cloth=[]"],
            "--set cloth=[]: expected a section (a table of keys), not a list",
        ),
        (
            vec!["run", "seq.toml"],
            "seq.toml:1: time = [0.05]: expected a section (a table of keys), not a list",
        ),
        (
            vec!["run", "--set", "adaptivity.max_vertices=1"],
            "--set adaptivity.max_vertices=1: expected at least the 25 vertices the cloth starts with",
        ),
        (
            vec!["run", "square.toml"],
            "square.toml:5: adaptivity.max_vertices = 3: expected at least the 4 vertices",
        ),
        (
            vec!["run", "sphere"],
            "is read instead of the embedded scene `sphere`",
        ),
        // C1: the static baseline reads no strategy-specific key.
        (
            vec!["run", "--set", "adaptivity.remesh_min_angle=10"],
            "strategy `static` ignores this key; it applies to remesh only",
        ),
        // C6: render writes PNG only.
        (
            vec!["render", "frame.obj", "--out", "r4.jpg"],
            "--out r4.jpg: expected a file name ending in .png",
        ),
    ];
    for (args, needle) in cases {
        let (code, err) = adaptcloth_in(work, &args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// A7: the embedded bunny scene runs from a folder without `scenes/`, its mesh read from the copy
/// built into the binary, and its resolved scene says so (and runs again).
#[test]
fn the_embedded_bunny_runs_without_the_source_tree() {
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path();
    let args = [
        "run",
        "bunny",
        "--duration",
        "0.002",
        "--quiet",
        "--out",
        "b",
    ];
    let (code, err) = adaptcloth_in(work, &args);
    assert_eq!(code, 0, "{err}");
    let resolved = std::fs::read_to_string(work.join("b/scene.resolved.toml")).unwrap();
    assert!(
        resolved.contains("file = \"<embedded>/meshes/bunny.obj\""),
        "{resolved}"
    );
    let again = ["run", "b/scene.resolved.toml", "--quiet", "--out", "again"];
    let (code, err) = adaptcloth_in(work, &again);
    assert_eq!(code, 0, "{err}");
}
