//! `adaptcloth merge`: shard folders of one study combined into one comparison.

use super::table::{read_comparison, Comparison, Row, Skipped};
use super::{io_err, StudyError};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Combines shard folders into one comparison written to `out`: same scene, same reference and
/// same configuration list, each made with the same settings (their fingerprints), required;
/// each configuration must come from exactly one shard (a missing one is listed in the
/// manifest's `skipped` as missing, a duplicate is an error). Run folders are copied into
/// `out/runs/`, each replacing the folder of its label there, with their `rerun` lines pointing
/// at the copy. Every input is checked before anything is written: a merge that fails writes
/// nothing, and `out` may not be, or lie inside, an input folder. When `interrupt` is set no
/// further run is copied and the merge fails as interrupted.
pub fn merge(
    dirs: &[PathBuf],
    out: &Path,
    interrupt: Option<&AtomicBool>,
) -> Result<Comparison, StudyError> {
    let parts: Vec<(PathBuf, Comparison)> = dirs
        .iter()
        .map(|d| read_comparison(d).map(|c| (d.clone(), c)))
        .collect::<Result<_, _>>()?;
    check_out_outside_inputs(dirs, out)?;
    let Some((_, first)) = parts.first() else {
        return Err(StudyError::Merge("no folder given".into()));
    };
    let mut manifest = first.manifest.clone();
    for (d, c) in &parts[1..] {
        let m = &c.manifest;
        if m.scene != manifest.scene
            || m.reference.key != manifest.reference.key
            || m.configs != manifest.configs
        {
            return Err(StudyError::Merge(format!(
                "{} is not a shard of the same sweep as {} (scene, reference or configurations differ)",
                d.display(),
                dirs[0].display()
            )));
        }
    }
    check_same_settings(dirs, &parts)?;
    // Each configuration's row and the shard it comes from, all checked before any copy.
    let mut rows: Vec<Option<(&Path, &Row)>> = vec![None; manifest.configs.len()];
    for (d, c) in &parts {
        for r in &c.rows {
            let k = manifest
                .configs
                .iter()
                .position(|l| *l == r.label)
                .ok_or_else(|| {
                    StudyError::Merge(format!("{}: unknown run {}", d.display(), r.label))
                })?;
            if let Some((other, _)) = rows[k] {
                return Err(StudyError::Merge(format!(
                    "run {} appears in more than one shard ({} and {})",
                    r.label,
                    other.display(),
                    d.display()
                )));
            }
            rows[k] = Some((d, r));
        }
    }
    std::fs::create_dir_all(out.join("runs")).map_err(io_err(out))?;
    let present: Vec<(&Path, &Row)> = rows
        .iter()
        .flatten()
        .filter(|(d, r)| d.join("runs").join(&r.label).is_dir())
        .copied()
        .collect();
    for (k, (d, r)) in present.iter().enumerate() {
        if interrupt.is_some_and(|i| i.load(Ordering::SeqCst)) {
            return Err(StudyError::Interrupted(format!(
                "merge interrupted: {k} of {} run folder(s) copied into {}, no comparison \
                 written; run the merge again",
                present.len(),
                out.join("runs").display()
            )));
        }
        let to = out.join("runs").join(&r.label);
        // A folder of this label from an earlier merge would keep its frames beside these.
        if to.exists() {
            std::fs::remove_dir_all(&to).map_err(io_err(&to))?;
        }
        copy_dir(&d.join("runs").join(&r.label), &to)?;
        point_rerun_at(&to)?;
    }
    manifest.shard = None;
    // Each configuration without a row once: with the reason a shard gave (an interrupted shard
    // lists the runs it did not start), else missing.
    let listed = |label: &str| {
        parts
            .iter()
            .flat_map(|(_, c)| &c.manifest.skipped)
            .find(|s| s.label == label)
            .cloned()
    };
    manifest.skipped = manifest
        .configs
        .iter()
        .zip(&rows)
        .filter(|(_, row)| row.is_none())
        .map(|(label, _)| {
            listed(label).unwrap_or_else(|| {
                let folder = dirs.iter().find(|d| d.join("runs").join(label).is_dir());
                let reason = match folder {
                    Some(d) => format!(
                        "missing: {} holds its run folder but no row of it in comparison.csv \
                         (the table was edited, or the shard did not finish)",
                        d.display()
                    ),
                    None => "missing: no shard ran it".into(),
                };
                Skipped {
                    label: label.clone(),
                    reason,
                }
            })
        })
        .collect();
    let rows = rows.into_iter().flatten().map(|(_, r)| r.clone()).collect();
    Ok(Comparison { manifest, rows })
}

