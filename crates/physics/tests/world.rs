//! Colliders from scenes: shapes under rotation and non-uniform scale, degenerate geometry,
//! edits, heightfields, and the bundled levels.

use crate::support;

use std::sync::Arc;

use glam::{Vec2, Vec3};
use support::*;
use texel_physics::{PhysicsError, PhysicsWorld, Player, PlayerConfig};
use texel_scene::assets::AssetLibrary;
use texel_scene::primitives::primitive_mesh;
use texel_scene::terrain::{HeightSource, Heightfield, Terrain};
use texel_scene::{EntityRow, Geometry, Name, Scene, Transform, TriMesh};

/// The world box of a render mesh under `t`.
fn mesh_bounds(mesh: &TriMesh, t: &Transform) -> (Vec3, Vec3) {
    let m = t.matrix();
    mesh.positions
        .iter()
        .map(|p| m.transform_point3(*p))
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        })
}

#[test]
fn colliders_fit_their_primitives_under_rotation_and_non_uniform_scale() {
    let t = Transform {
        translation: Vec3::new(1.0, 2.0, -3.0),
        rotation: Vec3::new(20.0, 35.0, -10.0),
        scale: Vec3::new(2.0, 0.5, 1.5),
    };
    for geometry in [
        Geometry::Box {
            size: Vec3::new(1.0, 2.0, 3.0),
        },
        Geometry::Wedge {
            size: Vec3::new(2.0, 1.0, 3.0),
        },
        Geometry::Cylinder {
            radius: 0.5,
            height: 2.0,
            segments: 16,
        },
        Geometry::Sphere {
            radius: 1.0,
            segments: 16,
        },
    ] {
        let mut scene = Scene::new();
        let e = scene.spawn(EntityRow {
            transform: Some(t),
            geometry: Some(geometry.clone()),
            ..EntityRow::default()
        });
        let w = world(&scene);
        let c = w.colliders_of(e);
        assert_eq!(c.len(), 1, "{geometry:?}");
        assert_eq!(w.entity_of(c[0]), Some(e));
        let (lo, hi) = w.collider_bounds(c[0]).unwrap();
        let (mlo, mhi) = mesh_bounds(&primitive_mesh(&geometry).unwrap(), &t);
        let err = (lo - mlo).abs().max((hi - mhi).abs()).max_element();
        assert!(
            err < 1e-3,
            "{geometry:?}: {lo}..{hi} vs the mesh's {mlo}..{mhi}"
        );
    }
}

#[test]
fn degenerate_geometry_is_skipped_with_a_warning() {
    let mut scene = ground_scene(Vec3::ZERO);
    let row = |name: &str, t: Transform, g: Geometry| EntityRow {
        name: Some(Name(name.into())),
        transform: Some(t),
        geometry: Some(g),
        ..EntityRow::default()
    };
    let unit = Geometry::Box { size: Vec3::ONE };
    let nan = scene.spawn(row(
        "NaN",
        Transform::from_translation(Vec3::new(f32::NAN, 0.0, 0.0)),
        unit.clone(),
    ));
    let flat = scene.spawn(row(
        "Flat",
        Transform {
            scale: Vec3::new(1.0, 0.0, 1.0),
            ..Transform::default()
        },
        unit.clone(),
    ));
    let missing = scene.spawn(row(
        "Missing mesh",
        Transform::default(),
        Geometry::Mesh {
            path: "nowhere.glb".into(),
        },
    ));
    let terrain = scene.spawn(EntityRow {
        name: Some(Name("Unloaded terrain".into())),
        transform: Some(Transform::default()),
        terrain: Some(terrain(Vec2::splat(8.0))),
        ..EntityRow::default()
    });
    let w = PhysicsWorld::from_scene(&scene, &AssetLibrary::default()).unwrap();
    let warned: Vec<_> = w.warnings().iter().map(|w| w.entity).collect();
    assert_eq!(warned, [nan, flat, missing, terrain]);
    for e in warned {
        assert!(w.colliders_of(e).is_empty());
    }
    let text = w.warnings()[2].to_string();
    assert!(
        text.contains("Missing mesh") && text.contains("not loaded"),
        "{text}"
    );
    // The rest of the level still has its ground.
    assert_eq!(w.collider_count(), 1);
}

