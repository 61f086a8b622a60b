use super::*;
use crate::grid::{GridCell, ProbeKey};
use crate::probe_set::FadeConfig;
use crate::visibility::{CameraView, frustum};
use glam::IVec3;

const DT: f32 = 1.0 / 60.0;
const FAR: f32 = 100.0;

fn key(x: i32) -> ProbeKey {
    ProbeKey {
        cell: GridCell {
            index: IVec3::new(x, 0, 0),
            cell_size: 1.0,
        },
        face_resolution: 16,
        offset: Vec3::ZERO,
    }
}

fn view_at(position: Vec3, yaw: f32, fov_y: f32) -> Frustum {
    frustum(&CameraView {
        position,
        forward: Vec3::new(yaw.sin(), -0.1, yaw.cos()),
        up: Vec3::Y,
        fov_y,
        aspect: 16.0 / 9.0,
        near: 0.1,
        far: FAR,
    })
    .unwrap()
}

struct Rig {
    probes: ProbeSet,
    scheduler: Scheduler,
    generation: u64,
}

impl Rig {
    /// A budget of 18 faces, at most 2 stable faces a frame and 1 on a crossing frame.
    fn with_crossing_cap() -> Self {
        Rig {
            scheduler: Scheduler::new(18, FAR)
                .unwrap()
                .with_stable_faces_per_frame(2)
                .with_crossing_faces(1),
            ..Rig::new(18)
        }
    }

    fn new(max_faces: u32) -> Rig {
        let camera = Vec3::new(0.2, 0.1, -0.3);
        Rig {
            probes: ProbeSet::new(camera, key(0), FadeConfig::default()).unwrap(),
            scheduler: Scheduler::new(max_faces, FAR).unwrap(),
            generation: 0,
        }
    }

    /// One whole frame; returns its plan.
    fn frame(&mut self, camera: Vec3, cell: i32, yaw: f32, fov_y: f32) -> UpdatePlan {
        self.probes.begin_frame(camera, key(cell), DT);
        let plan = self
            .scheduler
            .plan(&view_at(camera, yaw, fov_y), &self.probes, self.generation);
        self.scheduler.commit(&plan);
        self.probes.advance_fade(plan.readiness());
        plan
    }
}

#[test]
fn eye_is_captured_every_frame() {
    let mut rig = Rig::new(12);
    let camera = Vec3::new(0.2, 0.1, -0.3);
    for _ in 0..3 {
        let plan = rig.frame(camera, 0, 0.3, 1.2);
        assert!(!plan.eye.visible.is_empty());
        assert_eq!(plan.eye.capture, plan.eye.visible);
        assert_eq!(plan.counts.eye, plan.eye.visible.count());
        assert!(
            plan.work[..plan.counts.eye as usize]
                .iter()
                .all(|w| w.role == Role::Eye)
        );
    }
}

#[test]
fn grid_faces_are_captured_once_while_the_view_holds() {
    let mut rig = Rig::new(12);
    let camera = Vec3::new(0.2, 0.1, -0.3);
    let first = rig.frame(camera, 0, 0.3, 1.2);
    assert_eq!(first.grid.capture, first.grid.visible);
    assert!(first.previous.is_none());
    for _ in 0..5 {
        let plan = rig.frame(camera, 0, 0.3, 1.2);
        assert_eq!(plan.counts.grid, 0);
        assert_eq!(plan.grid.draw, plan.grid.visible);
    }
}

