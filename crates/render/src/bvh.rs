//! A bounding volume hierarchy over the scene's triangles, for ray-traced shadows.
//!
//! The tree is built on the CPU with [obvhs](https://docs.rs/obvhs) (a PLOC binary BVH,
//! refined by SAH reinsertion and SAH leaf collapsing, up to [`MAX_LEAF_TRIANGLES`] per
//! leaf) and flattened into two storage buffers that `shaders/lib/bvh.wgsl` walks with
//! `bvh_any_hit`. [`any_hit_cpu`] is the same traversal on the CPU, step for step, so the
//! GPU answer can be checked against it and against [`any_hit_brute`].
//!
//! # GPU layout
//!
//! ```text
//! struct BvhNode {          // 32 bytes, align 16
//!     min: vec3<f32>,       //  0  box minimum (padded, see below)
//!     first: u32,           // 12  inner: index of the left child (right = first + 1)
//!                           //     leaf: index of its first triangle
//!     max: vec3<f32>,       // 16  box maximum (padded)
//!     count: u32,           // 28  leaf: triangle count (0 only in the empty tree)
//!                           //     inner: 0xffffffff (`INNER`)
//! }
//! struct BvhTriangle {      // 48 bytes, align 16
//!     v0: vec3<f32>,        //  0  first vertex
//!     id: u32,              // 12  index of the triangle in the slice given to `build_bvh`
//!     e1: vec3<f32>,        // 16  v1 - v0
//!     pad0: u32,            // 28
//!     e2: vec3<f32>,        // 32  v2 - v0
//!     pad1: u32,            // 44
//! }
//! ```
//!
//! Node 0 is the root; the two children of an inner node are adjacent, so one index names
//! both. A leaf's triangles are contiguous in the triangle buffer. The empty tree is a
//! single leaf with no triangles, so every ray misses it.
//!
//! # Guarantees
//!
//! - **Stack depth.** Subtrees deeper than [`STACK_SIZE`] levels are merged into one leaf
//!   while flattening, so inner nodes sit at depth ≤ `STACK_SIZE - 1` and the traversal
//!   stack (one entry per level at most) never holds more than `STACK_SIZE - 1` entries.
//!   Ordinary scenes stay far below it (measured: 10k, 100k and 1M random triangles give
//!   depths 15, 20 and 23); deeply nested geometry can reach it and then gets a few large
//!   leaves — slower, still exact. Should the stack overflow anyway, the ray is reported as
//!   hit, which can only darken, never leak light.
//! - **Boxes are conservative.** Every box is grown by `1e-5 × max(1, largest |coordinate|
//!   of the scene)`, far more than the rounding of the slab test, so the traversal never
//!   skips a triangle the ray hits: the answer is exactly "does any triangle's own test
//!   report a hit", whatever order the boxes are visited in. This assumes ray origins of
//!   the scene's magnitude (shadow rays start on surfaces).
//! - **Bad input.** Triangles with a NaN or infinite coordinate are left out.
//!
//! A hit is a triangle crossed at `t` in `(T_MIN, t_max)` along `origin + t * dir`
//! (Möller–Trumbore, both faces). `dir` need not be unit length (`t` is in units of
//! `dir`); `t_max` must be finite (WGSL may assume there are no infinities): use e.g. `1e30`
//! for a ray to a directional light.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::leaf_collapser::collapse;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::ploc::PlocBuilder;
use obvhs::triangle::Triangle;

pub mod field;
pub mod instances;
pub mod refit;

/// Entries of the traversal stack (`BVH_STACK_SIZE` in WGSL); also the depth at which the
/// builder merges deeper subtrees into a leaf.
pub const STACK_SIZE: usize = 32;
/// `BvhNode::count` of an inner node.
pub const INNER: u32 = u32::MAX;
/// Hits closer than this along the ray are ignored (self-shadowing of the surface the ray
/// starts on): the shared ray–triangle test's [`texel_geom::ray::RAY_T_MIN`].
pub const T_MIN: f32 = texel_geom::ray::RAY_T_MIN;
/// Most triangles the builder puts in one leaf (fewer where the SAH prefers).
pub const MAX_LEAF_TRIANGLES: u32 = 4;

