//! Many at once in the viewport: box select (a primary drag from empty space; Shift adds,
//! Ctrl toggles), the selection's outlines, and the gizmo on several entities, which moves,
//! turns and scales them about their common centre as one undo step.

use egui::{Color32, Painter, Pos2, Rect, Stroke};
use glam::{Quat, Vec3};
use texel_scene::{EntityRow, Geometry, Scene, Transform};

use super::gizmo::{self, Mode};
use super::overlay::segment;
use super::{Viewport, drag};
use crate::camera::Projector;
use crate::command::CommandError;
use crate::history::MergeKey;
use crate::selection::Pick;
use crate::state::EditorState;

/// The colour of selected things.
pub const SELECTED: Color32 = Color32::from_rgb(255, 200, 40);

/// A box being dragged out: where it started and what it does to the selection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxDrag {
    /// Where the button went down.
    pub from: Pos2,
    /// Replace, add or toggle.
    pub how: Pick,
}

/// The positions of the entities whose origin (translation) shows inside `area`.
pub fn in_box(proj: &Projector, scene: &Scene, area: Rect) -> Vec<usize> {
    let w = scene.world();
    (scene.entities().enumerate())
        .filter_map(|(i, e)| {
            let t = w.get::<&Transform>(e).ok()?;
            let at = proj.project(t.translation)?;
            area.contains(at).then_some(i)
        })
        .collect()
}

/// The common centre of `rows`: the mean of their translations (`None` without any).
pub fn centre(rows: &[(usize, EntityRow)]) -> Option<Vec3> {
    let ts: Vec<Vec3> = rows
        .iter()
        .filter_map(|(_, r)| r.transform.map(|t| t.translation))
        .collect();
    (!ts.is_empty()).then(|| ts.iter().sum::<Vec3>() / ts.len() as f32)
}

/// `t` moved as the gizmo moved its centre from `c` to `pivot` (translate), turned it by
/// `pivot.rotation` (rotate, about the world axis `axis`) or scaled it by `pivot.scale`
/// (scale, along `axis`). A terrain (`moved_only`) keeps its rotation and scale.
pub fn carry(
    t: &Transform,
    c: Vec3,
    pivot: &Transform,
    mode: Mode,
    axis: usize,
    moved_only: bool,
) -> Transform {
    let mut out = *t;
    match mode {
        Mode::Translate => out.translation += pivot.translation - c,
        Mode::Rotate => {
            let deg = pivot.rotation[axis];
            let q = Quat::from_axis_angle(Vec3::AXES[axis], deg.to_radians());
            out.translation = c + q * (t.translation - c);
            if !moved_only {
                out.rotation = turned(t.rotation, q, axis, deg);
            }
        }
        Mode::Scale => {
            let f = pivot.scale[axis];
            out.translation[axis] = c[axis] + (t.translation[axis] - c[axis]) * f;
            if !moved_only {
                out.scale[axis] = (t.scale[axis] * f).max(0.001);
            }
        }
    }
    out
}

/// Euler degrees (in [`Transform`]'s yaw, pitch, roll order) after turning by `q`: a turn
/// about Y adds to the yaw exactly (yaw comes first); others go through the quaternion,
/// rounded to 1e-4 degrees.
fn turned(rotation: Vec3, q: Quat, axis: usize, deg: f32) -> Vec3 {
    if axis == 1 {
        return rotation + Vec3::Y * deg;
    }
    let before = Transform {
        rotation,
        ..Transform::default()
    }
    .quat();
    let (yaw, pitch, roll) = (q * before).normalize().to_euler(glam::EulerRot::YXZ);
    let r = Vec3::new(pitch, yaw, roll) * (180.0 / std::f32::consts::PI);
    (r * 1e4).round() / 1e4
}

/// The local box of what `row` draws, roughly (a mesh or terrain: none).
fn local_box(row: &EntityRow) -> Option<Vec3> {
    Some(match row.geometry.as_ref()? {
        Geometry::Box { size } | Geometry::Wedge { size } => *size,
        Geometry::Sphere { radius, .. } => Vec3::splat(radius * 2.0),
        Geometry::Cylinder { radius, height, .. } => Vec3::new(radius * 2.0, *height, radius * 2.0),
        Geometry::Plane { size } => Vec3::new(size.x, 0.0, size.y),
        Geometry::Mesh { .. } => return None,
    })
}

/// Outlines every selected entity: its shape's box where it has one, else a ring at its
/// origin; the active one stronger.
pub fn paint_selected(p: &Painter, proj: &Projector, state: &EditorState) {
    let flags = state.hidden_and_locked();
    for (i, row) in state.selected_rows() {
        if flags.get(i).is_some_and(|f| f.0) {
            continue;
        }
        let Some(t) = row.transform else {
            continue;
        };
        let width = if state.selection == Some(i) { 2.0 } else { 1.2 };
        let stroke = Stroke::new(width, SELECTED);
        match local_box(&row) {
            Some(size) => {
                let m = t.matrix();
                let half = size * 0.5;
                let corner = |k: usize| {
                    let s = Vec3::new(
                        if k & 1 == 0 { -1.0 } else { 1.0 },
                        if k & 2 == 0 { -1.0 } else { 1.0 },
                        if k & 4 == 0 { -1.0 } else { 1.0 },
                    );
                    m.transform_point3(half * s)
                };
                for k in 0..8 {
                    for bit in [1, 2, 4] {
                        if k & bit == 0 {
                            segment(p, proj, corner(k), corner(k | bit), stroke);
                        }
                    }
                }
            }
            None => {
                if let Some(at) = proj.project(t.translation) {
                    p.circle_stroke(at, 6.0, stroke);
                }
            }
        }
    }
}

