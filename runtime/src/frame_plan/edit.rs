//! An edit of one entity, extracted alone ([`PreparedLevel::update_entity`]): its objects
//! replace the ones it had, the lights are read again, and the probe-placement tree is
//! refit; the rest of the prepared level stays. What the edit can have changed on screen
//! comes back as a box ([`EntityEdit::region`]) to mark the probe faces that may see it.

use std::sync::Arc;

use glam::Vec3;
use texel_render::input::{LightFilter, ObjectInput, PointLightInput, SceneInput, SunInput};
use texel_render::shadow_region::{bounds_under, point_shadow_bounds, sun_shadow_bounds};
use texel_scene::{DirectionalLight, PointLight, Transform};

use super::extraction::{PreparedLevel, add_entity, entity_id, level_look, start_camera};
use crate::extract::grid_overrides;
use crate::load::LoadedLevel;

/// Why an entity's edit cannot be taken alone: prepare the level again.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("the edit of entity {index} needs the level prepared again: {why}")]
pub struct NotAlone {
    /// The entity's position in the level.
    pub index: usize,
    /// What it changed.
    pub why: &'static str,
}

/// What an entity's edit changed.
#[derive(Debug, Clone, PartialEq)]
pub struct EntityEdit {
    /// Indices of its objects in the scene (the renderer rewrites these).
    pub objects: std::ops::Range<usize>,
    /// Where the change can show: the objects' old and new bounds grown by where their
    /// shadows may fall, and the reach of every light that changed; `None` when nothing
    /// that is drawn changed. A sun that changed is everywhere: `Some` of an infinite box.
    pub region: Option<(Vec3, Vec3)>,
    /// The objects' old and new bounds together, when they changed.
    pub changed: Option<(Vec3, Vec3)>,
    /// Where in the region the light may have changed on surfaces that stayed: the
    /// objects' old and new bounds as shadow casters, and every changed light's reach.
    pub filter: LightFilter,
    /// The probe grid's override volumes changed: every probe may stand elsewhere.
    pub grid_changed: bool,
}

