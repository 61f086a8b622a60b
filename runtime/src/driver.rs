//! The frame driver: turns a loaded level and a camera into what the renderer consumes.
//!
//! Once, at load: the hecs world becomes a [`SceneInput`] (one object per entity with
//! geometry, its id the entity's position in the level + 1) and the level's probe-grid
//! settings. Per frame: the camera is snapped to the grid ([`resolve_grid`]), the probe set
//! advances its crossfade ([`ProbeSet`]), the scheduler picks which faces to capture
//! ([`Scheduler`]), and all of it becomes a [`FrameInput`].
//!
//! Two schedules share the probe logic. **Ours** captures what the scheduler plans: the eye
//! probe's visible faces every frame, a stable probe's faces only when they are missing (new
//! origin, newly visible), within a budget so a cell crossing is spread over frames. The
//! **paper** schedule, for comparison, re-captures and re-lights the grid probe's visible faces
//! every frame, all three probes on the crossing frame, and grid and previous on alternate
//! frames during a fade, as the reference does. Its faces are the reference's too: those
//! within 103° (98° for the eye) of the view direction ([`reference_faces`]), plus any our
//! frustum test keeps, so it never draws less than ours.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{UVec2, Vec3, Vec4};
use texel_probes::cube::{Face, FaceMask};
use texel_probes::grid::{
    GridChoice, GridDefaults, GridError, GridOverride, first_crossing, resolve_grid,
};
use texel_probes::ortho::OrthoFrame;
use texel_probes::placement::{Placements, near_faces};
use texel_probes::probe_set::{FadeConfig, FadeDirection, ProbeSet, Role, TransitionEvent};
use texel_probes::schedule::{FaceWork, ProbePlan, Scheduler, UpdatePlan};
use texel_probes::visibility::{
    CameraView, REFERENCE_EYE_FACE_DEG, REFERENCE_STABLE_FACE_DEG, TexelRect, face_box_rect,
    frustum, reference_faces,
};
use texel_render::input::{
    Camera, CaptureInput, FrameInput, Look, MAX_NEAR_FACES, MaterialInput, ObjectInput,
    PointLightInput, ProbeView, SceneInput, Schedule, SunInput, TerrainInput, internal_size,
    view_up,
};
use texel_render::shadow_region::{
    bounds_under, point_shadow_bounds, scene_floor, sun_shadow_bounds,
};
use texel_scene::primitives::primitive_mesh;
use texel_scene::terrain::Terrain;
use texel_scene::{
    DirectionalLight, Geometry, Material, PixelScale, PlayerStart, PointLight, Scene, Transform,
};

use crate::extract::{Viewport, face_resolution, grid_overrides};
use crate::load::LoadedLevel;
use crate::occluders::SceneRays;

/// Faces captured per frame at most in our schedule (eye faces count against it).
pub const FACE_BUDGET: u32 = 9;
/// Stable-probe faces captured per frame at most: a cell crossing adds at most this many
/// faces to a frame, and the new grid probe completes over the following frames.
pub const STABLE_FACES_PER_FRAME: u32 = 2;
/// Stable faces captured at most on the frame that crosses into a new cell (which also
/// captures the eye and draws the previous probe alone) and on the frames after it until
/// the fade begins; the rest follow.
pub const CROSSING_STABLE_FACES: u32 = 1;
/// Stable faces of the next cell's grid probe captured per quiet frame ahead of a crossing
/// (the prefetched probe fills behind the grid probe once whole: `FrameDriver::frame`; two
/// a frame made it whole sooner, but a frame capturing two stable faces beside the eye's
/// took up to 1.7× the median).
pub const PREFETCH_FACES_PER_FRAME: u32 = 1;
/// How far ahead, in seconds of the camera's current velocity, a crossing is predicted (and
/// the next cell's probe captured, then drawn behind the grid probe).
pub const PREFETCH_LOOKAHEAD_S: f32 = 0.5;
/// Time constant of the camera velocity estimate, seconds.
const VELOCITY_TAU_S: f32 = 0.15;
/// Far distance of face visibility and captures.
pub const CAPTURE_FAR: f32 = texel_render::passes::capture::CAPTURE_FAR;

/// Why a frame could not be planned.
#[derive(Debug, thiserror::Error)]
pub enum DriverError {
    /// The camera or the level's grid settings are unusable.
    #[error("probe grid: {0}")]
    Grid(#[from] GridError),
    /// The camera does not describe a view.
    #[error("camera: {0}")]
    View(String),
}

/// What the frame driver and the renderer need of a level, extracted from it once: the scene
/// to upload, the look, the probe-grid settings that do not depend on the viewport, and the
/// player start.
#[derive(Debug)]
pub struct PreparedLevel {
    /// Sky, ambient light, bands and haze.
    pub look: Look,
    pixel_scale: PixelScale,
    cell_size: f32,
    overrides: Vec<GridOverride>,
    start: Camera,
    /// The renderer's view of the scene, and ray queries against it for probe placement.
    rays: SceneRays,
    /// What drives each animated object.
    pub animation: Animation,
    /// The lowest point of the scene, where sun shadows end ([`scene_floor`]).
    floor: f32,
}

/// The level's animated objects and what drives them: poses as a function of time, the same
/// wherever a frame is drawn (play, `texel-run render`, the evaluator's methods and its
/// reference).
#[derive(Debug, Clone, Default)]
pub struct Animation {
    objects: Vec<Animated>,
    /// Sprites whose frames play or whose entity an animator moves.
    sprites: Vec<crate::level_sprites::SpriteClock>,
}

impl Animation {
    /// The animated objects of `scene` (extracted from `level` by [`scene_input`]).
    pub fn new(level: &LoadedLevel, scene: &SceneInput) -> Self {
        Animation {
            objects: animated_objects(level, scene),
            sprites: sprite_clocks(level, scene),
        }
    }

    /// Whether nothing moves or plays.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty() && self.sprites.is_empty()
    }

    /// The state of every sprite that moves or plays, at `t` seconds.
    pub fn sprite_states(&self, t: f64) -> Vec<texel_render::input::SpriteState> {
        self.sprites.iter().map(|s| s.state(t)).collect()
    }

    /// Every animated object's pose at `t` seconds.
    pub fn poses(&self, t: f64) -> Vec<texel_render::input::Pose> {
        (self.objects.iter())
            .map(|a| texel_render::input::Pose {
                object: a.object,
                transform: a.animator.pose_at(&a.base, t).matrix(),
            })
            .collect()
    }

    /// The time of the frame after one at `t`, `dt` seconds later: how every frame source
    /// advances, so they all pose frame `i` alike (a `dt` that is not a positive number does
    /// not advance; one above a second counts as a second).
    pub fn next_time(t: f64, dt: f32) -> f64 {
        if dt.is_finite() && dt > 0.0 {
            t + f64::from(dt.min(1.0))
        } else {
            t
        }
    }

    /// World bounds of the animated object `k` (in [`Animation::poses`] order) under
    /// `transform`.
    fn bounds(&self, k: usize, transform: glam::Mat4) -> (Vec3, Vec3) {
        let a = &self.objects[k];
        bounds_under(transform, a.local_min, a.local_max)
    }
}

/// An animated object: its animator and base transform, and its mesh's bounds.
#[derive(Debug, Clone)]
struct Animated {
    object: usize,
    animator: texel_scene::animator::Animator,
    base: Transform,
    local_min: Vec3,
    local_max: Vec3,
}

impl PreparedLevel {
    /// Extracts what frames of `level` need.
    pub fn new(level: &LoadedLevel) -> Self {
        let s = &level.scene.settings;
        let scene = scene_input(level);
        let animation = Animation::new(level, &scene);
        PreparedLevel {
            animation,
            floor: scene_floor(&scene),
            rays: SceneRays::new(scene),
            look: level_look(&level.scene),
            pixel_scale: s.pixel_scale,
            cell_size: s.cell_size,
            overrides: grid_overrides(&level.scene),
            start: start_camera(&level.scene),
        }
    }

