//! The editor application: lays out the panels, routes shortcuts and menu actions, and does
//! the file chores (open, save, autosave, recover: `file_chores`). `EditorApp::ui` is what
//! both eframe and the UI tests call.

use std::path::Path;
use std::time::Instant;

use egui::{Key, KeyboardShortcut, Modifiers, Ui};

use crate::command::CommandError;
use crate::document::Document;
use crate::files::{self, Recent};
use crate::pixel::{PixelInfo, pixel_info};
use crate::state::EditorState;
use crate::terrain;
use crate::ui::dialogs::{Dialogs, Pending, Purpose};
use crate::ui::menu::{self, Action};
use crate::ui::palette_section;
use crate::ui::pixel_section::{self, PixelCalc};
use crate::ui::sprite_section::SpritePanel;
use crate::ui::{hierarchy, inspector};
use crate::viewport::Viewport;
use crate::viewport::gpu::GpuView;

mod asset_chores;
mod clipboard_chores;
mod file_chores;

/// The editor.
pub struct EditorApp {
    /// Document, selection, history.
    pub state: EditorState,
    /// The viewport.
    pub viewport: Viewport,
    /// Open dialogs.
    pub dialogs: Dialogs,
    /// Recently opened files.
    pub recent: Recent,
    /// The inspector's sprite section between frames (its preview among it).
    pub sprite_panel: SpritePanel,
    rename: Option<(usize, String)>,
    /// The outliner's filter (for the session).
    pub outliner: hierarchy::OutlinerFilter,
    last_autosave: Instant,
    autosaved_id: u64,
    /// The history state last seen, and the edits seen since the last autosave.
    edits_seen: (u64, u32),
    /// The autosave being written beside the editor, if any.
    autosaving: Option<std::thread::JoinHandle<Result<(), String>>>,
    /// Where `--stats` writes the status bar's figures.
    stats: Option<crate::stats_log::StatsLog>,
    title: String,
    focus_seen: Option<egui::Id>,
    allow_close: bool,
    ctx: Option<egui::Context>,
    assets_checked: u64,
    /// The face-resolution calculator's inputs.
    pixel_calc: PixelCalc,
    /// The selected entity's pixel-perfect numbers, for the document revision, selection and
    /// viewport they were computed for (a glTF mesh's density walks its triangles).
    pixel_info: Option<(PixelKey, Option<PixelInfo>)>,
    /// eframe's measure of the UI thread's last frame, seconds (`None` in tests).
    cpu_usage: Option<f32>,
    /// The text the last copy put on the clipboard.
    copied: Option<String>,
    /// The asset panel (View → Asset panel).
    pub assets: crate::assets::AssetPanel,
}

type PixelKey = (u64, Option<usize>, u32);

impl EditorApp {
    /// Opens `path` (an empty level when `None`) with the recent list in the user's config.
    pub fn open(path: Option<&Path>) -> Self {
        Self::with_recent(path, Recent::load(Recent::default_store()))
    }

    /// Opens `path` with the given recent list (tests pass one that is not stored).
    pub fn with_recent(path: Option<&Path>, recent: Recent) -> Self {
        let mut app = EditorApp {
            state: EditorState::new(Document::new_empty()),
            viewport: Viewport::default(),
            dialogs: Dialogs::default(),
            recent,
            sprite_panel: SpritePanel::default(),
            rename: None,
            outliner: Default::default(),
            last_autosave: Instant::now(),
            autosaved_id: 0,
            edits_seen: (0, 0),
            autosaving: None,
            stats: None,
            title: String::new(),
            focus_seen: None,
            allow_close: false,
            ctx: None,
            assets_checked: 0,
            pixel_calc: PixelCalc::default(),
            pixel_info: None,
            cpu_usage: None,
            copied: None,
            assets: Default::default(),
        };
        match path {
            Some(p) => app.load(p),
            // An untitled document autosaved before a crash is offered back.
            None => app.dialogs.recover = app.recent.untitled_autosave().filter(|p| p.is_file()),
        }
        app
    }

