//! The three probes (eye, grid, previous), where their faces live, and the crossfade.
//!
//! **Probes.** The *eye* probe sits at the camera. The *grid* probe sits at the camera
//! position snapped to the grid ([`crate::grid`]). The *previous* probe holds the cell the
//! camera left while a crossfade runs. Probes live in three physical [`Slot`]s (six GPU
//! layers each): the eye in its own slot, the grid and previous probes in the two stable
//! slots. A crossing **moves roles, not data**: the old grid probe becomes the previous
//! probe in the slot it already occupies (no copy, no re-capture), and the new grid probe
//! takes the other stable slot.
//!
//! **Frame protocol.** [`ProbeSet::begin_frame`] (camera, snapped key, dt) handles cell
//! changes; the scheduler then plans captures; [`ProbeSet::advance_fade`] with the plan's
//! [`Readiness`] (which counts the plan's captures) moves the fade, and the frame is drawn
//! at the `fade_t` it leaves. [`ProbeSet::update`] does both for callers without a
//! scheduler.
//!
//! **Speed.** `fade_t` moves at `max(1 / fade_seconds, smoothed_speed / (fade_cells ·
//! cell_size))` per second, the speed being smoothed exponentially with time constant
//! `speed_tau` and `dt` capped at `max_dt` (the reference uses 0.5 s, one cell, 0.05 s and
//! 0.1 s): a fast camera's fade ends within `fade_cells` of a cell's travel. Two rules are ours:
//! - one frame moves `fade_t` by at most `1 / min_frames` (`min_frames >= 2`), and the
//!   frame a crossing starts does not move it, so a crossing takes at least `min_frames`
//!   frames after its trigger frame and no frame hands more than half of the pixels from
//!   one probe to the other;
//! - `fade_t` only moves toward a probe whose visible faces are all captured
//!   ([`Readiness`]), so the dither never reveals a face that is not there yet.
//!
//! **Crossings during a fade** never pop. The dither owner of a pixel is `grid` when its
//! Bayer threshold is below `fade_t`, else `previous` ([`crate::bayer`]):
//! - back into the previous cell: the fade **reverses** (runs toward `fade_t = 0`);
//!   reaching 0 ends it with the previous probe (in its slot) becoming the grid probe, at
//!   `fade_t = 1`: the same probe draws every pixel before and after. Returning to the
//!   grid cell turns it forward again.
//! - into a third cell while `fade_t == 0` (the grid probe draws nothing yet): the grid
//!   probe is **re-aimed** at the new cell in place.
//! - into a third cell otherwise: the fade **continues** in its direction; when it ends, the
//!   next frame starts an ordinary crossing to wherever the camera then is.
//!
//! So pixels only ever change owner through a moving `fade_t`, at most `1 / min_frames` of
//! them per frame, and only toward a probe that is ready.

use std::fmt;

use glam::Vec3;

use crate::bayer::{DitherOwner, owner_at_threshold};
use crate::grid::ProbeKey;

/// Tuning of the crossfade.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FadeConfig {
    /// Duration of a fade when the camera is slow, seconds (> 0).
    pub fade_seconds: f32,
    /// How much of a cell's travel a fade may take when the camera is fast (> 0): the
    /// reference's 1 ends a fade just as the next crossing may start; below 1 a fade ends
    /// before the camera is that far into the new cell, so fades do not run into each other.
    pub fade_cells: f32,
    /// Time constant of the camera-speed smoothing, seconds (> 0).
    pub speed_tau: f32,
    /// Largest frame time taken into account, seconds (> 0).
    pub max_dt: f32,
    /// Fewest frames a crossfade is spread over after its trigger frame (>= 2).
    pub min_frames: u32,
}

impl Default for FadeConfig {
    fn default() -> Self {
        FadeConfig {
            fade_seconds: 0.5,
            fade_cells: 1.0,
            speed_tau: 0.05,
            max_dt: 0.1,
            min_frames: 2,
        }
    }
}

impl FadeConfig {
    /// Checks every field, reporting the first bad one.
    pub fn validate(&self) -> Result<(), FadeConfigError> {
        let positive = |v: f32| v.is_finite() && v > 0.0;
        if !positive(self.fade_seconds) {
            return Err(FadeConfigError::FadeSeconds(self.fade_seconds));
        }
        if !positive(self.fade_cells) {
            return Err(FadeConfigError::FadeCells(self.fade_cells));
        }
        if !positive(self.speed_tau) {
            return Err(FadeConfigError::SpeedTau(self.speed_tau));
        }
        if !positive(self.max_dt) {
            return Err(FadeConfigError::MaxDt(self.max_dt));
        }
        if self.min_frames < 2 {
            return Err(FadeConfigError::MinFrames(self.min_frames));
        }
        Ok(())
    }

