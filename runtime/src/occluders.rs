//! The scene as probe placement sees it (`texel_probes::placement`): every triangle of every
//! object, world-space, wound as its mesh is (front faces counter-clockwise), in a CPU BVH.

use std::sync::OnceLock;

use texel_probes::placement::{RayHit, RayQuery};
use texel_render::bvh::refit::RefitIndex;
use texel_render::bvh::{GpuBvh, build_bvh, first_hit_cpu, triangles_in_box_cpu};
use texel_render::input::{ObjectInput, PointLightInput, SceneInput, SunInput};

/// Closest-hit ray queries against a scene. The BVH is built on the first query, so a level
/// whose grid probes never need placing (or an editor edit before the next frame) pays
/// nothing for it; an edit that moves objects refits it ([`SceneRays::replace_objects`]).
#[derive(Debug, Clone)]
pub struct SceneRays {
    scene: SceneInput,
    bvh: OnceLock<RayTree>,
    /// The objects appended after the tree was built, in a tree of their own
    /// ([`SceneRays::append_objects`]).
    extra: OnceLock<RayTree>,
}

/// The tree over the still objects' triangles, and where each object's start among them.
#[derive(Debug, Clone)]
struct RayTree {
    bvh: GpuBvh,
    /// Each object's triangles among the tree's inputs (`None`: animated, or before the
    /// objects a small tree of appended ones starts at; not in the tree). A blank's are
    /// points.
    spans: Vec<Option<std::ops::Range<u32>>>,
    /// The tree's inputs.
    inputs: usize,
    /// Made on the first refit.
    refit: Option<RefitIndex>,
}

impl SceneRays {
    /// Queries against `scene` (every object, shadow casters or not).
    pub fn new(scene: SceneInput) -> Self {
        SceneRays {
            scene,
            bvh: OnceLock::new(),
            extra: OnceLock::new(),
        }
    }

    /// The scene the rays are cast against.
    pub fn scene(&self) -> &SceneInput {
        &self.scene
    }

    /// The scene, to change what the tree does not hold (lights); objects change through
    /// [`SceneRays::replace_objects`].
    pub fn lights_mut(&mut self) -> (&mut Vec<SunInput>, &mut Vec<PointLightInput>) {
        (&mut self.scene.suns, &mut self.scene.points)
    }

    /// Replaces the objects from `at` on with `objects` (as many as there were: the same
    /// entity extracted again), refitting the tree when it was built and each object keeps
    /// its number of triangles, or dropping it to be built again on the next query.
    pub fn replace_objects(&mut self, at: usize, objects: Vec<ObjectInput>) {
        let range = at..at + objects.len();
        self.scene.objects.splice(range.clone(), objects);
        let Some(tree) = self.bvh.get_mut() else {
            return;
        };
        let mut moved = Vec::new();
        for i in range {
            if i >= tree.spans.len() {
                // Appended since the tree was built: in the small tree.
                self.extra = OnceLock::new();
                continue;
            }
            let Some(span) = tree.spans.get(i).cloned().flatten() else {
                continue;
            };
            let tris = world_triangles(&self.scene.objects[i]);
            if tris.len() != span.len() {
                self.bvh = OnceLock::new();
                return;
            }
            moved.extend(span.zip(tris));
        }
        let inputs = tree.inputs;
        let refitted = (tree.refit)
            .get_or_insert_with(|| RefitIndex::new(&tree.bvh, inputs))
            .refit(&mut tree.bvh, &moved);
        if refitted.is_none() {
            self.bvh = OnceLock::new();
        }
    }

    /// Gives objects other ids (`(index, id)` pairs): the tree stays.
    pub fn set_ids(&mut self, ids: &[(usize, u32)]) {
        for &(k, id) in ids {
            self.scene.objects[k].id = id;
        }
    }

    /// Appends `objects` after the last. A tree built already stays; the appended objects
    /// get a small tree of their own, built on the next query (and again after each append).
    pub fn append_objects(&mut self, objects: Vec<ObjectInput>) {
        self.scene.objects.extend(objects);
        self.extra = OnceLock::new();
    }

