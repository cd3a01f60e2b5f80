//! The computed reading of a comparison. Runs are grouped into **curves**: one per series (a
//! strategy, or a study run's label) and integrator, through its configurations (static: the grid
//! resolutions; adaptive: its sweep). Each curve is compared with the static curve of the same
//! integrator at the errors of static 17x17 and 33x33 (the two finest static grids when those are
//! missing), for the material-point error `e_rms` and the fold-insensitive surface distance
//! (Hausdorff) alike: speed-up = the static curve's wall time at that error / the curve's wall
//! time at it (both by log-log interpolation along the curves' Pareto fronts: a coarser static
//! grid as accurate as the target sets the static time, not the target's own run). Errors
//! within 2x of the reference floor are flagged as not resolved. Nothing here is written by
//! hand: it changes when the runs change.

use super::tables::{fmt_e, fmt_s};
use crate::eval::metrics::{pareto_front, static_time_at_error};
use crate::study::{Comparison, Row};
use std::fmt::Write as _;

/// An error measure of the comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    /// RMS over frames of the material-point error `e(t)`.
    Rms,
    /// Hausdorff distance between the final surfaces.
    Hausdorff,
}

impl Metric {
    /// Both measures, in report order.
    pub const ALL: [Metric; 2] = [Metric::Rms, Metric::Hausdorff];

    /// Its name in tables and plots.
    pub fn name(self) -> &'static str {
        match self {
            Metric::Rms => "e_rms",
            Metric::Hausdorff => "Hausdorff",
        }
    }

    /// Its value for a run (m).
    pub fn of(self, r: &Row) -> f64 {
        match self {
            Metric::Rms => r.e_rms,
            Metric::Hausdorff => r.hausdorff,
        }
    }

    /// The reference floor of this measure (m).
    pub fn floor(self, c: &Comparison) -> f64 {
        let f = &c.manifest.reference.floor;
        match self {
            Metric::Rms => f.e_rms,
            Metric::Hausdorff => f.hausdorff,
        }
    }

    /// Whether the reference resolves `error` (m) in this measure: at least twice its floor.
    /// Below that the reference cannot tell errors apart ("not resolved").
    pub fn resolves(self, c: &Comparison, error: f64) -> bool {
        error >= 2.0 * self.floor(c)
    }
}

/// One curve: the completed runs of a series under one integrator, by increasing wall time.
#[derive(Clone, Debug)]
pub struct Curve<'a> {
    /// The series (a strategy, or a study run's label).
    pub series: &'a str,
    /// Its strategy.
    pub strategy: &'a str,
    /// The integrator.
    pub integrator: &'a str,
    /// Its completed runs, fastest first.
    pub rows: Vec<&'a Row>,
}

impl Curve<'_> {
    /// Whether this is a static-mesh curve.
    pub fn is_static(&self) -> bool {
        self.strategy == "static"
    }
}

/// The integrators of a comparison, in the order runs first use them.
pub fn integrators(c: &Comparison) -> Vec<&str> {
    let mut out: Vec<&str> = Vec::new();
    for r in &c.rows {
        if !out.contains(&r.integrator.as_str()) {
            out.push(&r.integrator);
        }
    }
    out
}

/// The curves of one integrator: static first, then the others in the order they first appear.
pub fn curves<'a>(c: &'a Comparison, integrator: &str) -> Vec<Curve<'a>> {
    let mut out: Vec<Curve<'a>> = Vec::new();
    for r in c
        .rows
        .iter()
        .filter(|r| r.integrator == integrator && r.completed())
    {
        match out.iter_mut().find(|k| k.series == r.series) {
            Some(k) => k.rows.push(r),
            None => out.push(Curve {
                series: &r.series,
                strategy: &r.strategy,
                integrator: &r.integrator,
                rows: vec![r],
            }),
        }
    }
    for k in &mut out {
        k.rows.sort_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
    }
    out.sort_by_key(|k| !k.is_static());
    out
}

/// How a curve reaches an error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reach {
    /// At this wall time (s), interpolated along the curve.
    At(f64),
    /// Already at its fastest run (s): the error is reached in at most this time.
    AtMost(f64),
    /// Never: its best error (m) is above.
    Never(f64),
}

