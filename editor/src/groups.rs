//! Groups: parent–child links between entities ([`texel_scene::hierarchy`]) and the edits
//! that make and unmake them — Group (Ctrl+G), Ungroup (Ctrl+Shift+G), reparent (a row
//! dragged onto another in the outliner, or onto the empty space below the rows) — each one
//! undo step that keeps every entity's place in the world. The scene's rows hold world
//! transforms, so a new parent changes a row's `parent` and nothing else.
//!
//! A parent is named by its name in the level, which must be unique: an edit that makes an
//! entity a parent gives it a unique name first when it has none or shares it (in the same
//! undo step). Deleting, duplicating and copying a parent take its descendants along
//! ([`EditorState::with_descendants`]); copies of parents get names of their own and their
//! children's `parent` follows.

use std::collections::{BTreeSet, HashMap, HashSet};

use glam::Vec3;
use hecs::Entity;
use texel_scene::animator::Animator;
use texel_scene::hierarchy::MAX_DEPTH;
use texel_scene::terrain::Terrain;
use texel_scene::{EntityRow, Level, Name, Scene, Transform};

use crate::command::{Command, CommandError, entity_at};
use crate::state::EditorState;

/// Each live entity's position in the level order.
fn positions(scene: &Scene) -> HashMap<Entity, usize> {
    scene.entities().enumerate().map(|(i, e)| (e, i)).collect()
}

impl EditorState {
    /// `indices` and every descendant of them, ascending.
    pub fn with_descendants(&self, indices: &[usize]) -> Vec<usize> {
        let scene = self.scene();
        if !scene.has_hierarchy() {
            return indices.to_vec();
        }
        let ents: Vec<Entity> = scene.entities().collect();
        let roots: Vec<Entity> = indices
            .iter()
            .filter_map(|&i| ents.get(i).copied())
            .collect();
        let below = scene.descendants_of(&roots);
        if below.is_empty() {
            return indices.to_vec();
        }
        let at = positions(scene);
        let mut out: BTreeSet<usize> = indices.iter().copied().collect();
        out.extend(below.iter().filter_map(|d| at.get(d)));
        out.into_iter().collect()
    }

