//! `texel-eval compare`: the methods side by side along one path, as an animated GIF with
//! each frame's shimmer written under each panel, and the same numbers as JSON beside it.
//!
//! The frames and numbers come from the runner ([`run_path_observed`] with the sources of
//! [`method_source`] and the references of [`path_references`]), so the shimmer under a panel
//! is the value `texel-eval run` reports for that frame. The GIF has one palette for every
//! frame (exact when the frames hold at most 256 colours, NeuQuant otherwise), so the
//! encoding itself cannot make a still colour change from frame to frame.
//!
//! With [`Overlay::Flicker`], each panel shows where the metric found flicker instead of
//! the plain frame ([`flicker_overlay`]): the frame dimmed to grey, pixels that changed in
//! red (magenta where the method took them from the eye probe). With [`Overlay::Coverage`],
//! where its object ids differ from the reference's ([`coverage_overlay`]), by kind.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use glam::UVec2;
use serde::{Deserialize, Serialize};
use texel_render::context::GpuContext;
use texel_runtime::frame_plan::{Animation, scene_input};
use texel_runtime::load::load_level;

use crate::gpu::{level_look, set_face_res};
use crate::metrics::{MetricParams, Summary};
use crate::runner::{EvalError, Method, run_path_observed};
use crate::suite::{
    DEFAULT_FOV_DEG, ReferenceKind, SourceView, load_path, method_source, path_references, runs_on,
};

/// Gap between panels, pixels.
pub const GAP: u32 = 4;
/// Height of the label strip under the panels, pixels.
pub const LABEL_HEIGHT: u32 = 38;
/// Label font size, pixels.
const FONT_PX: f32 = 13.0;
const BACKGROUND: [u8; 3] = [24, 24, 28];
const TEXT: [u8; 3] = [235, 235, 235];
const DIM: [u8; 3] = [150, 150, 160];
const BAR: [u8; 3] = [240, 150, 40];

/// Why a comparison could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// Rendering or measuring failed.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// A file could not be written.
    #[error("writing {file}: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The GIF encoder refused the frames.
    #[error("encoding {0}: {1}")]
    Gif(PathBuf, String),
    /// The frames cannot be laid out (nothing to show, sizes that disagree, too large).
    #[error("{0}")]
    Layout(String),
}

/// What to compare.
#[derive(Debug, Clone, PartialEq)]
pub struct ComparePlan {
    /// Level file.
    pub level: PathBuf,
    /// Camera-path file.
    pub path: PathBuf,
    /// Methods, left to right.
    pub methods: Vec<Method>,
    /// Face resolution of every method.
    pub face_res: u32,
    /// Output size of each method's frames.
    pub size: UVec2,
    /// Where the reference G-buffers come from.
    pub reference: ReferenceKind,
    /// What the panels show.
    pub overlay: Overlay,
}

/// What the panels of a comparison show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Overlay {
    /// The frames.
    #[default]
    Frames,
    /// The flicker the shimmer metric found ([`flicker_overlay`]).
    Flicker,
    /// The pixels the coverage metric counts ([`coverage_overlay`]).
    Coverage,
}

/// Frame `cur` dimmed to grey, with the pixels whose object id differs from the reference's
/// (the coverage error) coloured by kind: blue where the method shows an object over the
/// reference's sky (silhouettes grown), yellow where it shows sky over an object (holes,
/// silhouettes shrunk), red where it shows another object (occlusion drawn wrong, mostly
/// where one object's silhouette meets another). RGBA8 like the frames.
pub fn coverage_overlay(cur: &crate::meter::OwnedFrame) -> Result<Vec<u8>, EvalError> {
    let reference = &cur.reference.id;
    if reference.len() != cur.ids.len() || cur.colour.len() != 4 * cur.ids.len() {
        return Err(EvalError::Render(format!(
            "coverage overlay: {} reference ids, {} ids, {} colour bytes",
            reference.len(),
            cur.ids.len(),
            cur.colour.len()
        )));
    }
    let mut out = cur.colour.clone();
    for ((px, &want), &got) in out.chunks_exact_mut(4).zip(reference).zip(&cur.ids) {
        let grey = ((u32::from(px[0]) * 3 + u32::from(px[1]) * 6 + u32::from(px[2])) / 20) as u8;
        let rgb = match (want, got) {
            (w, g) if w == g => [grey, grey, grey],
            (0, _) => [60, 110, 255],
            (_, 0) => [255, 220, 40],
            _ => [255, 40, 40],
        };
        px[..3].copy_from_slice(&rgb);
    }
    Ok(out)
}

