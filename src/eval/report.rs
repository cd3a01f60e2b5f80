//! The reports of a comparison: the plots, `report.md` (and `report.html` and the snapshots
//! through [`super::render_hook`]) in the comparison's folder, and `docs/results.md` over several
//! scenes. Every number comes from the comparison's rows and runs; the reading (speed-up at equal
//! error, where the time goes) is computed, not written by hand.

use super::compare::{io_err, read_numeric_csv, write_tables, CompareError, Comparison, Row};
use super::metrics::{pareto_front, static_time_at_error};
use super::plots::{self, Panel, Series, SpeedPoint};
use super::render_hook::{self, RenderOutcome, Section};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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

/// Source thesis tables 5.2, 5.4 and 5.6 (Oliveira 2013), quoted for context: total CPU time,
/// number of steps ("quadros") and time per step of each mesh, in its own units.
pub const SOURCE_TABLES: &str = "\
| source table | scene | mesh | total time (s) | steps (\"quadros\") | time per step (s) |
|---|---|---|---:|---:|---:|
| 5.2 (Test I) | bunny | coarse 5x5 | 24.8 | 2236 | 0.01109 |
| 5.2 (Test I) | bunny | adaptive (remeshing) | 10401.7 | 134127 | 0.07755 |
| 5.2 (Test I) | bunny | fine 17x17 | 19237.7 | 174312 | 0.11036 |
| 5.4 (Test II) | round_table | coarse 5x5 | 14.3 | 4391 | 0.00326 |
| 5.4 (Test II) | round_table | adaptive (remeshing) | 35986.4 | 1020828 | 0.03525 |
| 5.4 (Test II) | round_table | fine 17x17 | 13870.7 | 346795 | 0.03999 |
| 5.6 (Test III) | sphere | 1-to-4 (Simnett) | 20086.4 | 122509 | 0.16395 |
| 5.6 (Test III) | sphere | remeshing | 21204.5 | 269071 | 0.07880 |
";

fn fmt_e(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "-".into()
    }
}

fn fmt_s(x: f64) -> String {
    if x.is_finite() {
        if x >= 100.0 {
            format!("{x:.0}")
        } else if x >= 1.0 {
            format!("{x:.1}")
        } else {
            format!("{x:.3}")
        }
    } else {
        "-".into()
    }
}

/// Series of one column of each run's `metrics.csv` over time.
fn metric_series(out: &Path, c: &Comparison, column: &str) -> Vec<Series> {
    c.rows
        .iter()
        .filter_map(|r| {
            let (header, rows) =
                read_numeric_csv(&out.join("runs").join(&r.label).join("metrics.csv")).ok()?;
            let t = header.iter().position(|h| h == "t")?;
            let k = header.iter().position(|h| h == column)?;
            Some(Series {
                label: r.label.clone(),
                points: rows.iter().map(|row| (row[t], row[k])).collect(),
                dashed: false,
            })
        })
        .collect()
}