/// Where `curve` reaches `error` in `metric`.
pub fn reach(curve: &Curve, metric: Metric, error: f64) -> Reach {
    let points: Vec<(f64, f64)> = curve
        .rows
        .iter()
        .map(|r| (r.wall_s, metric.of(r)))
        .collect();
    let front: Vec<(f64, f64)> = pareto_front(&points)
        .into_iter()
        .map(|i| points[i])
        .collect();
    let best = front.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    match front.first() {
        Some(&(t, e)) if e <= error => Reach::AtMost(t),
        _ if best.is_nan() || best > error => Reach::Never(best),
        _ => static_time_at_error(&points, error).map_or(Reach::Never(best), Reach::At),
    }
}

/// The static runs whose errors are the targets: 17x17 and 33x33, or the two finest.
pub fn targets<'a>(statics: &Curve<'a>) -> Vec<&'a Row> {
    let mut by_grid = statics.rows.clone();
    by_grid.sort_by_key(|r| r.resolution);
    let named: Vec<&Row> = by_grid
        .iter()
        .copied()
        .filter(|r| r.resolution == 17 || r.resolution == 33)
        .collect();
    if named.len() == 2 {
        return named;
    }
    by_grid.iter().rev().take(2).rev().copied().collect()
}

/// The static curve's wall time (s) at `error` in `metric`: its cheapest way to that error,
/// interpolated along its Pareto front, so a coarser grid as accurate as a target grid sets the
/// time, not the target's own run. `fallback` (s) when the curve cannot tell (it never gets
/// there).
pub fn static_time(statics: &Curve, metric: Metric, error: f64, fallback: f64) -> f64 {
    match reach(statics, metric, error) {
        Reach::At(t) | Reach::AtMost(t) => t,
        Reach::Never(_) => fallback,
    }
}

/// A speed-up cell against the static curve's time `baseline` (s) at the target's error: `x2.31`,
/// `>= x4.0`, `does not reach (best 3.1e-2 m)`; its speed-up (0 when it does not reach).
fn speedup_cell(curve: &Curve, target: &Row, baseline: f64, metric: Metric) -> (String, f64) {
    match reach(curve, metric, metric.of(target)) {
        Reach::At(t) => (format!("x{:.2}", baseline / t), baseline / t),
        Reach::AtMost(t) => (format!(">= x{:.2}", baseline / t), baseline / t),
        Reach::Never(best) => (format!("does not reach (best {} m)", fmt_e(best)), 0.0),
    }
}

/// What the summary's cells and headers mean (markdown, one paragraph): printed under the
/// summary tables of `report.md` and `docs/results.md` alike.
pub const SUMMARY_NOTE: &str = "\
Per scene and integrator, each strategy is a curve through its configurations. At the error of \
static 17x17 and of static 33x33 (the two finest static grids when those are missing; e_rms and \
Hausdorff alike), the speed-up is the static curve's wall time for that error over the time the \
strategy's curve needs for the same error (log-log interpolation along both curves' Pareto \
fronts). The static curve's time, given in each column's header, is that of its cheapest grid \
that gets there: a coarser grid as accurate as the target sets it, so it can be shorter than \
the target grid's own run (and shorter for 33x33 than for 17x17). `>=`: the strategy's fastest \
run is already below that error. Above 1 the strategy buys more accuracy per second than the \
static mesh. **not resolved**: the target error is within 2x of the reference's error floor; \
the reference cannot tell errors that small apart, so that column's speed-ups and winner are \
not evidence either way.
";

/// The answer first: per scene and integrator, each strategy's speed-up over the static curve at
/// the errors of the target static grids, for e_rms and Hausdorff, and the winner, then
/// [`SUMMARY_NOTE`] (markdown).
pub fn summary<'a>(comparisons: impl IntoIterator<Item = &'a Comparison>) -> String {
    let mut s = String::new();
    for c in comparisons {
        for integrator in integrators(c) {
            s += &summary_block(c, integrator);
        }
    }
    if s.is_empty() {
        return "No static and adaptive curves to compare yet.\n".into();
    }
    s + SUMMARY_NOTE
}

