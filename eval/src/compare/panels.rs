//! The comparison's frames: the methods' panels side by side on one canvas, each labelled
//! with its name and shimmer, and a bar of the frame's shimmer.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use glam::UVec2;

use super::{CompareError, CompareRun};

/// Gap between panels, pixels.
pub const GAP: u32 = 4;
/// Height of the label strip under the panels, pixels.
pub const LABEL_HEIGHT: u32 = 38;
/// Label font size, pixels.
pub(super) const FONT_PX: f32 = 13.0;
pub(super) const BACKGROUND: [u8; 3] = [24, 24, 28];
pub(super) const TEXT: [u8; 3] = [235, 235, 235];
pub(super) const DIM: [u8; 3] = [150, 150, 160];
pub(super) const BAR: [u8; 3] = [240, 150, 40];

/// An RGB8 image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Canvas {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGB8, row-major.
    pub rgb: Vec<u8>,
}

impl Canvas {
    fn new(width: u32, height: u32, fill: [u8; 3]) -> Self {
        Canvas {
            width,
            height,
            rgb: fill.repeat((width * height) as usize),
        }
    }

    fn fill_rect(&mut self, x: u32, y: u32, w: u32, h: u32, c: [u8; 3]) {
        for yy in y..(y + h).min(self.height) {
            for xx in x..(x + w).min(self.width) {
                let i = ((yy * self.width + xx) * 3) as usize;
                self.rgb[i..i + 3].copy_from_slice(&c);
            }
        }
    }

    fn blend(&mut self, x: i32, y: i32, c: [u8; 3], a: f32) {
        if x < 0 || y < 0 || x as u32 >= self.width || y as u32 >= self.height {
            return;
        }
        let i = ((y as u32 * self.width + x as u32) * 3) as usize;
        // Quantise coverage to eighths: fewer colours for the GIF palette, same look.
        let a = (a.clamp(0.0, 1.0) * 8.0).round() / 8.0;
        for (d, s) in self.rgb[i..i + 3].iter_mut().zip(c) {
            *d = (f32::from(*d) * (1.0 - a) + f32::from(s) * a).round() as u8;
        }
    }
}

/// Where each panel and its label go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// Panels.
    pub panels: u32,
    /// Size of one panel after the upscale.
    pub panel: UVec2,
    /// Size of the whole frame.
    pub frame: UVec2,
}

impl Layout {
    /// The layout of `panels` frames of `size`, upscaled `scale` times.
    pub fn new(panels: u32, size: UVec2, scale: u32) -> Result<Self, CompareError> {
        if panels == 0 || size.x == 0 || size.y == 0 || scale == 0 {
            return Err(CompareError::Layout(
                "nothing to lay out (no method, an empty frame or a zero scale)".into(),
            ));
        }
        let panel = size * scale;
        let frame = UVec2::new(
            panels * panel.x + (panels - 1) * GAP,
            panel.y + LABEL_HEIGHT,
        );
        if frame.x > u32::from(u16::MAX) || frame.y > u32::from(u16::MAX) {
            return Err(CompareError::Layout(format!(
                "a {}×{} frame is larger than a GIF can hold (65535)",
                frame.x, frame.y
            )));
        }
        Ok(Layout {
            panels,
            panel,
            frame,
        })
    }

    /// The left edge of panel `i`.
    pub fn panel_x(&self, i: u32) -> u32 {
        i * (self.panel.x + GAP)
    }
}

/// Draws `s` with its top-left at `pos`, clipped on the right at `x1`.
fn draw_text(
    canvas: &mut Canvas,
    font: &FontRef<'_>,
    pos: (i32, i32),
    x1: i32,
    c: [u8; 3],
    s: &str,
) {
    let scaled = font.as_scaled(PxScale::from(FONT_PX));
    let (x0, y) = pos;
    let baseline = y as f32 + scaled.ascent();
    let mut caret = x0 as f32;
    let mut prev = None;
    for ch in s.chars() {
        let id = font.glyph_id(ch);
        if let Some(p) = prev {
            caret += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(FONT_PX, point(caret, baseline));
        caret += scaled.h_advance(id);
        prev = Some(id);
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, a| {
                let px = b.min.x as i32 + gx as i32;
                if px >= x0 && px < x1 {
                    canvas.blend(px, b.min.y as i32 + gy as i32, c, a);
                }
            });
        }
    }
}

