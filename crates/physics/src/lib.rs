//! `texel_physics` lets a player walk through a Texel level: colliders built from the level's
//! geometry (primitives as rapier shapes, glTF meshes as triangle meshes, terrains as
//! heightfields), kinematic bodies for things an animator moves, and a capsule [`Player`]
//! driven by rapier's `KinematicCharacterController` at a fixed timestep: it walks, climbs
//! steps and ramps within its slope limit, slides along walls, falls, jumps, lands, rides
//! moving platforms, and respawns at the level's start when it falls out of the world.
//!
//! It sits between the scene and its callers (`texel_scene` → `texel_physics` → runtime,
//! editor) and knows nothing of the GPU. rapier keeps its own copy of glam (its math types);
//! the conversions live in one private module, so callers see only the workspace's glam.
//!
//! A fly (free camera) mode is simply not stepping the player: the world needs no step of
//! its own, and the player resumes where it was (or call [`Player::teleport`]).

mod colliders;
mod convert;
mod player;
mod world;

pub use player::{MAX_FRAME, MAX_WISH_SPEED, MoveInput, Player, PlayerConfig, SUBSTEP, StepReport};
pub use world::{KILL_MARGIN, PhysicsWorld, Spawn};

use hecs::Entity;

/// Most triangles the level's triangle-mesh colliders may hold together (terrains, stored
/// as heightfields, are not counted): past it the BVHs take seconds and gigabytes to build.
pub const MAX_TRIANGLES: usize = 4_000_000;

/// Why the physics world could not be built or changed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    /// The level's meshes hold more triangles than [`MAX_TRIANGLES`].
    #[error(
        "the level's collision meshes hold {triangles} triangles, more than the {limit} allowed"
    )]
    TooManyTriangles {
        /// Triangles counted.
        triangles: usize,
        /// [`MAX_TRIANGLES`].
        limit: usize,
    },
    /// The entity has no collider in the world.
    #[error("entity {0:?} has no collider")]
    UnknownEntity(Entity),
    /// The entity is not a terrain.
    #[error("entity {0:?} is not a terrain")]
    NotATerrain(Entity),
    /// A heightfield that cannot be a collider (fewer than 2 × 2 samples, a sample count that
    /// does not match its size, a NaN or infinite height).
    #[error("entity {entity:?}: bad heightfield: {message}")]
    BadHeightfield {
        /// The terrain.
        entity: Entity,
        /// What is wrong.
        message: String,
    },
    /// A pose with a NaN or infinite number, or a scale that is not positive.
    #[error("entity {0:?}: the pose is not finite or its scale is not positive")]
    BadPose(Entity),
}

/// Geometry that gave no collider (or only part of one), and why. The world is built
/// without it; nothing panics.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsWarning {
    /// The entity.
    pub entity: Entity,
    /// Its name, or `unnamed`.
    pub name: String,
    /// What was skipped and why.
    pub message: String,
}

impl std::fmt::Display for PhysicsWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "entity {} ({:?}): {}",
            self.name, self.entity, self.message
        )
    }
}
