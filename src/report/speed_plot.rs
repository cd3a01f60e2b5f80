//! The speed-error plot: wall time against error, log-log, one panel per integrator (the same
//! axes in every panel), each strategy a line through its configurations (static: the grid
//! resolutions, circles; adaptive: its sweep, triangles), each point tagged with what varies
//! along its line (a tag that would overlap one already drawn moves below or left of its point,
//! else is left out), the reference floor dashed, and under the lines a thin black staircase:
//! the Pareto front of the panel's runs. The legend is a column of its own beside the panels, so
//! it never hides a point or a label.

use super::plots::{
    color, log_range, log_tick, log_tick_sci, register_fonts, write_figure, DrawResult, PlotError,
};
use crate::eval::metrics::pareto_front;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// One line of a panel: a strategy (or study series) through its configurations.
#[derive(Clone, Debug)]
pub struct SpeedCurve {
    /// Legend label (the same label has the same colour in every panel).
    pub label: String,
    /// Static mesh (circles) or adaptive (triangles).
    pub is_static: bool,
    /// `(wall time s, error m, tag)` per configuration; drawn in order of wall time.
    pub points: Vec<(f64, f64, String)>,
}

/// One panel: the curves of one integrator.
#[derive(Clone, Debug)]
pub struct SpeedPanel {
    /// Panel title (the integrator).
    pub title: String,
    /// Its curves.
    pub curves: Vec<SpeedCurve>,
    /// The reference floor of the error (m), dashed.
    pub floor: Option<f64>,
}

const PANEL_WIDTH: u32 = 560;
const LEGEND_WIDTH: u32 = 230;
const HEIGHT: u32 = 560;

fn finite_positive(p: &(f64, f64, String)) -> bool {
    p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite()
}

/// The Pareto front of a panel over the runs of all its curves (those no other run of the panel
/// beats in both wall time and error), as a staircase `(s, m)` from the fastest run to the most
/// accurate: from each front run right at its error to the next one's time, then down to its
/// error. Empty without a finite, positive point.
fn front_steps(panel: &SpeedPanel) -> Vec<(f64, f64)> {
    let points: Vec<(f64, f64)> = panel
        .curves
        .iter()
        .flat_map(|c| &c.points)
        .filter(|p| finite_positive(p))
        .map(|p| (p.0, p.1))
        .collect();
    let mut steps: Vec<(f64, f64)> = Vec::new();
    for (t, e) in pareto_front(&points).into_iter().map(|i| points[i]) {
        if let Some(&(_, above)) = steps.last() {
            steps.push((t, above));
        }
        steps.push((t, e));
    }
    steps
}

/// A label's box in backend pixels: `(left, top, right, bottom)`.
type LabelBox = (i32, i32, i32, i32);

/// Where a label of `size` (w, h px) for the point at `at` (px) goes, as an offset from it: the
/// first of above right, below right, above left and below left whose box overlaps no box in
/// `placed` (the box then joins them); `None` when every place overlaps (the label is left out,
/// the point keeps its marker).
fn place_label(at: (i32, i32), size: (u32, u32), placed: &mut Vec<LabelBox>) -> Option<(i32, i32)> {
    let (w, h) = (size.0 as i32, size.1 as i32);
    let offsets = [(6, -14), (6, 4), (-6 - w, -14), (-6 - w, 4)];
    let overlaps = |a: LabelBox, b: LabelBox| a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3;
    let (dx, dy) = offsets.into_iter().find(|&(dx, dy)| {
        let b = (at.0 + dx, at.1 + dy, at.0 + dx + w, at.1 + dy + h);
        !placed.iter().any(|&p| overlaps(p, b))
    })?;
    placed.push((at.0 + dx, at.1 + dy, at.0 + dx + w, at.1 + dy + h));
    Some((dx, dy))
}

/// Draws the plot to `stem.svg` and `stem.png` and returns the files written.
pub fn speed_error(
    stem: &Path,
    title: &str,
    error_name: &str,
    panels: &[SpeedPanel],
) -> Result<Vec<PathBuf>, PlotError> {
    register_fonts();
    let size = (
        PANEL_WIDTH * panels.len().max(1) as u32 + LEGEND_WIDTH,
        HEIGHT,
    );
    write_figure(
        stem,
        size,
        |root| draw(root, title, error_name, panels),
        |root| draw(root, title, error_name, panels),
    )
}

