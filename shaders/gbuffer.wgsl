// G-buffer: rasterizes the scene from a camera into screen targets, for the baseline methods
// (crates/render/src/baselines/gbuffer.rs). Per pixel: world position and view-axis depth
// (world), world normal, normal-mapped where the surface has a normal map (normal), object index + 1 (ids.x; 0 = sky) and albedo × vertex
// colour with the object flags in alpha, packed RGBA8 (ids.y). The evaluator's reference G-buffer is this pass at full resolution.

#include "lib/common.wgsl"
#include "lib/texture.wgsl"
#include "lib/terrain.wgsl"
#include "lib/raster.wgsl"
#include "lib/motion.wgsl"

struct Camera {
    view_proj: mat4x4<f32>,
    // World-space view axis (unit) and, in w, its dot with the camera position.
    axis: vec4<f32>,
    // Clip → world, for the rays through neighbouring pixels (texture footprints).
    inv_view_proj: mat4x4<f32>,
    // Target size in pixels (xy); z 1 under an orthographic camera.
    size: vec4<f32>,
    // The camera position (bands of terrain pixels are measured from it).
    eye: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<storage, read> objects: array<Object>;
@group(0) @binding(7) var<storage, read> motions: array<Motion>;

@vertex
fn vs(v: SceneVertex, i: SceneInstance) -> VsOut {
    // Animated objects where they are this frame (their UV gradients are covectors: the
    // normal matrix carries them too); objects drawn from a shared mesh where they stand.
    var w = instance_vertex(v, i);
    let flags = objects[w.object].flags;
    if is_animated(flags) {
        let m = motions[flags >> 8u];
        w.position = (m.to_now * vec4(v.position, 1.0)).xyz;
        w.normal = (m.normal_now * vec4(v.normal, 0.0)).xyz;
        w.grad_u = (m.normal_now * vec4(v.grad_u, 0.0)).xyz;
        w.grad_v = (m.normal_now * vec4(v.grad_v, 0.0)).xyz;
    }
    return raster_vertex(w, camera.view_proj);
}

struct FsOut {
    @location(0) world: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) ids: vec2<u32>,
}

// Where the ray through target pixel `pixel` meets the plane through `p` with normal `n`
// (perspective or orthographic: the ray runs from the near plane to the far one).
fn pixel_hit(pixel: vec2<f32>, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let ndc = vec2(pixel.x / camera.size.x * 2.0 - 1.0, 1.0 - pixel.y / camera.size.y * 2.0);
    let a = camera.inv_view_proj * vec4(ndc, 0.0, 1.0);
    let b = camera.inv_view_proj * vec4(ndc, 1.0, 1.0);
    let o = a.xyz / a.w;
    return plane_hit(p, n, o, b.xyz / b.w - o);
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let obj = objects[in.object];
    let plane = surface_plane_normal(in);
    let centre = pixel_hit(in.clip.xy, in.world, plane);
    let fx = pixel_hit(in.clip.xy + vec2(1.0, 0.0), in.world, plane) - centre;
    let fy = pixel_hit(in.clip.xy + vec2(0.0, 1.0), in.world, plane) - centre;
    let t = surface_uv(in, fx, fy);
    let s = surfaces[in.surface];
    var out: FsOut;
    out.world = vec4(in.world, dot(in.world, camera.axis.xyz) - camera.axis.w);
    out.normal = vec4(surface_shading_normal(s, surface_normal(in.normal), in.grad_u, in.grad_v, t), 0.0);
    var albedo = surface_albedo(obj, in.colour, surface_texture_colour(s, t));
    if (obj.flags & FLAG_TERRAIN) != 0u {
        // Screen methods measure bands from the camera, with no texel bound: the seed's own
        // method. An orthographic camera takes none (its finest pixels everywhere), as an
        // orthographic probe's texels do.
        let ortho = select(0.0, 1.0e-9, camera.size.z > 0.5);
        let sizing = BandFrom(camera.eye.xyz, 1.0e9, ortho);
        let terrain = terrain_colour(terrains[obj.flags >> 8u], centre, sizing);
        albedo = vec4(albedo.rgb * terrain, albedo.a);
    }
    out.ids = vec2(in.object + 1u, pack4x8unorm(albedo));
    return out;
}
