//! Snapping and the outliner's filter, hide and lock, driven through egui_kittest without a
//! GPU: grid snap lands a gizmo move on multiples of the step (Ctrl drags freely), angle snap
//! a turn on multiples of the angle; Add lands on the surface under the viewport's centre
//! (not on a hidden entity; on the ground with surface snap off); the outliner filters by name
//! and by component; a hidden entity is left out of what the viewport draws but saved whole;
//! a locked one is not box-selected nor moved.

use crate::support;

use support::{click_row, editor, outliner_label};

use egui::{Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::Vec3;
use texel_editor::app::EditorApp;
use texel_editor::camera::Projector;
use texel_editor::ui::widgets::display_name;
use texel_editor::viewport::gizmo;

const STANDING_STONE_1: usize = 10;
const ALTAR: usize = 20;

fn name(h: &Harness<'_, EditorApp>, i: usize) -> String {
    let row = h.state().state.row_at(i).expect("an entity");
    display_name(&row, i)
}

fn transform(h: &Harness<'_, EditorApp>, i: usize) -> texel_scene::Transform {
    let row = h.state().state.row_at(i).expect("an entity");
    row.transform.expect("a transform")
}

fn steps(h: &Harness<'_, EditorApp>) -> usize {
    h.state().state.history.undo_len()
}

/// Drags the primary button from `from` to `to` over a few frames, with `modifiers` held.
fn drag(h: &mut Harness<'_, EditorApp>, from: Pos2, to: Pos2, modifiers: Modifiers) {
    h.event(Event::PointerMoved(from));
    h.run();
    let button = |pos, pressed| Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers,
    };
    h.event_modifiers(button(from, true), modifiers);
    h.step();
    for k in 1..=4 {
        let at = from + (to - from) * (k as f32 / 4.0);
        h.event_modifiers(Event::PointerMoved(at), modifiers);
        h.step();
    }
    h.event_modifiers(button(to, false), modifiers);
    h.run();
}

fn projector(h: &Harness<'_, EditorApp>) -> Projector {
    let app = h.state();
    let rect = app.viewport.rect.expect("the viewport was drawn");
    Projector::new(&app.viewport.render_camera(), rect)
}

/// Drags the gizmo of the selection (standing at `origin`) along its handle `axis` by 60
/// pixels.
fn drag_handle(h: &mut Harness<'_, EditorApp>, origin: Vec3, axis: usize, modifiers: Modifiers) {
    let proj = projector(h);
    let (o, ends) = gizmo::handles(&proj, origin).expect("the gizmo is in view");
    let on = o + (ends[axis] - o) * 0.7;
    let along = (ends[axis] - o).normalized() * 60.0;
    drag(h, on, on + along, modifiers);
}

fn on_multiple(v: f32, step: f32) -> bool {
    ((v / step) - (v / step).round()).abs() < 1e-3
}

#[test]
fn grid_snap_lands_a_move_on_multiples_and_ctrl_drags_freely() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let i = STANDING_STONE_1;
    click_row(&mut h, i, Modifiers::NONE);
    let start = transform(&h, i).translation;
    assert!(!on_multiple(start.x, 0.5), "the stone starts off the grid");
    h.state_mut().viewport.snap.grid = true;
    h.state_mut().viewport.snap.step = 0.5;
    let n = steps(&h);
    drag_handle(&mut h, start, 0, Modifiers::NONE);
    let moved = transform(&h, i).translation;
    assert_eq!(steps(&h), n + 1, "one undo step");
    assert!(on_multiple(moved.x, 0.5), "x = {}", moved.x);
    assert!(
        (moved.x - start.x).abs() > 0.1,
        "it moved: {start} → {moved}"
    );
    assert_eq!((moved.y, moved.z), (start.y, start.z));
    // Ctrl turns the snap off for the drag: from 0.37 off the grid, a free move.
    h.state_mut().viewport.snap.step = 0.25;
    drag_handle(&mut h, moved, 1, Modifiers::COMMAND);
    let free = transform(&h, i).translation;
    assert!((free.y - moved.y).abs() > 0.05, "{moved} → {free}");
    assert!(!on_multiple(free.y, 0.25), "free: y = {}", free.y);
    assert_eq!(steps(&h), n + 2);
}

