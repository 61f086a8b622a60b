//! One player step (1/60 s: two 1/120 s substeps) walking in circles through the colliders
//! of `stone_circle` and `terrain_hills` (alone, and with an entity moved as a kinematic body
//! every frame), and building those colliders.
//!
//! `cargo bench -p texel_physics --bench player_step` measures; `cargo test --benches` runs
//! each benchmark once as a smoke test.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use texel_physics::{MoveInput, PhysicsWorld, Player, PlayerConfig};
use texel_scene::assets::{AssetLibrary, load_assets};
use texel_scene::{Geometry, Level, Scene, Transform};

fn load(name: &str) -> (Scene, AssetLibrary) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/levels")
        .join(format!("{name}.ron"));
    let level = Level::load(&path).expect("level");
    let assets = load_assets(&level, &path, None).expect("assets");
    (Scene::from_level(&level), assets)
}

fn bench(c: &mut Criterion) {
    for name in ["stone_circle", "terrain_hills"] {
        let (scene, assets) = load(name);
        c.bench_function(&format!("build_colliders/{name}"), |b| {
            b.iter(|| PhysicsWorld::from_scene(black_box(&scene), &assets).expect("world"))
        });
        let mut world = PhysicsWorld::from_scene(&scene, &assets).expect("world");
        let config = PlayerConfig::default();
        let mut player = Player::new(config, world.spawn().feet);
        let mut frame = 0u32;
        c.bench_function(&format!("player_step/{name}"), |b| {
            b.iter(|| {
                // Sprinting round a wide circle, jumping now and then.
                frame = frame.wrapping_add(1);
                let a = frame as f32 * 0.01;
                let input = MoveInput {
                    wish: config.wish(Vec3::new(a.cos(), 0.0, a.sin()), true),
                    jump: frame.is_multiple_of(90),
                };
                black_box(player.step(&mut world, &input, 1.0 / 60.0))
            })
        });
        // The same with one stone moved as a kinematic body every frame: what rapier's
        // broad phase update costs on top.
        let moving = scene
            .entities()
            .filter(|e| {
                scene
                    .world()
                    .get::<&Geometry>(*e)
                    .is_ok_and(|g| matches!(*g, Geometry::Box { .. }))
            })
            .last()
            .expect("a box");
        let base = *scene.world().get::<&Transform>(moving).expect("transform");
        c.bench_function(&format!("player_step_moving_entity/{name}"), |b| {
            b.iter(|| {
                frame = frame.wrapping_add(1);
                let a = frame as f32 * 0.01;
                let pose = Transform {
                    translation: base.translation + Vec3::new(a.sin(), 0.0, 0.0),
                    ..base
                };
                world
                    .set_kinematic_pose(moving, &pose, 1.0 / 60.0)
                    .expect("pose");
                let input = MoveInput {
                    wish: config.wish(Vec3::new(a.cos(), 0.0, a.sin()), true),
                    jump: false,
                };
                black_box(player.step(&mut world, &input, 1.0 / 60.0))
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
