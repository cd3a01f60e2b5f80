//! The self-contained `report.html` of `adaptcloth compare`: markdown sections with their images
//! embedded, and an interactive 3D replay of the runs.
//!
//! Nothing is fetched when the page is opened: the CSS and JavaScript are inline, images are data
//! URIs (PNG and SVG, base64), and the replay's frames are a JSON block in the page. The replay is
//! a 2D canvas drawn with the painter's algorithm (robust everywhere, headless browsers included):
//! a run selector, a time slider, play/pause with a speed choice, mouse-drag orbit and wheel zoom;
//! the cloth with its mesh edges (blue front, orange back) and the obstacles in grey, all runs
//! through the same initial camera as the PNG snapshots (3/4 view, 30 degrees down).
//!
//! A link `report.html#t=0.5` opens the replay at 0.5 s.
//!
//! Frame encoding: positions as integers in units of 0.1 mm; a run's face list is stored once per
//! topology and shared by consecutive frames whose faces are unchanged. When an obstacle moves,
//! each frame also holds every obstacle's rigid motion at its time (`o`: row-major rotation then
//! translation in m, the identity for still ones), which the replay applies to the obstacle's
//! mesh as the scene places it.
//!
//! For tests, the page reports in `<pre id="status">` and in globals: `window.__replayDrawn`
//! (true once the first replay frame is drawn), `window.__replayTriangles` (triangles drawn in
//! it), `window.__errors` (script errors caught by `window.onerror`); the status reads
//! `drawn N triangles; errors: E; view radius R m` (R: the radius of the sphere the camera
//! frames: every frame of every run and the solid obstacles where they stand in each).

pub mod markdown;

use crate::report::render::{FrameMesh, ObstacleMeshes};
use base64::Engine as _;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Quantum of the embedded positions (m).
const POSITION_QUANTUM: f64 = 1e-4;

const STYLE: &str = include_str!("report.css");
const SCRIPT: &str = include_str!("replay.js");

/// One run in the 3D replay.
#[derive(Clone, Debug, Default)]
pub struct ReplayRun {
    /// The run's name in the selector.
    pub label: String,
    /// Time of each frame (s), increasing; same length as `frames`.
    pub frame_times: Vec<f64>,
    /// The cloth at each time.
    pub frames: Vec<FrameMesh>,
}

/// One section of the report.
#[derive(Clone, Debug, Default)]
pub struct HtmlSection {
    /// Section title (an `<h2>`).
    pub title: String,
    /// Body in the markdown subset of [`markdown`]; `![alt](file)` images are embedded when the
    /// file (relative to the report's folder) is a PNG or SVG, else shown as their alt text.
    pub markdown: String,
    /// Figures shown after the text, embedded: `.svg` or `.png` files.
    pub images: Vec<PathBuf>,
}

#[derive(Serialize)]
struct MeshJson {
    /// Positions, flat `x y z`, in quanta.
    p: Vec<i64>,
    /// Faces, flat, 0-based.
    f: Vec<u32>,
}

#[derive(Serialize)]
struct FrameJson {
    /// Index of the run's topology (face list).
    k: usize,
    /// Positions, flat `x y z`, in quanta.
    p: Vec<i64>,
    /// Each obstacle's rigid motion at the frame's time, when an obstacle moves.
    #[serde(skip_serializing_if = "Option::is_none")]
    o: Option<Vec<[f64; 12]>>,
}

#[derive(Serialize)]
struct RunJson {
    label: String,
    times: Vec<f64>,
    topologies: Vec<Vec<u32>>,
    frames: Vec<FrameJson>,
}

#[derive(Serialize)]
struct ReplayJson {
    title: String,
    quantum: f64,
    obstacles: Vec<MeshJson>,
    runs: Vec<RunJson>,
}

fn quantise(positions: &[[f32; 3]]) -> Vec<i64> {
    positions
        .iter()
        .flatten()
        .map(|&x| {
            let q = (x as f64 / POSITION_QUANTUM).round();
            if q.is_finite() {
                q as i64
            } else {
                0
            }
        })
        .collect()
}

fn flat_faces(m: &FrameMesh) -> Vec<u32> {
    m.faces.iter().flatten().copied().collect()
}

fn replay_json(
    title: &str,
    replays: &[ReplayRun],
    obstacles: &ObstacleMeshes,
) -> std::io::Result<String> {
    let runs = replays
        .iter()
        .map(|run| {
            let mut topologies: Vec<Vec<u32>> = Vec::new();
            let frames = run
                .frames
                .iter()
                .enumerate()
                .map(|(i, m)| {
                    let faces = flat_faces(m);
                    if topologies.last() != Some(&faces) {
                        topologies.push(faces);
                    }
                    let t = run.frame_times.get(i).copied().unwrap_or(0.0);
                    FrameJson {
                        k: topologies.len() - 1,
                        p: quantise(&m.positions),
                        o: obstacles.poses(t),
                    }
                })
                .collect::<Vec<_>>();
            let mut times = run.frame_times.clone();
            times.resize(frames.len(), times.last().copied().unwrap_or(0.0));
            RunJson {
                label: run.label.clone(),
                times: times
                    .iter()
                    .map(|t| if t.is_finite() { *t } else { 0.0 })
                    .collect(),
                topologies,
                frames,
            }
        })
        .collect();
    let data = ReplayJson {
        title: title.to_string(),
        quantum: POSITION_QUANTUM,
        obstacles: obstacles
            .iter()
            .map(|m| MeshJson {
                p: quantise(&m.positions),
                f: flat_faces(m),
            })
            .collect(),
        runs,
    };
    let json = serde_json::to_string(&data).map_err(std::io::Error::other)?;
    // `<` only occurs inside JSON strings, where `\u003c` means the same: the block can never
    // close its <script> element early.
    Ok(json.replace('<', "\\u003c"))
}

