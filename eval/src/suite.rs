//! Runs and suites: loads levels and paths, computes each path's reference G-buffers once,
//! runs every method at every face resolution against them, and turns the outcomes into
//! [`RunRecord`]s.

use std::path::{Path, PathBuf};

use glam::UVec2;
use texel_render::context::GpuContext;
use texel_render::input::{Camera, Display, Look, SceneInput, Schedule};
use texel_runtime::frame_plan::{Animation, scene_input};
use texel_runtime::load::{LoadedLevel, load_level};
use texel_runtime::path::{CameraPath, Projection};

use crate::colour::{ColourError, Truth, art_pixel_grid, colour_error, raster_first};
use crate::gpu::{
    BaselineSource, GpuReference, SplatSource, baseline_of, level_look, set_face_res,
};
use crate::metrics::MetricParams;
use crate::reference::CpuScene;
use crate::report::RunRecord;
use crate::runner::{
    CachedReferences, EvalError, FrameSource, Method, ReferenceSource, TruthOf, counter_means,
    frame_timing, march_means, pass_medians, run_path_observed,
};

/// Vertical field of view of paths that do not set one: 60°.
pub const DEFAULT_FOV_DEG: f32 = 60.0;

/// Where reference G-buffers come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ReferenceKind {
    /// The baselines' plain full-resolution raster (exact to the rasterizer's coverage rule).
    #[default]
    Gpu,
    /// A CPU ray cast through pixel centres (no GPU needed; slower).
    Cpu,
}

impl ReferenceKind {
    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            ReferenceKind::Gpu => "gpu",
            ReferenceKind::Cpu => "cpu",
        }
    }
}

/// Methods × face resolutions along one path of one level.
#[derive(Debug, Clone, PartialEq)]
pub struct RunPlan {
    /// Level file.
    pub level: PathBuf,
    /// Camera-path file.
    pub path: PathBuf,
    /// Methods to run.
    pub methods: Vec<Method>,
    /// Face resolutions to run each method at.
    pub face_res: Vec<u32>,
    /// Output size.
    pub size: UVec2,
    /// Whether the level's animators are taken off first: its moving objects then stand at
    /// their transforms as still geometry (the still-world baseline of a path with motion).
    pub freeze: bool,
    /// Fly only the path's first this many frames ([`CameraPath::first`]); `None`: all.
    pub first_frames: Option<u32>,
}

/// Which paths the suite flies on which bundled level.
pub const SUITE_PATHS: [(&str, &str); 22] = [
    ("stone_circle", "yaw"),
    ("stone_circle", "strafe_in_cell"),
    ("stone_circle", "walk_cells"),
    ("stone_circle", "sprint_cells"),
    ("stone_circle", "dolly"),
    ("stone_circle", "orbit"),
    ("stone_circle", "ortho_pan"),
    ("stone_circle", "iso_orbit"),
    ("stone_circle", "low_orbit"),
    ("stone_circle", "stone_edge"),
    ("colonnade", "wall_graze"),
    ("colonnade", "occluder_pass"),
    ("colonnade", "wall_brush"),
    ("textured", "textured_strafe"),
    ("textured", "textured_walk"),
    ("terrain_hills", "terrain_walk"),
    ("terrain_hills", "terrain_descent"),
    ("moving_parts", "moving_still"),
    ("moving_parts", "moving_walk"),
    ("moving_parts", "moving_orbit"),
    ("sprites", "yaw"),
    ("sprites", "strafe_in_cell"),
];

/// The paths written for the weak classes of views (issue 60; `assets/paths/classes/`, whose
/// README says what each flies), each on its level: `texel-eval suite --set classes`.
pub const CLASS_PATHS: [(&str, &str); 10] = [
    ("sprites", "classes/sprites_near_strafe"),
    ("sprites", "classes/sprites_near_orbit"),
    ("moving_parts", "classes/moving_toward_mill"),
    ("moving_parts", "classes/moving_toward_platform"),
    ("colonnade", "classes/colonnade_diagonal"),
    ("stone_circle", "classes/circle_diagonal"),
    ("stone_circle", "classes/circle_low_outside"),
    ("colonnade", "classes/colonnade_low_outside"),
    ("stone_circle", "classes/circle_brush_stone"),
    ("colonnade", "classes/colonnade_brush_pillars"),
];

