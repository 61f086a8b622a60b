//! The palette tools, driven through egui_kittest without a GPU: a palette picked (through
//! the command path a file dialog ends in), its dither and alternate; swatches shown and a
//! swatch edit as one undo step; saving writes the level and the edited palette file (in
//! its own format, atomically) and a reload shows the edited colours; an autosave keeps
//! unsaved swatch edits and recovering it brings them back; a bad palette file is an error
//! dialog naming its line, and nothing changes; Night (N) toggles.

use std::path::{Path, PathBuf};

use egui::Key;
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use texel_editor::app::EditorApp;
use texel_editor::files::Recent;
use texel_editor::history::MergeKey;
use texel_editor::palette_edits::Slot;
use texel_editor::ui::menu::Action;
use texel_scene::Scene;
use texel_scene::palette::Palette;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A copy of stone_circle in `dir/levels`, and copies of the shipped palettes in
/// `dir/palettes` (never the shipped files themselves: saving writes palettes).
fn level_and_palettes(dir: &Path) -> PathBuf {
    let levels = dir.join("levels");
    let palettes = dir.join("palettes");
    std::fs::create_dir_all(&levels).expect("levels");
    std::fs::create_dir_all(&palettes).expect("palettes");
    for name in ["texel-meadow.hex", "texel-night.gpl", "texel-ember.pal"] {
        std::fs::copy(
            workspace().join("assets/palettes").join(name),
            palettes.join(name),
        )
        .expect("copy palette");
    }
    let to = levels.join("stone_circle.ron");
    std::fs::copy(workspace().join("assets/levels/stone_circle.ron"), &to).expect("copy level");
    to
}

fn harness(path: &Path) -> Harness<'static, EditorApp> {
    let mut h = Harness::builder()
        .with_size([1200.0, 900.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::with_recent(Some(path), Recent::default()),
        );
    h.run();
    h
}

/// The level's palette and alternate picked as the file dialog would.
fn pick_both(h: &mut Harness<'_, EditorApp>, dir: &Path) {
    let palettes = dir.join("palettes");
    let main = palettes.join("texel-ember.pal");
    h.state_mut().act(Action::PalettePath(Slot::Main, main));
    let night = palettes.join("texel-night.gpl");
    h.state_mut()
        .act(Action::PalettePath(Slot::Alternate, night));
    h.run();
}

#[test]
fn a_palette_picked_shows_as_swatches_and_saves_with_the_level() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_and_palettes(dir.path());
    let mut h = harness(&path);
    assert!(h.state().state.scene().palette.is_none());
    assert!(!h.state().state.is_dirty());
    pick_both(&mut h, dir.path());
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    let setting = h.state().state.scene().palette.clone().expect("a palette");
    assert_eq!(setting.file, "../palettes/texel-ember.pal");
    assert_eq!(
        setting.alternate.as_deref(),
        Some("../palettes/texel-night.gpl")
    );
    assert!(h.state().state.is_dirty());
    assert!(h.state().title().contains('*'));
    // Eight swatches of the day palette, twelve of the night one.
    h.get_by_label("Day swatch 7");
    assert!(h.query_by_label("Day swatch 8").is_none());
    h.get_by_label("Night swatch 11");

    // Dither from the slider, one step.
    h.get_by_role_and_label(Role::Slider, "Dither")
        .set_value_accesskit(0.75);
    h.run();
    let dither = h.state().state.scene().palette.as_ref().map(|p| p.dither);
    assert_eq!(dither, Some(0.75));

    // Undo steps back through dither, alternate, palette.
    for _ in 0..3 {
        h.state_mut().act(Action::Undo);
    }
    h.run();
    assert!(h.state().state.scene().palette.is_none());
    assert!(!h.state().state.is_dirty());
    for _ in 0..3 {
        h.state_mut().act(Action::Redo);
    }
    h.run();
    h.key_press_modifiers(egui::Modifiers::COMMAND, Key::S);
    h.run();
    assert!(!h.state().state.is_dirty());
    let saved = Scene::load(&path).expect("reload");
    assert_eq!(saved.palette.as_ref().map(|p| p.dither), Some(0.75));
    assert_eq!(saved.palette, h.state().state.scene().palette);
}

