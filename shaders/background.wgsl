// Background: a fullscreen triangle drawn after the splats with a depth test. Each pixel shows
// the eye probe's lit texel in its view direction (the sky where the eye probe saw none;
// past a silhouette's edge, the texel beyond it: `past_edge`), sRGB-encoded like the
// splats, at the depth of the eye's surface pushed back by half its distance (`GAP_DEPTH`;
// under an orthographic camera at the far plane). So it shades the pixels no quad covered,
// and also those where the quad that landed lies far behind what the eye sees: gaps between
// a stable probe's quads that the camera, off the probe's origin, sees into (a wall a cell
// from the probe, seen from its neighbour face at a grazing angle, is drawn as quads
// standing across it like the slats of a blind).
// crates/render/src/passes/background.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"
#include "lib/fullscreen.wgsl"

// How much farther than the eye's surface a splat must lie for the eye to show instead, as a
// fraction of the distance. Well above the depth error of a grazing texel's face-parallel
// quad (about tan θ / n of the distance: 5% at faces of 128, 20% at 32 for a floor seen at
// 82°), so only real gaps are filled. Measured at faces of 128 on 320×180 against the far
// plane's fill: occluder_pass 0.0062 -> 0.0053 mean shimmer (coverage error 0.0185 ->
// 0.0151), dolly 0.0033 -> 0.0031, wall_brush 0.0038 -> 0.0037, walk_cells 0.0042 ->
// 0.0041, the rest within ±0.0001; at 0.1 terrain_walk rose 0.0131 -> 0.0143 (grazing hill
// sides taken by the eye), at 0.25 to 0.0133.
const GAP_DEPTH: f32 = 0.5;

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var eye_ids: texture_2d_array<u32>;
@group(0) @binding(2) var eye_lit: texture_2d_array<f32>;
@group(0) @binding(3) var eye_geo: texture_2d_array<f32>;
// Each eye texel's strips (`strip_ends`, which writes them through bindings 6 and 7 in a
// layout of its own): where they start (`strip_starts`), and its colour's OKLab lightness a
// band darker and lighter, then its a and b (`strip_lab`).
@group(0) @binding(4) var eye_starts: texture_2d_array<f32>;
@group(0) @binding(5) var eye_lab: texture_2d_array<f32>;
@group(0) @binding(6) var starts_out: texture_storage_2d_array<rgba32float, write>;
@group(0) @binding(7) var lab_out: texture_storage_2d_array<rgba32float, write>;

@vertex
fn vs(@builtin(vertex_index) vi: u32) -> FullscreenOut {
    return fullscreen(vi, NDC_FAR);
}

struct FsOut {
    @location(0) colour: vec4<f32>,
    @location(1) key: u32,
    @builtin(frag_depth) depth: f32,
}

// Where direction `uv` of a face of n texels lies past the edge the shade pass found on a
// side of texel `t` toward the sky or a farther surface (`side_edge`, from the texel's lit
// bits), the step to the neighbour beyond it, as the texel's quad ends there; zero
// elsewhere. Without it the nearest texel alone drew every silhouette half a texel out where
// no stable quad covered the sky beside it (the eye's texels along a silhouette, and the
// sky past it).
fn past_edge(uv: vec2<f32>, n: u32, t: vec2<u32>, bits: u32) -> vec2<i32> {
    // Where `uv` lies from the texel's centre, in texels.
    let g = (uv * 0.5 + 0.5) * f32(n) - (vec2<f32>(t) + 0.5);
    let toward = select(vec2(1), vec2(-1), g < vec2(0.0));
    // The side toward `uv` along x (left 0, right 1) and along y (up 2, down 3).
    let kx = select(1u, 0u, g.x < 0.0);
    let ky = select(3u, 2u, g.y < 0.0);
    let step_x = side_code(bits, kx) >= 2u && abs(g.x) > side_edge(bits, kx);
    let step_y = side_code(bits, ky) >= 2u && abs(g.y) > side_edge(bits, ky);
    var step = select(vec2(0), toward, vec2(step_x, step_y));
    // Past a cut corner's line (`corner_cut`: through the two sides' edges), though short of
    // both edges: toward the side it lies farther past.
    let past = abs(g) / vec2(side_edge(bits, kx), side_edge(bits, ky));
    if !step_x && !step_y && corner_cut(bits, kx, ky) && past.x + past.y > 1.0 {
        step = select(vec2(0, toward.y), vec2(toward.x, 0), past.x > past.y);
    }
    // Past the face's edge: no step (the neighbour there lies on another face).
    let q = vec2<i32>(t) + step;
    if any(q < vec2(0)) || any(q >= vec2(i32(n))) {
        return vec2(0);
    }
    return step;
}

