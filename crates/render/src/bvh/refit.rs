//! Refitting a built tree after some of its triangles moved (an editor edit, a level file
//! changed on disk): the moved triangles are rewritten where they lie and only the boxes on
//! the path from their leaves to the root are grown or shrunk again. The topology stays, so
//! a refit tree answers every any-hit query exactly as a rebuilt one does (the traversal is
//! exact whatever the boxes, see the module doc of [`crate::bvh`]); only its speed can
//! drift when things move far.

use glam::Vec3;

use super::{BOX_PAD, BvhNode, BvhTriangle, GpuBvh};

/// Where each input triangle of one tree lies and which node is each node's parent: what a
/// refit needs, found once in O(tree).
#[derive(Debug, Clone, Default)]
pub struct RefitIndex {
    /// Position in `GpuBvh::triangles` of each input triangle (`u32::MAX`: left out, it
    /// had a coordinate that is not finite).
    position: Vec<u32>,
    /// The leaf holding each position of `GpuBvh::triangles` (of this tree).
    leaf: Vec<u32>,
    /// Each node's parent (`u32::MAX` for the root and for nodes of other trees).
    parent: Vec<u32>,
    /// The box padding the tree was built with.
    pad: f32,
}

/// What a refit changed, to write to the GPU copy: indices of triangles and nodes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Refitted {
    /// Positions in `GpuBvh::triangles` rewritten, ascending.
    pub triangles: Vec<u32>,
    /// Nodes whose boxes were recomputed, ascending.
    pub nodes: Vec<u32>,
}

impl RefitIndex {
    /// The index of the tree rooted at node 0 of `bvh`, built from `inputs` triangles (trees
    /// appended after it are not indexed).
    pub fn new(bvh: &GpuBvh, inputs: usize) -> Self {
        let mut index = RefitIndex {
            position: vec![u32::MAX; inputs],
            leaf: vec![u32::MAX; bvh.triangles.len()],
            parent: vec![u32::MAX; bvh.nodes.len()],
            pad: 0.0,
        };
        let root = bvh.nodes[0];
        let magnitude = Vec3::from(root.min)
            .abs()
            .max(Vec3::from(root.max).abs())
            .max_element()
            .max(1.0);
        index.pad = BOX_PAD * magnitude;
        let mut todo = vec![0u32];
        while let Some(n) = todo.pop() {
            let node = bvh.nodes[n as usize];
            if node.is_leaf() {
                for p in node.first..node.first + node.count {
                    let id = bvh.triangles[p as usize].id as usize;
                    if let Some(slot) = index.position.get_mut(id) {
                        *slot = p;
                    }
                    index.leaf[p as usize] = n;
                }
            } else {
                for child in [node.first, node.first + 1] {
                    index.parent[child as usize] = n;
                    todo.push(child);
                }
            }
        }
        index
    }

    /// Where input triangle `id` lies in `GpuBvh::triangles` (`None`: not in the tree).
    pub fn position(&self, id: u32) -> Option<u32> {
        (self.position.get(id as usize).copied()).filter(|&p| p != u32::MAX)
    }

    /// Rewrites the input triangles `moved` (`(input index, world vertices)`) in `bvh` and
    /// refits the boxes above them. `None`, with `bvh` untouched, when a triangle is not in
    /// the tree (it was left out, or the index is past the input) or a new one is not
    /// finite: the tree must be built again.
    pub fn refit(&self, bvh: &mut GpuBvh, moved: &[(u32, [Vec3; 3])]) -> Option<Refitted> {
        let mut positions = Vec::with_capacity(moved.len());
        for (id, tri) in moved {
            let p = *self.position.get(*id as usize)?;
            if p == u32::MAX || !tri.iter().all(|v| v.is_finite()) {
                return None;
            }
            positions.push(p);
        }
        let mut leaves: Vec<u32> = Vec::new();
        for ((id, tri), &p) in moved.iter().zip(&positions) {
            bvh.triangles[p as usize] = BvhTriangle::new(*id, tri);
            leaves.push(self.leaf[p as usize]);
        }
        // A new coordinate beyond the tree's magnitude widens the padding, as a build would.
        let magnitude = (moved.iter())
            .flat_map(|(_, t)| t.iter())
            .fold(0.0f32, |m, v| m.max(v.abs().max_element()));
        let pad = self.pad.max(BOX_PAD * magnitude);
        leaves.sort_unstable();
        leaves.dedup();
        let mut nodes: Vec<u32> = Vec::new();
        for &leaf in &leaves {
            let node = &mut bvh.nodes[leaf as usize];
            let (lo, hi) = leaf_bounds(&bvh.triangles, node);
            node.min = (lo - pad).to_array();
            node.max = (hi + pad).to_array();
            nodes.push(leaf);
        }
        for &leaf in &leaves {
            let mut n = self.parent[leaf as usize];
            while n != u32::MAX {
                let first = bvh.nodes[n as usize].first as usize;
                let (a, b) = (bvh.nodes[first], bvh.nodes[first + 1]);
                let node = &mut bvh.nodes[n as usize];
                node.min = Vec3::from(a.min).min(Vec3::from(b.min)).to_array();
                node.max = Vec3::from(a.max).max(Vec3::from(b.max)).to_array();
                nodes.push(n);
                n = self.parent[n as usize];
            }
        }
        nodes.sort_unstable();
        nodes.dedup();
        positions.sort_unstable();
        positions.dedup();
        Some(Refitted {
            triangles: positions,
            nodes,
        })
    }
}

