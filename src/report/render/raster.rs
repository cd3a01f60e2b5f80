//! The rasteriser: z-buffered, flat-shaded triangles on a supersampled canvas, mesh edges drawn
//! inside each triangle where a pixel lies within a line half-width of one of its edges.
//!
//! Drawing edges from the triangle's own pixels means an edge shows exactly where its face is
//! visible: hidden edges never bleed through and no depth bias is needed.

use super::camera::{cross, dot, normalize, sub, Camera};
use super::{FrameMesh, RenderError};

/// Supersampling factor per axis (2 gives 4 samples per pixel).
pub(crate) const SUPERSAMPLE: usize = 2;
/// Light direction (towards the light, world frame): above, in front of and left of the scene
/// as the camera sees it.
const LIGHT: [f32; 3] = [0.1, -0.8, 1.2];
/// Ambient share of the shading.
const AMBIENT: f32 = 0.35;
/// Diffuse (Lambert) share of the shading.
const DIFFUSE: f32 = 0.65;
/// Colour of the mesh edges (linear RGB in [0, 1]).
const EDGE_COLOR: [f32; 3] = [0.08, 0.1, 0.16];
/// Opacity of the mesh edges over the face colour.
const EDGE_ALPHA: f32 = 0.7;
/// Edges of triangles whose shortest side is below this length (final pixels) are drawn fainter,
/// in proportion, down to `EDGE_MIN_FADE` of their opacity.
const EDGE_FADE_LENGTH: f32 = 8.0;
const EDGE_MIN_FADE: f32 = 0.4;
/// Half width of an edge line on each side of the edge (final pixels).
const EDGE_HALF_WIDTH: f32 = 0.45;

/// How to draw one mesh.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Style {
    /// Colour of faces whose front (counter-clockwise) side faces the camera.
    pub front: [f32; 3],
    /// Colour of faces seen from behind (two-sided lighting: they are shaded too).
    pub back: [f32; 3],
    /// Whether the mesh edges are drawn.
    pub edges: bool,
    /// Depth bias: the mesh is drawn as if this fraction of its view depth nearer (0 for none).
    pub depth_bias: f32,
}

/// A supersampled colour and depth buffer.
pub(crate) struct Canvas {
    width: usize,
    height: usize,
    color: Vec<[f32; 3]>,
    /// Inverse view depth (1/m) of the nearest surface so far; 0 where nothing is drawn.
    inv_depth: Vec<f32>,
}

fn edge_fn(a: [f32; 3], b: [f32; 3], x: f32, y: f32) -> f32 {
    (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])
}

impl Canvas {
    /// A white canvas for a picture of `width` x `height` final pixels.
    pub(crate) fn new(width: usize, height: usize) -> Canvas {
        let (w, h) = (width * SUPERSAMPLE, height * SUPERSAMPLE);
        Canvas {
            width: w,
            height: h,
            color: vec![[1.0; 3]; w * h],
            inv_depth: vec![0.0; w * h],
        }
    }

    /// Draws a mesh seen by `camera` (framed for the final picture size).
    pub(crate) fn draw_mesh(
        &mut self,
        camera: &Camera,
        mesh: &FrameMesh,
        style: Style,
    ) -> Result<(), RenderError> {
        mesh.validate()?;
        let cam = camera.scaled(SUPERSAMPLE as f32);
        let light = normalize(LIGHT);
        let eye = cam.eye();
        let bias = |p: [f32; 3]| [p[0], p[1], p[2] * (1.0 - style.depth_bias)];
        let views: Vec<[f32; 3]> = mesh.positions.iter().map(|&p| cam.view(p)).collect();
        for f in &mesh.faces {
            let [a, b, c] = f.map(|i| mesh.positions[i as usize]);
            let n = cross(sub(b, a), sub(c, a));
            if dot(n, n) == 0.0 {
                continue;
            }
            let n = normalize(n);
            let (base, n) = if dot(n, sub(a, eye)) < 0.0 {
                (style.front, n)
            } else {
                (style.back, n.map(|x| -x))
            };
            let shade = AMBIENT + DIFFUSE * dot(n, light).max(0.0);
            let color = base.map(|x| x * shade);
            let v = f.map(|i| views[i as usize]);
            if v.iter().all(|p| p[2] >= cam.near) {
                self.fill(v.map(|p| bias(cam.screen(p))), color, style.edges);
            } else {
                // Clip against the near plane (only the ground reaches behind the camera);
                // clipped pieces get no edges since their sides are not mesh edges.
                let poly = clip_near(v, cam.near);
                for i in 1..poly.len().saturating_sub(1) {
                    let t = [poly[0], poly[i], poly[i + 1]].map(|p| bias(cam.screen(p)));
                    self.fill(t, color, false);
                }
            }
        }
        Ok(())
    }

