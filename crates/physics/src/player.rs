//! A walking player: a capsule moved by rapier's `KinematicCharacterController` in fixed
//! 1/120 s substeps, so a run is the same for the same inputs whatever the frame rate.
//!
//! Each substep: ride the platform stood on (its pose change since the last substep, applied
//! to the feet), then gravity or a jump, then the controller's move (slides along walls,
//! climbs ramps up to `max_slope`, steps up `max_step` while grounded, snaps down onto ramps
//! and stairs), then a short cast down decides whether the player stands: only on ground no
//! steeper than `max_slope`, so a steeper ramp is slid down, never stood on. Falling below
//! the world's kill height respawns at the level's start.

use glam::{Quat, Vec3};
use hecs::Entity;
use rapier3d::control::{CharacterLength, KinematicCharacterController};
use rapier3d::parry::bounding_volume::BoundingVolume;
use rapier3d::parry::query::{DefaultQueryDispatcher, PersistentQueryDispatcher, ShapeCastOptions};
use rapier3d::parry::shape::{Capsule, Shape};
use rapier3d::prelude::{ColliderHandle, ContactManifold, QueryFilter, QueryPipeline, Ray};

use crate::PhysicsWorld;
use crate::convert::{pose, vec3, vector};
use crate::world::yaw_of;

/// The fixed substep, seconds.
pub const SUBSTEP: f32 = 1.0 / 120.0;
/// Longest frame one [`Player::step`] simulates (a longer `dt` is clamped: after a hitch the
/// player slows down rather than tunnelling or spending seconds catching up).
pub const MAX_FRAME: f32 = 0.25;
/// Fastest horizontal wish honoured, world units per second.
pub const MAX_WISH_SPEED: f32 = 50.0;
/// The gap the controller keeps between the capsule and the world.
const SKIN: f32 = 0.02;
/// How far below the feet ground still counts as stood on.
const GROUND_PROBE: f32 = 0.06;
/// How far past and above a rim contact the ray looking for the walkable face starts.
const RIM_INSET: f32 = 0.01;

/// The player's body and how it moves. Lengths in world units, speeds per second.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayerConfig {
    /// Capsule radius.
    pub radius: f32,
    /// Capsule height, feet to crown (at least twice the radius).
    pub height: f32,
    /// Eye above the feet (a level's [`PlayerStart::eye_height`](texel_scene::PlayerStart)).
    pub eye_height: f32,
    /// Walking speed.
    pub walk_speed: f32,
    /// Sprinting speed.
    pub sprint_speed: f32,
    /// Upward speed at the start of a jump.
    pub jump_speed: f32,
    /// Downward acceleration.
    pub gravity: f32,
    /// Steepest ground that can be walked up and stood on, degrees.
    pub max_slope: f32,
    /// Highest step climbed without a jump.
    pub max_step: f32,
    /// How far down the player is pulled onto ground while walking (down ramps and stairs
    /// without leaving the ground); 0 turns it off.
    pub snap_to_ground: f32,
    /// Fastest fall.
    pub max_fall_speed: f32,
}

impl Default for PlayerConfig {
    fn default() -> Self {
        PlayerConfig {
            radius: 0.3,
            height: 1.8,
            eye_height: 1.6,
            walk_speed: 4.0,
            sprint_speed: 7.0,
            jump_speed: 6.0,
            gravity: 18.0,
            max_slope: 45.0,
            max_step: 0.3,
            snap_to_ground: 0.3,
            max_fall_speed: 50.0,
        }
    }
}

impl PlayerConfig {
    /// The wish for walking (or sprinting) along `direction`: its horizontal part, at most
    /// unit length, times the speed.
    pub fn wish(&self, direction: Vec3, sprint: bool) -> Vec3 {
        let d = Vec3::new(direction.x, 0.0, direction.z).clamp_length_max(1.0);
        d * if sprint {
            self.sprint_speed
        } else {
            self.walk_speed
        }
    }

