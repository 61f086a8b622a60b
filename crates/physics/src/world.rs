//! The level's colliders in a rapier world: one body per entity with geometry or a terrain
//! (fixed until something moves it), its colliders tagged with the entity.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Quat, Vec2, Vec3};
use hecs::Entity;
use rapier3d::prelude as rp;
use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};
use texel_scene::assets::AssetLibrary;
use texel_scene::terrain::{Heightfield, Terrain};
use texel_scene::{Geometry, Name, PlayerStart, Scene, Transform, TriMesh};

use crate::colliders::{self, Shapes};
use crate::convert::{parts, pose, vec3};
use crate::{MAX_TRIANGLES, PhysicsError, PhysicsWarning};

/// How far below the level's lowest collider a player counts as fallen out of the world.
pub const KILL_MARGIN: f32 = 20.0;

/// Where a player (re)starts: the level's [`PlayerStart`], or above the origin when the level
/// has none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spawn {
    /// The feet.
    pub feet: Vec3,
    /// Heading in degrees (see [`PlayerStart::yaw`]).
    pub yaw: f32,
    /// Pitch in degrees.
    pub pitch: f32,
    /// Eye above the feet.
    pub eye_height: f32,
}

/// Ids of bodies, unique across worlds, so a player can tell the body it stood on from one
/// rebuilt for the same entity (rapier's handles restart in a new world).
static NEXT_BODY_ID: AtomicU64 = AtomicU64::new(1);

/// What an entity's colliders were built from, to rebuild them at another scale.
struct Body {
    handle: RigidBodyHandle,
    id: u64,
    colliders: Vec<ColliderHandle>,
    /// The geometry and its loaded mesh, when it has geometry.
    geometry: Option<(Geometry, Option<Arc<TriMesh>>)>,
    /// The terrain's extent and its collider, when it is a terrain.
    terrain: Option<(Vec2, ColliderHandle)>,
    /// The scale the geometry's shapes were built at.
    scale: Vec3,
    /// Triangles in its triangle meshes.
    triangles: usize,
    /// Velocity of its last kinematic move.
    velocity: Vec3,
}

/// A level's colliders, ready for [`Player`](crate::Player)s to walk through.
pub struct PhysicsWorld {
    pub(crate) rapier: rp::PhysicsWorld,
    bodies: HashMap<Entity, Body>,
    warnings: Vec<PhysicsWarning>,
    spawn: Option<Spawn>,
    bounds: Option<(Vec3, Vec3)>,
    triangles: usize,
    /// Bodies moved or colliders changed since rapier's broad phase last saw them.
    dirty: bool,
}

impl std::fmt::Debug for PhysicsWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PhysicsWorld")
            .field("entities", &self.bodies.len())
            .field("colliders", &self.rapier.colliders.len())
            .field("warnings", &self.warnings.len())
            .field("bounds", &self.bounds)
            .finish()
    }
}

fn name_of(scene: &Scene, e: Entity) -> String {
    scene
        .world()
        .get::<&Name>(e)
        .map_or_else(|_| "unnamed".to_owned(), |n| n.0.clone())
}

fn finite(t: &Transform) -> bool {
    t.translation.is_finite() && t.rotation.is_finite() && t.scale.is_finite()
}

impl PhysicsWorld {
    /// Colliders for every entity of `scene` with geometry or a terrain, meshes and heights
    /// from `assets`. Geometry that cannot be a collider is left out and reported in
    /// [`PhysicsWorld::warnings`]; only a level whose meshes exceed [`MAX_TRIANGLES`] fails.
    pub fn from_scene(scene: &Scene, assets: &AssetLibrary) -> Result<Self, PhysicsError> {
        let mut world = PhysicsWorld {
            rapier: rp::PhysicsWorld::new(),
            bodies: HashMap::new(),
            warnings: Vec::new(),
            spawn: None,
            bounds: None,
            triangles: 0,
            dirty: true,
        };
        let mut cache = HashMap::new();
        for e in scene.entities() {
            world.insert_entity(scene, assets, e, &mut cache)?;
        }
        world.sync();
        world.spawn = find_spawn(scene).map(|s| world.out_of_terrain(s));
        Ok(world)
    }

