//! The scene on the GPU: one vertex buffer of world-space triangles (meshes are static, so
//! they are transformed once at upload), one record per object (material and entity id),
//! the textures (`textures`: one atlas, a record per image, a record per distinct surface),
//! the lights, and the shadow BVH: a flat tree over the shadow-casting triangles, and one
//! tree per shape that many still casters share under a top level over them
//! (`gpu_scene/shapes.rs`; a mesh several objects share is also drawn from one copy,
//! `gpu_scene/instances.rs`). The upload itself, one step per resource, is
//! `gpu_scene/upload.rs`; the draw ranges, their culling and terrain levels of detail are
//! `gpu_scene/ranges.rs`.

use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Vec3};

use crate::bvh::BvhNode;
use crate::textures::{AtlasError, GpuTextures};

mod instances;
pub mod light_grid;
mod range_index;
mod ranges;
pub mod shapes;
#[cfg(test)]
mod tests;
mod update;
mod upload;

pub use update::{InPlaceEdit, NotInPlace};

pub use range_index::RangeIndex;
pub use ranges::{
    CaptureCull, DRAW_MIN_TEXELS, DrawRange, EYE_LOD_SAMPLE_TEXELS, LOD_SAMPLE_TEXELS, LodFrom,
    RANGE_TRIANGLES, Run, chunk_lod, full_detail_runs, spans_a_texel, visible_runs,
    visible_runs_by_kind, visible_runs_where,
};

/// Choices of an upload that tests and measurements compare against ([`GpuScene::upload_with`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Upload {
    /// A mesh several still objects share is uploaded once and instanced (else every copy
    /// is written out in world space).
    pub instancing: bool,
    /// The shade pass traces only the point lights near a texel ([`light_grid`]; else every
    /// light, each found out of reach or not).
    pub light_grid: bool,
}

impl Default for Upload {
    fn default() -> Self {
        Upload {
            instancing: true,
            light_grid: true,
        }
    }
}

/// Largest number of directional lights the shade pass reads.
pub const MAX_SUNS: usize = 4;

/// One capture vertex (68 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct Vertex {
    /// World position.
    pub position: [f32; 3],
    /// Index into the object buffer.
    pub object: u32,
    /// World normal.
    pub normal: [f32; 3],
    /// Vertex colour, RGBA8 (linear), multiplied into the albedo.
    pub colour: u32,
    /// Texture coordinates (before the surface's UV scale).
    pub uv: [f32; 2],
    /// Index of the surface's textures (`textures::GpuSurface`; 0 = none).
    pub surface: u32,
    /// World-space gradient of the triangle's U (the same on its three vertices): with
    /// [`Vertex::grad_v`], the UV footprint of any probe texel or pixel follows from its
    /// world footprint, without screen derivatives (which some rasterizers get wrong in
    /// quads that straddle a triangle edge), and it is the normal map's tangent frame.
    pub grad_u: [f32; 3],
    /// World-space gradient of the triangle's V.
    pub grad_v: [f32; 3],
}

/// One draw's placement of a mesh (80 bytes; the per-instance vertex attributes of
/// `lib/raster.wgsl` `SceneInstance`). Record 0 is the identity, for vertices written in
/// world space (each carries its object); a mesh several still objects share is uploaded
/// once in object space and drawn once per object with that object's record.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuInstance {
    /// Object → world, columns. Only similarities (rotation, mirror, uniform scale and
    /// translation) are instanced, so it also carries normals and UV gradients (divided by
    /// the squared scale).
    pub model: [[f32; 4]; 4],
    /// The object's index; [`GpuInstance::WORLD`]'s is `u32::MAX`: the vertex's own.
    pub object: u32,
    /// Padding.
    pub _pad: [u32; 3],
}