/// Every curve label in first-appearance order: a label's colour is its position here.
fn labels(panels: &[SpeedPanel]) -> Vec<(String, bool)> {
    let mut out: Vec<(String, bool)> = Vec::new();
    for c in panels.iter().flat_map(|p| &p.curves) {
        if !out.iter().any(|(l, _)| *l == c.label) {
            out.push((c.label.clone(), c.is_static));
        }
    }
    out
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    error_name: &str,
    panels: &[SpeedPanel],
) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 20))?;
    let points = || {
        panels
            .iter()
            .flat_map(|p| &p.curves)
            .flat_map(|c| &c.points)
            .filter(|p| finite_positive(p))
    };
    let (x0, x1) = log_range(points().map(|p| p.0));
    let floors = panels.iter().filter_map(|p| p.floor);
    let (y0, y1) = log_range(points().map(|p| p.1).chain(floors));
    let legend = labels(panels);
    let (plots, side) = root.split_horizontally(root.dim_in_pixel().0 - LEGEND_WIDTH);
    let areas = plots.split_evenly((1, panels.len().max(1)));
    for (area, panel) in areas.iter().zip(panels) {
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 16))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("wall time (s)")
            .y_desc(format!("{error_name} (m)"))
            .light_line_style(WHITE)
            .label_style(("sans-serif", 12))
            .axis_desc_style(("sans-serif", 14))
            .x_label_formatter(&|v| log_tick(*v))
            .y_label_formatter(&|v| log_tick_sci(*v))
            .draw()?;
        if let Some(f) = panel.floor.filter(|f| *f > 0.0 && f.is_finite()) {
            let style = ShapeStyle::from(&RGBColor(120, 120, 120)).stroke_width(1);
            let (l0, l1) = (x0.ln(), x1.ln());
            for k in (0..40).step_by(2) {
                let a = (l0 + (l1 - l0) * k as f64 / 40.0).exp();
                let b = (l0 + (l1 - l0) * (k + 1) as f64 / 40.0).exp();
                chart.draw_series(LineSeries::new(vec![(a, f), (b, f)], style))?;
            }
        }
        let front = ShapeStyle::from(&BLACK).stroke_width(1);
        chart.draw_series(LineSeries::new(front_steps(panel), front))?;
        let mut placed: Vec<LabelBox> = Vec::new();
        for curve in &panel.curves {
            let k = legend
                .iter()
                .position(|(l, _)| *l == curve.label)
                .unwrap_or(0);
            let c = color(k);
            let mut pts: Vec<&(f64, f64, String)> =
                curve.points.iter().filter(|p| finite_positive(p)).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let line = ShapeStyle::from(&c).stroke_width(2);
            chart.draw_series(LineSeries::new(pts.iter().map(|p| (p.0, p.1)), line))?;
            let fill = ShapeStyle::from(&c).filled();
            for p in pts {
                let at = (p.0, p.1);
                if curve.is_static {
                    chart.draw_series(std::iter::once(Circle::new(at, 5, fill)))?;
                } else {
                    chart.draw_series(std::iter::once(TriangleMarker::new(at, 7, fill)))?;
                }
                let font = ("sans-serif", 11).into_font().color(&c);
                let size = area.estimate_text_size(&p.2, &font)?;
                if let Some(offset) = place_label(chart.backend_coord(&at), size, &mut placed) {
                    chart.draw_series(std::iter::once(
                        EmptyElement::at(at) + Text::new(p.2.clone(), offset, font),
                    ))?;
                }
            }
        }
    }
    draw_legend(&side, &legend, panels.iter().any(|p| p.floor.is_some()))
}

