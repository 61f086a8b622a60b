//! UI flows driven through egui_kittest: add, edit in the inspector, undo, redo, save,
//! reload; probe-grid overrides reaching the probes; Play and Esc; broken levels; the
//! unsaved-changes guard, the typed-path prompt and autosave recovery.

use std::path::{Path, PathBuf};

use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use texel_editor::app::EditorApp;
use texel_editor::files::{self, Recent};
use texel_editor::ui::dialogs::{Prompt, Purpose};
use texel_editor::ui::menu::Action;
use texel_runtime::extract::{Viewport, grid_settings};
use texel_scene::{Geometry, Scene};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A copy of stone_circle in a temporary directory.
fn level_copy(dir: &Path) -> PathBuf {
    let to = dir.join("stone_circle.ron");
    std::fs::copy(workspace().join("assets/levels/stone_circle.ron"), &to).expect("copy level");
    to
}

fn harness(app: EditorApp) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size([1200.0, 800.0])
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app)
}

fn add_from_menu(h: &mut Harness<'_, EditorApp>, item: &str) {
    h.get_by_label("Add").click();
    h.run();
    h.get_by_label(item).click();
    h.run();
}

fn selected_translation_x(app: &EditorApp) -> f32 {
    let (_, row) = app.state.selected_row().expect("a selection");
    row.transform.expect("a transform").translation.x
}

#[test]
fn add_edit_undo_redo_save_reload() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_copy(dir.path());
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.run();
    let n = h.state().state.scene().len();
    assert!(!h.state().title().contains('*'));

    add_from_menu(&mut h, "Box");
    assert_eq!(h.state().state.scene().len(), n + 1);
    assert_eq!(h.state().state.selection, Some(n));
    let (_, row) = h.state().state.selected_row().expect("selected");
    assert!(matches!(row.geometry, Some(Geometry::Box { .. })));
    assert!(h.state().title().contains('*'), "{}", h.state().title());
    // Where Add put it: on the surface under the viewport's centre.
    let x0 = selected_translation_x(h.state());

    h.get_by_label("Translation X").set_value_accesskit(3.5);
    h.run();
    assert_eq!(selected_translation_x(h.state()), 3.5);

    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(selected_translation_x(h.state()), x0);
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    h.run();
    assert_eq!(selected_translation_x(h.state()), 3.5);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    h.run();
    assert_eq!(selected_translation_x(h.state()), 3.5);

    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert!(!h.state().state.is_dirty());
    assert!(!h.state().title().contains('*'));
    let reloaded = Scene::load(&path).expect("reload");
    assert_eq!(reloaded.to_level(), h.state().state.scene().to_level());
    assert_eq!(reloaded.len(), n + 1);

    // Undoing past the save marks the document modified again; undoing everything restores
    // the original level.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert!(h.state().state.is_dirty());
    let original = Scene::load(&workspace().join("assets/levels/stone_circle.ron")).expect("load");
    assert_eq!(h.state().state.scene().to_level(), original.to_level());
}

#[test]
fn probe_grid_override_reaches_the_probes() {
    let mut h = harness(EditorApp::with_recent(None, Recent::default()));
    h.run();
    add_from_menu(&mut h, "Probe-grid override");
    h.get_by_role_and_label(Role::SpinButton, "Cell size")
        .set_value_accesskit(0.25);
    h.run();
    h.get_by_label("Volume X").set_value_accesskit(10.0);
    h.run();
    let viewport = Viewport {
        height: 400,
        fov_y: 1.0,
    };
    let (_, overrides) = grid_settings(h.state().state.scene(), viewport);
    assert_eq!(overrides.len(), 1);
    let o = &overrides[0];
    assert_eq!(o.cell_size, 0.25);
    assert!((o.max.x - o.min.x - 10.0).abs() < 1e-5, "{o:?}");
    // One undo step per field edit.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    let (_, overrides) = grid_settings(h.state().state.scene(), viewport);
    assert!((overrides[0].max.x - overrides[0].min.x - 4.0).abs() < 1e-5);
    assert_eq!(overrides[0].cell_size, 0.25);
}

