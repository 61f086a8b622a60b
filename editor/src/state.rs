//! The editor's state: the document, what is selected, and the history of commands.
//! Panels borrow the parts they need; every change goes through [`EditorState::apply`].

use std::collections::BTreeSet;
use std::path::Path;

use texel_scene::{EntityRow, Scene};

use crate::command::{Command, CommandError, Focus, entity_at};
use crate::document::Document;
use crate::history::{History, MergeKey};

/// Which entity is selected, by position in the level order.
pub type Selection = Option<usize>;

/// Document, selection and history.
///
/// The selection is the active entity ([`EditorState::selection`]: the one last clicked,
/// whose components the inspector shows and the single-entity tools use) and the others
/// selected with it ([`EditorState::also_selected`]); `crate::selection` has the ways to
/// change it.
pub struct EditorState {
    /// The level being edited.
    pub document: Document,
    /// The active entity (`None`: nothing is selected, whatever `also_selected` holds).
    pub selection: Selection,
    /// The other entities selected with the active one.
    pub also_selected: BTreeSet<usize>,
    /// Undo and redo.
    pub history: History,
    /// What is hidden and locked (editor-only, [`crate::visibility`]).
    pub visibility: crate::visibility::Visibility,
    saved_id: u64,
}

impl EditorState {
    /// Starts editing `document` (unmodified).
    pub fn new(document: Document) -> Self {
        EditorState {
            document,
            selection: None,
            also_selected: BTreeSet::new(),
            history: History::default(),
            visibility: Default::default(),
            saved_id: 0,
        }
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        self.document.scene()
    }

    /// Executes `command` and records it (folded into the open step with the same `merge`).
    pub fn apply(&mut self, command: Command, merge: Option<MergeKey>) -> Result<(), CommandError> {
        let (scene, assets) = self.parts_for(&command, true);
        let focus = command.execute(scene, assets)?;
        self.focus(focus);
        self.history.push(command, merge);
        Ok(())
    }

    /// Undoes the last step: `Ok(false)` when there is none; an error (with the step kept
    /// on the undo stack) when the scene no longer matches it.
    pub fn undo(&mut self) -> Result<bool, CommandError> {
        let Some(cmd) = self.history.pop_undo().cloned() else {
            return Ok(false);
        };
        let (scene, assets) = self.parts_for(&cmd, false);
        match cmd.revert(scene, assets) {
            Ok(f) => {
                self.focus(f);
                Ok(true)
            }
            Err(e) => {
                self.history.cancel_undo();
                Err(e)
            }
        }
    }

    /// Redoes the last undone step: `Ok(false)` when there is none; an error (with the step
    /// kept on the redo stack) when the scene no longer matches it.
    pub fn redo(&mut self) -> Result<bool, CommandError> {
        let Some(cmd) = self.history.pop_redo().cloned() else {
            return Ok(false);
        };
        let (scene, assets) = self.parts_for(&cmd, true);
        match cmd.execute(scene, assets) {
            Ok(f) => {
                self.focus(f);
                Ok(true)
            }
            Err(e) => {
                self.history.cancel_redo();
                Err(e)
            }
        }
    }

    /// The scene and assets for `command` to change, executed (`forward`) or reverted:
    /// marked as entities' changes when it replaces, adds or removes entities, so the
    /// viewport takes in those entities alone.
    fn parts_for(
        &mut self,
        command: &Command,
        forward: bool,
    ) -> (&mut Scene, &mut texel_scene::assets::AssetLibrary) {
        let edited = match command {
            Command::SetRow { index, .. } => Some(vec![*index]),
            _ => command.edited_rows(),
        };
        match (command, edited) {
            (Command::SetPalette { .. }, _) => self.document.palette_parts_mut(),
            // A parent's children move with it: they are taken in too.
            (_, Some(rows)) if self.scene().has_hierarchy() => {
                let rows = self.with_descendants(&rows);
                self.document.entities_parts_mut(&rows)
            }
            (Command::SetRow { index, .. }, _) => self.document.entity_parts_mut(*index),
            (_, Some(rows)) => self.document.entities_parts_mut(&rows),
            // Entities added or removed: taken in alone too.
            (_, None) => match command.row_edits(forward) {
                Some(edits) if !self.scene().has_hierarchy() => {
                    self.document.rows_parts_mut(&edits)
                }
                _ => self.document.parts_mut(),
            },
        }
    }