impl Viewport {
    /// Box select: a primary drag that began on nothing else draws a box; on release the
    /// entities whose origin lies inside are selected (Shift adds, Ctrl toggles).
    pub(super) fn box_select(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        painter: &Painter,
        proj: &Projector,
        state: &mut EditorState,
        used: bool,
    ) {
        let pointer = drag::Pointer::read(ui, response);
        if pointer.started
            && !used
            && let Some(from) = pointer.pressed
        {
            let how = Pick::from_modifiers(ui.input(|i| i.modifiers), Pick::Add);
            self.box_drag = Some(BoxDrag { from, how });
        }
        let Some(b) = self.box_drag else {
            return;
        };
        let Some(to) = pointer.at else {
            return;
        };
        let area = Rect::from_two_pos(b.from, to);
        if pointer.held {
            painter.rect_filled(area, 0.0, SELECTED.gamma_multiply(0.12));
            let stroke = Stroke::new(1.0, SELECTED);
            painter.rect_stroke(area, 0.0, stroke, egui::StrokeKind::Inside);
        } else {
            self.box_drag = None;
            let flags = state.hidden_and_locked();
            let mut hits = in_box(proj, state.scene(), area);
            hits.retain(|i| flags.get(*i).is_some_and(|f| !f.0 && !f.1));
            state.pick_many(&hits, b.how);
        }
    }

    /// The gizmo on several selected entities, at their common centre: a drag moves, turns
    /// or scales them all about it, one undo step. True when the pointer is on a handle or
    /// drags one.
    pub(super) fn gizmo_many(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        painter: &Painter,
        proj: &Projector,
        state: &mut EditorState,
    ) -> Result<bool, CommandError> {
        // Locked and hidden entities stay put; the gizmo stands at the others' centre.
        let flags = state.hidden_and_locked();
        let mut rows = state.selected_rows();
        rows.retain(|(i, _)| flags.get(*i).is_some_and(|f| !f.0 && !f.1));
        let Some(c) = centre(&rows) else {
            self.drag = None;
            return Ok(false);
        };
        let Some((o, ends)) = gizmo::handles(proj, c) else {
            return Ok(false);
        };
        // Rotate and scale only when some selected entity takes them (not terrains alone).
        let mode = (rows.iter())
            .map(|(_, r)| gizmo::mode_for(self.gizmo, r))
            .find(|m| *m != Mode::Translate)
            .unwrap_or(Mode::Translate);
        let pointer = drag::Pointer::read(ui, response);
        let hit = |p| gizmo::hit(o, ends, p);
        let was = self.drag.is_some();
        let frame = drag::update(
            &mut self.drag,
            &pointer,
            hit,
            Transform::from_translation(c),
        );
        if !was && self.drag.is_some() {
            self.drag_rows = rows;
        }
        gizmo::draw(painter, o, ends, mode, frame.highlight);
        if let Some(d) = frame.dragged {
            let c0 = d.start.translation;
            let world_len = gizmo::world_len(proj, c0);
            let ctrl = ui.input(|i| i.modifiers.ctrl || i.modifiers.command);
            let snap = self.snap.now(ctrl);
            let (o0, ends0) = gizmo::handles(proj, c0).unwrap_or((o, ends));
            let pivot = gizmo::apply(&d, mode, o0, ends0[d.handle], world_len, snap);
            let next: Vec<(usize, EntityRow)> = (self.drag_rows.iter())
                .map(|(i, r)| {
                    let mut r = r.clone();
                    let moved_only = r.terrain.is_some();
                    if let Some(t) = &mut r.transform {
                        *t = carry(t, c0, &pivot, mode, d.handle, moved_only);
                    }
                    (*i, r)
                })
                .collect();
            let index = state.selection.unwrap_or_default();
            state.set_rows(next, Some(MergeKey::Gizmo { index }))?;
        }
        Ok(frame.used)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turn_and_a_scale_go_about_the_centre() {
        let c = Vec3::ZERO;
        let t = Transform::from_translation(Vec3::new(2.0, 0.0, 0.0));
        let mut pivot = Transform::default();
        pivot.rotation.y = 90.0;
        let r = carry(&t, c, &pivot, Mode::Rotate, 1, false);
        assert!(
            (r.translation - Vec3::new(0.0, 0.0, -2.0)).length() < 1e-5,
            "{r:?}"
        );
        assert_eq!(r.rotation.y, 90.0);
        let fixed = carry(&t, c, &pivot, Mode::Rotate, 1, true);
        assert_eq!(fixed.rotation, Vec3::ZERO, "a terrain is only moved");
        let mut pivot = Transform::default();
        pivot.scale.x = 2.0;
        let s = carry(&t, c, &pivot, Mode::Scale, 0, false);
        assert_eq!((s.translation.x, s.scale.x), (4.0, 2.0));
        let mut pivot = Transform::default();
        pivot.rotation.x = 90.0;
        let x = carry(&t, c, &pivot, Mode::Rotate, 0, false);
        assert!((x.rotation.x - 90.0).abs() < 1e-3, "{:?}", x.rotation);
    }
}