fn terrain(size: Vec2) -> Terrain {
    Terrain {
        size,
        heightmap: HeightSource::Noise {
            seed: 1,
            resolution: 9,
            frequency: 0.1,
            octaves: 1,
            island: 0.0,
        },
        max_height: 4.0,
        gradient: vec![texel_scene::terrain::GradientStop {
            at: 0.0,
            colour: Vec3::ONE,
        }],
        displacement: None,
        paint: None,
        pixel_density: 4.0,
        band_distance: 8.0,
        band_transition: 0.0,
        casts_shadows: true,
        outlined: true,
    }
}

#[test]
fn edits_update_one_entity_and_sculpting_updates_the_heightfield() {
    let mut scene = ground_scene(Vec3::new(0.0, 0.0, 5.0));
    let pillar = block(&mut scene, "Pillar", Vec3::ZERO, Vec3::new(1.0, 2.0, 1.0));
    let t = terrain(Vec2::splat(8.0));
    let ground_terrain = scene.spawn(EntityRow {
        name: Some(Name("Terrain".into())),
        transform: Some(Transform::from_translation(Vec3::new(20.0, 1.0, 0.0))),
        terrain: Some(t.clone()),
        ..EntityRow::default()
    });
    let mut assets = AssetLibrary::default();
    assets.insert_heightfield(&t, Arc::new(Heightfield::flat(9, 9, 0.5)));
    let mut w = PhysicsWorld::from_scene(&scene, &assets).unwrap();
    assert!(w.warnings().is_empty());
    let down = -Vec3::Y;
    let hit = |w: &mut PhysicsWorld, x: f32, z: f32| {
        w.cast_ray(Vec3::new(x, 50.0, z), down, 100.0)
            .map(|(d, c)| (50.0 - d, w.entity_of(c)))
    };
    assert_eq!(hit(&mut w, 0.0, 0.0), Some((2.0, Some(pillar))));
    // Heights above the terrain's translation, centred on it.
    let (y, e) = hit(&mut w, 20.0 + 3.9, -3.9).unwrap();
    assert!((y - 1.5).abs() < 1e-4 && e == Some(ground_terrain), "{y}");

    // Move the pillar in the scene: only it is rebuilt.
    let colliders = w.collider_count();
    scene
        .world_mut()
        .get::<&mut Transform>(pillar)
        .unwrap()
        .translation = Vec3::new(3.0, 1.0, 0.0);
    w.update_entity(&scene, &assets, pillar).unwrap();
    assert_eq!(w.collider_count(), colliders);
    assert_eq!(hit(&mut w, 3.0, 0.0).unwrap().1, Some(pillar));
    assert_ne!(hit(&mut w, 0.0, 0.0).unwrap().1, Some(pillar));
    scene.despawn(pillar);
    w.update_entity(&scene, &assets, pillar).unwrap();
    assert_eq!(w.collider_count(), colliders - 1);

    // Sculpt: a raised field replaces the terrain's shape.
    let mut raised = Heightfield::flat(9, 9, 0.5);
    raised.heights[4 * 9 + 4] = 3.0;
    w.update_heightfield(ground_terrain, &raised).unwrap();
    let (y, _) = hit(&mut w, 20.0, 0.0).unwrap();
    assert!((y - 4.0).abs() < 1e-4, "{y}");
    let bad = Heightfield::flat(1, 9, 0.0);
    assert!(matches!(
        w.update_heightfield(ground_terrain, &bad),
        Err(PhysicsError::BadHeightfield { .. })
    ));
    let ground = scene.entities().next().unwrap();
    assert_eq!(
        w.update_heightfield(ground, &raised),
        Err(PhysicsError::NotATerrain(ground))
    );
}

