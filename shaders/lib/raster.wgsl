// Scene rasterization shared by the probe capture (capture.wgsl) and the baselines' G-buffer
// (gbuffer.wgsl): the vertex layout of `GpuScene::vertices`, what the vertex stage passes on,
// and the surface albedo. The includer includes lib/common.wgsl (for `Object`).

struct SceneVertex {
    @location(0) position: vec3<f32>,
    @location(1) object: u32,
    @location(2) normal: vec3<f32>,
    // Vertex colour, RGBA8.
    @location(3) colour: u32,
}

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
    @location(3) colour: vec4<f32>,
}

fn raster_vertex(v: SceneVertex, view_proj: mat4x4<f32>) -> VsOut {
    var out: VsOut;
    out.clip = view_proj * vec4(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.object = v.object;
    out.colour = unpack4x8unorm(v.colour);
    return out;
}

// Albedo × vertex colour (rgb) and the object flags (a, as flags / 255).
fn surface_albedo(obj: Object, colour: vec4<f32>) -> vec4<f32> {
    return vec4(obj.albedo * colour.rgb, f32(obj.flags) / 255.0);
}
