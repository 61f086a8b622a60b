//! Per-frame update plans: which faces of which probe to capture and shade.
//!
//! The scheduler remembers, per slot and face, what the face was last captured for: a
//! [`CaptureStamp`] (origin, face resolution, scene generation). A face is **valid** when
//! its stamp matches the probe now in the slot and the caller's current scene generation;
//! it is **drawable** when it was captured at the probe's current origin and resolution
//! (any generation: after a scene edit the old image is still in the right place and is
//! drawn until its re-capture comes up). Faces captured at another origin are never drawn:
//! a quad splatted from the wrong origin would pop.
//!
//! Rules of [`Scheduler::plan`]:
//! - **Eye**: every visible face, every frame (the eye moves with the camera).
//! - **Grid / previous**: only visible faces that are not valid: origin changed, scene
//!   changed, or visible for the first time. Invisible faces are never captured.
//! - **Budget**: at most `max_faces` captures per frame, eye first. The stable probes share
//!   the rest: missing faces (holes) of both before stale faces of either; between the two
//!   probes, the one drawing more pixels first (grid on ties); within a probe, faces closer
//!   to the view direction first. So on a cell crossing the new grid probe's faces spread
//!   over frames, while the previous probe (same slot, same stamps: nothing to do) keeps
//!   drawing; the fade waits for the grid via [`UpdatePlan::readiness`], and a scene that
//!   changes every frame cannot stall it. The crossing frame itself (a new grid origin with
//!   nothing captured yet, the previous probe drawing) may take a lower cap
//!   ([`Scheduler::with_crossing_faces`]): it is the frame that also pays for everything else;
//!   with that cap set, a fade's first frame toward a grid probe that draws some face already
//!   (prefetched) captures no stable face (the previous probe owns every pixel then).
//!
//! - **Prefetch** ([`Scheduler::prefetch`]): on a frame with no stable work, a few faces of
//!   the grid probe of the cell the camera is heading into, in the free stable slot, so the
//!   crossing itself captures (almost) nothing.
//!
//! Frame order: `ProbeSet::begin_frame` → [`Scheduler::plan`] (→ [`Scheduler::prefetch`]) →
//! [`Scheduler::commit`] → `ProbeSet::advance_fade(plan.readiness())` → capture the plan's
//! faces, then splat at the `fade_t` that left (readiness counts this frame's captures).

use std::fmt;

use glam::Vec3;

use crate::cube::{Face, FaceMask};
use crate::probe_set::{Probe, ProbeSet, Readiness, Role, Slot};
use crate::visibility::{Frustum, face_box_rect, splat_extent, visible_faces};

/// Smallest accepted budget: six eye faces plus one stable face, so stable probes always
/// make progress.
pub const MIN_FACE_BUDGET: u32 = 7;

/// Whether the cube face `face` of a probe at `origin` (capturing up to `far`, Chebyshev)
/// may see any point of the box `min..max`: false when every corner lies beyond one of the
/// face pyramid's planes (behind the face, past one of its four sides, or farther than
/// `far`), or when the box clipped to the pyramid is empty (a box beside the probe, past
/// the face's plane on one side and outside its corner on another: [`face_box_rect`]).
pub fn face_may_see_box(face: Face, origin: Vec3, min: Vec3, max: Vec3, far: f32) -> bool {
    planes_may_see_box(face, origin, min, max, far)
        && face_box_rect(face, origin, (min, max), 1, 0).is_some()
}

/// [`face_may_see_box`]'s first test: no plane of the face's pyramid has every corner
/// beyond it.
fn planes_may_see_box(face: Face, origin: Vec3, min: Vec3, max: Vec3, far: f32) -> bool {
    let (a, u, v) = (face.axis(), face.u_axis(), face.v_axis());
    let corners: [Vec3; 8] = std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        ) - origin
    });
    let all = |f: &dyn Fn(Vec3) -> bool| corners.iter().all(|&c| f(c));
    !(all(&|c| c.dot(a) <= 0.0)
        || all(&|c| c.dot(u) > c.dot(a))
        || all(&|c| c.dot(u) < -c.dot(a))
        || all(&|c| c.dot(v) > c.dot(a))
        || all(&|c| c.dot(v) < -c.dot(a))
        || all(&|c| c.dot(a) > far))
}

