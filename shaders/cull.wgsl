// Cull: turns the drawn faces' texels into a compact list of splat quads with indirect draw
// arguments. Skips sky, faces not drawn, and — in our schedule — texels whose quad lies
// outside the view frustum or faces away from the camera, and eye texels whose surface the
// grid probe already shows. The quad corners are computed here, once per texel, from the
// probe's data alone (never the camera), so they are bit-identical while the probe stays.
// crates/render/src/passes/cull.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"

struct Splat {
    // xyz: corner; c0.w key + 1, c1.w packed sRGB colour, c2.w role, c3.w unused (bitcast).
    c0: vec4<f32>,
    c1: vec4<f32>,
    c2: vec4<f32>,
    c3: vec4<f32>,
}

struct DrawArgs {
    index_count: u32,
    instance_count: atomic<u32>,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var<storage, read_write> splats: array<Splat>;
@group(0) @binding(2) var<storage, read_write> args: DrawArgs;
// The drawn (slot, face) pairs; the dispatch's z runs over them.
struct CullWork {
    count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    faces: array<vec4<u32>, 18>,
}
@group(0) @binding(3) var<uniform> work: CullWork;
@group(1) @binding(0) var geo0: texture_2d_array<f32>;
@group(1) @binding(1) var geo1: texture_2d_array<f32>;
@group(1) @binding(2) var geo2: texture_2d_array<f32>;
@group(1) @binding(3) var ids0: texture_2d_array<u32>;
@group(1) @binding(4) var ids1: texture_2d_array<u32>;
@group(1) @binding(5) var ids2: texture_2d_array<u32>;
@group(1) @binding(6) var lit0: texture_2d_array<f32>;
@group(1) @binding(7) var lit1: texture_2d_array<f32>;
@group(1) @binding(8) var lit2: texture_2d_array<f32>;

fn load_geo(slot: u32, t: vec2<u32>, f: u32) -> vec4<f32> {
    switch slot {
        case 0u: { return textureLoad(geo0, t, f, 0); }
        case 1u: { return textureLoad(geo1, t, f, 0); }
        default: { return textureLoad(geo2, t, f, 0); }
    }
}

fn load_id(slot: u32, t: vec2<u32>, f: u32) -> u32 {
    switch slot {
        case 0u: { return textureLoad(ids0, t, f, 0).r; }
        case 1u: { return textureLoad(ids1, t, f, 0).r; }
        default: { return textureLoad(ids2, t, f, 0).r; }
    }
}

fn load_lit(slot: u32, t: vec2<u32>, f: u32) -> vec4<f32> {
    switch slot {
        case 0u: { return textureLoad(lit0, t, f, 0); }
        case 1u: { return textureLoad(lit1, t, f, 0); }
        default: { return textureLoad(lit2, t, f, 0); }
    }
}

// Whether the stable probe in `slot` shows the surface point `p` of object `id`.
fn stable_shows(slot: u32, p: vec3<f32>, id: u32) -> bool {
    let s = view.slots[slot];
    let r = p - s.origin;
    let fu = cube_face_uv(r);
    if (s.draw_mask & (1u << fu.face)) == 0u {
        return false;
    }
    let t = texel_of_uv(fu.uv, s.n);
    if load_id(slot, t, fu.face) != id {
        return false;
    }
    return same_surface(chebyshev(r), load_geo(slot, t, fu.face).w, s.n);
}

// Whether every stable probe drawing pixels this frame shows the eye texel's surface.
fn eye_texel_covered(p: vec3<f32>, id: u32) -> bool {
    var covered = false;
    for (var s = 0u; s < 3u; s++) {
        if draws_pixels(view.slots[s].role) {
            if !stable_shows(s, p, id) {
                return false;
            }
            covered = true;
        }
    }
    return covered;
}


// Half-size toward one neighbour, in texels: tight (grazing-scaled by the angle between the
// surface and the probe ray, camera-independent) toward a similar one, a full texel otherwise.
fn half_size(similar: bool, cos_theta: f32) -> f32 {
    if !similar {
        return 1.0;
    }
    let c = max(cos_theta, 0.14);
    let tan_theta = sqrt(1.0 - c * c) / c;
    return min(0.575 + 0.05 * tan_theta, 1.0);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.z >= work.count {
        return;
    }
    let slot = work.faces[gid.z].x;
    let face = work.faces[gid.z].y;
    let s = view.slots[slot];
    let t = gid.xy;
    if s.role == ROLE_NONE || (s.draw_mask & (1u << face)) == 0u || t.x >= s.n || t.y >= s.n {
        return;
    }
    let id = load_id(slot, t, face);
    if id == 0u {
        return;
    }
    let geo = load_geo(slot, t, face);
    let uv = texel_center_uv(t, s.n);
    let ray = cube_dir(face, uv.x, uv.y);
    let d = geo.w;
    let p = probe_point(s.origin, ray, d);
    let texel_world = texel_world_size(d, s.n, ray);
    if view.schedule == 0u {
        if s.role != ROLE_EYE && !draws_pixels(s.role) {
            return;
        }
        if !quad_in_view(p, texel_world) {
            return;
        }
        // Back-facing surfaces cannot be seen (meshes are closed or one-sided).
        if dot(geo.xyz, view.camera.xyz - p) < -1.0e-3 * d {
            return;
        }
        if s.role == ROLE_EYE && eye_texel_covered(p, id) {
            return;
        }
    }
    let lit = load_lit(slot, t, face);
    let bits = u32(lit.a);
    let cos_theta = abs(dot(geo.xyz, normalize(ray)));
    let h = 2.0 / f32(s.n);
    let left = uv.x - half_size((bits & 1u) != 0u, cos_theta) * h;
    let right = uv.x + half_size((bits & 2u) != 0u, cos_theta) * h;
    let top = uv.y - half_size((bits & 4u) != 0u, cos_theta) * h;
    let bottom = uv.y + half_size((bits & 8u) != 0u, cos_theta) * h;
    let key = texel_key(slot, face, t, view.max_n) + 1u;
    let colour = pack4x8unorm(vec4(linear_to_srgb(hazed(lit.rgb, length(p - view.camera.xyz))), 1.0));
    var out: Splat;
    out.c0 = vec4(probe_point(s.origin, cube_dir(face, left, top), d), bitcast<f32>(key));
    out.c1 = vec4(probe_point(s.origin, cube_dir(face, right, top), d), bitcast<f32>(colour));
    out.c2 = vec4(probe_point(s.origin, cube_dir(face, right, bottom), d), bitcast<f32>(s.role));
    out.c3 = vec4(probe_point(s.origin, cube_dir(face, left, bottom), d), 0.0);
    let index = atomicAdd(&args.instance_count, 1u);
    if index < arrayLength(&splats) {
        splats[index] = out;
    }
}
