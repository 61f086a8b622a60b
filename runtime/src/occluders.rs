//! The scene as probe placement sees it (`texel_probes::placement`): every triangle of every
//! object, world-space, wound as its mesh is (front faces counter-clockwise), in a CPU BVH.

use std::sync::OnceLock;

use texel_probes::placement::{RayHit, RayQuery};
use texel_render::bvh::{GpuBvh, build_bvh, first_hit_cpu, triangles_in_box_cpu};
use texel_render::input::SceneInput;

/// Closest-hit ray queries against a scene. The BVH is built on the first query, so a level
/// whose grid probes never need placing (or an editor edit before the next frame) pays
/// nothing for it.
#[derive(Debug)]
pub struct SceneRays {
    scene: SceneInput,
    bvh: OnceLock<GpuBvh>,
}

impl SceneRays {
    /// Queries against `scene` (every object, shadow casters or not).
    pub fn new(scene: SceneInput) -> Self {
        SceneRays {
            scene,
            bvh: OnceLock::new(),
        }
    }

    /// The scene the rays are cast against.
    pub fn scene(&self) -> &SceneInput {
        &self.scene
    }

    fn bvh(&self) -> &GpuBvh {
        self.bvh.get_or_init(|| build(&self.scene))
    }
}

/// The BVH over every triangle of `scene`, world-space, wound as its meshes are.
fn build(scene: &SceneInput) -> GpuBvh {
    {
        let mut triangles = Vec::new();
        // Moving objects are left out: a probe's place is a function of the static scene.
        let still = (scene.objects.iter().enumerate())
            .filter(|(i, _)| !scene.animated.contains(i))
            .map(|(_, o)| o);
        for object in still {
            let m = object.transform;
            // A mirroring transform turns counter-clockwise into clockwise: swap back.
            let flip = m.determinant() < 0.0;
            let mesh = &object.mesh;
            for tri in mesh.indices.chunks_exact(3) {
                let vertex = |i: u32| {
                    let p = mesh.positions.get(i as usize).copied().unwrap_or_default();
                    m.transform_point3(p)
                };
                let (a, b, c) = (vertex(tri[0]), vertex(tri[1]), vertex(tri[2]));
                triangles.push(if flip { [a, c, b] } else { [a, b, c] });
            }
        }
        build_bvh(&triangles)
    }
}

impl RayQuery for SceneRays {
    fn triangles_in(&self, min: glam::Vec3, max: glam::Vec3) -> Vec<[glam::Vec3; 3]> {
        triangles_in_box_cpu(self.bvh(), min, max)
    }

    fn first_hit(&self, origin: glam::Vec3, dir: glam::Vec3, max: f32) -> Option<RayHit> {
        first_hit_cpu(self.bvh(), origin, dir, max).map(|(t, tri)| RayHit {
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