/// Box growth relative to the scene's coordinate magnitude.
const BOX_PAD: f32 = 1e-5;
/// Direction components smaller than this are replaced by it before inverting, so the slab
/// test never computes `0 × ∞`.
const DIR_EPS: f32 = 1e-20;

/// A BVH node as the GPU reads it (see the module doc for the WGSL struct).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    /// Box minimum.
    pub min: [f32; 3],
    /// Inner node: index of the left child (the right one follows it). Leaf: first triangle.
    pub first: u32,
    /// Box maximum.
    pub max: [f32; 3],
    /// Leaf: number of triangles. Inner node: [`INNER`].
    pub count: u32,
}

impl BvhNode {
    /// Whether this node holds triangles rather than children.
    pub fn is_leaf(&self) -> bool {
        self.count != INNER
    }
}

/// A triangle as the GPU reads it: a vertex and two edges, ready for Möller–Trumbore.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct BvhTriangle {
    /// First vertex.
    pub v0: [f32; 3],
    /// Index of this triangle in the slice given to [`build_bvh`].
    pub id: u32,
    /// Second vertex minus the first.
    pub e1: [f32; 3],
    pad0: u32,
    /// Third vertex minus the first.
    pub e2: [f32; 3],
    pad1: u32,
}

const _: () = assert!(size_of::<BvhNode>() == 32 && size_of::<BvhTriangle>() == 48);

impl BvhTriangle {
    /// The triangle `[v0, v1, v2]`, remembered as `id`.
    pub fn new(id: u32, [v0, v1, v2]: &[Vec3; 3]) -> Self {
        BvhTriangle {
            v0: v0.to_array(),
            id,
            e1: (*v1 - *v0).to_array(),
            pad0: 0,
            e2: (*v2 - *v0).to_array(),
            pad1: 0,
        }
    }

    /// Whether the ray crosses this triangle at `t` in `(T_MIN, t_max)` (Möller–Trumbore,
    /// both faces: [`texel_geom::ray::ray_triangle`], the same operations as
    /// `ray_triangle_hit` in WGSL).
    pub fn hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        self.hit_at(origin, dir, t_max).is_some()
    }

    /// The `t` at which the ray crosses this triangle, if in `(T_MIN, t_max)` (see
    /// [`BvhTriangle::hit`]).
    pub fn hit_at(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<f32> {
        let (v0, e1, e2) = (self.v0.into(), self.e1.into(), self.e2.into());
        texel_geom::ray::ray_triangle(origin, dir, v0, e1, e2, t_max)
    }

    /// The geometric normal `e1 × e2` (not normalised): it points out of the side the
    /// triangle's vertices wind counter-clockwise around.
    pub fn normal(&self) -> Vec3 {
        Vec3::from(self.e1).cross(Vec3::from(self.e2))
    }
}

/// A flattened BVH, ready to upload (see the module doc for the layout).
#[derive(Clone, Debug, PartialEq)]
pub struct GpuBvh {
    /// Nodes; the root is node 0. Never empty.
    pub nodes: Vec<BvhNode>,
    /// Triangles in leaf order. Empty when the scene has no (finite) triangles.
    pub triangles: Vec<BvhTriangle>,
}

impl GpuBvh {
    /// The tree with no triangles: one empty leaf, which every ray misses.
    pub fn empty() -> Self {
        GpuBvh {
            nodes: vec![BvhNode {
                min: [0.0; 3],
                first: 0,
                max: [0.0; 3],
                count: 0,
            }],
            triangles: Vec::new(),
        }
    }

