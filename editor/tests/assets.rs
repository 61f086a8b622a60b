//! The asset panel, driven through egui_kittest without a GPU, on a copy of stone_circle
//! (its asset folders linked, its palettes and a broken PNG copied or written beside it,
//! never in `assets/`): it lists the project's meshes, textures, sprite sheets and palettes;
//! the first frame shows placeholders while the thumbnails are made on their thread; dropping
//! a mesh tile on the viewport adds one entity on the surface under the pointer (one undo
//! step); a palette tile sets the level's palette; a broken PNG shows as broken and dropping
//! it changes nothing but the error dialog; a clicked tile is added at the view's centre.

use crate::support;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use egui::{Event, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::Vec3;
use texel_editor::app::EditorApp;
use texel_editor::assets::thumbs::Thumb;
use texel_editor::assets::{AssetDrag, AssetKind};
use texel_editor::camera::Projector;
use texel_editor::files::Recent;
use texel_editor::ui::menu::Action;
use texel_scene::Geometry;

/// A copy of stone_circle in `dir/levels`, the bundled palettes copied into `dir/palettes`
/// and a PNG that is not one in `dir/extra`; an editor on it with the asset panel shown,
/// one frame drawn.
fn editor(dir: &Path) -> Harness<'static, EditorApp> {
    let path = support::bundled_copy(dir, "stone_circle");
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/palettes");
    std::fs::create_dir_all(dir.join("palettes")).expect("palettes");
    for name in ["texel-ember.pal", "texel-meadow.hex", "texel-night.gpl"] {
        std::fs::copy(bundled.join(name), dir.join("palettes").join(name)).expect("palette");
    }
    std::fs::create_dir_all(dir.join("extra")).expect("extra");
    std::fs::write(dir.join("extra/broken.png"), b"\x89PNG but not really").expect("png");
    let mut app = EditorApp::with_recent(Some(&path), Recent::default());
    app.assets.open = true;
    // Held, the thumbnail loader makes nothing: frames must go on without it.
    app.assets.thumbs.hold(true);
    let mut h = Harness::builder()
        .with_size([1200.0, 800.0])
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app);
    h.step();
    wait_for_walk(&mut h);
    h
}

/// Runs frames until the walk of the project folder has answered (at most 30 s).
fn wait_for_walk(h: &mut Harness<'_, EditorApp>) {
    let start = Instant::now();
    while h.state().assets.walking() {
        assert!(start.elapsed() < Duration::from_secs(30), "the folder walk");
        std::thread::sleep(Duration::from_millis(10));
        h.step();
    }
}