    /// A copy whose every field is usable: non-finite fields take the default, lengths are
    /// kept positive and the capsule at least a ball.
    fn sanitized(&self) -> PlayerConfig {
        let d = PlayerConfig::default();
        let pick = |v: f32, def: f32, lo: f32, hi: f32| {
            if v.is_finite() { v.clamp(lo, hi) } else { def }
        };
        let radius = pick(self.radius, d.radius, 0.01, 10.0);
        PlayerConfig {
            radius,
            height: pick(self.height, d.height, 2.0 * radius, 100.0),
            eye_height: pick(self.eye_height, d.eye_height, 0.0, 100.0),
            walk_speed: pick(self.walk_speed, d.walk_speed, 0.0, MAX_WISH_SPEED),
            sprint_speed: pick(self.sprint_speed, d.sprint_speed, 0.0, MAX_WISH_SPEED),
            jump_speed: pick(self.jump_speed, d.jump_speed, 0.0, 100.0),
            gravity: pick(self.gravity, d.gravity, 0.0, 1000.0),
            max_slope: pick(self.max_slope, d.max_slope, 0.0, 89.0),
            max_step: pick(self.max_step, d.max_step, 0.0, 10.0),
            snap_to_ground: pick(self.snap_to_ground, d.snap_to_ground, 0.0, 10.0),
            max_fall_speed: pick(self.max_fall_speed, d.max_fall_speed, 0.1, 1000.0),
        }
    }
}

/// What the player wants this frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MoveInput {
    /// Horizontal world direction times speed (see [`PlayerConfig::wish`]); the vertical
    /// part is ignored, the length capped at [`MAX_WISH_SPEED`].
    pub wish: Vec3,
    /// Jump when next standing (held: jumps again on landing).
    pub jump: bool,
}

/// What one [`Player::step`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepReport {
    /// Fixed substeps simulated (0 when the input was ignored or `dt` was short).
    pub substeps: u32,
    /// The input had a NaN or infinite `dt` or wish and was ignored: nothing changed.
    pub ignored: bool,
    /// Standing at the end.
    pub grounded: bool,
    /// Came down onto ground during the step.
    pub landed: bool,
    /// Left the ground by jumping.
    pub jumped: bool,
    /// Fell out of the world and was put back at the spawn.
    pub respawned: bool,
    /// Radians a platform turned the player about +Y (add to the camera's yaw).
    pub turned: f32,
}

/// What the player stands on.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ground {
    entity: Option<Entity>,
    /// The id of the entity's body when it was stood on (see [`PhysicsWorld::body_id`]).
    body: Option<u64>,
    /// Height of the walkable surface found.
    level: f32,
    /// The pose of a kinematic body stood on, when it was last carried.
    platform: Option<(Vec3, Quat)>,
}

/// A capsule walking through a [`PhysicsWorld`].
#[derive(Debug, Clone)]
pub struct Player {
    /// Body and movement settings (read at every step).
    pub config: PlayerConfig,
    feet: Vec3,
    prev_feet: Vec3,
    /// Vertical speed, and in the air the horizontal momentum kept from a platform.
    velocity: Vec3,
    ground: Option<Ground>,
    accumulator: f32,
    jump_latch: bool,
}

impl Player {
    /// A player standing (or about to fall) with its feet at `feet`; typically a world's
    /// [`PhysicsWorld::spawn`], with `config.eye_height` from it.
    pub fn new(config: PlayerConfig, feet: Vec3) -> Self {
        Player {
            config,
            feet,
            prev_feet: feet,
            velocity: Vec3::ZERO,
            ground: None,
            accumulator: 0.0,
            jump_latch: false,
        }
    }

    /// The feet at the last substep.
    pub fn feet(&self) -> Vec3 {
        self.feet
    }

    /// The camera position: the eye, interpolated between the last two substeps by the time
    /// left over, so motion looks smooth at any frame rate.
    pub fn eye(&self) -> Vec3 {
        let t = (self.accumulator / SUBSTEP).clamp(0.0, 1.0);
        self.prev_feet.lerp(self.feet, t) + Vec3::Y * self.config.sanitized().eye_height
    }

    /// Velocity: vertical speed, and the horizontal momentum kept in the air (walking is
    /// the wish itself and not stored).
    pub fn velocity(&self) -> Vec3 {
        self.velocity
    }

    /// Whether the player stands on walkable ground.
    pub fn is_grounded(&self) -> bool {
        self.ground.is_some()
    }

    /// The entity stood on.
    pub fn ground_entity(&self) -> Option<Entity> {
        self.ground.and_then(|g| g.entity)
    }

    /// Puts the feet at `feet`, at rest (after a fly-mode stretch, or an editor's "play from
    /// here"). Non-finite positions are ignored.
    pub fn teleport(&mut self, feet: Vec3) {
        if feet.is_finite() {
            self.feet = feet;
            self.prev_feet = feet;
            self.velocity = Vec3::ZERO;
            self.ground = None;
            self.accumulator = 0.0;
        }
    }

