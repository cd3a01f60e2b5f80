//! The public pictures: one mesh ([`render_png`]) and the snapshot grid ([`snapshot_grid`]), and
//! PNG encoding.

use super::camera::{is_flat, union_bounds, Camera};
use super::raster::{Canvas, Style};
use super::text::{draw_text, text_width, Image};
use super::{FrameMesh, ObstacleMeshes, RenderError};
use std::path::Path;

/// Cloth faces seen from their front (counter-clockwise) side: blue.
const CLOTH_FRONT: [f32; 3] = [0.36, 0.58, 0.88];
/// Cloth faces seen from behind: orange, so folds read clearly.
const CLOTH_BACK: [f32; 3] = [0.93, 0.62, 0.32];
/// Solid obstacles: light grey.
const OBSTACLE: [f32; 3] = [0.8, 0.8, 0.8];
/// The ground (flat obstacles): white, which the shading turns into a very light grey.
const GROUND: [f32; 3] = [1.0, 1.0, 1.0];
/// Cloth depth bias (fraction of view depth): the flat cloth triangles between vertices resting on
/// a curved obstacle cut its surface by the sagitta (about 2 mm for 6 cm edges on a 25 cm
/// sphere); this bias hides such small cuts so fine meshes do not look speckled, while the deep
/// cuts of coarse meshes (a real error of the discretisation) still show.
const CLOTH_DEPTH_BIAS: f32 = 0.004;
/// Size of one grid cell (pixels).
const CELL_WIDTH: usize = 360;
const CELL_HEIGHT: usize = 270;
/// Label font size (pixels).
const LABEL_SIZE: f32 = 16.0;
/// Height of the header row holding the time labels (pixels).
const HEADER_HEIGHT: usize = 30;
/// Padding around labels (pixels).
const PAD: usize = 12;
/// Label colour.
const TEXT_COLOR: [u8; 3] = [20, 20, 20];
/// Grid separator colour.
const RULE_COLOR: [u8; 3] = [215, 215, 215];
/// Largest picture side accepted (pixels).
pub const MAX_SIDE: u32 = 16384;
/// Most pixels a picture may have (4096 x 4096): drawing takes about 55 bytes a pixel (912 MB
/// measured at 4096 x 4096), so two sides of 16384 would need some 15 GB.
pub const MAX_PIXELS: u64 = 4096 * 4096;

/// One row of a snapshot grid: a run's label and its frames at the chosen times.
#[derive(Clone, Debug, Default)]
pub struct SnapshotRow {
    /// The run's label, drawn left of the row.
    pub label: String,
    /// `(time (s), cloth mesh)` per column, left to right.
    pub frames: Vec<(f64, FrameMesh)>,
}

/// The camera framing the cloth meshes and the solid obstacles (flat ones, the ground, are drawn
/// but not framed).
fn camera_for<'a>(
    cloth: impl IntoIterator<Item = &'a FrameMesh>,
    obstacles: impl IntoIterator<Item = &'a FrameMesh>,
    width: usize,
    height: usize,
) -> Camera {
    let solid = obstacles.into_iter().filter(|m| !is_flat(m));
    let bounds = union_bounds(cloth.into_iter().chain(solid));
    Camera::framing(bounds, width as f32, height as f32)
}

/// Draws the cloth (edges visible) and the obstacles (grey, no edges): RGB bytes.
pub(crate) fn draw_scene(
    camera: &Camera,
    cloth: &FrameMesh,
    obstacles: &[FrameMesh],
    width: usize,
    height: usize,
) -> Result<Vec<u8>, RenderError> {
    let mut canvas = Canvas::new(width, height);
    for m in obstacles {
        let grey = if is_flat(m) { GROUND } else { OBSTACLE };
        let style = Style {
            front: grey,
            back: grey,
            edges: false,
            depth_bias: 0.0,
        };
        canvas.draw_mesh(camera, m, style)?;
    }
    let style = Style {
        front: CLOTH_FRONT,
        back: CLOTH_BACK,
        edges: true,
        depth_bias: CLOTH_DEPTH_BIAS,
    };
    canvas.draw_mesh(camera, cloth, style)?;
    Ok(canvas.resolve())
}

fn check_size(width: u32, height: u32) -> Result<(), RenderError> {
    let pixels = u64::from(width) * u64::from(height);
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE || pixels > MAX_PIXELS {
        return Err(RenderError::Size { width, height });
    }
    Ok(())
}

/// One picture of `mesh` (the cloth, edges visible) with the obstacles, `width` x `height`
/// pixels, framed on the mesh and the solid obstacles; written as an RGB PNG to `path`.
///
/// Errors: a side of zero or above 16384, or more than 4096 x 4096 pixels
/// ([`RenderError::Size`]), a face index out of range
/// ([`RenderError::BadFace`]), the file cannot be written ([`RenderError::Io`],
/// [`RenderError::Png`]).
pub fn render_png(
    mesh: &FrameMesh,
    obstacles: &[FrameMesh],
    width: u32,
    height: u32,
    path: &Path,
) -> Result<(), RenderError> {
    check_size(width, height)?;
    let (w, h) = (width as usize, height as usize);
    let camera = camera_for([mesh], obstacles, w, h);
    let rgb = draw_scene(&camera, mesh, obstacles, w, h)?;
    write_png(path, width, height, &rgb)
}

