// Sprites as this frame's view turns them (shared by shaders/sprite_shade.wgsl, which
// lights each sprite texel, and shaders/sprites.wgsl, which draws them): toward which probe a
// sprite drawn for a role turns, its quad, the eye its relief and refraction rays start from,
// and which texel a frame coordinate takes. The includer declares `view: ViewGlobals`,
// `globals: SpriteGlobals` and what lib/sprite.wgsl needs, and includes lib/view.wgsl.

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
    // Moves every frame while the cached sprite texels cannot be trusted (sprite_shade.wgsl).
    epoch: u32,
    _pad1: u32,
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
    if slot.half > 0.0 {
        // An orthographic probe's rays are parallel: the sprite faces back along them, one
        // sprite pixel per texel of its face, its anchor on the probe's texel lattice.
        let f = slot_frame(slot);
        let eye = eye_for(s, role);
        var q = sprite_quad(s, eye, eye - s.position, slot.n, false);
        let at = frame_locate(f, s.position);
        let uv = texel_center_uv(texel_of_uv(at.uv, slot.n), slot.n);
        q.corner += frame_point(f, 0u, uv, at.depth) - s.position;
        return q;
    }
    return sprite_quad(s, slot.origin, slot.origin - s.position, slot.n, true);
}

// The eye a sprite's relief and refraction rays start from: its probe's origin (so what a
// texel shows is fixed inside a cell), or the camera. For an orthographic probe, a point back
// along its parallel rays, one face half from the sprite: as far as a texel of that face
// spans one texel (so matched sizes and cells come out one texel of the face).
fn eye_for(s: Sprite, role: u32) -> vec3<f32> {
    if globals.facing != 0u {
        return view.camera.xyz;
    }
    let slot = view.slots[role_slot(role)];
    if slot.half > 0.0 {
        return s.position - slot.forward.xyz * slot.half;
    }
    return slot.origin;
}

// The side of the square cells sprite `s` (quad `q`, drawn for `role`) is lit in, in
// texels. Toward the probes, a sprite texel is never smaller than a probe texel at the
// sprite (as terrain pixels): where the picture is finer, cells of k × k texels (k a power of
// two) take the texel at their centre, so a far sprite does not alias into the pixels.
fn sprite_cell_size(s: Sprite, q: SpriteQuad, role: u32) -> u32 {
    if globals.facing != 0u {
        return 1u;
    }
    let slot = view.slots[role_slot(role)];
    let probe_texel = 2.0 * distance(sprite_point(q, vec2(0.5)), eye_for(s, role)) / f32(max(slot.n, 1u));
    let texel = max(q.size.x / f32(s.frame_px.x), q.size.y / f32(s.frame_px.y));
    return u32(exp2(ceil(log2(clamp(probe_texel / max(texel, 1.0e-6), 1.0, 64.0)))));
}

// The texel whose light texel `t` takes: its cell's centre texel, cells of `k` texels.
fn sprite_cell_texel(t: vec2<u32>, k: u32, px: vec2<u32>) -> vec2<u32> {
    return min((t / k) * k + k / 2u, px - 1u);
}

// Where sprite `s`'s texels for `role` start in the lit buffer (two copies: grid, previous).
fn lit_index(s: Sprite, role: u32, t: vec2<u32>) -> u32 {
    let texels = s.frame_px.x * s.frame_px.y;
    return s.lit_base + select(0u, texels, role == ROLE_PREVIOUS) + t.y * s.frame_px.x + t.x;
}
