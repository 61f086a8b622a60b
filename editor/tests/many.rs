//! Many at once, driven through egui_kittest without a GPU: selecting several entities in
//! the outliner (Ctrl toggles, Shift a range), by box in the viewport, all and none; the
//! inspector and the gizmo on three entities; duplicate, copy, cut, paste and delete, each one
//! undo step; paste between two editors; text that is not entities refused.

use crate::support;

use support::{click_row, editor};

use egui::accesskit::Role;
use egui::{Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::Vec3;
use texel_editor::app::EditorApp;
use texel_editor::camera::Projector;
use texel_editor::files::Recent;
use texel_editor::viewport::gizmo;
use texel_scene::{EntityRow, Level};

fn selected(h: &Harness<'_, EditorApp>) -> Vec<usize> {
    h.state().state.selected()
}

fn level(h: &Harness<'_, EditorApp>) -> Level {
    h.state().state.scene().to_level()
}

fn translation(h: &Harness<'_, EditorApp>, i: usize) -> Vec3 {
    let row = h.state().state.row_at(i).expect("an entity");
    row.transform.expect("a transform").translation
}

fn undo(h: &mut Harness<'_, EditorApp>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
}

fn steps(h: &Harness<'_, EditorApp>) -> usize {
    h.state().state.history.undo_len()
}

/// Three standing stones: apart on the ground, each with a transform.
const STONES: [usize; 3] = [10, 11, 12];

fn select_stones(h: &mut Harness<'_, EditorApp>) {
    click_row(h, STONES[0], Modifiers::NONE);
    click_row(h, STONES[2], Modifiers::SHIFT);
    assert_eq!(selected(h), STONES);
}

#[test]
fn outliner_ctrl_click_toggles_and_shift_click_selects_a_range() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    click_row(&mut h, 2, Modifiers::NONE);
    assert_eq!(selected(&h), [2]);
    click_row(&mut h, 5, Modifiers::COMMAND);
    assert_eq!(selected(&h), [2, 5]);
    assert_eq!(
        h.state().state.selection,
        Some(5),
        "the last clicked is active"
    );
    click_row(&mut h, 2, Modifiers::COMMAND);
    assert_eq!(selected(&h), [5], "a second Ctrl-click takes it away");
    click_row(&mut h, 8, Modifiers::SHIFT);
    assert_eq!(
        selected(&h),
        [5, 6, 7, 8],
        "from the active one to the clicked one"
    );
    click_row(&mut h, 3, Modifiers::SHIFT);
    assert_eq!(
        selected(&h),
        [3, 4, 5],
        "the range starts at the same place"
    );
    click_row(&mut h, 1, Modifiers::NONE);
    assert_eq!(selected(&h), [1]);
}

#[test]
fn select_all_and_none_and_play_keeps_its_escape() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let n = h.state().state.scene().len();
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.run();
    assert_eq!(selected(&h), (0..n).collect::<Vec<_>>());
    h.key_press(Key::Escape);
    h.run();
    assert!(selected(&h).is_empty());
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::A);
    h.run();
    assert!(selected(&h).is_empty());
    // In Play, Esc stops Play and leaves the selection alone.
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.run();
    h.key_press(Key::F5);
    h.step();
    assert!(h.state().viewport.playing());
    h.key_press(Key::Escape);
    h.step();
    assert!(!h.state().viewport.playing());
    assert_eq!(selected(&h).len(), n);
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

