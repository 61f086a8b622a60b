//! The player in hand-built scenes: ramps, steps, walls, falls, jumps, platforms, respawns
//! and bad input. CPU only.

use crate::support;

use glam::{Vec2, Vec3};
use support::*;
use texel_physics::{MoveInput, PhysicsWorld, Player, PlayerConfig};
use texel_scene::{Geometry, Transform};

/// A scene with a ramp of `degrees` rising toward −Z from z = −2 (4 units deep, so its top
/// is at 4·tan θ), and the player at z = 2 facing it.
fn ramp(degrees: f32) -> (PhysicsWorld, Player, f32) {
    let mut scene = ground_scene(Vec3::new(0.0, 0.0, 2.0));
    let height = 4.0 * degrees.to_radians().tan();
    solid(
        &mut scene,
        "Ramp",
        Vec3::new(0.0, 0.5 * height, -4.0),
        0.0,
        Geometry::Wedge {
            size: Vec3::new(4.0, height, 4.0),
        },
    );
    let w = world(&scene);
    let p = player(&w);
    (w, p, height)
}

#[test]
fn walks_up_a_30_degree_ramp_but_not_a_60_degree_one() {
    let (mut w, mut p, height) = ramp(30.0);
    let r = run(&mut p, &mut w, walk(-Vec3::Z), 2.0);
    // Past the ramp's foot by now; stands on it at the height of the slope under the feet
    // (a capsule on a slope rests a little above the point under its centre).
    let z = p.feet().z;
    assert!(z < -3.0, "walked only to z = {z}");
    let slope_height = (-2.0 - z) * 30f32.to_radians().tan();
    assert!(
        (p.feet().y - slope_height).abs() < 0.12,
        "feet at {} on a slope {slope_height} high there",
        p.feet()
    );
    assert!(p.is_grounded() && r.max_y <= height + 0.05);

    let (mut w, mut p, _) = ramp(60.0);
    let r = run(&mut p, &mut w, walk(-Vec3::Z), 3.0);
    assert!(
        r.max_y < PlayerConfig::default().max_step + 0.05,
        "climbed a 60° ramp to {}",
        r.max_y
    );
    assert!(p.feet().z > -2.3, "went into the ramp: {}", p.feet());
    assert!(p.is_grounded(), "stands on the floor in front of it");
}

#[test]
fn climbs_a_step_but_not_a_ledge() {
    let mut scene = ground_scene(Vec3::new(0.0, 0.0, 2.0));
    block(
        &mut scene,
        "Step",
        Vec3::new(0.0, 0.0, -4.0),
        Vec3::new(4.0, 0.25, 4.0),
    );
    let mut w = world(&scene);
    let mut p = player(&w);
    run(&mut p, &mut w, walk(-Vec3::Z), 1.5);
    assert!(p.feet().z < -2.5, "stuck at the step: {}", p.feet());
    assert!((p.feet().y - 0.25).abs() < 0.05 && p.is_grounded());

    let mut scene = ground_scene(Vec3::new(0.0, 0.0, 2.0));
    block(
        &mut scene,
        "Ledge",
        Vec3::new(0.0, 0.0, -4.0),
        Vec3::new(4.0, 0.6, 4.0),
    );
    let mut w = world(&scene);
    let mut p = player(&w);
    let r = run(&mut p, &mut w, walk(-Vec3::Z), 1.5);
    assert!(r.max_y < 0.05, "climbed a 0.6 ledge: {}", r.max_y);
    assert!(p.feet().z > -2.0 + 0.25, "in the ledge: {}", p.feet());
}

#[test]
fn climbs_stairs_and_walks_down_them_without_leaving_the_ground() {
    let mut scene = ground_scene(Vec3::new(0.0, 0.0, 1.0));
    // Five steps of 0.2 over treads of 0.5, rising toward −Z from z = −1; the top one deep.
    for i in 0..5 {
        let depth = if i == 4 { 4.0 } else { 0.5 };
        let front = -1.0 - 0.5 * i as f32;
        block(
            &mut scene,
            &format!("Step {i}"),
            Vec3::new(0.0, 0.0, front - 0.5 * depth),
            Vec3::new(3.0, 0.2 * (i + 1) as f32, depth),
        );
    }
    let mut w = world(&scene);
    let mut p = player(&w);
    run(&mut p, &mut w, walk(-Vec3::Z), 2.0);
    assert!(p.feet().z < -3.5, "stopped on the stairs: {}", p.feet());
    assert!(
        (p.feet().y - 1.0).abs() < 0.03 && p.is_grounded(),
        "{}",
        p.feet()
    );
    let mut airborne = 0;
    for _ in 0..120 {
        p.step(&mut w, &walk(Vec3::Z), FRAME);
        airborne += u32::from(!p.is_grounded());
    }
    assert!(p.feet().z > 0.0 && p.feet().y < 0.03, "{}", p.feet());
    assert_eq!(airborne, 0, "left the ground walking down");
}

