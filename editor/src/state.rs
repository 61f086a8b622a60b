//! The editor's state: the document, what is selected, and the history of commands.
//! Panels borrow the parts they need; every change goes through [`EditorState::apply`].

use std::path::Path;

use texel_scene::{EntityRow, Scene};

use crate::command::{Command, CommandError, Focus, entity_at};
use crate::document::Document;
use crate::history::{History, MergeKey};

/// Which entity is selected, by position in the level order.
pub type Selection = Option<usize>;

/// Document, selection and history.
pub struct EditorState {
    /// The level being edited.
    pub document: Document,
    /// The selected entity.
    pub selection: Selection,
    /// Undo and redo.
    pub history: History,
    saved_id: u64,
}

impl EditorState {
    /// Starts editing `document` (unmodified).
    pub fn new(document: Document) -> Self {
        EditorState {
            document,
            selection: None,
            history: History::default(),
            saved_id: 0,
        }
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        self.document.scene()
    }

    /// Executes `command` and records it (folded into the open step with the same `merge`).
    pub fn apply(&mut self, command: Command, merge: Option<MergeKey>) -> Result<(), CommandError> {
        let focus = command.execute(self.document.scene_mut())?;
        self.focus(focus);
        self.history.push(command, merge);
        Ok(())
    }

    /// Undoes the last step; false when there is none.
    pub fn undo(&mut self) -> bool {
        let Some(cmd) = self.history.pop_undo().cloned() else {
            return false;
        };
        match cmd.revert(self.document.scene_mut()) {
            Ok(f) => {
                self.focus(f);
                true
            }
            Err(_) => {
                self.history.cancel_undo();
                false
            }
        }
    }

    /// Redoes the last undone step; false when there is none.
    pub fn redo(&mut self) -> bool {
        let Some(cmd) = self.history.pop_redo().cloned() else {
            return false;
        };
        match cmd.execute(self.document.scene_mut()) {
            Ok(f) => {
                self.focus(f);
                true
            }
            Err(_) => {
                self.history.cancel_redo();
                false
            }
        }
    }

    fn focus(&mut self, focus: Focus) {
        match focus {
            Focus::Keep => {}
            Focus::Entity(i) => self.selection = Some(i),
            Focus::Nothing => self.selection = None,
        }
        if self.selection.is_some_and(|i| i >= self.scene().len()) {
            self.selection = None;
        }
    }

    /// Whether there are changes since the last save (or open).
    pub fn is_dirty(&self) -> bool {
        self.history.state_id() != self.saved_id
    }

    /// Saves to `path` and marks the document clean.
    pub fn save_as(&mut self, path: &Path) -> Result<(), String> {
        self.document.save_as(path)?;
        self.saved_id = self.history.state_id();
        Ok(())
    }

    /// Marks the document modified though its history says otherwise (a recovered autosave).
    pub fn mark_dirty(&mut self) {
        self.saved_id = u64::MAX;
    }

    /// The selected entity's components.
    pub fn selected_row(&self) -> Option<(usize, EntityRow)> {
        let i = self.selection?;
        let e = entity_at(self.scene(), i).ok()?;
        Some((i, self.scene().row(e)?))
    }

    /// The components of the entity at `index`.
    pub fn row_at(&self, index: usize) -> Option<EntityRow> {
        let e = entity_at(self.scene(), index).ok()?;
        self.scene().row(e)
    }

    /// Replaces the components of the entity at `index` (one undo step per gesture `merge`).
    pub fn set_row(&mut self, index: usize, after: EntityRow, merge: Option<MergeKey>) {
        if let Some(before) = self.row_at(index)
            && before != after
        {
            let cmd = Command::SetRow {
                index,
                before: Box::new(before),
                after: Box::new(after),
            };
            let _ = self.apply(cmd, merge);
        }
    }

    /// Adds an entity at the end of the level and selects it.
    pub fn add(&mut self, row: EntityRow) {
        let index = self.scene().len();
        let _ = self.apply(
            Command::Spawn {
                index,
                row: Box::new(row),
            },
            None,
        );
    }

    /// Duplicates the entity at `index`, placing the copy right after it.
    pub fn duplicate(&mut self, index: usize) {
        if let Some(mut row) = self.row_at(index) {
            if let Some(n) = &mut row.name {
                n.0.push_str(" copy");
            }
            let _ = self.apply(
                Command::Spawn {
                    index: index + 1,
                    row: Box::new(row),
                },
                None,
            );
        }
    }

    /// Deletes the entity at `index`.
    pub fn delete(&mut self, index: usize) {
        if let Some(row) = self.row_at(index) {
            let _ = self.apply(
                Command::Despawn {
                    index,
                    row: Box::new(row),
                },
                None,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_scene::{Name, Transform};

    fn boxed(name: &str) -> EntityRow {
        EntityRow {
            name: Some(Name(name.into())),
            transform: Some(Transform::default()),
            ..EntityRow::default()
        }
    }

    #[test]
    fn undo_redo_round_trip_and_dirty_mark() {
        let mut s = EditorState::new(Document::new_empty());
        assert!(!s.is_dirty());
        s.add(boxed("a"));
        s.duplicate(0);
        assert_eq!(s.scene().len(), 2);
        assert_eq!(s.selection, Some(1));
        assert!(s.is_dirty());
        assert!(s.undo());
        assert!(s.undo());
        assert!(!s.is_dirty());
        assert!(s.scene().is_empty());
        assert!(!s.undo());
        assert!(s.redo());
        assert!(s.redo());
        assert_eq!(s.scene().len(), 2);
        assert_eq!(
            s.row_at(1).and_then(|r| r.name).map(|n| n.0),
            Some("a copy".to_owned())
        );
    }

    #[test]
    fn a_gesture_is_one_step() {
        let mut s = EditorState::new(Document::new_empty());
        s.add(boxed("a"));
        s.history.seal();
        for x in 1..=5 {
            let mut r = boxed("a");
            if let Some(t) = &mut r.transform {
                t.translation.x = x as f32;
            }
            s.set_row(0, r, Some("t0".into()));
        }
        s.history.seal();
        assert_eq!(s.history.undo_len(), 2);
        assert!(s.undo());
        assert_eq!(s.row_at(0), Some(boxed("a")));
    }
}