/// The plots of a comparison, written into `out`.
pub fn write_plots(
    out: &Path,
    c: &Comparison,
) -> Result<Vec<(String, PathBuf, PathBuf)>, CompareError> {
    let m = &c.manifest;
    let mut files = Vec::new();
    let plot_err = |e: plots::PlotError| CompareError::Io {
        path: e.path.clone(),
        source: std::io::Error::other(e.message),
    };
    let mut push = |name: &str, f: Vec<PathBuf>| {
        if let [svg, png] = &f[..] {
            files.push((name.to_string(), svg.clone(), png.clone()));
        }
    };
    let completed: Vec<&Row> = c.rows.iter().filter(|r| r.completed()).collect();
    let points: Vec<SpeedPoint> = completed
        .iter()
        .map(|r| SpeedPoint {
            label: r.label.clone(),
            wall_s: r.wall_s,
            error: r.e_rms,
            is_static: r.strategy == "static",
        })
        .collect();
    let pairs: Vec<(f64, f64)> = points.iter().map(|p| (p.wall_s, p.error)).collect();
    let front = pareto_front(&pairs);
    let f = plots::speed_error(
        &out.join("speed_error"),
        &format!(
            "{}: wall time vs error (reference {}x{})",
            m.scene, m.reference.resolution, m.reference.resolution
        ),
        "e_rms",
        &points,
        &front,
        Some(m.reference.floor.e_rms),
    )
    .map_err(plot_err)?;
    push("speed_error", f);

    let elements = vec![
        Panel {
            y_label: "faces".into(),
            log_y: false,
            series: metric_series(out, c, "faces"),
            hline: None,
        },
        Panel {
            y_label: "vertices".into(),
            log_y: false,
            series: metric_series(out, c, "vertices"),
            hline: None,
        },
    ];
    let f = plots::time_series(
        &out.join("elements"),
        &format!("{}: element count", m.scene),
        &elements,
    )
    .map_err(plot_err)?;
    push("elements", f);

    let step = vec![
        Panel {
            y_label: "dt (s)".into(),
            log_y: true,
            series: metric_series(out, c, "dt"),
            hline: None,
        },
        Panel {
            y_label: "min mass (kg)".into(),
            log_y: true,
            series: metric_series(out, c, "min_mass"),
            hline: None,
        },
        Panel {
            y_label: "max stiffness (N/m)".into(),
            log_y: true,
            series: metric_series(out, c, "max_stiffness"),
            hline: None,
        },
    ];
    let f = plots::time_series(
        &out.join("step"),
        &format!("{}: time step, minimum mass, maximum stiffness", m.scene),
        &step,
    )
    .map_err(plot_err)?;
    push("step", f);

    let mut tracked = Vec::new();
    for (axis, col) in ["x", "y", "z"].iter().enumerate() {
        let mut series = metric_series(out, c, &format!("p0_{col}"));
        if !m.reference.tracked.is_empty() {
            series.push(Series {
                label: format!("reference {0}x{0}", m.reference.resolution),
                points: m
                    .reference
                    .tracked
                    .iter()
                    .map(|p| (p[0], p[axis + 1]))
                    .collect(),
                dashed: true,
            });
        }
        tracked.push(Panel {
            y_label: format!("P {col} (m)"),
            log_y: false,
            series,
            hline: None,
        });
    }
    let f = plots::time_series(
        &out.join("tracked"),
        &format!("{}: tracked point P", m.scene),
        &tracked,
    )
    .map_err(plot_err)?;
    push("tracked", f);

    let error_series: Vec<Series> = c
        .rows
        .iter()
        .filter_map(|r| {
            let (_, rows) =
                read_numeric_csv(&out.join("runs").join(&r.label).join("error.csv")).ok()?;
            Some(Series {
                label: r.label.clone(),
                points: rows.iter().map(|row| (row[0], row[1])).collect(),
                dashed: false,
            })
        })
        .collect();
    let f = plots::time_series(
        &out.join("error"),
        &format!("{}: e(t) against the reference", m.scene),
        &[Panel {
            y_label: "e(t) (m)".into(),
            log_y: true,
            series: error_series,
            hline: Some((
                format!("floor e_rms ({0}x{0})", m.reference.floor.resolution),
                m.reference.floor.e_rms,
            )),
        }],
    )
    .map_err(plot_err)?;
    push("error", f);
    Ok(files)
}

