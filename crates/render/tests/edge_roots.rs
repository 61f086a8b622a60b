//! A texel's edge rays (the silhouette edges' search) walk the still instances' top level
//! from a subtree that holds every instance they may meet (`lib/edge_rays.wgsl`
//! `edge_statics`), and find what they found from its root: among 400 primitives casting
//! through shared shapes, the frames are the same, byte for byte, with and without
//! (`Renderer::set_edge_roots(false)`, as `TEXEL_NO_EDGE_ROOTS` does).

use crate::common;

use glam::{UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, SceneInput, Schedule};

fn render(scene: &SceneInput, roots: bool) -> Vec<Vec<u8>> {
    let ctx = test_context().expect("device");
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_edge_roots(roots);
    r.set_scene(&ctx, scene).expect("scene");
    let size = UVec2::new(200, 112);
    // Near the primitives (large texels, long edge rays), and over them from above.
    [
        (Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0)),
        (Vec3::new(4.5, 3.0, -1.0), Vec3::new(-1.0, -0.5, -0.8)),
        (Vec3::new(-3.0, 6.0, 6.0), Vec3::new(0.4, -0.8, -0.6)),
    ]
    .into_iter()
    .map(|(eye, look)| {
        let input = common::frame(Camera::looking(eye, look), eye, 48, size, Schedule::Ours);
        r.render_offscreen(&ctx, &input).unwrap().1
    })
    .collect()
}

#[test]
fn edge_rays_from_their_texels_subtrees_find_what_they_find_from_the_root() {
    if test_context().is_none() {
        return;
    }
    let scene = crate::instancing::primitives_scene();
    let roots = render(&scene, true);
    let whole = render(&scene, false);
    for (k, (a, b)) in roots.iter().zip(&whole).enumerate() {
        let differ = common::differing_pixels(a, b);
        assert_eq!(differ, 0, "view {k}: {differ} pixels differ");
        let lit = a.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
        assert!(lit > a.len() / 8, "view {k} shows something: {lit} pixels");
    }
}