#[test]
fn a_kinematic_body_rescales_and_moves_its_colliders() {
    let mut scene = ground_scene(Vec3::ZERO);
    let lift = block(&mut scene, "Lift", Vec3::ZERO, Vec3::ONE);
    let mut w = world(&scene);
    let t = Transform {
        translation: Vec3::new(0.0, 3.0, 0.0),
        rotation: Vec3::ZERO,
        scale: Vec3::new(2.0, 1.0, 1.0),
    };
    w.set_kinematic_pose(lift, &t, 0.5).unwrap();
    let (d, c) = w
        .cast_ray(Vec3::new(0.9, 10.0, 0.0), -Vec3::Y, 20.0)
        .unwrap();
    assert_eq!(w.entity_of(c), Some(lift));
    assert!((10.0 - d - 3.5).abs() < 1e-4);
    assert!((w.velocity(lift) - Vec3::new(0.0, 5.0, 0.0)).length() < 1e-4);
    assert!(w.is_kinematic(lift));
}

#[test]
fn every_bundled_level_builds_its_colliders_without_warnings() -> anyhow::Result<()> {
    for name in [
        "stone_circle",
        "terrain_hills",
        "colonnade",
        "sandbox",
        "textured",
    ] {
        let (scene, assets) = load_level(name)?;
        let w = PhysicsWorld::from_scene(&scene, &assets)?;
        assert!(w.warnings().is_empty(), "{name}: {:?}", w.warnings());
        let world = scene.world();
        for e in scene.entities() {
            let solid = world.get::<&Geometry>(e).is_ok() || world.get::<&Terrain>(e).is_ok();
            assert_eq!(!w.colliders_of(e).is_empty(), solid, "{name}: {e:?}");
        }
    }
    Ok(())
}

#[test]
fn a_player_walking_at_a_stone_of_stone_circle_is_stopped_by_it() -> anyhow::Result<()> {
    let (scene, assets) = load_level("stone_circle")?;
    let mut w = PhysicsWorld::from_scene(&scene, &assets)?;
    let spawn = w.spawn();
    assert_eq!(spawn.feet, Vec3::new(0.0, 0.0, 13.0));
    let mut p = Player::new(PlayerConfig::default(), spawn.feet);
    run(&mut p, &mut w, idle(), 0.5);
    assert!(p.is_grounded() && p.feet().y < 0.03);
    // "Standing stone 1": a 0.948 × 2.504 × 0.469 box at (4.596, _, 3.857), turned 43.451°
    // about Y; walk square at its broad face from 3 units away.
    let stone = Vec3::new(4.596, 0.0, 3.857);
    let yaw = 43.451f32.to_radians();
    let face = Vec3::new(yaw.sin(), 0.0, yaw.cos());
    p.teleport(stone + face * 3.0);
    run(&mut p, &mut w, walk(-face), 2.0);
    let off = p.feet() - stone;
    let (along, across) = (off.dot(face), (off - face * off.dot(face)).length());
    // Half its thickness, the radius, the skin; a little tilt.
    assert!(
        (0.5..0.62).contains(&along) && across < 0.1,
        "feet at {} ({along} in front of the stone, {across} aside)",
        p.feet()
    );
    Ok(())
}

/// The height of the terrain's surface at world (x, z), from its heightfield: the triangle
/// of the cell split from (x + 1, z) to (x, z + 1), like the terrain's mesh.
fn surface(field: &Heightfield, size: Vec2, origin: Vec3, x: f32, z: f32) -> f32 {
    let gx = (x - origin.x + 0.5 * size.x) / size.x * (field.width - 1) as f32;
    let gz = (z - origin.z + 0.5 * size.y) / size.y * (field.depth - 1) as f32;
    let (i, j) = (gx.floor(), gz.floor());
    let (fx, fz) = (gx - i, gz - j);
    let h = |a: f32, b: f32| field.at(a as i64, b as i64);
    let (h00, h10, h01, h11) = (h(i, j), h(i + 1.0, j), h(i, j + 1.0), h(i + 1.0, j + 1.0));
    origin.y
        + if fx + fz <= 1.0 {
            h00 + (h10 - h00) * fx + (h01 - h00) * fz
        } else {
            h11 + (h01 - h11) * (1.0 - fx) + (h10 - h11) * (1.0 - fz)
        }
}