    /// The renderer's view of the scene.
    pub fn scene(&self) -> &SceneInput {
        self.rays.scene()
    }

    /// The box `min..max` grown by where its contents may cast sun shadows (see
    /// [`shadow_extended`]), with the scene's lowest point found once, at load.
    pub fn shadow_region(&self, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
        sun_shadow_bounds(&self.scene().suns, self.floor, min, max)
    }

    /// The grid defaults on a viewport (the face resolution may follow its height).
    fn grid_defaults(&self, viewport: Viewport) -> GridDefaults {
        GridDefaults {
            cell_size: self.cell_size,
            face_resolution: face_resolution(self.pixel_scale, viewport),
        }
    }
}

/// The animated objects of `scene` (extracted from `level` by [`scene_input`]): entities with
/// geometry and an animator, matched to their objects by entity id.
fn animated_objects(level: &LoadedLevel, scene: &SceneInput) -> Vec<Animated> {
    let w = level.scene.world();
    let entities: Vec<hecs::Entity> = level.scene.entities().collect();
    scene
        .animated
        .iter()
        .filter_map(|&object| {
            let o = &scene.objects[object];
            let e = *entities.get(o.id.checked_sub(1)? as usize)?;
            let animator = w.get::<&texel_scene::animator::Animator>(e).ok()?;
            let base = w.get::<&Transform>(e).map(|t| *t).ok()?;
            let (local_min, local_max) = o.mesh.bounds()?;
            Some(Animated {
                object,
                animator: (*animator).clone(),
                base,
                local_min,
                local_max,
            })
        })
        .collect()
}

fn sprite_clocks(
    level: &LoadedLevel,
    scene: &SceneInput,
) -> Vec<crate::level_sprites::SpriteClock> {
    let w = level.scene.world();
    let entities: Vec<hecs::Entity> = level.scene.entities().collect();
    (scene.sprites.iter().enumerate())
        .filter_map(|(index, input)| {
            let e = *entities.get(input.id.checked_sub(1)? as usize)?;
            let sprite = w.get::<&texel_scene::sprite::Sprite>(e).ok()?;
            let base = w.get::<&Transform>(e).map(|t| *t).ok()?;
            let animator =
                (w.get::<&texel_scene::animator::Animator>(e).ok()).map(|a| (*a).clone());
            crate::level_sprites::SpriteClock::new(index, &sprite, input, base, animator)
        })
        .collect()
}

/// The level's look: sky, ambient light, bands and haze (what every method draws with).
pub fn level_look(scene: &Scene) -> Look {
    let s = &scene.settings;
    Look {
        sky: s.sky,
        ambient: s.ambient,
        bands: s.bands,
        haze: s.haze,
    }
}

/// Per-level, per-frame probe logic.
pub struct FrameDriver {
    level: Arc<PreparedLevel>,
    /// Where each cell's grid probe sits (cached per cell).
    placements: Placements,
    /// The big flat faces passing near each stable probe origin (`placement::near_faces`,
    /// found with the lattice's cell size when the probe is first drawn), cached per origin
    /// until the scene changes.
    near_faces: HashMap<[u32; 3], [Vec4; MAX_NEAR_FACES]>,
    fov_y: f32,
    defaults: GridDefaults,
    overrides: Vec<GridOverride>,
    probes: Option<ProbeSet>,
    scheduler: Scheduler,
    size: UVec2,
    start: Camera,
    frame_index: u64,
    fade_frame: u64,
    /// Camera position last frame and the smoothed velocity, for prefetching.
    last_position: Option<Vec3>,
    velocity: Vec3,
    /// Animation time, seconds: the sum of the frames' `dt` (so a replayed path poses
    /// every frame as it did).
    time: f64,
    /// Each animated object's transform last frame, for the faces its shadow left.
    last_poses: Vec<glam::Mat4>,
    /// Whether the animation time stands still (the editor outside Play).
    paused: bool,
    /// The frames of the last orthographic grid probes, by origin (newest last).
    ortho_frames: Vec<(Vec3, OrthoFrame)>,
    /// This frame's orthographic eye probe: origin and frame.
    ortho_eye: Option<(Vec3, OrthoFrame)>,
}

impl FrameDriver {
    /// A driver for `level` on an output of `size` pixels with a vertical field of view of
    /// `fov_y` radians.
    pub fn new(level: &LoadedLevel, size: UVec2, fov_y: f32) -> Result<Self, DriverError> {
        Self::prepared(Arc::new(PreparedLevel::new(level)), size, fov_y)
    }

    /// A driver for a level already extracted (drivers for several viewports share it).
    pub fn prepared(
        level: Arc<PreparedLevel>,
        size: UVec2,
        fov_y: f32,
    ) -> Result<Self, DriverError> {
        let viewport = Viewport {
            height: size.y,
            fov_y,
        };
        let defaults = level.grid_defaults(viewport);
        let overrides = level.overrides.clone();
        let mut start = level.start;
        start.fov_y = fov_y;
        Ok(FrameDriver {
            level,
            placements: Placements::new(),
            near_faces: HashMap::new(),
            fov_y,
            defaults,
            overrides,
            probes: None,
            scheduler: Scheduler::new(FACE_BUDGET, CAPTURE_FAR)
                .map_err(|e| DriverError::View(e.to_string()))?
                .with_stable_faces_per_frame(STABLE_FACES_PER_FRAME)
                .with_crossing_faces(CROSSING_STABLE_FACES),
            size,
            start,
            frame_index: 0,
            fade_frame: 0,
            last_position: None,
            velocity: Vec3::ZERO,
            time: 0.0,
            last_poses: Vec::new(),
            paused: false,
            ortho_frames: Vec::new(),
            ortho_eye: None,
        })
    }

    /// Takes `level` in place of the current one after an edit confined to the box
    /// `min..max` (world units, including where the edit's shadows may fall): the probes and
    /// their captures stay, only the captured faces that may see the box are marked stale
    /// (drawn until captured again, spread over frames by the usual budget), and only the
    /// probe placements of cells near it are recomputed. Returns the faces marked.
    pub fn replace_level(&mut self, level: Arc<PreparedLevel>, min: Vec3, max: Vec3) -> u32 {
        self.level = level;
        self.overrides = self.level.overrides.clone();
        self.placements.forget_near(min, max);
        self.near_faces.clear();
        self.scheduler.invalidate_region(min, max)
    }

    /// The scene to upload to the renderer.
    pub fn scene_input(&self) -> &SceneInput {
        self.level.scene()
    }

    /// The vertical field of view it plans for, radians.
    pub fn fov_y(&self) -> f32 {
        self.fov_y
    }

    /// The camera at the level's player start (or looking at the origin from +Z).
    pub fn start_camera(&self) -> Camera {
        self.start
    }

    /// Output size.
    pub fn size(&self) -> UVec2 {
        self.size
    }

    /// The grid probe a camera at `camera` draws from once any crossfade is over: its origin
    /// and face resolution (what sprites turn toward; the evaluator's reference turns them
    /// so).
    pub fn grid_probe(&mut self, camera: &Camera) -> Result<(Vec3, u32), DriverError> {
        let choice = match self.ortho_probes(camera) {
            Some(o) => self.ortho_choice(o.grid.0, o.grid.2)?,
            None => self.resolve(camera.position)?,
        };
        Ok((choice.origin(), choice.key.face_resolution))
    }

    /// The orthographic probes of `camera`, `None` for a perspective one.
    fn ortho_probes(&self, camera: &Camera) -> Option<OrthoProbes> {
        let aspect = self.size.x as f32 / self.size.y.max(1) as f32;
        (camera.ortho_height)
            .map(|h| ortho_probes(camera, h, self.defaults.face_resolution, aspect))
    }

