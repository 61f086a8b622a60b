//! [`GpuScene::upload`], one step per resource: the animated objects, then per object its
//! record, surfaces, draw ranges, vertices and shadow casters ([`Meshes`]); the motion
//! records, the point lights and suns, the terrain records, the textures, the sprites, the
//! shadow trees ([`ShadowTrees`]), the heightfields, and last the buffers.

use bytemuck::Zeroable;
use glam::{Mat3, Vec3};
use texel_geom::mesh::LodPiece;
use wgpu::util::DeviceExt;

use super::ranges::{DrawRange, RANGE_TRIANGLES, merge_runs};
use super::shapes::ShadowShapes;
use super::update::{InPlace, ObjectSlot};
use super::{
    AnimatedObject, FLAG_ANIMATED, FLAG_EMISSIVE, FLAG_IN_BVH, FLAG_OUTLINED, FLAG_TERRAIN,
    GpuBvhInstance, GpuInstance, GpuMotion, GpuObject, GpuPointLight, GpuScene, GpuTerrain,
    MAX_SUNS, UploadError, Vertex, transform_bounds,
};
use crate::bvh::instances::{TopLevel, instance_record};
use crate::bvh::{BvhNode, GpuBvh, build_bvh};
use crate::context::GpuContext;
use crate::input::{ObjectInput, SceneInput};
use crate::textures::{NO_TEXTURE, TextureSet};

impl GpuScene {
    /// Uploads `scene`: a mesh several still objects share once, in object space, with an
    /// instance record per object (`gpu_scene/instances.rs`), every other mesh transformed
    /// to world space; packs the textures and builds the shadow trees. Fails only when the
    /// textures do not fit the device's limits.
    pub fn upload(ctx: &GpuContext, scene: &SceneInput) -> Result<GpuScene, UploadError> {
        Self::upload_with(ctx, scene, super::Upload::default())
    }

    /// [`GpuScene::upload`] with the choices tests and measurements compare against.
    pub fn upload_with(
        ctx: &GpuContext,
        scene: &SceneInput,
        choices: super::Upload,
    ) -> Result<GpuScene, UploadError> {
        let shapes = ShadowShapes::new(scene, choices.instancing);
        Self::upload_shaped(ctx, scene, choices, shapes)
    }

