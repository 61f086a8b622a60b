// Ray-traced shadows: any-hit traversal of the BVH built by `crates/render/src/bvh.rs`
// (layout, build and guarantees are documented there; `any_hit_cpu` is this traversal on
// the CPU, step for step).
//
// This file declares no bindings. A shader that includes it must declare, in any group and
// binding it likes, exactly these two names:
//
//   @group(G) @binding(B0) var<storage, read> bvh_nodes: array<BvhNode>;
//   @group(G) @binding(B1) var<storage, read> bvh_triangles: array<BvhTriangle>;
//   @group(G) @binding(B2) var<storage, read> bvh_instances: array<BvhInstance>;
//
//   @group(G) @binding(B3) var<uniform> bvh_fields: BvhFields;
//   @group(G) @binding(B4) var bvh_field_data: texture_2d_array<f32>;
//
// filled from `GpuBvh::upload` (buffers `bvh::nodes` and `bvh::triangles`),
// `GpuScene::bvh_instances` and the terrains' heightfields (`crates/render/src/bvh/field.rs`:
// a terrain casts through its max-height quadtree, not through triangles in the tree). The
// static scene's tree (objects whose meshes no other shares) has its root at node 0; each
// animated object's tree follows it, built in the object's base pose, and its instance
// record carries rays from where the object is now into that pose; then one tree per shared
// mesh, in object space, which the still objects drawing it reach through their instance
// records (`crates/render/src/bvh/instances.rs`); last, two top-level trees whose leaves
// name instance records: one over the animated casters' bounds now, rebuilt each frame, one
// over the still instances, refit when one moves (record 0 is a header holding both roots).

#include "lib/constants.wgsl"
#include "lib/ray.wgsl"

// Traversal stack entries. The builder merges subtrees deeper than this into leaves, so
// the stack cannot overflow; if it ever did, the ray counts as hit (shadowed).
const BVH_STACK_SIZE: u32 = 32u;
// `BvhNode::count` of an inner node.
const BVH_INNER: u32 = 0xffffffffu;
// Smaller direction components are replaced by this before inverting (no 0 * inf).
const BVH_DIR_EPS: f32 = 1e-20;

// 112 bytes (crates/render/src/gpu_scene.rs `GpuBvhInstance`).
struct BvhInstance {
    // World now → base-pose world.
    from_now: mat4x4<f32>,
    // World bounds now.
    min: vec4<f32>,
    max: vec4<f32>,
    // Root node of its tree; 0xffffffff: casts no shadow.
    root: u32,
    // In the header (record 0) only: how many still instances there are (0: none) and the
    // root of their top-level tree.
    statics: u32,
    statics_root: u32,
    pad2: u32,
}

// 32 bytes. Inner node: children at `first` and `first + 1`, `count` = BVH_INNER.
// Leaf: triangles `first .. first + count`.
struct BvhNode {
    min: vec3<f32>,
    first: u32,
    max: vec3<f32>,
    count: u32,
}

// 48 bytes: a vertex and the two edges from it; `id` indexes the builder's input.
struct BvhTriangle {
    v0: vec3<f32>,
    id: u32,
    e1: vec3<f32>,
    pad0: u32,
    e2: vec3<f32>,
    pad1: u32,
}

// A hit at t in (RAY_T_MIN, t_max) (lib/ray.wgsl, the shared test).
fn bvh_triangle_hit(tri: BvhTriangle, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    return ray_triangle_hit(tri.v0, tri.e1, tri.e2, origin, dir, t_max);
}

// Entry distance into the node's box clipped to [0, t_max], or -1 for a miss.
fn bvh_box_entry(node: BvhNode, origin: vec3<f32>, inv_dir: vec3<f32>, t_max: f32) -> f32 {
    let t0 = (node.min - origin) * inv_dir;
    let t1 = (node.max - origin) * inv_dir;
    let lo = min(t0, t1);
    let hi = max(t0, t1);
    let near = max(max(max(lo.x, lo.y), lo.z), 0.0);
    let far = min(min(min(hi.x, hi.y), hi.z), t_max);
    return select(-1.0, near, near <= far);
}

fn bvh_leaf_hit(node: BvhNode, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    for (var i = node.first; i < node.first + node.count; i++) {
        if bvh_triangle_hit(bvh_triangles[i], origin, dir, t_max) {
            return true;
        }
    }
    return false;
}

