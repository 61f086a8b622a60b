//! Textures in the editor, driven through egui_kittest (no GPU): a texture set on an entity
//! is loaded and its pixel-perfect numbers shown, a broken one is refused; the face-resolution
//! calculator applies to the level as one undo step; Frame 1:1 puts the camera on the facing
//! face's normal at the 1:1 distance; the texel-density view switches on with its legend.
//! On a headless device, the density view reaches the renderer and survives a level edit.

use std::path::{Path, PathBuf};

use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::{UVec2, Vec3};
use texel_editor::app::EditorApp;
use texel_editor::files::Recent;
use texel_editor::ui::menu::Action;
use texel_editor::viewport::debug::{DENSITY_LEGEND, DebugView};
use texel_render::context::test_context;
use texel_render::input::Schedule;
use texel_scene::{
    EntityRow, Geometry, LevelSettings, Material, Name, PixelScale, Scene, TextureMap, Transform,
};

use crate::support;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A level in `dir` with one untextured unit box at the origin (rotated `yaw` degrees) on
/// fixed 128-texel faces, and `textures/planks.png` beside it.
fn box_level(dir: &Path, yaw: f32) -> PathBuf {
    let textures = dir.join("textures");
    std::fs::create_dir_all(&textures).expect("mkdir");
    std::fs::copy(
        workspace().join("assets/textures/planks.png"),
        textures.join("planks.png"),
    )
    .expect("copy texture");
    let mut scene = Scene::new();
    scene.settings = LevelSettings {
        pixel_scale: PixelScale::FaceResolution(128),
        ..LevelSettings::default()
    };
    scene.spawn(EntityRow {
        name: Some(Name("Crate".into())),
        transform: Some(Transform {
            rotation: Vec3::new(0.0, yaw, 0.0),
            ..Transform::default()
        }),
        geometry: Some(Geometry::Box { size: Vec3::ONE }),
        material: Some(Material::default()),
        ..EntityRow::default()
    });
    let path = dir.join("level.ron");
    scene.save(&path).expect("save level");
    path
}

fn harness(app: EditorApp) -> Harness<'static, EditorApp> {
    let mut h = Harness::builder()
        .with_size([1200.0, 800.0])
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app);
    h.run();
    h
}

/// Opens `path`, selects the box and gives it `textures/planks.png` through the state API
/// (at the default 16 pixels per unit).
fn textured_box(path: &Path) -> Harness<'static, EditorApp> {
    let mut h = harness(EditorApp::with_recent(Some(path), Recent::default()));
    set_texture(&mut h, "textures/planks.png");
    h
}

fn set_texture(h: &mut Harness<'_, EditorApp>, texture: &str) {
    h.state_mut().state.selection = Some(0);
    let (index, mut row) = h.state().state.selected_row().expect("selected");
    if let Some(m) = &mut row.material {
        m.texture = Some(TextureMap::new(texture));
    }
    h.state_mut()
        .state
        .set_row(index, row, None)
        .expect("set row");
    h.state_mut().state.history.seal();
    h.run();
}

fn texture_of(h: &Harness<'_, EditorApp>) -> Option<String> {
    let (_, row) = h.state().state.selected_row()?;
    row.material?.texture.map(|t| t.path)
}

#[test]
fn a_texture_set_on_an_entity_is_loaded_and_its_one_to_one_distance_shown() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = box_level(dir.path(), 0.0);
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    h.get_by_label_contains("Untextured");
    set_texture(&mut h, "textures/planks.png");
    let assets = &h.state().state.document.level.assets;
    assert!(assets.texture("textures/planks.png").is_some());
    assert!(h.state().dialogs.error.is_none());
    // 16 pixels per unit on 128-texel faces: 1:1 at 128 / 32 = 4 units, which is the
    // level's reference distance.
    h.get_by_label("16.00 px/unit");
    h.get_by_label("128 texels");
    h.get_by_label("4.00 units");
    h.get_by_label("1.00 texture px per art px");
    h.get_by_label("1:1");

    // A texture that cannot be loaded is shown, and the edit that named it undone.
    set_texture(&mut h, "textures/missing.png");
    let error = h.state().dialogs.error.clone().expect("an error is shown");
    assert!(error.contains("missing.png"), "{error}");
    assert_eq!(texture_of(&h).as_deref(), Some("textures/planks.png"));
    h.get_by_label("OK").click();
    h.run();
    // Not an image at all: refused the same way.
    std::fs::write(dir.path().join("textures/garbage.png"), b"not a png").expect("write");
    set_texture(&mut h, "textures/garbage.png");
    assert!(h.state().dialogs.error.is_some());
    assert_eq!(texture_of(&h).as_deref(), Some("textures/planks.png"));
    assert!(
        h.state()
            .state
            .document
            .level
            .assets
            .texture("textures/planks.png")
            .is_some()
    );
}