/// What a face's data was captured for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaptureStamp {
    /// Probe origin at capture.
    pub origin: Vec3,
    /// Face resolution at capture.
    pub face_resolution: u32,
    /// Scene generation at capture.
    pub scene_generation: u64,
}

/// One face to capture and shade this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceWork {
    /// Role of the probe.
    pub role: Role,
    /// Slot to write (layer `slot.layer_base() + face.index()`).
    pub slot: Slot,
    /// The face.
    pub face: Face,
    /// Probe origin to render from.
    pub origin: Vec3,
    /// Texels per face edge.
    pub face_resolution: u32,
}

/// The plan for one probe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbePlan {
    /// The probe.
    pub probe: Probe,
    /// Faces that may contribute to the view.
    pub visible: FaceMask,
    /// Faces captured and shaded this frame.
    pub capture: FaceMask,
    /// Visible faces that hold data for this origin after the plan: splat these.
    pub draw: FaceMask,
    /// Visible faces still not drawable after the plan (waiting for budget).
    pub missing: FaceMask,
    /// Visible faces with data from an older scene generation, not re-captured yet.
    pub stale: FaceMask,
}

/// Work counts of a plan, for the evaluator's counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanCounts {
    /// Eye faces captured.
    pub eye: u32,
    /// Grid faces captured.
    pub grid: u32,
    /// Previous faces captured.
    pub previous: u32,
    /// Visible stable faces left waiting (missing or stale) for lack of budget.
    pub deferred: u32,
}

impl PlanCounts {
    /// Faces captured in total.
    pub fn total(&self) -> u32 {
        self.eye + self.grid + self.previous
    }
}

/// Everything to capture this frame and what may be drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct UpdatePlan {
    /// Scene generation the captures are for.
    pub scene_generation: u64,
    /// The eye probe.
    pub eye: ProbePlan,
    /// The grid probe.
    pub grid: ProbePlan,
    /// The previous probe, while a fade runs.
    pub previous: Option<ProbePlan>,
    /// The next grid probe whose faces are captured ahead of a predicted crossing
    /// ([`Scheduler::prefetch`]); drawn by nobody yet.
    pub prefetch: Option<ProbePlan>,
    /// Captures in execution order (eye first).
    pub work: Vec<FaceWork>,
    /// Per-role counts.
    pub counts: PlanCounts,
}

impl UpdatePlan {
    /// The plan of `role`, if that probe exists.
    pub fn probe(&self, role: Role) -> Option<&ProbePlan> {
        match role {
            Role::Eye => Some(&self.eye),
            Role::Grid => Some(&self.grid),
            Role::Previous => self.previous.as_ref(),
        }
    }

    /// Whether each stable probe can draw all its visible faces once the plan has run.
    pub fn readiness(&self) -> Readiness {
        Readiness {
            grid: self.grid.missing.is_empty(),
            previous: self.previous.is_none_or(|p| p.missing.is_empty()),
            grid_partial: !self.grid.draw.is_empty(),
        }
    }
}

/// Invalid scheduler settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ScheduleError {
    /// `max_faces` is below [`MIN_FACE_BUDGET`].
    BudgetTooSmall(u32),
    /// The capture range is not finite and positive.
    CaptureRange(f32),
}

impl fmt::Display for ScheduleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScheduleError::BudgetTooSmall(n) => {
                write!(f, "face budget {n} is below the minimum {MIN_FACE_BUDGET}")
            }
            ScheduleError::CaptureRange(v) => write!(f, "capture range {v} must be > 0"),
        }
    }
}

impl std::error::Error for ScheduleError {}

/// The face cache and the planning rules.
#[derive(Clone, Debug, PartialEq)]
pub struct Scheduler {
    max_faces: u32,
    stable_cap: Option<u32>,
    /// Stable faces per frame at most on a cell-crossing frame.
    crossing_cap: Option<u32>,
    capture_far: f32,
    stamps: [[Option<CaptureStamp>; 6]; 3],
    /// Every probe is one orthographic face stored as face +X ([`crate::ortho`]).
    orthographic: bool,
}

impl Scheduler {
    /// A scheduler with an empty cache. `max_faces` is the per-frame capture budget
    /// (>= [`MIN_FACE_BUDGET`]); `capture_far` the probes' capture range (Chebyshev).
    pub fn new(max_faces: u32, capture_far: f32) -> Result<Self, ScheduleError> {
        if max_faces < MIN_FACE_BUDGET {
            return Err(ScheduleError::BudgetTooSmall(max_faces));
        }
        if !(capture_far.is_finite() && capture_far > 0.0) {
            return Err(ScheduleError::CaptureRange(capture_far));
        }
        Ok(Scheduler {
            max_faces,
            stable_cap: None,
            crossing_cap: None,
            capture_far,
            stamps: [[None; 6]; 3],
            orthographic: false,
        })
    }