    /// [`GpuScene::upload_with`], the still casters' shapes found already (`shapes`, of
    /// `scene`: [`ShadowShapes::new`]).
    pub fn upload_shaped(
        ctx: &GpuContext,
        scene: &SceneInput,
        choices: super::Upload,
        shapes: ShadowShapes,
    ) -> Result<GpuScene, UploadError> {
        let mut textures = TextureSet::default();
        let mut meshes = Meshes::new(scene);
        // Surfaces first, in object order (the atlas is laid out as they come), then which
        // still objects share a mesh.
        let surfaces: Vec<(u32, Vec<u32>)> = (scene.objects.iter())
            .map(|o| surfaces(o, &mut textures))
            .collect();
        let mut shared = match choices.instancing {
            true => super::instances::SharedMeshes::new(scene, &meshes.animated_index, &surfaces),
            false => super::instances::SharedMeshes::new(&SceneInput::default(), &[], &[]),
        };
        let mut slots = Vec::with_capacity(scene.objects.len());
        for (index, (own, parts)) in surfaces.into_iter().enumerate() {
            let before = meshes.mark();
            let o = &scene.objects[index];
            let instance = match shared.group(index) {
                Some(g) => Some(meshes.add_instance(scene, index, g, &mut shared, (own, &parts))),
                None => {
                    meshes.add_object(scene, index, (own, &parts), shapes.shared(index));
                    None
                }
            };
            meshes.add_shadow(o, index, instance.is_some(), &shapes);
            let fixed = meshes.animated_index[index].is_some() || o.material.terrain.is_some();
            slots.push(ObjectSlot::new(
                o,
                (before, meshes.mark()),
                (own, parts),
                fixed,
                instance,
            ));
        }
        let motions = motion_records(&meshes.animated);
        let vertex_count = meshes.vertices.len() as u32;
        meshes.pad();
        let (points, point_count) = point_lights(scene);
        let suns = suns(scene);
        let (gpu_terrains, terrain_data) = terrain_records(scene, &mut textures);
        let textures = textures.upload(ctx)?;
        // Shadow-casting sprites: frame 0's silhouette, standing toward the first sun.
        let toward_sun = suns_toward(scene);
        for sprite in scene.sprites.iter().filter(|s| s.casts_shadows) {
            (meshes.casters).extend(crate::gpu_sprites::shadow_triangles(sprite, toward_sun));
        }
        let sprites = crate::gpu_sprites::GpuSprites::upload(ctx, &scene.sprites)?;
        let mut trees = ShadowTrees::build(
            &meshes.casters,
            &meshes.animated_casters,
            shapes.triangles(),
            &meshes.casting_instances,
        );
        let static_top = trees.static_top();
        let (lights, caster_nodes_at) =
            light_words_with_casters(&mut trees, &points, point_count, choices.light_grid);
        let bvh_records = trees.record_of(&meshes.casting_objects, scene.objects.len());
        for (&(i, _), &root) in meshes.animated_casters.iter().zip(&trees.animated_roots) {
            meshes.animated[i].bvh_root = root;
        }
        let (bvh_nodes, bvh_triangles) = trees.bvh.upload(&ctx.device);
        let static_casters = meshes.casters.len();
        let (bvh_fields, field_data) = upload_fields(ctx, scene, &meshes.cast_fields);
        let storage = |label, contents: &[u8], usage| {
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage,
                })
        };
        let writable = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let read_only = wgpu::BufferUsages::STORAGE;
        let gpu = GpuScene {
            vertices: storage(
                "scene::vertices",
                bytemuck::cast_slice(&meshes.vertices),
                wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            ),
            vertex_count,
            instances: storage(
                "scene::instances",
                bytemuck::cast_slice(&meshes.instances),
                wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            ),
            instanced: (meshes.instances.len() - 1, shared.meshes()),
            light_grid: choices.light_grid,
            objects: storage(
                "scene::objects",
                bytemuck::cast_slice(&meshes.objects),
                writable,
            ),
            points: storage("scene::points", bytemuck::cast_slice(&lights), writable),
            point_count,
            suns,
            bvh_nodes,
            bvh_triangles,
            shadow_triangles: meshes.casters.len(),
            // Sprites after the objects: a sprite pixel's key names `key_base + index`.
            object_ids: (scene.objects.iter().map(|o| o.id))
                .chain(scene.sprites.iter().map(|s| s.id))
                .collect(),
            sprites,
            textures,
            ranges: meshes.ranges,
            bvh_instances: storage(
                "scene::bvh_instances",
                bytemuck::cast_slice(&trees.instances.clone()),
                writable,
            ),
            motions: storage("scene::motions", bytemuck::cast_slice(&motions), writable),
            animated: meshes.animated,
            tlas_root: trees.tlas_root,
            static_top,
            caster_nodes_at,
            casters: std::sync::Mutex::new(Vec::new()),
            shadow_lights: crate::shadow_region::ShadowLights::new(scene),
            terrain_count: scene.terrains.len(),
            terrains: storage(
                "scene::terrains",
                bytemuck::cast_slice(&gpu_terrains),
                read_only,
            ),
            terrain_data: storage(
                "scene::terrain_data",
                bytemuck::cast_slice(&terrain_data),
                read_only,
            ),
            bvh_fields,
            field_data,
            shadow_fields: meshes.cast_fields.len(),
            edits: InPlace::new(slots, trees.bvh, static_casters)
                .with_instances(trees.top, trees.instances.clone(), (bvh_records, shapes))
                .with_records(meshes.objects.clone()),
        };
        // The casters at their base poses until a frame says otherwise.
        gpu.set_poses(&ctx.queue, &[]);
        Ok(gpu)
    }
}