/// The suite: every path of `set` (`level`, `path` under `paths/`: [`SUITE_PATHS`] or
/// [`CLASS_PATHS`]) on its level, every method, at `face_res` and `size`. On the sprites
/// level, `splat` brings `splat-facing` along (the same frames with the sprites turned
/// toward the camera), so the chart shows what turning them toward the probes gains.
pub fn suite_plans(
    assets: &Path,
    set: &[(&str, &str)],
    methods: &[Method],
    (face_res, size): (&[u32], UVec2),
) -> Vec<RunPlan> {
    set.iter()
        .map(|(level, path)| RunPlan {
            level: assets.join("levels").join(format!("{level}.ron")),
            path: assets.join("paths").join(format!("{path}.ron")),
            methods: with_facing(level, methods),
            face_res: face_res.to_vec(),
            size,
            freeze: false,
            first_frames: None,
        })
        .collect()
}

fn with_facing(level: &str, methods: &[Method]) -> Vec<Method> {
    let mut out = methods.to_vec();
    if *level == *"sprites" && out.contains(&Method::Splat) && !out.contains(&Method::SplatFacing) {
        out.push(Method::SplatFacing);
    }
    out
}

/// Frames `plans` render in all (each path's references count once), for a progress bar.
pub fn total_frames(plans: &[RunPlan]) -> Result<u64, EvalError> {
    let mut total = 0;
    for p in plans {
        let path = plan_path(p)?;
        let per_res = p.methods.iter().filter(|m| runs_on(**m, &path)).count();
        let raster = p.methods.contains(&Method::Raster) as usize;
        // A level with sprites has its references made for each face resolution.
        let sprites = texel_scene::Scene::load(&p.level).is_ok_and(|scene| {
            let world = scene.world();
            let mut q = world.query::<&texel_scene::sprite::Sprite>();
            q.iter().next().is_some()
        });
        let references = if sprites { p.face_res.len() } else { 1 };
        let runs = (per_res * p.face_res.len() + references
            - raster * p.face_res.len().saturating_sub(1)) as u64;
        total += u64::from(path.frames) * runs;
    }
    Ok(total)
}

/// Loads a camera path, naming the file in the error.
pub fn load_path(file: &Path) -> Result<CameraPath, EvalError> {
    CameraPath::load(file).map_err(|e| EvalError::Input(e.to_string()))
}

/// The frames a test flies in its short form: the first half of `path`'s when the running
/// test is one the test plan shortens on this driver ([`texel_render::context::short_form`]);
/// `None` (every frame) otherwise.
pub fn short_form_frames(path: &Path) -> Option<u32> {
    if !texel_render::context::short_form() {
        return None;
    }
    let frames = load_path(path).ok()?.frames;
    let first = frames.div_ceil(2).max(2);
    eprintln!("short form: the first {first} of {frames} frames");
    Some(first)
}

/// The path `plan` flies: its file, cut to its first frames when the plan says so.
fn plan_path(plan: &RunPlan) -> Result<CameraPath, EvalError> {
    let path = load_path(&plan.path)?;
    Ok(match plan.first_frames {
        Some(k) => path.first(k),
        None => path,
    })
}

