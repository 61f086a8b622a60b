//! Entities added, removed or given other geometry without preparing the level again
//! ([`PreparedLevel::edit_rows`]).
//!
//! The data flow. A renderer object's *index* in the scene is what the GPU keeps: probe
//! faces store it in their id texels, shading reads its record by it, the vertices carry
//! it. Its *id* (the entity's position + 1, [`entity_id`]) is only read on the CPU, to name
//! what a pixel shows (`GpuScene::object_ids`). So indices stay and ids follow the rows:
//!
//! - an entity removed leaves its objects as blanks (an empty mesh that draws, casts and
//!   captures nothing, id 0) where they were, and every later entity's objects take the
//!   id of its new position;
//! - an entity added (or extracted again with more or fewer objects) takes the blanks of
//!   an entity deleted before whose objects had the same meshes, maps and shadow casting
//!   (a delete undone, a copy of something deleted), which the renderer fills in place;
//!   else its objects are appended after the last; its old ones, if any, become blanks;
//! - [`PreparedLevel::rows`] maps each entity's position to where its objects lie.
//!
//! Every other object keeps its index, so the probe faces captured before the edit still
//! name the right objects, and only the faces that may see the entity's old or new bounds
//! (grown by where their shadows fall) or a light added or removed are captured again
//! ([`RowsEdit::region`], as [`EntityEdit::region`](super::EntityEdit) for an edit in
//! place). The order in the scene no longer follows the level's, which nothing that is
//! drawn depends on. Preparing the level again (a fresh session, `Session::set_level`)
//! drops the blanks and restores level order. What shifts object indices or entity ids the
//! GPU keeps otherwise (sprites, animated objects, terrains) is [`NotAlone`].

use std::ops::Range;
use std::sync::{Arc, OnceLock};

use glam::Vec3;
use texel_render::input::{LightFilter, MaterialInput, ObjectInput, PointLightInput, SceneInput};

use super::edit::{NotAlone, bounds, light_reach, lights, shadow_region, union};
use super::extraction::{PreparedLevel, add_entity, entity_id, level_look, start_camera};
use super::partial::EditArea;
use crate::extract::grid_overrides;
use crate::load::LoadedLevel;

/// Blanks (deleted entities' objects) the scene may hold, beyond a quarter of its objects,
/// before an add or delete prepares the level again instead (which drops them).
pub const MAX_BLANKS: usize = 1024;

/// How many of the latest deleted entities an added one may take the blanks of.
pub const REUSE_SEARCH: usize = 64;

/// One change of the level's entities, by position in the level as it stood after the
/// changes before it (an editor command's order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RowEdit {
    /// The entity at this position changed its components.
    Set(usize),
    /// An entity was inserted at this position (later ones moved up by one).
    Insert(usize),
    /// The entity at this position was removed (later ones moved down by one).
    Remove(usize),
}

impl RowsEdit {
    /// Adds `area` to where the change can show.
    fn widen(&mut self, area: EditArea) {
        self.region = union(self.region, area.region);
        self.area = Some(match self.area.take() {
            Some(a) => a.union(&area),
            None => area,
        });
    }
}

/// What [`PreparedLevel::edit_rows`] changed.
#[derive(Debug, Clone, PartialEq)]
pub struct RowsEdit {
    /// Objects (by index in the scene) rewritten with the same layout: the renderer may
    /// rewrite these in place.
    pub objects: Vec<usize>,
    /// Objects blanked (by index in the scene): the renderer may stop drawing these in
    /// place.
    pub blanked: Vec<usize>,
    /// Whether objects were appended or blanked (the renderer's scene changed shape).
    pub reshaped: bool,
    /// Where the change can show (see [`super::EntityEdit::region`]).
    pub region: Option<(Vec3, Vec3)>,
    /// The same, with what in it may have changed ([`EditArea`]): an entity edited in
    /// place by its bounds and a filter, a light added or removed by its reach, the rest
    /// captured and lit again wherever its region shows.
    pub area: Option<EditArea>,
    /// The probe grid's override volumes changed.
    pub grid_changed: bool,
}

