// Terrain splats: for each one-texel terrain quad of the cull pass's list, the terrain pixels
// it shows (lib/view.wgsl `TerrainSplat`), which the splat pass's fragments pick from by
// where their view ray meets the terrain: a terrain's pixels then follow the world rather
// than each probe's texel grid. Once per quad, between cull and splat. What a texel shows
// depends on the camera only through the haze, so each record is kept, unhazed, in a cache
// slot of the texel's key and band shift (`cache_slot`), stamped with what it was made from
// (`record_stamp`) and sealed with its contents and the shadows' epoch where it lies
// (`sealed`): a texel drawn again with the same point (an eye texel: the same block),
// outline and probe takes its record from there. Each is also kept by its block and pixels
// (`block_slot`), which is all a record is made from: a texel the first cache misses (a
// crossing's new probe, the eye on ground a stable probe showed) finds it there once
// `shadows` has found its block. A record's pixels are shadowed from their
// own centres (`cast_rays`, rays through the BVH), not by the texel's rays: two probes whose
// texels both show a pixel then agree on its shadow, as they agree on its colour.
// crates/render/src/passes/terrain_splat.rs.

#include "lib/common.wgsl"
#include "lib/view.wgsl"
#include "lib/texture.wgsl"
#include "lib/terrain.wgsl"
#include "lib/lights.wgsl"
#include "lib/shade_globals.wgsl"
#include "lib/bvh.wgsl"

