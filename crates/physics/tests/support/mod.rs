//! Scenes built by hand and a player driven through them, for the physics tests.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use hecs::Entity;
use texel_physics::{MoveInput, PhysicsWorld, Player, PlayerConfig, StepReport};
use texel_scene::assets::{AssetLibrary, load_assets};
use texel_scene::{EntityRow, Geometry, Level, Name, PlayerStart, Scene, Transform};

/// One frame at 60 Hz.
pub const FRAME: f32 = 1.0 / 60.0;

/// A scene with a 40 × 40 ground plane at y = 0 and a player start at `start`.
pub fn ground_scene(start: Vec3) -> Scene {
    let mut scene = Scene::new();
    solid(
        &mut scene,
        "Ground",
        Vec3::ZERO,
        0.0,
        Geometry::Plane {
            size: Vec2::splat(40.0),
        },
    );
    player_start(&mut scene, start);
    scene
}

/// Adds a player start.
pub fn player_start(scene: &mut Scene, at: Vec3) -> Entity {
    scene.spawn(EntityRow {
        name: Some(Name("Player start".into())),
        transform: Some(Transform::from_translation(at)),
        player_start: Some(PlayerStart::default()),
        ..EntityRow::default()
    })
}

/// Adds an entity with `geometry` at `at`, turned `yaw` degrees about Y.
pub fn solid(scene: &mut Scene, name: &str, at: Vec3, yaw: f32, geometry: Geometry) -> Entity {
    scene.spawn(EntityRow {
        name: Some(Name(name.into())),
        transform: Some(Transform {
            translation: at,
            rotation: Vec3::new(0.0, yaw, 0.0),
            scale: Vec3::ONE,
        }),
        geometry: Some(geometry),
        ..EntityRow::default()
    })
}

/// A box of `size` whose bottom face is centred on `bottom`.
pub fn block(scene: &mut Scene, name: &str, bottom: Vec3, size: Vec3) -> Entity {
    solid(
        scene,
        name,
        bottom + Vec3::Y * (0.5 * size.y),
        0.0,
        Geometry::Box { size },
    )
}

/// The world of a scene without assets; panics on warnings, which hand-built scenes lack.
pub fn world(scene: &Scene) -> PhysicsWorld {
    let w = PhysicsWorld::from_scene(scene, &AssetLibrary::default()).expect("world");
    assert!(w.warnings().is_empty(), "{:?}", w.warnings());
    w
}

/// A player at the world's spawn with the default body.
pub fn player(world: &PhysicsWorld) -> Player {
    Player::new(PlayerConfig::default(), world.spawn().feet)
}

/// Everything the frames of a run reported, and the highest and lowest feet seen.
#[derive(Debug, Default)]
pub struct Run {
    pub landed: bool,
    pub jumped: bool,
    pub respawned: bool,
    pub turned: f32,
    pub max_y: f32,
    pub min_y: f32,
    pub last: StepReport,
}

/// Steps `player` for `seconds` in 60 Hz frames with `input`, calling `each_frame` first
/// (to move platforms) with the time since the run began.
pub fn run_with(
    player: &mut Player,
    world: &mut PhysicsWorld,
    input: MoveInput,
    seconds: f32,
    mut each_frame: impl FnMut(&mut PhysicsWorld, f32),
) -> Run {
    let mut run = Run {
        max_y: f32::NEG_INFINITY,
        min_y: f32::INFINITY,
        ..Run::default()
    };
    let frames = (seconds / FRAME).round() as u32;
    for i in 0..frames {
        each_frame(world, (i + 1) as f32 * FRAME);
        let r = player.step(world, &input, FRAME);
        run.landed |= r.landed;
        run.jumped |= r.jumped;
        run.respawned |= r.respawned;
        run.turned += r.turned;
        run.max_y = run.max_y.max(player.feet().y);
        run.min_y = run.min_y.min(player.feet().y);
        run.last = r;
    }
    run
}

/// [`run_with`] with nothing moving.
pub fn run(player: &mut Player, world: &mut PhysicsWorld, input: MoveInput, seconds: f32) -> Run {
    run_with(player, world, input, seconds, |_, _| {})
}

/// Walking along `dir` at walking speed.
pub fn walk(dir: Vec3) -> MoveInput {
    MoveInput {
        wish: PlayerConfig::default().wish(dir.normalize(), false),
        jump: false,
    }
}

/// Standing still.
pub fn idle() -> MoveInput {
    MoveInput::default()
}

/// A bundled level file.
pub fn level_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/levels")
        .join(format!("{name}.ron"))
}

/// A bundled level with its assets.
pub fn load_level(name: &str) -> anyhow::Result<(Scene, AssetLibrary)> {
    let path = level_path(name);
    let level = Level::load(&path)?;
    let assets = load_assets(&level, &path, None)?;
    Ok((Scene::from_level(&level), assets))
}
