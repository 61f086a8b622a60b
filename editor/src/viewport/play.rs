//! Play: the physics behind the walking camera ([`PlayPhysics`]: the level's colliders and
//! a player, through `texel_runtime::walk` as in `texel-run play`), and pointer capture: the
//! cursor is hidden and held in the window so the mouse looks around without a drag; Esc
//! (which stops Play) or losing the window's focus gives it back. When the platform refuses
//! the grab, raw motion may not arrive, and dragging still looks around.

use egui::ViewportCommand;
use egui::viewport::CursorGrab;
use glam::Vec2;
use texel_runtime::first_person::{InputState, WalkCamera};
use texel_runtime::frame_plan::Animation;
use texel_runtime::load::LoadedLevel;
use texel_runtime::walk::Walker;

use crate::document::Document;

/// The level's colliders and the player walking through them during Play, built from the
/// document when Play starts (and again after an edit made while playing), dropped when it
/// stops.
#[derive(Debug)]
pub struct PlayPhysics {
    /// `None` when the colliders could not be built: the camera then only flies.
    walker: Option<Walker>,
    /// The document revision the colliders were built from.
    revision: u64,
    /// The animation time of the next frame: Play's one clock (the render worker draws
    /// each frame at the time its physics frame posed the moving objects at).
    clock: f64,
    /// The animation time the last frame posed the moving objects at.
    posed: f64,
    /// What the colliders left out, or why there are none, for the Play banner.
    pub note: Option<String>,
}

impl PlayPhysics {
    /// Colliders for `document`'s level, the player at its start; `camera` (the walking
    /// camera at the start) flies when no collider could be built.
    pub fn new(document: &Document, camera: &mut WalkCamera) -> Self {
        let mut physics = PlayPhysics {
            walker: None,
            revision: document.revision,
            clock: 0.0,
            posed: 0.0,
            note: None,
        };
        physics.build(&document.level, camera);
        physics
    }

    fn build(&mut self, level: &LoadedLevel, camera: &mut WalkCamera) {
        match Walker::new(&level.scene, &level.assets) {
            Ok(w) => {
                self.note = match w.warnings() {
                    [] => None,
                    [one] => Some(format!("no collider: {one}")),
                    [first, rest @ ..] => {
                        Some(format!("no collider: {first} (and {} more)", rest.len()))
                    }
                };
                self.walker = Some(w);
            }
            Err(e) => {
                self.note = Some(format!("no collision, flying only: {e}"));
                self.walker = None;
                if !camera.fly {
                    camera.toggle_fly();
                }
            }
        }
    }

    /// One Play frame, `dt` seconds long: the moving objects posed at the physics' clock
    /// ([`PlayPhysics::time`], which the viewport's frame is drawn at), which then advances;
    /// a document at another revision than the colliders' builds them again, keeping the
    /// player where it is.
    pub fn frame(
        &mut self,
        document: &Document,
        camera: &mut WalkCamera,
        input: &InputState,
        look: Vec2,
        dt: f32,
    ) {
        let level = &document.level;
        if document.revision != self.revision {
            self.revision = document.revision;
            match &mut self.walker {
                Some(w) => {
                    if let Err(e) = w.rebuild(&level.scene, &level.assets) {
                        self.walker = None;
                        self.note = Some(format!("no collision, flying only: {e}"));
                        if !camera.fly {
                            camera.toggle_fly();
                        }
                    }
                }
                None => self.build(level, camera),
            }
        }
        let t = self.clock;
        self.posed = t;
        self.clock = Animation::next_time(t, dt);
        match &mut self.walker {
            Some(w) => {
                w.frame(&level.scene, t, camera, input, look, dt);
            }
            None => camera.update(input, look, dt),
        }
    }

    /// Flying on or off (landing puts the player under the camera); without colliders the
    /// camera keeps flying.
    pub fn toggle_fly(&mut self, camera: &mut WalkCamera) {
        if let Some(w) = &mut self.walker {
            w.toggle_fly(camera);
        }
    }

    /// The animation time the last frame posed the moving objects at: the frame drawn for
    /// it shows them there.
    pub fn time(&self) -> f64 {
        self.posed
    }

    /// The walker, when there are colliders.
    pub fn walker(&self) -> Option<&Walker> {
        self.walker.as_ref()
    }
}

/// The grab mode asked of the platform: macOS only locks the cursor, X11 and Windows only
/// confine it (raw motion keeps arriving at the window's edge), Wayland does both.
pub fn grab_mode() -> CursorGrab {
    if cfg!(target_os = "macos") {
        CursorGrab::Locked
    } else {
        CursorGrab::Confined
    }
}

/// The viewport commands that take (`on`) or give back the pointer.
pub fn grab_commands(on: bool) -> [ViewportCommand; 2] {
    if on {
        [
            ViewportCommand::CursorGrab(grab_mode()),
            ViewportCommand::CursorVisible(false),
        ]
    } else {
        [
            ViewportCommand::CursorGrab(CursorGrab::None),
            ViewportCommand::CursorVisible(true),
        ]
    }
}

/// Raw mouse motion of this frame (`Event::MouseMoved`, which eframe forwards from the
/// device and which keeps coming while the cursor is held still).
pub fn raw_motion(input: &egui::InputState) -> Vec2 {
    input
        .raw
        .events
        .iter()
        .filter_map(|e| match e {
            egui::Event::MouseMoved(d) => Some(Vec2::new(d.x, d.y)),
            _ => None,
        })
        .sum()
}

/// The look motion of a Play frame: raw motion while the pointer is grabbed, else the drag.
pub fn look(grabbed: bool, raw: Vec2, dragging: bool, drag: Vec2) -> Vec2 {
    if grabbed && raw != Vec2::ZERO {
        raw
    } else if dragging {
        drag
    } else {
        Vec2::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grabbed_pointer_looks_without_a_drag() {
        let raw = Vec2::new(3.0, -1.0);
        assert_eq!(look(true, raw, false, Vec2::ZERO), raw);
        // Refused grab: no raw motion, the drag still looks.
        assert_eq!(
            look(true, Vec2::ZERO, true, Vec2::X),
            Vec2::X,
            "drag fallback"
        );
        assert_eq!(look(false, raw, false, Vec2::X), Vec2::ZERO);
        assert!(matches!(
            grab_commands(false)[0],
            ViewportCommand::CursorGrab(CursorGrab::None)
        ));
    }
}