#[test]
fn box_select_picks_what_is_inside() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let proj = projector(&h);
    let rect = h.state().viewport.rect.expect("drawn");
    let on_screen: Vec<(usize, Pos2)> = (0..h.state().state.scene().len())
        .filter_map(|i| {
            let t = h.state().state.row_at(i)?.transform?;
            let at = proj.project(t.translation)?;
            rect.shrink(4.0).contains(at).then_some((i, at))
        })
        .collect();
    assert!(on_screen.len() >= 5, "the default view shows the circle");
    // A small box around one origin that no other origin is near.
    let alone = |&(i, p): &(usize, Pos2)| {
        let clear = on_screen
            .iter()
            .all(|&(j, q)| j == i || (q - p).length() > 30.0);
        clear.then_some((i, p))
    };
    let lone: Vec<(usize, Pos2)> = on_screen.iter().filter_map(alone).collect();
    assert!(
        lone.len() >= 2,
        "two entities stand apart on screen: {on_screen:?}"
    );
    let (a, pa) = lone[0];
    let (b, pb) = *lone
        .iter()
        .max_by(|x, y| (x.1 - pa).length().total_cmp(&(y.1 - pa).length()))
        .expect("b");
    let d = egui::vec2(12.0, 12.0);
    drag(&mut h, pa - d, pa + d, Modifiers::NONE);
    assert_eq!(selected(&h), [a]);
    // Shift adds: from the far corner, away from the gizmo on `a`.
    drag(&mut h, pb + d, pb - d, Modifiers::SHIFT);
    let mut both = vec![a, b];
    both.sort_unstable();
    assert_eq!(selected(&h), both);
    // The whole view: everything whose origin shows.
    h.key_press(Key::Escape);
    h.run();
    drag(
        &mut h,
        rect.left_top() + egui::vec2(2.0, 2.0),
        rect.right_bottom() - egui::vec2(2.0, 2.0),
        Modifiers::NONE,
    );
    let all: Vec<usize> = on_screen.iter().map(|e| e.0).collect();
    let got = selected(&h);
    assert!(
        all.iter().all(|i| got.contains(i)),
        "{got:?} should hold {all:?}"
    );
}

#[test]
fn the_inspector_edits_three_as_one_step_and_shows_mixed_values() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    select_stones(&mut h);
    let before = level(&h);
    let xs: Vec<f32> = STONES.iter().map(|&i| translation(&h, i).x).collect();
    assert!(xs[0] != xs[1], "the stones stand apart: {xs:?}");
    let x = h.get_by_role_and_label(Role::SpinButton, "Translation X");
    assert_eq!(
        x.value().as_deref(),
        Some("\u{2014}"),
        "a mixed value shows as mixed"
    );
    let y = h.get_by_role_and_label(Role::SpinButton, "Scale Y");
    assert_ne!(
        y.value().as_deref(),
        Some("\u{2014}"),
        "a shared value shows"
    );
    let n = steps(&h);
    h.get_by_role_and_label(Role::SpinButton, "Translation Y")
        .set_value_accesskit(5.0);
    h.run();
    assert_eq!(steps(&h), n + 1, "one undo step");
    for (k, &i) in STONES.iter().enumerate() {
        assert_eq!(
            translation(&h, i),
            Vec3::new(xs[k], 5.0, translation(&h, i).z)
        );
    }
    let y = h.get_by_role_and_label(Role::SpinButton, "Translation Y");
    assert_eq!(y.value().as_deref(), Some("5.00"), "no longer mixed");
    undo(&mut h);
    assert_eq!(level(&h), before, "one undo restores all three");
    assert_eq!(selected(&h), STONES);
}

#[test]
fn the_gizmo_moves_three_as_one_step() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    select_stones(&mut h);
    let before = level(&h);
    let starts: Vec<Vec3> = STONES.iter().map(|&i| translation(&h, i)).collect();
    let centre = starts.iter().sum::<Vec3>() / 3.0;
    let proj = projector(&h);
    let (o, ends) = gizmo::handles(&proj, centre).expect("the centre is in view");
    let on_x = o + (ends[0] - o) * 0.7;
    let along = (ends[0] - o).normalized() * 60.0;
    let n = steps(&h);
    drag(&mut h, on_x, on_x + along, Modifiers::NONE);
    assert_eq!(steps(&h), n + 1, "the drag is one undo step");
    let moved: Vec<Vec3> = STONES.iter().map(|&i| translation(&h, i)).collect();
    let dx = moved[0].x - starts[0].x;
    assert!(dx.abs() > 0.1, "moved along X: {dx}");
    for (m, s) in moved.iter().zip(&starts) {
        assert!(
            (*m - *s - Vec3::X * dx).length() < 1e-4,
            "all by the same: {m} {s}"
        );
    }
    undo(&mut h);
    assert_eq!(level(&h), before);
}

