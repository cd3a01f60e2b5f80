//! The ranked table a study prints when a scene is done (plain text, for the terminal): every
//! completed run of one integrator, ranked by its speed-up over the static curve at its own
//! error (the static mesh's wall time for the run's e_rms, interpolated along the static runs,
//! over the run's wall time).

use super::reading::{curves, integrators, reach, Metric, Reach};
use super::tables::{fmt_e, fmt_s};
use crate::study::{Comparison, Row};
use std::fmt::Write;

/// The speed-up cell of one run and its sort key (larger is better): the speed-up, or its upper
/// bound when the run is less accurate than the fastest static run; a run more accurate than
/// every static run sorts first.
fn speedup(statics: Option<&super::reading::Curve>, r: &Row) -> (String, f64) {
    match statics.map(|k| reach(k, Metric::Rms, r.e_rms)) {
        Some(Reach::At(t)) => (format!("x{:.2}", t / r.wall_s), t / r.wall_s),
        Some(Reach::AtMost(t)) => (format!("<= x{:.2}", t / r.wall_s), t / r.wall_s),
        Some(Reach::Never(_)) => ("beyond the static runs".into(), f64::INFINITY),
        None => ("no static run".into(), -1.0),
    }
}

/// The ranked tables of a comparison, one per integrator: the runs of the strategies that adapt
/// (the static runs are the baseline, listed after them), then what the cells mean.
pub fn ranking(c: &Comparison) -> String {
    let floor = c.manifest.reference.floor.e_rms;
    let mut s = String::new();
    for integrator in integrators(c) {
        let all = curves(c, integrator);
        let statics = all.iter().find(|k| k.is_static());
        let mut rows: Vec<(&Row, String, f64)> = all
            .iter()
            .filter(|k| !k.is_static())
            .flat_map(|k| k.rows.iter().copied())
            .map(|r| {
                let (cell, key) = speedup(statics, r);
                (r, cell, key)
            })
            .collect();
        rows.sort_by(|a, b| b.2.total_cmp(&a.2).then(a.0.wall_s.total_cmp(&b.0.wall_s)));
        let width = rows
            .iter()
            .map(|(r, _, _)| r.label.len())
            .max()
            .unwrap_or(3);
        let _ = writeln!(
            s,
            "{} with {integrator}, ranked by speed-up over the static mesh at equal error \
             (e_rms against static {}x{} {}):",
            c.manifest.scene,
            c.manifest.reference.resolution,
            c.manifest.reference.resolution,
            c.manifest.reference.integrator,
        );
        let _ = writeln!(
            s,
            "  {:>2}  {:<width$}  {:<8}  {:>8}  {:>9}  speed-up",
            "#", "run", "strategy", "wall (s)", "e_rms (m)"
        );
        for (i, (r, cell, _)) in rows.iter().enumerate() {
            let flag = if Metric::Rms.resolves(c, r.e_rms) {
                ""
            } else {
                "  (not resolved)"
            };
            let _ = writeln!(
                s,
                "  {:>2}  {:<width$}  {:<8}  {:>8}  {:>9}  {cell}{flag}",
                i + 1,
                r.label,
                r.strategy,
                fmt_s(r.wall_s),
                fmt_e(r.e_rms),
            );
        }
        if rows.is_empty() {
            let _ = writeln!(s, "  (no adaptive run completed with {integrator})");
        }
        if !rows.is_empty()
            && rows
                .iter()
                .all(|(r, _, _)| !Metric::Rms.resolves(c, r.e_rms))
        {
            let _ = writeln!(
                s,
                "  none of these runs is resolved: every error is within 2x of the reference's \
                 floor, so this reference cannot rank them; a finer one can ([reference] \
                 resolution, 65 by default)"
            );
        }
        if let Some(k) = statics {
            let mut by_grid = k.rows.clone();
            by_grid.sort_by_key(|r| r.resolution);
            let list: Vec<String> = by_grid
                .iter()
                .map(|r| {
                    let n = r.resolution;
                    format!("{n}x{n} {} m in {} s", fmt_e(r.e_rms), fmt_s(r.wall_s))
                })
                .collect();
            let _ = writeln!(s, "  static baseline: {}", list.join(", "));
        }
    }
    let _ = writeln!(
        s,
        "  speed-up: the static mesh's time for the run's e_rms (interpolated between static \
         grids) over the run's time; \"<=\": less accurate than the fastest static run, an upper \
         bound. Not resolved: e_rms within 2x of the reference's floor ({} m). Sub-second wall \
         times vary by tens of percent between runs and with the runs beside them (--jobs 1 \
         gives the steadiest).",
        fmt_e(floor)
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::reading::tests::{comparison, run};

    #[test]
    fn runs_are_ranked_by_their_speed_up_at_equal_error() {
        let rows = [
            run("static", "static", 9, 1.0, 4e-2),
            run("static", "static", 17, 10.0, 2e-2),
            run("static", "static", 33, 100.0, 1e-2),
            // Reaches 2e-2 in 2 s where static needs 10 s: x5.
            run("bisect48", "bisect48", 5, 2.0, 2e-2),
            // Reaches 1e-2 in 200 s where static needs 100 s: x0.5.
            run("remesh", "remesh", 5, 200.0, 1e-2),
        ];
        let c = comparison(&rows);
        let text = ranking(&c);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].contains("with rk4"), "{text}");
        // The adaptive runs are ranked; the static runs are the baseline line after them.
        assert!(
            lines[2].contains("bisect48-5-rk4") && lines[2].ends_with("x5.00"),
            "{text}"
        );
        assert!(lines[3].contains("remesh-5-rk4"), "{text}");
        assert!(lines[3].ends_with("x0.50"), "{text}");
        assert!(lines[4].starts_with("  static baseline: 9x9"), "{text}");
        assert!(lines[5].contains("upper bound"), "{text}");
        assert_eq!(lines.len(), 6, "{text}");
        assert!(!text.contains("none of these runs is resolved"), "{text}");
    }

    /// When every adaptive run is within 2x of the reference's floor, the table says the
    /// reference cannot rank them.
    #[test]
    fn a_ranking_of_unresolved_runs_says_so() {
        let rows = [
            run("static", "static", 9, 1.0, 4e-2),
            run("static", "static", 17, 10.0, 2e-2),
            run("bisect48", "bisect48", 5, 2.0, 2e-2),
            run("remesh", "remesh", 5, 20.0, 1.5e-2),
        ];
        let mut c = comparison(&rows);
        c.manifest.reference.floor.e_rms = 1.5e-2;
        let text = ranking(&c);
        assert!(text.contains("none of these runs is resolved"), "{text}");
        c.manifest.reference.floor.e_rms = 0.9e-2; // bisect48 at 2e-2 is now resolved
        assert!(!ranking(&c).contains("none of these runs is resolved"));
    }

    /// A study interrupted before its adaptive runs completed says so instead of an empty table.
    #[test]
    fn a_ranking_without_completed_adaptive_runs_says_so() {
        let rows = [
            run("static", "static", 9, 1.0, 4e-2),
            run("bisect48", "bisect48", 5, 2.0, 2e-2),
        ];
        let mut c = comparison(&rows);
        let text = ranking(&c);
        assert!(!text.contains("no adaptive run completed"), "{text}");
        c.rows[1].status = "not run".into();
        let text = ranking(&c);
        assert!(
            text.contains("(no adaptive run completed with rk4)"),
            "{text}"
        );
    }
}
