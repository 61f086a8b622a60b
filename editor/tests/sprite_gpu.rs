//! Sprites in the editor's viewport: picking a pixel of a sprite selects its entity, and the
//! animation clock (running in Play, stopped at 0 outside it) plays its frames.

use std::path::Path;

use glam::{UVec2, Vec3};
use texel_editor::camera::EditorCamera;
use texel_render::context::test_context;
use texel_render::input::Schedule;
use texel_runtime::load::load_level;

use crate::support;

#[test]
fn picking_a_sprite_selects_it() {
    let Some(ctx) = test_context() else {
        return;
    };
    let mut gpu = support::gpu_view(&ctx);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/sprites.ron");
    let level = load_level(&path).expect("sprites");
    let walker = level
        .scene
        .entities()
        .position(|e| {
            (level.scene.world().get::<&texel_scene::Name>(e)).is_ok_and(|n| n.0 == "Walker")
        })
        .expect("the walker");
    let mut camera = EditorCamera::default();
    // The walker's chest, from 4 units away.
    camera.focus(Vec3::new(2.2, 1.1, 9.0), 4.0);
    let size = UVec2::new(160, 120);
    for _ in 0..3 {
        gpu.render(&level, 0, camera.camera(), size, Schedule::Ours, 0.016)
            .expect("render");
    }
    let picked = gpu.pick(size / 2).expect("pick");
    assert_eq!(picked, Some(walker as u32 + 1), "the walker's entity id");
}
