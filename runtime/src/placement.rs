//! The scene as probe placement sees it (`texel_probes::placement`): every triangle of every
//! object, world-space, wound as its mesh is (front faces counter-clockwise), in a CPU BVH.

use texel_probes::placement::{RayHit, RayQuery};
use texel_render::bvh::{GpuBvh, build_bvh, first_hit_cpu};
use texel_render::input::SceneInput;

/// Closest-hit ray queries against a scene.
#[derive(Debug, Clone)]
pub struct SceneRays {
    bvh: GpuBvh,
}

impl SceneRays {
    /// Builds the BVH over every object of `scene` (shadow casters or not).
    pub fn new(scene: &SceneInput) -> Self {
        let mut triangles = Vec::new();
        for object in &scene.objects {
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
        SceneRays {
            bvh: build_bvh(&triangles),
        }
    }
}

impl RayQuery for SceneRays {
    fn first_hit(&self, origin: glam::Vec3, dir: glam::Vec3, max: f32) -> Option<RayHit> {
        first_hit_cpu(&self.bvh, origin, dir, max).map(|(t, tri)| RayHit {
            t,
            back_face: tri.normal().dot(dir) > 0.0,
        })
    }
}
