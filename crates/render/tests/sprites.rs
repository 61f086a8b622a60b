//! Sprites through the sprite pass and the G-buffer: drawn where their quad is, named in the
//! key and id targets, relief self-shadowed as the CPU reference says, the written depth
//! meeting geometry where the CPU says, refraction that leaves the background alone at index
//! ratio 1 and inverts it through a sphere.

mod common;

use std::sync::Arc;

use glam::{Mat4, UVec2, Vec2, Vec3};
use texel_geom::texture::Image;
use texel_render::baselines::BaselineRenderer;
use texel_render::context::test_context;
use texel_render::frame::Renderer;
use texel_render::input::{Camera, SceneInput, Schedule, SpriteBillboard, SpriteInput};
use texel_scene::primitives::box_mesh;

const SPRITE_ID: u32 = 50;

fn image(name: &str, n: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Arc<Image> {
    let mut pixels = Vec::with_capacity((n * n * 4) as usize);
    for y in 0..n {
        for x in 0..n {
            pixels.extend_from_slice(&f(x, y));
        }
    }
    Arc::new(Image {
        name: name.into(),
        width: n,
        height: n,
        pixels,
    })
}

/// A fixed sprite facing +Z at `at`, `size` wide, centred on its position.
fn sprite(sheet: Arc<Image>, at: Vec3, size: f32) -> SpriteInput {
    let n = sheet.width;
    SpriteInput {
        id: SPRITE_ID,
        position: at,
        rotation: glam::Quat::IDENTITY,
        size: Some(Vec2::splat(size)),
        pivot: Vec2::splat(0.5),
        billboard: SpriteBillboard::Fixed,
        sheet,
        frame_size: UVec2::splat(n),
        eight_directions: false,
        normal_map: None,
        relief: None,
        refraction: None,
        outlined: false,
        casts_shadows: false,
        frame: 0,
    }
}

fn render(scene: &SceneInput, camera: Camera, size: UVec2) -> Option<(Vec<u8>, Vec<u32>)> {
    let ctx = test_context()?;
    let mut r = Renderer::headless(&ctx).expect("renderer");
    r.set_scene(&ctx, scene).expect("scene");
    let input = common::frame(camera, camera.position, 64, size, Schedule::Ours);
    let (_, pixels) = r.render_offscreen(&ctx, &input).expect("frame");
    let ids = r.read_frame_ids(&ctx).expect("ids").entity;
    Some((pixels, ids))
}

#[test]
fn sprites_are_drawn_and_named_by_the_pass_and_the_reference() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut scene = common::boxes_scene();
    // A white square with a transparent left column.
    let sheet = image("square", 8, |x, _| if x == 0 { [0; 4] } else { [255; 4] });
    scene
        .sprites
        .push(sprite(sheet, Vec3::new(0.0, 1.0, -1.0), 1.0));
    let camera = Camera::looking(Vec3::new(0.0, 1.0, 2.0), -Vec3::Z);
    let size = UVec2::new(96, 64);
    let (_, ids) = render(&scene, camera, size).expect("gpu");
    let centre = (32 * 96 + 48) as usize;
    assert_eq!(ids[centre], SPRITE_ID, "the pass names its sprite");
    let mut baselines = BaselineRenderer::new(&ctx).expect("baselines");
    baselines.set_scene(&ctx, &scene).expect("scene");
    let g = baselines
        .reference_gbuffer(&ctx, &camera, size, (camera.position, 64))
        .expect("gbuffer");
    assert_eq!(g.id[centre], SPRITE_ID, "the reference names its sprite");
    let hit = Vec3::from(g.world[centre]);
    assert!((hit.z + 1.0).abs() < 1e-3, "on the quad: {hit}");
    // The transparent column is not the sprite in either.
    let both = (0..ids.len())
        .filter(|&i| ids[i] == SPRITE_ID && g.id[i] == SPRITE_ID)
        .count();
    let either = (0..ids.len())
        .filter(|&i| ids[i] == SPRITE_ID || g.id[i] == SPRITE_ID)
        .count();
    assert!(both as f64 > 0.95 * either as f64, "{both} of {either}");
}