// 112 bytes (crates/render/src/bvh/field.rs `GpuField`): a terrain's heights and the
// levels of its max-height quadtree in `bvh_field_data`.
struct BvhField {
    corner: vec3<f32>,
    levels: u32,
    inv_step: vec2<f32>,
    cells: vec2<u32>,
    heights_at: u32,
    // The terrain (index into the scene's terrains, as in an object's flags) it walks.
    terrain: u32,
    pad1: u32,
    pad2: u32,
    level_at: array<vec4<u32>, 4>,
}

struct BvhFields {
    count: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    fields: array<BvhField, BVH_MAX_FIELDS>,
}

// Float `i` of the fields' flat data.
fn field_load(i: u32) -> f32 {
    let w = FIELD_DATA_WIDTH;
    return textureLoad(bvh_field_data, vec2(i % w, (i / w) % w), i / (w * w), 0).r;
}

fn field_height(f: BvhField, x: u32, z: u32) -> f32 {
    return field_load(f.heights_at + z * (f.cells.x + 1u) + x);
}

// The field walking terrain `terrain`, or BVH_MAX_FIELDS if none does.
fn field_of_terrain(terrain: u32) -> u32 {
    for (var i = 0u; i < min(bvh_fields.count, BVH_MAX_FIELDS); i++) {
        if bvh_fields.fields[i].terrain == terrain {
            return i;
        }
    }
    return BVH_MAX_FIELDS;
}

// The world height of field `f`'s surface at world `xz` (clamped to its cells), on the
// triangles `field_cell_hit` crosses.
fn field_surface_y(f: BvhField, xz: vec2<f32>) -> f32 {
    let cells = vec2<f32>(f.cells);
    let g = clamp((xz - f.corner.xz) * f.inv_step, vec2(0.0), cells);
    let i = vec2<u32>(min(floor(g), cells - 1.0));
    let r = g - vec2<f32>(i);
    let h10 = field_height(f, i.x + 1u, i.y);
    let h01 = field_height(f, i.x, i.y + 1u);
    if r.x + r.y <= 1.0 {
        let h00 = field_height(f, i.x, i.y);
        return f.corner.y + h00 + r.x * (h10 - h00) + r.y * (h01 - h00);
    }
    let h11 = field_height(f, i.x + 1u, i.y + 1u);
    return f.corner.y + h11 + (1.0 - r.x) * (h01 - h11) + (1.0 - r.y) * (h10 - h11);
}

// Whether the ray (in the field's grid space) crosses cell (x, z)'s two triangles, split as
// the terrain mesh splits it.
fn field_cell_hit(f: BvhField, x: u32, z: u32, o: vec3<f32>, d: vec3<f32>, t_max: f32) -> bool {
    let fx = f32(x);
    let fz = f32(z);
    let a = vec3(fx, field_height(f, x, z), fz);
    let b = vec3(fx + 1.0, field_height(f, x + 1u, z), fz);
    let c = vec3(fx, field_height(f, x, z + 1u), fz + 1.0);
    let e = vec3(fx + 1.0, field_height(f, x + 1u, z + 1u), fz + 1.0);
    return bvh_triangle_hit(BvhTriangle(a, 0u, c - a, 0u, b - a, 0u), o, d, t_max)
        || bvh_triangle_hit(BvhTriangle(b, 0u, c - b, 0u, e - b, 0u), o, d, t_max);
}

