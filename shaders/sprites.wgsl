// Sprites: one instance per sprite (4 vertices, a strip) drawn into the frame after the
// splats and the moving objects, depth-tested against them. A sprite is never captured into
// the probes, so it keeps the texel world's rules itself: its quad turns toward the grid
// probe's origin (not the camera), its anchor sits on the probe's texel grid, its matched
// size makes one sprite pixel one probe texel, its 8-direction frame is the one the probe's
// origin sees, and during a crossfade the previous probe's copy of it keeps the pixels the
// splats' Bayer pattern gives the previous probe. So while the camera moves inside a cell
// a sprite's pixels are fixed in the world. Every pixel of a sprite texel is lit once at the
// texel's centre (suns and points, BVH shadows, the normal map; relief: the texel's ray from
// the probe's origin marched into the depth map, self-shadowed per light, its depth written;
// refraction: the bent ray marched through the grid probe's cube faces), posterized and
// outlined at alpha edges. crates/render/src/passes/sprites.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"
#include "lib/bvh.wgsl"
#include "lib/lighting.wgsl"
#include "lib/slots.wgsl"

struct SpriteGlobals {
    suns: array<Sun, 4>,
    ambient: vec4<f32>,
    sun_count: u32,
    point_count: u32,
    bands: u32,
    // 0: toward the probes; 1: toward the camera (for comparison).
    facing: u32,
    // A sprite pixel's key: MOVING_KEY | (key_base + sprite index).
    key_base: u32,
    count: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var<storage, read> sprites: array<Sprite>;
@group(0) @binding(2) var sprite_frames: texture_2d_array<f32>;
@group(0) @binding(3) var<uniform> globals: SpriteGlobals;
@group(0) @binding(4) var<storage, read> points: array<PointLight>;
@group(2) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(2) @binding(1) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(2) @binding(2) var<storage, read> bvh_instances: array<BvhInstance>;

#include "lib/sprite.wgsl"

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) sprite: u32,
    @location(2) @interpolate(flat) role: u32,
}

// The slot whose origin a sprite drawn for `role` turns toward.
fn role_slot(role: u32) -> u32 {
    if role == ROLE_GRID {
        return view.grid_slot;
    }
    for (var s = 1u; s < 3u; s++) {
        if view.slots[s].role == ROLE_PREVIOUS {
            return s;
        }
    }
    return 3u;
}

// Sprite `s` as drawn for `role`: toward that probe's origin, or the camera.
fn quad_for(s: Sprite, role: u32) -> SpriteQuad {
    let grid = view.slots[view.grid_slot];
    if globals.facing != 0u {
        // The view axis, from the far plane's centre toward the near plane's.
        let near = view.inv_view_proj * vec4(0.0, 0.0, NDC_NEAR, 1.0);
        let far = view.inv_view_proj * vec4(0.0, 0.0, NDC_FAR, 1.0);
        let back = near.xyz / near.w - far.xyz / far.w;
        return sprite_quad(s, view.camera.xyz, back, grid.n, false);
    }
    let slot = view.slots[role_slot(role)];
    return sprite_quad(s, slot.origin, slot.origin - s.position, slot.n, true);
}

// The eye a sprite's relief and refraction rays start from: its probe's origin (so what a
// texel shows is fixed inside a cell), or the camera.
fn eye_for(role: u32) -> vec3<f32> {
    if globals.facing != 0u {
        return view.camera.xyz;
    }
    return view.slots[role_slot(role)].origin;
}