    /// Replaces the objects in `range` by `blank` (a removed entity's, with no triangles).
    /// In a tree built already, their triangles shrink to points, which no ray hits and no
    /// box query returns, and the boxes above them are refit.
    pub fn blank_objects(&mut self, range: std::ops::Range<usize>, blank: ObjectInput) {
        let old: Vec<Vec<[glam::Vec3; 3]>> = (self.scene.objects[range.clone()].iter())
            .map(world_triangles)
            .collect();
        self.scene.objects[range.clone()].fill(blank);
        let Some(tree) = self.bvh.get_mut() else {
            return;
        };
        let mut moved = Vec::new();
        for (i, old) in range.zip(old) {
            match tree.spans.get_mut(i) {
                // Kept: an object that takes the blank again is refit back.
                Some(span) => {
                    let span = span.clone().unwrap_or_default();
                    moved.extend(span.zip(old.into_iter().map(|t| [t[0]; 3])));
                }
                // Appended since the tree was built: in the small tree.
                None => self.extra = OnceLock::new(),
            }
        }
        let inputs = tree.inputs;
        let refitted = (tree.refit)
            .get_or_insert_with(|| RefitIndex::new(&tree.bvh, inputs))
            .refit(&mut tree.bvh, &moved);
        if refitted.is_none() {
            self.bvh = OnceLock::new();
        }
    }

    fn bvh(&self) -> &GpuBvh {
        &self.bvh.get_or_init(|| build(&self.scene, 0)).bvh
    }

    /// The small tree over the objects appended since the main tree was built (`None`
    /// when there are none).
    fn extra(&self) -> Option<&GpuBvh> {
        let from = self.bvh.get()?.spans.len();
        (from < self.scene.objects.len())
            .then(|| &self.extra.get_or_init(|| build(&self.scene, from)).bvh)
    }
}

/// The BVH over every triangle of `scene`'s objects from `from` on, world-space, wound as
/// their meshes are, with where each object's triangles start (`None` before `from`).
fn build(scene: &SceneInput, from: usize) -> RayTree {
    let mut triangles = Vec::new();
    let mut spans = vec![None; from];
    spans.reserve(scene.objects.len() - from);
    let animated: std::collections::HashSet<usize> = scene.animated.iter().copied().collect();
    for (i, object) in scene.objects.iter().enumerate().skip(from) {
        // Moving objects are left out: a probe's place is a function of the static scene.
        if animated.contains(&i) {
            spans.push(None);
            continue;
        }
        let first = triangles.len() as u32;
        triangles.extend(world_triangles(object));
        spans.push(Some(first..triangles.len() as u32));
    }
    RayTree {
        bvh: build_bvh(&triangles),
        inputs: triangles.len(),
        spans,
        refit: None,
    }
}

/// `object`'s triangles in world space, wound as its mesh is.
fn world_triangles(object: &ObjectInput) -> Vec<[glam::Vec3; 3]> {
    let m = object.transform;
    // A mirroring transform turns counter-clockwise into clockwise: swap back.
    let flip = m.determinant() < 0.0;
    let mesh = &object.mesh;
    (mesh.indices.chunks_exact(3))
        .map(|tri| {
            let vertex = |i: u32| {
                let p = mesh.positions.get(i as usize).copied().unwrap_or_default();
                m.transform_point3(p)
            };
            let (a, b, c) = (vertex(tri[0]), vertex(tri[1]), vertex(tri[2]));
            if flip { [a, c, b] } else { [a, b, c] }
        })
        .collect()
}

impl RayQuery for SceneRays {
    fn triangles_in(&self, min: glam::Vec3, max: glam::Vec3) -> Vec<[glam::Vec3; 3]> {
        let mut out = triangles_in_box_cpu(self.bvh(), min, max);
        // Blanked triangles are points (a box query may meet them): left out.
        out.retain(|t| t[0] != t[1] || t[0] != t[2]);
        if let Some(extra) = self.extra() {
            out.extend(triangles_in_box_cpu(extra, min, max));
        }
        out
    }