/// An `<img>` with the file embedded as a data URI; an error for other file types.
fn embedded_image(path: &Path, alt: &str) -> std::io::Result<String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let mime = match ext.as_str() {
        "png" => "image/png",
        "svg" => "image/svg+xml",
        _ => {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!(
                    "{}: only .png and .svg images can be embedded",
                    path.display()
                ),
            ))
        }
    };
    let bytes = std::fs::read(path)
        .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
    let data = base64::engine::general_purpose::STANDARD.encode(bytes);
    Ok(format!(
        "<img src=\"data:{mime};base64,{data}\" alt=\"{}\">",
        markdown::escape(alt)
    ))
}

/// Writes the self-contained HTML report to `path`: `title`, a table of contents, the sections
/// (markdown and embedded images) and, when `replays` is not empty, the 3D replay of those runs
/// with the `obstacles` (moving ones where they stand at each frame's time).
///
/// Errors: an image that is not a readable `.png` or `.svg` file, or the report cannot be written.
pub fn write_report_html(
    path: &Path,
    title: &str,
    sections: &[HtmlSection],
    replays: &[ReplayRun],
    obstacles: &ObstacleMeshes,
) -> std::io::Result<()> {
    use markdown::escape;
    let base = path.parent().unwrap_or(Path::new("."));
    // Markdown images: embedded when they are local PNG/SVG files, else their alt text.
    let md_image = |src: &str, alt: &str| -> String {
        let local = !src.contains("://") && !src.starts_with("data:");
        match local.then(|| embedded_image(&base.join(src), alt)) {
            Some(Ok(img)) => format!("<figure>{img}</figure>"),
            _ => format!("<em>[{}]</em>", escape(alt)),
        }
    };
    let mut body = String::new();
    let mut toc = String::new();
    for (k, s) in sections.iter().enumerate() {
        let id = format!("section-{}", k + 1);
        toc.push_str(&format!(
            "<li><a href=\"#{id}\">{}</a></li>",
            escape(&s.title)
        ));
        body.push_str(&format!(
            "<section id=\"{id}\">\n<h2>{}</h2>\n",
            escape(&s.title)
        ));
        body.push_str(&markdown::to_html(&s.markdown, &md_image));
        for img in &s.images {
            let caption = img.file_stem().and_then(|s| s.to_str()).unwrap_or("");
            body.push_str(&format!(
                "<figure>{}<figcaption>{}</figcaption></figure>\n",
                embedded_image(img, caption)?,
                escape(caption)
            ));
        }
        body.push_str("</section>\n");
    }
    if !replays.is_empty() {
        toc.push_str("<li><a href=\"#replay\">3D replay</a></li>");
        body.push_str(REPLAY_SECTION);
    }
    let json = replay_json(title, replays, obstacles)?;
    let title = escape(title);
    let html = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{title}</title>\n<style>\n{STYLE}</style>\n<script>\n{ERROR_HOOK}</script>\n</head>\n\
         <body>\n<header>\n<h1>{title}</h1>\n<nav><ul>{toc}</ul></nav>\n</header>\n<main>\n{body}</main>\n\
         <footer><pre id=\"status\">loading; errors: 0</pre></footer>\n\
         <script type=\"application/json\" id=\"replay-data\">{json}</script>\n\
         <script>\n{SCRIPT}</script>\n</body>\n</html>\n"
    );
    crate::io::write_atomic(path, html.as_bytes())
}

/// Counts script errors from the very start (a syntax error in the replay script included).
const ERROR_HOOK: &str = "window.__errors = 0;\n\
window.onerror = function (message) {\n\
  window.__errors += 1;\n\
  var s = document.getElementById('status');\n\
  if (s) { s.textContent = (window.__replayDrawn ? 'drawn ' + window.__replayTriangles + ' triangles' : 'not drawn') + '; errors: ' + window.__errors + ' (' + message + ')'; }\n\
};\n";

const REPLAY_SECTION: &str = r#"<section id="replay">
<h2>3D replay</h2>
<div class="replay-controls">
<label>Run <select id="replay-run"></select></label>
<button id="replay-play" type="button">Play</button>
<label>Speed <select id="replay-speed"><option value="0.1">0.1x</option><option value="0.25" selected>0.25x</option><option value="0.5">0.5x</option><option value="1">1x</option></select></label>
<input id="replay-slider" type="range" min="0" max="0" value="0" step="1">
<span id="replay-time"></span>
</div>
<canvas id="replay-canvas" width="960" height="600"></canvas>
<p class="hint">Drag to orbit, wheel to zoom, double-click to reset the view. Cloth: blue front, orange back, mesh edges dark; obstacles grey.</p>
</section>
"#;

#[cfg(test)]
mod tests;