#[test]
fn a_player_dropped_on_terrain_hills_lands_on_the_heightfield() -> anyhow::Result<()> {
    let (scene, assets) = load_level("terrain_hills")?;
    let mut w = PhysicsWorld::from_scene(&scene, &assets)?;
    let (island, t, origin) = scene
        .entities()
        .find_map(|e| {
            let world = scene.world();
            let t = world.get::<&Terrain>(e).ok()?;
            let origin = world.get::<&Transform>(e).ok()?.translation;
            Some((e, (*t).clone(), origin))
        })
        .unwrap();
    let field = assets.heightfield(&t).unwrap().clone();
    let mut tried = 0;
    // Points on a coarse grid over the island, on ground above the sea and gentle enough
    // that a capsule's round bottom rests close to the point under its centre.
    for k in 0..49 {
        let (x, z) = (-36.0 + (k % 7) as f32 * 12.0, -36.0 + (k / 7) as f32 * 12.0);
        let y = surface(&field, t.size, origin, x, z);
        let slope = [(0.5, 0.0), (-0.5, 0.0), (0.0, 0.5), (0.0, -0.5)]
            .iter()
            .map(|(dx, dz)| (surface(&field, t.size, origin, x + dx, z + dz) - y).abs() / 0.5)
            .fold(0.0f32, f32::max);
        // Only where the terrain is what is under the player (not the sea, not a stone).
        let top = w.cast_ray(Vec3::new(x, 50.0, z), -Vec3::Y, 100.0);
        if y < 1.0 || slope > 0.35 || top.and_then(|(_, c)| w.entity_of(c)) != Some(island) {
            continue;
        }
        let mut p = Player::new(PlayerConfig::default(), Vec3::new(x, y + 3.0, z));
        let r = run(&mut p, &mut w, idle(), 1.5);
        assert!(r.landed && p.is_grounded(), "({x}, {z}) did not land");
        assert_eq!(p.ground_entity(), Some(island));
        // Resting height over the point under the centre: the skin, plus r(1/cos θ − 1) for
        // the round bottom on a slope.
        let rest = 0.02 + 0.3 * ((1.0 + slope * slope).sqrt() - 1.0);
        let above = p.feet().y - y;
        assert!(
            (-0.01..=rest + 0.02).contains(&above),
            "({x}, {z}): feet {above} above the surface, {rest} expected at most"
        );
        tried += 1;
    }
    assert!(tried >= 5, "only {tried} points tried");
    Ok(())
}

/// A player start buried under a hill is lifted onto the terrain's surface, and the player
/// stands there instead of falling through the hill; a start on open ground stays where it
/// is.
#[test]
fn a_start_under_a_terrain_is_lifted_onto_it() -> anyhow::Result<()> {
    let (mut scene, assets) = load_level("terrain_hills")?;
    // Bury terrain_hills' start 2.6 units under the ground.
    let start = scene
        .entities()
        .find(|&e| scene.world().get::<&texel_scene::PlayerStart>(e).is_ok())
        .expect("a player start");
    scene
        .world_mut()
        .get::<&mut Transform>(start)
        .expect("a transform")
        .translation
        .y = 2.6;
    let mut w = PhysicsWorld::from_scene(&scene, &assets)?;
    let (island, t, origin) = scene
        .entities()
        .find_map(|e| {
            let world = scene.world();
            let t = world.get::<&Terrain>(e).ok()?;
            let origin = world.get::<&Transform>(e).ok()?.translation;
            Some((e, (*t).clone(), origin))
        })
        .unwrap();
    let field = assets.heightfield(&t).unwrap().clone();
    let written = scene
        .entities()
        .find_map(|e| {
            let world = scene.world();
            world.get::<&texel_scene::PlayerStart>(e).ok()?;
            Some(world.get::<&Transform>(e).ok()?.translation)
        })
        .expect("a player start");
    let spawn = w.spawn();
    let ground = surface(&field, t.size, origin, spawn.feet.x, spawn.feet.z);
    assert!(
        written.y < ground - 1.0,
        "the written start is under the hill"
    );
    assert!(
        (spawn.feet.y - ground).abs() < 0.05,
        "lifted to {} (ground {ground})",
        spawn.feet
    );
    let mut p = Player::new(PlayerConfig::default(), spawn.feet);
    run(&mut p, &mut w, idle(), 1.0);
    assert!(
        p.is_grounded() && (p.feet().y - ground).abs() < 0.1,
        "feet {}",
        p.feet()
    );
    assert_eq!(p.ground_entity(), Some(island));
    let (scene, assets) = load_level("stone_circle")?;
    let w = PhysicsWorld::from_scene(&scene, &assets)?;
    assert_eq!(w.spawn().feet, Vec3::new(0.0, 0.0, 13.0));
    Ok(())
}

