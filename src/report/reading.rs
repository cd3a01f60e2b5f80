//! The computed reading of a comparison: the speed-up of each adaptive run over the static mesh
//! at equal error (log-log interpolation along the static Pareto front), whether the reference
//! resolves it, the verdict, and why a strategy loses (stage times, steps, vertices). Nothing here
//! is written by hand: it changes when the runs change.

use super::tables::{fmt_e, fmt_s};
use crate::eval::metrics::static_time_at_error;
use crate::study::{Comparison, Row};
use std::fmt::Write as _;
use std::path::PathBuf;

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
