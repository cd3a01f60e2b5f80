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
            "a grid may have at most 4000000 vertices",
        ),
        (
            vec![
                "compare",
                "--samples",
                "100000000",
                "--out",
                "/nonexistent/o",
            ],
            "the sample grid at most 1000 points per side",
        ),
        (vec!["run", "/dev/zero"], "not a regular file"),
        (vec!["study", "/dev/zero"], "not a regular file"),
        (
            vec!["compare", "--docs-notes", "/dev/zero"],
            "not a regular file",
        ),
        (
            vec!["render", "/dev/zero", "--out", "/nonexistent/x.png"],
            "not a regular file",
        ),
        (
            vec!["frame-diff", "/dev/zero", "/dev/zero"],
            "not a regular file",
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

/// `--force` runs what the step estimate refuses: here a run of 1e-300 s steps that stops at
/// its first step (the cloth starts faster than `time.max_speed`).
#[test]
fn force_runs_a_run_refused_by_the_step_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let mut args = vec![
        "run",
        "--set",
        "time.dt_initial=1e-300",
        "--set",
        "cloth.velocity=[0.0, 0.0, 1.0]",
        "--set",
        "time.max_speed=0.5",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    let (code, err) = adaptcloth(&args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--force runs it anyway"), "{err}");
    assert!(!out.join("summary.json").exists());
    args.push("--force");
    let (code, err) = adaptcloth(&args);
    assert_eq!(code, 1, "{err}");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"diverged\""), "{summary}");
}

/// `study --force` and `compare --force` run what the step estimate refuses, run by run; the
/// reference is checked whatever `--force` says.
#[test]
fn study_and_compare_force_reaches_every_run_but_not_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("f.toml");
    std::fs::write(
        &file,
        "scenes = [\"sphere\"]\nduration = 0.02\n[reference]\nresolution = 5\nfloor = 3\n\
         samples = 4\n[[runs]]\nstrategy = \"static\"\nresolution = 3\nset = { \
         \"time.dt_initial\" = 1e-300, \"cloth.velocity\" = [0.0, 0.0, 1.0], \
         \"time.max_speed\" = 0.5 }\n",
    )
    .unwrap();
    let (out, cache) = (dir.path().join("o"), dir.path().join("cache"));
    let mut args = vec![
        "study",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
        "--quiet",
    ];
    let (code, err) = adaptcloth(&args);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("run static-3-rk4: this run would take"),
        "{err}"
    );
    assert!(err.contains("--force runs it anyway"), "{err}");
    assert!(!cache.exists(), "nothing runs before the check");
    args.push("--force");
    let (code, err) = adaptcloth(&args);
    assert_eq!(code, 0, "{err}");
    let summary = std::fs::read_to_string(out.join("sphere/runs/static-3-rk4/summary.json"));
    assert!(summary.unwrap().contains("\"status\": \"diverged\""));
    for command in ["study", "compare"] {
        let help = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
            .args([command, "--help"])
            .output()
            .unwrap();
        let help = String::from_utf8_lossy(&help.stdout).into_owned();
        assert!(
            help.lines()
                .any(|l| l.trim() == "--force" || l.trim().starts_with("--force ")),
            "{command}: {help}"
        );
    }
    let (code, err) = adaptcloth(&[
        "compare",
        "--runs",
        "static@3",
        "--set",
        "material.E=1e308",
        "--ref-resolution",
        "5",
        "--floor-resolution",
        "3",
        "--cache",
        cache.to_str().unwrap(),
        "--out",
        dir.path().join("c").to_str().unwrap(),
        "--force",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("the reference run of <embedded sphere> (not covered by --force)"),
        "{err}"
    );
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
    // `render` finds the scene (and so the sphere) from the run's folder.
    let with = dir.path().join("with.png");
    let without = dir.path().join("without.png");
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

/// An integrator stable at any step on its scene's dynamic step (set by the explicit
/// integrators' stability) is told so, with how to fix the step, by `run` and by a study (naming
/// the run); nothing is said on a fixed step or for an explicit integrator.
#[test]
fn implicit_runs_on_the_dynamic_step_are_told_how_to_take_large_steps() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let out = out.to_str().unwrap();
    let note = "takes the scene's dynamic step";
    let run = |extra: &[&str]| {
        let mut args = vec!["run", "--quiet", "--duration", "0.01", "--out", out];
        args.extend_from_slice(extra);
        let (code, err) = adaptcloth(&args);
        assert_eq!(code, 0, "{err}");
        err
    };
    let err = run(&["--integrator", "implicit_euler"]);
    assert!(
        err.contains(note) && err.contains("--set time.mode=fixed"),
        "{err}"
    );
    assert!(run(&["--integrator", "bdf2"]).contains(note));
    let fixed = ["--set", "time.mode=fixed", "--set", "time.dt=0.002"];
    let err = run(&[&["--integrator", "implicit_euler"][..], &fixed[..]].concat());
    assert!(!err.contains(note), "{err}");
    let err = run(&["--integrator", "rk4"]);
    assert!(!err.contains(note), "{err}");

    let args = small_study(
        dir.path(),
        "duration = 0.01",
        "[[runs]]\nstrategy = \"static\"\nintegrator = \"implicit_euler\"\nresolution = 5\n\
         [[runs]]\nlabel = \"fixed\"\nstrategy = \"static\"\nintegrator = \"implicit_euler\"\n\
         resolution = 5\ndt = 0.002\n",
    );
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    let line = err
        .lines()
        .find(|l| l.contains("take the scene's dynamic step"))
        .expect("a note");
    assert!(line.contains("static-5-implicit_euler"), "{line}");
    assert!(!line.contains("fixed-5"), "{line}");
}

