// G-buffer sprites: the sprites drawn into the G-buffer after the scene (crates/render/src/
// baselines/gbuffer.rs), turned toward a given point (the evaluator's reference: the grid
// probe's origin of the frame, where texel splatting turns them; the screen-space baselines:
// their camera), their relief marched from it. Per pixel: the sprite texel's world point,
// its normal-mapped normal, id (key base + sprite + 1) and albedo, as gbuffer.wgsl writes.

#include "lib/common.wgsl"

struct SpriteCamera {
    view_proj: mat4x4<f32>,
    // World-space view axis (unit) and, in w, its dot with the camera position.
    axis: vec4<f32>,
    // The point sprites turn toward (xyz) and the face resolution their matched size and
    // snapping use (w, as a float).
    eye: vec4<f32>,
    // Sprite ids start at key_base + 1.
    key_base: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> camera: SpriteCamera;
@group(0) @binding(1) var<storage, read> sprites: array<Sprite>;
@group(0) @binding(2) var sprite_frames: texture_2d_array<f32>;

#include "lib/sprite.wgsl"

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) sprite: u32,
}

fn quad_of(s: Sprite) -> SpriteQuad {
    return sprite_quad(s, camera.eye.xyz, camera.eye.xyz - s.position, u32(camera.eye.w), true);
}

@vertex
fn vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    out.sprite = ii;
    let q = quad_of(sprites[ii]);
    let uv = vec2(f32(vi & 1u), f32(vi >> 1u));
    out.uv = uv;
    out.clip = camera.view_proj * vec4(sprite_point(q, uv), 1.0);
    return out;
}

struct FsOut {
    @location(0) world: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) ids: vec2<u32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs(in: VsOut) -> FsOut {
    let s = sprites[in.sprite];
    let q = quad_of(s);
    var t = sprite_texel_at(in.uv, s.frame_px);
    let uv0 = (vec2<f32>(t) + 0.5) / vec2<f32>(s.frame_px);
    // The pixel's own point on the quad (a relief's: where the texel's ray meets it).
    var p = sprite_point(q, in.uv);
    var depth = in.clip.z;
    if s.layers.z != NO_LAYER && s.relief_depth > 0.0 {
        let p0 = sprite_point(q, uv0);
        let ray = normalize(p0 - camera.eye.xyz);
        let h = relief_march(s, q, uv0, ray);
        if !h.hit {
            discard;
        }
        t = sprite_texel_at(h.uv, s.frame_px);
        p = p0 + ray * h.t;
        let clip = camera.view_proj * vec4(p, 1.0);
        depth = clamp(clip.z / clip.w, 0.0, 1.0);
    }
    let texel = sprite_texel(s.layers.x, q, t);
    if texel.a < 0.5 {
        discard;
    }
    var out: FsOut;
    out.world = vec4(p, dot(p, camera.axis.xyz) - camera.axis.w);
    out.normal = vec4(sprite_normal(s, q, t), 0.0);
    let flags = select(0u, FLAG_OUTLINED, (s.flags & SPRITE_OUTLINED) != 0u);
    let albedo = vec4(srgb_to_linear(texel.rgb), f32(flags) / 255.0);
    out.ids = vec2(camera.key_base + in.sprite + 1u, pack4x8unorm(albedo));
    out.depth = depth;
    return out;
}
