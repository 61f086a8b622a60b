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
// The shift of the pixel in direction `e` on eye texel `t` (outline `sides`, neighbour
// `bits`): -1 on a dark strip, 1 on a lit crease's, 0 on the body.
fn strip_shift(e: EyeRay, t: vec2<u32>, sides: u32, bits: u32) -> f32 {
    let n = view.slots[view.eye_slot].n;
    // Where the pixel lies from the texel's centre toward left, right, up and down, in texels.
    let g = (e.uv * 0.5 + 0.5) * f32(n) - (vec2<f32>(t) + 0.5);
    let toward = vec4(-g.x, g.x, -g.y, g.y);
    let creases = (sides >> OUTLINE_CREASE_AT) & 15u;
    let lit_sides = (sides >> OUTLINE_LIT_AT) & 15u;
    let outlined = ((sides >> OUTLINE_SILHOUETTE_AT) & 15u) | creases;
    // Each side's end, in texels from the centre.
    var ends = vec4(0.5);
    for (var k = 0u; k < 4u; k++) {
        if (creases & (1u << k)) != 0u {
            ends[k] = eye_crease_at(e.face, t, k);
        } else if side_code(bits, k) >= 2u {
            ends[k] = side_edge(bits, k);
        }
    }
    var shift = 0.0;
    for (var k = 0u; k < 4u; k++) {
        if (outlined & (1u << k)) == 0u {
            continue;
        }
        // A body narrower than half a strip across this axis is left out: the strips meet.
        let o = k ^ 1u;
        let width = ends[k] + ends[o] - OUTLINE_STRIP - select(0.0, OUTLINE_STRIP, (outlined & (1u << o)) != 0u);
        if toward[k] > ends[k] - OUTLINE_STRIP || width < 0.5 * OUTLINE_STRIP {
            if (lit_sides & (1u << k)) == 0u {
                return -1.0;
            }
            shift = 1.0;
        }
    }
    return shift;
}

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
        let shift = strip_shift(e, t, sides, u32(lit.a));
        if shift != 0.0 {
            colour = posterize(lit.rgb, view.bands, shift);
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