#[test]
fn texture_fields_edit_the_material_as_undoable_steps() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = box_level(dir.path(), 0.0);
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(0);
    h.run();
    // Ticking Texture adds one with an empty path: nothing to load yet, no error.
    h.get_by_role_and_label(Role::CheckBox, "Texture").click();
    h.run();
    assert_eq!(texture_of(&h).as_deref(), Some(""));
    assert!(h.state().dialogs.error.is_none());
    h.get_by_label_contains("Type the texture's path");
    h.get_by_label("Texture path").focus();
    h.run();
    h.get_by_label("Texture path")
        .type_text("textures/planks.png");
    h.run();
    assert!(h.state().state.document.level.assets.texture_count() == 0);
    // Typing ends when the focus leaves the field: then the file is loaded.
    h.key_press(Key::Escape);
    h.run();
    assert_eq!(texture_of(&h).as_deref(), Some("textures/planks.png"));
    let assets = &h.state().state.document.level.assets;
    assert!(assets.texture("textures/planks.png").is_some());
    h.get_by_label("4.00 units");

    h.get_by_role_and_label(Role::SpinButton, "Density")
        .set_value_accesskit(32.0);
    h.run();
    h.get_by_label("Linear").click();
    h.run();
    h.get_by_label("UV scale U").set_value_accesskit(2.0);
    h.run();
    let (_, row) = h.state().state.selected_row().expect("selected");
    let t = row.material.expect("material").texture.expect("texture");
    assert_eq!(t.density, 32.0);
    assert_eq!(t.sampling, texel_scene::Sampling::Linear);
    assert_eq!(t.uv_scale.x, 2.0);
    // Density 32 × UV scale √2 over 128-texel faces.
    let d = 128.0 / (2.0 * 32.0 * 2f32.sqrt());
    h.get_by_label(&format!("{d:.2} units"));

    h.get_by_role_and_label(Role::CheckBox, "Normal map")
        .click();
    h.run();
    let (_, row) = h.state().state.selected_row().expect("selected");
    assert_eq!(
        row.material.expect("material").normal_map.as_deref(),
        Some("")
    );

    // Each field was its own step: undo walks them back to the untextured box.
    for _ in 0..6 {
        h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
        h.run();
    }
    assert_eq!(texture_of(&h), None);
    h.get_by_role_and_label(Role::CheckBox, "Texture");
}

#[test]
fn face_resolution_calculator_applies_to_the_level_as_one_undo_step() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = box_level(dir.path(), 0.0);
    let mut h = textured_box(&path);
    // The defaults: this material's density at the reference distance give the level's 128.
    h.get_by_label("128 texels (exactly 128.0)");
    h.get_by_label("Calculator distance")
        .set_value_accesskit(6.1);
    h.run();
    // 2 × 6.1 × 16 = 195.2, snapped to a multiple of 8.
    h.get_by_label("192 texels (exactly 195.2)");
    h.get_by_label("Apply 192 to the level").click_accesskit();
    h.run();
    let settings = h.state().state.scene().settings;
    assert_eq!(settings.pixel_scale, PixelScale::FaceResolution(192));
    h.get_by_label("6.00 units");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run();
    let settings = h.state().state.scene().settings;
    assert_eq!(settings.pixel_scale, PixelScale::FaceResolution(128));
    h.get_by_label("4.00 units");
    // The texture is still set: only the settings were undone.
    assert_eq!(texture_of(&h).as_deref(), Some("textures/planks.png"));
    // Out of range is clamped: 1000 units asks for 32,000 texels.
    h.get_by_label("Calculator distance")
        .set_value_accesskit(1000.0);
    h.run();
    h.get_by_label_contains("2048 texels");
}

fn assert_near(a: Vec3, b: Vec3, what: &str) {
    assert!((a - b).length() < 1e-3, "{what}: {a} != {b}");
}

#[test]
fn frame_one_to_one_looks_along_the_facing_faces_normal_from_the_one_to_one_distance() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = box_level(dir.path(), 0.0);
    let mut h = textured_box(&path);
    // In front of the box, a little above and to the side: the +Z face faces the camera.
    h.state_mut().viewport.camera.eye = Vec3::new(0.6, 0.8, 6.0);
    h.get_by_label("Frame 1:1").click_accesskit();
    h.run();
    let c = h.state().viewport.camera;
    // 1:1 at 128 / (2 × 16) = 4 units in front of the face's centre (0, 0, 0.5).
    assert_near(c.eye, Vec3::new(0.0, 0.0, 4.5), "eye");
    assert_near(c.forward(), Vec3::NEG_Z, "forward");
    assert!((c.distance - 4.0).abs() < 1e-5, "{}", c.distance);

    // From above, through the View menu: straight down onto the top face.
    h.state_mut().viewport.camera.eye = Vec3::new(0.3, 7.0, 0.2);
    h.get_by_label("View").click();
    h.run();
    h.get_by_label("Frame 1:1 (selected texture)").click();
    h.run();
    let c = h.state().viewport.camera;
    assert_near(c.eye, Vec3::new(0.0, 4.5, 0.0), "eye above");
    assert_near(c.forward(), Vec3::NEG_Y, "forward down");
    assert!(h.state().dialogs.error.is_none());
    // The document did not change.
    assert_eq!(h.state().state.history.undo_len(), 1);
}