// Whether the ray crosses field `f`'s surface at t in (RAY_T_MIN, t_max): the quadtree
// walked nearest child first (farthest first if `far_first`), a node skipped where the ray
// passes above its highest height (`HeightField::hit` on the CPU, step for step).
fn field_hit(f: BvhField, origin: vec3<f32>, dir: vec3<f32>, t_max: f32, far_first: bool) -> bool {
    let inv_step = vec3(f.inv_step.x, 1.0, f.inv_step.y);
    let o = (origin - f.corner) * inv_step;
    let d = dir * inv_step;
    let safe = select(d.xz, vec2<f32>(BVH_DIR_EPS), abs(d.xz) < vec2<f32>(BVH_DIR_EPS));
    let inv = 1.0 / safe;
    let nx = select(0u, 1u, (d.x < 0.0) != far_first);
    let nz = select(0u, 1u, (d.z < 0.0) != far_first);
    // Start: the part of the ray over the cells and below the highest height, and the
    // finest level whose nodes cover that part two by two at most (`HeightField::start`).
    let cells = vec2<f32>(f.cells);
    let s0 = (vec2(-FIELD_NODE_MARGIN) - o.xz) * inv;
    let s1 = (cells + FIELD_NODE_MARGIN - o.xz) * inv;
    var near = max(max(min(s0.x, s1.x), min(s0.y, s1.y)), 0.0);
    var far = min(min(max(s0.x, s1.x), max(s0.y, s1.y)), t_max);
    let highest = field_load(f.level_at[(f.levels - 1u) / 4u][(f.levels - 1u) % 4u]);
    let ceiling = highest + 1e-4 * (1.0 + abs(highest));
    if d.y > 0.0 {
        far = min(far, (ceiling - o.y) / d.y);
    } else if d.y < 0.0 {
        near = max(near, (ceiling - o.y) / d.y);
    } else if o.y > ceiling {
        return false;
    }
    if near > far {
        return false;
    }
    let a = o.xz + d.xz * near;
    let b = o.xz + d.xz * far;
    let last = cells - 1.0;
    let lo = vec2<u32>(clamp(floor(min(a, b) - FIELD_NODE_MARGIN), vec2(0.0), last));
    let hi = vec2<u32>(clamp(floor(max(a, b) + FIELD_NODE_MARGIN), vec2(0.0), last));
    var level = 0u;
    while level + 1u < f.levels && any((hi >> vec2(level)) - (lo >> vec2(level)) > vec2(1u)) {
        level += 1u;
    }
    var stack: array<u32, FIELD_STACK>;
    var sp = 0u;
    for (var j = lo.y >> level; j <= hi.y >> level; j++) {
        for (var i = lo.x >> level; i <= hi.x >> level; i++) {
            stack[sp] = (level << 28u) | (i << 14u) | j;
            sp += 1u;
        }
    }
    while sp > 0u {
        sp -= 1u;
        let key = stack[sp];
        let k = key >> 28u;
        let ij = vec2((key >> 14u) & 0x3fffu, key & 0x3fffu);
        let lo = vec2<f32>(ij << vec2(k)) - FIELD_NODE_MARGIN;
        let hi = vec2<f32>(min((ij + 1u) << vec2(k), f.cells)) + FIELD_NODE_MARGIN;
        let t0 = (lo - o.xz) * inv;
        let t1 = (hi - o.xz) * inv;
        let near = max(max(min(t0.x, t1.x), min(t0.y, t1.y)), 0.0);
        let far = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), t_max);
        if near > far {
            continue;
        }
        let y = min(o.y + d.y * near, o.y + d.y * far);
        let dims = (f.cells + (1u << k) - 1u) >> vec2(k);
        let top = field_load(f.level_at[k / 4u][k % 4u] + ij.y * dims.x + ij.x);
        if y > top + 1e-4 * (1.0 + abs(top)) {
            continue;
        }
        if k == 0u {
            if field_cell_hit(f, ij.x, ij.y, o, d, t_max) {
                return true;
            }
            continue;
        }
        let child = (f.cells + (1u << (k - 1u)) - 1u) >> vec2(k - 1u);
        // Farthest child first, so the nearest is taken next (or the other way round).
        for (var c = 0u; c < 4u; c++) {
            let a = select(1u - nx, nx, (c & 1u) != 0u);
            let b = select(1u - nz, nz, c >= 2u);
            let cij = 2u * ij + vec2(a, b);
            if cij.x < child.x && cij.y < child.y {
                if sp == FIELD_STACK {
                    return true;
                }
                stack[sp] = ((k - 1u) << 28u) | (cij.x << 14u) | cij.y;
                sp += 1u;
            }
        }
    }
    return false;
}

// Whether the ray `origin + t * dir` hits any triangle at t in (1e-4, t_max): the static
// scene's, a terrain's, or an animated object's where it is now. `dir` need not be unit length (t is in
// units of it); `t_max` must be finite (1e30 for "no limit").
fn bvh_any_hit(origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    return bvh_any_hit_from(origin, dir, t_max, false, BVH_STATICS_ALL);
}