impl PreparedLevel {
    /// Takes in `edits` (in order) whose result is `level`, extracting only the entities
    /// they touch (see the module doc). [`NotAlone`] when they cannot be taken so: prepare
    /// the level again (the prepared level may be changed in part by then).
    pub fn edit_rows(
        &mut self,
        level: &LoadedLevel,
        edits: &[RowEdit],
    ) -> Result<RowsEdit, NotAlone> {
        let finals = final_positions(edits)?;
        let structural = edits.iter().any(|e| !matches!(e, RowEdit::Set(_)));
        let blanks = self.blank_objects();
        if structural && blanks > MAX_BLANKS && blanks > self.scene().objects.len() / 4 {
            return Err(NotAlone {
                index: 0,
                why: "the scene holds many blanks: prepared again, it holds none",
            });
        }
        let scene = self.scene();
        if structural && (!scene.sprites.is_empty() || !scene.animated.is_empty()) {
            let index = finals.iter().flatten().next().copied().unwrap_or(0);
            return Err(NotAlone {
                index,
                why: "the level has sprites or animated objects, whose numbers it would shift",
            });
        }
        let (old_suns, old_points) = (scene.suns.clone(), scene.points.clone());
        let (suns, points) = lights(level);
        let mut out = RowsEdit {
            objects: Vec::new(),
            blanked: Vec::new(),
            reshaped: false,
            region: None,
            area: None,
            grid_changed: false,
        };
        for (edit, at) in edits.iter().zip(&finals) {
            let grown = match (*edit, *at) {
                (RowEdit::Insert(i), Some(f)) => {
                    self.rows.insert(i, 0..0);
                    self.renumber(i + 1);
                    self.append_row(level, (i, f), &points, &mut out)?
                }
                (RowEdit::Remove(i), _) => {
                    out.blanked
                        .extend(self.rows.get(i).cloned().unwrap_or_default());
                    out.reshaped = true;
                    self.remove_row(i, &points)?
                }
                _ => None,
            };
            if let Some(b) = grown {
                out.widen(EditArea::whole(b));
            }
        }
        if self.rows.len() != level.scene.len() {
            return Err(NotAlone {
                index: self.rows.len(),
                why: "the edits do not lead to the level's entities",
            });
        }
        // The level's lights from here on (an entity set below may be one).
        *self.rays.lights_mut().0 = suns.clone();
        *self.rays.lights_mut().1 = points.clone();
        // The entities set, at their final positions, after every insert and removal.
        let mut sets: Vec<usize> = (edits.iter().zip(&finals))
            .filter_map(|(e, f)| matches!(e, RowEdit::Set(_)).then_some(*f).flatten())
            .collect();
        sets.sort_unstable();
        sets.dedup();
        for f in sets {
            match self.update_entity(level, f) {
                Ok(edit) => {
                    let objects = Some(edit.objects.clone().map(|o| o as u32).collect());
                    out.objects.extend(edit.objects);
                    out.grid_changed |= edit.grid_changed;
                    if let Some(region) = edit.region {
                        out.widen(EditArea {
                            region,
                            changed: edit.changed,
                            filter: edit.filter,
                            objects,
                        });
                    }
                }
                Err(e) if e.why == "it gained or lost geometry" => {
                    out.blanked.extend(self.rows[f].clone());
                    out.reshaped = true;
                    let old = self.remove_objects(f);
                    let new = self.append_row(level, (f, f), &points, &mut out)?;
                    for b in [old, new].into_iter().flatten() {
                        out.widen(EditArea::whole(b));
                    }
                }
                Err(e) => return Err(e),
            }
        }
        // Lights added or removed: what they reach (the ones between the lists' common
        // start and end).
        let same = |a: &[PointLightInput], b: &[PointLightInput]| a.len() == b.len() && a == b;
        if !same(&old_points, &points) {
            let head = (old_points.iter().zip(&points))
                .take_while(|(a, b)| a == b)
                .count();
            let tail = (old_points[head..]
                .iter()
                .rev()
                .zip(points[head..].iter().rev()))
            .take_while(|(a, b)| a == b)
            .count();
            let changed = (old_points[head..old_points.len() - tail].iter())
                .chain(&points[head..points.len() - tail]);
            for p in changed {
                let reach = light_reach(p);
                out.widen(EditArea {
                    region: reach,
                    changed: None,
                    filter: LightFilter {
                        casters: Vec::new(),
                        lit: vec![reach],
                    },
                    objects: Some(Vec::new()),
                });
            }
        }
        if suns != old_suns {
            let everywhere = (Vec3::splat(f32::NEG_INFINITY), Vec3::splat(f32::INFINITY));
            out.widen(EditArea::whole(everywhere));
        }
        out.grid_changed |= self.take_settings(level);
        Ok(out)
    }

