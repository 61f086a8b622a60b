//! The editor's terrain tools driven through egui_kittest (no GPU): Add → Terrain and its
//! undo; the inspector's terrain fields as undo steps; the terrain tool's brushes stroked in
//! the viewport (raise and Ctrl-lower, smooth, flatten), each stroke one undo step; saving a
//! sculpted terrain writes its 16-bit heightmap beside the level and a failed write keeps the
//! document; heightmap import (refusing 8-bit files) and export; the brush's hit on a flat
//! terrain under a known cursor ray, in the perspective and the orthographic view.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use egui::accesskit::Role;
use egui::{Key, Modifiers, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::{Vec2, Vec3};
use texel_editor::app::EditorApp;
use texel_editor::camera::{EditorCamera, Projector};
use texel_editor::files::Recent;
use texel_editor::terrain::BrushKind;
use texel_editor::terrain_edits::selected_terrain;
use texel_editor::ui::menu::Action;
use texel_scene::terrain::{HeightSource, Heightfield};
use texel_scene::texture::{Image, encode_heightmap, encode_png};
use texel_scene::{EntityRow, Scene};

use crate::flat_terrain;
use flat_terrain::{FLAT, TOP, flat_level, harness};

/// A level in `dir` holding only the default terrain (baked noise).
fn noise_level(dir: &Path) -> PathBuf {
    let mut scene = Scene::new();
    scene.spawn(texel_editor::terrain::terrain_row(Vec3::ZERO));
    let path = dir.join("hills.ron");
    scene.save(&path).expect("save level");
    path
}

/// Opens `path` with its first entity (the terrain) selected, the camera looking down at
/// 45° at `look_at` from 14 units, and the terrain tool on with `kind`.
fn sculpting(path: &Path, kind: BrushKind, look_at: Vec3) -> Harness<'static, EditorApp> {
    let mut h = harness(EditorApp::with_recent(Some(path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.state_mut().viewport.camera = looking_at(look_at);
    h.state_mut().act(Action::ToggleTerrainTool);
    h.state_mut().viewport.terrain.brush.kind = kind;
    h.run();
    assert!(h.state().viewport.terrain.active);
    h
}

fn looking_at(target: Vec3) -> EditorCamera {
    let mut c = EditorCamera {
        yaw_deg: 0.0,
        pitch_deg: -45.0,
        ..EditorCamera::default()
    };
    c.focus(target, 14.0);
    c
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

fn heights(h: &Harness<'_, EditorApp>) -> Arc<Heightfield> {
    selected_terrain(&h.state().state)
        .expect("a terrain with heights")
        .field
}

fn terrain_row(h: &Harness<'_, EditorApp>) -> EntityRow {
    h.state().state.row_at(0).expect("row")
}

fn undo(h: &mut Harness<'_, EditorApp>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
}

fn redo(h: &mut Harness<'_, EditorApp>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    h.run();
}

#[test]
fn add_terrain_from_the_menu_then_undo_and_redo() {
    let mut h = harness(EditorApp::with_recent(None, Recent::default()));
    h.state_mut().viewport.camera = looking_at(Vec3::new(5.0, 0.0, -3.0));
    h.get_by_label("Add").click();
    h.run();
    h.get_by_label("Terrain").click();
    h.run();
    let state = &h.state().state;
    assert_eq!(state.scene().len(), 1);
    assert_eq!(state.selection, Some(0));
    let row = state.row_at(0).expect("row");
    let t = row.terrain.clone().expect("a terrain");
    assert_eq!(t.size, Vec2::splat(64.0));
    assert!(matches!(
        t.heightmap,
        HeightSource::Noise {
            resolution: 129,
            ..
        }
    ));
    assert_eq!(t.gradient.len(), 5);
    assert!(t.displacement.is_none());
    assert_eq!(
        (t.pixel_density, t.band_distance, t.band_transition),
        (6.0, 8.0, 0.3)
    );
    // At the view's focus on the ground.
    let at = row.transform.expect("transform").translation;
    assert!((at - Vec3::new(5.0, 0.0, -3.0)).length() < 1e-3, "{at}");
    // Its heights are baked at once, so it shows and can be sculpted.
    let field = heights(&h);
    assert_eq!((field.width, field.depth), (129, 129));
    assert!(h.state().title().contains('*'));

    undo(&mut h);
    assert!(h.state().state.scene().is_empty());
    assert!(!h.state().state.is_dirty());
    redo(&mut h);
    assert_eq!(h.state().state.row_at(0), Some(row));
    assert_eq!(h.state().state.selection, Some(0));
}

#[test]
fn terrain_fields_are_undoable_inspector_edits() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = noise_level(dir.path());
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    let steps = h.state().state.history.undo_len();
    let t0 = terrain_row(&h).terrain.expect("terrain");

    h.get_by_role_and_label(Role::SpinButton, "Max height")
        .set_value_accesskit(12.0);
    h.run();
    h.get_by_role_and_label(Role::SpinButton, "Seed")
        .set_value_accesskit(9.0);
    h.run();
    h.get_by_label("Add stop after 1").click_accesskit();
    h.run();
    // A stop's elevation stays between its neighbours: stop 2 (now at 0.075) cannot pass
    // stop 3 (at 0.15).
    h.get_by_label("Stop 2 at").set_value_accesskit(0.9);
    h.run();
    h.get_by_role_and_label(Role::SpinButton, "Band transition")
        .set_value_accesskit(5.0);
    h.run();
    let t = terrain_row(&h).terrain.expect("terrain");
    assert_eq!(t.max_height, 12.0);
    assert!(matches!(t.heightmap, HeightSource::Noise { seed: 9, .. }));
    assert_eq!(t.gradient.len(), 6);
    assert!((t.gradient[1].at - 0.15).abs() < 1e-6, "{:?}", t.gradient);
    assert_eq!(t.band_transition, 1.0, "clamped to 0..=1");
    // The new noise is baked for the new max height: the terrain still shows.
    let field = heights(&h);
    assert!(field.heights.iter().all(|v| (0.0..=12.0).contains(v)));
    assert_eq!(h.state().state.history.undo_len(), steps + 5);

    for _ in 0..5 {
        undo(&mut h);
    }
    assert_eq!(terrain_row(&h).terrain, Some(t0));

    // Switching the heights to File keeps them, saved to a file beside the level.
    let before = heights(&h);
    h.get_by_role_and_label(Role::RadioButton, "File").click();
    h.run();
    let t = terrain_row(&h).terrain.expect("terrain");
    assert_eq!(
        t.heightmap,
        HeightSource::File {
            path: "hills_Terrain.png".into()
        }
    );
    assert_eq!(*heights(&h), *before);
    assert!(h.state().dialogs.error.is_none());
}

#[test]
fn a_raise_stroke_lifts_the_centre_most_leaves_far_samples_and_ctrl_lowers() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = flat_level(dir.path());
    let centre = Vec3::new(0.0, FLAT, 0.0);
    let mut h = sculpting(&path, BrushKind::Raise, centre);
    let steps = h.state().state.history.undo_len();
    let flat = heights(&h).at(0, 0);
    assert!((flat - FLAT).abs() < 1e-4);
    let at = screen(&h, centre);
    stroke(&mut h, at, 4);
    let f = heights(&h);
    // Brush radius 4 with half of it fading: sample (16, 16) is the centre, (19, 16) is 3
    // units out (half weight), (0, 0) far away.
    let (mid, edge, far) = (f.at(16, 16), f.at(19, 16), f.at(0, 0));
    assert!(mid > flat + 0.5, "centre {mid}");
    assert!(
        edge > flat + 0.1 && edge < mid - 0.1,
        "edge {edge}, centre {mid}"
    );
    assert_eq!(far, flat, "far samples untouched");
    assert_eq!(f.at(16, 21), flat, "outside the radius");
    assert_eq!(h.state().state.history.undo_len(), steps + 1);
    assert!(h.state().state.is_dirty());

    // Ctrl inverts: the same stroke lowers.
    h.event(egui::Event::ModifiersChanged(Modifiers::CTRL));
    let at = screen(&h, Vec3::new(0.0, mid, 0.0));
    stroke(&mut h, at, 4);
    h.event(egui::Event::ModifiersChanged(Modifiers::NONE));
    h.run();
    let g = heights(&h);
    assert!(g.at(16, 16) < mid - 0.5, "{} after {mid}", g.at(16, 16));
    assert_eq!(g.at(0, 0), flat);
    assert_eq!(h.state().state.history.undo_len(), steps + 2);
}

fn variance(f: &Heightfield, centre: (i64, i64), r: i64) -> f32 {
    let mut v = Vec::new();
    for z in centre.1 - r..=centre.1 + r {
        for x in centre.0 - r..=centre.0 + r {
            v.push(f.at(x, z));
        }
    }
    let mean = v.iter().sum::<f32>() / v.len() as f32;
    v.iter().map(|h| (h - mean).powi(2)).sum::<f32>() / v.len() as f32
}

/// The sample nearest the world point `p` on the selected terrain.
fn sample_of(h: &Harness<'_, EditorApp>, p: Vec3) -> (i64, i64) {
    let place = selected_terrain(&h.state().state).expect("terrain").place;
    let g = place.to_grid(p).round();
    (g.x as i64, g.y as i64)
}

#[test]
fn smoothing_reduces_the_variance_under_the_brush() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = noise_level(dir.path());
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    // A rough patch to smooth: the noise brush, then smoothing over it.
    let target = selected_terrain(&h.state().state).expect("terrain");
    let p = target
        .place
        .surface(&target.field, Vec3::new(4.0, 0.0, 4.0));
    h.state_mut().viewport.camera = looking_at(p);
    h.state_mut().act(Action::ToggleTerrainTool);
    h.state_mut().viewport.terrain.brush.kind = BrushKind::Noise;
    h.state_mut().viewport.terrain.brush.strength = 1.0;
    h.run();
    let at = screen(&h, p);
    stroke(&mut h, at, 6);
    let s = sample_of(&h, p);
    let rough = variance(&heights(&h), s, 2);
    h.state_mut().viewport.terrain.brush.kind = BrushKind::Smooth;
    stroke(&mut h, at, 6);
    let smooth = variance(&heights(&h), s, 2);
    assert!(smooth < rough * 0.5, "variance {rough} -> {smooth}");
}

#[test]
fn flatten_levels_to_the_height_under_the_strokes_start_and_a_stroke_is_one_exact_undo_step() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = noise_level(dir.path());
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    let target = selected_terrain(&h.state().state).expect("terrain");
    let p = target
        .place
        .surface(&target.field, Vec3::new(-6.0, 0.0, 2.0));
    h.state_mut().viewport.camera = looking_at(p);
    h.state_mut().act(Action::ToggleTerrainTool);
    {
        let b = &mut h.state_mut().viewport.terrain.brush;
        b.kind = BrushKind::Flatten;
        b.strength = 1.0;
        b.falloff = 0.0;
        b.radius = 3.0;
    }
    h.run();
    let before = heights(&h);
    let row_before = terrain_row(&h);
    let steps = h.state().state.history.undo_len();
    let at = screen(&h, p);
    // Where the stroke starts: the hit under the cursor.
    h.hover_at(at);
    h.run();
    let start = h.state().viewport.terrain.hover.expect("hit") - target.place.origin;
    stroke(&mut h, at, 8);
    let after = heights(&h);
    let s = sample_of(&h, p);
    for (dx, dz) in [(0, 0), (2, 0), (-2, 1), (0, -2), (1, 1)] {
        let v = after.at(s.0 + dx, s.1 + dz);
        assert!((v - start.y).abs() < 0.01, "{v} vs {}", start.y);
    }
    assert!(variance(&after, s, 2) < variance(&before, s, 2) * 0.01);

    // One stroke, one step; the first sculpt turned the noise into a file beside the level.
    assert_eq!(h.state().state.history.undo_len(), steps + 1);
    let row = terrain_row(&h);
    assert_eq!(
        row.terrain.as_ref().map(|t| t.heightmap.clone()),
        Some(HeightSource::File {
            path: "hills_Terrain.png".into()
        })
    );
    undo(&mut h);
    assert_eq!(terrain_row(&h), row_before);
    assert_eq!(heights(&h).heights, before.heights, "every sample restored");
    redo(&mut h);
    assert_eq!(terrain_row(&h), row);
    assert_eq!(heights(&h).heights, after.heights);
}

