//! Runs one method along one camera path: renders every frame through a [`FrameSource`],
//! fetches the reference G-buffer of the same camera from a [`ReferenceSource`], feeds both
//! to a [`PathMeter`], and summarises the frame times and counters. The sources are traits so
//! this logic is tested with synthetic methods; [`crate::gpu`] has the real ones.

use std::collections::BTreeMap;

use glam::{UVec2, Vec3};
use texel_render::input::{Camera, Pose, SceneInput};
use texel_render::stats::FrameStats;
use texel_runtime::frame_plan::Animation;
use texel_runtime::path::CameraPath;

use crate::meter::{OwnedFrame, PathMeter, Scores};
use crate::metrics::{MetricError, MetricParams, Reference, percentile};
use crate::report::{CounterMeans, Timing};

/// A render method the evaluator compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Method {
    /// Plain full-resolution raster (no pixel art).
    Raster,
    /// Low-resolution raster, nearest-neighbour upscale.
    Naive,
    /// Low-resolution raster with the camera snapped to the art-pixel grid.
    Snap,
    /// A cubemap around the camera, re-captured every frame.
    Cubemap,
    /// Texel splatting with the paper's schedule.
    SplatPaper,
    /// Texel splatting with our schedule.
    Splat,
    /// Texel marching: our schedule's probes, each pixel's view ray marched through them.
    March,
    /// Texel splatting with sprites turned toward the camera, as screen-space sprite
    /// renderers do (not in [`Method::ALL`]: it differs from `splat` only on sprites, and is
    /// kept to show what turning them toward the probes gains).
    SplatFacing,
}

impl Method {
    /// Every method, cheapest idea first.
    pub const ALL: [Method; 7] = [
        Method::Raster,
        Method::Naive,
        Method::Snap,
        Method::Cubemap,
        Method::SplatPaper,
        Method::Splat,
        Method::March,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Raster => "raster",
            Method::Naive => "naive",
            Method::Snap => "snap",
            Method::Cubemap => "cubemap",
            Method::SplatPaper => "splat-paper",
            Method::Splat => "splat",
            Method::March => "march",
            Method::SplatFacing => "splat-facing",
        }
    }

    /// The method called `name`.
    pub fn parse(name: &str) -> Result<Method, EvalError> {
        (Method::ALL.into_iter().chain([Method::SplatFacing]))
            .find(|m| m.name() == name.trim())
            .ok_or_else(|| EvalError::UnknownMethod(name.to_owned()))
    }

    /// Whether the method draws probe texels (and so reports eye provenance).
    pub fn is_splat(self) -> bool {
        matches!(
            self,
            Method::Splat | Method::SplatPaper | Method::March | Method::SplatFacing
        )
    }
}

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// A method name nobody knows.
    #[error(
        "unknown method `{0}` (expected raster, naive, snap, cubemap, splat-paper, splat, march \
         or splat-facing)"
    )]
    UnknownMethod(String),
    /// The metrics could not compare the frames.
    #[error(transparent)]
    Metric(#[from] MetricError),
    /// Rendering failed.
    #[error("rendering failed: {0}")]
    Render(String),
    /// A level, path or option is unusable.
    #[error("{0}")]
    Input(String),
}

/// One rendered frame of a method.
#[derive(Debug, Clone, Default)]
pub struct RenderedFrame {
    /// Cost and work.
    pub stats: FrameStats,
    /// RGBA8 sRGB colour, row-major.
    pub pixels: Vec<u8>,
    /// Object id per pixel (0 = sky or nothing).
    pub ids: Vec<u32>,
    /// Per pixel, whether it came from the eye probe (splat methods only).
    pub from_eye: Option<Vec<bool>>,
    /// Whether the frame crossfades from one stable probe to the next (splat methods; false
    /// for the others, which have no probes to hand over).
    pub crossfading: bool,
}

