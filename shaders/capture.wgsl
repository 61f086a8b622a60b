// Capture: rasterizes the scene into one cube face of a probe. Per texel: world normal and
// Chebyshev depth from the probe origin (geo), object index + 1 (ids; 0 = sky), albedo and
// object flags. Crates/render/src/passes/capture.rs.

#include "lib/common.wgsl"

struct FaceParams {
    view_proj: mat4x4<f32>,
    origin: vec4<f32>,
}

@group(0) @binding(0) var<uniform> face: FaceParams;
@group(0) @binding(1) var<storage, read> objects: array<Object>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
    @location(3) colour: vec4<f32>,
}

@vertex
fn vs(
    @location(0) position: vec3<f32>,
    @location(1) object: u32,
    @location(2) normal: vec3<f32>,
    @location(3) colour: u32,
) -> VsOut {
    var out: VsOut;
    out.clip = face.view_proj * vec4(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.object = object;
    out.colour = unpack4x8unorm(colour);
    return out;
}

struct FsOut {
    @location(0) geo: vec4<f32>,
    @location(1) id: u32,
    @location(2) albedo: vec4<f32>,
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let obj = objects[in.object];
    var out: FsOut;
    out.geo = vec4(normalize(in.normal), chebyshev(in.world - face.origin.xyz));
    out.id = in.object + 1u;
    out.albedo = vec4(obj.albedo * in.colour.rgb, f32(obj.flags) / 255.0);
    return out;
}