// The eye's outlined texels (shade.wgsl `texel_colour`) keep their colour and name their
// outlined sides, like a stable probe's: a strip of `OUTLINE_STRIP` texels along each is a
// band darker (a lit crease's lighter), measured from the silhouette edge the shade pass
// found or from where the texel's plane meets its neighbour's, as the cull pass draws a
// stable probe's (cull.wgsl `emit_outlined`). Those ends are fixed to the world, so the
// strip lies on the same stretch of surface as the camera moves; a whole texel's shift
// ran from the edge to the eye's texel grid, which slides with the camera.
//
// The shift of the pixel in direction `e` on eye texel `t` (outline `sides`): -1 on a dark
// strip, 1 on a lit crease's, 0 on the body. The pixel lies on side k's strip where it lies
// farther toward k than the threshold `strip_ends` worked out for the texel. Worked out here,
// per pixel, the crease ends' neighbour loads and plane gaps cost every pixel of the frame
// (lavapipe runs a fragment shader's branches for all the pixels it shades together): the
// stone circle's walk_cells background 8.1 -> 11.7 ms at 1280×720.
fn strip_shift(e: EyeRay, t: vec2<u32>, sides: u32) -> f32 {
    let n = view.slots[view.eye_slot].n;
    // Where the pixel lies from the texel's centre toward left, right, up and down, in texels.
    let g = (e.uv * 0.5 + 0.5) * f32(n) - (vec2<f32>(t) + 0.5);
    let toward = vec4(-g.x, g.x, -g.y, g.y);
    let on = toward > textureLoad(eye_starts, t, e.face, 0);
    let lit_sides = (sides >> OUTLINE_LIT_AT) & 15u;
    let lit = (vec4(lit_sides) & vec4(1u, 2u, 4u, 8u)) != vec4(0u);
    if any(on & !lit) {
        return -1.0;
    }
    return select(0.0, 1.0, any(on));
}

// Where each side's strip of eye texel `t` of `face` (outline `sides`, neighbour `bits`)
// begins, in texels from its centre toward left, right, up and down (`strip_shift`): a strip
// of `OUTLINE_STRIP` texels ending where a crease side's plane meets its neighbour's
// (`eye_crease_at`), at a silhouette side's edge the shade pass found, else half a texel
// out; the whole texel (-BIG) where the body across that axis is narrower than half a strip
// (the strips meet); nowhere (BIG) on a side not outlined.
fn strip_starts(face: u32, t: vec2<u32>, sides: u32, bits: u32) -> vec4<f32> {
    let creases = (sides >> OUTLINE_CREASE_AT) & 15u;
    let outlined = ((sides >> OUTLINE_SILHOUETTE_AT) & 15u) | creases;
    var ends = vec4(0.5);
    for (var k = 0u; k < 4u; k++) {
        if (creases & (1u << k)) != 0u {
            ends[k] = eye_crease_at(face, t, k);
        } else if side_code(bits, k) >= 2u {
            ends[k] = side_edge(bits, k);
        }
    }
    var starts = vec4(BIG);
    for (var k = 0u; k < 4u; k++) {
        if (outlined & (1u << k)) == 0u {
            continue;
        }
        let o = k ^ 1u;
        let width = ends[k] + ends[o] - OUTLINE_STRIP - select(0.0, OUTLINE_STRIP, (outlined & (1u << o)) != 0u);
        starts[k] = select(ends[k] - OUTLINE_STRIP, -BIG, width < 0.5 * OUTLINE_STRIP);
    }
    return starts;
}

// Farther than any pixel lies from its texel's centre, in texels.
const BIG: f32 = 1.0e30;

// How far, in texels from eye texel `t`'s centre toward side `k`, its plane meets its
// neighbour's there (cull.wgsl `crease_at`, in texels).
fn eye_crease_at(face: u32, t: vec2<u32>, k: u32) -> f32 {
    let s = view.slots[view.eye_slot];
    let q = vec2<i32>(t) + NEIGHBOURS[k];
    if any(q < vec2(0)) || any(q >= vec2(i32(s.n))) {
        return 0.5;
    }
    let fr = slot_frame(s);
    let ga = textureLoad(eye_geo, t, face, 0);
    let gb = textureLoad(eye_geo, vec2<u32>(q), face, 0);
    let uv0 = texel_center_uv(t, s.n);
    let uv1 = texel_center_uv(vec2<u32>(q), s.n);
    let pa = frame_point(fr, face, uv0, ga.w);
    let pb = frame_point(fr, face, uv1, gb.w);
    let f0 = plane_gap(fr, face, uv0, pa, ga.xyz, pb, gb.xyz);
    let f1 = plane_gap(fr, face, uv1, pa, ga.xyz, pb, gb.xyz);
    if f0 * f1 < 0.0 {
        return clamp(f0 / (f0 - f1), 0.05, 1.0);
    }
    return 0.5;
}