// `bvh_any_hit`, the terrains walked from the ray's far end first when `far_first`: the
// same answer, found sooner for a ray that expects its hit near `t_max` (an edge ray
// toward a silhouette). The still instances are walked from node `statics` of their top
// level, which must hold every one the ray may meet (a point light's caster root,
// `gpu_scene/light_grid.rs`; an edge ray's texel's subtree, `bvh_statics_within`);
// BVH_STATICS_ALL: from its root; BVH_STATICS_NONE: not at all.
fn bvh_any_hit_from(origin: vec3<f32>, dir: vec3<f32>, t_max: f32, far_first: bool, statics: u32) -> bool {
    if bvh_tree_hit(0u, origin, dir, t_max) {
        return true;
    }
    for (var i = 0u; i < min(bvh_fields.count, BVH_MAX_FIELDS); i++) {
        if field_hit(bvh_fields.fields[i], origin, dir, t_max, far_first) {
            return true;
        }
    }
    // Record 0 is the header: its `root` is the top-level tree over the animated casters'
    // bounds now, its `statics_root` the one over the still objects sharing meshes.
    let header = bvh_instances[0];
    let statics_root = select(statics, header.statics_root, statics == BVH_STATICS_ALL);
    if header.statics != 0u && statics != BVH_STATICS_NONE && bvh_top_hit(statics_root, origin, dir, t_max) {
        return true;
    }
    return header.root != 0xffffffffu && bvh_top_hit(header.root, origin, dir, t_max);
}

// Whether box `a` meets the box `lo..hi` (NaN counts as meeting).
fn bvh_box_meets(a: BvhNode, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    return !(any(a.min > hi) || any(a.max < lo));
}

// Where rays that stay within the box `lo..hi` walk the still instances' top level
// (`bvh_any_hit_from`'s `statics`): from its root, down while only one child's box meets
// the box (a ray within it cannot enter the other, so the walk from the root would take the
// same way down, and go on from there step for step: the same answer); BVH_STATICS_NONE
// where no box meets it; BVH_STATICS_ALL for a box that is not a number.
fn bvh_statics_within(lo: vec3<f32>, hi: vec3<f32>) -> u32 {
    let header = bvh_instances[0];
    if header.statics == 0u || !all(lo <= hi) {
        return BVH_STATICS_ALL;
    }
    var at = header.statics_root;
    if !bvh_box_meets(bvh_nodes[at], lo, hi) {
        return BVH_STATICS_NONE;
    }
    // Deeper than the traversal's stack the builder makes no tree; stopping sooner is
    // only slower.
    for (var depth = 0u; depth < BVH_STACK_SIZE; depth++) {
        let node = bvh_nodes[at];
        if node.count != BVH_INNER {
            break;
        }
        let a = bvh_box_meets(bvh_nodes[node.first], lo, hi);
        let b = bvh_box_meets(bvh_nodes[node.first + 1u], lo, hi);
        if a == b {
            return select(BVH_STATICS_NONE, at, a);
        }
        at = select(node.first + 1u, node.first, a);
    }
    return at;
}

// Whether the ray hits instance `i`'s tree, carried into the object's base pose (an affine
// map keeps the ray's parameter: t means the same point in both poses).
fn bvh_instance_hit(i: u32, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    let inst = bvh_instances[i];
    let o = (inst.from_now * vec4(origin, 1.0)).xyz;
    let d = (inst.from_now * vec4(dir, 0.0)).xyz;
    return bvh_tree_hit(inst.root, o, d, t_max);
}

fn bvh_top_leaf_hit(node: BvhNode, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    for (var i = node.first; i < node.first + node.count; i++) {
        if bvh_instance_hit(i, origin, dir, t_max) {
            return true;
        }
    }
    return false;
}

// Where a walk down a tree goes next (`bvh_walk_next`).
const BVH_WALK_ON: u32 = 0u;
const BVH_WALK_MISSED: u32 = 1u;
const BVH_WALK_FULL: u32 = 2u;

// A walk down one tree, shared by `bvh_tree_hit` and `bvh_top_hit` (WGSL has no recursion,
// so the two walks, whose leaves differ, are two functions around these steps): the pairs
// of children still to visit and the pair at hand.
struct BvhWalk {
    stack: array<u32, BVH_STACK_SIZE>,
    sp: u32,
    pair: u32,
}

// The inverse of `dir` for the slab test, tiny components replaced (no 0 * inf).
fn bvh_inv_dir(dir: vec3<f32>) -> vec3<f32> {
    let safe = select(dir, vec3<f32>(BVH_DIR_EPS), abs(dir) < vec3<f32>(BVH_DIR_EPS));
    return 1.0 / safe;
}