    /// Why the entity at `index` cannot be given an animator: it is inside a moving entity
    /// (it would move by two), or holds one with an animator or a terrain of its own.
    pub fn why_no_animator(&self, index: usize) -> Option<&'static str> {
        let scene = self.scene();
        if !scene.has_hierarchy() {
            return None;
        }
        let e = entity_at(scene, index).ok()?;
        if scene.parent(e).is_some_and(|p| moves(scene, p)) {
            return Some("it is inside a moving entity, which carries it");
        }
        let inside = scene.descendants(e);
        let w = scene.world();
        if inside.iter().any(|&d| w.get::<&Animator>(d).is_ok()) {
            return Some("an entity inside it has an animator, and would move by two");
        }
        if inside.iter().any(|&d| w.get::<&Terrain>(d).is_ok()) {
            return Some("it holds a terrain, and terrains do not move");
        }
        None
    }

    /// The position of the parent of the entity at `index`.
    pub fn parent_of(&self, index: usize) -> Option<usize> {
        let scene = self.scene();
        let p = scene.parent(entity_at(scene, index).ok()?)?;
        scene.index_of(p)
    }

    /// The rows of the entities at `indices` and their descendants as a level file holds
    /// them (for the clipboard): a child of a parent among them relative to it, the others
    /// at the root, where they are in the world.
    pub fn rows_for_copy(&self, indices: &[usize]) -> Vec<EntityRow> {
        let all = self.with_descendants(indices);
        let scene = self.scene();
        let inside: HashSet<Entity> = all
            .iter()
            .filter_map(|&i| entity_at(scene, i).ok())
            .collect();
        all.iter()
            .filter_map(|&i| {
                let e = entity_at(scene, i).ok()?;
                let mut row = scene.row(e)?;
                match scene.parent(e) {
                    Some(p) if inside.contains(&p) => row.transform = scene.local_transform(e),
                    _ => row.parent = None,
                }
                Some(row)
            })
            .collect()
    }

    /// `base`, or `base 2`, `base 3`, … : a name no entity has (but the one at `except`)
    /// nor `also` holds.
    pub fn unique_name(&self, base: &str, except: Option<usize>, also: &HashSet<String>) -> String {
        let scene = self.scene();
        let taken: HashSet<String> = scene
            .entities()
            .enumerate()
            .filter(|(i, _)| Some(*i) != except)
            .filter_map(|(_, e)| scene.world().get::<&Name>(e).ok().map(|n| n.0.clone()))
            .collect();
        let free = |n: &str| !taken.contains(n) && !also.contains(n);
        if free(base) {
            return base.to_owned();
        }
        (2..)
            .map(|k| format!("{base} {k}"))
            .find(|n| free(n))
            .unwrap_or_else(|| base.to_owned())
    }

    /// The name the entity at `index` is known by as a parent: its own when no other entity
    /// has it, else a new unique one, set at once by a step pushed onto `steps` (so the rows
    /// read after it, which name the parent, name it as the later steps find it; running
    /// the step again with the batch changes nothing).
    fn parent_name(
        &mut self,
        index: usize,
        steps: &mut Vec<Command>,
    ) -> Result<Name, CommandError> {
        let row = self.row_at(index).ok_or_else(|| no_entity(index))?;
        let base = row.name.as_ref().map_or("Group", |n| n.0.as_str()).trim();
        let base = if base.is_empty() { "Group" } else { base };
        let name = self.unique_name(base, Some(index), &HashSet::new());
        if row.name.as_ref().is_some_and(|n| n.0 == name) {
            return Ok(Name(name));
        }
        let after = EntityRow {
            name: Some(Name(name.clone())),
            ..row.clone()
        };
        let rename = set_row(index, row, after);
        let (scene, assets) = self.document.parts_mut();
        rename.execute(scene, assets)?;
        steps.push(rename);
        Ok(Name(name))
    }

    /// Applies `steps` as one undo step named `label`; when that fails, the renames
    /// [`EditorState::parent_name`] already ran (the first of the steps) are taken back.
    fn apply_steps(
        &mut self,
        label: &'static str,
        steps: Vec<Command>,
    ) -> Result<(), CommandError> {
        let renames: Vec<Command> = steps
            .iter()
            .take_while(|c| matches!(c, Command::SetRow { before, after, .. } if before.name != after.name && before.parent == after.parent))
            .cloned()
            .collect();
        let result = self.apply(Command::Batch { label, steps }, None);
        if result.is_err() {
            let (scene, assets) = self.document.parts_mut();
            for r in renames.iter().rev() {
                let _ = r.revert(scene, assets);
            }
        }
        result
    }

    /// Makes the entity at `parent` (or the root, for `None`) the parent of the entities at
    /// `moved`, each keeping its place in the world, as one undo step. Refused (nothing
    /// changes) when the parent is one of them or their descendant, or moves (an animator,
    /// its own or an ancestor's) while one of them, or a descendant, has an animator or a
    /// terrain of its own.
    pub fn reparent(&mut self, moved: &[usize], parent: Option<usize>) -> Result<(), CommandError> {
        let scene = self.scene();
        // Only the outermost: a child moved with its parent stays in it.
        let ents: Vec<Entity> = moved
            .iter()
            .filter_map(|&i| entity_at(scene, i).ok())
            .collect();
        let moved: Vec<usize> = moved
            .iter()
            .zip(&ents)
            .filter(|(_, e)| !ents.iter().any(|a| scene.is_ancestor(*a, **e)))
            .map(|(i, _)| *i)
            .collect();
        let moved = moved.as_slice();
        if let Some(p) = parent {
            let pe = entity_at(scene, p)?;
            for &m in moved {
                let me = entity_at(scene, m)?;
                if me == pe || scene.is_ancestor(me, pe) {
                    return Err(CommandError(format!(
                        "{} cannot go into {}: it is inside it",
                        label(scene, me),
                        label(scene, pe)
                    )));
                }
                if moves(scene, pe)
                    && let Some(why) = moves_itself(scene, me)
                {
                    return Err(CommandError(format!(
                        "{} cannot go into {}, which moves: {why}",
                        label(scene, me),
                        label(scene, pe)
                    )));
                }
            }
            if scene.depth(pe) + 1 > MAX_DEPTH {
                return Err(CommandError("groups nest 32 deep at most".into()));
            }
        }
        let mut steps = Vec::new();
        let name = match parent {
            Some(p) => Some(self.parent_name(p, &mut steps)?),
            None => None,
        };
        for &m in moved {
            let before = self.row_at(m).ok_or_else(|| no_entity(m))?;
            let after = EntityRow {
                parent: name.clone(),
                ..before.clone()
            };
            if after != before {
                steps.push(set_row(m, before, after));
            }
        }
        if steps.is_empty() {
            return Ok(());
        }
        self.apply_steps("reparent", steps)?;
        self.select_many(moved.iter().copied(), self.selection);
        Ok(())
    }

    /// Group (Ctrl+G): a new entity "Group" at the centre of the selected entities becomes
    /// their parent (itself under their parent, when they share one), placed before the
    /// first of them; one undo step; the group becomes the selection.
    pub fn group_selection(&mut self) -> Result<(), CommandError> {
        let scene = self.scene();
        let selected = self.selected();
        let at = positions(scene);
        let ents: Vec<Entity> = selected
            .iter()
            .filter_map(|&i| entity_at(scene, i).ok())
            .collect();
        // Only the outermost: a selected child stays in its selected parent.
        let roots: Vec<usize> = selected
            .iter()
            .zip(&ents)
            .filter(|(_, e)| !ents.iter().any(|a| scene.is_ancestor(*a, **e)))
            .map(|(i, _)| *i)
            .collect();
        let Some(&first) = roots.first() else {
            return Ok(());
        };
        let parents: BTreeSet<Option<usize>> = roots
            .iter()
            .map(|&i| {
                scene
                    .parent(entity_at(scene, i).ok()?)
                    .and_then(|p| at.get(&p).copied())
            })
            .collect();
        let shared = (parents.len() == 1)
            .then(|| *parents.first().expect("one"))
            .flatten();
        let places: Vec<Vec3> = roots
            .iter()
            .filter_map(|&i| self.row_at(i)?.transform.map(|t| t.translation))
            .collect();
        let centre = places.iter().sum::<Vec3>() / places.len().max(1) as f32;
        let mut steps = Vec::new();
        let up = match shared {
            Some(p) => Some(self.parent_name(p, &mut steps)?),
            None => None,
        };
        let name = self.unique_name("Group", None, &HashSet::new());
        let group = EntityRow {
            name: Some(Name(name.clone())),
            parent: up,
            transform: Some(Transform::from_translation(centre)),
            ..EntityRow::default()
        };
        steps.push(Command::Spawn {
            index: first,
            row: Box::new(group),
        });
        for &i in &roots {
            let before = self.row_at(i).ok_or_else(|| no_entity(i))?;
            let after = EntityRow {
                parent: Some(Name(name.clone())),
                ..before.clone()
            };
            // The group went in at `first`, before every one of them.
            steps.push(set_row(i + 1, before, after));
        }
        self.apply_steps("group", steps)?;
        self.select_only(first);
        Ok(())
    }

    /// Ungroup (Ctrl+Shift+G): the children of each selected entity that has any go to its
    /// parent (or the root), keeping their places in the world, and it is deleted; one undo
    /// step; the children become the selection.
    pub fn ungroup_selection(&mut self) -> Result<(), CommandError> {
        let scene = self.scene();
        let at = positions(scene);
        let groups: Vec<(usize, Entity)> = (self.selected().into_iter())
            .filter_map(|i| Some((i, entity_at(scene, i).ok()?)))
            .filter(|(_, e)| !scene.children(*e).is_empty())
            .collect();
        if groups.is_empty() {
            return Ok(());
        }
        let gone: HashSet<Entity> = groups.iter().map(|g| g.1).collect();
        let mut moves: Vec<(usize, Option<usize>)> = Vec::new();
        for (_, g) in &groups {
            let mut up = scene.parent(*g);
            while let Some(u) = up.filter(|u| gone.contains(u)) {
                up = scene.parent(u);
            }
            let up = up.and_then(|u| at.get(&u).copied());
            for c in scene.children(*g).into_iter().filter(|c| !gone.contains(c)) {
                moves.push((at[&c], up));
            }
        }
        let mut steps = Vec::new();
        let mut names: HashMap<usize, Name> = HashMap::new();
        for &(c, up) in &moves {
            let name = match up {
                Some(u) if !names.contains_key(&u) => {
                    let n = self.parent_name(u, &mut steps)?;
                    names.insert(u, n.clone());
                    Some(n)
                }
                Some(u) => names.get(&u).cloned(),
                None => None,
            };
            let before = self.row_at(c).ok_or_else(|| no_entity(c))?;
            let after = EntityRow {
                parent: name,
                ..before.clone()
            };
            steps.push(set_row(c, before, after));
        }
        let mut doomed: Vec<usize> = groups.iter().map(|g| g.0).collect();
        doomed.sort_unstable();
        for &g in doomed.iter().rev() {
            let row = self.row_at(g).ok_or_else(|| no_entity(g))?;
            steps.push(Command::Despawn {
                index: g,
                row: Box::new(row),
            });
        }
        self.apply_steps("ungroup", steps)?;
        let kept = moves
            .iter()
            .map(|&(c, _)| c - doomed.iter().filter(|&&g| g < c).count());
        self.select_many(kept, None);
        Ok(())
    }
}