/// Runs one plan; `tick(label)` is called after every frame rendered (references included).
pub fn run_plan(
    ctx: &GpuContext,
    plan: &RunPlan,
    reference: ReferenceKind,
    tick: &mut dyn FnMut(&str),
) -> Result<Vec<RunRecord>, EvalError> {
    if plan.face_res.is_empty() || plan.methods.is_empty() {
        return Err(EvalError::Input(
            "a run needs a method and a face resolution".into(),
        ));
    }
    let mut level = load_level(&plan.level).map_err(|e| EvalError::Input(e.to_string()))?;
    if plan.freeze {
        freeze(&mut level);
    }
    let path = plan_path(plan)?;
    let fov_y = path.fov_y(DEFAULT_FOV_DEG.to_radians());
    let scene = scene_input(&level);
    let animation = Animation::new(&level, &scene);
    let stem = |p: &Path| {
        p.file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into())
    };
    let name = format!("{} / {}", stem(&plan.level), stem(&plan.path));
    let moving = (&scene, &animation);
    // Sprites in the reference snap to the grid probe's texels like splat's, so a level with
    // sprites has its references made again for each face resolution.
    let per_res = !scene.sprites.is_empty();
    let mut refs = None;
    let warm_up = path.camera(0, fov_y);
    let look = level_look(&level);
    let mut records = Vec::new();
    let methods = raster_first(&plan.methods);
    let mut truth: Option<Truth> = None;
    for &n in &plan.face_res {
        set_face_res(&mut level, n)?;
        let mut splat_fading = None;
        if refs.is_none() || per_res {
            refs = Some(path_references(
                ctx,
                &level,
                moving,
                &path,
                fov_y,
                plan.size,
                reference,
                &mut || tick(&format!("{name}: reference")),
            )?);
        }
        let refs = refs
            .as_ref()
            .ok_or(EvalError::Input("no references".into()))?;
        let grid = art_pixel_grid(plan.size, n, fov_y)?;
        for &method in &methods {
            if !runs_on(method, &path) || (method == Method::Raster && n != plan.face_res[0]) {
                // Raster does not depend on the face resolution: run it once.
                continue;
            }
            let view = SourceView {
                size: plan.size,
                face_res: n,
                fov_y,
                look,
                warm_up,
            };
            let mut source = method_source(ctx, &level, moving, method, &view)?;
            let label = format!("{name}: {} @{n}", method.name());
            let params = MetricParams::default();
            let mut kept = Vec::new();
            let mut colours: Vec<ColourError> = Vec::new();
            let against = match (method, truth.as_ref()) {
                (Method::Raster, _) => TruthOf::Itself,
                (_, Some(t)) => TruthOf::Frames(t),
                (_, None) => TruthOf::None,
            };
            let outcome = run_path_observed(
                &path,
                fov_y,
                source.as_mut(),
                refs,
                (params, against),
                &mut |i, frame| {
                    tick(&label);
                    if method == Method::Raster {
                        kept.push((frame.pixels.clone(), frame.ids.clone()));
                    } else if let Some((t, ids)) = truth.as_ref().and_then(|t| t.get(i as usize))
                        && let Some(e) = colour_error(&frame.pixels, t, ids, plan.size, grid)
                    {
                        colours.push(e);
                    }
                },
            )?;
            if method == Method::Raster {
                truth = Some(kept);
            }
            let colour_error = match method {
                Method::Raster => Some(ColourError::default()),
                _ if colours.is_empty() => None,
                _ => Some(ColourError::mean_of(&colours)),
            };
            let (steps_per_pixel, fallback_fraction) = march_means(&outcome.stats);
            records.push(RunRecord {
                level: plan.level.display().to_string(),
                path: plan.path.display().to_string(),
                method: method.name().to_owned(),
                face_res: n,
                size: plan.size.to_array(),
                frames: path.frames,
                reference: reference.name().to_owned(),
                frame_ms: frame_timing(&outcome.stats),
                pass_ms: pass_medians(&outcome.stats),
                counters: counter_means(&outcome.stats),
                shimmer: outcome.scores.shimmer,
                shimmer_per_frame: outcome.scores.shimmer_per_frame,
                shimmer_all: Some(outcome.scores.shimmer_all),
                coverage_error: outcome.scores.coverage_error,
                colour_error,
                hole_rate: outcome.scores.hole_rate,
                eye_fraction: outcome.scores.eye_fraction,
                eye_flicker_share: outcome.scores.eye_flicker_share,
                moving_shimmer: outcome.scores.moving_shimmer,
                still_shimmer: outcome.scores.still_shimmer,
                sprite_shimmer: outcome.scores.sprite_shimmer,
                steps_per_pixel,
                fallback_fraction,
                crossings: None,
            });
            if method == Method::Splat {
                splat_fading = Some(outcome.fading);
            }
        }
        if let Some(fading) = splat_fading {
            crate::crossings::split_runs(&mut records, n, &fading);
        }
    }
    Ok(records)
}