#[test]
fn stops_at_a_wall_and_slides_along_it_when_moving_diagonally() {
    let mut scene = ground_scene(Vec3::new(0.0, 0.0, 0.0));
    // Its face toward the player at z = −2.
    block(
        &mut scene,
        "Wall",
        Vec3::new(0.0, 0.0, -2.5),
        Vec3::new(30.0, 3.0, 1.0),
    );
    let mut w = world(&scene);
    let mut p = player(&w);
    run(&mut p, &mut w, walk(-Vec3::Z), 1.5);
    let f = p.feet();
    assert!(
        f.z > -2.0 + 0.29 && f.z < -2.0 + 0.35,
        "not against the wall: {f}"
    );
    assert!(f.x.abs() < 0.01, "drifted sideways: {f}");

    let mut p = player(&w);
    run(&mut p, &mut w, walk(Vec3::new(-1.0, 0.0, -1.0)), 2.0);
    let f = p.feet();
    assert!(f.z > -2.0 + 0.29, "through the wall: {f}");
    // Tangential speed 4·cos 45° ≈ 2.8/s: ~5 units along the wall, less the approach.
    assert!(f.x < -4.0, "did not slide along the wall: {f}");
}

#[test]
fn lands_after_a_fall_and_stands() {
    let mut w = world(&ground_scene(Vec3::new(0.0, 5.0, 0.0)));
    let mut p = player(&w);
    let first = p.step(&mut w, &idle(), FRAME);
    assert!(!first.grounded && p.velocity().y < 0.0, "falls");
    let r = run(&mut p, &mut w, idle(), 1.5);
    assert!(r.landed && p.is_grounded());
    assert!(
        p.feet().y >= 0.0 && p.feet().y < 0.04,
        "feet at {}",
        p.feet()
    );
    assert_eq!(p.velocity(), Vec3::ZERO);
    // Standing still stays put.
    let before = p.feet();
    run(&mut p, &mut w, idle(), 1.0);
    assert!((p.feet() - before).length() < 1e-4);
}

#[test]
fn jumps_and_comes_back_down() {
    let mut w = world(&ground_scene(Vec3::ZERO));
    let mut p = player(&w);
    run(&mut p, &mut w, idle(), 0.2);
    let ground = p.feet().y;
    let jump = MoveInput {
        jump: true,
        ..idle()
    };
    let r = p.step(&mut w, &jump, FRAME);
    assert!(r.jumped && !r.grounded);
    let r = run(&mut p, &mut w, idle(), 1.5);
    let c = PlayerConfig::default();
    let apex = c.jump_speed * c.jump_speed / (2.0 * c.gravity);
    assert!(
        (r.max_y - ground - apex).abs() < 0.06,
        "apex {} for {apex}",
        r.max_y - ground
    );
    assert!(r.landed && p.is_grounded() && (p.feet().y - ground).abs() < 1e-3);
    // A jump pressed in the air does nothing.
    let mut p = Player::new(c, Vec3::new(0.0, 3.0, 0.0));
    let r = p.step(&mut w, &jump, FRAME);
    assert!(!r.jumped && p.velocity().y < 0.0);
}

