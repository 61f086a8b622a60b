//! UI flows of the viewport driven through egui_kittest (no GPU): the View menu's render
//! method radio buttons and debug views, the orthographic view (menu and key 5), the face
//! handles of a probe-grid override volume, and the pointer grab while playing.

use egui::viewport::CursorGrab;
use egui::{Key, Modifiers, Pos2, ViewportCommand, ViewportId};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::Vec3;
use texel_editor::app::EditorApp;
use texel_editor::camera::Projector;
use texel_editor::files::Recent;
use texel_editor::viewport::ViewMode;
use texel_editor::viewport::debug::DebugView;
use texel_editor::viewport::handles;
use texel_render::input::Schedule;

fn harness() -> Harness<'static, EditorApp> {
    let mut h = Harness::builder()
        .with_size([1200.0, 800.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::with_recent(None, Recent::default()),
        );
    h.run();
    h
}

fn menu(h: &mut Harness<'_, EditorApp>, top: &str, item: &str) {
    h.get_by_label(top).click();
    h.run();
    h.get_by_label(item).click();
    h.run();
}

/// Number of shapes egui painted in the last frame.
fn shapes(h: &Harness<'_, EditorApp>) -> usize {
    h.output().shapes.len()
}

fn viewport_commands(h: &Harness<'_, EditorApp>) -> Vec<ViewportCommand> {
    h.output()
        .viewport_output
        .get(&ViewportId::ROOT)
        .map(|v| v.commands.clone())
        .unwrap_or_default()
}

#[test]
fn view_menu_switches_method_and_debug_views() {
    let mut h = harness();
    assert_eq!(h.state().viewport.schedule, Schedule::Ours);
    menu(&mut h, "View", "Paper: every texel of every drawn face");
    assert_eq!(h.state().viewport.schedule, Schedule::Paper);

    let before = shapes(&h);
    menu(&mut h, "View", DebugView::GridCells.label());
    assert!(h.state().viewport.debug.flags.grid_cells);
    h.run();
    // 27 cell boxes of 12 edges in pieces: many more shapes than before.
    let with_cells = shapes(&h);
    assert!(with_cells > before + 100, "{before} -> {with_cells}");

    for v in [
        DebugView::EyePixels,
        DebugView::ProbeOrigins,
        DebugView::CubeFaces,
    ] {
        menu(&mut h, "View", v.label());
        assert!(h.state().viewport.debug.flags.get(v), "{v:?}");
    }
    h.run();
    // Without a GPU the faces window says so, and nothing was read back.
    assert!(h.query_by_label("no grid probe yet").is_some());
    assert_eq!(h.state().viewport.debug.readbacks, 0);
    // Closing the window switches the view off.
    menu(&mut h, "View", DebugView::CubeFaces.label());
    assert!(!h.state().viewport.debug.flags.cube_faces);
    assert!(h.query_by_label("no grid probe yet").is_none());
    // Debug views do not touch the document.
    assert!(!h.state().state.is_dirty());
}

#[test]
fn orthographic_view_from_the_menu_and_key_5_but_never_in_play() {
    let mut h = harness();
    assert!(!h.state().viewport.camera.ortho);
    assert_eq!(h.state().viewport.render_camera().ortho_height, None);
    assert!(h.query_by_label("ortho").is_none());

    menu(&mut h, "View", "Orthographic view  (5)");
    let cam = h.state().viewport.camera;
    assert!(cam.ortho);
    let rendered = h.state().viewport.render_camera();
    assert_eq!(rendered.ortho_height, Some(cam.ortho_height()));
    // The render camera stands back along the view (nothing near the eye is clipped); the
    // picture's centre is still the focus point.
    let back = cam.eye - cam.forward() * texel_editor::camera::ORTHO_PULL_BACK * cam.distance;
    assert!(
        (rendered.position - back).length() < 1e-4,
        "{:?}",
        rendered.position
    );
    // The status bar says so.
    assert!(h.query_by_label("ortho").is_some());
    // The wheel zooms the orthographic view: a smaller height.
    let before = cam.ortho_height();
    let centre = h.state().viewport.rect.expect("drawn").center();
    h.hover_at(centre);
    h.event(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, 120.0),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Wheel,
        modifiers: Modifiers::NONE,
    });
    h.run();
    let zoomed = h
        .state()
        .viewport
        .render_camera()
        .ortho_height
        .expect("ortho");
    assert!(zoomed < before * 0.95, "{before} -> {zoomed}");

    // Key 5 switches back, and again.
    h.key_press(Key::Num5);
    h.run();
    assert!(!h.state().viewport.camera.ortho);
    assert_eq!(h.state().viewport.render_camera().ortho_height, None);
    h.key_press(Key::Num5);
    h.run();
    assert!(h.state().viewport.camera.ortho);

    // Play walks with the perspective camera, and 5 does nothing there (Play repaints all
    // the time: steps, not runs).
    h.key_press(Key::F5);
    h.step();
    assert!(h.state().viewport.playing());
    assert_eq!(h.state().viewport.render_camera().ortho_height, None);
    h.key_press(Key::Num5);
    h.step();
    assert!(h.state().viewport.camera.ortho);
    assert_eq!(h.state().viewport.render_camera().ortho_height, None);
    // Back in the editor the orthographic view is as it was.
    h.key_press(Key::Escape);
    h.run();
    assert!(!h.state().viewport.playing());
    assert!(h.state().viewport.render_camera().ortho_height.is_some());
    // None of it touches the document.
    assert!(!h.state().state.is_dirty());
}

