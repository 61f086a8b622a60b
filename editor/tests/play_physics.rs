//! Play walks through the level's colliders (egui_kittest, a fixed 1/60 s step): a player
//! started in the air falls to the ground, and the moving objects' clock stands still while
//! editing and runs in Play (on a headless GPU, lavapipe in CI, for the session's clock).

use std::path::{Path, PathBuf};

use egui::Key;
use egui_kittest::Harness;
use texel_editor::app::EditorApp;
use texel_editor::files::Recent;
use texel_editor::viewport::ViewMode;
use texel_render::context::test_context;

use crate::support;

const STEP: f32 = 1.0 / 60.0;

/// A copy of `assets/levels/<name>.ron` in `dir`, its player start moved to `start`
/// (written as the level writes it).
fn level_copy(dir: &Path, name: &str, start: &str) -> PathBuf {
    let from = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../assets/levels/{name}.ron"));
    let text = std::fs::read_to_string(from).expect("level");
    let at = "translation: (0.0, 0.0, 13.0)";
    assert_eq!(text.matches(at).count(), 1, "the player start's line");
    let to = dir.join(format!("{name}.ron"));
    std::fs::write(&to, text.replace(at, &format!("translation: {start}"))).expect("copy");
    to
}

fn harness(path: &Path, size: [f32; 2]) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size(size)
        .with_step_dt(STEP)
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::with_recent(Some(path), Recent::default()),
        )
}

fn eye_y(h: &Harness<'_, EditorApp>) -> f32 {
    match h.state().viewport.mode {
        ViewMode::Play(w) => w.eye().y,
        ViewMode::Edit => f32::NAN,
    }
}

#[test]
fn play_from_a_start_in_the_air_falls_to_the_ground_within_a_second() {
    let dir = tempfile::tempdir().expect("tempdir");
    // stone_circle's start, 3 units up; its ground is at y = 0 and the eye 1.6 above.
    let path = level_copy(dir.path(), "stone_circle", "(0.0, 3.0, 13.0)");
    let mut h = harness(&path, [800.0, 600.0]);
    h.run();
    let before = h.state().state.scene().to_level();
    h.key_press(Key::F5);
    h.step();
    assert!(h.state().viewport.playing());
    assert!(eye_y(&h) > 4.4, "still up: {}", eye_y(&h));
    for _ in 0..60 {
        h.step();
    }
    assert!(
        (eye_y(&h) - 1.6).abs() < 0.03,
        "the eye is {} after a second",
        eye_y(&h)
    );
    assert_eq!(
        h.state().viewport.play_note(),
        None,
        "every object collides"
    );
    // F flies (up with Space), F again lands and falls back.
    h.key_press(Key::F);
    for _ in 0..30 {
        h.key_down(Key::Space);
        h.step();
    }
    h.key_up(Key::Space);
    h.step();
    assert!(eye_y(&h) > 2.5, "flew up to {}", eye_y(&h));
    h.key_press(Key::F);
    for _ in 0..60 {
        h.step();
    }
    assert!((eye_y(&h) - 1.6).abs() < 0.03, "landed at {}", eye_y(&h));
    h.key_press(Key::Escape);
    h.step();
    assert!(!h.state().viewport.playing());
    assert_eq!(
        h.state().state.scene().to_level(),
        before,
        "the document as it was"
    );
}

#[test]
fn the_animation_clock_stands_still_while_editing_and_runs_in_play() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_copy(dir.path(), "moving_parts", "(0.0, 0.0, 13.0)");
    // A small window: lavapipe draws every frame of Play.
    let mut h = harness(&path, [480.0, 320.0]);
    let egui = h.ctx.clone();
    h.state_mut().viewport.attach(support::gpu_view(&ctx), egui);
    // The time the worker's frame of the last UI frame posed the moving objects at.
    let time = |h: &Harness<'_, EditorApp>| {
        let worker = h.state().viewport.worker.as_ref().expect("worker");
        worker.wait_drawn().expect("a frame").time
    };
    for _ in 0..8 {
        h.step();
    }
    assert!(
        h.state().viewport.error.is_none(),
        "{:?}",
        h.state().viewport.error
    );
    assert_eq!(
        time(&h),
        0.0,
        "edit frames leave the objects where they stand"
    );

    h.key_press(Key::F5);
    h.step();
    assert!(h.state().viewport.playing());
    for _ in 0..10 {
        h.step();
    }
    // Ten Play frames: the last posed them after nine steps of the physics' clock.
    let t = time(&h);
    let frames = t / f64::from(STEP);
    assert!((8.5..=10.5).contains(&frames), "{t} s: {frames} frames");

    h.key_press(Key::Escape);
    h.step();
    assert!(!h.state().viewport.playing());
    for _ in 0..8 {
        h.step();
    }
    assert_eq!(time(&h), 0.0, "stopping Play puts the objects back");
}