/// The comparison table (markdown).
pub fn table(c: &Comparison) -> String {
    let mut s = String::from(
        "| run | status | wall (s) | steps | mean / max vertices | e_rms (m) | e_final (m) | tracked (m) | Hausdorff (m) | max penetration (m) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in &c.rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.0} / {} | {} | {} | {} | {} | {} |",
            r.label,
            r.status,
            fmt_s(r.wall_s),
            r.steps,
            r.mean_vertices,
            r.max_vertices,
            fmt_e(r.e_rms),
            fmt_e(r.e_final),
            fmt_e(r.tracked_err),
            fmt_e(r.hausdorff),
            fmt_e(r.max_penetration)
        );
    }
    let f = &c.manifest.reference.floor;
    let _ = writeln!(
        s,
        "| *floor: static {0}x{0} vs reference* | | {1} | {2} | | {3} | {4} | {5} | {6} | |",
        f.resolution,
        fmt_s(f.wall_s),
        f.steps,
        fmt_e(f.e_rms),
        fmt_e(f.e_final),
        fmt_e(f.tracked_err),
        fmt_e(f.hausdorff)
    );
    s
}

/// Where each run's time goes (per step stage) and its adaptation jumps (markdown).
pub fn profile(c: &Comparison) -> String {
    let mut s = String::from(
        "| run | µs / step | integrate | collide | adapt | rebuild | record | adaptation events | max momentum jump (kg m/s) | max KE jump (J) | total KE change (J) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in &c.rows {
        let total = r.integrate_s + r.collide_s + r.adapt_s + r.rebuild_s + r.record_s;
        let pct = |x: f64| {
            if total > 0.0 {
                format!("{:.0} %", 100.0 * x / total)
            } else {
                "-".into()
            }
        };
        let per_step = if r.steps > 0 {
            format!("{:.1}", 1e6 * r.wall_s / r.steps as f64)
        } else {
            "-".into()
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.label,
            per_step,
            pct(r.integrate_s),
            pct(r.collide_s),
            pct(r.adapt_s),
            pct(r.rebuild_s),
            pct(r.record_s),
            r.adapt_events,
            fmt_e(r.max_momentum_jump),
            fmt_e(r.max_energy_jump),
            fmt_e(r.total_energy_jump)
        );
    }
    s
}

/// The completed static runs of a comparison.
fn static_rows(c: &Comparison) -> Vec<&Row> {
    c.rows
        .iter()
        .filter(|r| r.strategy == "static" && r.completed())
        .collect()
}

/// The wall time (s) the static mesh needs for `r`'s e_rms, by log-log interpolation along the
/// static runs' Pareto front; `None` when the front does not bracket that error.
fn static_time_for(c: &Comparison, r: &Row) -> Option<f64> {
    let points: Vec<(f64, f64)> = static_rows(c).iter().map(|s| (s.wall_s, s.e_rms)).collect();
    static_time_at_error(&points, r.e_rms)
}

/// Whether a run's error is resolved by the reference: at least twice the reference's floor.
fn resolved(c: &Comparison, r: &Row) -> bool {
    r.e_rms >= 2.0 * c.manifest.reference.floor.e_rms
}

/// "wins" when a speed-up at equal error is at least 1, else "loses".
fn verdict(speedup: f64) -> &'static str {
    if speedup >= 1.0 {
        "wins"
    } else {
        "loses"
    }
}

/// One cell of the summary table: the speed-up at equal error, or why there is none.
fn summary_cell(c: &Comparison, label: &str) -> String {
    let Some(r) = c.rows.iter().find(|r| r.label == label) else {
        return "not run".into();
    };
    if !r.completed() {
        return format!("{} at t = {:.3} s", r.status, r.sim_time);
    }
    let Some(t_static) = static_time_for(c, r) else {
        return "not bracketed by the static runs".into();
    };
    let speedup = t_static / r.wall_s;
    let verdict = verdict(speedup);
    if resolved(c, r) {
        format!("**x{speedup:.2}** ({verdict})")
    } else {
        format!("x{speedup:.2} ({verdict}; not resolved: within 2x of the floor)")
    }
}

