//! The scene's parent–child links ([`crate::hierarchy`]): who is whose parent, the local
//! transforms a level file holds, and children following their parent.

use std::collections::{HashMap, HashSet};

use hecs::Entity;

use super::Scene;
use crate::components::{Name, Transform};
use crate::hierarchy::{self, Local, MAX_DEPTH, Parent};

/// A parent named by a row, not yet in the scene: linked when an entity of that name comes
/// ([`Scene::spawn`]), so rows may arrive in any order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Pending(pub Name);

impl Scene {
    /// `e`'s parent, if it has one that is alive.
    pub fn parent(&self, e: Entity) -> Option<Entity> {
        let p = self.world.get::<&Parent>(e).ok()?.0;
        self.world.contains(p).then_some(p)
    }

    /// Whether any entity has a parent.
    pub fn has_hierarchy(&self) -> bool {
        self.world.query::<&Parent>().iter().next().is_some()
    }

    /// `e`'s children, in level order.
    pub fn children(&self, e: Entity) -> Vec<Entity> {
        let mut kids: Vec<Entity> = self
            .world
            .query::<(Entity, &Parent)>()
            .iter()
            .filter(|(_, p)| p.0 == e)
            .map(|(c, _)| c)
            .collect();
        if kids.len() > 1 {
            let at = |k: &Entity| self.order.iter().position(|o| o == k);
            kids.sort_by_key(at);
        }
        kids
    }

    /// Every descendant of `e`, each after its parent (children in level order).
    pub fn descendants(&self, e: Entity) -> Vec<Entity> {
        self.descendants_of(&[e])
    }

    /// Every descendant of the entities `roots` (those not among them), each once, after
    /// its parent: one pass over the links, however many roots.
    pub fn descendants_of(&self, roots: &[Entity]) -> Vec<Entity> {
        let links: Vec<(Entity, Entity)> = self
            .world
            .query::<(Entity, &Parent)>()
            .iter()
            .map(|(c, p)| (p.0, c))
            .collect();
        if links.is_empty() {
            return Vec::new();
        }
        let pos: HashMap<Entity, usize> = self
            .order
            .iter()
            .enumerate()
            .map(|(i, e)| (*e, i))
            .collect();
        let mut kids: HashMap<Entity, Vec<Entity>> = HashMap::new();
        for (p, c) in links {
            kids.entry(p).or_default().push(c);
        }
        for v in kids.values_mut() {
            v.sort_by_key(|k| pos.get(k).copied().unwrap_or(usize::MAX));
        }
        let mut seen: HashSet<Entity> = roots.iter().copied().collect();
        let mut out = Vec::new();
        for &r in roots {
            let mut stack: Vec<Entity> =
                kids.get(&r).into_iter().flatten().rev().copied().collect();
            while let Some(at) = stack.pop() {
                if !seen.insert(at) {
                    continue;
                }
                out.push(at);
                stack.extend(kids.get(&at).into_iter().flatten().rev().copied());
            }
        }
        out
    }

    /// Whether `a` is `e`'s parent, its parent's parent, ….
    pub fn is_ancestor(&self, a: Entity, e: Entity) -> bool {
        let mut at = self.parent(e);
        for _ in 0..=MAX_DEPTH {
            match at {
                Some(p) if p == a => return true,
                Some(p) => at = self.parent(p),
                None => return false,
            }
        }
        false
    }

    /// How many ancestors `e` has.
    pub fn depth(&self, e: Entity) -> usize {
        let mut n = 0;
        let mut at = self.parent(e);
        while let Some(p) = at {
            n += 1;
            if n > MAX_DEPTH {
                break;
            }
            at = self.parent(p);
        }
        n
    }

    /// `e`'s transform relative to its parent (as a level file holds it): its world
    /// transform for a root; `None` without a transform.
    pub fn local_transform(&self, e: Entity) -> Option<Transform> {
        let world = *self.world.get::<&Transform>(e).ok()?;
        let Some(p) = self.parent(e) else {
            return Some(world);
        };
        let parent_world = self.world_of(p);
        if let Ok(l) = self.world.get::<&Local>(e)
            && l.world == world
            && l.parent_world == parent_world
        {
            return Some(l.local);
        }
        Some(hierarchy::relative(&parent_world, &world))
    }

