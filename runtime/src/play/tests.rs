//! Unit tests of the play loop's pure parts.
use super::*;
use texel_render::stats::{FrameStats, PassTime};

#[test]
fn sizes_parse() {
    assert_eq!(parse_size("1280x720"), Ok((1280, 720)));
    assert_eq!(parse_size(" 640X480 "), Ok((640, 480)));
    for bad in [
        "", "1280", "0x720", "x720", "1280x", "-1x5", "99999x10", "axb",
    ] {
        assert!(parse_size(bad).is_err(), "{bad}");
    }
}

#[test]
fn keys_map_to_actions() {
    let mut input = InputState::default();
    for code in [
        KeyCode::KeyW,
        KeyCode::KeyA,
        KeyCode::ShiftLeft,
        KeyCode::KeyQ,
    ] {
        match key_action(code) {
            Some(KeyAction::Move(key)) => *key.flag(&mut input) = true,
            other => panic!("{code:?}: {other:?}"),
        }
    }
    let want = InputState {
        forward: true,
        left: true,
        run: true,
        down: true,
        ..InputState::default()
    };
    assert_eq!(input, want);
    assert_eq!(key_action(KeyCode::KeyF), Some(KeyAction::ToggleFly));
    assert_eq!(key_action(KeyCode::Tab), Some(KeyAction::ToggleSchedule));
    assert_eq!(key_action(KeyCode::F3), Some(KeyAction::ToggleOverlay));
    assert_eq!(key_action(KeyCode::Escape), Some(KeyAction::Escape));
    assert_eq!(key_action(KeyCode::KeyR), Some(KeyAction::Sculpt(true)));
    assert_eq!(key_action(KeyCode::KeyG), Some(KeyAction::Sculpt(false)));
    assert_eq!(key_action(KeyCode::KeyZ), None);
}

#[test]
fn fps_averages_over_half_a_second() {
    let mut m = FpsMeter::default();
    let mut shown = 0.0;
    for _ in 0..30 {
        shown = m.tick(1.0 / 60.0);
    }
    assert!((shown - 60.0).abs() < 0.5, "{shown}");
    // Holds its value between windows.
    assert_eq!(m.tick(0.01), shown);
}

#[test]
fn overlay_lists_passes_counters_and_modes() {
    let stats = FrameStats {
        passes: vec![
            PassTime {
                pass: "capture",
                ms: 1.5,
            },
            PassTime {
                pass: "splat",
                ms: 12.25,
            },
        ],
        gpu_timestamps: true,
        frame_ms: 14.0,
        counters: texel_render::stats::Counters {
            faces_captured: 6,
            texels_shaded: 1234,
            quads_splatted: 999,
            screen_visible_texels: 77,
            ..Default::default()
        },
    };
    let mut camera = WalkCamera::from_start(glam::Vec3::ZERO, &Default::default());
    camera.toggle_fly();
    let text = overlay_lines(&stats, 59.9, Schedule::Paper, &camera).join("\n");
    for want in [
        "59.9 fps",
        "frame 14.00 ms",
        "schedule: paper",
        "fly",
        "eye (0.00, 1.60, 0.00)",
        "capture",
        "12.250 ms (GPU)",
        "faces captured 6",
        "texels shaded 1234",
        "quads splatted 999",
        "visible texels 77",
        KEY_HELP[0],
        KEY_HELP[1],
        KEY_HELP[2],
    ] {
        assert!(text.contains(want), "missing `{want}` in\n{text}");
    }
    camera.toggle_fly();
    let walk = overlay_lines(&FrameStats::default(), 0.0, Schedule::Ours, &camera).join("\n");
    assert!(
        walk.contains("schedule: ours") && walk.contains("walk"),
        "{walk}"
    );
    assert_eq!(dab_line(None), None, "no line before the first dab");
    assert_eq!(
        dab_line(Some(7)).as_deref(),
        Some("last dab marked 7 probe faces")
    );
}