    /// Advances the player by `dt` seconds of `input`, in fixed substeps (the remainder
    /// waits for the next call). A NaN or infinite `dt` or wish is ignored with no change;
    /// `dt` is clamped to [`MAX_FRAME`]. Never panics.
    pub fn step(&mut self, world: &mut PhysicsWorld, input: &MoveInput, dt: f32) -> StepReport {
        if !dt.is_finite() || !input.wish.is_finite() {
            return StepReport {
                ignored: true,
                grounded: self.is_grounded(),
                ..StepReport::default()
            };
        }
        world.sync();
        let config = self.config.sanitized();
        let wish = Vec3::new(input.wish.x, 0.0, input.wish.z).clamp_length_max(MAX_WISH_SPEED);
        self.jump_latch |= input.jump;
        self.accumulator += dt.clamp(0.0, MAX_FRAME);
        let mut report = StepReport::default();
        // A hair of slack, so 1/60 s frames give two substeps each, never 1 then 3.
        while self.accumulator >= SUBSTEP * (1.0 - 1e-4) {
            self.accumulator = (self.accumulator - SUBSTEP).max(0.0);
            let jump = std::mem::take(&mut self.jump_latch);
            self.substep(world, &config, wish, jump, &mut report);
            report.substeps += 1;
        }
        report.grounded = self.is_grounded();
        report
    }

    fn substep(
        &mut self,
        world: &PhysicsWorld,
        config: &PlayerConfig,
        wish: Vec3,
        jump: bool,
        report: &mut StepReport,
    ) {
        let h = SUBSTEP;
        self.prev_feet = self.feet;
        let mover = Mover::new(world, config, QueryFilter::default().exclude_sensors());

        self.ride(world, config, report);

        // Gravity, or a jump from the ground.
        let was_grounded = self.ground.is_some();
        let ground_entity = self.ground.and_then(|g| g.entity);
        let jumped = was_grounded && jump;
        if jumped {
            let carried = ground_entity.map_or(Vec3::ZERO, |e| world.velocity(e));
            self.velocity = Vec3::new(carried.x, config.jump_speed + carried.y.max(0.0), carried.z);
            self.ground = None;
            report.jumped = true;
        } else if !was_grounded {
            self.velocity.y = (self.velocity.y - config.gravity * h).max(-config.max_fall_speed);
        }
        let desired = (wish + self.velocity) * h;
        let (mut feet, ceiling) = mover.slide(self.feet, desired);
        if ceiling && self.velocity.y > 0.0 {
            self.velocity.y = 0.0;
        }
        let walking = was_grounded && !jumped;
        if walking && config.max_step > 0.0 {
            let flat = |v: Vec3| Vec3::new(v.x, 0.0, v.z).length();
            let (want, got) = (flat(desired), flat(feet - self.feet));
            if got < 0.99 * want - 1e-6
                && let Some(up) = mover.step_up(self.feet, desired, got, config.max_step)
            {
                feet = up;
            }
        }
        if walking && config.snap_to_ground > 0.0 {
            feet = mover.snap_down(feet, config.snap_to_ground);
        }
        if feet.is_finite() {
            self.feet = feet;
        }

        // Standing?
        let ground = (self.velocity.y <= 0.0)
            .then(|| mover.ground(self.feet))
            .flatten();
        match ground {
            Some(g) => {
                if !was_grounded {
                    report.landed = true;
                }
                self.velocity = Vec3::ZERO;
                self.ground = Some(g);
            }
            None => {
                if let (Some(e), false) = (ground_entity, jumped) {
                    // Walked off a moving platform: keep its momentum.
                    let v = world.velocity(e);
                    self.velocity.x = v.x;
                    self.velocity.z = v.z;
                }
                self.ground = None;
            }
        }

        if !self.feet.is_finite() || self.feet.y < world.kill_height() {
            let spawn = world.spawn();
            self.teleport(spawn.feet);
            report.respawned = true;
        }
    }

