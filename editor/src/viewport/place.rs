//! Where something added lands: on the surface under the viewport's centre (a CPU ray
//! against the level as the viewport draws it, hidden entities left out, through
//! `texel_runtime`'s [`SceneRays`]), or on the ground plane there when surface snap is off
//! or the ray meets nothing.

use glam::Vec3;
use texel_probes::placement::RayQuery;
use texel_runtime::load::LoadedLevel;
use texel_runtime::occluders::SceneRays;
use texel_scene::{EntityRow, Scene};

use super::Viewport;
use crate::assets::AssetDrag;
use crate::camera::Projector;
use crate::state::EditorState;

/// How far the placing ray looks, units.
const PLACE_RANGE: f32 = 500.0;

/// The first point where the ray from `origin` along `dir` meets what the viewport draws of
/// `state`'s level (hidden entities are not drawn), within `max` units.
pub fn surface_hit(state: &EditorState, origin: Vec3, dir: Vec3, max: f32) -> Option<Vec3> {
    let dir = dir.try_normalize()?;
    let drawn = LoadedLevel {
        path: state.document.level.path.clone(),
        scene: Scene::from_level(&state.render_level()),
        assets: state.document.level.assets.clone(),
    };
    let rays = SceneRays::new(texel_runtime::frame_plan::scene_input(&drawn));
    let hit = rays.first_hit(origin, dir, max)?;
    Some(origin + dir * hit.t)
}

/// `row` placed at `at`: its translation is taken as an offset from there (the Add menu's
/// shapes stand half their height up, lights above), so a shape stands on the point. A
/// row without a transform (a sun) is unchanged.
pub fn placed_at(mut row: EntityRow, at: Vec3) -> EntityRow {
    if let Some(t) = &mut row.transform {
        t.translation += at;
    }
    row
}

impl Viewport {
    /// Where something added goes: with surface snap on ([`crate::snap::Snap::surface`]),
    /// the surface under the viewport's centre; else (or when the centre shows only sky)
    /// where the centre line meets the ground ([`Viewport::ground_focus`]).
    pub fn place_point(&self, state: &EditorState) -> Vec3 {
        let camera = self.camera.camera();
        let hit = (self.snap.surface)
            .then(|| surface_hit(state, camera.position, camera.forward, PLACE_RANGE))
            .flatten();
        hit.unwrap_or_else(|| self.ground_focus())
    }

    /// Where something dropped at screen position `pos` of the viewport drawn in `rect`
    /// lands: with surface snap on, the surface under it (the ray through `pos`); else, or
    /// over sky, where that ray meets the ground (y = 0) within the placing range; else the
    /// point on it as far as the camera's focus.
    pub fn point_under(&self, state: &EditorState, rect: egui::Rect, pos: egui::Pos2) -> Vec3 {
        let (origin, dir) = Projector::new(&self.render_camera(), rect).ray(pos);
        let hit = (self.snap.surface)
            .then(|| surface_hit(state, origin, dir, PLACE_RANGE))
            .flatten();
        hit.or_else(|| {
            let t = -origin.y / dir.y;
            (dir.y < -1e-3 && (0.0..=PLACE_RANGE).contains(&t)).then(|| origin + dir * t)
        })
        .unwrap_or(origin + dir * self.camera.distance)
    }

    /// Takes an asset tile released over the viewport (`response`, drawn in `rect`) this
    /// frame: it lands at [`Viewport::point_under`] the pointer (not in Play).
    pub(super) fn asset_drop(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        rect: egui::Rect,
        state: &EditorState,
    ) {
        if self.playing() {
            return;
        }
        let Some(drag) = response.dnd_release_payload::<AssetDrag>() else {
            return;
        };
        let pos = ui
            .input(|i| i.pointer.interact_pos())
            .unwrap_or(rect.center());
        self.dropped_asset = Some(((*drag).clone(), self.point_under(state, rect, pos)));
    }
}
