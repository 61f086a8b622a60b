// Upscale: draws a shaded screen image (full or low resolution) at the output size with
// nearest sampling, offset by a sub-texel remainder (the snap method's restored camera
// motion). Writes the colour and the entity id of the texel each pixel shows; with a
// palette, the colour is the palette's, dithered by the source texel (the method's own art
// pixel, anchored where the method anchors it).
// crates/render/src/baselines/upscale.rs.

#include "lib/fullscreen.wgsl"
#include "lib/common.wgsl"
#include "lib/palette.wgsl"

struct Upscale {
    // Source texels per output pixel (x, y), then the source coordinate of output (0, 0).
    scale: vec2<f32>,
    offset: vec2<f32>,
    src_size: vec2<u32>,
    _pad: vec2<u32>,
}

@group(0) @binding(0) var<uniform> up: Upscale;
@group(0) @binding(1) var lit: texture_2d<f32>;
@group(0) @binding(2) var ids: texture_2d<u32>;
@group(0) @binding(3) var<storage, read> objects: array<Object>;
@group(0) @binding(4) var<uniform> palette: Palette;

@vertex
fn vs(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return vec4(fullscreen_xy(vi), 0.0, 1.0);
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) id: u32,
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> FsOut {
    let src = floor(frag.xy * up.scale + up.offset);
    let t = vec2<u32>(clamp(src, vec2(0.0), vec2<f32>(up.src_size) - 1.0));
    let object = textureLoad(ids, t, 0).r;
    var id = 0u;
    if object != 0u {
        id = objects[object - 1u].id;
    }
    var colour = textureLoad(lit, t, 0).rgb;
    if palette.count > 0u {
        colour = srgb_to_linear(palette.srgb[palette_index(colour, bayer4(t))].rgb);
    }
    return FsOut(vec4(colour, 1.0), id);
}
