//! Animated objects through the moving pass: never captured into the probes, drawn where
//! their pose puts them, and their pixels carried with them.

use crate::common;

use std::sync::Arc;

use glam::{Mat4, UVec2, Vec3};
use texel_geom::texture::{Image, SurfaceMaps, TextureRef};
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, Pose, SceneInput, Schedule};
use texel_scene::primitives::box_mesh;

/// A 16×16 texture of distinct colours: every texture pixel (a quarter unit on a box with
/// world-unit UVs at `uv_scale` 1/4) tells where on the surface it is.
fn mosaic() -> TextureRef {
    let mut pixels = Vec::with_capacity(16 * 16 * 4);
    for y in 0..16u32 {
        for x in 0..16u32 {
            let h = (x * 73 + y * 151) % 256;
            pixels.extend_from_slice(&[h as u8, (x * 16) as u8, (y * 16) as u8, 255]);
        }
    }
    TextureRef {
        image: Arc::new(Image {
            name: "mosaic".into(),
            width: 16,
            height: 16,
            pixels,
        }),
        sampler: Default::default(),
    }
}

/// One textured box (object 0, id 10), animated, in an otherwise empty world with a sun.
fn one_moving_box(with_floor: bool) -> SceneInput {
    let mut scene = common::boxes_scene();
    scene.objects.clear();
    let mut b = common::object(
        box_mesh(Vec3::new(1.5, 1.0, 1.2)),
        Mat4::from_translation(Vec3::new(0.0, 1.0, -4.0)),
        Vec3::ONE,
        10,
    );
    b.material.maps = SurfaceMaps {
        albedo: Some(mosaic()),
        normal: None,
        uv_scale: glam::Vec2::splat(0.25),
    };
    b.material.outlined = false;
    scene.objects.push(b);
    if with_floor {
        scene.objects.push(common::object(
            texel_scene::primitives::plane(glam::Vec2::splat(40.0)),
            Mat4::IDENTITY,
            Vec3::new(0.3, 0.5, 0.25),
            1,
        ));
    }
    scene.animated = vec![0];
    scene
}

fn pose(transform: Mat4) -> Vec<Pose> {
    vec![Pose {
        object: 0,
        transform,
    }]
}

/// Moving the box and the camera together by the same step (not a whole number of the
/// box's cells) leaves the picture as it was: the box's pixels are cut on a grid fixed to
/// the box, not to the world or the screen.
#[test]
fn a_moving_objects_pixels_move_with_it() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &one_moving_box(false)).expect("scene");
    let size = UVec2::new(160, 90);
    let base = Mat4::from_translation(Vec3::new(0.0, 1.0, -4.0))
        * Mat4::from_rotation_y(0.6)
        * Mat4::from_rotation_x(0.3);
    let eye = Vec3::new(0.3, 1.6, 2.0);
    let grid = Vec3::new(0.5, 1.5, 2.5);
    let look = Vec3::new(0.0, -0.1, -1.0);
    let render = |r: &mut Renderer, shift: Vec3| {
        let cam = Camera::looking(eye + shift, look);
        let mut input = common::frame(cam, grid + shift, 64, size, Schedule::Ours);
        input.poses = pose(Mat4::from_translation(shift) * base);
        r.render_offscreen(&ctx, &input).unwrap().1
    };
    let still = render(&mut r, Vec3::ZERO);
    common::save_png("moving_still.png", &still, size);
    // Everything but the box is sky (the top-left pixel's colour).
    let sky = still[..4].to_vec();
    let box_pixels = still.chunks_exact(4).filter(|p| *p != sky).count();
    assert!(box_pixels > 300, "the box covers {box_pixels} pixels");
    for shift in [Vec3::new(0.37, 0.11, -0.23), Vec3::new(-0.61, 0.05, 0.29)] {
        let moved = render(&mut r, shift);
        let differ = still
            .chunks_exact(4)
            .zip(moved.chunks_exact(4))
            .filter(|(a, b)| a != b)
            .count();
        // Only pixels along the box's outline may round the other way.
        assert!(
            differ * 40 < box_pixels,
            "{differ} of the box's {box_pixels} pixels changed when box and camera moved by \
             {shift}"
        );
    }
}

