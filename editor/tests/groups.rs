//! Groups, driven through egui_kittest without a GPU: Group (Ctrl+G) and Ungroup
//! (Ctrl+Shift+G), reparenting by dragging outliner rows, each one undo step that keeps every
//! entity's place in the world; the gizmo moving a group moves its children; delete,
//! duplicate, copy and paste carry a group's children; the filter shows a child with its
//! ancestors; the tree saves and loads back equal.

use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::Vec3;
use texel_editor::app::EditorApp;
use texel_editor::camera::Projector;
use texel_editor::ui::hierarchy::{OutlinerFilter, lines};
use texel_editor::ui::widgets::display_name;
use texel_editor::viewport::gizmo;
use texel_scene::{Level, Name, Scene, Transform};

use crate::support;

use support::{click_row, editor, outliner_label};

fn level(h: &Harness<'_, EditorApp>) -> Level {
    h.state().state.scene().to_level()
}

fn steps(h: &Harness<'_, EditorApp>) -> usize {
    h.state().state.history.undo_len()
}

fn undo(h: &mut Harness<'_, EditorApp>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
}

fn redo(h: &mut Harness<'_, EditorApp>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    h.run();
}

/// World transforms by name.
fn world(h: &Harness<'_, EditorApp>, name: &str) -> Transform {
    let scene = h.state().state.scene();
    let e = scene
        .entities()
        .find(|&e| scene.world().get::<&Name>(e).is_ok_and(|n| n.0 == name))
        .unwrap_or_else(|| panic!("no {name}"));
    *scene.world().get::<&Transform>(e).expect("a transform")
}

fn index(h: &Harness<'_, EditorApp>, name: &str) -> usize {
    let rows = level(h).entities;
    rows.iter()
        .position(|r| r.name.as_ref().is_some_and(|n| n.0 == name))
        .unwrap_or_else(|| panic!("no {name}"))
}

fn parent(h: &Harness<'_, EditorApp>, name: &str) -> Option<String> {
    let rows = level(h).entities;
    rows[index(h, name)].parent.clone().map(|n| n.0)
}

const STONES: [&str; 3] = ["Standing stone 1", "Standing stone 2", "Standing stone 3"];

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-3
}

/// Selects the three stones (rows 10 to 12) and groups them.
fn group_stones(h: &mut Harness<'_, EditorApp>) {
    click_row(h, 10, Modifiers::NONE);
    click_row(h, 12, Modifiers::SHIFT);
    h.key_press_modifiers(Modifiers::COMMAND, Key::G);
    h.run();
}

#[test]
fn group_and_ungroup_keep_places_are_one_step_each_and_save() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let before = level(&h);
    let places: Vec<Transform> = STONES.iter().map(|s| world(&h, s)).collect();
    group_stones(&mut h);
    assert_eq!(steps(&h), 1, "Group is one undo step");
    assert_eq!(
        index(&h, "Group"),
        10,
        "the group goes before its first child"
    );
    assert_eq!(h.state().state.selected(), [10], "the group is selected");
    let centre = places.iter().map(|t| t.translation).sum::<Vec3>() / 3.0;
    assert!(close(world(&h, "Group").translation, centre));
    for (s, t) in STONES.iter().zip(&places) {
        assert_eq!(parent(&h, s).as_deref(), Some("Group"), "{s}");
        assert_eq!(world(&h, s), *t, "{s} stays where it was");
    }
    // The outliner shows them under the group, one level in, and folds them away.
    let shown = |h: &Harness<'_, EditorApp>| {
        let app = h.state();
        let rows: Vec<_> = app.state.scene().to_level().entities;
        lines(&app.state, &app.outliner, &rows)
    };
    let tree = shown(&h);
    let at = tree
        .iter()
        .position(|l| l.index == 10)
        .expect("group shown");
    assert!(tree[at].parent && tree[at].depth == 0);
    assert_eq!(
        tree[at + 1..at + 4]
            .iter()
            .map(|l| (l.index, l.depth))
            .collect::<Vec<_>>(),
        [(11, 1), (12, 1), (13, 1)]
    );
    h.get_by_label("Fold Group").click();
    h.run();
    assert!(
        h.query_by_label(&outliner_label(&h, 11)).is_none(),
        "folded"
    );
    h.get_by_label("Unfold Group").click();
    h.run();
    assert!(h.query_by_label(&outliner_label(&h, 11)).is_some());

    // Saved and opened again: the same tree, the same places.
    let file = dir.path().join("grouped.ron");
    h.state_mut().state.save_as(&file).expect("save");
    let text = std::fs::read_to_string(&file).expect("read");
    assert!(text.contains("parent: \"Group\""), "{text}");
    let loaded = Scene::load(&file).expect("load");
    assert_eq!(loaded.to_level(), level(&h));

    undo(&mut h);
    assert_eq!(level(&h), before, "undone whole");
    redo(&mut h);
    assert_eq!(parent(&h, STONES[1]).as_deref(), Some("Group"));

    // Ungroup: the stones back at the root, where they are; the group gone.
    let n = steps(&h);
    click_row(&mut h, 10, Modifiers::NONE);
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::G);
    h.run();
    assert_eq!(steps(&h), n + 1, "Ungroup is one undo step");
    assert_eq!(level(&h), before, "as before grouping");
    assert_eq!(
        h.state().state.selected(),
        [10, 11, 12],
        "the children are selected"
    );
    undo(&mut h);
    assert_eq!(parent(&h, STONES[2]).as_deref(), Some("Group"));
    for (s, t) in STONES.iter().zip(&places) {
        assert_eq!(world(&h, s), *t, "{s}");
    }
}