/// Something that renders a method frame by frame.
pub trait FrameSource {
    /// Renders frame `index` at `camera`, `dt` seconds after the previous one.
    fn render(&mut self, index: u32, camera: &Camera, dt: f32) -> Result<RenderedFrame, EvalError>;
}

/// Where a camera's sprites turn: a point and the face resolution of matched sizes.
pub type SpriteEye<'a> = dyn FnMut(&Camera) -> Result<(Vec3, u32), EvalError> + 'a;

/// What changes from one reference frame to the next besides the camera.
#[derive(Debug, Clone, Copy)]
pub struct RefFrame<'a> {
    /// The moving objects' poses.
    pub poses: &'a [Pose],
    /// The sprites that move or play, and their state.
    pub sprites: &'a [texel_render::input::SpriteState],
    /// The point sprites turn toward and the face resolution of matched sizes: the frame's
    /// grid probe, where texel splatting turns them.
    pub sprite_eye: (Vec3, u32),
}

/// Something that produces reference G-buffers.
pub trait ReferenceSource {
    /// The reference G-buffer at `camera` for a `size` frame, with what moves at `frame`.
    fn reference(
        &mut self,
        camera: &Camera,
        size: UVec2,
        frame: &RefFrame<'_>,
    ) -> Result<Reference, EvalError>;
}

/// References computed once and replayed (the reference does not depend on the method).
#[derive(Debug, Clone, Default)]
pub struct CachedReferences {
    /// One per frame.
    pub frames: Vec<Reference>,
}

impl CachedReferences {
    /// Computes the references of every frame of `path`, the moving objects of `scene` posed
    /// by `animation` at each frame's time (as every frame source poses them), its sprites
    /// turned toward `sprite_eye` of each frame's camera.
    pub fn compute(
        source: &mut dyn ReferenceSource,
        path: &CameraPath,
        fov_y: f32,
        size: UVec2,
        (scene, animation): (&SceneInput, &Animation),
        sprite_eye: &mut SpriteEye<'_>,
    ) -> Result<Self, EvalError> {
        let mut t = 0.0;
        let mut frames = Vec::with_capacity(path.frames as usize);
        for i in 0..path.frames {
            let poses = animation.poses(t);
            let sprites = animation.sprite_states(t);
            let camera = path.camera(i, fov_y);
            let frame = RefFrame {
                poses: &poses,
                sprites: &sprites,
                sprite_eye: sprite_eye(&camera)?,
            };
            let mut r = source.reference(&camera, size, &frame)?;
            r.poses = (poses.iter())
                .filter_map(|p| Some((scene.objects.get(p.object)?.id, p.transform)))
                .collect();
            // Sprites an animator moves are followed like moving objects (by translation).
            r.poses.extend(sprites.iter().filter_map(|s| {
                let base = scene.sprites.get(s.sprite)?;
                (base.position != s.position)
                    .then(|| (base.id, glam::Mat4::from_translation(s.position)))
            }));
            r.sprites = scene.sprites.iter().map(|s| s.id).collect();
            frames.push(r);
            t = Animation::next_time(t, path.dt);
        }
        Ok(CachedReferences { frames })
    }
}

/// What a run measured.
#[derive(Debug, Clone, Default)]
pub struct RunOutcome {
    /// Stability and accuracy.
    pub scores: Scores,
    /// Per-frame cost and work.
    pub stats: Vec<FrameStats>,
    /// Per frame, whether it crossfaded ([`RenderedFrame::crossfading`]).
    pub fading: Vec<bool>,
}

/// Renders every frame of `path` with `method` and measures it against `references`
/// (one per frame), without a truth. `tick` is called after each frame (for a progress bar).
pub fn run_path(
    path: &CameraPath,
    fov_y: f32,
    method: &mut dyn FrameSource,
    references: &CachedReferences,
    params: MetricParams,
    tick: &mut dyn FnMut(),
) -> Result<RunOutcome, EvalError> {
    let measure = (params, TruthOf::None);
    run_path_observed(path, fov_y, method, references, measure, &mut |_, _| tick())
}

