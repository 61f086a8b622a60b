// Sprites (crates/render/src/gpu_sprites.rs): one instance record per sprite, expanded to a quad
// in the vertex stage, turned toward a viewer point. Shared by the sprite pass
// (shaders/sprites.wgsl) and the G-buffer (shaders/gbuffer.wgsl). The includer declares
// `sprites: array<Sprite>` and `sprite_frames: texture_2d_array<f32>` and includes
// lib/common.wgsl.

struct Sprite {
    position: vec3<f32>,
    frame: u32,
    rotation: vec4<f32>,
    size: vec2<f32>,
    pivot: vec2<f32>,
    frame_px: vec2<u32>,
    columns: u32,
    flags: u32,
    // First layer of the sheet's frames, the normal map's, the depth map's, the back depth
    // map's (NO_LAYER where missing).
    layers: vec4<u32>,
    relief_depth: f32,
    index_ratio: f32,
    frames: u32,
    // Where its lit texels start (crates/render/src/gpu_sprites.rs).
    lit_base: u32,
}

const SPRITE_BILLBOARD: u32 = 3u;
const SPRITE_SPHERICAL: u32 = 0u;
const SPRITE_FIXED: u32 = 2u;
const SPRITE_EIGHT: u32 = 4u;
const SPRITE_OUTLINED: u32 = 8u;
const SPRITE_MATCHED: u32 = 16u;
const NO_LAYER: u32 = 0xffffffffu;

// A sprite's quad as one viewer sees it.
struct SpriteQuad {
    // The frame's top-left corner in the world.
    corner: vec3<f32>,
    // Unit axes: right along the frame's x, up against its y, front toward the viewer.
    right: vec3<f32>,
    up: vec3<f32>,
    front: vec3<f32>,
    // World size of the whole frame.
    size: vec2<f32>,
    // The frame on the sheet (direction included), clamped to the sheet.
    frame: u32,
}

fn quat_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

// Which of 8 directions a viewer at `eye` sees sprite `s` from (texel_scene::sprite::
// direction_index): its bearing about +Y in the sprite's frame, from the front (+Z) toward
// +X, rounded to 45°.
fn sprite_direction(s: Sprite, eye: vec3<f32>) -> u32 {
    let inv = vec4(-s.rotation.xyz, s.rotation.w);
    let v = quat_rotate(inv, s.position - eye);
    let x = -v.x;
    let z = -v.z;
    if x * x + z * z <= 1.0e-12 * dot(v, v) {
        return 0u;
    }
    let d = floor(atan2(x, z) / 0.7853981633974483 + 0.5);
    return u32(i32(d) + 8) % 8u;
}

// `p` moved to the centre of the texel of a face of `n` texels around `origin` that holds it,
// at the same Chebyshev distance: a sprite's anchor on the probe's texel grid, so a moving
// sprite steps texel by texel with the world's art pixels instead of swimming between them.
fn snap_to_probe_texel(p: vec3<f32>, origin: vec3<f32>, n: u32) -> vec3<f32> {
    let d = p - origin;
    let a = abs(d);
    let m = max(a.x, max(a.y, a.z));
    if m < 1.0e-6 || n == 0u {
        return p;
    }
    let nf = f32(n);
    var q = d / m;
    // The two coordinates across the face, snapped to texel centres in [-1, 1].
    let snapped = (floor((q * 0.5 + 0.5) * nf) + 0.5) / nf * 2.0 - 1.0;
    let c = clamp(snapped, vec3(-1.0), vec3(1.0));
    if a.x >= a.y && a.x >= a.z {
        q = vec3(q.x, c.y, c.z);
    } else if a.y >= a.z {
        q = vec3(c.x, q.y, c.z);
    } else {
        q = vec3(c.x, c.y, q.z);
    }
    return origin + q * m;
}

// Sprite `s` seen from `eye`, turned toward `toward` (the unit direction from the sprite to
// its viewer; for a camera-facing sprite the camera's backward axis), its size matched to a
// face of `n` texels at `eye` when the sprite asks for it, its anchor snapped to that face's
// texels when `snap`.
fn sprite_quad(s: Sprite, eye: vec3<f32>, toward_in: vec3<f32>, n: u32, snap: bool) -> SpriteQuad {
    var anchor = s.position;
    if snap {
        anchor = snap_to_probe_texel(anchor, eye, n);
    }
    var toward = toward_in;
    let mode = s.flags & SPRITE_BILLBOARD;
    var q: SpriteQuad;
    if mode == SPRITE_FIXED {
        q.right = quat_rotate(s.rotation, vec3(1.0, 0.0, 0.0));
        q.up = quat_rotate(s.rotation, vec3(0.0, 1.0, 0.0));
        q.front = quat_rotate(s.rotation, vec3(0.0, 0.0, 1.0));
    } else {
        if mode != SPRITE_SPHERICAL {
            toward.y = 0.0;
        }
        if dot(toward, toward) < 1.0e-10 {
            toward = quat_rotate(s.rotation, vec3(0.0, 0.0, 1.0));
            if mode != SPRITE_SPHERICAL {
                toward.y = 0.0;
            }
            if dot(toward, toward) < 1.0e-10 {
                toward = vec3(0.0, 0.0, 1.0);
            }
        }
        q.front = normalize(toward);
        var side = cross(vec3(0.0, 1.0, 0.0), q.front);
        if dot(side, side) < 1.0e-10 {
            side = vec3(1.0, 0.0, 0.0);
        }
        q.right = normalize(side);
        q.up = cross(q.front, q.right);
    }
    if (s.flags & SPRITE_MATCHED) != 0u {
        // One sprite pixel per probe texel at the sprite's distance (as moving objects' and
        // terrain cells are measured).
        let texel = 2.0 * max(distance(anchor, eye), 1.0e-3) / f32(max(n, 1u));
        q.size = vec2<f32>(s.frame_px) * texel;
    } else {
        q.size = s.size;
    }
    q.corner = anchor - q.right * (s.pivot.x * q.size.x) + q.up * (s.pivot.y * q.size.y);
    var frame = s.frame;
    if (s.flags & SPRITE_EIGHT) != 0u {
        frame += sprite_direction(s, eye) * s.columns;
    }
    q.frame = min(frame, max(s.frames, 1u) - 1u);
    return q;
}

