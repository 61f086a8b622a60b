//! `texel_editor` is the egui level editor for Texel levels. The document is a
//! [`texel_scene::Scene`]; every change to it goes through a [`command::Command`] kept in a
//! [`history::History`], so undo and redo are complete by construction. The UI panels borrow
//! the [`state::EditorState`] they need; the viewport renders the level with `texel_render`
//! on eframe's own wgpu device.

pub mod add_sprite;
pub mod app;
pub mod assets;
pub mod camera;
pub mod clipboard;
pub mod command;
pub mod document;
pub mod files;
pub mod groups;
pub mod history;
pub mod paint;
pub mod palette_edits;
pub mod pixel;
pub mod selection;
pub mod snap;
pub mod state;
pub mod stats_log;
pub mod terrain;
pub mod terrain_edits;
pub mod ui;
pub mod viewport;
pub mod visibility;

use std::path::PathBuf;

/// The level opened when none is given on the command line.
pub const DEFAULT_LEVEL: &str = "assets/levels/stone_circle.ron";

/// Opens the editor window on `path` (or [`DEFAULT_LEVEL`]) and runs until it is closed;
/// with `stats`, appends the status bar's figures to that file once a second
/// ([`stats_log`]).
pub fn run(path: Option<PathBuf>, stats: Option<PathBuf>) -> anyhow::Result<()> {
    let stats = (stats.as_deref())
        .map(stats_log::StatsLog::open)
        .transpose()
        .map_err(|e| anyhow::anyhow!(e))?;
    let path = path.unwrap_or_else(|| PathBuf::from(DEFAULT_LEVEL));
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1280.0, 800.0])
            .with_title("Texel editor")
            .with_drag_and_drop(true),
        ..Default::default()
    };
    eframe::run_native(
        "Texel editor",
        options,
        Box::new(move |cc| {
            let gpu = cc.wgpu_render_state.clone();
            let mut app = app::EditorApp::open(Some(&path));
            app.attach_gpu(gpu, &cc.egui_ctx);
            if let Some(log) = stats {
                app.set_stats_log(log);
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the editor window: {e}"))
}
