//! The editor camera (look, fly, zoom, focus), perspective or orthographic, and the
//! projection between world and the viewport rectangle, shared by the overlay, the gizmo and
//! picking. The projection is the render camera's own ([`Camera::projection`] and
//! [`Camera::view`]), so what the overlay draws and what a click picks line up with the
//! rendered picture in both modes.

use egui::{Pos2, Rect};
use glam::{Mat4, Vec2, Vec3, Vec4};
use texel_render::input::Camera;

/// Vertical field of view of the editor camera, degrees.
pub const FOV_Y_DEG: f32 = 60.0;

/// How far behind the eye, in focus distances, the orthographic render camera stands.
pub const ORTHO_PULL_BACK: f32 = 1.0;

/// A fly camera that also orbits a focus point `distance` ahead of the eye. Orthographic
/// (`ortho`), its view is as tall as the perspective one is at the focus point
/// ([`EditorCamera::ortho_height`]), so switching keeps the framing there and zooming (which
/// changes `distance`) changes the height; the eye stays where it is.
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
    /// Orthographic view (parallel rays) instead of perspective.
    pub ortho: bool,
}

impl Default for EditorCamera {
    fn default() -> Self {
        let mut c = EditorCamera {
            eye: Vec3::ZERO,
            yaw_deg: 30.0,
            pitch_deg: -25.0,
            distance: 18.0,
            ortho: false,
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

    /// Height in world units of the orthographic view: what the perspective view spans at
    /// the focus point, `2 · distance · tan(FOV_Y / 2)`.
    pub fn ortho_height(&self) -> f32 {
        2.0 * self.distance * (FOV_Y_DEG.to_radians() * 0.5).tan()
    }

    /// The render camera (orthographic when `ortho`; it keeps the field of view, which the
    /// frame driver reads for the art pixel's size). Orthographic, it stands
    /// [`ORTHO_PULL_BACK`] focus distances behind the eye, along the view: the picture is
    /// the same (rays are parallel), but what lies just behind the eye's plane, such as the
    /// ground under the bottom edge of a view looking down, is not clipped away (as
    /// Blender pulls its orthographic clipping plane back).
    pub fn camera(&self) -> Camera {
        let eye = if self.ortho {
            self.eye - self.forward() * ORTHO_PULL_BACK * self.distance
        } else {
            self.eye
        };
        Camera {
            fov_y: FOV_Y_DEG.to_radians(),
            ortho_height: self.ortho.then(|| self.ortho_height()),
            ..Camera::from_yaw_pitch(eye, self.yaw_deg, self.pitch_deg)
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

/// World ↔ screen mapping for one viewport rectangle, through the render camera's view and
/// projection (perspective or orthographic).
#[derive(Debug, Clone, Copy)]
pub struct Projector {
    view_proj: Mat4,
    inverse: Mat4,
    rect: Rect,
    eye: Vec3,
    forward: Vec3,
    fov_y: f32,
    ortho_height: Option<f32>,
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
            eye: camera.position,
            forward: camera.forward.normalize_or_zero(),
            fov_y: camera.fov_y,
            ortho_height: camera.ortho_height,
        }
    }

    /// Depth of `p` in front of the camera's plane, along the view direction.
    pub fn depth(&self, p: Vec3) -> f32 {
        (p - self.eye).dot(self.forward)
    }

    /// Screen position of `p`, or `None` behind the camera (behind its plane when
    /// orthographic, which the renderer clips there too).
    pub fn project(&self, p: Vec3) -> Option<Pos2> {
        let c = self.view_proj * p.extend(1.0);
        let depth = match self.ortho_height {
            Some(_) => self.depth(p),
            None => c.w,
        };
        if depth <= 1e-4 {
            return None;
        }
        let n = c.truncate() / c.w;
        Some(Pos2::new(
            self.rect.min.x + (n.x + 1.0) * 0.5 * self.rect.width(),
            self.rect.min.y + (1.0 - n.y) * 0.5 * self.rect.height(),
        ))
    }

    /// The world ray under screen position `pos`: origin on the near plane and unit
    /// direction. Orthographic rays are parallel: every one runs along the view direction.
    pub fn ray(&self, pos: Pos2) -> (Vec3, Vec3) {
        let nx = (pos.x - self.rect.min.x) / self.rect.width() * 2.0 - 1.0;
        let ny = 1.0 - (pos.y - self.rect.min.y) / self.rect.height() * 2.0;
        let near = self.inverse * Vec4::new(nx, ny, 0.0, 1.0);
        let a = near.truncate() / near.w;
        if self.ortho_height.is_some() {
            return (a, self.forward);
        }
        let far = self.inverse * Vec4::new(nx, ny, 1.0, 1.0);
        let b = far.truncate() / far.w;
        (a, (b - a).normalize_or_zero())
    }

    /// The rectangle.
    pub fn rect(&self) -> Rect {
        self.rect
    }

    /// The distance from which a perspective view would show things at `p` at the size this
    /// view shows them: the eye's distance to `p`, or for an orthographic view the distance
    /// whose perspective view height is the orthographic height (the same at every depth).
    pub fn apparent_distance(&self, p: Vec3) -> f32 {
        match self.ortho_height {
            Some(h) => h / (2.0 * (self.fov_y * 0.5).tan()),
            None => (p - self.eye).length(),
        }
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

    /// Distance from `p` to the ray `(o, d)` (unit `d`), and how far along the ray it lies.
    fn off_ray(p: Vec3, (o, d): (Vec3, Vec3)) -> (f32, f32) {
        let t = (p - o).dot(d);
        ((o + d * t - p).length(), t)
    }

    fn ortho_view() -> (EditorCamera, Rect) {
        let mut c = EditorCamera {
            ortho: true,
            ..EditorCamera::default()
        };
        c.focus(Vec3::new(3.0, 1.0, -2.0), 10.0);
        let rect = Rect::from_min_size(Pos2::new(10.0, 20.0), egui::vec2(400.0, 300.0));
        (c, rect)
    }

    #[test]
    fn ortho_picking_rays_pass_through_the_projected_points() {
        let (c, rect) = ortho_view();
        let cam = c.camera();
        assert_eq!(cam.ortho_height, Some(c.ortho_height()));
        let p = Projector::new(&cam, rect);
        let focus = c.eye + c.forward() * c.distance;
        let up = c.right().cross(c.forward());
        for (k, depth) in [0.5f32, 3.0, 10.0, 25.0, 120.0].into_iter().enumerate() {
            let off = c.right() * (k as f32 - 2.0) * 1.7 + up * (1.0 - k as f32 * 0.6);
            let w = c.eye + c.forward() * depth + off;
            let s = p.project(w).expect("in front");
            let ray = p.ray(s);
            assert!((ray.1 - c.forward()).length() < 1e-5, "parallel rays");
            // The ray starts on the near plane, under the cursor.
            assert!((p.depth(ray.0) - cam.near).abs() < 1e-3, "{:?}", ray.0);
            let (miss, t) = off_ray(w, ray);
            assert!(
                miss < 1e-3 * depth.max(1.0),
                "depth {depth}: misses by {miss}"
            );
            assert!(t > 0.0);
        }
        // The focus is still the centre; a point just behind the eye's plane is still drawn
        // (the render camera stands ORTHO_PULL_BACK focus distances back), one behind that
        // is not.
        let s = p.project(focus).expect("in front");
        assert!((s - rect.center()).length() < 0.01, "{s:?}");
        assert!(p.project(c.eye - c.forward() + c.right()).is_some());
        let behind = c.eye - c.forward() * (ORTHO_PULL_BACK * c.distance + 1.0);
        assert!(p.project(behind + c.right()).is_none());
    }

    #[test]
    fn ortho_rays_are_parallel_and_perspective_ones_are_not() {
        let (c, rect) = ortho_view();
        let near = c.eye + c.forward() * 2.0 + c.right() * 1.5 + Vec3::Y * 0.7;
        let far = near + c.forward() * 30.0;
        let ortho = Projector::new(&c.camera(), rect);
        let (a, b) = (ortho.project(near).unwrap(), ortho.project(far).unwrap());
        assert!((a - b).length() < 0.01, "{a:?} {b:?}");
        assert!((a - rect.center()).length() > 10.0, "off the centre");
        let persp = EditorCamera { ortho: false, ..c };
        let persp = Projector::new(&persp.camera(), rect);
        let (a, b) = (persp.project(near).unwrap(), persp.project(far).unwrap());
        assert!((a - b).length() > 10.0, "{a:?} {b:?}");
    }

    #[test]
    fn ortho_frames_the_focus_plane_as_perspective_does() {
        let (c, rect) = ortho_view();
        let focus = c.eye + c.forward() * c.distance;
        let up = c.right().cross(c.forward());
        let ortho = Projector::new(&c.camera(), rect);
        let persp = Projector::new(&EditorCamera { ortho: false, ..c }.camera(), rect);
        for w in [
            focus + c.right() * 4.0,
            focus - up * 2.5,
            focus + c.right() * -6.0 + up * 3.0,
        ] {
            let (a, b) = (ortho.project(w).unwrap(), persp.project(w).unwrap());
            assert!((a - b).length() < 0.05, "{a:?} {b:?}");
        }
        assert!((ortho.apparent_distance(focus) - c.distance).abs() < 1e-3);
    }

    #[test]
    fn zoom_changes_the_ortho_height() {
        let (mut c, _) = ortho_view();
        let before = c.camera().ortho_height.expect("ortho");
        assert!((before - 2.0 * 10.0 * 30f32.to_radians().tan()).abs() < 1e-4);
        c.zoom(3.0);
        let zoomed_in = c.camera().ortho_height.expect("ortho");
        assert!(zoomed_in < before * 0.75, "{before} -> {zoomed_in}");
        c.zoom(-6.0);
        assert!(c.camera().ortho_height.expect("ortho") > before);
        c.ortho = false;
        assert_eq!(c.camera().ortho_height, None);
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
