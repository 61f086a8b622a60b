// G-buffer: rasterizes the scene from a camera into screen targets, for the baseline methods
// (crates/render/src/baselines/gbuffer.rs). Per pixel: world position and view-axis depth
// (world), world normal (normal), object index + 1 (ids.x; 0 = sky) and albedo × vertex
// colour with the object flags in alpha, packed RGBA8 (ids.y). The evaluator's reference G-buffer is this pass at full resolution.

#include "lib/common.wgsl"

struct Camera {
    view_proj: mat4x4<f32>,
    // World-space view axis (unit) and, in w, its dot with the camera position.
    axis: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
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
    out.clip = camera.view_proj * vec4(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.object = object;
    out.colour = unpack4x8unorm(colour);
    return out;
}

struct FsOut {
    @location(0) world: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) ids: vec2<u32>,
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let obj = objects[in.object];
    var out: FsOut;
    out.world = vec4(in.world, dot(in.world, camera.axis.xyz) - camera.axis.w);
    out.normal = vec4(normalize(in.normal), 0.0);
    let albedo = vec4(obj.albedo * in.colour.rgb, f32(obj.flags) / 255.0);
    out.ids = vec2(in.object + 1u, pack4x8unorm(albedo));
    return out;
}