// Before the fullscreen draw, once per texel of the faces the eye draws (the `gid.z`-th of
// its draw mask): the texel's strip ends (`texel_ends`) for `fs`, which reads them where the
// texel is outlined (elsewhere they are never read). A few tens of thousands of texels
// against the frame's hundreds of thousands of pixels.
@compute @workgroup_size(8, 8, 1)
fn strip_ends(@builtin(global_invocation_id) gid: vec3<u32>) {
    let eye = view.slots[view.eye_slot];
    var face = 6u;
    var seen = 0u;
    for (var f = 0u; f < 6u; f++) {
        if (eye.draw_mask & (1u << f)) != 0u {
            if seen == gid.z {
                face = f;
            }
            seen++;
        }
    }
    if face > 5u || gid.x >= eye.n || gid.y >= eye.n {
        return;
    }
    let t = gid.xy;
    let lit = textureLoad(eye_lit, t, face, 0);
    let sides = lit_outline(lit.rgb);
    textureStore(starts_out, t, face, strip_starts(face, t, sides, u32(lit.a)));
    textureStore(lab_out, t, face, strip_lab(lit.rgb));
}

// Lit colour `c` in OKLab, its lightness posterized a band darker and a band lighter
// (`posterize` with a shift of -1 and 1, which it finishes per pixel): (dark L, light L, a, b).
fn strip_lab(c: vec3<f32>) -> vec4<f32> {
    let lab = oklab_from_linear(max(c, vec3(0.0)));
    let dark = posterized_lightness(lab.x, view.bands, -1.0);
    let light = posterized_lightness(lab.x, view.bands, 1.0);
    return vec4(dark, light, lab.yz);
}

@fragment
fn fs(in: FullscreenOut) -> FsOut {
    let e = eye_ray(in.ndc);
    let eye = view.slots[view.eye_slot];
    if e.face > 5u || (eye.draw_mask & (1u << e.face)) == 0u {
        return FsOut(vec4(linear_to_srgb(view.sky.rgb), 1.0), 0u, NDC_FAR);
    }
    var t = texel_of_uv(e.uv, eye.n);
    var id = textureLoad(eye_ids, t, e.face, 0).r;
    var lit = textureLoad(eye_lit, t, e.face, 0);
    if id != 0u {
        let step = past_edge(e.uv, eye.n, t, u32(lit.a));
        if any(step != vec2(0)) {
            t = vec2<u32>(vec2<i32>(t) + step);
            id = textureLoad(eye_ids, t, e.face, 0).r;
            lit = textureLoad(eye_lit, t, e.face, 0);
        }
    }
    var key = 0u;
    var colour = lit.rgb;
    let sides = lit_outline(lit.rgb);
    if id != 0u && sides != 0u {
        // `posterize(lit.rgb, view.bands, shift)`, from its start `strip_ends` worked out
        // (its cube roots, for every pixel, were a fifth of the pass).
        let shift = strip_shift(e, t, sides);
        if shift != 0.0 {
            let lab = textureLoad(eye_lab, t, e.face, 0);
            colour = max(linear_from_oklab(vec3(select(lab.y, lab.x, shift < 0.0), lab.zw)), vec3(0.0));
        }
    }
    var depth = NDC_FAR;
    let p = eye_point(e, textureLoad(eye_geo, t, e.face, 0).w);
    let clip = view.view_proj * vec4(p, 1.0);
    let in_depth = within_view_depth(clip);
    if id != 0u && !in_depth {
        colour = sky_texel(view.sky.rgb, view.bands);
    }
    if id != 0u && in_depth {
        key = texel_key(view.eye_slot, e.face, t, view.max_n) + 1u;
        colour = hazed(colour, length(p - e.start));
        // Reversed depth is about near / distance under perspective: dividing it pushes the
        // distance back by a fraction. An orthographic probe's quads are exact, so there are
        // no gaps to fill: there the fill stays at the far plane. (The clip position is
        // worked out outside any branch: computed inside a nested one, lavapipe's resident
        // memory grew 67 MiB over 300 frames of the `texel-run soak` test.)
        if view.ortho == 0u {
            depth = clamp(clip.z / clip.w / (1.0 + GAP_DEPTH), NDC_FAR, 1.0);
        }
    }
    return FsOut(vec4(linear_to_srgb(colour), 1.0), key, depth);
}