/// Drags the row `from` onto the row `to` (or, for `None`, onto the space below the rows).
fn drag_row(h: &mut Harness<'_, EditorApp>, from: usize, to: Option<usize>) {
    let start = h.get_by_label(&outliner_label(h, from)).rect().center();
    let end = match to {
        Some(t) => h.get_by_label(&outliner_label(h, t)).rect().center(),
        None => {
            let last = h.state().state.scene().len() - 1;
            h.get_by_label(&outliner_label(h, last)).rect().center() + egui::vec2(0.0, 60.0)
        }
    };
    h.hover_at(start);
    h.run();
    h.drag_at(start);
    h.step();
    for k in 1..=6 {
        h.hover_at(start + (end - start) * (k as f32 / 6.0));
        h.step();
    }
    h.drop_at(end);
    h.run();
}

#[test]
fn dragging_a_row_onto_another_reparents_it_where_it_is() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let before = level(&h);
    let stone = world(&h, STONES[0]);
    let other = display_name(&before.entities[11], 11);
    drag_row(&mut h, 10, Some(11));
    assert_eq!(
        parent(&h, STONES[0]),
        Some(other.clone()),
        "dropped onto row 11"
    );
    assert_eq!(steps(&h), 1, "one undo step");
    let moved = world(&h, STONES[0]);
    assert!(close(moved.translation, stone.translation), "{moved:?}");
    assert!(close(moved.rotation, stone.rotation), "{moved:?}");
    // Onto itself's child: refused, nothing changes.
    let err = h.state_mut().state.reparent(&[11], Some(10));
    assert!(err.is_err(), "a parent cannot go into its child");
    // Below the rows: back to the root.
    drag_row(&mut h, 10, None);
    assert_eq!(parent(&h, STONES[0]), None);
    assert_eq!(steps(&h), 2);
    assert_eq!(level(&h), before, "where it was, at the root");
    undo(&mut h);
    undo(&mut h);
    assert_eq!(level(&h), before);
    // A selected row dragged onto another selected row: the rest of the selection goes in.
    click_row(&mut h, 10, Modifiers::NONE);
    click_row(&mut h, 12, Modifiers::SHIFT);
    drag_row(&mut h, 10, Some(12));
    assert_eq!(parent(&h, STONES[0]).as_deref(), Some(STONES[2]));
    assert_eq!(parent(&h, STONES[1]).as_deref(), Some(STONES[2]));
    assert_eq!(parent(&h, STONES[2]), None);
    assert!(h.state().dialogs.error.is_none());
}

fn projector(h: &Harness<'_, EditorApp>) -> Projector {
    let app = h.state();
    let rect = app.viewport.rect.expect("the viewport was drawn");
    Projector::new(&app.viewport.render_camera(), rect)
}

/// Drags the primary button from `from` to `to` over a few frames.
fn drag(h: &mut Harness<'_, EditorApp>, from: egui::Pos2, to: egui::Pos2) {
    h.hover_at(from);
    h.run();
    h.drag_at(from);
    h.step();
    for k in 1..=4 {
        h.hover_at(from + (to - from) * (k as f32 / 4.0));
        h.step();
    }
    h.drop_at(to);
    h.run();
}

