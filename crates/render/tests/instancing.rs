//! Mesh instancing: a mesh several still objects share is uploaded once, in object space,
//! and drawn per object with its transform; its shadows go through one tree in object space
//! under a top level over the objects. The frames must equal those of the same scene with
//! every copy written out in world space (`Renderer::set_scene_with(.., false)`).

use crate::common;

use std::sync::Arc;

use glam::{Mat4, Quat, UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, ObjectInput, PointLightInput, SceneInput, Schedule};
use texel_scene::primitives::{box_mesh, sphere};

/// The boxes scene with `placements` copies of one sphere and of one box (every other a
/// box), each placed by its transform: 2 shared meshes.
fn copies_scene(placements: &[Mat4]) -> SceneInput {
    let mut scene = common::boxes_scene();
    let ball = Arc::new(sphere(0.45, 12));
    let crate_ = Arc::new(box_mesh(Vec3::new(0.7, 0.5, 0.9)));
    for (i, &m) in placements.iter().enumerate() {
        let mut o: ObjectInput = common::object(Default::default(), m, Vec3::new(0.6, 0.5, 0.4), 0);
        o.mesh = if i % 2 == 0 {
            ball.clone()
        } else {
            crate_.clone()
        };
        o.id = scene.objects.len() as u32 + 1;
        scene.objects.push(o);
    }
    scene.points.push(PointLightInput {
        position: Vec3::new(0.5, 2.5, -4.0),
        colour: Vec3::new(1.0, 0.8, 0.5) * 3.0,
        radius: 8.0,
    });
    scene
}

/// `n` placements on a ring around the boxes: turned by quarter turns at whole coordinates
/// when `exact` (so a transform rounds nothing), else at any angle and place, one mirrored
/// and one scaled.
fn placements(n: usize, exact: bool) -> Vec<Mat4> {
    (0..n)
        .map(|i| {
            let a = i as f32 / n as f32 * std::f32::consts::TAU;
            if exact {
                let at = Vec3::new((3.0 * a.cos()).round(), 0.5, (3.0 * a.sin()).round() - 4.0);
                let turn = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2 * (i % 4) as f32);
                Mat4::from_rotation_translation(turn, at)
            } else {
                let at = Vec3::new(3.1 * a.cos(), 0.55, 3.3 * a.sin() - 4.2);
                let scale = match i {
                    3 => Vec3::new(-1.0, 1.0, 1.0),
                    4 => Vec3::splat(1.4),
                    _ => Vec3::ONE,
                };
                Mat4::from_scale_rotation_translation(
                    scale,
                    Quat::from_rotation_y(0.37 * i as f32),
                    at,
                )
            }
        })
        .collect()
}

/// Renders `scene` with instancing and shapes (`shared`) or every object written out, from
/// two cameras; the frames, the last frame's counters and how many objects were instanced.
fn render(
    scene: &SceneInput,
    shared: bool,
) -> (Vec<Vec<u8>>, texel_render::stats::Counters, (usize, usize)) {
    let ctx = test_context().expect("device");
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene_with(&ctx, scene, shared).expect("scene");
    let size = UVec2::new(240, 136);
    let mut frames = Vec::new();
    let mut counters = Default::default();
    for (eye, look) in [
        (Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0)),
        (Vec3::new(4.5, 3.0, -1.0), Vec3::new(-1.0, -0.5, -0.8)),
    ] {
        let cam = Camera::looking(eye, look);
        let input = common::frame(cam, eye + Vec3::Y * 0.4, 64, size, Schedule::Ours);
        let (stats, px) = r.render_offscreen(&ctx, &input).unwrap();
        counters = stats.counters;
        frames.push(px);
    }
    (frames, counters, r.instanced())
}

