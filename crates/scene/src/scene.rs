//! The live scene: a hecs world holding the level's entities, in a stable order.
//!
//! hecs is used as a library: callers query [`Scene::world`] with ordinary functions. The
//! scene only adds what a level file needs on top: the level settings and the order in which
//! entities are written, so that saving never reshuffles rows.

mod tree;

use std::path::Path;

use hecs::{Entity, EntityBuilder, World};

use crate::animator::Animator;
use crate::components::{
    DirectionalLight, Geometry, LevelSettings, Material, Name, PlayerStart, PointLight,
    ProbeGridOverride, Transform,
};
use crate::hierarchy;
use crate::level::{EntityRow, Level, LevelError};
use crate::sprite::Sprite;
use crate::terrain::Terrain;

/// A level loaded into a hecs world.
#[derive(Default)]
pub struct Scene {
    /// Level-wide settings.
    pub settings: LevelSettings,
    /// The palette the frames are mapped to, if any.
    pub palette: Option<crate::components::PaletteSetting>,
    world: World,
    order: Vec<Entity>,
}

impl Scene {
    /// An empty scene with default settings.
    pub fn new() -> Self {
        Self::default()
    }

    /// Spawns every row of `level`, in order. Here the level's parents are resolved
    /// ([`crate::hierarchy`]): each entity's [`Transform`] in the world is its world
    /// transform, and each child holds a [`Parent`].
    pub fn from_level(level: &Level) -> Self {
        let mut scene = Scene {
            settings: level.settings,
            palette: level.palette.clone(),
            ..Scene::default()
        };
        let (parents, worlds) = hierarchy::resolve(&level.entities);
        for (row, world) in level.entities.iter().zip(&worlds) {
            let row = EntityRow {
                parent: None,
                transform: *world,
                ..row.clone()
            };
            let e = scene.world.spawn(build(row).build());
            scene.order.push(e);
        }
        for (i, p) in parents.iter().enumerate() {
            let Some(p) = *p else { continue };
            let (child, parent) = (scene.order[i], scene.order[p]);
            scene.link(child, parent, level.entities[i].transform);
        }
        scene
    }

    /// Loads a level file into a new scene.
    pub fn load(path: &Path) -> Result<Self, LevelError> {
        Level::load(path).map(|l| Scene::from_level(&l))
    }

    /// Saves the scene atomically as a level file.
    pub fn save(&self, path: &Path) -> Result<(), LevelError> {
        self.to_level().save(path)
    }

    /// The level this scene holds, rows in the scene's order, each child's transform
    /// relative to its parent's.
    pub fn to_level(&self) -> Level {
        let entities = self
            .entities()
            .filter_map(|e| {
                let mut row = self.row(e)?;
                if row.parent.is_some() {
                    row.transform = self.local_transform(e);
                }
                Some(row)
            })
            .collect();
        Level {
            settings: self.settings,
            palette: self.palette.clone(),
            entities,
            ..Level::default()
        }
    }

