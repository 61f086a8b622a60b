// Sprite shade: lights every texel of every sprite in view once per frame (as the shade
// pass lights probe texels), for the grid probe's copy and, during a crossfade, the
// previous probe's: the texel at its centre on the quad turned toward that probe (suns and
// points, BVH shadows, the normal map; relief: the texel's ray from the probe's origin
// marched into the depth map, self-shadowed per light; refraction: the bent ray marched
// through the grid probe's cube faces), posterized, one band darker at alpha edges. Writes
// per texel its sRGB colour (alpha 0: nothing there) and how far along its ray the relief
// surface lies, which the sprite pass (shaders/sprites.wgsl) reads per pixel.
// crates/render/src/passes/sprites.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"
#include "lib/bvh.wgsl"
#include "lib/lighting.wgsl"
#include "lib/slots.wgsl"

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var<storage, read> sprites: array<Sprite>;
@group(0) @binding(2) var sprite_frames: texture_2d_array<f32>;
@group(0) @binding(3) var<uniform> globals: SpriteGlobals;
@group(0) @binding(4) var<storage, read> points: array<PointLight>;
fn point_record(i: u32) -> PointLight {
    return points[i];
}
@group(0) @binding(5) var<storage, read_write> lit: array<vec2<u32>>;
// Per sprite and copy, what its texels were last lit for (crates/render/src/gpu_sprites.rs).
@group(0) @binding(6) var<storage, read_write> lit_keys: array<vec4<u32>>;
@group(2) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(2) @binding(1) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(2) @binding(2) var<storage, read> bvh_instances: array<BvhInstance>;
@group(2) @binding(3) var<uniform> bvh_fields: BvhFields;
@group(2) @binding(4) var bvh_field_data: texture_2d_array<f32>;

#include "lib/sprite.wgsl"
#include "lib/sprite_view.wgsl"

// Whether the sheet is empty at texel `t` + `d` of the frame (outside the frame is empty).
fn empty_at(s: Sprite, q: SpriteQuad, t: vec2<u32>, d: vec2<i32>) -> bool {
    let p = vec2<i32>(t) + d;
    if any(p < vec2(0)) || any(p >= vec2<i32>(s.frame_px)) {
        return true;
    }
    return sprite_texel(s.layers.x, q, vec2<u32>(p)).a < 0.5;
}

// The grid probe's shaded colour where the ray from `p` along `dir` first passes behind the
// surface it stores (the refraction's background): marched in growing steps; the last
// direction's texel when nothing is met.
fn probe_background(p: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    let slot = view.grid_slot;
    let g = view.slots[slot];
    let n = max(g.n, 1u);
    var t = 0.02;
    var colour = view.sky.rgb;
    for (var i = 0u; i < 48u; i++) {
        let x = p + dir * t;
        let fu = frame_locate(slot_frame(g), x);
        let tx = texel_of_uv(fu.uv, n);
        let stored = load_geo(slot, tx, fu.face).w;
        colour = load_lit(slot, tx, fu.face).rgb;
        if stored > 0.0 && fu.depth >= stored {
            return colour;
        }
        t *= 1.25;
    }
    return colour;
}