    /// Attaches eframe's wgpu renderer, so the viewport can render the level: its render
    /// worker starts, and asks `ctx` to repaint when a frame is done.
    pub fn attach_gpu(&mut self, rs: Option<egui_wgpu::RenderState>, ctx: &egui::Context) {
        let Some(rs) = rs else {
            return;
        };
        // A device of its own for the viewport; eframe's if the driver will not open a
        // second one (the window's frames then queue with the viewport's).
        match GpuView::beside(&rs).or_else(|_| GpuView::new(&rs)) {
            Ok(gpu) => {
                self.viewport.attach(gpu, ctx.clone());
                self.viewport.picture_target = Some(rs.target_format);
            }
            Err(e) => self.viewport.error = Some(e),
        }
    }

    /// Replaces the document with `path`; on failure keeps the current one and shows why.
    pub fn load(&mut self, path: &Path) {
        self.finish_autosave();
        match Document::open(path) {
            Ok(doc) => {
                self.state = EditorState::new(doc);
                self.recent.touch(path);
                self.dialogs.recover = files::recoverable(path);
                self.autosaved_id = 0;
            }
            Err(e) => self.dialogs.error = Some(e),
        }
    }

    /// The window title: file name, a `*` when modified.
    pub fn title(&self) -> String {
        let mark = if self.state.is_dirty() { " *" } else { "" };
        format!("{}{mark} — Texel editor", self.state.document.title())
    }

    /// One frame of the whole UI.
    pub fn ui(&mut self, ui: &mut Ui) {
        let started = Instant::now();
        let ctx = ui.ctx().clone();
        self.ctx = Some(ctx.clone());
        let mut actions = self.shortcuts(&ctx);
        let playing = self.viewport.playing();
        let info = self.selected_pixel_info();
        let mut frame = false;
        egui::Panel::top("menu").show(ui, |ui| {
            let (u, r) = (
                self.state.history.undo_label(),
                self.state.history.redo_label(),
            );
            let view = menu::ViewChoice {
                schedule: self.viewport.schedule,
                debug: self.viewport.debug.flags,
                textured_selection: info.is_some(),
                terrain_selection: crate::terrain_edits::selected_terrain(&self.state).is_some(),
                terrain_tool: self.viewport.terrain.active,
                ortho: self.viewport.camera.ortho,
                night: (self.state.scene().palette.as_ref())
                    .and_then(|p| p.alternate.as_ref())
                    .map(|_| self.viewport.night),
                assets: self.assets.open,
            };
            if let Some(a) = menu::show(ui, &self.recent.files, u, r, playing, view) {
                actions.push(a);
            }
        });
        egui::Panel::bottom("status").show(ui, |ui| self.status(ui));
        actions.extend(self.asset_panel(ui, playing));
        let edited = egui::Panel::left("hierarchy")
            .default_size(230.0)
            .show(ui, |ui| {
                // While playing the document is frozen: Esc returns to it unchanged.
                ui.add_enabled_ui(!playing, |ui| {
                    hierarchy::show(ui, &mut self.state, &mut self.rename, &mut self.outliner)
                })
                .inner
            })
            .inner;
        self.report("edit", edited);
        let edited = egui::Panel::right("inspector")
            .default_size(320.0)
            .show(ui, |ui| {
                ui.add_enabled_ui(!playing, |ui| {
                    egui::ScrollArea::vertical()
                        .show(ui, |ui| {
                            ui.heading("Inspector");
                            let entity =
                                inspector::entity(ui, &mut self.state, &mut self.sprite_panel);
                            let pixel = pixel_section::pixel_perfect(
                                ui,
                                &mut self.state,
                                info.as_ref(),
                                &mut self.pixel_calc,
                            );
                            if pixel == Ok(true) {
                                frame = true;
                            }
                            let entity = entity.and(pixel.map(|_| ()));
                            ui.separator();
                            let settings = egui::CollapsingHeader::new("Level settings")
                                .default_open(self.state.selection.is_none())
                                .show(ui, |ui| inspector::settings(ui, &mut self.state))
                                .body_returned;
                            let (palette, asked) = egui::CollapsingHeader::new("Palette")
                                .default_open(self.state.selection.is_none())
                                .show(ui, |ui| palette_section::show(ui, &mut self.state))
                                .body_returned
                                .unwrap_or((Ok(()), None));
                            actions.extend(asked);
                            entity.and(settings.unwrap_or(Ok(()))).and(palette)
                        })
                        .inner
                })
                .inner
            })
            .inner;
        self.report("edit", edited);
        if frame {
            actions.push(Action::FrameOneToOne);
        }
        let had_error = self.viewport.error.is_some();
        let edited = egui::CentralPanel::no_frame()
            .show(ui, |ui| self.viewport.show(ui, &mut self.state))
            .inner;
        self.report("edit", edited);
        // An asset dropped on the viewport, at the point under the pointer.
        if let Some((drag, at)) = self.viewport.dropped_asset.take() {
            actions.push(Action::PlaceAsset(drag, Some(at)));
        }
        // The renderer just failed (a GPU error, a lost device): the viewport says why, and a
        // modified document is autosaved at once rather than at the next minute.
        if !had_error && self.viewport.error.is_some() && self.state.is_dirty() {
            self.autosave_now();
        }
        if let Some(answer) = self.dialogs.show(&ctx) {
            self.answer(answer);
        }
        self.dropped_files(&ctx);
        for a in actions {
            self.act(a);
        }
        self.load_new_assets(&ctx);
        self.end_gesture(&ctx);
        self.close_request(&ctx);
        self.autosave(&ctx);
        // The UI thread's own time: eframe's measure of the last frame (the UI and its
        // painting) when there is one, else this update's.
        let own = started.elapsed().as_secs_f32();
        self.viewport.ui_busy_ms = self.cpu_usage.take().unwrap_or(own) * 1e3;
        self.log_stats();
        let title = self.title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
    }