    /// The world, for queries.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The world, for editing components in place. Spawn and despawn through the scene, so
    /// the entity order stays right.
    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }

    /// Live entities in level order.
    pub fn entities(&self) -> impl Iterator<Item = Entity> + '_ {
        self.order
            .iter()
            .copied()
            .filter(|e| self.world.contains(*e))
    }

    /// Number of live entities.
    pub fn len(&self) -> usize {
        self.world.len() as usize
    }

    /// Whether the scene has no entities.
    pub fn is_empty(&self) -> bool {
        self.world.is_empty()
    }

    /// Spawns an entity with `row`'s components at the end of the order. As with every
    /// row the scene takes or gives, `row.transform` is the world transform and
    /// `row.parent` names the parent ([`Scene::set_row`]).
    pub fn spawn(&mut self, row: EntityRow) -> Entity {
        let parent = row.parent.clone();
        let e = self.world.spawn(build(row).build());
        self.order.push(e);
        self.set_parent_named(e, parent.as_ref());
        self.adopt_pending(e);
        e
    }

    /// Spawns an entity at `index` in the order (clamped), e.g. to undo a delete.
    pub fn spawn_at(&mut self, index: usize, row: EntityRow) -> Entity {
        let parent = row.parent.clone();
        let e = self.world.spawn(build(row).build());
        self.order.retain(|o| self.world.contains(*o));
        self.order.insert(index.min(self.order.len()), e);
        self.set_parent_named(e, parent.as_ref());
        self.adopt_pending(e);
        e
    }

    /// Position of `e` in the order.
    pub fn index_of(&self, e: Entity) -> Option<usize> {
        self.entities().position(|o| o == e)
    }

    /// Removes an entity, returning its components. Its children, if any stay, become roots
    /// where they are.
    pub fn despawn(&mut self, e: Entity) -> Option<EntityRow> {
        let row = self.row(e)?;
        self.world.despawn(e).ok()?;
        self.order.retain(|o| *o != e);
        Some(row)
    }

    /// A copy of every level component `e` has: its world transform, and its parent's
    /// name ([`Scene::to_level`] gives rows as files hold them, transforms relative).
    pub fn row(&self, e: Entity) -> Option<EntityRow> {
        let r = self.world.entity(e).ok()?;
        Some(EntityRow {
            name: r.get::<&Name>().map(|c| (*c).clone()),
            parent: self.parent_name(e),
            transform: r.get::<&Transform>().map(|c| *c),
            geometry: r.get::<&Geometry>().map(|c| (*c).clone()),
            material: r.get::<&Material>().map(|c| (*c).clone()),
            directional_light: r.get::<&DirectionalLight>().map(|c| *c),
            point_light: r.get::<&PointLight>().map(|c| *c),
            probe_grid_override: r.get::<&ProbeGridOverride>().map(|c| *c),
            player_start: r.get::<&PlayerStart>().map(|c| *c),
            terrain: r.get::<&Terrain>().map(|c| (*c).clone()),
            animator: r.get::<&Animator>().map(|c| (*c).clone()),
            sprite: r.get::<&Sprite>().map(|c| (*c).clone()),
        })
    }

    /// Replaces every level component of `e` with `row`'s (components `row` lacks are
    /// removed). Other components, not part of levels, are kept. `row.transform` is the
    /// world transform; `row.parent` names the parent (the first entity of that name; one
    /// that is missing, is `e` or one of its descendants leaves `e` a root). `e`'s
    /// descendants keep their places relative to it, so they move with it.
    pub fn set_row(&mut self, e: Entity, row: EntityRow) -> Result<(), hecs::NoSuchEntity> {
        if !self.world.contains(e) {
            return Err(hecs::NoSuchEntity);
        }
        let below = self.descendant_locals(e);
        let parent = row.parent.clone();
        remove_each(&mut self.world, e);
        self.world
            .insert(e, build(row).build())
            .map_err(|_| hecs::NoSuchEntity)?;
        self.set_parent_named(e, parent.as_ref());
        self.place_descendants(below);
        self.adopt_pending(e);
        Ok(())
    }
}

fn remove_each(world: &mut World, e: Entity) {
    let _ = world.remove_one::<Name>(e);
    let _ = world.remove_one::<tree::Pending>(e);
    let _ = world.remove_one::<Transform>(e);
    let _ = world.remove_one::<Geometry>(e);
    let _ = world.remove_one::<Material>(e);
    let _ = world.remove_one::<DirectionalLight>(e);
    let _ = world.remove_one::<PointLight>(e);
    let _ = world.remove_one::<ProbeGridOverride>(e);
    let _ = world.remove_one::<PlayerStart>(e);
    let _ = world.remove_one::<Terrain>(e);
    let _ = world.remove_one::<Animator>(e);
    let _ = world.remove_one::<Sprite>(e);
}

fn build(row: EntityRow) -> EntityBuilder {
    let mut b = EntityBuilder::new();
    if let Some(c) = row.name {
        b.add(c);
    }
    if let Some(c) = row.transform {
        b.add(c);
    }
    if let Some(c) = row.geometry {
        b.add(c);
    }
    if let Some(c) = row.material {
        b.add(c);
    }
    if let Some(c) = row.directional_light {
        b.add(c);
    }
    if let Some(c) = row.terrain {
        b.add(c);
    }
    if let Some(c) = row.point_light {
        b.add(c);
    }
    if let Some(c) = row.probe_grid_override {
        b.add(c);
    }
    if let Some(c) = row.player_start {
        b.add(c);
    }
    if let Some(c) = row.animator {
        b.add(c);
    }
    if let Some(c) = row.sprite {
        b.add(c);
    }
    b
}