// After the pair (`a`, `b`) whose boxes the ray enters at `ta` and `tb` (negative: missed,
// or a leaf already tested): descends into the nearer box and keeps the farther one for
// later, or takes the one entered, or the last one kept. BVH_WALK_MISSED when none is left;
// BVH_WALK_FULL when the stack would overflow (the ray counts as hit).
fn bvh_walk_next(w: ptr<function, BvhWalk>, a: BvhNode, b: BvhNode, ta: f32, tb: f32) -> u32 {
    if ta >= 0.0 && tb >= 0.0 {
        if (*w).sp == BVH_STACK_SIZE {
            return BVH_WALK_FULL;
        }
        // Descend into the nearer box, keep the farther one for later.
        let a_first = ta <= tb;
        (*w).stack[(*w).sp] = select(a.first, b.first, a_first);
        (*w).sp += 1u;
        (*w).pair = select(b.first, a.first, a_first);
    } else if ta >= 0.0 {
        (*w).pair = a.first;
    } else if tb >= 0.0 {
        (*w).pair = b.first;
    } else {
        if (*w).sp == 0u {
            return BVH_WALK_MISSED;
        }
        (*w).sp -= 1u;
        (*w).pair = (*w).stack[(*w).sp];
    }
    return BVH_WALK_ON;
}

// `bvh_tree_hit`'s walk over the top-level tree, whose leaves name instances.
fn bvh_top_hit(root_index: u32, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    let inv_dir = bvh_inv_dir(dir);
    let root = bvh_nodes[root_index];
    if bvh_box_entry(root, origin, inv_dir, t_max) < 0.0 {
        return false;
    }
    if root.count != BVH_INNER {
        return bvh_top_leaf_hit(root, origin, dir, t_max);
    }
    var w: BvhWalk;
    w.pair = root.first;
    let steps = arrayLength(&bvh_nodes);
    for (var step = 0u; step < steps; step++) {
        let a = bvh_nodes[w.pair];
        let b = bvh_nodes[w.pair + 1u];
        var ta = bvh_box_entry(a, origin, inv_dir, t_max);
        var tb = bvh_box_entry(b, origin, inv_dir, t_max);
        if ta >= 0.0 && a.count != BVH_INNER {
            if bvh_top_leaf_hit(a, origin, dir, t_max) {
                return true;
            }
            ta = -1.0;
        }
        if tb >= 0.0 && b.count != BVH_INNER {
            if bvh_top_leaf_hit(b, origin, dir, t_max) {
                return true;
            }
            tb = -1.0;
        }
        let next = bvh_walk_next(&w, a, b, ta, tb);
        if next != BVH_WALK_ON {
            return next == BVH_WALK_FULL;
        }
    }
    return true;
}

// Whether the ray hits a triangle of the tree whose root is node `root`.
fn bvh_tree_hit(root_index: u32, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    let inv_dir = bvh_inv_dir(dir);
    let root = bvh_nodes[root_index];
    if bvh_box_entry(root, origin, inv_dir, t_max) < 0.0 {
        return false;
    }
    if root.count != BVH_INNER {
        return bvh_leaf_hit(root, origin, dir, t_max);
    }
    var w: BvhWalk;
    w.pair = root.first;
    // Each pair of children is visited at most once: the bound only stops a corrupt tree.
    let steps = arrayLength(&bvh_nodes);
    for (var step = 0u; step < steps; step++) {
        let a = bvh_nodes[w.pair];
        let b = bvh_nodes[w.pair + 1u];
        var ta = bvh_box_entry(a, origin, inv_dir, t_max);
        var tb = bvh_box_entry(b, origin, inv_dir, t_max);
        if ta >= 0.0 && a.count != BVH_INNER {
            if bvh_leaf_hit(a, origin, dir, t_max) {
                return true;
            }
            ta = -1.0;
        }
        if tb >= 0.0 && b.count != BVH_INNER {
            if bvh_leaf_hit(b, origin, dir, t_max) {
                return true;
            }
            tb = -1.0;
        }
        let next = bvh_walk_next(&w, a, b, ta, tb);
        if next != BVH_WALK_ON {
            return next == BVH_WALK_FULL;
        }
    }
    return true;
}
