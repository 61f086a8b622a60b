//! Many entities at once: the ways the selection changes (select one, toggle, a range, all,
//! none, what a viewport pick or box asks for), and the edits of the whole selection
//! (duplicate, delete, paste, one row set per entity), each one undo step.

use texel_scene::EntityRow;

use crate::command::{Command, CommandError};
use crate::history::MergeKey;
use crate::state::EditorState;

/// How a click (in the viewport or the outliner) or a box changes the selection.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pick {
    /// Select what was hit alone (nothing hit: select nothing).
    #[default]
    Replace,
    /// Add what was hit (Shift in the viewport).
    Add,
    /// Add what was hit, or take it away when it was selected (Ctrl).
    Toggle,
    /// Select the range from the active entity to what was hit (Shift in the outliner).
    Range,
}

impl Pick {
    /// The pick the held modifiers ask for: Ctrl (⌘) toggles, Shift adds (`shift`: what
    /// Shift does where the click is).
    pub fn from_modifiers(m: egui::Modifiers, shift: Pick) -> Pick {
        if m.command || m.ctrl {
            Pick::Toggle
        } else if m.shift {
            shift
        } else {
            Pick::Replace
        }
    }
}

impl EditorState {
    /// Every selected position, ascending (empty when nothing is active).
    pub fn selected(&self) -> Vec<usize> {
        let Some(active) = self.selection else {
            return Vec::new();
        };
        let mut v: Vec<usize> = self.also_selected.iter().copied().collect();
        if let Err(at) = v.binary_search(&active) {
            v.insert(at, active);
        }
        v
    }

    /// Whether the entity at `index` is selected.
    pub fn is_selected(&self, index: usize) -> bool {
        self.selection.is_some()
            && (self.selection == Some(index) || self.also_selected.contains(&index))
    }

    /// How many entities are selected.
    pub fn selected_count(&self) -> usize {
        self.selected().len()
    }

    /// Selects the entity at `index` alone.
    pub fn select_only(&mut self, index: usize) {
        self.selection = Some(index);
        self.also_selected.clear();
    }

    /// Selects exactly `indices`; `active` (when among them) or the last one is active.
    pub fn select_many(&mut self, indices: impl IntoIterator<Item = usize>, active: Option<usize>) {
        self.also_selected = indices.into_iter().collect();
        self.selection = active
            .filter(|a| self.also_selected.contains(a))
            .or_else(|| self.also_selected.last().copied());
        if let Some(a) = self.selection {
            self.also_selected.remove(&a);
        }
    }

    /// Selects nothing.
    pub fn select_none(&mut self) {
        self.selection = None;
        self.also_selected.clear();
    }

    /// Selects every entity, keeping the active one.
    pub fn select_all(&mut self) {
        let active = self.selection;
        self.select_many(0..self.scene().len(), active);
    }

    /// Changes the selection for a click on the entity at `hit` (`None`: on nothing).
    pub fn pick(&mut self, hit: Option<usize>, how: Pick) {
        let Some(i) = hit else {
            if how == Pick::Replace {
                self.select_none();
            }
            return;
        };
        match how {
            Pick::Replace => self.select_only(i),
            Pick::Add => self.pick_many(&[i], Pick::Add),
            Pick::Toggle if self.is_selected(i) => {
                let mut rest = self.selected();
                rest.retain(|&j| j != i);
                let active = self.selection.filter(|&a| a != i);
                self.select_many(rest, active);
            }
            Pick::Toggle => self.pick_many(&[i], Pick::Add),
            Pick::Range => {
                let anchor = self.selection.unwrap_or(i);
                let (a, b) = (anchor.min(i), anchor.max(i));
                self.select_many(a..=b, Some(anchor));
            }
        }
    }

    /// Changes the selection for a box holding `hits`: replaces it, adds to it, or toggles
    /// each (a range is taken as a replace).
    pub fn pick_many(&mut self, hits: &[usize], how: Pick) {
        match how {
            Pick::Replace | Pick::Range => {
                let active = self.selection.filter(|a| hits.contains(a));
                self.select_many(hits.iter().copied(), active);
            }
            Pick::Add => {
                let mut all = self.selected();
                all.extend_from_slice(hits);
                let active = hits.last().copied().or(self.selection);
                self.select_many(all, active);
            }
            Pick::Toggle => {
                for &i in hits {
                    self.pick(Some(i), Pick::Toggle);
                }
            }
        }
    }

