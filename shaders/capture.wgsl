// Capture: rasterizes the scene into one cube face of a probe. Per texel: world normal and
// Chebyshev depth from the probe origin (geo), object index + 1 (ids; 0 = sky), albedo and
// object flags. Crates/render/src/passes/capture.rs.

#include "lib/common.wgsl"
#include "lib/raster.wgsl"

struct FaceParams {
    view_proj: mat4x4<f32>,
    origin: vec4<f32>,
    // The cube face (0..6) and its texels per edge.
    face: u32,
    n: u32,
    _pad0: u32,
    _pad1: u32,
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

// The Chebyshev depth of the surface along this texel's centre ray. The interpolated world
// point is on the triangle but not exactly on that ray: the rasterizer snaps vertices to its
// sub-pixel grid (4 bits on SwiftShader, 8 on lavapipe), and far along a grazing floor a
// sixteenth of a texel puts the point hundredths of a unit off the floor where the shade pass
// rebuilds it from the centre ray, enough for the floor to shadow itself. So the depth is
// where the centre ray meets the triangle's plane (from the point's screen derivatives),
// which every driver agrees on; edge-on, the interpolated depth.
fn centre_depth(world: vec3<f32>, pixel: vec2<f32>) -> f32 {
    let q = world - face.origin.xyz;
    let interpolated = chebyshev(q);
    let uv = pixel * (2.0 / f32(face.n)) - 1.0;
    let centre = cube_dir(face.face, uv.x, uv.y);
    let plane = cross(dpdx(world), dpdy(world));
    let den = dot(centre, plane);
    if abs(den) <= 1e-3 * length(centre) * length(plane) {
        return interpolated;
    }
    // |centre| is 1 in the Chebyshev norm, so the ray parameter is the depth.
    let t = dot(q, plane) / den;
    if t <= 0.0 || abs(t - interpolated) > 0.25 * interpolated {
        return interpolated;
    }
    return t;
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let obj = objects[in.object];
    var out: FsOut;
    out.geo = vec4(surface_normal(in.normal), centre_depth(in.world, in.clip.xy));
    out.id = in.object + 1u;
    out.albedo = surface_albedo(obj, in.colour);
    return out;
}
