// Present: the nearest-neighbour upscale of the internal-resolution frame to the output
// (crates/render/src/passes/present.rs). Texel-exact: each output pixel copies the internal
// pixel under its centre. The internal frame holds sRGB-encoded bytes in a plain unorm
// texture: `fs` copies them to a plain target, `fs_decode` decodes them for an sRGB one.
// With a palette, `fs_map` first maps each internal pixel to its palette colour, dithered by
// its texel's surface (the rank its alpha carries) or the texel its key names, into a
// texture of the internal size that `fs` then upscales.

#include "lib/fullscreen.wgsl"
#include "lib/common.wgsl"
#include "lib/palette.wgsl"

struct Sizes {
    output: vec2<u32>,
    internal: vec2<u32>,
    // Internal pixels per output pixel.
    scale: vec2<f32>,
    _pad: vec2<u32>,
}

@group(0) @binding(0) var frame: texture_2d<f32>;
@group(0) @binding(1) var<uniform> sizes: Sizes;
@group(0) @binding(2) var keys: texture_2d<u32>;
@group(0) @binding(3) var<uniform> palette: Palette;

@vertex
fn vs(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return vec4(fullscreen_xy(vi), 0.0, 1.0);
}

// The internal pixel under output pixel `pos`'s centre (one multiply: no per-pixel integer
// division, which CPU rasterizers run lane by lane); present.rs mirrors it.
fn source(pos: vec2<f32>) -> vec4<f32> {
    let src = min(vec2<u32>(pos * sizes.scale), sizes.internal - vec2(1u));
    return textureLoad(frame, src, 0);
}

@fragment
fn fs(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return source(pos.xy);
}

@fragment
fn fs_decode(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let c = source(pos.xy);
    return vec4(srgb_to_linear(c.rgb), c.a);
}

// Internal pixel `pos` of the frame in its palette colour (drawn at the internal size).
@fragment
fn fs_map(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let src = min(vec2<u32>(pos.xy), sizes.internal - vec2(1u));
    let c = textureLoad(frame, src, 0);
    let t = texel_threshold(textureLoad(keys, src, 0).r, src, palette.max_n, c.a);
    return vec4(palette.srgb[palette_index(srgb_to_linear(c.rgb), t)].rgb, 1.0);
}