struct DrawArgs {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

struct DispatchArgs {
    x: u32,
    y: u32,
    z: u32,
}

const GROUP: u32 = 64u;

@group(0) @binding(0) var<uniform> view: ViewGlobals;
// The scene's objects, textures and terrains (bindings 1-6 as in passes/raster.rs
// `scene_layout_entries`, less the surfaces), the shade pass's globals and point lights.
@group(0) @binding(1) var<storage, read> objects: array<Object>;
@group(0) @binding(7) var<uniform> globals: ShadeGlobals;
@group(0) @binding(8) var<storage, read> points: array<PointLight>;
fn point_record(i: u32) -> PointLight {
    return points[i];
}
@group(0) @binding(9) var<storage, read> splats: array<Splat>;
@group(0) @binding(10) var<storage, read> args: DrawArgs;
// One record per splat of the list (at its index), then the cache: one per texel key
// (`texel_key`), at the list's capacity plus the key, where the buffer holds it.
@group(0) @binding(11) var<storage, read_write> records: array<TerrainSplat>;
// Its own group: bound only while `size` writes it, not while `main` is dispatched by it.
@group(1) @binding(0) var<storage, read_write> dispatch: DispatchArgs;
// The shadow BVH (lib/bvh.wgsl, passes/mod.rs `bvh_layout`), bound only for `shadows`.
@group(2) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(2) @binding(1) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(2) @binding(2) var<storage, read> bvh_instances: array<BvhInstance>;
@group(2) @binding(3) var<uniform> bvh_fields: BvhFields;
@group(2) @binding(4) var bvh_field_data: texture_2d_array<f32>;

// The dispatch of `main`: one invocation per quad of the list; and an empty queue of misses.
@compute @workgroup_size(1)
fn size() {
    let quads = min(args.instance_count, arrayLength(&splats));
    dispatch = DispatchArgs((quads + GROUP - 1u) / GROUP, 1u, 1u);
    misses.quads = quads;
    atomicStore(&misses.count, 0u);
    atomicStore(&misses.rays_cast, 0u);
    atomicStore(&misses.found, 0u);
    atomicStore(&misses.to_make, 0u);
    atomicStore(&misses.to_cast, 0u);
}

// The quads whose record was not in the cache, found on their block or queued for `make` by
// `shadows`, in dispatches of their own: a miss among hits would keep its whole SIMD group
// waiting (lavapipe runs 8 lanes, a GPU 32 or 64), and misses are few and scattered (the
// eye's texels, a new probe's faces). `quads` is the list's count as `size` found it (so
// `main` binds no `args`: a stage has 8 storage buffers in WebGPU's limits). `to_make` and
// `to_cast` count the lists of misses `make` and `cast_rays` take (`Miss::make_at`, `Miss::cast_at`): each dispatch runs only the misses with work for it, as
// an invocation paid for its shader's rare code whether it ran it or not (measured on
// `terrain_walk` at 1280×720, with CI running beside it: the pass's mean 89.6 -> 62.7 ms with
// `shadows`' rays left out, though they were cast for a few hundred pixels a frame; on a
// quiet machine the pass went 55.5 -> 24.5 ms with these lists).
// `rays_cast` counts the pixels whose shadow rays this pass cast, `found` the misses whose
// record another probe's or texel's quad had made on its block (`block_slot`; both read back
// as frame counters).
// `lights`: the lights that reach terrain pixels' centres, as `cast_rays` found them: one word
// per slot, at a hash of the pixel and the shadows' epoch around it (`pixel_hash`), its check
// bits (`pixel_check`) above TERRAIN_LIGHTS bits of lights; 0 is empty. A pixel is shared by
// the blocks of every probe and frame that show it, so its rays are cast once, not once per
// record (a new probe's records at its crossing, the eye's as it moves). Cleared with the
// records. (Here, not a buffer of its own, so that `cast_rays` binds the BVH within the 8.)
struct Misses {
    quads: u32,
    count: atomic<u32>,
    rays_cast: atomic<u32>,
    found: atomic<u32>,
    _pad0: u32,
    to_make: atomic<u32>,
    to_cast: atomic<u32>,
    // Scalars, not a vec3 (aligned to 16): `lights` starts at byte 32, as terrain_splat.rs
    // `MISSES_HEADER_BYTES` has it.
    _pad2: u32,
    lights: array<atomic<u32>, CELL_LIGHT_SLOTS>,
    at: array<Miss>,
}

const CELL_LIGHT_SLOTS: u32 = 1048576u;

// A queued miss: what `shadows` and `cast_rays` need of its quad (`cast_rays` binds neither
// the list nor the objects, to stay within those 8 buffers with the BVH's) and what they
// found.
struct Miss {
    // The quad's index in the list.
    index: u32,
    // Its terrain's index << 8 | its probe's role (`miss_terrain`, `miss_role`).
    kind: u32,
    // The quad's object word (the splat's c3.w: object, band shift, the texel's lights).
    word: u32,
    // Entry `i` of `make`'s list, held by miss `i`: the miss it names (`Misses::to_make`).
    make_at: u32,
    // What `shadows` and `cast_rays` found, for `make`: bit TERRAIN_LIGHTS · (k & 1) + i of
    // word k >> 1, light i reaches the centre of the pixel of cell k of the quad's block
    // (`pixel_reach`);
    reach: vec2<u32>,
    // the block's first cell and its cells' size (`terrain_block`; `main` finds an eye
    // quad's, size 0 asks `shadows` to);
    base: vec2<f32>,
    size: f32,
    // bit k: cell k shows the promoted pixel around it (`block_pixel`); bit CAST_AT + k: its
    // pixel's rays are `cast_rays`' to cast, bit CLAIMED_AT + k: and their lights to write to
    // the table (`shadows` claimed its slot), bit WAIT_AT + k: another miss claimed it, and
    // `make` reads them from there. Until `shadows`, the band of a block `main` found, from
    // bit 8.
    promoted: u32,
    // Entry `i` of `cast_rays`' list, held by miss `i` (`Misses::to_cast`).
    cast_at: u32,
}

const CAST_AT: u32 = 4u;
const CLAIMED_AT: u32 = 8u;
const WAIT_AT: u32 = 12u;
// In a table word: its pixel's rays are being cast this pass, by the miss that claimed it.
const PIXEL_PENDING: u32 = 1u << TERRAIN_LIGHTS;
// A table word's lights (below its check bits).
const LIGHT_BITS: u32 = (1u << TERRAIN_LIGHTS) - 1u;

// A miss's `reach` with the lights of table word `bits` added for its block's cell `k`.
fn with_pixel_lights(reach: vec2<u32>, k: u32, bits: u32) -> vec2<u32> {
    var r = reach;
    r[k >> 1u] |= (bits & LIGHT_BITS) << (TERRAIN_LIGHTS * (k & 1u));
    return r;
}

fn miss_terrain(m: Miss) -> u32 {
    return m.kind >> 8u;
}

fn miss_role(m: Miss) -> u32 {
    return m.kind & 0xffu;
}

@group(0) @binding(12) var<storage, read_write> misses: Misses;

// When shadows last changed around each patch of ground (crates/render/src/shadow_region.rs
// `ShadowTiles`): tiles of TILE_BASE · 2^level units at TILE_LEVELS levels, each level's
// wrapped onto TILE_WRAP² entries (`tile_entry`), holding the epoch of the last moved
// caster's shadow area that overlapped one of them. A terrain pixel's table word and a
// record are stamped with the latest epoch around them (`tile_epoch`), so a caster that
// moves has only the pixels and records its shadow may have come or gone from made again.
@group(0) @binding(14) var<uniform> shadow_tiles: array<vec4<u32>, 4096>;

const TILE_LEVELS: u32 = 16u;
const TILE_BASE: f32 = 0.25;
const TILE_WRAP: u32 = 32u;

// Each quad of the list: its record from the cache, hazed, or queued for `shadows` and `make`.
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let ii = gid.x;
    let capacity = arrayLength(&splats);
    if ii >= min(misses.quads, arrayLength(&records)) {
        return;
    }
    let s = splats[ii];
    if !is_terrain_splat(s) {
        return;
    }
    let word = bitcast<u32>(s.c3.w);
    let mid = splat_mid(s);
    let role = splat_role(s);
    let probe = splat_probe(role);
    // The eye's texels move with the camera: an eye quad's record is stamped with the block
    // its point lies toward (which is all a record is made from), not with the point, and
    // kept in a slot of that block (`cache_slot`), so a texel that shows a block an eye
    // texel showed before, on this frame or an earlier one, finds its record. Only the eye
    // and the misses read the quad's object (its terrain).
    var terrain = 0u;
    var block = TerrainBlock(0u, 0.0, vec2(0.0));
    if role == ROLE_EYE {
        terrain = objects[word >> SPLAT_TERRAIN_OBJECT_AT].flags >> 8u;
        block = terrain_block(terrains[terrain], mid, probe);
    }
    let slots = texel_slots(capacity);
    if slots > 0u {
        let stamp = record_stamp(word, stamp_point(role, mid, block), probe);
        let r = records[capacity + cache_slot(s, role, block, slots)];
        if bitcast<u32>(r.grid.w) == sealed(stamp, r) {
            records[ii] = r;
            return;
        }
    }
    if role != ROLE_EYE {
        terrain = objects[word >> SPLAT_TERRAIN_OBJECT_AT].flags >> 8u;
    }
    let k = atomicAdd(&misses.count, 1u);
    if k < arrayLength(&misses.at) {
        var m: Miss;
        m.index = ii;
        m.kind = (terrain << 8u) | role;
        m.word = word;
        // The eye's block as found here (`shadows` finds the others').
        m.base = block.base;
        m.size = block.size;
        m.promoted = block.band << 8u;
        misses.at[k] = m;
    }
}

