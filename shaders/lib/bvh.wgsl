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
// filled from `GpuBvh::upload` (buffers `bvh::nodes` and `bvh::triangles`) and
// `GpuScene::bvh_instances`. The static scene's tree has its root at node 0; each animated
// object's tree follows it, built in the object's base pose, and its instance record carries
// rays from where the object is now into that pose; last, a top-level tree over the casters'
// bounds now, rebuilt each frame, whose leaves name instance records (record 0 is a header
// holding the top-level root).

// Traversal stack entries. The builder merges subtrees deeper than this into leaves, so
// the stack cannot overflow; if it ever did, the ray counts as hit (shadowed).
const BVH_STACK_SIZE: u32 = 32u;
// `BvhNode::count` of an inner node.
const BVH_INNER: u32 = 0xffffffffu;
// Hits closer than this are ignored (the surface the ray starts on).
const BVH_T_MIN: f32 = 1e-4;
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
    pad0: u32,
    pad1: u32,
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

// Möller–Trumbore, both faces: a hit at t in (BVH_T_MIN, t_max).
fn bvh_triangle_hit(tri: BvhTriangle, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    let p = cross(dir, tri.e2);
    let det = dot(tri.e1, p);
    if det == 0.0 {
        return false;
    }
    let inv = 1.0 / det;
    let s = origin - tri.v0;
    let u = dot(s, p) * inv;
    if u < 0.0 || u > 1.0 {
        return false;
    }
    let q = cross(s, tri.e1);
    let v = dot(dir, q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = dot(tri.e2, q) * inv;
    return t > BVH_T_MIN && t < t_max;
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

// Whether the ray `origin + t * dir` hits any triangle at t in (1e-4, t_max): the static
// scene's or an animated object's where it is now. `dir` need not be unit length (t is in
// units of it); `t_max` must be finite (1e30 for "no limit").
fn bvh_any_hit(origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    if bvh_tree_hit(0u, origin, dir, t_max) {
        return true;
    }
    // Record 0 is the header: its `root` is the top-level tree over the casters' bounds.
    let top = bvh_instances[0].root;
    return top != 0xffffffffu && bvh_top_hit(top, origin, dir, t_max);
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

// `bvh_tree_hit`'s walk over the top-level tree, whose leaves name instances (WGSL has no
// recursion, so the walk is written twice rather than calling itself through a leaf).
fn bvh_top_hit(root_index: u32, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    let safe = select(dir, vec3<f32>(BVH_DIR_EPS), abs(dir) < vec3<f32>(BVH_DIR_EPS));
    let inv_dir = 1.0 / safe;
    let root = bvh_nodes[root_index];
    if bvh_box_entry(root, origin, inv_dir, t_max) < 0.0 {
        return false;
    }
    if root.count != BVH_INNER {
        return bvh_top_leaf_hit(root, origin, dir, t_max);
    }
    var stack: array<u32, BVH_STACK_SIZE>;
    var sp = 0u;
    var pair = root.first;
    let steps = arrayLength(&bvh_nodes);
    for (var step = 0u; step < steps; step++) {
        let a = bvh_nodes[pair];
        let b = bvh_nodes[pair + 1u];
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
        if ta >= 0.0 && tb >= 0.0 {
            if sp == BVH_STACK_SIZE {
                return true;
            }
            stack[sp] = select(a.first, b.first, ta <= tb);
            sp += 1u;
            pair = select(b.first, a.first, ta <= tb);
        } else if ta >= 0.0 {
            pair = a.first;
        } else if tb >= 0.0 {
            pair = b.first;
        } else {
            if sp == 0u {
                return false;
            }
            sp -= 1u;
            pair = stack[sp];
        }
    }
    return true;
}

// Whether the ray hits a triangle of the tree whose root is node `root`.
fn bvh_tree_hit(root_index: u32, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> bool {
    let safe = select(dir, vec3<f32>(BVH_DIR_EPS), abs(dir) < vec3<f32>(BVH_DIR_EPS));
    let inv_dir = 1.0 / safe;
    let root = bvh_nodes[root_index];
    if bvh_box_entry(root, origin, inv_dir, t_max) < 0.0 {
        return false;
    }
    if root.count != BVH_INNER {
        return bvh_leaf_hit(root, origin, dir, t_max);
    }
    var stack: array<u32, BVH_STACK_SIZE>;
    var sp = 0u;
    var pair = root.first;
    // Each pair of children is visited at most once: the bound only stops a corrupt tree.
    let steps = arrayLength(&bvh_nodes);
    for (var step = 0u; step < steps; step++) {
        let a = bvh_nodes[pair];
        let b = bvh_nodes[pair + 1u];
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
        if ta >= 0.0 && tb >= 0.0 {
            if sp == BVH_STACK_SIZE {
                return true;
            }
            // Descend into the nearer box, keep the farther one for later.
            let a_first = ta <= tb;
            stack[sp] = select(a.first, b.first, a_first);
            sp += 1u;
            pair = select(b.first, a.first, a_first);
        } else if ta >= 0.0 {
            pair = a.first;
        } else if tb >= 0.0 {
            pair = b.first;
        } else {
            if sp == 0u {
                return false;
            }
            sp -= 1u;
            pair = stack[sp];
        }
    }
    return true;
}