/// The lights' words (`light_grid::light_words`) with each point light's caster root, its
/// trees appended after `trees`' nodes (`light_grid::caster_nodes`); and where they start.
fn light_words_with_casters(
    trees: &mut ShadowTrees,
    points: &[GpuPointLight],
    point_count: u32,
    light_grid: bool,
) -> (Vec<u32>, u32) {
    let at = trees.bvh.nodes.len() as u32;
    let (roots, nodes) =
        super::light_grid::caster_nodes(points, point_count, trees.top.as_ref(), at);
    trees.bvh.nodes.extend(nodes);
    let words = super::light_grid::light_words(points, point_count, light_grid, &roots);
    (words, at)
}

/// Every object's vertices, draw ranges, record and shadow casters, as the upload walks the
/// scene's objects in order.
pub(super) struct Meshes {
    /// Index of the first of `vertices` in the scene's vertex buffer (0 but when one
    /// object's vertices are made again: [`Meshes::one`]).
    pub(super) base: u32,
    /// Capture vertices, world space.
    pub(super) vertices: Vec<Vertex>,
    /// Draw ranges of the captured (not animated) objects.
    pub(super) ranges: Vec<DrawRange>,
    /// One record per object.
    pub(super) objects: Vec<GpuObject>,
    /// Instance records: the identity, then one per object drawn from a shared mesh.
    pub(super) instances: Vec<GpuInstance>,
    /// The static shadow casters' triangles (world space).
    pub(super) casters: Vec<[Vec3; 3]>,
    /// Motion record index of each animated object (terrains never move).
    pub(super) animated_index: Vec<Option<u32>>,
    /// The animated objects, in motion record order.
    animated: Vec<AnimatedObject>,
    /// Each still object casting through a shape ([`ShadowShapes`]): its shape and
    /// placement, and its object.
    pub(super) casting_instances: Vec<(usize, glam::Mat4)>,
    pub(super) casting_objects: Vec<usize>,
    /// Each animated caster's triangles in its base pose, by index into `animated`.
    animated_casters: Vec<(usize, Vec<[Vec3; 3]>)>,
    /// Terrains whose shadows and edge rays walk their heights rather than triangles.
    walked: Vec<bool>,
    /// The walked terrains that cast shadows.
    cast_fields: Vec<usize>,
}

/// What the triangle walk needs of one object besides its mesh.
pub(super) struct ObjectTriangles<'a> {
    /// The object.
    pub(super) object: &'a ObjectInput,
    /// Its index in the scene.
    pub(super) index: u32,
    /// The surface of triangles before its mesh's first part.
    pub(super) own: u32,
    /// The surface of each of its mesh's parts.
    pub(super) part_surfaces: &'a [u32],
    /// Its surface comes from the heightmap alone (no texture, no normal map).
    pub(super) plain_terrain: bool,
    /// Its full-detail triangles cast shadows through the BVH.
    pub(super) casts: bool,
    /// It is animated: its casters go into a tree of its own.
    pub(super) moving: bool,
}

impl Meshes {
    /// Empty lists, with the animated objects of `scene` known (their poses to come).
    fn new(scene: &SceneInput) -> Self {
        let (animated_index, animated) = animated_objects(scene);
        Meshes {
            base: 0,
            vertices: Vec::new(),
            ranges: Vec::new(),
            objects: Vec::with_capacity(scene.objects.len().max(1)),
            instances: vec![GpuInstance::WORLD],
            casters: Vec::new(),
            animated_index,
            animated,
            casting_instances: Vec::new(),
            casting_objects: Vec::new(),
            animated_casters: Vec::new(),
            walked: crate::bvh::field::walked_terrains(&scene.terrains),
            cast_fields: Vec::new(),
        }
    }