#[test]
fn saving_writes_the_heightmap_the_level_names_and_reloads_the_same_heights() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = noise_level(dir.path());
    let p = Vec3::new(0.0, 3.0, 0.0);
    let mut h = sculpting(&path, BrushKind::Raise, p);
    let at = screen(&h, h.state().viewport.terrain.hover.unwrap_or(p));
    stroke(&mut h, at, 3);
    let sculpted = heights(&h);
    let png = dir.path().join("hills_Terrain.png");
    assert!(!png.exists(), "nothing is written before saving");
    // Reloading the level's files (a mesh added, a path typed) keeps the sculpted heights,
    // whose file does not exist yet.
    h.state_mut().state.reload_assets().expect("reload");
    assert_eq!(heights(&h), sculpted);
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    assert!(!h.state().state.is_dirty());
    assert!(png.is_file());
    let level = Scene::load(&path).expect("reload");
    let e = level.entities().next().expect("terrain");
    let t = level.row(e).and_then(|r| r.terrain).expect("terrain");
    assert_eq!(
        t.heightmap,
        HeightSource::File {
            path: "hills_Terrain.png".into()
        }
    );
    let reloaded = EditorApp::with_recent(Some(&path), Recent::default());
    let field = reloaded
        .state
        .document
        .level
        .assets
        .heightfield(&t)
        .expect("heights load")
        .clone();
    assert_eq!((field.width, field.depth), (sculpted.width, sculpted.depth));
    let worst = field
        .heights
        .iter()
        .zip(&sculpted.heights)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f32::max);
    assert!(worst <= t.max_height / 65535.0, "{worst}");

    // A save that cannot write the heightmap keeps everything: the level file, the
    // document's changes, its modified mark; the error is shown.
    let level_text = std::fs::read_to_string(&path).expect("level");
    stroke(&mut h, at, 2);
    std::fs::remove_file(&png).expect("rm");
    std::fs::create_dir(&png).expect("a folder where the heightmap goes");
    let kept = heights(&h);
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    let error = h.state().dialogs.error.clone().expect("the error is shown");
    assert!(error.contains("hills_Terrain.png"), "{error}");
    assert!(h.state().state.is_dirty());
    assert!(h.state().title().contains('*'));
    assert_eq!(heights(&h), kept);
    assert_eq!(std::fs::read_to_string(&path).expect("level"), level_text);
    h.get_by_label("OK").click();
    h.run();
    // Once the way is clear, saving works.
    std::fs::remove_dir(&png).expect("rmdir");
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert!(png.is_file() && !h.state().state.is_dirty());
}

