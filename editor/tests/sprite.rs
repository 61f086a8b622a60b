//! Sprites in the editor, driven through egui_kittest (no GPU): Add → Sprite makes an entity
//! of the sheet (its path relative to the level), a file that is not an image is refused and
//! nothing added; each inspector edit of the sprite is one undo step; values the level would
//! refuse (a frame size that does not divide the sheet, an fps of 0, frames off the sheet, a
//! map of another size, a geometry beside the sprite) are refused with a message and change
//! nothing; typed paths load or are undone; the preview shows the frame `Sprite::frame_at`
//! gives, uploads the sheet once, and plays.

use std::path::{Path, PathBuf};

use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::{UVec2, Vec2};
use texel_editor::app::EditorApp;
use texel_editor::files::Recent;
use texel_editor::ui::dialogs::{Prompt, Purpose};
use texel_editor::ui::menu::Action;
use texel_scene::sprite::{Billboard, Sprite, SpriteAnimation, SpriteSize};
use texel_scene::{EntityRow, Name, Scene, Transform};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The bundled walker: 24×32 frames on a 120×256 sheet, 8 directions, walking and idle.
fn walker() -> Sprite {
    let anim = |name: &str, frames: &[u32], fps| SpriteAnimation {
        name: name.into(),
        frames: frames.to_vec(),
        fps,
    };
    Sprite {
        animations: vec![anim("walk", &[1, 2, 3, 4], 8.0), anim("idle", &[0], 1.0)],
        directions: 8,
        ..Sprite::new(
            "sprites/walker.png",
            UVec2::new(24, 32),
            SpriteSize::World(Vec2::new(1.44, 1.92)),
        )
    }
}

/// A level in `dir` with the walker standing at the origin and a tuft of grass (a 32×16
/// sheet), and some bundled sheets in `sprites/` beside it.
fn walker_level(dir: &Path) -> PathBuf {
    let sprites = dir.join("sprites");
    std::fs::create_dir_all(&sprites).expect("mkdir");
    for sheet in ["walker.png", "walker_n.png", "grass_a.png", "tablet_n.png"] {
        std::fs::copy(
            workspace().join("assets/sprites").join(sheet),
            sprites.join(sheet),
        )
        .expect("copy sheet");
    }
    let mut scene = Scene::new();
    scene.spawn(EntityRow {
        name: Some(Name("Walker".into())),
        transform: Some(Transform::default()),
        sprite: Some(walker()),
        ..EntityRow::default()
    });
    scene.spawn(EntityRow {
        name: Some(Name("Grass".into())),
        transform: Some(Transform::default()),
        sprite: Some(Sprite::new(
            "sprites/grass_a.png",
            UVec2::new(16, 16),
            SpriteSize::Matched,
        )),
        ..EntityRow::default()
    });
    let path = dir.join("level.ron");
    scene.save(&path).expect("save level");
    path
}

fn harness(app: EditorApp) -> Harness<'static, EditorApp> {
    let mut h = Harness::builder()
        .with_size([1200.0, 1800.0])
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app);
    h.run();
    h
}

/// The walker level opened with the walker selected.
fn walker_harness(dir: &Path) -> Harness<'static, EditorApp> {
    let path = walker_level(dir);
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    h
}

fn selected(h: &Harness<'_, EditorApp>) -> EntityRow {
    h.state().state.selected_row().expect("a selection").1
}

fn sprite(h: &Harness<'_, EditorApp>) -> Sprite {
    selected(h).sprite.expect("a sprite")
}