    /// Empty lists for one still object's vertices, the first of them at `base` in the
    /// scene's vertex buffer (an edit made in place: `gpu_scene::update`).
    pub(super) fn one(base: u32) -> Self {
        Meshes {
            base,
            vertices: Vec::new(),
            ranges: Vec::new(),
            objects: Vec::new(),
            instances: Vec::new(),
            casters: Vec::new(),
            animated_index: Vec::new(),
            animated: Vec::new(),
            casting_instances: Vec::new(),
            casting_objects: Vec::new(),
            animated_casters: Vec::new(),
            walked: Vec::new(),
            cast_fields: Vec::new(),
        }
    }

    /// How many vertices, draw ranges and static casters there are so far.
    fn mark(&self) -> [u32; 3] {
        [self.vertices.len(), self.ranges.len(), self.casters.len()].map(|n| n as u32)
    }

    /// Adds object `index` of `scene` with its surfaces `(own, parts)`: its record, its
    /// triangles (its shadow casters too, unless it casts through a shape: `shaped`) and,
    /// for an animated object, its runs and bounds.
    fn add_object(
        &mut self,
        scene: &SceneInput,
        index: usize,
        (own, part_surfaces): (u32, &[u32]),
        shaped: bool,
    ) {
        let o = &scene.objects[index];
        let m = &o.material;
        let terrain = m
            .terrain
            .filter(|&t| t < scene.terrains.len())
            .map_or(0, |t| FLAG_TERRAIN | ((t as u32) << 8));
        let moving = self.animated_index[index].filter(|_| terrain == 0);
        let field = m.terrain.filter(|&t| self.walked.get(t) == Some(&true));
        if let Some(t) = field.filter(|t| m.casts_shadows && !self.cast_fields.contains(t)) {
            self.cast_fields.push(t);
        }
        let ranges_before = self.ranges.len();
        self.objects.push(object_record(o, terrain, moving));
        let own_casters = self.add_triangles(&ObjectTriangles {
            object: o,
            index: index as u32,
            own,
            plain_terrain: terrain != 0 && own == 0 && part_surfaces.iter().all(|&s| s == 0),
            part_surfaces,
            casts: m.casts_shadows && field.is_none() && !shaped,
            moving: moving.is_some(),
        });
        if let Some(i) = moving {
            self.settle_animated(i as usize, ranges_before, own_casters);
        }
    }

    /// Adds the object's triangles (world space) to the vertices, opening a new draw range
    /// at every piece (level of a chunk) and every [`RANGE_TRIANGLES`]; the static casters
    /// go to `casters`, an animated object's are returned.
    pub(super) fn add_triangles(&mut self, ob: &ObjectTriangles) -> Vec<[Vec3; 3]> {
        let o = ob.object;
        let normal_m = Mat3::from_mat4(o.transform).inverse().transpose();
        let order = if o.transform.determinant() < 0.0 {
            [0, 2, 1]
        } else {
            [0, 1, 2]
        };
        let mut own_casters: Vec<[Vec3; 3]> = Vec::new();
        let mut piece = 0usize;
        let mut piece_start = 0u32;
        for (t, tri) in o.mesh.indices.chunks_exact(3).enumerate() {
            let t = t as u32;
            while piece < o.mesh.pieces.len()
                && t >= o.mesh.pieces[piece].first_triangle + o.mesh.pieces[piece].triangles
            {
                piece += 1;
            }
            let lod_piece = o.mesh.pieces.get(piece).filter(|p| t >= p.first_triangle);
            let starts_piece = lod_piece.is_some_and(|p| p.first_triangle == t);
            if starts_piece {
                piece_start = t;
            }
            if starts_piece || (t - piece_start).is_multiple_of(RANGE_TRIANGLES) {
                let first = self.base + self.vertices.len() as u32;
                (self.ranges).push(new_range(o.transform, lod_piece, first, ob.plain_terrain));
            }
            let level0 = lod_piece.is_none_or(|p| p.lod == 0);
            let surface = match o.mesh.parts.partition_point(|p| p.first_triangle <= t) {
                0 => ob.own,
                after => ob.part_surfaces[after - 1],
            };
            let world: [Vec3; 3] = order.map(|c| {
                o.transform
                    .transform_point3(o.mesh.positions[tri[c] as usize])
            });
            self.push_triangle(ob, tri, order, world, surface, normal_m);
            if ob.casts && level0 {
                match ob.moving {
                    false => self.casters.push(world),
                    true => own_casters.push(world),
                }
            }
        }
        own_casters
    }