// The world point of frame coordinate `uv` (0..1, y down) on quad `q`.
fn sprite_point(q: SpriteQuad, uv: vec2<f32>) -> vec3<f32> {
    return q.corner + q.right * (uv.x * q.size.x) - q.up * (uv.y * q.size.y);
}

// Texel `t` of map `base` (a layer index, NO_LAYER for none) of the quad's frame.
fn sprite_texel(base: u32, q: SpriteQuad, t: vec2<u32>) -> vec4<f32> {
    return textureLoad(sprite_frames, t, base + q.frame, 0);
}

// The texel of a `px`-texel frame holding frame coordinate `uv`.
fn sprite_texel_at(uv: vec2<f32>, px: vec2<u32>) -> vec2<u32> {
    return min(vec2<u32>(max(floor(uv * vec2<f32>(px)), vec2(0.0))), px - 1u);
}

// The world normal of the sprite's surface at texel `t`: the normal map's (tangent space on
// the quad: red right, green up, blue front) or the quad's front.
fn sprite_normal(s: Sprite, q: SpriteQuad, t: vec2<u32>) -> vec3<f32> {
    if s.layers.y == NO_LAYER {
        return q.front;
    }
    let m = sprite_texel(s.layers.y, q, t).xyz * 2.0 - 1.0;
    let n = q.right * m.x + q.up * m.y + q.front * m.z;
    if dot(n, n) < 1.0e-8 {
        return q.front;
    }
    return normalize(n);
}

// Relief: depth behind the quad at texel `t` in world units, the deepest (255) a hair less
// than the relief's depth so that the march's last step, at exactly that depth, meets it
// whatever the rounding; no surface (infinitely deep) where the sheet is empty.
fn sprite_depth(s: Sprite, q: SpriteQuad, t: vec2<u32>) -> f32 {
    if sprite_texel(s.layers.x, q, t).a < 0.5 {
        return 1.0e30;
    }
    return min(sprite_texel(s.layers.z, q, t).r, 0.999) * s.relief_depth;
}

// Where a ray meets a relief sprite's surface: frame coordinate, distance along the ray.
struct ReliefHit {
    uv: vec2<f32>,
    t: f32,
    hit: bool,
}

// The ray from the quad point at `uv0` along unit world direction `dir` (into the sprite),
// marched through the depth map: linear steps, then a binary search between the last two
// (the paper's relief mapping).
fn relief_march(s: Sprite, q: SpriteQuad, uv0: vec2<f32>, dir: vec3<f32>) -> ReliefHit {
    var out = ReliefHit(uv0, 0.0, false);
    let dc = -dot(dir, q.front);
    if dc <= 1.0e-4 {
        return out;
    }
    // Frame coordinates and depth per unit along the ray.
    let duv = vec2(dot(dir, q.right) / q.size.x, -dot(dir, q.up) / q.size.y);
    let t_max = s.relief_depth / dc;
    let steps = clamp(max(s.frame_px.x, s.frame_px.y), 8u, 64u);
    var lo = 0.0;
    var hi = -1.0;
    for (var i = 0u; i <= steps; i++) {
        let t = t_max * f32(i) / f32(steps);
        let uv = uv0 + duv * t;
        if any(uv < vec2(0.0)) || any(uv >= vec2(1.0)) {
            return out;
        }
        if dc * t >= sprite_depth(s, q, sprite_texel_at(uv, s.frame_px)) {
            hi = t;
            break;
        }
        lo = t;
    }
    if hi < 0.0 {
        return out;
    }
    for (var i = 0u; i < 6u; i++) {
        let mid = 0.5 * (lo + hi);
        let uv = uv0 + duv * mid;
        if dc * mid >= sprite_depth(s, q, sprite_texel_at(uv, s.frame_px)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    out.t = hi;
    out.uv = clamp(uv0 + duv * hi, vec2(0.0), vec2(0.999999));
    out.hit = true;
    return out;
}

// Whether the relief itself blocks unit direction `l` from the surface point at frame
// coordinate `uv`, `c` deep: marched toward the light until it leaves through the front.
// A light behind the quad is blocked (the picture is opaque).
fn relief_shadowed(s: Sprite, q: SpriteQuad, uv: vec2<f32>, c: f32, l: vec3<f32>) -> bool {
    let lc = -dot(l, q.front);
    if lc >= -1.0e-4 {
        return true;
    }
    let duv = vec2(dot(l, q.right) / q.size.x, -dot(l, q.up) / q.size.y);
    let t_max = c / -lc;
    let steps = clamp(max(s.frame_px.x, s.frame_px.y), 8u, 64u);
    // A texel's own depth step is not an occluder: start half a step out.
    for (var i = 1u; i < steps; i++) {
        let t = t_max * (f32(i) + 0.5) / f32(steps);
        let p = uv + duv * t;
        if any(p < vec2(0.0)) || any(p >= vec2(1.0)) {
            return false;
        }
        let depth = c + lc * t;
        let here = sprite_texel_at(p, s.frame_px);
        if sprite_texel(s.layers.x, q, here).a >= 0.5
            && depth > sprite_texel(s.layers.z, q, here).r * s.relief_depth + 1.0e-4 {
            return true;
        }
    }
    return false;
}