fn steps(h: &Harness<'_, EditorApp>) -> usize {
    h.state().state.history.undo_len()
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

fn set_text(h: &mut Harness<'_, EditorApp>, label: &str, text: &str) {
    h.get_by_label(label).set_text_value_accesskit(text);
    h.run();
}

fn click(h: &mut Harness<'_, EditorApp>, label: &str) {
    h.get_by_label(label).click();
    h.run();
}

fn refused(h: &Harness<'_, EditorApp>) -> String {
    h.state().sprite_panel.refused.clone().expect("refused")
}

#[test]
fn add_sprite_makes_an_entity_of_the_sheet_relative_to_the_level() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = walker_level(dir.path());
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.get_by_label("Add").click();
    h.run();
    h.get_by_label("Sprite…");
    h.key_press(Key::Escape);
    h.run();

    // The typed-path prompt (where no file dialog exists) adds a sprite of the sheet.
    let before = steps(&h);
    std::fs::create_dir_all(dir.path().join("more")).expect("mkdir");
    let grass = dir.path().join("more/grass.png");
    std::fs::copy(dir.path().join("sprites/grass_a.png"), &grass).expect("copy");
    h.state_mut().dialogs.prompt = Some(Prompt {
        purpose: Purpose::Sprite,
        text: grass.display().to_string(),
    });
    h.run();
    click(&mut h, "OK");
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    assert_eq!(h.state().state.scene().len(), 3);
    assert_eq!(steps(&h), before + 1, "one undo step");
    let row = selected(&h);
    assert_eq!(row.name, Some(Name("grass".into())));
    let at = h.state().viewport.ground_focus();
    assert_eq!(row.transform.expect("a transform").translation, at);
    // A 32×16 strip: two 16×16 frames, played; a unit square quad standing on its foot.
    let s = row.sprite.expect("a sprite");
    assert_eq!(s.sheet, "more/grass.png");
    assert_eq!(s.frame_size, UVec2::new(16, 16));
    assert_eq!(s.animations[0].frames, vec![0, 1]);
    assert_eq!(s.size, SpriteSize::World(Vec2::ONE));
    assert_eq!(
        (s.pivot, s.billboard),
        (Vec2::new(0.5, 1.0), Billboard::Upright)
    );
    let assets = &h.state().state.document.level.assets;
    let sheet = assets.sprite_sheet(&s).expect("the sheet is loaded");
    assert_eq!((sheet.width, sheet.height), (32, 16));
    h.get_by_label("[sprite] grass");

    // It saves and loads back as it is.
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    let reloaded = Scene::load(&path).expect("reload");
    assert_eq!(reloaded.to_level(), h.state().state.scene().to_level());

    undo(&mut h);
    assert_eq!(h.state().state.scene().len(), 2);
}

#[test]
fn a_sheet_that_is_not_an_image_is_refused_and_nothing_added() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = walker_harness(dir.path());
    let before = (h.state().state.scene().len(), steps(&h));
    let garbage = dir.path().join("sprites/garbage.png");
    std::fs::write(&garbage, b"not a png").expect("write");
    for file in [garbage, dir.path().join("sprites/missing.png")] {
        h.state_mut().act(Action::AddSpritePath(file.clone()));
        h.run();
        let error = h.state().dialogs.error.clone().expect("an error is shown");
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            error.contains("cannot add the sprite") && error.contains(&name),
            "{error}"
        );
        assert_eq!((h.state().state.scene().len(), steps(&h)), before);
        click(&mut h, "OK");
    }
    // An untitled level has nowhere for a relative path to start from.
    let mut h = harness(EditorApp::with_recent(None, Recent::default()));
    let grass = workspace().join("assets/sprites/grass_a.png");
    h.state_mut().act(Action::AddSpritePath(grass));
    h.run();
    let error = h.state().dialogs.error.clone().expect("an error is shown");
    assert!(error.contains("save the level first"), "{error}");
    assert!(h.state().state.scene().is_empty());
}

#[test]
fn each_sprite_edit_is_one_undo_step() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = walker_harness(dir.path());
    let start = steps(&h);
    set(&mut h, "Pivot Y", 0.5);
    assert_eq!(sprite(&h).pivot, Vec2::new(0.5, 0.5));
    click(&mut h, "Billboard Fixed");
    assert_eq!(sprite(&h).billboard, Billboard::Fixed);
    click(&mut h, "Size Matched");
    assert_eq!(sprite(&h).size, SpriteSize::Matched);
    // Back to world units: the frame's proportions, one unit high.
    click(&mut h, "Size World");
    assert_eq!(sprite(&h).size, SpriteSize::World(Vec2::new(0.75, 1.0)));
    set(&mut h, "Sprite width", 2.0);
    assert_eq!(sprite(&h).size, SpriteSize::World(Vec2::new(2.0, 1.0)));
    click(&mut h, "1 direction");
    assert_eq!(sprite(&h).directions, 1);
    click(&mut h, "Sprite casts shadows");
    assert!(sprite(&h).casts_shadows);
    click(&mut h, "Sprite outlined");
    assert!(!sprite(&h).outlined);
    set(&mut h, "Animation 1 fps", 12.0);
    assert_eq!(sprite(&h).animations[0].fps, 12.0);
    set_text(&mut h, "Animation 1 frames", "4, 3, 2");
    assert_eq!(sprite(&h).animations[0].frames, vec![4, 3, 2]);
    set_text(&mut h, "Animation 2 name", "stand");
    assert_eq!(sprite(&h).animations[1].name, "stand");
    click(&mut h, "Add animation");
    let added = &sprite(&h).animations[2];
    assert_eq!(
        (added.name.as_str(), added.frames.as_slice()),
        ("animation 3", &[0][..])
    );
    click(&mut h, "Remove animation 1");
    assert_eq!(sprite(&h).animations.len(), 2);
    assert_eq!(sprite(&h).animations[0].name, "stand");
    // Typed and left with Enter, as a person types.
    h.get_by_label("Animation 2 name").focus();
    h.run();
    h.key_press(Key::End);
    h.run();
    h.get_by_label("Animation 2 name").type_text("b");
    h.run();
    assert_eq!(
        sprite(&h).animations[1].name,
        "animation 3",
        "taken when left"
    );
    h.key_press(Key::Enter);
    h.run();
    assert_eq!(sprite(&h).animations[1].name, "animation 3b");

    let edits = steps(&h) - start;
    assert_eq!(edits, 14, "one undo step per edit");
    for _ in 0..edits {
        undo(&mut h);
    }
    assert_eq!(sprite(&h), walker());
    click(&mut h, "Remove Sprite");
    assert_eq!(selected(&h).sprite, None);
    undo(&mut h);
    assert_eq!(sprite(&h), walker());
}

