//! An edit made in place ([`GpuScene::update_objects`]): a still object moved, turned,
//! scaled or given another colour, and the lights changed, cost what they change. The
//! object's vertices are made again (as the upload makes them) and written over its old
//! ones, its record and draw ranges replaced, its shadow-casting triangles rewritten in the
//! shadow tree and the boxes above them refit ([`crate::bvh::refit`]), the point lights
//! rewritten. An object blanked (a deleted entity's: its mesh now empty) keeps its slot:
//! its draw ranges are emptied, its shadow triangles shrink to points (no ray hits them) and
//! its shadow instance casts nothing; an object of the same mesh, maps and shadow casting
//! may take the slot again (a delete undone), made as any edited object is; objects whose
//! entity id changed (the rows after a deleted one) have the id rewritten in their records. What changes the size or the layout
//! of a buffer (an object more, another mesh, other textures, shadows turned on or off, an
//! animated object, a terrain, sprites, a light more or less) is [`NotInPlace`]: the caller
//! uploads the scene again.

use std::ops::Range;
use std::sync::Arc;

use glam::Vec3;
use texel_geom::mesh::TriMesh;
use texel_geom::texture::SurfaceMaps;

use super::GpuBvhInstance;
use super::shapes::ShadowShapes;
use super::upload::{Meshes, ObjectTriangles, object_record, point_lights, suns};
use super::{GpuObject, GpuScene, Vertex};
use crate::bvh::GpuBvh;
use crate::bvh::instances::{TopLevel, instance_record};
use crate::bvh::refit::RefitIndex;
use crate::input::{ObjectInput, SceneInput};

/// Why an edit cannot be made in place: upload the scene again.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("the edit cannot be made in place: {0}")]
pub struct NotInPlace(pub String);

/// What an edit made in place wrote.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InPlaceEdit {
    /// Objects rewritten.
    pub objects: usize,
    /// Vertices rewritten.
    pub vertices: usize,
    /// Instance records rewritten (objects drawn from a shared mesh: their vertices stay).
    pub instances: usize,
    /// Shadow-casting triangles rewritten in the tree.
    pub shadow_triangles: usize,
    /// Tree nodes refit.
    pub nodes: usize,
    /// Top-level nodes refit (still instances moved: their meshes' trees stay).
    pub top_nodes: usize,
    /// Objects blanked (their entity deleted).
    pub blanked: usize,
    /// Object records whose entity id was rewritten.
    pub renumbered: usize,
}

/// One object as uploaded: where its data lies and what it was made from.
pub(super) struct ObjectSlot {
    /// Its vertices in the vertex buffer.
    vertices: Range<u32>,
    /// Its draw ranges in `GpuScene::ranges` (none for an animated object).
    ranges: Range<u32>,
    /// Its triangles among the static tree's inputs.
    casters: Range<u32>,
    /// Its own surface and each mesh part's.
    own: u32,
    parts: Vec<u32>,
    /// The mesh and maps its vertices and surfaces came from.
    mesh: Arc<TriMesh>,
    maps: SurfaceMaps,
    /// Whether its triangles cast shadows through the static tree.
    casts: bool,
    /// An animated object or a terrain: never edited in place.
    fixed: bool,
    /// Blanked (its entity deleted): drawn and cast by nothing until an object of the same
    /// mesh, maps and shadow casting takes the slot again (a delete undone).
    blank: bool,
    /// Its instance record, when it draws a shared mesh (its vertices are the mesh's).
    instance: Option<u32>,
}

impl ObjectSlot {
    /// Object `o`, whose data lies between the marks `(before, after)` (vertices, ranges,
    /// casters) with surfaces `(own, parts)`.
    pub(super) fn new(
        o: &ObjectInput,
        (before, after): ([u32; 3], [u32; 3]),
        (own, parts): (u32, Vec<u32>),
        fixed: bool,
        instance: Option<u32>,
    ) -> Self {
        ObjectSlot {
            // A shared mesh's vertices are its mesh's, not its own (the first user's
            // marks hold them): nothing to rewrite.
            vertices: match instance {
                Some(_) => after[0]..after[0],
                None => before[0]..after[0],
            },
            ranges: before[1]..after[1],
            casters: before[2]..after[2],
            own,
            parts,
            mesh: o.mesh.clone(),
            maps: o.material.maps.clone(),
            casts: o.material.casts_shadows,
            fixed,
            blank: false,
            instance,
        }
    }
}