#[test]
fn the_gizmo_moves_a_group_with_its_children() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    group_stones(&mut h);
    let starts: Vec<Vec3> = STONES.iter().map(|s| world(&h, s).translation).collect();
    let centre = world(&h, "Group").translation;
    let proj = projector(&h);
    let (o, ends) = gizmo::handles(&proj, centre).expect("the group is in view");
    let on_x = o + (ends[0] - o) * 0.7;
    let n = steps(&h);
    drag(&mut h, on_x, on_x + (ends[0] - o).normalized() * 60.0);
    assert_eq!(steps(&h), n + 1, "the drag is one undo step");
    let dx = world(&h, "Group").translation.x - centre.x;
    assert!(dx.abs() > 0.1, "the group moved: {dx}");
    for (s, start) in STONES.iter().zip(&starts) {
        let now = world(&h, s).translation;
        assert!(close(now, *start + Vec3::X * dx), "{s}: {now} {start}");
    }
    // Saved, each stone's transform relative to the group is what it was.
    let rows = level(&h).entities;
    assert!(close(
        rows[11].transform.expect("t").translation,
        starts[0] - centre
    ));
}

#[test]
fn delete_duplicate_copy_and_paste_carry_a_groups_children() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    group_stones(&mut h);
    let grouped = level(&h);
    let n = grouped.entities.len();

    // Duplicate the group: a group of copies, under a name of its own.
    h.key_press_modifiers(Modifiers::COMMAND, Key::D);
    h.run();
    assert_eq!(level(&h).entities.len(), n + 4);
    for s in STONES {
        let copy = format!("{s} copy");
        assert_eq!(parent(&h, &copy).as_deref(), Some("Group copy"), "{copy}");
        assert_eq!(
            world(&h, &copy),
            world(&h, s),
            "{copy} where its original is"
        );
    }
    undo(&mut h);
    assert_eq!(level(&h), grouped);

    // Copy and paste: the pasted group is renamed, its children follow.
    click_row(&mut h, 10, Modifiers::NONE);
    h.event(egui::Event::Copy);
    h.step();
    let text = h.state().copied().expect("copied").to_owned();
    assert!(Level::from_ron_str(&text, std::path::Path::new("clip")).is_ok());
    h.event(egui::Event::Paste(text));
    h.run();
    assert_eq!(level(&h).entities.len(), n + 4);
    assert_eq!(index(&h, "Group 2"), n, "pasted at the end, renamed");
    let pasted = &level(&h).entities[n + 1..];
    for (row, s) in pasted.iter().zip(STONES) {
        assert_eq!(row.parent, Some(Name("Group 2".into())), "{s}");
    }
    undo(&mut h);

    // Delete the group: its children go with it, in one step; undo brings all back.
    click_row(&mut h, 10, Modifiers::NONE);
    let k = steps(&h);
    h.key_press(Key::Delete);
    h.run();
    assert_eq!(level(&h).entities.len(), n - 4);
    assert_eq!(steps(&h), k + 1);
    undo(&mut h);
    assert_eq!(level(&h), grouped);
}

#[test]
fn a_moving_group_carries_its_children_and_they_take_no_animator() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    group_stones(&mut h);
    let n = steps(&h);
    h.get_by_label("Add Animator").click();
    h.run();
    assert_eq!(steps(&h), n + 1, "the group moves");
    assert!(level(&h).entities[10].animator.is_some());
    let scene = h.state().state.scene();
    let moving: Vec<usize> = (scene.animated_poses(0.5).iter())
        .filter_map(|(e, _)| scene.index_of(*e))
        .collect();
    assert_eq!(moving, [10, 11, 12, 13], "the group and its stones");
    // A stone in the moving group cannot move by itself too.
    click_row(&mut h, 11, Modifiers::NONE);
    h.get_by_label("Add Animator").click();
    h.run();
    assert_eq!(steps(&h), n + 1, "nothing changed");
    assert!(level(&h).entities[11].animator.is_none());
    let error = h
        .state()
        .dialogs
        .error
        .clone()
        .expect("the editor says why");
    assert!(error.contains("inside a moving entity"), "{error}");
}

#[test]
fn the_filter_shows_a_matching_child_with_its_ancestors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    group_stones(&mut h);
    h.state_mut().outliner = OutlinerFilter {
        text: "stone 2".into(),
        ..OutlinerFilter::default()
    };
    h.run();
    assert!(
        h.query_by_label(&outliner_label(&h, 12)).is_some(),
        "the match"
    );
    assert!(
        h.query_by_label(&outliner_label(&h, 10)).is_some(),
        "its group"
    );
    assert!(
        h.query_by_label(&outliner_label(&h, 11)).is_none(),
        "not its sibling"
    );
}