    /// Appends `other`'s tree after this one's (its node and triangle indices moved past
    /// ours) and returns the index of its root: a tree traversal started there sees only
    /// `other`'s triangles. How animated objects keep their own trees in the scene's buffers.
    pub fn append(&mut self, other: &GpuBvh) -> u32 {
        let (node_off, tri_off) = (self.nodes.len() as u32, self.triangles.len() as u32);
        self.nodes.extend(other.nodes.iter().map(|n| BvhNode {
            first: n.first + if n.is_leaf() { tri_off } else { node_off },
            ..*n
        }));
        self.triangles.extend_from_slice(&other.triangles);
        node_off
    }

    /// Levels below the root (0 for a lone leaf). Inner nodes are shallower than
    /// [`STACK_SIZE`], so this is at most `STACK_SIZE`.
    pub fn depth(&self) -> usize {
        let mut deepest = 0;
        let mut todo = vec![(0usize, 0usize)];
        while let Some((i, d)) = todo.pop() {
            deepest = deepest.max(d);
            let n = &self.nodes[i];
            if !n.is_leaf() {
                todo.push((n.first as usize, d + 1));
                todo.push((n.first as usize + 1, d + 1));
            }
        }
        deepest
    }

    /// Creates the storage buffers `bvh::nodes` and `bvh::triangles` (also `COPY_DST`, to
    /// be rewritten in place). An empty triangle list still gets one zeroed triangle, since
    /// wgpu rejects zero-sized bindings; no node refers to it.
    pub fn upload(&self, device: &wgpu::Device) -> (wgpu::Buffer, wgpu::Buffer) {
        use wgpu::util::DeviceExt;
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let nodes = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("bvh::nodes"),
            contents: bytemuck::cast_slice(&self.nodes),
            usage,
        });
        let dummy = [BvhTriangle::zeroed()];
        let tris: &[BvhTriangle] = if self.triangles.is_empty() {
            &dummy
        } else {
            &self.triangles
        };
        let triangles = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("bvh::triangles"),
            contents: bytemuck::cast_slice(tris),
            usage,
        });
        (nodes, triangles)
    }
}

/// A top-level tree over boxes (the animated objects' bounds where they are now), rebuilt
/// every frame: nodes in [`BvhNode`]'s layout with absolute child indices (the root is
/// `node_offset`, children pairs follow it), leaves naming at most two items as
/// `first_item + position` in the returned order. Each node splits where the surface area
/// heuristic prices it least ([`sah_split`]), or at the median of the centres along their
/// longest axis where that finds no split or the tree would grow too deep for the
/// traversal's stack; empty input: no nodes.
pub fn build_tlas(
    bounds: &[(Vec3, Vec3)],
    node_offset: u32,
    first_item: u32,
) -> (Vec<BvhNode>, Vec<u32>) {
    build_tlas_split(bounds, node_offset, first_item, true)
}