/// Rows a paste adds (as a level file holds them: children relative to parents among them)
/// as the scene takes them: world transforms, and a parent among them renamed when its name
/// is taken in `state`'s scene, its children following.
pub fn rows_to_paste(state: &EditorState, rows: Vec<EntityRow>) -> Vec<EntityRow> {
    if rows.iter().all(|r| r.parent.is_none()) {
        return rows;
    }
    let level = Level {
        entities: rows,
        ..Level::default()
    };
    let scene = Scene::from_level(&level);
    let mut out: Vec<EntityRow> = scene.entities().filter_map(|e| scene.row(e)).collect();
    let parents: HashSet<String> = out
        .iter()
        .filter_map(|r| r.parent.as_ref().map(|p| p.0.clone()))
        .collect();
    let mut given: HashSet<String> = HashSet::new();
    let mut renamed: HashMap<String, String> = HashMap::new();
    for row in &mut out {
        let Some(n) = &mut row.name else { continue };
        if parents.contains(&n.0) {
            let fresh = state.unique_name(&n.0, None, &given);
            given.insert(fresh.clone());
            renamed.insert(n.0.clone(), fresh.clone());
            n.0 = fresh;
        }
    }
    for row in &mut out {
        if let Some(p) = &mut row.parent
            && let Some(n) = renamed.get(&p.0)
        {
            p.0 = n.clone();
        }
    }
    out
}

