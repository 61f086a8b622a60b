// Capture: rasterizes the scene into one cube face of a probe. Per texel: world normal and
// Chebyshev depth from the probe origin (geo), object index + 1 (ids; 0 = sky), albedo (×
// the texture, sampled for the probe texel's footprint) and object flags, the normal-mapped
// normal when the surface has a normal map (shading). Then `colour_terrain` colours the
// face's terrain texels, once each (in the fragment stage the colour of a distant terrain's
// tiny triangles was worked out for whole blocks of pixels the triangle barely touched).
// Crates/render/src/passes/capture.rs.

#include "lib/common.wgsl"
#include "lib/texture.wgsl"
#include "lib/terrain.wgsl"
#include "lib/raster.wgsl"

struct FaceParams {
    view_proj: mat4x4<f32>,
    origin: vec4<f32>,
    // The cube face (0..6) and its texels per edge.
    face: u32,
    n: u32,
    // 0: albedo; 1: texture-density debug colour.
    mode: u32,
    // An orthographic probe's frame (lib/common.wgsl `ProbeFrame`): half extent, 0 for a cube.
    half: f32,
    // Where terrain bands are measured from: the grid probe's origin (for the eye probe's
    // faces too, so terrain colours agree between the probes).
    band_origin: vec4<f32>,
    right: vec4<f32>,
    down: vec4<f32>,
    forward: vec4<f32>,
    // The texels drawn: columns x..z, rows y..w (the eye's faces: the view's part).
    rect: vec4<u32>,
}

fn capture_frame() -> ProbeFrame {
    return ProbeFrame(face.origin.xyz, face.half, face.right.xyz, face.down.xyz, face.forward.xyz);
}

// Face coordinates of face pixel `pixel` (texel centres at half-integers).
fn pixel_uv(pixel: vec2<f32>) -> vec2<f32> {
    return pixel * (2.0 / f32(face.n)) - 1.0;
}

@group(0) @binding(0) var<uniform> face: FaceParams;
@group(0) @binding(1) var<storage, read> objects: array<Object>;

@vertex
fn vs(v: SceneVertex, i: SceneInstance) -> VsOut {
    return raster_vertex(instance_vertex(v, i), face.view_proj);
}

struct FsOut {
    @location(0) geo: vec4<f32>,
    @location(1) id: u32,
    @location(2) albedo: vec4<f32>,
    // pack4x8snorm(normal-mapped normal, 1), or 0 when the geometric normal is the one.
    @location(3) shading: u32,
}

// The Chebyshev depth of the surface along this texel's centre ray. The interpolated world
// point is on the triangle but not exactly on that ray: the rasterizer snaps vertices to its
// sub-pixel grid (4 bits on SwiftShader, 8 on lavapipe), and far along a grazing floor a
// sixteenth of a texel puts the point hundredths of a unit off the floor where the shade pass
// rebuilds it from the centre ray, enough for the floor to shadow itself. So the depth is
// where the centre ray meets the triangle's plane (from the point's screen derivatives),
// which every driver agrees on; edge-on, the interpolated depth.
fn centre_depth(world: vec3<f32>, pixel: vec2<f32>, pdx: vec3<f32>, pdy: vec3<f32>) -> f32 {
    let fr = capture_frame();
    let uv = pixel_uv(pixel);
    let q = world - frame_ray_start(fr, uv);
    let interpolated = frame_locate(fr, world).depth;
    let centre = frame_ray(fr, face.face, uv);
    let plane = cross(pdx, pdy);
    let den = dot(centre, plane);
    if abs(den) <= 1e-3 * length(centre) * length(plane) {
        return interpolated;
    }
    // |centre| is 1 in the Chebyshev norm (or `forward`, a unit vector), so the ray
    // parameter is the depth.
    let t = dot(q, plane) / den;
    if t <= 0.0 || abs(t - interpolated) > 0.25 * interpolated {
        return interpolated;
    }
    return t;
}

// The texel-density debug colour of an untextured surface.
const UNTEXTURED_DENSITY: vec3<f32> = vec3(0.35);

// The texel-density debug colour: green where a probe texel (an art pixel) spans one texture
// pixel (within a factor √2), blue where the texture is magnified (a texture pixel spans
// several art pixels), red where minified, deeper the further from 1:1 (up to 2^3); grey
// untextured.
fn density_colour(s: Surface, t: SurfaceUv) -> vec3<f32> {
    var index = s.albedo;
    if index == NO_TEXTURE {
        index = s.normal;
    }
    if index == NO_TEXTURE {
        return UNTEXTURED_DENSITY;
    }
    let lod = tex_lod(tex_infos[index], t.dx, t.dy);
    if abs(lod) <= 0.5 {
        return vec3(0.1, 0.75, 0.1);
    }
    let k = clamp((abs(lod) - 0.5) / 2.5, 0.0, 1.0);
    if lod < 0.0 {
        return mix(vec3(0.35, 0.55, 1.0), vec3(0.02, 0.05, 0.8), k);
    }
    return mix(vec3(1.0, 0.6, 0.25), vec3(0.8, 0.02, 0.02), k);
}

// The direction of the ray through face pixel `pixel` (texel centres at half-integers).
fn pixel_ray(pixel: vec2<f32>) -> vec3<f32> {
    return frame_ray(capture_frame(), face.face, pixel_uv(pixel));
}