#[test]
fn rides_a_moving_platform() {
    let mut scene = ground_scene(Vec3::new(0.0, 2.4, 0.0));
    let platform = block(
        &mut scene,
        "Platform",
        Vec3::new(0.0, 1.75, 0.0),
        Vec3::new(4.0, 0.5, 4.0),
    );
    let mut w = world(&scene);
    let mut p = player(&w);
    // Sideways at 1 unit/s and bobbing up and down by 0.5.
    let pose = |t: f32| Vec3::new(t, 2.0 + 0.5 * (2.0 * t).sin(), 0.0);
    let mut mover = |w: &mut PhysicsWorld, t: f32| {
        w.set_kinematic_pose(platform, &Transform::from_translation(pose(t)), FRAME)
            .unwrap();
    };
    let settled = run(&mut p, &mut w, idle(), 0.3);
    assert!(settled.landed && p.is_grounded());
    let start = p.feet();
    run_with(&mut p, &mut w, idle(), 3.0, &mut mover);
    let top = pose(3.0) + Vec3::Y * 0.25 + Vec3::new(start.x, 0.0, start.z);
    assert!(p.is_grounded());
    assert_eq!(p.ground_entity(), Some(platform));
    assert!(
        (p.feet() - top).length() < 0.05,
        "feet {} on a platform whose top is {top}",
        p.feet()
    );
    assert!(w.is_kinematic(platform));
    assert!((w.velocity(platform).x - 1.0).abs() < 0.01);

    // Walking off it keeps its sideways momentum for the fall.
    let (mut left, mut landed) = (None, None);
    for i in 0..90 {
        mover(&mut w, 3.0 + (i + 1) as f32 * FRAME);
        let r = p.step(&mut w, &walk(Vec3::Z), FRAME);
        if left.is_none() && !p.is_grounded() {
            left = Some(p.feet().x);
        }
        if left.is_some() && r.landed {
            landed = Some(p.feet());
            break;
        }
    }
    let (left, landed) = (left.expect("walked off"), landed.expect("landed"));
    assert!(landed.y < 0.03, "landed at {landed}");
    let fall = (2.0 * 2.0 / PlayerConfig::default().gravity).sqrt();
    assert!(
        landed.x - left > 0.7 * fall,
        "drifted {} in a {fall} s fall",
        landed.x - left
    );
}

#[test]
fn a_turning_platform_carries_and_turns_the_player() {
    let mut scene = ground_scene(Vec3::new(1.0, 0.55, 0.0));
    let platform = block(
        &mut scene,
        "Turntable",
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(4.0, 0.5, 4.0),
    );
    let mut w = world(&scene);
    let mut p = player(&w);
    run(&mut p, &mut w, idle(), 0.3);
    assert_eq!(p.ground_entity(), Some(platform));
    // 45°/s about Y for 2 s: a quarter turn takes +X to −Z.
    let r = run_with(&mut p, &mut w, idle(), 2.0, |w, t| {
        let pose = Transform {
            translation: Vec3::new(0.0, 0.25, 0.0),
            rotation: Vec3::new(0.0, 45.0 * t, 0.0),
            scale: Vec3::ONE,
        };
        w.set_kinematic_pose(platform, &pose, FRAME).unwrap();
    });
    let f = p.feet();
    assert!(
        (f - Vec3::new(0.0, 0.5, -1.0)).length() < 0.05,
        "feet at {f} after a quarter turn"
    );
    assert!(
        (r.turned - std::f32::consts::FRAC_PI_2).abs() < 1e-3,
        "{}",
        r.turned
    );
}

#[test]
fn respawns_after_falling_off_the_world() {
    let mut scene = texel_scene::Scene::new();
    block(
        &mut scene,
        "Island",
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(2.0, 1.0, 2.0),
    );
    player_start(&mut scene, Vec3::ZERO);
    let mut w = world(&scene);
    assert!((w.kill_height() - (-1.0 - texel_physics::KILL_MARGIN)).abs() < 1e-4);
    let mut p = player(&w);
    let mut respawned = false;
    for _ in 0..400 {
        let r = p.step(&mut w, &walk(Vec3::X), FRAME);
        if r.respawned {
            respawned = true;
            // Back at the start (and walking again from there).
            assert!((p.feet() - Vec3::ZERO).length() < 0.2, "{}", p.feet());
            break;
        }
        assert!(p.feet().y > w.kill_height() - 1.0);
    }
    assert!(respawned, "never respawned: {}", p.feet());
}