/// The answer first: per scene, each adaptive configuration's speed-up over the static mesh at
/// equal error (markdown table; columns in the order configurations first appear).
pub fn summary(items: &[(PathBuf, Comparison)]) -> String {
    let mut labels: Vec<&str> = Vec::new();
    for (_, c) in items {
        for r in c.rows.iter().filter(|r| r.strategy != "static") {
            if !labels.contains(&r.label.as_str()) {
                labels.push(&r.label);
            }
        }
    }
    if labels.is_empty() {
        return "No adaptive strategy ran: there is no speed-up to report yet.\n".into();
    }
    let mut s = format!(
        "| scene | reference floor e_rms (m) | {} |\n|---|---:|{}\n",
        labels.join(" | "),
        "---|".repeat(labels.len())
    );
    for (_, c) in items {
        let cells: Vec<String> = labels.iter().map(|l| summary_cell(c, l)).collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} |",
            c.manifest.scene,
            fmt_e(c.manifest.reference.floor.e_rms),
            cells.join(" | ")
        );
    }
    s
}

/// The computed reading: the static curve, and for each adaptive strategy the speed-up over the
/// static mesh at equal error and where its time goes (markdown).
pub fn reading(c: &Comparison) -> String {
    let mut s = String::new();
    let floor = c.manifest.reference.floor.e_rms;
    let statics = static_rows(c);
    let failed: Vec<&Row> = c.rows.iter().filter(|r| !r.completed()).collect();
    for r in &failed {
        let _ = writeln!(
            s,
            "- **{}** did not complete (status `{}`, reached t = {:.3} s); it is left out of the \
             Pareto front and the speed-ups.",
            r.label, r.status, r.sim_time
        );
    }
    // The static curve.
    let mut sorted = statics.clone();
    sorted.sort_by_key(|r| r.resolution);
    if !sorted.is_empty() {
        let list: Vec<String> = sorted
            .iter()
            .map(|r| {
                format!(
                    "{}x{}: e_rms {} m in {} s",
                    r.resolution,
                    r.resolution,
                    fmt_e(r.e_rms),
                    fmt_s(r.wall_s)
                )
            })
            .collect();
        let _ = writeln!(s, "- Static mesh: {}.", list.join("; "));
        for w in sorted.windows(2) {
            let (a, b) = (w[0], w[1]);
            let h = ((a.resolution - 1) as f64 / (b.resolution - 1) as f64).ln();
            let order = (a.e_rms / b.e_rms).ln() / (-h);
            let cost = (b.wall_s / a.wall_s).ln() / (-h);
            let _ = writeln!(
                s,
                "  - {}x{} -> {}x{}: error x{:.2} (observed order {:.2} in the edge length), wall time x{:.1} (exponent {:.2}).",
                a.resolution, a.resolution, b.resolution, b.resolution,
                b.e_rms / a.e_rms, order, b.wall_s / a.wall_s, cost
            );
        }
        let near: Vec<String> = sorted
            .iter()
            .filter(|r| !resolved(c, r))
            .map(|r| r.label.clone())
            .collect();
        if !near.is_empty() {
            let _ = writeln!(
                s,
                "  - Within a factor 2 of the reference floor ({} m), so not resolved by this reference: {}.",
                fmt_e(floor),
                near.join(", ")
            );
        }
    }
    let adaptive: Vec<&Row> = c
        .rows
        .iter()
        .filter(|r| r.strategy != "static" && r.completed())
        .collect();
    if adaptive.is_empty() {
        let skipped: Vec<String> = c.manifest.skipped.iter().map(|k| k.label.clone()).collect();
        let _ = writeln!(
            s,
            "- No adaptive strategy ran{}: there is no speed-up to report yet. This section is \
             regenerated from the runs, so it fills in when the strategies are built.",
            if skipped.is_empty() {
                String::new()
            } else {
                format!(" (skipped: {})", skipped.join(", "))
            }
        );
        return s;
    }
    for r in adaptive {
        let total = r.integrate_s + r.collide_s + r.adapt_s + r.rebuild_s + r.record_s;
        let stage = |x: f64| 100.0 * x / total.max(1e-300);
        let where_time = format!(
            "integrate {:.0} %, collide {:.0} %, adapt {:.0} %, rebuild {:.0} %, record {:.0} %; {} steps, {:.0} mean vertices",
            stage(r.integrate_s), stage(r.collide_s), stage(r.adapt_s), stage(r.rebuild_s), stage(r.record_s),
            r.steps, r.mean_vertices
        );
        match static_time_for(c, r) {
            Some(t_static) => {
                let speedup = t_static / r.wall_s;
                let verdict = verdict(speedup);
                let _ = writeln!(
                    s,
                    "- **{}**: e_rms {} m in {} s; the static mesh needs {} s for that error \
                     (log-log interpolation): speed-up **x{:.2}** ({verdict}). Time: {where_time}.",
                    r.label,
                    fmt_e(r.e_rms),
                    fmt_s(r.wall_s),
                    fmt_s(t_static),
                    speedup
                );
                if !resolved(c, r) {
                    let _ = writeln!(
                        s,
                        "  - Its error is within a factor 2 of the reference floor ({} m): the \
                         reference does not resolve it, so this speed-up is indicative only.",
                        fmt_e(floor)
                    );
                }
                if speedup < 1.0 {
                    let _ = writeln!(s, "  - {}", why_slow(r, &statics));
                }
            }
            None => {
                let best = statics
                    .iter()
                    .map(|x| x.e_rms)
                    .fold(f64::INFINITY, f64::min);
                let worst = statics.iter().map(|x| x.e_rms).fold(0.0, f64::max);
                let position = if r.e_rms < best {
                    "more accurate than every static run (the speed-up is not measurable without a finer static run)"
                } else if r.e_rms > worst {
                    "less accurate than the coarsest static run"
                } else {
                    "not bracketed by the static Pareto front"
                };
                let _ = writeln!(
                    s,
                    "- **{}**: e_rms {} m in {} s: {position}. Time: {where_time}.",
                    r.label,
                    fmt_e(r.e_rms),
                    fmt_s(r.wall_s)
                );
                if r.e_rms > worst {
                    let _ = writeln!(s, "  - {}", why_slow(r, &statics));
                }
            }
        }
    }
    s
}

