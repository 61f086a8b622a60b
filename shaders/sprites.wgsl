// Sprites: one instance per sprite (4 vertices, a strip) drawn into the frame after the
// splats and the moving objects, depth-tested against them. A sprite is never captured into
// the probes, so it keeps the texel world's rules itself: its quad turns toward the grid
// probe's origin (not the camera), its anchor sits on the probe's texel grid, its matched
// size makes one sprite pixel one probe texel, its 8-direction frame is the one the probe's
// origin sees, and during a crossfade the previous probe's copy of it keeps the pixels the
// splats' Bayer pattern gives the previous probe. So while the camera moves inside a cell
// a sprite's pixels are fixed in the world. Each pixel takes its texel's colour, lit once
// this frame by shaders/sprite_shade.wgsl; a relief texel writes the depth of the surface
// its ray met. crates/render/src/passes/sprites.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var<storage, read> sprites: array<Sprite>;
@group(0) @binding(2) var sprite_frames: texture_2d_array<f32>;
@group(0) @binding(3) var<uniform> globals: SpriteGlobals;
@group(0) @binding(4) var<storage, read> lit: array<vec2<u32>>;

#include "lib/sprite.wgsl"
#include "lib/sprite_view.wgsl"

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) sprite: u32,
    @location(2) @interpolate(flat) role: u32,
    // The side of its lit cells in texels (the same for the whole quad).
    @location(3) @interpolate(flat) cell: u32,
    // The pixel's point on the quad (haze).
    @location(4) world: vec3<f32>,
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
    out.world = sprite_point(q, uv);
    out.clip = view.view_proj * vec4(out.world, 1.0);
    out.cell = sprite_cell_size(s, q, role);
    return out;
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
    @builtin(frag_depth) depth: f32,
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
    let t = sprite_cell_texel(sprite_texel_at(in.uv, s.frame_px), in.cell, s.frame_px);
    let texel = lit[lit_index(s, role, t)];
    if texel.x == 0u {
        discard;
    }
    var out: FsOut;
    out.colour = vec4(unpack4x8unorm(texel.x).rgb, 1.0);
    if view.haze > 0.0 {
        let c = hazed(srgb_to_linear(out.colour.rgb), length(in.world - view.camera.xyz));
        out.colour = vec4(linear_to_srgb(c), 1.0);
    }
    // Not a probe texel: the sprite's index after the objects, under the moving bit
    // (crates/render/src/readback.rs `MOVING_KEY`): picking and the evaluator's ids name it.
    out.key = 0x80000000u | (globals.key_base + in.sprite);
    out.depth = in.clip.z;
    let t_hit = bitcast<f32>(texel.y);
    if t_hit > 0.0 {
        // A relief texel: where its ray met the surface (the quad again, relief sprites only).
        let q = quad_for(s, role);
        let uv0 = (vec2<f32>(t) + 0.5) / vec2<f32>(s.frame_px);
        let p0 = sprite_point(q, uv0);
        let p = p0 + normalize(p0 - eye_for(s, role)) * t_hit;
        let clip = view.view_proj * vec4(p, 1.0);
        out.depth = clamp(clip.z / clip.w, 0.0, 1.0);
    }
    return out;
}