    /// A grid choice for an orthographic probe at exactly `origin` (its cell's key, moved
    /// there), with faces of `n` texels. No placement: the probe stands where its lattice
    /// puts it, outside the scene.
    fn ortho_choice(&self, origin: Vec3, n: u32) -> Result<GridChoice, GridError> {
        let mut c = resolve_grid(origin, &self.defaults, &self.overrides)?;
        c.key.offset = origin - c.key.cell.origin();
        c.key.face_resolution = n;
        Ok(c)
    }

    /// The orthographic frame of the probe at `origin`, if one of the last frames' was there.
    fn ortho_frame(&self, origin: Vec3) -> Option<OrthoFrame> {
        (self.ortho_eye.iter().chain(&self.ortho_frames))
            .find(|(o, _)| *o == origin)
            .map(|(_, f)| *f)
    }

    /// Plans one frame for `camera`, `dt` seconds after the last.
    pub fn frame(
        &mut self,
        camera: Camera,
        dt: f32,
        schedule: Schedule,
    ) -> Result<FrameInput, DriverError> {
        let ortho = self.ortho_probes(&camera);
        self.scheduler.set_orthographic(ortho.is_some());
        let choice = match &ortho {
            Some(o) => {
                let c = self.ortho_choice(o.grid.0, o.grid.2)?;
                // Keep the frames of the stable probes that may still be drawn (grid,
                // previous), and this frame's eye's.
                if self.ortho_frame(c.origin()).is_none() {
                    self.ortho_frames.push((c.origin(), o.grid.1));
                }
                let excess = self.ortho_frames.len().saturating_sub(ORTHO_FRAMES_KEPT);
                self.ortho_frames.drain(..excess);
                self.ortho_eye = Some((o.eye.0, o.eye.1));
                c
            }
            None => self.resolve(camera.position)?,
        };
        let cell_size = choice.key.cell.cell_size;
        // An orthographic eye probe stands on its texel lattice in the camera's plane.
        let eye_at = ortho.map_or(camera.position, |o| o.eye.0);
        self.track_velocity(camera.position, dt);
        let event = match &mut self.probes {
            Some(p) => p.begin_frame(eye_at, choice.key, dt),
            None => {
                let set = ProbeSet::new(eye_at, choice.key, fade_config(schedule))
                    .map_err(|e| DriverError::View(e.to_string()))?;
                self.probes = Some(set);
                TransitionEvent::CrossingStarted
            }
        };
        let probes = self
            .probes
            .as_ref()
            .ok_or_else(|| DriverError::View("no probes".into()))?;
        let view = CameraView {
            position: camera.position,
            forward: camera.forward,
            up: camera.up(),
            fov_y: camera.fov_y,
            aspect: self.size.x as f32 / self.size.y.max(1) as f32,
            near: camera.near,
            far: camera.far.min(CAPTURE_FAR),
        };
        let frustum = frustum(&view).map_err(|e| DriverError::View(e.to_string()))?;
        let mut plan = self.scheduler.plan(&frustum, probes, 0);
        // An orthographic camera's probe holds still while it pans: nothing to prefetch;
        // nor while a fade runs (no stable slot is free).
        let mut next = None;
        if schedule == Schedule::Ours && camera.ortho_height.is_none() && plan.previous.is_none() {
            // The cell the camera enters next, if it does within the look-ahead.
            let ahead = camera.position + self.velocity * PREFETCH_LOOKAHEAD_S;
            next = first_crossing(camera.position, ahead, &self.defaults, &self.overrides)
                .and_then(|p| {
                    let rays = &self.level.rays;
                    let c = self
                        .placements
                        .resolve(p, &self.defaults, &self.overrides, rays);
                    c.ok()
                })
                .and_then(|c| probes.next_probe(c.key));
            if let Some(next) = &next {
                let faces = PREFETCH_FACES_PER_FRAME;
                self.scheduler.prefetch(&mut plan, &frustum, next, faces);
            }
        }
        if event == TransitionEvent::CrossingStarted {
            self.fade_frame = 0;
        }
        if schedule == Schedule::Paper && ortho.is_none() {
            widen_to_reference(&mut plan, camera.forward);
            plan.work = self.paper_work(&plan, event);
        }
        if let Some(o) = &ortho {
            // The eye probe fills what the grid's held direction misses, at its own size.
            let n = o.eye.2;
            plan.eye.probe.face_resolution = n;
            for w in plan.work.iter_mut().filter(|w| w.role == Role::Eye) {
                w.face_resolution = n;
            }
        }
        let captures: Vec<CaptureInput> = (plan.work.iter())
            .map(|w| CaptureInput {
                ortho: self.ortho_frame(w.origin),
                ..capture_of(w)
            })
            .collect();
        self.scheduler.commit(&plan);
        // The fade moves before the frame is drawn: this frame's captures are done by the
        // time it splats, so readiness already counts them (a crossing's trigger frame still
        // draws at 0: `advance_fade` leaves it alone there).
        let direction = probes.fade_direction();
        let finished = match &mut self.probes {
            Some(p) => p.advance_fade(plan.readiness()),
            None => false,
        };
        // The probe of the cell ahead, once every face it would show is captured, fills
        // behind the grid probe until the crossing: the camera, nearing the cell's edge, sees
        // past a near occluder what the grid probe cannot, and that probe, nearer, often
        // can; without it the eye probe fills there, its texels sliding with the camera.
        let filler =
            (next.as_ref()).and_then(|n| self.scheduler.ready(&frustum, n, plan.scene_generation));
        let (fade_t, keep_previous) = match (finished, direction) {
            // Ended toward the grid probe: it draws every pixel, the previous one none.
            (true, Some(FadeDirection::TowardGrid)) => (1.0, false),
            // Back in the previous cell: the previous probe draws every pixel; from the next
            // frame on it is the grid probe.
            (true, Some(FadeDirection::TowardPrevious)) => (0.0, true),
            _ => (self.probes.as_ref().map_or(1.0, ProbeSet::fade_t), true),
        };
        // The faces near this frame's stable probes (none under an orthographic camera,
        // whose quads are exact).
        if ortho.is_none() {
            let stable = [
                Some(&plan.grid),
                plan.previous.as_ref(),
                plan.prefetch.as_ref(),
                filler.as_ref(),
            ];
            for p in stable.into_iter().flatten() {
                let (origin, s) = (p.probe.origin, cell_size);
                let rays = &self.level.rays;
                self.near_faces.entry(near_key(origin)).or_insert_with(|| {
                    let mut out = [Vec4::ZERO; MAX_NEAR_FACES];
                    for (o, f) in out.iter_mut().zip(near_faces(origin, s, rays)) {
                        *o = f.normal.extend(-f.normal.dot(f.point));
                    }
                    out
                });
            }
        }
        let view = |p: &ProbePlan| self.probe_view(p, &captures, schedule);
        // An orthographic probe's texel is an art pixel of the level's face resolution.
        let n = match ortho {
            Some(_) => self.defaults.face_resolution,
            None => plan.grid.probe.face_resolution,
        };
        let internal = internal_size(self.size, n, camera.fov_y);
        // With a filler the frame is drawn as a crossing's first frame: the cell's probe owns
        // every pixel as the previous one (fade 0), the next probe's quads kept behind.
        let (grid, previous, fade_t, prefetch, grid_complete) = match &filler {
            Some(f) => {
                let home = ProbeView {
                    role: Role::Previous,
                    ..view(&plan.grid)
                };
                (view(f), Some(home), 0.0, None, true)
            }
            None => {
                let previous = plan.previous.as_ref().filter(|_| keep_previous).map(view);
                let prefetch = plan.prefetch.as_ref().map(|p| ProbeView {
                    draw: FaceMask::EMPTY,
                    ..view(p)
                });
                let complete = plan.readiness().grid;
                (view(&plan.grid), previous, fade_t, prefetch, complete)
            }
        };
        let mut input = FrameInput {
            camera: pixel_snapped(camera, internal),
            size: self.size,
            internal_size: internal,
            look: self.level.look,
            eye: view(&plan.eye),
            grid,
            previous,
            fade_t,
            filling_ahead: filler.is_some(),
            prefetch,
            captures,
            schedule,
            grid_complete,
            poses: Vec::new(),
            relight: Vec::new(),
            sprites: Vec::new(),
        };
        self.animate(&mut input, dt);
        self.frame_index += 1;
        self.fade_frame += 1;
        Ok(input)
    }

