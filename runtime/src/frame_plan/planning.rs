//! Planning, once per frame: which grid probe the camera draws from, which probe faces are
//! captured (within a budget, the next cell's ahead of a crossing), how far the crossfade
//! has come, and what each probe draws; our schedule or the paper's.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{UVec2, Vec3, Vec4};
use texel_probes::cube::{Face, FaceMask};
use texel_probes::grid::{
    GridChoice, GridDefaults, GridError, GridOverride, ProbeKey, first_crossing,
};
use texel_probes::placement::{Placements, near_faces};
use texel_probes::probe_set::{FadeDirection, Probe, ProbeSet, Role, TransitionEvent};
use texel_probes::schedule::{FaceWork, ProbePlan, Scheduler, UpdatePlan};
use texel_probes::visibility::{
    CameraView, Frustum, REFERENCE_EYE_FACE_DEG, REFERENCE_STABLE_FACE_DEG, frustum,
    reference_faces,
};
use texel_render::input::{
    Camera, CaptureInput, FrameInput, MAX_NEAR_FACES, ProbeView, SceneInput, Schedule,
    internal_size,
};

use super::animation::Clock;
use super::extraction::PreparedLevel;
use super::fade::fade_config;
use super::ortho::{OrthoFrames, OrthoProbes, ortho_choice, ortho_probes, pixel_snapped};
use super::partial::{EditArea, EditedFaces};
use crate::extract::Viewport;
use crate::load::LoadedLevel;

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

