//! The first-person camera: mouse look, and the movement the held keys ask for.
//!
//! Pure CPU and free of winit, so every rule is unit-tested here; `play` maps keys and mouse
//! motion onto [`InputState`] and a pixel delta. Angles follow the level's player start and
//! [`Camera::from_yaw_pitch`]: yaw 0 looks along −Z, positive yaw turns toward −X
//! (counter-clockwise seen from above), positive pitch looks up, so the view direction is
//! `(−sin yaw · cos pitch, sin pitch, −cos yaw · cos pitch)`.
//!
//! Walking, the camera does not move itself: [`WalkCamera::walk_direction`] gives the
//! player's wish, and [`crate::walk::Walker`] puts the camera at the eye of a player that
//! collides, falls and rides platforms. Flying, [`WalkCamera::update`] moves the eye freely
//! along the view, through everything.

use glam::{Vec2, Vec3};
use texel_render::input::Camera;
use texel_scene::{PlayerStart, Scene, Transform};

/// Flying speed in world units per second (the reference's walking speed; walking speeds
/// are the player's, `texel_physics::PlayerConfig`).
pub const FLY_SPEED: f32 = 2.5;
/// Speed multiplier while Shift is held (the reference's number).
pub const RUN_MULTIPLIER: f32 = 3.0;
/// Mouse-look sensitivity in degrees per pixel of mouse motion.
pub const LOOK_SENSITIVITY: f32 = 0.15;
/// Pitch limit in degrees, short of straight up or down so the view never flips.
pub const MAX_PITCH: f32 = 89.0;
/// Longest time step one update integrates, in seconds: after a hitch (a slow first frame,
/// a window drag) the camera moves at most this much instead of jumping across the level.
pub const MAX_DT: f32 = 0.1;

/// Which movement keys are held this frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InputState {
    /// Move along the view (W).
    pub forward: bool,
    /// Move against the view (S).
    pub back: bool,
    /// Strafe left (A).
    pub left: bool,
    /// Strafe right (D).
    pub right: bool,
    /// Jump when walking, rise when flying (Space or E).
    pub up: bool,
    /// Sink, fly mode only (Ctrl or Q).
    pub down: bool,
    /// Move [`RUN_MULTIPLIER`] times faster (Shift).
    pub run: bool,
}

impl InputState {
    fn axis(positive: bool, negative: bool) -> f32 {
        f32::from(u8::from(positive)) - f32::from(u8::from(negative))
    }
}

/// A first-person camera that walks (where a [`crate::walk::Walker`] puts it) or flies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkCamera {
    /// The feet in walk mode; the eye in fly mode (see [`WalkCamera::eye`]).
    pub position: Vec3,
    /// Heading in degrees, kept within (−180, 180].
    pub yaw_deg: f32,
    /// Pitch in degrees, within ±[`MAX_PITCH`].
    pub pitch_deg: f32,
    /// Height of the eye above the feet.
    pub eye_height: f32,
    /// Whether the camera flies (true) or walks (false).
    pub fly: bool,
    /// Mouse-look sensitivity, degrees per pixel.
    pub sensitivity: f32,
    /// Flying speed, world units per second.
    pub speed: f32,
}

impl WalkCamera {
    /// A walking camera with its feet at `position`, facing as `start` says.
    pub fn from_start(position: Vec3, start: &PlayerStart) -> Self {
        WalkCamera {
            position,
            yaw_deg: wrap_degrees(start.yaw),
            pitch_deg: start.pitch.clamp(-MAX_PITCH, MAX_PITCH),
            eye_height: start.eye_height,
            fly: false,
            sensitivity: LOOK_SENSITIVITY,
            speed: FLY_SPEED,
        }
    }

    /// A walking camera at the scene's first player start (in level order), or at the
    /// origin with a default start when the level has none.
    pub fn from_scene(scene: &Scene) -> Self {
        let (position, start) = level_start(scene).unwrap_or((Vec3::ZERO, PlayerStart::default()));
        Self::from_start(position, &start)
    }