/// How many entities of each kind a scene holds (for summaries).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KindCounts {
    /// All entities.
    pub entities: usize,
    /// Entities with primitive geometry.
    pub primitives: usize,
    /// Entities with a glTF mesh.
    pub meshes: usize,
    /// Directional lights.
    pub directional_lights: usize,
    /// Point lights.
    pub point_lights: usize,
    /// Probe-grid overrides.
    pub probe_overrides: usize,
    /// Player starts.
    pub player_starts: usize,
    /// Terrains.
    pub terrains: usize,
    /// Sprites.
    pub sprites: usize,
}

impl Scene {
    /// Every moving entity of the scene (one [`Scene::carried`] moves: an [`Animator`] and a
    /// [`Transform`], or a descendant of such an entity; no terrain) with its pose at `t`
    /// seconds, in level order. The scene is not changed.
    pub fn animated_poses(&self, t: f64) -> Vec<(Entity, Transform)> {
        self.entities()
            .filter_map(|e| Some((e, self.pose_at(e, t)?)))
            .collect()
    }

    /// `e`'s pose at `t` seconds when an animator moves it ([`Scene::carried`]'s pose,
    /// without copying the animator).
    pub fn pose_at(&self, e: Entity, t: f64) -> Option<Transform> {
        let r = self.world.entity(e).ok()?;
        if r.has::<Terrain>() {
            return None;
        }
        let world = *r.get::<&Transform>()?;
        if let Some(animator) = r.get::<&Animator>() {
            return Some(animator.pose_at(&world, t));
        }
        let a = self.animated_ancestor(e)?;
        let animator = self.world.get::<&Animator>(a).ok()?;
        let base = (self.world.get::<&Transform>(a)).map_or(Transform::default(), |t| *t);
        let pose = animator.pose_at(&base, t);
        Some(hierarchy::compose(
            &pose,
            &hierarchy::relative(&base, &world),
        ))
    }

    /// `e`'s nearest ancestor with an animator.
    fn animated_ancestor(&self, e: Entity) -> Option<Entity> {
        let mut at = self.parent(e);
        for _ in 0..=hierarchy::MAX_DEPTH {
            let a = at?;
            if self.world.get::<&Animator>(a).is_ok() {
                return Some(a);
            }
            at = self.parent(a);
        }
        None
    }

    /// What moves `e`: its own animator, or its nearest animated ancestor's, which carries
    /// it ([`crate::hierarchy::Carried`]); `None` for an entity nothing moves, one without a
    /// transform, and a terrain.
    pub fn carried(&self, e: Entity) -> Option<crate::hierarchy::Carried> {
        let r = self.world.entity(e).ok()?;
        if r.has::<Terrain>() {
            return None;
        }
        let world = *r.get::<&Transform>()?;
        if let Some(animator) = r.get::<&Animator>() {
            return Some(crate::hierarchy::Carried {
                animator: (*animator).clone(),
                base: world,
                offset: None,
            });
        }
        let a = self.animated_ancestor(e)?;
        let animator = self.world.get::<&Animator>(a).ok()?;
        let base = (self.world.get::<&Transform>(a)).map_or(Transform::default(), |t| *t);
        Some(crate::hierarchy::Carried {
            animator: (*animator).clone(),
            base,
            offset: Some(hierarchy::relative(&base, &world)),
        })
    }

    /// Counts entities by kind.
    pub fn kind_counts(&self) -> KindCounts {
        let w = &self.world;
        let mut k = KindCounts {
            entities: self.len(),
            ..KindCounts::default()
        };
        for g in w.query::<&Geometry>().iter() {
            match g {
                Geometry::Mesh { .. } => k.meshes += 1,
                _ => k.primitives += 1,
            }
        }
        k.directional_lights = w.query::<&DirectionalLight>().iter().count();
        k.point_lights = w.query::<&PointLight>().iter().count();
        k.probe_overrides = w.query::<&ProbeGridOverride>().iter().count();
        k.player_starts = w.query::<&PlayerStart>().iter().count();
        k.terrains = w.query::<&Terrain>().iter().count();
        k.sprites = w.query::<&Sprite>().iter().count();
        k
    }
}

impl std::fmt::Display for KindCounts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} entities: {} primitives, {} meshes, {} directional lights, {} point lights, \
             {} probe-grid overrides, {} player starts, {} terrains, {} sprites",
            self.entities,
            self.primitives,
            self.meshes,
            self.directional_lights,
            self.point_lights,
            self.probe_overrides,
            self.player_starts,
            self.terrains,
            self.sprites
        )
    }
}