    /// The most `fade_t` may move in one frame: `1 / min_frames`.
    pub fn max_step(&self) -> f32 {
        1.0 / self.min_frames as f32
    }
}

/// A [`FadeConfig`] field that cannot be used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FadeConfigError {
    /// `fade_seconds` is not finite and positive.
    FadeSeconds(f32),
    /// `fade_cells` is not finite and positive.
    FadeCells(f32),
    /// `speed_tau` is not finite and positive.
    SpeedTau(f32),
    /// `max_dt` is not finite and positive.
    MaxDt(f32),
    /// `min_frames` is below 2.
    MinFrames(u32),
}

impl fmt::Display for FadeConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FadeConfigError::FadeSeconds(v) => write!(f, "fade_seconds {v} must be > 0"),
            FadeConfigError::FadeCells(v) => write!(f, "fade_cells {v} must be > 0"),
            FadeConfigError::SpeedTau(v) => write!(f, "speed_tau {v} must be > 0"),
            FadeConfigError::MaxDt(v) => write!(f, "max_dt {v} must be > 0"),
            FadeConfigError::MinFrames(v) => write!(f, "min_frames {v} must be >= 2"),
        }
    }
}

impl std::error::Error for FadeConfigError {}

/// The part a probe plays this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// At the camera; fills disocclusion; re-captured every frame.
    Eye,
    /// At the snapped camera position; the stable content.
    Grid,
    /// At the cell the camera left; drawn while a crossfade runs.
    Previous,
}

impl Role {
    /// All roles, in scheduling-report order.
    pub const ALL: [Role; 3] = [Role::Eye, Role::Grid, Role::Previous];
}

/// Physical storage of a probe: six GPU layers starting at [`Slot::layer_base`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Slot {
    /// Layers 0..6: the eye probe.
    Eye = 0,
    /// Layers 6..12: one of the two stable (grid / previous) probes.
    StableA = 1,
    /// Layers 12..18: the other stable probe.
    StableB = 2,
}

impl Slot {
    /// All slots in layer order.
    pub const ALL: [Slot; 3] = [Slot::Eye, Slot::StableA, Slot::StableB];

    /// Slot number, `0..3`.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// First GPU array layer of the slot (`6 · index`); face `f` is at `layer_base + f`.
    pub const fn layer_base(self) -> u32 {
        6 * self as u32
    }

    /// The other stable slot (the eye slot maps to itself).
    pub const fn other_stable(self) -> Slot {
        match self {
            Slot::Eye => Slot::Eye,
            Slot::StableA => Slot::StableB,
            Slot::StableB => Slot::StableA,
        }
    }
}

/// One probe as the renderer and scheduler see it this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    /// The part it plays.
    pub role: Role,
    /// Where its faces are stored.
    pub slot: Slot,
    /// Its origin (the eye probe: the camera position).
    pub origin: Vec3,
    /// Texels per face edge (the eye probe uses the grid probe's).
    pub face_resolution: u32,
}

/// Whether each stable probe has every face it needs (visible faces) captured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Readiness {
    /// The grid probe is ready.
    pub grid: bool,
    /// The previous probe is ready (or inactive).
    pub previous: bool,
    /// The grid probe draws some of its visible faces (the renderer keeps the previous
    /// probe's pixels where the grid's face is missing, so the fade may run short of its
    /// end).
    pub grid_partial: bool,
}

impl Readiness {
    /// Both probes ready.
    pub const ALL: Readiness = Readiness {
        grid: true,
        previous: true,
        grid_partial: true,
    };

    /// Readiness of whole probes only (no partial grid).
    pub const fn whole(grid: bool, previous: bool) -> Readiness {
        Readiness {
            grid,
            previous,
            grid_partial: grid,
        }
    }
}

/// Furthest a fade runs toward a grid probe that still misses visible faces: all but one
/// Bayer level (the previous probe keeps every pixel on the missing faces anyway, and the
/// fade ends only once the grid probe is whole).
pub const PARTIAL_FADE_LIMIT: f32 = 15.0 / 16.0;

/// Which way a running crossfade moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FadeDirection {
    /// `fade_t` rises: the grid probe takes over.
    TowardGrid,
    /// `fade_t` falls: the camera went back, the previous probe takes over again.
    TowardPrevious,
}

/// What [`ProbeSet::begin_frame`] did with the camera's cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransitionEvent {
    /// Nothing changed.
    Steady,
    /// The camera entered a new cell: the old grid probe became previous, a fade began.
    CrossingStarted,
    /// A running fade changed direction.
    Reversed,
    /// The invisible grid probe (at `fade_t == 0`) was re-aimed at a third cell.
    Retargeted,
    /// The camera is in a third cell; the running fade goes on and the crossing waits.
    Deferred,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Fade {
    previous: ProbeKey,
    previous_slot: Slot,
    t: f32,
    direction: FadeDirection,
    /// Set on the trigger frame: the first `advance_fade` leaves `t` alone.
    fresh: bool,
}

