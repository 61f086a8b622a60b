// G-buffer: rasterizes the scene from a camera into screen targets, for the baseline methods
// (crates/render/src/baselines/gbuffer.rs). Per pixel: world position and view-axis depth
// (world), world normal, normal-mapped where the surface has a normal map (normal), object index + 1 (ids.x; 0 = sky) and albedo × vertex
// colour with the object flags in alpha, packed RGBA8 (ids.y). The evaluator's reference G-buffer is this pass at full resolution.

#include "lib/common.wgsl"
#include "lib/texture.wgsl"
#include "lib/raster.wgsl"

struct Camera {
    view_proj: mat4x4<f32>,
    // World-space view axis (unit) and, in w, its dot with the camera position.
    axis: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<storage, read> objects: array<Object>;

@vertex
fn vs(v: SceneVertex) -> VsOut {
    return raster_vertex(v, camera.view_proj);
}

struct FsOut {
    @location(0) world: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) ids: vec2<u32>,
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let obj = objects[in.object];
    let t = surface_uv(in);
    let pdx = dpdx(in.world);
    let pdy = dpdy(in.world);
    let s = surfaces[in.surface];
    var out: FsOut;
    out.world = vec4(in.world, dot(in.world, camera.axis.xyz) - camera.axis.w);
    out.normal = vec4(surface_shading_normal(s, surface_normal(in.normal), pdx, pdy, t), 0.0);
    let albedo = surface_albedo(obj, in.colour, surface_texture_colour(s, t));
    out.ids = vec2(in.object + 1u, pack4x8unorm(albedo));
    return out;
}
