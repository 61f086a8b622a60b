//! A bounding volume tree over the draw ranges' bounds, so that a face's cull visits the
//! ranges its frustum meets rather than every range of the scene (a town of 10,000 entities
//! has some 10,000; a stable face's frustum holds about a sixth of them, an eye face's near
//! part far fewer). Built once per scene, on the first cull ([`super::GpuScene::range_index`]);
//! an edit made in place refits it ([`RangeIndex::refit`]).
//!
//! It only rules ranges out: a subtree is skipped when its box lies wholly beyond one plane
//! of the face's clip volume (so does every box inside it), or, culling by footprint, when
//! none of its ranges could span a texel at the box's nearest point (the bound below
//! [`super::spans_a_texel`]'s, for any range inside it). The ranges left are then tested one
//! by one as without it, in buffer order, so a face draws exactly what it drew.

use glam::{Mat4, Vec3};

use super::ranges::{CaptureCull, DRAW_MIN_TEXELS, DrawRange, LodFrom, box_may_be_visible};

/// Most ranges in a leaf.
const LEAF: usize = 4;

/// A node: its box, the longest diagonal of a range under it, whether a terrain chunk lies
/// under it; a leaf's ranges (`order[first..first + count]`), or (`count` 0) its two
/// children at `first` and `first + 1`.
#[derive(Debug, Clone, Copy)]
struct Node {
    min: Vec3,
    max: Vec3,
    max_diagonal: f32,
    terrain: bool,
    first: u32,
    count: u32,
}

/// The tree over a scene's draw ranges.
#[derive(Debug, Clone, Default)]
pub struct RangeIndex {
    /// Parents before their children (node 0 the root, when there is one).
    nodes: Vec<Node>,
    /// Range indices, in leaf order.
    order: Vec<u32>,
}

impl RangeIndex {
    /// The tree over `ranges`: split at the median centre along the longest axis of the
    /// centres' bounds, down to leaves of [`LEAF`] ranges.
    pub fn build(ranges: &[DrawRange]) -> Self {
        let mut index = RangeIndex {
            nodes: Vec::new(),
            order: (0..ranges.len() as u32).collect(),
        };
        if !ranges.is_empty() {
            index.nodes.push(leaf(0, ranges.len()));
            let mut todo = vec![0usize];
            while let Some(at) = todo.pop() {
                let (first, count) = (
                    index.nodes[at].first as usize,
                    index.nodes[at].count as usize,
                );
                if count <= LEAF {
                    continue;
                }
                let items = &mut index.order[first..first + count];
                let centre = |i: &u32| {
                    let r = &ranges[*i as usize];
                    (r.min + r.max) * 0.5
                };
                let (lo, hi) = (items.iter())
                    .map(centre)
                    .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), c| {
                        (lo.min(c), hi.max(c))
                    });
                let extent = hi - lo;
                let axis = if extent.x >= extent.y && extent.x >= extent.z {
                    0
                } else if extent.y >= extent.z {
                    1
                } else {
                    2
                };
                let half = count / 2;
                items.select_nth_unstable_by(half, |a, b| {
                    (centre(a)[axis].total_cmp(&centre(b)[axis])).then(a.cmp(b))
                });
                let children = index.nodes.len();
                index.nodes.push(leaf(first, half));
                index.nodes.push(leaf(first + half, count - half));
                index.nodes[at].first = children as u32;
                index.nodes[at].count = 0;
                todo.extend([children, children + 1]);
            }
        }
        index.refit(ranges);
        index
    }

    /// Sets every node's box, longest diagonal and terrain flag from `ranges` (the same
    /// ranges as built, some of them moved by an edit).
    pub fn refit(&mut self, ranges: &[DrawRange]) {
        for at in (0..self.nodes.len()).rev() {
            let node = self.nodes[at];
            let (min, max, max_diagonal, terrain) = if node.count > 0 {
                let of = &self.order[node.first as usize..(node.first + node.count) as usize];
                of.iter().map(|&i| &ranges[i as usize]).fold(
                    (Vec3::INFINITY, Vec3::NEG_INFINITY, 0.0f32, false),
                    |(lo, hi, d, t), r| {
                        let diagonal = (r.max - r.min).length();
                        (
                            lo.min(r.min),
                            hi.max(r.max),
                            d.max(diagonal),
                            t || r.terrain,
                        )
                    },
                )
            } else {
                let [a, b] = [
                    self.nodes[node.first as usize],
                    self.nodes[node.first as usize + 1],
                ];
                (
                    a.min.min(b.min),
                    a.max.max(b.max),
                    a.max_diagonal.max(b.max_diagonal),
                    a.terrain || b.terrain,
                )
            };
            let n = &mut self.nodes[at];
            (n.min, n.max, n.max_diagonal, n.terrain) = (min, max, max_diagonal, terrain);
        }
    }

    /// The ranges `cull` may leave in a face of clip volume `view_proj` capturing for `lod`,
    /// by index, ascending: a superset of those it draws.
    pub fn candidates(&self, view_proj: &Mat4, lod: LodFrom, cull: CaptureCull) -> Vec<u32> {
        let mut out = Vec::new();
        let mut todo = if self.nodes.is_empty() {
            vec![]
        } else {
            vec![0usize]
        };
        while let Some(at) = todo.pop() {
            let node = &self.nodes[at];
            if cull != CaptureCull::Nothing && !box_may_be_visible(node.min, node.max, view_proj) {
                continue;
            }
            if cull == CaptureCull::Footprint && !node.terrain && !may_span_a_texel(node, lod) {
                continue;
            }
            if node.count > 0 {
                let (first, count) = (node.first as usize, node.count as usize);
                out.extend_from_slice(&self.order[first..first + count]);
            } else {
                todo.extend([node.first as usize, node.first as usize + 1]);
            }
        }
        out.sort_unstable();
        out
    }
}