    /// Fills one triangle given in pixel coordinates and view depth.
    fn fill(&mut self, p: [[f32; 3]; 3], color: [f32; 3], edges: bool) {
        let area = edge_fn(p[0], p[1], p[2][0], p[2][1]);
        if area.is_nan() || area.abs() <= 1e-9 {
            return;
        }
        let xmin = p
            .iter()
            .map(|q| q[0])
            .fold(f32::MAX, f32::min)
            .floor()
            .max(0.0);
        let ymin = p
            .iter()
            .map(|q| q[1])
            .fold(f32::MAX, f32::min)
            .floor()
            .max(0.0);
        let xmax = p.iter().map(|q| q[0]).fold(f32::MIN, f32::max).ceil();
        let ymax = p.iter().map(|q| q[1]).fold(f32::MIN, f32::max).ceil();
        let xmax = xmax.min(self.width as f32 - 1.0);
        let ymax = ymax.min(self.height as f32 - 1.0);
        if xmin > xmax || ymin > ymax {
            return;
        }
        let inv_z = p.map(|q| 1.0 / q[2]);
        let len = [0, 1, 2].map(|i| {
            let (a, b) = (p[(i + 1) % 3], p[(i + 2) % 3]);
            ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2))
                .sqrt()
                .max(1e-6)
        });
        let half_width = EDGE_HALF_WIDTH * SUPERSAMPLE as f32;
        // Small triangles get fainter edges so fine meshes do not turn dark.
        let shortest = len[0].min(len[1]).min(len[2]) / SUPERSAMPLE as f32;
        let alpha = EDGE_ALPHA * (shortest / EDGE_FADE_LENGTH).clamp(EDGE_MIN_FADE, 1.0);
        let edge_color = [0, 1, 2].map(|k| color[k] + alpha * (EDGE_COLOR[k] - color[k]));
        let inv_area = 1.0 / area;
        for y in ymin as usize..=ymax as usize {
            let py = y as f32 + 0.5;
            let row = y * self.width;
            for x in xmin as usize..=xmax as usize {
                let px = x as f32 + 0.5;
                let w0 = edge_fn(p[1], p[2], px, py) * inv_area;
                let w1 = edge_fn(p[2], p[0], px, py) * inv_area;
                let w2 = 1.0 - w0 - w1;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let depth = w0 * inv_z[0] + w1 * inv_z[1] + w2 * inv_z[2];
                let i = row + x;
                if depth <= self.inv_depth[i] {
                    continue;
                }
                self.inv_depth[i] = depth;
                let on_edge = edges && {
                    let a = area.abs();
                    (w0 * a / len[0]).min(w1 * a / len[1]).min(w2 * a / len[2]) < half_width
                };
                self.color[i] = if on_edge { edge_color } else { color };
            }
        }
    }

    /// The final picture: RGB bytes, row-major, each pixel the mean of its samples.
    pub(crate) fn resolve(&self) -> Vec<u8> {
        let (w, h) = (self.width / SUPERSAMPLE, self.height / SUPERSAMPLE);
        let mut out = Vec::with_capacity(w * h * 3);
        let weight = 1.0 / (SUPERSAMPLE * SUPERSAMPLE) as f32;
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0f32; 3];
                for sy in 0..SUPERSAMPLE {
                    let row = (y * SUPERSAMPLE + sy) * self.width;
                    for sx in 0..SUPERSAMPLE {
                        let c = self.color[row + x * SUPERSAMPLE + sx];
                        (0..3).for_each(|k| sum[k] += c[k]);
                    }
                }
                out.extend(sum.map(|s| (s * weight * 255.0 + 0.5).clamp(0.0, 255.0) as u8));
            }
        }
        out
    }
}

/// The part of a triangle (view coordinates) at depth `near` or beyond: a polygon of 0, 3 or 4
/// vertices.
fn clip_near(v: [[f32; 3]; 3], near: f32) -> Vec<[f32; 3]> {
    let mut out = Vec::with_capacity(4);
    for i in 0..3 {
        let (a, b) = (v[i], v[(i + 1) % 3]);
        let (a_in, b_in) = (a[2] >= near, b[2] >= near);
        if a_in {
            out.push(a);
        }
        if a_in != b_in {
            let t = (near - a[2]) / (b[2] - a[2]);
            out.push([0, 1, 2].map(|k| a[k] + t * (b[k] - a[k])));
        }
    }
    out
}
