//! The records Rust and WGSL share, in one table: a test reflects every shader with naga
//! and compares each struct's size with its Rust twin's. Above the passes, the scene and the
//! baselines whose records it lists, so none of them imports another for it.

use crate::passes;

/// Byte sizes of the Rust records shared with WGSL, by their WGSL struct name and the shader
/// file that declares them: a test reflects every shader with naga and compares, so a field
/// added on one side only cannot slip through.
pub fn shared_layouts() -> Vec<(&'static str, &'static str, usize)> {
    vec![
        (
            "capture.wgsl",
            "FaceParams",
            passes::capture::FACE_PARAMS_SIZE,
        ),
        (
            "capture.wgsl",
            "TexInfo",
            size_of::<crate::textures::GpuTexInfo>(),
        ),
        (
            "gbuffer.wgsl",
            "Surface",
            size_of::<crate::textures::GpuSurface>(),
        ),
        (
            "capture.wgsl",
            "Terrain",
            size_of::<crate::gpu_scene::GpuTerrain>(),
        ),
        ("shade.wgsl", "ShadeFace", passes::shade::SHADE_FACE_SIZE),
        (
            "shade.wgsl",
            "BvhField",
            size_of::<crate::bvh::field::GpuField>(),
        ),
        (
            "shade.wgsl",
            "BvhFields",
            size_of::<crate::bvh::field::GpuFields>(),
        ),
        (
            "shade.wgsl",
            "ShadeGlobals",
            size_of::<passes::shade::ShadeGlobals>(),
        ),
        (
            "shade.wgsl",
            "Object",
            size_of::<crate::gpu_scene::GpuObject>(),
        ),
        (
            "shade.wgsl",
            "PointLight",
            size_of::<crate::gpu_scene::GpuPointLight>(),
        ),
        ("shade.wgsl", "BvhNode", size_of::<crate::bvh::BvhNode>()),
        (
            "shade.wgsl",
            "BvhInstance",
            size_of::<crate::gpu_scene::GpuBvhInstance>(),
        ),
        (
            "shade.wgsl",
            "BvhTriangle",
            size_of::<crate::bvh::BvhTriangle>(),
        ),
        (
            "cull.wgsl",
            "ViewGlobals",
            size_of::<crate::view::ViewGlobals>(),
        ),
        ("cull.wgsl", "SlotView", size_of::<crate::view::SlotView>()),
        ("cull.wgsl", "CullWork", passes::cull::CULL_WORK_SIZE),
        ("cull.wgsl", "DrawArgs", size_of::<passes::cull::DrawArgs>()),
        ("cull.wgsl", "Splat", passes::cull::SPLAT_BYTES as usize),
        ("present.wgsl", "Sizes", passes::present::SIZES_SIZE),
        ("runs.wgsl", "RunsFaces", passes::runs::RUNS_FACES_SIZE),
        (
            "moving.wgsl",
            "Motion",
            size_of::<crate::gpu_scene::GpuMotion>(),
        ),
        (
            "sprites.wgsl",
            "SpriteGlobals",
            size_of::<passes::sprites::SpriteGlobals>(),
        ),
        (
            "gbuffer_sprites.wgsl",
            "SpriteCamera",
            size_of::<crate::baselines::gbuffer::SpriteCamera>(),
        ),
        (
            "sprites.wgsl",
            "Sprite",
            size_of::<crate::gpu_sprites::GpuSprite>(),
        ),
        (
            "moving.wgsl",
            "LightGlobals",
            size_of::<passes::moving::LightGlobals>(),
        ),
    ]
}
