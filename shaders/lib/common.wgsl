// Shared WGSL: the cube-face convention (the same as texel_probes::cube, pinned by tests on
// both sides), OKLab colour, and the 4×4 Bayer matrix.
//
// Faces: 0 +X, 1 −X, 2 +Y, 3 −Y, 4 +Z, 5 −Z. Face coordinates (u, v) in [−1, 1], v down:
//   +X (1, −v, −u)   −X (−1, −v, u)   +Y (u, 1, v)   −Y (u, −1, −v)   +Z (u, −v, 1)   −Z (−u, −v, −1)
// On ties X wins over Y, Y over Z.

#include "lib/constants.wgsl"

fn cube_dir(face: u32, u: f32, v: f32) -> vec3<f32> {
    switch face {
        case 0u: { return vec3(1.0, -v, -u); }
        case 1u: { return vec3(-1.0, -v, u); }
        case 2u: { return vec3(u, 1.0, v); }
        case 3u: { return vec3(u, -1.0, -v); }
        case 4u: { return vec3(u, -v, 1.0); }
        default: { return vec3(-u, -v, -1.0); }
    }
}

struct FaceUv {
    face: u32,
    uv: vec2<f32>,
}

fn cube_face_uv(r: vec3<f32>) -> FaceUv {
    let a = abs(r);
    if a.x >= a.y && a.x >= a.z {
        if r.x >= 0.0 { return FaceUv(0u, vec2(-r.z, -r.y) / a.x); }
        return FaceUv(1u, vec2(r.z, -r.y) / a.x);
    }
    if a.y >= a.z {
        if r.y >= 0.0 { return FaceUv(2u, vec2(r.x, r.z) / a.y); }
        return FaceUv(3u, vec2(r.x, -r.z) / a.y);
    }
    if r.z >= 0.0 { return FaceUv(4u, vec2(r.x, -r.y) / a.z); }
    return FaceUv(5u, vec2(-r.x, -r.y) / a.z);
}

// Texel (column, row) of face coordinates on a face of n texels, clamped to the face.
fn texel_of_uv(uv: vec2<f32>, n: u32) -> vec2<u32> {
    let t = floor((uv * 0.5 + 0.5) * f32(n));
    return vec2<u32>(clamp(t, vec2(0.0), vec2(f32(n) - 1.0)));
}

// Face coordinates of a texel centre.
fn texel_center_uv(texel: vec2<u32>, n: u32) -> vec2<f32> {
    return (vec2<f32>(texel) + 0.5) * (2.0 / f32(n)) - 1.0;
}

fn chebyshev(r: vec3<f32>) -> f32 {
    let a = abs(r);
    return max(a.x, max(a.y, a.z));
}

// Equation (1) of the paper: the world point at Chebyshev depth d along r from o.
fn probe_point(o: vec3<f32>, r: vec3<f32>, d: f32) -> vec3<f32> {
    return o + r * (d / chebyshev(r));
}

// A probe's texel frame: a cube (`half` 0: texel rays leave `origin` along `cube_dir`, depth
// Chebyshev) or one orthographic face (`half` > 0, crates/probes/src/ortho.rs: face 0 only,
// every texel's ray runs along `forward` from the plane through `origin` spanned by `right`
// (u) and `down` (v), `half` world units from its centre to each edge; depth along
// `forward`).
struct ProbeFrame {
    origin: vec3<f32>,
    half: f32,
    right: vec3<f32>,
    down: vec3<f32>,
    forward: vec3<f32>,
}

// The world point of face coordinates `uv` of `face` at depth `d`.
fn frame_point(f: ProbeFrame, face: u32, uv: vec2<f32>, d: f32) -> vec3<f32> {
    if f.half > 0.0 {
        return f.origin + f.half * (uv.x * f.right + uv.y * f.down) + d * f.forward;
    }
    return probe_point(f.origin, cube_dir(face, uv.x, uv.y), d);
}

// The direction of the ray through face coordinates `uv` of `face` (a cube direction, |·|∞ = 1,
// or `forward`): a texel's point is its ray's start plus this times its depth.
fn frame_ray(f: ProbeFrame, face: u32, uv: vec2<f32>) -> vec3<f32> {
    if f.half > 0.0 {
        return f.forward;
    }
    return cube_dir(face, uv.x, uv.y);
}

