//! The error-map picture of a run: one panel per time, each the rest-space pattern `(u, v)`
//! coloured by the error `e(u, v)` (bilinear between the sample grid's points) with the run's
//! mesh at that time drawn over it, so one sees whether the vertices are where the error is. A
//! colour bar with its scale (m) closes the row; the scale is given by the caller so the maps of
//! several runs compare directly.

use super::picture::write_png;
use super::text::{draw_text, text_width, Image};
use super::RenderError;
use crate::eval::error_map::ErrorMap;
use std::path::Path;

/// Side of one map panel (pixels).
const PANEL: usize = 260;
/// Margin around panels (pixels).
const PAD: usize = 12;
/// Height of the label row above the panels (pixels).
const HEADER: usize = 28;
/// Width of the colour bar and its labels (pixels).
const BAR: usize = 120;
/// Mesh edge colour.
const EDGE: [u8; 3] = [30, 30, 40];
/// Label colour.
const TEXT: [u8; 3] = [20, 20, 20];

/// One panel: the map and the mesh's rest-space triangles (m) at that time.
pub struct MapPanel<'a> {
    /// The error map.
    pub map: &'a ErrorMap,
    /// The triangles of the mesh at that time, in rest coordinates `(u, v)` (m).
    pub triangles: Vec<[[f64; 2]; 3]>,
}

/// A colour for `s` in [0, 1]: white, yellow, orange, red, dark red (monotonic in lightness).
fn heat(s: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [255.0, 255.0, 255.0],
        [255.0, 230.0, 110.0],
        [245.0, 150.0, 40.0],
        [200.0, 40.0, 30.0],
        [90.0, 0.0, 20.0],
    ];
    let s = if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = s * (STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let w = x - k as f64;
    [0, 1, 2].map(|c| (STOPS[k][c] * (1.0 - w) + STOPS[k + 1][c] * w).round() as u8)
}

/// The sample grid of a map: its rest bounds, side and values row-major (`v` rows, `u` columns).
struct Grid {
    lo: [f64; 2],
    hi: [f64; 2],
    nu: usize,
    nv: usize,
    e: Vec<f64>,
}

impl Grid {
    /// The grid of a map whose samples form a complete rectangular grid; `None` otherwise.
    fn of(map: &ErrorMap) -> Option<Grid> {
        let mut us: Vec<f64> = map.samples.iter().map(|s| s.0[0]).collect();
        let mut vs: Vec<f64> = map.samples.iter().map(|s| s.0[1]).collect();
        for a in [&mut us, &mut vs] {
            a.sort_by(f64::total_cmp);
            a.dedup();
        }
        let (nu, nv) = (us.len(), vs.len());
        if nu < 2 || nv < 2 || nu * nv != map.samples.len() {
            return None;
        }
        let mut e = vec![f64::NAN; nu * nv];
        for ([u, v], x) in &map.samples {
            let i = us.partition_point(|a| a < u);
            let j = vs.partition_point(|a| a < v);
            e[j * nu + i] = *x;
        }
        Some(Grid {
            lo: [us[0], vs[0]],
            hi: [us[nu - 1], vs[nv - 1]],
            nu,
            nv,
            e,
        })
    }

    /// Bilinear value at rest point `(u, v)`.
    fn at(&self, u: f64, v: f64) -> f64 {
        let fx = ((u - self.lo[0]) / (self.hi[0] - self.lo[0]) * (self.nu - 1) as f64)
            .clamp(0.0, (self.nu - 1) as f64);
        let fy = ((v - self.lo[1]) / (self.hi[1] - self.lo[1]) * (self.nv - 1) as f64)
            .clamp(0.0, (self.nv - 1) as f64);
        let (i, j) = (
            (fx as usize).min(self.nu - 2),
            (fy as usize).min(self.nv - 2),
        );
        let (a, b) = (fx - i as f64, fy - j as f64);
        let g = |i: usize, j: usize| self.e[j * self.nu + i];
        (1.0 - a) * (1.0 - b) * g(i, j)
            + a * (1.0 - b) * g(i + 1, j)
            + (1.0 - a) * b * g(i, j + 1)
            + a * b * g(i + 1, j + 1)
    }
}

/// Draws a 1-pixel line (DDA) clipped to the image.
fn line(img: &mut Image, a: [f64; 2], b: [f64; 2], color: [u8; 3]) {
    let n = (b[0] - a[0]).abs().max((b[1] - a[1]).abs()).ceil().max(1.0) as usize;
    for k in 0..=n {
        let s = k as f64 / n as f64;
        let (x, y) = (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]));
        if x >= 0.0 && y >= 0.0 {
            img.fill_rect(x.round() as usize, y.round() as usize, 1, 1, color);
        }
    }
}