/// What in-place edits need: every object's slot and the CPU copy of the shadow trees (the
/// static one at node 0, with its refit index made on the first edit).
pub(super) struct InPlace {
    objects: Vec<ObjectSlot>,
    bvh: GpuBvh,
    /// Inputs of the static tree (its triangles' ids are below this).
    static_casters: usize,
    refit: Option<RefitIndex>,
    /// The still instances' top-level tree, the shadow instance records (all of them, as
    /// uploaded) and each object's record, if it is such an instance, and their shapes.
    top: Option<TopLevel>,
    records: Vec<GpuBvhInstance>,
    record_of: Vec<Option<u32>>,
    /// The tree over `GpuScene::ranges`, built on the first cull
    /// ([`GpuScene::range_index`]), refit by an edit.
    range_index: std::sync::OnceLock<super::RangeIndex>,
    shapes: ShadowShapes,
    /// Every object's record as uploaded (their ids are rewritten when rows renumber).
    records_cpu: Vec<GpuObject>,
}

impl InPlace {
    /// The slots of an upload, its trees and how many inputs the static tree had.
    pub(super) fn new(objects: Vec<ObjectSlot>, bvh: GpuBvh, static_casters: usize) -> Self {
        InPlace {
            objects,
            bvh,
            static_casters,
            refit: None,
            top: None,
            records: Vec::new(),
            record_of: Vec::new(),
            range_index: std::sync::OnceLock::new(),
            shapes: ShadowShapes::default(),
            records_cpu: Vec::new(),
        }
    }

    /// With every object's record as uploaded.
    pub(super) fn with_records(self, records_cpu: Vec<GpuObject>) -> Self {
        InPlace {
            records_cpu,
            ..self
        }
    }

    /// With the still instances' top level `top`, the instance records, each object's and
    /// the shapes they place.
    pub(super) fn with_instances(
        self,
        top: Option<TopLevel>,
        records: Vec<GpuBvhInstance>,
        (record_of, shapes): (Vec<Option<u32>>, ShadowShapes),
    ) -> Self {
        InPlace {
            top,
            records,
            record_of,
            shapes,
            ..self
        }
    }
}

/// One object made again: its vertices, ranges, record and casters.
struct Remade {
    index: usize,
    meshes: Meshes,
    record: GpuObject,
}

impl GpuScene {
    /// The tree over [`GpuScene::ranges`] a face's cull walks (built now if this is the
    /// first cull since the upload).
    pub fn range_index(&self) -> &super::RangeIndex {
        (self.edits.range_index).get_or_init(|| super::RangeIndex::build(&self.ranges))
    }

