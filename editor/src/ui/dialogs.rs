//! Modal-ish windows: errors, "discard unsaved changes?", a typed path where no native
//! dialog exists, and the offer to recover an autosave.

use std::path::PathBuf;

use egui::Context;

/// What a typed path is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Purpose {
    /// Open a level.
    Open,
    /// Save the level.
    SaveAs,
    /// Add a glTF mesh.
    Mesh,
    /// Add a sprite of a sheet.
    Sprite,
    /// Import a heightmap into the selected terrain.
    ImportHeightmap,
    /// Export the selected terrain's heightmap.
    ExportHeightmap,
    /// Pick the level's palette or its alternate.
    Palette(crate::palette_edits::Slot),
}

/// A typed-path prompt.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Prompt {
    /// What the path is for.
    pub purpose: Purpose,
    /// The text typed so far.
    pub text: String,
}

/// What waits for "discard unsaved changes?".
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Pending {
    /// A new level.
    New,
    /// Opening another level (asks where when `None`).
    Open(Option<PathBuf>),
    /// Closing the editor.
    Quit,
}

/// What a dialog answered this frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Answer {
    /// A typed path was confirmed.
    Path(Purpose, PathBuf),
    /// Discard changes and carry on with the pending action.
    Discard(Pending),
    /// Recover the autosave.
    Recover(PathBuf),
}

/// Dialog state.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Dialogs {
    /// An error to show (e.g. `level.ron:3:7: …`).
    pub error: Option<String>,
    /// A typed-path prompt.
    pub prompt: Option<Prompt>,
    /// An action waiting for confirmation.
    pub confirm: Option<Pending>,
    /// An autosave that can be recovered.
    pub recover: Option<PathBuf>,
}

impl Dialogs {
    /// Whether any dialog is open (the viewport ignores keys then).
    pub fn any_open(&self) -> bool {
        self.error.is_some()
            || self.prompt.is_some()
            || self.confirm.is_some()
            || self.recover.is_some()
    }

    /// Draws the open dialogs and returns what was answered.
    pub fn show(&mut self, ctx: &Context) -> Option<Answer> {
        let mut out = None;
        if let Some(e) = &self.error {
            let mut close = false;
            egui::Window::new("Error")
                .collapsible(false)
                .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
                .show(ctx, |ui| {
                    ui.label(egui::RichText::new(e).color(egui::Color32::from_rgb(255, 130, 130)));
                    close = ui.button("OK").clicked();
                });
            if close {
                self.error = None;
            }
        }
        if let Some(p) = &mut self.prompt {
            let mut done = None;
            let title = match p.purpose {
                Purpose::Open => "Open level (path)",
                Purpose::SaveAs => "Save level as (path)",
                Purpose::Mesh => "Add glTF mesh (path)",
                Purpose::Sprite => "Add sprite sheet (PNG path)",
                Purpose::ImportHeightmap => "Import 16-bit heightmap (path)",
                Purpose::ExportHeightmap => "Export 16-bit heightmap (path)",
                Purpose::Palette(_) => "Palette file (.gpl, .hex or .pal path)",
            };
            egui::Window::new(title)
                .collapsible(false)
                .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
                .show(ctx, |ui| {
                    ui.label("No file dialog is available here; type a path.");
                    let r = ui
                        .add(egui::TextEdit::singleline(&mut p.text).desired_width(360.0))
                        .accessible_name("Path");
                    let enter = r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    ui.horizontal(|ui| {
                        if ui.button("OK").clicked() || enter {
                            done = Some(true);
                        }
                        if ui.button("Cancel").clicked() {
                            done = Some(false);
                        }
                    });
                });
            match done {
                Some(true) if !p.text.trim().is_empty() => {
                    out = Some(Answer::Path(p.purpose, PathBuf::from(p.text.trim())));
                    self.prompt = None;
                }
                Some(_) => self.prompt = None,
                None => {}
            }
        }
        if let Some(pending) = &self.confirm {
            let mut done = None;
            egui::Window::new("Unsaved changes")
                .collapsible(false)
                .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
                .show(ctx, |ui| {
                    ui.label("The level has unsaved changes. Discard them?");
                    ui.horizontal(|ui| {
                        if ui.button("Discard").clicked() {
                            done = Some(true);
                        }
                        if ui.button("Keep editing").clicked() {
                            done = Some(false);
                        }
                    });
                });
            match done {
                Some(true) => {
                    out = Some(Answer::Discard(pending.clone()));
                    self.confirm = None;
                }
                Some(false) => self.confirm = None,
                None => {}
            }
        }
        if let Some(path) = &self.recover {
            let mut done = None;
            egui::Window::new("Recover autosave?")
                .collapsible(false)
                .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
                .show(ctx, |ui| {
                    ui.label(format!(
                        "An autosave newer than the level exists:\n{}",
                        path.display()
                    ));
                    ui.horizontal(|ui| {
                        let recover = ui.button("Recover").on_hover_text("Enter");
                        if recover.clicked() {
                            done = Some(true);
                        }
                        if ui.button("Ignore").clicked() {
                            done = Some(false);
                        }
                    });
                });
            // Enter recovers (the offer's default), unless a text field takes the key.
            if !ctx.egui_wants_keyboard_input() && ctx.input(|i| i.key_pressed(egui::Key::Enter)) {
                done = Some(true);
            }
            match done {
                Some(true) => {
                    out = Some(Answer::Recover(path.clone()));
                    self.recover = None;
                }
                Some(false) => self.recover = None,
                None => {}
            }
        }
        out
    }
}