impl GpuInstance {
    /// The identity record: the vertices are in world space and name their objects.
    pub const WORLD: GpuInstance = GpuInstance {
        model: [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
        object: u32::MAX,
        _pad: [0; 3],
    };

    /// Object `object` placed by `model`.
    pub fn new(model: glam::Mat4, object: u32) -> Self {
        GpuInstance {
            model: model.to_cols_array_2d(),
            object,
            _pad: [0; 3],
        }
    }
}

/// Whether `m` is a similarity whose normals and UV gradients an instance may carry: an
/// affine map whose linear part has orthogonal columns of one length (within 1e-5).
pub fn is_similarity(m: glam::Mat4) -> bool {
    let row3 = m.row(3);
    if !m.is_finite() || row3 != glam::Vec4::W {
        return false;
    }
    let (a, b, c) = (
        m.x_axis.truncate(),
        m.y_axis.truncate(),
        m.z_axis.truncate(),
    );
    let s2 = a.length_squared();
    let close = |x: f32, y: f32| (x - y).abs() <= 1e-5 * s2;
    s2 > 1e-12
        && close(b.length_squared(), s2)
        && close(c.length_squared(), s2)
        && close(a.dot(b), 0.0)
        && close(a.dot(c), 0.0)
        && close(b.dot(c), 0.0)
}

/// World bounds of an object-space box under `m`.
pub(crate) fn transform_bounds(m: glam::Mat4, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        );
        let p = m.transform_point3(c);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    (lo, hi)
}
/// One object's material and id (48 bytes; `shaders/lib/common.wgsl` `Object`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuObject {
    /// Linear albedo.
    pub albedo: [f32; 3],
    /// Bit 0: outlined; bit 1: emissive (drawn unlit); bit 2: a terrain, whose index is in
    /// bits 8..32 (only the low 8 bits reach the albedo target's alpha).
    pub flags: u32,
    /// Linear emissive colour.
    pub emissive: [f32; 3],
    /// Entity id (non-zero).
    pub id: u32,
    /// The highlight's strength (0: none) and shininess; two words of padding.
    pub specular: [f32; 4],
}

/// A point light (32 bytes; WGSL `PointLight`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuPointLight {
    /// World position.
    pub position: [f32; 3],
    /// Fade-out radius.
    pub radius: f32,
    /// Colour × intensity.
    pub colour: [f32; 4],
}

/// Object flag: outlines are drawn on it.
pub const FLAG_OUTLINED: u32 = 1;
/// Object flag: drawn unlit with its emissive colour.
pub const FLAG_EMISSIVE: u32 = 2;
/// Object flag: coloured as the terrain whose index is `flags >> 8`.
pub const FLAG_TERRAIN: u32 = 4;
/// Object flag: animated (drawn by the moving pass, never captured); its motion record's
/// index is in bits 8..32.
pub const FLAG_ANIMATED: u32 = 8;
/// Object flag: its triangles are in the static BVH (it casts shadows and is not animated),
/// so rays can find its silhouette's edges (`shaders/shade.wgsl`, the edge search).
pub const FLAG_IN_BVH: u32 = 16;

/// One animated object's pose this frame (272 bytes; WGSL `Motion` in `shaders/moving.wgsl`,
/// also read by `gbuffer.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuMotion {
    /// Base-pose world → world now.
    pub to_now: [[f32; 4]; 4],
    /// Its normal matrix (upper 3×3).
    pub normal_now: [[f32; 4]; 4],
    /// Base-pose world → the object's rigid frame.
    pub frame: [[f32; 4]; 4],
    /// The rigid frame → base-pose world.
    pub frame_inv: [[f32; 4]; 4],
    /// Bounds centre in base-pose world (xyz).
    pub centre: [f32; 4],
}

/// An animated object's shadow-casting tree where the object is now (112 bytes; WGSL
/// `BvhInstance` in `shaders/lib/bvh.wgsl`): shadow rays in world space are carried into the
/// base pose and traverse the tree built there, so a moving object's shadow moves without a
/// rebuild.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuBvhInstance {
    /// World now → base-pose world.
    pub from_now: [[f32; 4]; 4],
    /// World bounds now (xyz).
    pub min: [f32; 4],
    /// World bounds now (xyz).
    pub max: [f32; 4],
    /// Root node of its tree in the scene's BVH buffers; `u32::MAX`: casts no shadow.
    pub root: u32,
    /// Padding.
    pub _pad: [u32; 3],
}

impl GpuBvhInstance {
    /// The record of no tree (every ray misses it).
    pub const NONE: GpuBvhInstance = GpuBvhInstance {
        from_now: [[0.0; 4]; 4],
        min: [0.0; 4],
        max: [0.0; 4],
        root: u32::MAX,
        _pad: [0; 3],
    };
}

/// An animated object as uploaded: where its vertices are and how its poses map onto them.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimatedObject {
    /// Index into the scene's objects.
    pub object: usize,
    /// Its base transform (object → world), the pose its vertices were uploaded at.
    pub base: glam::Mat4,
    /// Base-pose world → its rigid frame (the base transform's rotation and translation,
    /// inverted; scale is left in the world units the cells are measured in).
    pub frame: glam::Mat4,
    /// Bounds centre, base-pose world.
    pub centre: Vec3,
    /// Bounds, base-pose world.
    pub min: Vec3,
    /// Bounds, base-pose world.
    pub max: Vec3,
    /// Root of its shadow tree in the scene's BVH buffers (`u32::MAX`: casts no shadow).
    pub bvh_root: u32,
    /// Vertex runs `(first, count)`.
    pub runs: Vec<(u32, u32)>,
}