/// The legend column: one line per curve label, the Pareto front, then the floor.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    legend: &[(String, bool)],
    floor: bool,
) -> DrawResult<DB> {
    let font = ("sans-serif", 13).into_font();
    let mut y = 60;
    for (k, (label, is_static)) in legend.iter().enumerate() {
        let c = color(k);
        let fill = ShapeStyle::from(&c).filled();
        area.draw(&PathElement::new(
            vec![(8, y), (36, y)],
            ShapeStyle::from(&c).stroke_width(2),
        ))?;
        if *is_static {
            area.draw(&Circle::new((22, y), 5, fill))?;
        } else {
            area.draw(&TriangleMarker::new((22, y), 7, fill))?;
        }
        area.draw(&Text::new(label.clone(), (44, y - 8), font.clone()))?;
        y += 24;
    }
    let black = ShapeStyle::from(&BLACK).stroke_width(1);
    area.draw(&PathElement::new(
        vec![(8, y), (22, y), (22, y + 6), (36, y + 6)],
        black,
    ))?;
    area.draw(&Text::new(
        "Pareto front (all runs)",
        (44, y - 5),
        font.clone(),
    ))?;
    y += 24;
    if floor {
        let grey = ShapeStyle::from(&RGBColor(120, 120, 120)).stroke_width(1);
        area.draw(&PathElement::new(vec![(8, y), (16, y)], grey))?;
        area.draw(&PathElement::new(vec![(24, y), (32, y)], grey))?;
        area.draw(&Text::new("reference floor", (44, y - 8), font))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_panel_per_integrator_and_the_legend_beside_them() {
        let dir = tempfile::tempdir().unwrap();
        let curve = |label: &str, is_static: bool, k: f64| SpeedCurve {
            label: label.into(),
            is_static,
            points: vec![(k, 0.1 / k, "5".into()), (10.0 * k, 0.01 / k, "17".into())],
        };
        let panel = |title: &str| SpeedPanel {
            title: title.into(),
            curves: vec![curve("static", true, 1.0), curve("bisect48", false, 2.0)],
            floor: Some(1e-3),
        };
        let files = speed_error(
            &dir.path().join("se"),
            "t",
            "e_rms",
            &[panel("rk4"), panel("implicit_euler")],
        )
        .unwrap();
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        assert!(svg.contains(&format!("width=\"{}\"", 2 * PANEL_WIDTH + LEGEND_WIDTH)));
        for text in [
            "rk4",
            "implicit_euler",
            "bisect48",
            "reference floor",
            "Pareto front",
        ] {
            assert!(svg.contains(text), "{text}");
        }
        // Each panel's front: all four runs are on it (static at 1 and 10 s, bisect48 at 2 and
        // 20 s, each more accurate than the faster ones), a black staircase of 7 points; the
        // axes, ticks and the legend's sample are black polylines of at most 4.
        assert_eq!(front_steps(&panel("rk4")).len(), 7);
        let polylines = svg
            .split("<polyline")
            .skip(1)
            .map(|p| p.split("/>").next().unwrap());
        let staircases = polylines
            .filter(|p| p.contains("stroke=\"#000000\""))
            .map(|p| {
                p.split("points=\"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap()
            })
            .filter(|points| points.split_whitespace().count() >= 7)
            .count();
        assert_eq!(staircases, 2, "{svg}");
        assert!(std::fs::metadata(&files[1]).unwrap().len() > 1000);
    }

    #[test]
    fn the_front_steps_through_the_runs_no_other_run_beats() {
        let curve = |label: &str, points: &[(f64, f64)]| SpeedCurve {
            label: label.into(),
            is_static: label == "static",
            points: points.iter().map(|&(t, e)| (t, e, String::new())).collect(),
        };
        let panel = SpeedPanel {
            title: "rk4".into(),
            curves: vec![
                // 4 s is beaten by bisect48's 3 s run; 0 s cannot be drawn on a log axis.
                curve(
                    "static",
                    &[(1.0, 0.1), (4.0, 0.04), (10.0, 0.01), (0.0, 1e-9)],
                ),
                curve("bisect48", &[(3.0, 0.03), (20.0, 0.02), (f64::NAN, 1e-9)]),
            ],
            floor: None,
        };
        assert_eq!(
            front_steps(&panel),
            [
                (1.0, 0.1),
                (3.0, 0.1),
                (3.0, 0.03),
                (10.0, 0.03),
                (10.0, 0.01)
            ]
        );
        let empty = SpeedPanel {
            curves: Vec::new(),
            ..panel
        };
        assert!(front_steps(&empty).is_empty());
    }

    #[test]
    fn a_label_that_would_overlap_moves_and_is_left_out_when_nowhere_is_free() {
        let mut placed = Vec::new();
        let size = (20, 10);
        // Four labels of one spot take the four places in turn; a fifth has none.
        assert_eq!(place_label((100, 100), size, &mut placed), Some((6, -14)));
        assert_eq!(place_label((102, 101), size, &mut placed), Some((6, 4)));
        assert_eq!(place_label((100, 100), size, &mut placed), Some((-26, -14)));
        assert_eq!(place_label((100, 100), size, &mut placed), Some((-26, 4)));
        assert_eq!(place_label((100, 100), size, &mut placed), None);
        assert_eq!(placed.len(), 4);
        // A label clear of the others keeps the first place.
        assert_eq!(place_label((200, 100), size, &mut placed), Some((6, -14)));
    }

    #[test]
    fn tags_of_points_in_one_spot_are_drawn_where_they_fit_and_no_more() {
        let dir = tempfile::tempdir().unwrap();
        let points = (0..5)
            .map(|k| (1.0 + 1e-3 * k as f64, 0.01, format!("tag{k}")))
            .chain([(10.0, 0.001, "far".into())])
            .collect();
        let panel = SpeedPanel {
            title: "rk4".into(),
            curves: vec![SpeedCurve {
                label: "bisect48".into(),
                is_static: false,
                points,
            }],
            floor: None,
        };
        let files = speed_error(&dir.path().join("se"), "t", "e_rms", &[panel]).unwrap();
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        let drawn = (0..5)
            .filter(|k| svg.contains(&format!("\ntag{k}\n")))
            .count();
        assert_eq!(drawn, 4, "{svg}");
        assert!(svg.contains("\nfar\n"), "{svg}");
    }
}
