//! Walking through a level while playing: the level's colliders ([`texel_physics`]) and the
//! player whose eye the play camera follows, stepped once a frame by `texel-run play` and the
//! editor's Play alike.
//!
//! A frame: the moving objects' colliders go where the renderer draws them this frame (the
//! animators' poses at the frame's animation time, [`crate::session::Session::animation_time`]
//! read before the frame is drawn), then the player steps with the held keys as its wish and
//! Space/E as a jump, and the camera takes its eye; a platform's turn turns the view with it.
//! Flying steps no player: the camera moves itself through everything, and landing puts the
//! player's feet under it.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use hecs::Entity;
use texel_physics::{
    MoveInput, PhysicsError, PhysicsWarning, PhysicsWorld, Player, PlayerConfig, StepReport,
};
use texel_scene::assets::AssetLibrary;
use texel_scene::sculpt::Placement;
use texel_scene::terrain::Terrain;
use texel_scene::{Scene, Transform};

use crate::first_person::{InputState, WalkCamera};

/// A level's physics world and the player walking through it.
#[derive(Debug)]
pub struct Walker {
    world: PhysicsWorld,
    player: Player,
}

impl Walker {
    /// The colliders of `scene` (meshes and heights from `assets`) and a player at the level's
    /// start, its eye as high above the feet as the start says. Geometry that gives no
    /// collider is left out ([`Walker::warnings`]); only a level with too many collision
    /// triangles fails.
    pub fn new(scene: &Scene, assets: &AssetLibrary) -> Result<Self, PhysicsError> {
        let world = PhysicsWorld::from_scene(scene, assets)?;
        let spawn = world.spawn();
        let config = PlayerConfig {
            eye_height: spawn.eye_height,
            ..PlayerConfig::default()
        };
        Ok(Walker {
            player: Player::new(config, spawn.feet),
            world,
        })
    }

    /// Geometry that gave no collider, or only part of one, and why.
    pub fn warnings(&self) -> &[PhysicsWarning] {
        self.world.warnings()
    }

    /// The physics world.
    pub fn world(&self) -> &PhysicsWorld {
        &self.world
    }

    /// The player.
    pub fn player(&self) -> &Player {
        &self.player
    }

    /// One frame of play, `dt` seconds long, whose moving objects stand at animation time
    /// `t`: `mouse_delta` turns `camera`; walking, the player steps with `input` and the
    /// camera moves to its eye (the step's report returned); flying, the camera moves itself
    /// and `None` is returned.
    pub fn frame(
        &mut self,
        scene: &Scene,
        t: f64,
        camera: &mut WalkCamera,
        input: &InputState,
        mouse_delta: Vec2,
        dt: f32,
    ) -> Option<StepReport> {
        // Moved while flying too, so landing finds them where they are drawn. A bad pose
        // (the level validates its animators, so none is expected) leaves its object where
        // it was, and the others still move.
        let poses = scene.animated_poses(t);
        let _ = self.world.set_kinematic_poses(&poses, dt);
        camera.update(input, mouse_delta, dt);
        if camera.fly {
            return None;
        }
        let (direction, sprint) = camera.walk_direction(input);
        let wish = MoveInput {
            wish: self.player.config.wish(direction, sprint),
            jump: input.up,
        };
        let report = self.player.step(&mut self.world, &wish, dt);
        if report.respawned {
            let spawn = self.world.spawn();
            camera.face(spawn.yaw, spawn.pitch);
        }
        camera.turn(report.turned.to_degrees());
        camera.set_eye(self.player.eye());
        Some(report)
    }

    /// Switches `camera` between walking and flying; landing puts the player's feet under the
    /// camera (it falls from there).
    pub fn toggle_fly(&mut self, camera: &mut WalkCamera) {
        camera.toggle_fly();
        if !camera.fly {
            self.player.teleport(camera.position);
        }
    }

