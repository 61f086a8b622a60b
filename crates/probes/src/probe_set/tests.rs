use super::*;
use crate::bayer::threshold_of;
use crate::grid::GridCell;
use glam::IVec3;

const DT: f32 = 1.0 / 60.0;

fn key(x: i32) -> ProbeKey {
    ProbeKey {
        cell: GridCell {
            index: IVec3::new(x, 0, 0),
            cell_size: 1.0,
        },
        face_resolution: 32,
        offset: Vec3::ZERO,
    }
}

fn set_at(x: i32) -> ProbeSet {
    ProbeSet::new(EDGE, key(x), FadeConfig::default()).unwrap()
}

/// A camera on the boundary between cells 0 and 1 (cells are chosen by the tests).
const EDGE: Vec3 = Vec3::new(0.5, 0.0, 0.0);

/// Runs frames with the camera still at [`EDGE`], snapped to cell `x`, until the fade
/// ends; returns the frames run.
fn run_until_done(set: &mut ProbeSet, x: i32, dt: f32) -> u32 {
    let mut frames = 0;
    while set.previous_active() {
        set.update(EDGE, key(x), dt, Readiness::ALL);
        frames += 1;
        assert!(frames < 10_000, "fade never ends");
    }
    frames
}

/// The stable probe drawing each of the 16 dither cells.
fn owners(set: &ProbeSet) -> Vec<(Slot, Vec3)> {
    (0..16u8)
        .map(|v| set.stable_owner(threshold_of(v)))
        .map(|p| (p.slot, p.origin))
        .collect()
}

#[test]
fn starts_at_rest() {
    let set = set_at(3);
    assert!(!set.previous_active());
    assert_eq!(set.fade_t(), 1.0);
    assert_eq!(set.grid().origin, Vec3::new(3.0, 0.0, 0.0));
    assert_eq!(set.grid().slot, Slot::StableA);
    assert_eq!(set.eye().slot, Slot::Eye);
    assert_eq!(set.probe(Role::Previous), None);
    assert_eq!(set.drawn_share(Role::Previous), 0.0);
}

#[test]
fn crossing_moves_roles_not_data() {
    let mut set = set_at(0);
    let event = set.begin_frame(Vec3::new(0.6, 0.0, 0.0), key(1), DT);
    assert_eq!(event, TransitionEvent::CrossingStarted);
    let prev = set.previous().unwrap();
    assert_eq!(prev.origin, Vec3::ZERO);
    assert_eq!(prev.slot, Slot::StableA, "old grid stays in its slot");
    assert_eq!(set.grid().slot, Slot::StableB);
    assert_eq!(set.grid().origin, Vec3::X);
    assert_eq!(set.fade_t(), 0.0);
    // The trigger frame does not move the fade, even when everything is ready.
    assert!(!set.advance_fade(Readiness::ALL));
    assert_eq!(set.fade_t(), 0.0);
    assert_eq!(set.fade_direction(), Some(FadeDirection::TowardGrid));
}

#[test]
fn slow_fade_takes_fade_seconds() {
    let mut set = set_at(0);
    set.update(EDGE, key(1), DT, Readiness::ALL);
    let frames = run_until_done(&mut set, 1, DT);
    // 0.5 s at 60 fps = 30 frames (+1 for float rounding).
    assert!((30..=31).contains(&frames), "{frames}");
    assert_eq!(set.fade_t(), 1.0);
    assert_eq!(set.grid().origin, Vec3::X);
}

#[test]
fn never_completes_in_fewer_than_two_frames() {
    let cfg = FadeConfig::default();
    let mut set = ProbeSet::new(Vec3::ZERO, key(0), cfg).unwrap();
    // A teleport with a long frame: enormous speed, dt capped.
    set.update(Vec3::new(500.0, 0.0, 0.0), key(500), 1.0, Readiness::ALL);
    assert_eq!(set.fade_t(), 0.0, "trigger frame");
    set.update(Vec3::new(500.0, 0.0, 0.0), key(500), 1.0, Readiness::ALL);
    assert_eq!(set.fade_t(), 0.5, "capped at 1/min_frames");
    assert!(set.previous_active());
    set.update(Vec3::new(500.0, 0.0, 0.0), key(500), 1.0, Readiness::ALL);
    assert!(!set.previous_active());
}