    fn first_hit(&self, origin: glam::Vec3, dir: glam::Vec3, max: f32) -> Option<RayHit> {
        let mut hit = first_hit_cpu(self.bvh(), origin, dir, max);
        if let Some(extra) = self.extra() {
            let reach = hit.map_or(max, |h| h.0);
            hit = first_hit_cpu(extra, origin, dir, reach).or(hit);
        }
        hit.map(|(t, tri)| RayHit {
            t,
            back_face: tri.normal().dot(dir) > 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame_plan::scene_input;
    use crate::load::load_level;
    use glam::{IVec3, Vec3};
    use texel_probes::grid::GridCell;
    use texel_probes::placement::{near_faces, place_probe};

    /// A box blanked after the tree was built is no longer hit, a box appended is (through
    /// the small tree), as by a tree built afresh.
    #[test]
    fn blanked_and_appended_objects_answer_as_a_tree_built_afresh() {
        let boxed = |x: f32, id: u32| ObjectInput {
            mesh: std::sync::Arc::new(texel_scene::primitives::box_mesh(Vec3::ONE)),
            transform: glam::Mat4::from_translation(Vec3::new(x, 0.0, 0.0)),
            material: Default::default(),
            id,
        };
        let scene = SceneInput {
            objects: vec![boxed(2.0, 1), boxed(5.0, 2)],
            ..SceneInput::default()
        };
        let mut rays = SceneRays::new(scene);
        let hit = |r: &SceneRays| r.first_hit(Vec3::ZERO, Vec3::X, 100.0).map(|h| h.t);
        assert_eq!(hit(&rays), Some(1.5));
        let blank = ObjectInput {
            mesh: Default::default(),
            ..boxed(0.0, 0)
        };
        rays.blank_objects(0..1, blank);
        assert_eq!(hit(&rays), Some(4.5), "the first box is gone");
        let (lo, hi) = (Vec3::new(1.4, -0.6, -0.6), Vec3::new(2.45, 0.6, 0.6));
        assert!(
            rays.triangles_in(lo, hi).is_empty(),
            "its triangles are points"
        );
        rays.append_objects(vec![boxed(3.0, 3)]);
        assert_eq!(hit(&rays), Some(2.5), "the appended box is hit");
        let (lo, hi) = (Vec3::new(2.45, -0.6, -0.6), Vec3::new(3.55, 0.6, 0.6));
        assert_eq!(rays.triangles_in(lo, hi).len(), 12);
        let fresh = SceneRays::new(rays.scene().clone());
        assert_eq!(hit(&fresh), hit(&rays));
    }

    /// The textured level's brick wall (its back face at z = −4.75, its top at y = 2.5): the
    /// probes of the cells above and behind it stand 0.25 off the back face's plane, where
    /// a survey walk saw the face edge-on (`texel-eval survey`, seed 1, walk 01); the box
    /// query finds that face for them (and for no probe a cell farther back).
    #[test]
    fn probes_behind_the_textured_levels_brick_wall_find_its_back_face() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/textured.ron");
        let level = load_level(&path).expect("bundled level loads");
        let rays = SceneRays::new(scene_input(&level));
        let cell = |x, z| GridCell {
            index: IVec3::new(x, 3, z),
            cell_size: 1.0,
        };
        for x in [-2, 0, 2] {
            let p = place_probe(&cell(x, -5), &rays);
            let faces = near_faces(p, 1.0, &rays);
            assert!(
                faces.iter().any(
                    |f| f.normal.abs_diff_eq(-Vec3::Z, 1e-4) && (f.point.z + 4.75).abs() < 1e-3
                ),
                "cell ({x}, 3, -5), probe {p}: {faces:?}"
            );
            let back = place_probe(&cell(x, -7), &rays);
            assert!(near_faces(back, 1.0, &rays).is_empty(), "{back}");
        }
    }
}