    /// Rebuilds every collider from the level as it is now (after a load or a large edit),
    /// every body fixed again at its entity's transform. A player keeps walking; the body it
    /// stood on is forgotten (it is not carried by the jump back to the level's pose).
    pub fn rebuild(&mut self, scene: &Scene, assets: &AssetLibrary) -> Result<(), PhysicsError> {
        *self = PhysicsWorld::from_scene(scene, assets)?;
        Ok(())
    }

    /// Rebuilds the colliders of one entity after an edit (moved, resized, new geometry,
    /// despawned), as a fixed body at its transform, and re-reads the player start. Warnings
    /// about the entity are replaced; a player standing on it is not carried by the edit.
    pub fn update_entity(
        &mut self,
        scene: &Scene,
        assets: &AssetLibrary,
        entity: Entity,
    ) -> Result<(), PhysicsError> {
        self.remove_entity(entity);
        if scene.world().contains(entity) {
            self.insert_entity(scene, assets, entity, &mut HashMap::new())?;
        }
        self.spawn = find_spawn(scene).map(|s| self.out_of_terrain(s));
        Ok(())
    }

    /// Removes an entity's colliders (and its warnings). Unknown entities are ignored.
    pub fn remove_entity(&mut self, entity: Entity) {
        self.warnings.retain(|w| w.entity != entity);
        if let Some(body) = self.bodies.remove(&entity) {
            self.rapier.remove_body_with_colliders(body.handle, true);
            self.triangles -= body.triangles;
            self.dirty = true;
        }
    }

    /// Replaces a terrain's heights (a sculpt stroke, an imported heightmap). The field must
    /// have at least 2 × 2 finite samples.
    pub fn update_heightfield(
        &mut self,
        entity: Entity,
        field: &Heightfield,
    ) -> Result<(), PhysicsError> {
        let body = self
            .bodies
            .get(&entity)
            .ok_or(PhysicsError::UnknownEntity(entity))?;
        let (size, handle) = body.terrain.ok_or(PhysicsError::NotATerrain(entity))?;
        let shape = colliders::heightfield(size, field)
            .map_err(|message| PhysicsError::BadHeightfield { entity, message })?;
        if let Some(c) = self.rapier.colliders.get_mut(handle) {
            c.set_shape(shape);
        }
        self.dirty = true;
        Ok(())
    }

    /// Moves an entity's colliders to `transform` as a kinematic (position-based) body: the
    /// first call turns its fixed body kinematic; a new scale rebuilds its shapes. `dt` is
    /// the time the move takes (for the body's velocity; not finite or not positive: the
    /// velocity is left as it was). Players standing on it are carried along on their next
    /// step. Call it for every moving entity before stepping the players.
    pub fn set_kinematic_pose(
        &mut self,
        entity: Entity,
        transform: &Transform,
        dt: f32,
    ) -> Result<(), PhysicsError> {
        if !finite(transform) || transform.scale.min_element() <= 0.0 {
            return Err(PhysicsError::BadPose(entity));
        }
        let body = self
            .bodies
            .get(&entity)
            .ok_or(PhysicsError::UnknownEntity(entity))?;
        let handle = body.handle;
        if !same_scale(body.scale, transform.scale)
            && let Some((geometry, mesh)) = body.geometry.clone()
        {
            self.rescale(entity, &geometry, mesh.as_deref(), transform.scale)?;
        }
        let quat = transform.quat();
        let target = pose(transform.translation, quat);
        let Some(rb) = self.rapier.bodies.get_mut(handle) else {
            return Err(PhysicsError::UnknownEntity(entity));
        };
        if !rb.is_kinematic() {
            rb.set_body_type(rp::RigidBodyType::KinematicPositionBased, true);
        }
        let (old_t, _) = parts(rb.position());
        rb.set_next_kinematic_position(target);
        rb.set_position(target, true);
        if let Some(body) = self.bodies.get_mut(&entity) {
            let v = (transform.translation - old_t) / dt;
            if dt > 0.0 && v.is_finite() {
                body.velocity = v;
            }
        }
        self.dirty = true;
        Ok(())
    }