impl AnimatedObject {
    /// Its shadow tree's record for `transform` (object → world now).
    pub fn instance(&self, transform: glam::Mat4) -> GpuBvhInstance {
        if self.bvh_root == u32::MAX {
            return GpuBvhInstance::NONE;
        }
        let to_now = transform * self.base.inverse();
        let (min, max) = transform_bounds(to_now, self.min, self.max);
        GpuBvhInstance {
            from_now: to_now.inverse().to_cols_array_2d(),
            min: min.extend(0.0).to_array(),
            max: max.extend(0.0).to_array(),
            root: self.bvh_root,
            _pad: [0; 3],
        }
    }

    /// Its motion record for `transform` (object → world now).
    pub fn motion(&self, transform: glam::Mat4) -> GpuMotion {
        let to_now = transform * self.base.inverse();
        let normal = glam::Mat4::from_mat3(Mat3::from_mat4(to_now).inverse().transpose());
        GpuMotion {
            to_now: to_now.to_cols_array_2d(),
            normal_now: normal.to_cols_array_2d(),
            frame: self.frame.to_cols_array_2d(),
            frame_inv: self.frame.inverse().to_cols_array_2d(),
            centre: self.centre.extend(1.0).to_array(),
        }
    }
}

/// One terrain's colouring (80 bytes; WGSL `Terrain` in `lib/terrain.wgsl`); its heights and
/// gradient live in the shared `terrain_data` buffer.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTerrain {
    /// World position of sample (0, 0) at height 0.
    pub corner: [f32; 3],
    /// Height of normalised elevation 1.
    pub max_height: f32,
    /// World extent X, Z.
    pub size: [f32; 2],
    /// Samples along X, Z.
    pub samples: [u32; 2],
    /// First height in `terrain_data`.
    pub heights_at: u32,
    /// First gradient stop in `terrain_data` (4 floats each: at, r, g, b).
    pub gradient_at: u32,
    /// Number of stops.
    pub gradient_len: u32,
    /// Displacement texture record, or `textures::NO_TEXTURE`.
    pub displacement: u32,
    /// Displacement strength.
    pub strength: f32,
    /// Displacement tile size, world units.
    pub tile_size: f32,
    /// Pixels per world unit in band 0.
    pub pixel_density: f32,
    /// Distance of band 0.
    pub band_distance: f32,
    /// Transition share of a band.
    pub band_transition: f32,
    /// Paint layer texture record, or `textures::NO_TEXTURE`.
    pub paint: u32,
    /// Padding.
    pub _pad: [u32; 2],
}