#[test]
fn play_then_escape_leaves_the_document_unchanged() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_copy(dir.path());
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.run();
    let before = h.state().state.scene().to_level();
    let steps = h.state().state.history.undo_len();
    h.key_press(Key::F5);
    h.step();
    assert!(h.state().viewport.playing());
    for _ in 0..5 {
        h.key_press(Key::W);
        h.step();
    }
    h.key_press(Key::Escape);
    h.step();
    assert!(!h.state().viewport.playing());
    assert_eq!(h.state().state.scene().to_level(), before);
    assert_eq!(h.state().state.history.undo_len(), steps);
    assert!(!h.state().state.is_dirty());
}

#[test]
fn broken_levels_show_their_error_and_nothing_panics() {
    let data = workspace().join("crates/scene/tests/data/levels");
    let mut shown = 0;
    let mut entries: Vec<PathBuf> = std::fs::read_dir(&data)
        .expect("broken levels")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for path in entries {
        let app = EditorApp::with_recent(Some(&path), Recent::default());
        let Some(error) = app.dialogs.error.clone() else {
            continue;
        };
        let name = path.file_name().and_then(|n| n.to_str()).expect("name");
        assert!(error.contains(name), "{error}");
        let mut h = harness(app);
        h.run();
        h.get_by_label_contains(name);
        h.get_by_label("OK").click();
        h.run();
        assert!(h.state().dialogs.error.is_none());
        shown += 1;
        if name == "syntax_error.ron" {
            let at = error.split(name).nth(1).unwrap_or_default();
            let mut parts = at.trim_start_matches(':').split(':');
            let line = parts.next().and_then(|l| l.parse::<u32>().ok());
            let col = parts.next().and_then(|c| c.trim().parse::<u32>().ok());
            assert!(line.is_some() && col.is_some(), "no line:column in {error}");
        }
    }
    assert!(shown >= 20, "only {shown} broken levels were reported");
}

#[test]
fn discarding_changes_needs_confirmation() {
    let mut h = harness(EditorApp::with_recent(None, Recent::default()));
    h.run();
    add_from_menu(&mut h, "Sphere");
    h.state_mut().act(Action::New);
    h.run();
    assert_eq!(h.state().state.scene().len(), 1, "discarded without asking");
    h.get_by_label("Keep editing").click();
    h.run();
    assert_eq!(h.state().state.scene().len(), 1);
    h.state_mut().act(Action::New);
    h.run();
    h.get_by_label("Discard").click();
    h.run();
    assert!(h.state().state.scene().is_empty());
    assert!(!h.state().state.is_dirty());
}

/// Sets the modification time of the file at `path`.
fn set_modified(path: &Path, time: std::time::SystemTime) {
    std::fs::File::options()
        .write(true)
        .open(path)
        .and_then(|f| f.set_modified(time))
        .expect("set file time");
}

#[test]
fn typed_path_saves_and_autosave_is_recovered() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("typed.ron");
    let mut h = harness(EditorApp::with_recent(None, Recent::default()));
    h.run();
    add_from_menu(&mut h, "Player start");
    h.state_mut().dialogs.prompt = Some(Prompt {
        purpose: Purpose::SaveAs,
        text: path.display().to_string(),
    });
    h.run();
    h.get_by_label("OK").click();
    h.run();
    assert!(!h.state().state.is_dirty());
    assert_eq!(Scene::load(&path).expect("saved").len(), 1);

    // A crash after an autosave: the next open offers to recover it.
    add_from_menu(&mut h, "Point light");
    h.state_mut().autosave_now();
    let auto = files::autosave_path(&path);
    assert!(auto.exists());
    // File times are set explicitly rather than waited for (file systems round them): an
    // autosave older than the level is stale, a newer one is offered.
    let saved = std::fs::metadata(&path)
        .and_then(|m| m.modified())
        .expect("level time");
    let minute = std::time::Duration::from_secs(60);
    set_modified(&auto, saved - minute);
    assert_eq!(files::recoverable(&path), None);
    set_modified(&auto, saved + minute);
    assert_eq!(files::recoverable(&path), Some(auto.clone()));
    drop(h);
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.run();
    assert_eq!(h.state().state.scene().len(), 1);
    h.get_by_label("Recover").click();
    h.run();
    assert_eq!(h.state().state.scene().len(), 2);
    assert!(h.state().state.is_dirty());
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert_eq!(Scene::load(&path).expect("saved").len(), 2);
    assert!(!files::autosave_path(&path).exists());
}