    /// Animation time of the next frame, seconds.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Sets the animation time of the next frame (seconds; a time that is not a finite,
    /// non-negative number is ignored).
    pub fn set_time(&mut self, t: f64) {
        if t.is_finite() && t >= 0.0 {
            self.time = t;
        }
    }

    /// Stops (or restarts) the animation clock: paused, every frame poses the animated
    /// objects at the same time.
    pub fn set_paused(&mut self, paused: bool) {
        self.paused = paused;
    }

    /// Takes over `other`'s animation clock (its time and whether it is paused): a driver
    /// planned afresh for a new viewport or level does not restart the animations.
    pub fn keep_clock(&mut self, other: &FrameDriver) {
        self.time = other.time;
        self.paused = other.paused;
    }

    /// Poses the animated objects at this frame's time (then advances it by `dt`), and lists
    /// the stable faces to light again where a moved object's shadow may have come or gone:
    /// those that may see its old or new bounds, pushed along each sun to the ground, or the
    /// reach of a point light the object is within.
    fn animate(&mut self, input: &mut FrameInput, dt: f32) {
        let animation = &self.level.animation;
        if animation.is_empty() {
            return;
        }
        let poses = animation.poses(self.time);
        input.sprites = animation.sprite_states(self.time);
        if !self.paused {
            self.time = Animation::next_time(self.time, dt);
        }
        let scene = self.level.scene();
        // Where each moved object's shadows may have come or gone: its old and new bounds
        // and their shadows, along each sun to the ground and away from each point light
        // whose reach it is in, out to that reach.
        let mut regions: Vec<(Vec3, Vec3)> = Vec::new();
        for (k, pose) in poses.iter().enumerate() {
            let now = pose.transform;
            let before = self.last_poses.get(k).copied().unwrap_or(now);
            if before == now && !self.last_poses.is_empty() {
                continue;
            }
            let (a, b) = (animation.bounds(k, before), animation.bounds(k, now));
            let (lo, hi) = (a.0.min(b.0), a.1.max(b.1));
            let (mut lo2, mut hi2) = self.level.shadow_region(lo, hi);
            for p in &scene.points {
                if let Some((plo, phi)) = point_shadow_bounds(p.position, p.radius, lo, hi) {
                    lo2 = lo2.min(plo);
                    hi2 = hi2.max(phi);
                }
            }
            regions.push((lo2, hi2));
        }
        self.last_poses = poses.iter().map(|p| p.transform).collect();
        input.poses = poses;
        // The texels of each stable face that may see a region: one rectangle per face.
        let stable = [
            Some(&input.grid),
            input.previous.as_ref(),
            input.prefetch.as_ref(),
        ];
        for p in stable.into_iter().flatten() {
            let n = p.face_resolution;
            for face in p.valid.iter() {
                let rect = (regions.iter())
                    .filter_map(|&r| face_box_rect(face, p.origin, r, n, 1))
                    .reduce(|a, b| TexelRect {
                        x0: a.x0.min(b.x0),
                        y0: a.y0.min(b.y0),
                        x1: a.x1.max(b.x1),
                        y1: a.y1.max(b.y1),
                    });
                if let Some(rect) = rect.filter(|r| r.area() > 0) {
                    let slot = p.slot;
                    (input.relight).push(texel_render::input::Relight { slot, face, rect });
                }
            }
        }
    }

    /// The grid probe of the cell at `position`, placed where it can see.
    fn resolve(&mut self, position: Vec3) -> Result<GridChoice, GridError> {
        (self.placements).resolve(position, &self.defaults, &self.overrides, &self.level.rays)
    }

    /// Updates the smoothed camera velocity (a jump of more than a few cells, e.g. a
    /// teleport, resets it).
    fn track_velocity(&mut self, position: Vec3, dt: f32) {
        if let Some(last) = self.last_position
            && dt > 0.0
            && dt.is_finite()
        {
            let v = (position - last) / dt;
            // A step of a cell or more in one frame (30 cells a second at 30 fps) is a jump,
            // not motion: it would leave a velocity that, decaying, still predicted
            // crossings (and called in the next cell's probe) long after the camera stopped.
            if v.is_finite() && (position - last).length() < self.defaults.cell_size {
                let alpha = 1.0 - (-dt / VELOCITY_TAU_S).exp();
                self.velocity += (v - self.velocity) * alpha;
            } else {
                self.velocity = Vec3::ZERO;
            }
        }
        self.last_position = position.is_finite().then_some(position);
    }

    /// The reference's schedule: eye and grid every frame; previous as well on the crossing
    /// frame; grid and previous alternating while a fade runs.
    fn paper_work(&self, plan: &UpdatePlan, event: TransitionEvent) -> Vec<FaceWork> {
        let mut out: Vec<FaceWork> = Vec::new();
        let mut add = |p: &ProbePlan, mask: FaceMask| {
            for face in mask.iter() {
                out.push(FaceWork {
                    role: p.probe.role,
                    slot: p.probe.slot,
                    face,
                    origin: p.probe.origin,
                    face_resolution: p.probe.face_resolution,
                });
            }
        };
        add(&plan.eye, plan.eye.visible);
        let crossing = event == TransitionEvent::CrossingStarted;
        let odd = self.fade_frame % 2 == 1;
        match &plan.previous {
            Some(prev) if crossing => {
                add(&plan.grid, plan.grid.visible);
                add(prev, prev.visible);
            }
            Some(prev) if odd => add(prev, prev.visible),
            _ => add(&plan.grid, plan.grid.visible),
        }
        // Faces our scheduler needs (newly visible ones) must be there too.
        for w in &plan.work {
            if !out.iter().any(|o| (o.slot, o.face) == (w.slot, w.face)) {
                out.push(*w);
            }
        }
        out
    }
}

/// Our crossfade at rest lasts a quarter second; the paper's schedule keeps the reference's
/// half second ([`FadeConfig::default`]). While a fade runs, each stable probe fills behind
/// the other's pixels (`shaders/splat.wgsl` `FadeFsOut`), so a short fade opens no holes; what
/// a fade costs is its screen-fixed dither sliding over the moving scene, which a shorter
/// fade shows for fewer frames (`texel-eval run --methods splat` on walk_cells: 0.5 s 0.0049,
/// 0.25 s 0.0046, 0.15 s 0.0040 mean shimmer, but worst frames grow below a quarter second).
pub const OUR_FADE_SECONDS: f32 = 0.25;

/// A fast camera's fade of ours is paced to end within half a cell of travel (the
/// reference's within one; the frames a fade waits for its grid's captures and the
/// per-frame cap below lengthen both). At the reference's pace a sprint's fades had reached
/// only 0.77–0.97 when the next crossing came (`texel-run render` on sprint_cells, stats.json
/// `fade_t`): each crossing waited, the camera left both stable probes' views behind, and
/// the eye probe filled 4.7% of the pixels; at ours each fade ends as the next begins.
/// Measured with `texel-eval run --methods splat --face-res 128 --size 320x180` on
/// stone_circle: sprint_cells 0.0134 -> 0.0107 mean shimmer (worst frame 0.084 -> 0.046,
/// eye pixels 4.7% -> 1.7%), walk_cells 0.0047 -> 0.0042; the other crossing paths within
/// ±0.0003 but textured_walk (0.0190 -> 0.0171).
pub const OUR_FADE_CELLS: f32 = 0.5;

