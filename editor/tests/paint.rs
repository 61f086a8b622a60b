//! The terrain tool's Paint brush driven through egui_kittest (no GPU): a first stroke gives
//! a terrain its paint layer (named beside the level) and is one undo step; Ctrl erases;
//! saving writes the layer as an RGBA PNG and reopening shows the same paint; unsaved paint
//! survives an asset reload, an autosave and its recovery; the inspector's "Clear paint" is
//! one undo step that undo brings back.

use std::path::Path;
use std::sync::Arc;

use egui::{Key, Modifiers, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::Vec3;
use texel_editor::app::EditorApp;
use texel_editor::camera::{EditorCamera, Projector};
use texel_editor::files::Recent;
use texel_editor::terrain::BrushKind;
use texel_scene::Scene;
use texel_scene::terrain::{PaintLayer, Terrain};
use texel_scene::texture::Image;

use crate::flat_terrain;
use flat_terrain::{FLAT, flat_level, harness};

/// The brush's colour.
const RED: [u8; 3] = [220, 30, 20];

/// Opens `path` with the terrain selected, the camera looking down at 45° at the terrain's
/// centre, and the terrain tool on with the Paint brush (red, radius 4, full opacity, half
/// of it fading).
fn painting(path: &Path) -> Harness<'static, EditorApp> {
    let mut h = harness(EditorApp::with_recent(Some(path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    let mut c = EditorCamera {
        yaw_deg: 0.0,
        pitch_deg: -45.0,
        ..EditorCamera::default()
    };
    c.focus(Vec3::new(0.0, FLAT, 0.0), 14.0);
    h.state_mut().viewport.camera = c;
    h.state_mut()
        .act(texel_editor::ui::menu::Action::ToggleTerrainTool);
    {
        let b = &mut h.state_mut().viewport.terrain.brush;
        b.kind = BrushKind::Paint;
        b.colour = RED;
        b.strength = 1.0;
        b.radius = 4.0;
        b.falloff = 0.5;
    }
    h.run();
    h
}

/// Where the world point `p` is on screen.
fn screen(h: &Harness<'_, EditorApp>, p: Vec3) -> Pos2 {
    let rect = h.state().viewport.rect.expect("viewport drawn");
    let proj = Projector::new(&h.state().viewport.camera.camera(), rect);
    proj.project(p).expect("in front of the camera")
}

/// Presses at `at`, holds for `frames` frames and releases: one stroke.
fn stroke(h: &mut Harness<'_, EditorApp>, at: Pos2, frames: usize) {
    h.hover_at(at);
    h.step();
    h.drag_at(at);
    h.step();
    for _ in 0..frames {
        h.hover_at(at);
        h.step();
    }
    h.drop_at(at);
    h.run();
}

fn terrain(h: &Harness<'_, EditorApp>) -> Terrain {
    (h.state().state.row_at(0))
        .and_then(|r| r.terrain)
        .expect("a terrain")
}

/// The selected terrain's paint layer in the library.
fn paint(h: &Harness<'_, EditorApp>) -> Option<Arc<Image>> {
    let t = terrain(h);
    h.state().state.document.level.assets.paint(&t).cloned()
}

fn press(h: &mut Harness<'_, EditorApp>, key: Key) {
    h.key_press_modifiers(Modifiers::COMMAND, key);
    h.run();
}

fn no_error(h: &Harness<'_, EditorApp>) {
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
}

/// The layer pixel whose cell holds the world point (x, z) on the 32-unit terrain.
fn pixel_at(image: &Image, x: f32, z: f32) -> [u8; 4] {
    let i = ((x + 16.0) / 32.0 * image.width as f32).floor() as u32;
    let j = ((z + 16.0) / 32.0 * image.height as f32).floor() as u32;
    image.pixel(i, j)
}

#[test]
fn a_first_paint_stroke_gives_the_terrain_a_layer_as_one_undo_step_and_ctrl_erases() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = flat_level(dir.path());
    let mut h = painting(&path);
    let steps = h.state().state.history.undo_len();
    let row_before = h.state().state.row_at(0).expect("row");
    assert_eq!(terrain(&h).paint, None);
    let heights = h
        .state()
        .state
        .document
        .level
        .assets
        .heightfield(&terrain(&h))
        .cloned();
    let at = screen(&h, Vec3::new(0.0, FLAT, 0.0));
    stroke(&mut h, at, 3);
    no_error(&h);
    assert_eq!(
        terrain(&h).paint,
        Some(PaintLayer {
            path: "flat_Flat_paint.png".into()
        })
    );
    let layer = paint(&h).expect("a layer");
    assert_eq!(
        (layer.width, layer.height),
        (33, 33),
        "the heightmap's grid"
    );
    let [r, g, b, a] = pixel_at(&layer, 0.0, 0.0);
    assert_eq!(
        [r, g, b, a],
        [RED[0], RED[1], RED[2], 255],
        "the brush's core"
    );
    let ring = pixel_at(&layer, 3.2, 0.0);
    assert!(
        ring[3] > 0 && ring[3] < 255,
        "fading toward the rim: {ring:?}"
    );
    assert_eq!(pixel_at(&layer, 10.0, -10.0), [0; 4], "far away: unpainted");
    assert_eq!(h.state().state.history.undo_len(), steps + 1);
    assert!(h.state().state.is_dirty());
    // Painting leaves the heights alone.
    let t = terrain(&h);
    assert_eq!(
        h.state()
            .state
            .document
            .level
            .assets
            .heightfield(&t)
            .cloned(),
        heights
    );

    // Undo: no layer; redo: the same one.
    press(&mut h, Key::Z);
    assert_eq!(h.state().state.row_at(0), Some(row_before));
    press(&mut h, Key::Y);
    assert_eq!(
        paint(&h).map(|p| p.pixels.clone()),
        Some(layer.pixels.clone())
    );

    // Ctrl erases: the core's cover falls, far pixels stay; one more step, on the same file.
    h.state_mut().viewport.terrain.brush.strength = 0.5;
    h.event(egui::Event::ModifiersChanged(Modifiers::CTRL));
    stroke(&mut h, at, 3);
    h.event(egui::Event::ModifiersChanged(Modifiers::NONE));
    h.run();
    let erased = paint(&h).expect("a layer");
    assert_eq!(pixel_at(&erased, 0.0, 0.0), [RED[0], RED[1], RED[2], 128]);
    assert_eq!(pixel_at(&erased, 10.0, -10.0), [0; 4]);
    assert_eq!(h.state().state.history.undo_len(), steps + 2);
    assert_eq!(
        terrain(&h).paint.map(|p| p.path),
        Some("flat_Flat_paint.png".into())
    );
    press(&mut h, Key::Z);
    assert_eq!(
        paint(&h).map(|p| p.pixels.clone()),
        Some(layer.pixels.clone())
    );
}

#[test]
fn a_painted_terrain_saves_its_layer_reopens_alike_and_clear_paint_is_undoable() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = flat_level(dir.path());
    let mut h = painting(&path);
    let at = screen(&h, Vec3::new(0.0, FLAT, 0.0));
    stroke(&mut h, at, 3);
    let painted = paint(&h).expect("a layer");
    let png = dir.path().join("flat_Flat_paint.png");
    assert!(!png.exists(), "nothing is written before saving");
    // Reloading the level's files keeps the unsaved paint.
    h.state_mut().state.reload_assets().expect("reload");
    assert_eq!(
        paint(&h).map(|p| p.pixels.clone()),
        Some(painted.pixels.clone())
    );

    // An autosave keeps the unsaved layer beside it, and recovering brings it back.
    h.state_mut().autosave_now();
    no_error(&h);
    let kept = dir.path().join("flat_Flat_paint.autosave.png");
    assert!(kept.is_file(), "the autosave keeps the unsaved paint");
    let auto = texel_editor::files::autosave_path(&path);
    let autosaved = Scene::load(&auto).expect("autosave");
    let e = autosaved.entities().next().expect("terrain");
    assert_eq!(
        autosaved
            .row(e)
            .and_then(|r| r.terrain)
            .and_then(|t| t.paint),
        Some(PaintLayer {
            path: "flat_Flat_paint.autosave.png".into()
        })
    );
    drop(h);
    let level_time = std::fs::metadata(&path)
        .and_then(|m| m.modified())
        .expect("time");
    std::fs::File::options()
        .write(true)
        .open(&auto)
        .and_then(|f| f.set_modified(level_time + std::time::Duration::from_secs(60)))
        .expect("set time");
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.get_by_label("Recover").click();
    h.run();
    h.state_mut().state.selection = Some(0);
    h.run();
    assert!(h.state().state.is_dirty());
    assert_eq!(
        terrain(&h).paint.map(|p| p.path),
        Some("flat_Flat_paint.png".into())
    );
    assert_eq!(
        paint(&h).map(|p| p.pixels.clone()),
        Some(painted.pixels.clone())
    );

    // Saving writes the layer as an RGBA PNG, forgets the autosave, and the level reopens
    // with the same paint.
    press(&mut h, Key::S);
    no_error(&h);
    assert!(!h.state().state.is_dirty());
    assert!(png.is_file() && !auto.exists() && !kept.exists());
    let reopened = EditorApp::with_recent(Some(&path), Recent::default());
    let doc = &reopened.state.document;
    let scene = doc.scene();
    let e = scene.entities().next().expect("terrain");
    let t = scene.row(e).and_then(|r| r.terrain).expect("terrain");
    let loaded = doc.level.assets.paint(&t).expect("the layer loads");
    assert_eq!(loaded.pixels, painted.pixels);

    // "Clear paint" in the inspector: no layer, one step; undo brings it back.
    let steps = h.state().state.history.undo_len();
    h.get_by_label("Clear paint").click();
    h.run();
    no_error(&h);
    assert_eq!(terrain(&h).paint, None);
    assert_eq!(h.state().state.history.undo_len(), steps + 1);
    h.get_by_label_contains("No paint layer");
    press(&mut h, Key::Z);
    assert_eq!(
        terrain(&h).paint.map(|p| p.path),
        Some("flat_Flat_paint.png".into())
    );
    assert_eq!(
        paint(&h).map(|p| p.pixels.clone()),
        Some(painted.pixels.clone())
    );
    h.get_by_label_contains("Paint layer: flat_Flat_paint.png (33×33)");
}
