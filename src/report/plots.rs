//! Plots (plotters, SVG and PNG, fonts from the embedded DejaVu Sans so no system font library is
//! needed): the shared helpers (fonts, colours, log ticks, ranges) and time series (any quantity
//! over simulated time, one line per run, one or more panels). The speed-error plot is
//! [`super::speed_plot`].

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// Why a plot could not be drawn.
#[derive(Debug, thiserror::Error)]
#[error("plot {path}: {message}")]
pub struct PlotError {
    /// The file.
    pub path: String,
    /// The backend's message.
    pub message: String,
}

pub(crate) fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// One line of a time series.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// `(t, y)` points.
    pub points: Vec<(f64, f64)>,
    /// Dashed (e.g. the reference).
    pub dashed: bool,
}

/// One panel of a time-series figure.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Y-axis label (with unit).
    pub y_label: String,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// The lines.
    pub series: Vec<Series>,
    /// Optional horizontal line `(label, y)` (e.g. the floor).
    pub hline: Option<(String, f64)>,
}

pub(crate) fn color(i: usize) -> RGBColor {
    const C: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    C[i % C.len()]
}

pub(crate) fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Whether `v` is 1, 2 or 5 times a power of ten (the labelled ticks of a log axis).
fn at_1_2_5(v: f64) -> bool {
    if !(v.is_finite() && v > 0.0) {
        return false;
    }
    let m = v / 10f64.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .any(|k| (m - k).abs() < 1e-6 * k)
}

/// A tick label on a log axis: only at 1, 2 and 5 times a power of ten (others left blank so the
/// labels do not collide).
pub(crate) fn log_tick(v: f64) -> String {
    if !at_1_2_5(v) {
        String::new()
    } else if v >= 1.0 {
        format!("{v:.0}")
    } else {
        let d = (-v.log10()).ceil().max(0.0) as usize;
        format!("{v:.d$}")
    }
}

/// [`log_tick`] in scientific notation (errors in metres).
pub(crate) fn log_tick_sci(v: f64) -> String {
    if at_1_2_5(v) {
        format!("{v:.0e}")
    } else {
        String::new()
    }
}

/// Log-axis range covering `values` (positive, finite), padded by a factor, and holding a power
/// of ten: plotters' log axis puts its ticks from the first power of ten in the range upwards, so
/// a range inside one decade (errors from 1.2e-2 to 9e-2 m) would have no tick and no label. The
/// low end then goes down below the power of ten under it (by a margin, as plotters finds that
/// power by rounding `ln(lo) / ln(10)` up, which lands on the next decade for `lo` exactly 1e-2).
pub(crate) fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for v in values.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    let (lo, hi) = if hi <= lo * 1.0001 {
        (lo / 2.0, hi * 2.0)
    } else {
        (lo / 1.6, hi * 1.6)
    };
    let decade = 10f64.powf(lo.log10().floor());
    let holds_a_power_of_ten = decade * 10.0 <= hi || decade >= lo;
    (
        if holds_a_power_of_ten {
            lo
        } else {
            decade / 1.25
        },
        hi,
    )
}

pub(crate) fn lin_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

pub(crate) type DrawResult<DB> =
    Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Draws a figure of stacked panels sharing the time axis to `stem.svg` and `stem.png`.
pub fn time_series(stem: &Path, title: &str, panels: &[Panel]) -> Result<Vec<PathBuf>, PlotError> {
    register_fonts();
    let h = 80 + 300 * panels.len() as u32;
    write_figure(
        stem,
        (860, h),
        |root| draw_panels(root, title, panels),
        |root| draw_panels(root, title, panels),
    )
}