/// The probes never hold an animated object: a grid probe captured with the box in front of
/// it shows the floor behind, and no texel of any face has the box's id; the frame still
/// shows the box (the moving pass), and picking names it.
#[test]
fn animated_objects_are_never_captured() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &one_moving_box(true)).expect("scene");
    let size = UVec2::new(160, 90);
    let cam = Camera::looking(Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.0, -0.15, -1.0));
    let mut input = common::frame(cam, Vec3::new(0.0, 1.5, 0.0), 64, size, Schedule::Ours);
    input.poses = pose(Mat4::from_translation(Vec3::new(0.0, 1.0, -4.0)));
    let (_, px) = r.render_offscreen(&ctx, &input).unwrap();
    common::save_png("moving_not_captured.png", &px, size);
    let ids = r.read_frame_ids(&ctx).unwrap();
    let shown = ids.entity.iter().filter(|&&e| e == 10).count();
    assert!(shown > 300, "the box shows in {shown} pixels");
    let centre = UVec2::new(size.x / 2, size.y / 2);
    assert_eq!(
        r.pick(&ctx, centre).unwrap(),
        Some(10),
        "picking names the box"
    );
    // Every grid-probe texel that is not sky is the floor (id 1).
    for slot in [
        texel_probes::probe_set::Slot::StableA,
        texel_probes::probe_set::Slot::Eye,
    ] {
        let n = r.probes().slot(slot).n;
        for face in 0..6u32 {
            for y in (0..n).step_by(3) {
                for x in (0..n).step_by(3) {
                    let id = r
                        .probe_texel_entity(&ctx, slot, face, UVec2::new(x, y))
                        .unwrap();
                    assert!(
                        id.is_none() || id == Some(1),
                        "{slot:?} face {face} texel ({x}, {y}) holds entity {id:?}"
                    );
                }
            }
        }
    }
}

/// The pose moves the object: with the box moved 2 units left, its pixels move left.
#[test]
fn the_pose_places_the_object() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &one_moving_box(false)).expect("scene");
    let size = UVec2::new(160, 90);
    let cam = Camera::looking(Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.0, -0.15, -1.0));
    let mean_x = |r: &mut Renderer, x: f32| {
        let mut input = common::frame(cam, Vec3::new(0.0, 1.5, 0.0), 64, size, Schedule::Ours);
        input.poses = pose(Mat4::from_translation(Vec3::new(x, 1.0, -4.0)));
        r.render_offscreen(&ctx, &input).unwrap();
        let ids = r.read_frame_ids(&ctx).unwrap();
        let xs: Vec<u32> = (0..ids.entity.len() as u32)
            .filter(|&i| ids.entity[i as usize] == 10)
            .map(|i| i % size.x)
            .collect();
        assert!(xs.len() > 200, "{} box pixels", xs.len());
        xs.iter().sum::<u32>() as f32 / xs.len() as f32
    };
    let centred = mean_x(&mut r, 0.0);
    let left = mean_x(&mut r, -2.0);
    assert!((centred - 80.0).abs() < 4.0, "centred box at x {centred}");
    assert!(
        left < centred - 20.0,
        "moved box at x {left}, was {centred}"
    );
}

