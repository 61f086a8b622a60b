// Cull: turns the drawn faces' texels into a compact list of splat quads with indirect draw
// arguments. Our schedule walks the faces' draw lists (`listed`, one dispatch for all of
// them: a stable face's run heads, runs.wgsl; the eye texels the shade pass lit this frame),
// so it never scans a face, and skips quads that lie outside the view frustum or face away
// from the camera; one quad draws a whole run. The paper schedule (and ours with runs off)
// scans every texel of the drawn faces (`main`). Both only list what they keep, the
// outlined texels and runs for `outlined`, the rest for `kept_quads`, which work out the
// quads' corners. The corners are computed from the probe's data alone (never the camera),
// so they are bit-identical while the probe stays. crates/render/src/passes/cull.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"

struct DrawArgs {
    index_count: u32,
    instance_count: atomic<u32>,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
    // Texels and run heads looked at (crates/render/src/passes/cull.rs `DrawArgs::entries`).
    entries: u32,
}

@group(0) @binding(0) var<uniform> view: ViewGlobals;
@group(0) @binding(1) var<storage, read_write> splats: array<Splat>;
@group(0) @binding(2) var<storage, read_write> args: DrawArgs;
// The drawn (slot, face) pairs: the `count` that `main` scans (its dispatch's z runs over
// them), then the `listed` ones whose draw lists `listed` walks.
struct CullWork {
    count: u32,
    listed: u32,
    _pad1: u32,
    _pad2: u32,
    faces: array<vec4<u32>, 18>,
}
@group(0) @binding(3) var<uniform> work: CullWork;
// `listed`'s workgroup counts, written by `listed_args`.
struct DispatchArgs {
    x: u32,
    y: u32,
    z: u32,
}
// Where each listed face's entries start in `listed`'s index space (then the total).
@group(2) @binding(0) var<storage, read_write> starts: array<u32, 19>;
// The texels and runs `main` and `listed` keep (texel x | y << 16; slot | face << 2 |
// run << 5; cull.rs `kept`): the plain ones from the front of `at` for `kept_quads`, the
// outlined ones from its back for `outlined`. `emit`'s corners and `emit_outlined` are most
// of the compiled cull: lavapipe's and SwiftShader's invocations paid for them whether they
// drew or not (without `emit_outlined` in `listed`, an invocation that returns at once cost
// a third as much on lavapipe; the paper's scan took 357 -> 143 ms on SwiftShader), and most
// entries are culled, few outlined. Should the two ends meet (more entries than `at` holds,
// as many as the splat list), neither dispatch reads past the other's end.
struct Kept {
    plain: atomic<u32>,
    outlined: atomic<u32>,
    at: array<vec2<u32>>,
}
@group(2) @binding(1) var<storage, read_write> kept: Kept;
// Its own group: bound only while `listed_args` (or `kept_args`, `outlined_args`) writes it,
// not while the dispatch it sizes reads it.
@group(3) @binding(0) var<storage, read_write> dispatch: DispatchArgs;
// Most workgroups in one dimension of a dispatch (wgpu's default limit).
const MAX_GROUPS: u32 = 65535u;
#include "lib/slots.wgsl"

// Half-size toward neighbour `k` (left, right, up, down) of a texel with neighbour `bits`
// (two bits per side, k and 4 + k: see shade.wgsl), in texels. Toward a similar neighbour,
// tight (grazing-scaled by the angle between the surface and the probe ray, camera-
// independent). At a silhouette against farther geometry, exact: this texel occludes it, and
// the farther quad reaches under this one. Against the sky, exact: a texel is the object's
// when its centre ray meets it, so its square is already as often past the true edge as
// short of it. Only where the surface curves (`SIMILAR_CURVED`: a hill's crest, whose
// silhouette rolls over the surface as the viewpoint moves) a little more as it turns away
// (up to a quarter texel at grazing angles, where a quad standing across the ray tilts away
// from the surface). Faces of 128, 320×180: a fixed quarter texel more had grown every
// silhouette against the sky (coverage error on walk_cells 0.0251); grown by the angle
// everywhere, walk_cells 0.0204, wall_graze 0.0180, dolly 0.0237 (naive 0.0176, 0.0119,
// 0.0188); grown only where curved, 0.0183, 0.0157, 0.0213 (on flat surfaces by their tilt
// along each side's axis, 0.0200, 0.0174, 0.0233: the growth lay along the grazing side of
// every convex silhouette). Its cost: holes over the suite's paths 0.0006 -> 0.0009 (naive
// 0.0029). Exact everywhere opened the hills' crests (terrain_walk holes at faces of 48,
// 160×90: 0.0037; grown by the angle everywhere 0.0022, only where curved 0.0025). Toward
// a nearer surface, a full texel, reaching under the occluder so no gap opens between them
// when the camera moves off the probe origin (sized as a similar neighbour where the two meet at one depth, a wall on a
// floor: coverage error on occluder_pass 0.0158 -> 0.0161, walk_cells 0.0183 -> 0.0190).
// Reaching one texel under a nearer surface covers the slivers the camera sees past an
// occluder's edge from off the probe origin (measured: wall_graze eye pixels 32% -> 23%,
// ortho_pan's 2% -> 1.4%), so the eye probe fills less. Half sizes are at most 2 (the splat
// list stores them halved, as unorm).
const NEARER_HALF: f32 = 1.5;
// An orthographic probe's quads are exactly the texel squares toward similar neighbours
// (`quad_half`): its rays run along the view (or within half a turn step of it), so no gap
// opens between neighbours as the camera moves, and what the held direction misses the eye
// fills. Measured (stone_circle, 320×180, faces of 128): coverage error on ortho_pan 0.0195
// with the expanded quads, 0.0179 exact (snap 0.0189); iso_orbit 0.0179, 0.0167 (snap
// 0.0164); shimmer 0.0000 and 0.0035 either way. With silhouette sides ending at their
// edges and sides toward nearer surfaces reaching under them: ortho_pan 0.0116 (at faces of
// 64, 0.0385 -> 0.0207, naive 0.0342), iso_orbit 0.0096; shimmer 0.0000 and 0.0037.

