// Shade: lights one captured cube face, once per texel. Camera-independent, so the result is
// cached until the probe's origin or the scene changes. Per texel: sun and point lights with
// ray-traced shadows, ambient, emissive; OKLab posterization; silhouette (id) and crease
// (normal) outlines as one-band lightness shifts, found across cube-face seams too; and four
// "similar neighbour" bits the splat pass uses to size quads. crates/render/src/passes/shade.rs.

#include "lib/common.wgsl"
#include "lib/bvh.wgsl"
#include "lib/lighting.wgsl"
#include "lib/lists.wgsl"
#include "lib/view.wgsl"
#include "lib/shade_globals.wgsl"
#include "lib/light_words.wgsl"
#include "lib/edit_filter.wgsl"
#include "lib/edge_rays.wgsl"

struct ShadeFace {
    origin: vec3<f32>,
    face: u32,
    n: u32,
    // 1 for the eye probe: only texels whose direction lies in the view are lit.
    view_cull: u32,
    // Bit f: face f of this probe holds data for this origin (neighbours are read there only).
    valid_mask: u32,
    // This job's index (its record in `all_faces`).
    job: u32,
    slot: u32,
    _pad0: u32,
    // First texel of the dispatch (the eye's faces: only the part the view can see).
    rect_min: vec2<u32>,
    // After an edit (`edit_wants`): the texels always lit again (where the edit's geometry
    // may show), from `keep_min` to before `keep_max`.
    keep_min: vec2<u32>,
    keep_max: vec2<u32>,
    // 0: every texel of the dispatch is lit; else 1 + the edit's boxes, box i from
    // `box_corners[2i]` to `box_corners[2i + 1]`: a texel outside `keep` is lit again only
    // when a ray from it toward a light that reaches it meets a box (the edited objects'
    // bounds: a shadow came or went), or when it lies in a box of `lit_mask` (a changed
    // light's reach).
    boxes: u32,
    lit_mask: u32,
    _pad1: vec2<u32>,
    box_corners: array<vec4<f32>, 8>,
}

// A job's record at its 256-byte uniform stride.
struct JobRecord {
    f: ShadeFace,
    _pad: array<vec4<u32>, 3>,
}

// The job of this dispatch (dynamic offset); for `light`, any job of the slot it lights.
@group(0) @binding(0) var<uniform> job_face: ShadeFace;
// Every job of the frame, for `light`, which runs texels of several jobs of one slot.
@group(0) @binding(10) var<uniform> all_faces: array<JobRecord, 54>;
// The job whose texel this invocation shades (set first by every entry point).
var<private> sf: ShadeFace;
@group(0) @binding(1) var<uniform> globals: ShadeGlobals;
@group(0) @binding(2) var geo_tex: texture_2d_array<f32>;
@group(0) @binding(3) var id_tex: texture_2d_array<u32>;
@group(0) @binding(4) var albedo_tex: texture_2d_array<f32>;
// Normal-mapped normals (pack4x8snorm, w = 1), 0 where the geometric normal lights the texel.
@group(0) @binding(11) var shading_tex: texture_2d_array<u32>;
@group(0) @binding(5) var lit_out: texture_storage_2d_array<rgba32float, write>;
@group(0) @binding(6) var<storage, read> objects: array<Object>;
// The point lights' records (8 words each), then the grid of which reach where
// (`gpu_scene::light_grid`): a header, a (first, count) pair per cell, the cells' lists.
@group(0) @binding(7) var<storage, read> light_words: array<u32>;
// Work of this frame's jobs: the texels lit (WORK_SHADED), each slot's queue length (from
// WORK_COUNTS, per slot), and the queue of texels that need lighting (from WORK_QUEUE, each
// slot's part at `globals.queue_base`; job | x << 6 | y << 19), gathered by `main` so that
// `light` runs them densely, one dispatch per slot rather than per job: lighting
// (shadow rays) is the expensive part, and lanes of a group that skip it would otherwise
// wait for the ones that do.
@group(0) @binding(8) var<storage, read_write> work: array<atomic<u32>>;
const WORK_SHADED: u32 = 0u;
const WORK_COUNTS: u32 = 1u;
const WORK_QUEUE: u32 = 64u;
// The slot's draw list: view-culled (eye) jobs list the texels they light for the cull pass.
@group(0) @binding(9) var<storage, read_write> list: array<atomic<u32>>;
// Per slot: `light`'s indirect dispatch arguments (x, y, z, padding); bound for `main` only.
@group(3) @binding(0) var<storage, read_write> job_args: array<atomic<u32>>;
// The two stable slots (grid and previous, in whichever order the slots hold them) and the
// frame's view: an eye texel whose surface every drawing stable probe already shows is not
// splatted, and is read only by the hole fill, so it copies the stable probe's colour
// instead of being lit again. (For stable jobs these bind the eye slot's textures, unused.)
@group(2) @binding(0) var geo_a: texture_2d_array<f32>;
@group(2) @binding(1) var ids_a: texture_2d_array<u32>;
@group(2) @binding(2) var lit_a: texture_2d_array<f32>;
@group(2) @binding(3) var geo_b: texture_2d_array<f32>;
@group(2) @binding(4) var ids_b: texture_2d_array<u32>;
@group(2) @binding(5) var lit_b: texture_2d_array<f32>;
@group(2) @binding(6) var<uniform> view: ViewGlobals;
@group(1) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(1) @binding(1) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(1) @binding(2) var<storage, read> bvh_instances: array<BvhInstance>;
@group(1) @binding(3) var<uniform> bvh_fields: BvhFields;
@group(1) @binding(4) var bvh_field_data: texture_2d_array<f32>;

