//! Behaviour lock: a short study (every strategy, both step regimes' integrators, a tiny reference)
//! must give the same comparison table and the same frames, byte for byte, as when the digest in
//! `tests/golden/short_study.txt` was recorded. Refactors keep it green; a change that is meant
//! to move results re-records it with `ADAPTCLOTH_BLESS=1 cargo test --release golden` and says
//! why in its commit.
//!
//! The digest holds the comparison table without its wall-time columns, and a 64-bit FNV-1a hash
//! of every frame and of every `metrics.csv` (which holds no wall time).
use std::path::{Path, PathBuf};
use std::process::Command;

/// Columns of `comparison.csv` that are wall-clock times (they differ from run to run).
const TIME_COLUMNS: &[&str] = &[
    "wall_s",
    "integrate_s",
    "collide_s",
    "adapt_s",
    "rebuild_s",
    "record_s",
];

fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// `comparison.csv` without the wall-time columns.
fn table_without_times(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("comparison.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !TIME_COLUMNS.contains(&header[i]))
        .collect();
    let pick = |line: &str| {
        let cells: Vec<&str> = line.split(',').collect();
        keep.iter()
            .map(|&i| cells.get(i).copied().unwrap_or(""))
            .collect::<Vec<_>>()
            .join(",")
    };
    let mut out = pick(&header.join(","));
    out.push('\n');
    for l in lines {
        out.push_str(&pick(l));
        out.push('\n');
    }
    out
}

/// Every file under `dir` whose name ends in `.obj` or is `metrics.csv`, sorted.
fn hashed_files(dir: &Path, found: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("run folder")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            hashed_files(&p, found);
        } else if p.extension().is_some_and(|e| e == "obj")
            || p.file_name().is_some_and(|n| n == "metrics.csv")
        {
            found.push(p);
        }
    }
}

fn digest(out: &Path) -> String {
    let mut s = table_without_times(&out.join("comparison.csv"));
    let mut files = Vec::new();
    hashed_files(&out.join("runs"), &mut files);
    for f in files {
        let rel = f
            .strip_prefix(out)
            .expect("inside out")
            .display()
            .to_string();
        let bytes = std::fs::read(&f).expect("readable");
        s.push_str(&format!("{rel} {:016x}\n", fnv1a(&bytes)));
    }
    s
}

fn study(out: &Path, cache: &Path, integrator: &str, extra: &[&str]) {
    let mut args = vec![
        "compare",
        "sphere",
        "--runs",
        "static@3,static@5,remesh,simnett,bisect48",
        "--integrators",
        integrator,
        "--ref-resolution",
        "7",
        "--floor-resolution",
        "5",
        "--samples",
        "10",
        "--jobs",
        "2",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = Command::new(env!("CARGO_BIN_EXE_adaptcloth"))
        .args(&args)
        .output()
        .expect("binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn a_short_study_gives_the_recorded_table_and_frames() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let rk4 = dir.path().join("rk4");
    let implicit = dir.path().join("implicit");
    study(&rk4, &cache, "rk4", &["--duration", "0.3"]);
    study(
        &implicit,
        &cache,
        "implicit_euler",
        &[
            "--duration",
            "0.4",
            "--set",
            "time.mode=\"fixed\"",
            "--set",
            "time.dt=0.004",
            "--set",
            "time.frame_rate=20",
            "--ref-integrator",
            "implicit_euler",
        ],
    );
    let got = format!(
        "# rk4, dynamic step, 0.3 s\n{}# implicit_euler, fixed 4 ms, 0.4 s\n{}",
        digest(&rk4),
        digest(&implicit)
    );
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/short_study.txt");
    if std::env::var_os("ADAPTCLOTH_BLESS").is_some() {
        std::fs::create_dir_all(golden.parent().unwrap()).unwrap();
        std::fs::write(&golden, &got).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&golden).expect("tests/golden/short_study.txt");
    if got != want {
        let first = got
            .lines()
            .zip(want.lines())
            .find(|(g, w)| g != w)
            .map(|(g, w)| format!("first difference:\n  got  {g}\n  want {w}"))
            .unwrap_or_else(|| "the digests differ in length".into());
        panic!("the short study's outputs changed ({first})");
    }
}
