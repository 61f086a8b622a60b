// Runs: groups the texels of each face into runs that one splat quad can draw. A run is a
// stretch of neighbours along a row (or, among the texels no row run took, along a column)
// on one object with the same lit colour, similar to each other (the shade pass's neighbour
// bits), the same similarity on both sides, the same normal, and the same Chebyshev depth
// (a floor seen from a side face, a wall facing its face): their quads then lie in one
// plane and abut, so one quad spanning them covers what they would. Rows (then columns) are
// cut into aligned segments of SEGMENT texels, each scanned by one thread; the first texel
// of a run stores its length (| RUN_COLUMN for a column run), the others 0; `columns` also lists the
// heads of the face for the cull pass (lib/lists.wgsl). Runs depend on the probe's data
// alone, so they are cached with its shading. crates/render/src/passes/runs.rs.

#include "lib/common.wgsl"
#include "lib/lists.wgsl"

const SEGMENT: u32 = 16u;
// How far a run's depth may wander from its head's, in units of the depth step between
// neighbours on a surface at 45° to the face (2/n of the depth).
const DEPTH_TOLERANCE: f32 = 0.01;

struct RunsFaces {
    n: u32,
    // Bit f: recompute the runs of face f.
    face_mask: u32,
    slot: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> rf: RunsFaces;
@group(0) @binding(1) var geo_tex: texture_2d_array<f32>;
@group(0) @binding(2) var id_tex: texture_2d_array<u32>;
@group(0) @binding(3) var lit_tex: texture_2d_array<f32>;
@group(0) @binding(4) var runs_out: texture_storage_2d_array<r32uint, read_write>;
@group(0) @binding(5) var<storage, read_write> list: array<atomic<u32>>;

struct Texel {
    geo: vec4<f32>,
    lit: vec4<f32>,
    id: u32,
}

fn load(t: vec2<u32>, face: u32) -> Texel {
    return Texel(
        textureLoad(geo_tex, t, face, 0),
        textureLoad(lit_tex, t, face, 0),
        textureLoad(id_tex, t, face, 0).r,
    );
}

// Whether `next` continues the run that starts at `head` and last took `prev`; `fore` and
// `back` are the similar bits toward the next and the previous texel along the run, `sides`
// those across it.
fn joins(head: Texel, prev: Texel, next: Texel, n: u32, fore: u32, back: u32, sides: u32) -> bool {
    let head_bits = u32(head.lit.a);
    let prev_bits = u32(prev.lit.a);
    let next_bits = u32(next.lit.a);
    let tolerance = head.geo.w * (2.0 / f32(n)) * DEPTH_TOLERANCE;
    // Across the run, its texels share both their similar and their silhouette bits.
    let sides_all = sides | (sides << 4u);
    // A terrain texel is drawn alone: the splat pass colours its pixels from the terrain
    // (splat.wgsl `pixel_colour`), which a run's quad could not hold.
    return head.id != 0u && next.id == head.id
        && lit_terrain(head.lit.rgb) == NO_TERRAIN
        && all(next.lit.rgb == head.lit.rgb)
        && (prev_bits & fore) != 0u && (next_bits & back) != 0u
        && (next_bits & sides_all) == (head_bits & sides_all)
        && abs(next.geo.w - head.geo.w) <= tolerance
        && dot(next.geo.xyz, head.geo.xyz) >= 0.9999;
}

// The texel `i` steps along segment `seg` of face `face`: along rows, or down columns.
fn at(seg: u32, i: u32, segments: u32, columns: bool) -> vec2<u32> {
    let line = seg / segments;
    let along = (seg % segments) * SEGMENT + i;
    if columns {
        return vec2(line, along);
    }
    return vec2(along, line);
}

// Texels in segment `seg` of `face` (0 when the face is not asked for or `seg` is past
// the last segment).
fn segment_length(seg: u32, face: u32) -> u32 {
    let segments = (rf.n + SEGMENT - 1u) / SEGMENT;
    if (rf.face_mask & (1u << face)) == 0u || seg >= segments * rf.n {
        return 0u;
    }
    return min(SEGMENT, rf.n - (seg % segments) * SEGMENT);
}

// Row runs over every texel.
@compute @workgroup_size(64)
fn rows(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = rf.n;
    let segments = (n + SEGMENT - 1u) / SEGMENT;
    let face = gid.z;
    let count = segment_length(gid.x, face);
    if count == 0u {
        return;
    }
    var head_i = 0u;
    var head = load(at(gid.x, 0u, segments, false), face);
    var prev = head;
    for (var i = 1u; i < count; i++) {
        let t = at(gid.x, i, segments, false);
        let next = load(t, face);
        if joins(head, prev, next, n, 2u, 1u, 12u) {
            textureStore(runs_out, t, face, vec4(0u));
        } else {
            textureStore(runs_out, at(gid.x, head_i, segments, false), face, vec4(i - head_i));
            head_i = i;
            head = next;
        }
        prev = next;
    }
    textureStore(runs_out, at(gid.x, head_i, segments, false), face, vec4(count - head_i));
}

// Ends the column run of `len` texels from `head` (at `t`): a run of several is marked and
// listed; a lone texel is listed unless it is sky.
fn close_column(t: vec2<u32>, face: u32, len: u32, head: Texel) {
    if len > 1u {
        textureStore(runs_out, t, face, vec4(len | RUN_COLUMN));
        list_push(face, rf.n, t);
    } else if len == 1u && head.id != 0u {
        list_push(face, rf.n, t);
    }
}

// Column runs over the texels the row runs left alone (runs of one); then every head, of a
// row run or of a column run, goes on the face's draw list.
@compute @workgroup_size(64)
fn columns(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = rf.n;
    let segments = (n + SEGMENT - 1u) / SEGMENT;
    let face = gid.z;
    let count = segment_length(gid.x, face);
    if count == 0u {
        return;
    }
    var head_i = 0u;
    var len = 0u;
    var head: Texel;
    var prev: Texel;
    for (var i = 0u; i < count; i++) {
        let t = at(gid.x, i, segments, true);
        let run = textureLoad(runs_out, t, face).r;
        let alone = run == 1u;
        var next: Texel;
        if alone {
            next = load(t, face);
        }
        if len > 0u && alone && joins(head, prev, next, n, 8u, 4u, 3u) {
            textureStore(runs_out, t, face, vec4(0u));
            len += 1u;
        } else {
            close_column(at(gid.x, head_i, segments, true), face, len, head);
            if run > 1u {
                // The head of a row run (never sky).
                list_push(face, n, t);
            }
            len = select(0u, 1u, alone);
            head_i = i;
            head = next;
        }
        prev = next;
    }
    close_column(at(gid.x, head_i, segments, true), face, len, head);
}