    /// `e`'s world transform (identity without one).
    fn world_of(&self, e: Entity) -> Transform {
        self.world
            .get::<&Transform>(e)
            .map_or(Transform::default(), |t| *t)
    }

    /// Makes `parent` `child`'s parent; `local` is the child's transform relative to it,
    /// when known exactly (read from a file).
    pub(super) fn link(&mut self, child: Entity, parent: Entity, local: Option<Transform>) {
        let _ = self.world.insert_one(child, Parent(parent));
        if let (Some(local), Ok(world)) = (local, self.world.get::<&Transform>(child).map(|t| *t)) {
            let parent_world = self.world_of(parent);
            let cache = Local {
                local,
                world,
                parent_world,
            };
            let _ = self.world.insert_one(child, cache);
        }
    }

    /// Links `e` to the first entity named `name` (in level order), unless that is `e`, one
    /// of its descendants, or would make a chain deeper than [`MAX_DEPTH`]: `e` is then a
    /// root.
    pub(super) fn set_parent_named(&mut self, e: Entity, name: Option<&Name>) {
        let found = name.and_then(|name| {
            self.order
                .iter()
                .copied()
                .find(|&o| o != e && self.world.get::<&Name>(o).is_ok_and(|n| n.0 == name.0))
        });
        let new = found.filter(|&p| !self.is_ancestor(e, p) && self.depth(p) < MAX_DEPTH);
        let _ = self.world.remove_one::<Pending>(e);
        if new.is_some() && new == self.parent(e) {
            // The same parent: the exact local transform stays while it is true.
            return;
        }
        let _ = self.world.remove_one::<Parent>(e);
        let _ = self.world.remove_one::<Local>(e);
        if let Some(p) = new {
            self.link(e, p, None);
        } else if let (Some(name), None) = (name, found) {
            let _ = self.world.insert_one(e, Pending(name.clone()));
        }
    }

    /// Links to `e` the entities waiting for a parent of `e`'s name (spawned before it, as
    /// when a delete of a group and its children is undone), where they are.
    pub(super) fn adopt_pending(&mut self, e: Entity) {
        let Ok(name) = self.world.get::<&Name>(e).map(|n| n.0.clone()) else {
            return;
        };
        let waiting: Vec<Entity> = self
            .world
            .query::<(Entity, &Pending)>()
            .iter()
            .filter(|(c, p)| *c != e && p.0.0 == name)
            .map(|(c, _)| c)
            .collect();
        for c in waiting {
            let _ = self.world.remove_one::<Pending>(c);
            if !self.is_ancestor(c, e) && c != e && self.depth(e) < MAX_DEPTH {
                self.link(c, e, None);
            }
        }
    }

    /// The name of `e`'s parent, or of the parent it waits for.
    pub(super) fn parent_name(&self, e: Entity) -> Option<Name> {
        if let Some(p) = self.parent(e) {
            let name = self.world.get::<&Name>(p).map(|n| (*n).clone());
            return Some(name.unwrap_or(Name(String::new())));
        }
        self.world.get::<&Pending>(e).ok().map(|p| p.0.clone())
    }

    /// The local transform of every descendant of `e`, parents first, before `e` changes.
    pub(super) fn descendant_locals(&self, e: Entity) -> Vec<(Entity, Option<Transform>)> {
        // Most entities have no children: no maps built for them.
        if !self.world.query::<&Parent>().iter().any(|p| p.0 == e) {
            return Vec::new();
        }
        self.descendants(e)
            .into_iter()
            .map(|d| (d, self.local_transform(d)))
            .collect()
    }

    /// Places each of `below` (parents first) at its local transform in its parent's
    /// frame, as it is now.
    pub(super) fn place_descendants(&mut self, below: Vec<(Entity, Option<Transform>)>) {
        for (d, local) in below {
            let (Some(local), Some(p)) = (local, self.parent(d)) else {
                continue;
            };
            let parent_world = self.world_of(p);
            let world = hierarchy::compose(&parent_world, &local);
            if let Ok(mut t) = self.world.get::<&mut Transform>(d) {
                *t = world;
            }
            let cache = Local {
                local,
                world,
                parent_world,
            };
            let _ = self.world.insert_one(d, cache);
        }
    }
}