#[test]
fn a_swatch_edit_is_one_undo_step_and_saving_writes_the_palette() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_and_palettes(dir.path());
    let mut h = harness(&path);
    pick_both(&mut h, dir.path());
    h.key_press_modifiers(egui::Modifiers::COMMAND, Key::S);
    h.run();
    let file = dir.path().join("palettes/texel-night.gpl");
    let original = Palette::load(&file).expect("night");
    let text_before = std::fs::read_to_string(&file).expect("read");
    assert!(
        text_before.contains("Night sky"),
        "unedited palettes are not written again"
    );
    let undo_before = h.state().state.history.undo_len();

    // A colour picker drag: many changes under one gesture.
    let key = Some(MergeKey::Palette {
        widget: egui::Id::unique("picker"),
    });
    let rel = "../palettes/texel-night.gpl";
    for g in [10u8, 60, 120, 200] {
        (h.state_mut().state.set_swatch(rel, 3, [250, g, 5], key)).expect("swatch");
    }
    h.state_mut().state.history.seal();
    h.run();
    assert_eq!(h.state().state.history.undo_len(), undo_before + 1);
    assert!(h.state().state.is_dirty());
    let edited = |h: &Harness<'_, EditorApp>| {
        let assets = &h.state().state.document.level.assets;
        assets.palette(rel).expect("loaded").colours[3]
    };
    assert_eq!(edited(&h), [250, 200, 5]);
    h.state_mut().act(Action::Undo);
    h.run();
    assert_eq!(edited(&h), original.colours[3], "one undo undoes the drag");
    assert!(!h.state().state.is_dirty());
    h.state_mut().act(Action::Redo);
    h.run();
    assert_eq!(edited(&h), [250, 200, 5]);

    h.key_press_modifiers(egui::Modifiers::COMMAND, Key::S);
    h.run();
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    let on_disk = Palette::load(&file).expect("written");
    assert_eq!(on_disk.colours[3], [250, 200, 5]);
    assert_eq!(on_disk.colours.len(), original.colours.len());
    let text = std::fs::read_to_string(&file).expect("read");
    assert!(
        text.starts_with("GIMP Palette\n"),
        "the format it was read in: {text}"
    );
    let ember = std::fs::read_to_string(dir.path().join("palettes/texel-ember.pal"));
    assert!(ember.expect("ember").starts_with("JASC-PAL"));
    // Written atomically: nothing but the palettes is left in their folder.
    let names: Vec<String> = std::fs::read_dir(dir.path().join("palettes"))
        .expect("folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 3, "{names:?}");

    // Opened again, the level shows the edited colours.
    let h2 = harness(&path);
    let assets = &h2.state().state.document.level.assets;
    assert_eq!(
        assets.palette(rel).expect("loaded").colours[3],
        [250, 200, 5]
    );
}

#[test]
fn a_bad_palette_file_is_an_error_and_nothing_changes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_and_palettes(dir.path());
    let mut h = harness(&path);
    pick_both(&mut h, dir.path());
    let before = h.state().state.scene().to_level();
    let undo = h.state().state.history.undo_len();
    let bad = dir.path().join("palettes/bad.hex");
    std::fs::write(&bad, "00ff00\nnot a colour\n").expect("write");
    h.state_mut().act(Action::PalettePath(Slot::Main, bad));
    h.run();
    let e = h.state().dialogs.error.clone().expect("an error dialog");
    assert!(e.contains("bad.hex:2"), "{e}");
    h.get_by_label(&e);
    assert_eq!(h.state().state.scene().to_level(), before);
    assert_eq!(h.state().state.history.undo_len(), undo);
    let missing = dir.path().join("palettes/none.gpl");
    h.state_mut().act(Action::PalettePath(Slot::Main, missing));
    let e = h.state().dialogs.error.clone().expect("an error dialog");
    assert!(e.contains("none.gpl"), "{e}");
    assert_eq!(h.state().state.scene().to_level(), before);
}

