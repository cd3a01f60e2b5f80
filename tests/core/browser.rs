//! The HTML report in a real browser: a report built from real frames of a tiny run loads in
//! headless Chromium without script errors and draws its 3D replay.
//!
//! Skipped (with a clear message) when no Chromium is installed, except under CI (`CI=true`),
//! where a missing browser fails the test: `.ci/run` installs Debian's `chromium`.
use crate::common::{run_into, scene};
use adaptcloth::report::html::{write_report_html, HtmlSection, ReplayRun};
use adaptcloth::report::render::{self, FrameMesh, SnapshotRow};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The Chromium executable: `$CHROMIUM`, `/usr/bin/chromium`, or `chromium` /
/// `chromium-browser` on `PATH`.
fn find_chromium() -> Option<PathBuf> {
    let mut candidates: Vec<PathBuf> = std::env::var_os("CHROMIUM")
        .map(PathBuf::from)
        .into_iter()
        .collect();
    candidates.push(PathBuf::from("/usr/bin/chromium"));
    if let Some(path) = std::env::var_os("PATH") {
        for dir in std::env::split_paths(&path) {
            candidates.push(dir.join("chromium"));
            candidates.push(dir.join("chromium-browser"));
        }
    }
    candidates.into_iter().find(|p| p.is_file())
}