    /// Gives the objects of the entities from position `from` on the ids of their
    /// positions.
    fn renumber(&mut self, from: usize) {
        let renumbered: Vec<(usize, u32)> = (self.rows.iter().enumerate().skip(from))
            .flat_map(|(row, r)| r.clone().map(move |k| (k, entity_id(row))))
            .collect();
        self.rays.set_ids(&renumbered);
    }

    /// Gives the entity at `final_index` of `level` objects as the entity at position
    /// `index` of the prepared level (which holds none for it yet): the blanks of an entity
    /// deleted before with the same meshes, maps and shadow casting when there are (a
    /// delete undone: listed in `out.objects`, the renderer fills them in place), else
    /// appended (`out.reshaped`). Returns where they may show.
    fn append_row(
        &mut self,
        level: &LoadedLevel,
        (index, final_index): (usize, usize),
        points: &[PointLightInput],
        out: &mut RowsEdit,
    ) -> Result<Option<(Vec3, Vec3)>, NotAlone> {
        let not = |why| Err(NotAlone { index, why });
        let Some(e) = level.scene.entities().nth(final_index) else {
            return not("it is not in the level");
        };
        let mut one = SceneInput::default();
        add_entity(level, index, e, &mut one);
        if !one.terrains.is_empty() {
            return not("it is a terrain");
        }
        if !one.sprites.is_empty() {
            return not("it is a sprite");
        }
        if !one.animated.is_empty() {
            return not("it is animated");
        }
        let region = self.shadowed(&one.objects, points);
        if let Some((lo, _)) = bounds(&one.objects) {
            self.floor = self.floor.min(lo.y);
        }
        if let Some(range) = self.reuse_blanks(&mut one.objects) {
            self.rows[index] = range.clone();
            out.objects.extend(range.clone());
            self.rays.replace_objects(range.start, one.objects);
            return Ok(region);
        }
        let at = self.scene().objects.len();
        self.rows[index] = at..at + one.objects.len();
        out.reshaped = true;
        self.rays.append_objects(one.objects);
        Ok(region)
    }

    /// The blanks, among the latest [`REUSE_SEARCH`] entities deleted, whose objects had the
    /// meshes, maps and shadow casting of `objects` (then given those very meshes, so the
    /// renderer sees the meshes it uploaded), taken off the list; `None` when there are none.
    fn reuse_blanks(&mut self, objects: &mut [ObjectInput]) -> Option<Range<usize>> {
        let fits = |old: &ObjectInput, new: &ObjectInput| {
            (Arc::ptr_eq(&old.mesh, &new.mesh) || old.mesh == new.mesh)
                && old.material.maps == new.material.maps
                && old.material.casts_shadows == new.material.casts_shadows
                && old.material.terrain.is_none()
                && new.material.terrain.is_none()
        };
        let first = self.graves.len().saturating_sub(REUSE_SEARCH);
        let k = (first..self.graves.len()).rev().find(|&k| {
            let old = &self.graves[k].1;
            !objects.is_empty()
                && old.len() == objects.len()
                && old.iter().zip(objects.iter()).all(|(a, b)| fits(a, b))
        })?;
        let (range, old) = self.graves.remove(k);
        for (new, old) in objects.iter_mut().zip(old) {
            new.mesh = old.mesh;
        }
        Some(range)
    }