    /// Brings the uploaded scene up to `scene`, which differs from what was uploaded only in
    /// the objects `changed` (their transforms and materials) and in its lights, by
    /// rewriting what changed in place. [`NotInPlace`], with nothing written, when the edit
    /// changes a buffer's size or layout (see the module doc): upload `scene` instead.
    pub fn update_objects(
        &mut self,
        queue: &wgpu::Queue,
        scene: &SceneInput,
        changed: &[usize],
    ) -> Result<InPlaceEdit, NotInPlace> {
        let not = |why: &str| Err(NotInPlace(why.to_owned()));
        if scene.objects.len() != self.edits.objects.len() {
            return not("objects were added or removed");
        }
        if self.sprites.is_some() || !scene.sprites.is_empty() {
            return not("the scene has sprites, whose lit texels are cached");
        }
        if scene.terrains.len() != self.terrain_count {
            return not("terrains were added or removed");
        }
        let (points, point_count) = point_lights(scene);
        if point_count != self.point_count {
            return not("point lights were added or removed");
        }
        let (grid, caster_at) = (self.light_grid, self.caster_nodes_at);
        let words = |top: Option<&crate::bvh::instances::TopLevel>| {
            let (roots, nodes) =
                super::light_grid::caster_nodes(&points, point_count, top, caster_at);
            (
                super::light_grid::light_words(&points, point_count, grid, &roots),
                nodes,
            )
        };
        if std::mem::size_of_val(words(self.edits.top.as_ref()).0.as_slice()) as u64
            > self.points.size()
        {
            return not("the point lights' grid grew");
        }
        let (blanks, changed): (Vec<usize>, Vec<usize>) =
            changed.iter().partition(|&&i| self.is_blanking(scene, i));
        if let Some(&i) = blanks.iter().find(|&&i| self.edits.objects[i].fixed) {
            return not(&format!("object {i} is animated or a terrain"));
        }
        let remade = (changed.iter())
            .map(|&i| self.remake(scene, i))
            .collect::<Result<Vec<Remade>, NotInPlace>>()?;
        let mut moved: Vec<(u32, [Vec3; 3])> = (remade.iter())
            .flat_map(|r| {
                let first = self.edits.objects[r.index].casters.start;
                (r.meshes.casters.iter().enumerate()).map(move |(k, t)| (first + k as u32, *t))
            })
            .collect();
        let edits = &mut self.edits;
        let blank_casters = (blanks.iter()).flat_map(|&i| edits.objects[i].casters.clone());
        let blank_casters: Vec<u32> = blank_casters.collect();
        let refit = match moved.is_empty() && blank_casters.is_empty() {
            true => None,
            false => {
                let index = (edits.refit)
                    .get_or_insert_with(|| RefitIndex::new(&edits.bvh, edits.static_casters));
                // A blanked object's triangles shrink to a point of their own: no ray hits
                // them, and the boxes above stay where they were.
                for id in blank_casters {
                    let p = (index.position(id))
                        .ok_or_else(|| NotInPlace("a shadow triangle is not in the tree".into()))?;
                    moved.push((id, [Vec3::from(edits.bvh.triangles[p as usize].v0); 3]));
                }
                let refitted = (index.refit(&mut edits.bvh, &moved))
                    .ok_or_else(|| NotInPlace("a shadow triangle is not in the tree".into()))?;
                let (nodes, triangles) = (&self.bvh_nodes, &self.bvh_triangles);
                edits.bvh.write_refitted(queue, &refitted, nodes, triangles);
                Some(refitted)
            }
        };
        let mut cost = InPlaceEdit {
            objects: remade.len(),
            shadow_triangles: moved.len(),
            nodes: refit.map_or(0, |r| r.nodes.len()),
            ..InPlaceEdit::default()
        };
        for r in &remade {
            cost.top_nodes += self.move_shadow_instance(queue, r.index, Some(scene));
        }
        for &i in &blanks {
            cost.top_nodes += self.move_shadow_instance(queue, i, None);
            let slot = &mut self.edits.objects[i];
            for r in &mut self.ranges[slot.ranges.start as usize..slot.ranges.end as usize] {
                r.count = 0;
            }
            slot.blank = true;
            cost.blanked += 1;
        }
        for r in remade {
            let slot = &self.edits.objects[r.index];
            if let (Some(k), Some(record)) = (slot.instance, r.meshes.instances.first()) {
                let offset = u64::from(k) * size_of::<super::GpuInstance>() as u64;
                queue.write_buffer(&self.instances, offset, bytemuck::bytes_of(record));
                cost.instances += 1;
            }
            if !r.meshes.vertices.is_empty() {
                let offset = u64::from(slot.vertices.start) * size_of::<Vertex>() as u64;
                let vertices = bytemuck::cast_slice(&r.meshes.vertices);
                queue.write_buffer(&self.vertices, offset, vertices);
            }
            let at = slot.ranges.start as usize..slot.ranges.end as usize;
            self.ranges[at].copy_from_slice(&r.meshes.ranges);
            let offset = (r.index * size_of::<GpuObject>()) as u64;
            queue.write_buffer(&self.objects, offset, bytemuck::bytes_of(&r.record));
            if let Some(record) = self.edits.records_cpu.get_mut(r.index) {
                *record = r.record;
            }
            // A blank taken again: drawn and cast as the object it now is.
            self.edits.objects[r.index].blank = false;
            cost.vertices += r.meshes.vertices.len();
        }
        cost.renumbered = self.renumber(queue, scene);
        if let Some(index) = self.edits.range_index.get_mut() {
            index.refit(&self.ranges);
        }
        // The lights' caster roots and trees from the top level as the moves left it.
        let (light_words, caster_nodes) = words(self.edits.top.as_ref());
        queue.write_buffer(&self.points, 0, bytemuck::cast_slice(&light_words));
        if !caster_nodes.is_empty() {
            let at = u64::from(caster_at) * size_of::<crate::bvh::BvhNode>() as u64;
            queue.write_buffer(&self.bvh_nodes, at, bytemuck::cast_slice(&caster_nodes));
        }
        self.suns = suns(scene);
        // Only moving casters and terrain pixels ask where a shadow may fall.
        if !self.animated.is_empty() || self.terrain_count > 0 {
            self.shadow_lights = crate::shadow_region::ShadowLights::new(scene);
        }
        Ok(cost)
    }