/// Copies of the entities at `indices` (ascending, descendants among them) for a duplicate:
/// each named `… copy`, a parent's copy with a name of its own and its children's copies
/// under it; a child whose parent is not copied stays beside its original.
pub fn copies(state: &EditorState, indices: &[usize]) -> Vec<EntityRow> {
    let rows: Vec<EntityRow> = indices.iter().filter_map(|&i| state.row_at(i)).collect();
    let parents: HashSet<String> = rows
        .iter()
        .filter_map(|r| r.parent.as_ref().map(|p| p.0.clone()))
        .collect();
    let mut given: HashSet<String> = HashSet::new();
    let mut renamed: HashMap<String, String> = HashMap::new();
    let mut out = rows;
    for row in &mut out {
        let Some(n) = &mut row.name else { continue };
        let copy = format!("{} copy", n.0);
        if parents.contains(&n.0) {
            let fresh = state.unique_name(&copy, None, &given);
            given.insert(fresh.clone());
            renamed.insert(n.0.clone(), fresh.clone());
            n.0 = fresh;
        } else {
            n.0 = copy;
        }
    }
    for row in &mut out {
        if let Some(p) = &mut row.parent
            && let Some(n) = renamed.get(&p.0)
        {
            p.0 = n.clone();
        }
    }
    out
}

/// Whether an animator moves `e`: its own or an ancestor's.
pub fn moves(scene: &Scene, e: Entity) -> bool {
    let animated = |e: Entity| scene.world().get::<&Animator>(e).is_ok();
    animated(e)
        || (0..=MAX_DEPTH)
            .scan(scene.parent(e), |at, _| {
                let a = (*at)?;
                *at = scene.parent(a);
                Some(a)
            })
            .any(animated)
}

/// Why `e` cannot be carried by a moving parent: it, or a descendant, has an animator (it
/// would move by two) or a terrain (terrains do not move).
pub fn moves_itself(scene: &Scene, e: Entity) -> Option<&'static str> {
    let mut all = vec![e];
    all.extend(scene.descendants(e));
    let w = scene.world();
    if all.iter().any(|&d| w.get::<&Animator>(d).is_ok()) {
        Some("an entity moves with one animator, and it (or one inside it) has its own")
    } else if all.iter().any(|&d| w.get::<&Terrain>(d).is_ok()) {
        Some("terrains do not move, and it is (or holds) a terrain")
    } else {
        None
    }
}

fn set_row(index: usize, before: EntityRow, after: EntityRow) -> Command {
    Command::SetRow {
        index,
        before: Box::new(before),
        after: Box::new(after),
    }
}

fn no_entity(index: usize) -> CommandError {
    CommandError(format!("no entity at position {index}"))
}