#[test]
fn dt_is_capped() {
    let mut set = set_at(0);
    set.update(EDGE, key(1), DT, Readiness::ALL);
    set.update(EDGE, key(1), 5.0, Readiness::ALL);
    // rate 2/s at rest; dt capped to 0.1 s.
    assert!((set.fade_t() - 0.2).abs() < 1e-3, "{}", set.fade_t());
}

#[test]
fn speed_is_smoothed_and_speeds_up_the_fade() {
    let mut set = set_at(0);
    let speed = 7.5;
    let mut x = 0.0;
    for _ in 0..120 {
        x += speed * DT;
        set.begin_frame(Vec3::new(x, 0.0, 0.0), key(0), DT);
        set.advance_fade(Readiness::ALL);
    }
    assert!((set.smoothed_speed() - speed).abs() < 0.01);
    for _ in 0..2 {
        x += speed * DT;
        set.update(Vec3::new(x, 0.0, 0.0), key(1), DT, Readiness::ALL);
    }
    // One moving frame after the trigger: 7.5 cells/s beats 1/0.5 s.
    assert!((set.fade_t() - speed * DT).abs() < 1e-3, "{}", set.fade_t());
}

#[test]
fn a_fast_fade_ends_within_fade_cells_of_travel() {
    // 3 cells/s at 60 fps: the reference's fade takes a whole cell (20 frames), one with
    // fade_cells 0.5 half of it (10 frames), so it is over before the camera is halfway
    // into the new cell.
    for (fade_cells, frames) in [(1.0, 20), (0.5, 10)] {
        let cfg = FadeConfig {
            fade_cells,
            ..FadeConfig::default()
        };
        let mut set = ProbeSet::new(Vec3::ZERO, key(0), cfg).unwrap();
        let speed = 3.0;
        let mut x = 0.0;
        while x < 0.5 {
            x += speed * DT;
            set.update(Vec3::new(x, 0.0, 0.0), key(0), DT, Readiness::ALL);
        }
        let mut n = 0;
        set.update(Vec3::new(x, 0.0, 0.0), key(1), DT, Readiness::ALL);
        while set.previous_active() {
            x += speed * DT;
            set.update(Vec3::new(x, 0.0, 0.0), key(1), DT, Readiness::ALL);
            n += 1;
            assert!(n < 1000);
        }
        assert!(
            (frames..=frames + 1).contains(&n),
            "fade_cells {fade_cells}: {n} frames"
        );
    }
}

#[test]
fn smoothing_follows_tau() {
    let mut set = set_at(0);
    // One frame of dt = tau at 10 u/s moves the average by 1 - 1/e.
    set.begin_frame(EDGE + Vec3::new(0.5, 0.0, 0.0), key(0), 0.05);
    let expect = 10.0 * (1.0 - (-1.0f32).exp());
    assert!((set.smoothed_speed() - expect).abs() < 1e-3);
}

#[test]
fn fade_waits_for_a_ready_grid() {
    let mut set = set_at(0);
    let not_ready = Readiness::whole(false, true);
    set.update(EDGE, key(1), DT, not_ready);
    for _ in 0..10 {
        set.update(EDGE, key(1), DT, not_ready);
    }
    assert_eq!(set.fade_t(), 0.0);
    set.update(EDGE, key(1), DT, Readiness::ALL);
    assert!(set.fade_t() > 0.0);
}

#[test]
fn a_partly_captured_grid_fades_short_of_the_end() {
    let mut set = set_at(0);
    let partial = Readiness {
        grid: false,
        previous: true,
        grid_partial: true,
    };
    for _ in 0..60 {
        set.update(EDGE, key(1), DT, partial);
    }
    assert_eq!(
        set.fade_t(),
        PARTIAL_FADE_LIMIT,
        "runs to the limit and holds"
    );
    assert!(
        set.previous_active(),
        "the previous probe keeps the missing faces"
    );
    set.update(EDGE, key(1), DT, Readiness::ALL);
    assert!(set.fade_t() > PARTIAL_FADE_LIMIT || !set.previous_active());
}

#[test]
fn returning_reverses_the_fade_without_a_pop() {
    let mut set = set_at(0);
    set.update(EDGE, key(1), DT, Readiness::ALL);
    for _ in 0..9 {
        set.update(EDGE, key(1), DT, Readiness::ALL);
    }
    let t = set.fade_t();
    assert!(t > 0.2 && t < 0.4);
    let before = owners(&set);
    let event = set.begin_frame(EDGE, key(0), DT);
    assert_eq!(event, TransitionEvent::Reversed);
    assert_eq!(owners(&set), before, "turning changes no pixel");
    set.advance_fade(Readiness::ALL);
    assert!(set.fade_t() < t);
    run_until_done(&mut set, 0, DT);
    assert_eq!(set.grid().origin, Vec3::ZERO);
    assert_eq!(set.grid().slot, Slot::StableA, "back in its original slot");
}