#[test]
fn an_unsaved_document_keeps_sculpted_heights_until_save_as() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(EditorApp::with_recent(None, Recent::default()));
    h.state_mut().act(Action::AddTerrain);
    h.state_mut().act(Action::ToggleTerrainTool);
    h.run();
    let centre = selected_terrain(&h.state().state).expect("terrain");
    let p = centre.place.surface(
        &centre.field,
        centre.place.origin + Vec3::new(3.0, 0.0, 3.0),
    );
    h.state_mut().viewport.camera = looking_at(p);
    h.run();
    let at = screen(&h, p);
    stroke(&mut h, at, 3);
    let sculpted = heights(&h);
    let t = terrain_row(&h).terrain.expect("terrain");
    let HeightSource::File { path: rel } = &t.heightmap else {
        panic!("a sculpted terrain is file-backed: {:?}", t.heightmap);
    };
    assert_eq!(rel, "untitled_Terrain.png");
    let level = dir.path().join("new.ron");
    h.state_mut().save_to(&level);
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    let file = dir.path().join(rel);
    let reread = texel_editor::terrain::read_heightmap(&file, t.max_height).expect("written");
    assert_eq!((reread.width, reread.depth), (129, 129));
    assert!(
        reread
            .heights
            .iter()
            .zip(&sculpted.heights)
            .all(|(a, b)| (a - b).abs() <= t.max_height / 65535.0)
    );
}