/// Draws a figure of `size` pixels into memory, with `svg` and with `png` (the same drawing code
/// on each backend), and writes `stem.svg` and `stem.png` atomically ([`crate::io::write_atomic`]):
/// a failed draw or write leaves each file as it was and no temporary file. Returns the two files.
pub(crate) fn write_figure(
    stem: &Path,
    size: (u32, u32),
    svg: impl for<'a, 'b> FnOnce(&'a DrawingArea<SVGBackend<'b>, Shift>) -> DrawResult<SVGBackend<'b>>,
    png: impl for<'a, 'b> FnOnce(
        &'a DrawingArea<BitMapBackend<'b>, Shift>,
    ) -> DrawResult<BitMapBackend<'b>>,
) -> Result<Vec<PathBuf>, PlotError> {
    let (svg_path, png_path) = (stem.with_extension("svg"), stem.with_extension("png"));
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        svg(&root).map_err(|e| err(&svg_path, e))?;
        root.present().map_err(|e| err(&svg_path, e))?;
    }
    let mut rgb = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        png(&root).map_err(|e| err(&png_path, e))?;
        root.present().map_err(|e| err(&png_path, e))?;
    }
    let bytes =
        crate::report::render::encode_png(size.0, size.1, &rgb).map_err(|e| err(&png_path, e))?;
    crate::io::write_atomic(&svg_path, text.as_bytes()).map_err(|e| err(&svg_path, e))?;
    crate::io::write_atomic(&png_path, &bytes).map_err(|e| err(&png_path, e))?;
    Ok(vec![svg_path, png_path])
}

/// At most `n` points of a line, evenly picked (keeps files small).
fn thin(points: &[(f64, f64)], n: usize) -> Vec<(f64, f64)> {
    if points.len() <= n {
        return points.to_vec();
    }
    let step = points.len() as f64 / n as f64;
    let mut out: Vec<(f64, f64)> = (0..n).map(|k| points[(k as f64 * step) as usize]).collect();
    if let Some(last) = points.last() {
        out.push(*last);
    }
    out
}

fn draw_panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    panels: &[Panel],
) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 20))?;
    let areas = root.split_evenly((panels.len().max(1), 1));
    for (panel, area) in panels.iter().zip(areas) {
        let all = || {
            panel
                .series
                .iter()
                .flat_map(|s| s.points.iter().copied())
                .filter(|(t, y)| t.is_finite() && y.is_finite())
        };
        let (t0, t1) = lin_range(all().map(|p| p.0));
        let hline = panel.hline.as_ref().map(|h| h.1);
        let mut chart = ChartBuilder::on(&area);
        chart.margin(10).x_label_area_size(35).y_label_area_size(80);
        if panel.log_y {
            let (y0, y1) = log_range(all().map(|p| p.1).chain(hline));
            let mut c = chart.build_cartesian_2d(t0..t1, (y0..y1).log_scale())?;
            c.configure_mesh()
                .x_desc("t (s)")
                .y_desc(panel.y_label.as_str())
                .label_style(("sans-serif", 12))
                .axis_desc_style(("sans-serif", 14))
                .y_label_formatter(&|v| format!("{v:.1e}"))
                .draw()?;
            draw_lines(&mut c, panel, (t0, t1))?;
        } else {
            let (y0, y1) = lin_range(all().map(|p| p.1).chain(hline));
            let mut c = chart.build_cartesian_2d(t0..t1, y0..y1)?;
            c.configure_mesh()
                .x_desc("t (s)")
                .y_desc(panel.y_label.as_str())
                .label_style(("sans-serif", 12))
                .axis_desc_style(("sans-serif", 14))
                .y_label_formatter(&|v| format!("{v:.3}"))
                .draw()?;
            draw_lines(&mut c, panel, (t0, t1))?;
        }
    }
    Ok(())
}

