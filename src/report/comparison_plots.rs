//! The plots of one comparison, written into its folder: speed against error (e_rms and
//! Hausdorff), element counts,
//! step and its limits, the tracked point, and `e(t)`.

use super::plots::{self, Panel, Series};
use super::reading::{curves, integrators, Metric};
use super::speed_plot::{speed_error, SpeedCurve, SpeedPanel};
use super::ReportError;
use crate::io::read_numeric_csv;
use crate::study::{Comparison, Row};
use std::path::{Path, PathBuf};

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

/// What varies along a curve at one run, short: the grid for static runs and runs without a
/// sweep, else the swept values (`0.03` for `...-h_min=0.03`; `0.03/2` for two swept keys).
fn tag(r: &Row) -> String {
    let sweep = r
        .label
        .split_once(&format!("-{}-", r.integrator))
        .map(|(_, rest)| rest)
        .filter(|rest| r.strategy != "static" && !rest.is_empty());
    match sweep {
        Some(rest) => rest
            .split('-')
            .filter_map(|kv| kv.split_once('=').map(|(_, v)| v))
            .collect::<Vec<_>>()
            .join("/"),
        None => r.resolution.to_string(),
    }
}

/// The speed-error panels of a comparison in `metric`: one per integrator, one curve per series.
fn speed_panels(c: &Comparison, metric: Metric) -> Vec<SpeedPanel> {
    integrators(c)
        .into_iter()
        .map(|integrator| SpeedPanel {
            title: integrator.to_string(),
            curves: curves(c, integrator)
                .iter()
                .map(|k| SpeedCurve {
                    label: k.series.to_string(),
                    is_static: k.is_static(),
                    points: k
                        .rows
                        .iter()
                        .map(|r| (r.wall_s, metric.of(r), tag(r)))
                        .collect(),
                })
                .collect(),
            floor: Some(metric.floor(c)),
        })
        .collect()
}

/// The plots of a comparison, written into `out`.
pub fn write_plots(
    out: &Path,
    c: &Comparison,
) -> Result<Vec<(String, PathBuf, PathBuf)>, ReportError> {
    let m = &c.manifest;
    let mut files = Vec::new();
    let plot_err = |e: plots::PlotError| ReportError::Io {
        path: e.path.clone(),
        source: std::io::Error::other(e.message),
    };
    let mut push = |name: &str, f: Vec<PathBuf>| {
        if let [svg, png] = &f[..] {
            files.push((name.to_string(), svg.clone(), png.clone()));
        }
    };
    for (name, metric) in [
        ("speed_error", Metric::Rms),
        ("speed_hausdorff", Metric::Hausdorff),
    ] {
        let title = format!(
            "{}: wall time vs {} (reference {}x{})",
            m.scene,
            metric.name(),
            m.reference.resolution,
            m.reference.resolution
        );
        let panels = speed_panels(c, metric);
        let f = speed_error(&out.join(name), &title, metric.name(), &panels).map_err(plot_err)?;
        push(name, f);
    }

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::table::tests::row;

    #[test]
    fn tags_name_what_varies_along_a_curve() {
        let r = |strategy: &str, label: &str| Row {
            strategy: strategy.into(),
            label: label.into(),
            integrator: "implicit_euler".into(),
            resolution: 5,
            ..row("x")
        };
        assert_eq!(tag(&r("static", "static-5-implicit_euler")), "5");
        assert_eq!(tag(&r("bisect48", "bisect48-5-implicit_euler")), "5");
        assert_eq!(
            tag(&r("bisect48", "bisect48-5-implicit_euler-h_min=0.03")),
            "0.03"
        );
        assert_eq!(
            tag(&r("simnett", "s-5-implicit_euler-h_min=0.03-interval=0.01")),
            "0.03/0.01"
        );
    }
}