/// A reference to compute is announced, with its grids and step counts, before it is computed;
/// once cached, it is not.
#[test]
fn a_reference_to_compute_is_announced_before_it_runs() {
    let dir = tempfile::tempdir().unwrap();
    let args = small_study(
        dir.path(),
        "duration = 0.01",
        "[[runs]]\nstrategy = \"static\"\nresolution = 5\n",
    );
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    let announced = err
        .lines()
        .position(|l| l.contains("computing static 9x9") && l.contains("floor 5x5"))
        .expect("the reference announced");
    let done = err
        .lines()
        .position(|l| l.starts_with("reference sphere: static 9x9"))
        .expect("the reference reported");
    assert!(announced < done, "{err}");
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("computing static"), "{err}");
}

/// A study's pages are the ones `adaptcloth report` makes from its folder afterwards: made from
/// the tables as written, not from the unrounded numbers in memory.
#[test]
fn report_on_a_study_folder_rewrites_the_same_pages() {
    let dir = tempfile::tempdir().unwrap();
    let args = small_study(
        dir.path(),
        "duration = 0.02",
        "[[runs]]\nstrategy = \"static\"\nsweep = { \"cloth.resolution\" = [3, 5] }\n\
         [[runs]]\nstrategy = \"bisect48\"\nresolution = 3\n",
    );
    let out = dir.path().join("out");
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    let folder = out.join("sphere");
    let read = |f: &str| std::fs::read(folder.join(f)).unwrap();
    let (report, table) = (read("report.md"), read("comparison.csv"));
    let (code, err) = adaptcloth(&["report", folder.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(read("report.md") == report, "report.md differs");
    assert!(read("comparison.csv") == table, "comparison.csv differs");
}

/// A study-wide `h_min` reaches every run, its static baseline included, which ignores it; a
/// run on its own with `h_min` and the static strategy runs, told that `h_min` is ignored, and
/// so does its rerun line (its resolved scene keeps `h_min`).
#[test]
fn a_study_wide_h_min_leaves_its_static_baseline_alone() {
    let dir = tempfile::tempdir().unwrap();
    let alone = dir.path().join("alone");
    let (code, err) = adaptcloth(&[
        "run",
        "--quiet",
        "--duration",
        "0.01",
        "--set",
        "adaptivity.h_min=0.03",
        "--out",
        alone.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("adaptivity.h_min = 0.03 is ignored") && err.contains("--strategy bisect48"),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(alone.join("summary.json")).unwrap())
            .unwrap();
    let rerun = summary["rerun"].as_str().unwrap();
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!("{rerun} --quiet"))
        .stderr(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "{rerun}");

    let args = small_study(
        dir.path(),
        "duration = 0.01\nset = { \"adaptivity.h_min\" = 0.03 }",
        "[[runs]]\nstrategy = \"static\"\nresolution = 5\n\
         [[runs]]\nstrategy = \"bisect48\"\nresolution = 5\n",
    );
    let out = dir.path().join("out");
    let (code, err) = adaptcloth(&strs(&args));
    assert_eq!(code, 0, "{err}");
    let table = std::fs::read_to_string(out.join("sphere/comparison.csv")).unwrap();
    assert_eq!(table.matches(",completed,").count(), 2, "{table}");
}

/// Writes `DIR/s.toml`, a study of the sphere with a 9x9 reference and a 5x5 floor, its
/// top-level keys `top` (`duration = ...` first) and its `[[runs]]` entries `runs`; the
/// arguments that run it quietly into `DIR/out`, its references cached in `DIR/cache`.
fn small_study(dir: &std::path::Path, top: &str, runs: &str) -> Vec<String> {
    let study = dir.join("s.toml");
    let text = format!(
        "name = \"s\"\ndescription = \"d\"\nscenes = [\"sphere\"]\n{top}\n\
         [reference]\nresolution = 9\nfloor = 5\n{runs}"
    );
    std::fs::write(&study, text).unwrap();
    let path = |p: std::path::PathBuf| p.to_str().unwrap().to_string();
    vec![
        "study".into(),
        path(study),
        "--quiet".into(),
        "--out".into(),
        path(dir.join("out")),
        "--cache".into(),
        path(dir.join("cache")),
    ]
}

/// `args` as the string slices [`adaptcloth`] takes.
fn strs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}