fn draw_lines<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel,
    (t0, t1): (f64, f64),
) -> DrawResult<DB>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    for (i, s) in panel.series.iter().enumerate() {
        let c = if s.dashed { BLACK } else { color(i) };
        let style = ShapeStyle::from(&c).stroke_width(if s.dashed { 1 } else { 2 });
        let pts: Vec<(f64, f64)> = thin(&s.points, 600)
            .into_iter()
            .filter(|(t, y)| t.is_finite() && y.is_finite() && (!panel.log_y || *y > 0.0))
            .collect();
        if pts.is_empty() {
            continue;
        }
        let series = if s.dashed {
            chart.draw_series(DashedLineSeries::new(pts, 6, 4, style))?
        } else {
            chart.draw_series(LineSeries::new(pts, style))?
        };
        series
            .label(s.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], style));
    }
    if let Some((label, y)) = &panel.hline {
        if y.is_finite() && (!panel.log_y || *y > 0.0) {
            let style = ShapeStyle::from(&RGBColor(120, 120, 120)).stroke_width(1);
            chart
                .draw_series(DashedLineSeries::new(vec![(t0, *y), (t1, *y)], 8, 6, style))?
                .label(label.clone())
                .legend(move |(x, yy)| PathElement::new(vec![(x, yy), (x + 18, yy)], style));
        }
    }
    if !panel.series.is_empty() {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 12))
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every log range holds a power of ten (where plotters' ticks start) and covers its values.
    #[test]
    fn a_log_range_inside_one_decade_reaches_down_to_its_power_of_ten() {
        for values in [
            vec![1.9e-2, 5.7e-2],
            vec![3.0e-2, 3.0e-2],
            vec![0.9e-2, 1.5e-2],
            vec![1e-4, 2.0],
            vec![123.0, 456.0],
        ] {
            let (lo, hi) = log_range(values.iter().copied());
            assert!(
                values.iter().all(|v| lo < *v && *v < hi),
                "{values:?}: {lo} {hi}"
            );
            // As plotters finds it.
            let first_power = 10f64.powf((lo.ln() / 10f64.ln()).ceil());
            assert!(first_power <= hi * (1.0 + 1e-12), "{values:?}: {lo} {hi}");
        }
        // A range already holding a power of ten keeps its padding.
        assert_eq!(log_range([1e-4, 2.0].into_iter()), (1e-4 / 1.6, 2.0 * 1.6));
    }

    #[test]
    fn time_series_are_written_without_system_fonts() {
        let dir = tempfile::tempdir().unwrap();
        let panel = Panel {
            y_label: "y".into(),
            log_y: true,
            series: vec![Series {
                label: "s".into(),
                points: (1..100).map(|k| (k as f64 * 0.01, k as f64)).collect(),
                dashed: false,
            }],
            hline: Some(("floor".into(), 3.0)),
        };
        let files = time_series(&dir.path().join("ts"), "t", &[panel.clone(), panel]).unwrap();
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        assert!(svg.contains("<svg"));
    }

    /// A plot replaces its files by a rename, never by writing into them: a reader holding the
    /// old file (here a hard link to it) keeps it whole; a failed write leaves no temporary file.
    #[test]
    fn plots_are_written_atomically() {
        let dir = tempfile::tempdir().unwrap();
        let panel = Panel {
            y_label: "y".into(),
            log_y: false,
            series: vec![Series {
                label: "s".into(),
                points: vec![(0.0, 1.0), (1.0, 2.0)],
                dashed: false,
            }],
            hline: None,
        };
        let stem = dir.path().join("ts");
        for ext in ["svg", "png"] {
            std::fs::write(stem.with_extension(ext), "old").unwrap();
            std::fs::hard_link(stem.with_extension(ext), dir.path().join(ext)).unwrap();
        }
        time_series(&stem, "t", std::slice::from_ref(&panel)).unwrap();
        for ext in ["svg", "png"] {
            assert_eq!(
                std::fs::read(dir.path().join(ext)).unwrap(),
                b"old",
                "{ext}"
            );
        }
        assert!(std::fs::read(stem.with_extension("png"))
            .unwrap()
            .starts_with(b"\x89PNG"));
        // A folder in the way of the PNG: an error, and nothing left under a temporary name.
        std::fs::remove_file(stem.with_extension("png")).unwrap();
        std::fs::create_dir(stem.with_extension("png")).unwrap();
        assert!(time_series(&stem, "t", &[panel]).is_err());
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
    }
}