// Where that ray starts.
fn pixel_start(pixel: vec2<f32>) -> vec3<f32> {
    return frame_ray_start(capture_frame(), pixel_uv(pixel));
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let obj = objects[in.object];
    let pdx = dpdx(in.world);
    let pdy = dpdy(in.world);
    var depth = centre_depth(in.world, in.clip.xy, pdx, pdy);
    // The probe texel's footprint on the triangle's plane: where the rays through this texel
    // and its neighbours meet it.
    let o = pixel_start(in.clip.xy);
    let plane = surface_plane_normal(in);
    var centre = plane_hit(in.world, plane, o, pixel_ray(in.clip.xy));
    var n = surface_normal(in.normal);
    if (obj.flags & FLAG_TERRAIN) != 0u {
        // A terrain chunk may be drawn at a coarser level (gpu_scene.rs `chunk_lod`): the
        // texel stores the point and normal of the full-detail surface on its centre ray,
        // the surface shadow rays and G-buffers see, so every level stores the same points.
        // At level 0 the first step finds the plane hit already there: the rasterizer's
        // normal is the one (no normal reads for most fragments).
        let tr = terrains[obj.flags >> 8u];
        let ray = pixel_ray(in.clip.xy);
        let refined = terrain_level0_hit(tr, o, ray, depth);
        if abs(refined - depth) > 1e-5 * max(depth, 1.0) {
            depth = refined;
            centre = o + ray * depth;
            n = surface_normal(terrain_normal(tr, centre.xz - tr.corner.xz));
        }
    }
    let px = in.clip.xy + vec2(1.0, 0.0);
    let py = in.clip.xy + vec2(0.0, 1.0);
    let fx = plane_hit(in.world, plane, pixel_start(px), pixel_ray(px)) - centre;
    let fy = plane_hit(in.world, plane, pixel_start(py), pixel_ray(py)) - centre;
    let t = surface_uv(in, fx, fy);
    let s = surfaces[in.surface];
    var out: FsOut;
    out.geo = vec4(n, depth);
    out.id = in.object + 1u;
    out.albedo = surface_albedo(obj, in.colour, surface_texture_colour(s, t));
    if (obj.flags & FLAG_TERRAIN) != 0u {
        // Coloured by `terrain_colour` once the face is drawn.
        out.albedo = terrain_albedo(obj, vec3(1.0));
    }
    if face.mode == 1u {
        out.albedo = vec4(density_colour(s, t), out.albedo.a);
    }
    out.shading = 0u;
    if s.normal != NO_TEXTURE {
        out.shading = pack4x8snorm(vec4(surface_shading_normal(s, n, in.grad_u, in.grad_v, t), 1.0));
    }
    return out;
}

// What the vertex stage of a plain terrain chunk (crates/render/src/gpu_scene.rs
// `DrawRange::terrain`: no texture, no normal map) reads, and passes on: its point and object
// alone. The fragment finds the rest on the heightmap, so lavapipe, whose cost per triangle
// grows with the varyings it sets up, draws the terrain's many small triangles at half the
// cost of `vs`.
struct PointVertex {
    @location(0) position: vec3<f32>,
    @location(1) object: u32,
}

struct TerrainVsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) object: u32,
}

@vertex
fn vs_terrain(v: PointVertex) -> TerrainVsOut {
    return TerrainVsOut(face.view_proj * vec4(v.position, 1.0), v.position, v.object);
}

// `fs` for a plain terrain: the full-detail surface's point on the texel's centre ray and
// its normal there (what `fs` stores for a terrain at any level), the object, and the
// material's albedo (coloured by `colour_terrain` once the face is drawn).
@fragment
fn fs_terrain(in: TerrainVsOut) -> FsOut {
    let depth0 = centre_depth(in.world, in.clip.xy, dpdx(in.world), dpdy(in.world));
    let obj = objects[in.object];
    let tr = terrains[obj.flags >> 8u];
    let o = pixel_start(in.clip.xy);
    let ray = pixel_ray(in.clip.xy);
    let depth = terrain_level0_hit(tr, o, ray, depth0);
    let centre = o + ray * depth;
    var out: FsOut;
    out.geo = vec4(surface_normal(terrain_normal(tr, centre.xz - tr.corner.xz)), depth);
    out.id = in.object + 1u;
    out.albedo = terrain_albedo(obj, vec3(1.0));
    if face.mode == 1u {
        out.albedo = vec4(UNTEXTURED_DENSITY, out.albedo.a);
    }
    out.shading = 0u;
    return out;
}

// A terrain texel's albedo: the material's albedo × the terrain's colour there, and the
// object flags.
fn terrain_albedo(obj: Object, colour: vec3<f32>) -> vec4<f32> {
    return vec4(obj.albedo * colour, f32(obj.flags & 0xffu) / 255.0);
}

// The face just drawn (this capture's layer of the slot).
@group(1) @binding(0) var drawn_geo: texture_2d<f32>;
@group(1) @binding(1) var drawn_ids: texture_2d<u32>;
@group(1) @binding(2) var drawn_albedo: texture_storage_2d<rgba8unorm, write>;

// Colours the terrain texels of the face just drawn, inside `face.rect`: the terrain pixel
// holding the point on the texel's centre ray at its stored depth (bands from
// `face.band_origin`).
@compute @workgroup_size(8, 8)
fn colour_terrain(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = gid.xy + face.rect.xy;
    if any(t >= min(face.rect.zw, vec2(face.n))) {
        return;
    }
    let id = textureLoad(drawn_ids, t, 0).r;
    if id == 0u {
        return;
    }
    let obj = objects[id - 1u];
    if (obj.flags & FLAG_TERRAIN) == 0u {
        return;
    }
    let pixel = vec2<f32>(t) + 0.5;
    let centre = pixel_start(pixel) + pixel_ray(pixel) * textureLoad(drawn_geo, t, 0).w;
    let sizing = band_from(face.band_origin.xyz, f32(face.n), face.half);
    let colour = terrain_colour(terrains[obj.flags >> 8u], centre, sizing);
    textureStore(drawn_albedo, t, terrain_albedo(obj, colour));
}