    /// Pushes the three vertices of triangle `tri` of the object (at `world`, corners in `order`)
    /// and grows the last range's bounds around them (unless it is a chunk's, bounded by
    /// its piece).
    fn push_triangle(
        &mut self,
        ob: &ObjectTriangles,
        tri: &[u32],
        order: [usize; 3],
        world: [Vec3; 3],
        surface: u32,
        normal_m: Mat3,
    ) {
        let o = ob.object;
        let (gu, gv) = uv_gradients(world, order.map(|c| o.mesh.uv(tri[c] as usize)));
        if let Some(r) = self.ranges.last_mut() {
            r.count += 3;
            if r.max_lod == 0 {
                for p in world {
                    r.min = r.min.min(p);
                    r.max = r.max.max(p);
                }
            }
        }
        for (k, &c) in order.iter().enumerate() {
            let i = tri[c] as usize;
            let p = world[k];
            let n = (normal_m * o.mesh.normals[i]).normalize_or_zero();
            self.vertices.push(Vertex {
                position: p.to_array(),
                object: ob.index,
                normal: n.to_array(),
                colour: pack_colour(o.mesh.colors.get(i).copied().unwrap_or([1.0; 4])),
                uv: o.mesh.uv(i).to_array(),
                surface,
                grad_u: gu.to_array(),
                grad_v: gv.to_array(),
            });
        }
    }

    /// An animated object's ranges (from `ranges_before` on) are drawn by the moving pass
    /// (and the G-buffer), never by a capture: they become its runs and bounds, and its
    /// casters wait for a tree of their own.
    fn settle_animated(&mut self, i: usize, ranges_before: usize, casters: Vec<[Vec3; 3]>) {
        let own: Vec<DrawRange> = self.ranges.drain(ranges_before..).collect();
        let a = &mut self.animated[i];
        let (lo, hi) = own.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), r| (lo.min(r.min), hi.max(r.max)),
        );
        if lo.cmple(hi).all() {
            a.centre = 0.5 * (lo + hi);
            (a.min, a.max) = (lo, hi);
        }
        a.runs = merge_runs(own.iter()).iter().map(|r| (r.0, r.1)).collect();
        if !casters.is_empty() {
            self.animated_casters.push((i, casters));
        }
    }

    /// At least one object and one vertex, as bindings need.
    fn pad(&mut self) {
        if self.objects.is_empty() {
            self.objects.push(GpuObject::zeroed());
        }
        if self.vertices.is_empty() {
            self.vertices.push(Vertex::zeroed());
        }
    }
}

/// The motion record index of each of `scene`'s objects that is animated (not a terrain),
/// and those objects at their base poses.
fn animated_objects(scene: &SceneInput) -> (Vec<Option<u32>>, Vec<AnimatedObject>) {
    let mut animated_index: Vec<Option<u32>> = vec![None; scene.objects.len()];
    let mut animated: Vec<AnimatedObject> = Vec::new();
    for &i in &scene.animated {
        let terrain = scene.objects.get(i).and_then(|o| o.material.terrain);
        if i < scene.objects.len() && terrain.is_none() && animated_index[i].is_none() {
            animated_index[i] = Some(animated.len() as u32);
            let o = &scene.objects[i];
            let (_, rotation, translation) = o.transform.to_scale_rotation_translation();
            animated.push(AnimatedObject {
                object: i,
                base: o.transform,
                frame: glam::Mat4::from_rotation_translation(rotation, translation).inverse(),
                centre: translation,
                min: translation,
                max: translation,
                bvh_root: u32::MAX,
                runs: Vec::new(),
            });
        }
    }
    (animated_index, animated)
}