#[test]
fn frame_one_to_one_on_a_turned_box_follows_its_face() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = box_level(dir.path(), 30.0);
    let mut h = textured_box(&path);
    h.state_mut().viewport.camera.eye = Vec3::new(1.0, 0.5, 6.0);
    h.state_mut().act(Action::FrameOneToOne);
    let c = h.state().viewport.camera;
    // The box's +Z face turned 30° about Y faces (sin 30°, 0, cos 30°).
    let n = Vec3::new(30f32.to_radians().sin(), 0.0, 30f32.to_radians().cos());
    assert_near(c.forward(), -n, "forward");
    assert_near(c.eye, n * 0.5 + n * 4.0, "eye");
    // Nothing selected: nothing to frame, said in the error dialog, camera unmoved.
    h.state_mut().state.selection = None;
    h.state_mut().act(Action::FrameOneToOne);
    assert_eq!(h.state().viewport.camera, c);
    assert!(h.state().dialogs.error.is_some());
}

#[test]
fn texel_density_view_toggles_with_its_legend() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = support::bundled_copy(dir.path(), "textured");
    let mut h = harness(EditorApp::with_recent(Some(&path), Recent::default()));
    h.state_mut().state.selection = Some(2);
    h.run();
    h.get_by_label("View").click();
    h.run();
    h.get_by_label(DebugView::TexelDensity.label()).click();
    h.run();
    assert!(h.state().viewport.debug.flags.texel_density);
    for (_, text) in DENSITY_LEGEND {
        h.get_by_label(text);
    }
    // An edit with the view on.
    let (index, mut row) = h.state().state.selected_row().expect("selected");
    if let Some(t) = &mut row.transform {
        t.translation.y += 1.0;
    }
    h.state_mut().state.set_row(index, row, None).expect("edit");
    h.run();
    assert!(h.state().viewport.debug.flags.texel_density);
    h.state_mut()
        .act(Action::ToggleDebug(DebugView::TexelDensity));
    h.run();
    assert!(h.query_by_label(DENSITY_LEGEND[0].1).is_none());
    assert!(h.state().dialogs.error.is_none());
}

/// Mean absolute difference of two sets of face images.
fn difference(a: &[Vec<u8>], b: &[Vec<u8>]) -> f64 {
    let (mut sum, mut n) = (0u64, 0u64);
    for (x, y) in a.iter().zip(b) {
        for (p, q) in x.iter().zip(y) {
            sum += u64::from(p.abs_diff(*q));
            n += 1;
        }
    }
    sum as f64 / n.max(1) as f64
}

#[test]
fn texel_density_view_reaches_the_renderer_and_survives_level_edits() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut gpu = support::gpu_view(&ctx);
    let level = texel_runtime::load::load_level(&workspace().join("assets/levels/textured.ron"))
        .expect("textured level");
    let mut camera = texel_editor::camera::EditorCamera::default();
    camera.focus(Vec3::new(0.0, 1.0, -3.0), 6.0);
    let size = UVec2::new(160, 120);
    let faces = |gpu: &mut texel_editor::viewport::gpu::GpuView, revision: u64| {
        for _ in 0..8 {
            gpu.render(
                &level,
                revision,
                camera.camera(),
                size,
                Schedule::Ours,
                0.016,
            )
            .expect("render");
        }
        let probes = gpu.probes.expect("probes");
        gpu.probe_faces(&probes.grid).expect("faces").1
    };
    let plain = faces(&mut gpu, 0);
    gpu.set_texture_density_view(true).expect("density view");
    assert!(gpu.texture_density_view());
    let density = faces(&mut gpu, 0);
    let changed = difference(&plain, &density);
    assert!(
        changed > 8.0,
        "the density view recoloured the faces: {changed}"
    );
    // A level edit (a new revision): the session's level is replaced, the view stays.
    let edited = faces(&mut gpu, 1);
    let same = difference(&density, &edited);
    let back = difference(&plain, &edited);
    eprintln!("plain/density {changed:.1}, density/edited {same:.1}, plain/edited {back:.1}");
    assert!(same < changed / 4.0, "{same} vs {changed}");
    gpu.set_texture_density_view(false).expect("off");
    let off = faces(&mut gpu, 1);
    assert!(difference(&plain, &off) < changed / 4.0);
}