    /// Whether object `index` of `scene` blanks an object that was drawn (its entity was
    /// deleted: its mesh is now empty).
    fn is_blanking(&self, scene: &SceneInput, index: usize) -> bool {
        let (Some(o), Some(slot)) = (scene.objects.get(index), self.edits.objects.get(index))
        else {
            return false;
        };
        o.mesh.indices.is_empty() && !slot.mesh.indices.is_empty() && !slot.blank
    }

    /// Gives every object the entity id `scene` gives it: in [`GpuScene::object_ids`] and in
    /// the records, written in one span. Returns the records rewritten.
    fn renumber(&mut self, queue: &wgpu::Queue, scene: &SceneInput) -> usize {
        let records = &mut self.edits.records_cpu;
        let mut span: Option<(usize, usize)> = None;
        let mut count = 0;
        for (i, o) in scene.objects.iter().enumerate() {
            let (Some(id), Some(record)) = (self.object_ids.get_mut(i), records.get_mut(i)) else {
                break;
            };
            if *id != o.id || record.id != o.id {
                *id = o.id;
                record.id = o.id;
                span = Some(span.map_or((i, i + 1), |(a, _)| (a, i + 1)));
                count += 1;
            }
        }
        if let Some((a, b)) = span {
            let offset = (a * size_of::<GpuObject>()) as u64;
            queue.write_buffer(&self.objects, offset, bytemuck::cast_slice(&records[a..b]));
        }
        count
    }

    /// Moves object `index`'s shadow instance, if it is one, to where `scene` places it (or,
    /// for `None`, makes it cast nothing): its record rewritten, the top-level boxes above
    /// it refit. Returns the nodes refit.
    fn move_shadow_instance(
        &mut self,
        queue: &wgpu::Queue,
        index: usize,
        scene: Option<&SceneInput>,
    ) -> usize {
        let e = &mut self.edits;
        let (Some(Some(k)), Some(top)) = (e.record_of.get(index).copied(), e.top.as_mut()) else {
            return 0;
        };
        let old = e.records[k as usize];
        let record_size = size_of::<GpuBvhInstance>() as u64;
        let Some(scene) = scene else {
            // Blanked: the GPU's record names no tree (the CPU's keeps its tree and box, for
            // an object that takes the slot again; the top level's boxes stay).
            let none = GpuBvhInstance {
                min: old.min,
                max: old.max,
                ..GpuBvhInstance::NONE
            };
            let at = u64::from(k) * record_size;
            queue.write_buffer(&self.bvh_instances, at, bytemuck::bytes_of(&none));
            return 0;
        };
        let transform = scene.objects[index].transform;
        let Some((_, model)) = e.shapes.placement(index, transform) else {
            return 0;
        };
        let record = instance_record(&e.bvh, old.root, model);
        e.records[k as usize] = record;
        queue.write_buffer(
            &self.bvh_instances,
            u64::from(k) * record_size,
            bytemuck::bytes_of(&record),
        );
        let changed = top.refit(&e.records, (k - top.first_item) as usize);
        let node_size = size_of::<crate::bvh::BvhNode>() as u64;
        for &i in &changed {
            let at = u64::from(top.node_offset + i) * node_size;
            queue.write_buffer(
                &self.bvh_nodes,
                at,
                bytemuck::bytes_of(&top.nodes[i as usize]),
            );
        }
        changed.len()
    }

