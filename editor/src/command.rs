//! Commands: the only way the document changes. Each knows how to execute and revert itself
//! (Fyrox-style), so history is complete by construction.
//!
//! Entities are addressed by their position in the level order rather than by hecs handle:
//! a handle dies with a delete, while the position survives undoing it.

use texel_scene::{EntityRow, LevelSettings, Scene};

/// One undoable change to the scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Replaces every component of the entity at `index`.
    SetRow {
        /// Position in the level order.
        index: usize,
        /// The components before.
        before: Box<EntityRow>,
        /// The components after.
        after: Box<EntityRow>,
    },
    /// Inserts an entity at `index`.
    Spawn {
        /// Position in the level order.
        index: usize,
        /// Its components.
        row: Box<EntityRow>,
    },
    /// Removes the entity at `index` (which has `row`).
    Despawn {
        /// Position in the level order.
        index: usize,
        /// Its components, to restore it.
        row: Box<EntityRow>,
    },
    /// Replaces the level settings.
    SetSettings {
        /// Before.
        before: LevelSettings,
        /// After.
        after: LevelSettings,
    },
}

/// What should be selected after a command ran.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Focus {
    /// Leave the selection as it is.
    Keep,
    /// Select the entity at this position.
    Entity(usize),
    /// Select nothing.
    Nothing,
}

/// Why a command could not run (the scene is not what the command expects).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CommandError(pub String);

impl std::fmt::Display for CommandError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CommandError {}

impl Command {
    /// Applies the change.
    pub fn execute(&self, scene: &mut Scene) -> Result<Focus, CommandError> {
        match self {
            Command::SetRow { index, after, .. } => {
                let e = entity_at(scene, *index)?;
                scene
                    .set_row(e, (**after).clone())
                    .map_err(|_| CommandError(format!("entity {index} vanished")))?;
                Ok(Focus::Entity(*index))
            }
            Command::Spawn { index, row } => {
                if *index > scene.len() {
                    return Err(CommandError(format!("no position {index} to insert at")));
                }
                scene.spawn_at(*index, (**row).clone());
                Ok(Focus::Entity(*index))
            }
            Command::Despawn { index, .. } => {
                let e = entity_at(scene, *index)?;
                scene.despawn(e);
                Ok(Focus::Nothing)
            }
            Command::SetSettings { after, .. } => {
                scene.settings = *after;
                Ok(Focus::Keep)
            }
        }
    }

    /// Undoes the change.
    pub fn revert(&self, scene: &mut Scene) -> Result<Focus, CommandError> {
        self.inverse().execute(scene)
    }

    /// The command that undoes this one.
    pub fn inverse(&self) -> Command {
        match self {
            Command::SetRow {
                index,
                before,
                after,
            } => Command::SetRow {
                index: *index,
                before: after.clone(),
                after: before.clone(),
            },
            Command::Spawn { index, row } => Command::Despawn {
                index: *index,
                row: row.clone(),
            },
            Command::Despawn { index, row } => Command::Spawn {
                index: *index,
                row: row.clone(),
            },
            Command::SetSettings { before, after } => Command::SetSettings {
                before: *after,
                after: *before,
            },
        }
    }

    /// Folds a later edit of the same thing into this one (a drag becomes one step).
    /// Returns false when `next` is about something else.
    pub fn absorb(&mut self, next: &Command) -> bool {
        match (self, next) {
            (
                Command::SetRow { index, after, .. },
                Command::SetRow {
                    index: i2,
                    after: a2,
                    ..
                },
            ) if *index == *i2 => {
                *after = a2.clone();
                true
            }
            (Command::SetSettings { after, .. }, Command::SetSettings { after: a2, .. }) => {
                *after = *a2;
                true
            }
            _ => false,
        }
    }

    /// A short description for menus ("Undo move").
    pub fn describe(&self) -> &'static str {
        match self {
            Command::SetRow { .. } => "edit",
            Command::Spawn { .. } => "add",
            Command::Despawn { .. } => "delete",
            Command::SetSettings { .. } => "level settings",
        }
    }
}

/// The entity at `index` in the level order.
pub fn entity_at(scene: &Scene, index: usize) -> Result<hecs::Entity, CommandError> {
    scene
        .entities()
        .nth(index)
        .ok_or_else(|| CommandError(format!("no entity at position {index}")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_scene::{Name, Transform};

    fn row(name: &str) -> EntityRow {
        EntityRow {
            name: Some(Name(name.into())),
            transform: Some(Transform::default()),
            ..EntityRow::default()
        }
    }

    #[test]
    fn despawn_then_revert_restores_position_and_components() {
        let mut scene = Scene::new();
        for n in ["a", "b", "c"] {
            scene.spawn(row(n));
        }
        let before = scene.to_level();
        let cmd = Command::Despawn {
            index: 1,
            row: Box::new(row("b")),
        };
        assert_eq!(cmd.execute(&mut scene), Ok(Focus::Nothing));
        assert_eq!(scene.len(), 2);
        cmd.revert(&mut scene).expect("revert");
        assert_eq!(scene.to_level(), before);
    }

    #[test]
    fn absorb_keeps_the_first_before() {
        let mut a = Command::SetRow {
            index: 0,
            before: Box::new(row("a")),
            after: Box::new(row("b")),
        };
        let b = Command::SetRow {
            index: 0,
            before: Box::new(row("b")),
            after: Box::new(row("c")),
        };
        assert!(a.absorb(&b));
        assert_eq!(a.inverse().inverse(), a);
        if let Command::SetRow { before, after, .. } = &a {
            assert_eq!(**before, row("a"));
            assert_eq!(**after, row("c"));
        }
        let other = Command::SetRow {
            index: 1,
            before: Box::new(row("b")),
            after: Box::new(row("c")),
        };
        assert!(!a.absorb(&other));
    }

    #[test]
    fn command_on_a_missing_entity_is_an_error() {
        let mut scene = Scene::new();
        let cmd = Command::Despawn {
            index: 3,
            row: Box::new(row("x")),
        };
        assert!(cmd.execute(&mut scene).is_err());
    }
}