#[test]
fn importing_refuses_eight_bit_files_and_replaces_the_heights_as_one_step() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = flat_level(dir.path());
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    let before = heights(&h);
    let steps = h.state().state.history.undo_len();

    let eight = dir.path().join("eight.png");
    let rgba = Image::solid("eight", 16, 16, [128, 128, 128, 255]);
    std::fs::write(&eight, encode_png(&rgba)).expect("write");
    h.state_mut()
        .act(Action::ImportHeightmapPath(eight.clone()));
    h.run();
    let error = h.state().dialogs.error.clone().expect("refused");
    assert!(error.contains("16-bit"), "{error}");
    h.get_by_label_contains("16-bit");
    assert_eq!(heights(&h), before);
    assert_eq!(h.state().state.history.undo_len(), steps);
    h.get_by_label("OK").click();
    h.run();
    // Too small is refused as well.
    let thin = dir.path().join("thin.png");
    std::fs::write(&thin, encode_heightmap(1, 5, &[0; 5])).expect("write");
    h.state_mut().act(Action::ImportHeightmapPath(thin));
    assert!(h.state_mut().dialogs.error.take().is_some());
    assert_eq!(heights(&h), before);

    // A 16-bit file replaces the heights (and the grid size) as one step.
    let ramp: Vec<u16> = (0..65 * 17).map(|i| (i % 65 * 1000) as u16).collect();
    let good = dir.path().join("ramp.png");
    std::fs::write(&good, encode_heightmap(65, 17, &ramp)).expect("write");
    h.state_mut().act(Action::ImportHeightmapPath(good));
    h.run();
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    let f = heights(&h);
    assert_eq!((f.width, f.depth), (65, 17));
    assert_eq!(f.to_u16(TOP), ramp);
    assert_eq!(h.state().state.history.undo_len(), steps + 1);
    undo(&mut h);
    assert_eq!(heights(&h), before);

    // Export writes what is there as a 16-bit PNG.
    let out = dir.path().join("out/exported.png");
    h.state_mut().act(Action::ExportHeightmapPath(out.clone()));
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    let (w, d, samples) = texel_scene::texture::load_heightmap(&out).expect("16-bit PNG");
    assert_eq!((w, d), (33, 33));
    assert_eq!(samples, before.to_u16(TOP));
}