// The texel frame of the face being lit: its own origin, the slot's orthographic frame (a
// cube when the slot's view says none).
fn face_frame() -> ProbeFrame {
    var f = slot_frame(view.slots[sf.slot]);
    f.origin = sf.origin;
    return f;
}


struct Sample {
    geo: vec4<f32>,
    id: u32,
}

fn load(face: u32, t: vec2<u32>) -> Sample {
    return Sample(textureLoad(geo_tex, t, face, 0), textureLoad(id_tex, t, face, 0).r);
}

// The neighbour of texel `t` one step along `o`, on the neighbouring face past a seam.
fn neighbour(t: vec2<u32>, o: vec2<i32>) -> Sample {
    let n = sf.n;
    let q = vec2<i32>(t) + o;
    if all(q >= vec2(0)) && all(q < vec2(i32(n))) {
        return load(sf.face, vec2<u32>(q));
    }
    if face_frame().half > 0.0 {
        // An orthographic face has no neighbour past its edge.
        return load(sf.face, t);
    }
    // Past the edge: continue the face plane and re-project onto the cube.
    let uv = (vec2<f32>(q) + 0.5) * (2.0 / f32(n)) - 1.0;
    let f = cube_face_uv(cube_dir(sf.face, uv.x, uv.y));
    if (sf.valid_mask & (1u << f.face)) == 0u {
        // Not captured for this origin (yet): no outline and no expansion across the seam;
        // the border is shaded again when that face arrives.
        return load(sf.face, t);
    }
    return load(f.face, texel_of_uv(f.uv, n));
}

var<workgroup> group_count: atomic<u32>;

// Sorts the texels of a face: sky, off-view and covered texels are settled here, the rest
// queued for `light`.
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    sf = job_face;
    let t = gid.xy + sf.rect_min;
    if t.x < sf.n && t.y < sf.n && edit_wants(t) && needs_light(t) {
        queue_texel(t);
    }
}


// Appends texel `t` of the job's face to its slot's light queue, growing the indirect
// dispatch by a workgroup every 64 texels.
fn queue_texel(t: vec2<u32>) {
    let index = atomicAdd(&work[WORK_COUNTS + sf.slot], 1u);
    if index % 64u == 0u {
        atomicAdd(&job_args[sf.slot * 4u], 1u);
    }
    let at = WORK_QUEUE + globals.queue_base[sf.slot] + index;
    atomicStore(&work[at], sf.job | (t.x << 6u) | (t.y << 19u));
}

// Lights the texels `main` queued for the slot of `job_face`.
@compute @workgroup_size(64)
fn light(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let slot = job_face.slot;
    if gid.x < atomicLoad(&work[WORK_COUNTS + slot]) {
        let packed = atomicLoad(&work[WORK_QUEUE + globals.queue_base[slot] + gid.x]);
        sf = all_faces[packed & 63u].f;
        light_texel(vec2((packed >> 6u) & 0x1fffu, packed >> 19u));
        atomicAdd(&group_count, 1u);
    }
    workgroupBarrier();
    if li == 0u {
        atomicAdd(&work[WORK_SHADED], atomicLoad(&group_count));
    }
}