fn half_size(bits: u32, k: u32, cos_theta: f32) -> f32 {
    let code = side_code(bits, k);
    if code == 0u {
        return NEARER_HALF;
    }
    let c = max(cos_theta, 0.14);
    let tan_theta = sqrt(1.0 - c * c) / c;
    if code == 1u {
        return min(0.575 + 0.05 * tan_theta, 1.0);
    }
    // A silhouette side ends where the shade pass found the edge (`SIMILAR_EDGE_AT`).
    let edge = side_edge(bits, k);
    if code == 3u && (bits & SIMILAR_CURVED) != 0u {
        return edge + min(0.05 * tan_theta, 0.25);
    }
    return edge;
}

// How far out the corner between sides `kx` and `ky` lies, as a fraction of its offsets:
// 0.6 where it is cut (`corner_cut`), else all of them. Half puts it on the line through the
// two edges; measured at faces of 64, 320×180 (tests/data/slanted_edges.ron, whose boxes'
// silhouettes slant at many angles): coverage error 0.0202 uncut, 0.0157 at 0.5, 0.0158 at
// 0.6, 0.0164 at 0.7 (naive 0.0186); holes 0.0007, 0.0015, 0.0012, 0.0010.
fn cut_scale(bits: u32, kx: u32, ky: u32) -> f32 {
    return select(1.0, 0.6, corner_cut(bits, kx, ky));
}

// `half_size`, or for an orthographic or eye probe (`exact`) exactly half a texel toward a
// similar neighbour; a silhouette side ends at the edge the shade pass found, and a side
// toward a nearer surface reaches under it (so no gap opens where that surface's edge is
// short of half a texel; seen along the probe's rays it stays hidden behind it).
fn quad_half(bits: u32, k: u32, cos_theta: f32, exact: bool) -> f32 {
    if exact {
        let code = side_code(bits, k);
        if code == 0u {
            return NEARER_HALF;
        }
        if code == 1u {
            return 0.5;
        }
        return side_edge(bits, k);
    }
    return half_size(bits, k, cos_theta);
}

// `quad_half` toward left, right, up and down.
fn quad_halves(bits: u32, cos_theta: f32, exact: bool) -> vec4<f32> {
    return vec4(quad_half(bits, 0u, cos_theta, exact), quad_half(bits, 1u, cos_theta, exact), quad_half(bits, 2u, cos_theta, exact), quad_half(bits, 3u, cos_theta, exact));
}

// A quad's corners lie at the texel's depth, in a plane facing the probe, so a quad seen
// from off the probe's origin is a little off its surface: far along a floor seen at a
// grazing angle, its side half a texel out stands above the floor, and its edge there shows
// a pixel past (or short of) where the floor meets the wall. Where a side ends at an edge
// against farther geometry (`ends_at_edge`: a silhouette or a junction the shade pass
// found) on a flat texel, its two corners are moved along their rays onto the surface's
// plane (`plane_corner`), so the edge is drawn where it lies in the world, from every
// viewpoint. Other sides keep the depth: measured (faces of 128, 320×180), corners on the
// plane on every side flickered under pure yaw (0.0001 -> 0.0022: a convex crease's quad
// continued its plane out past the crease); toward the sky too, 0.0003; here 0.0002, with
// coverage error on occluder_pass 0.0108 -> 0.0059 (naive 0.0090; the junctions searched
// without moving corners, 0.0099), walk_cells 0.0127 -> 0.0124, orbit 0.0131 -> 0.0123.
// At faces of 64 it had cost the colonnade's wall paths (wall_graze 0.0235 -> 0.0255, 0.0241
// without moving corners: the floor's junction seen slanting along the wall), until the
// corners inside the wall were clipped to its plane (`clip_behind`).
//
// Where corner `q`'s ray meets the plane through `on` (the run's middle point: its texels
// share the depth and the plane) with normal `nrm` (at most a quarter
// further or a fifth nearer than depth `d`, the texel's: a grazing plane runs far).
fn plane_corner(fr: ProbeFrame, face: u32, q: vec2<f32>, on: vec3<f32>, nrm: vec3<f32>, d: f32) -> vec3<f32> {
    let at_depth = frame_point(fr, face, q, d);
    let start = frame_ray_start(fr, q);
    let r = at_depth - start;
    let den = dot(nrm, r);
    if den >= 0.0 {
        return at_depth;
    }
    return start + r * clamp(dot(nrm, on - start) / den, 0.8, 1.25);
}

// Per side (left, right, up, down): it ends at an edge against farther geometry (bits 10),
// on a texel the shade pass marked `SIMILAR_APART`: flat (a curved surface's plane is only
// its tangent: terrain crests' corners moved onto it raised terrain_walk's shimmer 0.0123 ->
// 0.0165), and the farther neighbours are other objects or hide its plane (this surface
// past a convex crease, an architrave's side turning into its underside, is not: the
// underside's quad reaching under the side's met its plane-bound corners in depth, and the
// crease broke into speckles).
fn ends_at_edge(bits: u32) -> vec4<bool> {
    let codes = vec4(side_code(bits, 0u), side_code(bits, 1u), side_code(bits, 2u), side_code(bits, 3u));
    return codes == vec4(2u) & vec4((bits & SIMILAR_APART) != 0u);
}