/// The probe set and its transition state.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeSet {
    config: FadeConfig,
    eye: Vec3,
    grid: ProbeKey,
    grid_slot: Slot,
    fade: Option<Fade>,
    smoothed_speed: f32,
    frame_dt: f32,
    advanced: bool,
}

impl ProbeSet {
    /// A set at rest: eye at `camera` (at the grid origin if `camera` is not finite), grid
    /// probe `grid` in [`Slot::StableA`], no fade.
    pub fn new(camera: Vec3, grid: ProbeKey, config: FadeConfig) -> Result<Self, FadeConfigError> {
        config.validate()?;
        Ok(ProbeSet {
            config,
            eye: if camera.is_finite() {
                camera
            } else {
                grid.origin()
            },
            grid,
            grid_slot: Slot::StableA,
            fade: None,
            smoothed_speed: 0.0,
            frame_dt: 0.0,
            advanced: true,
        })
    }

    /// Starts a frame: moves the eye to `camera`, updates the smoothed speed and applies
    /// the crossing rules to the snapped `key` (see the module doc).
    ///
    /// A negative or non-finite `dt` counts as 0; a non-finite `camera` keeps the eye
    /// where it was.
    pub fn begin_frame(&mut self, camera: Vec3, key: ProbeKey, dt: f32) -> TransitionEvent {
        self.track_camera(camera, dt);
        self.advanced = false;
        self.apply_cell(key)
    }

    /// Ends a frame's transition work: moves `fade_t` toward its target if that probe is
    /// ready. Returns whether the fade finished. Only the first call per frame acts.
    pub fn advance_fade(&mut self, ready: Readiness) -> bool {
        if std::mem::replace(&mut self.advanced, true) {
            return false;
        }
        let step = self.fade_step();
        let Some(mut fade) = self.fade else {
            return false;
        };
        if std::mem::take(&mut fade.fresh) {
            self.fade = Some(fade);
            return false;
        }
        match fade.direction {
            FadeDirection::TowardGrid => self.fade_forward(fade, step, ready),
            FadeDirection::TowardPrevious => self.fade_backward(fade, step, ready.previous),
        }
    }

    /// `begin_frame` then `advance_fade`, for callers without a scheduler.
    pub fn update(
        &mut self,
        camera: Vec3,
        key: ProbeKey,
        dt: f32,
        ready: Readiness,
    ) -> TransitionEvent {
        let event = self.begin_frame(camera, key, dt);
        self.advance_fade(ready);
        event
    }

    /// Crossfade amount in `[0, 1]`: the share of dither cells the grid probe draws.
    /// 1 when no fade runs.
    pub fn fade_t(&self) -> f32 {
        self.fade.map_or(1.0, |f| f.t)
    }

    /// Whether this frame starts (or turns) a fade: its first `advance_fade` leaves `fade_t`
    /// alone, so the probe faded away from still draws every pixel it drew.
    pub fn fade_starts(&self) -> bool {
        self.fade.is_some_and(|f| f.fresh)
    }

    /// Whether the previous probe exists (a fade is running).
    pub fn previous_active(&self) -> bool {
        self.fade.is_some()
    }

    /// Direction of the running fade, if any.
    pub fn fade_direction(&self) -> Option<FadeDirection> {
        self.fade.map(|f| f.direction)
    }

    /// The eye probe.
    pub fn eye(&self) -> Probe {
        Probe {
            role: Role::Eye,
            slot: Slot::Eye,
            origin: self.eye,
            face_resolution: self.grid.face_resolution,
        }
    }

    /// The grid probe.
    pub fn grid(&self) -> Probe {
        probe_of(Role::Grid, self.grid_slot, self.grid)
    }

    /// The probe a crossing into `key` would make the grid probe, while no fade runs and
    /// `key` is not the grid's: it would go to the free stable slot, so its faces can be
    /// captured there ahead of the crossing ([`crate::schedule::Scheduler::prefetch`]).
    pub fn next_probe(&self, key: ProbeKey) -> Option<Probe> {
        (self.fade.is_none() && key != self.grid)
            .then(|| probe_of(Role::Grid, self.grid_slot.other_stable(), key))
    }

    /// The previous probe, while a fade runs.
    pub fn previous(&self) -> Option<Probe> {
        self.fade
            .map(|f| probe_of(Role::Previous, f.previous_slot, f.previous))
    }

    /// The probe playing `role`, if any.
    pub fn probe(&self, role: Role) -> Option<Probe> {
        match role {
            Role::Eye => Some(self.eye()),
            Role::Grid => Some(self.grid()),
            Role::Previous => self.previous(),
        }
    }