    /// Caps the stable (grid and previous) faces captured per frame at `n` (at least 1),
    /// whatever the eye leaves of the budget: a cell crossing then costs at most `n` extra
    /// faces in any frame, and the new grid probe fills in over the next frames while the
    /// previous probe keeps drawing.
    pub fn with_stable_faces_per_frame(mut self, n: u32) -> Self {
        self.stable_cap = Some(n.max(1));
        self
    }

    /// Caps the stable faces captured on a cell-crossing frame (the first frame of a new grid
    /// origin, while the previous probe draws) and on the frames after it until the fade
    /// begins (fade_t 0) at `n` (at least 1), below the per-frame cap; and at none on a
    /// fade's first frame when the grid probe draws some face already.
    pub fn with_crossing_faces(mut self, n: u32) -> Self {
        self.crossing_cap = Some(n.max(1));
        self
    }

    /// Plans every probe as one orthographic face (layer +X, [`crate::ortho`]) when `on`, as
    /// cubes otherwise. Switching drops the cache: a face's data belongs to one projection.
    pub fn set_orthographic(&mut self, on: bool) {
        if self.orthographic != on {
            self.orthographic = on;
            self.invalidate_all();
        }
    }

    /// The per-frame capture budget.
    pub fn max_faces(&self) -> u32 {
        self.max_faces
    }

    /// What `face` of `slot` was last captured for.
    pub fn stamp(&self, slot: Slot, face: Face) -> Option<CaptureStamp> {
        self.stamps[slot.index()][face.index()]
    }

    /// Forgets every capture (e.g. after the GPU textures were recreated).
    pub fn invalidate_all(&mut self) {
        self.stamps = [[None; 6]; 3];
    }

    /// Marks stale every captured face (of any slot) that may see the box `min..max`: it stays
    /// drawable (its old image is in the right place) and is captured again when the budget
    /// allows, like after a scene change, but faces that cannot see the box keep their
    /// captures. Returns how many faces were marked. A scene edit (a terrain brush dab, an
    /// object moved) then costs the faces it touches, not every face of every probe.
    pub fn invalidate_region(&mut self, min: Vec3, max: Vec3) -> u32 {
        self.invalidate_region_faces(min, max).len() as u32
    }

    /// [`Scheduler::invalidate_region`], returning each face marked with its slot and its
    /// capture's stamp (where and at what resolution it was captured).
    pub fn invalidate_region_faces(
        &mut self,
        min: Vec3,
        max: Vec3,
    ) -> Vec<(Slot, Face, CaptureStamp)> {
        let mut marked = Vec::new();
        for (slot, stamps) in Slot::ALL.into_iter().zip(&mut self.stamps) {
            for (f, stamp) in stamps.iter_mut().enumerate() {
                let Some(s) = stamp else {
                    continue;
                };
                if face_may_see_box(Face::ALL[f], s.origin, min, max, self.capture_far) {
                    s.scene_generation = s.scene_generation.wrapping_add(1);
                    marked.push((slot, Face::ALL[f], *s));
                }
            }
        }
        marked
    }

    /// Records that every face of `plan` was captured.
    pub fn commit(&mut self, plan: &UpdatePlan) {
        for w in &plan.work {
            self.stamps[w.slot.index()][w.face.index()] = Some(CaptureStamp {
                origin: w.origin,
                face_resolution: w.face_resolution,
                scene_generation: plan.scene_generation,
            });
        }
    }