// The point a quad's record stamp holds (`record_stamp`): a stable probe's texel point, or
// an eye texel's block (`main`).
fn stamp_point(role: u32, mid: vec3<f32>, block: TerrainBlock) -> vec3<f32> {
    if role == ROLE_EYE {
        return vec3(block.base, block.size);
    }
    return mid;
}

// The dispatch of `shadows`: one invocation per queued miss.
@compute @workgroup_size(1)
fn size_misses() {
    size_dispatch(min(atomicLoad(&misses.count), arrayLength(&misses.at)));
}

// The dispatch of `cast_rays`: one invocation per miss `shadows` listed for it.
@compute @workgroup_size(1)
fn size_casts() {
    size_dispatch(atomicLoad(&misses.to_cast));
}

// The dispatch of `make`: one invocation per miss `shadows` listed for it.
@compute @workgroup_size(1)
fn size_makes() {
    size_dispatch(atomicLoad(&misses.to_make));
}

// `dispatch`: workgroups of GROUP over `n` invocations.
fn size_dispatch(n: u32) {
    dispatch = DispatchArgs((n + GROUP - 1u) / GROUP, 1u, 1u);
}

// Each queued miss: its block and its pixels (`block_pixel`); its record where a quad of
// another probe or texel made it for the same block and pixels (`block_slot`: a crossing's
// new probe shows mostly the blocks the old one did), written to the list and the quad's
// cache slot here; else it is listed for `make`, with which lights reach the centres of its
// block's four pixels where a frame before cast their rays (the table), and listed for
// `cast_rays` if some pixel's are not there. The first miss to find a pixel missing claims
// its slot (PIXEL_PENDING, by an atomic compare-exchange) and casts for it; the others that
// show it wait, and `make` reads its lights from the table. (Unclaimed, every miss of the
// dispatch that showed a pixel cast its rays: 17,000–22,000 pixels on a crossing's frame of
// `terrain_walk` at 1280×720 against 750 while `shadows` cast them in place and wrote the
// table at once.) A pixel whose slot another pixel claimed, or whose claim failed, is cast
// for this miss alone. Each field of the miss is written on its own: other invocations write
// the list entries (`make_at`, `cast_at`) this miss holds.
@compute @workgroup_size(64)
fn shadows(@builtin(global_invocation_id) gid: vec3<u32>) {
    let g = gid.x;
    if g >= min(atomicLoad(&misses.count), arrayLength(&misses.at)) {
        return;
    }
    // Field by field: other invocations write this element's list entries meanwhile.
    var m: Miss;
    m.index = misses.at[g].index;
    m.kind = misses.at[g].kind;
    m.word = misses.at[g].word;
    m.base = misses.at[g].base;
    m.size = misses.at[g].size;
    m.promoted = misses.at[g].promoted;
    let s = splats[m.index];
    let mid = splat_mid(s);
    let t = miss_terrain(m);
    let tr = terrains[t];
    let role = miss_role(m);
    let probe = splat_probe(role);
    var b = TerrainBlock(m.promoted >> 8u, m.size, m.base);
    if m.size == 0.0 {
        b = terrain_block(tr, mid, probe);
    }
    m.base = b.base;
    m.size = b.size;
    m.promoted = 0u;
    var px: array<TerrainPixel, 4>;
    for (var k = 0u; k < 4u; k++) {
        px[k] = block_pixel(tr, b, k, probe);
        m.promoted |= select(0u, 1u << k, px[k].size > b.size);
    }
    let capacity = arrayLength(&splats);
    let slots = texel_slots(capacity);
    if slots > 0u {
        var r = records[block_slot(m)];
        if bitcast<u32>(r.grid.w) == sealed(block_stamp(m), r) {
            records[m.index] = r;
            let block = TerrainBlock(0u, m.size, m.base);
            r.grid.w = bitcast<f32>(sealed(record_stamp(m.word, stamp_point(role, mid, block), probe), r));
            records[capacity + cache_slot(s, role, block, slots)] = r;
            atomicAdd(&misses.found, 1u);
            return;
        }
    }
    var reach = vec2(0u);
    // Pixels whose rays `cast_rays` casts, those of them whose table slot this miss claimed,
    // and those another miss claimed.
    var uncast = 0u;
    var claimed = 0u;
    var wait = 0u;
    for (var k = 0u; k < 4u; k++) {
        let h = pixel_hash(t, tr, px[k]);
        let slot = h % CELL_LIGHT_SLOTS;
        let check = pixel_check(h);
        let bits = atomicLoad(&misses.lights[slot]);
        if (bits & ~LIGHT_BITS) == check {
            reach = with_pixel_lights(reach, k, bits);
        } else if (bits & ~LIGHT_BITS) == (check | PIXEL_PENDING) {
            wait |= 1u << k;
        } else {
            uncast |= 1u << k;
            // Not a slot another pixel's miss claimed (its answer is on its way there).
            if (bits & PIXEL_PENDING) == 0u && atomicCompareExchangeWeak(&misses.lights[slot], bits, check | PIXEL_PENDING).exchanged {
                claimed |= 1u << k;
            }
        }
    }
    misses.at[g].base = m.base;
    misses.at[g].size = m.size;
    misses.at[g].promoted = m.promoted | (uncast << CAST_AT) | (claimed << CLAIMED_AT) | (wait << WAIT_AT);
    misses.at[g].reach = reach;
    misses.at[atomicAdd(&misses.to_make, 1u)].make_at = g;
    if uncast != 0u {
        misses.at[atomicAdd(&misses.to_cast, 1u)].cast_at = g;
    }
}