#[test]
fn the_brush_lands_where_the_cursor_ray_meets_a_flat_terrain() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = flat_level(dir.path());
    let target = Vec3::new(3.0, FLAT, -5.0);
    let mut h = sculpting(&path, BrushKind::Raise, target);
    // The view's centre looks at `target`: a cursor there finds it.
    let centre = h.state().viewport.rect.expect("drawn").center();
    h.hover_at(centre);
    h.run();
    let hit = h.state().viewport.terrain.hover.expect("a hit");
    assert!((hit - target).length() < 0.02, "{hit}");
    // 100 points to the right: on the ray through that pixel, at the terrain's height.
    let rect = h.state().viewport.rect.expect("drawn");
    let proj = Projector::new(&h.state().viewport.camera.camera(), rect);
    let (o, d) = proj.ray(centre + egui::vec2(100.0, 0.0));
    let expected = o + d * ((FLAT - o.y) / d.y);
    h.hover_at(centre + egui::vec2(100.0, 0.0));
    h.run();
    let hit = h.state().viewport.terrain.hover.expect("a hit");
    assert!((hit - expected).length() < 0.02, "{hit} vs {expected}");
    // Hovering does not change the document; the brush circle is drawn.
    assert!(!h.state().state.is_dirty());
    let with_circle = h.output().shapes.len();
    // Off the terrain: no hit, no circle.
    let sky = rect.center_top() + egui::vec2(0.0, 20.0);
    h.hover_at(sky);
    h.run();
    assert!(h.state().viewport.terrain.hover.is_none());
    let without = h.output().shapes.len();
    assert!(with_circle >= without + 64, "{without} -> {with_circle}");
}

#[test]
fn in_the_orthographic_view_the_brush_lands_under_the_cursor_along_the_view() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = flat_level(dir.path());
    let target = Vec3::new(3.0, FLAT, -5.0);
    let mut h = sculpting(&path, BrushKind::Raise, target);
    h.state_mut().viewport.camera.ortho = true;
    h.run();
    let rect = h.state().viewport.rect.expect("drawn");
    h.hover_at(rect.center());
    h.run();
    let hit = h.state().viewport.terrain.hover.expect("a hit");
    assert!((hit - target).length() < 0.02, "{hit}");
    // 100 points down: the ray starts `s` world units below the centre's (the view is
    // `ortho_height` units tall) and runs along the view, parallel to the centre's.
    let cam = h.state().viewport.camera;
    let s = 100.0 * cam.ortho_height() / rect.height();
    let (forward, up) = (cam.forward(), cam.right().cross(cam.forward()));
    let expected = target - up * s + forward * (up.y * s / forward.y);
    h.hover_at(rect.center() + egui::vec2(0.0, 100.0));
    h.run();
    let hit = h.state().viewport.terrain.hover.expect("a hit");
    assert!((hit - expected).length() < 0.02, "{hit} vs {expected}");
    // A perspective ray through that pixel meets the ground elsewhere.
    h.state_mut().viewport.camera.ortho = false;
    h.run();
    let persp = h.state().viewport.terrain.hover.expect("a hit");
    assert!((persp - expected).length() > 0.2, "{persp} vs {expected}");
}

