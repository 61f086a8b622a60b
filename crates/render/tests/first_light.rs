//! A whole frame on the GPU: the boxes scene from one camera, in both schedules.

use crate::common;

use glam::{UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, Schedule};

#[test]
fn boxes_render_with_sky_ground_and_boxes() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &common::boxes_scene()).expect("scene");
    let size = UVec2::new(320, 180);
    let cam = Camera::looking(Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0));
    for schedule in [Schedule::Ours, Schedule::Paper] {
        let input = common::frame(cam, Vec3::new(0.0, 2.0, 3.0), 64, size, schedule);
        let (stats, px) = r.render_offscreen(&ctx, &input).unwrap();
        common::save_png(&format!("first_light_{schedule:?}.png"), &px, size);
        println!("{schedule:?}: {stats:?}");
        assert_eq!(stats.counters.faces_captured, 12);
        let c = stats.counters;
        match schedule {
            // Runs: one quad draws a stretch of alike texels (the ground's rows).
            Schedule::Ours => assert!(
                c.quads_splatted > 100 && c.quads_splatted < c.screen_visible_texels,
                "{c:?}"
            ),
            // The paper draws every texel of the visible faces, seen or not.
            Schedule::Paper => assert!(c.quads_splatted > c.screen_visible_texels, "{c:?}"),
        }
        assert!(
            stats.counters.screen_visible_texels > 500,
            "{:?}",
            stats.counters
        );
        // Top row is sky, bottom row is ground.
        let at = |x: u32, y: u32| {
            let i = ((y * size.x + x) * 4) as usize;
            [px[i], px[i + 1], px[i + 2]]
        };
        let sky = at(160, 2);
        assert!(sky[2] > sky[0] && sky[2] > 150, "sky is blue: {sky:?}");
        let ground = at(10, 175);
        assert!(
            ground[1] > ground[0] && ground[1] > ground[2],
            "ground is green: {ground:?}"
        );
    }
}

#[test]
fn haze_pulls_far_surfaces_toward_the_sky() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &common::boxes_scene()).expect("scene");
    let size = UVec2::new(160, 90);
    let cam = Camera::looking(Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.1, -1.0));
    let mut clear = common::frame(cam, Vec3::new(0.0, 2.0, 3.0), 32, size, Schedule::Ours);
    let (_, sharp) = r.render_offscreen(&ctx, &clear).unwrap();
    clear.look.haze = 0.15;
    let (_, hazy) = r.render_offscreen(&ctx, &clear).unwrap();
    let px = |img: &[u8], x: u32, y: u32| {
        let i = ((y * size.x + x) * 4) as usize;
        [img[i], img[i + 1], img[i + 2]].map(i32::from)
    };
    let sky = px(&sharp, 80, 1);
    let dist = |a: [i32; 3], b: [i32; 3]| (0..3).map(|i| (a[i] - b[i]).abs()).sum::<i32>();
    // Ground just below the horizon is far; at the bottom edge it is near.
    let (far_sharp, far_hazy) = (px(&sharp, 10, 47), px(&hazy, 10, 47));
    let (near_sharp, near_hazy) = (px(&sharp, 10, 88), px(&hazy, 10, 88));
    assert!(
        dist(far_hazy, sky) + 20 < dist(far_sharp, sky),
        "far ground moves toward the sky: {far_sharp:?} → {far_hazy:?} (sky {sky:?})"
    );
    assert!(
        dist(near_hazy, near_sharp) < dist(far_hazy, far_sharp),
        "near ground changes less than far ground"
    );
}

/// Pipelines are made once per device (`pipeline_cache`): a second renderer on the same
/// device compiles none of the pipelines the first compiled, and draws the same frame. A
/// device of its own, so no other test's pipelines are counted.
#[test]
fn a_second_renderer_on_a_device_compiles_nothing_and_draws_the_same_frame() {
    if test_context().is_none() {
        return;
    }
    let ctx = texel_render::context::GpuContext::headless().expect("a device");
    let size = UVec2::new(160, 90);
    let cam = Camera::looking(Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0));
    let input = common::frame(cam, Vec3::new(0.0, 2.0, 3.0), 32, size, Schedule::Ours);
    let frame = || {
        let mut r = Renderer::headless(&ctx).unwrap();
        r.set_scene(&ctx, &common::boxes_scene()).expect("scene");
        r.render_offscreen(&ctx, &input).unwrap().1
    };
    let first = frame();
    let compiled = ctx.pipelines_compiled();
    assert!(
        compiled >= 5,
        "the first frame compiled {compiled} pipelines"
    );
    let second = frame();
    assert_eq!(
        ctx.pipelines_compiled(),
        compiled,
        "the second renderer compiled again"
    );
    assert!(first == second, "the second renderer's frame differs");
    // A clone is the same device, with the same pipelines.
    let clone = ctx.clone();
    let mut r = Renderer::headless(&clone).unwrap();
    r.set_scene(&clone, &common::boxes_scene()).expect("scene");
    assert!(r.render_offscreen(&clone, &input).unwrap().1 == first);
    assert_eq!(clone.pipelines_compiled(), compiled);
}

/// Two contexts of two instances may hold devices wgpu numbers alike; each keeps its own
/// pipelines, so renderers on both draw (a cache found by the device's id handed one
/// device's pipelines to the other, which wgpu-core refused with a panic).
#[test]
fn renderers_on_two_instances_keep_their_own_pipelines() {
    if test_context().is_none() {
        return;
    }
    let open = || texel_render::context::GpuContext::headless().expect("a device");
    let (a, b) = (open(), open());
    let size = UVec2::new(96, 54);
    let cam = Camera::looking(Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0));
    let input = common::frame(cam, Vec3::new(0.0, 2.0, 3.0), 32, size, Schedule::Ours);
    let frame = |ctx: &texel_render::context::GpuContext| {
        let mut r = Renderer::headless(ctx).unwrap();
        r.set_scene(ctx, &common::boxes_scene()).expect("scene");
        r.render_offscreen(ctx, &input).unwrap().1
    };
    let (on_a, on_b) = (frame(&a), frame(&b));
    assert!(on_a == on_b, "the two devices drew different frames");
    assert!(a.pipelines_compiled() > 0 && b.pipelines_compiled() == a.pipelines_compiled());
}