// The misses `shadows` listed for it: the shadow rays from the centre of each of their
// pixels the table did not hold, into the miss's `reach` and, where the miss claimed the
// pixel's slot, the table (where `make` reads them for the misses that waited on it).
@compute @workgroup_size(64)
fn cast_rays(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= atomicLoad(&misses.to_cast) {
        return;
    }
    let g = misses.at[gid.x].cast_at;
    let m = misses.at[g];
    let t = miss_terrain(m);
    let tr = terrains[t];
    var reach = m.reach;
    for (var k = 0u; k < 4u; k++) {
        if ((m.promoted >> (CAST_AT + k)) & 1u) != 0u {
            let px = miss_pixel(m, k);
            let h = pixel_hash(t, tr, px);
            let bits = pixel_check(h) | pixel_reach(tr, px);
            if ((m.promoted >> (CLAIMED_AT + k)) & 1u) != 0u {
                atomicStore(&misses.lights[h % CELL_LIGHT_SLOTS], bits);
            }
            atomicAdd(&misses.rays_cast, 1u);
            reach = with_pixel_lights(reach, k, bits);
        }
    }
    misses.at[g].reach = reach;
}

// The slots of the records' cache kept by texel (`cache_slot`), behind a list of `capacity`:
// those the buffer holds less the last BLOCK_SLOTS, kept by block (`block_slot`); 0 where
// the buffer holds only the list.
fn texel_slots(capacity: u32) -> u32 {
    let n = arrayLength(&records);
    if n <= capacity + BLOCK_SLOTS {
        return 0u;
    }
    return n - capacity - BLOCK_SLOTS;
}

// Slots of the records kept by block (terrain_splat.rs `BLOCK_SLOTS`), the buffer's last.
const BLOCK_SLOTS: u32 = 262144u;

