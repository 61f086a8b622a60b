//! Shadow shapes: still objects whose meshes are one mesh up to a scale along each axis (a
//! level's boxes of every size, its spheres of every radius, one shape per tessellation,
//! copies of one glTF mesh) cast their shadows through one tree in the shape's own space, each object
//! a record under the still instances' top level (`bvh::instances`), placed by its transform
//! times its scale. A ray is carried into the shape's space by an affine map, which keeps its
//! parameter, so non-uniform scales are as exact as turns. What is drawn is not touched:
//! an object's vertices are its own (world space) or its shared mesh's
//! (`gpu_scene/instances.rs`); only its shadow-casting triangles move out of the flat tree.
//!
//! A shape is the first member's positions divided by their extent along each axis (the
//! largest |coordinate|, 1 where it is 0); another object belongs to it when its mesh has the
//! same indices and its positions are the shape's times its own extents to within 1e-6 of
//! their size (primitive meshes are made as unit directions times sizes, so they differ from
//! that product by rounding only). A shape is shared whole when its objects hold
//! [`SHARED_TRIANGLES`] or more in all, else by its exact copies alone; a shape of one object
//! is no shape: it stays in the flat tree, as does an animated object, a terrain, a mesh
//! with levels of detail, and an object casting no shadow.

use std::collections::HashMap;

use glam::{Mat4, Vec3};
use texel_geom::mesh::TriMesh;

use super::upload::Meshes;
use crate::input::{ObjectInput, SceneInput};

/// Triangles a shape's objects hold in all from which every one of them casts through it:
/// a ray pays a top-level walk and a change of space to meet an object of a shape, which a
/// level of a few dozen boxes (the stone circle: its shading cost 13 % more with every box
/// an instance) does not win back, while the towns of 1,000 and more do (their boxes and
/// balls pass it). Below it only exact copies share it (as they share their vertices:
/// `gpu_scene/instances.rs`).
pub const SHARED_TRIANGLES: usize = 4096;
/// How close (relative to the object's extent) a member's positions must be to its shape's.
const SAME_SHAPE: f32 = 1e-6;
/// Steps of a canonical coordinate in the hash that buckets candidates (checked after).
const BUCKET_STEPS: f32 = 4096.0;

/// Which still objects cast their shadows through a shared shape's tree.
#[derive(Debug, Clone, Default)]
pub struct ShadowShapes {
    /// Each object's shape and its extents (the scale from the shape's space to its mesh's).
    of: Vec<Option<(u32, Vec3)>>,
    /// Each shape's triangles in its own space.
    triangles: Vec<Vec<[Vec3; 3]>>,
}

impl ShadowShapes {
    /// The shapes of `scene`'s still shadow casters, each shared when its objects hold
    /// [`SHARED_TRIANGLES`] or more triangles in all (else by its exact copies alone); none
    /// when `on` is false: every caster in the flat tree.
    pub fn new(scene: &SceneInput, on: bool) -> Self {
        match on {
            true => Self::sharing(scene, SHARED_TRIANGLES),
            false => Self::sharing(&SceneInput::default(), 0),
        }
    }

    /// [`ShadowShapes::new`] with shapes shared whole from `least` triangles in all on.
    pub fn sharing(scene: &SceneInput, least: usize) -> Self {
        let mut of = vec![None; scene.objects.len()];
        let animated: std::collections::HashSet<usize> = scene.animated.iter().copied().collect();
        // Candidates bucketed by a hash of their canonical positions; in a bucket, groups
        // of objects checked against the group's first.
        let mut buckets: HashMap<u64, Vec<Vec<(usize, Vec3)>>> = HashMap::new();
        let mut canonical_of: HashMap<*const TriMesh, (u64, Vec3)> = HashMap::new();
        for (i, o) in scene.objects.iter().enumerate() {
            if !eligible(o) || animated.contains(&i) {
                continue;
            }
            let (key, extent) = *canonical_of
                .entry(std::sync::Arc::as_ptr(&o.mesh))
                .or_insert_with(|| canonical_key(&o.mesh));
            let groups = buckets.entry(key).or_default();
            let same = |g: &Vec<(usize, Vec3)>| {
                let (first, e) = g[0];
                same_shape(&scene.objects[first].mesh, e, &o.mesh, extent)
            };
            match groups.iter_mut().find(|g| same(g)) {
                Some(g) => g.push((i, extent)),
                None => groups.push(vec![(i, extent)]),
            }
        }
        let mut groups: Vec<Vec<(usize, Vec3)>> = (buckets.into_values().flatten())
            .map(|g| few_keep_copies(g, least, |i| scene.objects[i].mesh.indices.len() / 3))
            .filter(|g| g.len() > 1)
            .collect();
        groups.sort_unstable_by_key(|g| g[0].0);
        let mut triangles = Vec::with_capacity(groups.len());
        for (s, g) in groups.iter().enumerate() {
            let (first, e) = g[0];
            let m = &scene.objects[first].mesh;
            let unit = |i: u32| m.positions[i as usize] / e;
            triangles.push(
                (m.indices.chunks_exact(3))
                    .map(|t| [unit(t[0]), unit(t[1]), unit(t[2])])
                    .collect(),
            );
            for &(i, extent) in g {
                of[i] = Some((s as u32, extent));
            }
        }
        ShadowShapes { of, triangles }
    }

