//! `adaptcloth merge`: shard folders of one study combined into one comparison.

use super::table::{read_comparison, Comparison, Row, Skipped};
use super::{io_err, StudyError};
use std::path::{Path, PathBuf};

/// Combines shard folders into one comparison written to `out`: same scene, same reference and
/// same configuration list required; each configuration must come from exactly one shard (a
/// missing one is listed in the manifest's `skipped` as missing, a duplicate is an error). Run
/// folders are copied into `out/runs/`.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Comparison, StudyError> {
    let parts: Vec<(PathBuf, Comparison)> = dirs
        .iter()
        .map(|d| read_comparison(d).map(|c| (d.clone(), c)))
        .collect::<Result<_, _>>()?;
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
    let mut rows: Vec<Option<Row>> = vec![None; manifest.configs.len()];
    std::fs::create_dir_all(out.join("runs")).map_err(io_err(out))?;
    for (d, c) in &parts {
        for r in &c.rows {
            let k = manifest
                .configs
                .iter()
                .position(|l| *l == r.label)
                .ok_or_else(|| {
                    StudyError::Merge(format!("{}: unknown run {}", d.display(), r.label))
                })?;
            if rows[k].is_some() {
                return Err(StudyError::Merge(format!(
                    "run {} appears in more than one shard",
                    r.label
                )));
            }
            rows[k] = Some(r.clone());
            let from = d.join("runs").join(&r.label);
            let to = out.join("runs").join(&r.label);
            if from.is_dir() && !same_dir(&from, &to) {
                copy_dir(&from, &to)?;
            }
        }
    }
    manifest.shard = None;
    for (label, row) in manifest.configs.iter().zip(&rows) {
        if row.is_none() {
            manifest.skipped.push(Skipped {
                label: label.clone(),
                reason: "missing: no shard ran it".into(),
            });
        }
    }
    Ok(Comparison {
        manifest,
        rows: rows.into_iter().flatten().collect(),
    })
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
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
