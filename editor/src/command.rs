//! Commands: the only way the document changes. Each knows how to execute and revert itself
//! (Fyrox-style), so history is complete by construction.
//!
//! Entities are addressed by their position in the level order rather than by hecs handle:
//! a handle dies with a delete, while the position survives undoing it.

use std::sync::Arc;

use texel_runtime::frame_plan::RowEdit;
use texel_scene::assets::AssetLibrary;
use texel_scene::terrain::{HeightSource, Heightfield, Terrain};
use texel_scene::{EntityRow, LevelSettings, Scene};

use crate::paint::PaintChange;
use crate::palette_edits::PaletteState;
use crate::terrain::HeightChange;

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
    /// Changes the heights of the terrain of the entity at `index` (a sculpt stroke, an
    /// imported heightmap) and its components (a noise source becomes the file its heights
    /// are saved to).
    SetHeights {
        /// Position in the level order.
        index: usize,
        /// The components before.
        before: Box<EntityRow>,
        /// The components after.
        after: Box<EntityRow>,
        /// The heights changed.
        change: Arc<HeightChange>,
    },
    /// Changes the paint layer of the terrain of the entity at `index` (a paint stroke,
    /// "Clear paint") and its components (a terrain painted the first time names the file
    /// its layer is saved to; a cleared one names none).
    SetPaint {
        /// Position in the level order.
        index: usize,
        /// The components before.
        before: Box<EntityRow>,
        /// The components after.
        after: Box<EntityRow>,
        /// The pixels changed.
        change: Arc<PaintChange>,
    },
    /// Replaces the level's palette: the files it names, its dither and the colours of
    /// each file (a palette picked, a swatch edited).
    SetPalette {
        /// Before.
        before: Box<PaletteState>,
        /// After.
        after: Box<PaletteState>,
    },
    /// Several commands as one undo step (an edit of many entities, a paste, a delete of
    /// the selection), executed in order and reverted in reverse order.
    Batch {
        /// What it does, for menus ("Undo duplicate").
        label: &'static str,
        /// The steps, in execution order.
        steps: Vec<Command>,
    },
}

