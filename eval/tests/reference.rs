//! The two reference G-buffers agree: the GPU raster (the default) and the CPU ray cast
//! (no GPU needed) see the same object at almost every pixel and the same world point there.
//! They differ only on silhouettes, where raster coverage and a ray through the pixel centre
//! can pick different sides.

use std::path::Path;

use glam::{UVec2, Vec3};
use texel_eval::gpu::GpuReference;
use texel_eval::reference::CpuScene;
use texel_eval::runner::{RefFrame, ReferenceSource};
use texel_render::context::test_context;
use texel_runtime::frame_plan::{scene_input, start_camera};
use texel_runtime::load::load_level;

#[test]
fn gpu_and_cpu_references_agree_off_silhouettes() {
    let Some(ctx) = test_context() else {
        return;
    };
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/stone_circle.ron");
    let level = load_level(&file).expect("level loads");
    let scene = scene_input(&level);
    let camera = start_camera(&level.scene);
    let size = UVec2::new(160, 90);
    let gpu = GpuReference::new(&ctx, &scene)
        .expect("reference renderer")
        .reference(
            &camera,
            size,
            &RefFrame {
                poses: &[],
                sprites: &[],
                sprite_eye: (camera.position, 64),
            },
        )
        .expect("gpu reference");
    let cpu = CpuScene::new(&scene).gbuffer(&camera, size);
    let n = gpu.id.len();
    let same = (0..n).filter(|&i| gpu.id[i] == cpu.id[i]).count();
    let geometry = gpu.id.iter().filter(|i| **i != 0).count();
    assert!(geometry > n / 4, "the start view shows the level");
    // Measured: all 14,400 pixels agree at the player start; allow 1 % for silhouettes.
    assert!(same as f64 > 0.99 * n as f64, "{same} of {n} agree");
    let far = (0..n)
        .filter(|&i| gpu.id[i] != 0 && gpu.id[i] == cpu.id[i])
        .filter(|&i| {
            let d = (Vec3::from(gpu.world[i]) - Vec3::from(cpu.world[i])).length();
            let dist = (Vec3::from(cpu.world[i]) - camera.position).length();
            d > 0.01 * dist
        })
        .count();
    assert!(
        far * 100 < geometry,
        "{far} of {geometry} world points disagree"
    );
}