// A stable probe that stands in line with a big flat face, past its edge (its plane within
// 0.4 cells of the probe, `texel_probes::placement::near_faces`, handed over per slot as
// `SlotView::near_faces`), sees the face at a grazing angle, each texel a long strip on it.
// Its quads, standing across the face toward the probe, are then seen from a camera
// elsewhere in the cell, farther off the plane and so more steeply, like the slats of a
// blind, and the eye probe fills between them in stripes (a survey walk over the textured
// level's brick wall, its probes 0.25 off the wall's back face's plane: `texel-eval survey
// --level assets/levels/textured.ron --count 6 --seed 1`, walk 01). There each quad lies on
// the face's plane, all four corners (`near_plane`), with exact half sizes: the texels'
// footprints on a flat face tile it from every viewpoint. Laid flat wherever a plane passes
// that near the probe, a round pillar's facets beside it flickered (colonnade survey walk
// 04 0.0074 -> 0.0104), and every flat texel seen at a grazing angle laid flat, floors did
// (pure yaw 0.0002 -> 0.0006): only big faces' texels are.
fn on_near_face(s: SlotView, p: vec3<f32>, nrm: vec3<f32>, d: f32) -> bool {
    for (var i = 0u; i < 4u; i++) {
        let f = s.near_faces[i];
        if dot(f.xyz, nrm) >= 0.999 && abs(dot(f.xyz, p) + f.w) <= 1.0e-3 * d + 1.0e-4 {
            return true;
        }
    }
    return false;
}

// Set per quad by `emit`: whether it lies on a stable probe's near face (`on_near_face`), so
// every corner of it lies on that plane.
var<private> near_plane: bool;

// Corner `q` of a quad: on the surface's plane where one of its two sides `ends_at_edge`,
// else at the texel's depth.
fn corner_at(fr: ProbeFrame, face: u32, q: vec2<f32>, on: vec3<f32>, nrm: vec3<f32>, d: f32, on_plane: bool) -> vec3<f32> {
    if on_plane {
        return plane_corner(fr, face, q, on, nrm, d);
    }
    return frame_point(fr, face, q, d);
}

// Corner `c` of a quad on the surface's plane, where its side `k` (left, right, up, down) of
// texel `t` ends against farther geometry: moved toward the quad's middle `p` (on the same
// plane) onto the plane of the texel across that side, if it lay behind it. An edge's
// corners are half a texel apart across its slant, so where a floor meets a wall one of
// them lies inside the wall, and seen from off the probe's origin that half of the floor's
// quad showed in front of the wall's quads (which stand across the wall, at their texels'
// depth) as a sawtooth of wedges along the junction. On the junction line the two planes
// meet, so the corner is where the edge is in the world, from every viewpoint. Measured at
// faces of 64, 320×180: coverage error on wall_graze 0.0228 -> 0.0222 (naive 0.0213),
// occluder_pass 0.0060 -> 0.0035; its cost, one more load per such side, about 2 ms of
// culling a frame on terrain_walk at 1280×720 (lavapipe: 9.2–10.2 -> 12.0–12.2 ms in
// alternated runs), where hills end against farther chunks.
fn clip_behind(slot: u32, face: u32, fr: ProbeFrame, t: vec2<u32>, k: u32, p: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let n = view.slots[slot].n;
    let q = vec2<i32>(t) + NEIGHBOURS[k];
    if any(q < vec2(0)) || any(q >= vec2(i32(n))) {
        return c;
    }
    // A side that ends at an edge has farther geometry past it (never the sky).
    let nt = vec2<u32>(q);
    let g = load_geo(slot, nt, face);
    let w = frame_point(fr, face, texel_center_uv(nt, n), g.w);
    let behind = dot(g.xyz, c - w);
    let front = dot(g.xyz, p - w);
    if behind >= 0.0 || front <= 0.0 {
        return c;
    }
    return p + (c - p) * (front / (front - behind));
}

// The corner of a quad where side `kx` (left 0, right 1) of texel `t` meets its side `ky`
// (up 2, down 3), all from that one texel (the first or last of a run) and its `bits`:
// `halves` (`quad_halves`, in face coordinates) out from its centre, less where a slanting
// edge runs across it (`cut_scale`: a rectangle's corner there lay outside the surface on
// every texel along the edge, so slanting silhouettes erred outward); on the surface's
// plane where either side `ends_at_edge`, and then not behind the texel past that side
// (`clip_behind`).
fn quad_corner(slot: u32, face: u32, fr: ProbeFrame, t: vec2<u32>, bits: u32, halves: vec4<f32>, kx: u32, ky: u32, p: vec3<f32>, nrm: vec3<f32>, d: f32) -> vec3<f32> {
    let x = f32(NEIGHBOURS[kx].x) * halves[kx];
    let y = f32(NEIGHBOURS[ky].y) * halves[ky];
    return split_corner(slot, face, fr, t, bits, x, y, kx, ky, true, true, p, nrm, d, 0u);
}

// How the stable probe that owns the pixel (the one that is not `role`) sees `p`.
const OWNER_SEES: u32 = 0u; // its texel there shows the same surface
const OWNER_PAST: u32 = 1u; // the sky or a farther surface: `p` lies past its silhouette
const OWNER_HIDDEN: u32 = 2u; // something nearer, or a face it has not captured