// Queues only the four edges of a face for `light`, after a neighbouring face was captured:
// the texels whose outlines and neighbour bits look across that seam. (Queued rather than
// lit here, so the one big lighting pipeline is the only one that compiles `light_texel`.)
@compute @workgroup_size(64)
fn border(@builtin(global_invocation_id) gid: vec3<u32>) {
    sf = job_face;
    let n = sf.n;
    let i = gid.x;
    if i < 4u * n {
        let side = i / n;
        let k = i % n;
        var t: vec2<u32>;
        switch side {
            case 0u: { t = vec2(k, 0u); }
            case 1u: { t = vec2(k, n - 1u); }
            case 2u: { t = vec2(0u, k); }
            default: { t = vec2(n - 1u, k); }
        }
        if needs_light(t) {
            queue_texel(t);
        }
    }
}

// The lit colour of stable slot `s` (1 or 2) where it shows `p` on object `id`, or a
// negative alpha when it does not.
fn stable_colour(s: u32, p: vec3<f32>, id: u32) -> vec4<f32> {
    let sv = view.slots[s];
    let fu = frame_locate(slot_frame(sv), p);
    if (sv.draw_mask & (1u << fu.face)) == 0u || any(abs(fu.uv) > vec2(1.0)) {
        return vec4(-1.0);
    }
    let t = texel_of_uv(fu.uv, sv.n);
    var nid: u32;
    var dn: f32;
    var lit: vec4<f32>;
    if s == 1u {
        nid = textureLoad(ids_a, t, fu.face, 0).r;
        dn = textureLoad(geo_a, t, fu.face, 0).w;
        lit = textureLoad(lit_a, t, fu.face, 0);
    } else {
        nid = textureLoad(ids_b, t, fu.face, 0).r;
        dn = textureLoad(geo_b, t, fu.face, 0).w;
        lit = textureLoad(lit_b, t, fu.face, 0);
    }
    if nid != id || !frame_same_surface(slot_frame(sv), fu.depth, dn, sv.n) {
        return vec4(-1.0);
    }
    return vec4(lit.rgb, 0.0);
}

// The colour the drawing stable probes show for the eye texel at `p`, if they all show it
// (the grid's when it draws); a negative alpha otherwise.
fn covered_colour(p: vec3<f32>, id: u32) -> vec4<f32> {
    var found = vec4(-1.0);
    for (var s = 1u; s < 3u; s++) {
        if draws_pixels(view.slots[s].role) {
            let c = stable_colour(s, p, id);
            if c.a < 0.0 {
                return vec4(-1.0);
            }
            if found.a < 0.0 || view.slots[s].role == ROLE_GRID {
                found = c;
            }
        }
    }
    return found;
}

// Settles a texel that needs no lighting and returns false: a sky texel; an eye texel whose
// quad cannot reach the view (cleared: never drawn nor seen); one inside its surface that a
// stable probe shows (its colour copied). Returns true for the rest.
fn needs_light(t: vec2<u32>) -> bool {
    let n = sf.n;
    let me = load(sf.face, t);
    if me.id == 0u {
        textureStore(lit_out, t, sf.face, vec4(sky_texel(globals.sky.rgb, globals.bands), 0.0));
        return false;
    }
    if sf.view_cull != 0u {
        let uv = texel_center_uv(t, n);
        let fr = face_frame();
        let ray = frame_ray(fr, sf.face, uv);
        let p = frame_point(fr, sf.face, uv, me.geo.w);
        if !quad_in_view(p, frame_texel_size(fr, me.geo.w, n, ray)) {
            textureStore(lit_out, t, sf.face, vec4(0.0));
            return false;
        }
        // A texel on a silhouette is lit anyway: its edges are searched, where the
        // background pass ends its pixels.
        let copied = covered_colour(p, me.id);
        if copied.a >= 0.0 && !on_silhouette(t, me.id) {
            // Without the stable texel's outline sides: they are not this texel's
            // (background.wgsl draws an eye texel's strips from its own edges).
            textureStore(lit_out, t, sf.face, vec4(without_outline(copied.rgb), copied.a));
            return false;
        }
    }
    return true;
}