    /// Key (cell and resolution) of the grid probe.
    pub fn grid_key(&self) -> ProbeKey {
        self.grid
    }

    /// Key of the previous probe, while a fade runs.
    pub fn previous_key(&self) -> Option<ProbeKey> {
        self.fade.map(|f| f.previous)
    }

    /// Share of the dither cells `role` draws: eye 1, grid `fade_t`, previous
    /// `1 - fade_t` (0 when inactive).
    pub fn drawn_share(&self, role: Role) -> f32 {
        match role {
            Role::Eye => 1.0,
            Role::Grid => self.fade_t(),
            Role::Previous => self.fade.map_or(0.0, |f| 1.0 - f.t),
        }
    }

    /// The stable probe that draws a pixel whose Bayer threshold is `threshold`.
    pub fn stable_owner(&self, threshold: f32) -> Probe {
        match (
            owner_at_threshold(threshold, self.fade_t()),
            self.previous(),
        ) {
            (DitherOwner::Previous, Some(previous)) => previous,
            _ => self.grid(),
        }
    }

    /// Smoothed camera speed, world units per second.
    pub fn smoothed_speed(&self) -> f32 {
        self.smoothed_speed
    }

    /// The crossfade tuning.
    pub fn config(&self) -> &FadeConfig {
        &self.config
    }

    fn track_camera(&mut self, camera: Vec3, dt: f32) {
        let dt = if dt.is_finite() && dt > 0.0 { dt } else { 0.0 };
        self.frame_dt = dt.min(self.config.max_dt);
        if !camera.is_finite() {
            return;
        }
        if dt > 0.0 {
            // True speed over the real dt; the smoothing weight uses the capped dt.
            let speed = camera.distance(self.eye) / dt;
            let alpha = 1.0 - (-self.frame_dt / self.config.speed_tau).exp();
            self.smoothed_speed += (speed - self.smoothed_speed) * alpha;
        }
        self.eye = camera;
    }

    fn apply_cell(&mut self, key: ProbeKey) -> TransitionEvent {
        let Some(fade) = self.fade.as_mut() else {
            if key == self.grid {
                return TransitionEvent::Steady;
            }
            self.start_crossing(key);
            return TransitionEvent::CrossingStarted;
        };
        if key == self.grid {
            return turn(fade, FadeDirection::TowardGrid);
        }
        if key == fade.previous {
            return turn(fade, FadeDirection::TowardPrevious);
        }
        if fade.t == 0.0 {
            // The grid probe owns no pixel: re-aiming it cannot be seen.
            fade.direction = FadeDirection::TowardGrid;
            fade.fresh = true;
            self.grid = key;
            return TransitionEvent::Retargeted;
        }
        TransitionEvent::Deferred
    }

    fn start_crossing(&mut self, key: ProbeKey) {
        self.fade = Some(Fade {
            previous: self.grid,
            previous_slot: self.grid_slot,
            t: 0.0,
            direction: FadeDirection::TowardGrid,
            fresh: true,
        });
        self.grid = key;
        self.grid_slot = self.grid_slot.other_stable();
    }

    fn fade_step(&self) -> f32 {
        let c = &self.config;
        let by_speed = self.smoothed_speed / (c.fade_cells * self.grid.cell.cell_size);
        let rate = (1.0 / c.fade_seconds).max(by_speed);
        (rate * self.frame_dt).min(c.max_step())
    }

    fn fade_forward(&mut self, mut fade: Fade, step: f32, ready: Readiness) -> bool {
        if ready.grid {
            fade.t = (fade.t + step).min(1.0);
        } else if ready.grid_partial && fade.t < PARTIAL_FADE_LIMIT {
            fade.t = (fade.t + step).min(PARTIAL_FADE_LIMIT);
        }
        if fade.t >= 1.0 {
            self.fade = None;
            return true;
        }
        self.fade = Some(fade);
        false
    }

    fn fade_backward(&mut self, mut fade: Fade, step: f32, ready: bool) -> bool {
        if ready {
            fade.t = (fade.t - step).max(0.0);
        }
        if fade.t <= 0.0 {
            // The previous probe draws every pixel: it becomes the grid probe in place.
            self.grid = fade.previous;
            self.grid_slot = fade.previous_slot;
            self.fade = None;
            return true;
        }
        self.fade = Some(fade);
        false
    }
}

fn probe_of(role: Role, slot: Slot, key: ProbeKey) -> Probe {
    Probe {
        role,
        slot,
        origin: key.origin(),
        face_resolution: key.face_resolution,
    }
}

fn turn(fade: &mut Fade, direction: FadeDirection) -> TransitionEvent {
    if fade.direction == direction {
        return TransitionEvent::Steady;
    }
    fade.direction = direction;
    TransitionEvent::Reversed
}

#[cfg(test)]
mod tests;