impl PreparedLevel {
    /// Takes in the edit of the entity at `index` of `level` (its transform, material,
    /// lights: anything that keeps its number of objects and leaves terrains, sprites and
    /// animation alone), extracting that entity only. [`NotAlone`], with nothing changed,
    /// otherwise.
    pub fn update_entity(
        &mut self,
        level: &LoadedLevel,
        index: usize,
    ) -> Result<EntityEdit, NotAlone> {
        let not = |why| Err(NotAlone { index, why });
        let Some(e) = level.scene.entities().nth(index) else {
            return not("it is not in the level");
        };
        let mut one = SceneInput::default();
        add_entity(level, index, e, &mut one);
        let id = entity_id(index);
        let scene = self.scene();
        // Where its objects lie (`PreparedLevel::rows`: level order until a row is added).
        let Some(std::ops::Range { start: at, end }) = self.rows.get(index).cloned() else {
            return not("it is not in the level");
        };
        if one.objects.len() != end - at {
            return not("it gained or lost geometry");
        }
        if !one.terrains.is_empty()
            || scene.objects[at..end]
                .iter()
                .any(|o| o.material.terrain.is_some())
        {
            return not("it is a terrain");
        }
        if !one.sprites.is_empty() || scene.sprites.iter().any(|s| s.id == id) {
            return not("it is a sprite");
        }
        if !one.animated.is_empty() || scene.animated.iter().any(|i| (at..end).contains(i)) {
            return not("it is animated");
        }
        let (suns, points) = lights(level);
        if points.len() != scene.points.len() {
            return not("a point light was added or removed");
        }
        let mut objects = one.objects;
        let old = &scene.objects[at..end];
        for (new, old) in objects.iter_mut().zip(old) {
            // A primitive is made again by extraction: the same shape keeps the old mesh, so
            // the renderer sees the mesh it uploaded.
            if !Arc::ptr_eq(&new.mesh, &old.mesh) && new.mesh == old.mesh {
                new.mesh = old.mesh.clone();
            }
        }
        let changed = changed_objects(old, &objects);
        // A material changed alone (colours, maps, outlines: not whether it casts shadows)
        // changes only where the objects show: their shadows and silhouette rays stay.
        let casts_alike = old.iter().zip(&objects).all(|(a, b)| {
            Arc::ptr_eq(&a.mesh, &b.mesh)
                && a.transform == b.transform
                && a.material.casts_shadows == b.material.casts_shadows
        });
        let mut region = changed.map(|(lo, hi)| match casts_alike {
            true => (lo, hi),
            false => shadow_region(&suns, &points, self.floor.min(lo.y), lo, hi),
        });
        let mut filter = LightFilter::default();
        if changed.is_some() && !casts_alike {
            filter.casters.extend(bounds(old));
            filter.casters.extend(bounds(&objects));
        }
        for (a, b) in scene.points.iter().zip(&points) {
            if a != b {
                region = union(region, light_reach(a));
                region = union(region, light_reach(b));
                filter = filter.union(&LightFilter {
                    casters: Vec::new(),
                    lit: vec![light_reach(a), light_reach(b)],
                });
            }
        }
        if suns != scene.suns {
            region = Some((Vec3::splat(f32::NEG_INFINITY), Vec3::splat(f32::INFINITY)));
        }
        if let Some((lo, _)) = bounds(&objects) {
            self.floor = self.floor.min(lo.y);
        }
        self.rays.replace_objects(at, objects);
        *self.rays.lights_mut().0 = suns;
        *self.rays.lights_mut().1 = points;
        let s = &level.scene;
        self.look = level_look(s);
        self.pixel_scale = s.settings.pixel_scale;
        self.cell_size = s.settings.cell_size;
        let overrides = grid_overrides(s);
        let grid_changed = overrides != self.overrides;
        self.overrides = overrides;
        self.start = start_camera(s);
        Ok(EntityEdit {
            objects: at..end,
            region,
            changed,
            filter,
            grid_changed,
        })
    }
}

/// The level's suns and point lights, in its order (as [`super::scene_input`] reads them).
pub(super) fn lights(level: &LoadedLevel) -> (Vec<SunInput>, Vec<PointLightInput>) {
    let w = level.scene.world();
    let (mut suns, mut points) = (Vec::new(), Vec::new());
    for e in level.scene.entities() {
        if let Ok(sun) = w.get::<&DirectionalLight>(e) {
            suns.push(SunInput {
                direction: sun.direction,
                colour: sun.colour * sun.intensity,
            });
        }
        if let Ok(p) = w.get::<&PointLight>(e) {
            let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
            points.push(PointLightInput {
                position: t.translation,
                colour: p.colour * p.intensity,
                radius: p.radius,
            });
        }
    }
    (suns, points)
}

/// The bounds of `old` and `new` together when they differ (`None`: the same objects).
fn changed_objects(old: &[ObjectInput], new: &[ObjectInput]) -> Option<(Vec3, Vec3)> {
    let same = old.iter().zip(new).all(|(a, b)| {
        Arc::ptr_eq(&a.mesh, &b.mesh)
            && a.transform == b.transform
            && a.material == b.material
            && a.id == b.id
    });
    if same {
        return None;
    }
    match (bounds(old), bounds(new)) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, b) => a.or(b),
    }
}

/// World bounds of `objects` (`None` for no vertices).
pub(super) fn bounds(objects: &[ObjectInput]) -> Option<(Vec3, Vec3)> {
    (objects.iter())
        .filter_map(|o| {
            o.mesh
                .bounds()
                .map(|(lo, hi)| bounds_under(o.transform, lo, hi))
        })
        .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
}