/// Lets the thumbnail loader go on and runs frames until no thumbnail is being made (at most 30 s).
fn wait_for_thumbnails(h: &mut Harness<'_, EditorApp>) {
    h.state().assets.thumbs.hold(false);
    let start = Instant::now();
    loop {
        h.step();
        if h.state().assets.thumbs.pending() == 0 {
            return;
        }
        assert!(start.elapsed() < Duration::from_secs(30), "thumbnails");
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn shown(h: &Harness<'_, EditorApp>, kind: AssetKind) -> Vec<String> {
    let scan = h.state().assets.scan.clone().expect("a scan");
    (scan.files.iter())
        .filter(|f| f.kind == kind)
        .map(|f| f.shown.clone())
        .collect()
}

fn asset(dir: &Path, rel: &str, kind: AssetKind) -> AssetDrag {
    AssetDrag {
        path: dir.join(rel),
        kind,
    }
}

/// Drags with the primary button from `from` to `to` over a few frames.
fn drag(h: &mut Harness<'_, EditorApp>, from: Pos2, to: Pos2) {
    h.event(Event::PointerMoved(from));
    h.step();
    let button = |pos, pressed| Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    h.event(button(from, true));
    h.step();
    for k in 1..=6 {
        h.event(Event::PointerMoved(from + (to - from) * (k as f32 / 6.0)));
        h.step();
    }
    h.event(button(to, false));
    h.step();
    h.step();
}

/// Looks down at the altar stone's top (y = 0.5) from above; returns that point.
fn look_at_altar(h: &mut Harness<'_, EditorApp>) -> Vec3 {
    let top = Vec3::new(0.6, 0.5, 0.4);
    let cam = &mut h.state_mut().viewport.camera;
    cam.pitch_deg = -60.0;
    cam.focus(top, 5.0);
    h.step();
    top
}

fn steps(h: &Harness<'_, EditorApp>) -> usize {
    h.state().state.history.undo_len()
}

#[test]
fn the_panel_lists_the_projects_assets_and_makes_thumbnails_off_the_frame() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let meshes = shown(&h, AssetKind::Mesh);
    assert_eq!(
        meshes,
        ["meshes/arch.glb", "meshes/crate.glb", "meshes/obelisk.gltf"]
    );
    let textures = shown(&h, AssetKind::Texture);
    assert!(
        textures.contains(&"textures/bricks.png".to_owned()),
        "{textures:?}"
    );
    assert!(textures.contains(&"extra/broken.png".to_owned()));
    let sprites = shown(&h, AssetKind::Sprite);
    assert!(
        sprites.contains(&"sprites/walker.png".to_owned()),
        "{sprites:?}"
    );
    assert!(!textures.iter().any(|t| t.starts_with("sprites/")));
    assert_eq!(
        shown(&h, AssetKind::Palette),
        [
            "palettes/texel-ember.pal",
            "palettes/texel-meadow.hex",
            "palettes/texel-night.gpl"
        ]
    );
    // The loader is held: the frames asked for the thumbnails on screen and go on with
    // placeholders (were a frame waiting for an image, this test would hang here).
    for _ in 0..3 {
        h.step();
    }
    let first = h.state().assets.thumbs.pending();
    assert!(first > 0, "placeholders while the loader works");
    let bricks = dir.path().join("textures/bricks.png");
    assert!(matches!(
        h.state().assets.thumbs.peek(&bricks),
        Some(Thumb::Pending)
    ));
    h.get_by_label("crate.glb");
    wait_for_thumbnails(&mut h);
    let Some(Thumb::Image(tex)) = h.state().assets.thumbs.peek(&bricks) else {
        panic!("the bricks' thumbnail is an image");
    };
    let [w, hh] = tex.size();
    assert!(w <= 48 && hh <= 48 && w.max(hh) > 8, "{w}×{hh}");
    let ember = dir.path().join("palettes/texel-ember.pal");
    let Some(Thumb::Swatches(c)) = h.state().assets.thumbs.peek(&ember) else {
        panic!("the palette's swatches");
    };
    assert!(c.len() > 2);
    // View → Asset panel hides it.
    h.state_mut().act(Action::ToggleAssetPanel);
    h.run();
    assert!(h.query_by_label("crate.glb").is_none());
}

#[test]
fn dropping_a_mesh_adds_one_entity_on_the_surface_under_the_pointer() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    let top = look_at_altar(&mut h);
    // Drop it a little off the centre, on the altar's top.
    let target = top + Vec3::new(0.2, 0.0, 0.1);
    let app = h.state();
    let rect = app.viewport.rect.expect("the viewport was drawn");
    let to = Projector::new(&app.viewport.render_camera(), rect)
        .project(target)
        .expect("on screen");
    let from = h.get_by_label("crate.glb").rect().center();
    let (n, undo) = (h.state().state.scene().len(), steps(&h));
    drag(&mut h, from, to);
    assert_eq!(h.state().dialogs.error, None);
    assert_eq!(h.state().state.scene().len(), n + 1, "one entity added");
    assert_eq!(steps(&h), undo + 1, "one undo step");
    let row = h.state().state.row_at(n).expect("the new row");
    assert_eq!(
        row.geometry,
        Some(Geometry::Mesh {
            path: "../meshes/crate.glb".into()
        })
    );
    let at = row.transform.expect("a transform").translation;
    assert!((at - target).length() < 0.05, "{at} vs {target}");
    h.state_mut().act(Action::Undo);
    h.step();
    assert_eq!(h.state().state.scene().len(), n, "undo takes it out");
}

