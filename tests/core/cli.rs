//! The command line: bad input exits with status 2 and a clear message, never a panic.
use std::process::Command;

/// Runs the binary with `args`: its exit code and its standard error.
pub(crate) fn adaptcloth(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(args)
        .output()
        .expect("binary runs");
    let text = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code().unwrap_or(-1), text)
}

#[test]
fn bad_input_exits_2_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[material]\nrho = -5.0\n").unwrap();
    let typo = dir.path().join("typo.toml");
    std::fs::write(&typo, "[cloth]\nresolution = 5\nresolutoin = 6\n").unwrap();
    let missing_mesh = dir.path().join("mesh.toml");
    std::fs::write(
        &missing_mesh,
        "[[obstacles]]\nkind = \"mesh\"\nfile = \"gone.obj\"\n",
    )
    .unwrap();
    let boxed = dir.path().join("box.toml");
    std::fs::write(
        &boxed,
        "[[obstacles]]\nkind = \"box\"\ncenter = [0.0, 0.0, 0.0]\nhalf_extents = [0.1, nan, 0.1]\n",
    )
    .unwrap();
    let box_nan = ["run", boxed.to_str().unwrap()];
    let box_ok = dir.path().join("box_ok.toml");
    std::fs::write(
        &box_ok,
        "[[obstacles]]\nkind = \"box\"\ncenter = [0.0, 0.0, 0.0]\nhalf_extents = [0.1, 0.1, 0.1]\n",
    )
    .unwrap();
    let box_huge = [
        "run",
        box_ok.to_str().unwrap(),
        "--set",
        "obstacles.0.half_extents=[1e308, 1e308, 1e308]",
    ];
    // The file must be valid as written, also where an option replaces its value (trial report
    // B1: a NaN duration under --duration ran).
    let dur_nan = dir.path().join("dur_nan.toml");
    std::fs::write(&dur_nan, "[time]\nduration = nan\n").unwrap();
    let dur_replaced = ["run", dur_nan.to_str().unwrap(), "--duration", "0.02"];
    let dur_set = [
        "run",
        dur_nan.to_str().unwrap(),
        "--set",
        "time.duration=0.02",
    ];
    let empty = dir.path().join("empty.toml");
    std::fs::write(&empty, "# nothing\n\n").unwrap();
    // A file where the output folder should be, or one of its parents.
    let file_out = empty.to_str().unwrap();
    let docs = dir.path().join("docs");
    let docs_dir = docs.to_str().unwrap();
    let under_file = format!("{file_out}/x.md");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["run", "--out", file_out], "it is a file, not a folder"),
        (vec!["study", "--out", file_out], "is a file, not a folder"),
        (vec!["study", "--jobs", "0"], "0 is not in 1..=1024"),
        (vec!["reference", "--jobs", "0"], "0 is not in 1..=1024"),
        (vec!["run", bad.to_str().unwrap()], "material.rho"),
        (vec!["run", typo.to_str().unwrap()], "resolutoin"),
        (vec!["run", missing_mesh.to_str().unwrap()], "gone.obj"),
        (vec!["run", "no_such_scene"], "no such file"),
        (vec!["run", "--strategy", "magic"], "bisect48"),
        (vec!["run", "--integrator", "leapfrog"], "symplectic_euler"),
        (vec!["run", "--set", "cloth.nokey=1"], "cloth.nokey"),
        (vec!["run", "--set", "time.dt=0"], "time.dt"),
        (
            vec!["run", "--set", "cloth.resolution=1"],
            "cloth.resolution",
        ),
        (
            vec!["run", "--duration=-1"],
            "--duration -1: expected a finite value > 0",
        ),
        // A negative value after a space is the option's value, not an unknown option.
        (
            vec!["run", "--duration", "-1"],
            "--duration -1: expected a finite value > 0",
        ),
        (
            vec!["render", "/dev/zero", "--width", "0"],
            "invalid value '0' for '--width <WIDTH>': 0 is not in 1..=16384",
        ),
        (
            vec!["study", "scenes/sphere.toml"],
            "this looks like a scene file",
        ),
        (vec!["run", "studies/quick.toml"], "this looks like a study file"),
        // Found by the hostile sweep after issue 15: allocation aborts and endless reads.
        (
            vec![
                "compare",
                "--ref-resolution",
                "100000",
                "--out",
                "/nonexistent/o",
            ],
            "invalid value '100000' for '--ref-resolution <REF_RESOLUTION>': 100000 is not in 2..=2000",
        ),
        (
            vec![
                "compare",
                "--samples",
                "100000000",
                "--out",
                "/nonexistent/o",
            ],
            "invalid value '100000000' for '--samples <SAMPLES>': 100000000 is not in 2..=1000",
        ),
        (vec!["run", "/dev/zero"], "not a regular file"),
        (vec!["study", "/dev/zero"], "not a regular file"),
        (
            vec!["compare", "--docs-notes", "/dev/zero", "--write-docs", docs_dir],
            "not a regular file",
        ),
        // Options that only mean something with --write-docs were ignored without it.
        (
            vec!["report", "out", "--docs-notes", "notes.md"],
            "--write-docs <DIR>",
        ),
        (
            vec!["integrators", "--docs", "docs/x.md"],
            "--write-docs",
        ),
        (
            vec!["render", "/dev/zero", "--out", "/nonexistent/x.png"],
            "not a regular file",
        ),
        (
            vec!["frame-diff", "/dev/zero", "/dev/zero"],
            "not a regular file",
        ),
        // Raw system errors, or nothing to go on (the hostile sweep of 2026-11-29).
        (
            vec!["stability", "--quick", "--out", &under_file],
            "cannot create its folder: it is a file, not a folder",
        ),
        (
            vec!["integrators", "--write-docs", "--docs", "/nonexistent/i.md"],
            "--docs /nonexistent/i.md",
        ),
        (
            vec!["run", "--set", "cloth.resolution.x=5"],
            "none (cloth.resolution is a value, not a section)",
        ),
        // Accepted, then diverged at the first step (the hostile sweep of 2026-11-29).
        (
            vec!["run", "--set", "cloth.velocity=[0, 0, 1e10]"],
            "cloth.velocity=[0, 0, 1e10]: expected a speed below time.max_speed",
        ),
        (
            vec!["run", "hanging", "--set", "cloth.pinned_velocity=[[0, 0, 1e300]]"],
            "cloth.pinned_velocity.0",
        ),
        // The speed bound's own mistake is said before the speeds measured against it.
        (
            vec!["run", "--set", "time.max_speed=nan"],
            "--set time.max_speed=nan: expected a finite value > 0",
        ),
        (
            vec!["run", "--set", "adaptivity.max_depth=4294967296"],
            "expected a whole number from 0 to 4294967295",
        ),
        // Two pins on one vertex with different velocities: one of them won silently.
        (
            vec![
                "run",
                "hanging",
                "--set",
                "cloth.pinned=[[0.5, 1.0], [0.5, 1.0]]",
                "--set",
                "cloth.pinned_velocity=[[0, 0, 0], [0, 0, 1]]",
            ],
            "expected a point of its own: it pins the vertex cloth.pinned[0] pins",
        ),
        (
            vec!["run", "--set", "forces.g=[0, 0, 1e300]"],
            "expected an acceleration of at most 1e4 m/s²",
        ),
        (
            vec!["run", "--set", "cloth.center=[1e300, 0, 0]"],
            "expected three finite coordinates within ±1e6 m",
        ),
        // The sizing criteria on a run that never adapts (the scene says static).
        (
            vec!["run", "--set", "adaptivity.criteria=\"sizing\""],
            "strategy `static` never adapts the mesh",
        ),
        // Values that passed validation and panicked later (issue 15, defect 1).
        (vec!["run", "--set", "cloth.size=[1.0, nan]"], "cloth.size"),
        (vec!["run", "--set", "cloth.size=[1.0, inf]"], "cloth.size"),
        (
            vec!["run", "--set", "cloth.size=[1e308, 1e308]"],
            "cloth.size",
        ),
        (
            vec!["run", "--set", "cloth.size=[1e-200, 1e-200]"],
            "cloth.size",
        ),
        (box_nan.as_slice().to_vec(), "half_extents"),
        (
            dur_replaced.as_slice().to_vec(),
            "dur_nan.toml:2: time.duration = NaN: expected a finite value > 0",
        ),
        (
            dur_set.as_slice().to_vec(),
            "dur_nan.toml:2: time.duration = NaN: expected a finite value > 0",
        ),
        // The hostile sweep: a huge box passed `> 0` and panicked in the contact query.
        (
            box_huge.as_slice().to_vec(),
            "half_extents=[1e308, 1e308, 1e308]: expected a length in (0, 1e6] m",
        ),
        (vec!["run", empty.to_str().unwrap()], "sets nothing"),
        // Two scenes of one name would share a folder (trial report A2).
        (
            vec!["compare", "sphere", "sphere", "--out", "/nonexistent/o"],
            "scene 1 = \"sphere\" (<embedded sphere>, named `sphere`) and scene 2 = \"sphere\" \
             (<embedded sphere>, named `sphere`) would write to the same folder /nonexistent/o/sphere",
        ),
        // Runs that would never finish (issue 15, defect 3).
        (
            vec!["run", "--set", "time.metrics_rate=1e20"],
            "metrics rows",
        ),
        (vec!["run", "--set", "time.frame_rate=1e9"], "frames"),
        (
            vec![
                "run",
                "--set",
                "time.mode=\"fixed\"",
                "--set",
                "time.dt=1e-300",
            ],
            "steps",
        ),
        (
            vec!["run", dir.path().to_str().unwrap()],
            "cannot read scene file",
        ),
        // A dynamic step that makes the run endless (issue 15): refused with the estimate.
        (
            vec!["run", "--set", "material.E=1e308"],
            "capped by the damping and bending stability limit (1.915e-304 s",
        ),
        (
            vec!["run", "--set", "time.dt_initial=1e-300"],
            "time.dt_initial = 1e-300 s until the first contact",
        ),
        // Caps on growth and on the loops inside one step (issue 15).
        (
            vec!["run", "--set", "adaptivity.max_vertices=0"],
            "adaptivity.max_vertices",
        ),
        (
            vec!["run", "--set", "integrator.relaxation_passes=1000000000000"],
            "expected at most 1000 passes per step",
        ),
        (
            vec!["run", "--set", "integrator.cg_max_iterations=1000000000000"],
            "expected 1 to 10000 iterations per step",
        ),
        (
            vec!["run", "--set", "integrator.on_unconverged=\"loud\""],
            "in `integrator.on_unconverged`",
        ),
        // Sizes that aborted allocating or wrapped (issue 15): refused with the memory they need.
        (
            vec!["run", "--set", "cloth.resolution=100000"],
            "1.024e4 GB of memory; at most 4000000 vertices",
        ),
        (
            vec!["run", "--set", "cloth.resolution=9223372036854775807"],
            "more vertices than this machine can count",
        ),
        (
            vec!["run", "--set", "cloth.resolution_v=100000000"],
            "--set cloth.resolution_v=100000000: a 5 x 100000000 grid",
        ),
        (
            vec![
                "run",
                "--set",
                "cloth.shape=\"disk\"",
                "--set",
                "cloth.resolution=9223372036854775807",
            ],
            "a disk of 9223372036854775807 rings has more vertices",
        ),
    ];
    for (args, needle) in cases {
        let (code, err) = adaptcloth(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// `--force` runs what the step estimate refuses: here a run of 1e-300 s steps (stopped by
/// Ctrl-C once it has started).
#[test]
fn force_runs_a_run_refused_by_the_step_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let mut args = vec![
        "run",
        "--set",
        "time.dt_initial=1e-300",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    let (code, err) = adaptcloth(&args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--force runs it anyway"), "{err}");
    assert!(!out.join("summary.json").exists());
    args.push("--force");
    let (code, err) = super::common::interrupted_once(&args, &out.join("metrics.csv.partial"));
    assert_eq!(code, 130, "{err}");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"interrupted\""), "{summary}");
}

/// A folder named like an embedded scene does not hide it (only a file does): `mkdir sphere;
/// adaptcloth run sphere` said "sphere is a folder".
#[test]
fn a_folder_named_like_an_embedded_scene_does_not_hide_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("sphere")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .current_dir(dir.path())
        .args([
            "run",
            "sphere",
            "--duration",
            "0.01",
            "--quiet",
            "--out",
            "o",
        ])
        .output()
        .expect("binary runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let summary = std::fs::read_to_string(dir.path().join("o/summary.json")).unwrap();
    assert!(summary.contains("<embedded sphere>"), "{summary}");
}

#[test]
fn run_writes_outputs_and_exits_0() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let (code, err) = adaptcloth(&[
        "run",
        "--duration",
        "0.02",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.join("summary.json").is_file());
    assert!(out.join("metrics.csv").is_file());
    assert!(out.join("frames/frame_00001.obj").is_file());
    // The run records what it ran: the resolved scene (loadable on its own), the command and
    // the version.
    let resolved = out.join("scene.resolved.toml");
    let text = std::fs::read_to_string(&resolved).unwrap();
    assert!(
        text.contains("# Command: ") && text.contains("--duration 0.02"),
        "{text}"
    );
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"version\": \"") && summary.contains("--duration 0.02"),
        "{summary}"
    );
    let again = dir.path().join("again");
    let (code, err) = adaptcloth(&[
        "run",
        resolved.to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read(out.join("frames/frame_00001.obj")).unwrap(),
        std::fs::read(again.join("frames/frame_00001.obj")).unwrap(),
        "re-running the resolved scene gives the same frames"
    );
    // `render` finds the scene (and so the sphere) from the run's folder, and creates the
    // folder of its picture.
    let with = dir.path().join("with.png");
    let without = dir.path().join("new/folder/without.png");
    let frame = out.join("frames/frame_00001.obj");
    let frame = frame.to_str().unwrap();
    let (code, err) = adaptcloth(&["render", frame, "--out", without.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = adaptcloth(&[
        "render",
        frame,
        "--out",
        with.to_str().unwrap(),
        "--scene",
        "sphere",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read(with).unwrap(),
        std::fs::read(without).unwrap()
    );
}

#[test]
fn an_error_in_a_command_line_value_names_the_option_not_a_scene_line() {
    for (args, option) in [
        (
            vec!["run", "--set", "material.rho=-1"],
            "--set material.rho=-1",
        ),
        (vec!["run", "--strategy", "magic"], "--strategy magic"),
        (vec!["run", "--duration=-1"], "--duration -1"),
    ] {
        let (code, err) = adaptcloth(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains(&format!("error: {option}:")),
            "{args:?}: {err}"
        );
        assert!(!err.contains("embedded"), "{args:?}: {err}");
    }
    // A value from the file still names the file and its line.
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[material]\nrho = -5.0\n").unwrap();
    let (code, err) = adaptcloth(&["run", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.toml:2: material.rho"), "{err}");
    std::fs::write(
        &bad,
        "[integrator]\nname = \"implicit_euler\"\non_unconverged = \"loud\"\n",
    )
    .unwrap();
    let (code, err) = adaptcloth(&["run", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("bad.toml: TOML parse error at line 3")
            && err.contains("expected `warn` or `fail`"),
        "{err}"
    );
}

/// Mistakes inside `[[obstacles]]` name the key and its own line (the parser gave the header's
/// line and no key); points off the cloth and mesh paths that are folders or devices say so with
/// their line (issue 15).
#[test]
fn errors_name_the_key_and_its_own_line() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = "[cloth]\nresolution = 5\n\n[[obstacles]]\nkind = \"sphere\"\n";
    let cases = [
        (
            format!("{sphere}center = [0.0, 0.0, 0.0]\nradius = \"big\"\n"),
            ":7: obstacles.0.radius = \"big\": invalid type: string \"big\", expected a number",
        ),
        (
            format!("{sphere}center = [0.0, 0.0, 0.0]\nradius = 1.0\nfoo = 2\n"),
            ":8: obstacles.0.foo = 2: no such key for this kind; valid keys: center, friction",
        ),
        (
            format!("{sphere}center = [0.0, 0.0]\nradius = 1.0\n"),
            ":6: obstacles.0.center = [0.0, 0.0]: invalid length 2",
        ),
        (
            "[[obstacles]]\nkind = \"ground\"\n[[obstacles]]\nkind = \"blob\"\n".to_string(),
            ":4: obstacles.1.kind = \"blob\": expected one of: \"ground\", \"sphere\"",
        ),
        (
            "[[obstacles]]\nkind = \"mesh\"\nfile = \"/dev/null\"\n".to_string(),
            ":3: obstacles.0.file = /dev/null: expected an existing OBJ file (/dev/null is not a \
             regular file",
        ),
        (
            "[[obstacles]]\nkind = \"mesh\"\nfile = \"/tmp\"\n".to_string(),
            ":3: obstacles.0.file = /tmp: expected an existing OBJ file (/tmp is a folder)",
        ),
        (
            "[cloth]\nshape = \"obj\"\nmesh = \"/tmp\"\n".to_string(),
            ":3: cloth.mesh = /tmp: expected an existing OBJ file (/tmp is a folder)",
        ),
        (
            "[cloth]\nresolution = 5\npinned = [[0.0, 0.0], [5.0, 5.0]]\n".to_string(),
            ":3: cloth.pinned[1] = [5, 5]: expected a rest point on the cloth pattern",
        ),
        (
            "[cloth]\nresolution = 5\n\n[[tracked]]\nname = \"far\"\nrest = [9.0, 9.0]\n"
                .to_string(),
            ":6: tracked.0.rest = [9, 9]: expected a rest point on the cloth pattern",
        ),
    ];
    for (k, (text, needle)) in cases.iter().enumerate() {
        let file = dir.path().join(format!("s{k}.toml"));
        std::fs::write(&file, text).unwrap();
        let (code, err) = adaptcloth(&["run", file.to_str().unwrap()]);
        assert_eq!(code, 2, "{text}: {err}");
        let expected = format!("{}{needle}", file.display());
        assert!(
            err.contains(&expected),
            "{text}\nexpected {expected}\ngot {err}"
        );
    }
    // The same from the command line names the option.
    for (args, needle) in [
        (
            ["run", "--set", "obstacles.0.radius=\"big\""],
            "--set obstacles.0.radius=\"big\": invalid type",
        ),
        (
            ["run", "--set", "cloth.pinned=[[5.0, 5.0]]"],
            "--set cloth.pinned=[[5.0, 5.0]]: cloth.pinned[0] = [5, 5]: expected a rest point",
        ),
    ] {
        let (code, err) = adaptcloth(&args);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// An unwritable report path is refused at once (exit 2, naming `--out`), not after the suite.
#[test]
fn stability_refuses_an_unwritable_report_before_running() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("a_folder");
    std::fs::create_dir(&folder).unwrap();
    let file = dir.path().join("a_file");
    std::fs::write(&file, "x").unwrap();
    for out in [folder.clone(), file.join("report.md")] {
        let started = std::time::Instant::now();
        let (code, err) = adaptcloth(&["stability", "--out", out.to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("--out"), "{err}");
        assert!(
            !err.contains("adaptcloth stability:"),
            "the suite ran: {err}"
        );
        assert!(started.elapsed().as_secs() < 30);
    }
}

#[test]
fn stability_quick_writes_outside_docs_and_its_exit_status_says_whether_a_case_failed() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
            .args(args)
            .current_dir(dir.path())
            .output()
            .expect("binary runs")
    };
    // An unknown strategy is refused before anything runs.
    let refused = run(&["stability", "--quick", "--strategy", "magic"]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("bisect48"));
    // One strategy (the whole quick suite is tests/stability.rs's work).
    let out = run(&["stability", "--quick", "--strategy", "static"]);
    let report = dir.path().join("out/stability-quick-static.md");
    assert!(report.is_file(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        !dir.path().join("docs").exists(),
        "--quick wrote into docs/"
    );
    let text = std::fs::read_to_string(report).unwrap();
    assert!(text.contains("Strategies: static."), "{text}");
    // The report ends with "N case(s) failed. Suite wall time ...".
    let failed: usize = text
        .lines()
        .find(|l| l.contains(" case(s) failed."))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .expect("the report counts its failures");
    let code = out.status.code().unwrap_or(-1);
    assert_eq!(
        code,
        if failed > 0 { 1 } else { 0 },
        "{failed} failed, exit {code}"
    );
}