fn names(h: &Harness<'_, EditorApp>) -> Vec<String> {
    level(h)
        .entities
        .iter()
        .map(|r| r.name.clone().map(|n| n.0).unwrap_or_default())
        .collect()
}

/// The text the last frame put on the clipboard (the frame of the copy: `step`, not `run`).
fn clipboard(h: &Harness<'_, EditorApp>) -> Option<String> {
    h.output()
        .platform_output
        .commands
        .iter()
        .find_map(|c| match c {
            egui::OutputCommand::CopyText(t) => Some(t.clone()),
            _ => None,
        })
}

#[test]
fn duplicate_copy_cut_paste_and_delete_are_one_step_each() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let original = level(&h);
    let n = original.entities.len();
    select_stones(&mut h);
    let stones: Vec<EntityRow> = STONES
        .iter()
        .map(|&i| original.entities[i].clone())
        .collect();

    h.key_press_modifiers(Modifiers::COMMAND, Key::D);
    h.run();
    assert_eq!(
        names(&h)[11],
        "Standing stone 1 copy",
        "each copy after its original"
    );
    assert_eq!(selected(&h), [11, 13, 15], "the copies are selected");
    assert_eq!(translation(&h, 11), translation(&h, 10), "kept in place");
    assert_eq!(steps(&h), 1);
    undo(&mut h);
    assert_eq!(level(&h), original);

    select_stones(&mut h);
    h.key_press(Key::Delete);
    h.run();
    assert_eq!(level(&h).entities.len(), n - 3);
    assert!(selected(&h).is_empty());
    assert_eq!(steps(&h), 1);
    undo(&mut h);
    assert_eq!(level(&h), original);
    assert_eq!(selected(&h), STONES, "what came back is selected");

    h.event(Event::Copy);
    h.step();
    let text = clipboard(&h).expect("copied to the clipboard");
    assert_eq!(h.state().copied(), Some(text.as_str()));
    assert_eq!(level(&h), original, "a copy changes nothing");
    h.event(Event::Cut);
    h.run();
    assert_eq!(level(&h).entities.len(), n - 3);
    assert_eq!(steps(&h), 1, "a cut is one step");
    h.event(Event::Paste(text));
    h.run();
    assert_eq!(steps(&h), 2, "a paste is one step");
    assert_eq!(level(&h).entities[n - 3..], stones[..], "pasted at the end");
    assert_eq!(
        selected(&h),
        [n - 3, n - 2, n - 1],
        "the pasted entities are selected"
    );
    undo(&mut h);
    assert_eq!(level(&h).entities.len(), n - 3);
    undo(&mut h);
    assert_eq!(level(&h), original);
}

#[test]
fn paste_takes_another_editors_copy_and_refuses_other_text() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut a = editor(&dir.path().join("a"));
    select_stones(&mut a);
    a.event(Event::Copy);
    a.step();
    let text = clipboard(&a).expect("copied");
    let stones: Vec<EntityRow> = STONES
        .iter()
        .map(|&i| level(&a).entities[i].clone())
        .collect();

    let mut b = Harness::builder()
        .with_size([1200.0, 800.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::with_recent(None, Recent::default()),
        );
    b.run();
    for bad in [
        "",
        "hello, world",
        "(version: 1, entities: [(nmae: \"x\")])",
    ] {
        b.event(Event::Paste(bad.to_owned()));
        b.run();
        let error = b.state().dialogs.error.clone().expect("a message");
        assert!(error.contains("cannot paste"), "{error}");
        b.get_by_label("OK").click();
        b.run();
        assert!(b.state().state.scene().is_empty(), "nothing changed");
        assert_eq!(steps(&b), 0);
    }
    b.event(Event::Paste(text));
    b.run();
    assert!(b.state().dialogs.error.is_none());
    assert_eq!(level(&b).entities, stones);
    assert_eq!(selected(&b), [0, 1, 2]);
    assert_eq!(steps(&b), 1);
}
