//! A level file changed on disk, taken in the way an editor edit is: the rows that differ
//! from the level being drawn, and the rows added or removed, go through
//! [`Session::edit_rows`] (each extracted alone, only the faces that may see them captured
//! again); a level that changed its settings is drawn afresh. `texel-run play` watches its
//! level file with [`LevelWatch`].

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use texel_render::context::GpuContext;
use texel_scene::Scene;

use crate::frame_plan::RowEdit;
use crate::load::LoadedLevel;
use crate::session::{EditUpdate, Session, SessionError};

/// How often the level file's modification time is read.
pub const WATCH_INTERVAL: Duration = Duration::from_millis(500);

/// The positions of the entities whose rows differ between `old` and `new`, when the two
/// have the same entities in number and the same settings; `None` otherwise.
pub fn changed_rows(old: &Scene, new: &Scene) -> Option<Vec<usize>> {
    if old.len() != new.len() || old.settings != new.settings {
        return None;
    }
    let rows = old.entities().zip(new.entities()).enumerate();
    Some(
        rows.filter(|(_, (a, b))| old.row(*a) != new.row(*b))
            .map(|(i, _)| i)
            .collect(),
    )
}

/// The edits that turn `old`'s entities into `new`'s, when the two have the same settings
/// (`None` otherwise): past the rows both start and end with, the rows between are set one
/// for one, and the rest of the longer run removed or inserted.
pub fn row_edits(old: &Scene, new: &Scene) -> Option<Vec<RowEdit>> {
    if old.settings != new.settings {
        return None;
    }
    let a: Vec<_> = old.entities().filter_map(|e| old.row(e)).collect();
    let b: Vec<_> = new.entities().filter_map(|e| new.row(e)).collect();
    let head = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let tail = (a[head..].iter().rev().zip(b[head..].iter().rev()))
        .take_while(|(x, y)| x == y)
        .count();
    let (a, b) = (&a[head..a.len() - tail], &b[head..b.len() - tail]);
    let both = a.len().min(b.len());
    let mut edits: Vec<RowEdit> = (0..both)
        .filter(|&i| a[i] != b[i])
        .map(|i| RowEdit::Set(head + i))
        .collect();
    edits.extend((both..a.len()).map(|_| RowEdit::Remove(head + both)));
    edits.extend((both..b.len()).map(|i| RowEdit::Insert(head + i)));
    Some(edits)
}

impl Session {
    /// Takes in `new`, the session's level `old` read again (a file changed on disk): only
    /// the rows that changed, were added or were removed, as edits ([`Session::edit_rows`],
    /// [`row_edits`]), or the whole level when its settings changed ([`Session::set_level`]).
    pub fn reload(
        &mut self,
        ctx: &GpuContext,
        old: &LoadedLevel,
        new: &LoadedLevel,
    ) -> Result<EditUpdate, SessionError> {
        match row_edits(&old.scene, &new.scene) {
            Some(edits) if edits.is_empty() => Ok(EditUpdate::InPlace { faces_marked: 0 }),
            Some(edits) => self.edit_rows(ctx, new, &edits),
            None => {
                self.set_level(ctx, new)?;
                Ok(EditUpdate::Rebuilt)
            }
        }
    }
}

/// Watches a level file: [`LevelWatch::changed`] says when its modification time moved.
#[derive(Debug, Clone)]
pub struct LevelWatch {
    path: PathBuf,
    modified: Option<SystemTime>,
    checked: Instant,
}

impl LevelWatch {
    /// Watches `path` from its current modification time.
    pub fn new(path: &Path) -> Self {
        LevelWatch {
            path: path.to_owned(),
            modified: modified(path),
            checked: Instant::now(),
        }
    }

    /// Whether the file was modified since the last call that said so (read at most every
    /// [`WATCH_INTERVAL`]; a file that vanished is not a change: an editor saving
    /// atomically replaces it).
    pub fn changed(&mut self) -> bool {
        if self.checked.elapsed() < WATCH_INTERVAL {
            return false;
        }
        self.checked = Instant::now();
        match modified(&self.path) {
            Some(m) if Some(m) != self.modified => {
                self.modified = Some(m);
                true
            }
            _ => false,
        }
    }
}

/// The file's modification time, if it can be read.
fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_scene::{EntityRow, Name, Transform};

    fn scene(n: usize) -> Scene {
        let mut s = Scene::new();
        for i in 0..n {
            s.spawn(EntityRow {
                name: Some(Name(format!("E{i}"))),
                transform: Some(Transform::default()),
                ..EntityRow::default()
            });
        }
        s
    }

    /// Rows that differ are listed by position; another count or other settings are `None`.
    #[test]
    fn changed_rows_lists_the_rows_that_differ() {
        let old = scene(4);
        let mut new = scene(4);
        assert_eq!(changed_rows(&old, &new), Some(vec![]));
        let e = new.entities().nth(2).expect("entity");
        let mut row = new.row(e).expect("row");
        row.transform.as_mut().expect("transform").translation.x = 1.0;
        new.set_row(e, row).expect("set");
        assert_eq!(changed_rows(&old, &new), Some(vec![2]));
        assert_eq!(changed_rows(&old, &scene(5)), None);
        let mut other = scene(4);
        other.settings.cell_size *= 2.0;
        assert_eq!(changed_rows(&old, &other), None);
    }

    /// A row removed, added or changed is one edit at its position; other settings are
    /// `None`.
    #[test]
    fn row_edits_name_rows_removed_added_and_set() {
        let old = scene(5);
        assert_eq!(row_edits(&old, &scene(5)), Some(vec![]));
        let mut fewer = scene(5);
        let e = fewer.entities().nth(2).expect("entity");
        fewer.despawn(e).expect("despawn");
        assert_eq!(row_edits(&old, &fewer), Some(vec![RowEdit::Remove(2)]));
        assert_eq!(row_edits(&fewer, &old), Some(vec![RowEdit::Insert(2)]));
        assert_eq!(
            row_edits(&old, &scene(7)),
            Some(vec![RowEdit::Insert(5), RowEdit::Insert(6)])
        );
        let mut moved = scene(5);
        let e = moved.entities().nth(1).expect("entity");
        let mut row = moved.row(e).expect("row");
        row.transform.as_mut().expect("transform").translation.x = 1.0;
        moved.set_row(e, row).expect("set");
        assert_eq!(row_edits(&old, &moved), Some(vec![RowEdit::Set(1)]));
        let mut other = scene(5);
        other.settings.cell_size *= 2.0;
        assert_eq!(row_edits(&old, &other), None);
    }
}