/// Where a run's truth comes from, for its shimmer to leave out what the truth changed
/// ([`crate::metrics`]).
#[derive(Debug, Clone, Copy)]
pub enum TruthOf<'a> {
    /// No truth: every tested pixel counts.
    None,
    /// The truth's frames of the same path (the raster's, run first).
    Frames(&'a crate::colour::Truth),
    /// The run is the truth (the raster itself): every change it makes is intended.
    Itself,
}

/// [`run_path`] that shows every rendered frame to `observe(index, frame)` before measuring
/// it (`texel-eval compare` keeps the pixels this way, so its numbers are `run`'s), with the
/// shimmer measured against `truth`.
pub fn run_path_observed(
    path: &CameraPath,
    fov_y: f32,
    method: &mut dyn FrameSource,
    references: &CachedReferences,
    (params, truth): (MetricParams, TruthOf<'_>),
    observe: &mut dyn FnMut(u32, &RenderedFrame),
) -> Result<RunOutcome, EvalError> {
    let mut meter = PathMeter::new(params);
    let mut stats = Vec::with_capacity(path.frames as usize);
    let mut fading = Vec::with_capacity(path.frames as usize);
    for (i, reference) in (0..path.frames).zip(&references.frames) {
        let camera = path.camera(i, fov_y);
        let frame = method.render(i, &camera, path.dt)?;
        observe(i, &frame);
        stats.push(frame.stats);
        fading.push(frame.crossfading);
        let truth = match truth {
            TruthOf::None => None,
            TruthOf::Frames(t) => t.get(i as usize).map(|(colour, _)| colour.clone()),
            TruthOf::Itself => Some(frame.pixels.clone()),
        };
        meter.push(OwnedFrame {
            camera,
            reference: reference.clone(),
            colour: frame.pixels,
            ids: frame.ids,
            from_eye: frame.from_eye,
            truth,
        })?;
    }
    Ok(RunOutcome {
        scores: meter.scores(),
        stats,
        fading,
    })
}

/// Median and 90th percentile of the frame times.
pub fn frame_timing(stats: &[FrameStats]) -> Timing {
    let mut ms: Vec<f64> = stats.iter().map(|s| s.frame_ms).collect();
    ms.sort_by(f64::total_cmp);
    Timing {
        median: percentile(&ms, 0.5),
        p90: percentile(&ms, 0.9),
    }
}

/// Median milliseconds of each pass over the frames.
pub fn pass_medians(stats: &[FrameStats]) -> BTreeMap<String, f64> {
    let mut per: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for s in stats {
        for p in &s.passes {
            per.entry(p.pass.to_owned()).or_default().push(p.ms);
        }
    }
    per.into_iter()
        .map(|(k, mut v)| {
            v.sort_by(f64::total_cmp);
            (k, percentile(&v, 0.5))
        })
        .collect()
}

/// Mean of each work counter over the frames.
pub fn counter_means(stats: &[FrameStats]) -> CounterMeans {
    let n = stats.len().max(1) as f64;
    let sum = |f: fn(&FrameStats) -> f64| stats.iter().map(f).sum::<f64>() / n;
    CounterMeans {
        faces_captured: sum(|s| f64::from(s.counters.faces_captured)),
        texels_shaded: sum(|s| s.counters.texels_shaded as f64),
        quads_splatted: sum(|s| s.counters.quads_splatted as f64),
        screen_visible_texels: sum(|s| s.counters.screen_visible_texels as f64),
    }
}

/// Mean steps per marched pixel and the fraction of marched pixels that fell back, over the
/// frames; `None` when no pixel was marched (every method but `march`).
pub fn march_means(stats: &[FrameStats]) -> (Option<f64>, Option<f64>) {
    let total = |f: fn(&FrameStats) -> u64| stats.iter().map(f).sum::<u64>() as f64;
    let pixels = total(|s| s.counters.pixels_marched);
    if pixels == 0.0 {
        return (None, None);
    }
    (
        Some(total(|s| s.counters.march_steps) / pixels),
        Some(total(|s| s.counters.march_fallbacks) / pixels),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use texel_render::stats::PassTime;
    use texel_runtime::path::Keyframe;

    /// A method that shows the reference ids with a flat colour, and a colour that flips
    /// every frame when `flip`.
    struct Flat {
        size: UVec2,
        flip: bool,
    }

    impl FrameSource for Flat {
        fn render(&mut self, i: u32, _c: &Camera, _dt: f32) -> Result<RenderedFrame, EvalError> {
            let n = (self.size.x * self.size.y) as usize;
            let v = if self.flip && i % 2 == 1 { 250 } else { 20 };
            Ok(RenderedFrame {
                stats: FrameStats {
                    frame_ms: f64::from(i + 1),
                    passes: vec![PassTime {
                        pass: "draw",
                        ms: 2.0,
                    }],
                    ..Default::default()
                },
                pixels: [v, v, v, 255].repeat(n),
                ids: vec![1; n],
                from_eye: None,
                crossfading: false,
            })
        }
    }

    struct Wall;

    impl ReferenceSource for Wall {
        fn reference(
            &mut self,
            c: &Camera,
            size: UVec2,
            _frame: &RefFrame<'_>,
        ) -> Result<Reference, EvalError> {
            // A wall facing the camera 5 units ahead, id 1 everywhere.
            let inv = crate::metrics::view_proj(c, size).inverse();
            let world = (0..size.x * size.y)
                .map(|i| {
                    let (x, y) = (i % size.x, i / size.x);
                    let nx = (x as f32 + 0.5) / size.x as f32 * 2.0 - 1.0;
                    let ny = 1.0 - (y as f32 + 0.5) / size.y as f32 * 2.0;
                    let a = inv.project_point3(Vec3::new(nx, ny, 0.0));
                    let b = inv.project_point3(Vec3::new(nx, ny, 1.0));
                    let t = (a.z + 5.0) / (a.z - b.z);
                    (a + (b - a) * t).to_array()
                })
                .collect();
            let id = vec![1; (size.x * size.y) as usize];
            Ok(Reference {
                size,
                world,
                id,
                poses: Vec::new(),
                sprites: Vec::new(),
            })
        }
    }

    #[test]
    fn a_flipping_method_flickers_everywhere_and_a_flat_one_nowhere() {
        let size = UVec2::new(24, 16);
        let k = Keyframe {
            position: (0.0, 0.0, 0.0),
            yaw: 0.0,
            pitch: 0.0,
        };
        let path = CameraPath::still(k, 5);
        let refs = CachedReferences::compute(
            &mut Wall,
            &path,
            1.0,
            size,
            (&SceneInput::default(), &Animation::default()),
            &mut |_| Ok((Vec3::ZERO, 64)),
        )
        .expect("refs");
        let mut ticks = 0;
        let mut run = |flip| {
            let mut m = Flat { size, flip };
            run_path(
                &path,
                1.0,
                &mut m,
                &refs,
                MetricParams::default(),
                &mut || ticks += 1,
            )
            .expect("run")
        };
        let still = run(false);
        assert_eq!(still.scores.shimmer.max, 0.0);
        let flipping = run(true);
        assert_eq!(flipping.scores.shimmer.mean, 1.0);
        assert_eq!(ticks, 10);
        let t = frame_timing(&flipping.stats);
        assert_eq!((t.median, t.p90), (3.0, 5.0));
        assert_eq!(pass_medians(&flipping.stats)["draw"], 2.0);
        assert_eq!(counter_means(&flipping.stats).faces_captured, 0.0);
    }

    #[test]
    fn method_names_round_trip() {
        for m in Method::ALL {
            assert_eq!(Method::parse(m.name()).expect("known"), m);
        }
        assert!(Method::parse("splat-ours").is_err());
        assert!(Method::Splat.is_splat() && !Method::Snap.is_splat());
    }
}
