//! The perspective camera: a 3/4 view looking down at 30 degrees, zoomed and shifted so a given
//! box fills the picture.

use super::FrameMesh;

/// Elevation of the view direction above the horizontal (degrees): the camera looks down this much.
const ELEVATION_DEG: f32 = 30.0;
/// Azimuth of the camera around the vertical axis, from +x (degrees): in front (-y) and to the
/// right (+x) of the scene.
const AZIMUTH_DEG: f32 = -55.0;
/// Camera distance from the box centre, in box half-diagonals (sets the perspective strength).
const DISTANCE_FACTOR: f32 = 3.0;
/// Empty border left around the framed box, as a fraction of the picture size on each side.
const MARGIN: f32 = 0.05;

/// A pinhole camera: world point to pixel coordinates plus view depth.
#[derive(Clone, Debug)]
pub(crate) struct Camera {
    eye: [f32; 3],
    right: [f32; 3],
    up: [f32; 3],
    forward: [f32; 3],
    /// Focal length (pixels).
    focal: f32,
    /// Pixel position of the optical axis.
    cx: f32,
    cy: f32,
    /// Near clipping depth (m).
    pub near: f32,
}

pub(crate) fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(crate) fn normalize(a: [f32; 3]) -> [f32; 3] {
    let n = dot(a, a).sqrt();
    if n > 0.0 {
        [a[0] / n, a[1] / n, a[2] / n]
    } else {
        a
    }
}

/// Whether a mesh is flat and horizontal (the ground square): drawn, but not framed, so the
/// picture shows the cloth and the solid obstacles rather than the whole floor.
pub(crate) fn is_flat(mesh: &FrameMesh) -> bool {
    match mesh.bounds() {
        Some((lo, hi)) => {
            let span = (hi[0] - lo[0]).max(hi[1] - lo[1]);
            hi[2] - lo[2] <= 1e-4 * span
        }
        None => true,
    }
}

/// Union of the bounds of the meshes (m); a unit box around the origin when all are empty.
pub(crate) fn union_bounds<'a>(meshes: impl IntoIterator<Item = &'a FrameMesh>) -> [[f32; 3]; 2] {
    let mut out: Option<[[f32; 3]; 2]> = None;
    for (lo, hi) in meshes.into_iter().filter_map(FrameMesh::bounds) {
        out = Some(match out {
            None => [lo, hi],
            Some([a, b]) => [
                [a[0].min(lo[0]), a[1].min(lo[1]), a[2].min(lo[2])],
                [b[0].max(hi[0]), b[1].max(hi[1]), b[2].max(hi[2])],
            ],
        });
    }
    out.unwrap_or([[-0.5; 3], [0.5; 3]])
}

impl Camera {
    /// The camera whose picture of `width` x `height` pixels shows the box `[lo, hi]` (m) whole
    /// and as large as the margins allow, centred.
    pub(crate) fn framing(bounds: [[f32; 3]; 2], width: f32, height: f32) -> Camera {
        let [lo, hi] = bounds;
        let center = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        let radius = (0.5 * dot(sub(hi, lo), sub(hi, lo)).sqrt()).max(1e-3);
        let (el, az) = (ELEVATION_DEG.to_radians(), AZIMUTH_DEG.to_radians());
        let to_eye = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
        let eye = [0, 1, 2].map(|k| center[k] + DISTANCE_FACTOR * radius * to_eye[k]);
        let forward = to_eye.map(|c| -c);
        let right = normalize(cross(forward, [0.0, 0.0, 1.0]));
        let up = cross(right, forward);
        let mut cam = Camera {
            eye,
            right,
            up,
            forward,
            focal: 1.0,
            cx: 0.0,
            cy: 0.0,
            near: 0.01 * radius,
        };
        // Project the box corners with a unit focal length, then zoom and shift to fit.
        let (mut x0, mut x1, mut y0, mut y1) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for k in 0..8 {
            let p = [0, 1, 2].map(|i| if k >> i & 1 == 1 { hi[i] } else { lo[i] });
            let v = cam.view(p);
            let (x, y) = (v[0] / v[2], v[1] / v[2]);
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let usable = 1.0 - 2.0 * MARGIN;
        cam.focal =
            (width * usable / (x1 - x0).max(1e-6)).min(height * usable / (y1 - y0).max(1e-6));
        cam.cx = 0.5 * width - cam.focal * 0.5 * (x0 + x1);
        cam.cy = 0.5 * height + cam.focal * 0.5 * (y0 + y1);
        cam
    }

    /// View coordinates of a world point: right, up, depth along the view direction (m).
    pub(crate) fn view(&self, p: [f32; 3]) -> [f32; 3] {
        let d = sub(p, self.eye);
        [dot(d, self.right), dot(d, self.up), dot(d, self.forward)]
    }

    /// Pixel coordinates (x right, y down) and depth of a point in view coordinates; only for
    /// depths at or beyond `near`.
    pub(crate) fn screen(&self, v: [f32; 3]) -> [f32; 3] {
        [
            self.cx + self.focal * v[0] / v[2],
            self.cy - self.focal * v[1] / v[2],
            v[2],
        ]
    }

    /// The camera position (m).
    pub(crate) fn eye(&self) -> [f32; 3] {
        self.eye
    }

    /// The same camera for a picture `factor` times larger in each direction.
    pub(crate) fn scaled(&self, factor: f32) -> Camera {
        Camera {
            focal: self.focal * factor,
            cx: self.cx * factor,
            cy: self.cy * factor,
            ..self.clone()
        }
    }
}