    /// Takes the heights `assets` now holds for the terrain `entity` (after a sculpt dab), for
    /// it and every terrain sharing its heightmap, so the player walks on the new ground. A
    /// player standing on ground that rose above its feet is lifted onto it (the controller
    /// does not climb out of ground that swallowed it; it would fall through).
    pub fn update_heights(
        &mut self,
        scene: &Scene,
        assets: &AssetLibrary,
        entity: Entity,
    ) -> Result<(), PhysicsError> {
        let world = scene.world();
        let field_of = |e: Entity| {
            let terrain = world.get::<&Terrain>(e).ok()?;
            assets.heightfield(&terrain).cloned()
        };
        let field = field_of(entity).ok_or(PhysicsError::NotATerrain(entity))?;
        let stood_on = self.player.ground_entity();
        let feet = self.player.feet();
        let mut lift = None::<f32>;
        for e in scene.entities() {
            if !field_of(e).is_some_and(|f| Arc::ptr_eq(&f, &field)) {
                continue;
            }
            self.world.update_heightfield(e, &field)?;
            if stood_on == Some(e)
                && let Ok(terrain) = world.get::<&Terrain>(e)
            {
                let at = world
                    .get::<&Transform>(e)
                    .map_or(Vec3::ZERO, |t| t.translation);
                let ground = Placement::new(&terrain, at, &field).surface(&field, feet).y;
                lift = Some(lift.map_or(ground, |l| l.max(ground)));
            }
        }
        if let Some(ground) = lift.filter(|g| *g > feet.y) {
            self.player.teleport(Vec3::new(feet.x, ground, feet.z));
        }
        Ok(())
    }

    /// Builds every collider again from the level as it is now (after an edit); the player
    /// stays where it is.
    pub fn rebuild(&mut self, scene: &Scene, assets: &AssetLibrary) -> Result<(), PhysicsError> {
        self.world.rebuild(scene, assets)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::load::{LoadedLevel, load_level};
    use crate::play_sculpt::dab_level;

    const DT: f32 = 1.0 / 60.0;

    fn frames(walker: &mut Walker, camera: &mut WalkCamera, level: &LoadedLevel, n: u32) {
        for _ in 0..n {
            let idle = InputState::default();
            walker.frame(&level.scene, 0.0, camera, &idle, Vec2::ZERO, DT);
        }
    }

    #[test]
    fn the_player_stands_on_ground_raised_under_its_feet() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/terrain_hills.ron");
        let mut level = load_level(&path).expect("level");
        let mut walker = Walker::new(&level.scene, &level.assets).expect("walker");
        let mut camera = WalkCamera::from_scene(&level.scene);
        // Onto the hill in the middle of the island (its ground at 5.0), by flying there.
        walker.toggle_fly(&mut camera);
        camera.position = Vec3::new(0.0, 8.0, 0.0);
        walker.toggle_fly(&mut camera);
        frames(&mut walker, &mut camera, &level, 60);
        let before = walker.player().feet();
        assert!(
            walker.player().is_grounded() && (before.y - 5.0).abs() < 0.1,
            "{before}"
        );

        // Look straight down and raise the ground under the feet: three dabs.
        camera.face(camera.yaw_deg, -90.0);
        let done = dab_level(&mut level, &camera.camera(1.0), true, 3).expect("dabbed");
        walker
            .update_heights(&level.scene, &level.assets, done.entity)
            .expect("heights");
        let over = before + Vec3::Y * 5.0;
        let (drop, _) = (walker.world.cast_ray(over, -Vec3::Y, 10.0)).expect("the ground");
        let ground = over.y - drop;
        assert!(ground > before.y + 0.5, "the ground rose to {ground}");
        frames(&mut walker, &mut camera, &level, 60);
        let feet = walker.player().feet();
        assert!(walker.player().is_grounded(), "standing at {feet}");
        assert!(
            (feet.y - ground).abs() < 0.1,
            "feet at {feet} on ground at {ground}"
        );
        let aside = Vec2::new(feet.x - before.x, feet.z - before.z).length();
        assert!(aside < 0.1, "pushed {aside} aside, to {feet}");
        assert!((camera.eye() - feet - Vec3::Y * 1.6).length() < 1e-3);
    }
}