/// A grid of snapshots written as a PNG to `path`: one row per run (its label on the left), one
/// column per time (the first row's times label the columns; a cell whose time, as labelled,
/// differs from its column's says its own). Each cell is 360 x 270 pixels showing the cloth with its mesh edges
/// and the obstacles in grey, all cells through the same camera, framed on every frame of every
/// row and the solid obstacles (moving ones where they stand in every cell), so cells compare
/// directly. Each cell draws moving obstacles where they stand at its time.
///
/// Errors: as [`render_png`].
pub fn snapshot_grid(
    rows: &[SnapshotRow],
    obstacles: &ObstacleMeshes,
    path: &Path,
) -> Result<(), RenderError> {
    let columns = rows
        .iter()
        .map(|r| r.frames.len())
        .max()
        .unwrap_or(0)
        .max(1);
    let label_width = rows
        .iter()
        .map(|r| text_width(&r.label, LABEL_SIZE).ceil() as usize)
        .max()
        .unwrap_or(0)
        + 2 * PAD;
    let width = label_width + columns * CELL_WIDTH;
    let height = HEADER_HEIGHT + rows.len().max(1) * CELL_HEIGHT;
    check_size(width as u32, height as u32)?;
    let cloth = rows.iter().flat_map(|r| r.frames.iter().map(|(_, m)| m));
    // Moving obstacles are framed where they stand in every cell, still ones where they are.
    let posed: Vec<FrameMesh> = if obstacles.moves() {
        let times = rows.iter().flat_map(|r| r.frames.iter().map(|(t, _)| *t));
        times.flat_map(|t| obstacles.at(t).into_owned()).collect()
    } else {
        Vec::new()
    };
    let framed: &[FrameMesh] = if obstacles.moves() { &posed } else { obstacles };
    let camera = camera_for(cloth, framed, CELL_WIDTH, CELL_HEIGHT);
    let mut img = Image::new(width, height);
    let column_time = |c: usize| rows.iter().find_map(|r| r.frames.get(c).map(|f| f.0));
    let decimals = time_decimals(rows.iter().flat_map(|r| r.frames.iter().map(|f| f.0)));
    for c in 0..columns {
        if let Some(t) = column_time(c) {
            let text = time_label(t, decimals);
            let x = label_width + c * CELL_WIDTH;
            let dx = (CELL_WIDTH as f32 - text_width(&text, LABEL_SIZE)) * 0.5;
            draw_text(
                &mut img,
                x as f32 + dx,
                HEADER_HEIGHT as f32 - 9.0,
                &text,
                LABEL_SIZE,
                TEXT_COLOR,
            );
        }
    }
    for (r, row) in rows.iter().enumerate() {
        let y = HEADER_HEIGHT + r * CELL_HEIGHT;
        let baseline = y as f32 + 0.5 * (CELL_HEIGHT as f32 + LABEL_SIZE * 0.7);
        draw_text(
            &mut img, PAD as f32, baseline, &row.label, LABEL_SIZE, TEXT_COLOR,
        );
        for (c, (t, mesh)) in row.frames.iter().enumerate() {
            let x = label_width + c * CELL_WIDTH;
            let rgb = draw_scene(&camera, mesh, &obstacles.at(*t), CELL_WIDTH, CELL_HEIGHT)?;
            img.blit(x, y, CELL_WIDTH, CELL_HEIGHT, &rgb);
            let text = time_label(*t, decimals);
            if column_time(c).is_some_and(|ct| time_label(ct, decimals) != text) {
                draw_text(
                    &mut img,
                    (x + 6) as f32,
                    (y + 18) as f32,
                    &text,
                    13.0,
                    TEXT_COLOR,
                );
            }
        }
    }
    // Separators between rows and columns.
    for r in 0..=rows.len() {
        img.fill_rect(0, HEADER_HEIGHT + r * CELL_HEIGHT, width, 1, RULE_COLOR);
    }
    for c in 0..=columns {
        img.fill_rect(
            label_width + c * CELL_WIDTH,
            HEADER_HEIGHT,
            1,
            height,
            RULE_COLOR,
        );
    }
    write_png(path, width as u32, height as u32, &img.rgb)
}

/// Decimals for time labels: two, or enough to show two significant digits of the smallest
/// non-zero time (at most six).
fn time_decimals(times: impl Iterator<Item = f64>) -> usize {
    times
        .filter(|t| t.is_finite() && *t != 0.0)
        .map(|t| (1.0 - t.abs().log10().floor()).clamp(2.0, 6.0) as usize)
        .max()
        .unwrap_or(2)
}

/// `t = 0.25 s`.
fn time_label(t: f64, decimals: usize) -> String {
    format!("t = {t:.decimals$} s")
}

/// Writes RGB bytes as an 8-bit PNG, atomically ([`crate::io::write_atomic`]): a failed write
/// leaves `path` as it was and no temporary file.
pub(crate) fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[u8],
) -> Result<(), RenderError> {
    let bytes = encode_png(width, height, rgb).map_err(|source| RenderError::Png {
        path: path.to_path_buf(),
        source,
    })?;
    crate::io::write_atomic(path, &bytes).map_err(|source| RenderError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// RGB bytes (`width x height x 3`) encoded as an 8-bit PNG in memory.
pub(crate) fn encode_png(
    width: u32,
    height: u32,
    rgb: &[u8],
) -> Result<Vec<u8>, png::EncodingError> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()?;
    Ok(bytes)
}
