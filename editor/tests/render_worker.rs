//! The viewport renders on a thread of its own (`viewport::worker`), on a headless GPU
//! (lavapipe in CI): a UI frame completes while the worker is held busy and keeps showing
//! the last finished frame, and the next frame shows once the worker is let go; a click
//! selects through the worker's pick; the debug views read what the worker read back; a
//! renderer error becomes the viewport's message and a good frame clears it; closing the
//! editor ends and joins the thread. Nothing here is timed: the tests wait for the worker's
//! frames, not for a clock.

use std::path::Path;

use egui_kittest::Harness;
use glam::Vec2;
use texel_editor::app::EditorApp;
use texel_editor::files::Recent;
use texel_editor::viewport::debug::DebugView;
use texel_editor::viewport::worker::RenderWorker;
use texel_render::context::test_context;

use crate::support;

/// The editor on a copy of stone_circle in `dir` (its autosaves land there).
fn harness(dir: &Path) -> Harness<'static, EditorApp> {
    let path = support::bundled_copy(dir, "stone_circle");
    Harness::builder()
        .with_size([1000.0, 600.0])
        .with_step_dt(1.0 / 60.0)
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::with_recent(Some(&path), Recent::default()),
        )
}

/// The editor with its render worker on `ctx`'s device, looking at the first trilithon, on
/// a level copied into `dir`.
fn editor_on(ctx: &texel_render::context::GpuContext, dir: &Path) -> Harness<'static, EditorApp> {
    let mut h = harness(dir);
    let egui = h.ctx.clone();
    let viewport = &mut h.state_mut().viewport;
    viewport.attach(support::gpu_view(ctx), egui);
    viewport.camera = support::camera();
    h
}

fn worker<'a>(h: &'a Harness<'_, EditorApp>) -> &'a RenderWorker {
    h.state().viewport.worker.as_ref().expect("a render worker")
}

fn shown(h: &Harness<'_, EditorApp>) -> u64 {
    h.state().viewport.shown.as_ref().map_or(0, |f| f.number)
}

#[test]
fn a_ui_frame_completes_while_the_worker_is_busy_and_the_next_frame_follows() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    worker(&h).wait_drawn().expect("a first frame");
    h.step();
    assert!(shown(&h) > 0, "the first frame is shown");

    // The worker is held: it finishes the frame in hand, if any, and draws no other.
    let hold = worker(&h).hold();
    hold.wait_held().expect("the worker waits");
    h.step();
    let held = shown(&h);
    let before = h.state().viewport.render_camera();
    h.state_mut().viewport.camera.look(Vec2::new(60.0, 0.0));
    // These UI frames complete (were the UI waiting for a frame, this would never return).
    for _ in 0..3 {
        h.step();
    }
    let now = h.state().viewport.render_camera();
    assert_ne!(now, before, "the camera turned");
    let frame = h.state().viewport.shown.clone().expect("a frame");
    assert_eq!(frame.number, held, "the last finished frame is held");
    assert_eq!(
        frame.view.camera, before,
        "drawn from the camera before the turn"
    );
    assert!(h.state().viewport.error.is_none());

    // Let go: the frame of the turned camera follows.
    drop(hold);
    let next = worker(&h).wait_drawn().expect("the next frame");
    assert_eq!(next.view.camera, now);
    h.step();
    assert!(shown(&h) > held, "a newer frame is shown");
    let frame = h.state().viewport.shown.clone().expect("a frame");
    assert!(frame.number >= next.number);
    assert_eq!(frame.view.camera, now);
}

#[test]
fn a_click_selects_what_the_worker_picks() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    worker(&h).wait_drawn().expect("a first frame");
    h.step();
    h.state_mut().state.selection = None;
    press_centre(&mut h, egui::Modifiers::NONE);
    assert_eq!(
        h.state().state.selection,
        None,
        "not yet: the worker answers"
    );
    // The answer comes from the worker; the UI takes it at its next frame.
    worker(&h).wait_picked().expect("an answer");
    h.step();
    let (_, row) = h
        .state()
        .state
        .selected_row()
        .expect("something is selected");
    let name = format!("{:?}", row.name);
    assert!(
        name.contains("Trilithon 1"),
        "the trilithon under the cursor: {name}"
    );
}

#[test]
fn the_debug_views_take_their_data_from_the_workers_frames() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    worker(&h).wait_drawn().expect("a first frame");
    h.step();
    assert_eq!(
        h.state().viewport.debug.readbacks,
        0,
        "nothing read while off"
    );
    let flags = &mut h.state_mut().viewport.debug.flags;
    flags.toggle(DebugView::EyePixels);
    flags.toggle(DebugView::CubeFaces);
    // The views are part of the request: the worker draws again and reads what they need.
    h.step();
    worker(&h)
        .wait_drawn()
        .expect("a frame with the views' data");
    h.step();
    let debug = &h.state().viewport.debug;
    assert!(debug.has_eye_tint(), "the eye-sourced pixels' tint");
    assert_eq!(debug.face_count(), 6, "the grid probe's faces");
}

