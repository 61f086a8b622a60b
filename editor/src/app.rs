//! The editor application: lays out the panels, routes shortcuts and menu actions, and does
//! the file chores (open, save, autosave, recover). `EditorApp::ui` is what both eframe and
//! the UI tests call.

use std::path::{Path, PathBuf};
use std::time::Instant;

use egui::{Key, KeyboardShortcut, Modifiers, Ui};
use texel_scene::{EntityRow, Geometry, Material, Name, Transform};

use crate::command::{Command, CommandError};
use crate::document::{Document, unloaded_paths};
use crate::files::{self, Picked, Recent};
use crate::pixel::{PixelInfo, pixel_info};
use crate::state::EditorState;
use crate::terrain;
use crate::ui::dialogs::{Answer, Dialogs, Pending, Prompt, Purpose};
use crate::ui::inspector::PixelCalc;
use crate::ui::menu::{self, Action};
use crate::ui::sprite_section::SpritePanel;
use crate::ui::{hierarchy, inspector};
use crate::viewport::Viewport;
use crate::viewport::gpu::GpuView;

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
    last_autosave: Instant,
    autosaved_id: u64,
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
            last_autosave: Instant::now(),
            autosaved_id: 0,
            title: String::new(),
            focus_seen: None,
            allow_close: false,
            ctx: None,
            assets_checked: 0,
            pixel_calc: PixelCalc::default(),
            pixel_info: None,
        };
        match path {
            Some(p) => app.load(p),
            // An untitled document autosaved before a crash is offered back.
            None => app.dialogs.recover = app.recent.untitled_autosave().filter(|p| p.is_file()),
        }
        app
    }

    /// Attaches eframe's wgpu renderer, so the viewport can render the level.
    pub fn attach_gpu(&mut self, rs: Option<egui_wgpu::RenderState>) {
        match rs.as_ref().map(GpuView::new) {
            Some(Ok(gpu)) => self.viewport.gpu = Some(gpu),
            Some(Err(e)) => self.viewport.error = Some(e),
            None => {}
        }
    }

    /// Replaces the document with `path`; on failure keeps the current one and shows why.
    pub fn load(&mut self, path: &Path) {
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
            };
            if let Some(a) = menu::show(ui, &self.recent.files, u, r, playing, view) {
                actions.push(a);
            }
        });
        egui::Panel::bottom("status").show(ui, |ui| self.status(ui));
        let edited = egui::Panel::left("hierarchy")
            .default_size(230.0)
            .show(ui, |ui| {
                // While playing the document is frozen: Esc returns to it unchanged.
                ui.add_enabled_ui(!playing, |ui| {
                    hierarchy::show(ui, &mut self.state, &mut self.rename)
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
                            let pixel = inspector::pixel_perfect(
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
                            entity.and(settings.unwrap_or(Ok(())))
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
        self.autosave();
        let title = self.title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
    }

    fn status(&self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            let r = self.viewport.gpu.as_ref().map(|g| &g.report);
            match r {
                Some(r) => {
                    // Before the first edit, what the renderer's start took.
                    let (what, ms) = match r.upload_ms {
                        Some(ms) => ("scene upload", ms),
                        None => ("renderer start", r.start_ms),
                    };
                    ui.label(format!(
                        "render {:.1} ms · {what} {ms:.1} ms · {}×{}",
                        r.frame_ms, r.size.x, r.size.y
                    ));
                    if let Some(s) = &r.stats {
                        let c = &s.counters;
                        ui.label(format!(
                            "faces {} · texels shaded {} · quads {} · visible texels {}",
                            c.faces_captured,
                            c.texels_shaded,
                            c.quads_splatted,
                            c.screen_visible_texels
                        ));
                    }
                }
                None => {
                    ui.label("no renderer");
                }
            }
            ui.separator();
            ui.label(format!("ui frame {:.0} ms", self.viewport.ui_frame_ms));
            ui.label(format!(
                "edit stall {:.0} ms · {:?}",
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
            if i.key_pressed(Key::F5) {
                out.push(Action::TogglePlay);
            }
            if !typing && i.key_pressed(Key::Delete) {
                out.push(Action::Delete);
            }
        });
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
                | Action::ImportHeightmapPath(_)
                | Action::ToggleTerrainTool
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
                let added = self.state.add(*row);
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
                if let Some(i) = self.state.selection {
                    let duplicated = self.state.duplicate(i);
                    self.report("duplicate", duplicated);
                }
            }
            Action::Delete => {
                if let Some(i) = self.state.selection {
                    let deleted = self.state.delete(i);
                    self.report("delete", deleted);
                }
            }
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
            Action::Quit => self.guard(Pending::Quit),
        }
        self.state.history.seal();
    }

    /// Runs `pending` now, or after "discard changes?" when the document is modified.
    fn guard(&mut self, pending: Pending) {
        if self.state.is_dirty() {
            self.dialogs.confirm = Some(pending);
        } else {
            self.proceed(pending);
        }
    }

    fn proceed(&mut self, pending: Pending) {
        match pending {
            Pending::New => {
                self.discard_autosave();
                self.state = EditorState::new(Document::new_empty());
            }
            Pending::Open(Some(p)) => {
                self.discard_autosave();
                self.load(&p);
            }
            Pending::Open(None) => self.ask(Purpose::Open),
            Pending::Quit => {
                self.discard_autosave();
                self.allow_close = true;
                self.title.clear();
                if let Some(ctx) = &self.ctx {
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                }
            }
        }
    }

    /// Asks for a path with a native dialog, or a typed-path prompt when none exists.
    fn ask(&mut self, purpose: Purpose) {
        let picked = match purpose {
            Purpose::Open => files::pick_open(),
            Purpose::SaveAs => files::pick_save(self.state.document.path.as_deref()),
            Purpose::Mesh => files::pick_mesh(),
            Purpose::Sprite => files::pick_sprite(),
            Purpose::ImportHeightmap => files::pick_heightmap(),
            Purpose::ExportHeightmap => files::pick_heightmap_save(&self.export_name()),
        };
        match picked {
            Picked::Path(p) => self.answer(Answer::Path(purpose, p)),
            Picked::Cancelled => {}
            Picked::NoService => {
                let text = match purpose {
                    Purpose::SaveAs => self
                        .state
                        .document
                        .path
                        .as_ref()
                        .map(|p| p.display().to_string())
                        .unwrap_or_default(),
                    Purpose::ExportHeightmap => self.export_name(),
                    _ => String::new(),
                };
                self.dialogs.prompt = Some(Prompt { purpose, text });
            }
        }
    }

    fn answer(&mut self, answer: Answer) {
        match answer {
            Answer::Path(Purpose::Open, p) => self.proceed(Pending::Open(Some(p))),
            Answer::Path(Purpose::SaveAs, p) => self.save_to(&p),
            Answer::Path(Purpose::Mesh, p) => self.add_mesh(&p),
            Answer::Path(Purpose::Sprite, p) => self.add_sprite(&p),
            Answer::Path(Purpose::ImportHeightmap, p) => self.import_heightmap(&p),
            Answer::Path(Purpose::ExportHeightmap, p) => self.export_heightmap(&p),
            Answer::Discard(pending) => self.proceed(pending),
            Answer::Recover(p) => self.recover(&p),
        }
    }

    /// Saves to `path` (atomically) and forgets the autosave.
    pub fn save_to(&mut self, path: &Path) {
        let old = self.autosave_file();
        match self.state.save_as(path) {
            Ok(()) => {
                if let Some(o) = old {
                    files::remove_autosave_file(&o);
                }
                files::remove_autosave(path);
                self.recent.touch(path);
            }
            Err(e) => self.dialogs.error = Some(e),
        }
    }

    fn recover(&mut self, auto: &Path) {
        let level_path = self.state.document.path.clone();
        match Document::open(auto) {
            Ok(mut doc) => {
                doc.adopt_autosaved_heights();
                // The recovered document is the level it autosaved (or stays untitled).
                doc.level.path = level_path
                    .clone()
                    .unwrap_or_else(|| Document::new_empty().level.path);
                doc.path = level_path;
                self.state = EditorState::new(doc);
                self.state.mark_dirty();
            }
            Err(e) => self.dialogs.error = Some(format!("cannot recover the autosave: {e}")),
        }
    }

    fn add_mesh(&mut self, file: &Path) {
        let Some(level) = self.state.document.path.clone() else {
            self.dialogs.error =
                Some("save the level first: mesh paths are relative to the level file".into());
            return;
        };
        let rel = texel_scene::assets::relative_path(&level, file);
        let row = EntityRow {
            name: file
                .file_stem()
                .map(|s| Name(s.to_string_lossy().into_owned())),
            transform: Some(Transform::default()),
            geometry: Some(Geometry::Mesh { path: rel }),
            material: Some(Material::default()),
            ..EntityRow::default()
        };
        if let Err(e) = self.state.add(row) {
            self.report("add the mesh", Err(e));
            return;
        }
        if let Err(e) = self.state.reload_assets() {
            // Take the entity back out; the load error is what the person needs to see.
            self.dialogs.error = Some(match self.state.undo() {
                Ok(_) => e,
                Err(u) => format!("{e} (and the mesh could not be taken out again: {u})"),
            });
        }
    }

    /// Adds a sprite of the sheet `file` standing at the view's focus
    /// ([`crate::add_sprite::add_sprite`]); a file that is not an image is shown in the error
    /// dialog, and nothing is added.
    pub fn add_sprite(&mut self, file: &Path) {
        self.viewport.stop();
        let at = self.viewport.ground_focus();
        if let Err(e) = crate::add_sprite::add_sprite(&mut self.state, file, at) {
            self.dialogs.error = Some(format!("cannot add the sprite: {e}"));
        }
    }

    /// Replaces the selected terrain's heights with the 16-bit heightmap `file`, as one undo
    /// step; a file that cannot be imported is shown in the error dialog and changes nothing.
    pub fn import_heightmap(&mut self, file: &Path) {
        let result = match self.state.selection {
            Some(i) => crate::terrain_edits::import_heightmap(&mut self.state, i, file),
            None => Err("select a terrain first".to_owned()),
        };
        if let Err(e) = result {
            self.dialogs.error = Some(format!("cannot import the heightmap: {e}"));
        }
    }

    /// Writes the selected terrain's heights to `file` as a 16-bit PNG; a failure is shown
    /// in the error dialog.
    pub fn export_heightmap(&mut self, file: &Path) {
        let result = match self.state.selection {
            Some(i) => crate::terrain_edits::export_heightmap(&self.state, i, file),
            None => Err("select a terrain first".to_owned()),
        };
        if let Err(e) = result {
            self.dialogs.error = Some(format!("cannot export the heightmap: {e}"));
        }
    }

    /// The file name an export suggests: the selected entity's name.
    fn export_name(&self) -> String {
        let name = self
            .state
            .selected_row()
            .and_then(|(_, r)| r.name)
            .map_or_else(|| "terrain".to_owned(), |n| n.0);
        format!("{name}.png")
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

    fn dropped_files(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_owned())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        for p in dropped {
            let ext = p
                .extension()
                .map(|e| e.to_string_lossy().to_lowercase())
                .unwrap_or_default();
            match ext.as_str() {
                "gltf" | "glb" => self.add_mesh(&p),
                "ron" => self.guard(Pending::Open(Some(p))),
                _ => {
                    self.dialogs.error =
                        Some(format!("{}: not a level or a glTF mesh", p.display()))
                }
            }
        }
    }

    /// Loads meshes and textures the scene names but the library lacks (a path typed in the
    /// inspector), once the person has stopped typing. A file that cannot be loaded is shown
    /// in the error dialog, and the edit that named it is undone, so the level stays as it
    /// was (as a broken mesh added from the menu is taken out again).
    fn load_new_assets(&mut self, ctx: &egui::Context) {
        let revision = self.state.document.revision;
        if revision == self.assets_checked || ctx.memory(|m| m.focused()).is_some() {
            return;
        }
        self.assets_checked = revision;
        if self.state.document.path.is_none() || !self.state.document.has_unloaded_assets() {
            return;
        }
        if let Err(e) = self.state.reload_assets() {
            let assets = &self.state.document.level.assets;
            let named_by_last_edit = match self.state.history.last_undo() {
                Some(Command::SetRow { before, after, .. }) => {
                    let old = unloaded_paths(before, assets);
                    unloaded_paths(after, assets)
                        .iter()
                        .any(|p| !old.contains(p))
                }
                _ => false,
            };
            self.dialogs.error = Some(if named_by_last_edit {
                match self.state.undo() {
                    Ok(_) => format!("{e}\n\nThe edit that named it was undone."),
                    Err(u) => format!("{e} (and the edit could not be undone: {u})"),
                }
            } else {
                e
            });
            ctx.request_repaint();
        }
        self.assets_checked = self.state.document.revision;
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

    fn close_request(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested())
            && self.state.is_dirty()
            && !self.allow_close
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.dialogs.confirm = Some(Pending::Quit);
        }
    }

    fn autosave(&mut self) {
        let id = self.state.history.state_id();
        if self.state.is_dirty()
            && id != self.autosaved_id
            && self.last_autosave.elapsed() >= files::AUTOSAVE_EVERY
        {
            self.autosave_now();
        }
    }

    /// Where the document is autosaved: beside its level, or for an untitled document beside
    /// the recent-files list (none when there is no such place).
    pub fn autosave_file(&self) -> Option<PathBuf> {
        match &self.state.document.path {
            Some(level) => Some(files::autosave_path(level)),
            None => self.recent.untitled_autosave(),
        }
    }

    /// Writes the autosave now.
    pub fn autosave_now(&mut self) {
        self.last_autosave = Instant::now();
        self.autosaved_id = self.state.history.state_id();
        let Some(file) = self.autosave_file() else {
            return;
        };
        let before = files::autosave_heightmaps(&file);
        match self.state.document.write_autosave(&file) {
            // Heightmaps the previous autosave kept and this one does not are dropped.
            Ok(kept) => {
                for png in before.iter().filter(|p| !kept.contains(p)) {
                    let _ = std::fs::remove_file(png);
                }
            }
            Err(e) => self.dialogs.error = Some(format!("autosave failed: {e}")),
        }
    }

    fn discard_autosave(&mut self) {
        if let Some(file) = self.autosave_file() {
            files::remove_autosave_file(&file);
        }
    }
}

impl eframe::App for EditorApp {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        EditorApp::ui(self, ui);
    }
}