    /// The shape object `index` casts through and its placement (object transform times its
    /// extents), if it casts through one.
    pub fn placement(&self, index: usize, transform: Mat4) -> Option<(u32, Mat4)> {
        let (s, extent) = self.of.get(index).copied().flatten()?;
        Some((s, transform * Mat4::from_scale(extent)))
    }

    /// Whether object `index` casts through a shape.
    pub fn shared(&self, index: usize) -> bool {
        self.of.get(index).is_some_and(|s| s.is_some())
    }

    /// Each shape's triangles in its own space.
    pub fn triangles(&self) -> &[Vec<[Vec3; 3]>] {
        &self.triangles
    }

    /// How many objects cast through a shape.
    pub fn instances(&self) -> usize {
        self.of.iter().flatten().count()
    }
}

impl Meshes {
    /// Object `index`'s (`o`'s) shadows: a record placing its shape, or, when it is drawn
    /// from a shared mesh (`drawn_shared`, whose vertices bring no casters) but has no
    /// shape, its world-space triangles in the flat tree.
    pub(super) fn add_shadow(
        &mut self,
        o: &ObjectInput,
        index: usize,
        drawn_shared: bool,
        shapes: &ShadowShapes,
    ) {
        if let Some((s, model)) = shapes.placement(index, o.transform) {
            self.casting_instances.push((s as usize, model));
            self.casting_objects.push(index);
        } else if drawn_shared && o.material.casts_shadows {
            let p = |i: u32| o.transform.transform_point3(o.mesh.positions[i as usize]);
            (self.casters)
                .extend((o.mesh.indices.chunks_exact(3)).map(|t| [p(t[0]), p(t[1]), p(t[2])]));
        }
    }
}

/// Group `g` (objects and extents) whole when its objects hold `least` triangles or more in
/// all (`triangles` of an object), else only its objects whose extents another one has
/// too (copies).
fn few_keep_copies(
    mut g: Vec<(usize, Vec3)>,
    least: usize,
    triangles: impl Fn(usize) -> usize,
) -> Vec<(usize, Vec3)> {
    if g.iter().map(|&(i, _)| triangles(i)).sum::<usize>() >= least {
        return g;
    }
    let key = |e: Vec3| e.to_array().map(f32::to_bits);
    let mut count: HashMap<[u32; 3], usize> = HashMap::new();
    g.iter()
        .for_each(|&(_, e)| *count.entry(key(e)).or_default() += 1);
    g.retain(|&(_, e)| count[&key(e)] > 1);
    g
}

/// Whether `o` may cast through a shape: a still caster's finite triangle mesh without
/// levels of detail, placed by an invertible affine map.
fn eligible(o: &ObjectInput) -> bool {
    o.material.casts_shadows
        && o.material.terrain.is_none()
        && o.mesh.pieces.is_empty()
        && !o.mesh.indices.is_empty()
        && o.mesh.indices.len().is_multiple_of(3)
        && (o.mesh.indices.iter()).all(|&i| (i as usize) < o.mesh.positions.len())
        && o.mesh.positions.iter().all(|p| p.is_finite())
        && placeable(o.transform)
}

/// Whether a shape's record may be placed by `t` (a finite affine map, invertible).
pub fn placeable(t: Mat4) -> bool {
    t.is_finite() && t.row(3) == glam::Vec4::W && t.determinant().abs() > 1e-12
}

/// The mesh's extent along each axis (largest |coordinate|, 1 where all are 0) and a hash of
/// its indices and of its positions divided by that extent, rounded to [`BUCKET_STEPS`].
fn canonical_key(m: &TriMesh) -> (u64, Vec3) {
    let extent = m.positions.iter().fold(Vec3::ZERO, |e, p| e.max(p.abs()));
    let extent = Vec3::select(extent.cmpgt(Vec3::ZERO), extent, Vec3::ONE);
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut mix = |x: u64| h = (h ^ x).wrapping_mul(0x0100_0000_01b3).rotate_left(17);
    mix(m.positions.len() as u64);
    m.indices.iter().for_each(|&i| mix(u64::from(i)));
    for p in &m.positions {
        let q = (*p / extent * BUCKET_STEPS).round();
        mix((q.x as i64 as u64) ^ ((q.y as i64 as u64) << 21) ^ ((q.z as i64 as u64) << 42));
    }
    (h, extent)
}