/// Why a scene does not fit the device.
#[derive(Debug, thiserror::Error)]
pub enum UploadError {
    /// The textures.
    #[error(transparent)]
    Atlas(#[from] AtlasError),
    /// The sprites' sheets.
    #[error(transparent)]
    Sprites(#[from] crate::gpu_sprites::SpriteError),
}

/// The uploaded scene.
pub struct GpuScene {
    /// Capture vertices.
    pub vertices: wgpu::Buffer,
    /// Number of vertices (non-indexed triangle list).
    pub vertex_count: u32,
    /// Instance records ([`GpuInstance`]; record 0 the identity), the second vertex buffer.
    pub instances: wgpu::Buffer,
    /// Objects drawn from a shared mesh, and the distinct meshes they share.
    pub instanced: (usize, usize),
    /// Whether the point lights' grid lists the lights near each cell (else one cell lists
    /// them all: [`Upload::light_grid`]).
    pub light_grid: bool,
    /// Object records.
    pub objects: wgpu::Buffer,
    /// Point lights (at least one record; `point_count` says how many are real), then the
    /// grid of which reach where ([`light_grid`]).
    pub points: wgpu::Buffer,
    /// Number of point lights.
    pub point_count: u32,
    /// Directional lights, `(direction toward the light, colour)`.
    pub suns: Vec<(Vec3, Vec3)>,
    /// Shadow BVH nodes.
    pub bvh_nodes: wgpu::Buffer,
    /// Shadow BVH triangles.
    pub bvh_triangles: wgpu::Buffer,
    /// Shadow-casting triangles in the BVH.
    pub shadow_triangles: usize,
    /// Entity id of each object, by object index.
    pub object_ids: Vec<u32>,
    /// The textures.
    pub textures: GpuTextures,
    /// Consecutive runs of at most [`RANGE_TRIANGLES`] triangles of one object with their
    /// world bounds: a raster draws only the ranges its frustum meets.
    pub ranges: Vec<DrawRange>,
    /// Animated objects' shadow trees where they are now: a header (its `root` the top-level
    /// tree's root, or none), then one record per caster in the top-level tree's order.
    pub bvh_instances: wgpu::Buffer,
    /// Where the animated casters' top-level tree's nodes start in `bvh_nodes`.
    pub tlas_root: u32,
    /// The still instances' top level, as the header carries it: `[records, root]`
    /// (`[0, 0]`: none; `bvh::instances`).
    pub static_top: [u32; 2],
    /// Where the point lights' own caster trees start in `bvh_nodes`
    /// (`light_grid::caster_nodes`).
    pub caster_nodes_at: u32,
    /// Animated objects' motion records, one per [`GpuScene::animated`] (at least one).
    pub motions: wgpu::Buffer,
    /// The animated objects, in motion record order.
    pub animated: Vec<AnimatedObject>,
    /// Terrain records (at least one).
    pub terrains: wgpu::Buffer,
    /// Terrains in the scene (records in use).
    pub terrain_count: usize,
    /// The sprites, if the scene has any.
    pub sprites: Option<crate::gpu_sprites::GpuSprites>,
    /// Terrain heights and gradient stops (at least one word).
    pub terrain_data: wgpu::Buffer,
    /// The shadow-casting terrains walked as heightfields: their records
    /// ([`crate::bvh::field::GpuFields`]) and data (`r32float`, a flat list).
    pub bvh_fields: wgpu::Buffer,
    /// View of the fields' data texture.
    pub field_data: wgpu::TextureView,
    /// Terrains walked as heightfields by the shadow rays.
    pub shadow_fields: usize,
    /// Where each animated shadow caster stands ([`GpuScene::casters`]).
    casters: std::sync::Mutex<Vec<CasterNow>>,
    /// The scene's lights and lowest point, for where a moved caster's shadow may fall.
    pub shadow_lights: crate::shadow_region::ShadowLights,
    /// Where each object's vertices, ranges and casters lie, and the shadow tree's CPU copy:
    /// what an edit made in place needs ([`GpuScene::update_objects`]).
    edits: update::InPlace,
}

/// Where an animated shadow caster stands ([`GpuScene::casters`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CasterNow {
    /// A hash of its instance record (its pose and bounds).
    pub key: u64,
    /// World bounds now.
    pub min: Vec3,
    /// World bounds now.
    pub max: Vec3,
}

impl GpuScene {
    /// GPU bytes of the scene, its shadow trees and its textures (the probes are the
    /// renderer's: [`crate::probe_store::ProbeStore::bytes`]).
    pub fn memory(&self) -> crate::memory::GpuMemory {
        use crate::memory::{buffer_bytes, texture_bytes};
        let sprites = self.sprites.as_ref().map_or(0, |s| {
            texture_bytes(&s.frames) + buffer_bytes(&[&s.records, &s.lit, &s.lit_keys])
        });
        crate::memory::GpuMemory {
            scene: buffer_bytes(&[
                &self.vertices,
                &self.instances,
                &self.objects,
                &self.points,
                &self.motions,
                &self.terrains,
                &self.terrain_data,
                &self.textures.surfaces,
            ]),
            bvh: buffer_bytes(&[
                &self.bvh_nodes,
                &self.bvh_triangles,
                &self.bvh_instances,
                &self.bvh_fields,
            ]) + texture_bytes(self.field_data.texture()),
            textures: self.textures.bytes() + sprites,
            probes: 0,
        }
    }

    /// What the shadow BVH group binds ([`crate::passes::bvh_layout`]).
    pub fn bvh_resources(&self) -> [wgpu::BindingResource<'_>; 5] {
        [
            self.bvh_nodes.as_entire_binding(),
            self.bvh_triangles.as_entire_binding(),
            self.bvh_instances.as_entire_binding(),
            self.bvh_fields.as_entire_binding(),
            wgpu::BindingResource::TextureView(&self.field_data),
        ]
    }