/// No frame of our fades hands more than a third of the pixels from one probe to the other
/// (the reference's half): a fast fade then spreads a crossing's change over three frames
/// instead of two, which lowers the worst frame, and a sprint's fade still ends before the
/// next crossing. Measured as above: sprint_cells 0.0107 -> 0.0103 (worst frame 0.046 -> 0.029),
/// iso_orbit 0.0035 -> 0.0032, terrain_descent 0.0090 -> 0.0082, terrain_walk 0.0137 ->
/// 0.0131; the other crossing paths unchanged.
pub const OUR_MIN_FADE_FRAMES: u32 = 3;

fn fade_config(schedule: Schedule) -> FadeConfig {
    match schedule {
        Schedule::Ours => FadeConfig {
            fade_seconds: OUR_FADE_SECONDS,
            fade_cells: OUR_FADE_CELLS,
            min_frames: OUR_MIN_FADE_FRAMES,
            ..FadeConfig::default()
        },
        Schedule::Paper => FadeConfig::default(),
    }
}

/// The view-direction steps (yaw and pitch, degrees) at which an orthographic camera's grid
/// probe turns with it.
pub const ORTHO_TURN_STEP_DEG: f32 = 5.0;

/// Orthographic grid probes' frames remembered (a previous probe is an old grid probe).
const ORTHO_FRAMES_KEPT: usize = 4;

/// The probes of an orthographic camera (see [`texel_probes::ortho`]): one orthographic face
/// each, one texel per art pixel.
#[derive(Debug, Clone, Copy)]
struct OrthoProbes {
    /// The grid probe: the view direction held in `ORTHO_TURN_STEP_DEG` steps, its origin on
    /// a lattice of a quarter face in its plane, so it holds while the camera pans and turns
    /// a little.
    grid: (Vec3, OrthoFrame, u32),
    /// The eye probe: the exact view direction, its origin on the texel lattice nearest the
    /// camera, in the camera's plane: it sees what the camera sees.
    eye: (Vec3, OrthoFrame, u32),
}

/// An orthographic camera sees along parallel rays, so its probe is not a point but a plane
/// of texels whose rays all run along the view: from there every texel meets the scene where
/// the view rays through it do, nothing is hidden from the probe that the camera sees (when
/// the directions agree), and texels are one size at every depth. Its texel is one art pixel
/// of the level's size (the size the naive and snap methods draw: `level_face_resolution ·
/// tan(fov_y / 2)` art pixels per view height), and its origin lies on a lattice of whole
/// texels in its plane, so every probe looking the same way samples the same world lines: a
/// pan changes no texel. The grid probe sits `half` behind the camera's plane, as far as a
/// texel's distance was for the cube probe this replaces (and sprites turn toward it).
fn ortho_probes(
    camera: &Camera,
    ortho_height: f32,
    level_face_resolution: u32,
    aspect: f32,
) -> OrthoProbes {
    let art_pixels = (level_face_resolution as f32 * (camera.fov_y * 0.5).tan()).max(1.0);
    let texel = ortho_height / art_pixels;
    // The view's diagonal in texels, and faces that hold it: the eye's around the camera,
    // the grid's while the camera is up to an eighth of a face off its centre.
    let diagonal = art_pixels * (1.0 + aspect * aspect).sqrt();
    let max_n = *texel_scene::components::FACE_RESOLUTIONS.end();
    let pow2 = |t: f32| {
        (t.ceil().max(1.0) as u32)
            .next_power_of_two()
            .clamp(64, max_n)
    };
    let eye_n = pow2(diagonal + 4.0);
    let grid_n = pow2((0.5 * diagonal + 4.0) * 8.0 / 3.0);
    let snap = |v: f32, step: f32| (v / step).round() * step;
    let p = camera.position;
    // The grid's direction: the view rounded to ORTHO_TURN_STEP_DEG of yaw and pitch.
    let d = camera.forward.normalize();
    let turn = ORTHO_TURN_STEP_DEG.to_radians();
    let yaw = ((-d.x).atan2(-d.z) / turn).round() * turn;
    let pitch = (d.y.clamp(-1.0, 1.0).asin() / turn).round() * turn;
    let f = Vec3::new(
        -yaw.sin() * pitch.cos(),
        pitch.sin(),
        -yaw.cos() * pitch.cos(),
    );
    let grid = OrthoFrame::new(f, view_up(f), 0.5 * grid_n as f32 * texel);
    let step = 0.25 * grid_n as f32 * texel;
    let plane = |fr: &OrthoFrame, step: f32| {
        fr.right * snap(p.dot(fr.right), step) + fr.down * snap(p.dot(fr.down), step)
    };
    let grid_origin =
        plane(&grid, step) + grid.forward * (snap(p.dot(grid.forward), step) - step - grid.half);
    let eye = OrthoFrame::new(d, camera.up(), 0.5 * eye_n as f32 * texel);
    let eye_origin = plane(&eye, texel) + eye.forward * p.dot(eye.forward);
    OrthoProbes {
        grid: (grid_origin, grid, grid_n),
        eye: (eye_origin, eye, eye_n),
    }
}

/// An orthographic camera moved in its view plane to the nearest whole internal pixel: a pan
/// then moves every quad by whole pixels, so nothing is resampled (the probe's texels stand
/// still in the world). A perspective camera is returned as it is.
fn pixel_snapped(camera: Camera, internal: UVec2) -> Camera {
    let Some(h) = camera.ortho_height else {
        return camera;
    };
    let pixel = h / internal.y.max(1) as f32;
    let f = camera.forward.normalize();
    let r = f.cross(camera.up()).normalize();
    let u = r.cross(f);
    let p = camera.position;
    let snap = |v: f32| (v / pixel).round() * pixel;
    Camera {
        position: p + r * (snap(p.dot(r)) - p.dot(r)) + u * (snap(p.dot(u)) - p.dot(u)),
        ..camera
    }
}

/// Widens the plan's visible faces to the reference's face mask (the paper schedule).
fn widen_to_reference(plan: &mut UpdatePlan, forward: Vec3) {
    let eye = reference_faces(forward, REFERENCE_EYE_FACE_DEG);
    let stable = reference_faces(forward, REFERENCE_STABLE_FACE_DEG);
    plan.eye.visible = plan.eye.visible.union(eye);
    for p in [Some(&mut plan.grid), plan.previous.as_mut()]
        .into_iter()
        .flatten()
    {
        p.visible = p.visible.union(stable);
    }
}

fn capture_of(w: &texel_probes::schedule::FaceWork) -> CaptureInput {
    CaptureInput {
        slot: w.slot,
        face: w.face,
        origin: w.origin,
        face_resolution: w.face_resolution,
        ortho: None,
    }
}

impl FrameDriver {
    /// The renderer's view of a probe: what to draw, and which faces hold data for its
    /// origin (captured this frame, or earlier for the same origin and resolution).
    /// The paper schedule draws every visible face with data (as the reference does); ours
    /// what the scheduler planned.
    fn probe_view(
        &self,
        p: &ProbePlan,
        captures: &[CaptureInput],
        schedule: Schedule,
    ) -> ProbeView {
        let mut valid = FaceMask::EMPTY;
        for face in Face::ALL {
            let now = captures
                .iter()
                .any(|c| c.slot == p.probe.slot && c.face == face);
            let kept = p.probe.role != Role::Eye
                && self.scheduler.stamp(p.probe.slot, face).is_some_and(|s| {
                    s.origin == p.probe.origin && s.face_resolution == p.probe.face_resolution
                });
            if now || kept {
                valid.insert(face);
            }
        }
        ProbeView {
            role: p.probe.role,
            slot: p.probe.slot,
            origin: p.probe.origin,
            face_resolution: p.probe.face_resolution,
            draw: match (p.probe.role, schedule) {
                (Role::Eye, _) => p.visible,
                (_, Schedule::Paper) => p.visible.intersection(valid),
                _ => p.draw,
            },
            valid,
            ortho: self.ortho_frame(p.probe.origin),
            near_faces: match p.probe.role {
                Role::Eye => [Vec4::ZERO; MAX_NEAR_FACES],
                _ => (self.near_faces.get(&near_key(p.probe.origin)))
                    .copied()
                    .unwrap_or([Vec4::ZERO; MAX_NEAR_FACES]),
            },
        }
    }
}

