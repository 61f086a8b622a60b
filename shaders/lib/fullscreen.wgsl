// The fullscreen triangle of the passes that cover the screen (background, march, present,
// and the baselines' cubemap and upscale): three vertices whose triangle covers NDC
// [-1, 1]², drawn with `draw(0..3, 0..1)` and no vertex buffer.

// NDC xy of vertex `vi` (0, 1, 2).
fn fullscreen_xy(vi: u32) -> vec2<f32> {
    return vec2(f32((vi << 1u) & 2u), f32(vi & 2u)) * 2.0 - 1.0;
}

// A fullscreen vertex at NDC depth `z`, passing its NDC xy on for unprojecting.
struct FullscreenOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

fn fullscreen(vi: u32, z: f32) -> FullscreenOut {
    let xy = fullscreen_xy(vi);
    return FullscreenOut(vec4(xy, z, 1.0), xy);
}