    /// Moves the animated objects to `poses` (the others to their base transforms).
    pub fn set_poses(&self, queue: &wgpu::Queue, poses: &[crate::input::Pose]) {
        if self.animated.is_empty() {
            return;
        }
        let transforms: Vec<glam::Mat4> = self
            .animated
            .iter()
            .map(|a| {
                let pose = poses.iter().rev().find(|p| p.object == a.object);
                pose.map(|p| p.transform)
                    .filter(|m| m.is_finite() && m.determinant().abs() > 1e-12)
                    .unwrap_or(a.base)
            })
            .collect();
        let records: Vec<GpuMotion> = (self.animated.iter().zip(&transforms))
            .map(|(a, &m)| a.motion(m))
            .collect();
        queue.write_buffer(&self.motions, 0, bytemuck::cast_slice(&records));
        // The casters where they are now, under a top-level tree over their bounds (so a
        // shadow ray tests the few whose boxes it meets, not every one), behind a header.
        let casting: Vec<GpuBvhInstance> = (self.animated.iter().zip(&transforms))
            .map(|(a, &m)| a.instance(m))
            .filter(|i| i.root != u32::MAX)
            .collect();
        let bounds: Vec<(Vec3, Vec3)> = (casting.iter())
            .map(|i| (Vec3::from_slice(&i.min[..3]), Vec3::from_slice(&i.max[..3])))
            .collect();
        let (nodes, order) = crate::bvh::build_tlas(&bounds, self.tlas_root, 1);
        let mut header = GpuBvhInstance::NONE;
        header._pad[..2].copy_from_slice(&self.static_top);
        if !nodes.is_empty() {
            header.root = self.tlas_root;
            let offset = u64::from(self.tlas_root) * size_of::<BvhNode>() as u64;
            queue.write_buffer(&self.bvh_nodes, offset, bytemuck::cast_slice(&nodes));
        }
        // Animated casters have records 1..; the still instances' follow theirs, untouched.
        let records: Vec<GpuBvhInstance> = std::iter::once(header)
            .chain(order.iter().map(|&k| casting[k as usize]))
            .collect();
        queue.write_buffer(&self.bvh_instances, 0, bytemuck::cast_slice(&records));
        let casters = casting
            .iter()
            .map(|i| {
                use std::hash::{Hash, Hasher};
                let mut h = std::collections::hash_map::DefaultHasher::new();
                bytemuck::bytes_of(i).hash(&mut h);
                CasterNow {
                    key: h.finish(),
                    min: Vec3::from_slice(&i.min[..3]),
                    max: Vec3::from_slice(&i.max[..3]),
                }
            })
            .collect();
        *self.casters.lock().unwrap_or_else(|e| e.into_inner()) = casters;
    }

    /// Where the animated shadow casters stand, in a fixed order (empty for a scene without
    /// them): what a shadow cast through the BVH depends on beyond the scene.
    pub fn casters(&self) -> Vec<CasterNow> {
        self.casters
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// Where sprites' indices start in the keys of their pixels (after the objects).
    pub fn sprite_key_base(&self) -> u32 {
        (self.object_ids.len() - self.sprites.as_ref().map_or(0, |s| s.cpu.len())) as u32
    }

    /// Every animated object's vertex runs.
    pub fn animated_runs(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.animated.iter().flat_map(|a| a.runs.iter().copied())
    }

    /// What every scene raster (capture, G-buffer) binds after its own uniform, bindings
    /// 1..=6 of `lib/raster.wgsl`'s includers: objects, the texture atlas, its records, the
    /// surfaces, the terrains and their data ([`crate::passes::raster::scene_layout_entries`]).
    pub fn raster_resources(&self) -> [wgpu::BindingResource<'_>; 6] {
        [
            self.objects.as_entire_binding(),
            wgpu::BindingResource::TextureView(&self.textures.view),
            self.textures.infos_buffer.as_entire_binding(),
            self.textures.surfaces.as_entire_binding(),
            self.terrains.as_entire_binding(),
            self.terrain_data.as_entire_binding(),
        ]
    }

    /// The vertex buffer's point and object index alone (locations 0 and 1), for a vertex
    /// stage that needs nothing else (`shaders/capture.wgsl` `vs_terrain`).
    pub fn point_vertex_layout() -> wgpu::VertexBufferLayout<'static> {
        const ATTRS: [wgpu::VertexAttribute; 2] =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Uint32];
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &ATTRS,
        }
    }

    /// The per-instance layout of [`GpuInstance`] (locations 8..=12: the model matrix's
    /// columns, the object), the scene rasters' second vertex buffer.
    pub fn instance_layout() -> wgpu::VertexBufferLayout<'static> {
        const ATTRS: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
            8 => Float32x4, 9 => Float32x4, 10 => Float32x4, 11 => Float32x4, 12 => Uint32
        ];
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<GpuInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &ATTRS,
        }
    }

    /// The vertex layout of [`Vertex`].
    pub fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
        const ATTRS: [wgpu::VertexAttribute; 8] = wgpu::vertex_attr_array![
            0 => Float32x3, 1 => Uint32, 2 => Float32x3, 3 => Uint32, 4 => Float32x2, 5 => Uint32,
            6 => Float32x3, 7 => Float32x3
        ];
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &ATTRS,
        }
    }
}