fn owner_view(role: u32, p: vec3<f32>) -> u32 {
    let owner = select(ROLE_GRID, ROLE_PREVIOUS, role == ROLE_GRID);
    for (var s = 1u; s < 3u; s++) {
        let v = view.slots[s];
        if v.role != owner {
            continue;
        }
        let fr = slot_frame(v);
        let hit = frame_locate(fr, p);
        if (v.draw_mask & (1u << hit.face)) == 0u || any(abs(hit.uv) > vec2(1.0)) {
            return OWNER_HIDDEN;
        }
        let t = texel_of_uv(hit.uv, v.n);
        if load_id(s, t, hit.face) == 0u {
            return OWNER_PAST;
        }
        let dn = load_geo(s, t, hit.face).w;
        if frame_same_surface(fr, hit.depth, dn, v.n) {
            return OWNER_SEES;
        }
        return select(OWNER_PAST, OWNER_HIDDEN, dn < hit.depth);
    }
    return OWNER_HIDDEN;
}

// A corner's bit of `owner_miss_bits` (x), and whether it is hidden from the owner (y).
fn owner_corner(role: u32, p: vec3<f32>, bit: u32) -> vec2<u32> {
    let seen = owner_view(role, p);
    return vec2(select(0u, bit, seen != OWNER_PAST), select(0u, 1u, seen == OWNER_HIDDEN));
}

// While a crossfade runs (our schedule), bit i (from `SPLAT_OWNER_MISSES`) set where the
// stable probe that owns a pixel cannot see corner i of a stable probe's quad (`c0`..`c3`),
// for the splat pass's kept-behind pixels. Decided here once per quad rather than in the
// splat's vertex stage (measured on walk_cells at 1280×720, faces of 128, lavapipe: the
// vertex stage's test cost about 7 of a fade frame's 19 ms of splatting).
// Also (y) how many of the corners something hides from the owner.
fn owner_miss_bits(role: u32, c0: vec3<f32>, c1: vec3<f32>, c2: vec3<f32>, c3: vec3<f32>) -> vec2<u32> {
    if view.schedule != 0u || role == ROLE_EYE || view.fade_t >= 1.0 {
        return vec2(0u);
    }
    // Unrolled, like `listed`'s dispatch: SwiftShader's compiler took gigabytes on a loop
    // around `emit` (a loop in it was not tried).
    let b = owner_corner(role, c0, 1u) + owner_corner(role, c1, 2u) + owner_corner(role, c2, 4u) + owner_corner(role, c3, 8u);
    return vec2(b.x << SPLAT_OWNER_MISSES, b.y);
}

// Every texel of the faces in `work` (the paper schedule; ours with runs off), tested and
// listed for `kept_quads` or `outlined` as `listed` does its entries (`admit`).
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.z < work.count {
        admit(work.faces[gid.z].x, work.faces[gid.z].y, gid.xy, 1u);
    }
}

// The draw lists of the listed faces (our schedule): stable faces' run heads, the eye
// texels the shade pass lit this frame. One indirect dispatch, sized by `listed_args`, has
// an invocation per entry of all the lists together (x, and z past 65535 groups); each finds
// its face among the lists' starts. No invocation loops over entries: SwiftShader's shader
// compiler took gigabytes and never finished on `emit` inside a loop.
@compute @workgroup_size(64)
fn listed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = gid.x + gid.z * groups.x * 64u;
    if i >= starts[work.listed] {
        return;
    }
    var k = 0u;
    while k + 1u < work.listed && starts[k + 1u] <= i {
        k++;
    }
    let f = work.faces[work.count + k];
    let slot = f.x;
    let face = f.y;
    let n = view.slots[slot].n;
    let packed = load_list(slot, LIST_HEADER + face * n * n + i - starts[k]);
    let t = vec2(packed & 0xffffu, packed >> 16u);
    var run = 1u;
    if view.slots[slot].role != ROLE_EYE {
        run = load_run(slot, t, face);
    }
    admit(slot, face, t, run);
}

// Where texel `t` of `face` in `slot` lies, and the run of `run` texels it heads (runs.wgsl's
// length, | RUN_COLUMN down a column): what `admit` tests and `emit` draws from.
struct Head {
    s: SlotView,
    fr: ProbeFrame,
    // The run's last texel, whether it runs down a column, its texels.
    last: vec2<u32>,
    column: bool,
    texels: u32,
    // The first texel's normal and depth (`load_geo`).
    geo: vec4<f32>,
    // The first and the last texel's centre rays.
    ray: vec3<f32>,
    ray_last: vec3<f32>,
    // The run's middle point.
    p: vec3<f32>,
}

fn head_of(slot: u32, face: u32, t: vec2<u32>, run: u32) -> Head {
    var h: Head;
    h.s = view.slots[slot];
    h.fr = slot_frame(h.s);
    h.column = (run & RUN_COLUMN) != 0u;
    h.texels = run & 0xffffu;
    h.last = select(vec2(t.x + h.texels - 1u, t.y), vec2(t.x, t.y + h.texels - 1u), h.column);
    h.geo = load_geo(slot, t, face);
    let uv = texel_center_uv(t, h.s.n);
    let uv_last = texel_center_uv(h.last, h.s.n);
    h.ray = frame_ray(h.fr, face, uv);
    h.ray_last = frame_ray(h.fr, face, uv_last);
    h.p = frame_point(h.fr, face, 0.5 * (uv + uv_last), h.geo.w);
    return h;
}