/// Writes the error-map picture of one run: `title` above, one panel per map, the colour bar
/// from 0 to `e_max` (m). Maps whose samples do not form a rectangular grid are left blank.
pub fn error_map_png(
    path: &Path,
    title: &str,
    panels: &[MapPanel],
    e_max: f64,
) -> Result<(), RenderError> {
    let n = panels.len().max(1);
    let width = PAD + n * (PANEL + PAD) + BAR;
    let height = HEADER + PANEL + 2 * PAD + 16;
    let mut img = Image::new(width, height);
    draw_text(&mut img, PAD as f32, 18.0, title, 15.0, TEXT);
    let scale = if e_max.is_finite() && e_max > 0.0 {
        e_max
    } else {
        1.0
    };
    for (k, p) in panels.iter().enumerate() {
        let x0 = PAD + k * (PANEL + PAD);
        let y0 = HEADER + PAD;
        let Some(g) = Grid::of(p.map) else { continue };
        // Rest space to pixels: u to the right, v up, the pattern's aspect kept.
        let span = (g.hi[0] - g.lo[0]).max(g.hi[1] - g.lo[1]);
        let to_px = |u: f64, v: f64| {
            [
                x0 as f64 + (u - g.lo[0]) / span * (PANEL - 1) as f64,
                (y0 + PANEL - 1) as f64 - (v - g.lo[1]) / span * (PANEL - 1) as f64,
            ]
        };
        for py in 0..PANEL {
            for px in 0..PANEL {
                let u = g.lo[0] + px as f64 / (PANEL - 1) as f64 * span;
                let v = g.lo[1] + (PANEL - 1 - py) as f64 / (PANEL - 1) as f64 * span;
                if u <= g.hi[0] + 1e-12 && v <= g.hi[1] + 1e-12 {
                    let c = heat(g.at(u, v) / scale);
                    img.fill_rect(x0 + px, y0 + py, 1, 1, c);
                }
            }
        }
        for t in &p.triangles {
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                line(&mut img, to_px(a[0], a[1]), to_px(b[0], b[1]), EDGE);
            }
        }
        let label = format!("t = {:.3} s", p.map.t);
        let lx = x0 as f32 + (PANEL as f32 - text_width(&label, 13.0)) * 0.5;
        draw_text(&mut img, lx, (y0 + PANEL + 16) as f32, &label, 13.0, TEXT);
    }
    // The colour bar: 0 at the bottom, e_max at the top.
    let bx = PAD + n * (PANEL + PAD);
    let y0 = HEADER + PAD;
    for py in 0..PANEL {
        let c = heat(1.0 - py as f64 / (PANEL - 1) as f64);
        img.fill_rect(bx, y0 + py, 16, 1, c);
    }
    draw_text(
        &mut img,
        (bx + 22) as f32,
        (y0 + 10) as f32,
        &format!("{scale:.2e} m"),
        12.0,
        TEXT,
    );
    draw_text(
        &mut img,
        (bx + 22) as f32,
        (y0 + PANEL) as f32,
        "0",
        12.0,
        TEXT,
    );
    draw_text(
        &mut img,
        (bx + 22) as f32,
        (y0 + PANEL / 2) as f32,
        "e(u, v)",
        12.0,
        TEXT,
    );
    write_png(path, width as u32, height as u32, &img.rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_error_is_drawn_where_it_is_and_the_mesh_over_it() {
        // A 3x3 grid over [0, 1]^2 with the error only at the corner (1, 1).
        let samples: Vec<([f64; 2], f64)> = (0..9)
            .map(|i| {
                let r = [(i % 3) as f64 * 0.5, (i / 3) as f64 * 0.5];
                (r, if i == 8 { 0.1 } else { 0.0 })
            })
            .collect();
        let map = ErrorMap { t: 0.5, samples };
        let g = Grid::of(&map).unwrap();
        assert_eq!((g.nu, g.nv), (3, 3));
        assert!((g.at(1.0, 1.0) - 0.1).abs() < 1e-12);
        assert!((g.at(0.75, 0.75) - 0.025).abs() < 1e-12, "bilinear");
        assert_eq!(g.at(0.0, 0.0), 0.0);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.png");
        let panel = MapPanel {
            map: &map,
            triangles: vec![[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]],
        };
        error_map_png(&path, "run", &[panel], 0.1).unwrap();
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        let pixel = |x: usize, y: usize| {
            let i = (y * info.width as usize + x) * 3;
            [buf[i], buf[i + 1], buf[i + 2]]
        };
        let (x0, y0) = (PAD, HEADER + PAD);
        // Top-right corner of the panel (u = v = 1): the darkest colour; bottom-left: white.
        let corner = pixel(x0 + PANEL - 3, y0 + 8);
        assert!(corner[1] < 60, "dark red near (1, 1): {corner:?}");
        assert_eq!(
            pixel(x0 + 30, y0 + PANEL - 10),
            [255, 255, 255],
            "no error: white"
        );
        // The diagonal edge from (0, 0) to (1, 1) is drawn over the map.
        assert_eq!(pixel(x0 + PANEL / 2, y0 + PANEL / 2 - 1), EDGE);
    }
}
