//! The editor camera (look, fly, zoom, focus) and the projection between world and the
//! viewport rectangle, shared by the overlay, the gizmo and picking.

use egui::{Pos2, Rect};
use glam::{Mat4, Vec2, Vec3, Vec4};
use texel_render::input::Camera;

/// Vertical field of view of the editor camera, degrees.
pub const FOV_Y_DEG: f32 = 60.0;

/// A fly camera that also orbits a focus point `distance` ahead of the eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EditorCamera {
    /// The eye.
    pub eye: Vec3,
    /// Heading in degrees (0 looks along −Z, positive turns toward −X).
    pub yaw_deg: f32,
    /// Pitch in degrees, positive looks up.
    pub pitch_deg: f32,
    /// Distance to the point the camera looks at (what the wheel zooms toward).
    pub distance: f32,
}

impl Default for EditorCamera {
    fn default() -> Self {
        let mut c = EditorCamera {
            eye: Vec3::ZERO,
            yaw_deg: 30.0,
            pitch_deg: -25.0,
            distance: 18.0,
        };
        c.focus(Vec3::new(0.0, 1.0, 0.0), 18.0);
        c
    }
}

impl EditorCamera {
    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        let (y, p) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        Vec3::new(-y.sin() * p.cos(), p.sin(), -y.cos() * p.cos())
    }

    /// Unit right vector (horizontal).
    pub fn right(&self) -> Vec3 {
        let (s, c) = self.yaw_deg.to_radians().sin_cos();
        Vec3::new(c, 0.0, -s)
    }

    /// The render camera.
    pub fn camera(&self) -> Camera {
        Camera {
            fov_y: FOV_Y_DEG.to_radians(),
            ..Camera::from_yaw_pitch(self.eye, self.yaw_deg, self.pitch_deg)
        }
    }

    /// Turns the view by a mouse motion in pixels (eye fixed).
    pub fn look(&mut self, delta: Vec2) {
        if delta.is_finite() {
            self.yaw_deg = (self.yaw_deg - delta.x * 0.25).rem_euclid(360.0);
            self.pitch_deg = (self.pitch_deg - delta.y * 0.25).clamp(-89.0, 89.0);
        }
    }

    /// Moves the eye by `local` (x right, y up, z forward) world units.
    pub fn fly(&mut self, local: Vec3) {
        if local.is_finite() {
            self.eye += self.right() * local.x + Vec3::Y * local.y + self.forward() * local.z;
        }
    }

    /// Zooms toward the focus point by wheel `steps` (positive zooms in).
    pub fn zoom(&mut self, steps: f32) {
        if !steps.is_finite() {
            return;
        }
        let target = self.eye + self.forward() * self.distance;
        self.distance = (self.distance * 0.9f32.powf(steps)).clamp(0.2, 1000.0);
        self.eye = target - self.forward() * self.distance;
    }

    /// Looks at `target` from `distance` away, keeping the view direction.
    pub fn focus(&mut self, target: Vec3, distance: f32) {
        self.distance = distance.clamp(0.5, 1000.0);
        self.eye = target - self.forward() * self.distance;
    }
}

/// World ↔ screen mapping for one viewport rectangle.
#[derive(Debug, Clone, Copy)]
pub struct Projector {
    view_proj: Mat4,
    inverse: Mat4,
    rect: Rect,
}

impl Projector {
    /// The mapping for `camera` drawn into `rect`.
    pub fn new(camera: &Camera, rect: Rect) -> Self {
        let aspect = rect.width() / rect.height().max(1.0);
        let view_proj = camera.projection(aspect) * camera.view();
        Projector {
            view_proj,
            inverse: view_proj.inverse(),
            rect,
        }
    }

    /// Screen position of `p`, or `None` behind the camera.
    pub fn project(&self, p: Vec3) -> Option<Pos2> {
        let c = self.view_proj * p.extend(1.0);
        if c.w <= 1e-4 {
            return None;
        }
        let n = c.truncate() / c.w;
        Some(Pos2::new(
            self.rect.min.x + (n.x + 1.0) * 0.5 * self.rect.width(),
            self.rect.min.y + (1.0 - n.y) * 0.5 * self.rect.height(),
        ))
    }

    /// The world ray under screen position `pos`: origin and unit direction.
    pub fn ray(&self, pos: Pos2) -> (Vec3, Vec3) {
        let nx = (pos.x - self.rect.min.x) / self.rect.width() * 2.0 - 1.0;
        let ny = 1.0 - (pos.y - self.rect.min.y) / self.rect.height() * 2.0;
        let near = self.inverse * Vec4::new(nx, ny, 0.0, 1.0);
        let far = self.inverse * Vec4::new(nx, ny, 1.0, 1.0);
        let (a, b) = (near.truncate() / near.w, far.truncate() / far.w);
        (a, (b - a).normalize_or_zero())
    }

    /// The rectangle.
    pub fn rect(&self) -> Rect {
        self.rect
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn focused_point_projects_to_the_centre_and_ray_returns() {
        let mut c = EditorCamera::default();
        c.focus(Vec3::new(3.0, 1.0, -2.0), 10.0);
        let rect = Rect::from_min_size(Pos2::new(10.0, 20.0), egui::vec2(400.0, 300.0));
        let p = Projector::new(&c.camera(), rect);
        let s = p.project(Vec3::new(3.0, 1.0, -2.0)).expect("in front");
        assert!((s - rect.center()).length() < 0.01, "{s:?}");
        let (o, d) = p.ray(rect.center());
        assert!((d - c.forward()).length() < 1e-3);
        assert!((o - c.eye).length() < 0.2);
        assert!(p.project(c.eye - c.forward()).is_none());
    }

    #[test]
    fn zoom_keeps_the_target() {
        let mut c = EditorCamera::default();
        let target = c.eye + c.forward() * c.distance;
        c.zoom(3.0);
        assert!(c.distance < 18.0);
        assert!((c.eye + c.forward() * c.distance - target).length() < 1e-3);
    }
}