#[test]
fn grid_snap_lands_the_centre_of_several_on_multiples() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let stones = [10, 11, 12];
    click_row(&mut h, stones[0], Modifiers::NONE);
    let label = outliner_label(&h, stones[2]);
    h.get_by_label(&label).click_modifiers(Modifiers::SHIFT);
    h.run();
    let centre = |h: &Harness<'_, EditorApp>| {
        stones
            .iter()
            .map(|&i| transform(h, i).translation)
            .sum::<Vec3>()
            / 3.0
    };
    let (c0, before) = (centre(&h), transform(&h, stones[0]).translation);
    h.state_mut().viewport.snap.grid = true;
    h.state_mut().viewport.snap.step = 1.0;
    drag_handle(&mut h, c0, 2, Modifiers::NONE);
    let c1 = centre(&h);
    assert!(on_multiple(c1.z, 1.0), "centre z = {}", c1.z);
    assert!((c1.z - c0.z).abs() > 0.1);
    let d = transform(&h, stones[0]).translation - before;
    assert!((d.z - (c1.z - c0.z)).abs() < 1e-4, "each moved as much");
}

#[test]
fn angle_snap_turns_by_multiples_of_the_angle() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    // Trilithon 1 upright L: rotation (0, 20, 0).
    click_row(&mut h, 1, Modifiers::NONE);
    let start = transform(&h, 1);
    assert_eq!(start.rotation.y, 20.0);
    h.state_mut().viewport.snap.angle = true;
    h.state_mut().viewport.snap.angle_step = 15.0;
    h.key_press(Key::E);
    h.run();
    drag_handle(&mut h, start.translation, 1, Modifiers::NONE);
    let turned = transform(&h, 1);
    assert!(
        on_multiple(turned.rotation.y, 15.0),
        "yaw = {}",
        turned.rotation.y
    );
    assert_ne!(turned.rotation.y, 20.0);
    assert_eq!(turned.translation, start.translation);
    // With angle snap off, the same drag lands off the multiples of 15 (20 + a free angle).
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    h.state_mut().viewport.snap.angle = false;
    drag_handle(&mut h, start.translation, 1, Modifiers::NONE);
    let free = transform(&h, 1).rotation.y;
    assert!(!on_multiple(free, 15.0), "free yaw = {free}");
}

/// Clicks Add → `what` and returns the new entity's translation (then undoes the add).
fn add(h: &mut Harness<'_, EditorApp>, what: &str) -> Vec3 {
    h.key_press(Key::Escape);
    h.run();
    let n = h.state().state.scene().len();
    h.get_by_label("Add").click();
    h.run();
    h.get_by_label(what).click();
    h.run();
    assert_eq!(h.state().state.scene().len(), n + 1, "{what} added");
    let at = transform(h, n).translation;
    // Taken out again, so the next one is not landed on it.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(h.state().state.scene().len(), n);
    at
}

#[test]
fn add_lands_on_the_surface_under_the_centre() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    // Look down at the altar stone's top (y = 0.5) from above.
    let top = Vec3::new(0.6, 0.5, 0.4);
    let cam = &mut h.state_mut().viewport.camera;
    cam.pitch_deg = -60.0;
    cam.focus(top, 5.0);
    h.run();
    let on_altar = add(&mut h, "Box");
    // A unit box stands on it: its centre half a unit above the point.
    assert!(
        (on_altar - (top + Vec3::Y * 0.5)).length() < 0.01,
        "{on_altar}"
    );
    let light = add(&mut h, "Point light");
    assert!((light - (top + Vec3::Y * 2.0)).length() < 0.01, "{light}");
    // Hidden, the altar is not landed on: the ground under it is.
    h.state_mut().state.set_hidden(ALTAR, true);
    let through = add(&mut h, "Box");
    let ground = h.state().viewport.ground_focus();
    assert!(ground.y.abs() < 1e-4);
    assert!(
        (through - (ground + Vec3::Y * 0.5)).length() < 0.02,
        "{through}"
    );
    h.state_mut().state.set_hidden(ALTAR, false);
    // With surface snap off: the ground plane under the centre, the altar ignored.
    h.state_mut().viewport.snap.surface = false;
    let off = add(&mut h, "Box");
    assert!((off - through).length() < 0.02, "{off}");
}

