//! Hiding and locking, the outliner's eye and padlock: editor-only session state, never in
//! the level (a saved level holds every entity as it is, hidden or locked or not). Kept by
//! entity handle, so it follows an entity while others are added, deleted or reordered; an
//! entity deleted and brought back by undo comes back shown and unlocked.
//!
//! A hidden entity is drawn by nothing: the render worker's level snapshot holds it as a row
//! of its name and transform only ([`EditorState::render_level`]), so it keeps its position
//! (the renderer's ids, and so picking, stay those of the document) but has no shape, light,
//! sprite, terrain or probe override; its markers and outline are not painted, it is not
//! box-selected, and Add does not land on it. A locked entity is drawn but cannot be picked
//! in the viewport, box-selected, or moved by the gizmo or the face handles; the outliner and
//! the inspector still select and edit it.

use std::collections::HashSet;

use texel_scene::{EntityRow, Level};

use crate::command::entity_at;
use crate::state::EditorState;

/// The hidden and the locked entities.
#[derive(Debug, Clone, Default)]
pub struct Visibility {
    hidden: HashSet<hecs::Entity>,
    locked: HashSet<hecs::Entity>,
    /// One more at each change of what is hidden (the viewport sends a new snapshot).
    revision: u64,
}

impl EditorState {
    fn handle(&self, index: usize) -> Option<hecs::Entity> {
        entity_at(self.scene(), index).ok()
    }

    /// Whether the entity at `index` is hidden.
    pub fn is_hidden(&self, index: usize) -> bool {
        (self.handle(index)).is_some_and(|e| self.visibility.hidden.contains(&e))
    }

    /// Whether the entity at `index` is locked.
    pub fn is_locked(&self, index: usize) -> bool {
        (self.handle(index)).is_some_and(|e| self.visibility.locked.contains(&e))
    }

    /// Whether the viewport may pick, box-select or move the entity at `index`: it is there,
    /// shown and not locked.
    pub fn pickable(&self, index: usize) -> bool {
        self.handle(index).is_some_and(|e| {
            !self.visibility.hidden.contains(&e) && !self.visibility.locked.contains(&e)
        })
    }

    /// Hides or shows the entity at `index`.
    pub fn set_hidden(&mut self, index: usize, hidden: bool) {
        let Some(e) = self.handle(index) else {
            return;
        };
        let changed = if hidden {
            self.visibility.hidden.insert(e)
        } else {
            self.visibility.hidden.remove(&e)
        };
        if changed {
            self.visibility.revision += 1;
        }
    }

    /// Locks or unlocks the entity at `index`.
    pub fn set_locked(&mut self, index: usize, locked: bool) {
        if let Some(e) = self.handle(index) {
            if locked {
                self.visibility.locked.insert(e);
            } else {
                self.visibility.locked.remove(&e);
            }
        }
    }

    /// Whether each entity, in level order, is hidden and whether it is locked (one pass,
    /// for the outliner and the viewport's overlays; [`EditorState::is_hidden`] walks the
    /// level to its entity).
    pub fn hidden_and_locked(&self) -> Vec<(bool, bool)> {
        let v = &self.visibility;
        if v.hidden.is_empty() && v.locked.is_empty() {
            return vec![(false, false); self.scene().len()];
        }
        (self.scene().entities())
            .map(|e| (v.hidden.contains(&e), v.locked.contains(&e)))
            .collect()
    }

    /// How many times what is hidden changed.
    pub fn visibility_revision(&self) -> u64 {
        self.visibility.revision
    }

    /// The level as the viewport draws it: every row, a hidden one reduced to its name,
    /// parent, transform and animator (at its own position, so ids and positions stay the
    /// document's, and its children stay where they are and move as they do).
    pub fn render_level(&self) -> Level {
        let mut level = self.scene().to_level();
        if self.visibility.hidden.is_empty() {
            return level;
        }
        for (row, e) in level.entities.iter_mut().zip(self.scene().entities()) {
            if self.visibility.hidden.contains(&e) {
                *row = EntityRow {
                    name: row.name.take(),
                    parent: row.parent.take(),
                    transform: row.transform,
                    // A hidden moving group still carries its children.
                    animator: row.animator.take(),
                    ..EntityRow::default()
                };
            }
        }
        level
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::Document;
    use texel_scene::{Geometry, Name, Transform};

    fn boxed(name: &str) -> EntityRow {
        EntityRow {
            name: Some(Name(name.into())),
            transform: Some(Transform::default()),
            geometry: Some(Geometry::Box {
                size: glam::Vec3::ONE,
            }),
            ..EntityRow::default()
        }
    }

    #[test]
    fn hiding_follows_the_entity_and_strips_only_the_render_rows() {
        let mut s = EditorState::new(Document::new_empty());
        for n in ["a", "b", "c"] {
            s.add(boxed(n)).expect("add");
        }
        s.set_hidden(1, true);
        s.set_locked(2, true);
        assert_eq!(s.visibility_revision(), 1);
        assert!(s.is_hidden(1) && !s.pickable(1));
        assert!(s.is_locked(2) && !s.pickable(2));
        assert!(s.pickable(0));
        let flags = [(false, false), (true, false), (false, true)];
        assert_eq!(s.hidden_and_locked(), flags);
        let drawn = s.render_level();
        assert_eq!(drawn.entities.len(), 3);
        assert!(drawn.entities[1].geometry.is_none());
        assert_eq!(drawn.entities[1].name, Some(Name("b".into())));
        assert!(drawn.entities[2].geometry.is_some(), "locked is drawn");
        assert!(s.scene().to_level().entities[1].geometry.is_some());
        // Deleting the first keeps "b" hidden, now at 0.
        s.delete(0).expect("delete");
        assert!(s.is_hidden(0) && s.is_locked(1));
        s.set_hidden(0, false);
        assert!(s.pickable(0));
        assert_eq!(s.visibility_revision(), 2);
    }
}