    /// Plans this frame's captures for `probes` seen through `frustum`.
    pub fn plan(&self, frustum: &Frustum, probes: &ProbeSet, scene_generation: u64) -> UpdatePlan {
        let mut pass = Pass {
            frustum,
            forward: view_forward(frustum),
            budget: self.max_faces,
            work: Vec::new(),
        };
        let eye = self.plan_eye(&mut pass, &probes.eye());
        if let Some(cap) = self.stable_cap {
            pass.budget = pass.budget.min(cap);
        }
        let mut grid = self.needs(frustum, &probes.grid(), scene_generation);
        let mut previous = (probes.previous()).map(|p| self.needs(frustum, &p, scene_generation));
        // The frame that crosses into a new cell (a grid probe with nothing captured at its
        // origin while the previous one still draws, or the fade's first frame) captures
        // fewer stable faces: it also pays for the eye and both stable probes' quads. So do
        // the frames after it while the fade has not begun (fade_t 0: a crossing nothing
        // could be prefetched for, as when it comes while the last fade still ran; on
        // textured_walk the worst frame 1.75-2.19x the median became 1.56-1.66x, shimmer
        // unchanged on every path). None at all on the fade's first frame when the grid
        // probe draws some face already (prefetched): then the previous probe owns every
        // pixel, and it keeps those of the faces the grid probe misses.
        if let Some(cap) = self.crossing_cap
            && previous.is_some()
            && (grid.drawable.is_empty() || probes.fade_starts() || probes.fade_t() <= 0.0)
        {
            let cap = if !grid.drawable.is_empty() && probes.fade_starts() {
                0
            } else {
                cap
            };
            pass.budget = pass.budget.min(cap);
        }
        let mut order = vec![&mut grid];
        if let Some(prev) = previous.as_mut() {
            // The probe drawing more pixels first (grid on ties).
            if probes.drawn_share(Role::Previous) > probes.drawn_share(Role::Grid) {
                order.insert(0, prev);
            } else {
                order.push(prev);
            }
        }
        // Holes of both stable probes come before stale faces of either, so a scene that
        // changes every frame cannot starve a missing face (and stall the fade).
        for n in order.iter_mut() {
            n.capture = pass.take(n.missing);
        }
        for n in order.iter_mut() {
            n.capture = n.capture.union(pass.take(n.stale));
            pass.queue(&n.probe, n.capture);
        }
        let grid = grid.into_plan();
        let previous = previous.map(Needs::into_plan);
        let counts = count(&eye, &grid, previous.as_ref());
        UpdatePlan {
            scene_generation,
            eye,
            grid,
            previous,
            prefetch: None,
            work: pass.work,
            counts,
        }
    }

    /// Adds to `plan` up to `max_faces` captures of `next` (from
    /// [`ProbeSet::next_probe`]: the grid probe of the cell the camera is about to enter, in
    /// the free stable slot), faces facing the view first, when the frame has no other
    /// stable work: a quiet frame pays for the crossing ahead, and the crossing frame finds
    /// those faces already captured (same slot, origin and resolution), so it neither
    /// captures nor waits for them.
    pub fn prefetch(&self, plan: &mut UpdatePlan, frustum: &Frustum, next: &Probe, max_faces: u32) {
        let stable_work = plan.work.iter().any(|w| w.role != Role::Eye);
        if stable_work || plan.previous.is_some() || next.slot == plan.grid.probe.slot {
            return;
        }
        let spare = self.max_faces.saturating_sub(plan.counts.total());
        let mut pass = Pass {
            frustum,
            forward: view_forward(frustum),
            budget: max_faces.min(spare),
            work: Vec::new(),
        };
        let mut needs = self.needs(frustum, next, plan.scene_generation);
        needs.capture = pass.take(needs.missing);
        if needs.capture.is_empty() {
            return;
        }
        pass.queue(next, needs.capture);
        plan.work.extend(pass.work);
        plan.counts.grid += needs.capture.count();
        plan.prefetch = Some(needs.into_plan());
    }

    /// `next`'s plan (every face it would show drawn, none captured) when each of those faces
    /// holds data of `scene_generation` for its origin, as [`Self::prefetch`] leaves them
    /// once committed; `None` while any is missing or stale. Such a probe can fill behind
    /// the grid probe before the crossing, as it does on the crossing's first frame.
    pub fn ready(
        &self,
        frustum: &Frustum,
        next: &Probe,
        scene_generation: u64,
    ) -> Option<ProbePlan> {
        let needs = self.needs(frustum, next, scene_generation);
        let whole = needs.missing.is_empty() && needs.stale.is_empty();
        (whole && !needs.visible.is_empty()).then(|| needs.into_plan())
    }

    fn plan_eye(&self, pass: &mut Pass<'_>, eye: &Probe) -> ProbePlan {
        let visible = self.visible(pass.frustum, eye);
        pass.queue(eye, visible);
        pass.budget = pass.budget.saturating_sub(visible.count());
        ProbePlan {
            probe: *eye,
            visible,
            capture: visible,
            draw: visible,
            missing: FaceMask::EMPTY,
            stale: FaceMask::EMPTY,
        }
    }