#[test]
fn rotating_in_place_only_captures_newly_visible_faces() {
    let mut rig = Rig::new(12);
    let camera = Vec3::new(0.2, 0.1, -0.3);
    let mut ever_visible = FaceMask::EMPTY;
    let mut captures = [0u32; 6];
    for step in 0..=72 {
        let yaw = step as f32 * 10.0_f32.to_radians();
        let plan = rig.frame(camera, 0, yaw, 1.0);
        let newly = plan.grid.visible.difference(ever_visible);
        assert_eq!(plan.grid.capture, newly, "step {step}");
        assert_eq!(plan.grid.draw, plan.grid.visible);
        assert!(plan.previous.is_none());
        for f in plan.grid.capture.iter() {
            captures[f.index()] += 1;
        }
        ever_visible = ever_visible.union(plan.grid.visible);
    }
    assert!(captures.iter().all(|&c| c <= 1), "{captures:?}");
    assert!(
        ever_visible.count() >= 5,
        "a full turn sees the ring and the floor"
    );
}

#[test]
fn crossing_spreads_the_new_grid_over_frames() {
    let mut rig = Rig::new(7);
    let yaw = 0.0;
    let fov = 2.2; // Wide: the eye sees 5 faces, leaving 2 for stable probes.
    let inside = Vec3::new(0.45, 0.1, 0.0);
    for _ in 0..10 {
        rig.frame(inside, 0, yaw, fov);
    }
    let settled = rig.frame(inside, 0, yaw, fov);
    assert!(settled.grid.missing.is_empty());
    let eye_faces = settled.eye.visible.count();
    assert!(eye_faces >= 5, "{eye_faces}");

    let crossed = Vec3::new(0.55, 0.1, 0.0);
    let plan = rig.frame(crossed, 1, yaw, fov);
    assert!(plan.counts.total() <= 7, "no spike on the crossing frame");
    let previous = plan.previous.expect("fade started");
    assert_eq!(
        previous.capture,
        FaceMask::EMPTY,
        "previous is already shaded"
    );
    assert_eq!(previous.draw, previous.visible, "previous keeps drawing");
    assert!(
        !plan.grid.missing.is_empty(),
        "the new grid needs more than one frame"
    );
    assert!(!plan.readiness().grid);
    assert_eq!(rig.probes.fade_t(), 0.0);

    let mut frames = 1;
    while !rig.frame(crossed, 1, yaw, fov).readiness().grid {
        // A part-captured grid fades in where it has faces, never to the end.
        assert!(rig.probes.fade_t() <= crate::probe_set::PARTIAL_FADE_LIMIT);
        assert!(
            rig.probes.previous_active(),
            "the fade waits for the whole grid"
        );
        frames += 1;
        assert!(frames < 10);
    }
    assert!(frames >= 2);
    rig.frame(crossed, 1, yaw, fov);
    assert!(
        rig.probes.fade_t() > 0.0,
        "fading once the grid is complete"
    );
}

#[test]
fn budget_is_respected_and_everything_arrives() {
    let mut rig = Rig::new(8);
    let mut camera = Vec3::new(0.0, 0.1, 0.0);
    let mut last = None;
    for i in 0..240 {
        // Walk along +x through several cells, turning, at ~3 u/s.
        camera.x += 3.0 * DT;
        let cell = camera.x.round() as i32;
        let plan = rig.frame(camera, cell, i as f32 * 0.05, 1.3);
        assert!(plan.counts.total() <= 8, "frame {i}: {:?}", plan.counts);
        assert_eq!(plan.work.len() as u32, plan.counts.total());
        last = Some(cell);
    }
    let cell = last.unwrap();
    for _ in 0..60 {
        rig.frame(camera, cell, 12.0, 1.3);
    }
    let plan = rig.frame(camera, cell, 12.0, 1.3);
    assert!(plan.previous.is_none());
    assert!(plan.grid.missing.is_empty() && plan.grid.stale.is_empty());
    assert_eq!(plan.grid.draw, plan.grid.visible);
    assert_eq!(plan.counts.deferred, 0);
}

