//! Presenting studies: everything a person reads or looks at. Above `study` (which runs and
//! tabulates) and below the command line.
//!
//! - [`write_report`] (this file): a comparison folder's `report.md`, `report.html`, plots and
//!   snapshots. Every number comes from the comparison's rows and runs.
//! - [`tables`], [`reading`]: the markdown tables and the computed reading (speed-up at equal
//!   error, where the time goes).
//! - [`comparison_plots`] over [`speed_plot`] and [`plots`] (plotters, embedded DejaVu font).
//! - [`results`]: `docs/results.md` over several scenes.
//! - [`pictures`]: snapshots and the HTML report of a comparison, over [`render`] (the software
//!   rasteriser) and [`html`] (the self-contained `report.html` with its 3D replay).

pub mod comparison_plots;
pub mod html;
pub mod pictures;
pub mod plots;
pub mod ranking;
pub mod reading;
pub mod render;
pub mod results;
pub mod speed_plot;
pub mod tables;

pub use results::write_docs;

use crate::study::{table::write_tables, Comparison, StudyError};
use pictures::{RenderOutcome, Section};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tables::rel;

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: String,
        /// The error.
        source: std::io::Error,
    },
    /// Writing the comparison's tables failed.
    #[error(transparent)]
    Study(#[from] StudyError),
}

/// Maps an I/O error on `path` to [`ReportError::Io`].
pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError + '_ {
    move |source| ReportError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// The files a report wrote (relative to its folder), by kind.
#[derive(Clone, Debug, Default)]
pub struct ReportFiles {
    /// Plots: `(name, svg, png)`.
    pub plots: Vec<(String, PathBuf, PathBuf)>,
    /// The snapshot grid.
    pub snapshots: Option<RenderOutcome>,
    /// The HTML report.
    pub html: Option<RenderOutcome>,
}