    /// Removes the entity at `index`: its objects blanked, its position dropped, the later
    /// entities renumbered. Returns where it may have shown.
    fn remove_row(
        &mut self,
        index: usize,
        points: &[PointLightInput],
    ) -> Result<Option<(Vec3, Vec3)>, NotAlone> {
        let Some(range) = self.rows.get(index).cloned() else {
            return Err(NotAlone {
                index,
                why: "it is not in the level",
            });
        };
        if self.scene().objects[range.clone()]
            .iter()
            .any(|o| o.material.terrain.is_some())
        {
            return Err(NotAlone {
                index,
                why: "it is a terrain",
            });
        }
        let old = self.scene().objects[range].to_vec();
        let region = self.shadowed(&old, points);
        self.remove_objects(index);
        self.rows.remove(index);
        self.renumber(index);
        Ok(region)
    }

    /// Blanks the objects of the entity at `index` (its row then holds none). Returns where
    /// they may have shown (with the scene's lights).
    fn remove_objects(&mut self, index: usize) -> Option<(Vec3, Vec3)> {
        let range = std::mem::replace(&mut self.rows[index], 0..0);
        let old = self.scene().objects[range.clone()].to_vec();
        let points = self.scene().points.clone();
        let region = self.shadowed(&old, &points);
        self.rays.blank_objects(range.clone(), blank());
        if !range.is_empty() {
            self.graves.push((range, old));
        }
        region
    }

    /// Where `objects` may show: their bounds grown by where their shadows may fall.
    fn shadowed(
        &self,
        objects: &[ObjectInput],
        points: &[PointLightInput],
    ) -> Option<(Vec3, Vec3)> {
        let (lo, hi) = bounds(objects)?;
        let floor = self.floor.min(lo.y);
        Some(shadow_region(&self.scene().suns, points, floor, lo, hi))
    }

    /// The level's settings read again (as [`PreparedLevel::update_entity`] does); returns
    /// whether the probe grid's overrides changed.
    fn take_settings(&mut self, level: &LoadedLevel) -> bool {
        let s = &level.scene;
        self.look = level_look(s);
        self.pixel_scale = s.settings.pixel_scale;
        self.cell_size = s.settings.cell_size;
        let overrides = grid_overrides(s);
        let changed = overrides != self.overrides;
        self.overrides = overrides;
        self.start = start_camera(s);
        changed
    }

    /// How many of the scene's objects are blanks left by removed entities.
    pub fn blank_objects(&self) -> usize {
        self.graves.iter().map(|g| g.0.len()).sum()
    }
}

/// Each edit's position in the final level: where an inserted or set entity ends up
/// (`None` for a removal, and for a set of an entity removed later). [`NotAlone`] for an
/// entity inserted and removed again.
fn final_positions(edits: &[RowEdit]) -> Result<Vec<Option<usize>>, NotAlone> {
    let mut out = Vec::with_capacity(edits.len());
    for (k, edit) in edits.iter().enumerate() {
        let mut at = match *edit {
            RowEdit::Set(i) | RowEdit::Insert(i) => Some(i),
            RowEdit::Remove(_) => None,
        };
        for later in &edits[k + 1..] {
            at = match (at, *later) {
                (Some(p), RowEdit::Insert(j)) if j <= p => Some(p + 1),
                (Some(p), RowEdit::Remove(j)) if j == p => None,
                (Some(p), RowEdit::Remove(j)) if j < p => Some(p - 1),
                (at, _) => at,
            };
        }
        if let (RowEdit::Insert(i), None) = (edit, at) {
            return Err(NotAlone {
                index: *i,
                why: "it was added and removed again",
            });
        }
        out.push(at);
    }
    Ok(out)
}

