// The shade pass's per-frame globals (crates/render/src/passes/shade.rs `ShadeGlobals`):
// lights, ambient, sky, posterization bands, dithering. Read by the shade pass, and by the terrain
// splats pass to colour terrain pixels (terrain_splat.wgsl).

struct ShadeGlobals {
    suns: array<Sun, 4>,
    ambient: vec4<f32>,
    sky: vec4<f32>,
    sun_count: u32,
    point_count: u32,
    bands: u32,
    // 1: search silhouettes' edges (our schedule's, not the paper's).
    edges: u32,
    // Where each slot's part of the light queue starts in `work` (after WORK_QUEUE).
    queue_base: vec4<u32>,
    // 1: the frame is mapped to a dithered palette: lit texels carry their surface's
    // dither rank (lib/common.wgsl `lit_with_dither`).
    dither: u32,
    // 1: edge rays walk the still instances from their texel's subtree (lib/edge_rays.wgsl
    // `edge_statics`); 0: from the root.
    edge_roots: u32,
    _pad1: u32,
    _pad2: u32,
}
