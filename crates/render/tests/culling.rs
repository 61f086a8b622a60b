//! A face's CPU cull through the draw ranges' tree (`gpu_scene::RangeIndex`), which an edit
//! made in place refits: what moves into a face's view is drawn there.

use crate::common;

use glam::{Mat4, UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, Schedule};
use texel_scene::primitives::box_mesh;

/// A box from far behind the camera (among boxes there, so the tree's leaves around it lie
/// there too) moved in place to just in front of it: the frame equals a fresh upload's. Had
/// the edit left the tree's boxes where they were, every face in front would skip it.
#[test]
fn a_box_moved_into_view_in_place_is_drawn_as_after_a_fresh_upload() {
    let Some(ctx) = test_context() else { return };
    let mut scene = common::boxes_scene();
    let first = scene.objects.len();
    for i in 0..48u32 {
        let (x, z) = ((i % 8) as f32 * 6.0 - 21.0, (i / 8) as f32 * 6.0 + 60.0);
        let size = Vec3::new(1.0, 1.0 + (i % 3) as f32, 1.0);
        let at = Mat4::from_translation(Vec3::new(x, 0.5 * size.y, z));
        scene.objects.push(common::object(
            box_mesh(size),
            at,
            Vec3::new(0.7, 0.5, 0.3),
            100 + i,
        ));
    }
    let moved = first + 27;
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_scene(&ctx, &scene).expect("scene");
    let size = UVec2::new(160, 120);
    let eye = Vec3::new(0.0, 1.6, 3.0);
    let cam = Camera::looking(eye, Vec3::new(0.0, -0.3, -1.0));
    let input = common::frame(cam, eye, 32, size, Schedule::Ours);
    let (_, before) = r.render_offscreen(&ctx, &input).unwrap();
    scene.objects[moved].transform = Mat4::from_translation(Vec3::new(0.3, 0.5, -1.0));
    let edit = r.update_scene(&ctx, &scene, &[moved]).unwrap();
    assert!(edit.is_some_and(|e| e.objects == 1), "in place: {edit:?}");
    let (_, after) = r.render_offscreen(&ctx, &input).unwrap();
    assert!(after != before, "the moved box shows");
    let rebuilt = common::fresh_frame(&ctx, &scene, &input);
    let differ = common::differing_pixels(&after, &rebuilt);
    assert_eq!(differ, 0, "pixels differing from a fresh upload's frame");
}