#[test]
fn a_player_rides_the_animated_platform_of_moving_parts() -> anyhow::Result<()> {
    let (scene, assets) = load_level("moving_parts")?;
    let mut w = PhysicsWorld::from_scene(&scene, &assets)?;
    assert!(w.warnings().is_empty(), "{:?}", w.warnings());
    let platform = scene
        .entities()
        .find(|e| {
            scene
                .world()
                .get::<&Name>(*e)
                .is_ok_and(|n| n.0 == "Moving platform")
        })
        .expect("the level's platform");
    // On its top at t = 0: (-3.4, 0.2 + 0.15, 2.2).
    let mut p = Player::new(PlayerConfig::default(), Vec3::new(-3.4, 0.4, 2.2));
    let frames = (3.0 / FRAME).round() as u32;
    for i in 0..=frames {
        let t = f64::from(i) * f64::from(FRAME);
        w.set_kinematic_poses(&scene.animated_poses(t), FRAME)?;
        p.step(&mut w, &idle(), FRAME);
    }
    // At 3 s it is halfway from (-3.4, 1.2, 2.2) to (-3.4, 1.2, 0.8).
    let top = Vec3::new(-3.4, 1.35, 1.5);
    assert!(
        (p.feet() - top).length() < 0.05,
        "feet at {} on a platform whose top is at {top}",
        p.feet()
    );
    assert_eq!(p.ground_entity(), Some(platform));
    Ok(())
}

/// A step on the platform of moving_parts, its child in the file: the platform carries it,
/// its collider moves as a kinematic body, and a player on it rides it.
#[test]
fn a_player_rides_a_child_of_the_animated_platform() -> anyhow::Result<()> {
    let (scene, assets) = load_level("moving_parts")?;
    let mut level = scene.to_level();
    level.entities.push(EntityRow {
        name: Some(Name("Step".into())),
        parent: Some(Name("Moving platform".into())),
        transform: Some(Transform::from_translation(Vec3::new(0.0, 0.25, 0.0))),
        geometry: Some(Geometry::Box {
            size: Vec3::new(1.0, 0.2, 1.0),
        }),
        ..EntityRow::default()
    });
    let scene = Scene::from_level(&level);
    let step = scene.entities().last().expect("the step");
    let mut w = PhysicsWorld::from_scene(&scene, &assets)?;
    // On the step's top at t = 0: 0.2 + 0.25 + 0.1.
    let mut p = Player::new(PlayerConfig::default(), Vec3::new(-3.4, 0.6, 2.2));
    let frames = (3.0 / FRAME).round() as u32;
    for i in 0..=frames {
        let t = f64::from(i) * f64::from(FRAME);
        w.set_kinematic_poses(&scene.animated_poses(t), FRAME)?;
        p.step(&mut w, &idle(), FRAME);
    }
    assert!(w.is_kinematic(step), "the step is carried");
    // At 3 s the platform is at (-3.4, 1.2, 1.5): the step's top at 1.55.
    let top = Vec3::new(-3.4, 1.55, 1.5);
    assert!(
        (p.feet() - top).length() < 0.05,
        "feet at {} on a step whose top is at {top}",
        p.feet()
    );
    assert_eq!(p.ground_entity(), Some(step));
    Ok(())
}