/// Whether mesh `b` (extents `eb`) is mesh `a` (extents `ea`) scaled by `eb / ea`, to within
/// [`SAME_SHAPE`] of its extent, with the same indices.
fn same_shape(a: &TriMesh, ea: Vec3, b: &TriMesh, eb: Vec3) -> bool {
    if std::ptr::eq(a, b) {
        return true;
    }
    let tolerance = SAME_SHAPE * eb.max_element();
    a.indices == b.indices
        && a.positions.len() == b.positions.len()
        && (a.positions.iter().zip(&b.positions))
            .all(|(p, q)| (*p / ea * eb - *q).abs().max_element() <= tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::MaterialInput;
    use std::sync::Arc;
    use texel_geom::mesh::TriMesh;

    fn object(mesh: TriMesh, transform: Mat4, casts_shadows: bool) -> ObjectInput {
        ObjectInput {
            mesh: Arc::new(mesh),
            transform,
            material: MaterialInput {
                albedo: Vec3::ONE,
                casts_shadows,
                ..Default::default()
            },
            id: 1,
        }
    }

    /// A box of `size` centred on the origin: 8 corners, 12 triangles.
    fn cuboid(size: Vec3) -> TriMesh {
        let h = size * 0.5;
        let positions = (0..8)
            .map(|i| {
                let s = |b| if i & b == 0 { -1.0 } else { 1.0 };
                Vec3::new(s(1), s(2), s(4)) * h
            })
            .collect::<Vec<_>>();
        TriMesh {
            normals: vec![Vec3::Y; 8],
            colors: vec![[1.0; 4]; 8],
            indices: vec![
                0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0,
                6, 4, 1, 5, 7, 1, 7, 3,
            ],
            positions,
            ..Default::default()
        }
    }

    #[test]
    fn boxes_of_every_size_share_one_shape_and_odd_ones_out_stay_flat() {
        let mut lopsided = cuboid(Vec3::ONE);
        lopsided.positions[7] += Vec3::splat(0.1);
        let scene = SceneInput {
            objects: vec![
                object(cuboid(Vec3::new(2.0, 3.0, 0.5)), Mat4::IDENTITY, true),
                object(
                    cuboid(Vec3::new(0.2, 7.0, 1.0)),
                    Mat4::from_rotation_y(0.3),
                    true,
                ),
                object(cuboid(Vec3::ONE), Mat4::from_translation(Vec3::X), true),
                // Casts no shadow; another shape alone; animated.
                object(cuboid(Vec3::splat(2.0)), Mat4::IDENTITY, false),
                object(lopsided, Mat4::IDENTITY, true),
                object(cuboid(Vec3::splat(4.0)), Mat4::IDENTITY, true),
            ],
            animated: vec![5],
            ..Default::default()
        };
        let shapes = ShadowShapes::sharing(&scene, 0);
        assert_eq!(shapes.triangles().len(), 1);
        assert_eq!(shapes.instances(), 3);
        assert!((0..3).all(|i| shapes.shared(i)) && !(3..6).any(|i| shapes.shared(i)));
        // The shape is the unit cube's corners at ±1; each placement maps it onto the
        // object's own triangles.
        for (i, o) in scene.objects.iter().enumerate().take(3) {
            let (s, model) = shapes.placement(i, o.transform).unwrap();
            let shape = &shapes.triangles()[s as usize];
            for (t, tri) in o.mesh.indices.chunks_exact(3).enumerate() {
                for c in 0..3 {
                    let want = o
                        .transform
                        .transform_point3(o.mesh.positions[tri[c] as usize]);
                    let got = model.transform_point3(shape[t][c]);
                    assert!(want.abs_diff_eq(got, 1e-6), "object {i}: {want} {got}");
                }
            }
        }
        assert!(ShadowShapes::new(&scene, false).triangles().is_empty());
        // 36 triangles in all: too few to share but between copies, and these differ.
        assert_eq!(ShadowShapes::new(&scene, true).instances(), 0);
    }

    #[test]
    fn a_shape_of_few_triangles_is_shared_by_exact_copies_alone() {
        let size = Vec3::new(1.0, 2.0, 3.0);
        let objects = |n: usize| -> Vec<ObjectInput> {
            (0..n)
                .map(|i| {
                    let at = Mat4::from_translation(Vec3::X * i as f32);
                    let size = if i < 2 { size } else { size * (1.0 + i as f32) };
                    object(cuboid(size), at, true)
                })
                .collect()
        };
        let few = SceneInput {
            objects: objects(4),
            ..Default::default()
        };
        let shapes = ShadowShapes::new(&few, true);
        assert_eq!(shapes.instances(), 2);
        assert!(shapes.shared(0) && shapes.shared(1) && !shapes.shared(2));
        // 342 boxes of 12 triangles reach SHARED_TRIANGLES: every one shares the shape.
        let many = SceneInput {
            objects: objects(SHARED_TRIANGLES.div_ceil(12)),
            ..Default::default()
        };
        let shapes = ShadowShapes::new(&many, true);
        assert_eq!(
            (shapes.triangles().len(), shapes.instances()),
            (1, many.objects.len())
        );
    }
}