// Where the ray through `uv` starts: the origin of a cube, the face plane of an orthographic
// probe.
fn frame_ray_start(f: ProbeFrame, uv: vec2<f32>) -> vec3<f32> {
    if f.half > 0.0 {
        return f.origin + f.half * (uv.x * f.right + uv.y * f.down);
    }
    return f.origin;
}

// World size of a texel of a face of `n` texels at depth `d` along `ray` (frame_ray).
fn frame_texel_size(f: ProbeFrame, d: f32, n: u32, ray: vec3<f32>) -> f32 {
    if f.half > 0.0 {
        return 2.0 * f.half / f32(n);
    }
    return d * (2.0 / f32(n)) * length(ray);
}

// The face, face coordinates and depth at which `f` sees world point `p`.
struct FrameHit {
    face: u32,
    uv: vec2<f32>,
    depth: f32,
}

fn frame_locate(f: ProbeFrame, p: vec3<f32>) -> FrameHit {
    let q = p - f.origin;
    if f.half > 0.0 {
        return FrameHit(0u, vec2(dot(q, f.right), dot(q, f.down)) / f.half, dot(q, f.forward));
    }
    let fu = cube_face_uv(q);
    return FrameHit(fu.face, fu.uv, chebyshev(q));
}

// Face coordinates of world point `m` on face `face` of frame `f`, past the face's edge
// where its plane goes on (a point behind a cube face's plane lands far outside).
fn frame_uv_on(f: ProbeFrame, face: u32, m: vec3<f32>) -> vec2<f32> {
    let w = m - f.origin;
    if f.half > 0.0 {
        return vec2(dot(w, f.right), dot(w, f.down)) / f.half;
    }
    let axis = cube_dir(face, 0.0, 0.0);
    let s = w / max(dot(w, axis), 1e-6);
    return vec2(dot(s, cube_dir(face, 1.0, 0.0) - axis), dot(s, cube_dir(face, 0.0, 1.0) - axis));
}

// --- colour ---

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3(2.4)), c / 12.92, c <= vec3(0.04045));
}

fn oklab_from_linear(c: vec3<f32>) -> vec3<f32> {
    let l = 0.4122214708 * c.r + 0.5363325363 * c.g + 0.0514459929 * c.b;
    let m = 0.2119034982 * c.r + 0.6806995451 * c.g + 0.1073969566 * c.b;
    let s = 0.0883024619 * c.r + 0.2817188376 * c.g + 0.6299787005 * c.b;
    let l3 = pow(max(l, 0.0), 1.0 / 3.0);
    let m3 = pow(max(m, 0.0), 1.0 / 3.0);
    let s3 = pow(max(s, 0.0), 1.0 / 3.0);
    return vec3(
        0.2104542553 * l3 + 0.7936177850 * m3 - 0.0040720468 * s3,
        1.9779984951 * l3 - 2.4285922050 * m3 + 0.4505937099 * s3,
        0.0259040371 * l3 + 0.7827717662 * m3 - 0.8086757660 * s3,
    );
}

fn linear_from_oklab(c: vec3<f32>) -> vec3<f32> {
    let l3 = c.x + 0.3963377774 * c.y + 0.2158037573 * c.z;
    let m3 = c.x - 0.1055613458 * c.y - 0.0638541728 * c.z;
    let s3 = c.x - 0.0894841775 * c.y - 1.2914855480 * c.z;
    let l = l3 * l3 * l3;
    let m = m3 * m3 * m3;
    let s = s3 * s3 * s3;
    return vec3(
        4.0767416621 * l - 3.3077115913 * m + 0.2309699292 * s,
        -1.2684380046 * l + 2.6097574011 * m - 0.3413193965 * s,
        -0.0041960863 * l - 0.7034186147 * m + 1.7076147010 * s,
    );
}

// A lit colour rounded to a half float's 10 bits of mantissa: posterization fixes the
// lightness only, and runs.wgsl joins texels of exactly one colour, so hue and chroma are
// rounded as they were when the lit texture held half floats (its alpha now needs more bits
// than a half's). By bits: pack2x16float needs a capability not every device has.
fn half_precision(c: vec3<f32>) -> vec3<f32> {
    return bitcast<vec3<f32>>((bitcast<vec3<u32>>(c) + vec3(0x1000u)) & vec3(0xffffe000u));
}