#[test]
fn sculpting_a_duplicate_gives_it_its_own_heightmap() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = flat_level(dir.path());
    let centre = Vec3::new(0.0, FLAT, 0.0);
    let mut h = sculpting(&path, BrushKind::Raise, centre);
    let original = heights(&h);
    h.state_mut().act(Action::Duplicate);
    h.run();
    assert_eq!(h.state().state.selection, Some(1));
    let at = screen(&h, centre);
    stroke(&mut h, at, 3);
    let copy = h
        .state()
        .state
        .row_at(1)
        .and_then(|r| r.terrain)
        .expect("copy");
    assert_eq!(
        copy.heightmap,
        HeightSource::File {
            path: "flat_Flat_copy.png".into()
        }
    );
    assert!(heights(&h).at(16, 16) > original.at(16, 16) + 0.5);
    // The original still names flat.png, whose heights did not change.
    h.state_mut().state.selection = Some(0);
    assert_eq!(
        terrain_row(&h).terrain.map(|t| t.heightmap),
        Some(HeightSource::File {
            path: "flat.png".into()
        })
    );
    assert_eq!(heights(&h), original);
}

#[test]
fn an_autosave_keeps_sculpted_heights_and_recovering_it_brings_them_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = noise_level(dir.path());
    let p = Vec3::new(0.0, 3.0, 0.0);
    let mut h = sculpting(&path, BrushKind::Raise, p);
    let at = screen(&h, h.state().viewport.terrain.hover.unwrap_or(p));
    stroke(&mut h, at, 3);
    let sculpted = heights(&h);
    h.state_mut().autosave_now();
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    let auto = texel_editor::files::autosave_path(&path);
    let kept = dir.path().join("hills_Terrain.autosave.png");
    assert!(kept.is_file(), "the autosave keeps the unsaved heights");
    assert!(!dir.path().join("hills_Terrain.png").exists());
    let autosaved = Scene::load(&auto).expect("autosave");
    let e = autosaved.entities().next().expect("terrain");
    assert_eq!(
        autosaved
            .row(e)
            .and_then(|r| r.terrain)
            .map(|t| t.heightmap),
        Some(HeightSource::File {
            path: "hills_Terrain.autosave.png".into()
        })
    );

    // A crash, then recovery: the heights come back, named as the level will save them.
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
    assert!(h.state().state.is_dirty());
    let t = terrain_row(&h).terrain.expect("terrain");
    assert_eq!(
        t.heightmap,
        HeightSource::File {
            path: "hills_Terrain.png".into()
        }
    );
    let back = heights(&h);
    assert!(
        back.heights
            .iter()
            .zip(&sculpted.heights)
            .all(|(a, b)| (a - b).abs() <= t.max_height / 65535.0)
    );
    // Saving writes the heightmap and forgets the autosave and what it kept.
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run();
    assert!(
        h.state().dialogs.error.is_none(),
        "{:?}",
        h.state().dialogs.error
    );
    assert!(dir.path().join("hills_Terrain.png").is_file());
    assert!(!auto.exists() && !kept.exists());
}

/// A terrain lies along the world's axes: the inspector says so where its rotation or scale
/// is set (the loader warns too), and says nothing for a terrain placed by its translation.
#[test]
fn the_inspector_names_a_terrains_rotation_as_not_applied() {
    let dir = tempfile::tempdir().unwrap();
    let path = flat_level(dir.path());
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    assert!(
        h.query_by_label_contains("not applied").is_none(),
        "a terrain placed by its translation gets no warning"
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let turned = text.replacen("rotation: (0.0, 0.0, 0.0)", "rotation: (0.0, 30.0, 0.0)", 1);
    assert_ne!(turned, text, "the level names its rotation");
    std::fs::write(&path, turned).unwrap();
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    h.get_by_label_contains("rotation [0.0, 30.0, 0.0] not applied");
}