/// Why an adaptive run is slow, from its profile compared with the static run of its grid.
fn why_slow(r: &Row, statics: &[&Row]) -> String {
    let base = statics.iter().find(|s| s.resolution == r.resolution);
    let total = r.integrate_s + r.collide_s + r.adapt_s + r.rebuild_s + r.record_s;
    let overhead = (r.adapt_s + r.rebuild_s) / total.max(1e-300);
    let mut parts = vec![format!(
        "adaptation and element rebuilds take {:.0} % of its time",
        100.0 * overhead
    )];
    if let Some(b) = base {
        parts.push(format!(
            "it takes {:.1}x the steps of static {}x{} ({} vs {}: smaller elements shrink dt = beta pi sqrt(m_min/k_max))",
            r.steps as f64 / b.steps.max(1) as f64,
            b.resolution,
            b.resolution,
            r.steps,
            b.steps
        ));
        parts.push(format!(
            "{:.1}x the mean vertex count ({:.0} vs {:.0})",
            r.mean_vertices / b.mean_vertices,
            r.mean_vertices,
            b.mean_vertices
        ));
    }
    format!("Why: {}.", parts.join("; "))
}

fn rel(out: &Path, p: &Path) -> String {
    p.strip_prefix(out).unwrap_or(p).display().to_string()
}