/// Writes the tables, plots, snapshots, `report.md` and `report.html` of a comparison into `out`.
pub fn write_report(out: &Path, c: &Comparison) -> Result<ReportFiles, ReportError> {
    write_tables(out, c)?;
    let plots = comparison_plots::write_plots(out, c)?;
    let snapshots = pictures::snapshots(out, c);
    let maps = pictures::error_maps(out, c);
    let m = &c.manifest;
    let mut md = String::new();
    let _ = writeln!(md, "# Comparison: {}\n", m.scene);
    if let Some(shard) = m.shard {
        let _ = writeln!(
            md,
            "Shard {shard} of the sweep: only its runs are here; combine the shards with `adaptcloth merge`.\n"
        );
    }
    let _ = writeln!(md, "{}\n", tables::settings(c));
    if !m.command.is_empty() {
        let _ = writeln!(
            md,
            "Made by `{}` (adaptcloth {}).\n",
            m.command.replace('`', "'"),
            m.version
        );
    }
    let summary = reading::summary([c]);
    let _ = writeln!(
        md,
        "## Summary: speed-up over the static mesh at equal error\n\n{}",
        summary
    );
    let _ = writeln!(md, "## Runs\n\n{}", tables::table(c));
    let _ = writeln!(md, "Table: [comparison.csv](comparison.csv); manifest: [comparison.json](comparison.json); each run's outputs in `runs/<label>/`.\n");
    // A run in the table whose folder is gone (a copied or pruned comparison) has no curves.
    let without: Vec<&str> = c
        .rows
        .iter()
        .filter(|r| {
            r.completed()
                && !out
                    .join("runs")
                    .join(&r.label)
                    .join("metrics.csv")
                    .is_file()
        })
        .map(|r| r.label.as_str())
        .collect();
    // Files present that do not read as the plots need (edited or truncated) leave their run
    // out of those plots too.
    for r in c.rows.iter().filter(|r| r.completed()) {
        let dir = out.join("runs").join(&r.label);
        let files = [
            ("metrics.csv", &["t", "vertices"][..], true),
            ("error.csv", &["t", "e"][..], r.e_rms.is_finite()),
        ];
        for (name, columns, expected) in files {
            let path = dir.join(name);
            if !expected || !path.is_file() {
                continue;
            }
            if let Some(why) = crate::io::numeric_csv_problem(&path, columns) {
                crate::note!(
                    "warning: {}: {why}: run {} left out of the plots that read it",
                    path.display(),
                    r.label
                );
                let _ = writeln!(
                    md,
                    "`runs/{}/{name}` does not read ({why}): the run is left out of the plots \
                     that read it.\n",
                    r.label
                );
            }
        }
    }
    if !without.is_empty() {
        let list = without.join(", ");
        crate::note!(
            "warning: {}: no runs/<label>/metrics.csv for {list}: in the tables, not in the plots",
            out.display()
        );
        let _ = writeln!(
            md,
            "Runs in the table without their folder's metrics.csv, left out of the plots: {list}.\n"
        );
    }
    // Folders under runs/ that no row names: an earlier study's, written into the same --out.
    let mut stale: Vec<String> = std::fs::read_dir(out.join("runs"))
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|name| !c.rows.iter().any(|r| &r.label == name))
        .collect();
    stale.sort();
    if !stale.is_empty() {
        let list = stale.join(", ");
        crate::note!(
            "note: {}: runs/ also holds {list}, not in this comparison (an earlier one's?): left \
             as they are, in no table or plot",
            out.display()
        );
        let _ = writeln!(
            md,
            "Folders under `runs/` that are not runs of this comparison (left as they are): {list}.\n"
        );
    }
    if !m.skipped.is_empty() {
        let _ = writeln!(md, "Missing runs:\n");
        for k in &m.skipped {
            let _ = writeln!(md, "- `{}`: {}", k.label, k.reason);
        }
        let _ = writeln!(md);
    }
    let _ = writeln!(md, "## Reading\n\n{}", reading::reading(c));
    let _ = writeln!(md, "## Where the time goes\n\n{}", tables::profile(c));
    let _ = writeln!(md, "## Plots\n");
    for (name, svg, png) in &plots {
        let _ = writeln!(
            md,
            "- {name}: [svg]({}) [png]({})\n\n  ![{name}]({})\n",
            rel(out, svg),
            rel(out, png),
            rel(out, svg)
        );
    }
    let _ = writeln!(
        md,
        "## Error maps\n\nWhere each run's error is: `e(u, v)`, the distance between the run's and \
         the reference's positions of the material point at rest position `(u, v)`, at a few \
         times, over the pattern with the run's mesh at that time drawn on it (one colour scale \
         for all runs).\n"
    );
    for (label, outcome) in &maps {
        let _ = writeln!(md, "{}", outcome_line(label, outcome, out));
    }
    let _ = writeln!(md, "## Snapshots and replay\n");
    let _ = writeln!(md, "{}", outcome_line("snapshots", &snapshots, out));
    let sections = vec![
        Section {
            title: format!("Comparison: {}", m.scene),
            markdown: format!(
                "{}\n\n{summary}\n{}\n\n{}\n\n## Where the time goes\n\n{}",
                tables::settings(c),
                tables::table(c),
                reading::reading(c),
                tables::profile(c)
            ),
            images: plots.iter().take(2).map(|p| p.1.clone()).collect(),
        },
        Section {
            title: "Time series".into(),
            markdown: String::new(),
            images: plots.iter().skip(2).map(|p| p.1.clone()).collect(),
        },
        Section {
            title: "Error maps".into(),
            markdown:
                "e(u, v) over the pattern with each run's mesh, one colour scale for all runs."
                    .into(),
            images: maps
                .iter()
                .filter_map(|(_, o)| match o {
                    RenderOutcome::Written(p) => Some(p.clone()),
                    RenderOutcome::Failed(_) => None,
                })
                .collect(),
        },
        Section {
            title: "Snapshots".into(),
            markdown: String::new(),
            images: match &snapshots {
                RenderOutcome::Written(p) => vec![p.clone()],
                _ => Vec::new(),
            },
        },
    ];
    let html = pictures::html(
        out,
        c,
        &format!("adaptcloth comparison: {}", m.scene),
        &sections,
    );
    let _ = writeln!(md, "{}", outcome_line("report.html", &html, out));
    let path = out.join("report.md");
    crate::io::write_atomic(&path, md.as_bytes()).map_err(io_err(&path))?;
    Ok(ReportFiles {
        plots,
        snapshots: Some(snapshots),
        html: Some(html),
    })
}

fn outcome_line(what: &str, o: &RenderOutcome, out: &Path) -> String {
    match o {
        RenderOutcome::Written(p) => {
            let r = rel(out, p);
            if r.ends_with(".png") {
                format!("- {what}: [{r}]({r})\n\n  ![{what}]({r})\n")
            } else {
                format!("- {what}: [{r}]({r})\n")
            }
        }
        RenderOutcome::Failed(why) => format!("- {what}: **failed**: {why}\n"),
    }
}
