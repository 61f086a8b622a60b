//! Undo and redo stacks of [`Command`]s.
//!
//! An edit that continues over several frames (a drag, typing into a field) is pushed with
//! a merge key; while the entry stays open, later pushes with the same key fold into it, so
//! the whole gesture is one undo step. [`History::seal`] closes the entry when the gesture ends.

use crate::command::Command;

/// Identifies what a continuing edit is about: pushes with equal keys fold into one step
/// while the entry is open.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MergeKey {
    /// The inspector editing the row of the entity at `index` through one widget.
    Row {
        /// Position in the level order.
        index: usize,
        /// The widget being dragged or typed into.
        widget: egui::Id,
    },
    /// The inspector editing the level settings through one widget.
    Settings {
        /// The widget being dragged or typed into.
        widget: egui::Id,
    },
    /// The palette section editing the level's palette through one widget (a swatch's
    /// colour picker, the dither slider).
    Palette {
        /// The widget being dragged or typed into.
        widget: egui::Id,
    },
    /// The viewport gizmo dragging the entity at `index`.
    Gizmo {
        /// Position in the level order.
        index: usize,
    },
    /// A face handle resizing the probe-grid override of the entity at `index`.
    Resize {
        /// Position in the level order.
        index: usize,
    },
}

struct Entry {
    command: Command,
    merge: Option<MergeKey>,
    id: u64,
}

/// The command history.
#[derive(Default)]
pub struct History {
    undo: Vec<Entry>,
    redo: Vec<Entry>,
    open: bool,
    next_id: u64,
}

impl History {
    /// Records an executed command. Returns true when it was folded into the last entry.
    pub fn push(&mut self, command: Command, merge: Option<MergeKey>) -> bool {
        self.redo.clear();
        self.next_id += 1;
        if let (true, Some(key), Some(last)) = (self.open, merge, self.undo.last_mut())
            && last.merge == Some(key)
            && last.command.absorb(&command)
        {
            last.id = self.next_id;
            return true;
        }
        self.undo.push(Entry {
            command,
            merge,
            id: self.next_id,
        });
        self.open = true;
        false
    }

    /// Ends the current gesture: the next push starts a new step.
    pub fn seal(&mut self) {
        self.open = false;
    }

    /// Moves the last step to the redo stack and returns it, for the caller to revert.
    pub fn pop_undo(&mut self) -> Option<&Command> {
        self.open = false;
        let e = self.undo.pop()?;
        self.redo.push(e);
        self.redo.last().map(|e| &e.command)
    }

    /// Moves the last undone step back and returns it, for the caller to execute.
    pub fn pop_redo(&mut self) -> Option<&Command> {
        self.open = false;
        let e = self.redo.pop()?;
        self.undo.push(e);
        self.undo.last().map(|e| &e.command)
    }

    /// Puts back an undo that could not be reverted.
    pub fn cancel_undo(&mut self) {
        if let Some(e) = self.redo.pop() {
            self.undo.push(e);
        }
    }

    /// Puts back a redo that could not be executed.
    pub fn cancel_redo(&mut self) {
        if let Some(e) = self.undo.pop() {
            self.redo.push(e);
        }
    }

    /// Identifies the current document state: equal ids mean equal documents.
    pub fn state_id(&self) -> u64 {
        self.undo.last().map_or(0, |e| e.id)
    }

    /// Description of the next undo, if any.
    pub fn undo_label(&self) -> Option<&'static str> {
        self.undo.last().map(|e| e.command.describe())
    }

    /// Description of the next redo, if any.
    pub fn redo_label(&self) -> Option<&'static str> {
        self.redo.last().map(|e| e.command.describe())
    }

    /// The step the next undo would revert.
    pub fn last_undo(&self) -> Option<&Command> {
        self.undo.last().map(|e| &e.command)
    }

    /// Every step kept, undoable and redoable.
    pub fn commands(&self) -> impl Iterator<Item = &Command> {
        self.undo.iter().chain(&self.redo).map(|e| &e.command)
    }

    /// Number of undo steps.
    pub fn undo_len(&self) -> usize {
        self.undo.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_scene::LevelSettings;

    fn settings(bands: u32) -> Command {
        let before = LevelSettings::default();
        let after = LevelSettings { bands, ..before };
        Command::SetSettings { before, after }
    }

    #[test]
    fn only_pushes_with_the_same_key_fold() {
        let mut h = History::default();
        let (a, b) = (egui::Id::unique("a"), egui::Id::unique("b"));
        let key = |widget| Some(MergeKey::Settings { widget });
        assert!(!h.push(settings(3), key(a)));
        assert!(h.push(settings(4), key(a)));
        assert!(!h.push(settings(5), key(b)));
        assert!(!h.push(settings(6), None));
        assert!(!h.push(settings(7), None), "no key never folds");
        h.seal();
        assert!(!h.push(settings(8), key(a)), "a sealed entry stays closed");
        assert_eq!(h.undo_len(), 5);
    }
}
