// Per-frame view data shared by cull, splat and background (crates/render/src/frame.rs
// `ViewGlobals`).

struct SlotView {
    origin: vec3<f32>,
    n: u32,
    // 0 eye, 1 grid, 2 previous, 3 unused this frame.
    role: u32,
    // Bit f set: face f is drawn.
    draw_mask: u32,
    _pad0: u32,
    _pad1: u32,
}

struct ViewGlobals {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    planes: array<vec4<f32>, 6>,
    camera: vec4<f32>,
    sky: vec4<f32>,
    slots: array<SlotView, 3>,
    size: vec2<u32>,
    max_n: u32,
    // 0 ours, 1 paper.
    schedule: u32,
    fade_t: f32,
    eye_bias: f32,
    eye_slot: u32,
    grid_slot: u32,
    // Haze density per world unit (0 = none).
    haze: f32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// The colour `c` seen from `dist` world units away through the haze.
fn hazed(c: vec3<f32>, dist: f32) -> vec3<f32> {
    let f = 1.0 - exp(-view.haze * dist);
    return mix(c, view.sky.rgb, f);
}

const ROLE_EYE: u32 = 0u;
const ROLE_GRID: u32 = 1u;
const ROLE_PREVIOUS: u32 = 2u;
const ROLE_NONE: u32 = 3u;