    /// Where the eye is: `eye_height` above the feet when walking, `position` when flying.
    pub fn eye(&self) -> Vec3 {
        if self.fly {
            self.position
        } else {
            self.position + Vec3::Y * self.eye_height
        }
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        let (y, p) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        Vec3::new(-y.sin() * p.cos(), p.sin(), -y.cos() * p.cos())
    }

    /// The render camera at the eye, with vertical field of view `fov_y` (radians).
    pub fn camera(&self, fov_y: f32) -> Camera {
        Camera {
            fov_y,
            ..Camera::from_yaw_pitch(self.eye(), self.yaw_deg, self.pitch_deg)
        }
    }

    /// Puts the eye at `eye` (the walking player's), keeping the view's direction.
    pub fn set_eye(&mut self, eye: Vec3) {
        if !eye.is_finite() {
            return;
        }
        self.position = if self.fly {
            eye
        } else {
            eye - Vec3::Y * self.eye_height
        };
    }

    /// Applies one frame of input: `mouse_delta` in pixels (x right, y down) turns the view;
    /// when flying, held keys move the eye for `dt` seconds (at most [`MAX_DT`]) along the
    /// view, Space/E and Ctrl/Q straight up and down. Walking, nothing moves here: see
    /// [`WalkCamera::walk_direction`].
    pub fn update(&mut self, input: &InputState, mouse_delta: Vec2, dt: f32) {
        self.look(mouse_delta);
        if !self.fly {
            return;
        }
        let dt = if dt.is_finite() {
            dt.clamp(0.0, MAX_DT)
        } else {
            0.0
        };
        let (_, right) = self.ground_axes();
        let dir = self.forward() * InputState::axis(input.forward, input.back)
            + right * InputState::axis(input.right, input.left)
            + Vec3::Y * InputState::axis(input.up, input.down);
        // Normalised so that diagonals are no faster than straight lines.
        let dir = dir.normalize_or_zero();
        let speed = self.speed * if input.run { RUN_MULTIPLIER } else { 1.0 };
        self.position += dir * speed * dt;
    }

    /// The horizontal direction the held keys walk in (unit length, or zero when none or
    /// opposite ones are held) and whether Shift asks to sprint: what
    /// `texel_physics::PlayerConfig::wish` takes. W walks along the view's ground
    /// projection, A and D strafe.
    pub fn walk_direction(&self, input: &InputState) -> (Vec3, bool) {
        let (ahead, right) = self.ground_axes();
        let dir = ahead * InputState::axis(input.forward, input.back)
            + right * InputState::axis(input.right, input.left);
        (dir.normalize_or_zero(), input.run)
    }

    /// The view's horizontal forward and right directions.
    fn ground_axes(&self) -> (Vec3, Vec3) {
        let (sin, cos) = self.yaw_deg.to_radians().sin_cos();
        (Vec3::new(-sin, 0.0, -cos), Vec3::new(cos, 0.0, -sin))
    }

    /// Turns the heading by `degrees` (positive toward −X, as yaw; a platform turning under
    /// the player). Not finite: no turn.
    pub fn turn(&mut self, degrees: f32) {
        if degrees.is_finite() {
            self.yaw_deg = wrap_degrees(self.yaw_deg + degrees);
        }
    }

    /// Faces heading `yaw` and pitch `pitch`, degrees (a respawn at the level's start).
    pub fn face(&mut self, yaw: f32, pitch: f32) {
        if yaw.is_finite() && pitch.is_finite() {
            self.yaw_deg = wrap_degrees(yaw);
            self.pitch_deg = pitch.clamp(-MAX_PITCH, MAX_PITCH);
        }
    }