fn text_width(font: &FontRef<'_>, s: &str) -> f32 {
    let scaled = font.as_scaled(PxScale::from(FONT_PX));
    s.chars().map(|c| scaled.h_advance(font.glyph_id(c))).sum()
}

fn label_font() -> Result<FontRef<'static>, CompareError> {
    FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR)
        .map_err(|e| CompareError::Layout(format!("the bundled label font: {e}")))
}

/// Checks that every method has the same number of frames, each `run.size`.
pub(super) fn check_run(run: &CompareRun) -> Result<u32, CompareError> {
    let Some(first) = run.methods.first() else {
        return Err(CompareError::Layout("compare has no method to show".into()));
    };
    let frames = first.frames.len();
    let bytes = (run.size.x * run.size.y * 4) as usize;
    for m in &run.methods {
        if m.frames.len() != frames || m.frames.iter().any(|f| f.len() != bytes) {
            return Err(CompareError::Layout(format!(
                "{}: frames disagree with {} frames of {}×{}",
                m.method.name(),
                frames,
                run.size.x,
                run.size.y
            )));
        }
    }
    if frames == 0 {
        return Err(CompareError::Layout("compare has no frame to show".into()));
    }
    Ok(frames as u32)
}

/// Frame `t` of the comparison: the panels upscaled `scale` times, left to right, and under
/// each the method's name, its mean shimmer, frame `t`'s shimmer and a bar of it (full width
/// at the largest shimmer of any method in any frame).
pub fn compose_frame(
    run: &CompareRun,
    layout: &Layout,
    scale: u32,
    t: usize,
) -> Result<Canvas, CompareError> {
    let font = label_font()?;
    let mut c = Canvas::new(layout.frame.x, layout.frame.y, BACKGROUND);
    let top = run
        .methods
        .iter()
        .flat_map(|m| m.shimmer_per_frame.iter().copied())
        .fold(0.0f64, f64::max);
    let size = run.size;
    for (i, m) in run.methods.iter().enumerate() {
        let x0 = layout.panel_x(i as u32);
        let src = m
            .frames
            .get(t)
            .ok_or_else(|| CompareError::Layout(format!("{} has no frame {t}", m.method.name())))?;
        for y in 0..layout.panel.y {
            let sy = y / scale;
            let row = ((y * c.width + x0) * 3) as usize;
            for x in 0..layout.panel.x {
                let s = ((sy * size.x + x / scale) * 4) as usize;
                let d = row + (x * 3) as usize;
                c.rgb[d..d + 3].copy_from_slice(&src[s..s + 3]);
            }
        }
        let (left, right) = (x0 as i32 + 3, (x0 + layout.panel.x) as i32);
        let y = layout.panel.y as i32 + 2;
        draw_text(&mut c, &font, (left, y), right, TEXT, m.method.name());
        let mean = format!("mean {:.4}", m.shimmer.mean);
        let mx = right - 3 - text_width(&font, &mean).ceil() as i32;
        let name_end = left + text_width(&font, m.method.name()).ceil() as i32 + 8;
        if mx >= name_end {
            draw_text(&mut c, &font, (mx, y), right, DIM, &mean);
        }
        // Frame 0 has no predecessor: no shimmer yet.
        let now = t.checked_sub(1).and_then(|k| m.shimmer_per_frame.get(k));
        let line = match now {
            Some(v) => format!("shimmer {v:.4}"),
            None => "shimmer -".to_owned(),
        };
        draw_text(&mut c, &font, (left, y + 16), right, TEXT, &line);
        if let Some(v) = now.filter(|_| top > 0.0) {
            let w = ((v / top) * f64::from(layout.panel.x)).round() as u32;
            c.fill_rect(x0, layout.frame.y - 4, w, 3, BAR);
        }
    }
    Ok(c)
}