    /// Replaces the components of several entities as one undo step (one gesture per
    /// `merge`): a single [`Command::SetRow`] for one entity, else a batch of them that the
    /// viewport takes in entity by entity. Nothing happens when nothing changes.
    pub fn set_rows(
        &mut self,
        rows: Vec<(usize, EntityRow)>,
        merge: Option<MergeKey>,
    ) -> Result<(), CommandError> {
        if let [(index, row)] = rows.as_slice() {
            return self.set_row(*index, row.clone(), merge);
        }
        let mut steps = Vec::with_capacity(rows.len());
        let mut changed = false;
        // Parents first: a parent's step moves its children, then theirs place them.
        let mut rows = rows;
        if self.scene().has_hierarchy() {
            let scene = self.scene();
            let ents: Vec<hecs::Entity> = scene.entities().collect();
            let depth = |i: usize| ents.get(i).map_or(0, |e| scene.depth(*e));
            rows.sort_by_cached_key(|(i, _)| depth(*i));
        }
        for (index, after) in rows {
            let before = self.existing(index)?;
            changed |= before != after;
            steps.push(Command::SetRow {
                index,
                before: Box::new(before),
                after: Box::new(after),
            });
        }
        if !changed {
            return Ok(());
        }
        let label = "edit";
        self.apply(Command::Batch { label, steps }, merge)
    }

    /// Duplicates every selected entity in place, each copy right after its original, as
    /// one undo step; the copies become the selection. A parent's descendants are copied
    /// with it, under its copy ([`crate::groups::copies`]).
    pub fn duplicate_selection(&mut self) -> Result<(), CommandError> {
        self.duplicate_indices(&self.selected())
    }

    /// Duplicates the entities at `indices` and their descendants, as one undo step.
    pub fn duplicate_indices(&mut self, indices: &[usize]) -> Result<(), CommandError> {
        let all = self.with_descendants(indices);
        let rows = crate::groups::copies(self, &all);
        let mut steps = Vec::new();
        for (k, (index, row)) in all.into_iter().zip(rows).enumerate() {
            // The copies before this one pushed it `k` places on.
            let (index, row) = (index + k + 1, Box::new(row));
            steps.push(Command::Spawn { index, row });
        }
        self.apply_batch("duplicate", steps)
    }

    /// Deletes every selected entity, and their descendants, as one undo step.
    pub fn delete_selection(&mut self) -> Result<(), CommandError> {
        self.delete_indices(&self.selected())
    }

    /// Deletes the entities at `indices` and their descendants, as one undo step.
    pub fn delete_indices(&mut self, indices: &[usize]) -> Result<(), CommandError> {
        let mut steps = Vec::new();
        for index in self.with_descendants(indices).into_iter().rev() {
            let row = Box::new(self.existing(index)?);
            steps.push(Command::Despawn { index, row });
        }
        self.apply_batch("delete", steps)
    }

    /// Adds `rows` (as a level file holds them) at the end of the level as one undo step;
    /// they become the selection. Pasted parents whose names are taken are renamed, their
    /// children following ([`crate::groups::rows_to_paste`]).
    pub fn paste_rows(&mut self, rows: Vec<EntityRow>) -> Result<(), CommandError> {
        let rows = crate::groups::rows_to_paste(self, rows);
        let start = self.scene().len();
        let steps = rows
            .into_iter()
            .enumerate()
            .map(|(k, row)| Command::Spawn {
                index: start + k,
                row: Box::new(row),
            })
            .collect();
        self.apply_batch("paste", steps)
    }

    /// The components of every selected entity, in level order.
    pub fn selected_rows(&self) -> Vec<(usize, EntityRow)> {
        (self.selected().into_iter())
            .filter_map(|i| Some((i, self.row_at(i)?)))
            .collect()
    }