// What the record of miss `m` (after `shadows` found its block and pixels) is made from,
// whichever probe's texel shows it: its object and band shift, its block's first cell and
// cells' size, which cells are promoted. Never 0, which a cleared cache holds.
fn block_stamp(m: Miss) -> u32 {
    let h = block_key(m.word, TerrainBlock(0u, m.size, m.base));
    return max(hash_u32(h ^ (m.promoted & 15u)), 1u);
}

// The slot of miss `m`'s record among those kept by block: a hash of `block_stamp`.
fn block_slot(m: Miss) -> u32 {
    return arrayLength(&records) - BLOCK_SLOTS + hash_u32(block_stamp(m)) % BLOCK_SLOTS;
}

// The terrain pixel that holds cell `k` (x: bit 0, z: bit 1) of miss `m`'s block, as
// `shadows` found it.
fn miss_pixel(m: Miss, k: u32) -> TerrainPixel {
    let cell = m.base + vec2(f32(k & 1u), f32(k >> 1u));
    if ((m.promoted >> k) & 1u) != 0u {
        return TerrainPixel((floor(0.5 * cell) + 0.5) * (2.0 * m.size), 2.0 * m.size);
    }
    return TerrainPixel((cell + 0.5) * m.size, m.size);
}

// The check bits of the pixel whose hash is `h`: from another hash of it, above the
// TERRAIN_LIGHTS bits of lights and PIXEL_PENDING, never all zero (an empty slot).
fn pixel_check(h: u32) -> u32 {
    return (hash_u32(h ^ 0x5bd1e995u) << (TERRAIN_LIGHTS + 1u)) | (1u << 31u);
}

// A hash of pixel `px` of terrain `tr` (index `t`) and the shadows' epoch around it.
fn pixel_hash(t: u32, tr: Terrain, px: TerrainPixel) -> u32 {
    let c = vec2<i32>(floor(px.centre / px.size));
    var h = hash_u32(t ^ 0x9e3779b9u);
    h = hash_u32(h ^ bitcast<u32>(px.size));
    h = hash_u32(h ^ bitcast<u32>(c.x));
    h = hash_u32(h ^ bitcast<u32>(c.y));
    // Where its shadow rays start: its square, and a ray's offset off the surface.
    let reach = 0.5 * px.size + max(SHADOW_OFFSET, 0.1 * px.size);
    let at = tr.corner.xz + px.centre;
    return hash_u32(h ^ tile_epoch(at - reach, at + reach));
}

// The entry of tile (`x`, `z`) of `level` in `shadow_tiles` (shadow_region.rs `tile_entry`):
// (x mod 32, z mod 32) in its level's table.
fn tile_entry(level: u32, x: i32, z: i32) -> u32 {
    let w = TILE_WRAP - 1u;
    return (level * TILE_WRAP + (bitcast<u32>(z) & w)) * TILE_WRAP + (bitcast<u32>(x) & w);
}

// The latest shadow epoch over the world XZ square `lo`..`hi`: of the tiles it overlaps at
// the first level whose tiles are at least as wide (2 × 2 at most; at the last level, the
// 2 × 2 from its corner `lo`: no terrain pixel is thousands of units wide). (Tiles half as
// wide, 3 × 3 of them, wrap at half the distance: a moving box's shadow beside the lantern
// on terrain_hills then spanned a whole level, and more records were made again.)
fn tile_epoch(lo: vec2<f32>, hi: vec2<f32>) -> u32 {
    let w = max(hi.x - lo.x, hi.y - lo.y);
    var level = 0u;
    var side = TILE_BASE;
    while level + 1u < TILE_LEVELS && side < w {
        level++;
        side *= 2.0;
    }
    let a = vec2<i32>(floor(lo / side));
    let b = min(vec2<i32>(floor(hi / side)), a + 1);
    var e = 0u;
    for (var x = a.x; x <= b.x; x++) {
        for (var z = a.y; z <= b.y; z++) {
            let i = tile_entry(level, x, z);
            e = max(e, shadow_tiles[i >> 2u][i & 3u]);
        }
    }
    return e;
}

// The lights (bit i: light i, below TERRAIN_LIGHTS) that reach the centre of terrain pixel
// `px` of `tr`: a shadow ray from its centre on the level-0 surface (the one the BVH walks),
// a tenth of a pixel off along the normal (as the shade pass starts a texel's a tenth of a
// texel off). A light behind the normal or out of reach counts as reaching;
// `terrain_lit_pixel` lights by the normal.
fn pixel_reach(tr: Terrain, px: TerrainPixel) -> u32 {
    let size = px.size;
    let q = clamp(px.centre, vec2(0.0), tr.size);
    let centre = vec3(tr.corner.x + q.x, tr.corner.y + terrain_plane(tr, q).height, tr.corner.z + q.y);
    let normal = terrain_normal(tr, q);
    let offset = max(SHADOW_OFFSET, 0.1 * size);
    let start = centre + normal * offset;
    var reach = 0u;
    for (var i = 0u; i < min(light_count(), TERRAIN_LIGHTS); i++) {
        let r = light_ray(i, centre);
        let traced = dot(normal, r.dir) > 0.0 && r.reach > 0.0;
        if !traced || !bvh_any_hit(start, r.dir, light_reach(r, offset)) {
            reach |= 1u << i;
        }
    }
    return reach;
}