#[test]
fn night_toggles_with_n_and_the_palette_comes_off_undoably() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_and_palettes(dir.path());
    let mut h = harness(&path);
    assert!(!h.state().viewport.night);
    pick_both(&mut h, dir.path());
    h.key_press(Key::N);
    h.run();
    assert!(h.state().viewport.night, "N shows the alternate");
    h.get_by_label("Night (N)").click();
    h.run();
    assert!(!h.state().viewport.night, "the toolbar button toggles back");

    h.get_by_label("No Alternate").click();
    h.run();
    let setting = h.state().state.scene().palette.clone().expect("kept");
    assert_eq!(setting.alternate, None);
    h.get_by_label("No Palette").click();
    h.run();
    assert!(h.state().state.scene().palette.is_none());
    h.state_mut().act(Action::Undo);
    h.run();
    assert_eq!(h.state().state.scene().palette, Some(setting));
}

/// Swatch edits not yet saved ride in the autosave as `name.autosave.gpl` beside the
/// palette; recovering after a crash brings the colours back under the palette's own name,
/// and saving writes them there and removes what the autosave kept.
#[test]
fn an_autosave_keeps_unsaved_swatch_edits_and_recovering_brings_them_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = level_and_palettes(dir.path());
    let mut h = harness(&path);
    pick_both(&mut h, dir.path());
    h.key_press_modifiers(egui::Modifiers::COMMAND, Key::S);
    h.run();
    let rel = "../palettes/texel-night.gpl";
    (h.state_mut().state.set_swatch(rel, 3, [250, 200, 5], None)).expect("swatch");
    h.state_mut().autosave_now();
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    let auto = texel_editor::files::autosave_path(&path);
    let kept = dir.path().join("palettes/texel-night.autosave.gpl");
    let colours = Palette::load(&kept).expect("the autosave keeps the edited palette");
    assert_eq!(colours.colours[3], [250, 200, 5]);
    let autosaved = Scene::load(&auto).expect("autosave");
    let setting = autosaved.palette.expect("a palette");
    assert_eq!(
        setting.alternate.as_deref(),
        Some("../palettes/texel-night.autosave.gpl")
    );
    assert_eq!(
        setting.file, "../palettes/texel-ember.pal",
        "unedited: named as it is"
    );
    let file = dir.path().join("palettes/texel-night.gpl");
    assert_ne!(
        Palette::load(&file).expect("night").colours[3],
        [250, 200, 5]
    );

    // A crash, then recovery: the colours come back, named as the level will save them.
    drop(h);
    let level_time = std::fs::metadata(&path)
        .and_then(|m| m.modified())
        .expect("time");
    std::fs::File::options()
        .write(true)
        .open(&auto)
        .and_then(|f| f.set_modified(level_time + std::time::Duration::from_secs(60)))
        .expect("set time");
    let mut h = harness(&path);
    h.get_by_label("Recover").click();
    h.run();
    assert!(h.state().state.is_dirty());
    let document = &h.state().state.document;
    let setting = document.level.scene.palette.clone().expect("a palette");
    assert_eq!(setting.alternate.as_deref(), Some(rel));
    let back = document.level.assets.palette(rel).expect("loaded");
    assert_eq!(back.colours[3], [250, 200, 5]);
    assert!(document.palettes_edited(), "not saved yet");

    // Saving writes the palette and forgets the autosave and what it kept.
    h.key_press_modifiers(egui::Modifiers::COMMAND, Key::S);
    h.run();
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    assert_eq!(
        Palette::load(&file).expect("night").colours[3],
        [250, 200, 5]
    );
    assert!(!auto.exists() && !kept.exists());
}