/// The key of a stable probe's near faces: its origin.
fn near_key(origin: Vec3) -> [u32; 3] {
    origin.to_array().map(f32::to_bits)
}

/// The camera at the player start, or at (0, 1.6, 10) looking at the origin.
pub fn start_camera(scene: &Scene) -> Camera {
    let w = scene.world();
    for e in scene.entities() {
        if let Ok(start) = w.get::<&PlayerStart>(e) {
            let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
            let eye = t.translation + Vec3::Y * start.eye_height;
            return Camera::from_yaw_pitch(eye, start.yaw, start.pitch);
        }
    }
    Camera::looking(Vec3::new(0.0, 1.6, 10.0), -Vec3::Z)
}

/// The renderer's id of the entity at `index` in the level's order (0 is the sky): the rule
/// [`scene_input`] numbers objects by and [`entity_index`] inverts.
pub fn entity_id(index: usize) -> u32 {
    index as u32 + 1
}

/// The level index of the entity a renderer id names, `None` for the sky (0).
pub fn entity_index(id: u32) -> Option<usize> {
    id.checked_sub(1).map(|i| i as usize)
}

/// The renderer's view of the scene: one object per entity with geometry, lights.
pub fn scene_input(level: &LoadedLevel) -> SceneInput {
    let scene = &level.scene;
    let w = scene.world();
    let mut out = SceneInput::default();
    for (index, e) in scene.entities().enumerate() {
        let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
        if let Ok(g) = w.get::<&Geometry>(e) {
            let primitive = !matches!(&*g, Geometry::Mesh { .. });
            let mesh = match &*g {
                Geometry::Mesh { path } => level.assets.get(path).cloned(),
                other => primitive_mesh(other).map(Arc::new),
            };
            let m = w
                .get::<&Material>(e)
                .map(|m| (*m).clone())
                .unwrap_or_default();
            if let Some(mesh) = mesh {
                if w.get::<&texel_scene::animator::Animator>(e).is_ok() {
                    out.animated.push(out.objects.len());
                }
                out.objects.push(ObjectInput {
                    mesh,
                    transform: t.matrix(),
                    material: MaterialInput {
                        albedo: m.albedo,
                        emissive: m.emissive,
                        casts_shadows: m.casts_shadows,
                        outlined: m.outlined,
                        maps: level.assets.surface_maps(&m, primitive),
                        terrain: None,
                    },
                    id: entity_id(index),
                });
            }
        }
        if let Ok(terrain) = w.get::<&Terrain>(e)
            && let Some((input, mesh)) = terrain_input(&terrain, &t, &level.assets)
        {
            out.objects.push(ObjectInput {
                mesh,
                transform: glam::Mat4::from_translation(t.translation),
                material: MaterialInput {
                    albedo: Vec3::ONE,
                    emissive: Vec3::ZERO,
                    casts_shadows: terrain.casts_shadows,
                    outlined: terrain.outlined,
                    maps: Default::default(),
                    terrain: Some(out.terrains.len()),
                },
                id: entity_id(index),
            });
            out.terrains.push(input);
        }
        if let Ok(sprite) = w.get::<&texel_scene::sprite::Sprite>(e)
            && let Some(input) =
                crate::level_sprites::sprite_input(&sprite, &t, &level.assets, entity_id(index))
        {
            out.sprites.push(input);
        }
        if let Ok(sun) = w.get::<&DirectionalLight>(e) {
            out.suns.push(SunInput {
                direction: sun.direction,
                colour: sun.colour * sun.intensity,
            });
        }
        if let Ok(p) = w.get::<&PointLight>(e) {
            out.points.push(PointLightInput {
                position: t.translation,
                colour: p.colour * p.intensity,
                radius: p.radius,
            });
        }
    }
    out
}

/// A terrain's colouring and mesh, `None` when its heights are not loaded. Only the
/// transform's translation applies (terrains lie along the world axes).
pub fn terrain_input(
    terrain: &Terrain,
    t: &Transform,
    assets: &texel_scene::assets::AssetLibrary,
) -> Option<(TerrainInput, Arc<texel_scene::TriMesh>)> {
    let field = assets.heightfield(terrain)?;
    // Skirts deep enough to hide the cracks between levels: the largest height step between
    // neighbouring samples bounds what a coarser level can miss.
    let mesh = Arc::new(field.lod_mesh(terrain.size, skirt_depth(field)));
    let corner = t.translation - Vec3::new(0.5 * terrain.size.x, 0.0, 0.5 * terrain.size.y);
    let displacement = terrain.displacement.as_ref().and_then(|d| {
        let image = assets.texture(&d.path)?.clone();
        let texture = texel_render::input::TextureRef {
            image,
            sampler: Default::default(),
        };
        Some((texture, d.strength, d.tile_size))
    });
    Some((
        TerrainInput {
            corner,
            size: terrain.size,
            samples: glam::UVec2::new(field.width, field.depth),
            heights: Arc::new(field.heights.clone()),
            max_height: terrain.max_height,
            gradient: terrain.gradient.iter().map(|g| (g.at, g.colour)).collect(),
            displacement,
            paint: assets.paint(terrain).cloned(),
            pixel_density: terrain.pixel_density,
            band_distance: terrain.band_distance,
            band_transition: terrain.band_transition,
        },
        mesh,
    ))
}

/// How deep a terrain's chunk skirts hang: the steepest step between neighbouring samples,
/// times the widest stride a coarse level skips (bounded by the whole height range).
fn skirt_depth(field: &texel_scene::terrain::Heightfield) -> f32 {
    let mut step: f32 = 0.0;
    let (w, d) = (i64::from(field.width), i64::from(field.depth));
    for z in 0..d {
        for x in 0..w {
            let h = field.at(x, z);
            step = step
                .max((field.at(x + 1, z) - h).abs())
                .max((field.at(x, z + 1) - h).abs());
        }
    }
    let (lo, hi) = field
        .heights
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &h| (a.min(h), b.max(h)));
    (step * texel_scene::terrain::CHUNK_QUADS as f32 * 0.5)
        .min(hi - lo)
        .max(0.05)
}