// Each miss `shadows` listed for it: its record made, sealed into its cache slot and its
// block's (`block_slot`), and hazed into the list's.
@compute @workgroup_size(64)
fn make(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= atomicLoad(&misses.to_make) {
        return;
    }
    var m = misses.at[misses.at[gid.x].make_at];
    // The lights of the pixels another miss cast for, from the table: the slot it claimed
    // holds them now (no other miss writes a claimed slot).
    let t = miss_terrain(m);
    let tr = terrains[t];
    for (var k = 0u; k < 4u; k++) {
        if ((m.promoted >> (WAIT_AT + k)) & 1u) != 0u {
            let h = pixel_hash(t, tr, miss_pixel(m, k));
            m.reach = with_pixel_lights(m.reach, k, atomicLoad(&misses.lights[h % CELL_LIGHT_SLOTS]));
        }
    }
    let ii = m.index;
    let capacity = arrayLength(&splats);
    let s = splats[ii];
    let mid = splat_mid(s);
    let role = miss_role(m);
    let probe = splat_probe(role);
    let block = TerrainBlock(0u, m.size, m.base);
    let stamp = record_stamp(m.word, stamp_point(role, mid, block), probe);
    let slots = texel_slots(capacity);
    var r = terrain_splat(m.word, m);
    r.grid.w = bitcast<f32>(sealed(stamp, r));
    if slots > 0u {
        records[capacity + cache_slot(s, role, block, slots)] = r;
        var by_block = r;
        by_block.grid.w = bitcast<f32>(sealed(block_stamp(m), r));
        records[block_slot(m)] = by_block;
    }
    records[ii] = r;
}

// The haze over each terrain quad's record (`hazed_record`), a dispatch of its own that runs
// only on a frame with haze (terrain_splat.rs). Inside `main`, `shadows` and `make` the
// invocations paid for it on lavapipe with no haze too: the pass's mean on terrain_walk at
// 1280×720, heights 257, went 24.5 -> 22.7 ms (quiet) without it; with haze 0.03 the
// dispatch costs a little more than it saves, 24.9 -> 26.0. (Not every skipped branch costs
// so: `main`'s eye branch taken out changed nothing.)
@compute @workgroup_size(64)
fn haze(@builtin(global_invocation_id) gid: vec3<u32>) {
    let ii = gid.x;
    if ii >= min(misses.quads, arrayLength(&records)) {
        return;
    }
    let s = splats[ii];
    if is_terrain_splat(s) {
        records[ii] = hazed_record(records[ii], splat_mid(s));
    }
}

fn splat_role(s: Splat) -> u32 {
    return bitcast<u32>(s.c2.w) & 0xffu;
}

// The cache slot of terrain quad `s` of probe role `role` (an eye quad's block `b`) among
// `slots` (> 0), by its record's key. A stable probe's: its texel's key (1-based) and its
// pixels' band shift (an outline's strips are a band darker or lighter than the body;
// strips of one shift show the same record). The eye's: its block and its object and shift
// (`block_key`), among its slot's keys. Its own slot where there is one per texel key (3
// shifts × 3 probe slots × 6 faces × max_n²), else a hash of the key. Two keys sharing a
// slot may both write it in one pass; `sealed` tells a record so overwritten, or torn
// between the two.
fn cache_slot(s: Splat, role: u32, b: TerrainBlock, slots: u32) -> u32 {
    let shift = min((bitcast<u32>(s.c3.w) >> TERRAIN_LIGHTS) & 3u, 2u);
    let key = 3u * (bitcast<u32>(s.c0.w) - 1u) + shift;
    let per_slot = 18u * view.max_n * view.max_n;
    let direct = 3u * per_slot <= slots;
    if role == ROLE_EYE {
        let h = block_key(bitcast<u32>(s.c3.w), b);
        if direct {
            return key - key % per_slot + h % per_slot;
        }
        return h % slots;
    }
    if direct {
        return key;
    }
    return hash_u32(key) % slots;
}

