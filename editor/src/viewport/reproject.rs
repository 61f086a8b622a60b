//! The shown frame painted for the camera of this UI frame, which may have moved since the
//! frame was drawn: the frame is re-projected as a plane facing its own camera at the
//! depth the editor camera orbits (exact for turning on the spot, and at that depth for
//! orbiting and zooming), through a grid of [`CELLS`]² quads so the perspective holds. Until
//! the next frame arrives, looking around and zooming move the picture at once.

use egui::epaint::{Mesh, Vertex};
use egui::{Color32, Painter, Pos2, Rect, TextureId};
use glam::Vec3;
use texel_render::input::Camera;

use crate::camera::Projector;

/// Quads across each side of the re-projected frame.
pub const CELLS: usize = 8;

/// The picture's triangles for the frame drawn from `drawn`, painted into `rect` as seen
/// from `camera`, its content placed at `depth` along the frame camera's view: three
/// (screen point, texture coordinate) each. One quad over `rect` (the frame held in place)
/// when the cameras are the same or the plane leaves the view (behind the eye).
pub fn triangles(rect: Rect, drawn: &Camera, camera: &Camera, depth: f32) -> Vec<(Pos2, Pos2)> {
    let uv = |x: usize, y: usize, cells: usize| {
        Pos2::new(x as f32 / cells as f32, y as f32 / cells as f32)
    };
    let (points, cells) = match (drawn != camera)
        .then(|| warped(rect, drawn, camera, depth))
        .flatten()
    {
        Some(points) => (points, CELLS),
        None => (
            vec![
                rect.left_top(),
                rect.right_top(),
                rect.left_bottom(),
                rect.right_bottom(),
            ],
            1,
        ),
    };
    let n = cells + 1;
    let mut out = Vec::with_capacity(cells * cells * 6);
    for y in 0..cells {
        for x in 0..cells {
            let corner =
                |dx: usize, dy: usize| (points[(y + dy) * n + x + dx], uv(x + dx, y + dy, cells));
            let (a, b, c, d) = (corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1));
            out.extend([a, b, d, a, d, c]);
        }
    }
    out
}

/// Paints `triangles` ([`triangles`]) with `texture` through egui's own image path.
pub fn paint(painter: &Painter, texture: TextureId, triangles: &[(Pos2, Pos2)]) {
    let mut mesh = Mesh::with_texture(texture);
    for (i, &(pos, uv)) in triangles.iter().enumerate() {
        mesh.vertices.push(Vertex {
            pos,
            uv,
            color: Color32::WHITE,
        });
        mesh.indices.push(i as u32);
    }
    painter.add(mesh);
}

/// Where the grid points of `rect` as `drawn` saw them land for `camera`, row by row
/// (`(CELLS + 1)²` of them); `None` when one falls behind `camera`.
pub fn warped(rect: Rect, drawn: &Camera, camera: &Camera, depth: f32) -> Option<Vec<Pos2>> {
    let from = Projector::new(drawn, rect);
    let to = Projector::new(camera, rect);
    let forward = drawn.forward.normalize_or_zero();
    let n = CELLS + 1;
    let mut points = Vec::with_capacity(n * n);
    for y in 0..n {
        for x in 0..n {
            let at = rect.min
                + egui::vec2(
                    rect.width() * x as f32 / CELLS as f32,
                    rect.height() * y as f32 / CELLS as f32,
                );
            let (origin, dir) = from.ray(at);
            let along = dir.dot(forward);
            if along <= 1e-4 {
                return None;
            }
            let t = (depth - (origin - drawn.position).dot(forward)) / along;
            let world: Vec3 = origin + dir * t;
            points.push(to.project(world)?);
        }
    }
    points
        .iter()
        .all(|p| p.x.is_finite() && p.y.is_finite())
        .then_some(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> Rect {
        Rect::from_min_size(Pos2::new(10.0, 20.0), egui::vec2(400.0, 300.0))
    }

    #[test]
    fn the_same_camera_leaves_the_frame_in_place() {
        let c = Camera::looking(Vec3::new(0.0, 2.0, 5.0), Vec3::new(0.0, -0.2, -1.0));
        let points = warped(rect(), &c, &c, 8.0).expect("in view");
        assert!((points[0] - rect().min).length() < 1e-2, "{:?}", points[0]);
        let last = points[points.len() - 1];
        assert!((last - rect().max).length() < 1e-2, "{last:?}");
    }

    #[test]
    fn turning_right_moves_the_frame_left() {
        let a = Camera::looking(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
        let b = Camera::looking(Vec3::ZERO, Vec3::new(0.1, 0.0, -1.0));
        let points = warped(rect(), &a, &b, 8.0).expect("in view");
        let centre = points[points.len() / 2];
        assert!(centre.x < rect().center().x - 10.0, "{centre:?}");
        // Turning on the spot: any depth gives the same picture.
        let far = warped(rect(), &a, &b, 80.0).expect("in view");
        assert!((far[points.len() / 2] - centre).length() < 1e-2);
    }

    #[test]
    fn a_plane_behind_the_new_eye_holds_the_frame() {
        let a = Camera::looking(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
        let b = Camera::looking(Vec3::new(0.0, 0.0, -20.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(warped(rect(), &a, &b, 8.0).is_none());
        // Held: one quad over the rectangle, the whole frame on it.
        let held = triangles(rect(), &a, &b, 8.0);
        assert_eq!(held.len(), 6);
        assert!(held.contains(&(rect().right_bottom(), Pos2::new(1.0, 1.0))));
    }

    #[test]
    fn a_turn_draws_the_grid() {
        let a = Camera::looking(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
        let b = Camera::looking(Vec3::ZERO, Vec3::new(0.1, 0.0, -1.0));
        assert_eq!(triangles(rect(), &a, &b, 8.0).len(), CELLS * CELLS * 6);
        assert_eq!(triangles(rect(), &a, &a, 8.0).len(), 6);
    }
}