/// Frame `cur` dimmed to grey, with the pixels [`crate::metrics::flicker_map`] found changed
/// since `prev` in red (magenta: taken from the eye probe). RGBA8 like the frames.
pub fn flicker_overlay(
    prev: &crate::meter::OwnedFrame,
    cur: &crate::meter::OwnedFrame,
) -> Result<Vec<u8>, EvalError> {
    use crate::metrics::map;
    let (_, mask) =
        crate::metrics::flicker_map(&prev.view(), &cur.view(), &MetricParams::default())?;
    let mut out = cur.colour.clone();
    for (px, m) in out.chunks_exact_mut(4).zip(mask) {
        let grey = ((u32::from(px[0]) * 3 + u32::from(px[1]) * 6 + u32::from(px[2])) / 20) as u8;
        let rgb = match m {
            map::FLICKER => [255, 40, 40],
            map::FLICKER_EYE => [255, 40, 255],
            _ => [grey, grey, grey],
        };
        px[..3].copy_from_slice(&rgb);
    }
    Ok(out)
}

/// One method's frames and per-frame shimmer.
#[derive(Debug, Clone)]
pub struct MethodFrames {
    /// The method.
    pub method: Method,
    /// Every frame, RGBA8 sRGB, row-major, the run's size.
    pub frames: Vec<Vec<u8>>,
    /// Shimmer of frames 1.. (frame 0 has no predecessor), as `run` reports it.
    pub shimmer_per_frame: Vec<f64>,
    /// Summary of `shimmer_per_frame`.
    pub shimmer: Summary,
}

/// The methods' frames along one path.
#[derive(Debug, Clone, Default)]
pub struct CompareRun {
    /// Level file.
    pub level: String,
    /// Camera-path file.
    pub path: String,
    /// Face resolution.
    pub face_res: u32,
    /// Size of each frame.
    pub size: UVec2,
    /// Seconds between frames along the path.
    pub dt: f32,
    /// One per method, left to right.
    pub methods: Vec<MethodFrames>,
}

/// The per-frame numbers written beside the GIF (`<name>.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompareNumbers {
    /// Level file.
    pub level: String,
    /// Camera-path file.
    pub path: String,
    /// Face resolution.
    pub face_res: u32,
    /// Size of each method's frames, before `scale`.
    pub size: [u32; 2],
    /// Nearest-neighbour upscale of the panels in the GIF.
    pub scale: u32,
    /// Frames along the path (and in the GIF).
    pub frames: u32,
    /// Frames per second of the GIF.
    pub fps: f32,
    /// One per method, left to right.
    pub methods: Vec<MethodNumbers>,
}

/// One method's numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodNumbers {
    /// Method name.
    pub method: String,
    /// Mean, p95 and max of the per-frame shimmer.
    pub shimmer: Summary,
    /// Shimmer of frames 1.. (frame 0 has no predecessor).
    pub shimmer_per_frame: Vec<f64>,
}

/// Frames `plan` renders (references included), for a progress bar.
pub fn compare_frames(plan: &ComparePlan) -> Result<u64, EvalError> {
    let path = load_path(&plan.path)?;
    Ok(u64::from(path.frames) * (plan.methods.len() as u64 + 1))
}

