//! Labels: text drawn with the DejaVu Sans font (compiled in, no system font libraries) onto an
//! RGB image, anti-aliased by the glyph coverage.

use ab_glyph::{point, Font, FontRef, ScaleFont};

/// An RGB picture (8 bits per channel, row-major).
pub(crate) struct Image {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<u8>,
}

impl Image {
    /// A white picture.
    pub(crate) fn new(width: usize, height: usize) -> Image {
        Image {
            width,
            height,
            rgb: vec![255; width * height * 3],
        }
    }

    /// Copies a `w` x `h` RGB block with its top-left corner at `(x, y)`, clipped to the image.
    pub(crate) fn blit(&mut self, x: usize, y: usize, w: usize, h: usize, rgb: &[u8]) {
        for row in 0..h.min(self.height.saturating_sub(y)) {
            let n = w.min(self.width.saturating_sub(x)) * 3;
            let dst = ((y + row) * self.width + x) * 3;
            let src = row * w * 3;
            self.rgb[dst..dst + n].copy_from_slice(&rgb[src..src + n]);
        }
    }

    /// Fills a rectangle, clipped to the image.
    pub(crate) fn fill_rect(&mut self, x: usize, y: usize, w: usize, h: usize, color: [u8; 3]) {
        for yy in y..(y + h).min(self.height) {
            for xx in x..(x + w).min(self.width) {
                let i = (yy * self.width + xx) * 3;
                self.rgb[i..i + 3].copy_from_slice(&color);
            }
        }
    }

    fn blend(&mut self, x: i64, y: i64, color: [u8; 3], coverage: f32) {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return;
        }
        let i = (y as usize * self.width + x as usize) * 3;
        let a = coverage.clamp(0.0, 1.0);
        for (dst, &src) in self.rgb[i..i + 3].iter_mut().zip(&color) {
            let old = *dst as f32;
            *dst = (old + a * (src as f32 - old) + 0.5) as u8;
        }
    }
}

fn font() -> Option<FontRef<'static>> {
    FontRef::try_from_slice(dejavu::sans::regular()).ok()
}

/// Width of `text` at `size` pixels (em height), in pixels.
pub(crate) fn text_width(text: &str, size: f32) -> f32 {
    let Some(font) = font() else { return 0.0 };
    let scaled = font.as_scaled(size);
    let mut width = 0.0;
    let mut previous = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            width += scaled.kern(p, id);
        }
        width += scaled.h_advance(id);
        previous = Some(id);
    }
    width
}

/// Draws `text` at `size` pixels with its baseline starting at `(x, baseline)`.
pub(crate) fn draw_text(
    img: &mut Image,
    x: f32,
    baseline: f32,
    text: &str,
    size: f32,
    color: [u8; 3],
) {
    let Some(font) = font() else { return };
    let scaled = font.as_scaled(size);
    let mut caret = x;
    let mut previous = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            caret += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(size, point(caret, baseline));
        caret += scaled.h_advance(id);
        previous = Some(id);
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                let (px, py) = (b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64);
                img.blend(px, py, color, coverage);
            });
        }
    }
}