// Whether texel `t` of object `id` has a neighbour in its face of another object or the sky
// (past the face's edge, not looked at: the border is rare, and such a texel is only
// copied rather than searched).
fn on_silhouette(t: vec2<u32>, id: u32) -> bool {
    for (var k = 0u; k < 4u; k++) {
        let q = vec2<i32>(t) + NEIGHBOURS[k];
        if all(q >= vec2(0)) && all(q < vec2(i32(sf.n))) && textureLoad(id_tex, vec2<u32>(q), sf.face, 0).r != id {
            return true;
        }
    }
    return false;
}

// Where each silhouette side's edge lies (`SIMILAR_EDGE_AT`): a texel belongs to its surface
// when its centre ray meets it, so a side whose neighbour sees the sky or a farther surface
// has its edge somewhere between the two centres, and a quad that ends half a texel out
// rounds every straight silhouette (a stone's top, the horizon) the same way for as long as
// the probe stays. Rays between the centres, cast against the BVH, find it by bisection: a
// ray that meets something before the far side's depth (halfway to farther geometry; for
// the sky, four times this texel's depth) is still on this side. Only for surfaces in the
// BVH (`FLAG_IN_BVH`: they cast shadows and do not move); elsewhere half a texel. An
// orthographic probe's rays are parallel: its edge rays start between the two texels'
// starts (`toward_ray`). `trace_rays` casts these rays in its shadow rays' loop, over the
// searched sides only.
//
// A farther neighbour that lies in front of this texel's plane (`hides_plane`: a wall
// standing on a floor, a stone on a terrain) does not end the surface: it hides it. There
// the depth halfway between the two says nothing (the two meet at one depth), so the edge is
// where the plane stops being the first thing a ray meets: a ray is on this side when
// nothing in the BVH lies before the plane along it. That asks the BVH for the neighbour,
// not for this surface, so a floor that casts no shadow finds its junction with a wall that
// does. Measured on occluder_pass (faces of 128, 320×180): the floor's junction with the
// long wall had been a whole row off over the frame's width.
//
// Bisection steps of the silhouette edges' search: the edge to a sixteenth of a texel.
const EDGE_STEPS: u32 = 4u;
// Every side's edge half a texel out (`SIMILAR_EDGE_AT`: c = 4).
const EDGES_UNKNOWN: u32 = 0x6dbu << SIMILAR_EDGE_AT;

// A probe ray: from `start` along `dir` (`frame_ray`: a point at depth t is start + dir·t).
struct ProbeRay {
    start: vec3<f32>,
    dir: vec3<f32>,
}

// The ray through face coordinates `uv` of the face being lit (past the face's edge a cube
// face's plane goes on).
fn probe_ray(fr: ProbeFrame, uv: vec2<f32>) -> ProbeRay {
    return ProbeRay(frame_ray_start(fr, uv), frame_ray(fr, sf.face, uv));
}

// The ray through the point `s` of the way from the texel at `uv` to its neighbour on side
// `k` (s = 1: the neighbour's centre).
fn toward_ray(fr: ProbeFrame, uv: vec2<f32>, k: u32, s: f32) -> ProbeRay {
    return probe_ray(fr, uv + vec2<f32>(NEIGHBOURS[k]) * (2.0 * s / f32(sf.n)));
}

// The depth at which ray `r` meets the plane through `p` with normal `n`; only where
// `dot(n, r.dir) < 0`.
fn plane_depth(n: vec3<f32>, p: vec3<f32>, r: ProbeRay) -> f32 {
    return dot(n, p - r.start) / dot(n, r.dir);
}

// Whether neighbour `nb`, seen along `nr`, lies on the plane of `me` (whose point is `p`):
// the same object, at the depth where that plane meets its ray (within 1%). A surface seen
// at a grazing angle has its next texel far behind, yet no silhouette between them: the
// edge search would find its edge where the depth passes the halfway mark, about half a
// texel out, as without a search.
fn on_plane(me: Sample, p: vec3<f32>, nb: Sample, nr: ProbeRay) -> bool {
    if nb.id != me.id || dot(me.geo.xyz, nr.dir) >= 0.0 {
        return false;
    }
    return abs(plane_depth(me.geo.xyz, p, nr) - nb.geo.w) <= 0.01 * nb.geo.w;
}