    fn focus(&mut self, focus: Focus) {
        match focus {
            Focus::Keep => {}
            Focus::Entity(i) if self.is_selected(i) => {}
            Focus::Entity(i) => self.select_only(i),
            Focus::Entities(v) => {
                let active = self.selection.filter(|a| v.contains(a));
                self.select_many(v, active);
            }
            Focus::Nothing => self.select_none(),
        }
        let len = self.scene().len();
        self.also_selected.retain(|&i| i < len);
        if self.selection.is_some_and(|i| i >= len) {
            self.selection = self.also_selected.pop_last();
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

    /// Reloads the meshes and textures the scene names ([`Document::reload_assets`]), keeping
    /// in memory the terrain heights of the scene and of every step undo or redo can bring
    /// back.
    pub fn reload_assets(&mut self) -> Result<(), String> {
        let terrains: Vec<_> = self
            .history
            .commands()
            .flat_map(|c| c.rows())
            .filter_map(|r| r.terrain.clone())
            .collect();
        self.document.reload_assets_keeping(&terrains)
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

    /// Replaces the components of the entity at `index` (one undo step per gesture `merge`);
    /// nothing happens when they are unchanged.
    pub fn set_row(
        &mut self,
        index: usize,
        after: EntityRow,
        merge: Option<MergeKey>,
    ) -> Result<(), CommandError> {
        let before = self.existing_row(index)?;
        if before == after {
            return Ok(());
        }
        let cmd = Command::SetRow {
            index,
            before: Box::new(before),
            after: Box::new(after),
        };
        self.apply(cmd, merge)
    }

    /// Adds an entity at the end of the level and selects it.
    pub fn add(&mut self, row: EntityRow) -> Result<(), CommandError> {
        let index = self.scene().len();
        let row = Box::new(row);
        self.apply(Command::Spawn { index, row }, None)
    }

    /// Duplicates the entity at `index` (and its descendants), placing the copy right after
    /// it.
    pub fn duplicate(&mut self, index: usize) -> Result<(), CommandError> {
        self.existing_row(index)?;
        self.duplicate_indices(&[index])
    }

    /// Deletes the entity at `index` (and its descendants).
    pub fn delete(&mut self, index: usize) -> Result<(), CommandError> {
        self.existing_row(index)?;
        self.delete_indices(&[index])
    }

    /// The components of the entity at `index`, or why there is none.
    fn existing_row(&self, index: usize) -> Result<EntityRow, CommandError> {
        self.row_at(index)
            .ok_or_else(|| CommandError(format!("no entity at position {index}")))
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

    /// Adding, duplicating and deleting entities (and undoing them) are marked as those
    /// changes of rows, in order, so the viewport takes them in alone.
    #[test]
    fn adds_and_deletes_are_marked_as_row_changes() {
        use texel_runtime::frame_plan::RowEdit::{Insert, Remove};
        let mut s = EditorState::new(Document::new_empty());
        let r0 = s.document.revision;
        s.add(boxed("a")).expect("add");
        s.add(boxed("b")).expect("add");
        s.duplicate(0).expect("duplicate");
        assert_eq!(
            s.document.entities_since(r0),
            Some(vec![Insert(0), Insert(1), Insert(1)])
        );
        let r1 = s.document.revision;
        s.delete_indices(&[0, 2]).expect("delete");
        assert_eq!(
            s.document.entities_since(r1),
            Some(vec![Remove(2), Remove(0)])
        );
        let r2 = s.document.revision;
        assert_eq!(s.undo(), Ok(true));
        assert_eq!(
            s.document.entities_since(r2),
            Some(vec![Insert(0), Insert(2)])
        );
        assert_eq!(s.scene().len(), 3);
    }

    #[test]
    fn undo_redo_round_trip_and_dirty_mark() {
        let mut s = EditorState::new(Document::new_empty());
        assert!(!s.is_dirty());
        s.add(boxed("a")).expect("add");
        s.duplicate(0).expect("duplicate");
        assert_eq!(s.scene().len(), 2);
        assert_eq!(s.selection, Some(1));
        assert!(s.is_dirty());
        assert_eq!(s.undo(), Ok(true));
        assert_eq!(s.undo(), Ok(true));
        assert!(!s.is_dirty());
        assert!(s.scene().is_empty());
        assert_eq!(s.undo(), Ok(false));
        assert_eq!(s.redo(), Ok(true));
        assert_eq!(s.redo(), Ok(true));
        assert_eq!(s.scene().len(), 2);
        assert_eq!(
            s.row_at(1).and_then(|r| r.name).map(|n| n.0),
            Some("a copy".to_owned())
        );
    }

    #[test]
    fn a_gesture_is_one_step() {
        let mut s = EditorState::new(Document::new_empty());
        s.add(boxed("a")).expect("add");
        s.history.seal();
        for x in 1..=5 {
            let mut r = boxed("a");
            if let Some(t) = &mut r.transform {
                t.translation.x = x as f32;
            }
            s.set_row(0, r, Some(MergeKey::Gizmo { index: 0 }))
                .expect("set");
        }
        s.history.seal();
        assert_eq!(s.history.undo_len(), 2);
        assert_eq!(s.undo(), Ok(true));
        assert_eq!(s.row_at(0), Some(boxed("a")));
    }

    #[test]
    fn failed_commands_are_errors_and_leave_the_history_alone() {
        let mut s = EditorState::new(Document::new_empty());
        assert!(s.delete(0).is_err());
        assert!(s.duplicate(3).is_err());
        assert!(s.set_row(0, boxed("x"), None).is_err());
        assert_eq!(s.history.undo_len(), 0);
        s.add(boxed("a")).expect("add");
        // The scene changes behind the history's back: undoing the add finds no entity.
        let e = entity_at(s.scene(), 0).expect("entity");
        assert!(s.document.scene_mut().despawn(e).is_some());
        assert!(s.undo().is_err());
        assert_eq!(s.history.undo_len(), 1, "the failed undo stays undoable");
    }
}