/// Refuses shards whose runs of one label were made with different settings (their
/// fingerprints in the manifests: the study file changed between shards, or two studies share
/// labels); manifests written before fingerprints were kept are not compared.
fn check_same_settings(
    dirs: &[PathBuf],
    parts: &[(PathBuf, Comparison)],
) -> Result<(), StudyError> {
    let first = &parts[0].1.manifest;
    for (d, c) in &parts[1..] {
        let m = &c.manifest;
        if m.settings.is_empty() || first.settings.is_empty() {
            continue;
        }
        if let Some(k) = (0..m.configs.len()).find(|&k| m.settings.get(k) != first.settings.get(k))
        {
            return Err(StudyError::Merge(format!(
                "{} and {} are shards of different studies: run {} has other settings in one \
                 than in the other (the study file changed between shards, or two studies share \
                 its label); merge only the shards of one study",
                dirs[0].display(),
                d.display(),
                m.configs[k]
            )));
        }
    }
    Ok(())
}

/// Rewrites the `rerun` line of the run copied to `dir` (its `summary.json`) to run the copy's
/// `scene.resolved.toml` into a folder beside the copy (it named the shard's folder, which may
/// be gone or on another machine). A summary that does not parse, or has no such line, is left
/// as it is.
fn point_rerun_at(dir: &Path) -> Result<(), StudyError> {
    let path = dir.join("summary.json");
    let Ok(text) = std::fs::read_to_string(&path) else {
        return Ok(());
    };
    let Ok(mut summary) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Ok(());
    };
    match summary.get_mut("rerun") {
        Some(serde_json::Value::String(line)) if !line.is_empty() => {
            *line = crate::sim::rerun_line(dir);
        }
        _ => return Ok(()),
    }
    let json = serde_json::to_string_pretty(&summary).unwrap_or(text);
    crate::io::write_atomic(&path, json.as_bytes()).map_err(io_err(&path))
}

/// Refuses an `out` that is one of `dirs` or inside one (it would rewrite that shard), the
/// paths compared canonicalised; `out` may not exist yet.
fn check_out_outside_inputs(dirs: &[PathBuf], out: &Path) -> Result<(), StudyError> {
    let target = canonical_to_be(out).map_err(io_err(out))?;
    for d in dirs {
        let input = d.canonicalize().map_err(io_err(d))?;
        if target.starts_with(&input) {
            let place = if target == input { "is" } else { "is inside" };
            return Err(StudyError::Merge(format!(
                "--out {} {place} the input folder {}: merging would rewrite that shard; give \
                 --out a new folder",
                out.display(),
                d.display()
            )));
        }
    }
    Ok(())
}

/// `path` canonicalised when it exists; else its longest existing prefix canonicalised with the
/// rest of `path` appended (`..` and `.` resolved by name: there is no link to follow there).
fn canonical_to_be(path: &Path) -> std::io::Result<PathBuf> {
    let absolute = std::path::absolute(path)?;
    let parts: Vec<Component> = absolute.components().collect();
    let prefix = |k: usize| parts[..k].iter().collect::<PathBuf>();
    let mut k = parts.len();
    while k > 1 && !prefix(k).exists() {
        k -= 1;
    }
    let mut out = prefix(k).canonicalize()?;
    for c in &parts[k..] {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::Normal(name) => out.push(name),
            _ => {}
        }
    }
    Ok(out)
}