/// Takes every animator off `level` and stops every sprite's frames: what moved stands
/// still at its transform, a sprite shows its first animation's first frame.
pub fn freeze(level: &mut LoadedLevel) {
    let entities: Vec<hecs::Entity> = level.scene.entities().collect();
    let world = level.scene.world_mut();
    for e in entities {
        let _ = world.remove_one::<texel_scene::animator::Animator>(e);
        if let Ok(mut sprite) = world.get::<&mut texel_scene::sprite::Sprite>(e) {
            for a in &mut sprite.animations {
                a.frames.truncate(1);
            }
        }
    }
}

/// The reference G-buffer of every frame of `path` through `level`; `tick` is called after
/// each.
#[allow(clippy::too_many_arguments)]
pub fn path_references(
    ctx: &GpuContext,
    level: &LoadedLevel,
    (scene, animation): (&SceneInput, &Animation),
    path: &CameraPath,
    fov_y: f32,
    size: UVec2,
    reference: ReferenceKind,
    tick: &mut dyn FnMut(),
) -> Result<CachedReferences, EvalError> {
    let mut counted = CountingReference {
        inner: match reference {
            ReferenceKind::Gpu => Box::new(GpuReference::new(ctx, scene)?),
            ReferenceKind::Cpu => Box::new(CpuScene::new(scene)),
        },
        tick: &mut |()| tick(),
    };
    // Sprites turn toward each frame's grid probe, as texel splatting turns them; a level
    // without sprites needs no frame driver (its probe placement builds a ray-cast tree).
    let mut driver = (!scene.sprites.is_empty())
        .then(|| texel_runtime::frame_plan::FrameDriver::new(level, size, fov_y))
        .transpose()
        .map_err(|e| EvalError::Input(e.to_string()))?;
    let mut eye = |c: &texel_render::input::Camera| match driver.as_mut() {
        Some(d) => d.grid_probe(c).map_err(|e| EvalError::Input(e.to_string())),
        None => Ok((c.position, 0)),
    };
    CachedReferences::compute(
        &mut counted,
        path,
        fov_y,
        size,
        (scene, animation),
        &mut eye,
    )
}

/// What a method's frame source renders: the output, the grid, the camera's lens.
#[derive(Debug, Clone, Copy)]
pub struct SourceView {
    /// Output size.
    pub size: UVec2,
    /// Face resolution (texels per cube-face edge; the art-pixel size of naive and snap).
    pub face_res: u32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// The level's look.
    pub look: Look,
    /// The camera the source warms up at (the path's first).
    pub warm_up: Camera,
}

/// The frame source of `method` on `level` (already at `view.face_res`), as `run` uses it.
pub fn method_source<'a>(
    ctx: &'a GpuContext,
    level: &LoadedLevel,
    (scene, animation): (&SceneInput, &Animation),
    method: Method,
    view: &SourceView,
) -> Result<Box<dyn FrameSource + 'a>, EvalError> {
    Ok(match baseline_of(method) {
        Some(b) => {
            let mut source = BaselineSource::new(
                ctx,
                (scene, animation),
                b,
                view.size,
                view.face_res,
                view.look,
                &view.warm_up,
            )?;
            let palettes = texel_runtime::frame_plan::level_palettes(level);
            source.set_palette(palettes.first());
            source.set_bloom(texel_runtime::frame_plan::level_bloom(&level.scene));
            Box::new(source)
        }
        None => {
            let schedule = match method {
                Method::SplatPaper => Schedule::Paper,
                _ => Schedule::Ours,
            };
            let display = match method {
                Method::March => Display::March,
                _ => Display::Splat,
            };
            let facing = match method {
                Method::SplatFacing => texel_render::input::SpriteFacing::Camera,
                _ => texel_render::input::SpriteFacing::Probe,
            };
            Box::new(
                SplatSource::new(
                    ctx,
                    level,
                    view.size,
                    view.fov_y,
                    (schedule, display),
                    &view.warm_up,
                )?
                .with_sprite_facing(facing),
            )
        }
    })
}