// A hash of the record an eye quad with object `word` (the splat's c3.w) shows on block `b`:
// its object, its band shift and the block (its first cell and cells' size).
fn block_key(word: u32, b: TerrainBlock) -> u32 {
    var h = hash_u32(0x2545f491u ^ (word & ~((1u << TERRAIN_LIGHTS) - 1u)));
    h = hash_u32(h ^ bitcast<u32>(b.size));
    h = hash_u32(h ^ bitcast<u32>(b.base.x));
    return hash_u32(h ^ bitcast<u32>(b.base.y));
}

// A record's stamp sealed with its contents: `stamp` (what it is made from) hashed with
// every word of `r` but the stamp's own, and with the shadows' epoch where its pixels lie
// (its block's cells, and the promoted pixels around them, one cell further; their rays'
// offset off the surface). Never 0, which a cleared cache holds.
fn sealed(stamp: u32, r: TerrainSplat) -> u32 {
    let size = r.grid.z;
    let reach = size + max(SHADOW_OFFSET, 0.2 * size);
    var h = hash_u32(stamp ^ tile_epoch(r.grid.xy - reach, r.grid.xy + 2.0 * size + reach));
    for (var k = 0u; k < 4u; k++) {
        h = hash_u32(h ^ r.cells[k]);
        h = hash_u32(h ^ bitcast<u32>(r.edges[k]));
    }
    for (var k = 0u; k < 3u; k++) {
        h = hash_u32(h ^ bitcast<u32>(r.grid[k]));
    }
    return max(h, 1u);
}

// What the probe of `role` sizes terrain pixels for (lib/terrain.wgsl `BandFrom`): the grid
// probe's origin for the eye, as in its capture (capture.wgsl `colour_terrain`).
fn splat_probe(role: u32) -> BandFrom {
    var k = select(role_slot(role), 3u, role == ROLE_EYE);
    var origin = view.slots[view.grid_slot].origin;
    if k < 3u {
        origin = view.slots[k].origin;
    } else {
        k = view.eye_slot;
    }
    return band_from(origin, f32(view.slots[k].n), view.slots[k].half);
}

// What a terrain quad's record is made from, hashed: its outline's band shift and its object
// (`word`, the splat's c3.w, less the lights that reach its texel, which the record's pixels
// do not use: `shadows` finds theirs), its texel's point or block `mid` (`stamp_point`) and
// its probe. Never 0, which a cleared cache holds. The frame's lights, colours and heights
// are not in it: the pass clears the cache when those change (terrain_splat.rs).
fn record_stamp(word: u32, mid: vec3<f32>, p: BandFrom) -> u32 {
    var h = 0x9e3779b9u;
    let words = array<u32, 9>(
        word & ~((1u << TERRAIN_LIGHTS) - 1u), bitcast<u32>(mid.x), bitcast<u32>(mid.y), bitcast<u32>(mid.z),
        bitcast<u32>(p.origin.x), bitcast<u32>(p.origin.y), bitcast<u32>(p.origin.z),
        bitcast<u32>(p.n), bitcast<u32>(p.ortho_texel),
    );
    for (var k = 0u; k < 9u; k++) {
        h = hash_u32(h ^ words[k]);
    }
    return max(h, 1u);
}

// A 32-bit integer hash (a multiply-xorshift finalizer).
fn hash_u32(x: u32) -> u32 {
    var h = x;
    h ^= h >> 16u;
    h *= 0x7feb352du;
    h ^= h >> 15u;
    h *= 0x846ca68bu;
    h ^= h >> 16u;
    return h;
}

// Record `r` of a quad whose texel point is `mid`, as seen from the camera: its cells
// through the haze at that point.
fn hazed_record(r: TerrainSplat, mid: vec3<f32>) -> TerrainSplat {
    if view.haze <= 0.0 {
        return r;
    }
    let dist = length(mid - view.camera.xyz);
    var out = r;
    for (var k = 0u; k < 4u; k++) {
        let c = srgb_to_linear(unpack4x8unorm(r.cells[k]).rgb);
        out.cells[k] = pack4x8unorm(vec4(linear_to_srgb(hazed(c, dist)), 1.0));
    }
    return out;
}

// The 2 × 2 block of cells a one-texel quad of terrain `tr` whose texel point is `mid`,
// drawn by `probe`, shows: their size and the first one's index (toward which the point
// lies in its own cell). The cells are its band's, before the Bayer promotion toward the
// band's end: each shows the pixel that holds it (`block_pixel`), its own or the promoted
// one around it, so the quad of a texel on a promoted pixel still shows its unpromoted
// neighbours at their size, and the other way round.
struct TerrainBlock {
    band: u32,
    size: f32,
    base: vec2<f32>,
}

