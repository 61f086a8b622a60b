//! A transform gizmo drawn with the egui painter: three axis handles that translate (W),
//! rotate (E) or scale (R) the selection, snapping as [`crate::snap`] says (Ctrl turns it the
//! other way). A drag is one undo step (its commands share a merge key until the pointer is
//! released).

use egui::{Color32, Painter, Pos2, Stroke};
use glam::Vec3;
use texel_scene::{EntityRow, Transform};

use super::drag::{AXIS_COLOURS, HandleDrag};
use crate::camera::Projector;
use crate::snap::{SCALE_STEP, SnapNow, to_step};

/// Which transform the gizmo changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mode {
    /// Move (W).
    #[default]
    Translate,
    /// Rotate (E).
    Rotate,
    /// Scale (R).
    Scale,
}

/// The mode the gizmo works in on `row`: a terrain lies along the world's axes and is placed
/// by its translation only (`texel_scene::terrain::unapplied_transform`), so on a terrain the
/// gizmo moves it whatever mode is chosen, rather than set a rotation or scale that would
/// not be applied.
pub fn mode_for(mode: Mode, row: &EntityRow) -> Mode {
    if row.terrain.is_some() {
        Mode::Translate
    } else {
        mode
    }
}

const HANDLE_PX: f32 = 80.0;
const PICK_PX: f32 = 8.0;
const AXES: [Vec3; 3] = [Vec3::X, Vec3::Y, Vec3::Z];

/// A drag in progress: `handle` is the axis index (0 X, 1 Y, 2 Z), `start` the transform
/// when the drag began.
pub type Drag = HandleDrag<Transform>;

/// The screen ends of the three handles of a gizmo at `origin`.
pub fn handles(proj: &Projector, origin: Vec3) -> Option<(Pos2, [Pos2; 3])> {
    let o = proj.project(origin)?;
    let world = world_len(proj, origin);
    let mut ends = [o; 3];
    for (k, a) in AXES.iter().enumerate() {
        ends[k] = proj.project(origin + *a * world)?;
    }
    Some((o, ends))
}

/// Draws the gizmo; `hot` is the highlighted axis.
pub fn draw(p: &Painter, o: Pos2, ends: [Pos2; 3], mode: Mode, hot: Option<usize>) {
    for (k, end) in ends.iter().enumerate() {
        let width = if hot == Some(k) { 4.0 } else { 2.5 };
        p.line_segment([o, *end], Stroke::new(width, AXIS_COLOURS[k]));
        match mode {
            Mode::Translate => {
                p.circle_filled(*end, 5.0, AXIS_COLOURS[k]);
            }
            Mode::Rotate => {
                p.circle_stroke(*end, 7.0, Stroke::new(width, AXIS_COLOURS[k]));
            }
            Mode::Scale => {
                let r = egui::Rect::from_center_size(*end, egui::vec2(9.0, 9.0));
                p.rect_filled(r, 0.0, AXIS_COLOURS[k]);
            }
        }
    }
    p.circle_filled(o, 3.0, Color32::WHITE);
}

/// The axis whose handle is under `pointer`.
pub fn hit(o: Pos2, ends: [Pos2; 3], pointer: Pos2) -> Option<usize> {
    (0..3)
        .map(|k| (k, distance_to_segment(pointer, o, ends[k])))
        .filter(|(_, d)| *d < PICK_PX)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k)
}

fn distance_to_segment(p: Pos2, a: Pos2, b: Pos2) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_sq().max(1e-6)).clamp(0.0, 1.0);
    (a + ab * t - p).length()
}

/// The transform after dragging `drag.moved` pixels along the handle from `o` to `end`, for a
/// handle `world_len` world units long. With grid snap the coordinate moved along lands on a
/// multiple of the step (and a scale factor on a multiple of [`SCALE_STEP`]); with angle snap
/// the angle turned lands on a multiple of the angle step.
pub fn apply(
    drag: &Drag,
    mode: Mode,
    o: Pos2,
    end: Pos2,
    world_len: f32,
    snap: SnapNow,
) -> Transform {
    let axis_px = end - o;
    let len_px = axis_px.length().max(1.0);
    let along = drag.moved.dot(axis_px / len_px);
    let mut t = drag.start;
    let k = drag.handle;
    match mode {
        Mode::Translate => {
            let d = along / len_px * world_len;
            let mut to = drag.start.translation[k] + d;
            if let Some(step) = snap.grid {
                to = to_step(to, step);
            }
            t.translation[k] = to;
        }
        Mode::Rotate => {
            let deg = (drag.moved.x - drag.moved.y) * 0.5;
            let mut to = drag.start.rotation[k] + deg;
            if let Some(step) = snap.angle {
                to = to_step(to, step);
            }
            t.rotation[k] = to;
        }
        Mode::Scale => {
            let mut f = (1.0 + along / len_px).max(0.01);
            if snap.grid.is_some() {
                f = to_step(f, SCALE_STEP).max(SCALE_STEP);
            }
            t.scale[k] = (drag.start.scale[k] * f).max(0.001);
        }
    }
    t
}