#[test]
fn dragging_a_face_handle_resizes_the_volume_and_undo_restores_it() {
    let mut h = harness();
    menu(&mut h, "Add", "Probe-grid override");
    let (index, row) = h.state().state.selected_row().expect("selected");
    let t0 = row.transform.expect("transform");
    let o0 = row.probe_grid_override.expect("volume");
    let steps = h.state().state.history.undo_len();

    let rect = h.state().viewport.rect.expect("viewport drawn");
    let proj = Projector::new(&h.state().viewport.camera.camera(), rect);
    let hs = handles::handles(&proj, &t0, &o0);
    let plus_x = hs[0].expect("+X handle on screen");
    let outward = hs[0].zip(proj.project(t0.translation + Vec3::new(o0.size.x, 0.0, 0.0)));
    let (a, b) = outward.expect("on screen");
    let dir = (b - a).normalized();
    let end: Pos2 = plus_x + dir * 40.0;

    h.hover_at(plus_x);
    h.step();
    h.drag_at(plus_x);
    h.step();
    for k in 1..=8 {
        h.hover_at(plus_x + (end - plus_x) * (k as f32 / 8.0));
        h.step();
    }
    h.drop_at(end);
    h.run();

    let row = h.state().state.row_at(index).expect("row");
    let (t1, o1) = (
        row.transform.expect("t"),
        row.probe_grid_override.expect("o"),
    );
    assert!(
        o1.size.x > o0.size.x + 0.1,
        "{:?} -> {:?}",
        o0.size,
        o1.size
    );
    assert_eq!((o1.size.y, o1.size.z), (o0.size.y, o0.size.z));
    // The −X face stays put.
    let min_x = |t: &texel_scene::Transform, o: &texel_scene::ProbeGridOverride| {
        t.translation.x - o.size.x * t.scale.x * 0.5
    };
    assert!(
        (min_x(&t1, &o1) - min_x(&t0, &o0)).abs() < 1e-4,
        "{t0:?} {o0:?} -> {t1:?} {o1:?}"
    );
    assert_eq!(h.state().state.history.undo_len(), steps + 1, "one step");
    assert_eq!(h.state().state.selection, Some(index));

    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    let row = h.state().state.row_at(index).expect("row");
    assert_eq!(row.probe_grid_override, Some(o0));
    assert_eq!(row.transform, Some(t0));
}

#[test]
fn play_grabs_the_pointer_and_escape_releases_it() {
    let mut h = harness();
    h.input_mut().focused = true;
    h.key_press(Key::F5);
    h.step();
    let mut took = viewport_commands(&h);
    h.step();
    took.extend(viewport_commands(&h));
    assert!(h.state().viewport.grabbed);
    assert!(
        took.iter()
            .any(|c| matches!(c, ViewportCommand::CursorGrab(g) if *g != CursorGrab::None)),
        "{took:?}"
    );
    assert!(took.contains(&ViewportCommand::CursorVisible(false)));

    // Raw mouse motion looks around without a drag.
    let yaw = |h: &Harness<'_, EditorApp>| match h.state().viewport.mode {
        ViewMode::Play(w) => w.yaw_deg,
        ViewMode::Edit => f32::NAN,
    };
    let y0 = yaw(&h);
    h.event(egui::Event::MouseMoved(egui::vec2(40.0, 0.0)));
    h.step();
    assert!((yaw(&h) - y0).abs() > 1.0, "{y0} -> {}", yaw(&h));

    // Only the key-down event: `key_press` would step once more for the key-up, and the
    // harness keeps the output of the last step only.
    h.event(egui::Event::Key {
        key: Key::Escape,
        physical_key: None,
        pressed: true,
        repeat: false,
        modifiers: Modifiers::NONE,
    });
    h.step();
    let mut gave = viewport_commands(&h);
    h.step();
    gave.extend(viewport_commands(&h));
    assert!(!h.state().viewport.playing());
    assert!(!h.state().viewport.grabbed);
    assert!(gave.contains(&ViewportCommand::CursorGrab(CursorGrab::None)));
    assert!(gave.contains(&ViewportCommand::CursorVisible(true)));

    // Losing the window's focus gives the pointer back; a click in the viewport takes it.
    h.key_press(Key::F5);
    h.step();
    h.step();
    assert!(h.state().viewport.grabbed);
    h.input_mut().focused = false;
    h.step();
    assert!(!h.state().viewport.grabbed);
    assert!(h.state().viewport.playing());
    h.input_mut().focused = true;
    let centre = h.state().viewport.rect.expect("drawn").center();
    h.hover_at(centre);
    h.step();
    h.drag_at(centre);
    h.step();
    h.drop_at(centre);
    h.step();
    h.step();
    assert!(h.state().viewport.grabbed);
}
