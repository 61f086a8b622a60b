// Capture: rasterizes the scene into one cube face of a probe. Per texel: world normal and
// Chebyshev depth from the probe origin (geo), object index + 1 (ids; 0 = sky), albedo and
// object flags. Crates/render/src/passes/capture.rs.

#include "lib/common.wgsl"
#include "lib/raster.wgsl"

struct FaceParams {
    view_proj: mat4x4<f32>,
    origin: vec4<f32>,
}

@group(0) @binding(0) var<uniform> face: FaceParams;
@group(0) @binding(1) var<storage, read> objects: array<Object>;

@vertex
fn vs(v: SceneVertex) -> VsOut {
    return raster_vertex(v, face.view_proj);
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
    out.albedo = surface_albedo(obj, in.colour);
    return out;
}