/// The box `min..max` grown by where its contents may cast sun shadows: each corner pushed
/// along every sun's direction until it has dropped to the lowest point of the scene (at
/// most 200 units along the ray; [`sun_shadow_bounds`]).
pub fn shadow_extended(scene: &SceneInput, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    sun_shadow_bounds(&scene.suns, scene_floor(scene), min, max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_probes::probe_set::Slot;

    /// A frame driver at 320 × 180 on the bundled level `name`.
    fn driver_on(name: &str) -> FrameDriver {
        FrameDriver::new(&bundled_level(name), UVec2::new(320, 180), 1.2).expect("driver")
    }

    /// The bundled level `name` (`assets/levels/NAME.ron`), loaded.
    fn bundled_level(name: &str) -> LoadedLevel {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        crate::load::load_level(&root.join(format!("assets/levels/{name}.ron")))
            .expect("level loads")
    }

    /// The one-unit cell (stone_circle's grid) holding `p`: cells are centred on whole
    /// coordinates.
    fn cell_of(p: Vec3) -> glam::IVec3 {
        p.round().as_ivec3()
    }

    /// Frames of a walk through `path` (camera position per frame, looking down -z) on
    /// stone_circle: faces prefetched before the first crossing, and that crossing's frame
    /// (the first whose camera is in another cell) with the stable faces it still captured.
    fn first_crossing_of(path: impl Fn(f32) -> Vec3) -> (usize, (usize, usize)) {
        let mut driver = driver_on("stone_circle");
        let dt = 1.0 / 30.0;
        let mut prefetched = 0;
        for i in 0..60 {
            let camera = Camera::from_yaw_pitch(path(i as f32 * dt), 0.0, -5.0);
            let input = driver.frame(camera, dt, Schedule::Ours).expect("frame");
            if let Some(p) = input.prefetch {
                assert_eq!(p.draw, FaceMask::EMPTY, "a prefetched probe is not drawn");
                assert_ne!(p.slot, input.grid.slot);
                prefetched += input.captures.iter().filter(|c| c.slot == p.slot).count();
            }
            if cell_of(camera.position) != cell_of(path(0.0)) {
                let stable = input.captures.iter().filter(|c| c.slot != Slot::Eye);
                return (prefetched, (i, stable.count()));
            }
        }
        panic!("the walk crosses no cell");
    }

    /// Walking slowly toward a cell boundary, quiet frames capture the next cell's grid
    /// probe ahead of time, so the crossing frame captures no stable face.
    #[test]
    fn a_slow_walk_prefetches_the_next_cell_before_crossing_it() {
        // 1 unit/s toward -z; the cell boundary at z = 12.5 comes after 15 frames.
        let (prefetched, (frame, stable)) = first_crossing_of(|t| Vec3::new(0.0, 1.6, 13.0 - t));
        assert!(prefetched >= 2, "prefetched {prefetched} faces");
        assert_eq!(
            stable, 0,
            "the crossing at frame {frame} captured {stable} faces"
        );
    }

    /// A diagonal walk that crosses its cell's z boundary 0.1 s before its x boundary:
    /// the point the look-ahead reaches lies in the diagonal cell, but the camera enters
    /// the cell beside its own first. The prefetch goes to the cell it enters.
    #[test]
    fn a_diagonal_walk_prefetches_the_cell_it_enters_not_the_one_ahead() {
        // z reaches 12.5 at t = 0.4 s (x = 0.46), x reaches 0.5 at t = 0.5 s.
        let path = |t: f32| Vec3::new(0.30 + 0.4 * t, 1.6, 12.9 - t);
        let (prefetched, (frame, stable)) = first_crossing_of(path);
        assert!(prefetched >= 2, "prefetched {prefetched} faces");
        assert_eq!(
            stable, 0,
            "the crossing at frame {frame} captured {stable} faces"
        );
    }

    /// What a fast walk's frames draw through a crossing: the trigger frame leaves every
    /// pixel to the previous probe (fade 0), and the very next frame, its grid probe
    /// prefetched, already hands pixels over; the frame the fade reaches 1 draws the grid
    /// probe alone. (The fade used to move only after a frame was drawn, so each crossing held
    /// at 0 for two frames, both drawing both probes' quads, and ended a frame late.)
    #[test]
    fn a_crossing_hands_pixels_over_from_the_frame_after_its_trigger() {
        let mut driver = driver_on("stone_circle");
        let dt = 1.0 / 30.0;
        let mut drawn = Vec::new();
        let mut trigger = None;
        for i in 0..30 {
            // 6 units/s toward -z: a cell every five frames.
            let camera =
                Camera::from_yaw_pitch(Vec3::new(0.0, 1.6, 13.4 - 0.2 * i as f32), 0.0, -5.0);
            let input = driver.frame(camera, dt, Schedule::Ours).expect("frame");
            drawn.push((input.previous.is_some(), input.fade_t));
            if trigger.is_none() && camera.position.z < 12.5 {
                trigger = Some(i);
            }
        }
        let trigger = trigger.expect("the walk crosses a cell");
        assert_eq!(drawn[trigger].1, 0.0, "the trigger frame: {drawn:?}");
        let (previous, t) = drawn[trigger + 1];
        assert!(
            previous && t > 0.0 && t <= 0.5,
            "the frame after it: {drawn:?}"
        );
        let end = (trigger..drawn.len())
            .find(|&i| !drawn[i].0)
            .expect("the fade ends");
        assert_eq!(drawn[end].1, 1.0, "{drawn:?}");
        assert!(end - trigger <= 3, "frames with both probes: {drawn:?}");
    }

    /// Walking slowly toward a cell boundary, once the next cell's probe has every face the
    /// view needs captured, frames before the crossing draw it behind the grid probe: the
    /// grid probe as the previous one owning every pixel (fade 0), the next as the grid
    /// probe in its own slot, just as the crossing's first frame draws them; a camera at
    /// rest draws its grid probe alone.
    #[test]
    fn a_walk_draws_the_next_cells_probe_behind_the_grid_probe_before_the_crossing() {
        let mut driver = driver_on("stone_circle");
        let dt = 1.0 / 30.0;
        let still = Camera::from_yaw_pitch(Vec3::new(0.0, 1.6, 13.0), 0.0, -5.0);
        for i in 0..10 {
            let input = driver.frame(still, dt, Schedule::Ours).expect("frame");
            assert!(input.previous.is_none(), "frame {i} at rest");
        }
        let home = driver.frame(still, dt, Schedule::Ours).expect("frame").grid;
        let mut fillers = Vec::new();
        for i in 1..30 {
            // 1 unit/s toward -z: the boundary at z = 12.5 after 15 frames.
            let z = 13.0 - i as f32 * dt;
            let camera = Camera::from_yaw_pitch(Vec3::new(0.0, 1.6, z), 0.0, -5.0);
            let input = driver.frame(camera, dt, Schedule::Ours).expect("frame");
            let drawn = |v: &ProbeView| (v.role, v.origin, v.slot);
            if z >= 12.5 {
                assert_eq!(input.grid.origin.z < 13.0, input.previous.is_some());
                assert_eq!(input.filling_ahead, input.previous.is_some(), "frame {i}");
                assert_eq!(input.cell_probe().origin, home.origin, "frame {i}");
                if let Some(p) = &input.previous {
                    assert_eq!(drawn(p), (Role::Previous, home.origin, home.slot));
                    assert_eq!(
                        input.fade_t, 0.0,
                        "frame {i}: the grid probe owns every pixel"
                    );
                    assert_ne!(input.grid.slot, home.slot, "frame {i}");
                    assert_eq!(input.grid.origin, home.origin - Vec3::Z, "frame {i}");
                    fillers.push((drawn(&input.grid), drawn(p)));
                }
                continue;
            }
            // The crossing's first frame draws what the last frame before it drew.
            let previous = input.previous.expect("the crossing starts a fade");
            let last = *fillers.last().expect("frames with the next probe behind");
            assert_eq!((drawn(&input.grid), drawn(&previous)), last);
            assert_eq!(input.fade_t, 0.0);
            assert!(!input.filling_ahead, "a crossing is not ahead of itself");
            assert_eq!(input.cell_probe().origin, input.grid.origin);
            assert!(fillers.len() >= 2, "{fillers:?}");
            return;
        }
        panic!("the walk crosses no cell");
    }

    /// A camera that steps over a cell boundary and straight back: the fade turns toward the
    /// previous probe and ends there at once. That frame draws fade 0 with both probes (the
    /// previous one owns every pixel), and from the next the same probe, in the same slot,
    /// is the grid probe alone: no pixel changes owner.
    #[test]
    fn a_fade_that_ends_back_in_the_cell_it_left_keeps_the_previous_probe_drawing() {
        let mut driver = driver_on("stone_circle");
        let dt = 1.0 / 30.0;
        // The cell boundary at z = 12.5: two frames past it, then back.
        let zs = [13.0, 13.0, 13.0, 12.9, 12.8, 12.4, 12.8, 12.9, 13.0];
        let drawn: Vec<_> = (zs.iter())
            .map(|&z| {
                let camera = Camera::from_yaw_pitch(Vec3::new(0.0, 1.6, z), 0.0, -5.0);
                driver.frame(camera, dt, Schedule::Ours).expect("frame")
            })
            .collect();
        let home = drawn[0].grid;
        let crossing = &drawn[5];
        let previous = crossing
            .previous
            .expect("the step over the boundary starts a fade");
        assert_eq!((previous.origin, previous.slot), (home.origin, home.slot));
        assert_eq!(crossing.fade_t, 0.0);
        let back = &drawn[6];
        assert_eq!(back.fade_t, 0.0, "the frame the fade ends back home");
        let previous = back.previous.expect("the previous probe draws that frame");
        assert_eq!((previous.origin, previous.slot), (home.origin, home.slot));
        for (i, input) in drawn.iter().enumerate().skip(7) {
            assert!(input.previous.is_none(), "frame {i}: no fade runs");
            assert_eq!(input.fade_t, 1.0);
            let grid = (input.grid.origin, input.grid.slot);
            assert_eq!(grid, (home.origin, home.slot), "frame {i}");
        }
    }

    /// The animation clock: each frame poses the moving objects at the time the frames'
    /// `dt` add up to (the same poses `Animation` gives), a paused clock stands still, and
    /// the faces whose view a moved object's shadow may change are lit again, as rectangles.
    #[test]
    fn frames_pose_moving_objects_by_the_sum_of_their_dt() {
        let mut driver = driver_on("moving_parts");
        let animation = driver.level.animation.clone();
        assert_eq!(
            animation.poses(0.0).len(),
            5,
            "windmill blades, hub, door, platform"
        );
        let camera = Camera::from_yaw_pitch(Vec3::new(-1.2, 2.0, 5.2), 8.0, -6.0);
        let dt = 1.0 / 30.0;
        let mut t = 0.0;
        let mut relit = 0;
        for _ in 0..12 {
            let input = driver.frame(camera, dt, Schedule::Ours).expect("frame");
            assert_eq!(input.poses, animation.poses(t));
            relit += input.relight.len();
            for r in &input.relight {
                assert!(r.rect.area() > 0 && r.rect.x1 <= 64 * 64, "{r:?}");
            }
            t = Animation::next_time(t, dt);
        }
        assert!((driver.time() - 12.0 * f64::from(dt)).abs() < 1e-9);
        assert!(relit > 0, "moving shadows relight some faces");
        driver.set_paused(true);
        let a = driver.frame(camera, dt, Schedule::Ours).expect("frame");
        let b = driver.frame(camera, dt, Schedule::Ours).expect("frame");
        assert_eq!(a.poses, b.poses);
        assert!(
            b.relight.is_empty(),
            "nothing moved: nothing to light again"
        );
        driver.set_time(2.0);
        let c = driver.frame(camera, dt, Schedule::Ours).expect("frame");
        assert_eq!(c.poses, animation.poses(2.0));
        driver.set_time(f64::NAN);
        assert_eq!(driver.time(), 2.0);
    }

    /// The paper schedule does the reference's work: with the camera level, the eye and
    /// the grid probe each capture and draw five faces (all but the one behind), every
    /// frame, where ours captures only what its frustum test needs, once.
    #[test]
    fn the_paper_schedule_captures_the_reference_faces_every_frame() {
        let level = bundled_level("stone_circle");
        let camera = Camera::from_yaw_pitch(Vec3::new(0.2, 1.6, 13.0), 0.0, 0.0);
        let behind = Face::ALL
            .into_iter()
            .min_by(|a, b| {
                camera
                    .forward
                    .dot(a.axis())
                    .total_cmp(&camera.forward.dot(b.axis()))
            })
            .expect("six faces");
        let five: FaceMask = Face::ALL.into_iter().filter(|f| *f != behind).collect();
        let size = UVec2::new(320, 180);
        let mut paper = FrameDriver::new(&level, size, 1.0).expect("driver");
        let mut ours = FrameDriver::new(&level, size, 1.0).expect("driver");
        for frame in 0..3 {
            let input = paper
                .frame(camera, 1.0 / 60.0, Schedule::Paper)
                .expect("frame");
            assert_eq!(input.eye.draw, five, "frame {frame}");
            assert_eq!(input.grid.draw, five, "frame {frame}");
            let of = |slot| {
                let faces = input.captures.iter().filter(|c| c.slot == slot);
                faces.map(|c| c.face).collect::<FaceMask>()
            };
            assert_eq!(of(input.eye.slot), five, "frame {frame}");
            assert_eq!(of(input.grid.slot), five, "frame {frame}");
            let input = ours
                .frame(camera, 1.0 / 60.0, Schedule::Ours)
                .expect("frame");
            assert!(input.eye.draw.count() < 5 && input.grid.draw.count() < 5);
            let stable = input
                .captures
                .iter()
                .filter(|c| c.slot != Slot::Eye)
                .count();
            assert_eq!(stable == 0, frame > 1, "ours captures the grid probe once");
        }
    }

    /// An orthographic camera's probes are orthographic faces whose origins stand on a
    /// lattice of whole texels: panning moves the grid probe by whole texels (so it samples
    /// the same world lines), the grid's face holds the whole view, the eye's stands in the
    /// camera's plane, and a turn within half a step keeps the grid's direction.
    #[test]
    fn orthographic_probes_stand_on_a_texel_lattice_and_hold_the_view() {
        let level = bundled_level("stone_circle");
        let size = UVec2::new(320, 180);
        let mut driver = FrameDriver::new(&level, size, 1.2).expect("driver");
        let camera = |x: f32, yaw: f32| Camera {
            ortho_height: Some(12.0),
            ..Camera::from_yaw_pitch(Vec3::new(x, 9.0, 14.0), yaw, -35.0)
        };
        let mut grids = Vec::new();
        for k in 0..40 {
            let c = camera(-2.0 + 0.77 * k as f32, 1.0);
            let input = driver.frame(c, 1.0 / 30.0, Schedule::Ours).expect("frame");
            let (grid, eye) = (input.grid, input.eye);
            let (gf, ef) = (
                grid.ortho.expect("ortho grid"),
                eye.ortho.expect("ortho eye"),
            );
            assert_eq!(grid.draw.bits(), 1, "one face");
            // The eye looks exactly along the view, from the camera's plane.
            assert!((ef.forward - c.forward).length() < 1e-5);
            assert!((eye.origin - c.position).dot(c.forward).abs() < 1e-3);
            // The grid's direction is the view's rounded to 5°: here yaw 0.
            assert!((gf.forward - camera(0.0, 0.0).forward).length() < 1e-5);
            // The whole view (its corners, with the pixel snap's margin) lies on the face.
            let h = 12.0;
            let w = h * size.x as f32 / size.y as f32;
            let up = ef.down * -1.0;
            for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let corner = c.position + ef.right * (sx * 0.5 * w) + up * (sy * 0.5 * h);
                let (u, v, _) = gf.locate(grid.origin, corner);
                assert!(u.abs() < 1.0 && v.abs() < 1.0, "view corner at ({u}, {v})");
            }
            grids.push((grid.origin, gf, grid.face_resolution));
        }
        let (o0, f0, n) = grids[0];
        let texel = f0.texel(n);
        let moved = grids.iter().filter(|g| g.0 != o0).count();
        assert!(moved > 0, "a 30-unit pan moves the grid probe");
        for (o, f, _) in &grids {
            assert_eq!(*f, f0);
            let d = (*o - o0) / texel;
            for a in [d.dot(f0.right), d.dot(f0.down)] {
                assert!((a - a.round()).abs() < 2e-3, "{a} texels apart");
            }
        }
    }
}