#[test]
fn values_the_level_would_refuse_are_refused_with_a_message() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = walker_harness(dir.path());
    let start = steps(&h);
    // 23 does not divide the sheet's 120 pixels.
    set(&mut h, "Frame width", 23.0);
    let why = refused(&h);
    assert!(
        why.contains("frame size 23×32 does not divide the sheet's 120×256"),
        "{why}"
    );
    h.get_by_label_contains("Refused: frame size 23×32");
    assert_eq!((sprite(&h), steps(&h)), (walker(), start));
    // 40 divides it, but frame 3 is then in row 1, and 8 directions need 8 rows below it.
    set(&mut h, "Frame width", 40.0);
    assert!(refused(&h).contains("frame 3 is in row 1"));
    assert_eq!((sprite(&h), steps(&h)), (walker(), start));
    // 12 fits: taken, and the message goes.
    set(&mut h, "Frame width", 12.0);
    assert_eq!(sprite(&h).frame_size, UVec2::new(12, 32));
    assert_eq!(h.state().sprite_panel.refused, None);
    undo(&mut h);

    let refuse = |h: &mut Harness<'_, EditorApp>, what: &str| {
        let why = refused(h);
        assert!(why.contains(what), "{why}");
        assert_eq!((sprite(h), steps(h)), (walker(), start));
    };
    set(&mut h, "Animation 1 fps", 0.0);
    refuse(&mut h, "fps must be positive");
    // Frame 12 is in row 2: 8 directions need rows 2..=9 of a sheet with 8.
    set_text(&mut h, "Animation 1 frames", "1, 12");
    refuse(&mut h, "frame 12 is in row 2");
    set_text(&mut h, "Animation 1 frames", "1, two");
    refuse(&mut h, "`two` is not a frame number");
    set_text(&mut h, "Animation 1 frames", "");
    refuse(&mut h, "an animation needs at least one frame");
    set_text(&mut h, "Animation 2 name", "walk");
    refuse(&mut h, "two animations are called `walk`");
    set_text(&mut h, "Sprite sheet path", " ");
    refuse(&mut h, "sheet path is empty");
    // A refraction needs a relief.
    set_text(&mut h, "Refraction back depth path", "sprites/walker_n.png");
    refuse(&mut h, "a refraction needs a relief");
    // A map of another size than the sheet: refused at once when it is loaded (the grass's
    // sheet is)...
    set_text(&mut h, "Sprite normal map path", "sprites/grass_a.png");
    refuse(&mut h, "must be the size of its sheet");
    // ...and by the loader, which undoes the edit, when it is not.
    set_text(&mut h, "Sprite normal map path", "sprites/tablet_n.png");
    let error = h
        .state()
        .dialogs
        .error
        .clone()
        .expect("the loader refuses it");
    assert!(
        error.contains("maps must be the size of its sheet"),
        "{error}"
    );
    assert!(error.contains("undone"), "{error}");
    assert_eq!((sprite(&h), steps(&h)), (walker(), start));
    click(&mut h, "OK");
    // A sprite entity has no geometry and keeps its transform.
    click(&mut h, "Add Geometry");
    refuse(&mut h, "a sprite entity has no mesh");
    assert!(selected(&h).geometry.is_none());
    // Nor a terrain; and an animator does not leave with a refused transform.
    click(&mut h, "Add Terrain");
    refuse(&mut h, "an entity with a terrain cannot have a sprite");
    click(&mut h, "Add Animator");
    let start = steps(&h);
    click(&mut h, "Remove Transform");
    let why = refused(&h);
    assert!(why.contains("placed by its entity's transform"), "{why}");
    let row = selected(&h);
    assert!(row.transform.is_some() && row.animator.is_some());
    assert_eq!(steps(&h), start);
}

