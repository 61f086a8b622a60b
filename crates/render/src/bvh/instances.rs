//! Two-level shadow trees: a top-level tree over instances, each a record
//! ([`GpuBvhInstance`]: world → object, world bounds, the root of its mesh's tree), and one
//! bottom-level tree per mesh, built once in object space and appended to the scene's
//! trees ([`GpuBvh::append`]). A ray meeting an instance's box is carried into object space
//! by the record's inverse transform (an affine map keeps the ray parameter, so `t` and
//! `t_max` mean the same points, whatever the map's scales). Still objects casting through a
//! shared shape (`gpu_scene/shapes.rs`: boxes of every size, say, placed by their transforms
//! times their sizes) are such instances, built at upload and refit when one moves
//! ([`TopLevel::refit`]); animated casters are too, under a
//! top level rebuilt each frame (`GpuScene::set_poses`). `bvh_top_hit` in
//! `shaders/lib/bvh.wgsl` is [`any_hit_instances_cpu`] on the GPU.

use glam::{Mat4, Vec3};

use super::{BvhNode, GpuBvh, INNER, any_hit_cpu_from, box_entry, build_tlas, safe_inv_dir};
use crate::gpu_scene::{GpuBvhInstance, transform_bounds};

/// Box growth of an instance's world bounds, relative to their coordinates' magnitude (the
/// trees' own `BOX_PAD`): the transformed box of a padded object-space box, grown again so
/// its rounding cannot lose a hit.
const INSTANCE_PAD: f32 = 1e-5;

/// The record of an instance placed by `model` whose mesh's tree has its root `root` in
/// `bvh` (its root box, transformed and padded, bounds it).
pub fn instance_record(bvh: &GpuBvh, root: u32, model: Mat4) -> GpuBvhInstance {
    let node = &bvh.nodes[root as usize];
    let (min, max) = transform_bounds(model, node.min.into(), node.max.into());
    let pad = Vec3::splat(INSTANCE_PAD * min.abs().max(max.abs()).max_element().max(1.0));
    GpuBvhInstance {
        from_now: model.inverse().to_cols_array_2d(),
        min: (min - pad).extend(0.0).to_array(),
        max: (max + pad).extend(0.0).to_array(),
        root,
        _pad: [0; 3],
    }
}

/// A top-level tree over instance records, kept on the CPU to be refit.
#[derive(Debug, Clone)]
pub struct TopLevel {
    /// Where its nodes start in the scene's node buffer (its root).
    pub node_offset: u32,
    /// Its nodes (child and record indices absolute).
    pub nodes: Vec<BvhNode>,
    /// The input index of the record at each position (records `first_item + position`).
    pub order: Vec<u32>,
    /// The record index of the first position.
    pub first_item: u32,
    /// Each node's parent (local index; the root's is `u32::MAX`).
    parent: Vec<u32>,
    /// The leaf (local index) holding each position.
    leaf: Vec<u32>,
}

impl TopLevel {
    /// The tree over `bounds` (one per input record), its root at `node_offset`, its
    /// records from `first_item` on. `None` without input.
    pub fn build(bounds: &[(Vec3, Vec3)], node_offset: u32, first_item: u32) -> Option<Self> {
        let (nodes, order) = build_tlas(bounds, node_offset, first_item);
        if nodes.is_empty() {
            return None;
        }
        let mut parent = vec![u32::MAX; nodes.len()];
        let mut leaf = vec![0; order.len()];
        for (i, n) in nodes.iter().enumerate() {
            if n.count == INNER {
                let c = (n.first - node_offset) as usize;
                parent[c] = i as u32;
                parent[c + 1] = i as u32;
            } else {
                for p in n.first..n.first + n.count {
                    leaf[(p - first_item) as usize] = i as u32;
                }
            }
        }
        Some(TopLevel {
            node_offset,
            nodes,
            order,
            first_item,
            parent,
            leaf,
        })
    }