// Whether neighbour `nb`, seen along `nr`, lies in front of the plane of `me` (by more than
// 0.1%, far above the depths' rounding): it hides the plane there rather than showing what
// lies past the surface's end. (1%, `on_plane`'s margin, missed a junction whose
// neighbour's centre lay within 1% of the plane: a floor meeting a wall within a sixth of
// the texel from the wall's first texel's centre.)
fn hides_plane(me: Sample, p: vec3<f32>, nb: Sample, nr: ProbeRay) -> bool {
    return dot(me.geo.xyz, nr.dir) < 0.0 && nb.geo.w < 0.999 * plane_depth(me.geo.xyz, p, nr);
}

// Whether the farther neighbour on side `k` (at depth `nd`) of a texel of the terrain that
// field `field` walks (the texel's point `p`) shows that surface going on, nothing of it
// hidden between them: the terrain under the straight way from `p` to the neighbour's
// point, sampled at its quarters, lies in order across the side, each sample's place along
// it past the one before (a slope seen at a grazing angle, or a fold between two
// triangles); behind a crest the samples fall back behind `p`. There a search would only
// move the seam between two quads of one surface to where the depth passes halfway; it is
// left halfway. On a hilly terrain seen from eye height most farther neighbours are such:
// on terrain_walk (1280×720, faces of 128) the search's rays over the field were about 20
// of the pass's 50 ms, and this test takes about half of them away, coverage and shimmer
// as before.
fn terrain_goes_on(fr: ProbeFrame, uv: vec2<f32>, k: u32, p: vec3<f32>, nd: f32, field: u32) -> bool {
    if field >= BVH_MAX_FIELDS {
        return false;
    }
    let f = bvh_fields.fields[field];
    let step = vec2<f32>(NEIGHBOURS[k]) * (2.0 / f32(sf.n));
    let q = frame_point(fr, sf.face, uv + step, nd);
    var at = 0.0;
    for (var i = 1u; i < 4u; i++) {
        let xz = mix(p.xz, q.xz, 0.25 * f32(i));
        let m = vec3(xz.x, field_surface_y(f, xz), xz.y);
        let place = dot(frame_uv_on(fr, sf.face, m) - uv, step) / dot(step, step);
        if !(place > at) {
            return false;
        }
        at = place;
    }
    return at < 1.0;
}

// Whether object `id` (1-based) has its triangles in the BVH.
fn in_bvh(id: u32) -> bool {
    return id != 0u && id <= arrayLength(&objects) && (objects[id - 1u].flags & FLAG_IN_BVH) != 0u;
}

// The far limit of side `k`'s edge search.
fn edge_reach(t: vec2<u32>, d: f32, bits: u32, k: u32) -> f32 {
    if ((bits >> k) & 1u) == 0u {
        return 0.5 * (d + neighbour(t, NEIGHBOURS[k]).geo.w);
    }
    return 4.0 * d;
}

// Similar neighbours' normals at least this close are one flat surface (`SIMILAR_CURVED`).
const FLAT_DOT: f32 = 0.99995;

// The texel being lit, as `light_texel`'s steps read it: its texel, sample, face coordinates,
// the face's frame, its ray (`frame_ray`), depth, point and albedo flags.
struct Texel {
    t: vec2<u32>,
    me: Sample,
    uv: vec2<f32>,
    fr: ProbeFrame,
    ray: vec3<f32>,
    d: f32,
    p: vec3<f32>,
    flags: u32,
}

// What a texel's four neighbours say (`texel_sides`).
struct Sides {
    // The whole texel's outline shift: darkened, lightened.
    darken: bool,
    lighten: bool,
    // Bit k: side k is outlined as a silhouette, a crease, a lit crease.
    silhouettes: u32,
    creases: u32,
    lit_creases: u32,
    // The similar-neighbour bits (`SIMILAR_CURVED`, `SIMILAR_APART` included).
    similar: u32,
    // Bit k: side k's edge is searched (a silhouette, or where a neighbour hides the plane).
    seek: u32,
    // Bit k: side k's neighbour hides this texel's plane (`hides_plane`).
    hidden: u32,
}

