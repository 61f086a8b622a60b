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

/// Frames of play without a window: `level` under the name `name` in `assets/levels`, its
/// player start moved to `start` facing `yaw`, stepped through the App's own per-frame
/// movement.
mod walking {
    use std::sync::Arc;

    use glam::{UVec2, Vec3, Vec3Swizzles as _};
    use texel_scene::{Name, PlayerStart, Transform};

    use super::*;
    use crate::frame_plan::{FrameDriver, PreparedLevel};

    const DT: f32 = 1.0 / 60.0;

    fn app(name: &str, start: Vec3, yaw: f32) -> App {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels");
        let mut level = load_level(&root.join(format!("{name}.ron"))).expect("level");
        let e = (level.scene.entities())
            .find(|e| level.scene.world().get::<&PlayerStart>(*e).is_ok())
            .expect("a player start");
        let mut row = level.scene.row(e).expect("row");
        row.transform = Some(Transform::from_translation(start));
        row.player_start = Some(PlayerStart {
            yaw,
            pitch: 0.0,
            eye_height: 1.6,
        });
        level.scene.set_row(e, row).expect("start moved");
        let app = App::new(level, PlayOptions::default());
        assert!(app.walker.is_some(), "colliders built");
        app
    }

    /// `seconds` of frames with `input` held, the moving objects posed by the clock of a
    /// frame driver (the renderer's: each frame is drawn at its time, then it advances).
    fn run(app: &mut App, driver: &mut FrameDriver, input: InputState, seconds: f32) {
        app.input = input;
        for _ in 0..(seconds / DT).round() as u32 {
            let t = driver.time();
            app.advance(DT, t);
            let camera = app.camera.camera(FOV_Y_DEG.to_radians());
            driver.frame(camera, DT, Schedule::Ours).expect("frame");
        }
    }

    fn driver(app: &App) -> FrameDriver {
        let level = Arc::new(PreparedLevel::new(&app.level));
        FrameDriver::prepared(level, UVec2::new(64, 36), FOV_Y_DEG.to_radians()).expect("driver")
    }

    #[test]
    fn the_moving_platform_carries_a_player_standing_on_it_in_step_with_the_renderer() {
        // Above the platform's top at t = 0, (-3.4, 0.35, 2.2).
        let mut app = app("moving_parts", Vec3::new(-3.4, 0.6, 2.2), 0.0);
        let mut driver = driver(&app);
        run(&mut app, &mut driver, InputState::default(), 3.0);
        assert!((driver.time() - 3.0).abs() < 1e-6, "{}", driver.time());
        // Frame 180 (the last) was drawn at 2.983 s: the platform on its way from
        // (-3.4, 1.2, 2.2) at 2 s to (-3.4, 1.2, 0.8) at 4 s, its top 0.15 above.
        let t = 179.0 / 60.0;
        let top = Vec3::new(-3.4, 1.35, 2.2 - 1.4 * (t - 2.0) / 2.0);
        let eye = app.camera.eye() - Vec3::Y * 1.6;
        // Where the renderer drew it to a hair (a frame off would be 0.0117 away); the feet
        // ride the controller's 0.02 skin above its top.
        assert!(
            (eye.xz() - top.xz()).length() < 0.002 && (eye.y - top.y).abs() < 0.03,
            "feet at {eye} on a platform whose top is at {top}"
        );
        let walker = app.walker.as_ref().expect("walker");
        let platform = walker.player().ground_entity().expect("standing");
        let world = app.level.scene.world();
        assert_eq!(
            world.get::<&Name>(platform).expect("name").0,
            "Moving platform"
        );
    }

    #[test]
    fn a_stone_stops_the_walking_camera_and_flying_passes_through_it() {
        // "Standing stone 1" of stone_circle: 0.469 thick, turned 43.451 deg about Y. Start
        // 3 units in front of its broad face, looking at it, and hold W.
        let stone = Vec3::new(4.596, 0.0, 3.857);
        let yaw = 43.451f32;
        let face = Vec3::new(yaw.to_radians().sin(), 0.0, yaw.to_radians().cos());
        let mut app = app("stone_circle", stone + face * 3.0, yaw);
        let mut driver = driver(&app);
        let w = InputState {
            forward: true,
            ..InputState::default()
        };
        let along = |app: &App| (app.camera.eye() - stone).dot(face);
        run(&mut app, &mut driver, w, 2.0);
        assert!(!app.camera.fly);
        assert!(
            (0.5..0.62).contains(&along(&app)),
            "stopped {} in front of the stone",
            along(&app)
        );
        assert!(app.camera.eye().y - 1.6 < 0.03, "on the ground");

        // Flying at 2.5 units a second goes through it and out the other side.
        app.toggle_fly();
        run(&mut app, &mut driver, w, 1.0);
        assert!(along(&app) < -1.5, "flew to {}", along(&app));
        // Landing puts the player under the camera, on the ground behind the stone.
        app.toggle_fly();
        run(&mut app, &mut driver, InputState::default(), 0.5);
        assert!(along(&app) < -1.5 && app.camera.eye().y - 1.6 < 0.03);
    }
}
