//! The markdown tables and paragraphs of a comparison: the runs table, where the time goes, and
//! the settings (reference, floor, samples).

use crate::study::Comparison;
use std::fmt::Write as _;
use std::path::Path;

/// An error (m) with three significant digits, `-` when not finite.
pub(crate) fn fmt_e(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "-".into()
    }
}

/// A count, `-` when not measured (not finite).
fn fmt_count(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.0}")
    } else {
        "-".into()
    }
}

/// A time (s) with a precision for its size, `-` when not finite.
pub(crate) fn fmt_s(x: f64) -> String {
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

/// The comparison table (markdown).
pub fn table(c: &Comparison) -> String {
    let mut s = String::from(
        "| run | status | wall (s) | steps | mean / max vertices | e_rms (m) | e_final (m) | tracked (m) | Hausdorff (m) | max penetration: vertices / surface (m) | self-intersections (max) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in &c.rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.0} / {} | {} | {} | {} | {} | {} / {} | {} |",
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
            fmt_e(r.max_penetration),
            fmt_e(r.max_surface_penetration),
            fmt_count(r.max_self_intersections)
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
/// `p` relative to `out` when inside it.
pub(crate) fn rel(out: &Path, p: &Path) -> String {
    p.strip_prefix(out).unwrap_or(p).display().to_string()
}

/// The settings paragraph (markdown).
pub fn settings(c: &Comparison) -> String {
    let m = &c.manifest;
    let r = &m.reference;
    format!(
        "Scene `{}` ({}), {} s simulated; each run at the scene's parameters (its time stepping: \
         beta = {}) except what its configuration sets (integrator, step, swept keys: see its \
         label and its `scene.resolved.toml`); \
         {} parallel job(s) on this machine (wall times include writing frames and metrics). \
         Reference: static {res}x{res}, {}, {}, {} steps, {} s wall (cache key `{}`). \
         Errors are measured on {s}x{s} material points (MODEL.md §1). \
         **Error floor** (static {f}x{f} against the reference): e_rms {} m, e_final {} m, tracked {} m, Hausdorff {} m.{}",
        m.scene,
        m.source,
        m.duration,
        m.beta,
        m.jobs,
        r.integrator,
        crate::eval::reference::step_description(r.beta, r.dt_initial, r.dt),
        r.steps,
        fmt_s(r.wall_s),
        r.key,
        fmt_e(r.floor.e_rms),
        fmt_e(r.floor.e_final),
        fmt_e(r.floor.tracked_err),
        fmt_e(r.floor.hausdorff),
        match &m.collision {
            Some(c) if c.self_collision => format!(
                " **Self-collision on** (thickness {} m), in every run and in the reference.",
                c.thickness
            ),
            Some(_) => " Self-collision off.".to_string(),
            None => String::new(),
        },
        res = r.resolution,
        s = r.samples,
        f = r.floor.resolution,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::reading::tests::comparison;
    use crate::scene::CollisionSpec;

    #[test]
    fn the_settings_say_whether_the_cloth_collides_with_itself() {
        let mut c = comparison(&[]);
        assert!(
            !settings(&c).contains("elf-collision"),
            "unknown: said nothing"
        );
        c.manifest.collision = Some(CollisionSpec::default());
        assert!(settings(&c).contains("Self-collision off."));
        c.manifest.collision = Some(CollisionSpec {
            self_collision: true,
            ..CollisionSpec::default()
        });
        let text = settings(&c);
        assert!(
            text.contains("**Self-collision on** (thickness 0.002 m)"),
            "{text}"
        );
    }
}
