// Splat: draws the culled texels as world-space quads (4 vertices, indexed, corners pulled
// from the cull pass's list; a quad may span a run of texels along a face row). Eye quads are pushed back in depth so grid and previous quads
// win where both exist; grid and previous split the screen with complementary 4×4 Bayer
// patterns while a crossfade runs. Writes the colour and the texel key of every pixel.
// crates/render/src/passes/splat.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"

struct Splat {
    c0: vec4<f32>,
    c1: vec4<f32>,
    c2: vec4<f32>,
    c3: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var<storage, read> splats: array<Splat>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) colour: vec4<f32>,
    @location(1) @interpolate(flat) key: u32,
    @location(2) @interpolate(flat) role: u32,
    // Texel coordinate along a run quad (texel i spans [i, i + 1)), and its texels.
    @location(3) along: f32,
    @location(4) @interpolate(flat) texels: u32,
    // Key step from one texel of the run to the next: 1 along a row, max_n down a column.
    @location(5) @interpolate(flat) step: u32,
}

@vertex
fn vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    if ii >= arrayLength(&splats) {
        out.clip = vec4(0.0, 0.0, 2.0, 1.0);
        return out;
    }
    let s = splats[ii];
    var corner: vec3<f32>;
    switch vi {
        case 0u: { corner = s.c0.xyz; }
        case 1u: { corner = s.c1.xyz; }
        case 2u: { corner = s.c2.xyz; }
        default: { corner = s.c3.xyz; }
    }
    let shape = bitcast<u32>(s.c2.w);
    let role = shape & 0xffu;
    let column = (shape & SPLAT_COLUMN) != 0u;
    // Corners 0–3 are top-left, top-right, bottom-right, bottom-left: a row run starts on
    // the left (0, 3), a column run at the top (0, 1).
    out.texels = max((shape & 0xffffu) >> 8u, 1u);
    // Texel coordinate along the run: the first texel's centre is 0.5, the last's texels − 0.5.
    let reach = unpack2x16unorm(bitcast<u32>(s.c3.w));
    let at_start = select(vi == 0u || vi == 3u, vi <= 1u, column);
    out.along = select(f32(out.texels) - 0.5 + reach.y, 0.5 - reach.x, at_start);
    out.step = select(1u, view.max_n, column);
    let key = bitcast<u32>(s.c0.w);
    var clip = view.view_proj * vec4(corner, 1.0);
    // Overlapping coplanar quads (tight expansion toward similar neighbours) would tie in
    // depth and be resolved by draw order, which the cull pass's atomics leave unspecified;
    // a tiny per-texel offset makes the winner a function of the texel alone.
    let tie = f32((key * 2654435761u) >> 24u) * 1.0e-9;
    var bias = tie;
    if role == ROLE_EYE {
        bias += view.eye_bias;
    }
    clip.z = min(clip.z + bias * clip.w, clip.w);
    out.clip = clip;
    let c = unpack4x8unorm(bitcast<u32>(s.c1.w));
    out.colour = vec4(srgb_to_linear(c.rgb), 1.0);
    out.key = key;
    out.role = role;
    return out;
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
}

// The key of the texel under this pixel of a run quad.
fn pixel_key(in: VsOut) -> u32 {
    return in.key + in.step * u32(clamp(floor(in.along), 0.0, f32(in.texels - 1u)));
}

// Without a crossfade: no discard, so the depth test can run before the shader.
@fragment
fn fs(in: VsOut) -> FsOut {
    return FsOut(in.colour, pixel_key(in));
}

// During a crossfade: grid and previous split the pixels with complementary Bayer patterns.
@fragment
fn fs_dither(in: VsOut) -> FsOut {
    if in.role != ROLE_EYE {
        let threshold = bayer_threshold(vec2<u32>(in.clip.xy));
        let grid_wins = threshold < view.fade_t;
        if (in.role == ROLE_GRID) != grid_wins {
            discard;
        }
    }
    return FsOut(in.colour, pixel_key(in));
}