#[test]
fn instanced_and_copied_meshes_render_identically() {
    if test_context().is_none() {
        return;
    }
    for exact in [true, false] {
        let scene = copies_scene(&placements(12, exact));
        let (shared, shared_counters, counts) = render(&scene, true);
        let (copied, copied_counters, none) = render(&scene, false);
        let (shared_bytes, copied_bytes) = (
            shared_counters.gpu_scene_bytes,
            copied_counters.gpu_scene_bytes,
        );
        // The 12 copies draw 2 meshes; the boxes scene's three boxes differ in size.
        assert_eq!(counts, (12, 2), "exact: {exact}");
        assert_eq!(none, (0, 0));
        assert!(
            shared_bytes < copied_bytes,
            "{shared_bytes} < {copied_bytes}"
        );
        for (k, (a, b)) in shared.iter().zip(&copied).enumerate() {
            let size = UVec2::new(240, 136);
            common::save_png(&format!("instancing_{exact}_{k}_shared.png"), a, size);
            common::save_png(&format!("instancing_{exact}_{k}_copied.png"), b, size);
            let differ = common::differing_pixels(a, b);
            assert_eq!(
                differ, 0,
                "exact: {exact}, view {k}: {differ} pixels differ"
            );
        }
    }
}

/// One copy of a shared mesh moved and turned in place: its instance record is rewritten and
/// the top level above its shadow record refit; no vertex and no shadow triangle is, and the
/// frame equals that of a renderer given the moved scene afresh.
#[test]
fn moving_an_instance_rewrites_its_record_and_refits_the_top_level_only() {
    let Some(ctx) = test_context() else { return };
    let mut scene = copies_scene(&placements(12, false));
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &scene).expect("scene");
    let size = UVec2::new(240, 136);
    let eye = Vec3::new(0.3, 1.6, 3.0);
    let input = common::frame(
        Camera::looking(eye, Vec3::new(0.0, -0.25, -1.0)),
        eye,
        64,
        size,
        Schedule::Ours,
    );
    let (_, before) = r.render_offscreen(&ctx, &input).unwrap();
    let moved = scene.objects.len() - 3;
    scene.objects[moved].transform =
        Mat4::from_rotation_translation(Quat::from_rotation_y(0.8), Vec3::new(-0.8, 0.45, -1.5));
    let edit = r
        .update_scene(&ctx, &scene, &[moved])
        .unwrap()
        .expect("in place");
    assert_eq!(
        (edit.objects, edit.instances, edit.vertices),
        (1, 1, 0),
        "{edit:?}"
    );
    assert_eq!(edit.shadow_triangles, 0, "{edit:?}");
    assert!(edit.top_nodes > 0 && edit.nodes == 0, "{edit:?}");
    let (_, after) = r.render_offscreen(&ctx, &input).unwrap();
    assert!(after != before, "the move shows");
    let mut fresh = Renderer::headless(&ctx).unwrap();
    fresh.set_scene(&ctx, &scene).expect("scene");
    let (_, rebuilt) = fresh.render_offscreen(&ctx, &input).unwrap();
    let differ = after
        .chunks(4)
        .zip(rebuilt.chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differ, 0, "pixels differing from a fresh upload's frame");
}

/// The boxes scene with a grid of 400 small primitives around it (360 boxes, some of them
/// copies, drawn from one mesh; 40 balls of radii of their own, drawn from their own
/// world-space vertices: each kind past `SHARED_TRIANGLES`), turned, a third of them tilted
/// and scaled unevenly; every box and every ball casts through its kind's one shape.
pub(crate) fn primitives_scene() -> SceneInput {
    let mut scene = common::boxes_scene();
    for i in 0..400 {
        let k = i as f32;
        let mesh = match i % 10 {
            0 => sphere(0.12 + 0.0002 * k, 12),
            _ => box_mesh(Vec3::new(
                0.15 + 0.01 * (k % 17.0),
                0.2 + 0.02 * (k % 13.0),
                0.25,
            )),
        };
        let (scale, tilt) = match i % 3 {
            2 => (Vec3::new(1.0, 1.6, 0.7), 0.3),
            _ => (Vec3::ONE, 0.0),
        };
        let at = Vec3::new(
            -6.0 + 0.6 * (i % 20) as f32,
            0.3,
            -10.0 + 0.6 * (i / 20) as f32,
        );
        let m = Mat4::from_rotation_translation(Quat::from_rotation_y(0.41 * k), at)
            * Mat4::from_scale(scale)
            * Mat4::from_rotation_z(tilt);
        let colour = Vec3::new(0.5 + 0.01 * (k % 20.0), 0.45, 0.4);
        scene.objects.push(common::object(mesh, m, colour, 0));
        let id = scene.objects.len() as u32;
        if let Some(o) = scene.objects.last_mut() {
            o.id = id;
        }
    }
    scene.points.push(PointLightInput {
        position: Vec3::new(-0.5, 2.2, -3.0),
        colour: Vec3::new(1.0, 0.8, 0.5) * 3.0,
        radius: 8.0,
    });
    scene
}

