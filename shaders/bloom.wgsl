// Bloom (crates/render/src/passes/bloom.rs): light spilling from bright pixels, computed on
// the internal frame, whose pixels are the art pixels, so it holds as still as they do.
// `fs_h` takes each pixel's light above the threshold and blurs it along x (Gaussian,
// `radius` art pixels); `fs_v` blurs those sums along y and adds them, times the strength,
// to the frame. The frame holds sRGB-encoded colours (texel splatting's internal frame) or
// linear ones (the baselines' shaded screen), as `encoded` says; light is summed linear.

#include "lib/fullscreen.wgsl"
#include "lib/common.wgsl"

struct Bloom {
    // Light (relative luminance, linear) below which a pixel spills nothing.
    threshold: f32,
    // How much of the blurred light is added.
    strength: f32,
    // Blur radius in internal pixels.
    radius: u32,
    // 1: the frame's colours are sRGB-encoded; 0: linear.
    encoded: u32,
    // The internal frame's size.
    size: vec2<u32>,
    _pad2: vec2<u32>,
}

@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var<uniform> bloom: Bloom;
@group(0) @binding(2) var frame: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return vec4(fullscreen_xy(vi), 0.0, 1.0);
}

// The light of frame pixel `p` above the threshold (linear), its hue kept.
fn decoded(c: vec3<f32>) -> vec3<f32> {
    return select(c, srgb_to_linear(c), bloom.encoded != 0u);
}

fn bright(p: vec2<i32>) -> vec3<f32> {
    let c = decoded(textureLoad(src, p, 0).rgb);
    let l = dot(c, vec3(0.2126, 0.7152, 0.0722));
    return c * (max(l - bloom.threshold, 0.0) / max(l, 1e-4));
}

fn weight(i: i32) -> f32 {
    let sigma = max(f32(bloom.radius) * 0.5, 0.5);
    return exp(-f32(i * i) / (2.0 * sigma * sigma));
}

fn clamped(p: vec2<i32>) -> vec2<i32> {
    return clamp(p, vec2(0), vec2<i32>(bloom.size) - vec2(1));
}

// The Gaussian-weighted mean along `step` around `p` of the light above the threshold
// (`bright_light`: the frame's pixels) or of `src` as it is (the first pass's sums).
fn blurred(p: vec2<i32>, step: vec2<i32>, bright_light: bool) -> vec3<f32> {
    let r = i32(bloom.radius);
    var sum = vec3(0.0);
    var total = 0.0;
    for (var i = -r; i <= r; i++) {
        let w = weight(i);
        let q = clamped(p + step * i);
        if bright_light {
            sum += w * bright(q);
        } else {
            sum += w * textureLoad(src, q, 0).rgb;
        }
        total += w;
    }
    return sum / total;
}

@fragment
fn fs_h(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4(blurred(vec2<i32>(pos.xy), vec2(1, 0), true), 1.0);
}

@fragment
fn fs_v(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let base = textureLoad(frame, p, 0);
    let lit = decoded(base.rgb) + bloom.strength * blurred(p, vec2(0, 1), false);
    return vec4(select(lit, linear_to_srgb(lit), bloom.encoded != 0u), base.a);
}
