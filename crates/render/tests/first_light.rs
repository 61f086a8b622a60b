//! A whole frame on the GPU: the boxes scene from one camera, in both schedules.

mod common;

use glam::{UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, Schedule};

#[test]
fn boxes_render_with_sky_ground_and_boxes() {
    let Some(ctx) = test_context() else { return };
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &common::boxes_scene());
    let size = UVec2::new(320, 180);
    let cam = Camera::looking(Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0));
    for schedule in [Schedule::Ours, Schedule::Paper] {
        let input = common::frame(cam, Vec3::new(0.0, 2.0, 3.0), 64, size, schedule);
        let (stats, px) = r.render_offscreen(&ctx, &input).unwrap();
        common::save_png(&format!("first_light_{schedule:?}.png"), &px, size);
        println!("{schedule:?}: {stats:?}");
        assert_eq!(stats.counters.faces_captured, 12);
        assert!(stats.counters.quads_splatted > 1000, "{:?}", stats.counters);
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