/// `"name"` (or `entity N`) for messages.
fn label(scene: &Scene, e: Entity) -> String {
    match scene.world().get::<&Name>(e) {
        Ok(n) => format!("\"{}\"", n.0),
        Err(_) => format!("entity {}", scene.index_of(e).unwrap_or(0)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::Document;

    fn at(name: &str, x: f32) -> EntityRow {
        EntityRow {
            name: Some(Name(name.into())),
            transform: Some(Transform::from_translation(Vec3::new(x, 0.0, 0.0))),
            ..EntityRow::default()
        }
    }

    fn names(s: &EditorState) -> Vec<(String, Option<String>)> {
        let level = s.scene().to_level();
        (level.entities.iter())
            .map(|r| {
                let n = r.name.as_ref().map_or(String::new(), |n| n.0.clone());
                (n, r.parent.as_ref().map(|p| p.0.clone()))
            })
            .collect()
    }

    /// A parent whose name another entity shares is renamed in the same undo step, and undo
    /// and redo link each child to the right one.
    #[test]
    fn a_shared_name_is_made_unique_in_the_same_step() {
        let mut s = EditorState::new(Document::new_empty());
        for row in [at("Crate", 0.0), at("Crate", 5.0), at("Ball", 6.0)] {
            s.add(row).expect("add");
        }
        let before = s.scene().to_level();
        let n = s.history.undo_len();
        s.reparent(&[2], Some(1)).expect("reparent");
        assert_eq!(s.history.undo_len(), n + 1, "one step");
        let want = vec![
            ("Crate".to_owned(), None),
            ("Crate 2".to_owned(), None),
            ("Ball".to_owned(), Some("Crate 2".to_owned())),
        ];
        assert_eq!(names(&s), want);
        let ball = s.scene().to_level().entities[2].transform.expect("t");
        assert_eq!(ball.translation, Vec3::X, "relative to its crate");
        s.undo().expect("undo");
        assert_eq!(s.scene().to_level(), before);
        s.redo().expect("redo");
        assert_eq!(names(&s), want);
        // Ungroup the second crate: the ball back at the root, where it was.
        s.select_only(1);
        s.ungroup_selection().expect("ungroup");
        assert_eq!(
            names(&s),
            [("Crate".to_owned(), None), ("Ball".to_owned(), None)]
        );
        assert_eq!(
            s.row_at(1).and_then(|r| r.transform),
            Some(at("", 6.0).transform.expect("t"))
        );
        s.undo().expect("undo");
        assert_eq!(names(&s), want);
    }

    /// Grouping members of a group puts the new group inside it; a moving entity cannot
    /// take children.
    #[test]
    fn a_group_of_siblings_stays_in_their_parent_and_a_moving_parent_takes_no_motion_inside() {
        let mut s = EditorState::new(Document::new_empty());
        for row in [at("Shelf", 1.0), at("Jar", 2.0), at("Pot", 4.0)] {
            s.add(row).expect("add");
        }
        s.reparent(&[1, 2], Some(0)).expect("reparent");
        s.select_many([1, 2], None);
        s.group_selection().expect("group");
        assert_eq!(
            names(&s),
            [
                ("Shelf".to_owned(), None),
                ("Group".to_owned(), Some("Shelf".to_owned())),
                ("Jar".to_owned(), Some("Group".to_owned())),
                ("Pot".to_owned(), Some("Group".to_owned())),
            ]
        );
        let group = s.row_at(1).and_then(|r| r.transform).expect("t");
        assert_eq!(
            group.translation,
            Vec3::new(3.0, 0.0, 0.0),
            "at their centre"
        );
        let spin = texel_scene::animator::Animator {
            motion: texel_scene::animator::Motion::Rotate {
                axis: Vec3::Y,
                speed: 10.0,
            },
            phase: 0.0,
        };
        // A moving shelf carries what is on it; a lid with a motion of its own may not go in.
        let mut shelf = s.row_at(0).expect("row");
        shelf.animator = Some(spin.clone());
        s.set_row(0, shelf, None).expect("animate");
        let lid = EntityRow {
            animator: Some(spin),
            ..at("Lid", 0.0)
        };
        s.add(lid).expect("add");
        s.add(at("Cup", 0.5)).expect("add");
        s.reparent(&[5], Some(0)).expect("a still cup goes in");
        let steps = s.history.undo_len();
        let e = s.reparent(&[4], Some(0)).expect_err("refused");
        assert!(e.0.contains("which moves"), "{e}");
        assert_eq!(s.history.undo_len(), steps);
        assert_eq!(
            s.why_no_animator(5).map(|w| w.contains("inside")),
            Some(true)
        );
        assert_eq!(s.why_no_animator(4), None, "a root");
    }
}
