//! A level file changed on disk, taken in the way an editor edit is: the rows that differ
//! from the level being drawn go through [`Session::update_entities`] (each extracted alone,
//! rewritten in place, only the faces that may see them captured again); a level that gained
//! or lost entities, or changed its settings, is drawn afresh. `texel-run play` watches its
//! level file with [`LevelWatch`].

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use texel_render::context::GpuContext;
use texel_scene::Scene;

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

impl Session {
    /// Takes in `new`, the session's level `old` read again (a file changed on disk): only
    /// the rows that changed, as edits ([`Session::update_entities`]), or the whole level
    /// when its entities or settings changed ([`Session::set_level`]).
    pub fn reload(
        &mut self,
        ctx: &GpuContext,
        old: &LoadedLevel,
        new: &LoadedLevel,
    ) -> Result<EditUpdate, SessionError> {
        match changed_rows(&old.scene, &new.scene) {
            Some(rows) if rows.is_empty() => Ok(EditUpdate::InPlace { faces_marked: 0 }),
            Some(rows) => self.update_entities(ctx, new, &rows),
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
}