/// A leaf over `order[first..first + count]`, its box set by [`RangeIndex::refit`].
fn leaf(first: usize, count: usize) -> Node {
    Node {
        min: Vec3::ZERO,
        max: Vec3::ZERO,
        max_diagonal: 0.0,
        terrain: false,
        first: first as u32,
        count: count as u32,
    }
}

/// Whether a range under `node` may span a texel for `lod` ([`super::spans_a_texel`]): a
/// range inside the box lies at least as far as the box's nearest point, and its texel there
/// is at least a third of `2d / n` (cos² ≥ 1/3), so below that bound (less a thousandth, for
/// rounding) none does.
fn may_span_a_texel(node: &Node, lod: LodFrom) -> bool {
    let least_texel = match lod {
        LodFrom::Full => return true,
        LodFrom::Texel(size) => size,
        LodFrom::Probe(origin, n) | LodFrom::Eye(origin, n) => {
            let d = (origin.clamp(node.min, node.max) - origin).length();
            2.0 * d / n as f32 / 3.0 * 0.999
        }
    };
    node.max_diagonal >= DRAW_MIN_TEXELS * least_texel
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu_scene::ranges::ranges_drawn_by;

    /// Ranges of every size scattered over a town-like square, a few terrain chunks among
    /// them, from a little deterministic generator.
    fn scattered(count: u32) -> Vec<DrawRange> {
        let mut seed = 0x9e37_79b9u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        };
        (0..count)
            .map(|i| {
                let at = Vec3::new(
                    next() * 400.0 - 200.0,
                    next() * 10.0,
                    next() * 400.0 - 200.0,
                );
                let size = Vec3::new(next(), next(), next()) * (0.02 + 6.0 * next() * next());
                DrawRange {
                    first: 3 * i,
                    count: 3,
                    min: at - size,
                    max: at + size,
                    lod: 0,
                    max_lod: 0,
                    spacing: 0.0,
                    terrain: i % 97 == 0,
                    instance: i % 3,
                }
            })
            .collect()
    }

    /// Cube-face frusta from a few origins, looking six ways, and a narrow camera's.
    fn frusta() -> Vec<(Vec3, Mat4)> {
        use texel_probes::cube::{Face, face_view_projection};
        let origins = [
            Vec3::new(0.0, 1.6, 0.0),
            Vec3::new(120.0, 3.0, -80.0),
            Vec3::new(-199.0, 0.5, 199.0),
        ];
        let mut out = Vec::new();
        for o in origins {
            for face in Face::ALL {
                out.push((o, face_view_projection(o, face, 0.05, 500.0)));
            }
            let mut camera = crate::input::Camera::looking(o, Vec3::new(0.3, -0.1, -1.0));
            (camera.fov_y, camera.far) = (20f32.to_radians(), 64.0);
            out.push((o, camera.projection(1.5) * camera.view()));
        }
        out
    }

    #[test]
    fn a_face_culled_through_the_index_draws_what_it_draws_without() {
        let ranges = scattered(3000);
        let index = RangeIndex::build(&ranges);
        let all = |_: &DrawRange| true;
        let mut visited = 0;
        for (origin, view_proj) in frusta() {
            for lod in [
                LodFrom::Probe(origin, 128),
                LodFrom::Eye(origin, 32),
                LodFrom::Texel(0.3),
                LodFrom::Full,
            ] {
                for cull in [
                    CaptureCull::Nothing,
                    CaptureCull::Frustum,
                    CaptureCull::Footprint,
                ] {
                    let plain = ranges_drawn_by(&ranges, None, &view_proj, lod, cull, &all);
                    let indexed =
                        ranges_drawn_by(&ranges, Some(&index), &view_proj, lod, cull, &all);
                    assert_eq!(plain, indexed, "{lod:?} {cull:?} from {origin}");
                    if cull == CaptureCull::Footprint {
                        visited += index.candidates(&view_proj, lod, cull).len();
                    }
                }
            }
        }
        // And it visits fewer: not every range of every face.
        assert!(
            visited < frusta().len() * 4 * ranges.len() / 3,
            "visited {visited}"
        );
    }

    #[test]
    fn a_refit_index_follows_moved_ranges() {
        let mut ranges = scattered(500);
        let mut index = RangeIndex::build(&ranges);
        // Everything moves far off, then half of it comes back elsewhere.
        for (i, r) in ranges.iter_mut().enumerate() {
            let by = if i % 2 == 0 {
                Vec3::new(-300.0, 0.0, 250.0)
            } else {
                Vec3::splat(5000.0)
            };
            r.min += by;
            r.max += by;
        }
        index.refit(&ranges);
        let all = |_: &DrawRange| true;
        for (origin, view_proj) in frusta() {
            let lod = LodFrom::Probe(origin, 64);
            let cull = CaptureCull::Footprint;
            let plain = ranges_drawn_by(&ranges, None, &view_proj, lod, cull, &all);
            let indexed = ranges_drawn_by(&ranges, Some(&index), &view_proj, lod, cull, &all);
            assert_eq!(plain, indexed, "from {origin}");
        }
        assert!(
            RangeIndex::build(&[])
                .candidates(&Mat4::IDENTITY, LodFrom::Full, CaptureCull::Nothing)
                .is_empty()
        );
    }
}