#[test]
fn dropping_a_palette_sets_the_level_palette() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    assert!(h.state().state.scene().palette.is_none());
    let to = h.state().viewport.rect.expect("viewport").center();
    h.get_by_label("Palettes").click();
    h.step();
    let from = h.get_by_label("texel-meadow.hex").rect().center();
    let undo = steps(&h);
    drag(&mut h, from, to);
    assert_eq!(h.state().dialogs.error, None);
    let palette = h.state().state.scene().palette.clone().expect("a palette");
    assert_eq!(palette.file, "../palettes/texel-meadow.hex");
    assert_eq!(steps(&h), undo + 1, "one undo step");
}

#[test]
fn a_broken_png_shows_as_broken_and_dropping_it_changes_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    h.get_by_label("Textures").click();
    h.step();
    wait_for_thumbnails(&mut h);
    let broken: PathBuf = dir.path().join("extra/broken.png");
    assert!(
        matches!(
            h.state().assets.thumbs.peek(&broken),
            Some(Thumb::Broken(_))
        ),
        "shown as broken"
    );
    let (n, undo) = (h.state().state.scene().len(), steps(&h));
    let at = Some(Vec3::new(0.0, 0.0, 3.0));
    for kind in [AssetKind::Texture, AssetKind::Sprite] {
        h.state_mut().dialogs.error = None;
        let drop = asset(dir.path(), "extra/broken.png", kind);
        h.state_mut().act(Action::PlaceAsset(drop, at));
        let error = h.state().dialogs.error.clone().expect("the error dialog");
        assert!(error.contains("broken.png"), "{error}");
        assert_eq!(h.state().state.scene().len(), n);
        assert_eq!(steps(&h), undo);
    }
    // A good texture dropped the same way is a textured box standing there.
    h.state_mut().dialogs.error = None;
    let bricks = asset(dir.path(), "textures/bricks.png", AssetKind::Texture);
    h.state_mut().act(Action::PlaceAsset(bricks, at));
    assert_eq!(h.state().dialogs.error, None);
    let row = h.state().state.row_at(n).expect("the box");
    let texture = row.material.and_then(|m| m.texture).expect("textured");
    assert_eq!(texture.path, "../textures/bricks.png");
    let y = row.transform.expect("transform").translation.y;
    assert!((y - 0.5).abs() < 1e-4, "stands on the point: {y}");
}

#[test]
fn a_clicked_tile_is_added_at_the_view_centre() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = editor(dir.path());
    look_at_altar(&mut h);
    h.get_by_label("Sprites").click();
    h.step();
    h.get_by_label("walker.png").click();
    h.run();
    let n = h.state().state.scene().len();
    h.get_by_label("Add walker.png at view centre").click();
    h.step();
    assert_eq!(h.state().dialogs.error, None);
    assert_eq!(h.state().state.scene().len(), n + 1);
    let row = h.state().state.row_at(n).expect("the sprite");
    assert_eq!(row.sprite.expect("a sprite").sheet, "../sprites/walker.png");
    let at = row.transform.expect("transform").translation;
    let centre = h.state().viewport.place_point(&h.state().state);
    assert!((at - centre).length() < 0.05, "{at} vs {centre}");
}

/// The walk of the project folder runs on its own thread: held, the frames go on and the
/// panel says it is looking; let go, the list comes.
#[test]
fn frames_go_on_while_the_project_folder_is_walked() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = support::bundled_copy(dir.path(), "stone_circle");
    let app = EditorApp::with_recent(Some(&path), Recent::default());
    app.assets.hold_walks(true);
    let mut h = Harness::builder()
        .with_size([1200.0, 800.0])
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app);
    h.state_mut().assets.open = true;
    for _ in 0..3 {
        h.step();
    }
    assert!(h.state().assets.walking() && h.state().assets.scan.is_none());
    h.get_by_label("Looking through the project's folders…");
    h.state().assets.hold_walks(false);
    wait_for_walk(&mut h);
    assert!(shown(&h, AssetKind::Mesh).contains(&"meshes/crate.glb".to_owned()));
}