// Lists texel `t` of `face` in `slot` (heading `run`) in `kept`, for `outlined` if it is
// outlined, else for `kept_quads`, unless our schedule culls it (off the view frustum,
// facing away, a stable probe's quads not drawn this frame). That is all `main` and `listed`
// do: most entries are culled, and lavapipe's and SwiftShader's invocations pay for every
// line their shader holds whether they run it or not, so `emit`'s corners are compiled only
// into the dispatches over the entries kept.
fn admit(slot: u32, face: u32, t: vec2<u32>, run: u32) {
    let s = view.slots[slot];
    if s.role == ROLE_NONE || (s.draw_mask & (1u << face)) == 0u || t.x >= s.n || t.y >= s.n || run == 0u {
        return;
    }
    if load_id(slot, t, face) == 0u {
        return;
    }
    if view.schedule == 0u {
        if s.role != ROLE_EYE && !draws_quads(s.role) {
            return;
        }
        let h = head_of(slot, face, t, run);
        let d = h.geo.w;
        let texel_world = frame_texel_size(h.fr, d, s.n, h.ray);
        if !sphere_in_view(h.p, (2.5 + 0.5 * f32(h.texels - 1u)) * texel_world) {
            return;
        }
        // Back-facing surfaces cannot be seen (meshes are closed or one-sided). A run is
        // planar, so its middle decides for all of it. An orthographic camera looks along
        // one direction everywhere (its position says nothing about which way a surface
        // faces it: sides seen at a grazing angle were culled, and the eye filled them).
        var facing = dot(h.geo.xyz, view.camera.xyz - h.p) + 1.0e-3 * d;
        if view.ortho != 0u {
            facing = 1.0e-3 - dot(h.geo.xyz, view.forward.xyz);
        }
        if facing < 0.0 {
            return;
        }
    }
    let e = vec2(t.x | (t.y << 16u), slot | (face << 2u) | (run << 5u));
    // `emit_kept` reads it back.
    let n = arrayLength(&kept.at);
    if lit_outline(load_lit(slot, t, face).rgb) != 0u {
        let k = atomicAdd(&kept.outlined, 1u);
        if k < n {
            kept.at[n - 1u - k] = e;
        }
    } else {
        let k = atomicAdd(&kept.plain, 1u);
        if k < n {
            kept.at[k] = e;
        }
    }
}

// How many plain (`outlined` false) or outlined entries `kept` holds whole: none past where
// the other list's end reached.
fn kept_count(outlined: bool) -> u32 {
    let n = arrayLength(&kept.at);
    let plain = min(atomicLoad(&kept.plain), n);
    let other = min(atomicLoad(&kept.outlined), n);
    return select(min(plain, n - other), min(other, n - plain), outlined);
}

// The dispatch of `kept_quads`: workgroups of 64 over the plain entries `main` and `listed`
// kept.
@compute @workgroup_size(1)
fn kept_args() {
    size_dispatch(kept_count(false));
}

// The texels and runs `main` and `listed` kept that are not outlined, one quad each.
@compute @workgroup_size(64)
fn kept_quads(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = gid.x + gid.z * groups.x * 64u;
    if i < kept_count(false) {
        emit_kept(kept.at[i], false);
    }
}

// The quad of entry `e` of `kept` (as `admit` packs it); `outlines` as `emit` takes it, a
// constant at each call.
fn emit_kept(e: vec2<u32>, outlines: bool) {
    emit(e.y & 3u, (e.y >> 2u) & 7u, vec2(e.x & 0xffffu, e.x >> 16u), e.y >> 5u, outlines);
}

// The dispatch of `outlined`: workgroups of 64 over the outlined entries.
@compute @workgroup_size(1)
fn outlined_args() {
    size_dispatch(kept_count(true));
}

// The outlined texels and runs `main` and `listed` kept, drawn body and strips
// (`emit_outlined`).
@compute @workgroup_size(64)
fn outlined(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = gid.x + gid.z * groups.x * 64u;
    if i < kept_count(true) {
        emit_kept(kept.at[arrayLength(&kept.at) - 1u - i], true);
    }
}

// Where each listed face's entries start in `listed`'s index space, and its dispatch size:
// workgroups of 64 over all the entries.
@compute @workgroup_size(1)
fn listed_args() {
    var total = 0u;
    for (var k = 0u; k < work.listed; k++) {
        starts[k] = total;
        let f = work.faces[work.count + k];
        total += load_list(f.x, f.y);
    }
    starts[work.listed] = total;
    args.entries += total;
    size_dispatch(total);
}

// `dispatch`: workgroups of 64 over `total` invocations (x, and z past MAX_GROUPS).
fn size_dispatch(total: u32) {
    let groups = (total + 63u) / 64u;
    let x = clamp(groups, 1u, MAX_GROUPS);
    dispatch.x = x;
    dispatch.y = 1u;
    dispatch.z = (groups + x - 1u) / x;
}