    /// Carries the player by the move of the body it stands on since the last substep (its
    /// pose change applied to the feet, turning included), through the controller with that
    /// body left out, so a wall still stops it.
    fn ride(&mut self, world: &PhysicsWorld, config: &PlayerConfig, report: &mut StepReport) {
        let Some(Ground {
            entity: Some(entity),
            body: Some(id),
            platform: Some((old_t, old_q)),
            ..
        }) = self.ground
        else {
            return;
        };
        let (Some((t, q)), Some(body)) = (world.pose(entity), world.body_of(entity)) else {
            return;
        };
        if world.body_id(entity) != Some(id) {
            // Rebuilt since (an edit, a reload): not a move to follow.
            if let Some(g) = &mut self.ground {
                g.body = world.body_id(entity);
                g.platform = Some((t, q));
            }
            return;
        }
        if (t, q) == (old_t, old_q) {
            return;
        }
        let turn = q * old_q.inverse();
        let carried = t + turn * (self.feet - old_t);
        let filter = QueryFilter::default()
            .exclude_sensors()
            .exclude_rigid_body(body);
        let (feet, _) = Mover::new(world, config, filter).slide(self.feet, carried - self.feet);
        if feet.is_finite() {
            self.feet = feet;
        }
        let yaw = yaw_of(turn);
        if yaw.is_finite() {
            report.turned += yaw;
        }
        if let Some(g) = &mut self.ground {
            g.level += carried.y - old_t.y;
            g.platform = Some((t, q));
        }
    }
}

/// The capsule and the controller for one substep's queries.
struct Mover<'a> {
    world: &'a PhysicsWorld,
    queries: QueryPipeline<'a>,
    capsule: Capsule,
    /// From the feet to the capsule's centre.
    centre: Vec3,
    controller: KinematicCharacterController,
    /// The cosine of the steepest walkable slope.
    walkable: f32,
}

impl<'a> Mover<'a> {
    fn new(world: &'a PhysicsWorld, config: &PlayerConfig, filter: QueryFilter<'a>) -> Self {
        let slope = config.max_slope.to_radians();
        Mover {
            world,
            queries: world.rapier.query_pipeline_with_filter(filter),
            capsule: Capsule::new_y(0.5 * config.height - config.radius, config.radius),
            centre: Vec3::Y * (0.5 * config.height),
            // Stepping and snapping are done here (see `step_up`, `snap_down`): rapier's
            // autostep lifts a capsule only a little per move at 1/120 s substeps, and its
            // snap skips any move nudged upward off the floor, so the feet crept up.
            controller: KinematicCharacterController {
                offset: CharacterLength::Absolute(SKIN),
                slide: true,
                autostep: None,
                max_slope_climb_angle: slope,
                min_slope_slide_angle: slope,
                snap_to_ground: None,
                ..KinematicCharacterController::default()
            },
            walkable: slope.cos() - 1e-4,
        }
    }

    fn at(&self, feet: Vec3) -> rapier3d::math::Pose {
        pose(feet + self.centre, Quat::IDENTITY)
    }

    /// The controller's move from `feet` toward `feet + by`: where the feet end, and whether
    /// a ceiling was hit.
    fn slide(&self, feet: Vec3, by: Vec3) -> (Vec3, bool) {
        let mut ceiling = false;
        let moved = self.controller.move_shape(
            SUBSTEP,
            &self.queries,
            &self.capsule,
            &self.at(feet),
            vector(by),
            |c| ceiling |= c.hit.normal1.y < -0.5,
        );
        let step = vec3(moved.translation);
        (if step.is_finite() { feet + step } else { feet }, ceiling)
    }

    /// How far the capsule at `feet` can move along `dir` (unit) within `max`.
    fn free(&self, feet: Vec3, dir: Vec3, max: f32) -> Option<f32> {
        self.queries
            .cast_shape(
                &self.at(feet),
                vector(dir),
                &self.capsule,
                ShapeCastOptions {
                    target_distance: SKIN,
                    stop_at_penetration: false,
                    max_time_of_impact: max,
                    compute_impact_geometry_on_penetration: true,
                },
            )
            .map(|(_, hit)| hit.time_of_impact)
    }