fn terrain_block(tr: Terrain, mid: vec3<f32>, probe: BandFrom) -> TerrainBlock {
    let q = clamp(mid.xz - tr.corner.xz, vec2(0.0), tr.size);
    let point = vec3(tr.corner.x + q.x, tr.corner.y + terrain_height(tr, q), tr.corner.z + q.y);
    let own = terrain_band_cell(tr, point, probe);
    let g = q / own.size;
    let base = floor(g) - select(vec2(0.0), vec2(1.0), fract(g) < vec2(0.5));
    return TerrainBlock(own.band, own.size, base);
}

// The terrain pixel that holds cell `k` (x: bit 0, z: bit 1) of block `b`, sized for
// `probe`: the cell, or the promoted pixel around it (`promoted_pixel`). A cell is taken to
// be of the block's band (`terrain_pixel` would search the bands for it): past the band's
// far end its ramp is whole and it is promoted, as it should be.
fn block_pixel(tr: Terrain, b: TerrainBlock, k: u32, probe: BandFrom) -> TerrainPixel {
    let cell = b.base + vec2(f32(k & 1u), f32(k >> 1u));
    let d = distance(terrain_cell_point(tr, cell, b.size), probe.origin);
    return promoted_pixel(tr, BandCell(b.band, b.size, cell, d), probe);
}

// The terrain pixels (unhazed) a one-texel quad of a terrain (cull.wgsl) shows, with its
// lights, outline and object `word`, queued as miss `m`: the 2 × 2 block of its band's
// cells toward which its texel point lies in its own cell (`terrain_block`), each showing
// the pixel that holds it (`block_pixel`), as `shadows` found them. A terrain pixel is at
// least a probe texel, so a quad on ground facing the probe meets no other; on ground seen
// at a grazing angle its footprint reaches past the block, and a screen pixel whose ray
// meets the ground there takes the block's nearest cell (docs/stability-log.md, "Terrain").
// Each pixel is coloured and lit as the shade pass would light it from its centre (its
// colour, the terrain's normal there), shadowed from its centre (`m.reach`), with the
// texel's outline. Pixels of the terrain follow the world, not each probe's texel grid: a
// crossfade's two probes show the same pixel under each screen pixel, where each had drawn
// its own texels' steps.
fn terrain_splat(word: u32, m: Miss) -> TerrainSplat {
    var out: TerrainSplat;
    let obj = objects[word >> SPLAT_TERRAIN_OBJECT_AT];
    let tr = terrains[miss_terrain(m)];
    let size = m.size;
    let base = m.base;
    // The ground along the inner edges, through its heights at the edges' two cell middles
    // (points of the world's pixel grid, which a neighbouring block on that edge shares).
    let inner = (base + 1.0) * size;
    let first = (base + 0.5) * size;
    let hx0 = terrain_height(tr, vec2(inner.x, first.y));
    let hx1 = terrain_height(tr, vec2(inner.x, first.y + size));
    let hz0 = terrain_height(tr, vec2(first.x, inner.y));
    let hz1 = terrain_height(tr, vec2(first.x + size, inner.y));
    let bx = (hx1 - hx0) / size;
    let bz = (hz1 - hz0) / size;
    out.edges = vec4(tr.corner.y + hx0 - 0.5 * size * bx, bx, tr.corner.y + hz0 - 0.5 * size * bz, bz);
    let shift = f32((word >> TERRAIN_LIGHTS) & 3u) - 1.0;
    for (var k = 0u; k < 4u; k++) {
        let px = miss_pixel(m, k);
        let lights = (m.reach[k >> 1u] >> (TERRAIN_LIGHTS * (k & 1u))) & LIGHT_BITS;
        let lit = terrain_lit_pixel(tr, obj.albedo, px, lights, shift);
        out.cells[k] = pack4x8unorm(vec4(linear_to_srgb(lit), 1.0));
    }
    out.grid = vec4(tr.corner.xz + base * size, size, 0.0);
    return out;
}

// Terrain pixel `px` of `tr`, lit from its centre by the lights in `reach` (bit i: light i),
// posterized with `shift`.
fn terrain_lit_pixel(tr: Terrain, albedo: vec3<f32>, px: TerrainPixel, reach: u32, shift: f32) -> vec3<f32> {
    let colour = albedo * terrain_pixel_colour(tr, px);
    let centre = vec3(tr.corner.x + px.centre.x, tr.corner.y + terrain_height(tr, px.centre), tr.corner.z + px.centre.y);
    let normal = terrain_normal(tr, px.centre);
    var light = globals.ambient.rgb;
    for (var i = 0u; i < light_count(); i++) {
        if ((reach >> i) & 1u) == 0u {
            continue;
        }
        let r = light_ray(i, centre);
        let ndl = dot(normal, r.dir);
        if ndl > 0.0 && r.reach > 0.0 {
            light += r.colour * ndl * r.fall * r.fall;
        }
    }
    return posterize(colour * light, globals.bands, shift);
}
