//! The editor's file chores: asking before work is lost and acting on the dialogs' answers,
//! saving and recovering, meshes, sprites and heightmaps brought in from files (picked or
//! dropped) or written out, assets a new edit names, and the autosave.

use std::path::{Path, PathBuf};
use std::time::Instant;

use texel_scene::{EntityRow, Geometry, Material, Name, Transform};

use crate::command::Command;
use crate::document::{Document, unloaded_paths};
use crate::files::{self, Picked};
use crate::state::EditorState;
use crate::ui::dialogs::{Answer, Pending, Prompt, Purpose};

use super::EditorApp;

impl EditorApp {
    /// Runs `pending` now, or after "discard changes?" when the document is modified.
    pub(super) fn guard(&mut self, pending: Pending) {
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
    pub(super) fn ask(&mut self, purpose: Purpose) {
        let picked = match purpose {
            Purpose::Open => files::pick_open(),
            Purpose::SaveAs => files::pick_save(self.state.document.path.as_deref()),
            Purpose::Mesh => files::pick_mesh(),
            Purpose::Sprite => files::pick_sprite(),
            Purpose::ImportHeightmap => files::pick_heightmap(),
            Purpose::ExportHeightmap => files::pick_heightmap_save(&self.export_name()),
            Purpose::Palette(_) => files::pick_palette(),
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

    pub(super) fn answer(&mut self, answer: Answer) {
        match answer {
            Answer::Path(Purpose::Open, p) => self.proceed(Pending::Open(Some(p))),
            Answer::Path(Purpose::SaveAs, p) => self.save_to(&p),
            Answer::Path(Purpose::Mesh, p) => self.add_mesh(&p),
            Answer::Path(Purpose::Sprite, p) => self.add_sprite(&p),
            Answer::Path(Purpose::ImportHeightmap, p) => self.import_heightmap(&p),
            Answer::Path(Purpose::ExportHeightmap, p) => self.export_heightmap(&p),
            Answer::Path(Purpose::Palette(slot), p) => self.pick_palette(slot, &p),
            Answer::Discard(pending) => self.proceed(pending),
            Answer::Recover(p) => self.recover(&p),
        }
    }

    /// Saves to `path` (atomically) and forgets the autosave.
    pub fn save_to(&mut self, path: &Path) {
        // An autosave still being written would land after the save and outlive it.
        self.finish_autosave();
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

    pub(super) fn add_mesh(&mut self, file: &Path) {
        // At the surface under the viewport's centre (or the ground there).
        let at = self.viewport.place_point(&self.state);
        self.add_mesh_at(file, at);
    }

    /// Adds the glTF mesh `file` with its origin at `at`, as one undo step; a mesh that does
    /// not load is shown in the error dialog and taken out again.
    pub(super) fn add_mesh_at(&mut self, file: &Path, at: glam::Vec3) {
        let Some(level) = self.state.document.path.clone() else {
            self.dialogs.error =
                Some("save the level first: mesh paths are relative to the level file".into());
            return;
        };
        let rel = crate::assets::level_relative(&level, file);
        let row = EntityRow {
            name: file
                .file_stem()
                .map(|s| Name(s.to_string_lossy().into_owned())),
            transform: Some(Transform::from_translation(at)),
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

    /// Adds a sprite of the sheet `file` standing where Add places things
    /// ([`crate::viewport::Viewport::place_point`], [`crate::add_sprite::add_sprite`]); a file
    /// that is not an image is shown in the error dialog, and nothing is added.
    pub fn add_sprite(&mut self, file: &Path) {
        self.viewport.stop();
        let at = self.viewport.place_point(&self.state);
        if let Err(e) = crate::add_sprite::add_sprite(&mut self.state, file, at) {
            self.dialogs.error = Some(format!("cannot add the sprite: {e}"));
        }
    }

    /// Makes the palette file `file` the level's palette or its alternate (one undo step);
    /// a file that cannot be used is shown in the error dialog (its file and line), and
    /// nothing changes.
    pub fn pick_palette(&mut self, slot: crate::palette_edits::Slot, file: &Path) {
        if let Err(e) = self.state.pick_palette(slot, file) {
            self.dialogs.error = Some(format!("cannot use the palette: {e}"));
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

    pub(super) fn dropped_files(&mut self, ctx: &egui::Context) {
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
    pub(super) fn load_new_assets(&mut self, ctx: &egui::Context) {
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

    pub(super) fn close_request(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested())
            && self.state.is_dirty()
            && !self.allow_close
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.dialogs.confirm = Some(Pending::Quit);
        }
    }

    /// Autosaves a modified document every [`files::AUTOSAVE_EVERY`], or sooner after
    /// [`files::AUTOSAVE_AFTER_EDITS`] edits, on a thread of its own (the rows and images are
    /// taken now; formatting and writing them does not hold up the window). One write at a
    /// time; each is atomic, so a crash mid-write leaves the previous autosave. While changes
    /// wait for their autosave, `ctx` is asked to repaint when it falls due, so an idle window
    /// (no input, no frames) still writes it.
    pub(super) fn autosave(&mut self, ctx: &egui::Context) {
        if self.autosaving.as_ref().is_some_and(|h| h.is_finished()) {
            self.finish_autosave();
        }
        let id = self.state.history.state_id();
        if id != self.edits_seen.0 {
            self.edits_seen = (id, self.edits_seen.1.saturating_add(1));
        }
        let due = self.last_autosave.elapsed() >= files::AUTOSAVE_EVERY
            || self.edits_seen.1 >= files::AUTOSAVE_AFTER_EDITS;
        let waiting = self.state.is_dirty() && id != self.autosaved_id;
        if waiting && !(due && self.autosaving.is_none()) {
            let left = files::AUTOSAVE_EVERY.saturating_sub(self.last_autosave.elapsed());
            ctx.request_repaint_after(left.max(std::time::Duration::from_millis(100)));
        }
        if !(waiting && due && self.autosaving.is_none()) {
            return;
        }
        self.last_autosave = Instant::now();
        self.autosaved_id = id;
        self.edits_seen.1 = 0;
        let Some(file) = self.autosave_file() else {
            return;
        };
        let job = self.state.document.autosave_job(&file);
        self.autosaving = Some(std::thread::spawn(move || write_autosave_job(job)));
    }

    /// Waits for the autosave being written, if any, and reports its failure.
    pub(super) fn finish_autosave(&mut self) {
        let Some(handle) = self.autosaving.take() else {
            return;
        };
        let result = (handle.join()).unwrap_or_else(|_| Err("the autosave thread panicked".into()));
        if let Err(e) = result {
            self.dialogs.error = Some(format!("autosave failed: {e}"));
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

    /// Writes the autosave now (after the one being written, if any).
    pub fn autosave_now(&mut self) {
        self.finish_autosave();
        self.last_autosave = Instant::now();
        self.autosaved_id = self.state.history.state_id();
        self.edits_seen.1 = 0;
        let Some(file) = self.autosave_file() else {
            return;
        };
        if let Err(e) = write_autosave_job(self.state.document.autosave_job(&file)) {
            self.dialogs.error = Some(format!("autosave failed: {e}"));
        }
    }

    /// Whether an autosave is being written beside the editor.
    pub fn autosave_in_flight(&self) -> bool {
        self.autosaving.is_some()
    }

    fn discard_autosave(&mut self) {
        self.finish_autosave();
        if let Some(file) = self.autosave_file() {
            files::remove_autosave_file(&file);
        }
    }
}

/// Writes `job`, then drops the heightmaps the previous autosave in its place kept and this
/// one does not.
fn write_autosave_job(job: crate::document::AutosaveJob) -> Result<(), String> {
    let before = files::autosave_heightmaps(&job.file);
    let kept = job.write()?;
    for png in before.iter().filter(|p| !kept.contains(p)) {
        let _ = std::fs::remove_file(png);
    }
    Ok(())
}