    /// At most `most` nodes (absolute indices) whose subtrees together hold every record
    /// whose box may meet the ball around `centre` of `radius` (a ray within the ball can
    /// meet no other record's triangles): from the root, a node is replaced by the children
    /// whose boxes meet the ball while that keeps to `most`; none where no box meets it.
    pub fn ball_cut(&self, centre: Vec3, radius: f32, most: usize) -> Vec<u32> {
        let meets = |i: usize| {
            let n = &self.nodes[i];
            let nearest = centre.max(Vec3::from(n.min)).min(Vec3::from(n.max));
            let d = nearest.distance_squared(centre);
            // NaN bounds or centre: met, so the answer stays the whole tree's.
            d.is_nan() || d <= radius * radius
        };
        let mut cut: Vec<usize> = if meets(0) { vec![0] } else { Vec::new() };
        let mut k = 0;
        while k < cut.len() {
            let n = self.nodes[cut[k]];
            if n.count != INNER {
                k += 1;
                continue;
            }
            let c = (n.first - self.node_offset) as usize;
            let children: Vec<usize> = [c, c + 1].into_iter().filter(|&i| meets(i)).collect();
            if children.len() == 2 && cut.len() + 1 > most {
                k += 1;
                continue;
            }
            // Replaced by its children that meet the ball, which are looked at next.
            cut.splice(k..=k, children);
        }
        cut.into_iter()
            .map(|i| self.node_offset + i as u32)
            .collect()
    }

    /// Gives the record at `position` the bounds `min..max` and refits the boxes above it;
    /// returns the local indices of the nodes it changed (leaf first, root last).
    pub fn refit(&mut self, records: &[GpuBvhInstance], position: usize) -> Vec<u32> {
        let mut changed = Vec::new();
        let mut i = self.leaf[position];
        while i != u32::MAX {
            let n = self.nodes[i as usize];
            let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            if n.count == INNER {
                let c = (n.first - self.node_offset) as usize;
                for k in [c, c + 1] {
                    lo = lo.min(self.nodes[k].min.into());
                    hi = hi.max(self.nodes[k].max.into());
                }
            } else {
                for r in &records[n.first as usize..(n.first + n.count) as usize] {
                    lo = lo.min(Vec3::from_slice(&r.min[..3]));
                    hi = hi.max(Vec3::from_slice(&r.max[..3]));
                }
            }
            let node = &mut self.nodes[i as usize];
            (node.min, node.max) = (lo.to_array(), hi.to_array());
            changed.push(i);
            i = self.parent[i as usize];
        }
        changed
    }
}