/// What should be selected after a command ran.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Focus {
    /// Leave the selection as it is.
    Keep,
    /// The entity at this position was edited: keep a selection that holds it, else
    /// select it alone.
    Entity(usize),
    /// Select exactly these entities (the last one active).
    Entities(Vec<usize>),
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
    /// Applies the change to `scene`; terrain heights live in `assets`.
    pub fn execute(
        &self,
        scene: &mut Scene,
        assets: &mut AssetLibrary,
    ) -> Result<Focus, CommandError> {
        match self {
            Command::SetRow {
                index,
                before,
                after,
            } => {
                let e = entity_at(scene, *index)?;
                scene
                    .set_row(e, (**after).clone())
                    .map_err(|_| CommandError(format!("entity {index} vanished")))?;
                ensure_heights(before.terrain.as_ref(), after.terrain.as_ref(), assets);
                Ok(Focus::Entity(*index))
            }
            Command::Spawn { index, row } => {
                if *index > scene.len() {
                    return Err(CommandError(format!("no position {index} to insert at")));
                }
                scene.spawn_at(*index, (**row).clone());
                ensure_heights(None, row.terrain.as_ref(), assets);
                Ok(Focus::Entities(vec![*index]))
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
            Command::SetPalette { after, .. } => {
                after.apply(&mut scene.palette, assets);
                Ok(Focus::Keep)
            }
            Command::SetHeights { .. } => self.set_heights(scene, assets, true),
            Command::SetPaint { .. } => self.set_paint(scene, assets, true),
            Command::Batch { steps, .. } => batch(steps, scene, assets, true),
        }
    }

    /// Undoes the change.
    pub fn revert(
        &self,
        scene: &mut Scene,
        assets: &mut AssetLibrary,
    ) -> Result<Focus, CommandError> {
        match self {
            // Without copying the heights an inverse would hold.
            Command::SetHeights { .. } => self.set_heights(scene, assets, false),
            Command::SetPaint { .. } => self.set_paint(scene, assets, false),
            Command::Batch { steps, .. } => batch(steps, scene, assets, false),
            _ => self.inverse().execute(scene, assets),
        }
    }

    /// Runs a [`Command::SetHeights`] forward (execute) or backward (revert): the heights of
    /// the terrain it starts from, changed, become those of the terrain it ends with.
    fn set_heights(
        &self,
        scene: &mut Scene,
        assets: &mut AssetLibrary,
        forward: bool,
    ) -> Result<Focus, CommandError> {
        let Command::SetHeights {
            index,
            before,
            after,
            change,
        } = self
        else {
            return Err(CommandError("not a height change".into()));
        };
        let (e, to, tf, tt) = terrain_step(scene, *index, (before, after), forward, "sculpted")?;
        let field = assets
            .heightfield(tf)
            .ok_or_else(|| CommandError(format!("the heights of entity {index} are not loaded")))?;
        let next = change.apply(field, forward).map_err(CommandError)?;
        assets.insert_heightfield(tt, Arc::new(next));
        scene
            .set_row(e, to.clone())
            .map_err(|_| CommandError(format!("entity {index} vanished")))?;
        Ok(Focus::Entity(*index))
    }

    /// Runs a [`Command::SetPaint`] forward (execute) or backward (revert): the paint of the
    /// terrain it starts from (none, or its loaded layer), changed, becomes the layer of the
    /// terrain it ends with.
    fn set_paint(
        &self,
        scene: &mut Scene,
        assets: &mut AssetLibrary,
        forward: bool,
    ) -> Result<Focus, CommandError> {
        let Command::SetPaint {
            index,
            before,
            after,
            change,
        } = self
        else {
            return Err(CommandError("not a paint change".into()));
        };
        let (e, to, tf, tt) = terrain_step(scene, *index, (before, after), forward, "painted")?;
        let layer = match &tf.paint {
            Some(_) => Some(assets.paint(tf).ok_or_else(|| {
                CommandError(format!("the paint of entity {index} is not loaded"))
            })?),
            None => None,
        };
        let next = change
            .apply(layer.map(|l| &**l), forward)
            .map_err(CommandError)?;
        if let (Some(p), Some(mut image)) = (&tt.paint, next) {
            image.name = p.path.clone();
            assets.insert_texture(&p.path, Arc::new(image));
        }
        scene
            .set_row(e, to.clone())
            .map_err(|_| CommandError(format!("entity {index} vanished")))?;
        Ok(Focus::Entity(*index))
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
            Command::SetHeights {
                index,
                before,
                after,
                change,
            } => Command::SetHeights {
                index: *index,
                before: after.clone(),
                after: before.clone(),
                change: Arc::new(change.reversed()),
            },
            Command::SetPaint {
                index,
                before,
                after,
                change,
            } => Command::SetPaint {
                index: *index,
                before: after.clone(),
                after: before.clone(),
                change: Arc::new(change.reversed()),
            },
            Command::SetPalette { before, after } => Command::SetPalette {
                before: after.clone(),
                after: before.clone(),
            },
            Command::Batch { label, steps } => Command::Batch {
                label,
                steps: steps.iter().rev().map(Command::inverse).collect(),
            },
        }
    }

    /// The entity components the command holds (what it sets and what it restores).
    pub fn rows(&self) -> Vec<&EntityRow> {
        match self {
            Command::SetRow { before, after, .. }
            | Command::SetHeights { before, after, .. }
            | Command::SetPaint { before, after, .. } => vec![before, after],
            Command::Spawn { row, .. } | Command::Despawn { row, .. } => vec![row],
            Command::SetSettings { .. } | Command::SetPalette { .. } => Vec::new(),
            Command::Batch { steps, .. } => steps.iter().flat_map(Command::rows).collect(),
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
            (Command::SetPalette { after, .. }, Command::SetPalette { after: a2, .. }) => {
                *after = a2.clone();
                true
            }
            // The same entities edited again (a drag of the whole selection).
            (Command::Batch { steps, .. }, Command::Batch { steps: s2, .. })
                if steps.len() == s2.len() && steps.iter().zip(s2).all(|(a, b)| a.same_row(b)) =>
            {
                steps.iter_mut().zip(s2).all(|(a, b)| a.absorb(b))
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
            Command::SetPalette { .. } => "palette",
            Command::SetHeights { change, .. } => change.describe(),
            Command::SetPaint { change, .. } => change.describe(),
            Command::Batch { label, .. } => label,
        }
    }

    /// Whether both replace the components of the entity at the same position.
    fn same_row(&self, other: &Command) -> bool {
        matches!(
            (self, other),
            (Command::SetRow { index: a, .. }, Command::SetRow { index: b, .. }) if a == b
        )
    }

    /// The changes of the level's entities the command makes when executed (`forward`) or
    /// reverted, in order, when it only sets, adds or removes entities (the viewport then
    /// takes in those entities alone).
    pub fn row_edits(&self, forward: bool) -> Option<Vec<RowEdit>> {
        match (self, forward) {
            (Command::SetRow { index, .. }, _) => Some(vec![RowEdit::Set(*index)]),
            (Command::Spawn { index, .. }, true) | (Command::Despawn { index, .. }, false) => {
                Some(vec![RowEdit::Insert(*index)])
            }
            (Command::Despawn { index, .. }, true) | (Command::Spawn { index, .. }, false) => {
                Some(vec![RowEdit::Remove(*index)])
            }
            (Command::Batch { steps, .. }, _) => {
                let mut edits = Vec::new();
                let order: Vec<&Command> = match forward {
                    true => steps.iter().collect(),
                    false => steps.iter().rev().collect(),
                };
                for step in order {
                    edits.extend(step.row_edits(forward)?);
                }
                Some(edits)
            }
            _ => None,
        }
    }

    /// The positions of the entities a batch of [`Command::SetRow`]s edits, when it is one
    /// (the viewport then takes in those entities alone).
    pub fn edited_rows(&self) -> Option<Vec<usize>> {
        let Command::Batch { steps, .. } = self else {
            return None;
        };
        steps
            .iter()
            .map(|c| match c {
                Command::SetRow { index, .. } => Some(*index),
                _ => None,
            })
            .collect()
    }
}