// Emits the quad of texel `t`, or of the run of `run` texels it heads, which `admit` kept:
// an outlined one's body and strips where `outlines` (a constant at each call, so the
// compiled `kept_quads` holds no `emit_outlined`), else one quad.
fn emit(slot: u32, face: u32, t: vec2<u32>, run: u32, outlines: bool) {
    let head = head_of(slot, face, t, run);
    let s = head.s;
    let fr = head.fr;
    let last = head.last;
    let column = head.column;
    let texels = head.texels;
    let geo = head.geo;
    let d = geo.w;
    let p = head.p;
    let lit = load_lit(slot, t, face);
    let bits = u32(lit.a);
    var last_bits = bits;
    if texels > 1u {
        last_bits = u32(load_lit(slot, last, face).a);
    }
    // The more grazing end sizes the run's sides. Each side runs from where the first
    // texel's edge lies to where the last texel's does (silhouette edges: `half_size`), so a
    // straight silhouette along a run is met at both ends; a run's texels share the kinds of
    // the sides across it (runs.wgsl `joins`), and its end side is the last texel's.
    let cos_theta = min(abs(dot(geo.xyz, normalize(head.ray))), abs(dot(geo.xyz, normalize(head.ray_last))));
    // The eye probe lies at the camera: seen from its own origin its texel squares meet
    // without gaps, and its silhouettes do not roll, so its quads are exact too. Measured
    // (wall_graze, faces of 64, 320×180): coverage error 0.0238 -> 0.0228, the eye's pixels
    // over the reference's sky 5,907 -> 3,972 over the path (its pillars' curved silhouettes
    // had grown by up to a quarter texel).
    let exact = fr.half > 0.0 || s.role == ROLE_EYE;
    near_plane = !exact && ((bits | last_bits) & SIMILAR_CURVED) == 0u && on_near_face(s, p, geo.xyz, d);
    let h = 2.0 / f32(s.n);
    // Half sizes toward left, right, up and down at the first and the last texel.
    let first_halves = quad_halves(bits, cos_theta, exact || near_plane);
    let last_halves = quad_halves(last_bits, cos_theta, exact || near_plane);
    let start_half = select(first_halves.x, first_halves.z, column);
    let end_half = select(last_halves.y, last_halves.w, column);
    // The same in face coordinates.
    let f = first_halves * h;
    let l = last_halves * h;
    // Corners 0-3: top-left (the first texel's), top-right (the last's in a row run, the
    // first's in a column run), bottom-right (the last's), bottom-left (the first's in a row
    // run, the last's in a column run).
    let key = texel_key(slot, face, t, view.max_n) + 1u;
    var colour = pack4x8unorm(vec4(linear_to_srgb(hazed(lit.rgb, length(p - view.camera.xyz))), 1.0));
    // A dithered palette's rank (lib/common.wgsl `lit_dither`; a run's texels share it) in
    // the alpha byte, which the splat pass writes to the frame for present.wgsl `fs_map`.
    let rank = lit_dither(lit.rgb);
    if rank != NO_DITHER {
        colour = (colour & 0xffffffu) | (dither_alpha(rank) << 24u);
    }
    var reach = pack2x16unorm(0.5 * vec2(start_half, end_half));
    // A one-texel quad of a terrain: the splat pass colours its pixels from the terrain
    // (terrain_splat.wgsl); a run keeps its texels' colour.
    let terrain = lit_terrain(lit.rgb);
    if terrain != NO_TERRAIN && texels == 1u {
        let object = load_id(slot, t, face) - 1u;
        if object < SPLAT_TERRAIN_OBJECTS {
            colour = (colour & 0xffffffu) | (SPLAT_TERRAIN_ALPHA << 24u);
            reach = terrain | (object << SPLAT_TERRAIN_OBJECT_AT);
        }
    }
    if outlines {
        emit_outlined(slot, face, fr, t, last, column, bits, last_bits, f, l, lit_outline(lit.rgb), p, geo.xyz, d, key, texels, lit.rgb, colour, reach);
        return;
    }
    let a_t = select(last, t, column);
    let b_t = select(t, last, column);
    let a_bits = select(last_bits, bits, column);
    let b_bits = select(bits, last_bits, column);
    let c0 = quad_corner(slot, face, fr, t, bits, f, 0u, 2u, p, geo.xyz, d);
    let c1 = quad_corner(slot, face, fr, a_t, a_bits, select(l, f, column), 1u, 2u, p, geo.xyz, d);
    let c2 = quad_corner(slot, face, fr, last, last_bits, l, 1u, 3u, p, geo.xyz, d);
    let c3 = quad_corner(slot, face, fr, b_t, b_bits, select(f, l, column), 0u, 3u, p, geo.xyz, d);
    push_splat(s.role | (texels << 8u) | select(0u, SPLAT_COLUMN, column), key, colour, reach, c0, c1, c2, c3);
}

// Appends a splat of shape `shape` (role | texels << 8 | SPLAT_COLUMN | part; the owner-miss
// bits are added here) with corners c0-c3 to the list.
fn push_splat(shape: u32, key: u32, colour: u32, reach: u32, c0: vec3<f32>, c1: vec3<f32>, c2: vec3<f32>, c3: vec3<f32>) {
    let role = shape & 0xffu;
    let owner = owner_miss_bits(role, c0, c1, c2, c3);
    // A stable quad that wins no pixel this frame (the grid probe's at fade 0: a crossing's
    // first frame, or the next cell's probe filling behind the grid probe before it) is
    // drawn only to fill where the owner cannot see: not listed unless something hides one
    // of its corners from the owner. (Kept, its pixels would also fill the owner's gaps
    // between quads seen at a grazing angle, which the eye fills as on a quiet frame.)
    if view.schedule == 0u && role != ROLE_EYE && !draws_pixels(role) && owner.y == 0u {
        return;
    }
    var out: Splat;
    out.c0 = vec4(c0, bitcast<f32>(key));
    out.c1 = vec4(c1, bitcast<f32>(colour));
    out.c2 = vec4(c2, bitcast<f32>(shape | owner.x));
    out.c3 = vec4(c3, bitcast<f32>(reach));
    let index = atomicAdd(&args.instance_count, 1u);
    if index < arrayLength(&splats) {
        splats[index] = out;
    }
}