#[test]
fn forward_again_after_reversing() {
    let mut set = set_at(0);
    for _ in 0..6 {
        set.update(EDGE, key(1), DT, Readiness::ALL);
    }
    set.update(EDGE, key(0), DT, Readiness::ALL);
    assert_eq!(set.fade_direction(), Some(FadeDirection::TowardPrevious));
    assert_eq!(set.begin_frame(EDGE, key(1), DT), TransitionEvent::Reversed);
    assert_eq!(set.fade_direction(), Some(FadeDirection::TowardGrid));
}

#[test]
fn third_cell_waits_for_the_running_fade() {
    let mut set = set_at(0);
    set.update(EDGE, key(1), DT, Readiness::ALL);
    set.update(EDGE, key(1), DT, Readiness::ALL);
    let event = set.begin_frame(EDGE, key(2), DT);
    assert_eq!(event, TransitionEvent::Deferred);
    assert_eq!(set.grid().origin, Vec3::X);
    set.advance_fade(Readiness::ALL);
    run_until_done(&mut set, 2, DT);
    assert_eq!(
        set.grid().origin,
        Vec3::X,
        "the fade ended at its own target"
    );
    let event = set.begin_frame(EDGE, key(2), DT);
    assert_eq!(event, TransitionEvent::CrossingStarted);
    assert_eq!(set.previous().unwrap().origin, Vec3::X);
}

#[test]
fn third_cell_retargets_an_invisible_grid() {
    let mut set = set_at(0);
    let not_ready = Readiness::whole(false, true);
    set.update(EDGE, key(1), DT, not_ready);
    let slot = set.grid().slot;
    let before = owners(&set);
    let event = set.begin_frame(EDGE, key(2), DT);
    assert_eq!(event, TransitionEvent::Retargeted);
    assert_eq!(set.grid().origin, Vec3::new(2.0, 0.0, 0.0));
    assert_eq!(set.grid().slot, slot);
    assert_eq!(set.previous().unwrap().origin, Vec3::ZERO);
    assert_eq!(owners(&set), before, "the grid probe owned no pixel");
}

#[test]
fn only_one_advance_per_frame() {
    let mut set = set_at(0);
    set.update(EDGE, key(1), DT, Readiness::ALL);
    set.begin_frame(EDGE, key(1), DT);
    set.advance_fade(Readiness::ALL);
    let t = set.fade_t();
    set.advance_fade(Readiness::ALL);
    assert_eq!(set.fade_t(), t);
}

#[test]
fn bad_inputs_are_tolerated_or_rejected() {
    let mut set = set_at(0);
    set.begin_frame(Vec3::splat(f32::NAN), key(0), f32::NAN);
    assert_eq!(set.eye().origin, EDGE);
    assert_eq!(set.smoothed_speed(), 0.0);
    let bad = |c: FadeConfig| ProbeSet::new(Vec3::ZERO, key(0), c).unwrap_err();
    let d = FadeConfig::default();
    assert_eq!(
        bad(FadeConfig { min_frames: 1, ..d }),
        FadeConfigError::MinFrames(1)
    );
    assert!(matches!(
        bad(FadeConfig {
            fade_seconds: 0.0,
            ..d
        }),
        FadeConfigError::FadeSeconds(_)
    ));
    assert!(matches!(
        bad(FadeConfig {
            speed_tau: f32::NAN,
            ..d
        }),
        FadeConfigError::SpeedTau(_)
    ));
    assert!(matches!(
        bad(FadeConfig {
            fade_cells: 0.0,
            ..d
        }),
        FadeConfigError::FadeCells(_)
    ));
    assert!(matches!(
        bad(FadeConfig { max_dt: -1.0, ..d }),
        FadeConfigError::MaxDt(_)
    ));
    assert!(FadeConfigError::MinFrames(1).to_string().contains(">= 2"));
}

#[test]
fn slots_and_layers() {
    assert_eq!(Slot::StableB.layer_base(), 12);
    assert_eq!(Slot::StableA.other_stable(), Slot::StableB);
    assert_eq!(Slot::StableB.other_stable(), Slot::StableA);
    assert_eq!(Slot::ALL.map(Slot::index), [0, 1, 2]);
}
