//! The scene as probe placement sees it (`texel_probes::placement`): every triangle of every
//! object, world-space, wound as its mesh is (front faces counter-clockwise), in a CPU BVH.

use std::sync::OnceLock;

use texel_probes::placement::{RayHit, RayQuery};
use texel_render::bvh::{GpuBvh, build_bvh, first_hit_cpu};
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
    fn first_hit(&self, origin: glam::Vec3, dir: glam::Vec3, max: f32) -> Option<RayHit> {
        first_hit_cpu(self.bvh(), origin, dir, max).map(|(t, tri)| RayHit {
            t,
            back_face: tri.normal().dot(dir) > 0.0,
        })
    }
}