#[test]
fn the_outliner_filters_by_name_and_component() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let n = h.state().state.scene().len();
    let shown = |h: &Harness<'_, EditorApp>| -> Vec<usize> {
        (0..n)
            .filter(|&i| h.query_by_label(&outliner_label(h, i)).is_some())
            .collect()
    };
    assert_eq!(shown(&h).len(), n);
    h.get_by_label("Filter by name").click();
    h.run();
    h.get_by_label("Filter by name").type_text("STANDING");
    h.run();
    assert_eq!(shown(&h), (10..=18).collect::<Vec<_>>(), "any case");
    h.state_mut().outliner.text = "stone".into();
    h.run();
    // The standing stones, the fallen, altar and heel stones.
    assert_eq!(shown(&h), (10..=21).collect::<Vec<_>>());
    h.state_mut().outliner.text.clear();
    h.run();
    h.get_by_label("Component filter").click();
    h.run();
    h.get_by_label("light").click();
    h.run();
    assert_eq!(shown(&h), [22, 23], "the sun and the lantern");
    h.state_mut().outliner.kind = texel_editor::ui::hierarchy::KindFilter::Geometry;
    h.state_mut().outliner.text = "trilithon 2".into();
    h.run();
    assert_eq!(shown(&h), [4, 5, 6]);
}

#[test]
fn a_hidden_entity_is_not_drawn_but_is_saved() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let original = h.state().state.scene().to_level();
    let eye = format!("Hide {}", name(&h, ALTAR));
    h.get_by_label(&eye).click();
    h.run();
    assert!(h.state().state.is_hidden(ALTAR));
    // The rows the viewport's worker is handed: the altar keeps its place (ids stay the
    // document's) with nothing to draw; every other row as it is.
    let drawn = h.state().state.render_level();
    assert_eq!(drawn.entities.len(), original.entities.len());
    for (i, (d, o)) in drawn.entities.iter().zip(&original.entities).enumerate() {
        if i == ALTAR {
            assert!(d.geometry.is_none() && d.material.is_none(), "{d:?}");
            assert_eq!((&d.name, d.transform), (&o.name, o.transform));
        } else {
            assert_eq!(d, o);
        }
    }
    // Saved whole, and not a change to the level.
    assert!(!h.state().state.is_dirty());
    h.state_mut()
        .state
        .add(texel_scene::EntityRow::default())
        .expect("edit");
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    let path = dir.path().join("levels/stone_circle.ron");
    let text = std::fs::read_to_string(&path).expect("saved");
    let saved = texel_scene::Level::from_ron_str(&text, &path).expect("loads");
    assert_eq!(saved.entities[ALTAR], original.entities[ALTAR]);
    // Shown again: drawn again.
    h.get_by_label(&eye).click();
    h.run();
    assert!(!h.state().state.is_hidden(ALTAR));
    assert!(
        h.state().state.render_level().entities[ALTAR]
            .geometry
            .is_some()
    );
}

#[test]
fn a_locked_entity_is_not_box_selected_nor_moved() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let i = STANDING_STONE_1;
    let lock = format!("Lock {}", name(&h, i));
    h.get_by_label(&lock).click();
    h.run();
    assert!(h.state().state.is_locked(i) && !h.state().state.pickable(i));
    // The outliner still selects it; the gizmo does not move it.
    click_row(&mut h, i, Modifiers::NONE);
    assert_eq!(h.state().state.selected(), [i]);
    let start = transform(&h, i).translation;
    let n = steps(&h);
    drag_handle(&mut h, start, 0, Modifiers::NONE);
    assert_eq!(transform(&h, i).translation, start);
    assert_eq!(steps(&h), n, "no step");
    // A box around its origin selects nothing (it replaces the selection with nothing).
    let at = projector(&h).project(start).expect("in view");
    let d = egui::vec2(10.0, 10.0);
    drag(&mut h, at - d, at + d, Modifiers::NONE);
    assert!(h.state().state.selected().is_empty());
    // Unlocked: the same box takes it.
    h.get_by_label(&lock).click();
    h.run();
    drag(&mut h, at - d, at + d, Modifiers::NONE);
    assert_eq!(h.state().state.selected(), [i]);
    // Picking goes through `EditorState::pickable` (the viewport's pick answer filtered).
}