// The colour a sky texel of a lit face holds, for a sky of `sky` posterized to `bands`.
fn sky_texel(sky: vec3<f32>, bands: u32) -> vec3<f32> {
    return half_precision(posterize(sky, bands, 0.0));
}

// Quantizes OKLab lightness to `bands` steps, after shifting it by `shift` bands.
fn posterize(c: vec3<f32>, bands: u32, shift: f32) -> vec3<f32> {
    var lab = oklab_from_linear(max(c, vec3(0.0)));
    lab.x = posterized_lightness(lab.x, bands, shift);
    return max(linear_from_oklab(lab), vec3(0.0));
}

// OKLab lightness `l` shifted by `shift` bands and quantized to `bands` steps (`posterize`).
fn posterized_lightness(l: f32, bands: u32, shift: f32) -> f32 {
    let b = f32(bands);
    return clamp(round(l * b + shift) / b, 0.0, 1.0);
}

// --- dither ---

// (value + 0.5) / 16 of the 4×4 Bayer matrix at a pixel.
// The matrix is packed four bits an entry, row by row (rows 0–1 in the first word), so no
// array is built per fragment.
fn bayer_threshold(p: vec2<u32>) -> f32 {
    let i = (p.y % 4u) * 4u + (p.x % 4u);
    let words = vec2<u32>(0x6e4ca280u, 0x5d7f91b3u);
    let v = (words[i / 8u] >> ((i % 8u) * 4u)) & 15u;
    return (f32(v) + 0.5) / 16.0;
}

// --- scene records (crates/render/src/gpu_scene.rs) ---

struct Object {
    albedo: vec3<f32>,
    flags: u32,
    emissive: vec3<f32>,
    id: u32,
    // A highlight's strength (0: none) and shininess (crates/scene Material `specular`).
    specular: vec4<f32>,
}

// The Blinn-Phong highlight of a light from `to_light` on a surface of normal `n` seen along
// `to_eye` (both unit), for `spec` (strength, shininess).
fn highlight(n: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>, spec: vec4<f32>) -> f32 {
    if spec.x <= 0.0 {
        return 0.0;
    }
    let h = normalize(to_light + to_eye);
    return spec.x * pow(max(dot(n, h), 0.0), spec.y);
}

// A directional light: unit direction toward it, and its colour (crates/render/src/passes/
// shade.rs `Sun`).
struct Sun {
    to_light: vec4<f32>,
    colour: vec4<f32>,
}

struct PointLight {
    position: vec3<f32>,
    radius: f32,
    colour: vec4<f32>,
}

const FLAG_OUTLINED: u32 = 1u;
const FLAG_EMISSIVE: u32 = 2u;
// A terrain, whose index is flags >> 8 (only the low 8 bits reach the albedo target).
const FLAG_TERRAIN: u32 = 4u;
// Its triangles are in the static BVH (crates/render/src/gpu_scene.rs `FLAG_IN_BVH`).
const FLAG_IN_BVH: u32 = 16u;

// --- a terrain texel's lit colour (shade.wgsl writes it, cull.wgsl reads it) ---

// The splat pass colours each screen pixel of a terrain texel's quad from the terrain pixel
// under it (terrain_splat.wgsl), lit with the texel's shadows and outline: the shade
// pass hands those on in the low 13 mantissa bits of the lit colour's red and green, which
// its half-precision rounding leaves zero (readers of the colour see it within 2^-11): red
// holds a marker bit and bit i set where light i reaches the texel (the first
// `TERRAIN_LIGHTS`), green the outline's band shift + 1.
const TERRAIN_LIGHTS: u32 = 12u;
const TERRAIN_MARK: u32 = 0x1000u;

// Half-precision colour `c` (every channel's low 13 bits zero) carrying `unshadowed` and
// `shift`; channels are kept normal floats (at least 2^-14), which no driver flushes.
fn lit_with_terrain(c: vec3<f32>, unshadowed: u32, shift: f32) -> vec3<f32> {
    var bits = bitcast<vec3<u32>>(max(c, vec3(exp2(-14.0))));
    bits.x |= TERRAIN_MARK | (unshadowed & ((1u << TERRAIN_LIGHTS) - 1u));
    bits.y |= u32(clamp(shift + 1.0, 0.0, 2.0));
    return bitcast<vec3<f32>>(bits);
}

