//! The selection's keys (Ctrl+A, Ctrl+Shift+A, Esc) and the clipboard: copy, cut and paste
//! of entities as RON text ([`crate::clipboard`]), through egui's clipboard events (the
//! window turns Ctrl+C, Ctrl+X and Ctrl+V into them) and commands.

use egui::{Event, Key, KeyboardShortcut, Modifiers};

use super::EditorApp;
use crate::ui::menu::Action;

impl EditorApp {
    /// What the selection keys and the clipboard events of this frame ask for (outside
    /// text fields; the caller checks). Esc selects nothing only outside Play, where it
    /// stops Play, and when no widget had the keyboard in the last frame (egui lets go of
    /// the focus on Esc before the frame starts: that Esc ends typing).
    pub(super) fn selection_shortcuts(&self, ctx: &egui::Context) -> Vec<Action> {
        let mut out = Vec::new();
        let escapes = !self.viewport.playing() && self.focus_seen.is_none();
        let cmd = Modifiers::COMMAND;
        ctx.input_mut(|i| {
            if i.consume_shortcut(&KeyboardShortcut::new(cmd | Modifiers::SHIFT, Key::A)) {
                out.push(Action::SelectNone);
            }
            if i.consume_shortcut(&KeyboardShortcut::new(cmd, Key::A)) {
                out.push(Action::SelectAll);
            }
            if escapes && i.key_pressed(Key::Escape) {
                out.push(Action::SelectNone);
            }
            for e in &i.events {
                match e {
                    Event::Copy => out.push(Action::Copy),
                    Event::Cut => out.push(Action::Cut),
                    Event::Paste(text) => out.push(Action::Paste(text.clone())),
                    _ => {}
                }
            }
        });
        out
    }

    /// Puts the selected entities on the clipboard as RON (and deletes them, as one undo
    /// step, for a cut). Nothing selected: nothing happens.
    pub(super) fn copy(&mut self, cut: bool) {
        // A parent's descendants go with it, relative to it, as in a level file.
        let rows = self.state.rows_for_copy(&self.state.selected());
        if rows.is_empty() {
            return;
        }
        match crate::clipboard::to_text(rows) {
            Ok(text) => {
                if let Some(ctx) = &self.ctx {
                    ctx.copy_text(text.clone());
                }
                self.copied = Some(text);
            }
            Err(e) => {
                self.dialogs.error = Some(format!("cannot copy: {e}"));
                return;
            }
        }
        if cut {
            let deleted = self.state.delete_selection();
            self.report("cut", deleted);
        }
    }

    /// Asks the window for the clipboard's text; it comes back as a paste event.
    pub(super) fn request_paste(&self) {
        if let Some(ctx) = &self.ctx {
            ctx.send_viewport_cmd(egui::ViewportCommand::RequestPaste);
        }
    }

    /// Adds the entities `text` holds at the end of the level, as one undo step, and selects
    /// them; text that holds none is refused with a message and changes nothing.
    pub(super) fn paste(&mut self, text: &str) {
        match crate::clipboard::from_text(text) {
            Ok(rows) => {
                self.viewport.stop();
                let pasted = self.state.paste_rows(rows);
                self.report("paste", pasted);
            }
            Err(e) => self.dialogs.error = Some(format!("cannot paste: {e}")),
        }
    }

    /// The text the last copy or cut put on the clipboard.
    pub fn copied(&self) -> Option<&str> {
        self.copied.as_deref()
    }
}