/// Whether `method` is meaningful along `path`: the camera-centred cubemap has no
/// orthographic form, so it skips orthographic paths.
pub fn runs_on(method: Method, path: &CameraPath) -> bool {
    let ortho = matches!(path.projection, Some(Projection::Orthographic(_)));
    !(ortho && method == Method::Cubemap)
}

/// A reference source that reports each frame it makes.
struct CountingReference<'a> {
    inner: Box<dyn ReferenceSource + 'a>,
    tick: &'a mut dyn FnMut(()),
}

impl ReferenceSource for CountingReference<'_> {
    fn reference(
        &mut self,
        camera: &texel_render::input::Camera,
        size: UVec2,
        frame: &crate::runner::RefFrame<'_>,
    ) -> Result<crate::metrics::Reference, EvalError> {
        let r = self.inner.reference(camera, size, frame)?;
        (self.tick)(());
        Ok(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assets() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets")
    }

    #[test]
    fn every_suite_path_and_level_loads() {
        let plans = suite_plans(
            &assets(),
            &[SUITE_PATHS.as_slice(), CLASS_PATHS.as_slice()].concat(),
            &[Method::Splat],
            (&[32], UVec2::new(16, 9)),
        );
        assert_eq!(plans.len(), SUITE_PATHS.len() + CLASS_PATHS.len());
        for p in &plans {
            assert!(p.level.exists(), "{}", p.level.display());
            let path = load_path(&p.path).expect("path loads");
            assert!((20..=120).contains(&path.frames), "{}", p.path.display());
        }
        // Every class path the folder holds is in the set.
        let mut files: Vec<String> = std::fs::read_dir(assets().join("paths/classes"))
            .unwrap()
            .filter_map(|e| {
                let name = e.unwrap().file_name().into_string().unwrap();
                name.strip_suffix(".ron").map(|s| format!("classes/{s}"))
            })
            .collect();
        files.sort();
        let mut set: Vec<String> = CLASS_PATHS.iter().map(|(_, p)| p.to_string()).collect();
        set.sort();
        assert_eq!(files, set);
        // 12 paths × (1 method × 1 resolution + the reference) × their frames.
        let total = total_frames(&plans).expect("loads");
        assert!(total > 12 * 2 * 20, "{total}");
        // The sprites level compares both facings; the others run what was asked.
        for p in &plans {
            let sprites = p.level.ends_with("sprites.ron");
            assert_eq!(p.methods.contains(&Method::SplatFacing), sprites);
        }
    }

    #[test]
    fn the_cubemap_skips_orthographic_paths_and_raster_runs_once() {
        let ortho = load_path(&assets().join("paths/ortho_pan.ron")).expect("loads");
        let persp = load_path(&assets().join("paths/yaw.ron")).expect("loads");
        assert!(!runs_on(Method::Cubemap, &ortho) && runs_on(Method::Snap, &ortho));
        assert!(runs_on(Method::Cubemap, &persp));
        let plan = |level: &str, path: &str| RunPlan {
            level: assets().join(format!("levels/{level}.ron")),
            path: assets().join(format!("paths/{path}.ron")),
            methods: vec![Method::Raster, Method::Cubemap, Method::Splat],
            face_res: vec![32, 64],
            size: UVec2::new(16, 9),
            freeze: false,
            first_frames: None,
        };
        // yaw: reference + raster once + (cubemap, splat) × 2 = 6 passes over 30 frames.
        assert_eq!(
            total_frames(&[plan("stone_circle", "yaw")]).expect("loads"),
            6 * 30
        );
        // ortho_pan: reference + raster once + splat × 2 = 4 passes.
        assert_eq!(
            total_frames(&[plan("stone_circle", "ortho_pan")]).expect("loads"),
            4 * 30
        );
    }

    #[test]
    fn a_missing_path_is_an_error_naming_the_file() {
        let e = load_path(Path::new("/nonexistent/p.ron")).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/p.ron"), "{e}");
    }
}