#[test]
fn a_render_error_is_the_viewports_message_until_a_good_frame() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    worker(&h).wait_drawn().expect("a first frame");
    // A level the frame planner refuses: a probe-grid volume of cell size zero (added
    // straight to the scene, as a hand-edited file could not be: nothing in the UI shows
    // it to correct it).
    let bad = texel_scene::EntityRow {
        probe_grid_override: Some(texel_scene::components::ProbeGridOverride {
            cell_size: 0.0,
            ..Default::default()
        }),
        ..Default::default()
    };
    let entity = h.state_mut().state.document.scene_mut().spawn(bad);
    h.step();
    let error = worker(&h).wait_drawn().expect_err("the level is refused");
    h.step();
    let shown = h
        .state()
        .viewport
        .error
        .clone()
        .expect("the viewport's message");
    assert_eq!(shown, error);
    assert!(shown.contains("cell_size 0"), "{shown}");
    // The UI goes on: more frames complete while the error stands.
    h.step();
    assert!(h.state().viewport.error.is_some());

    h.state_mut().state.document.scene_mut().despawn(entity);
    h.step();
    worker(&h).wait_drawn().expect("a good frame again");
    h.step();
    assert_eq!(h.state().viewport.error, None, "the message goes");
}

#[test]
fn closing_the_editor_ends_and_joins_the_render_thread() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    let watch = worker(&h).watch();
    // Closed with a request waiting behind a hold: dropping the worker lets go and joins.
    let hold = worker(&h).hold();
    hold.wait_held().expect("the worker waits");
    h.state_mut().viewport.camera.look(Vec2::new(30.0, 0.0));
    h.step();
    assert!(worker(&h).running());
    assert!(!watch.ended());
    drop(h);
    assert!(watch.ended(), "the thread ended before the editor was gone");
    drop(hold);
}

/// A gizmo drag step or an inspector change reaches the worker as that entity alone: its
/// level snapshot says which entity changed since the one before, and the renderer rewrites
/// it in place (`Session::update_entities`) instead of rebuilding the scene.
#[test]
fn an_edited_entity_is_taken_in_alone_by_the_worker() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    worker(&h).wait_drawn().expect("a first frame");
    h.step();
    // Move the first trilithon's left upright half a unit, as one gizmo step would.
    let state = &mut h.state_mut().state;
    let scene = state.scene();
    let e = scene.entities().nth(1).expect("an entity");
    let before = scene.row(e).expect("row");
    let mut after = before.clone();
    let t = after.transform.as_mut().expect("a transform");
    t.translation.x += 0.5;
    let command = texel_editor::command::Command::SetRow {
        index: 1,
        before: Box::new(before),
        after: Box::new(after),
    };
    state.apply(command, None).expect("the move applies");
    let mut last = None;
    for _ in 0..40 {
        h.step();
        worker(&h).wait_drawn().expect("a frame");
        h.step();
        last = h
            .state()
            .viewport
            .shown
            .as_ref()
            .and_then(|f| f.report.last_edit);
        if last.is_some() {
            break;
        }
    }
    assert!(
        matches!(
            last,
            Some(texel_runtime::session::EditUpdate::InPlace { .. })
        ),
        "the worker took the edit in as {last:?}"
    );
}

/// The edits the shown frame's renderer has taken in, and how it took the last one.
fn edits_taken(h: &Harness<'_, EditorApp>) -> (u64, Option<texel_runtime::session::EditUpdate>) {
    (h.state().viewport.shown.as_ref())
        .map_or((0, None), |f| (f.report.uploads, f.report.last_edit))
}

/// Steps the editor, a frame at a time, until the shown frame's renderer has taken in an
/// edit more than `before` (at most 40 frames); returns how it took the last one.
fn wait_edit(
    h: &mut Harness<'_, EditorApp>,
    before: u64,
) -> Option<texel_runtime::session::EditUpdate> {
    for _ in 0..40 {
        h.step();
        worker(h).wait_drawn().expect("a frame");
        h.step();
        if edits_taken(h).0 > before {
            break;
        }
    }
    edits_taken(h).1
}

/// The name of the selected entity.
fn selected_name(h: &Harness<'_, EditorApp>) -> Option<String> {
    let state = &h.state().state;
    let row = state.row_at(state.selection?)?;
    row.name.map(|n| n.0)
}

