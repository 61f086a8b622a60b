//! A CPU reference G-buffer: casts one ray per pixel centre against the scene's triangles
//! (per-object bounding boxes first). It needs no GPU, so the metrics can be calibrated in
//! plain unit tests, and it serves the runner when no GPU reference is available.

use glam::{UVec2, Vec3};
use texel_geom::ray::ray_triangle;
use texel_render::input::{Camera, SceneInput};

use crate::metrics::{Reference, view_proj};

/// The scene's triangles in world space, grouped per object with a bounding box.
#[derive(Debug, Clone, Default)]
pub struct CpuScene {
    objects: Vec<CpuObject>,
    has_sprites: bool,
}

#[derive(Debug, Clone)]
struct CpuObject {
    id: u32,
    min: Vec3,
    max: Vec3,
    triangles: Vec<[Vec3; 3]>,
}

impl CpuScene {
    /// World-space triangles of every object of `scene`.
    pub fn new(scene: &SceneInput) -> Self {
        let objects = scene
            .objects
            .iter()
            .filter_map(|o| {
                let world: Vec<Vec3> = o
                    .mesh
                    .positions
                    .iter()
                    .map(|p| o.transform.transform_point3(*p))
                    .collect();
                let triangles: Vec<[Vec3; 3]> = o
                    .mesh
                    .indices
                    .chunks_exact(3)
                    .filter_map(|t| {
                        let v = |i: u32| world.get(i as usize).copied();
                        Some([v(t[0])?, v(t[1])?, v(t[2])?])
                    })
                    .collect();
                let (min, max) = triangles.iter().flatten().fold(
                    (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                    |(lo, hi), p| (lo.min(*p), hi.max(*p)),
                );
                (!triangles.is_empty()).then_some(CpuObject {
                    id: o.id,
                    min,
                    max,
                    triangles,
                })
            })
            .collect();
        CpuScene {
            objects,
            has_sprites: !scene.sprites.is_empty(),
        }
    }

    /// Whether the scene has sprites (which this reference does not draw).
    pub fn has_sprites(&self) -> bool {
        self.has_sprites
    }

    /// The nearest hit along `origin + t·dir` for t in (`RAY_T_MIN`, t_max) (the renderer's
    /// ray–triangle test, [`texel_geom::ray::ray_triangle`]): distance and object id.
    pub fn cast(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<(f32, u32)> {
        let inv = dir.recip();
        let mut best: Option<(f32, u32)> = None;
        for o in &self.objects {
            let limit = best.map_or(t_max, |b| b.0);
            if !ray_box(origin, inv, o.min, o.max, limit) {
                continue;
            }
            for t in &o.triangles {
                let limit = best.map_or(t_max, |b| b.0);
                let [a, b, c] = *t;
                if let Some(d) = ray_triangle(origin, dir, a, b - a, c - a, limit) {
                    best = Some((d, o.id));
                }
            }
        }
        best
    }

    /// The reference G-buffer at `camera` for a `size` frame.
    pub fn gbuffer(&self, camera: &Camera, size: UVec2) -> Reference {
        let inv = view_proj(camera, size).inverse();
        let n = (size.x * size.y) as usize;
        let mut out = Reference {
            size,
            world: vec![[0.0; 3]; n],
            id: vec![0; n],
            poses: Vec::new(),
            sprites: Vec::new(),
        };
        for y in 0..size.y {
            for x in 0..size.x {
                let nx = (x as f32 + 0.5) / size.x as f32 * 2.0 - 1.0;
                let ny = 1.0 - (y as f32 + 0.5) / size.y as f32 * 2.0;
                let near = inv.project_point3(Vec3::new(nx, ny, 0.0));
                let far = inv.project_point3(Vec3::new(nx, ny, 1.0));
                let (dir, len) = ((far - near).normalize_or_zero(), (far - near).length());
                if let Some((t, id)) = self.cast(near, dir, len) {
                    let i = (y * size.x + x) as usize;
                    out.world[i] = (near + dir * t).to_array();
                    out.id[i] = id;
                }
            }
        }
        out
    }
}

fn ray_box(origin: Vec3, inv: Vec3, min: Vec3, max: Vec3, t_max: f32) -> bool {
    let (a, b) = ((min - origin) * inv, (max - origin) * inv);
    let (lo, hi) = (a.min(b), a.max(b));
    let enter = lo.max_element().max(0.0);
    let exit = hi.min_element().min(t_max);
    // NaN (a ray in a box's plane) compares false: treat as a possible hit.
    enter.partial_cmp(&exit) != Some(std::cmp::Ordering::Greater)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use texel_render::input::{MaterialInput, ObjectInput};
    use texel_scene::Geometry;
    use texel_scene::primitives::primitive_mesh;

    #[test]
    fn a_box_in_front_is_seen_with_its_id_and_surface_point() {
        let mesh = primitive_mesh(&Geometry::Box {
            size: Vec3::splat(2.0),
        })
        .expect("box mesh");
        let scene = SceneInput {
            objects: vec![ObjectInput {
                mesh: Arc::new(mesh),
                transform: glam::Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0)),
                material: MaterialInput {
                    albedo: Vec3::ONE,
                    emissive: Vec3::ZERO,
                    casts_shadows: true,
                    outlined: false,
                    ..Default::default()
                },
                id: 7,
            }],
            ..Default::default()
        };
        let cam = Camera::looking(Vec3::ZERO, -Vec3::Z);
        let g = CpuScene::new(&scene).gbuffer(&cam, UVec2::new(33, 17));
        let centre = (8 * 33 + 16) as usize;
        assert_eq!(g.id[centre], 7);
        assert!(
            (g.world[centre][2] + 4.0).abs() < 1e-3,
            "{:?}",
            g.world[centre]
        );
        assert_eq!(g.id[0], 0, "the corner sees sky");
    }
}