// The quad of an outlined texel or run (`lit_outline`'s `sides`) as a body in its unshifted
// colour and a strip of OUTLINE_STRIP texels along each outlined side, in the colour a band
// darker or lighter (a terrain quad: its pixels' shift, terrain_splat.wgsl). A silhouette
// side's strip runs inward from the edge the shade pass found (the quad's side there), a
// crease side's from where the texel's plane meets its neighbour's (`crease_at`): both fixed
// to the world, so the strip lies on the same stretch of surface from every nearby probe,
// where a whole texel's shift ran to the inner side on each probe's texel grid (1/2 to 3/2
// texels wide). The body's outlined sides move in to the strips' inner sides; a body
// narrower than half a strip across the quad is left out, the strips of that axis meeting
// across it (a sliver a fraction of a pixel wide came and went as the view turned: stone
// circle `yaw`, faces of 128, 320×180, mean shimmer 0.00039 -> 0.00021 on lavapipe,
// 0.00050 -> 0.00033 on SwiftShader; coverage error down on every path measured). Strips
// come a little nearer the probe (`nudge`) so they win where they meet the body. A run's outlined sides are those across it (runs.wgsl
// joins texels of one lit colour, sides and all). Measured against a width on the surface
// (OUTLINE_STRIP texels at the edge's distance, not in face coordinates; 2026-12-02,
// `texel-eval compare --methods splat --face-res 128`): terrain_walk 0.0080 against 0.0075,
// jog_cells 0.0043 against 0.0038, as strips seen at a grazing angle thinned below a pixel.
fn emit_outlined(slot: u32, face: u32, fr: ProbeFrame, t: vec2<u32>, last: vec2<u32>, column: bool, bits: u32, last_bits: u32, f0: vec4<f32>, l0: vec4<f32>, sides: u32, p: vec3<f32>, nrm: vec3<f32>, d: f32, key: u32, texels: u32, lit: vec3<f32>, colour: u32, reach: u32) {
    let role = view.slots[slot].role;
    let strip = OUTLINE_STRIP * 2.0 / f32(view.slots[slot].n);
    let creases = (sides >> OUTLINE_CREASE_AT) & 15u;
    let lit_sides = (sides >> OUTLINE_LIT_AT) & 15u;
    let outlined = ((sides >> OUTLINE_SILHOUETTE_AT) & 15u) | creases;
    // A crease side ends where the texel's plane meets its neighbour's.
    var f = f0;
    var l = l0;
    for (var k = 0u; k < 4u; k++) {
        if (creases & (1u << k)) != 0u {
            f[k] = crease_at(slot, face, fr, t, k, p, nrm);
            l[k] = crease_at(slot, face, fr, last, k, p, nrm);
        }
    }
    // Corner i (top-left, top-right, bottom-right, bottom-left): its texel, bits and halves.
    var tt = array<vec2<u32>, 4>(t, last, last, t);
    var bb = array<u32, 4>(bits, last_bits, last_bits, bits);
    var hv = array<vec4<f32>, 4>(f, l, l, f);
    if column {
        tt = array<vec2<u32>, 4>(t, t, last, last);
        bb = array<u32, 4>(bits, bits, last_bits, last_bits);
        hv = array<vec4<f32>, 4>(f, f, l, l);
    }
    let kxs = array<u32, 4>(0u, 1u, 1u, 0u);
    let kys = array<u32, 4>(2u, 2u, 3u, 3u);
    // Each corner as the quad has it, moved in off its left/right side (`in_x`), off its
    // up/down side (`in_y`), and off both where they are outlined (the body's).
    var outer: array<vec3<f32>, 4>;
    var in_x: array<vec3<f32>, 4>;
    var in_y: array<vec3<f32>, 4>;
    var body: array<vec3<f32>, 4>;
    var has_body = true;
    for (var i = 0u; i < 4u; i++) {
        let kx = kxs[i];
        let ky = kys[i];
        let h = hv[i];
        let sx = f32(NEIGHBOURS[kx].x);
        let sy = f32(NEIGHBOURS[ky].y);
        let mx = (outlined & (1u << kx)) != 0u;
        let my = (outlined & (1u << ky)) != 0u;
        let ox = (outlined & (1u << (1u - kx))) != 0u;
        let oy = (outlined & (1u << (5u - ky))) != 0u;
        // The body's width across each axis at this corner's texel. A body narrower than half
        // a strip (or none: the strips overlap) is left out, and the strips of that axis reach
        // across it, meeting halfway where both sides are outlined. (A run's sides along it
        // are never outlined: its texels share their outlined sides and lie in one plane, so
        // none has an outline toward the next.)
        let wx = h[kx] + h[1u - kx] - select(0.0, strip, mx) - select(0.0, strip, ox);
        let wy = h[ky] + h[5u - ky] - select(0.0, strip, my) - select(0.0, strip, oy);
        let narrow_x = (mx || ox) && wx < 0.5 * strip;
        let narrow_y = (my || oy) && wy < 0.5 * strip;
        if narrow_x || narrow_y {
            has_body = false;
        }
        let grow_x = select(0.0, wx / select(1.0, 2.0, mx && ox), narrow_x);
        let grow_y = select(0.0, wy / select(1.0, 2.0, my && oy), narrow_y);
        let x = sx * h[kx];
        let y = sy * h[ky];
        let xi = sx * (h[kx] - strip - grow_x);
        let yi = sy * (h[ky] - strip - grow_y);
        outer[i] = split_corner(slot, face, fr, tt[i], bb[i], x, y, kx, ky, true, true, p, nrm, d, creases);
        in_x[i] = split_corner(slot, face, fr, tt[i], bb[i], xi, y, kx, ky, false, true, p, nrm, d, creases);
        in_y[i] = split_corner(slot, face, fr, tt[i], bb[i], x, yi, kx, ky, true, false, p, nrm, d, creases);
        body[i] = split_corner(slot, face, fr, tt[i], bb[i], select(x, xi, mx), select(y, yi, my), kx, ky, !mx, !my, p, nrm, d, creases);
    }
    let shape = role | (texels << 8u) | select(0u, SPLAT_COLUMN, column);
    if has_body {
        push_splat(shape, key, colour, reach, body[0], body[1], body[2], body[3]);
    }
    // The strips' colours: a terrain quad's pixels take the shift from `reach`.
    var dark = colour;
    var light = colour;
    var dark_reach = reach;
    var light_reach = reach;
    if (colour >> 24u) == SPLAT_TERRAIN_ALPHA {
        dark_reach = terrain_with_shift(reach, -1.0);
        light_reach = terrain_with_shift(reach, 1.0);
    } else {
        let dist = length(p - view.camera.xyz);
        let alpha = colour & 0xff000000u;
        dark = (pack4x8unorm(vec4(linear_to_srgb(hazed(posterize(lit, view.bands, -1.0), dist)), 1.0)) & 0xffffffu) | alpha;
        light = (pack4x8unorm(vec4(linear_to_srgb(hazed(posterize(lit, view.bands, 1.0), dist)), 1.0)) & 0xffffffu) | alpha;
    }
    // Strip k's corners: two of the quad's and the two moved in from them.
    for (var k = 0u; k < 4u; k++) {
        if (outlined & (1u << k)) == 0u {
            continue;
        }
        var q = array<vec3<f32>, 4>(outer[0], in_x[0], in_x[3], outer[3]);
        if k == 1u {
            q = array<vec3<f32>, 4>(in_x[1], outer[1], outer[2], in_x[2]);
        } else if k == 2u {
            q = array<vec3<f32>, 4>(outer[0], outer[1], in_y[1], in_y[0]);
        } else if k == 3u {
            q = array<vec3<f32>, 4>(in_y[3], in_y[2], outer[2], outer[3]);
        }
        let is_lit = (lit_sides & (1u << k)) != 0u;
        push_splat(shape | ((k + 1u) << SPLAT_PART_AT), key, select(dark, light, is_lit), select(dark_reach, light_reach, is_lit), nudge(fr, q[0]), nudge(fr, q[1]), nudge(fr, q[2]), nudge(fr, q[3]));
    }
}