/// Renders every method of `plan` along its path and measures it as `run` does. `tick(label)`
/// is called after every frame rendered (references included).
pub fn run_compare(
    ctx: &GpuContext,
    plan: &ComparePlan,
    tick: &mut dyn FnMut(&str),
) -> Result<CompareRun, EvalError> {
    if plan.methods.is_empty() {
        return Err(EvalError::Input("compare needs a method".into()));
    }
    let mut level = load_level(&plan.level).map_err(|e| EvalError::Input(e.to_string()))?;
    let path = load_path(&plan.path)?;
    if let Some(m) = plan.methods.iter().find(|m| !runs_on(**m, &path)) {
        return Err(EvalError::Input(format!(
            "{} has no orthographic form; {} is orthographic",
            m.name(),
            plan.path.display()
        )));
    }
    let fov_y = path.fov_y(DEFAULT_FOV_DEG.to_radians());
    let scene = scene_input(&level);
    let animation = Animation::new(&level, &scene);
    // Before the references: their sprites snap to the probe texels of this resolution.
    set_face_res(&mut level, plan.face_res)?;
    let refs = path_references(
        ctx,
        &level,
        (&scene, &animation),
        &path,
        fov_y,
        plan.size,
        plan.reference,
        &mut || tick("reference"),
    )?;
    let view = SourceView {
        size: plan.size,
        face_res: plan.face_res,
        fov_y,
        look: level_look(&level),
        warm_up: path.camera(0, fov_y),
    };
    let mut methods = Vec::with_capacity(plan.methods.len());
    for &method in &plan.methods {
        let mut source = method_source(ctx, &level, (&scene, &animation), method, &view)?;
        let mut frames = Vec::with_capacity(path.frames as usize);
        let mut prev: Option<crate::meter::OwnedFrame> = None;
        let mut overlay_error = None;
        let outcome = run_path_observed(
            &path,
            fov_y,
            source.as_mut(),
            &refs,
            MetricParams::default(),
            &mut |i, frame| {
                let cur = || crate::meter::OwnedFrame {
                    camera: path.camera(i, fov_y),
                    reference: refs.frames[i as usize].clone(),
                    colour: frame.pixels.clone(),
                    ids: frame.ids.clone(),
                    from_eye: frame.from_eye.clone(),
                };
                let mut shown = |r: Result<Vec<u8>, EvalError>| {
                    r.unwrap_or_else(|e| {
                        overlay_error = Some(e);
                        frame.pixels.clone()
                    })
                };
                match plan.overlay {
                    Overlay::Frames => frames.push(frame.pixels.clone()),
                    Overlay::Flicker => {
                        let cur = cur();
                        let image = match &prev {
                            Some(p) => shown(flicker_overlay(p, &cur)),
                            None => cur.colour.clone(),
                        };
                        frames.push(image);
                        prev = Some(cur);
                    }
                    Overlay::Coverage => frames.push(shown(coverage_overlay(&cur()))),
                }
                tick(method.name());
            },
        )?;
        if let Some(e) = overlay_error {
            return Err(e);
        }
        methods.push(MethodFrames {
            method,
            frames,
            shimmer_per_frame: outcome.scores.shimmer_per_frame,
            shimmer: outcome.scores.shimmer,
        });
    }
    Ok(CompareRun {
        level: plan.level.display().to_string(),
        path: plan.path.display().to_string(),
        face_res: plan.face_res,
        size: plan.size,
        dt: path.dt,
        methods,
    })
}

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
fn check_run(run: &CompareRun) -> Result<u32, CompareError> {
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

/// Maps colours to a palette of at most 256 shared by every frame.
struct Palette {
    rgb: Vec<u8>,
    exact: HashMap<[u8; 3], u8>,
    quant: Option<color_quant::NeuQuant>,
}

impl Palette {
    /// The palette of `frames`: their colours when at most 256, else NeuQuant's.
    fn of(frames: &[&Canvas]) -> Palette {
        let mut exact: HashMap<[u8; 3], u8> = HashMap::new();
        'scan: for f in frames {
            for p in f.rgb.chunks_exact(3) {
                let k = [p[0], p[1], p[2]];
                if !exact.contains_key(&k) {
                    if exact.len() == 256 {
                        exact.clear();
                        break 'scan;
                    }
                    exact.insert(k, exact.len() as u8);
                }
            }
        }
        if !exact.is_empty() {
            let mut rgb = vec![0; exact.len() * 3];
            for (k, i) in &exact {
                let i = usize::from(*i) * 3;
                rgb[i..i + 3].copy_from_slice(k);
            }
            return Palette {
                rgb,
                exact,
                quant: None,
            };
        }
        // Sample at most about a million pixels over all frames.
        let total: usize = frames.iter().map(|f| f.rgb.len() / 3).sum();
        let step = (total / 1_000_000).max(1);
        let mut samples = Vec::with_capacity(total / step * 4 + 4);
        let mut k = 0;
        for f in frames {
            for p in f.rgb.chunks_exact(3) {
                if k % step == 0 {
                    samples.extend_from_slice(&[p[0], p[1], p[2], 255]);
                }
                k += 1;
            }
        }
        let nq = color_quant::NeuQuant::new(10, 256, &samples);
        Palette {
            rgb: nq.color_map_rgb(),
            exact: HashMap::new(),
            quant: Some(nq),
        }
    }

    fn index(&mut self, frame: &Canvas) -> Vec<u8> {
        frame
            .rgb
            .chunks_exact(3)
            .map(|p| {
                let k = [p[0], p[1], p[2]];
                if let Some(i) = self.exact.get(&k) {
                    return *i;
                }
                let i = self
                    .quant
                    .as_ref()
                    .map_or(0, |q| q.index_of(&[p[0], p[1], p[2], 255]) as u8);
                self.exact.insert(k, i);
                i
            })
            .collect()
    }
}