/// Object `o`'s record: its material, flags (`terrain`: its terrain flag and index, or 0;
/// `moving`: its motion record) and id.
pub(super) fn object_record(o: &ObjectInput, terrain: u32, moving: Option<u32>) -> GpuObject {
    let m = &o.material;
    let emissive = m.emissive.max_element() > 0.0;
    let animated_flag = moving.map_or(0, |i| FLAG_ANIMATED | (i << 8));
    GpuObject {
        albedo: m.albedo.to_array(),
        flags: u32::from(m.outlined) * FLAG_OUTLINED
            + u32::from(emissive) * FLAG_EMISSIVE
            + terrain
            + animated_flag
            + u32::from(m.casts_shadows && moving.is_none()) * FLAG_IN_BVH,
        emissive: m.emissive.to_array(),
        id: o.id,
        specular: [m.specular.x.max(0.0), m.specular.y.max(1.0), 0.0, 0.0],
    }
}

/// The surface of `o`'s own maps and of each of its mesh's parts (the material's textures
/// win over the mesh's own), added to `textures` in that order.
pub(super) fn surfaces(o: &ObjectInput, textures: &mut TextureSet) -> (u32, Vec<u32>) {
    let m = &o.material;
    let own = textures.surface(&m.maps);
    let mut part_surfaces: Vec<u32> = Vec::with_capacity(o.mesh.parts.len());
    for part in &o.mesh.parts {
        let maps = if m.maps.is_empty() {
            &part.maps
        } else {
            &m.maps
        };
        part_surfaces.push(textures.surface(maps));
    }
    (own, part_surfaces)
}

/// A new, empty draw range starting at vertex `first`: bounded by its piece (a terrain
/// chunk's level, under `transform`), or open until its triangles grow it.
fn new_range(
    transform: glam::Mat4,
    piece: Option<&LodPiece>,
    first: u32,
    plain_terrain: bool,
) -> DrawRange {
    let (lod, max_lod, spacing, min, max) = match piece {
        Some(p) => {
            let (lo, hi) = transform_bounds(transform, p.min, p.max);
            (p.lod, p.max_lod, p.spacing * max_scale(transform), lo, hi)
        }
        None => (
            0,
            0,
            0.0,
            Vec3::splat(f32::INFINITY),
            Vec3::splat(f32::NEG_INFINITY),
        ),
    };
    DrawRange {
        first,
        count: 0,
        min,
        max,
        lod,
        max_lod,
        spacing,
        terrain: plain_terrain,
        instance: 0,
    }
}

/// The animated objects' motion records at their base poses (at least one record).
fn motion_records(animated: &[AnimatedObject]) -> Vec<GpuMotion> {
    if animated.is_empty() {
        vec![GpuMotion::zeroed()]
    } else {
        animated.iter().map(|a| a.motion(a.base)).collect()
    }
}

/// The point lights' records (at least one) and how many are real.
pub(super) fn point_lights(scene: &SceneInput) -> (Vec<GpuPointLight>, u32) {
    let mut points: Vec<GpuPointLight> = scene
        .points
        .iter()
        .map(|p| GpuPointLight {
            position: p.position.to_array(),
            radius: p.radius,
            colour: p.colour.extend(0.0).to_array(),
        })
        .collect();
    let point_count = points.len() as u32;
    if points.is_empty() {
        points.push(GpuPointLight::zeroed());
    }
    (points, point_count)
}

/// The first [`MAX_SUNS`] directional lights as `(direction toward the light, colour)`.
pub(super) fn suns(scene: &SceneInput) -> Vec<(Vec3, Vec3)> {
    scene
        .suns
        .iter()
        .take(MAX_SUNS)
        .map(|s| (-s.direction.normalize_or_zero(), s.colour))
        .collect()
}