// Word `word` of `lit_terrain` with its shift replaced by `shift` (-1, 0 or 1).
fn terrain_with_shift(word: u32, shift: f32) -> u32 {
    return (word & ~(3u << TERRAIN_LIGHTS)) | (u32(clamp(shift + 1.0, 0.0, 2.0)) << TERRAIN_LIGHTS);
}

// What `lit_with_terrain` put in lit colour `c`: the lights that reach it (bits 0-11) and
// the shift + 1 (bits 12-13); NO_TERRAIN where `c` carries nothing.
const NO_TERRAIN: u32 = 0xffffffffu;
fn lit_terrain(c: vec3<f32>) -> u32 {
    let bits = bitcast<vec3<u32>>(c);
    if (bits.x & TERRAIN_MARK) == 0u {
        return NO_TERRAIN;
    }
    return (bits.x & ((1u << TERRAIN_LIGHTS) - 1u)) | ((bits.y & 3u) << TERRAIN_LIGHTS);
}

// --- a texel's dither rank, anchored to the surface (shade.wgsl writes it, cull.wgsl
// passes it on in its quad's alpha, present.wgsl `fs_map` dithers by it) ---

// With a dithered palette, a texel's rank in the 4 × 4 Bayer matrix (0–15) rides in the
// low mantissa bits of its lit colour's green, which half precision leaves zero and a
// terrain texel uses only bits 0–1 of: bits DITHER_AT.. the rank, DITHER_MARK set. The
// rank is the surface's, not the face's: the Bayer cell of the texel's centre on the
// plane of its normal's dominant axis, each cell a power of two at least the texel's
// footprint along that axis, so the next probe's texels over the same surface mostly
// take the same ranks and a crossing does not redraw the pattern. A cell is capped at two
// texels' width before the power of two: at a grazing angle the footprint's box along
// both axes grows long, and uncapped cells drew streaks many texels wide (walk_cells,
// 2026-12-07: shimmer 0.0089 uncapped, 0.0091 capped; one texel's width on every axis
// instead skips ranks where texels stretch and scored 0.0111).
const DITHER_AT: u32 = 2u;
const DITHER_MARK: u32 = 0x40u;
const NO_DITHER: u32 = 0xffffffffu;

// The Bayer rank (0–15) of the surface of normal `n` at `p`, seen along `ray` (from the
// probe) by a texel `w` wide across the ray.
fn surface_dither_rank(p: vec3<f32>, n: vec3<f32>, ray: vec3<f32>, w: f32) -> u32 {
    let a = abs(n);
    // The plane's two axes: those other than the normal's dominant one.
    var axes = vec2(0u, 1u);
    if a.x >= a.y && a.x >= a.z {
        axes = vec2(1u, 2u);
    } else if a.y >= a.z {
        axes = vec2(0u, 2u);
    }
    // The texel's footprint: two sides w long across the ray, carried along it onto the
    // surface; its extent along each axis, so that every cell holds a texel's centre (all
    // 16 ranks show: the dither keeps its tone).
    let r = normalize(ray);
    let t1 = normalize(cross(r, select(vec3(0.0, 1.0, 0.0), vec3(1.0, 0.0, 0.0), abs(r.y) > 0.9)));
    let t2 = cross(r, t1);
    let nr = dot(n, r);
    let along = select(-1.0, 1.0, nr >= 0.0) / max(abs(nr), 0.05);
    let f1 = (t1 - r * (dot(n, t1) * along)) * w;
    let f2 = (t2 - r * (dot(n, t2) * along)) * w;
    let extent = vec2(abs(f1[axes.x]) + abs(f2[axes.x]), abs(f1[axes.y]) + abs(f2[axes.y]));
    let cell = exp2(ceil(log2(min(max(extent, vec2(1e-6)), vec2(max(2.0 * w, 1e-6))))));
    let c = vec2<i32>(floor(vec2(p[axes.x], p[axes.y]) / cell));
    return u32(bayer_threshold(vec2<u32>(c & vec2(3))) * 16.0);
}