/// The settings paragraph (markdown).
pub fn settings(c: &Comparison) -> String {
    let m = &c.manifest;
    let r = &m.reference;
    format!(
        "Scene `{}` ({}), {} s simulated, runs at the scene's parameters (dynamic step, beta = {}); \
         {} parallel job(s) on this machine (wall times include writing frames and metrics). \
         Reference: static {res}x{res}, {}, beta = {}{}, {} steps, {} s wall (cache key `{}`). \
         Errors are measured on {s}x{s} material points (MODEL.md §1). \
         **Error floor** (static {f}x{f} against the reference): e_rms {} m, e_final {} m, tracked {} m, Hausdorff {} m.",
        m.scene,
        m.source,
        m.duration,
        m.beta,
        m.jobs,
        r.integrator,
        r.beta,
        match r.dt_initial {
            Some(0.0) => ", dynamic step from the start".to_string(),
            Some(d) => format!(", {d} s until the first contact"),
            None => String::new(),
        },
        r.steps,
        fmt_s(r.wall_s),
        r.key,
        fmt_e(r.floor.e_rms),
        fmt_e(r.floor.e_final),
        fmt_e(r.floor.tracked_err),
        fmt_e(r.floor.hausdorff),
        res = r.resolution,
        s = r.samples,
        f = r.floor.resolution,
    )
}

