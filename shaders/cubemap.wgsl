// Cubemap: draws a camera-centred cubemap, captured and shaded this frame, at the output
// size: each pixel shows the lit texel (nearest) in its view direction, and that texel's
// entity id. crates/render/src/baselines/cubemap.rs.

#include "lib/common.wgsl"
#include "lib/fullscreen.wgsl"

struct CubeView {
    inv_view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    sky: vec4<f32>,
    n: u32,
    // Haze density per world unit (0 = none), as lib/view.wgsl `hazed`.
    haze: f32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> cv: CubeView;
@group(0) @binding(1) var lit: texture_2d_array<f32>;
@group(0) @binding(2) var ids: texture_2d_array<u32>;
@group(0) @binding(3) var<storage, read> objects: array<Object>;
@group(0) @binding(4) var geo: texture_2d_array<f32>;

@vertex
fn vs(@builtin(vertex_index) vi: u32) -> FullscreenOut {
    return fullscreen(vi, 0.0);
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) id: u32,
}

@fragment
fn fs(in: FullscreenOut) -> FsOut {
    let far = cv.inv_view_proj * vec4(in.ndc, 1.0, 1.0);
    let dir = far.xyz / far.w - cv.eye.xyz;
    let fu = cube_face_uv(dir);
    let t = texel_of_uv(fu.uv, cv.n);
    let object = textureLoad(ids, t, fu.face, 0).r;
    var colour = textureLoad(lit, t, fu.face, 0).rgb;
    var id = 0u;
    if object != 0u {
        id = objects[object - 1u].id;
        let dist = textureLoad(geo, t, fu.face, 0).w * length(dir) / chebyshev(dir);
        colour = mix(colour, cv.sky.rgb, 1.0 - exp(-cv.haze * dist));
    }
    return FsOut(vec4(colour, 1.0), id);
}