/// Runs headless Chromium on `page` with `extra` arguments; returns its standard output.
fn chromium(browser: &Path, profile: &Path, page: &Path, extra: &[&str]) -> String {
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-dev-shm-usage",
            "--virtual-time-budget=5000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("chromium starts");
    assert!(
        out.status.success(),
        "chromium failed: {}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Frames of a 5x5 run of the embedded scene `name` for 0.05 s (a frame every 0.01 s) with
/// their times.
/// The replay's status line in a dumped DOM and the triangles it drew; fails on a missing
/// status, an undrawn replay or any script error.
fn replay_status(dom: &str) -> (String, usize) {
    let status = dom
        .split("<pre id=\"status\">")
        .nth(1)
        .and_then(|s| s.split("</pre>").next())
        .unwrap_or_else(|| panic!("no status element in the DOM:\n{dom}"));
    assert!(status.contains("errors: 0"), "script errors: {status}");
    let drawn: usize = status
        .strip_prefix("drawn ")
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("replay not drawn: {status}"));
    (status.to_string(), drawn)
}

fn tiny_run(dir: &Path, name: &str) -> (Vec<f64>, Vec<FrameMesh>) {
    let loaded = scene(
        name,
        &[
            "cloth.resolution=5",
            "time.duration=0.05",
            "time.frame_rate=100",
        ],
    );
    run_into(&loaded, dir);
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    paths.sort();
    let times = paths
        .iter()
        .map(|p| {
            adaptcloth::io::read_frame_time(p)
                .unwrap()
                .expect("frame time")
        })
        .collect();
    let frames = paths.iter().map(|p| FrameMesh::read(p).unwrap()).collect();
    (times, frames)
}

#[test]
fn report_html_loads_without_errors_and_draws_the_replay_in_chromium() {
    let Some(browser) = find_chromium() else {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!(
                "no chromium found under CI: .ci/run must install it (apt-get install chromium)"
            );
        }
        crate::common::say_skipped("no chromium found (/usr/bin/chromium or on PATH); install it with `apt-get install -y chromium` to run this test");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let run_dir = dir.path().join("run");
    let (times, frames) = tiny_run(&run_dir, "sphere");
    assert!(frames.len() >= 3, "{} frames", frames.len());
    let loaded = scene("sphere", &[]);
    let obstacles = render::obstacle_meshes(&loaded.scene.obstacles, &loaded.base_dir).unwrap();
    let grid = dir.path().join("grid.png");
    let row = SnapshotRow {
        label: "static 5x5".into(),
        frames: vec![
            (times[0], frames[0].clone()),
            (times[times.len() - 1], frames[frames.len() - 1].clone()),
        ],
    };
    render::snapshot_grid(&[row], &obstacles, &grid).unwrap();
    let sections = [HtmlSection {
        title: "Summary".into(),
        markdown: "A tiny run.\n\n| run | frames |\n|---|--:|\n| static 5x5 | 6 |\n".into(),
        images: vec![grid],
    }];
    let cloth_triangles = frames[0].faces.len();
    let replays = [
        ReplayRun {
            label: "static 5x5".into(),
            frame_times: times.clone(),
            frames: frames.clone(),
        },
        ReplayRun {
            label: "copy".into(),
            frame_times: times,
            frames,
        },
    ];
    let page = dir.path().join("report.html");
    write_report_html(
        &page,
        "Browser test report",
        &sections,
        &replays,
        &obstacles,
    )
    .unwrap();

    let profile = tempfile::tempdir().unwrap();
    let dom = chromium(&browser, profile.path(), &page, &["--dump-dom"]);
    let (status, drawn) = replay_status(&dom);
    // The cloth and at least the visible half of the sphere.
    assert!(drawn > cloth_triangles, "{status}");
    assert!(dom.contains("<title>Browser test report</title>"));

    // A screenshot for looking at by eye; kept when ADAPTCLOTH_SCREENSHOT names a file.
    let shot = dir.path().join("report.png");
    let profile = tempfile::tempdir().unwrap();
    let arg = format!("--screenshot={}", shot.display());
    chromium(
        &browser,
        profile.path(),
        &page,
        &[&arg, "--window-size=1200,900"],
    );
    let png = std::fs::read(&shot).expect("screenshot written");
    assert_eq!(&png[1..4], b"PNG");
    if let Some(keep) = std::env::var_os("ADAPTCLOTH_SCREENSHOT") {
        std::fs::copy(&shot, keep).unwrap();
        std::fs::copy(
            &page,
            Path::new(&std::env::var_os("ADAPTCLOTH_SCREENSHOT").unwrap()).with_extension("html"),
        )
        .unwrap();
    }
}

/// The replay of a scene whose sphere moves (`moving_sphere`) draws every frame, the sphere moved
/// by its motion, without script errors.
#[test]
fn a_replay_with_a_moving_obstacle_draws_without_errors_in_chromium() {
    let Some(browser) = find_chromium() else {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("no chromium found under CI");
        }
        crate::common::say_skipped("no chromium found: moving-obstacle replay not checked");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (times, frames) = tiny_run(&dir.path().join("run"), "moving_sphere");
    let cloth_triangles = frames[0].faces.len();
    let replays = [ReplayRun {
        label: "static 5x5".into(),
        frame_times: times,
        frames,
    }];
    // The replay of the run with the scene's sphere (1 m/s: 5 cm by the last frame), and with
    // one that moves 50 m/s (2.5 m): the camera must frame it where it stands.
    let view_radius = |settings: &[&str], name: &str| -> f64 {
        let loaded = scene("moving_sphere", settings);
        let obstacles = render::obstacle_meshes(&loaded.scene.obstacles, &loaded.base_dir).unwrap();
        assert!(obstacles.poses(0.05).is_some());
        let page = dir.path().join(format!("{name}.html"));
        write_report_html(&page, "Moving sphere", &[], &replays, &obstacles).unwrap();
        // Open at the last frame.
        let profile = tempfile::tempdir().unwrap();
        let at_end = PathBuf::from(format!("{}#t=0.05", page.display()));
        let dom = chromium(&browser, profile.path(), &at_end, &["--dump-dom"]);
        let (status, drawn) = replay_status(&dom);
        assert!(drawn > cloth_triangles, "{status}");
        status
            .split("view radius ")
            .nth(1)
            .and_then(|s| s.split(' ').next())
            .and_then(|r| r.parse().ok())
            .unwrap_or_else(|| panic!("no view radius: {status}"))
    };
    let near = view_radius(&[], "near");
    let far = view_radius(&["obstacles.0.motion.velocity=[50.0, 0.0, 0.0]"], "far");
    assert!(
        far > near + 0.5,
        "view radius {near} m, {far} m with the far sphere"
    );
}