/// [`build_tlas`], at medians alone unless `sah` (the tests compare the two).
fn build_tlas_split(
    bounds: &[(Vec3, Vec3)],
    node_offset: u32,
    first_item: u32,
    sah: bool,
) -> (Vec<BvhNode>, Vec<u32>) {
    let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
    if bounds.is_empty() {
        return (Vec::new(), order);
    }
    let empty = BvhNode {
        min: [0.0; 3],
        first: 0,
        max: [0.0; 3],
        count: 0,
    };
    let mut nodes = vec![empty];
    // (node, items lo..hi, depth)
    let mut todo = vec![(0usize, 0usize, bounds.len(), 0usize)];
    while let Some((i, lo, hi, depth)) = todo.pop() {
        let items = &mut order[lo..hi];
        let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let (mut cmin, mut cmax) = (min, max);
        for &k in items.iter() {
            let (a, b) = bounds[k as usize];
            min = min.min(a);
            max = max.max(b);
            cmin = cmin.min(0.5 * (a + b));
            cmax = cmax.max(0.5 * (a + b));
        }
        if hi - lo <= 2 {
            nodes[i] = BvhNode {
                min: min.to_array(),
                first: first_item + lo as u32,
                max: max.to_array(),
                count: (hi - lo) as u32,
            };
            continue;
        }
        // Median splits below keep the subtree within the stack whatever its count.
        let median_depth = (hi - lo).ilog2() as usize + 1;
        let sah = (sah && depth + median_depth < STACK_SIZE - 2)
            .then(|| sah_split(bounds, items, cmin, cmax))
            .flatten();
        let mid = match sah {
            Some(left) => lo + left,
            None => {
                let extent = cmax - cmin;
                let axis = if extent.x >= extent.y && extent.x >= extent.z {
                    0
                } else if extent.y >= extent.z {
                    1
                } else {
                    2
                };
                let centre = |k: &u32| {
                    let (a, b) = bounds[*k as usize];
                    0.5 * (a[axis] + b[axis])
                };
                let mid = lo + (hi - lo) / 2;
                // The median alone (a sort per node made a top level over 100,000 objects
                // slow).
                items.select_nth_unstable_by(mid - lo, |x, y| centre(x).total_cmp(&centre(y)));
                mid
            }
        };
        let pair = nodes.len();
        nodes.push(empty);
        nodes.push(empty);
        nodes[i] = BvhNode {
            min: min.to_array(),
            first: node_offset + pair as u32,
            max: max.to_array(),
            count: INNER,
        };
        todo.push((pair, lo, mid, depth + 1));
        todo.push((pair + 1, mid, hi, depth + 1));
    }
    (nodes, order)
}

/// Bins of [`sah_split`] along each axis.
const SAH_BINS: usize = 16;

/// Splits `items` (indices into `bounds`, their centres within `cmin..cmax`) by the binned
/// surface area heuristic: of the planes between [`SAH_BINS`] bins of the centres along
/// each axis, the one whose two sides' box areas times their counts add up least. Puts the
/// left side first and returns its length, or `None` where every centre falls in one bin.
/// A shadow ray meets a box about in proportion to its area, so the two children a ray
/// must enter cost least this way: a town's top level over boxes from lamp posts to houses
/// split at medians had rays visiting about 14 nodes' pairs.
fn sah_split(bounds: &[(Vec3, Vec3)], items: &mut [u32], cmin: Vec3, cmax: Vec3) -> Option<usize> {
    let area = |lo: Vec3, hi: Vec3| {
        let d = (hi - lo).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    };
    let centre = |k: u32| {
        let (a, b) = bounds[k as usize];
        0.5 * (a + b)
    };
    let extent = cmax - cmin;
    let bin_of = |c: f32, axis: usize| {
        let b = ((c - cmin[axis]) / extent[axis] * SAH_BINS as f32) as usize;
        b.min(SAH_BINS - 1)
    };
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if extent[axis].is_nan() || extent[axis] <= 0.0 {
            continue;
        }
        let empty = (
            Vec3::splat(f32::INFINITY),
            Vec3::splat(f32::NEG_INFINITY),
            0usize,
        );
        let mut bins = [empty; SAH_BINS];
        for &k in items.iter() {
            let b = &mut bins[bin_of(centre(k)[axis], axis)];
            let (lo, hi) = bounds[k as usize];
            *b = (b.0.min(lo), b.1.max(hi), b.2 + 1);
        }
        // The right sides' areas and counts, then the left sides' swept against them.
        let mut right = [(0.0f32, 0usize); SAH_BINS];
        let mut acc = empty;
        for b in (1..SAH_BINS).rev() {
            acc = (
                acc.0.min(bins[b].0),
                acc.1.max(bins[b].1),
                acc.2 + bins[b].2,
            );
            right[b] = (area(acc.0, acc.1), acc.2);
        }
        let mut acc = empty;
        for b in 1..SAH_BINS {
            let l = bins[b - 1];
            acc = (acc.0.min(l.0), acc.1.max(l.1), acc.2 + l.2);
            let (ra, rn) = right[b];
            if acc.2 == 0 || rn == 0 {
                continue;
            }
            let cost = area(acc.0, acc.1) * acc.2 as f32 + ra * rn as f32;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, b));
            }
        }
    }
    let (_, axis, split) = best?;
    // Partition in place: the items of bins below `split` first.
    let mut left = 0;
    for i in 0..items.len() {
        if bin_of(centre(items[i])[axis], axis) < split {
            items.swap(i, left);
            left += 1;
        }
    }
    Some(left)
}