// Outlines, similar-neighbour bits and the sides to search, from the four neighbours of `x`
// (`object_flags`: its object's).
fn texel_sides(x: Texel, object_flags: u32) -> Sides {
    let normal = x.me.geo.xyz;
    let facing = dot(normal, -normalize(x.ray));
    var s = Sides(false, false, 0u, 0u, 0u, 0u, 0u, 0u);
    // Whether a similar neighbour shows this surface flat here, or turning (short of a
    // crease); a texel with neither counts as curved.
    var flat = false;
    var curved = false;
    // A farther neighbour is not this surface turning a convex crease (`SIMILAR_APART`).
    var apart = false;
    let me_in_bvh = (x.flags & FLAG_IN_BVH) != 0u;
    // The field that walks this texel's terrain, if it is one (`terrain_goes_on`).
    var field = BVH_MAX_FIELDS;
    if me_in_bvh && (object_flags & FLAG_TERRAIN) != 0u {
        field = field_of_terrain(object_flags >> 8u);
    }
    // Depth step between neighbours on a surface tilted ~37° from the face plane.
    let tolerance = frame_texel_size(x.fr, x.d, sf.n, x.ray) / length(x.ray) * 0.75;
    for (var k = 0u; k < 4u; k++) {
        let nb = neighbour(x.t, NEIGHBOURS[k]);
        // Two bits per side (k and 4 + k), read by cull.wgsl `half_size`: 01 a similar
        // neighbour; 10 a silhouette against farther geometry (this texel occludes it, so
        // its quad ends at the edge and the farther quad reaches under it); 11 a silhouette
        // against the sky; 00 a nearer surface, which this texel's quad reaches under.
        if nb.id == x.me.id && abs(nb.geo.w - x.d) <= tolerance {
            s.similar |= 1u << k;
            let turn = dot(normal, nb.geo.xyz);
            if turn >= FLAT_DOT {
                flat = true;
            } else if turn >= 0.7 {
                curved = true;
            }
        } else if nb.id == 0u {
            s.similar |= 17u << k;
            s.seek |= select(0u, 1u << k, me_in_bvh);
        } else if nb.geo.w > x.d {
            s.similar |= 16u << k;
            // Searched for its edge, unless the surface goes on there: against the neighbour
            // where it hides the plane, else against this surface.
            let nr = toward_ray(x.fr, x.uv, k, 1.0);
            if nb.id == x.me.id && terrain_goes_on(x.fr, x.uv, k, x.p, nb.geo.w, field) {
                // Nothing to search: the edge lies halfway.
            } else if hides_plane(x.me, x.p, nb, nr) {
                if in_bvh(nb.id) {
                    s.seek |= 1u << k;
                    s.hidden |= 1u << k;
                }
            } else if me_in_bvh && !on_plane(x.me, x.p, nb, nr) {
                s.seek |= 1u << k;
            }
            // Another object, or this one hiding itself: the edge lies on this plane.
            if nb.id != x.me.id || (s.hidden & (1u << k)) != 0u {
                apart = true;
            }
        }
        if (x.flags & FLAG_OUTLINED) == 0u {
            continue;
        }
        if nb.id != x.me.id {
            // Silhouette: the nearer side (the occluder) is outlined.
            if nb.id == 0u || x.d <= nb.geo.w {
                s.darken = true;
                s.silhouettes |= 1u << k;
            }
        } else if dot(normal, nb.geo.xyz) < 0.7 {
            // Crease: the side that faces the probe more is lit, the other darkened.
            let nb_facing = dot(nb.geo.xyz, -normalize(x.ray));
            s.creases |= 1u << k;
            if facing >= nb_facing {
                s.lighten = true;
                s.lit_creases |= 1u << k;
            } else {
                s.darken = true;
            }
        }
    }
    if curved || !flat {
        s.similar |= SIMILAR_CURVED;
        // The plane of a curved surface is only its tangent: nothing it hides is known.
        s.seek &= ~s.hidden;
        s.hidden = 0u;
    } else if apart && globals.edges != 0u {
        // Only where edges are searched (the paper's schedule keeps its quads as they were).
        s.similar |= SIMILAR_APART;
    }
    return s;
}

// What `trace_rays` found: the light reaching the texel, the lights not shadowed (bit i:
// light i, or not traced: behind the texel's normal, out of a point light's reach, which a
// terrain pixel decides by its own normal), the similar bits with the edges and corner
// cuts, and the number of lights.
struct Traced {
    light: vec3<f32>,
    unshadowed: u32,
    // The highlights of the lights that reach it, seen from the probe (linear colour).
    shine: vec3<f32>,
    similar: u32,
    lights: u32,
}