/// Work is never lost for more than a few seconds: edits reach the autosave beside the level
/// on their own (after [`files::AUTOSAVE_AFTER_EDITS`] edits or [`files::AUTOSAVE_EVERY`],
/// written beside the editor), and the level itself is never written over.
#[test]
fn edits_reach_the_autosave_within_seconds_without_a_save() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_copy(dir.path());
    let level_before = std::fs::read(&path).expect("the level");
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.run();
    let start = h.state().state.scene().len();
    let edits = files::AUTOSAVE_AFTER_EDITS as usize + 2;
    // One added, then duplicated: an edit each.
    add_from_menu(&mut h, "Cylinder");
    for _ in 1..edits {
        h.key_press_modifiers(Modifiers::COMMAND, Key::D);
        h.run();
    }
    assert_eq!(h.state().state.scene().len(), start + edits);
    let auto = files::autosave_path(&path);
    let deadline = std::time::Instant::now() + files::AUTOSAVE_EVERY * 3;
    let mut held = 0;
    while std::time::Instant::now() < deadline {
        h.run();
        if !h.state().autosave_in_flight() {
            held = Scene::load(&auto).map_or(0, |s| s.len());
            if held == start + edits {
                break;
            }
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    assert_eq!(held, start + edits, "the autosave should hold every edit");
    assert_eq!(std::fs::read(&path).expect("the level"), level_before);
    assert_eq!(files::recoverable(&path), Some(auto));
}

#[test]
fn an_untitled_document_is_autosaved_and_recovered() {
    let dir = tempfile::tempdir().expect("tempdir");
    let recent = || Recent::load(Some(dir.path().join("recent.txt")));
    let mut h = harness(EditorApp::with_recent(None, recent()));
    h.run();
    add_from_menu(&mut h, "Player start");
    add_from_menu(&mut h, "Point light");
    h.state_mut().autosave_now();
    let auto = dir.path().join("untitled.autosave.ron");
    assert_eq!(h.state().autosave_file(), Some(auto.clone()));
    assert_eq!(Scene::load(&auto).expect("autosaved").len(), 2);

    // A crash: the next untitled start offers the autosave back, untitled and modified.
    drop(h);
    let mut h = harness(EditorApp::with_recent(None, recent()));
    h.run();
    assert_eq!(h.state().state.scene().len(), 0);
    h.get_by_label("Recover").click();
    h.run();
    assert_eq!(h.state().state.scene().len(), 2);
    assert!(h.state().state.is_dirty());
    assert_eq!(h.state().state.document.path, None);

    // Saving it somewhere forgets the untitled autosave.
    let path = dir.path().join("named.ron");
    h.state_mut().save_to(&path);
    assert_eq!(Scene::load(&path).expect("saved").len(), 2);
    assert!(!auto.exists());
}

#[test]
fn hierarchy_duplicate_and_delete_are_undoable() {
    let mut h = harness(EditorApp::with_recent(None, Recent::default()));
    h.run();
    add_from_menu(&mut h, "Cylinder");
    h.key_press_modifiers(Modifiers::COMMAND, Key::D);
    h.run();
    assert_eq!(h.state().state.scene().len(), 2);
    h.get_by_label("[cyl] Cylinder copy");
    h.key_press(Key::Delete);
    h.run();
    assert_eq!(h.state().state.scene().len(), 1);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(h.state().state.scene().len(), 2);
}

#[test]
fn gltf_mesh_is_added_relative_to_the_level() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_copy(dir.path());
    let mesh = dir.path().join("meshes").join("arch.glb");
    std::fs::create_dir_all(mesh.parent().expect("dir")).expect("mkdir");
    std::fs::copy(workspace().join("assets/meshes/arch.glb"), &mesh).expect("copy mesh");
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.run();
    h.state_mut().act(Action::AddMeshPath(mesh.clone()));
    h.run();
    let (_, row) = h.state().state.selected_row().expect("selected");
    assert_eq!(
        row.geometry,
        Some(Geometry::Mesh {
            path: "meshes/arch.glb".into()
        })
    );
    assert!(
        h.state()
            .state
            .document
            .level
            .assets
            .get("meshes/arch.glb")
            .is_some()
    );
    // A path edited in the inspector is loaded once typing stops.
    std::fs::copy(&mesh, dir.path().join("meshes/arch2.glb")).expect("copy mesh");
    let (index, mut row) = h.state().state.selected_row().expect("selected");
    row.geometry = Some(Geometry::Mesh {
        path: "meshes/arch2.glb".into(),
    });
    h.state_mut()
        .state
        .set_row(index, row, None)
        .expect("set row");
    h.run();
    let meshes = &h.state().state.document.level.assets;
    assert!(meshes.get("meshes/arch2.glb").is_some());
    // A broken mesh is refused with a message, and the level is left as it was.
    let n = h.state().state.scene().len();
    let bad = workspace().join("crates/scene/tests/data/gltf/garbage.glb");
    h.state_mut().act(Action::AddMeshPath(bad));
    h.run();
    assert_eq!(h.state().state.scene().len(), n);
    assert!(h.state().dialogs.error.is_some());
}

