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
    let far = view.inv_view_proj * vec4(in.ndc, NDC_FAR, 1.0);
    let dir = far.xyz / far.w - view.camera.xyz;
    let eye = view.slots[view.eye_slot];
    var fu = cube_face_uv(dir);
    if eye.half > 0.0 {
        // An orthographic eye looks along the camera's parallel rays: the pixel's ray meets
        // its face where the pixel's near point projects onto it.
        let near = view.inv_view_proj * vec4(in.ndc, NDC_NEAR, 1.0);
        let hit = frame_locate(slot_frame(eye), near.xyz / near.w);
        fu = FaceUv(hit.face, hit.uv);
        if any(abs(hit.uv) > vec2(1.0)) {
            return FsOut(vec4(linear_to_srgb(view.sky.rgb), 1.0), 0u);
        }
    }
    if (eye.draw_mask & (1u << fu.face)) == 0u {
        return FsOut(vec4(linear_to_srgb(view.sky.rgb), 1.0), 0u);
    }
    let t = texel_of_uv(fu.uv, eye.n);
    let lit = textureLoad(eye_lit, t, fu.face, 0);
    var key = 0u;
    var colour = lit.rgb;
    if textureLoad(eye_ids, t, fu.face, 0).r != 0u {
        key = texel_key(view.eye_slot, fu.face, t, view.max_n) + 1u;
        let d = textureLoad(eye_geo, t, fu.face, 0).w;
        var dist = d * length(dir) / chebyshev(dir);
        if eye.half > 0.0 {
            // Depth along the view from the eye's plane, which lies in the camera's.
            dist = d;
        }
        colour = hazed(colour, dist);
    }
    return FsOut(vec4(linear_to_srgb(colour), 1.0), key);
}