/// The shadow BVH: the static casters' tree, each animated caster's own tree after it, each
/// shadow shape's tree (in its own space), room for the animated casters' per-frame
/// top-level tree, and the top-level tree over the still objects casting through shapes.
struct ShadowTrees {
    /// Every tree's nodes and triangles.
    bvh: GpuBvh,
    /// The root of each animated caster's tree, in `animated_casters` order.
    animated_roots: Vec<u32>,
    /// Where the animated casters' top-level tree's nodes start.
    tlas_root: u32,
    /// The instance records: a header, one per animated caster (placed each frame), then
    /// the still instances' in their top-level tree's order.
    instances: Vec<GpuBvhInstance>,
    /// The still instances' top-level tree.
    top: Option<TopLevel>,
}

impl ShadowTrees {
    /// Builds the static tree over `casters`, then each animated caster's own, in its base
    /// pose, then each shape's tree (`shared`: each shape's triangles) that a still object
    /// casting through it (`instances`: its shape and placement) uses, and the top level
    /// over those objects.
    fn build(
        casters: &[[Vec3; 3]],
        animated_casters: &[(usize, Vec<[Vec3; 3]>)],
        shared: &[Vec<[Vec3; 3]>],
        instances: &[(usize, glam::Mat4)],
    ) -> Self {
        let mut bvh: GpuBvh = build_bvh(casters);
        let animated_roots = (animated_casters.iter())
            .map(|(_, tris)| bvh.append(&build_bvh(tris)))
            .collect();
        let mut roots: Vec<Option<u32>> = vec![None; shared.len()];
        let records: Vec<GpuBvhInstance> = (instances.iter())
            .map(|&(g, model)| {
                let root = *roots[g].get_or_insert_with(|| bvh.append(&build_bvh(&shared[g])));
                instance_record(&bvh, root, model)
            })
            .collect();
        // Room after the trees for the per-frame top-level tree over the casters' bounds
        // (fewer than two nodes per caster), and the instance records behind a header.
        let tlas_root = bvh.nodes.len() as u32;
        let casters_n = animated_casters.len();
        bvh.nodes
            .extend(std::iter::repeat_n(BvhNode::zeroed(), 2 * casters_n));
        let bounds: Vec<(Vec3, Vec3)> = (records.iter())
            .map(|r| (Vec3::from_slice(&r.min[..3]), Vec3::from_slice(&r.max[..3])))
            .collect();
        let first_item = 1 + casters_n as u32;
        let top = TopLevel::build(&bounds, bvh.nodes.len() as u32, first_item);
        let mut all = vec![GpuBvhInstance::NONE; 1 + casters_n];
        if let Some(top) = &top {
            bvh.nodes.extend_from_slice(&top.nodes);
            all.extend(top.order.iter().map(|&k| records[k as usize]));
            all[0]._pad[..2].copy_from_slice(&[top.order.len() as u32, top.node_offset]);
        }
        ShadowTrees {
            bvh,
            animated_roots,
            tlas_root,
            instances: all,
            top,
        }
    }

    /// Each of `objects` objects' shadow instance record (`casting`: the object of each
    /// input of the top level), if it is one.
    fn record_of(&self, casting: &[usize], objects: usize) -> Vec<Option<u32>> {
        let mut at = vec![None; objects];
        if let Some(top) = &self.top {
            for (p, &k) in top.order.iter().enumerate() {
                at[casting[k as usize]] = Some(top.first_item + p as u32);
            }
        }
        at
    }

    /// The header's words for the still instances' top level: `[records, root]`.
    fn static_top(&self) -> [u32; 2] {
        self.top
            .as_ref()
            .map_or([0, 0], |t| [t.order.len() as u32, t.node_offset])
    }
}

