//! Mesh instancing: a mesh that several still objects use with the same surfaces is
//! uploaded once, in object space, and each object draws it with an instance record (its
//! transform and index: [`super::GpuInstance`]). Meshes are the same when their contents
//! are (a glTF mesh shared by its entities, primitives of one shape and size), not only when
//! they are one allocation. Only similarities are instanced (rotation, mirror, uniform
//! scale): their normals and UV gradients follow the model matrix, divided by the squared
//! scale. Objects whose mesh no other object shares, animated objects and terrains keep
//! their vertices written in world space, drawn with the identity record 0.

use std::collections::HashMap;

use glam::Vec3;
use texel_geom::mesh::TriMesh;

use super::ranges::{DrawRange, RANGE_TRIANGLES};
use super::upload::{Meshes, ObjectTriangles, object_record};
use super::{GpuInstance, is_similarity};
use crate::input::{ObjectInput, SceneInput};

/// Which objects share which mesh, and where each shared mesh's vertices were put.
pub(super) struct SharedMeshes {
    /// The group of each object that shares its mesh.
    group: Vec<Option<usize>>,
    /// Each group's first vertex, once its mesh is uploaded.
    first: Vec<Option<u32>>,
}

impl SharedMeshes {
    /// Groups `scene`'s still objects (not animated, not terrains, not levels of detail,
    /// placed by a similarity) by mesh contents and surfaces (`surfaces`, by object); a
    /// group of one is no group.
    pub(super) fn new(
        scene: &SceneInput,
        animated_index: &[Option<u32>],
        surfaces: &[(u32, Vec<u32>)],
    ) -> Self {
        let mut by_key: HashMap<(u64, u32, Vec<u32>), Vec<Vec<usize>>> = HashMap::new();
        let mut hashes: HashMap<*const TriMesh, u64> = HashMap::new();
        for (i, o) in scene.objects.iter().enumerate() {
            if !instanceable(o) || animated_index.get(i).copied().flatten().is_some() {
                continue;
            }
            let (own, parts) = &surfaces[i];
            let hash = *hashes
                .entry(std::sync::Arc::as_ptr(&o.mesh))
                .or_insert_with(|| mesh_hash(&o.mesh));
            let lists = by_key.entry((hash, *own, parts.clone())).or_default();
            // Equal hashes, unequal meshes: a list of their own.
            let same = |l: &Vec<usize>| {
                let m = &scene.objects[l[0]].mesh;
                std::sync::Arc::ptr_eq(m, &o.mesh) || **m == *o.mesh
            };
            match lists.iter_mut().find(|l| same(l)) {
                Some(l) => l.push(i),
                None => lists.push(vec![i]),
            }
        }
        let mut groups: Vec<Vec<usize>> = by_key
            .into_values()
            .flatten()
            .filter(|l| l.len() > 1)
            .collect();
        groups.sort_unstable_by_key(|l| l[0]);
        let mut group = vec![None; scene.objects.len()];
        for (g, l) in groups.iter().enumerate() {
            for &i in l {
                group[i] = Some(g);
            }
        }
        SharedMeshes {
            group,
            first: vec![None; groups.len()],
        }
    }

    /// The group of object `index`, if it shares its mesh (none when made from no scene).
    pub(super) fn group(&self, index: usize) -> Option<usize> {
        self.group.get(index).copied().flatten()
    }

    /// Distinct shared meshes.
    pub(super) fn meshes(&self) -> usize {
        self.first.len()
    }
}

/// Whether `o` may be drawn from a shared mesh.
fn instanceable(o: &ObjectInput) -> bool {
    o.material.terrain.is_none()
        && o.mesh.pieces.is_empty()
        && !o.mesh.indices.is_empty()
        && is_similarity(o.transform)
}

/// A hash of everything the upload reads of `m`: its words mixed FNV-style (equal hashes
/// are checked by comparing the meshes; a SipHash of every float took a tenth of a debug
/// build's load of a town of 10,000).
fn mesh_hash(m: &TriMesh) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut mix = |words: &[u32]| {
        h = (h ^ words.len() as u64).wrapping_mul(0x0100_0000_01b3);
        for &w in words {
            h = (h ^ u64::from(w)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    mix(bytemuck::cast_slice(&m.positions));
    mix(bytemuck::cast_slice(&m.normals));
    mix(bytemuck::cast_slice(&m.uvs));
    mix(bytemuck::cast_slice(&m.colors));
    mix(&m.indices);
    mix(&m
        .parts
        .iter()
        .map(|p| p.first_triangle)
        .collect::<Vec<u32>>());
    h
}

impl Meshes {
    /// Adds object `index` of `scene`, which shares its mesh (group `g`), with surfaces
    /// `(own, parts)`: the mesh's vertices in object space the first time the group is met,
    /// then the object's record, instance record and draw ranges (its shadows are its
    /// shape's: `gpu_scene/shapes.rs`). Returns its instance record's index.
    pub(super) fn add_instance(
        &mut self,
        scene: &SceneInput,
        index: usize,
        g: usize,
        shared: &mut SharedMeshes,
        (own, parts): (u32, &[u32]),
    ) -> u32 {
        let o = &scene.objects[index];
        let first = match shared.first[g] {
            Some(first) => first,
            None => {
                let first = self.base + self.vertices.len() as u32;
                let local = ObjectInput {
                    transform: glam::Mat4::IDENTITY,
                    ..o.clone()
                };
                let ranges = self.ranges.len();
                self.add_triangles(&ObjectTriangles {
                    object: &local,
                    index: index as u32,
                    own,
                    part_surfaces: parts,
                    plain_terrain: false,
                    casts: false,
                    moving: false,
                });
                self.ranges.truncate(ranges);
                shared.first[g] = Some(first);
                first
            }
        };
        self.objects.push(object_record(o, 0, None));
        let instance = self.instances.len() as u32;
        self.instances
            .push(GpuInstance::new(o.transform, index as u32));
        self.add_instance_ranges(o, first, instance);
        instance
    }

    /// The draw ranges of `o` drawn as instance `instance` of the shared vertices from
    /// `first` on, bounded by its triangles in world space, as its own vertices would be
    /// (its shadows are its mesh's tree's, under the top level).
    pub(super) fn add_instance_ranges(&mut self, o: &ObjectInput, first: u32, instance: u32) {
        let order = if o.transform.determinant() < 0.0 {
            [0, 2, 1]
        } else {
            [0, 1, 2]
        };
        for (t, tri) in o.mesh.indices.chunks_exact(3).enumerate() {
            let t = t as u32;
            if t.is_multiple_of(RANGE_TRIANGLES) {
                self.ranges.push(DrawRange {
                    first: first + 3 * t,
                    count: 0,
                    min: Vec3::splat(f32::INFINITY),
                    max: Vec3::splat(f32::NEG_INFINITY),
                    lod: 0,
                    max_lod: 0,
                    spacing: 0.0,
                    terrain: false,
                    instance,
                });
            }
            let world: [Vec3; 3] = order.map(|c| {
                o.transform
                    .transform_point3(o.mesh.positions[tri[c] as usize])
            });
            if let Some(r) = self.ranges.last_mut() {
                r.count += 3;
                for p in world {
                    r.min = r.min.min(p);
                    r.max = r.max.max(p);
                }
            }
        }
    }
}