/// Builds the BVH of `triangles` (world-space vertices). Triangles with a NaN or infinite
/// coordinate are skipped; no input makes it panic.
pub fn build_bvh(triangles: &[[Vec3; 3]]) -> GpuBvh {
    build_with_depth_limit(triangles, STACK_SIZE)
}

/// [`build_bvh`] with subtrees below `depth_limit` merged into leaves (tests use small
/// limits to exercise the merge).
fn build_with_depth_limit(triangles: &[[Vec3; 3]], depth_limit: usize) -> GpuBvh {
    let kept: Vec<u32> = (0..triangles.len() as u32)
        .filter(|&i| triangles[i as usize].iter().all(|v| v.is_finite()))
        .collect();
    if kept.is_empty() {
        return GpuBvh::empty();
    }
    let tris: Vec<Triangle> = kept
        .iter()
        .map(|&i| {
            let [a, b, c] = triangles[i as usize];
            Triangle {
                v0: Vec3A::from(a),
                v1: Vec3A::from(b),
                v2: Vec3A::from(c),
            }
        })
        .collect();
    let tree = build_bvh2(&tris);
    flatten(&tree, triangles, &kept, depth_limit)
}

/// obvhs's `build_bvh2` (PLOC, reinsertion, SAH collapse, reinsertion) without its
/// debug-build validation pass.
fn build_bvh2(tris: &[Triangle]) -> Bvh2 {
    let params = BvhBuildParams {
        max_prims_per_leaf: MAX_LEAF_TRIANGLES,
        ..BvhBuildParams::medium_build()
    };
    let mut tree = PlocBuilder::with_capacity(tris.len()).build(
        params.ploc_search_distance,
        tris,
        (0..tris.len() as u32).collect(),
        params.sort_precision,
        params.search_depth_threshold,
    );
    let mut reinsertion = ReinsertionOptimizer::default();
    reinsertion.run(&mut tree, params.reinsertion_batch_ratio, None);
    collapse(
        &mut tree,
        params.max_prims_per_leaf,
        params.collapse_traversal_cost,
    );
    reinsertion.run(
        &mut tree,
        params.reinsertion_batch_ratio * params.post_collapse_reinsertion_batch_ratio_multiplier,
        None,
    );
    tree
}

/// Copies `tree` into the GPU layout, depth first, padding boxes and merging subtrees
/// below `depth_limit` into single leaves. `kept[k]` is the input index of obvhs
/// primitive `k`.
fn flatten(tree: &Bvh2, triangles: &[[Vec3; 3]], kept: &[u32], depth_limit: usize) -> GpuBvh {
    let root = tree.nodes[0].aabb();
    let magnitude = root.min.abs().max(root.max.abs()).max_element().max(1.0);
    let pad = Vec3A::splat(BOX_PAD * magnitude);

    let mut nodes = vec![BvhNode::zeroed()];
    let mut out = Vec::with_capacity(kept.len());
    // (obvhs node, output slot, depth)
    let mut todo = vec![(0usize, 0usize, 0usize)];
    while let Some((src, dst, depth)) = todo.pop() {
        let node = &tree.nodes[src];
        let (min, max) = (
            (node.aabb().min - pad).to_array(),
            (node.aabb().max + pad).to_array(),
        );
        if node.is_leaf() || depth >= depth_limit {
            let first = out.len() as u32;
            for_each_primitive(tree, src, |k| {
                let id = kept[k as usize];
                out.push(BvhTriangle::new(id, &triangles[id as usize]));
            });
            let count = out.len() as u32 - first;
            nodes[dst] = BvhNode {
                min,
                first,
                max,
                count,
            };
        } else {
            let left = nodes.len();
            nodes.extend([BvhNode::zeroed(); 2]);
            nodes[dst] = BvhNode {
                min,
                first: left as u32,
                max,
                count: INNER,
            };
            let child = node.first_index as usize;
            todo.push((child + 1, left + 1, depth + 1));
            todo.push((child, left, depth + 1));
        }
    }
    GpuBvh {
        nodes,
        triangles: out,
    }
}

