// Background: a fullscreen triangle at the far plane, drawn after the splats with a depth
// test, so it shades only the pixels no quad covered. Each shows the eye probe's lit texel in
// its view direction (the sky where the eye probe saw none), sRGB-encoded like the splats.
// crates/render/src/passes/background.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"
#include "lib/fullscreen.wgsl"

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var eye_ids: texture_2d_array<u32>;
@group(0) @binding(2) var eye_lit: texture_2d_array<f32>;
@group(0) @binding(3) var eye_geo: texture_2d_array<f32>;

@vertex
fn vs(@builtin(vertex_index) vi: u32) -> FullscreenOut {
    return fullscreen(vi, NDC_FAR);
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
}

@fragment
fn fs(in: FullscreenOut) -> FsOut {
    let e = eye_ray(in.ndc);
    let eye = view.slots[view.eye_slot];
    if e.face > 5u || (eye.draw_mask & (1u << e.face)) == 0u {
        return FsOut(vec4(linear_to_srgb(view.sky.rgb), 1.0), 0u);
    }
    let t = texel_of_uv(e.uv, eye.n);
    let lit = textureLoad(eye_lit, t, e.face, 0);
    var key = 0u;
    var colour = lit.rgb;
    if textureLoad(eye_ids, t, e.face, 0).r != 0u {
        key = texel_key(view.eye_slot, e.face, t, view.max_n) + 1u;
        let d = textureLoad(eye_geo, t, e.face, 0).w;
        colour = hazed(colour, length(eye_point(e, d) - e.start));
    }
    return FsOut(vec4(linear_to_srgb(colour), 1.0), key);
}
