//! Face handles of a selected probe-grid override volume: a square at the centre of each of
//! the box's six faces. Dragging one moves that face along its normal while the opposite
//! face stays put, so one command changes the volume's `size` and the transform's
//! `translation` together. A drag is one undo step (one merge key until release).

use egui::{Color32, Painter, Pos2, Stroke};
use glam::Vec3;
use texel_scene::{ProbeGridOverride, Transform};

use super::drag::{AXIS_COLOURS, HandleDrag};
use crate::camera::Projector;

/// Pick radius around a handle, pixels.
const PICK_PX: f32 = 9.0;
/// Smallest world extent a drag leaves along an axis.
pub const MIN_EXTENT: f32 = 0.05;
/// A face drag in progress: `handle` is the face index (axis `face / 2`, outward normal
/// positive when `face` is even), `start` the transform and the volume when it began.
pub type FaceDrag = HandleDrag<(Transform, ProbeGridOverride)>;

/// Unit outward normal of `face`.
pub fn normal(face: usize) -> Vec3 {
    let axis = Vec3::AXES[face / 2 % 3];
    if face.is_multiple_of(2) { axis } else { -axis }
}

/// World centres of the six faces of the volume (axis-aligned, as the probe grid reads it).
pub fn face_centres(t: &Transform, o: &ProbeGridOverride) -> [Vec3; 6] {
    let half = o.size * t.scale * 0.5;
    std::array::from_fn(|f| t.translation + normal(f) * half[f / 2])
}

/// Screen positions of the six handles (`None` behind the camera).
pub fn handles(proj: &Projector, t: &Transform, o: &ProbeGridOverride) -> [Option<Pos2>; 6] {
    face_centres(t, o).map(|c| proj.project(c))
}

/// The face whose handle is under `pointer`.
pub fn hit(handles: &[Option<Pos2>; 6], pointer: Pos2) -> Option<usize> {
    handles
        .iter()
        .enumerate()
        .filter_map(|(f, h)| h.map(|h| (f, (h - pointer).length())))
        .filter(|(_, d)| *d < PICK_PX)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(f, _)| f)
}

/// Draws the handles; `hot` is highlighted.
pub fn draw(p: &Painter, handles: &[Option<Pos2>; 6], hot: Option<usize>) {
    for (f, h) in handles.iter().enumerate() {
        if let Some(h) = h {
            let r = if hot == Some(f) { 6.0 } else { 4.5 };
            let rect = egui::Rect::from_center_size(*h, egui::vec2(r * 2.0, r * 2.0));
            p.rect_filled(rect, 1.0, AXIS_COLOURS[f / 2]);
            p.rect_stroke(
                rect,
                1.0,
                Stroke::new(1.0, Color32::WHITE),
                egui::StrokeKind::Outside,
            );
        }
    }
}

/// World distance the pointer moved the face outward: `drag.moved` projected on the face
/// normal's screen direction, scaled by how many pixels one world unit spans there.
pub fn outward(proj: &Projector, drag: &FaceDrag) -> f32 {
    let (t, volume) = &drag.start;
    let centre = face_centres(t, volume)[drag.handle];
    let (Some(a), Some(b)) = (
        proj.project(centre),
        proj.project(centre + normal(drag.handle)),
    ) else {
        return 0.0;
    };
    let dir = b - a;
    let px_per_unit = dir.length();
    if px_per_unit < 1e-3 {
        return 0.0;
    }
    drag.moved.dot(dir / px_per_unit) / px_per_unit
}

/// The transform and volume after moving `face` outward by `d` world units: the extent
/// along the face's axis grows by `d` (never below [`MIN_EXTENT`]) and the centre moves
/// half as far, so the opposite face keeps its place. With grid snap (`snap`: the step) the
/// face moves by a multiple of the step.
pub fn resize(
    t: &Transform,
    o: &ProbeGridOverride,
    face: usize,
    d: f32,
    snap: Option<f32>,
) -> (Transform, ProbeGridOverride) {
    let axis = face / 2 % 3;
    let scale = t.scale[axis];
    if !d.is_finite() || scale.abs() < 1e-6 {
        return (*t, *o);
    }
    let d = snap.map_or(d, |step| crate::snap::to_step(d, step));
    let extent = (o.size[axis] * scale).abs();
    let grown = (extent + d).max(MIN_EXTENT);
    let (mut t2, mut o2) = (*t, *o);
    o2.size[axis] = grown / scale.abs();
    t2.translation += normal(face) * ((grown - extent) * 0.5);
    (t2, o2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::Rect;

    fn volume() -> (Transform, ProbeGridOverride) {
        let t = Transform {
            translation: Vec3::new(1.0, 2.0, 3.0),
            scale: Vec3::new(2.0, 1.0, 1.0),
            ..Transform::default()
        };
        let o = ProbeGridOverride {
            size: Vec3::new(2.0, 4.0, 6.0),
            ..ProbeGridOverride::default()
        };
        (t, o)
    }

    #[test]
    fn resizing_keeps_the_opposite_face() {
        let (t, o) = volume();
        for face in 0..6 {
            let before = face_centres(&t, &o);
            let (t2, o2) = resize(&t, &o, face, 1.5, None);
            let after = face_centres(&t2, &o2);
            let opposite = face ^ 1;
            assert!(
                (after[opposite] - before[opposite]).length() < 1e-5,
                "face {face}"
            );
            assert!((after[face] - (before[face] + normal(face) * 1.5)).length() < 1e-5);
        }
        // X is scaled by 2: a world extent of 4 + 1.5 is a size of 2.75.
        let (_, o2) = resize(&t, &o, 0, 1.5, None);
        assert!((o2.size.x - 2.75).abs() < 1e-5);
    }

    #[test]
    fn resizing_clamps_and_snaps() {
        let (t, o) = volume();
        let (_, o2) = resize(&t, &o, 2, -100.0, None);
        assert!((o2.size.y - MIN_EXTENT).abs() < 1e-5);
        let (t2, _) = resize(&t, &o, 4, 0.3, Some(0.25));
        assert!((t2.translation.z - (3.0 + 0.25 * 0.5)).abs() < 1e-5);
        assert_eq!(resize(&t, &o, 0, f32::NAN, None), (t, o));
    }

    #[test]
    fn handles_project_and_hit() {
        let (t, o) = volume();
        let mut cam = crate::camera::EditorCamera::default();
        cam.focus(t.translation, 20.0);
        let rect = Rect::from_min_size(Pos2::ZERO, egui::vec2(800.0, 600.0));
        let proj = Projector::new(&cam.camera(), rect);
        let hs = handles(&proj, &t, &o);
        let top = hs[2].expect("+Y handle in view");
        assert_eq!(hit(&hs, top + egui::vec2(2.0, 1.0)), Some(2));
        // Dragging the +Y handle up the screen moves it outward.
        let drag = FaceDrag {
            handle: 2,
            start: (t, o),
            moved: egui::vec2(0.0, -40.0),
        };
        assert!(outward(&proj, &drag) > 0.1);
    }
}
