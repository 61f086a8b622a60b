// Present: the nearest-neighbour upscale of the internal-resolution frame to the output
// (crates/render/src/passes/present.rs). Texel-exact: each output pixel copies one internal
// pixel.

struct Sizes {
    output: vec2<u32>,
    internal: vec2<u32>,
}

@group(0) @binding(0) var frame: texture_2d<f32>;
@group(0) @binding(1) var<uniform> sizes: Sizes;

@vertex
fn vs(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    let xy = vec2(f32((vi << 1u) & 2u), f32(vi & 2u)) * 2.0 - 1.0;
    return vec4(xy, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<u32>(pos.xy);
    let src = min(p * sizes.internal / sizes.output, sizes.internal - vec2(1u));
    return textureLoad(frame, src, 0);
}
