//! Helpers shared by the editor's GPU tests and benches: a viewport renderer on a headless
//! device, the `stone_circle` level and a camera looking at its first trilithon.

// Each test binary and bench includes this module and uses a part of it.
#![allow(dead_code)]

use std::path::Path;
use std::sync::Arc;

use egui::Modifiers;
use egui::mutex::RwLock;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use glam::Vec3;
use texel_editor::app::EditorApp;
use texel_editor::camera::EditorCamera;
use texel_editor::files::Recent;
use texel_editor::ui::widgets::{display_name, kind_icon};
use texel_editor::viewport::gpu::GpuView;
use texel_render::context::GpuContext;
use texel_runtime::load::{LoadedLevel, load_level};

/// The viewport's renderer on `ctx` (eframe's device, as it would hand it over).
pub fn gpu_view(ctx: &GpuContext) -> GpuView {
    gpu_view_and_egui(ctx).0
}

/// [`gpu_view`], with the egui renderer it registers its texture with (drawing into plain
/// RGBA8, as eframe prefers).
pub fn gpu_view_and_egui(ctx: &GpuContext) -> (GpuView, Arc<RwLock<egui_wgpu::Renderer>>) {
    let target = texel_render::target::FRAME_FORMAT;
    let egui_renderer = egui_wgpu::Renderer::new(&ctx.device, target, Default::default());
    let renderer = Arc::new(RwLock::new(egui_renderer));
    // On the test's own context: every view of a test process shares its compiled pipelines.
    let view = GpuView::on_context(ctx.clone(), renderer.clone());
    (view, renderer)
}

/// The `stone_circle` level.
pub fn stone_circle() -> LoadedLevel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/stone_circle.ron");
    load_level(&path).expect("stone_circle")
}

/// A copy of `assets/levels/<name>.ron` in `dir/levels`, beside links to the bundled asset
/// folders (so its relative paths resolve): an editor opened on it autosaves and recovers
/// there, never beside the bundled level, where a later test would be offered it back.
pub fn bundled_copy(dir: &Path, name: &str) -> std::path::PathBuf {
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
    let levels = dir.join("levels");
    std::fs::create_dir_all(&levels).expect("levels folder");
    for folder in ["meshes", "sprites", "textures"] {
        std::os::unix::fs::symlink(assets.join(folder), dir.join(folder)).expect("asset link");
    }
    let to = levels.join(format!("{name}.ron"));
    std::fs::copy(assets.join(format!("levels/{name}.ron")), &to).expect("copy level");
    to
}

/// A camera looking at the first trilithon from 6 units away.
pub fn camera() -> EditorCamera {
    let mut camera = EditorCamera::default();
    camera.focus(Vec3::new(1.206, 1.6, 5.946), 6.0);
    camera
}

/// An editor (kittest, no GPU) on a copy of stone_circle in `dir`, its first frames run.
pub fn editor(dir: &Path) -> Harness<'static, EditorApp> {
    let path = bundled_copy(dir, "stone_circle");
    let app = EditorApp::with_recent(Some(&path), Recent::default());
    let mut h = Harness::builder()
        .with_size([1200.0, 800.0])
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app);
    h.run();
    h
}

/// The outliner's label of the entity at `i`.
pub fn outliner_label(h: &Harness<'_, EditorApp>, i: usize) -> String {
    let row = h.state().state.row_at(i).expect("an entity");
    format!("{} {}", kind_icon(&row), display_name(&row, i))
}

/// Clicks the outliner's row of the entity at `i` with `modifiers` held.
pub fn click_row(h: &mut Harness<'_, EditorApp>, i: usize, modifiers: Modifiers) {
    let label = outliner_label(h, i);
    h.get_by_label(&label).click_modifiers(modifiers);
    h.run();
}