/// The uniform block of the terrains `cast` (indices into `scene.terrains`, all walkable)
/// and the texture holding their heights and quadtrees.
fn upload_fields(
    ctx: &GpuContext,
    scene: &SceneInput,
    cast: &[usize],
) -> (wgpu::Buffer, wgpu::TextureView) {
    use crate::bvh::field::{self, HeightField};
    let fields: Vec<(usize, HeightField)> = (cast.iter())
        .filter_map(|&i| {
            let t = &scene.terrains[i];
            HeightField::new(t.corner, t.size, t.samples, &t.heights).map(|f| (i, f))
        })
        .collect();
    let (block, data) = field::pack(&fields.iter().map(|(i, f)| (*i, f)).collect::<Vec<_>>());
    let view = field::upload_data(&ctx.device, &ctx.queue, &data);
    let buffer = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene::bvh_fields"),
            contents: bytemuck::bytes_of(&block),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    (buffer, view)
}

/// The largest axis scale of `m`.
fn max_scale(m: glam::Mat4) -> f32 {
    let (scale, _, _) = m.to_scale_rotation_translation();
    scale.abs().max_element()
}

/// The terrains' records and their heights and gradients in one float array (each list at
/// least one element long, as bindings need).
fn terrain_records(scene: &SceneInput, textures: &mut TextureSet) -> (Vec<GpuTerrain>, Vec<f32>) {
    let mut records = Vec::with_capacity(scene.terrains.len().max(1));
    let mut data: Vec<f32> = Vec::new();
    for t in &scene.terrains {
        let heights_at = data.len() as u32;
        data.extend_from_slice(&t.heights);
        let gradient_at = data.len() as u32;
        for (at, c) in &t.gradient {
            data.extend_from_slice(&[*at, c.x, c.y, c.z]);
        }
        let (displacement, strength, tile_size) = match &t.displacement {
            Some((tex, strength, tile)) => (textures.data_texture(tex), *strength, *tile),
            None => (NO_TEXTURE, 0.0, 1.0),
        };
        let paint = t
            .paint
            .as_ref()
            .map_or(NO_TEXTURE, |p| textures.paint_texture(p));
        records.push(GpuTerrain {
            corner: t.corner.to_array(),
            max_height: t.max_height,
            size: t.size.to_array(),
            samples: t.samples.to_array(),
            heights_at,
            gradient_at,
            gradient_len: t.gradient.len() as u32,
            displacement,
            strength,
            tile_size,
            pixel_density: t.pixel_density,
            band_distance: t.band_distance,
            band_transition: t.band_transition,
            paint,
            _pad: [0; 2],
        });
    }
    if records.is_empty() {
        records.push(GpuTerrain::zeroed());
    }
    if data.is_empty() {
        data.push(0.0);
    }
    (records, data)
}

/// The world-space gradients of U and V over the triangle `p` with UVs `uv` (zero for a
/// degenerate triangle or UV map).
pub fn uv_gradients(p: [Vec3; 3], uv: [glam::Vec2; 3]) -> (Vec3, Vec3) {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let n = e1.cross(e2);
    let area2 = n.length_squared();
    if !(area2.is_finite() && area2 > 1e-20) {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    // Gradients of the barycentric coordinates along e1 and e2.
    let ga = e2.cross(n) / area2;
    let gb = n.cross(e1) / area2;
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let gu = ga * d1.x + gb * d2.x;
    let gv = ga * d1.y + gb * d2.y;
    if gu.is_finite() && gv.is_finite() {
        (gu, gv)
    } else {
        (Vec3::ZERO, Vec3::ZERO)
    }
}

/// The horizontal direction toward the first sun (sprites' shadow proxies face it), +Z
/// without a sun or under a sun straight overhead.
fn suns_toward(scene: &SceneInput) -> Vec3 {
    scene
        .suns
        .first()
        .map(|s| Vec3::new(-s.direction.x, 0.0, -s.direction.z))
        .and_then(|v| v.try_normalize())
        .unwrap_or(Vec3::Z)
}

/// An RGBA colour in 0..1 as RGBA8 (clamped, rounded).
fn pack_colour(c: [f32; 4]) -> u32 {
    let b = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u32;
    b(c[0]) | (b(c[1]) << 8) | (b(c[2]) << 16) | (b(c[3]) << 24)
}