/// Writes the tables, plots, snapshots, `report.md` and `report.html` of a comparison into `out`.
pub fn write_report(out: &Path, c: &Comparison) -> Result<ReportFiles, CompareError> {
    write_tables(out, c)?;
    let plots = write_plots(out, c)?;
    let snapshots = render_hook::snapshots(out, c);
    let m = &c.manifest;
    let mut md = String::new();
    let _ = writeln!(md, "# Comparison: {}\n", m.scene);
    if let Some(shard) = m.shard {
        let _ = writeln!(
            md,
            "Shard {shard} of the sweep: only its runs are here; combine the shards with `adaptcloth merge`.\n"
        );
    }
    let _ = writeln!(md, "{}\n", settings(c));
    let _ = writeln!(md, "## Runs\n\n{}", table(c));
    let _ = writeln!(md, "Table: [comparison.csv](comparison.csv); manifest: [comparison.json](comparison.json); each run's outputs in `runs/<label>/`.\n");
    if !m.skipped.is_empty() {
        let _ = writeln!(md, "Skipped configurations:\n");
        for k in &m.skipped {
            let _ = writeln!(md, "- `{}`: {}", k.label, k.reason);
        }
        let _ = writeln!(md);
    }
    let _ = writeln!(md, "## Reading\n\n{}", reading(c));
    let _ = writeln!(md, "## Where the time goes\n\n{}", profile(c));
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
    let _ = writeln!(md, "## Snapshots and replay\n");
    let _ = writeln!(md, "{}", outcome_line("snapshots", &snapshots, out));
    let sections = vec![
        Section {
            title: format!("Comparison: {}", m.scene),
            markdown: format!(
                "{}\n\n{}\n\n{}\n\n## Where the time goes\n\n{}",
                settings(c),
                table(c),
                reading(c),
                profile(c)
            ),
            images: plots.iter().take(1).map(|p| p.1.clone()).collect(),
        },
        Section {
            title: "Time series".into(),
            markdown: String::new(),
            images: plots.iter().skip(1).map(|p| p.1.clone()).collect(),
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
    let html = render_hook::html(
        out,
        c,
        &format!("adaptcloth comparison: {}", m.scene),
        &sections,
    );
    let _ = writeln!(md, "{}", outcome_line("report.html", &html, out));
    let path = out.join("report.md");
    crate::output::write_atomic(&path, md.as_bytes()).map_err(io_err(&path))?;
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

/// Writes `docs_dir/results.md` over several comparisons (their folders and results), copying
/// their plots (SVG) into `docs_dir/results/<scene>/`. `command` is the command that regenerates
/// it; `notes` is extra markdown (settings and costs) placed after the introduction.
pub fn write_docs(
    docs_dir: &Path,
    items: &[(PathBuf, Comparison)],
    command: &str,
    notes: &str,
) -> Result<PathBuf, CompareError> {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Results: which adaptivity strategy buys the most accuracy per second?\n\n\
         *Generated by `{command}`; do not edit by hand: the tables, plots and readings are \
         computed from the runs (the settings notes are kept with the command that writes this \
         page).*\n"
    );
    let built: Vec<String> = crate::strategies::strategy_names()
        .iter()
        .filter(|s| crate::strategies::make_strategy(s).is_ok())
        .map(|s| format!("`{s}`"))
        .collect();
    let not_built: Vec<String> = crate::strategies::strategy_names()
        .iter()
        .filter(|s| crate::strategies::make_strategy(s).is_err())
        .map(|s| format!("`{s}`"))
        .collect();
    let _ = writeln!(
        md,
        "Strategies built in this version: {}.{}\n",
        built.join(", "),
        if not_built.is_empty() {
            String::new()
        } else {
            format!(
                " Not built yet (left out of every comparison, listed per scene): {}. \
                 The static curve below is the baseline they will be measured against; \
                 regenerate this page when they land.",
                not_built.join(", ")
            )
        }
    );
    let _ = writeln!(
        md,
        "## Summary: speed-up over the static mesh at equal error\n\n\
         Static wall time for the adaptive run's e_rms (log-log interpolation along the static \
         runs' Pareto front) over the adaptive run's wall time: above 1 the strategy buys more \
         accuracy per second than the static mesh. Details, profiles and plots per scene below.\n\n{}",
        summary(items)
    );
    let _ = writeln!(md, "{notes}\n");
    let _ = writeln!(
        md,
        "How to read: `e(t)` is the RMS distance between the run's and the reference's world \
         positions of the same material points at the same time; `e_rms` its RMS over the output \
         frames; the Hausdorff distance compares the final surfaces regardless of where each \
         material point went (fold-pattern-insensitive). The speed-error plot is log-log; the \
         black line is the Pareto front (runs no other run beats in both time and error); the \
         dashed line is the reference's error floor, below which differences are not resolved.\n"
    );
    for (out, c) in items {
        let scene = &c.manifest.scene;
        let dest = docs_dir.join("results").join(scene);
        std::fs::create_dir_all(&dest).map_err(io_err(&dest))?;
        let _ = writeln!(md, "## {scene}\n\n{}\n", settings(c));
        let _ = writeln!(md, "{}", table(c));
        if !c.manifest.skipped.is_empty() {
            let list: Vec<String> = c
                .manifest
                .skipped
                .iter()
                .map(|k| format!("`{}`", k.label))
                .collect();
            let _ = writeln!(md, "Skipped (not built): {}.\n", list.join(", "));
        }
        let _ = writeln!(md, "### Reading\n\n{}", reading(c));
        let _ = writeln!(md, "### Where the time goes\n\n{}", profile(c));
        for name in ["speed_error", "error", "elements", "step", "tracked"] {
            let from = out.join(format!("{name}.svg"));
            if from.is_file() {
                let to = dest.join(format!("{name}.svg"));
                std::fs::copy(&from, &to).map_err(io_err(&from))?;
                let _ = writeln!(md, "![{scene} {name}](results/{scene}/{name}.svg)\n");
            }
        }
    }
    let _ = writeln!(
        md,
        "## The source's own timings (for context)\n\n\
         Oliveira (2013), Tables 5.2, 5.4 and 5.6: CPU time of the source's C++ implementation, \
         per mesh, for the same scenes (durations 0.5 s, 1 s and 0.6 s; different machine, \
         integrator settings and step factors: coarse beta 0.008, adaptive 0.001, fine 0.0008). \
         The source measured no error against a reference; its adaptive run was slower than the \
         fine mesh on Test II.\n\n{SOURCE_TABLES}"
    );
    let path = docs_dir.join("results.md");
    crate::output::write_atomic(&path, md.as_bytes()).map_err(io_err(&path))?;
    Ok(path)
}