// The alpha byte of a quad's packed colour (cull.wgsl) and so of its pixels in the frame
// carrying dither rank `rank`: 16 rank + 8, below 255 (no rank) and SPLAT_TERRAIN_ALPHA.
fn dither_alpha(rank: u32) -> u32 {
    return (rank & 15u) * 16u + 8u;
}

// Half-precision colour `c` carrying dither rank `rank`; green is kept a normal float.
fn lit_with_dither(c: vec3<f32>, rank: u32) -> vec3<f32> {
    var bits = bitcast<vec3<u32>>(vec3(c.x, max(c.y, exp2(-14.0)), c.z));
    bits.y |= DITHER_MARK | ((rank & 15u) << DITHER_AT);
    return bitcast<vec3<f32>>(bits);
}

// The dither rank `lit_with_dither` put in lit colour `c`, NO_DITHER where none.
fn lit_dither(c: vec3<f32>) -> u32 {
    let g = bitcast<u32>(c.y);
    return select(NO_DITHER, (g >> DITHER_AT) & 15u, (g & DITHER_MARK) != 0u);
}

// --- an outlined texel's sides (shade.wgsl writes them, cull.wgsl draws them) ---

// An outline darkens (or lightens) one band of a texel, but the texel's quad runs from the
// edge it outlines (fixed to the world) to its inner side (on the probe's texel grid), so a
// whole-texel shift is 1/2 to 3/2 texels wide and differs from probe to probe. An outlined
// texel of a perspective grid or previous probe (shade.wgsl) instead keeps its unshifted
// colour and names the sides in the low 13 mantissa bits of its lit colour's blue (free like
// red's and green's, `lit_with_terrain`); the cull pass then draws a strip of
// `OUTLINE_STRIP` texels along each, measured from the silhouette edge or the crease line,
// the same from every probe. Bit 0 marks such a texel; bits 1-4 its silhouette sides
// (left, right, up, down: `NEIGHBOURS`), 5-8 its crease sides, 9-12 those of its crease
// sides that are lit rather than darkened.
const OUTLINE_MARK: u32 = 1u;
const OUTLINE_SILHOUETTE_AT: u32 = 1u;
const OUTLINE_CREASE_AT: u32 = 5u;
const OUTLINE_LIT_AT: u32 = 9u;
const OUTLINE_BITS: u32 = 0x1fffu;
const OUTLINE_STRIP: f32 = 0.5;

// Half-precision colour `c` carrying outline sides `sides` (OUTLINE_MARK | ...).
fn lit_with_outline(c: vec3<f32>, sides: u32) -> vec3<f32> {
    var bits = bitcast<vec3<u32>>(max(c, vec3(exp2(-14.0))));
    bits.z |= sides & OUTLINE_BITS;
    return bitcast<vec3<f32>>(bits);
}

// The outline sides `lit_with_outline` put in lit colour `c` (0 where none).
fn lit_outline(c: vec3<f32>) -> u32 {
    let sides = bitcast<vec3<u32>>(c).z & OUTLINE_BITS;
    return select(0u, sides, (sides & OUTLINE_MARK) != 0u);
}

// Lit colour `c` without the outline sides `lit_with_outline` put in it.
fn without_outline(c: vec3<f32>) -> vec3<f32> {
    if lit_outline(c) == 0u {
        return c;
    }
    var bits = bitcast<vec3<u32>>(c);
    bits.z &= ~OUTLINE_BITS;
    return bitcast<vec3<f32>>(bits);
}

// Lit colour `c` with its outline (`lit_outline`) as a whole texel's shift of one band
// (`bands`): darker where a side is a silhouette or a darkened crease, else lighter where one
// is a lit crease. For readers that show a texel whole (march.wgsl), not as quads.
fn lit_with_shift(c: vec3<f32>, bands: u32) -> vec3<f32> {
    let sides = lit_outline(c);
    if sides == 0u {
        return c;
    }
    let lit = (sides >> OUTLINE_LIT_AT) & 15u;
    let dark = ((sides >> OUTLINE_SILHOUETTE_AT) | ((sides >> OUTLINE_CREASE_AT) & ~lit)) & 15u;
    return posterize(c, bands, select(1.0, -1.0, dark != 0u));
}