/// What a removed entity's object becomes: nothing drawn, cast or captured.
fn blank() -> ObjectInput {
    static EMPTY: OnceLock<Arc<texel_scene::TriMesh>> = OnceLock::new();
    ObjectInput {
        mesh: EMPTY.get_or_init(Default::default).clone(),
        transform: glam::Mat4::IDENTITY,
        material: MaterialInput {
            casts_shadows: false,
            outlined: false,
            ..MaterialInput::default()
        },
        id: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    use texel_scene::assets::AssetLibrary;
    use texel_scene::{EntityRow, Geometry, Scene, Transform};

    fn boxed(x: f32) -> EntityRow {
        EntityRow {
            transform: Some(Transform {
                translation: Vec3::new(x, 0.5, 0.0),
                ..Transform::default()
            }),
            geometry: Some(Geometry::Box { size: Vec3::ONE }),
            ..EntityRow::default()
        }
    }

    fn level(xs: &[f32]) -> LoadedLevel {
        let mut scene = Scene::new();
        for &x in xs {
            scene.spawn(boxed(x));
        }
        LoadedLevel {
            path: PathBuf::from("splice.ron"),
            scene,
            assets: AssetLibrary::default(),
        }
    }

    /// Each entity's objects, by position: (x of its object, its id).
    fn shown(p: &PreparedLevel) -> Vec<Vec<(f32, u32)>> {
        (p.rows.iter())
            .map(|r| {
                (p.scene().objects[r.clone()].iter())
                    .map(|o| (o.transform.w_axis.x, o.id))
                    .collect()
            })
            .collect()
    }

    /// A box removed from the middle leaves a blank where its object was, and the later
    /// entities keep their objects under the ids of their new positions; a box inserted
    /// takes the blank, a ball is appended; an entity that loses its geometry is blanked;
    /// what the positions name matches a level prepared afresh.
    #[test]
    fn rows_added_and_removed_keep_every_other_object_where_it_was() {
        let mut lvl = level(&[0.0, 3.0, 6.0, 9.0]);
        let mut p = PreparedLevel::new(&lvl);
        let e = lvl.scene.entities().nth(1).expect("entity");
        lvl.scene.despawn(e);
        let edit = p.edit_rows(&lvl, &[RowEdit::Remove(1)]).expect("alone");
        assert!(edit.reshaped && edit.objects.is_empty());
        let (lo, hi) = edit.region.expect("where it stood");
        assert!(lo.x <= 2.5 && hi.x >= 3.5, "{lo} {hi}");
        assert_eq!(shown(&p), [[(0.0, 1)], [(6.0, 2)], [(9.0, 3)]]);
        assert_eq!(p.scene().objects.len(), 4, "the blank stays");
        assert_eq!(p.scene().objects[1].id, 0);
        assert_eq!(p.blank_objects(), 1);

        // A box of the deleted one's shape takes its blank; a ball is appended.
        lvl.scene.spawn_at(0, boxed(-3.0));
        let edit = p.edit_rows(&lvl, &[RowEdit::Insert(0)]).expect("alone");
        assert!(!edit.reshaped && edit.objects == [1], "{edit:?}");
        let ids: Vec<u32> = p.scene().objects.iter().map(|o| o.id).collect();
        assert_eq!(ids, [2, 1, 3, 4], "the blank taken, the others renumbered");
        let mut ball = boxed(12.0);
        ball.geometry = Some(Geometry::Sphere {
            radius: 0.5,
            segments: 8,
        });
        lvl.scene.spawn_at(4, ball);
        let edit = p.edit_rows(&lvl, &[RowEdit::Insert(4)]).expect("alone");
        assert!(edit.reshaped && edit.objects.is_empty());
        assert_eq!(p.scene().objects[4].id, 5, "appended");
        let fresh = PreparedLevel::new(&lvl);
        assert_eq!(shown(&p), shown(&fresh));

        // Set, then removed, in one go: the set is dropped; the box losing its geometry
        // is blanked.
        let e = lvl.scene.entities().nth(3).expect("entity");
        let mut row = lvl.scene.row(e).expect("row");
        row.geometry = None;
        lvl.scene.set_row(e, row).expect("set");
        let e = lvl.scene.entities().next().expect("entity");
        lvl.scene.despawn(e);
        let edits = [RowEdit::Set(0), RowEdit::Set(3), RowEdit::Remove(0)];
        let edit = p.edit_rows(&lvl, &edits).expect("alone");
        assert!(edit.reshaped);
        assert_eq!(shown(&p), shown(&PreparedLevel::new(&lvl)));
        assert_eq!(p.blank_objects(), 2);

        // An entity added and removed again cannot be taken alone.
        let not = p.edit_rows(&lvl, &[RowEdit::Insert(1), RowEdit::Remove(1)]);
        assert_eq!(not.map(|_| ()).expect_err("not alone").index, 1);
    }
}