// Lights and shadows, then the silhouette edges' search: one loop, one call of the BVH
// traversal (every call site is a copy of it in the compiled shader: with the edge
// search's own, lavapipe took 4.8 s longer to build the pipelines).
fn trace_rays(x: Texel, sides: Sides, emissive: bool) -> Traced {
    let normal = x.me.geo.xyz;
    // A texel's point is interpolated across its triangle by the rasterizer, a few
    // hundredths of a texel off the surface far from the probe (more on some drivers:
    // SwiftShader's far floor lay 0.02 below itself and shadowed itself): the shadow rays
    // start a tenth of a texel off, and never nearer than the screen's offset.
    let offset = max(SHADOW_OFFSET, 0.1 * frame_texel_size(x.fr, x.d, sf.n, x.ray));
    let shading = textureLoad(shading_tex, x.t, sf.face, 0).r;
    var lit_normal = normal;
    if shading != 0u {
        lit_normal = normalize(unpack4x8snorm(shading).xyz);
    }
    let start = x.p + lit_normal * offset;
    var out = Traced(globals.ambient.rgb, 0xffffffffu, vec3(0.0), sides.similar, select(light_count(), 0u, emissive));
    // Highlights as the probe sees them: the view is the texel's ray from its origin, so
    // the shine is cached with the texel and changes only where the probe does.
    let spec = objects[x.me.id - 1u].specular;
    // Only the lights that may reach it are traced (`near_points`); the rest would be out
    // of reach, and the bits of the unshadowed lights keep their indices among all.
    let near = near_points(x.p);
    let lights = select(globals.sun_count + near.y, 0u, emissive);
    let hidden = sides.hidden;
    let search = globals.edges != 0u && sides.seek != 0u;
    var e = EdgeSearch(select(0u, sides.seek, search), 0u, 0.0, 1.0, 0.0, 0u, EDGES_UNKNOWN);
    // Edge rays start halfway to the surface (nothing nearer lies on this texel's ray, and
    // the traversal skips the boxes before it).
    let skip = 0.5 * x.d;
    // They walk the still instances from one subtree that holds all they may meet.
    var edge_root = BVH_STATICS_ALL;
    if search && globals.edge_roots != 0u {
        edge_root = edge_statics(x, out.similar, e.left, hidden, skip);
    }
    let side_rays = EDGE_STEPS * countOneBits(e.left);
    // Corner rays (`CORNER_CUT_LEFT`), after the sides' search: bit j where the corner of
    // side j (left, right) with `corner_side` has both sides searched as silhouettes (not
    // where a neighbour hides the plane: there the edge is a junction, not the surface's
    // end).
    let open = e.left & ~hidden;
    let ky = corner_side(out.similar);
    let corners = select(0u, open & 3u, ((open >> ky) & 1u) != 0u);
    e.corners_left = corners;
    let rays = lights + side_rays + countOneBits(corners);
    for (var i = 0u; i < rays; i++) {
        var shot: CastRay;
        var r: LightRay;
        // The edge search's step on its side (from `lights` on).
        let step = select(0u, i - lights, i >= lights) % EDGE_STEPS;
        var light = 0u;
        var statics = edge_root;
        if i < lights {
            light = near_light(near, i);
            r = light_ray(light, x.p);
            if dot(lit_normal, r.dir) <= 0.0 || r.reach <= 0.0 {
                continue;
            }
            shot = CastRay(start, r.dir, light_reach(r, offset));
            statics = light_casters(light, offset);
        } else if i >= lights + side_rays {
            shot = corner_ray(&e, x, out.similar, ky, skip);
        } else {
            shot = side_ray(&e, x, out.similar, hidden, step, skip, offset);
        }
        // An edge ray's hit, if any, lies near the silhouette, at its far end.
        let hit = bvh_any_hit_from(shot.origin, shot.dir, shot.t_max, i >= lights, statics);
        if i < lights {
            if !hit {
                out.light += r.colour * dot(lit_normal, r.dir) * r.fall * r.fall;
                out.shine += r.colour * (r.fall * r.fall * highlight(lit_normal, r.dir, -normalize(x.ray), spec));
            } else {
                out.unshadowed &= ~(1u << light);
            }
        } else if i >= lights + side_rays {
            if !hit {
                out.similar |= select(CORNER_CUT_LEFT, CORNER_CUT_RIGHT, e.k == 1u);
            }
        } else {
            settle_side(&e, hit, hidden, step);
        }
    }
    out.similar |= e.edges;
    return out;
}

