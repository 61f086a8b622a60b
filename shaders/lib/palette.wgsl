// Palettes (crates/render/src/palette.rs): a frame's sRGB-encoded colours mapped to the
// nearest of a palette's colours in OKLab, optionally dithered between the two nearest by a
// threshold the caller anchors to the texel (`texel_threshold`), so the pattern moves with
// the world, not the screen. Needs lib/common.wgsl; the includer declares the uniform
// `palette: Palette`.

struct Palette {
    // Colours in use; 0: no palette, colours pass through.
    count: u32,
    // Dither strength, 0 (nearest colour only) to 1.
    dither: f32,
    // The faces' side in texels over which splat keys are dense (lib/common.wgsl
    // `texel_key`); 0 when the caller's keys are not texel keys.
    max_n: u32,
    _pad: u32,
    // Each colour in OKLab (xyz).
    lab: array<vec4<f32>, 256>,
    // Each colour sRGB-encoded, 0–1 (rgb): what is written.
    srgb: array<vec4<f32>, 256>,
}

// A 4 × 4 Bayer threshold in (0, 1) for a position.
fn bayer4(p: vec2<u32>) -> f32 {
    var m = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return (f32(m[(p.y & 3u) * 4u + (p.x & 3u)]) + 0.5) / 16.0;
}

// The dither threshold of a pixel whose frame key is `key` (lib/common.wgsl `texel_key`
// + 1) and alpha `alpha`: the rank of its texel's surface where the alpha carries one
// (lib/common.wgsl `dither_alpha`: the shade pass found it where the texel lies in the
// world, so a texel keeps its choice however the camera moves, and the next probe's texels
// over the same surface mostly share it), else the Bayer cell of its texel on its face (a
// terrain's). The sky (key 0), moving objects and sprites (the top bit) take their screen
// pixel's cell.
fn texel_threshold(key: u32, pixel: vec2<u32>, max_n: u32, alpha: f32) -> f32 {
    if max_n == 0u || key == 0u || key >= 0x80000000u {
        return bayer4(pixel);
    }
    let a = u32(round(alpha * 255.0));
    if a < 255u {
        return (f32(a / 16u) + 0.5) / 16.0;
    }
    let k = key - 1u;
    return bayer4(vec2(k % max_n, (k / max_n) % max_n));
}

// The palette colour for linear `c` at dither threshold `t` (its index): the nearest in
// OKLab, or the second nearest where `t` falls below the share of the way from the nearest
// to the second that `c` lies at, times the strength. `palette.srgb` holds what to write.
fn palette_index(c: vec3<f32>, t: f32) -> u32 {
    let lab = oklab_from_linear(max(c, vec3(0.0)));
    var best = 0u;
    var best_d = 1e30;
    var second = 0u;
    var second_d = 1e30;
    for (var i = 0u; i < palette.count; i++) {
        let e = palette.lab[i].xyz - lab;
        let d = dot(e, e);
        if d < best_d {
            second = best;
            second_d = best_d;
            best = i;
            best_d = d;
        } else if d < second_d {
            second = i;
            second_d = d;
        }
    }
    if palette.dither > 0.0 && palette.count > 1u {
        let a = palette.lab[best].xyz;
        let ab = palette.lab[second].xyz - a;
        let f = clamp(dot(lab - a, ab) / max(dot(ab, ab), 1e-12), 0.0, 1.0);
        if t < f * palette.dither {
            return second;
        }
    }
    return best;
}