#[test]
fn scene_changes_recapture_but_keep_drawing() {
    let mut rig = Rig::new(7);
    let camera = Vec3::new(0.1, 0.1, 0.1);
    for _ in 0..5 {
        rig.frame(camera, 0, 0.8, 2.2);
    }
    rig.generation += 1;
    let plan = rig.frame(camera, 0, 0.8, 2.2);
    assert_eq!(
        plan.grid.draw, plan.grid.visible,
        "stale faces stay on screen"
    );
    assert!(plan.grid.missing.is_empty());
    assert!(plan.counts.grid > 0);
    assert!(!plan.grid.stale.is_empty(), "budget spreads the re-capture");
    assert!(plan.readiness().grid, "stale is not missing");
    let mut frames = 0;
    while !rig.frame(camera, 0, 0.8, 2.2).grid.stale.is_empty() {
        frames += 1;
        assert!(frames < 10);
    }
    let again = rig.frame(camera, 0, 0.8, 2.2);
    assert_eq!(again.counts.grid, 0);
}

#[test]
fn a_scene_changing_every_frame_cannot_stall_a_crossing() {
    let mut rig = Rig::new(7);
    let (yaw, fov) = (0.0, 2.2);
    for _ in 0..10 {
        rig.generation += 1;
        rig.frame(Vec3::new(0.45, 0.1, 0.0), 0, yaw, fov);
    }
    let mut frames = 0;
    loop {
        rig.generation += 1;
        let plan = rig.frame(Vec3::new(0.55, 0.1, 0.0), 1, yaw, fov);
        if plan.readiness().grid {
            break;
        }
        let previous = plan.previous.unwrap();
        assert!(
            !previous.stale.is_empty(),
            "the previous probe is stale, yet waits"
        );
        frames += 1;
        assert!(frames < 10, "grid never got its faces");
    }
}

#[test]
fn returning_to_a_cell_reuses_its_slot() {
    let mut rig = Rig::new(12);
    let a = Vec3::new(0.0, 0.1, 0.0);
    let b = Vec3::new(1.0, 0.1, 0.0);
    for _ in 0..40 {
        rig.frame(a, 0, 0.0, 1.0);
    }
    for _ in 0..40 {
        rig.frame(b, 1, 0.0, 1.0);
    }
    assert!(!rig.probes.previous_active());
    let plan = rig.frame(a, 0, 0.0, 1.0);
    assert_eq!(plan.grid.probe.origin, Vec3::ZERO);
    assert_eq!(
        plan.counts.grid, 0,
        "cell 0's faces are still in the other slot"
    );
    assert_eq!(plan.grid.draw, plan.grid.visible);
}

#[test]
fn commit_records_stamps() {
    let mut rig = Rig::new(12);
    rig.generation = 9;
    let plan = rig.frame(Vec3::ZERO, 0, 0.0, 1.0);
    let w = plan.work.iter().find(|w| w.role == Role::Grid).unwrap();
    let stamp = rig.scheduler.stamp(w.slot, w.face).unwrap();
    assert_eq!(stamp.origin, Vec3::ZERO);
    assert_eq!(stamp.face_resolution, 16);
    assert_eq!(stamp.scene_generation, 9);
    rig.scheduler.invalidate_all();
    assert_eq!(rig.scheduler.stamp(w.slot, w.face), None);
}

#[test]
fn rejects_bad_settings() {
    assert_eq!(
        Scheduler::new(6, 10.0),
        Err(ScheduleError::BudgetTooSmall(6))
    );
    assert_eq!(
        Scheduler::new(7, 0.0),
        Err(ScheduleError::CaptureRange(0.0))
    );
    assert!(Scheduler::new(7, f32::NAN).is_err());
    assert_eq!(Scheduler::new(7, 1.0).unwrap().max_faces(), 7);
}