/// Runs the steps of a batch forward (execute, in order) or backward (revert, in reverse
/// order). A step that fails takes back the steps already run, so a batch happens whole or
/// not at all. The focus: every entity the steps focus, or nothing when one deletes.
fn batch(
    steps: &[Command],
    scene: &mut Scene,
    assets: &mut AssetLibrary,
    forward: bool,
) -> Result<Focus, CommandError> {
    let order: Vec<&Command> = if forward {
        steps.iter().collect()
    } else {
        steps.iter().rev().collect()
    };
    let run = |c: &Command, s: &mut Scene, a: &mut AssetLibrary, fwd: bool| {
        if fwd { c.execute(s, a) } else { c.revert(s, a) }
    };
    let mut focus = Some(Vec::new());
    for (done, &c) in order.iter().enumerate() {
        match run(c, scene, assets, forward) {
            Ok(Focus::Entity(i)) => focus.iter_mut().for_each(|f| f.push(i)),
            Ok(Focus::Entities(v)) => focus.iter_mut().for_each(|f| f.extend(&v)),
            Ok(Focus::Nothing) => focus = None,
            Ok(Focus::Keep) => {}
            Err(e) => {
                for &c in order[..done].iter().rev() {
                    // Best effort: the scene was as these steps expect a moment ago.
                    let _ = run(c, scene, assets, !forward);
                }
                return Err(e);
            }
        }
    }
    Ok(match focus {
        None => Focus::Nothing,
        Some(v) if v.is_empty() => Focus::Keep,
        Some(mut v) => {
            v.sort_unstable();
            v.dedup();
            Focus::Entities(v)
        }
    })
}

