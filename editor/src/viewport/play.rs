//! Pointer capture while playing: the cursor is hidden and held in the window so the mouse
//! looks around without a drag; Esc (which stops Play) or losing the window's focus gives
//! it back. When the platform refuses the grab, raw motion may not arrive, and dragging
//! still looks around.

use egui::ViewportCommand;
use egui::viewport::CursorGrab;
use glam::Vec2;

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
