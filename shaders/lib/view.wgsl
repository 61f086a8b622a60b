// Per-frame view data shared by cull, splat and background (crates/render/src/frame.rs
// `ViewGlobals`).

// The frame's depth is reversed (crates/render/src/input.rs `projection_reverse_z`): NDC
// depth 1 at the near plane, 0 at the far one, so a float depth buffer keeps its precision far
// away. Nearer is greater.
const NDC_NEAR: f32 = 1.0;
const NDC_FAR: f32 = 0.0;

struct SlotView {
    origin: vec3<f32>,
    n: u32,
    // 0 eye, 1 grid, 2 previous, 3 unused this frame.
    role: u32,
    // Bit f set: face f is drawn.
    draw_mask: u32,
    // An orthographic probe (lib/common.wgsl `ProbeFrame`): its half extent, 0 for a cube.
    half: f32,
    _pad0: u32,
    right: vec4<f32>,
    down: vec4<f32>,
    forward: vec4<f32>,
    // Planes (normal, d) of big flat faces that pass near this stable probe (input.rs
    // `ProbeView::near_faces`; zero where unused): cull.wgsl lays its texels on them flat.
    near_faces: array<vec4<f32>, 4>,
}

// The texel frame of slot view `s`.
fn slot_frame(s: SlotView) -> ProbeFrame {
    return ProbeFrame(s.origin, s.half, s.right.xyz, s.down.xyz, s.forward.xyz);
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
    // 1 for an orthographic camera (its depth is linear), 0 for a perspective one.
    ortho: u32,
    // OKLab lightness bands (the shade pass's).
    bands: u32,
    _pad: u32,
    // The camera's unit view direction (every view ray's, for an orthographic camera).
    forward: vec4<f32>,
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
// In a splat's shape word (role | texels << 8): the run goes down a column.
const SPLAT_COLUMN: u32 = 0x80000000u;
// In a splat's shape word: bits 20-22, which piece of an outlined texel's quad it is (0 the
// body or a whole quad, k + 1 the strip along side k: cull.wgsl `emit_outlined`).
const SPLAT_PART_AT: u32 = 20u;
// In a splat's shape word: bits 16-19, the owner of a crossfade's pixel cannot see corner
// 0-3 (cull.wgsl `owner_miss_bits`).
const SPLAT_OWNER_MISSES: u32 = 16u;

// One quad of the cull pass's list, drawn by the splat pass (crates/render/src/passes/cull.rs
// `SPLAT_BYTES`). xyz: corner; c0.w key + 1 of the first texel, c1.w packed sRGB colour,
// c2.w role | texels << 8 | SPLAT_COLUMN for a column run | the owner-miss bits of its
// corners (cull.wgsl `owner_miss_bits`), c3.w how far the quad reaches past the centres of
// its first and last texel along the run, in texels, halved (pack2x16unorm) (all bitcast).
// A one-texel quad of a terrain has the alpha byte of its colour SPLAT_TERRAIN_ALPHA, and
// c3.w its texel's `lit_terrain` | object index << SPLAT_TERRAIN_OBJECT_AT instead.
struct Splat {
    c0: vec4<f32>,
    c1: vec4<f32>,
    c2: vec4<f32>,
    c3: vec4<f32>,
}

const SPLAT_TERRAIN_ALPHA: u32 = 0xfeu;
const SPLAT_TERRAIN_OBJECT_AT: u32 = 14u;
// Objects past this index keep their texels' colour.
const SPLAT_TERRAIN_OBJECTS: u32 = 0x3ffffu;

// World position of corner `k` (0-3) of splat `s`.
fn splat_corner(s: Splat, k: u32) -> vec3<f32> {
    switch k {
        case 0u: { return s.c0.xyz; }
        case 1u: { return s.c1.xyz; }
        case 2u: { return s.c2.xyz; }
        default: { return s.c3.xyz; }
    }
}

// The middle of splat `s` (its corners' mean): a one-texel quad's texel point.
fn splat_mid(s: Splat) -> vec3<f32> {
    return 0.25 * (s.c0.xyz + s.c1.xyz + s.c2.xyz + s.c3.xyz);
}

// Whether splat `s` is a one-texel terrain quad (its pixels show the terrain's).
fn is_terrain_splat(s: Splat) -> bool {
    return (bitcast<u32>(s.c1.w) >> 24u) == SPLAT_TERRAIN_ALPHA;
}

// What a terrain quad shows (terrain_splat.wgsl, one per splat of the list, written for the
// terrain quads only): the packed sRGB colours of the 2 × 2 terrain pixels nearest its
// texel's point (x first, then z), their grid (the block's corner on X and Z, the pixel
// size; w the stamp of what it was made from, terrain_splat.wgsl `record_stamp`) and the
// ground along the block's two inner edges, which each screen pixel's view ray is tested
// against (splat.wgsl `terrain_sides`): from the block's corner, the height along x = size
// is `edges.x + edges.y · z` and along z = size `edges.z + edges.w · x`
// (crates/render/src/passes/terrain_splat.rs `RECORD_BYTES`).
struct TerrainSplat {
    cells: vec4<u32>,
    grid: vec4<f32>,
    edges: vec4<f32>,
}

// The view ray through `world`: from the camera toward it (`dir` = `world` − camera), or
// under an orthographic view from `world` itself along the view axis. Both are affine in
// `world`.
struct ViewRay {
    origin: vec3<f32>,
    dir: vec3<f32>,
}

fn view_ray_through(world: vec3<f32>) -> ViewRay {
    if view.ortho != 0u {
        return ViewRay(world, view.forward.xyz);
    }
    return ViewRay(view.camera.xyz, world - view.camera.xyz);
}

// The slot of the stable probe drawn for `role` (grid or previous), 3 when none is.
fn role_slot(role: u32) -> u32 {
    if role == ROLE_GRID {
        return view.grid_slot;
    }
    for (var s = 1u; s < 3u; s++) {
        if view.slots[s].role == ROLE_PREVIOUS {
            return s;
        }
    }
    return 3u;
}

// Whether a stable probe's quads can win any pixel this frame: the grid draws the Bayer
// cells below fade_t, the previous probe the rest.
fn draws_pixels(role: u32) -> bool {
    return (role == ROLE_GRID && view.fade_t > 0.0) || (role == ROLE_PREVIOUS && view.fade_t < 1.0);
}

// Whether a stable probe's quads are drawn this frame: those that win pixels, and while a
// crossfade runs the grid probe's from its first frame too, behind the previous probe's
// (splat.wgsl `fade_depth`), where it fills before the eye does.
fn draws_quads(role: u32) -> bool {
    return draws_pixels(role) || (role == ROLE_GRID && view.fade_t < 1.0);
}

// Whether a stable probe's texel with depth `dn` shows the surface point at Chebyshev
// distance `d` from its origin: within two texels' depth step of a 60° slope.
fn same_surface(d: f32, dn: f32, n: u32) -> bool {
    return abs(dn - d) <= d * (2.0 / f32(n)) * 3.5;
}

// How the eye probe sees the pixel at `ndc`: the face and face coordinates under it, and the
// ray its texels' depths are measured along. A cube eye sits at the camera and looks along
// the pixel's direction; an orthographic one looks along the view from the camera's plane,
// and the pixel's parallel ray meets its face where the pixel's near point projects onto it.
// `face` 6: the pixel lies off the eye's face.
struct EyeRay {
    face: u32,
    uv: vec2<f32>,
    start: vec3<f32>,
    dir: vec3<f32>,
    // A texel of depth `d` shows the point `start + dir · (d − depth0) / along`.
    depth0: f32,
    along: f32,
}

fn eye_ray(ndc: vec2<f32>) -> EyeRay {
    let eye = view.slots[view.eye_slot];
    let far = view.inv_view_proj * vec4(ndc, NDC_FAR, 1.0);
    if eye.half > 0.0 {
        let near = view.inv_view_proj * vec4(ndc, NDC_NEAR, 1.0);
        let start = near.xyz / near.w;
        let dir = normalize(far.xyz / far.w - start);
        let hit = frame_locate(slot_frame(eye), start);
        let face = select(hit.face, 6u, any(abs(hit.uv) > vec2(1.0)));
        return EyeRay(face, hit.uv, start, dir, hit.depth, max(dot(dir, eye.forward.xyz), 1e-6));
    }
    let dir = far.xyz / far.w - view.camera.xyz;
    let fu = cube_face_uv(dir);
    return EyeRay(fu.face, fu.uv, view.camera.xyz, dir, 0.0, chebyshev(dir));
}

// The world point an eye texel of depth `d` shows along `e`.
fn eye_point(e: EyeRay, d: f32) -> vec3<f32> {
    return e.start + e.dir * ((d - e.depth0) / e.along);
}

// Whether a point at clip position `clip` (`view.view_proj` of it) lies between the view's
// near and far planes. The eye probe captures as far as `CAPTURE_FAR`, which may lie past the
// view's far plane, and the shade pass leaves an eye texel whose quad cannot reach the view
// unlit (black): so a fill from the eye shows the sky where its texel lies past the far plane
// (or before the near one), as the splats' quads are clipped there and the raster shows
// nothing.
fn within_view_depth(clip: vec4<f32>) -> bool {
    return clip.w > 0.0 && clip.z >= NDC_FAR * clip.w && clip.z <= NDC_NEAR * clip.w;
}


// `same_surface` for frame `f`: an orthographic face's texels are one size at every depth.
fn frame_same_surface(f: ProbeFrame, d: f32, dn: f32, n: u32) -> bool {
    if f.half > 0.0 {
        return abs(dn - d) <= 2.0 * f.half / f32(n) * 3.5;
    }
    return same_surface(d, dn, n);
}

// World size of a texel of a face of `n` texels at Chebyshev depth `d` along `ray` (a cube
// direction, |ray| ≥ 1 stretches it off the face centre).
fn texel_world_size(d: f32, n: u32, ray: vec3<f32>) -> f32 {
    return d * (2.0 / f32(n)) * length(ray);
}

// Whether the splat quad of the texel at `p` can reach the view: a sphere of 2.5 texels
// (the largest expanded quad) against the six frustum planes. Cull draws by this test and
// shade lights eye texels by it, so every drawn eye quad was lit this frame.
fn quad_in_view(p: vec3<f32>, texel_world: f32) -> bool {
    return sphere_in_view(p, 2.5 * texel_world);
}

// Whether a sphere around `p` of `radius` reaches the view frustum.
fn sphere_in_view(p: vec3<f32>, radius: f32) -> bool {
    for (var i = 0u; i < 6u; i++) {
        if dot(view.planes[i].xyz, p) + view.planes[i].w < -radius {
            return false;
        }
    }
    return true;
}

// Along the ray through uv: its distance to plane (pa, na) less its distance to (pb, nb).
fn plane_gap(fr: ProbeFrame, face: u32, uv: vec2<f32>, pa: vec3<f32>, na: vec3<f32>, pb: vec3<f32>, nb: vec3<f32>) -> f32 {
    let o = frame_ray_start(fr, uv);
    let r = frame_ray(fr, face, uv);
    return dot(na, pa - o) / dot(na, r) - dot(nb, pb - o) / dot(nb, r);
}