// What texel `t` of sprite `s` (quad `q`, cells of `k` texels, drawn for `role`) shows: its
// sRGB colour (alpha 0: nothing) and the relief surface's distance along the texel's ray.
fn shade_texel(s: Sprite, q: SpriteQuad, role: u32, t_in: vec2<u32>, k: u32) -> vec2<u32> {
    var t = t_in;
    let uv0 = (vec2<f32>(t) + 0.5) / vec2<f32>(s.frame_px);
    let p0 = sprite_point(q, uv0);
    let eye = eye_for(s, role);
    var p = p0;
    var c = 0.0;
    var t_hit = 0.0;
    var uv = uv0;
    let relief = s.layers.z != NO_LAYER && s.relief_depth > 0.0;
    let ray = normalize(p0 - eye);
    if relief {
        let h = relief_march(s, q, uv0, ray);
        if !h.hit {
            return vec2(0u);
        }
        uv = h.uv;
        t = sprite_texel_at(uv, s.frame_px);
        p = p0 + ray * h.t;
        t_hit = h.t;
        c = -dot(ray, q.front) * h.t;
    }
    let texel = sprite_texel(s.layers.x, q, t);
    if texel.a < 0.5 {
        return vec2(0u);
    }
    // The sheet holds sRGB-encoded colours.
    let albedo = srgb_to_linear(texel.rgb);
    let normal = sprite_normal(s, q, t);
    var colour: vec3<f32>;
    if s.layers.w != NO_LAYER && s.index_ratio > 0.0 && relief {
        // Refraction: into the volume at the front surface, out through the back one (its
        // normal taken as the front's mirrored through the quad's plane, exact for volumes
        // symmetric about it, as the paper's sphere), then on through the probe's cube.
        var d1 = refract(ray, normal, s.index_ratio);
        if dot(d1, d1) < 1.0e-8 {
            d1 = reflect(ray, normal);
        }
        var exit = p;
        let dc = -dot(d1, q.front);
        if dc > 1.0e-4 {
            let duv = vec2(dot(d1, q.right) / q.size.x, -dot(d1, q.up) / q.size.y);
            let steps = clamp(max(s.frame_px.x, s.frame_px.y), 8u, 64u);
            let t_max = (s.relief_depth - c) / dc;
            var k = 0.0;
            for (var i = 1u; i <= steps; i++) {
                k = t_max * f32(i) / f32(steps);
                let at = uv + duv * k;
                if any(at < vec2(0.0)) || any(at >= vec2(1.0)) {
                    break;
                }
                let back = sprite_texel(s.layers.w, q, sprite_texel_at(at, s.frame_px)).r;
                if c + dc * k >= back * s.relief_depth {
                    break;
                }
            }
            exit = p + d1 * k;
        }
        let nb = normal - 2.0 * dot(normal, q.front) * q.front;
        var d2 = refract(d1, -nb, 1.0 / s.index_ratio);
        if dot(d2, d2) < 1.0e-8 {
            d2 = reflect(d1, -nb);
        }
        colour = probe_background(exit, normalize(d2)) * albedo;
    } else {
        var light = globals.ambient.rgb;
        let offset = max(SHADOW_OFFSET, 0.02 * max(q.size.x / f32(s.frame_px.x), q.size.y / f32(s.frame_px.y)));
        let start = p + normal * offset;
        for (var i = 0u; i < light_count(); i++) {
            let r = light_ray(i, p);
            let ndl = dot(normal, r.dir);
            if ndl <= 0.0 || r.reach <= 0.0 {
                continue;
            }
            if relief && relief_shadowed(s, q, uv, c, r.dir) {
                continue;
            }
            if !bvh_any_hit(start, r.dir, light_reach(r, offset)) {
                light += r.colour * ndl * r.fall * r.fall;
            }
        }
        colour = albedo * light;
    }
    // Outlines at the picture's edges, as the probes' silhouettes: one band darker.
    var shift = 0.0;
    if (s.flags & SPRITE_OUTLINED) != 0u
        && (empty_at(s, q, t_in, vec2(i32(k), 0)) || empty_at(s, q, t_in, vec2(-i32(k), 0))
            || empty_at(s, q, t_in, vec2(0, i32(k))) || empty_at(s, q, t_in, vec2(0, -i32(k)))) {
        shift = -1.0;
    }
    let shaded = posterize(colour, globals.bands, shift);
    // Haze is the draw's (it depends on the camera; these texels are kept while it moves).
    return vec2(pack4x8unorm(vec4(linear_to_srgb(shaded), 1.0)), bitcast<u32>(t_hit));
}

// What a sprite's texels for a copy depend on besides the scene: the probe it turns toward
// (origin, face resolution),
// its position and frame, the look, and the epoch (which moves every frame while something
// the cache cannot follow changes: moving shadows, a camera-facing quad). Never all zero, the
// state of a fresh buffer.
fn lit_key(s: Sprite, origin: vec3<f32>, n: u32) -> vec4<u32> {
    var h = (s.frame ^ (n << 16u)) * 0x9e3779b1u;
    h = (h ^ bitcast<u32>(s.position.x)) * 0x85ebca6bu;
    h = (h ^ bitcast<u32>(s.position.y)) * 0xc2b2ae35u;
    h = (h ^ bitcast<u32>(s.position.z)) * 0x27d4eb2fu;
    h = (h ^ globals.epoch) * 0x165667b1u;
    h = (h ^ globals.bands ^ bitcast<u32>(globals.ambient.r + 2.0 * globals.ambient.g + 4.0 * globals.ambient.b)) * 0x9e3779b1u;
    return vec4(bitcast<vec3<u32>>(origin), h | 1u);
}

var<workgroup> unchanged: u32;

// One workgroup per sprite and role; its threads take the sprite's texels in turn (only the
// cells' centre texels, which are all the pass reads). A copy whose texels were lit for the
// same probe, position, frame and look is left as it is (a refracting sprite, which sees the
// probes' changing faces, never is).
@compute @workgroup_size(64)
fn main(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let index = wg.z * 65535u + wg.x;
    let role = select(ROLE_GRID, ROLE_PREVIOUS, wg.y == 1u);
    if index >= globals.count || index >= arrayLength(&sprites) {
        return;
    }
    if role == ROLE_PREVIOUS && (globals.facing != 0u || view.fade_t >= 1.0 || role_slot(role) > 2u) {
        return;
    }
    let s = sprites[index];
    let q = quad_for(s, role);
    let centre = sprite_point(q, vec2(0.5));
    if !sphere_in_view(centre, 0.5 * length(q.size) + s.relief_depth) {
        return;
    }
    if li == 0u {
        let k = index * 2u + select(0u, 1u, role == ROLE_PREVIOUS);
        let slot = view.slots[role_slot(role)];
        let key = lit_key(s, slot.origin, slot.n);
        let refracts = s.layers.w != NO_LAYER && s.index_ratio > 0.0;
        let same = all(lit_keys[k] == key) && !refracts && globals.facing == 0u;
        unchanged = select(0u, 1u, same);
        lit_keys[k] = key;
    }
    if workgroupUniformLoad(&unchanged) == 1u {
        return;
    }
    let texels = s.frame_px.x * s.frame_px.y;
    let k = sprite_cell_size(s, q, role);
    for (var i = li; i < texels; i += 64u) {
        let t = vec2(i % s.frame_px.x, i / s.frame_px.x);
        // A cell's centre texel (what sprite_cell picks for every pixel of the cell).
        if any(sprite_cell_texel(t, k, s.frame_px) != t) {
            continue;
        }
        lit[lit_index(s, role, t)] = shade_texel(s, q, role, t, k);
    }
}