#[test]
fn level_settings_edits_are_undoable() {
    let mut h = harness(EditorApp::with_recent(None, Recent::default()));
    h.run();
    h.get_by_role_and_label(Role::SpinButton, "Bands")
        .set_value_accesskit(7.0);
    h.run();
    assert_eq!(h.state().state.scene().settings.bands, 7);
    assert!(h.state().state.is_dirty());
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    assert_eq!(h.state().state.scene().settings.bands, 32);
    assert!(!h.state().state.is_dirty());
}

#[test]
fn a_failed_command_is_shown_in_the_error_dialog() {
    let mut app = EditorApp::with_recent(None, Recent::default());
    // A selection the scene does not have (as after an outside change): deleting it fails.
    app.state.selection = Some(3);
    app.act(Action::Delete);
    let error = app.dialogs.error.clone().expect("an error is shown");
    assert!(error.contains("no entity at position 3"), "{error}");
    assert!(app.state.scene().is_empty());
    assert_eq!(app.state.history.undo_len(), 0);
}

/// `--stats FILE`: the status bar's figures, a JSON line a second, readable by tools.
#[test]
fn stats_lines_carry_the_status_bars_figures_once_a_second() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_copy(dir.path());
    let stats = dir.path().join("stats.jsonl");
    let mut app = EditorApp::with_recent(Some(&path), Recent::default());
    app.set_stats_log(texel_editor::stats_log::StatsLog::open(&stats).expect("opens"));
    let mut h = harness(app);
    let started = std::time::Instant::now();
    while started.elapsed() < texel_editor::stats_log::EVERY + std::time::Duration::from_millis(300)
    {
        h.run();
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let text = std::fs::read_to_string(&stats).expect("the stats file");
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    assert!((2..=3).contains(&lines.len()), "{text}");
    let entities = h.state().state.scene().len() as u64;
    for line in &lines {
        for key in [
            "ui_frame_ms",
            "render_ms",
            "edit_to_frame_ms",
            "uploads",
            "t_s",
        ] {
            assert!(line[key].is_number(), "{key} in {line}");
        }
        assert_eq!(line["entities"].as_u64(), Some(entities), "{line}");
        assert_eq!(line["playing"].as_bool(), Some(false), "{line}");
    }
    assert!(lines[1]["t_s"].as_f64() >= Some(0.9), "{text}");
    // A folder is not a file to append to: said at start.
    assert!(texel_editor::stats_log::StatsLog::open(dir.path()).is_err());
}