    fn status(&self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            match self.viewport.report() {
                Some(r) => {
                    // Before the first edit, what the renderer's start took.
                    let (what, ms) = match r.upload_ms {
                        Some(ms) => ("scene update", ms),
                        None => ("renderer start", r.start_ms),
                    };
                    ui.label(format!(
                        "render {:.1} ms · {what} {ms:.1} ms · {}×{}",
                        r.frame_ms, r.size.x, r.size.y
                    ));
                    if let Some(s) = &r.stats {
                        let c = &s.counters;
                        ui.label(format!(
                            "faces {} · objects a face {} · texels shaded {} · quads {} · \
                             visible texels {}",
                            c.faces_captured,
                            c.objects_captured / u64::from(c.faces_captured.max(1)),
                            c.texels_shaded,
                            c.quads_splatted,
                            c.screen_visible_texels
                        ));
                        let gpu = c.gpu_scene_bytes
                            + c.gpu_bvh_bytes
                            + c.texture_bytes
                            + c.gpu_probe_bytes;
                        ui.label(format!("GPU {:.0} MB", gpu as f64 / 1e6))
                            .on_hover_text(format!(
                                "scene {:.1} MB, shadow trees {:.1} MB, textures {:.1} MB, \
                                 probes {:.1} MB",
                                c.gpu_scene_bytes as f64 / 1e6,
                                c.gpu_bvh_bytes as f64 / 1e6,
                                c.texture_bytes as f64 / 1e6,
                                c.gpu_probe_bytes as f64 / 1e6
                            ));
                    }
                }
                None => {
                    ui.label("no renderer");
                }
            }
            ui.separator();
            ui.label(format!(
                "ui frame {:.0} ms · {} a second",
                self.viewport.ui_frame_ms, self.viewport.ui_fps
            ))
            .on_hover_text(format!(
                "the UI thread worked {:.1} ms of its last frame (the rest waited for the \
                 display); the viewport renders on a thread of its own",
                self.viewport.ui_busy_ms
            ));
            ui.label(format!(
                "edit to frame {:.0} ms · {:?}",
                self.viewport.edit_stall_ms, self.viewport.schedule
            ));
            ui.separator();
            ui.label(format!("{} entities", self.state.scene().len()));
            if self.viewport.playing() {
                ui.label("playing");
            } else if self.viewport.camera.ortho {
                ui.label("ortho");
            }
        });
    }

    fn shortcuts(&mut self, ctx: &egui::Context) -> Vec<Action> {
        let mut out = Vec::new();
        if self.dialogs.any_open() {
            return out;
        }
        let typing = ctx.egui_wants_keyboard_input();
        let cmd = Modifiers::COMMAND;
        let shift_cmd = Modifiers::COMMAND | Modifiers::SHIFT;
        ctx.input_mut(|i| {
            if i.consume_shortcut(&KeyboardShortcut::new(shift_cmd, Key::Z))
                || i.consume_shortcut(&KeyboardShortcut::new(cmd, Key::Y))
            {
                out.push(Action::Redo);
            }
            if i.consume_shortcut(&KeyboardShortcut::new(cmd, Key::Z)) {
                out.push(Action::Undo);
            }
            if i.consume_shortcut(&KeyboardShortcut::new(cmd, Key::S)) {
                out.push(Action::Save);
            }
            if i.consume_shortcut(&KeyboardShortcut::new(cmd, Key::D)) {
                out.push(Action::Duplicate);
            }
            if i.consume_shortcut(&KeyboardShortcut::new(shift_cmd, Key::G)) {
                out.push(Action::Ungroup);
            }
            if i.consume_shortcut(&KeyboardShortcut::new(cmd, Key::G)) {
                out.push(Action::Group);
            }
            if i.key_pressed(Key::F5) {
                out.push(Action::TogglePlay);
            }
            if !typing && i.key_pressed(Key::Delete) {
                out.push(Action::Delete);
            }
            if !typing && i.modifiers.is_none() && i.key_pressed(Key::N) {
                out.push(Action::ToggleNight);
            }
        });
        if !typing {
            out.extend(self.selection_shortcuts(ctx));
        }
        out
    }

    /// Carries out an action.
    pub fn act(&mut self, action: Action) {
        let edits = matches!(
            action,
            Action::Undo
                | Action::Redo
                | Action::Duplicate
                | Action::Delete
                | Action::Group
                | Action::Ungroup
                | Action::Cut
                | Action::Paste(_)
                | Action::ImportHeightmapPath(_)
                | Action::ToggleTerrainTool
                | Action::PickPalette(_)
                | Action::PalettePath(..)
                | Action::ClearPalette(_)
                | Action::PlaceAsset(..)
        );
        if edits && self.viewport.playing() {
            return;
        }
        // A sculpt stroke in progress lands before anything else happens.
        let landed = self.viewport.terrain.finish(&mut self.state);
        self.report("sculpt", landed);
        match action {
            Action::New => self.guard(Pending::New),
            Action::Open => self.guard(Pending::Open(None)),
            Action::OpenPath(p) => self.guard(Pending::Open(Some(p))),
            Action::Save => match self.state.document.path.clone() {
                Some(p) => self.save_to(&p),
                None => self.ask(Purpose::SaveAs),
            },
            Action::SaveAs => self.ask(Purpose::SaveAs),
            Action::Undo => {
                let undone = self.state.undo().map(|_| ());
                self.report("undo", undone);
            }
            Action::Redo => {
                let redone = self.state.redo().map(|_| ());
                self.report("redo", redone);
            }
            Action::Add(row) => {
                self.viewport.stop();
                // On the surface under the viewport's centre (or the ground there).
                let at = self.viewport.place_point(&self.state);
                let row = crate::viewport::place::placed_at(*row, at);
                let added = self.state.add(row);
                self.report("add", added);
            }
            Action::AddMesh => self.ask(Purpose::Mesh),
            Action::AddMeshPath(p) => self.add_mesh(&p),
            Action::AddTerrain => {
                self.viewport.stop();
                let at = self.viewport.ground_focus();
                let added = self.state.add(terrain::terrain_row(at));
                self.report("add a terrain", added);
            }
            Action::AddSprite => self.ask(Purpose::Sprite),
            Action::AddSpritePath(p) => self.add_sprite(&p),
            Action::ToggleTerrainTool => {
                let toggled = self.viewport.terrain.toggle(&mut self.state);
                self.report("sculpt", toggled);
            }
            Action::ImportHeightmap => self.ask(Purpose::ImportHeightmap),
            Action::ImportHeightmapPath(p) => self.import_heightmap(&p),
            Action::ExportHeightmap => self.ask(Purpose::ExportHeightmap),
            Action::ExportHeightmapPath(p) => self.export_heightmap(&p),
            Action::Duplicate => {
                let duplicated = self.state.duplicate_selection();
                self.report("duplicate", duplicated);
            }
            Action::Delete => {
                let deleted = self.state.delete_selection();
                self.report("delete", deleted);
            }
            Action::Group => {
                let grouped = self.state.group_selection();
                self.report("group", grouped);
            }
            Action::Ungroup => {
                let ungrouped = self.state.ungroup_selection();
                self.report("ungroup", ungrouped);
            }
            Action::Copy => self.copy(false),
            Action::Cut => self.copy(true),
            Action::RequestPaste => self.request_paste(),
            Action::Paste(text) => self.paste(&text),
            Action::SelectAll => self.state.select_all(),
            Action::SelectNone => self.state.select_none(),
            Action::TogglePlay => {
                if self.viewport.playing() {
                    self.viewport.stop();
                } else {
                    self.viewport.play(&self.state);
                }
            }
            Action::Schedule(s) => self.viewport.set_schedule(s),
            Action::ToggleDebug(v) => self.viewport.debug.flags.toggle(v),
            Action::ToggleOrtho => {
                if !self.viewport.playing() {
                    self.viewport.toggle_ortho();
                }
            }
            Action::FrameOneToOne => {
                if let Err(e) = self.viewport.frame_one_to_one(&self.state) {
                    self.dialogs.error = Some(format!("cannot frame 1:1: {e}"));
                }
            }
            Action::PickPalette(slot) => self.ask(Purpose::Palette(slot)),
            Action::PalettePath(slot, p) => self.pick_palette(slot, &p),
            Action::ClearPalette(slot) => {
                let cleared = self.state.clear_palette(slot);
                self.report("take the palette off", cleared);
            }
            Action::ToggleNight => self.viewport.night = !self.viewport.night,
            Action::ToggleAssetPanel => self.assets.open = !self.assets.open,
            Action::PlaceAsset(drag, at) => self.place_asset(&drag, at),
            Action::Quit => self.guard(Pending::Quit),
        }
        self.state.history.seal();
    }

    /// The selected entity's pixel-perfect numbers on the viewport (`None` without a loaded
    /// texture), computed again only when the document, the selection or the viewport's
    /// height changed.
    pub fn selected_pixel_info(&mut self) -> Option<PixelInfo> {
        let view = self.viewport.extract_viewport();
        let key = (
            self.state.document.revision,
            self.state.selection,
            view.height,
        );
        if let Some((k, info)) = &self.pixel_info
            && *k == key
        {
            return info.clone();
        }
        let info = self.state.selected_row().and_then(|(_, row)| {
            let level = &self.state.document.level;
            pixel_info(&row, &level.scene.settings, &level.assets, view)
        });
        self.pixel_info = Some((key, info.clone()));
        info
    }

    /// Shows a command that failed in the error dialog (the document is left as it was).
    fn report(&mut self, what: &str, result: Result<(), CommandError>) {
        if let Err(e) = result {
            self.dialogs.error = Some(format!("could not {what}: {e}"));
        }
    }

    /// Writes the status bar's figures to `log` once a second from now on.
    pub fn set_stats_log(&mut self, log: crate::stats_log::StatsLog) {
        self.stats = Some(log);
    }

    fn log_stats(&mut self) {
        let Some(log) = &mut self.stats else {
            return;
        };
        let report = self.viewport.report();
        let figures = crate::stats_log::Figures {
            ui_frame_ms: f64::from(self.viewport.ui_frame_ms),
            ui_busy_ms: f64::from(self.viewport.ui_busy_ms),
            ui_fps: self.viewport.ui_fps,
            render_ms: report.map_or(0.0, |r| r.frame_ms),
            edit_to_frame_ms: self.viewport.edit_stall_ms,
            upload_ms: report.and_then(|r| r.upload_ms),
            uploads: report.map_or(0, |r| r.uploads),
            entities: self.state.scene().len(),
            playing: self.viewport.playing(),
        };
        if let Err(e) = log.tick(&figures) {
            // Said once: the log stops rather than raising the dialog every second.
            self.stats = None;
            self.dialogs.error = Some(format!("--stats: {e}"));
        }
    }

    /// A gesture (drag, typing into one field) ends when the pointer is released or the
    /// keyboard focus moves; then the next edit starts a new undo step.
    fn end_gesture(&mut self, ctx: &egui::Context) {
        let focus = ctx.memory(|m| m.focused());
        let released = ctx.input(|i| i.pointer.any_released());
        let down = ctx.input(|i| i.pointer.any_down());
        if released || (!down && focus != self.focus_seen) {
            self.state.history.seal();
        }
        self.focus_seen = focus;
    }
}

impl eframe::App for EditorApp {
    fn ui(&mut self, ui: &mut Ui, frame: &mut eframe::Frame) {
        self.cpu_usage = frame.info().cpu_usage;
        EditorApp::ui(self, ui);
    }
}