/// The box `lo..hi` grown by where its contents may cast shadows: along every sun down to
/// `floor`, and away from every point light that reaches it out to that light's reach.
pub(super) fn shadow_region(
    suns: &[SunInput],
    points: &[PointLightInput],
    floor: f32,
    lo: Vec3,
    hi: Vec3,
) -> (Vec3, Vec3) {
    let mut region = sun_shadow_bounds(suns, floor, lo, hi);
    for p in points {
        if let Some(b) = point_shadow_bounds(p.position, p.radius, lo, hi) {
            region = (region.0.min(b.0), region.1.max(b.1));
        }
    }
    region
}

/// What a point light can light.
pub(super) fn light_reach(p: &PointLightInput) -> (Vec3, Vec3) {
    (
        p.position - Vec3::splat(p.radius),
        p.position + Vec3::splat(p.radius),
    )
}

/// `a` and `b` in one box.
pub(super) fn union(a: Option<(Vec3, Vec3)>, b: (Vec3, Vec3)) -> Option<(Vec3, Vec3)> {
    Some(a.map_or(b, |a| (a.0.min(b.0), a.1.max(b.1))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    use texel_scene::assets::AssetLibrary;
    use texel_scene::{EntityRow, Geometry, ProbeGridOverride, Scene};

    fn level() -> LoadedLevel {
        let mut scene = Scene::new();
        let at = |x: f32| {
            Some(Transform {
                translation: Vec3::new(x, 0.5, 0.0),
                ..Transform::default()
            })
        };
        for x in [0.0, 3.0] {
            scene.spawn(EntityRow {
                transform: at(x),
                geometry: Some(Geometry::Box { size: Vec3::ONE }),
                ..EntityRow::default()
            });
        }
        scene.spawn(EntityRow {
            transform: at(10.0),
            probe_grid_override: Some(ProbeGridOverride::default()),
            ..EntityRow::default()
        });
        LoadedLevel {
            path: PathBuf::from("edit.ron"),
            scene,
            assets: AssetLibrary::default(),
        }
    }

    fn set(level: &mut LoadedLevel, index: usize, f: impl FnOnce(&mut EntityRow)) {
        let e = level.scene.entities().nth(index).expect("entity");
        let mut row = level.scene.row(e).expect("row");
        f(&mut row);
        level.scene.set_row(e, row).expect("set");
    }

    /// A box moved: its object alone is replaced (keeping its mesh), the region holds its old
    /// and new bounds; a grid override moved says the grid changed; a box that loses its
    /// geometry cannot be taken alone.
    #[test]
    fn an_entity_is_taken_in_alone() {
        let mut level = level();
        let mut prepared = PreparedLevel::new(&level);
        let mesh = prepared.scene().objects[1].mesh.clone();
        set(&mut level, 1, |r| {
            r.transform.as_mut().unwrap().translation.x = 5.0
        });
        let edit = prepared.update_entity(&level, 1).expect("alone");
        assert_eq!(edit.objects, 1..2);
        assert!(!edit.grid_changed);
        let (lo, hi) = edit.region.expect("a drawn change");
        assert!(lo.x <= 2.5 && hi.x >= 5.5, "{lo} {hi}");
        let o = &prepared.scene().objects[1];
        assert!(Arc::ptr_eq(&o.mesh, &mesh), "the same shape keeps its mesh");
        assert_eq!(o.transform.w_axis.x, 5.0);
        assert_eq!(prepared.scene().objects[0].transform.w_axis.x, 0.0);

        set(&mut level, 2, |r| {
            r.transform.as_mut().unwrap().translation.x = 12.0
        });
        let edit = prepared.update_entity(&level, 2).expect("alone");
        assert!(edit.grid_changed && edit.region.is_none() && edit.objects.is_empty());

        set(&mut level, 0, |r| r.geometry = None);
        let not = prepared.update_entity(&level, 0).expect_err("not alone");
        assert_eq!(not.index, 0);
        assert_eq!(prepared.scene().objects.len(), 2, "left as it was");
    }
}