// Corner (x, y) (face coordinates from texel t's centre, toward sides kx and ky) of a piece
// of t's quad. Where it lies on the quad's own side along x (ox) or y (oy) it ends as
// `quad_corner`'s do, except that a crease side's corner lies on the texel's plane.
fn split_corner(slot: u32, face: u32, fr: ProbeFrame, t: vec2<u32>, bits: u32, x: f32, y: f32, kx: u32, ky: u32, ox: bool, oy: bool, p: vec3<f32>, nrm: vec3<f32>, d: f32, creases: u32) -> vec3<f32> {
    let centre = texel_center_uv(t, view.slots[slot].n);
    if (ox && (creases & (1u << kx)) != 0u) || (oy && (creases & (1u << ky)) != 0u) {
        return corner_at(fr, face, centre + vec2(x, y), p, nrm, d, true);
    }
    var scale = 1.0;
    if ox && oy {
        scale = cut_scale(bits, kx, ky);
    }
    let ends = ends_at_edge(bits);
    let ex = ox && ends[kx];
    let ey = oy && ends[ky];
    var c = corner_at(fr, face, centre + vec2(x, y) * scale, p, nrm, d, ex || ey || near_plane);
    if ex {
        c = clip_behind(slot, face, fr, t, kx, p, c);
    }
    if ey {
        c = clip_behind(slot, face, fr, t, ky, p, c);
    }
    return c;
}

// Corner `c` of a strip, a little nearer its probe along the probe's ray (an orthographic
// probe's rays are parallel: toward its plane, not its origin, which would move it sideways).
fn nudge(fr: ProbeFrame, c: vec3<f32>) -> vec3<f32> {
    if fr.half > 0.0 {
        return c - fr.forward * (2.0e-4 * dot(c - fr.origin, fr.forward));
    }
    return mix(c, fr.origin, 2.0e-4);
}

// How far (in face coordinates) from texel t's centre toward side k its plane (p, nrm) meets
// its neighbour's there: where the gap between the two planes along the rays changes sign
// between the two texels' centres (half a texel where it does not).
fn crease_at(slot: u32, face: u32, fr: ProbeFrame, t: vec2<u32>, k: u32, p: vec3<f32>, nrm: vec3<f32>) -> f32 {
    let n = view.slots[slot].n;
    let h = 2.0 / f32(n);
    let q = vec2<i32>(t) + NEIGHBOURS[k];
    if any(q < vec2(0)) || any(q >= vec2(i32(n))) {
        return 0.5 * h;
    }
    let nt = vec2<u32>(q);
    let g = load_geo(slot, nt, face);
    let uv1 = texel_center_uv(nt, n);
    let pb = frame_point(fr, face, uv1, g.w);
    let f0 = plane_gap(fr, face, texel_center_uv(t, n), p, nrm, pb, g.xyz);
    let f1 = plane_gap(fr, face, uv1, p, nrm, pb, g.xyz);
    var s = 0.5;
    if f0 * f1 < 0.0 {
        s = clamp(f0 / (f0 - f1), 0.05, 1.0);
    }
    return s * h;
}