#[test]
fn typed_paths_load_or_are_undone() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = walker_harness(dir.path());
    assert_eq!(h.state().sprite_panel.uploads, 1);
    // Another sheet of the same size: loaded once typing stops, and previewed.
    set_text(&mut h, "Sprite sheet path", "sprites/walker_n.png");
    assert_eq!(h.state().dialogs.error, None);
    assert_eq!(sprite(&h).sheet, "sprites/walker_n.png");
    let assets = &h.state().state.document.level.assets;
    assert!(assets.texture("sprites/walker_n.png").is_some());
    assert_eq!(h.state().sprite_panel.uploads, 2);
    // A normal map of the sheet's size; then a relief.
    set_text(&mut h, "Sprite normal map path", "sprites/walker.png");
    assert_eq!(sprite(&h).normal_map.as_deref(), Some("sprites/walker.png"));
    set_text(&mut h, "Relief depth map path", "sprites/walker.png");
    assert_eq!(sprite(&h).relief.as_ref().map(|r| r.depth), Some(0.5));
    set(&mut h, "Relief depth", 1.25);
    assert_eq!(sprite(&h).relief.as_ref().map(|r| r.depth), Some(1.25));
    set_text(&mut h, "Refraction back depth path", "sprites/walker.png");
    set(&mut h, "Index ratio", 0.5);
    assert_eq!(
        sprite(&h).refraction.as_ref().map(|r| r.index_ratio),
        Some(0.5)
    );
    set(&mut h, "Index ratio", 0.1);
    assert!(refused(&h).contains("index ratio must be in 0.2..=5.0"));
    // An empty path takes the map away.
    set_text(&mut h, "Sprite normal map path", "");
    assert_eq!(sprite(&h).normal_map, None);
    // A missing file: shown, and the edit that named it undone.
    let before = sprite(&h);
    set_text(&mut h, "Sprite sheet path", "sprites/missing.png");
    let error = h.state().dialogs.error.clone().expect("an error is shown");
    assert!(
        error.contains("missing.png") && error.contains("undone"),
        "{error}"
    );
    assert_eq!(sprite(&h), before);
}

#[test]
fn the_preview_shows_the_frame_frame_at_gives() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = walker_harness(dir.path());
    let s = walker();
    let sheet = UVec2::new(120, 256);
    let uv_of = |frame: u32| {
        let (x, y, w, h) = s.frame_rect(sheet, frame);
        let (sw, sh) = (120.0, 256.0);
        egui::Rect::from_min_max(
            egui::pos2(x as f32 / sw, y as f32 / sh),
            egui::pos2((x + w) as f32 / sw, (y + h) as f32 / sh),
        )
    };
    click(&mut h, "Pause preview");
    assert!(!h.state().sprite_panel.preview.playing);
    // Seen from the back-left (direction 3), walking.
    h.get_by_label("Direction").click();
    h.run();
    click(&mut h, "3 back-left");
    assert_eq!(h.state().sprite_panel.preview.direction, 3);
    for t in [0.0, 0.1, 0.125, 0.3, 0.49, 0.5, 7.77] {
        h.state_mut().sprite_panel.preview.time = t;
        h.run();
        let want = s.frame_at(sheet, 0, t, 3);
        let shown = h
            .state()
            .sprite_panel
            .preview
            .shown
            .expect("a frame is drawn");
        assert_eq!(shown.frame, want, "t {t}");
        assert_eq!(shown.uv, uv_of(want), "t {t}");
        assert!(shown.zoom >= 1);
        let step = texel_editor::ui::sprite_section::step_at(&s.animations[0], t);
        h.get_by_label(&format!("Frame {}/4 · sheet frame {want}", step + 1));
    }
    // One frame on: paused, on the next.
    h.state_mut().sprite_panel.preview.time = 0.0;
    h.run();
    click(&mut h, "Next frame");
    let p = h.state().sprite_panel.preview.clone();
    assert_eq!(
        p.shown.expect("drawn").frame,
        s.frame_at(sheet, 0, p.time, 3)
    );
    assert_eq!(p.shown.expect("drawn").frame, 2 + 3 * 5);
    click(&mut h, "Previous frame");
    click(&mut h, "Previous frame");
    assert_eq!(
        h.state().sprite_panel.preview.shown.expect("drawn").frame,
        4 + 3 * 5
    );
    // Playing: the clock runs, and the frame is still frame_at's.
    click(&mut h, "Play preview");
    let t0 = h.state().sprite_panel.preview.time;
    h.run_steps(3);
    let p = h.state().sprite_panel.preview.clone();
    assert!(p.time > t0, "the clock runs");
    assert_eq!(
        p.shown.expect("drawn").frame,
        s.frame_at(sheet, 0, p.time, 3)
    );
    // The other animation; the sheet was uploaded once through all of it.
    h.get_by_label("Animation").click();
    h.run();
    click(&mut h, "idle");
    h.get_by_label_contains("Frame 1/1 · sheet frame 15");
    assert_eq!(h.state().sprite_panel.uploads, 1);
}
