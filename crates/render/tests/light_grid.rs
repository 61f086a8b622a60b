//! The point lights' grid (`gpu_scene::light_grid`) changes what the shade pass traces, not
//! what it finds: a scene lit by 40 point lights of many sizes, some overlapping, some far
//! away, draws the same frames, byte for byte, with the grid and with one cell listing every
//! light (`Renderer::set_light_grid(false)`, as `TEXEL_NO_LIGHT_GRID` does). Among 400
//! primitives casting through shared shapes the grid's lights walk only their caster roots
//! of the still instances' top level (`light_grid::caster_nodes`), and find the same.

use crate::common;

use glam::{UVec2, Vec3};
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, PointLightInput, SceneInput, Schedule};

fn lit_scene() -> SceneInput {
    with_lights(common::boxes_scene())
}

fn with_lights(mut scene: SceneInput) -> SceneInput {
    let mut rng = fastrand::Rng::with_seed(11);
    for _ in 0..40 {
        scene.points.push(PointLightInput {
            position: Vec3::new(
                rng.f32() * 24.0 - 12.0,
                0.3 + rng.f32() * 3.0,
                rng.f32() * 24.0 - 16.0,
            ),
            colour: Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 1.5,
            radius: 0.5 + rng.f32() * 6.0,
        });
    }
    scene
}

fn render(scene: &SceneInput, grid: bool) -> Vec<Vec<u8>> {
    let ctx = test_context().expect("device");
    let mut r = Renderer::headless(&ctx).unwrap();
    r.set_light_grid(grid);
    r.set_scene(&ctx, scene).expect("scene");
    let size = UVec2::new(200, 112);
    [
        (Vec3::new(0.3, 1.6, 3.0), Vec3::new(0.0, -0.25, -1.0)),
        (Vec3::new(4.5, 3.0, -1.0), Vec3::new(-1.0, -0.5, -0.8)),
    ]
    .into_iter()
    .map(|(eye, look)| {
        let input = common::frame(Camera::looking(eye, look), eye, 48, size, Schedule::Ours);
        r.render_offscreen(&ctx, &input).unwrap().1
    })
    .collect()
}

#[test]
fn frames_with_the_light_grid_equal_frames_tracing_every_light() {
    if test_context().is_none() {
        return;
    }
    let scene = lit_scene();
    let grid = render(&scene, true);
    let every = render(&scene, false);
    for (k, (a, b)) in grid.iter().zip(&every).enumerate() {
        let differ = common::differing_pixels(a, b);
        assert_eq!(differ, 0, "view {k}: {differ} pixels differ");
        let lit = a.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
        assert!(lit > a.len() / 8, "view {k} shows something: {lit} pixels");
    }
}

#[test]
fn shadows_through_the_lights_caster_roots_equal_those_through_the_whole_top_level() {
    if test_context().is_none() {
        return;
    }
    let scene = with_lights(crate::instancing::primitives_scene());
    let grid = render(&scene, true);
    let every = render(&scene, false);
    for (k, (a, b)) in grid.iter().zip(&every).enumerate() {
        let differ = common::differing_pixels(a, b);
        assert_eq!(differ, 0, "view {k}: {differ} pixels differ");
    }
}