/// Calls `f` with every obvhs primitive under node `start`.
fn for_each_primitive(tree: &Bvh2, start: usize, mut f: impl FnMut(u32)) {
    let mut todo = vec![start];
    while let Some(i) = todo.pop() {
        let node = &tree.nodes[i];
        if node.is_leaf() {
            let range = node.first_index as usize..(node.first_index + node.prim_count) as usize;
            tree.primitive_indices[range].iter().for_each(|&k| f(k));
        } else {
            let child = node.first_index as usize;
            todo.extend([child + 1, child]);
        }
    }
}

/// The ray's entry distance into `node`'s box, clipped to `[0, t_max]`, or `None` when it
/// misses (`bvh_box_entry` in WGSL, which returns -1 for a miss).
fn box_entry(node: &BvhNode, origin: Vec3, inv_dir: Vec3, t_max: f32) -> Option<f32> {
    let t0 = (Vec3::from(node.min) - origin) * inv_dir;
    let t1 = (Vec3::from(node.max) - origin) * inv_dir;
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element().min(t_max);
    (near <= far).then_some(near)
}

/// The inverse of `dir` for the slab test, tiny components replaced (`bvh_inv_dir`).
fn safe_inv_dir(dir: Vec3) -> Vec3 {
    let safe = Vec3::select(
        dir.abs().cmplt(Vec3::splat(DIR_EPS)),
        Vec3::splat(DIR_EPS),
        dir,
    );
    safe.recip()
}

/// Whether any triangle of leaf `node` is hit.
fn leaf_hit(bvh: &GpuBvh, node: &BvhNode, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
    let range = node.first as usize..(node.first + node.count) as usize;
    bvh.triangles[range]
        .iter()
        .any(|tri| tri.hit(origin, dir, t_max))
}

/// Whether the ray `origin + t * dir` hits a triangle at `t` in `(T_MIN, t_max)`: the
/// traversal of `bvh_any_hit` in `shaders/lib/bvh.wgsl`, on the CPU.
pub fn any_hit_cpu(bvh: &GpuBvh, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
    any_hit_cpu_from(bvh, 0, origin, dir, t_max)
}

/// [`any_hit_cpu`] in the tree whose root is node `root` (one [`GpuBvh::append`] returned).
pub fn any_hit_cpu_from(bvh: &GpuBvh, root: u32, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
    let inv_dir = safe_inv_dir(dir);
    let Some(root) = bvh.nodes.get(root as usize) else {
        return false;
    };
    if box_entry(root, origin, inv_dir, t_max).is_none() {
        return false;
    }
    if root.is_leaf() {
        return leaf_hit(bvh, root, origin, dir, t_max);
    }
    let mut stack = [0u32; STACK_SIZE];
    let mut sp = 0;
    let mut pair = root.first;
    // Each pair of children is visited at most once: the bound only stops a corrupt tree.
    for _ in 0..bvh.nodes.len() {
        let a = &bvh.nodes[pair as usize];
        let b = &bvh.nodes[pair as usize + 1];
        let mut ta = box_entry(a, origin, inv_dir, t_max);
        let mut tb = box_entry(b, origin, inv_dir, t_max);
        if ta.is_some() && a.is_leaf() {
            if leaf_hit(bvh, a, origin, dir, t_max) {
                return true;
            }
            ta = None;
        }
        if tb.is_some() && b.is_leaf() {
            if leaf_hit(bvh, b, origin, dir, t_max) {
                return true;
            }
            tb = None;
        }
        pair = match (ta, tb) {
            (Some(ta), Some(tb)) => {
                let (near, far) = if ta <= tb { (a, b) } else { (b, a) };
                if sp == STACK_SIZE {
                    return true; // cannot happen (see the module doc); err towards shadow
                }
                stack[sp] = far.first;
                sp += 1;
                near.first
            }
            (Some(_), None) => a.first,
            (None, Some(_)) => b.first,
            (None, None) => {
                if sp == 0 {
                    return false;
                }
                sp -= 1;
                stack[sp]
            }
        };
    }
    true
}