/// The bounds of leaf `node`'s triangles (unpadded).
fn leaf_bounds(triangles: &[BvhTriangle], node: &BvhNode) -> (Vec3, Vec3) {
    let range = node.first as usize..(node.first + node.count) as usize;
    triangles[range].iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), t| {
            let v0 = Vec3::from(t.v0);
            let (v1, v2) = (v0 + Vec3::from(t.e1), v0 + Vec3::from(t.e2));
            (lo.min(v0).min(v1).min(v2), hi.max(v0).max(v1).max(v2))
        },
    )
}

/// Runs of consecutive indices in `sorted` as `(first, count)`: one GPU write each.
pub fn runs(sorted: &[u32]) -> Vec<(u32, u32)> {
    let mut out: Vec<(u32, u32)> = Vec::new();
    for &i in sorted {
        match out.last_mut() {
            Some((first, count)) if *first + *count == i => *count += 1,
            _ => out.push((i, 1)),
        }
    }
    out
}

impl GpuBvh {
    /// Writes the triangles and nodes `refitted` names from this tree into its GPU copy
    /// (`nodes`, `triangles`: what [`GpuBvh::upload`] made), one write per run of adjacent
    /// records.
    pub fn write_refitted(
        &self,
        queue: &wgpu::Queue,
        refitted: &Refitted,
        nodes: &wgpu::Buffer,
        triangles: &wgpu::Buffer,
    ) {
        for (first, count) in runs(&refitted.triangles) {
            let records = &self.triangles[first as usize..(first + count) as usize];
            let offset = u64::from(first) * size_of::<BvhTriangle>() as u64;
            queue.write_buffer(triangles, offset, bytemuck::cast_slice(records));
        }
        for (first, count) in runs(&refitted.nodes) {
            let records = &self.nodes[first as usize..(first + count) as usize];
            let offset = u64::from(first) * size_of::<BvhNode>() as u64;
            queue.write_buffer(nodes, offset, bytemuck::cast_slice(records));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{any_hit_brute, any_hit_cpu, build_bvh};

    fn grid(n: usize) -> Vec<[Vec3; 3]> {
        (0..n)
            .map(|i| {
                let o = Vec3::new((i % 10) as f32, (i / 10) as f32 * 0.5, (i % 7) as f32);
                [o, o + Vec3::X, o + Vec3::Y]
            })
            .collect()
    }

    /// A refit tree answers every ray as a brute-force test over the moved triangles does.
    #[test]
    fn a_refit_tree_answers_as_the_moved_triangles_do() {
        let mut tris = grid(200);
        let mut bvh = build_bvh(&tris);
        let index = RefitIndex::new(&bvh, tris.len());
        let moved: Vec<(u32, [Vec3; 3])> = (40..60u32)
            .map(|i| {
                let t = tris[i as usize].map(|v| v + Vec3::new(30.0, -4.0, 2.5));
                (i, t)
            })
            .collect();
        for (i, t) in &moved {
            tris[*i as usize] = *t;
        }
        let refitted = index
            .refit(&mut bvh, &moved)
            .expect("every triangle is in the tree");
        assert!(!refitted.nodes.is_empty() && refitted.nodes[0] == 0);
        assert_eq!(refitted.triangles.len(), 20);
        for k in 0..400 {
            let origin = Vec3::new(
                (k % 20) as f32 * 2.0 - 5.0,
                (k / 20) as f32 * 0.7 - 6.0,
                -10.0,
            );
            let dir = Vec3::new(0.3, 0.05 * (k % 5) as f32, 1.0);
            assert_eq!(
                any_hit_cpu(&bvh, origin, dir, 100.0),
                any_hit_brute(&tris, origin, dir, 100.0),
                "ray {k}"
            );
        }
    }

    /// A triangle that is not in the tree, or a new one that is not finite, asks for a build.
    #[test]
    fn a_triangle_outside_the_tree_asks_for_a_build() {
        let tris = grid(10);
        let mut bvh = build_bvh(&tris);
        let index = RefitIndex::new(&bvh, tris.len());
        assert!(index.refit(&mut bvh, &[(10, tris[0])]).is_none());
        let nan = [Vec3::NAN, Vec3::ZERO, Vec3::X];
        assert!(index.refit(&mut bvh, &[(3, nan)]).is_none());
        assert_eq!(bvh, build_bvh(&tris));
        assert_eq!(runs(&[1, 2, 3, 7, 9, 10]), vec![(1, 3), (7, 1), (9, 2)]);
    }
}