    fn visible(&self, frustum: &Frustum, probe: &Probe) -> FaceMask {
        if self.orthographic {
            let mut only = FaceMask::EMPTY;
            only.insert(Face::PosX);
            return only;
        }
        let extent = splat_extent(probe.face_resolution);
        visible_faces(frustum, probe.origin, self.capture_far, extent)
    }

    /// Faces of `probe` whose data belongs to its origin and resolution, and the subset
    /// that is also of the current scene generation.
    fn cached(&self, probe: &Probe, scene_generation: u64) -> (FaceMask, FaceMask) {
        let mut drawable = FaceMask::EMPTY;
        let mut valid = FaceMask::EMPTY;
        for face in Face::ALL {
            let Some(s) = self.stamp(probe.slot, face) else {
                continue;
            };
            if s.origin == probe.origin && s.face_resolution == probe.face_resolution {
                drawable.insert(face);
                if s.scene_generation == scene_generation {
                    valid.insert(face);
                }
            }
        }
        (drawable, valid)
    }

    fn needs(&self, frustum: &Frustum, probe: &Probe, scene_generation: u64) -> Needs {
        let visible = self.visible(frustum, probe);
        let (drawable, valid) = self.cached(probe, scene_generation);
        Needs {
            probe: *probe,
            visible,
            drawable,
            missing: visible.difference(drawable),
            stale: visible.intersection(drawable).difference(valid),
            capture: FaceMask::EMPTY,
        }
    }
}

/// What a stable probe needs this frame, and what it was granted.
struct Needs {
    probe: Probe,
    visible: FaceMask,
    drawable: FaceMask,
    /// Visible faces with no data for this origin (holes).
    missing: FaceMask,
    /// Visible faces with data from an older scene generation.
    stale: FaceMask,
    capture: FaceMask,
}

impl Needs {
    fn into_plan(self) -> ProbePlan {
        ProbePlan {
            probe: self.probe,
            visible: self.visible,
            capture: self.capture,
            draw: self.visible.intersection(self.drawable.union(self.capture)),
            missing: self.missing.difference(self.capture),
            stale: self.stale.difference(self.capture),
        }
    }
}

/// State of one planning pass: the remaining budget and the queued work.
struct Pass<'a> {
    frustum: &'a Frustum,
    forward: Vec3,
    budget: u32,
    work: Vec<FaceWork>,
}

impl Pass<'_> {
    /// As many faces of `wanted` as the budget allows, best first; spends the budget.
    fn take(&mut self, wanted: FaceMask) -> FaceMask {
        let granted: FaceMask = faces_by_priority(wanted, self.forward)
            .take(self.budget as usize)
            .collect();
        self.budget -= granted.count();
        granted
    }

    /// Appends captures of `faces` of `probe`, best first.
    fn queue(&mut self, probe: &Probe, faces: FaceMask) {
        let items = faces_by_priority(faces, self.forward).map(|f| work_item(probe, f));
        self.work.extend(items);
    }
}

/// The frustum's view direction: the inward normal of its near plane.
fn view_forward(frustum: &Frustum) -> Vec3 {
    frustum.planes[0].normal
}

/// Faces of `set`, most aligned with `forward` first (layer order on ties).
fn faces_by_priority(set: FaceMask, forward: Vec3) -> impl Iterator<Item = Face> {
    let mut faces: Vec<Face> = set.iter().collect();
    faces.sort_by(|a, b| forward.dot(b.axis()).total_cmp(&forward.dot(a.axis())));
    faces.into_iter()
}

fn work_item(probe: &Probe, face: Face) -> FaceWork {
    FaceWork {
        role: probe.role,
        slot: probe.slot,
        face,
        origin: probe.origin,
        face_resolution: probe.face_resolution,
    }
}

fn count(eye: &ProbePlan, grid: &ProbePlan, previous: Option<&ProbePlan>) -> PlanCounts {
    let waiting = |p: &ProbePlan| p.missing.count() + p.stale.count();
    PlanCounts {
        eye: eye.capture.count(),
        grid: grid.capture.count(),
        previous: previous.map_or(0, |p| p.capture.count()),
        deferred: waiting(grid) + previous.map_or(0, waiting),
    }
}

#[cfg(test)]
mod tests;