    /// Moves every listed entity that has colliders, as
    /// [`texel_scene::Scene::animated_poses`] lists them for a moment of the level's clock:
    /// call it once per frame before stepping the players. Entities without colliders (an
    /// animated light) are skipped; a bad pose is skipped too, and the first one is returned
    /// once the others are applied.
    pub fn set_kinematic_poses(
        &mut self,
        poses: &[(Entity, Transform)],
        dt: f32,
    ) -> Result<(), PhysicsError> {
        let mut first = Ok(());
        for (entity, transform) in poses {
            match self.set_kinematic_pose(*entity, transform, dt) {
                Ok(()) | Err(PhysicsError::UnknownEntity(_)) => {}
                Err(e) => {
                    if first.is_ok() {
                        first = Err(e);
                    }
                }
            }
        }
        first
    }

    /// The velocity of a kinematic entity's origin over its last move (zero for one that
    /// never moved).
    pub fn velocity(&self, entity: Entity) -> Vec3 {
        self.bodies.get(&entity).map_or(Vec3::ZERO, |b| b.velocity)
    }

    /// Whether an entity's body has been moved by [`PhysicsWorld::set_kinematic_pose`].
    pub fn is_kinematic(&self, entity: Entity) -> bool {
        self.body_of(entity)
            .and_then(|h| self.rapier.bodies.get(h))
            .is_some_and(|b| b.is_kinematic())
    }

    pub(crate) fn body_of(&self, entity: Entity) -> Option<RigidBodyHandle> {
        self.bodies.get(&entity).map(|b| b.handle)
    }

    /// The id of an entity's current body (a new one after every rebuild of it).
    pub(crate) fn body_id(&self, entity: Entity) -> Option<u64> {
        self.bodies.get(&entity).map(|b| b.id)
    }

    /// The rigid pose (translation, rotation) of an entity's body.
    pub fn pose(&self, entity: Entity) -> Option<(Vec3, Quat)> {
        let b = self.bodies.get(&entity)?;
        Some(parts(self.rapier.bodies.get(b.handle)?.position()))
    }

    fn rescale(
        &mut self,
        entity: Entity,
        geometry: &Geometry,
        mesh: Option<&TriMesh>,
        scale: Vec3,
    ) -> Result<(), PhysicsError> {
        let shapes = colliders::geometry_shapes(geometry, scale, mesh)
            .map_err(|_| PhysicsError::BadPose(entity))?;
        let body = self
            .bodies
            .get_mut(&entity)
            .ok_or(PhysicsError::UnknownEntity(entity))?;
        let terrain = body.terrain.map(|t| t.1);
        for c in body.colliders.drain(..).filter(|c| Some(*c) != terrain) {
            self.rapier.remove_collider(c);
        }
        body.colliders.extend(terrain);
        self.triangles = self.triangles - body.triangles + shapes.triangles;
        body.triangles = shapes.triangles;
        body.scale = scale;
        let handle = body.handle;
        let added = self.attach(entity, handle, &shapes, rp::Pose::IDENTITY);
        if let Some(body) = self.bodies.get_mut(&entity) {
            body.colliders.extend(added);
        }
        self.dirty = true;
        Ok(())
    }

    /// Geometry that gave no collider, or only part of one.
    pub fn warnings(&self) -> &[PhysicsWarning] {
        &self.warnings
    }

    /// Where players start: the level's first [`PlayerStart`], or above the origin at the
    /// top of the level when it has none.
    pub fn spawn(&self) -> Spawn {
        self.spawn.unwrap_or_else(|| Spawn {
            feet: Vec3::new(0.0, self.bounds.map_or(0.0, |b| b.1.y) + 1.0, 0.0),
            yaw: 0.0,
            pitch: 0.0,
            eye_height: PlayerStart::default().eye_height,
        })
    }

    /// `spawn` with its feet lifted onto a terrain whose surface is above them (a player start
    /// placed before the ground was raised, or under a hill): a start inside a terrain would
    /// drop the player through it. Starts under anything else (a roof) stay.
    fn out_of_terrain(&mut self, mut spawn: Spawn) -> Spawn {
        let Some((_, top)) = self.bounds else {
            return spawn;
        };
        let from = Vec3::new(spawn.feet.x, top.y + 1.0, spawn.feet.z);
        let down = Vec3::NEG_Y;
        let reach = from.y - spawn.feet.y;
        // The first terrain surface the ray from above meets, skipping what lies on it.
        let mut origin = from;
        for _ in 0..16 {
            let Some((t, collider)) = self.cast_ray(origin, down, from.y - origin.y + reach) else {
                break;
            };
            let hit = origin + down * t;
            if hit.y <= spawn.feet.y {
                break;
            }
            let terrain = self
                .entity_of(collider)
                .is_some_and(|e| self.bodies.get(&e).is_some_and(|b| b.terrain.is_some()));
            if terrain {
                spawn.feet.y = hit.y;
                break;
            }
            origin = hit + down * 1e-3;
        }
        spawn
    }