#[test]
fn a_stable_cap_limits_each_crossing_frame() {
    let mut rig = Rig::new(18);
    rig.scheduler = Scheduler::new(18, FAR)
        .unwrap()
        .with_stable_faces_per_frame(2);
    let wide = 100f32.to_radians();
    // Settle in cell 0, then cross into cell 1.
    for _ in 0..10 {
        rig.frame(Vec3::new(0.2, 0.1, -0.3), 0, 0.3, wide);
    }
    let mut frames = 0;
    loop {
        let plan = rig.frame(Vec3::new(0.8, 0.1, -0.3), 1, 0.3, wide);
        assert!(
            plan.counts.grid + plan.counts.previous <= 2,
            "{:?}",
            plan.counts
        );
        frames += 1;
        if plan.grid.missing.is_empty() {
            break;
        }
        assert!(frames < 10, "the new grid probe never completes");
    }
    assert!(
        frames >= 2,
        "a wide view needs more than two faces: the cap spread them"
    );
}

#[test]
fn the_crossing_frame_captures_fewer_stable_faces() {
    let mut rig = Rig::with_crossing_cap();
    let wide = 100f32.to_radians();
    let stable = |plan: &UpdatePlan| plan.counts.grid + plan.counts.previous;
    let first = rig.frame(Vec3::new(0.2, 0.1, -0.3), 0, 0.3, wide);
    assert_eq!(stable(&first), 2, "no previous probe yet: the usual cap");
    for _ in 0..10 {
        rig.frame(Vec3::new(0.2, 0.1, -0.3), 0, 0.3, wide);
    }
    let crossing = rig.frame(Vec3::new(0.8, 0.1, -0.3), 1, 0.3, wide);
    assert!(crossing.previous.is_some());
    assert_eq!(stable(&crossing), 1);
    // The rest follow at the crossing's cap while the fade has not begun (such a frame
    // also draws both probes' quads), then at the usual cap.
    assert_eq!(rig.probes.fade_t(), 0.0);
    let next = rig.frame(Vec3::new(0.8, 0.1, -0.3), 1, 0.3, wide);
    assert_eq!(stable(&next), 1, "one a frame while fade_t is 0");
    assert!(rig.probes.fade_t() > 0.0, "the fade begins");
    let after = rig.frame(Vec3::new(0.8, 0.1, -0.3), 1, 0.3, wide);
    assert_eq!(stable(&after), 2, "then the usual cap");
}

#[test]
fn prefetched_faces_spare_the_crossing_frame() {
    let mut rig = Rig::new(12);
    let camera = Vec3::new(0.2, 0.1, -0.3);
    let frustum = view_at(camera, 1.4, 1.2);
    // Settle the grid probe of cell 0.
    for _ in 0..4 {
        rig.frame(camera, 0, 1.4, 1.2);
    }
    assert_eq!(rig.probes.next_probe(key(0)), None, "the grid's own cell");
    let next = rig.probes.next_probe(key(1)).expect("no fade runs");
    assert_ne!(next.slot, rig.probes.grid().slot);
    let mut prefetched = 0;
    for _ in 0..8 {
        rig.probes.begin_frame(camera, key(0), DT);
        let mut plan = rig.scheduler.plan(&frustum, &rig.probes, rig.generation);
        rig.scheduler.prefetch(&mut plan, &frustum, &next, 1);
        let extra: Vec<_> = plan.work.iter().filter(|w| w.role != Role::Eye).collect();
        assert!(extra.len() <= 1, "one face per frame: {extra:?}");
        assert!(
            extra
                .iter()
                .all(|w| w.slot == next.slot && w.origin == next.origin)
        );
        prefetched += extra.len();
        rig.scheduler.commit(&plan);
        rig.probes.advance_fade(plan.readiness());
    }
    assert!(prefetched >= 2, "prefetched {prefetched} faces");
    // The crossing: the new grid probe's visible faces are already there.
    let plan = rig.frame(Vec3::new(1.2, 0.1, -0.3), 1, 1.4, 1.2);
    assert!(plan.previous.is_some(), "a fade starts");
    assert_eq!(plan.counts.grid, 0, "nothing left to capture: {plan:?}");
    assert!(plan.readiness().grid);
    // No prefetch while that fade runs.
    assert_eq!(rig.probes.next_probe(key(2)), None);
}