fn copy_dir(from: &Path, to: &Path) -> Result<(), StudyError> {
    std::fs::create_dir_all(to).map_err(io_err(to))?;
    for entry in std::fs::read_dir(from).map_err(io_err(from))? {
        let entry = entry.map_err(io_err(from))?;
        let p = entry.path();
        let q = to.join(entry.file_name());
        if p.is_dir() {
            copy_dir(&p, &q)?;
        } else {
            std::fs::copy(&p, &q).map_err(io_err(&p))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::table::tests::{manifest, row};
    use crate::study::table::write_tables;

    /// A shard folder `dir` of the sweep `a, b, c` holding the runs `labels`, each with a
    /// `runs/LABEL/summary.json`.
    fn shard(dir: &Path, labels: &[&str]) {
        let mut m = manifest();
        m.configs = ["a", "b", "c"].map(String::from).to_vec();
        let rows = labels.iter().map(|l| row(l)).collect();
        std::fs::create_dir_all(dir).unwrap();
        write_tables(dir, &Comparison { manifest: m, rows }).unwrap();
        for l in labels {
            let run = dir.join("runs").join(l);
            std::fs::create_dir_all(&run).unwrap();
            std::fs::write(run.join("summary.json"), "{}").unwrap();
        }
    }

    /// Every file and folder under `dir`, sorted.
    fn tree(dir: &Path) -> Vec<PathBuf> {
        let mut out = Vec::new();
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                out.extend(tree(&p));
            }
            out.push(p);
        }
        out.sort();
        out
    }

    /// A run an interrupted shard did not start, and no other shard ran, is listed once, with
    /// the shard's reason (it was listed twice: the first shard's list, then as missing).
    #[test]
    fn a_run_an_interrupted_shard_did_not_start_is_listed_once() {
        let d = tempfile::tempdir().unwrap();
        let (p1, p2) = (d.path().join("p1"), d.path().join("p2"));
        shard(&p1, &["a"]);
        shard(&p2, &[]);
        let mut interrupted = read_comparison(&p2).unwrap();
        interrupted.manifest.skipped = vec![Skipped {
            label: "b".into(),
            reason: "not started: the study was interrupted".into(),
        }];
        write_tables(&p2, &interrupted).unwrap();
        let merged = merge(&[p2, p1], &d.path().join("m"), None).unwrap();
        let skipped: Vec<(&str, &str)> = merged
            .manifest
            .skipped
            .iter()
            .map(|s| (s.label.as_str(), s.reason.as_str()))
            .collect();
        assert_eq!(
            skipped,
            [
                ("b", "not started: the study was interrupted"),
                ("c", "missing: no shard ran it")
            ]
        );
    }

    /// Regression (trial report A4): `--out` equal to, or inside, an input folder rewrote that
    /// shard (or put a folder among its runs). Refused before anything is written, also when
    /// `--out` does not exist yet or reaches the input through `..`.
    #[test]
    fn merge_refuses_an_out_folder_that_is_or_is_inside_an_input() {
        let d = tempfile::tempdir().unwrap();
        let (p1, p2) = (d.path().join("p1"), d.path().join("p2"));
        shard(&p1, &["a"]);
        shard(&p2, &["b"]);
        let before = tree(d.path());
        for (out, place) in [
            (p1.clone(), "is the input"),
            (p2.join("runs").join("x"), "is inside the input"),
            (d.path().join("new").join("..").join("p1"), "is the input"),
            (p1.join("."), "is the input"),
        ] {
            let e = merge(&[p1.clone(), p2.clone()], &out, None)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(place) && e.contains("--out"),
                "{}: {e}",
                out.display()
            );
            assert_eq!(tree(d.path()), before, "{}", out.display());
        }
        // A folder beside the inputs, or holding them, is fine.
        let merged = merge(&[p1.clone(), p2.clone()], d.path(), None).unwrap();
        assert_eq!(merged.rows.len(), 2);
        assert!(d.path().join("runs/b/summary.json").is_file());
    }

    /// Regression (study review 2026-11-29, findings 1, 2, 10 and 12c): shards of two studies
    /// with the same labels merged into one table; a merge into a folder of an earlier merge
    /// kept that merge's frames beside the new ones; the merged runs' rerun lines wrote into
    /// the shards; a run whose row was missing from its shard's table was said to be run by no
    /// shard.
    #[test]
    fn merge_takes_one_study_and_replaces_what_an_earlier_merge_left() {
        let d = tempfile::tempdir().unwrap();
        let (p1, p2, other) = (d.path().join("p1"), d.path().join("p2"), d.path().join("x"));
        shard(&p1, &["a"]);
        shard(&p2, &["b"]);
        shard(&other, &["b"]);
        let fingerprints = |dir: &Path, f: [&str; 3]| {
            let mut c = read_comparison(dir).unwrap();
            c.manifest.settings = f.map(String::from).to_vec();
            write_tables(dir, &c).unwrap();
        };
        fingerprints(&p1, ["1", "2", "3"]);
        fingerprints(&p2, ["1", "2", "3"]);
        fingerprints(&other, ["1", "9", "3"]);
        let out = d.path().join("m");
        let e = merge(&[p1.clone(), other], &out, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("shards of different studies: run b"), "{e}");
        assert!(!out.exists());
        // An earlier merge's run folder of label a, with a frame this run does not have.
        std::fs::create_dir_all(out.join("runs/a/frames")).unwrap();
        std::fs::write(out.join("runs/a/frames/stale.obj"), "v 0 0 0").unwrap();
        let run = p1.join("runs/a");
        let line = format!("adaptcloth run {}/scene.resolved.toml", run.display());
        std::fs::write(
            run.join("summary.json"),
            format!("{{\"rerun\": \"{line}\"}}"),
        )
        .unwrap();
        let merged = merge(&[p1.clone(), p2.clone()], &out, None).unwrap();
        assert_eq!(merged.rows.len(), 2);
        assert!(!out.join("runs/a/frames").exists(), "{:?}", tree(&out));
        let summary = std::fs::read_to_string(out.join("runs/a/summary.json")).unwrap();
        let copied = std::path::absolute(out.join("runs/a")).unwrap();
        assert!(
            summary.contains(&format!("{}/scene.resolved.toml", copied.display())),
            "{summary}"
        );
        // A run folder without its row.
        std::fs::create_dir_all(p2.join("runs/c")).unwrap();
        let merged = merge(&[p1, p2.clone()], &out, None).unwrap();
        let reason = &merged.manifest.skipped[0].reason;
        assert!(
            reason.contains(&format!("{} holds its run folder but no row", p2.display())),
            "{reason}"
        );
    }

    /// Regression (study review 2026-11-29, finding 6): Ctrl-C killed a merge half-way with no
    /// word. An interrupt stops it before the next run folder, with what was copied said.
    #[test]
    fn an_interrupted_merge_says_what_it_copied() {
        let d = tempfile::tempdir().unwrap();
        let (p1, p2) = (d.path().join("p1"), d.path().join("p2"));
        shard(&p1, &["a"]);
        shard(&p2, &["b", "c"]);
        let stop = AtomicBool::new(true);
        let e = merge(&[p1, p2], &d.path().join("m"), Some(&stop)).unwrap_err();
        assert!(matches!(e, StudyError::Interrupted(_)), "{e}");
        assert!(e.to_string().contains("0 of 3 run folder(s) copied"), "{e}");
        assert!(!d.path().join("m/comparison.json").exists());
    }

    /// Regression (trial report A5): a merge refused for a run in two shards had already copied
    /// the run folders of the shards before it. Nothing is written.
    #[test]
    fn a_failed_merge_writes_nothing() {
        let d = tempfile::tempdir().unwrap();
        let (p1, p2, p3) = (
            d.path().join("p1"),
            d.path().join("p2"),
            d.path().join("p3"),
        );
        shard(&p1, &["a"]);
        shard(&p2, &["b"]);
        shard(&p3, &["c", "a"]);
        let out = d.path().join("out");
        let e = merge(&[p1.clone(), p2, p3], &out, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("run a appears in more than one shard"), "{e}");
        assert!(!out.exists(), "{:?}", tree(&out));
        // An unknown run is refused the same way.
        shard(&d.path().join("p4"), &["b"]);
        let mut other = read_comparison(&d.path().join("p4")).unwrap();
        other.rows[0].label = "z".into();
        write_tables(&d.path().join("p4"), &other).unwrap();
        let e = merge(&[p1, d.path().join("p4")], &out, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown run z"), "{e}");
        assert!(!out.exists());
    }
}