    /// Turns the view by a mouse motion in pixels: right turns right, down looks down.
    pub fn look(&mut self, mouse_delta: Vec2) {
        if !mouse_delta.is_finite() {
            return;
        }
        self.yaw_deg = wrap_degrees(self.yaw_deg - mouse_delta.x * self.sensitivity);
        self.pitch_deg =
            (self.pitch_deg - mouse_delta.y * self.sensitivity).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Switches between walking and flying without moving the eye: landing puts the feet
    /// `eye_height` below it (where [`crate::walk::Walker::toggle_fly`] puts the player, who
    /// then falls to the ground), so a walk → fly → walk round trip with no movement in
    /// between leaves the camera exactly where it was.
    pub fn toggle_fly(&mut self) {
        if self.fly {
            self.position.y -= self.eye_height;
        } else {
            self.position = self.eye();
        }
        self.fly = !self.fly;
    }
}

/// The first player start in level order: its feet position and settings.
pub fn level_start(scene: &Scene) -> Option<(Vec3, PlayerStart)> {
    let world = scene.world();
    scene.entities().find_map(|e| {
        let start = *world.get::<&PlayerStart>(e).ok()?;
        let at = world
            .get::<&Transform>(e)
            .map(|t| t.translation)
            .unwrap_or(Vec3::ZERO);
        Some((at, start))
    })
}

/// `deg` wrapped into (−180, 180].
fn wrap_degrees(deg: f32) -> f32 {
    let w = (deg + 180.0).rem_euclid(360.0) - 180.0;
    if w == -180.0 { 180.0 } else { w }
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_scene::EntityRow;

    const EPS: f32 = 1e-5;

    fn start(yaw: f32, pitch: f32) -> WalkCamera {
        WalkCamera::from_start(
            Vec3::new(1.0, 0.5, 2.0),
            &PlayerStart {
                yaw,
                pitch,
                eye_height: 1.6,
            },
        )
    }

    fn held(f: impl FnOnce(&mut InputState)) -> InputState {
        let mut i = InputState::default();
        f(&mut i);
        i
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < EPS
    }

    #[test]
    fn matches_the_render_camera_convention() {
        for (yaw, pitch) in [(0.0, 0.0), (90.0, 0.0), (-135.0, 30.0), (170.0, -60.0)] {
            let cam = start(yaw, pitch);
            let reference = Camera::from_yaw_pitch(cam.eye(), yaw, pitch);
            assert!(close(cam.forward(), reference.forward), "{yaw} {pitch}");
            let c = cam.camera(1.0);
            assert!(close(c.forward, reference.forward));
            assert_eq!(c.position, cam.eye());
            assert_eq!(c.fov_y, 1.0);
        }
        assert!(close(start(0.0, 0.0).forward(), -Vec3::Z));
        assert!(close(start(90.0, 0.0).forward(), -Vec3::X));
    }

    #[test]
    fn eye_is_above_the_feet_when_walking() {
        let cam = start(0.0, 0.0);
        assert!(close(cam.eye(), Vec3::new(1.0, 2.1, 2.0)));
    }

    #[test]
    fn turning_in_place_moves_nothing() {
        let mut cam = start(10.0, 5.0);
        let before = cam.position;
        cam.update(&InputState::default(), Vec2::new(240.0, -80.0), 0.05);
        assert_eq!(cam.position, before);
        assert_ne!(cam.yaw_deg, 10.0);
        assert_ne!(cam.pitch_deg, 5.0);
    }

    #[test]
    fn mouse_right_turns_right_and_mouse_down_looks_down() {
        let mut cam = start(0.0, 0.0);
        cam.look(Vec2::new(100.0, 0.0));
        assert!(cam.forward().x > 0.0, "right of −Z is +X");
        let mut cam = start(0.0, 0.0);
        cam.look(Vec2::new(0.0, 100.0));
        assert!(cam.forward().y < 0.0);
    }

    fn flying(yaw: f32, pitch: f32) -> WalkCamera {
        let mut cam = start(yaw, pitch);
        cam.toggle_fly();
        cam
    }

    #[test]
    fn w_walks_along_the_ground_projection_of_the_view() {
        let cam = start(30.0, -40.0);
        let (dir, run) = cam.walk_direction(&held(|i| i.forward = true));
        let f = cam.forward();
        assert!(close(dir, Vec3::new(f.x, 0.0, f.z).normalize()), "{dir}");
        assert!(!run);
    }

    #[test]
    fn strafing_and_backing_follow_the_yaw() {
        let cam = start(0.0, 0.0);
        assert!(close(
            cam.walk_direction(&held(|i| i.right = true)).0,
            Vec3::X
        ));
        assert!(close(
            cam.walk_direction(&held(|i| i.back = true)).0,
            Vec3::Z
        ));
        let cam = start(90.0, 0.0);
        assert!(close(
            cam.walk_direction(&held(|i| i.left = true)).0,
            Vec3::Z
        ));
        let both = held(|i| {
            i.forward = true;
            i.back = true;
        });
        assert_eq!(cam.walk_direction(&both).0, Vec3::ZERO);
    }

    #[test]
    fn diagonals_are_no_faster() {
        let keys = held(|i| {
            i.forward = true;
            i.left = true;
        });
        let (dir, _) = start(0.0, 0.0).walk_direction(&keys);
        assert!((dir.length() - 1.0).abs() < EPS, "{dir}");
        let mut cam = flying(0.0, 0.0);
        let before = cam.position;
        cam.update(&keys, Vec2::ZERO, 0.1);
        assert!(((cam.position - before).length() - FLY_SPEED * 0.1).abs() < EPS);
    }

    #[test]
    fn shift_sprints_walking_and_triples_the_flying_distance() {
        let keys = held(|i| {
            i.forward = true;
            i.run = true;
        });
        assert!(start(0.0, 0.0).walk_direction(&keys).1);
        let (mut fly, mut run) = (flying(45.0, 0.0), flying(45.0, 0.0));
        fly.update(&held(|i| i.forward = true), Vec2::ZERO, 0.05);
        run.update(&keys, Vec2::ZERO, 0.05);
        let origin = flying(45.0, 0.0).position;
        let (w, r) = (
            (fly.position - origin).length(),
            (run.position - origin).length(),
        );
        assert!((r - 3.0 * w).abs() < EPS, "{w} {r}");
    }

    #[test]
    fn pitch_clamps() {
        let mut cam = start(0.0, 0.0);
        cam.look(Vec2::new(0.0, -1e6));
        assert_eq!(cam.pitch_deg, MAX_PITCH);
        cam.look(Vec2::new(0.0, 1e6));
        assert_eq!(cam.pitch_deg, -MAX_PITCH);
        assert_eq!(start(0.0, 120.0).pitch_deg, MAX_PITCH);
    }

    #[test]
    fn yaw_stays_wrapped() {
        let mut cam = start(170.0, 0.0);
        cam.look(Vec2::new(-200.0, 0.0)); // +30°
        assert!((cam.yaw_deg - -160.0).abs() < 1e-3, "{}", cam.yaw_deg);
        assert_eq!(wrap_degrees(-180.0), 180.0);
        assert_eq!(wrap_degrees(540.0), 180.0);
    }

    #[test]
    fn a_walking_camera_does_not_move_itself() {
        let mut cam = start(0.0, 0.0);
        let before = cam.position;
        let all = held(|i| {
            i.forward = true;
            i.right = true;
            i.up = true;
            i.run = true;
        });
        cam.update(&all, Vec2::ZERO, 0.1);
        assert_eq!(cam.position, before);
    }

    #[test]
    fn fly_mode_moves_vertically_and_along_the_view() {
        let mut cam = start(0.0, 0.0);
        cam.toggle_fly();
        let eye = cam.eye();
        cam.update(&held(|i| i.up = true), Vec2::ZERO, 0.1);
        assert!(close(cam.eye(), eye + Vec3::Y * 0.25));
        cam.update(&held(|i| i.down = true), Vec2::ZERO, 0.1);
        assert!(close(cam.eye(), eye));

        let mut cam = start(0.0, 60.0);
        cam.toggle_fly();
        let eye = cam.eye();
        cam.update(&held(|i| i.forward = true), Vec2::ZERO, 0.1);
        assert!(close(cam.eye(), eye + cam.forward() * 0.25));
        assert!(cam.eye().y > eye.y, "flying forward while looking up rises");
    }

    #[test]
    fn dt_is_clamped() {
        let (mut long, mut capped) = (flying(0.0, 0.0), flying(0.0, 0.0));
        let w = held(|i| i.forward = true);
        long.update(&w, Vec2::ZERO, 5.0);
        capped.update(&w, Vec2::ZERO, MAX_DT);
        assert_eq!(long.position, capped.position);
        let mut cam = flying(0.0, 0.0);
        let before = cam.position;
        cam.update(&w, Vec2::ZERO, -1.0);
        cam.update(&w, Vec2::ZERO, f32::NAN);
        assert_eq!(cam.position, before);
    }

    #[test]
    fn toggling_fly_twice_keeps_the_eye_still() {
        let mut cam = start(20.0, -10.0);
        let eye = cam.eye();
        cam.toggle_fly();
        assert!(cam.fly);
        assert!(close(cam.eye(), eye));
        cam.toggle_fly();
        assert!(!cam.fly);
        assert!(close(cam.eye(), eye));
        assert!(close(cam.position, start(20.0, -10.0).position));
    }

    #[test]
    fn landing_puts_the_feet_under_the_eye_and_set_eye_follows_the_mode() {
        let mut cam = flying(0.0, 0.0);
        cam.update(&held(|i| i.down = true), Vec2::ZERO, 1.0); // eye 2.1 → 1.85
        cam.toggle_fly();
        assert!(
            (cam.position.y - (1.85 - 1.6)).abs() < EPS,
            "{}",
            cam.position
        );
        cam.set_eye(Vec3::new(3.0, 4.0, 5.0));
        assert!(close(cam.position, Vec3::new(3.0, 2.4, 5.0)));
        cam.toggle_fly();
        cam.set_eye(Vec3::new(3.0, 4.0, 5.0));
        assert_eq!(cam.position, Vec3::new(3.0, 4.0, 5.0));
        cam.set_eye(Vec3::NAN);
        assert_eq!(cam.eye(), Vec3::new(3.0, 4.0, 5.0));
    }

    #[test]
    fn turning_and_facing_wrap_and_ignore_nan() {
        let mut cam = start(170.0, 0.0);
        cam.turn(20.0);
        assert!((cam.yaw_deg - -170.0).abs() < 1e-3, "{}", cam.yaw_deg);
        cam.turn(f32::NAN);
        assert!((cam.yaw_deg - -170.0).abs() < 1e-3);
        cam.face(30.0, 120.0);
        assert_eq!((cam.yaw_deg, cam.pitch_deg), (30.0, MAX_PITCH));
        cam.face(f32::INFINITY, 0.0);
        assert_eq!(cam.yaw_deg, 30.0);
    }

    #[test]
    fn starts_at_the_first_player_start() {
        let mut scene = Scene::new();
        assert!(level_start(&scene).is_none());
        assert_eq!(WalkCamera::from_scene(&scene).eye(), Vec3::Y * 1.6);
        let row = |x: f32, yaw: f32| EntityRow {
            transform: Some(Transform::from_translation(Vec3::new(x, 0.0, 13.0))),
            player_start: Some(PlayerStart {
                yaw,
                pitch: -5.0,
                eye_height: 1.7,
            }),
            ..EntityRow::default()
        };
        scene.spawn(EntityRow::default());
        scene.spawn(row(1.0, 30.0));
        scene.spawn(row(2.0, 60.0));
        let cam = WalkCamera::from_scene(&scene);
        assert_eq!(cam.position, Vec3::new(1.0, 0.0, 13.0));
        assert_eq!(
            (cam.yaw_deg, cam.pitch_deg, cam.eye_height),
            (30.0, -5.0, 1.7)
        );
        assert!(!cam.fly);
    }
}