#[test]
fn bad_input_changes_nothing_and_never_panics() {
    let scene = ground_scene(Vec3::new(0.0, 3.0, 0.0));
    let ground = scene.entities().next().unwrap();
    let mut w = world(&scene);
    let mut p = player(&w);
    p.step(&mut w, &idle(), FRAME);
    let (feet, vel, eye) = (p.feet(), p.velocity(), p.eye());
    for (wish, dt) in [
        (Vec3::ZERO, f32::NAN),
        (Vec3::ZERO, f32::INFINITY),
        (Vec3::ZERO, f32::NEG_INFINITY),
        (Vec3::new(f32::NAN, 0.0, 0.0), FRAME),
        (Vec3::new(0.0, 0.0, f32::INFINITY), FRAME),
    ] {
        let r = p.step(&mut w, &MoveInput { wish, jump: true }, dt);
        assert!(r.ignored && r.substeps == 0);
        assert_eq!((p.feet(), p.velocity(), p.eye()), (feet, vel, eye));
    }
    // Negative and zero frames simulate nothing; a huge one is clamped.
    assert_eq!(p.step(&mut w, &idle(), -1.0).substeps, 0);
    assert_eq!(p.step(&mut w, &idle(), 0.0).substeps, 0);
    assert_eq!(p.step(&mut w, &idle(), 1e9).substeps, 30);
    // An absurd wish is capped; an absurd config is made usable.
    let r = p.step(
        &mut w,
        &MoveInput {
            wish: Vec3::splat(1e30),
            jump: false,
        },
        FRAME,
    );
    assert!(!r.ignored && p.feet().is_finite());
    p.config.radius = f32::NAN;
    p.config.height = -3.0;
    p.config.gravity = f32::INFINITY;
    run(&mut p, &mut w, walk(Vec3::X), 0.5);
    assert!(p.feet().is_finite() && p.eye().is_finite());
    // Bad poses for kinematic bodies are refused.
    let bad = Transform::from_translation(Vec3::NAN);
    assert!(w.set_kinematic_pose(ground, &bad, FRAME).is_err());
    let flat = Transform {
        scale: Vec3::new(1.0, 0.0, 1.0),
        ..Transform::default()
    };
    assert!(w.set_kinematic_pose(ground, &flat, FRAME).is_err());
    assert!(!w.is_kinematic(ground));
}

#[test]
fn the_same_inputs_give_the_same_run() {
    let trace = || {
        let mut scene = ground_scene(Vec3::new(0.0, 1.0, 2.0));
        block(
            &mut scene,
            "Step",
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(2.0, 0.25, 2.0),
        );
        let mut w = world(&scene);
        let mut p = player(&w);
        let mut out = Vec::new();
        for i in 0..240u32 {
            let angle = i as f32 * 0.05;
            let input = MoveInput {
                wish: PlayerConfig::default().wish(
                    Vec3::new(angle.sin(), 0.0, -angle.cos()),
                    i.is_multiple_of(3),
                ),
                jump: i.is_multiple_of(50),
            };
            // Uneven frames, as a real clock gives.
            p.step(&mut w, &input, FRAME * (0.5 + (i % 4) as f32 * 0.4));
            out.push(p.eye());
        }
        out
    };
    assert_eq!(trace(), trace());
}

#[test]
fn a_plane_holds_the_player_from_above_at_any_speed() {
    let mut scene = texel_scene::Scene::new();
    solid(
        &mut scene,
        "Floor",
        Vec3::ZERO,
        0.0,
        Geometry::Plane {
            size: Vec2::splat(10.0),
        },
    );
    player_start(&mut scene, Vec3::new(0.0, 40.0, 0.0));
    let mut w = world(&scene);
    let mut p = player(&w);
    p.config.max_fall_speed = 200.0;
    let r = run(&mut p, &mut w, idle(), 4.0);
    assert!(
        r.landed && p.feet().y >= 0.0 && p.feet().y < 0.04,
        "{}",
        p.feet()
    );
}

#[test]
fn a_rebuilt_level_does_not_carry_the_player_back_with_its_platform() {
    let mut scene = ground_scene(Vec3::new(0.0, 1.1, 0.0));
    let platform = block(
        &mut scene,
        "Platform",
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(8.0, 0.5, 8.0),
    );
    let mut w = world(&scene);
    let mut p = player(&w);
    run(&mut p, &mut w, idle(), 0.3);
    let moved = Transform::from_translation(Vec3::new(2.0, 0.75, 0.0));
    w.set_kinematic_pose(platform, &moved, FRAME).unwrap();
    run(&mut p, &mut w, idle(), 0.1);
    assert!((p.feet().x - 2.0).abs() < 1e-3, "{}", p.feet());
    // The level reloads: the platform is back at its level pose, the player stays put.
    w.rebuild(&scene, &texel_scene::assets::AssetLibrary::default())
        .unwrap();
    run(&mut p, &mut w, idle(), 0.5);
    assert!((p.feet().x - 2.0).abs() < 1e-3, "{}", p.feet());
    assert_eq!(p.ground_entity(), Some(platform));
}