/// An entity deleted before the one in the middle of the view reaches the worker as that
/// removal alone (blanked in place: `Session::edit_rows`), and a click picks the same
/// entity at its new position; the delete undone reaches it as an insert (taking its blank
/// again, in place), and the click picks it at its old position.
#[test]
fn a_deleted_entity_is_taken_in_alone_and_picks_stay_right() {
    use texel_runtime::session::EditUpdate;
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    worker(&h).wait_drawn().expect("a first frame");
    h.step();
    click_centre(&mut h, egui::Modifiers::NONE);
    let picked = h.state().state.selection.expect("an entity in the middle");
    let name = selected_name(&h).expect("a named entity");
    assert!(picked > 0, "an entity before it to delete");
    let gone = picked - 1;
    let row = h.state().state.row_at(gone).expect("row");
    let command = texel_editor::command::Command::Despawn {
        index: gone,
        row: Box::new(row),
    };
    let (taken, _) = edits_taken(&h);
    let state = &mut h.state_mut().state;
    state.apply(command, None).expect("the delete applies");
    let last = wait_edit(&mut h, taken);
    assert!(
        matches!(last, Some(EditUpdate::InPlace { .. })),
        "the worker took the delete in as {last:?}"
    );
    click_centre(&mut h, egui::Modifiers::NONE);
    assert_eq!(h.state().state.selection, Some(picked - 1));
    assert_eq!(selected_name(&h).as_deref(), Some(name.as_str()));
    let (taken, _) = edits_taken(&h);
    assert_eq!(h.state_mut().state.undo(), Ok(true));
    let last = wait_edit(&mut h, taken);
    assert!(
        matches!(last, Some(EditUpdate::InPlace { .. })),
        "the worker took the undo in as {last:?}"
    );
    click_centre(&mut h, egui::Modifiers::NONE);
    assert_eq!(h.state().state.selection, Some(picked));
    assert_eq!(selected_name(&h).as_deref(), Some(name.as_str()));
}

/// Clicks the middle of the viewport with `modifiers` and waits for the worker's answer.
fn click_centre(h: &mut Harness<'_, EditorApp>, modifiers: egui::Modifiers) {
    press_centre(h, modifiers);
    worker(h).wait_picked().expect("an answer");
    h.step();
}

/// Clicks the middle of the viewport with `modifiers` (the pick is asked, not yet answered).
fn press_centre(h: &mut Harness<'_, EditorApp>, modifiers: egui::Modifiers) {
    let rect = h.state().viewport.rect.expect("the viewport was drawn");
    h.event(egui::Event::PointerMoved(rect.center()));
    h.step();
    for pressed in [true, false] {
        h.event_modifiers(
            egui::Event::PointerButton {
                pos: rect.center(),
                button: egui::PointerButton::Primary,
                pressed,
                modifiers,
            },
            modifiers,
        );
        h.step();
    }
}

#[test]
fn a_ctrl_click_adds_and_takes_away_what_the_worker_picks() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    worker(&h).wait_drawn().expect("a first frame");
    h.step();
    // The player start: nowhere near the middle of the view.
    let start = h.state().state.scene().len() - 1;
    h.state_mut().state.select_only(start);
    click_centre(&mut h, egui::Modifiers::COMMAND);
    let picked = h
        .state()
        .state
        .selection
        .expect("the picked entity is active");
    assert_ne!(picked, start);
    let mut both = vec![start, picked];
    both.sort_unstable();
    assert_eq!(h.state().state.selected(), both, "Ctrl-click adds");
    click_centre(&mut h, egui::Modifiers::COMMAND);
    assert_eq!(h.state().state.selected(), [start], "and takes away");
    click_centre(&mut h, egui::Modifiers::SHIFT);
    assert_eq!(h.state().state.selected(), both, "Shift-click adds");
    click_centre(&mut h, egui::Modifiers::NONE);
    assert_eq!(
        h.state().state.selected(),
        [picked],
        "a plain click selects it alone"
    );
}

/// A pick whose answer comes after the selection changed otherwise (a click, then Ctrl+A
/// before the worker answered) is dropped: the later choice stands.
#[test]
fn a_pick_answered_after_the_selection_changed_is_dropped() {
    let Some(ctx) = test_context() else {
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor_on(&ctx, dir.path());
    h.step();
    worker(&h).wait_drawn().expect("a first frame");
    h.step();
    h.state_mut().state.selection = None;
    // The worker is held, so the click's answer waits.
    let hold = worker(&h).hold();
    hold.wait_held().expect("the worker waits");
    press_centre(&mut h, egui::Modifiers::NONE);
    let n = h.state().state.scene().len();
    h.state_mut().state.select_all();
    drop(hold);
    worker(&h).wait_picked().expect("an answer");
    h.step();
    assert_eq!(h.state().state.selected().len(), n, "select all stands");
}