/// Every triangle whose bounding box meets the box `min..max`, as its three vertices (the
/// CPU's box query, e.g. for the flat faces near a probe).
pub fn triangles_in_box_cpu(bvh: &GpuBvh, min: Vec3, max: Vec3) -> Vec<[Vec3; 3]> {
    let overlaps = |lo: Vec3, hi: Vec3| lo.cmple(max).all() && hi.cmpge(min).all();
    let mut out = Vec::new();
    let mut todo = vec![0usize];
    while let Some(i) = todo.pop() {
        let Some(node) = bvh.nodes.get(i) else {
            continue;
        };
        if !overlaps(node.min.into(), node.max.into()) {
            continue;
        }
        if !node.is_leaf() {
            todo.extend([node.first as usize, node.first as usize + 1]);
            continue;
        }
        let range = node.first as usize..(node.first + node.count) as usize;
        for t in bvh.triangles.get(range).unwrap_or_default() {
            let a = Vec3::from(t.v0);
            let (b, c) = (a + Vec3::from(t.e1), a + Vec3::from(t.e2));
            if overlaps(a.min(b).min(c), a.max(b).max(c)) {
                out.push([a, b, c]);
            }
        }
    }
    out
}

/// The nearest triangle the ray `origin + t * dir` crosses at `t` in `(T_MIN, t_max)`, with
/// that `t` (the CPU's closest-hit query, e.g. for probe placement).
pub fn first_hit_cpu(
    bvh: &GpuBvh,
    origin: Vec3,
    dir: Vec3,
    t_max: f32,
) -> Option<(f32, &BvhTriangle)> {
    let safe = Vec3::select(
        dir.abs().cmplt(Vec3::splat(DIR_EPS)),
        Vec3::splat(DIR_EPS),
        dir,
    );
    let inv_dir = safe.recip();
    let mut best: Option<(f32, &BvhTriangle)> = None;
    let mut todo = vec![0u32];
    while let Some(i) = todo.pop() {
        let node = &bvh.nodes[i as usize];
        let reach = best.map_or(t_max, |(t, _)| t);
        if box_entry(node, origin, inv_dir, reach).is_none() {
            continue;
        }
        if node.is_leaf() {
            let range = node.first as usize..(node.first + node.count) as usize;
            for tri in &bvh.triangles[range] {
                let reach = best.map_or(t_max, |(t, _)| t);
                if let Some(t) = tri.hit_at(origin, dir, reach) {
                    best = Some((t, tri));
                }
            }
        } else if todo.len() < bvh.nodes.len() {
            todo.extend([node.first, node.first + 1]);
        }
    }
    best
}

/// The reference answer: tests every finite triangle of `triangles` with the same
/// ray/triangle test as the traversal.
pub fn any_hit_brute(triangles: &[[Vec3; 3]], origin: Vec3, dir: Vec3, t_max: f32) -> bool {
    triangles
        .iter()
        .filter(|t| t.iter().all(|v| v.is_finite()))
        .any(|t| BvhTriangle::new(0, t).hit(origin, dir, t_max))
}

#[cfg(test)]
mod tests;