// The lit colour of `x` (albedo `albedo`, `object_flags` its object's) from the light
// `traced` found, posterized with the outline's shift, or as outline strips (`OUTLINE_MARK`).
fn texel_colour(x: Texel, albedo: vec3<f32>, object_flags: u32, sides: Sides, traced: Traced) -> vec3<f32> {
    let emissive = (x.flags & FLAG_EMISSIVE) != 0u;
    var colour = albedo * traced.light;
    if (object_flags & FLAG_TERRAIN) == 0u {
        colour += traced.shine;
    }
    if emissive {
        colour = objects[x.me.id - 1u].emissive;
    }
    var darken = sides.darken;
    var lighten = sides.lighten;
    var shift = 0.0;
    // A perspective probe's outline, the eye's included, is drawn as strips from its edges
    // (OUTLINE_MARK: cull.wgsl `emit_outlined`, and for the eye's fill background.wgsl
    // `strip_shift`), fixed to the world where a whole texel's shift ran to the texel grid,
    // which for the eye slides with the camera. An eye texel the drawing stable probes also
    // show (a silhouette's, lit for its edges, its quad behind theirs) keeps the one-quad
    // whole-texel shift: with strips there too the eye drew 4-15 % more quads over the
    // suite's paths for the same shimmer (docs/stability-log.md, "The eye's outlines as
    // strips"). An orthographic probe's texels keep the whole-texel shift (they do not roll
    // as the camera pans; with strips the eye filled 0.7 % of ortho_pan's pixels at faces of
    // 32, against none: not looked into yet).
    var outline = 0u;
    if x.fr.half <= 0.0 && (sides.silhouettes | sides.creases) != 0u && !emissive && (sf.view_cull == 0u || covered_colour(x.p, x.me.id).a < 0.0) {
        darken = false;
        lighten = false;
        outline = OUTLINE_MARK | (sides.silhouettes << OUTLINE_SILHOUETTE_AT) | (sides.creases << OUTLINE_CREASE_AT) | (sides.lit_creases << OUTLINE_LIT_AT);
    }
    if darken {
        shift = -1.0;
    } else if lighten {
        shift = 1.0;
    }
    var lit = half_precision(posterize(colour, globals.bands, shift));
    if !emissive && (object_flags & FLAG_TERRAIN) != 0u && traced.lights <= TERRAIN_LIGHTS {
        lit = lit_with_terrain(lit, traced.unshadowed, shift);
    }
    if outline != 0u {
        lit = lit_with_outline(lit, outline);
    }
    return lit;
}

// Lights one texel: lights and shadows, posterization, outlines, similar-neighbour bits.
fn light_texel(t: vec2<u32>) {
    let n = sf.n;
    let me = load(sf.face, t);
    let uv = texel_center_uv(t, n);
    let fr = face_frame();
    let ray = frame_ray(fr, sf.face, uv);
    let d = me.geo.w;
    let p = frame_point(fr, sf.face, uv, d);
    let alb = textureLoad(albedo_tex, t, sf.face, 0);
    let flags = u32(round(alb.a * 255.0));
    let x = Texel(t, me, uv, fr, ray, d, p, flags);
    let object_flags = objects[me.id - 1u].flags;
    let sides = texel_sides(x, object_flags);
    let traced = trace_rays(x, sides, (flags & FLAG_EMISSIVE) != 0u);
    var lit = texel_colour(x, alb.rgb, object_flags, sides, traced);
    // A dithered palette's rank, from the surface (lib/common.wgsl `surface_dither_rank`);
    // a terrain's pixels take their screen pixel's (terrain_splat.wgsl draws them).
    if globals.dither != 0u && (object_flags & FLAG_TERRAIN) == 0u {
        lit = lit_with_dither(lit, surface_dither_rank(p, me.geo.xyz, ray, frame_texel_size(fr, d, n, ray)));
    }
    textureStore(lit_out, t, sf.face, vec4(lit, f32(traced.similar)));
    // The cull pass draws exactly the eye texels lit this frame.
    if sf.view_cull != 0u {
        list_push(sf.face, n, t);
    }
}