    /// Climbing a step: up by at most `max_step`, the horizontal part of `desired`, back
    /// down onto walkable ground. Taken only if it gets further than the plain move did
    /// (`got`), so a wall or a too-steep ramp still stops the player.
    fn step_up(&self, feet: Vec3, desired: Vec3, got: f32, max_step: f32) -> Option<Vec3> {
        let level = self.ground(feet)?.level;
        let rise = self.free(feet, Vec3::Y, max_step).unwrap_or(max_step);
        if rise < 1e-3 {
            return None;
        }
        let raised = feet + Vec3::Y * rise;
        let (ahead, _) = self.slide(raised, Vec3::new(desired.x, 0.0, desired.z));
        let gained = Vec3::new(ahead.x - feet.x, 0.0, ahead.z - feet.z).length();
        if gained <= got + 1e-5 {
            return None;
        }
        let drop = self.free(ahead, -Vec3::Y, rise + GROUND_PROBE)?;
        let landed = ahead - Vec3::Y * drop;
        // Onto ground at most a step above the ground left, however the round bottom met it.
        self.ground(landed)
            .filter(|g| g.level <= level + max_step + 1e-3)
            .map(|_| landed)
    }

    /// Pulls the feet down onto walkable ground at most `distance` below (down ramps and
    /// stairs, and against the controller's tiny upward nudges off the floor).
    fn snap_down(&self, feet: Vec3, distance: f32) -> Vec3 {
        match self.free(feet, -Vec3::Y, distance) {
            Some(drop) if drop > 0.0 => {
                let down = feet - Vec3::Y * drop;
                if self.ground(down).is_some() {
                    down
                } else {
                    feet
                }
            }
            _ => feet,
        }
    }

    /// The walkable ground just under `feet`, if any: of the contacts within
    /// [`GROUND_PROBE`] of the capsule, the one whose normal is nearest to up, if that is no
    /// steeper than the slope limit; failing that, a contact on the lower half-sphere at the
    /// edge of walkable ground (a step's rim, which the round bottom meets at a slant while
    /// climbing it). rapier's own "grounded" counts any contact facing up at all.
    fn ground(&self, feet: Vec3) -> Option<Ground> {
        let at = self.at(feet);
        let aabb = self.capsule.compute_aabb(&at).loosened(GROUND_PROBE);
        let mut manifolds: Vec<ContactManifold> = Vec::new();
        let mut best: Option<(f32, ColliderHandle, f32)> = None;
        for (handle, collider) in self.queries.intersect_aabb_conservative(aabb) {
            manifolds.clear();
            let pos12 = at.inv_mul(collider.position());
            let _ = DefaultQueryDispatcher.contact_manifolds(
                &pos12,
                &self.capsule,
                collider.shape(),
                GROUND_PROBE,
                &mut manifolds,
                &mut None,
            );
            for m in &manifolds {
                // The normal on the obstacle, toward the capsule.
                let n = -vec3(at.rotation * m.local_n1);
                for c in m.points.iter().filter(|c| c.dist <= GROUND_PROBE) {
                    let point = vec3(at * c.local_p1) - n * c.dist;
                    let (score, level) = if n.y >= self.walkable {
                        (n.y, point.y)
                    } else {
                        match self.rim(feet, point) {
                            Some(level) => (self.walkable, level),
                            None => continue,
                        }
                    };
                    if score.is_finite() && best.is_none_or(|(b, ..)| score > b) {
                        best = Some((score, handle, level));
                    }
                }
            }
        }
        let (_, collider, level) = best?;
        let entity = self.world.entity_of(collider);
        let platform = entity.and_then(|e| self.world.pose(e));
        Some(Ground {
            entity,
            body: entity.and_then(|e| self.world.body_id(e)),
            level,
            platform,
        })
    }

    /// Whether `point`, where the capsule at `feet` touches something, is on its lower
    /// half-sphere and at the rim of walkable ground: just past it (away from the capsule's
    /// axis) and a hair above, a short ray down from outside every solid meets a walkable
    /// face. The face's height, if so.
    fn rim(&self, feet: Vec3, point: Vec3) -> Option<f32> {
        let radius = self.capsule.radius;
        if point.y > feet.y + radius {
            return None;
        }
        let out = Vec3::new(point.x - feet.x, 0.0, point.z - feet.z).normalize_or_zero();
        let origin = point + out * RIM_INSET + Vec3::Y * RIM_INSET;
        let ray = Ray::new(vector(origin), vector(-Vec3::Y));
        let (_, hit) = self
            .queries
            .cast_ray_and_get_normal(&ray, 2.0 * RIM_INSET, true)?;
        // A hit at 0 started inside a solid (a slope rising past the inset): no rim.
        (hit.time_of_impact > 1e-5 && hit.normal.y >= self.walkable)
            .then_some(origin.y - hit.time_of_impact)
    }
}