/// A moving object casts its shadow where it is now: the grid probe's floor texels under the
/// box are dark, and after the box moves 3 units along X and the floor's faces are lit again
/// (no capture), the dark patch has moved with it.
#[test]
fn a_moving_objects_shadow_moves_on_the_cached_floor() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    let mut scene = one_moving_box(true);
    scene.objects[0].material.maps = SurfaceMaps::default();
    scene.suns[0].direction = Vec3::new(0.0, -1.0, 0.0);
    r.set_scene(&ctx, &scene).expect("scene");
    let size = UVec2::new(96, 54);
    let grid = Vec3::new(0.0, 6.0, -4.0);
    let cam = Camera::looking(Vec3::new(0.0, 6.0, -1.0), Vec3::new(0.0, -1.0, -0.4));
    let at = |x: f32| pose(Mat4::from_translation(Vec3::new(x, 1.5, -4.0)));
    let mut input = common::frame(cam, grid, 64, size, Schedule::Ours);
    input.poses = at(-1.5);
    r.render_offscreen(&ctx, &input).unwrap();
    let (n, before) = r
        .read_lit_faces(&ctx, texel_probes::probe_set::Slot::StableA)
        .unwrap();
    // Face −Y (3) looks down on the floor: luminance of the texels under x = −1.5 and +1.5.
    let texel_at = |x: f32| {
        let d = Vec3::new(x, 0.0, -4.0) - grid;
        let t = texel_probes::cube::texel_from_direction(d, n).expect("a texel");
        assert_eq!(t.face.index(), 3);
        ((t.y * n + t.x) * 4) as usize
    };
    let lum = |face: &[u8], x: f32| {
        let i = texel_at(x);
        face[i] as u32 + face[i + 1] as u32 + face[i + 2] as u32
    };
    let (left, right) = (lum(&before[3], -1.5), lum(&before[3], 1.5));
    assert!(
        left + 60 < right,
        "shadow under the box: {left} vs lit floor {right}"
    );
    // Moved; no capture this frame, the grid probe's faces lit again.
    input.poses = at(1.5);
    input.captures.clear();
    input.relight = texel_probes::cube::Face::ALL
        .map(|face| texel_render::input::Relight {
            slot: texel_probes::probe_set::Slot::StableA,
            face,
            rect: texel_probes::visibility::TexelRect {
                x0: 0,
                y0: 0,
                x1: n,
                y1: n,
            },
            filter: None,
        })
        .to_vec();
    let (stats, _) = r.render_offscreen(&ctx, &input).unwrap();
    assert_eq!(stats.counters.faces_captured, 0);
    let (_, after) = r
        .read_lit_faces(&ctx, texel_probes::probe_set::Slot::StableA)
        .unwrap();
    let (left2, right2) = (lum(&after[3], -1.5), lum(&after[3], 1.5));
    assert_eq!(left2, right, "the old shadow is lit again");
    assert_eq!(right2, left, "the shadow fell where the box went");
    // The same move, lit again only where a ray toward a light (or from the probe) meets
    // the box's old or new bounds (`LightFilter`): the same faces, byte for byte, from a
    // fraction of the texels.
    let bounds = |x: f32| {
        (
            Vec3::new(x - 0.75, 1.0, -4.6),
            Vec3::new(x + 0.75, 2.0, -3.4),
        )
    };
    let mut f = Renderer::headless(&ctx).unwrap();
    f.set_scene(&ctx, &scene).expect("scene");
    let mut filtered = common::frame(cam, grid, 64, size, Schedule::Ours);
    filtered.poses = at(-1.5);
    f.render_offscreen(&ctx, &filtered).unwrap();
    filtered.poses = at(1.5);
    filtered.captures.clear();
    let filter = texel_render::input::LightFilter {
        casters: vec![bounds(-1.5), bounds(1.5)],
        lit: Vec::new(),
    };
    filtered.relight = (input.relight.iter())
        .map(|r| texel_render::input::Relight {
            filter: Some(filter.clone()),
            ..r.clone()
        })
        .collect();
    let (few, _) = f.render_offscreen(&ctx, &filtered).unwrap();
    let (_, lit) = f
        .read_lit_faces(&ctx, texel_probes::probe_set::Slot::StableA)
        .unwrap();
    assert!(lit == after, "the filtered faces are the faces lit whole");
    let (all, some) = (stats.counters.texels_shaded, few.counters.texels_shaded);
    assert!(some * 4 < all, "{some} texels lit again, against {all}");
}