#[test]
fn primitives_casting_through_shapes_render_as_world_space_casters() {
    if test_context().is_none() {
        return;
    }
    let scene = primitives_scene();
    let (shaped, shaped_counters, _) = render(&scene, true);
    let (flat, flat_counters, _) = render(&scene, false);
    let (shaped_bytes, flat_bytes) = (shaped_counters.gpu_bvh_bytes, flat_counters.gpu_bvh_bytes);
    assert!(shaped_bytes < flat_bytes, "{shaped_bytes} < {flat_bytes}");
    for (k, (a, b)) in shaped.iter().zip(&flat).enumerate() {
        let size = UVec2::new(240, 136);
        common::save_png(&format!("shapes_{k}_shaped.png"), a, size);
        common::save_png(&format!("shapes_{k}_flat.png"), b, size);
        let differ = common::differing_pixels(a, b);
        // A shadow ray tested in a shape's space rounds otherwise than against world-space
        // triangles (about 1e-7 of the object's size), so one grazing an edge within that
        // may go either way; random rays agree (`bvh::instances`), but a texel's rays are
        // not random: edge rays run along surfaces, contact texels shoot from beside
        // another object. Among 400 objects a few texels may differ (measured: none here on
        // lavapipe and SwiftShader; 1 pixel of 32,640 with other ball sizes); anything wrong
        // in a shape's placement would darken or light whole shadows.
        assert!(differ <= 16, "view {k}: {differ} pixels differ");
    }
}

/// A ball drawn from its own vertices but casting through its shape, moved in place: its
/// vertices and its shadow record are rewritten and the top level above it refit, no shadow
/// triangle is, and the frame equals a fresh upload's.
#[test]
fn moving_a_shaped_caster_refits_the_top_level_only() {
    let Some(ctx) = test_context() else { return };
    let mut scene = primitives_scene();
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &scene).expect("scene");
    let size = UVec2::new(240, 136);
    let eye = Vec3::new(0.3, 1.6, 3.0);
    let input = common::frame(
        Camera::looking(eye, Vec3::new(0.0, -0.25, -1.0)),
        eye,
        64,
        size,
        Schedule::Ours,
    );
    let (_, before) = r.render_offscreen(&ctx, &input).unwrap();
    // The ball at i = 190 of the grid (every tenth is a ball, each of its own size).
    let moved = scene.objects.len() - 400 + 190;
    scene.objects[moved].transform = Mat4::from_scale_rotation_translation(
        Vec3::new(1.5, 0.8, 1.2),
        Quat::from_rotation_y(0.8),
        Vec3::new(-0.8, 0.45, -1.5),
    );
    let edit = r
        .update_scene(&ctx, &scene, &[moved])
        .unwrap()
        .expect("in place");
    assert_eq!((edit.objects, edit.instances), (1, 0), "{edit:?}");
    assert!(edit.vertices > 0 && edit.shadow_triangles == 0, "{edit:?}");
    assert!(edit.top_nodes > 0 && edit.nodes == 0, "{edit:?}");
    let (_, after) = r.render_offscreen(&ctx, &input).unwrap();
    assert!(after != before, "the move shows");
    let rebuilt = common::fresh_frame(&ctx, &scene, &input);
    let differ = common::differing_pixels(&after, &rebuilt);
    assert_eq!(differ, 0, "pixels differing from a fresh upload's frame");
}