    /// The box holding every collider, `None` when there is none.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bounds
    }

    /// Below this height a player has fallen out of the world: [`KILL_MARGIN`] under the
    /// lowest collider (or under the spawn, in an empty level).
    pub fn kill_height(&self) -> f32 {
        self.bounds
            .map_or(self.spawn().feet.y, |b| b.0.y.min(self.spawn().feet.y))
            - KILL_MARGIN
    }

    /// The entity a collider was built for.
    pub fn entity_of(&self, collider: ColliderHandle) -> Option<Entity> {
        let c = self.rapier.colliders.get(collider)?;
        Entity::from_bits(u64::try_from(c.user_data).ok()?)
    }

    /// The colliders built for an entity (empty when none).
    pub fn colliders_of(&self, entity: Entity) -> &[ColliderHandle] {
        self.bodies.get(&entity).map_or(&[], |b| &b.colliders)
    }

    /// Number of colliders.
    pub fn collider_count(&self) -> usize {
        self.rapier.colliders.len()
    }

    /// Triangles held by triangle-mesh colliders.
    pub fn triangle_count(&self) -> usize {
        self.triangles
    }

    /// The world-space box of one collider.
    pub fn collider_bounds(&self, collider: ColliderHandle) -> Option<(Vec3, Vec3)> {
        let aabb = self.rapier.colliders.get(collider)?.compute_aabb();
        Some((vec3(aabb.mins), vec3(aabb.maxs)))
    }

    /// The first surface a ray from `origin` along `dir` meets within `max_distance`: the
    /// distance and the collider. For tests, tools and placing things.
    pub fn cast_ray(
        &mut self,
        origin: Vec3,
        dir: Vec3,
        max_distance: f32,
    ) -> Option<(f32, ColliderHandle)> {
        if !(origin.is_finite() && dir.is_finite() && max_distance.is_finite()) {
            return None;
        }
        self.sync();
        let ray = rp::Ray::new(crate::convert::vector(origin), crate::convert::vector(dir));
        self.rapier
            .cast_ray(&ray, max_distance, true, rp::QueryFilter::default())
            .map(|(c, t)| (t, c))
    }

    /// Brings rapier's broad phase up to date with moved bodies and changed shapes.
    pub(crate) fn sync(&mut self) {
        if self.dirty {
            self.rapier.detect_collisions(&(), &());
            self.bounds = self
                .rapier
                .colliders
                .iter()
                .map(|(_, c)| c.compute_aabb())
                .filter(|a| a.mins.is_finite() && a.maxs.is_finite())
                .map(|a| (vec3(a.mins), vec3(a.maxs)))
                .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)));
            self.dirty = false;
        }
    }

    fn warn(&mut self, scene: &Scene, entity: Entity, message: String) {
        self.warnings.push(PhysicsWarning {
            entity,
            name: name_of(scene, entity),
            message,
        });
    }

    /// Adds `shapes` to `body` as colliders tagged with `entity`, each at `offset` times its
    /// own pose in the body's frame.
    fn attach(
        &mut self,
        entity: Entity,
        body: RigidBodyHandle,
        shapes: &Shapes,
        offset: rp::Pose,
    ) -> Vec<ColliderHandle> {
        let tag = u128::from(entity.to_bits().get());
        shapes
            .parts
            .iter()
            .map(|(local, shape)| {
                // Level colliders never touch each other, only the players' queries (whose
                // filters name no groups), so rapier's narrow phase skips every pair.
                let c = rp::ColliderBuilder::new(shape.clone())
                    .position(offset * *local)
                    .user_data(tag)
                    .collision_groups(rp::InteractionGroups::none())
                    .build();
                self.rapier.insert_collider(c, Some(body))
            })
            .collect()
    }

    fn insert_entity(
        &mut self,
        scene: &Scene,
        assets: &AssetLibrary,
        e: Entity,
        cache: &mut MeshCache,
    ) -> Result<(), PhysicsError> {
        let w = scene.world();
        let geometry = w.get::<&Geometry>(e).ok().map(|g| (*g).clone());
        let terrain = w.get::<&Terrain>(e).ok().map(|t| (*t).clone());
        if geometry.is_none() && terrain.is_none() {
            return Ok(());
        }
        let t = w.get::<&Transform>(e).map_or(Transform::default(), |t| *t);
        if !finite(&t) {
            self.warn(scene, e, "transform is not finite: no collider".to_owned());
            return Ok(());
        }
        let mesh = match &geometry {
            Some(Geometry::Mesh { path }) => assets.get(path).cloned(),
            _ => None,
        };
        let shapes = geometry.as_ref().and_then(|g| {
            let built = match (g, &mesh) {
                (Geometry::Mesh { path }, Some(m)) => {
                    let key = (path.clone(), t.scale.to_array().map(f32::to_bits));
                    cache
                        .entry(key)
                        .or_insert_with(|| colliders::trimesh(m, t.scale))
                        .clone()
                }
                _ => colliders::geometry_shapes(g, t.scale, mesh.as_deref()),
            };
            match built {
                Ok(s) => Some(s),
                Err(m) => {
                    self.warn(scene, e, format!("{m}: no collider"));
                    None
                }
            }
        });
        let heightfield = terrain.as_ref().and_then(|terrain| {
            let built = match assets.heightfield(terrain) {
                Some(field) => colliders::heightfield(terrain.size, field),
                None => Err("the terrain's heights are not loaded".to_owned()),
            };
            match built {
                Ok(s) => Some((terrain.size, s)),
                Err(m) => {
                    self.warn(scene, e, format!("{m}: no terrain collider"));
                    None
                }
            }
        });
        if shapes.is_none() && heightfield.is_none() {
            return Ok(());
        }
        let triangles = shapes.as_ref().map_or(0, |s| s.triangles);
        if self.triangles + triangles > MAX_TRIANGLES {
            return Err(PhysicsError::TooManyTriangles {
                triangles: self.triangles + triangles,
                limit: MAX_TRIANGLES,
            });
        }
        if let Some(note) = shapes.as_ref().and_then(|s| s.note.clone()) {
            self.warn(scene, e, note);
        }
        let quat = t.quat();
        let rb = rp::RigidBodyBuilder::fixed()
            .pose(pose(t.translation, quat))
            .user_data(u128::from(e.to_bits().get()))
            .build();
        let handle = self.rapier.insert_body(rb);
        let mut handles = Vec::new();
        if let Some(s) = &shapes {
            handles = self.attach(e, handle, s, rp::Pose::IDENTITY);
        }
        let terrain_collider = heightfield.map(|(size, shape)| {
            // A terrain lies along the world's axes at its translation: undo the rotation.
            let s = Shapes {
                parts: vec![(rp::Pose::IDENTITY, shape)],
                triangles: 0,
                note: None,
            };
            let undo = pose(Vec3::ZERO, quat.inverse());
            let c = self.attach(e, handle, &s, undo)[0];
            handles.push(c);
            (size, c)
        });
        self.triangles += triangles;
        self.bodies.insert(
            e,
            Body {
                handle,
                id: NEXT_BODY_ID.fetch_add(1, Ordering::Relaxed),
                colliders: handles,
                geometry: geometry.map(|g| (g, mesh)),
                terrain: terrain_collider,
                scale: t.scale,
                triangles,
                velocity: Vec3::ZERO,
            },
        );
        self.dirty = true;
        Ok(())
    }
}

/// Triangle meshes built so far, by path and scale bits: instances share one shape.
type MeshCache = HashMap<(String, [u32; 3]), Result<Shapes, String>>;

fn same_scale(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-6 * a.abs().max_element().max(1.0)
}

fn find_spawn(scene: &Scene) -> Option<Spawn> {
    let w = scene.world();
    scene.entities().find_map(|e| {
        let start = *w.get::<&PlayerStart>(e).ok()?;
        let t = w.get::<&Transform>(e).map_or(Transform::default(), |t| *t);
        t.translation.is_finite().then_some(Spawn {
            feet: t.translation,
            yaw: start.yaw,
            pitch: start.pitch,
            eye_height: start.eye_height,
        })
    })
}

/// The twist of `q` about +Y, in radians (a platform's turn under a standing player).
pub(crate) fn yaw_of(q: Quat) -> f32 {
    2.0 * q.y.atan2(q.w)
}