    /// Object `index` of `scene` made again where its old data lies, or why it cannot be.
    fn remake(&self, scene: &SceneInput, index: usize) -> Result<Remade, NotInPlace> {
        let not = |why: String| Err(NotInPlace(why));
        let (Some(o), Some(slot)) = (scene.objects.get(index), self.edits.objects.get(index))
        else {
            return not(format!("no object {index}"));
        };
        if slot.fixed || o.material.terrain.is_some() || scene.animated.contains(&index) {
            return not(format!("object {index} is animated or a terrain"));
        }
        if !Arc::ptr_eq(&slot.mesh, &o.mesh) {
            return not(format!("object {index} has another mesh"));
        }
        if slot.maps != o.material.maps {
            return not(format!("object {index} has other textures"));
        }
        if slot.casts != o.material.casts_shadows {
            return not(format!("object {index} casts shadows or stops casting"));
        }
        let shaped = self.edits.record_of.get(index).is_some_and(|r| r.is_some());
        if shaped && !super::shapes::placeable(o.transform) {
            return not(format!(
                "object {index} is no longer placed by an invertible map"
            ));
        }
        let mut meshes = Meshes::one(slot.vertices.start);
        if let Some(k) = slot.instance {
            if !super::is_similarity(o.transform) {
                return not(format!(
                    "object {index} is no longer placed by a similarity"
                ));
            }
            let first = self.ranges[slot.ranges.start as usize].first;
            meshes.add_instance_ranges(o, first, k);
            meshes
                .instances
                .push(super::GpuInstance::new(o.transform, index as u32));
        } else {
            meshes.add_triangles(&ObjectTriangles {
                object: o,
                index: index as u32,
                own: slot.own,
                part_surfaces: &slot.parts,
                plain_terrain: false,
                // A shape's caster moves its record, not triangles.
                casts: slot.casts && !shaped,
                moving: false,
            });
        }
        let same = meshes.vertices.len() == slot.vertices.len()
            && meshes.ranges.len() == slot.ranges.len()
            && meshes.casters.len() == slot.casters.len();
        if !same {
            return not(format!("object {index}'s triangles are laid out anew"));
        }
        Ok(Remade {
            index,
            meshes,
            record: object_record(o, 0, None),
        })
    }
}

impl GpuScene {
    /// Where object `object`'s draw ranges lie in [`GpuScene::ranges`], and whether it is a
    /// terrain or animated (drawn at a level of detail or by the moving pass); `None` for
    /// an object the scene does not hold.
    pub fn object_draws(&self, object: usize) -> Option<(Range<u32>, bool)> {
        (self.edits.objects.get(object)).map(|o| (o.ranges.clone(), o.fixed))
    }

    /// The box holding object `object`'s draw ranges (`None`: it has none).
    pub fn drawn_bounds(&self, object: usize) -> Option<(Vec3, Vec3)> {
        let (ranges, _) = self.object_draws(object)?;
        let ranges = self
            .ranges
            .get(ranges.start as usize..ranges.end as usize)?;
        (ranges.iter()).fold(None, |b, r| match b {
            None => Some((r.min, r.max)),
            Some((lo, hi)) => Some((r.min.min(lo), r.max.max(hi))),
        })
    }
}