/// Gives a terrain whose heights `assets` lacks the heights that can be made without reading
/// a file: noise is baked; a file source keeps the heights it had as `before` (a noise source
/// turned into a file keeps them as they are, a new max height rescales a file's). A path
/// that must be read is left to the app's asset loading.
pub fn ensure_heights(
    before: Option<&Terrain>,
    after: Option<&Terrain>,
    assets: &mut AssetLibrary,
) {
    let Some(after) = after else {
        return;
    };
    if assets.heightfield(after).is_some() {
        return;
    }
    match &after.heightmap {
        HeightSource::Noise { .. } => {
            if let Some(f) = Heightfield::from_noise(&after.heightmap, after.size, after.max_height)
            {
                assets.insert_heightfield(after, Arc::new(f));
            }
        }
        HeightSource::File { path } => {
            let Some(b) = before else {
                return;
            };
            let Some(old) = assets.heightfield(b).cloned() else {
                return;
            };
            let scale = match &b.heightmap {
                HeightSource::File { path: p } if p == path => after.max_height / b.max_height,
                HeightSource::Noise { .. } => 1.0,
                HeightSource::File { .. } => return,
            };
            let mut f = (*old).clone();
            for h in &mut f.heights {
                *h = (*h * scale).clamp(0.0, after.max_height);
            }
            assets.insert_heightfield(after, Arc::new(f));
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

/// The entity of a terrain change at `index`, the row it goes to (`forward`: before →
/// after) and the terrains it goes from and to, once the entity's terrain is the one the
/// change started from (`done` names what was done to it, for the message).
fn terrain_step<'a>(
    scene: &Scene,
    index: usize,
    (before, after): (&'a EntityRow, &'a EntityRow),
    forward: bool,
    done: &str,
) -> Result<(hecs::Entity, &'a EntityRow, &'a Terrain, &'a Terrain), CommandError> {
    let (from, to) = if forward {
        (before, after)
    } else {
        (after, before)
    };
    let e = entity_at(scene, index)?;
    let (Some(tf), Some(tt)) = (from.terrain.as_ref(), to.terrain.as_ref()) else {
        return Err(CommandError(format!("entity {index} has no terrain")));
    };
    if scene.row(e).and_then(|r| r.terrain).as_ref() != Some(tf) {
        return Err(CommandError(format!(
            "the terrain of entity {index} is not the one that was {done}"
        )));
    }
    Ok((e, to, tf, tt))
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
        let mut assets = AssetLibrary::default();
        assert_eq!(cmd.execute(&mut scene, &mut assets), Ok(Focus::Nothing));
        assert_eq!(scene.len(), 2);
        cmd.revert(&mut scene, &mut assets).expect("revert");
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
        assert!(
            cmd.execute(&mut scene, &mut AssetLibrary::default())
                .is_err()
        );
    }

    #[test]
    fn height_changes_turn_noise_into_a_file_and_back() {
        let mut scene = Scene::new();
        let mut assets = AssetLibrary::default();
        let noise = crate::terrain::terrain_row(glam::Vec3::ZERO);
        let spawn = Command::Spawn {
            index: 0,
            row: Box::new(noise.clone()),
        };
        spawn.execute(&mut scene, &mut assets).expect("spawn");
        let t0 = noise.terrain.clone().expect("terrain");
        let baked = assets
            .heightfield(&t0)
            .cloned()
            .expect("noise is baked on spawn");
        let mut file = noise.clone();
        if let Some(t) = &mut file.terrain {
            t.heightmap = HeightSource::File {
                path: "t.png".into(),
            };
        }
        let mut sculpted = (*baked).clone();
        sculpted.heights[5] = 7.5;
        let region = crate::terrain::Region {
            x0: 0,
            z0: 0,
            x1: 8,
            z1: 1,
        };
        let cmd = Command::SetHeights {
            index: 0,
            before: Box::new(noise.clone()),
            after: Box::new(file.clone()),
            change: Arc::new(HeightChange::patch(&baked, &sculpted, region)),
        };
        cmd.execute(&mut scene, &mut assets).expect("sculpt");
        let t1 = file.terrain.clone().expect("terrain");
        assert_eq!(**assets.heightfield(&t1).expect("file heights"), sculpted);
        assert_eq!(scene.to_level().entities[0], file);
        cmd.revert(&mut scene, &mut assets).expect("undo");
        assert_eq!(scene.to_level().entities[0], noise);
        assert_eq!(**assets.heightfield(&t0).expect("noise heights"), *baked);
        // The inverse undoes it as well.
        cmd.execute(&mut scene, &mut assets).expect("redo");
        cmd.inverse()
            .execute(&mut scene, &mut assets)
            .expect("inverse");
        assert_eq!(**assets.heightfield(&t0).expect("noise heights"), *baked);
        // A doubled max height on a file source doubles its heights.
        cmd.execute(&mut scene, &mut assets).expect("redo");
        let mut taller = t1.clone();
        taller.max_height *= 2.0;
        ensure_heights(Some(&t1), Some(&taller), &mut assets);
        let h = assets.heightfield(&taller).expect("rescaled");
        assert!((h.heights[5] - 15.0).abs() < 1e-4);
    }
}