#[test]
fn a_fade_toward_a_partly_prefetched_grid_starts_without_stable_captures() {
    let mut rig = Rig::with_crossing_cap();
    let camera = Vec3::new(0.2, 0.1, -0.3);
    let wide = 100f32.to_radians();
    let frustum = view_at(camera, 0.3, wide);
    for _ in 0..6 {
        rig.frame(camera, 0, 0.3, wide);
    }
    // One face of the next cell's grid probe only, where the view needs several.
    let next = rig.probes.next_probe(key(1)).expect("no fade runs");
    rig.probes.begin_frame(camera, key(0), DT);
    let mut plan = rig.scheduler.plan(&frustum, &rig.probes, rig.generation);
    rig.scheduler.prefetch(&mut plan, &frustum, &next, 1);
    assert_eq!(plan.work.iter().filter(|w| w.role != Role::Eye).count(), 1);
    rig.scheduler.commit(&plan);
    rig.probes.advance_fade(plan.readiness());
    let stable = |plan: &UpdatePlan| plan.counts.grid + plan.counts.previous;
    let crossing = rig.frame(Vec3::new(0.8, 0.1, -0.3), 1, 0.3, wide);
    assert!(crossing.previous.is_some(), "a fade starts");
    assert!(!crossing.grid.draw.is_empty(), "the prefetched face draws");
    assert!(!crossing.readiness().grid, "faces are missing");
    assert_eq!(stable(&crossing), 0, "the previous probe owns every pixel");
    assert_eq!(rig.probes.fade_t(), 0.0);
    // The missing faces follow, one a frame while the fade has not begun (each such frame
    // also draws both probes' quads).
    let next = rig.frame(Vec3::new(0.8, 0.1, -0.3), 1, 0.3, wide);
    assert_eq!(stable(&next), 1, "the missing faces follow: {next:?}");
    assert!(!next.readiness().grid, "more faces are missing");
    for _ in 0..40 {
        rig.frame(Vec3::new(0.8, 0.1, -0.3), 1, 0.3, wide);
    }
    assert_eq!(rig.probes.fade_t(), 1.0, "the fade ends");
}

#[test]
fn prefetch_waits_for_stable_work() {
    let mut rig = Rig::new(12);
    let camera = Vec3::new(0.2, 0.1, -0.3);
    let frustum = view_at(camera, 0.3, 1.2);
    rig.probes.begin_frame(camera, key(0), DT);
    // The first frame still captures the grid probe: no prefetch on top.
    let next = rig.probes.next_probe(key(1)).expect("no fade");
    let mut plan = rig.scheduler.plan(&frustum, &rig.probes, rig.generation);
    assert!(plan.counts.grid > 0);
    let before = plan.work.len();
    rig.scheduler.prefetch(&mut plan, &frustum, &next, 1);
    assert_eq!(plan.work.len(), before);
    assert_eq!(plan.prefetch, None);
}

#[test]
fn a_box_is_seen_only_by_the_faces_facing_it() {
    let o = Vec3::ZERO;
    let (min, max) = (Vec3::new(-1.0, -1.0, -10.0), Vec3::new(1.0, 1.0, -8.0));
    let seeing: Vec<Face> = Face::ALL
        .into_iter()
        .filter(|&f| face_may_see_box(f, o, min, max, 500.0))
        .collect();
    assert_eq!(seeing.len(), 1, "{seeing:?}");
    assert_eq!(seeing[0].axis(), -Vec3::Z);
    assert!(!face_may_see_box(seeing[0], o, min, max, 5.0), "beyond far");
    // A box around the origin is seen by every face.
    let all = Face::ALL
        .into_iter()
        .filter(|&f| face_may_see_box(f, o, Vec3::splat(-1.0), Vec3::splat(1.0), 500.0))
        .count();
    assert_eq!(all, 6);
}