/// World length of the handles at `origin`: what shows as about `HANDLE_PX` pixels there
/// (the same at every depth in an orthographic view).
pub fn world_len(proj: &Projector, origin: Vec3) -> f32 {
    let dist = proj.apparent_distance(origin).max(0.1);
    dist * HANDLE_PX / proj.rect().height().max(1.0) * 1.2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_terrain_is_only_moved() {
        let mut row = EntityRow::default();
        assert_eq!(mode_for(Mode::Rotate, &row), Mode::Rotate);
        assert_eq!(mode_for(Mode::Scale, &row), Mode::Scale);
        row.terrain = Some(crate::terrain::default_terrain());
        for mode in [Mode::Translate, Mode::Rotate, Mode::Scale] {
            assert_eq!(mode_for(mode, &row), Mode::Translate);
        }
    }

    #[test]
    fn translate_follows_the_axis_and_snaps() {
        let drag = Drag {
            handle: 0,
            start: Transform::default(),
            moved: egui::vec2(50.0, 0.0),
        };
        let (o, end) = (Pos2::new(0.0, 0.0), Pos2::new(100.0, 0.0));
        let free = SnapNow::default();
        let t = apply(&drag, Mode::Translate, o, end, 2.0, free);
        assert!((t.translation.x - 1.0).abs() < 1e-5);
        // From x = 0.3, a drag of 0.6 lands on 1.0 (a multiple of 0.5), not on 0.3 + 0.5.
        let drag = Drag {
            moved: egui::vec2(30.0, 0.0),
            start: Transform::from_translation(glam::Vec3::new(0.3, 0.0, 0.0)),
            ..drag
        };
        let snap = SnapNow {
            grid: Some(0.5),
            angle: Some(15.0),
        };
        let t = apply(&drag, Mode::Translate, o, end, 2.0, snap);
        assert_eq!(t.translation.x, 1.0);
        let mut turned = drag;
        turned.start.rotation.x = 10.0;
        let t = apply(&turned, Mode::Rotate, o, end, 2.0, snap);
        assert_eq!(t.rotation.x, 30.0, "10° + 15° lands on 30°");
        let t = apply(&turned, Mode::Rotate, o, end, 2.0, free);
        assert_eq!(t.rotation.x, 25.0);
    }

    #[test]
    fn ortho_handles_are_one_size_at_every_depth() {
        // (Sized by the distance from the eye, they would grow tenfold from 4 to 40 units.)
        // Looking along −Z: the X handle lies across the view.
        let mut cam = crate::camera::EditorCamera {
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            ..Default::default()
        };
        cam.focus(Vec3::ZERO, 10.0);
        let rect = egui::Rect::from_min_size(Pos2::ZERO, egui::vec2(400.0, 300.0));
        let length = |ortho: bool, depth: f32| {
            let c = crate::camera::EditorCamera { ortho, ..cam };
            let proj = Projector::new(&c.camera(), rect);
            let (o, ends) = handles(&proj, cam.eye + cam.forward() * depth).expect("in front");
            (ends[0] - o).length()
        };
        let (near, far) = (length(true, 4.0), length(true, 40.0));
        assert!((near - far).abs() < 0.01, "{near} {far}");
        // As long as the perspective view's handles at the focus point.
        assert!((near - length(false, 10.0)).abs() < 0.5, "{near}");
    }

    #[test]
    fn handle_hit_test() {
        let o = Pos2::new(0.0, 0.0);
        let ends = [
            Pos2::new(100.0, 0.0),
            Pos2::new(0.0, -100.0),
            Pos2::new(-70.0, 70.0),
        ];
        assert_eq!(hit(o, ends, Pos2::new(50.0, 3.0)), Some(0));
        assert_eq!(hit(o, ends, Pos2::new(2.0, -60.0)), Some(1));
        assert_eq!(hit(o, ends, Pos2::new(50.0, 50.0)), None);
    }
}