/// Per-level, per-frame probe logic.
pub struct FrameDriver {
    pub(super) level: Arc<PreparedLevel>,
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
    /// The viewport height the pixel scale is measured on (the output's unless the caller
    /// keeps another: [`FrameDriver::prepared_for`]).
    face_height: u32,
    start: Camera,
    frame_index: u64,
    fade_frame: u64,
    /// Camera position last frame and the smoothed velocity, for prefetching.
    last_position: Option<Vec3>,
    velocity: Vec3,
    /// The animation clock: the time the next frame is posed at.
    clock: Clock,
    /// The frames of the last orthographic probes, by origin.
    ortho: OrthoFrames,
    /// The part of each stable face edits changed, lit alone when it is captured again.
    edited: EditedFaces,
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
        Self::prepared_for(level, size, size.y, fov_y)
    }

    /// [`prepared`](Self::prepared), with the level's pixel scale measured on a viewport
    /// `face_height` pixels tall instead of the output's height: the editor draws its moving
    /// frames smaller than its still ones from the same probes.
    pub fn prepared_for(
        level: Arc<PreparedLevel>,
        size: UVec2,
        face_height: u32,
        fov_y: f32,
    ) -> Result<Self, DriverError> {
        let viewport = Viewport {
            height: face_height,
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
            face_height,
            start,
            frame_index: 0,
            fade_frame: 0,
            last_position: None,
            velocity: Vec3::ZERO,
            clock: Clock::default(),
            ortho: OrthoFrames::default(),
            edited: EditedFaces::default(),
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
        // A face an entity's edit changed in part may have changed anywhere now.
        self.edited.forget();
        self.scheduler.invalidate_region(min, max)
    }

    /// The prepared level, to edit in place (copied first if another driver shares it);
    /// then say where it changed ([`FrameDriver::level_edited`]).
    pub fn level_mut(&mut self) -> &mut PreparedLevel {
        Arc::make_mut(&mut self.level)
    }

    /// The prepared level it plans for.
    pub fn level(&self) -> &Arc<PreparedLevel> {
        &self.level
    }

    /// After an edit of the level in place ([`FrameDriver::level_mut`]) confined to `area`
    /// (`None`: nothing drawn changed, a name, a player start): the grid overrides and the
    /// player start read again and, as [`FrameDriver::replace_level`] does after taking a
    /// new level, the faces that may see its region marked stale and the placements near it
    /// found again; each marked face, once captured again, is captured and lit only where
    /// the changed geometry projects onto it, and lit elsewhere only where the area's filter
    /// says its light may have changed ([`FrameInput::partial`]). Returns the faces marked.
    pub fn level_edited(&mut self, area: Option<EditArea>) -> u32 {
        self.overrides = self.level.overrides.clone();
        self.start = Camera {
            fov_y: self.fov_y,
            ..self.level.start
        };
        let Some(area) = area else {
            return 0;
        };
        let (min, max) = area.region;
        self.placements.forget_near(min, max);
        self.near_faces.clear();
        let marked = self.scheduler.invalidate_region_faces(min, max);
        self.edited.mark(&marked, &area);
        marked.len() as u32
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

    /// The viewport height the level's pixel scale is measured on (see
    /// [`prepared_for`](Self::prepared_for)).
    pub fn face_height(&self) -> u32 {
        self.face_height
    }

    /// Takes a new output `size`, with the pixel scale measured on `face_height`, keeping
    /// every probe and its captures, when that gives the grid and face resolution planned
    /// for (always on a level of fixed face resolution); returns false, changing nothing,
    /// when it does not, and the driver must be planned afresh.
    pub fn resize(&mut self, size: UVec2, face_height: u32) -> bool {
        let viewport = Viewport {
            height: face_height,
            fov_y: self.fov_y,
        };
        if self.level.grid_defaults(viewport) != self.defaults {
            return false;
        }
        self.size = size;
        self.face_height = face_height;
        true
    }

    /// The grid probe a camera at `camera` draws from once any crossfade is over: its origin
    /// and face resolution (what sprites turn toward; the evaluator's reference turns them
    /// so).
    pub fn grid_probe(&mut self, camera: &Camera) -> Result<(Vec3, u32), DriverError> {
        let choice = match self.ortho_probes(camera) {
            Some(o) => ortho_choice(o.grid.0, o.grid.2, &self.defaults, &self.overrides)?,
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

    /// Animation time of the next frame, seconds.
    pub fn time(&self) -> f64 {
        self.clock.time
    }

    /// Sets the animation time of the next frame (seconds; a time that is not a finite,
    /// non-negative number is ignored).
    pub fn set_time(&mut self, t: f64) {
        if t.is_finite() && t >= 0.0 {
            self.clock.time = t;
        }
    }

    /// Stops (or restarts) the animation clock: paused, every frame poses the animated
    /// objects at the same time.
    pub fn set_paused(&mut self, paused: bool) {
        self.clock.paused = paused;
    }

    /// Takes over `other`'s animation clock (its time and whether it is paused): a driver
    /// planned afresh for a new viewport or level does not restart the animations.
    pub fn keep_clock(&mut self, other: &FrameDriver) {
        self.clock.time = other.clock.time;
        self.clock.paused = other.clock.paused;
    }

    /// Plans one frame for `camera`, `dt` seconds after the last: the grid probe the camera
    /// draws from, the faces to capture (and the next cell's to prefetch), the crossfade's
    /// step, and each probe's view.
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
                let c = ortho_choice(o.grid.0, o.grid.2, &self.defaults, &self.overrides)?;
                self.ortho.remember(c.origin(), o);
                c
            }
            None => self.resolve(camera.position)?,
        };
        let cell_size = choice.key.cell.cell_size;
        // An orthographic eye probe stands on its texel lattice in the camera's plane.
        let eye_at = ortho.map_or(camera.position, |o| o.eye.0);
        self.track_velocity(camera.position, dt);
        let event = self.begin_probe_frame(eye_at, choice.key, dt, schedule)?;
        let probes = self
            .probes
            .as_ref()
            .ok_or_else(|| DriverError::View("no probes".into()))?;
        let frustum = self.camera_frustum(&camera)?;
        let mut plan = self.scheduler.plan(&frustum, probes, 0);
        // An orthographic camera's probe holds still while it pans: nothing to prefetch;
        // nor while a fade runs (no stable slot is free).
        let mut next = None;
        if schedule == Schedule::Ours && camera.ortho_height.is_none() && plan.previous.is_none() {
            next = self.prefetch_next_cell(camera.position, &frustum, &mut plan);
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
                ortho: self.ortho.at(w.origin),
                ..capture_of(w)
            })
            .collect();
        self.scheduler.commit(&plan);
        let fade = self.advance_fade(&plan);
        // The probe of the cell ahead, once every face it would show is captured, fills
        // behind the grid probe until the crossing: the camera, nearing the cell's edge, sees
        // past a near occluder what the grid probe cannot, and that probe, nearer, often
        // can; without it the eye probe fills there, its texels sliding with the camera.
        let filler =
            (next.as_ref()).and_then(|n| self.scheduler.ready(&frustum, n, plan.scene_generation));
        // The faces near this frame's stable probes (none under an orthographic camera,
        // whose quads are exact).
        if ortho.is_none() {
            self.find_near_faces(&plan, filler.as_ref(), cell_size);
        }
        let mut input = self.frame_input(camera, &plan, captures, filler, fade, schedule);
        // The eye draws only what lies near it every frame; beyond, faces captured every
        // half cell (`texel_render::far_field`).
        input.far_field = (schedule == Schedule::Ours && ortho.is_none())
            .then_some(texel_render::far_field::FarFieldInput { cell: cell_size });
        match schedule {
            Schedule::Ours => input.partial = self.edited.take(&input.captures, &input),
            _ => self.edited.forget(),
        }
        let level = &self.level;
        (self.clock).animate(&level.animation, level.scene(), level.floor, &mut input, dt);
        self.frame_index += 1;
        self.fade_frame += 1;
        Ok(input)
    }

    /// Moves the probe set to this frame's eye position and grid probe (the first frame
    /// creates it, which counts as a crossing): what the move started or ended.
    fn begin_probe_frame(
        &mut self,
        eye_at: Vec3,
        key: ProbeKey,
        dt: f32,
        schedule: Schedule,
    ) -> Result<TransitionEvent, DriverError> {
        Ok(match &mut self.probes {
            Some(p) => p.begin_frame(eye_at, key, dt),
            None => {
                let set = ProbeSet::new(eye_at, key, fade_config(schedule))
                    .map_err(|e| DriverError::View(e.to_string()))?;
                self.probes = Some(set);
                TransitionEvent::CrossingStarted
            }
        })
    }

    /// The camera's view frustum, out to the capture distance at most.
    fn camera_frustum(&self, camera: &Camera) -> Result<Frustum, DriverError> {
        let view = CameraView {
            position: camera.position,
            forward: camera.forward,
            up: camera.up(),
            fov_y: camera.fov_y,
            aspect: self.size.x as f32 / self.size.y.max(1) as f32,
            near: camera.near,
            far: camera.far.min(CAPTURE_FAR),
        };
        frustum(&view).map_err(|e| DriverError::View(e.to_string()))
    }

    /// The probe of the cell a camera at `position` enters next, if it does within the
    /// look-ahead at its current velocity, with the faces of it to capture this frame added
    /// to `plan` (so the probe is whole, or nearly, by the crossing).
    fn prefetch_next_cell(
        &mut self,
        position: Vec3,
        frustum: &Frustum,
        plan: &mut UpdatePlan,
    ) -> Option<Probe> {
        let probes = self.probes.as_ref()?;
        // The cell the camera enters next, if it does within the look-ahead.
        let ahead = position + self.velocity * PREFETCH_LOOKAHEAD_S;
        let next = first_crossing(position, ahead, &self.defaults, &self.overrides)
            .and_then(|p| {
                let rays = &self.level.rays;
                let c = self
                    .placements
                    .resolve(p, &self.defaults, &self.overrides, rays);
                c.ok()
            })
            .and_then(|c| probes.next_probe(c.key))?;
        let faces = PREFETCH_FACES_PER_FRAME;
        self.scheduler.prefetch(plan, frustum, &next, faces);
        Some(next)
    }

    /// Steps the crossfade and returns where it stands for this frame: its `t` and whether
    /// the previous probe still draws. The fade moves before the frame is drawn: this
    /// frame's captures are done by the time it splats, so readiness already counts them (a
    /// crossing's trigger frame still draws at 0: `advance_fade` leaves it alone there).
    fn advance_fade(&mut self, plan: &UpdatePlan) -> (f32, bool) {
        let direction = self.probes.as_ref().and_then(ProbeSet::fade_direction);
        let finished = match &mut self.probes {
            Some(p) => p.advance_fade(plan.readiness()),
            None => false,
        };
        match (finished, direction) {
            // Ended toward the grid probe: it draws every pixel, the previous one none.
            (true, Some(FadeDirection::TowardGrid)) => (1.0, false),
            // Back in the previous cell: the previous probe draws every pixel; from the next
            // frame on it is the grid probe.
            (true, Some(FadeDirection::TowardPrevious)) => (0.0, true),
            _ => (self.probes.as_ref().map_or(1.0, ProbeSet::fade_t), true),
        }
    }

    /// Finds the big flat faces near each of this frame's stable probes (the plan's grid,
    /// previous and prefetched probes and the `filler`) not already known, for lattices of
    /// `cell_size`.
    fn find_near_faces(&mut self, plan: &UpdatePlan, filler: Option<&ProbePlan>, cell_size: f32) {
        let stable = [
            Some(&plan.grid),
            plan.previous.as_ref(),
            plan.prefetch.as_ref(),
            filler,
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

    /// The renderer's input for the frame `plan` planned for `camera`: each probe's view,
    /// the crossfade at `fade` (its `t`, and whether the previous probe still draws), the
    /// internal size and the camera snapped to its pixels. Poses are added by `animate`.
    fn frame_input(
        &self,
        camera: Camera,
        plan: &UpdatePlan,
        captures: Vec<CaptureInput>,
        filler: Option<ProbePlan>,
        (fade_t, keep_previous): (f32, bool),
        schedule: Schedule,
    ) -> FrameInput {
        let view = |p: &ProbePlan| self.probe_view(p, &captures, schedule);
        // An orthographic probe's texel is an art pixel of the level's face resolution.
        let n = match camera.ortho_height {
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
        FrameInput {
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
            partial: Vec::new(),
            sprites: Vec::new(),
            far_field: None,
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
            ortho: self.ortho.at(p.probe.origin),
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
