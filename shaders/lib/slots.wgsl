// The three probe slots' textures and draw lists as one bind group, and loads from a slot
// chosen at run time (a switch: WGSL has no arrays of textures without bindless). The
// includer puts the group at `@group(1)`: crates/render/src/passes/cull.rs
// `probe_textures_layout` / `probe_textures_bind_group`, shared by cull and march.

@group(1) @binding(0) var geo0: texture_2d_array<f32>;
@group(1) @binding(1) var geo1: texture_2d_array<f32>;
@group(1) @binding(2) var geo2: texture_2d_array<f32>;
@group(1) @binding(3) var ids0: texture_2d_array<u32>;
@group(1) @binding(4) var ids1: texture_2d_array<u32>;
@group(1) @binding(5) var ids2: texture_2d_array<u32>;
@group(1) @binding(6) var lit0: texture_2d_array<f32>;
@group(1) @binding(7) var lit1: texture_2d_array<f32>;
@group(1) @binding(8) var lit2: texture_2d_array<f32>;
@group(1) @binding(9) var runs0: texture_2d_array<u32>;
@group(1) @binding(10) var runs1: texture_2d_array<u32>;
@group(1) @binding(11) var runs2: texture_2d_array<u32>;
// The slots' draw lists (lib/lists.wgsl): run heads of stable faces, lit eye texels.
@group(1) @binding(12) var<storage, read> list0: array<u32>;
@group(1) @binding(13) var<storage, read> list1: array<u32>;
@group(1) @binding(14) var<storage, read> list2: array<u32>;

fn load_list(slot: u32, i: u32) -> u32 {
    switch slot {
        case 0u: { return list0[i]; }
        case 1u: { return list1[i]; }
        default: { return list2[i]; }
    }
}

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

fn load_run(slot: u32, t: vec2<u32>, f: u32) -> u32 {
    switch slot {
        case 0u: { return textureLoad(runs0, t, f, 0).r; }
        case 1u: { return textureLoad(runs1, t, f, 0).r; }
        default: { return textureLoad(runs2, t, f, 0).r; }
    }
}