/// The summary table of one scene and integrator.
fn summary_block(c: &Comparison, integrator: &str) -> String {
    let all = curves(c, integrator);
    let Some(statics) = all.iter().find(|k| k.is_static()) else {
        return String::new();
    };
    let targets = targets(statics);
    let others: Vec<&Curve> = all.iter().filter(|k| !k.is_static()).collect();
    if targets.is_empty() || others.is_empty() {
        return String::new();
    }
    let baseline = |m: Metric, t: &Row| static_time(statics, m, m.of(t), t.wall_s);
    let columns: Vec<(Metric, &Row)> = Metric::ALL
        .iter()
        .flat_map(|m| targets.iter().map(move |t| (*m, *t)))
        .collect();
    let flag = |m: Metric, t: &Row| {
        if m.resolves(c, m.of(t)) {
            ""
        } else {
            ", **not resolved**"
        }
    };
    let mut head = format!("| strategy ({}, `{integrator}`) |", c.manifest.scene);
    for &(m, t) in &columns {
        let _ = write!(
            head,
            " {} of static {}x{} ({} m{}; static curve {} s) |",
            m.name(),
            t.resolution,
            t.resolution,
            fmt_e(m.of(t)),
            flag(m, t),
            fmt_s(baseline(m, t))
        );
    }
    let mut s = format!("{head}\n|---|{}\n", "---:|".repeat(columns.len()));
    let mut best: Vec<(f64, &str)> = vec![(0.0, "none"); columns.len()];
    for k in &others {
        let mut row = format!("| `{}` |", k.series);
        for (j, &(m, t)) in columns.iter().enumerate() {
            let (cell, x) = speedup_cell(k, t, baseline(m, t), m);
            let _ = write!(row, " {cell} |");
            if x > best[j].0 {
                best[j] = (x, k.series);
            }
        }
        s += &row;
        s.push('\n');
    }
    let mut win = String::from("| **wins** |");
    for (&(x, name), &(m, t)) in best.iter().zip(&columns) {
        let who = if x >= 1.0 {
            format!("`{name}`")
        } else {
            "static".into()
        };
        let note = if flag(m, t).is_empty() {
            ""
        } else {
            " (not resolved)"
        };
        let _ = write!(win, " {who}{note} |");
    }
    s += &win;
    s += "\n\n";
    s
}

/// The computed reading (markdown): failed runs; per integrator, the static curve (observed
/// order and cost exponent between grids) and each other run's speed-up at its own error with
/// where its time goes.
pub fn reading(c: &Comparison) -> String {
    let mut s = String::new();
    for r in c.rows.iter().filter(|r| !r.completed()) {
        let _ = writeln!(
            s,
            "- **{}** did not complete (status `{}`, reached t = {:.3} s); it is left out of the \
             curves and the speed-ups.",
            r.label, r.status, r.sim_time
        );
    }
    for integrator in integrators(c) {
        let all = curves(c, integrator);
        let _ = writeln!(s, "- With `{integrator}`:");
        let statics = all.iter().find(|k| k.is_static());
        if let Some(st) = statics {
            s += &static_curve(c, st);
        }
        for k in all.iter().filter(|k| !k.is_static()) {
            for r in &k.rows {
                s += &run_line(c, r, statics);
            }
        }
    }
    s
}

/// The static curve: its points, and the observed order and cost exponent between grids.
fn static_curve(c: &Comparison, statics: &Curve) -> String {
    let mut s = String::new();
    let mut sorted = statics.rows.clone();
    sorted.sort_by_key(|r| r.resolution);
    let list: Vec<String> = sorted
        .iter()
        .map(|r| {
            let n = r.resolution;
            format!(
                "{n}x{n}: e_rms {} m in {} s",
                fmt_e(r.e_rms),
                fmt_s(r.wall_s)
            )
        })
        .collect();
    let _ = writeln!(s, "  - Static mesh: {}.", list.join("; "));
    for w in sorted.windows(2) {
        let (a, b) = (w[0], w[1]);
        let h = ((a.resolution - 1) as f64 / (b.resolution - 1) as f64).ln();
        let order = (a.e_rms / b.e_rms).ln() / (-h);
        let cost = (b.wall_s / a.wall_s).ln() / (-h);
        let _ = writeln!(
            s,
            "    - {}x{} -> {}x{}: error x{:.2} (observed order {:.2} in the edge length), wall time x{:.1} (exponent {:.2}).",
            a.resolution, a.resolution, b.resolution, b.resolution,
            b.e_rms / a.e_rms, order, b.wall_s / a.wall_s, cost
        );
    }
    let near: Vec<&str> = sorted
        .iter()
        .filter(|r| !Metric::Rms.resolves(c, r.e_rms))
        .map(|r| r.label.as_str())
        .collect();
    if !near.is_empty() {
        let _ = writeln!(
            s,
            "    - Within a factor 2 of the reference floor ({} m), so not resolved by this reference: {}.",
            fmt_e(c.manifest.reference.floor.e_rms),
            near.join(", ")
        );
    }
    s
}