/// An animated object is lit like the same object standing still in the probes: the mean
/// colour of its pixels from the moving pass is within a few levels of the captured one's.
#[test]
fn a_moving_object_is_lit_like_a_still_one() {
    let Some(ctx) = test_context() else { return };
    let size = UVec2::new(160, 90);
    let cam = Camera::looking(Vec3::new(0.7, 1.9, 0.0), Vec3::new(-0.15, -0.2, -1.0));
    let mut means = Vec::new();
    for animated in [true, false] {
        let mut scene = one_moving_box(true);
        scene.objects[0].material.maps = SurfaceMaps::default();
        scene.objects[0].material.albedo = Vec3::new(0.6, 0.4, 0.2);
        if !animated {
            scene.animated.clear();
        }
        let mut r = Renderer::headless(&ctx).unwrap();
        r.set_scene(&ctx, &scene).expect("scene");
        let mut input = common::frame(cam, Vec3::new(0.5, 1.5, 0.5), 64, size, Schedule::Ours);
        input.poses = pose(Mat4::from_translation(Vec3::new(0.0, 1.0, -4.0)));
        let (_, px) = r.render_offscreen(&ctx, &input).unwrap();
        common::save_png(&format!("moving_lit_{animated}.png"), &px, size);
        let ids = r.read_frame_ids(&ctx).unwrap();
        let (mut sum, mut count) = ([0u64; 3], 0u64);
        for (i, &e) in ids.entity.iter().enumerate() {
            if e == 10 {
                for c in 0..3 {
                    sum[c] += u64::from(px[i * 4 + c]);
                }
                count += 1;
            }
        }
        assert!(count > 300, "{count} box pixels");
        means.push(sum.map(|s| s as f32 / count as f32));
    }
    let (moving, still) = (means[0], means[1]);
    for c in 0..3 {
        assert!(
            (moving[c] - still[c]).abs() < 12.0,
            "moving {moving:?} vs still {still:?}"
        );
    }
}

/// Many moving casters (found through the top-level tree over their bounds): the floor
/// under each of seven boxes, posed along a row, is in shadow, and the floor between them lit.
#[test]
fn every_moving_caster_of_many_casts_its_shadow() {
    let Some(ctx) = test_context() else { return };
    let mut scene = one_moving_box(true);
    scene.objects[0].material.maps = SurfaceMaps::default();
    scene.suns[0].direction = Vec3::new(0.0, -1.0, 0.0);
    let floor = scene.objects.pop().expect("floor");
    let template = scene.objects[0].clone();
    scene.objects.clear();
    for i in 0..7u32 {
        let mut b = template.clone();
        b.id = 10 + i;
        scene.objects.push(b);
    }
    scene.objects.push(floor);
    scene.animated = (0..7).collect();
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &scene).expect("scene");
    let grid = Vec3::new(0.0, 8.0, -4.0);
    let cam = Camera::looking(Vec3::new(0.0, 8.0, -1.0), Vec3::new(0.0, -1.0, -0.4));
    let mut input = common::frame(cam, grid, 64, UVec2::new(96, 54), Schedule::Ours);
    input.poses = (0..7)
        .map(|i| Pose {
            object: i,
            transform: Mat4::from_translation(Vec3::new(i as f32 * 2.0 - 6.0, 1.5, -4.0)),
        })
        .collect();
    r.render_offscreen(&ctx, &input).unwrap();
    let (n, faces) = r
        .read_lit_faces(&ctx, texel_probes::probe_set::Slot::StableA)
        .unwrap();
    let lum = |x: f32| {
        let d = Vec3::new(x, 0.0, -4.0) - grid;
        let t = texel_probes::cube::texel_from_direction(d, n).expect("a texel");
        assert_eq!(t.face.index(), 3);
        let i = ((t.y * n + t.x) * 4) as usize;
        faces[3][i] as u32 + faces[3][i + 1] as u32 + faces[3][i + 2] as u32
    };
    for i in 0..7 {
        let x = i as f32 * 2.0 - 6.0;
        let (under, between) = (lum(x), lum(x + 1.0));
        assert!(
            under + 60 < between,
            "box {i}: floor under it {under}, beside it {between}"
        );
    }
}