    /// Runs `steps` as one undo step named `label` (a single step as itself); nothing for
    /// no steps.
    fn apply_batch(
        &mut self,
        label: &'static str,
        mut steps: Vec<Command>,
    ) -> Result<(), CommandError> {
        match steps.len() {
            0 => Ok(()),
            1 => {
                let step = steps.pop().expect("one step");
                self.apply(step, None)
            }
            _ => self.apply(Command::Batch { label, steps }, None),
        }
    }

    fn existing(&self, index: usize) -> Result<EntityRow, CommandError> {
        self.row_at(index)
            .ok_or_else(|| CommandError(format!("no entity at position {index}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::Document;
    use texel_scene::{Name, Transform};

    fn with(names: &[&str]) -> EditorState {
        let mut s = EditorState::new(Document::new_empty());
        for n in names {
            s.add(EntityRow {
                name: Some(Name((*n).into())),
                transform: Some(Transform::default()),
                ..EntityRow::default()
            })
            .expect("add");
        }
        s.history = Default::default();
        s
    }

    fn names(s: &EditorState) -> Vec<String> {
        s.scene()
            .to_level()
            .entities
            .iter()
            .map(|r| r.name.clone().map(|n| n.0).unwrap_or_default())
            .collect()
    }

    #[test]
    fn toggles_ranges_all_and_none() {
        let mut s = with(&["a", "b", "c", "d", "e"]);
        s.pick(Some(1), Pick::Replace);
        s.pick(Some(3), Pick::Toggle);
        assert_eq!((s.selected(), s.selection), (vec![1, 3], Some(3)));
        s.pick(Some(3), Pick::Toggle);
        assert_eq!((s.selected(), s.selection), (vec![1], Some(1)));
        s.pick(Some(4), Pick::Range);
        assert_eq!((s.selected(), s.selection), (vec![1, 2, 3, 4], Some(1)));
        s.pick(None, Pick::Add);
        assert_eq!(
            s.selected_count(),
            4,
            "a modified click on nothing keeps it"
        );
        s.select_all();
        assert_eq!(s.selected(), vec![0, 1, 2, 3, 4]);
        assert_eq!(s.selection, Some(1));
        s.pick(None, Pick::Replace);
        assert!(s.selected().is_empty());
        s.pick_many(&[0, 2], Pick::Replace);
        s.pick_many(&[2, 4], Pick::Toggle);
        assert_eq!(s.selected(), vec![0, 4]);
    }

    #[test]
    fn duplicate_delete_and_paste_are_one_step_each() {
        let mut s = with(&["a", "b", "c"]);
        s.select_many([0, 2], None);
        s.duplicate_selection().expect("duplicate");
        assert_eq!(names(&s), ["a", "a copy", "b", "c", "c copy"]);
        assert_eq!(s.selected(), vec![1, 4], "the copies are selected");
        assert_eq!(s.history.undo_len(), 1);
        s.delete_selection().expect("delete");
        assert_eq!(names(&s), ["a", "b", "c"]);
        assert!(s.selected().is_empty());
        s.undo().expect("undo delete");
        assert_eq!(names(&s), ["a", "a copy", "b", "c", "c copy"]);
        assert_eq!(
            s.selected(),
            vec![1, 4],
            "undoing a delete selects what came back"
        );
        s.undo().expect("undo duplicate");
        assert_eq!(names(&s), ["a", "b", "c"]);
        let rows = vec![s.row_at(1).expect("b"), s.row_at(1).expect("b")];
        s.paste_rows(rows).expect("paste");
        assert_eq!(names(&s), ["a", "b", "c", "b", "b"]);
        assert_eq!(s.selected(), vec![3, 4]);
        assert_eq!(s.history.undo_len(), 1);
    }

    #[test]
    fn a_batch_that_fails_changes_nothing() {
        let mut s = with(&["a", "b"]);
        s.selection = Some(5);
        s.also_selected.insert(0);
        let before = s.scene().to_level();
        assert!(s.delete_selection().is_err());
        assert_eq!(s.scene().to_level(), before);
        assert_eq!(s.history.undo_len(), 0);
    }
}