@vertex
fn vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let n = globals.count;
    let role = select(ROLE_GRID, ROLE_PREVIOUS, ii >= n);
    let index = ii % max(n, 1u);
    out.sprite = index;
    out.role = role;
    // The previous probe's copies only while a crossfade runs.
    if index >= arrayLength(&sprites) || (role == ROLE_PREVIOUS && (view.fade_t >= 1.0 || role_slot(role) > 2u)) {
        out.clip = vec4(0.0, 0.0, 2.0, 1.0);
        return out;
    }
    let s = sprites[index];
    let q = quad_for(s, role);
    // Strip order: top-left, top-right, bottom-left, bottom-right.
    let uv = vec2(f32(vi & 1u), f32(vi >> 1u));
    out.uv = uv;
    out.clip = view.view_proj * vec4(sprite_point(q, uv), 1.0);
    return out;
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
    @builtin(frag_depth) depth: f32,
}

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
        let r = x - g.origin;
        let fu = cube_face_uv(r);
        let tx = texel_of_uv(fu.uv, n);
        let stored = load_geo(slot, tx, fu.face).w;
        colour = load_lit(slot, tx, fu.face).rgb;
        if stored > 0.0 && chebyshev(r) >= stored {
            return colour;
        }
        t *= 1.25;
    }
    return colour;
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let s = sprites[in.sprite];
    let role = in.role;
    if globals.facing == 0u {
        let grid_wins = bayer_threshold(vec2<u32>(in.clip.xy)) < view.fade_t;
        if (role == ROLE_GRID) != grid_wins {
            discard;
        }
    }
    let q = quad_for(s, role);
    // Everything at the centre of the quad texel this pixel lies in. Toward the probes, a
    // sprite texel is never smaller than a probe texel at the sprite (as terrain pixels):
    // where the picture is finer, cells of k × k texels (k a power of two) take the texel at
    // their centre, so a far sprite does not alias into the pixels.
    var t = sprite_texel_at(in.uv, s.frame_px);
    var k = 1u;
    if globals.facing == 0u {
        let slot = view.slots[role_slot(role)];
        let probe_texel = 2.0 * distance(sprite_point(q, vec2(0.5)), slot.origin) / f32(max(slot.n, 1u));
        let texel = max(q.size.x / f32(s.frame_px.x), q.size.y / f32(s.frame_px.y));
        k = u32(exp2(ceil(log2(clamp(probe_texel / max(texel, 1.0e-6), 1.0, 64.0)))));
        t = min((t / k) * k + k / 2u, s.frame_px - 1u);
    }
    let uv0 = (vec2<f32>(t) + 0.5) / vec2<f32>(s.frame_px);
    let p0 = sprite_point(q, uv0);
    let eye = eye_for(role);
    var p = p0;
    var c = 0.0;
    var uv = uv0;
    var depth = in.clip.z;
    let relief = s.layers.z != NO_LAYER && s.relief_depth > 0.0;
    let ray = normalize(p0 - eye);
    if relief {
        let h = relief_march(s, q, uv0, ray);
        if !h.hit {
            discard;
        }
        uv = h.uv;
        t = sprite_texel_at(uv, s.frame_px);
        p = p0 + ray * h.t;
        c = -dot(ray, q.front) * h.t;
        let clip = view.view_proj * vec4(p, 1.0);
        depth = clamp(clip.z / clip.w, 0.0, 1.0);
    }
    let texel = sprite_texel(s.layers.x, q, t);
    if texel.a < 0.5 {
        discard;
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
        && (empty_at(s, q, t, vec2(i32(k), 0)) || empty_at(s, q, t, vec2(-i32(k), 0))
            || empty_at(s, q, t, vec2(0, i32(k))) || empty_at(s, q, t, vec2(0, -i32(k)))) {
        shift = -1.0;
    }
    let lit = posterize(colour, globals.bands, shift);
    var out: FsOut;
    out.colour = vec4(linear_to_srgb(hazed(lit, length(p - view.camera.xyz))), 1.0);
    // Not a probe texel: the sprite's index after the objects, under the moving bit
    // (crates/render/src/readback.rs `MOVING_KEY`): picking and the evaluator's ids name it.
    out.key = 0x80000000u | (globals.key_base + in.sprite);
    out.depth = depth;
    return out;
}