/// What [`write_compare`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareFiles {
    /// The animated GIF.
    pub gif: PathBuf,
    /// The per-frame numbers.
    pub json: PathBuf,
    /// Frames in the GIF.
    pub frames: u32,
    /// Width and height of the GIF.
    pub size: UVec2,
}

/// The GIF frame delay, in hundredths of a second, of `fps` (at least 2: browsers slow
/// shorter delays down to 10).
pub fn gif_delay(fps: f32) -> u16 {
    (100.0 / fps.max(0.01))
        .round()
        .clamp(2.0, f32::from(u16::MAX)) as u16
}

/// Writes `dir/<name>.gif` (looping forever, `fps` frames per second, default the path's)
/// and `dir/<name>.json` of `run`, the panels upscaled `scale` times.
pub fn write_compare(
    run: &CompareRun,
    dir: &Path,
    name: &str,
    scale: u32,
    fps: Option<f32>,
) -> Result<CompareFiles, CompareError> {
    let frames = check_run(run)?;
    let layout = Layout::new(run.methods.len() as u32, run.size, scale)?;
    let fps = fps.unwrap_or(if run.dt > 0.0 { 1.0 / run.dt } else { 30.0 });
    if !(fps.is_finite() && fps > 0.0) {
        return Err(CompareError::Layout(format!(
            "frames per second must be positive, got {fps}"
        )));
    }
    let io = |file: &Path| {
        let file = file.to_path_buf();
        move |source| CompareError::Io { file, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let gif_file = dir.join(format!("{name}.gif"));
    let json_file = dir.join(format!("{name}.json"));

    let composed = (0..frames as usize)
        .map(|t| compose_frame(run, &layout, scale, t))
        .collect::<Result<Vec<_>, _>>()?;
    let mut palette = Palette::of(&composed.iter().collect::<Vec<_>>());
    let gif_err = |e: gif::EncodingError| CompareError::Gif(gif_file.clone(), e.to_string());
    let file = std::fs::File::create(&gif_file).map_err(io(&gif_file))?;
    let (w, h) = (layout.frame.x as u16, layout.frame.y as u16);
    let mut encoder =
        gif::Encoder::new(std::io::BufWriter::new(file), w, h, &palette.rgb).map_err(gif_err)?;
    encoder.set_repeat(gif::Repeat::Infinite).map_err(gif_err)?;
    let delay = gif_delay(fps);
    for canvas in &composed {
        let mut frame = gif::Frame::from_indexed_pixels(w, h, palette.index(canvas), None);
        frame.delay = delay;
        encoder.write_frame(&frame).map_err(gif_err)?;
    }
    encoder.into_inner().map_err(gif_err)?;

    let numbers = CompareNumbers {
        level: run.level.clone(),
        path: run.path.clone(),
        face_res: run.face_res,
        size: run.size.to_array(),
        scale,
        frames,
        fps,
        methods: run
            .methods
            .iter()
            .map(|m| MethodNumbers {
                method: m.method.name().to_owned(),
                shimmer: m.shimmer,
                shimmer_per_frame: m.shimmer_per_frame.clone(),
            })
            .collect(),
    };
    let text = serde_json::to_string_pretty(&numbers)
        .map_err(|e| CompareError::Layout(format!("serialising the numbers: {e}")))?;
    std::fs::write(&json_file, text).map_err(io(&json_file))?;
    Ok(CompareFiles {
        gif: gif_file,
        json: json_file,
        frames,
        size: layout.frame,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decodes every frame of a GIF to RGBA.
    fn decode(file: &Path) -> (u16, u16, Vec<Vec<u8>>, Vec<u16>) {
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::RGBA);
        let mut d = opts
            .read_info(std::fs::File::open(file).expect("gif exists"))
            .expect("gif decodes");
        let (w, h) = (d.width(), d.height());
        let mut frames = Vec::new();
        let mut delays = Vec::new();
        while let Some(f) = d.read_next_frame().expect("frame decodes") {
            assert_eq!((f.width, f.height, f.left, f.top), (w, h, 0, 0));
            frames.push(f.buffer.to_vec());
            delays.push(f.delay);
        }
        (w, h, frames, delays)
    }

    fn px(frame: &[u8], w: u16, x: u32, y: u32) -> [u8; 3] {
        let i = ((y * u32::from(w) + x) * 4) as usize;
        [frame[i], frame[i + 1], frame[i + 2]]
    }

    #[test]
    fn the_coverage_overlay_colours_each_kind_of_wrong_pixel() {
        // Four pixels: right, an object over the sky, sky over an object, another object.
        let reference = crate::metrics::Reference {
            size: UVec2::new(4, 1),
            world: vec![[0.0; 3]; 4],
            id: vec![1, 0, 2, 3],
            ..Default::default()
        };
        let frame = crate::meter::OwnedFrame {
            camera: texel_render::input::Camera::from_yaw_pitch(glam::Vec3::ZERO, 0.0, 0.0),
            reference,
            colour: [200u8, 100, 0, 255].repeat(4),
            ids: vec![1, 5, 0, 4],
            from_eye: None,
        };
        let out = coverage_overlay(&frame).unwrap();
        let grey = ((200 * 3 + 100 * 6) / 20) as u8;
        assert_eq!(
            &out[0..4],
            &[grey, grey, grey, 255],
            "a right pixel is dimmed"
        );
        assert_eq!(&out[4..8], &[60, 110, 255, 255], "grown over the sky: blue");
        assert_eq!(&out[8..12], &[255, 220, 40, 255], "a hole: yellow");
        assert_eq!(&out[12..16], &[255, 40, 40, 255], "another object: red");
        let short = crate::meter::OwnedFrame {
            ids: vec![1],
            ..frame
        };
        assert!(
            coverage_overlay(&short).is_err(),
            "mismatched sizes are an error"
        );
    }

    /// Three methods of 4 frames of 20×10: `a` a still grey, `b` flipping between two colours,
    /// `c` a still grey identical to `a` except one quadrant.
    fn synthetic() -> CompareRun {
        let size = UVec2::new(20, 10);
        let n = (size.x * size.y) as usize;
        let flat = |v: [u8; 3]| [v[0], v[1], v[2], 255].repeat(n);
        let a = MethodFrames {
            method: Method::Naive,
            frames: vec![flat([90, 90, 90]); 4],
            shimmer_per_frame: vec![0.0; 3],
            shimmer: Summary::of(&[0.0; 3]),
        };
        let b = MethodFrames {
            method: Method::Snap,
            frames: (0..4)
                .map(|t| {
                    flat(if t % 2 == 0 {
                        [200, 40, 40]
                    } else {
                        [40, 40, 200]
                    })
                })
                .collect(),
            shimmer_per_frame: vec![1.0; 3],
            shimmer: Summary::of(&[1.0; 3]),
        };
        let mut quadrant = flat([90, 90, 90]);
        for y in 0..5 {
            for x in 0..10 {
                let i = (y * 20 + x) * 4;
                quadrant[i..i + 3].copy_from_slice(&[10, 220, 10]);
            }
        }
        let c = MethodFrames {
            method: Method::Splat,
            frames: vec![quadrant; 4],
            shimmer_per_frame: vec![0.25, 0.5, 0.0],
            shimmer: Summary::of(&[0.25, 0.5, 0.0]),
        };
        CompareRun {
            level: "l.ron".into(),
            path: "p.ron".into(),
            face_res: 64,
            size,
            dt: 0.05,
            methods: vec![a, b, c],
        }
    }

    #[test]
    fn the_gif_shows_each_method_in_its_panel_with_its_labels() {
        let dir = tempfile::tempdir().expect("temp dir");
        let run = synthetic();
        let files = write_compare(&run, dir.path(), "cmp", 6, None).expect("writes");
        let (w, h, frames, delays) = decode(&files.gif);
        // 3 panels of 120×60 with 2 gaps, and the label strip.
        assert_eq!(
            (u32::from(w), u32::from(h)),
            (3 * 120 + 2 * GAP, 60 + LABEL_HEIGHT)
        );
        assert_eq!(files.size, UVec2::new(u32::from(w), u32::from(h)));
        assert_eq!((frames.len(), files.frames), (4, 4));
        // dt 0.05 s: 20 fps, 5 hundredths per frame.
        assert!(delays.iter().all(|d| *d == 5), "{delays:?}");
        let (a, b, c) = (0, 120 + GAP, 2 * (120 + GAP));
        for (t, f) in frames.iter().enumerate() {
            // Panel a is still grey everywhere; panel c differs from it only in its quadrant.
            assert_eq!(px(f, w, a + 90, 50), [90, 90, 90]);
            assert_eq!(px(f, w, a + 10, 10), [90, 90, 90]);
            assert_eq!(px(f, w, c + 90, 50), [90, 90, 90]);
            assert_eq!(px(f, w, c + 10, 10), [10, 220, 10]);
            assert_eq!(px(f, w, c + 59, 29), [10, 220, 10]);
            assert_eq!(px(f, w, c + 60, 29), [90, 90, 90]);
            // Panel b flips every frame.
            let want = if t % 2 == 0 {
                [200, 40, 40]
            } else {
                [40, 40, 200]
            };
            assert_eq!(px(f, w, b + 60, 30), want, "frame {t}");
            // The gaps are background.
            assert_eq!(px(f, w, 120 + 1, 30), BACKGROUND);
        }
        // Labels: text pixels in each label strip, and the shimmer line changes with the
        // value (frame 1 and 2 of c differ: 0.2500 and 0.5000; a's stay the same).
        let strip = |f: &[u8], x0: u32| -> Vec<[u8; 3]> {
            (60..60 + LABEL_HEIGHT)
                .flat_map(|y| (x0..x0 + 120).map(move |x| (x, y)))
                .map(|(x, y)| px(f, w, x, y))
                .collect()
        };
        for x0 in [a, b, c] {
            assert!(
                strip(&frames[1], x0).contains(&TEXT),
                "no label text in the strip at {x0}"
            );
        }
        assert_ne!(strip(&frames[1], c), strip(&frames[2], c));
        assert_eq!(strip(&frames[1], a), strip(&frames[2], a));
        // b's bar is the full panel width (the largest shimmer), c's at frame 1 a quarter.
        let bar_y = 60 + LABEL_HEIGHT - 4;
        assert_eq!(px(&frames[1], w, b + 119, bar_y), BAR);
        assert_eq!(px(&frames[1], w, c + 25, bar_y), BAR);
        assert_ne!(px(&frames[1], w, c + 35, bar_y), BAR);
        assert_ne!(px(&frames[0], w, b + 10, bar_y), BAR);

        let numbers: CompareNumbers =
            serde_json::from_str(&std::fs::read_to_string(&files.json).expect("json written"))
                .expect("json parses");
        assert_eq!(numbers.frames, 4);
        assert_eq!(numbers.fps, 20.0);
        assert_eq!(numbers.methods[2].method, "splat");
        assert_eq!(numbers.methods[2].shimmer_per_frame, vec![0.25, 0.5, 0.0]);
    }

    #[test]
    fn more_than_256_colours_share_one_palette_across_frames() {
        let dir = tempfile::tempdir().expect("temp dir");
        let mut run = synthetic();
        // A gradient of 400 colours, the same in every frame.
        let n = (run.size.x * run.size.y) as usize;
        let g: Vec<u8> = (0..n)
            .flat_map(|i| {
                [
                    (i % 256) as u8,
                    (i / 2 % 256) as u8,
                    255 - (i % 200) as u8,
                    255,
                ]
            })
            .collect();
        run.methods[0].frames = vec![g; 4];
        let files = write_compare(&run, dir.path(), "grad", 1, Some(10.0)).expect("writes");
        let (w, _, frames, delays) = decode(&files.gif);
        assert_eq!(delays[0], 10);
        // Quantised, yet a still panel is the same in every frame.
        let panel = |f: &[u8]| -> Vec<[u8; 3]> {
            (0..10)
                .flat_map(|y| (0..20).map(move |x| (x, y)))
                .map(|(x, y)| px(f, w, x, y))
                .collect()
        };
        for f in &frames[1..] {
            assert_eq!(panel(f), panel(&frames[0]));
        }
    }

    #[test]
    fn unusable_runs_are_errors() {
        let dir = tempfile::tempdir().expect("temp dir");
        let mut run = synthetic();
        run.methods[1].frames.pop();
        let e = write_compare(&run, dir.path(), "x", 1, None).unwrap_err();
        assert!(e.to_string().contains("snap"), "{e}");
        let e = write_compare(&CompareRun::default(), dir.path(), "x", 1, None).unwrap_err();
        assert!(matches!(e, CompareError::Layout(_)), "{e}");
        assert!(Layout::new(3, UVec2::new(4096, 100), 8).is_err());
        assert!(write_compare(&synthetic(), dir.path(), "x", 0, None).is_err());
        assert_eq!(
            (gif_delay(30.0), gif_delay(100.0), gif_delay(10.0)),
            (3, 2, 10)
        );
    }
}