/// One adaptive run: its speed-up over the static curve at its own e_rms, and its time profile.
fn run_line(c: &Comparison, r: &Row, statics: Option<&Curve>) -> String {
    let total = r.integrate_s + r.collide_s + r.adapt_s + r.rebuild_s + r.record_s;
    let stage = |x: f64| 100.0 * x / total.max(1e-300);
    let time = format!(
        "integrate {:.0} %, collide {:.0} %, adapt {:.0} %, rebuild {:.0} %, record {:.0} %; {} steps, {:.0} mean vertices",
        stage(r.integrate_s), stage(r.collide_s), stage(r.adapt_s), stage(r.rebuild_s),
        stage(r.record_s), r.steps, r.mean_vertices
    );
    let head = format!(
        "  - **{}**: e_rms {} m in {} s",
        r.label,
        fmt_e(r.e_rms),
        fmt_s(r.wall_s)
    );
    let static_rows: Vec<&Row> = statics.map(|k| k.rows.clone()).unwrap_or_default();
    let mut s = match statics.map(|k| reach(k, Metric::Rms, r.e_rms)) {
        Some(Reach::At(t)) => {
            let x = t / r.wall_s;
            let verdict = if x >= 1.0 { "wins" } else { "loses" };
            let flag = if Metric::Rms.resolves(c, r.e_rms) {
                ""
            } else {
                "; not resolved: within 2x of the floor"
            };
            format!(
                "{head}; the static mesh needs {} s for that error: speed-up **x{x:.2}** ({verdict}{flag}). Time: {time}.\n",
                fmt_s(t)
            )
        }
        Some(Reach::AtMost(_)) => format!(
            "{head}: less accurate than the fastest static run. Time: {time}.\n"
        ),
        Some(Reach::Never(_)) => format!(
            "{head}: more accurate than every static run (no static time to compare). Time: {time}.\n"
        ),
        None => format!("{head}: no static run with this integrator. Time: {time}.\n"),
    };
    let loses = match statics.map(|k| reach(k, Metric::Rms, r.e_rms)) {
        Some(Reach::At(t)) => t < r.wall_s,
        Some(Reach::AtMost(_)) => true,
        _ => false,
    };
    if loses {
        let _ = writeln!(s, "    - {}", why_slow(r, &static_rows));
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
            "it takes {:.1}x the steps of static {}x{} ({} vs {})",
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::study::table::tests::row;

    pub(crate) fn run(series: &str, strategy: &str, resolution: usize, wall_s: f64, e: f64) -> Row {
        Row {
            series: series.into(),
            strategy: strategy.into(),
            resolution,
            label: format!("{series}-{resolution}-rk4"),
            wall_s,
            e_rms: e,
            hausdorff: 2.0 * e,
            ..row("x")
        }
    }

    /// A comparison of these rows under the test manifest.
    pub(crate) fn comparison(rows: &[Row]) -> Comparison {
        Comparison {
            manifest: crate::study::table::tests::manifest(),
            rows: rows.to_vec(),
        }
    }

    #[test]
    fn curves_reach_errors_by_interpolation_and_say_when_they_cannot() {
        let rows = [
            run("static", "static", 5, 1.0, 4e-2),
            run("static", "static", 17, 10.0, 2e-2),
            run("static", "static", 33, 100.0, 1e-2),
            run("bisect48", "bisect48", 5, 2.0, 3e-2),
            run("bisect48", "bisect48", 5, 20.0, 1e-2),
        ];
        let c = comparison(&rows);
        let all = curves(&c, "rk4");
        assert_eq!(all.len(), 2);
        assert!(all[0].is_static());
        let t = targets(&all[0]);
        assert_eq!(t.iter().map(|r| r.resolution).collect::<Vec<_>>(), [17, 33]);
        // bisect48 reaches 2e-2 between (2 s, 3e-2) and (20 s, 1e-2): log-log interpolation.
        let Reach::At(time) = reach(&all[1], Metric::Rms, 2e-2) else {
            panic!("reaches")
        };
        let s = (2e-2f64.ln() - 3e-2f64.ln()) / (1e-2f64.ln() - 3e-2f64.ln());
        assert!((time - (2f64.ln() + s * (20f64 / 2.0).ln()).exp()).abs() < 1e-9);
        assert_eq!(reach(&all[1], Metric::Rms, 5e-3), Reach::Never(1e-2));
        assert_eq!(reach(&all[1], Metric::Rms, 5e-2), Reach::AtMost(2.0));
        let table = summary([&c]);
        assert!(table.contains("e_rms of static 17x17"), "{table}");
        assert!(table.contains("Hausdorff of static 33x33"), "{table}");
        // At 33x33's error (1e-2 m in 100 s) bisect48 takes 20 s: x5.00, it wins there.
        assert!(table.contains("x5.00"), "{table}");
        assert!(table.contains("| **wins** |"), "{table}");
        assert!(table.contains("`bisect48`"), "{table}");
    }

    #[test]
    fn speed_ups_are_taken_against_the_static_curve_not_the_target_run() {
        // Static 9x9 is as accurate as 17x17 (fold noise) and 5x faster: at 17x17's error the
        // static curve takes 2 s, so bisect48 at 1 s is x2.00, not x10.00.
        let rows = [
            run("static", "static", 5, 0.5, 4e-2),
            run("static", "static", 9, 2.0, 2e-2),
            run("static", "static", 17, 10.0, 2e-2),
            run("static", "static", 33, 100.0, 1e-2),
            run("bisect48", "bisect48", 5, 1.0, 2e-2),
        ];
        let c = comparison(&rows);
        let all = curves(&c, "rk4");
        assert_eq!(static_time(&all[0], Metric::Rms, 2e-2, 10.0), 2.0);
        let table = summary([&c]);
        assert!(table.contains("static curve 2.0 s"), "{table}");
        assert!(table.contains("x2.00"), "{table}");
        assert!(!table.contains("x10.00"), "{table}");
    }

    #[test]
    fn a_target_within_2x_of_the_floor_flags_its_column_and_its_winner() {
        // The floor is 1e-4 m in both measures; static 33x33's e_rms (1.5e-4 m) is within 2x of
        // it, its Hausdorff (3e-4 m, twice e_rms) is not, nor is anything at 17x17.
        let rows = [
            run("static", "static", 5, 1.0, 4e-2),
            run("static", "static", 17, 10.0, 2e-2),
            run("static", "static", 33, 100.0, 1.5e-4),
            run("bisect48", "bisect48", 5, 2.0, 2e-2),
            run("bisect48", "bisect48", 9, 20.0, 1e-4),
        ];
        let c = comparison(&rows);
        assert!(!Metric::Rms.resolves(&c, 1.5e-4));
        assert!(Metric::Hausdorff.resolves(&c, 3e-4));
        let table = summary([&c]);
        let lines: Vec<&str> = table.lines().collect();
        let head: Vec<&str> = lines[0].trim_matches('|').split(" | ").collect();
        let flagged: Vec<bool> = head[1..]
            .iter()
            .map(|h| h.contains("**not resolved**"))
            .collect();
        // Columns: e_rms 17, e_rms 33, Hausdorff 17, Hausdorff 33.
        assert_eq!(flagged, [false, true, false, false], "{table}");
        let wins = lines
            .iter()
            .find(|l| l.starts_with("| **wins** |"))
            .expect("a verdict row");
        let verdict: Vec<&str> = wins.trim_matches('|').split(" | ").map(str::trim).collect();
        assert_eq!(
            verdict[1..],
            [
                "`bisect48`",
                "`bisect48` (not resolved)",
                "`bisect48`",
                "`bisect48`"
            ],
            "{table}"
        );
        // The definitions follow the table once, here as in docs/results.md.
        assert!(table.ends_with(SUMMARY_NOTE), "{table}");
        assert_eq!(table.matches("**not resolved**:").count(), 1, "{table}");
    }
}
