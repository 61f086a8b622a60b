// Animated objects (crates/render/src/gpu_scene.rs `GpuMotion`, `FLAG_ANIMATED`): their
// vertices are uploaded at the base pose, and each frame's record maps the base pose to where
// the object is now. The includer includes lib/common.wgsl and declares
// `motions: array<Motion>`.

struct Motion {
    // Base-pose world (where the vertex buffer holds it) → world now.
    to_now: mat4x4<f32>,
    // Its normal matrix (upper 3×3 used).
    normal_now: mat4x4<f32>,
    // Base-pose world → the object's rigid frame (its base translation and rotation).
    frame: mat4x4<f32>,
    // The rigid frame → base-pose world.
    frame_inv: mat4x4<f32>,
    // The object's bounds centre in base-pose world (xyz).
    centre: vec4<f32>,
}

const FLAG_ANIMATED: u32 = 8u;

// Whether object flags `flags` mark an animated object.
fn is_animated(flags: u32) -> bool {
    return (flags & (FLAG_ANIMATED | FLAG_TERRAIN)) == FLAG_ANIMATED;
}
