//! The inspector's animator section driven through egui_kittest (no GPU): add, each field
//! edit one undo step, kinds switched, path keys added and removed, a refused value kept
//! out, the animator leaving with the transform (and coming back with it on undo), the add
//! button disabled where a level cannot hold an animator, and a save that reloads the same.

use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use glam::Vec3;
use texel_editor::app::EditorApp;
use texel_editor::files::Recent;
use texel_editor::ui::animator::default_animator;
use texel_scene::animator::{Animator, Easing, Motion};
use texel_scene::{EntityRow, Scene};

fn harness() -> Harness<'static, EditorApp> {
    let mut h = Harness::builder()
        .with_size([1200.0, 1400.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::with_recent(None, Recent::default()),
        );
    h.run();
    h
}

fn add_from_menu(h: &mut Harness<'_, EditorApp>, item: &str) {
    h.get_by_label("Add").click();
    h.run();
    h.get_by_label(item).click();
    h.run();
}

fn selected(h: &Harness<'_, EditorApp>) -> EntityRow {
    h.state().state.selected_row().expect("a selection").1
}

fn animator(h: &Harness<'_, EditorApp>) -> Option<Animator> {
    selected(h).animator
}

fn undo(h: &mut Harness<'_, EditorApp>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
}

fn set(h: &mut Harness<'_, EditorApp>, label: &str, v: f64) {
    h.get_by_role_and_label(Role::SpinButton, label)
        .set_value_accesskit(v);
    h.run();
}

#[test]
fn animators_are_added_edited_and_undone_one_step_at_a_time() {
    let mut h = harness();
    add_from_menu(&mut h, "Box");
    let steps = h.state().state.history.undo_len();
    h.get_by_label("Add Animator").click();
    h.run();
    assert_eq!(animator(&h), Some(default_animator()));

    set(&mut h, "Speed", 90.0);
    assert!(matches!(
        animator(&h).unwrap().motion,
        Motion::Rotate { speed: 90.0, .. }
    ));
    // Zero is no speed: the level would refuse it, so the inspector does not take it.
    set(&mut h, "Speed", 0.0);
    assert!(matches!(
        animator(&h).unwrap().motion,
        Motion::Rotate { speed: 90.0, .. }
    ));
    set(&mut h, "Phase", 1.5);
    assert_eq!(animator(&h).unwrap().phase, 1.5);

    // Ping-pong: the other end starts 2 units along X from the box.
    h.get_by_label("Motion Ping-pong").click();
    h.run();
    let Motion::PingPong { to, period, easing } = animator(&h).unwrap().motion else {
        panic!("ping-pong")
    };
    let base = selected(&h).transform.unwrap();
    assert_eq!(to.translation, base.translation + Vec3::X * 2.0);
    assert_eq!((period, easing), (4.0, Easing::Smooth));
    set(&mut h, "Period", 6.0);
    h.get_by_label("Linear").click();
    h.run();
    set(&mut h, "To translation Y", 3.0);
    let Motion::PingPong { to, period, easing } = animator(&h).unwrap().motion else {
        panic!("ping-pong")
    };
    assert_eq!(
        (to.translation.y, period, easing),
        (3.0, 6.0, Easing::Linear)
    );

    // Path: two keys, one added between the second and the period, then removed.
    h.get_by_label("Motion Path").click();
    h.run();
    h.get_by_label("Add key after 2").click();
    h.run();
    let path = |h: &Harness<'_, EditorApp>| match animator(h).unwrap().motion {
        Motion::Path { keys, period } => (keys, period),
        other => panic!("{other:?}"),
    };
    let (keys, period) = path(&h);
    let times: Vec<f32> = keys.iter().map(|k| k.time).collect();
    assert_eq!((times, period), (vec![0.0, 2.0, 3.0], 4.0));
    set(&mut h, "Key 3 translation Y", 2.5);
    set(&mut h, "Key 2 time", 1.0);
    let (keys, _) = path(&h);
    assert_eq!((keys[1].time, keys[2].translation.y), (1.0, 2.5));
    h.get_by_label("Remove key 2").click();
    h.run();
    assert_eq!(path(&h).0.len(), 2);
    assert!(
        h.get_by_label("Remove key 2")
            .accesskit_node()
            .is_disabled(),
        "two keys are always left"
    );
    // Each of those edits was one step (the refused speed none): undoing them all leaves
    // the box as it was added.
    let edits = h.state().state.history.undo_len() - steps;
    assert_eq!(edits, 12, "one undo step per edit");
    for _ in 0..edits {
        undo(&mut h);
    }
    assert_eq!(animator(&h), None);
    assert_eq!(h.state().state.history.undo_len(), steps);
}

#[test]
fn the_animator_goes_with_the_transform_and_saves() {
    let mut h = harness();
    add_from_menu(&mut h, "Box");
    h.get_by_label("Add Animator").click();
    h.run();
    h.get_by_label("Remove Transform").click();
    h.run();
    let row = selected(&h);
    assert!(row.transform.is_none() && row.animator.is_none());
    // Now there is nothing to move.
    assert!(
        h.get_by_label("Add Animator")
            .accesskit_node()
            .is_disabled()
    );
    undo(&mut h);
    let row = selected(&h);
    assert!(row.transform.is_some() && row.animator == Some(default_animator()));
    h.get_by_label("Remove Animator").click();
    h.run();
    assert_eq!(animator(&h), None);
    undo(&mut h);

    // A sun has no transform, a terrain does not move.
    add_from_menu(&mut h, "Directional light");
    assert!(
        h.get_by_label("Add Animator")
            .accesskit_node()
            .is_disabled()
    );
    add_from_menu(&mut h, "Terrain");
    assert!(selected(&h).terrain.is_some());
    assert!(
        h.get_by_label("Add Animator")
            .accesskit_node()
            .is_disabled()
    );

    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("animated.ron");
    h.state_mut().state.save_as(&path).expect("save");
    let reloaded = Scene::load(&path).expect("reload");
    assert_eq!(reloaded.to_level(), h.state().state.scene().to_level());
    assert_eq!(
        reloaded.to_level().entities[0].animator,
        Some(default_animator())
    );
}