// --- splat keys: a dense index over (slot, face, texel) with faces of `max_n` texels ---

fn texel_key(slot: u32, face: u32, t: vec2<u32>, max_n: u32) -> u32 {
    return ((slot * 6u + face) * max_n + t.y) * max_n + t.x;
}

fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3(0.0), vec3(1.0));
    return select(1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055, x * 12.92, x <= vec3(0.0031308));
}

// Draw lists (lib/lists.wgsl): the per-face counts before the entries, in u32s.
const LIST_HEADER: u32 = 8u;
// In a lit texel's neighbour bits (shade.wgsl; bits 0-7 are two per side): the surface
// curves here (a similar neighbour's normal differs, short of a crease), so a silhouette
// of it against the sky rolls as the viewpoint moves (cull.wgsl `half_size`).
const SIMILAR_CURVED: u32 = 256u;
// In a lit texel's neighbour bits: from this bit, three per side (left, right, up, down),
// where a silhouette side's edge crosses the line to that neighbour's centre, c − 1 for c/8
// of a texel from this texel's centre (shade.wgsl, the edge search; 3, half a texel,
// where it is not searched). The bits stay below 2^24, exact in the lit texture's f32 alpha.
const SIMILAR_EDGE_AT: u32 = 9u;
// In a lit texel's neighbour bits: a flat texel whose farther neighbours are other objects,
// or hide its plane (shade.wgsl), not its own surface past a convex crease: its quad's
// sides toward them end on its plane (cull.wgsl `ends_at_edge`).
const SIMILAR_APART: u32 = 0x200000u;
// In a lit texel's neighbour bits: the corner where its left (`CORNER_CUT_LEFT`) or right
// (`CORNER_CUT_RIGHT`) side's edge meets its up side's (or, where up is no silhouette, its
// down side's) is cut: the surface's edge runs across it (a slanting silhouette), where a
// ray three quarters of the way to the corner missed the surface (shade.wgsl, the corner
// rays); a box's corner is kept. `corner_side` says which of up and down it is.
const CORNER_CUT_LEFT: u32 = 0x400000u;
const CORNER_CUT_RIGHT: u32 = 0x800000u;

// Offsets of the four neighbours, in the order of the similar bits: left, right, up, down.
const NEIGHBOURS = array<vec2<i32>, 4>(vec2(-1, 0), vec2(1, 0), vec2(0, -1), vec2(0, 1));

// Side `k`'s kind (left, right, up, down) in lit texel neighbour `bits`, from its two bits
// (k and 4 + k): 0 nearer, 1 similar, 2 farther, 3 sky.
fn side_code(bits: u32, k: u32) -> u32 {
    return ((bits >> k) & 1u) | (((bits >> (4u + k)) & 1u) << 1u);
}

// Where side `k`'s edge lies, in texels from the centre (`SIMILAR_EDGE_AT`).
fn side_edge(bits: u32, k: u32) -> f32 {
    return f32(((bits >> (SIMILAR_EDGE_AT + 3u * k)) & 7u) + 1u) / 8.0;
}

// Whether side `k` (left, right, up, down) of a texel with neighbour `bits` is a searched
// silhouette side: its edge was found (farther geometry or the sky past it).
fn silhouette_side(bits: u32, k: u32) -> bool {
    return side_code(bits, k) >= 2u;
}

// The horizontal side (up 2, down 3) whose edge a left or right corner cut meets
// (`CORNER_CUT_LEFT`): up where up is a silhouette side, else down.
fn corner_side(bits: u32) -> u32 {
    return select(3u, 2u, silhouette_side(bits, 2u));
}

// Whether the corner between side `kx` (left 0, right 1) and side `ky` (up 2, down 3) is
// cut (`CORNER_CUT_LEFT`).
fn corner_cut(bits: u32, kx: u32, ky: u32) -> bool {
    let bit = select(CORNER_CUT_LEFT, CORNER_CUT_RIGHT, kx == 1u);
    return (bits & bit) != 0u && corner_side(bits) == ky;
}

// In a run's length (runs.wgsl's runs texture): the run goes down a column.
const RUN_COLUMN: u32 = 0x10000u;
