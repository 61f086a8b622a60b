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
//! where its object ids differ from the reference's ([`coverage_overlay`]), by kind. With
//! [`Overlay::Colour`], the colour error against the raster's frame per art pixel.

use std::path::PathBuf;

use glam::UVec2;
use serde::{Deserialize, Serialize};
use texel_render::context::GpuContext;
use texel_runtime::frame_plan::{Animation, scene_input};
use texel_runtime::load::load_level;

use crate::gpu::{level_look, set_face_res};
use crate::metrics::{MetricParams, Summary};
use crate::runner::{EvalError, Method, TruthOf, run_path_observed};
use crate::suite::{
    DEFAULT_FOV_DEG, ReferenceKind, SourceView, load_path, method_source, path_references, runs_on,
};

mod files;
mod panels;
#[cfg(test)]
mod tests;

pub use files::{CompareFiles, gif_delay, write_compare};
pub use panels::{Canvas, GAP, LABEL_HEIGHT, Layout, compose_frame};

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
    /// Methods, left to right (the raster first when it is among them).
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
    /// Where the colour error comes from, per art pixel
    /// ([`crate::colour::colour_error_overlay`]); needs the raster among the methods.
    Colour,
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
/// since `prev` in red (magenta: taken from the eye probe; cyan: changed where the truth
/// changed too, which is not shimmer). RGBA8 like the frames.
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
            map::INTENDED => [40, 200, 255],
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
    let order = crate::colour::raster_first(&plan.methods);
    if plan.overlay == Overlay::Colour && order.first() != Some(&Method::Raster) {
        return Err(EvalError::Input(
            "--colour compares with the raster's frames: add raster to --methods".into(),
        ));
    }
    let grid = crate::colour::art_pixel_grid(plan.size, plan.face_res, fov_y)?;
    let mut truth = crate::colour::Truth::new();
    let mut methods = Vec::with_capacity(plan.methods.len());
    for &method in &order {
        let mut source = method_source(ctx, &level, (&scene, &animation), method, &view)?;
        let mut frames = Vec::with_capacity(path.frames as usize);
        let mut prev: Option<crate::meter::OwnedFrame> = None;
        let mut overlay_error = None;
        let mut kept = crate::colour::Truth::new();
        let against = match method {
            Method::Raster => TruthOf::Itself,
            _ if truth.is_empty() => TruthOf::None,
            _ => TruthOf::Frames(&truth),
        };
        let outcome = run_path_observed(
            &path,
            fov_y,
            source.as_mut(),
            &refs,
            (MetricParams::default(), against),
            &mut |i, frame| {
                let cur = || crate::meter::OwnedFrame {
                    camera: path.camera(i, fov_y),
                    reference: refs.frames[i as usize].clone(),
                    colour: frame.pixels.clone(),
                    ids: frame.ids.clone(),
                    from_eye: frame.from_eye.clone(),
                    truth: match method {
                        Method::Raster => Some(frame.pixels.clone()),
                        _ => truth.get(i as usize).map(|(t, _)| t.clone()),
                    },
                };
                if method == Method::Raster {
                    kept.push((frame.pixels.clone(), frame.ids.clone()));
                }
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
                    Overlay::Colour if method == Method::Raster => {
                        frames.push(frame.pixels.clone());
                    }
                    Overlay::Colour => match truth.get(i as usize) {
                        Some((t, ids)) => frames.push(crate::colour::colour_error_overlay(
                            &frame.pixels,
                            t,
                            ids,
                            plan.size,
                            grid,
                        )),
                        None => frames.push(frame.pixels.clone()),
                    },
                }
                tick(method.name());
            },
        )?;
        if let Some(e) = overlay_error {
            return Err(e);
        }
        if method == Method::Raster {
            truth = kept;
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
