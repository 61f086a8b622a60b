//! Undo and redo stacks of [`Command`]s.
//!
//! An edit that continues over several frames (a drag, typing into a field) is pushed with
//! a merge key; while the entry stays open, later pushes with the same key fold into it, so
//! the whole gesture is one undo step. [`History::seal`] closes the entry when the gesture ends.

use crate::command::Command;

/// Identifies what a continuing edit is about, e.g. "entity 3's transform".
pub type MergeKey = String;

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
        if let (true, Some(key), Some(last)) = (self.open, &merge, self.undo.last_mut())
            && last.merge.as_ref() == Some(key)
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

    /// Number of undo steps.
    pub fn undo_len(&self) -> usize {
        self.undo.len()
    }
}