/// Whether the ray hits an instance under the top-level tree whose root is node `top` of
/// `bvh` (leaves naming `records`): `bvh_top_hit` on the CPU.
pub fn any_hit_instances_cpu(
    bvh: &GpuBvh,
    records: &[GpuBvhInstance],
    top: u32,
    origin: Vec3,
    dir: Vec3,
    t_max: f32,
) -> bool {
    let inv_dir = safe_inv_dir(dir);
    let mut todo = vec![top];
    while let Some(i) = todo.pop() {
        let Some(node) = bvh.nodes.get(i as usize) else {
            continue;
        };
        if box_entry(node, origin, inv_dir, t_max).is_none() {
            continue;
        }
        if node.is_leaf() {
            for r in &records[node.first as usize..(node.first + node.count) as usize] {
                if r.root == u32::MAX {
                    continue;
                }
                let m = Mat4::from_cols_array_2d(&r.from_now);
                let (o, d) = (m.transform_point3(origin), m.transform_vector3(dir));
                if any_hit_cpu_from(bvh, r.root, o, d, t_max) {
                    return true;
                }
            }
        } else if todo.len() < bvh.nodes.len() {
            todo.extend([node.first, node.first + 1]);
        }
    }
    false
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::bvh::tests::Rng;
    use crate::bvh::{any_hit_cpu, build_bvh};
    use glam::Quat;

    /// A top level over `records`' boxes, its nodes appended to `bvh`'s; and the records in
    /// its order.
    pub(crate) fn top_over(
        bvh: &mut GpuBvh,
        records: &[GpuBvhInstance],
    ) -> (TopLevel, Vec<GpuBvhInstance>) {
        let bounds: Vec<(Vec3, Vec3)> = (records.iter())
            .map(|r| (Vec3::from_slice(&r.min[..3]), Vec3::from_slice(&r.max[..3])))
            .collect();
        let top = TopLevel::build(&bounds, bvh.nodes.len() as u32, 0).unwrap();
        bvh.nodes.extend_from_slice(&top.nodes);
        let placed = top.order.iter().map(|&k| records[k as usize]).collect();
        (top, placed)
    }

    /// A lumpy closed-ish mesh: a ring of quads around the Y axis with a wobble.
    fn mesh() -> Vec<[Vec3; 3]> {
        let n = 10;
        let p = |i: u32, y: f32| {
            let a = i as f32 / n as f32 * std::f32::consts::TAU;
            let r = 0.6 + 0.2 * (3.0 * a).sin() + 0.1 * y;
            Vec3::new(r * a.cos(), y, r * a.sin())
        };
        (0..n)
            .flat_map(|i| {
                let (a, b, c, d) = (p(i, -0.5), p(i + 1, -0.5), p(i, 0.7), p(i + 1, 0.7));
                [[a, b, c], [b, d, c], [c, d, Vec3::new(0.0, 0.9, 0.0)]]
            })
            .collect()
    }

    /// Random similarities: turned, some mirrored or scaled, spread over a 16-unit box.
    fn placements(rng: &mut Rng, n: usize) -> Vec<Mat4> {
        (0..n)
            .map(|i| {
                let q = Quat::from_euler(
                    glam::EulerRot::YXZ,
                    rng.next() * 6.3,
                    rng.next() - 0.5,
                    rng.next() - 0.5,
                );
                let s = 0.5 + 1.5 * rng.next();
                let mirror = if i % 5 == 0 { -1.0 } else { 1.0 };
                let at = Vec3::new(rng.next(), rng.next() * 0.3, rng.next()) * 16.0;
                Mat4::from_scale_rotation_translation(Vec3::new(mirror * s, s, s), q, at)
            })
            .collect()
    }

    /// The two levels over `models` and `tris`: the scene's trees and records.
    fn two_level(tris: &[[Vec3; 3]], models: &[Mat4]) -> (GpuBvh, Vec<GpuBvhInstance>, TopLevel) {
        let mut bvh = GpuBvh::empty();
        let root = bvh.append(&build_bvh(tris));
        let records: Vec<GpuBvhInstance> = models
            .iter()
            .map(|&m| instance_record(&bvh, root, m))
            .collect();
        let bounds: Vec<(Vec3, Vec3)> = (records.iter())
            .map(|r| (Vec3::from_slice(&r.min[..3]), Vec3::from_slice(&r.max[..3])))
            .collect();
        let top = TopLevel::build(&bounds, bvh.nodes.len() as u32, 0).unwrap();
        bvh.nodes.extend_from_slice(&top.nodes);
        let placed = top.order.iter().map(|&k| records[k as usize]).collect();
        (bvh, placed, top)
    }

    /// Every copy's triangles in world space, as the flat tree holds them.
    fn flat(tris: &[[Vec3; 3]], models: &[Mat4]) -> GpuBvh {
        let world: Vec<[Vec3; 3]> = (models.iter())
            .flat_map(|m| tris.iter().map(move |t| t.map(|v| m.transform_point3(v))))
            .collect();
        build_bvh(&world)
    }

    /// Over `rays`: how many the flat tree answers as hit, and on how many the two levels
    /// (`records` under the top level at `offset` in `bvh`) answer otherwise.
    fn agreement(
        (bvh, records, offset): (&GpuBvh, &[GpuBvhInstance], u32),
        flat: &GpuBvh,
        rays: &[(Vec3, Vec3, f32)],
    ) -> (usize, usize) {
        let (mut hits, mut differ) = (0, 0);
        for &(o, d, t_max) in rays {
            let a = any_hit_instances_cpu(bvh, records, offset, o, d, t_max);
            let b = any_hit_cpu(flat, o, d, t_max);
            hits += usize::from(b);
            differ += usize::from(a != b);
        }
        (hits, differ)
    }

    /// Random rays through the scene's box: some reach a light far away, some stop short.
    fn rays(rng: &mut Rng, n: usize) -> Vec<(Vec3, Vec3, f32)> {
        (0..n)
            .map(|i| {
                let o = Vec3::new(rng.next(), rng.next() * 0.3, rng.next()) * 18.0 - 1.0;
                let d = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
                let t_max = if i % 3 == 0 {
                    1e30
                } else {
                    2.0 + 10.0 * rng.next()
                };
                (o, d.normalize_or(Vec3::Y), t_max)
            })
            .collect()
    }

    #[test]
    fn two_level_any_hit_equals_the_flat_trees() {
        let mut rng = Rng(0x5858_1234_abcd_0001);
        let tris = mesh();
        let models = placements(&mut rng, 60);
        let (bvh, records, top) = two_level(&tris, &models);
        let flat = flat(&tris, &models);
        let two = (&bvh, records.as_slice(), top.node_offset);
        let (hits, differ) = agreement(two, &flat, &rays(&mut rng, 20_000));
        // Rays meet the copies often and miss them often; the answers agree on every one
        // (object-space tests round differently, so a ray grazing an edge within ~1e-6
        // could differ: none of these do).
        assert!(hits > 2_000 && hits < 18_000, "{hits} hits");
        assert_eq!(differ, 0, "{differ} of 20000 rays differ");
    }

    #[test]
    fn a_moved_instance_refits_the_top_level_only() {
        let mut rng = Rng(0x0707_9e37_79b9_7f4a);
        let tris = mesh();
        let mut models = placements(&mut rng, 40);
        let (mut bvh, mut records, mut top) = two_level(&tris, &models);
        let below = bvh.nodes[..top.node_offset as usize].to_vec();
        let triangles = bvh.triangles.clone();
        // Move the copy at position 5 far across the box and turn it.
        let k = top.order[5] as usize;
        models[k] =
            Mat4::from_rotation_translation(Quat::from_rotation_y(1.0), Vec3::new(14.0, 0.2, 1.0));
        records[5] = instance_record(&bvh, records[5].root, models[k]);
        let changed = top.refit(&records, 5);
        for &i in &changed {
            bvh.nodes[(top.node_offset + i) as usize] = top.nodes[i as usize];
        }
        // The mesh's tree is untouched, a path of the top level changed.
        assert_eq!(&bvh.nodes[..top.node_offset as usize], below.as_slice());
        assert_eq!(bvh.triangles, triangles);
        assert!(!changed.is_empty() && changed.len() < top.nodes.len() / 2);
        let flat = flat(&tris, &models);
        let rays = rays(&mut rng, 10_000);
        let (_, differ) = agreement((&bvh, &records, top.node_offset), &flat, &rays);
        let single = flat_one(&tris, models[k]);
        let hits_moved = (rays.iter())
            .filter(|&&(o, d, t_max)| any_hit_cpu(&single, o, d, t_max))
            .count();
        assert!(hits_moved > 10, "the moved copy is met: {hits_moved}");
        assert_eq!(differ, 0);
    }

    fn flat_one(tris: &[[Vec3; 3]], m: Mat4) -> GpuBvh {
        flat(tris, &[m])
    }

    /// Boxes, spheres of two tessellations and cylinders of many sizes, each placed by a
    /// turn, an uneven scale (a mirror for some) and another turn, so their maps shear: the
    /// shapes' two levels answer every ray as the flat tree over each object's own
    /// world-space triangles does.
    #[test]
    fn scaled_primitive_shapes_answer_as_the_flat_tree() {
        use crate::gpu_scene::shapes::ShadowShapes;
        use crate::input::{MaterialInput, ObjectInput, SceneInput};
        use std::sync::Arc;
        use texel_scene::primitives::{box_mesh, cylinder, sphere};
        let mut rng = Rng(0x5ca1_e0f0_1234_5678);
        let objects: Vec<ObjectInput> = (0..120)
            .map(|i| {
                let mut r = || rng.next();
                let mesh = match i % 4 {
                    0 => box_mesh(Vec3::new(0.2 + 3.0 * r(), 0.2 + 3.0 * r(), 0.2 + 3.0 * r())),
                    1 => sphere(0.2 + 1.5 * r(), 12),
                    2 => sphere(0.2 + 1.5 * r(), 8),
                    _ => cylinder(0.1 + r(), 0.5 + 3.0 * r(), 8),
                };
                let turn = |r: &mut dyn FnMut() -> f32| {
                    Quat::from_euler(glam::EulerRot::YXZ, r() * 6.3, r() - 0.5, r() - 0.5)
                };
                let (first, then) = (turn(&mut r), turn(&mut r));
                let mirror = if i % 7 == 0 { -1.0 } else { 1.0 };
                let scale = Vec3::new(mirror * (0.4 + r()), 0.4 + r(), 0.4 + r());
                let at = Vec3::new(r(), r() * 0.3, r()) * 16.0;
                ObjectInput {
                    mesh: Arc::new(mesh),
                    transform: Mat4::from_rotation_translation(then, at)
                        * Mat4::from_scale(scale)
                        * Mat4::from_quat(first),
                    material: MaterialInput {
                        albedo: Vec3::ONE,
                        casts_shadows: true,
                        ..Default::default()
                    },
                    id: i + 1,
                }
            })
            .collect();
        let scene = SceneInput {
            objects,
            ..Default::default()
        };
        let shapes = ShadowShapes::sharing(&scene, 0);
        // One shape per kind and tessellation, every object placed on one.
        assert_eq!((shapes.triangles().len(), shapes.instances()), (4, 120));
        let mut bvh = GpuBvh::empty();
        let roots: Vec<u32> = (shapes.triangles().iter())
            .map(|t| bvh.append(&build_bvh(t)))
            .collect();
        let records: Vec<GpuBvhInstance> = (scene.objects.iter().enumerate())
            .map(|(i, o)| {
                let (s, model) = shapes.placement(i, o.transform).unwrap();
                instance_record(&bvh, roots[s as usize], model)
            })
            .collect();
        let (top, placed) = top_over(&mut bvh, &records);
        let world: Vec<[Vec3; 3]> = (scene.objects.iter())
            .flat_map(|o| {
                let p = |i: u32| o.transform.transform_point3(o.mesh.positions[i as usize]);
                (o.mesh.indices.chunks_exact(3)).map(move |t| [p(t[0]), p(t[1]), p(t[2])])
            })
            .collect();
        let flat = build_bvh(&world);
        let two = (&bvh, placed.as_slice(), top.node_offset);
        let (hits, differ) = agreement(two, &flat, &rays(&mut rng, 20_000));
        assert!(hits > 2_000 && hits < 18_000, "{hits} hits");
        assert_eq!(differ, 0, "{differ} of 20000 rays differ");
        // The shapes hold a few hundred triangles where the flat tree holds every object's.
        let shape_triangles: usize = shapes.triangles().iter().map(Vec::len).sum();
        assert!(
            shape_triangles * 20 < world.len(),
            "{shape_triangles} {}",
            world.len()
        );
    }
}
